"""Stability sweep (``make stress``): eq. (7) over extreme mass ratios, coefficients and speeds.

Checks, on a full grid, that every outcome is finite, that momentum and the energy law (6) hold to
rounding, and that no energy is gained. Prints the worst cases; exits 1 if any check fails.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from .mechanics import impact

TOL = 1e-9


def sweep() -> dict[str, float]:
    ratio = np.logspace(-12, 12, 49)
    eps = np.array([0.0, 1e-12, 0.25, 0.5, 1 - 1e-12, 1.0])
    speed = np.array([1e-9, 1.0, 1e6])
    Mp, e1, e2, V0, V0p = np.meshgrid(ratio, eps, eps, speed, [0.0, -0.5], indexing="ij")
    V0p = V0p * V0
    M = np.ones_like(Mp)
    r = impact.direct_impact(M, Mp, V0, V0p, e1, e2)
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


def main() -> int:
    res = sweep()
    ok = (res["non_finite"] == 0 and res["max_momentum_rel_error"] < TOL and res["max_energy_law_rel_error"] < TOL
          and res["max_energy_gained_rel"] < TOL)
    lines = ["| check | value |", "|---|---|"] + [f"| {k} | {v:.3g} |" for k, v in res.items()]
    lines.append(f"| verdict (tolerance {TOL:g}) | {'stable' if ok else 'UNSTABLE'} |")
    out = Path("results") / "stress"
    out.mkdir(parents=True, exist_ok=True)
    (out / "stress.md").write_text("# Stress: §I direct impact, eq. (7)\n\n" + "\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
