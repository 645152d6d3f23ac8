"""Work-precision benchmark (``make bench``): run time against error for every model × path of the registry.

Each path of ``mechanics.registry`` is timed on the model's random scenes (closed forms on a large batch, the
ODE on a few) and its error measured against the ODE reference, both where it declares itself exact and over
all scenes (an approximation's error where its premise fails); ``auto`` is timed beside them. For §I the
reference integration is also run at several tolerances (the work-precision curve). Writes
``results/bench/work-precision.{md,json,png}`` and prints the table.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from .mechanics import paths, reference, registry


def _best_of(fn, repeat: int = 5) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def run(n_closed: int = 1_000_000, n_ode: int = 40) -> list[dict]:
    rows = []
    m = registry.MODELS["direct-impact"]
    big = m.scene(m.sample(np.random.default_rng(0), n_closed))
    t = _best_of(lambda: paths.solve(m, big, "exact"))
    rows.append({"path": "closed form eq. (7)", "tolerance": None, "seconds_per_scene": t / n_closed,
                 "max_rel_error": 0.0, "scenes": n_closed})
    small = m.scene(m.sample(np.random.default_rng(1), n_ode))
    exact = paths.solve(m, small, "exact")
    V0, V0p = small["V0"], small["V0p"]
    for rtol in (1e-4, 1e-6, 1e-8, 1e-10, 1e-12):
        def integrate(rtol: float = rtol) -> reference.ReferenceImpact:
            return reference.integrate_direct_impact(small["M"], small["Mp"], V0, V0p, exact.newton_e, rtol=rtol,
                                                     atol=rtol * 1e-2)

        t = _best_of(integrate, repeat=3)
        ode = integrate()
        err = max(np.max(np.abs(ode.V1 - exact.V1) / np.abs(V0 - V0p)),
                  np.max(np.abs(ode.V1p - exact.V1p) / np.abs(V0 - V0p)))
        rows.append({"path": "ODE two-phase contact (DOP853)", "tolerance": rtol, "seconds_per_scene": t / n_ode,
                     "max_rel_error": float(err), "scenes": n_ode, "mean_nfev": float(np.mean(ode.nfev))})
    rows += registry_rows()
    return rows


def registry_rows(n_fast: int = 20_000, n_ode: int = 24, seed: int = 5) -> list[dict]:
    """Every model × path (and auto): seconds per scene, and the largest error against the ODE path."""
    rows = []
    for m in registry.MODELS.values():
        rng = np.random.default_rng(seed)
        small = m.scene(m.sample(rng, n_ode))
        ode = paths.solve(m, small, "ode")
        for name in [p.name for p in m.paths] + ["auto"]:
            p = m.path(name) if name != "auto" else None
            keep = np.ones(n_ode, dtype=bool) if p is None else np.asarray(p.handles(small), dtype=bool)
            sub = {k: (v if k in m.static else v[keep]) for k, v in small.items()}
            ode_sub = paths.solve(m, sub, "ode") if not keep.all() else ode
            res = paths.solve(m, sub, name)
            err = m.error(sub, res, ode_sub)
            exact = np.ones(err.shape, bool) if p is None else np.asarray(p.exact_when(sub), dtype=bool)
            n = n_ode if p is not None and p.cost >= 1000 else n_fast
            big = m.scene(m.sample(np.random.default_rng(seed + 1), n))
            if p is not None:
                ok = np.asarray(p.handles(big), dtype=bool)
                big = {k: (v if k in m.static else v[ok]) for k, v in big.items()}
            count = int(np.size(big[paths.ONES]))
            t = _best_of(lambda m=m, big=big, name=name: paths.solve(m, big, name), repeat=1 if n == n_ode else 3)
            rows.append({"path": f"{m.name}: {name}", "tolerance": None, "seconds_per_scene": t / max(count, 1),
                         "max_rel_error": float(err[exact].max()) if exact.any() else None,
                         "max_rel_error_all": float(err.max()) if err.size else None, "scenes": count,
                         "kind": "auto" if p is None else p.kind.value})
    return rows


def _write(rows: list[dict], out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    (out / "work-precision.json").write_text(json.dumps(rows, indent=2) + "\n")
    def e(x: float | None) -> str:
        return "—" if x is None else f"{x:.2e}"

    lines = ["| path | rtol | time per scene | max rel. error where exact | over all scenes | mean nfev |",
             "|---|---|---|---|---|---|"]
    lines += [f"| {r['path']} | {r['tolerance'] or '—'} | {r['seconds_per_scene']:.3g} s | {e(r['max_rel_error'])} "
              f"| {e(r.get('max_rel_error_all'))} | {r.get('mean_nfev', '—')} |" for r in rows]
    (out / "work-precision.md").write_text("\n".join(lines) + "\n")
    fig, ax = plt.subplots(figsize=(6, 4.2), layout="constrained")
    ode = [r for r in rows if r["tolerance"] and r["path"].startswith("ODE two-phase")]
    ax.loglog([max(r["max_rel_error"], 1e-17) for r in ode], [r["seconds_per_scene"] for r in ode], "o-",
              label="ODE reference, rtol 1e-4 … 1e-12")
    ax.axhline(rows[0]["seconds_per_scene"], color="C3", ls="--", label="closed form eq. (7) (exact)")
    ax.set(xlabel="max relative error of V1, V1′", ylabel="seconds per scene", title="Work-precision, §I direct impact")
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    fig.savefig(out / "work-precision.png", dpi=120, metadata={"Software": None})
    plt.close(fig)
    print("\n".join(lines))


def main() -> int:
    rows = run()
    _write(rows, Path("results") / "bench")
    by = {r["path"]: r["seconds_per_scene"] for r in rows}
    ode = min(r["seconds_per_scene"] for r in rows if r["path"].startswith("ODE two-phase"))
    print(f"§I: the closed form is {ode / by['closed form eq. (7)']:.3g}× faster per scene than the cheapest ODE run")
    for m in registry.MODELS:
        t = {r["path"].split(": ")[1]: r["seconds_per_scene"] for r in rows if r["path"].startswith(m + ": ")}
        print(f"{m}: auto is {t['ode'] / t['auto']:.3g}× faster per scene than the ODE reference")
    return 0


if __name__ == "__main__":
    sys.exit(main())
