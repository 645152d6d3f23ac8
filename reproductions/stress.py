"""Stability sweep (``make stress``): eq. (7) over extreme mass ratios, coefficients and speeds, and every
model × path of the registry over its random scenes with speeds and spins scaled by 1e-6 … 1e6.

Checks that every outcome is finite, that momentum and the energy law (6) hold to rounding (eq. 7), and that
no path of an exact kind gains vis viva. Prints the worst cases; exits 1 if any check fails.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from .mechanics import impact, paths, registry

TOL = 1e-9


def sweep() -> dict[str, float]:
    ratio = np.logspace(-12, 12, 49)
    eps = np.array([0.0, 1e-12, 0.25, 0.5, 1 - 1e-12, 1.0])
    speed = np.array([1e-9, 1.0, 1e6])
    Mp, e1, e2, V0, V0p = np.meshgrid(ratio, eps, eps, speed, [0.0, -0.5], indexing="ij")
    V0p = V0p * V0
    M = np.ones_like(Mp)
    r = impact.direct_impact(M, Mp, V0, V0p, eps=e1, epsp=e2)
    p0 = M * V0 + Mp * V0p
    scale_p = M * np.abs(V0) + Mp * np.abs(V0p) + Mp * np.abs(r.V1p) + M * np.abs(r.V1)
    mom = np.abs(M * r.V1 + Mp * r.V1p - p0) / scale_p
    T0 = M * V0**2 + Mp * V0p**2 + M * r.V1**2 + Mp * r.V1p**2
    law = impact.vis_viva_loss(M, V0 - r.V1, e1, Mp, r.V1p - V0p, e2)
    energy = np.abs(r.vis_viva_lost - law) / T0
    gained = np.maximum(-r.vis_viva_lost / T0, 0.0)
    return {"scenes": float(M.size), "non_finite": float(np.sum(~np.isfinite(r.V1) | ~np.isfinite(r.V1p))),
            "max_momentum_rel_error": float(mom.max()), "max_energy_law_rel_error": float(energy.max()),
            "max_energy_gained_rel": float(gained.max())}


SPEED_UNITS = ("m/s", "rad/s")
EXACT_KINDS = (paths.Kind.CLOSED_FORM, paths.Kind.EXACT_NUMERICAL, paths.Kind.ODE)


def registry_sweep(n: int = 200, n_ode: int = 6, scales: tuple[float, ...] = (1e-6, 1.0, 1e6),
                   seed: int = 11) -> list[dict]:
    """Per model × path: scenes run, non-finite outputs, and the largest relative gain of vis viva (exact kinds).
    Speeds and spins (parameters in m/s or rad/s) are scaled together, so every scene keeps its regime."""
    rows = []
    for m in registry.MODELS.values():
        base = m.sample(np.random.default_rng(seed), n)
        speed = {p.name for p in m.params if p.unit in SPEED_UNITS}
        for p in m.paths:
            count, bad, gain = 0, 0, 0.0
            for c in scales if p.kind is not paths.Kind.ODE else (1.0,):
                raw = {k: (v * c if k in speed else v) for k, v in base.items()}
                if p.kind is paths.Kind.ODE:
                    raw = {k: (v if k in m.static else v[:n_ode]) for k, v in raw.items()}
                s = m.scene(raw)
                keep = np.asarray(p.handles(s), dtype=bool)
                s = {k: (v if k in m.static else v[keep]) for k, v in s.items()}
                res = paths.solve(m, s, p.name)
                outs = [np.asarray(getattr(res, o.partition("*")[0]), dtype=float) for o in m.outputs]
                finite = np.all(np.stack([np.all(np.isfinite(o.reshape(o.shape[0], -1)), axis=1) for o in outs]),
                                axis=0)
                count += int(keep.sum())
                bad += int((~finite).sum())
                if m.vis_viva is not None and p.kind in EXACT_KINDS:
                    before, after = m.vis_viva(s, res)
                    gain = max(gain, float(np.max(np.maximum(after - before, 0.0) / before, initial=0.0)))
            rows.append({"model": m.name, "path": p.name, "kind": p.kind.value, "scenes": count,
                         "non_finite": bad, "max_vis_viva_gain": gain})
    return rows


def main() -> int:
    res = sweep()
    ok = (res["non_finite"] == 0 and res["max_momentum_rel_error"] < TOL and res["max_energy_law_rel_error"] < TOL
          and res["max_energy_gained_rel"] < TOL)
    lines = ["| check | value |", "|---|---|"] + [f"| {k} | {v:.3g} |" for k, v in res.items()]
    lines.append(f"| verdict (tolerance {TOL:g}) | {'stable' if ok else 'UNSTABLE'} |")
    reg = registry_sweep()
    table = ["| model | path | kind | scenes | non-finite | max vis viva gain |", "|---|---|---|---|---|---|"]
    table += [f"| {r['model']} | {r['path']} | {r['kind']} | {r['scenes']} | {r['non_finite']} | "
              f"{r['max_vis_viva_gain']:.2g} |" for r in reg]
    reg_ok = all(r["non_finite"] == 0 and r["max_vis_viva_gain"] < TOL for r in reg)
    table.append(f"\nverdict: {'stable' if reg_ok else 'UNSTABLE'} (speeds and spins scaled by 1e-6, 1, 1e6)")
    out = Path("results") / "stress"
    out.mkdir(parents=True, exist_ok=True)
    (out / "stress.md").write_text("# Stress: §I direct impact, eq. (7)\n\n" + "\n".join(lines)
                                   + "\n\n# Every model × path of the registry\n\n" + "\n".join(table) + "\n")
    print("\n".join([*lines, "", *table]))
    return 0 if ok and reg_ok else 1


if __name__ == "__main__":
    sys.exit(main())
