"""Work-precision benchmark (``make bench``): run time against error for each solution path of §I.

The closed form of eq. (7) is timed on a large batch; the reference integration of the two-phase contact
is timed at several tolerances, and its error measured against the closed form. Writes
``results/bench/work-precision.{md,json,png}`` and prints the table.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from .mechanics import cushion, impact, reference


def _best_of(fn, repeat: int = 5) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def scenes(n: int, seed: int = 0) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    M, Mp = rng.uniform(0.1, 5, (2, n))
    V0 = rng.uniform(0.5, 3, n)
    V0p = V0 - rng.uniform(0.2, 3, n)
    eps, epsp = rng.uniform(0, 0.9, (2, n))
    return M, Mp, V0, V0p, eps, epsp


def run(n_closed: int = 1_000_000, n_ode: int = 40) -> list[dict]:
    rows = []
    big = scenes(n_closed)
    t = _best_of(lambda: impact.direct_impact(*big))
    rows.append({"path": "closed form eq. (7)", "tolerance": None, "seconds_per_scene": t / n_closed,
                 "max_rel_error": 0.0, "scenes": n_closed})
    small = scenes(n_ode, seed=1)
    exact = impact.direct_impact(*small)
    for rtol in (1e-4, 1e-6, 1e-8, 1e-10, 1e-12):
        def integrate(rtol: float = rtol) -> reference.ReferenceImpact:
            return reference.integrate_direct_impact(*small[:4], exact.newton_e, rtol=rtol, atol=rtol * 1e-2)

        t = _best_of(integrate, repeat=3)
        ode = integrate()
        err = max(np.max(np.abs(ode.V1 - exact.V1) / np.abs(small[2])),
                  np.max(np.abs(ode.V1p - exact.V1p) / np.abs(small[2])))
        rows.append({"path": "ODE two-phase contact (DOP853)", "tolerance": rtol, "seconds_per_scene": t / n_ode,
                     "max_rel_error": float(err), "scenes": n_ode, "mean_nfev": float(np.mean(ode.nfev))})
    # §IV: the closed form of the cushion integral against the integration of eqs (2)
    rng = np.random.default_rng(2)
    n_c = 20_000
    args = (rng.uniform(-3, 3, n_c), -rng.uniform(0.1, 3, n_c), rng.uniform(-100, 100, n_c),
            rng.uniform(-100, 100, n_c), 0.0305, 2.5, rng.uniform(0, 0.6, n_c), rng.uniform(0, 1, n_c))
    t = _best_of(lambda: cushion.cushion_impact(*args, method="exact"), repeat=3)
    small_args = tuple(a[:100] if isinstance(a, np.ndarray) else a for a in args)
    t_ode = _best_of(lambda: cushion.cushion_impact(*small_args, method="ode"), repeat=1)
    ex = cushion.cushion_impact(*small_args, method="exact")
    ode = cushion.cushion_impact(*small_args, method="ode")
    err = float(np.max(np.abs(ex.chi1 - ode.chi1) / np.abs(small_args[1])))
    rows.append({"path": "cushion §IV: closed form (₂F₁ + bisection)", "tolerance": None,
                 "seconds_per_scene": t / n_c, "max_rel_error": err, "scenes": n_c})
    rows.append({"path": "cushion §IV: ODE (DOP853, rtol 1e-11)", "tolerance": 1e-11,
                 "seconds_per_scene": t_ode / 100, "max_rel_error": err, "scenes": 100})
    return rows


def _write(rows: list[dict], out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    (out / "work-precision.json").write_text(json.dumps(rows, indent=2) + "\n")
    lines = ["| path | rtol | time per scene | max rel. error (/V0) | mean nfev |", "|---|---|---|---|---|"]
    lines += [f"| {r['path']} | {r['tolerance'] or '—'} | {r['seconds_per_scene']:.3g} s | {r['max_rel_error']:.2e} "
              f"| {r.get('mean_nfev', '—')} |" for r in rows]
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
    cu = [r["seconds_per_scene"] for r in rows if r["path"].startswith("cushion")]
    print(f"§IV: the closed form is {cu[1] / cu[0]:.3g}× faster per scene than the ODE, at the same accuracy")
    return 0


if __name__ == "__main__":
    sys.exit(main())
