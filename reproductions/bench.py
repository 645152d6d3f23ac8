"""Work-precision benchmark (``resal bench``, ``make bench``): run time against error for every model × path.

For each model of ``mechanics.registry``, a seeded batch of random scenes from the model's physical range. Each
path is timed (minimum over repeats after a warm-up, ``time.perf_counter``) on a large batch (closed forms) or
a small one (ODE paths, referees), and judged against a reference computed by a *different* method: the referee
(``mechanics.referee``, sharing no code with any path) where the model has one, else the ODE path at a tight
tolerance, for the closed forms and approximations; the exact path for the ODE and the referee themselves. Errors
are the model's own measure (``Model.error``: the largest output difference over the scene's speed scale);
failures count as NaN and are never dropped. Beside each path, its speed as a fraction of a floor measured in the
same run: one elementwise numpy pass over the batch's inputs and outputs. For §I the two-phase contact is also
integrated at a grid of tolerances (the work-precision curve of an ODE). For §VI on the cloth, three batches of the
same scenes are timed in turns through ``auto`` (``cloth_kinds``): k = k′, balls of a few kinds, and k, k′ per scene.

The Pareto verdict: for each model and scene class (the path ``auto`` chose × the regime), whether another path
that declares itself exact there is both faster and at least as accurate; then ``auto`` would be wrong, and the
declarations are what to fix. Writes ``results/bench/bench.{json,md}`` and ``work-precision-<model>.{png,pdf}``.
"""

from __future__ import annotations

import dataclasses
import json
import platform
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .mechanics import paths, reference, registry

__all__ = ["FITS", "FULL", "QUICK", "run", "selection", "write"]

FULL = {"n_fast": 100_000, "n_ode": 40, "repeat": 3, "solvers": ("RK45", "DOP853", "Radau", "LSODA"),
        "rtols": (1e-6, 1e-9, 1e-12)}
QUICK = {"n_fast": 2_000, "n_ode": 3, "repeat": 1, "solvers": ("RK45", "DOP853"), "rtols": (1e-6,)}
GRID_SCENES = 12
REFERENCE = ("DOP853", 1e-13)  # the reference the closed forms are judged against: the ODE path, tightened
N1_REPEAT = 300  # repeats of one scene (N = 1) through a closed form: its minimum is the cost without the noise
MAKE_ALL_REPEAT = 3  # `resal reproduce --all`, recomputed and reused: the median of this many runs each
FITS = "fit"  # the name that selects the fits on large files (``fitbench``) among the models
FASTER = 1.5  # "faster" in the Pareto verdict: by at least this factor (paths of equal cost differ by timing noise)


def _best_of(fn: Callable[[], Any], repeat: int, warm: bool = True) -> float:
    if warm:
        fn()
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def _take(m: paths.Model, s: dict[str, np.ndarray], keep: np.ndarray) -> dict[str, np.ndarray]:
    return {k: (v if k in m.static else v[keep]) for k, v in s.items()}


def _floor(m: paths.Model, s: dict[str, np.ndarray], res: Any, repeat: int) -> float:
    """One elementwise numpy pass over the batch's inputs and outputs (a copy of each array)."""
    arrays = [v for k, v in s.items() if k not in m.static and k != paths.ONES]
    arrays += [v for v in (getattr(res, f.name) for f in dataclasses.fields(res)) if isinstance(v, np.ndarray)]
    return _best_of(lambda: [np.copy(a) for a in arrays], repeat)


def _stats(err: np.ndarray) -> dict[str, float | int | None]:
    bad = ~np.isfinite(err)
    ok = err[~bad]
    return {"median_error": float(np.median(ok)) if ok.size else None,
            "max_error": float(np.max(ok)) if ok.size else None, "failures": int(bad.sum())}


def _tight(m: paths.Model, s: dict[str, np.ndarray]) -> tuple[Any, str]:
    """The ODE path at the reference tolerance (``REFERENCE``); its declared tolerance if that fails."""
    p = m.path("ode")
    solver, rtol = REFERENCE
    try:
        assert p.tuned is not None
        return p.tuned(s, rtol, solver), f"ode ({solver}, rtol {rtol:g})"
    except Exception:  # a solver failure is reported, not hidden: the label says which ran
        return paths.solve(m, s, "ode"), f"ode ({p.solver}, rtol {p.rtol:g}: {solver} at {rtol:g} failed)"


def ode_grid(m: paths.Model, s: dict[str, np.ndarray], exact: Any, solvers: Sequence[str],
             rtols: Sequence[float]) -> list[dict]:
    """The ODE path with each scipy solver at each tolerance: time per scene and error against the exact path
    (another method). A solver that fails counts every scene as a failure (NaN), not dropped."""
    p = m.path("ode")
    n = int(np.size(s[paths.ONES]))
    out = []
    for solver in solvers:
        for rtol in rtols:
            assert p.tuned is not None
            t0 = time.perf_counter()
            try:
                res = p.tuned(s, rtol, solver)
                err = m.error(s, res, exact)
            except Exception:  # counted as failures (NaN), never dropped
                err = np.full(n, np.nan)
            t = time.perf_counter() - t0
            out.append({"solver": solver, "rtol": rtol, "seconds_per_scene": t / max(n, 1)} | _stats(err))
    return out


def _is_slow(p: paths.Path | None) -> bool:
    """An ODE path or a referee (cost ≥ 1000): timed in the pool's workers, the closed forms in the parent alone."""
    return p is not None and p.cost >= 1000


def _samples(m: paths.Model, n_fast: int, n_ode: int, seed: int) -> tuple[dict, dict]:
    return m.scene(m.sample(np.random.default_rng(seed), n_ode)), m.scene(m.sample(np.random.default_rng(seed + 1),
                                                                                  n_fast))


def _exact_name(m: paths.Model) -> str:
    return next(p.name for p in m.paths if p.code is paths.PathCode.EXACT)


def _referee_name(m: paths.Model) -> str | None:
    return next((p.name for p in m.paths if p.kind is paths.Kind.REFEREE), None)


def _path_row(m: paths.Model, name: str, small: dict, big: dict, ref: Any, ref_name: str, ref_label: str,
              repeat: int) -> dict[str, Any]:
    """One path's row: its errors against ``ref`` on the small batch, its time per scene (the big batch for a
    closed form, the small one for an ODE path or a referee), its predicate's, the floor, one scene (N = 1)."""
    p = m.path(name) if name != "auto" else None
    n_ode = int(np.size(small[paths.ONES]))
    keep = np.ones(n_ode, bool) if p is None else np.asarray(p.handles(small), dtype=bool)
    sub = _take(m, small, keep)
    ref_sub = (_take_res(ref, keep) if not keep.all() else ref)
    res = paths.solve(m, sub, name)
    err = m.error(sub, res, ref_sub)
    exact = np.ones(err.shape, bool) if p is None else np.asarray(p.exact_when(sub), dtype=bool)
    ode_cost = _is_slow(p)
    batch = small if ode_cost else big
    if p is not None:
        batch = _take(m, batch, np.asarray(p.handles(batch), dtype=bool))
    count = int(np.size(batch[paths.ONES]))
    res_batch = paths.solve(m, batch, name) if count else None  # the warm-up, and the outputs for the floor
    t = _best_of(lambda b=batch, n=name: paths.solve(m, b, n), 1 if ode_cost else repeat,
                 warm=False) if count else np.nan
    # what it costs auto to know that this path is exact for a scene (its declared predicate)
    t_pred = _best_of(lambda b=batch, q=p: q.exact_when(b), repeat) if count and p is not None else 0.0
    floor = _floor(m, batch, res_batch, repeat) if count else np.nan
    # one scene (N = 1), the first of the small batch that the path handles: what a user waiting on one
    # `resal simulate` or one `api.simulate` call pays, overhead included
    first = np.flatnonzero(keep)[:1]
    one = _take(m, small, np.isin(np.arange(n_ode), first)) if first.size else None
    t_one = (_best_of(lambda b=one, n=name: paths.solve(m, b, n), 1 if ode_cost else N1_REPEAT)
             if one is not None else np.nan)
    referee = _referee_name(m)
    return {
        "path": name, "kind": "auto" if p is None else p.kind.value, "cost": None if p is None else p.cost,
        "declared_accuracy": None if p is None else p.accuracy,
        "reference": (referee or "ode") if ref_name == "ode" else ref_name,
        "reference_method": ref_label if ref_name == "ode" else f"{ref_name} path",
        "scenes_timed": count, "seconds_per_scene": t / max(count, 1), "scenes_per_second": count / t,
        "predicate_seconds_per_scene": t_pred / max(count, 1), "n1_seconds": t_one,
        "floor_fraction": floor / t, "where_exact": _stats(err[exact]) | {"scenes": int(exact.sum())},
        "all_scenes": _stats(err) | {"scenes": int(err.size)},
    }


def _reference(m: paths.Model, small: dict) -> tuple[Any, str]:
    """The reference the closed forms are judged against: the referee where the model has one (it shares no code
    with them), else the ODE path at a tight tolerance."""
    referee = _referee_name(m)
    if referee is not None:
        return paths.solve(m, small, referee), f"{referee} (the referee, shares no code)"
    return _tight(m, small)


def _ode_task(task: tuple) -> Any:
    """One piece of the benchmark's ODE part, in whichever process runs it: ``("tight", model, n_fast, n_ode,
    seed)`` (the reference of the closed forms), ``("row", …, path, repeat)`` (an ODE path's or a referee's row,
    judged against the exact path, timed here: its throughput per worker) or ``("grid", …, solvers, rtols)``."""
    kind, name, n_fast, n_ode, seed, *args = task
    m = registry.MODELS[name]
    small, big = _samples(m, n_fast if kind == "row" else 1, n_ode, seed)
    if kind == "tight":
        return _reference(m, small)
    exact_name = _exact_name(m)
    exact = paths.solve(m, small, exact_name)
    if kind == "row":
        path, repeat = args
        return _path_row(m, path, small, big, exact, exact_name, "", repeat)
    solvers, rtols = args
    few = np.arange(int(np.size(small[paths.ONES]))) < GRID_SCENES  # the grid is 12 integrations per scene
    return ode_grid(m, _take(m, small, few), _take_res(exact, few), solvers, rtols)


def _ode_tasks(m: paths.Model, n_ode: int, repeat: int, seed: int, solvers: Sequence[str],
               rtols: Sequence[float]) -> list[tuple]:
    # the row of a slow path times it on the small batch only: the big one is not drawn (n_fast 1)
    return ([("tight", m.name, 1, n_ode, seed)]
            + [("row", m.name, 1, n_ode, seed, p.name, repeat) for p in m.paths if _is_slow(p)]
            + [("grid", m.name, 1, n_ode, seed, tuple(solvers), tuple(rtols))])


def _part(task: tuple) -> str:
    """The key of a task's result in ``model_rows``'s ``ode_part``: the path of a row, else the task's kind."""
    return task[5] if task[0] == "row" else task[0]


def _step(task: tuple) -> str:
    """The progress bar's text for a task done."""
    return f"{task[1]}: {task[5]}" if task[0] == "row" else f"{task[1]}: ODE solvers × tolerances"


def ode_parts(models: Sequence[str], cfg: dict[str, Any], jobs: int | None = None, scheduler: str | None = None,
              progress: Callable[[str], None] | None = None, seed: int = 5) -> tuple[dict[str, dict], dict]:
    """The ODE part of every model (the references, the ODE paths' and referees' rows, the solver grids) on the
    executor of ``jobs`` and ``scheduler`` (``sweep.executor``), and how it ran: each slow path timed in the
    worker that ran it, so its scenes per second are a throughput per worker (per core)."""
    from .sweep import executor

    tasks = [t for name in models for t in _ode_tasks(registry.MODELS[name], cfg["n_ode"], cfg["repeat"], seed,
                                                      cfg["solvers"], cfg["rtols"])]

    def done(i: int, result: Any, seconds: float) -> None:
        if progress and tasks[i][0] != "tight":
            progress(_step(tasks[i]))

    t0 = time.perf_counter()
    with executor(jobs, scheduler) as ex:
        results = ex.map(_ode_task, tasks, done)
        how = ex.describe()
    parts: dict[str, dict] = {name: {} for name in models}
    for t, r in zip(tasks, results, strict=True):
        parts[t[1]][_part(t)] = r
    how["wall_seconds"] = round(time.perf_counter() - t0, 2)
    per: dict[str, dict[str, Any]] = {}
    for name in models:
        for p in registry.MODELS[name].paths:
            if _is_slow(p):
                r = parts[name][p.name]
                kind = per.setdefault(p.kind.value, {"scenes": 0, "seconds": 0.0, "models": {}})
                kind["scenes"] += r["scenes_timed"]
                kind["seconds"] += r["seconds_per_scene"] * r["scenes_timed"]
                kind["models"][name] = r["scenes_per_second"]
    for kind in per.values():
        kind["scenes_per_second_per_worker"] = kind["scenes"] / kind["seconds"] if kind["seconds"] > 0 else None
    how["throughput"] = per
    return parts, how


def model_rows(m: paths.Model, n_fast: int, n_ode: int, repeat: int, seed: int = 5,
               progress: Callable[[str], None] | None = None, solvers: Sequence[str] = ("DOP853",),
               rtols: Sequence[float] = (1e-9,), ode_part: dict[str, Any] | None = None) -> dict[str, Any]:
    """Every path of one model and ``auto``: errors against the reference, times, the floor, the verdict; and
    the ODE path's work-precision grid over scipy's solvers and tolerances. ``ode_part``: the slow part already
    computed (``_ode_task``'s results by kind and path, on the pool); else it is computed here."""
    small, big = _samples(m, n_fast, n_ode, seed)
    if ode_part is None:
        ode_part = {}
        for t in _ode_tasks(m, n_ode, repeat, seed, solvers, rtols):
            if progress and t[0] != "tight":
                progress(_step(t))
            ode_part[_part(t)] = _ode_task(t)
    tight, tight_label = ode_part["tight"]
    auto_small = paths.solve(m, small, "auto")
    rows = []
    for name in [p.name for p in m.paths] + ["auto"]:
        p = m.path(name) if name != "auto" else None
        if _is_slow(p):
            rows.append(ode_part[name])
            continue
        if progress:
            progress(f"{m.name}: {name}")
        rows.append(_path_row(m, name, small, big, tight, "ode", tight_label, repeat))
    return {"model": m.name, "section": m.section, "paths": rows, "ode_grid": ode_part["grid"],
            "pareto": _pareto(m, small, auto_small, rows, tight)}


def _pareto(m: paths.Model, small: dict[str, np.ndarray], auto: Any, rows: list[dict], ref: Any) -> list[dict]:
    """Per scene class (auto's path × regime): is another path declaring itself exact there faster and at least as
    accurate against the reference (faster by ``FASTER`` at least, its predicate's cost included)? Then auto chose
    wrong."""
    speed = {r["path"]: r["seconds_per_scene"] for r in rows}
    check = {r["path"]: r.get("predicate_seconds_per_scene", 0.0) for r in rows}
    out = []
    for code in np.unique(auto.path):
        for regime in np.unique(auto.regime[auto.path == code]):
            sel = (auto.path == code) & (auto.regime == regime)
            sub = _take(m, small, sel)
            chosen = next(p for p in m.paths if p.code == code)
            err_c = float(np.max(m.error(sub, _take_res(auto, sel), _take_res(ref, sel))))
            better = []
            for p in m.paths:
                if p is chosen or p.code is paths.PathCode.ODE:
                    continue
                ok = np.asarray(p.handles(sub), bool) & np.asarray(p.exact_when(sub), bool)
                if not ok.all():
                    continue
                e = float(np.max(m.error(sub, paths.solve(m, sub, p.name), _take_res(ref, sel))))
                # the alternative pays for its own predicate, which auto would have to evaluate to use it
                if (speed[p.name] + check[p.name]) * FASTER < speed[chosen.name] and e <= max(err_c, chosen.accuracy):
                    better.append(p.name)
            out.append({"auto_path": chosen.name, "regime": paths.Regime(int(regime)).name.lower(),
                        "scenes": int(sel.sum()), "max_error": err_c, "faster_and_as_accurate": better,
                        "verdict": "auto is right" if not better else "auto is wrong: " + ", ".join(better)})
    return out


def _take_res(res: Any, sel: np.ndarray) -> Any:
    values = {}
    for f in dataclasses.fields(res):
        v = getattr(res, f.name)
        values[f.name] = v[sel] if isinstance(v, np.ndarray) and v.ndim >= 1 else v
    return type(res)(**values)


def _direct_by_hand(s: dict[str, np.ndarray]) -> tuple[np.ndarray, ...]:
    M, Mp, V0, V0p, e, ep = (s[k] for k in ("M", "Mp", "V0", "V0p", "eps", "epsp"))
    d = 2 * Mp * (V0 - V0p) / (Mp * (1 + e) + M * (1 + ep))  # eq. (7)
    return V0 - d, V0p + M / Mp * d


def _plane_by_hand(s: dict[str, np.ndarray]) -> tuple[np.ndarray, ...]:
    v0 = s["chi0"] - s["p0"] * s["R"]
    dv = -np.sign(v0) * np.minimum(np.abs(v0), s["f"] * (1 + s["k"]) * (1 + s["nu"]) * np.abs(s["zeta0"]))
    pR1 = s["p0"] * s["R"] - s["k"] * dv / (1 + s["k"])
    return s["chi0"] + dv / (1 + s["k"]), -s["nu"] * s["zeta0"], pR1 / s["R"]


def _cloth_by_hand(s: dict[str, np.ndarray]) -> tuple[np.ndarray, ...]:
    ux, uy = s["vx"] - s["wy"] * s["R"], s["vy"] + s["wx"] * s["R"]
    u = np.hypot(ux, uy)
    fg = s["f"] * s["g"]
    t1 = u / ((1 + s["k"]) * fg)
    ex, ey = ux / np.where(u > 0, u, 1.0), uy / np.where(u > 0, u, 1.0)
    return t1, s["vx"] * t1 - 0.5 * fg * ex * t1**2, s["vy"] * t1 - 0.5 * fg * ey * t1**2


BY_HAND = {"direct-impact": _direct_by_hand, "plane-impact": _plane_by_hand, "cloth-slide": _cloth_by_hand}


def by_hand(n: int, repeat: int) -> list[dict]:
    """The closed forms of §I, §II, §III against one hand-written numpy expression of the same formula on the
    same batch: what the registry, the result convention and the regime codes cost over the bare arithmetic."""
    out = []
    for name, fn in BY_HAND.items():
        m = registry.MODELS[name]
        s = m.scene(m.sample(np.random.default_rng(7), n))
        t_path = _best_of(lambda m=m, s=s: paths.solve(m, s, "exact"), repeat)
        t_hand = _best_of(lambda fn=fn, s=s: fn(s), repeat)
        out.append({"model": name, "path_scenes_per_second": n / t_path, "hand_scenes_per_second": n / t_hand,
                    "slowdown": t_path / t_hand})
    return out


def direct_impact_curve(n: int, repeat: int) -> list[dict]:
    """§I: the two-phase contact integrated at a grid of tolerances against the closed form (DOP853)."""
    m = registry.MODELS["direct-impact"]
    s = m.scene(m.sample(np.random.default_rng(1), n))
    exact = paths.solve(m, s, "exact")
    out = []
    for rtol in (1e-4, 1e-6, 1e-8, 1e-10, 1e-12):
        def integrate(rtol: float = rtol) -> reference.ReferenceImpact:
            return reference.integrate_direct_impact(s["M"], s["Mp"], s["V0"], s["V0p"], exact.newton_e,
                                                     rtol=rtol, atol=rtol * 1e-2)

        t = _best_of(integrate, repeat)
        r = integrate()
        err = np.maximum(np.abs(r.V1 - exact.V1), np.abs(r.V1p - exact.V1p)) / np.abs(s["V0"] - s["V0p"])
        out.append({"rtol": rtol, "seconds_per_scene": t / n, "max_error": float(err.max()),
                    "mean_nfev": float(np.mean(r.nfev))})
    return out


# §VI batches of balls of a few kinds (issue 34, item 2: heterogeneous k, k′ not slower than homogeneous): each
# scene's two balls drawn among these (mass kg, MR²/I), a choice of ours: a set's object ball, a lighter one, and a
# heavier cue ball of another make; and a batch where every scene has its own k, k′ (uniform on 1.5–4)
BALL_KINDS = ((0.170, 2.5), (0.156, 2.5), (0.210, 2.2))


def cloth_kinds(n: int, repeat: int, seed: int = 5) -> dict[str, Any]:
    """§VI on the cloth through ``auto``, scenes/s on three batches of the model's sample (the same scenes): its own
    k = k′ = 5/2 (homogeneous), the balls of ``BALL_KINDS`` (a few classes of the slip's c: ``slip.classes``), and k,
    k′ per scene; timed in turns (``repeat`` rounds, the minimum of each), so that the machine's drift is shared."""
    m = registry.MODELS["spheres-cloth"]
    base = m.sample(np.random.default_rng(seed), n)
    r = np.random.default_rng(seed + 1)
    a, b = r.integers(0, len(BALL_KINDS), n), r.integers(0, len(BALL_KINDS), n)
    mass, k = np.array([x[0] for x in BALL_KINDS]), np.array([x[1] for x in BALL_KINDS])
    batches = {"homogeneous": base, "kinds": dict(base, M=mass[a], k=k[a], Mp=mass[b], kp=k[b]),
               "per_scene": dict(base, k=r.uniform(1.5, 4.0, n), kp=r.uniform(1.5, 4.0, n))}
    scenes = {name: m.scene(v) for name, v in batches.items()}
    best = dict.fromkeys(scenes, np.inf)
    for sc in scenes.values():
        paths.solve(m, sc, "auto")  # warm-up
    for _ in range(max(1, repeat)):
        for name, sc in scenes.items():
            t0 = time.perf_counter()
            paths.solve(m, sc, "auto")
            best[name] = min(best[name], time.perf_counter() - t0)
    return {"scenes": n, "kinds": [list(x) for x in BALL_KINDS], "repeat": max(1, repeat),
            "scenes_per_second": {name: n / t for name, t in best.items()}}


def make_all_times(repeat: int = MAKE_ALL_REPEAT, progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """``resal reproduce --all`` (``make all``) as a user runs it, a new process each time, into a scratch folder:
    ``cold``, everything recomputed (``--force``: the experiments, their figures and the reader's edition), then
    ``cached``, nothing changed (every folder reused). Wall and CPU seconds (the process's own and its workers'),
    each run and their median."""
    import os
    import resource
    import statistics
    import subprocess
    import tempfile

    def once(out: str, *extra: str) -> dict[str, float]:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "cli.main", "reproduce", "--all", "--out", out, *extra],
                              capture_output=True, text=True, env=os.environ | {"COLUMNS": "80"})
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if proc.returncode != 0:
            raise RuntimeError(f"resal reproduce --all failed ({proc.returncode}): {proc.stderr.strip()[-500:]}")
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        return {"wall": wall, "cpu": cpu}

    out: dict[str, Any] = {"repeat": repeat, "command": "resal reproduce --all --out <scratch> [--force]"}
    with tempfile.TemporaryDirectory(prefix="resal-bench-") as tmp:
        for what, extra in (("cold", ("--force",)), ("cached", ())):
            if progress:
                progress(f"make all: {what}")
            runs = [once(tmp, *extra) for _ in range(repeat)]
            out[what] = {"runs": runs, "median_wall": statistics.median(r["wall"] for r in runs),
                         "median_cpu": statistics.median(r["cpu"] for r in runs)}
    return out


def selection(models: Sequence[str], quick: bool) -> tuple[list[str], bool]:
    """The models ``run`` times for the names given (none: every model) and whether it times the fits (``FITS``
    named, or the full benchmark: no names, not quick)."""
    chosen = [x for x in models if x != FITS] or ([] if models else list(registry.MODELS))
    return chosen, FITS in models or (not models and not quick)


def run(models: Sequence[str] = (), quick: bool = False, progress: Callable[[str], None] | None = None,
        jobs: int | None = None, scheduler: str | None = None) -> dict:
    """The benchmark report (``bench.json``): per model its paths and Pareto verdict, and the machine. ``fit`` among
    ``models`` (alone: ``resal bench fit``) times ``resal fit`` on large files (``fitbench``): at 100 rows with
    ``quick``, 1000 and 10 000 rows otherwise; the full benchmark (no names, not quick) includes it.

    The ODE part (ODE paths, referees, solver grids: ``ode_parts``) runs first on ``jobs`` processes (None: one per
    core; 1: this one) or on the Dask cluster at ``scheduler``; its times are per worker (``ode_sweeps``: the
    throughput per core). Everything else is timed afterwards in this process alone, nothing running beside it."""
    cfg = QUICK if quick else FULL
    chosen, fits = selection(models, quick)
    unknown = [x for x in chosen if x not in registry.MODELS]
    if unknown:
        raise KeyError(f"unknown model(s) {', '.join(unknown)} (expected some of: {', '.join(registry.MODELS)}, "
                       f"or {FITS})")
    import scipy

    parts, how = ode_parts(chosen, cfg, jobs, scheduler, progress) if chosen else ({}, None)
    report: dict[str, Any] = {
        "quick": quick, "config": cfg, "timer": "time.perf_counter, minimum over repeats after a warm-up",
        "machine": {"python": platform.python_version(), "numpy": np.__version__, "scipy": scipy.__version__,
                    "processor": platform.processor() or platform.machine(), "system": platform.system()},
        "reference": f"the ODE path with {REFERENCE[0]} at rtol {REFERENCE[1]:g} (closed forms and "
                     "approximations); the exact path (the ODE itself and its solver grid)",
        "models": [model_rows(registry.MODELS[x], cfg["n_fast"], cfg["n_ode"], cfg["repeat"],
                              progress=progress, solvers=cfg["solvers"], rtols=cfg["rtols"], ode_part=parts[x])
                   for x in chosen]}
    if how is not None:
        report["ode_sweeps"] = how
    if "direct-impact" in chosen:
        report["direct_impact_ode_tolerances"] = direct_impact_curve(cfg["n_ode"], cfg["repeat"])
    if chosen:
        report["closed_forms_by_hand"] = by_hand(cfg["n_fast"], cfg["repeat"])
        if progress:
            progress("one scene (N = 1): where its time goes")
        from .mechanics import timing

        report["n1"] = timing.n1_times(chosen, repeat=200 if quick else 3000)
    if "spheres-cloth" in chosen:
        if progress:
            progress("§VI on the cloth: balls of a few kinds, k and k′ per scene")
        report["cloth_kinds"] = cloth_kinds(cfg["n_fast"], 2 * cfg["repeat"] + 1)
    if not quick and not models:  # the whole command, as a user waits on it (seconds each: not in --quick)
        report["make_all"] = make_all_times(progress=progress)
    if fits:
        from . import fitbench

        report["fits"] = fitbench.run(fitbench.sizes(quick), progress=progress)
    from . import targets

    report["calibration"] = targets.calibration()  # alone, after the rest: the machine as the timings found it
    from . import pooltool_side

    # where pooltool is installed: its collisions timed here, for the targets' side-by-side rows
    report["pooltool"] = pooltool_side.measure(200 if quick else 2000, progress=progress)
    report["targets"] = [t.as_dict() for t in targets.rows(report)]
    return report


def _e(x: float | None) -> str:
    return "—" if x is None else f"{x:.2e}"


def _us(seconds: float | None) -> str:
    return "—" if seconds is None or not np.isfinite(seconds) else f"{seconds * 1e6:.3g}"


# the error measure of each model (``Model.error``): the outputs compared, over the scale that makes them relative
_MEASURES = {
    "direct-impact": "|ΔV1|, |ΔV′1| over the approach speed |V0 − V′0|",
    "wall-impact": "|ΔV1| over the impact speed V0",
    "plane-impact": "|Δχ1|, |Δζ1|, R|Δp1| over |(χ0, ζ0)| + R|p0|",
    "ricochet": "the ranges, times, χ, ζ and Rp after each impact, over a0(1 + a0/g) + R|p0|",
    "cloth-slide": "|Δt1| over V/(fg), |Δx1|, |Δy1| over V²/(fg), |Δv1| over V = |v0| + R|ω0| (onset of rolling)",
    "cushion-impact": "|Δχ1|, |Δζ1|, R|Δp1|, R|Δn1| over |(χ0, ζ0)| + R|(p0, n0)|",
    "spheres-free": "|Δv1|, R|Δω1|, |Δv′1|, R′|Δω′1| over the approach speed",
    "spheres-cloth": "|Δv1|, R|Δω1|, |Δv′1|, R′|Δω′1| over the approach speed",
    "cue-stroke": "|Δχ1|, |Δη1|, R|Δn1|, R|Δp1|, R|Δq1|, |ΔV′1| over the cue's speed V′0",
}


def _measure(model: str) -> str:
    """What the x axis of a model's work-precision figure measures, in words."""
    if model in _MEASURES:
        return _MEASURES[model]
    m = registry.MODELS[model]
    return f"|Δ| of {', '.join(m.outputs)} over the model's speed scale"


def _work_precision_figure(plt: Any, mod: dict, rtols: Sequence[float]) -> Any:
    """One model's work-precision figure (``mod``: a model of the report): every path (dots) and auto (a star),
    every ODE solver over the tolerances (squares joined by a dashed line), each with a colour of its own. A path's
    dot is its largest error over the scenes where it declares itself exact, the number of bench.md's column "max
    error where exact"; where its error over all the scenes it handles is larger (the column "max error, all
    scenes"), an open ring of its colour marks that too. The x axis says so, and what the model's error measures.
    Sized for a phone (``report.FONT``, ``report.min_font_pt``); the caller saves and closes it."""
    import textwrap

    from matplotlib.lines import Line2D

    from .report import _FIG_W, FONT, minus_signs, plain_log_labels, subscripts

    fig, ax = plt.subplots(figsize=(_FIG_W, 5.8), layout="constrained")
    solvers = list(dict.fromkeys(g["solver"] for g in mod["ode_grid"]))
    n = len(mod["paths"]) + len(solvers)
    cmap = plt.get_cmap("tab10" if n <= 10 else "tab20")
    beyond = False
    for i, r in enumerate(mod["paths"]):
        exact, every = r["where_exact"]["max_error"], r["all_scenes"]["max_error"]
        style = ({"marker": "*", "color": "k", "ms": 13} if r["path"] == "auto" else
                 {"marker": "o", "color": cmap(i), "ms": 7})
        shown = exact if exact is not None else every  # a path exact nowhere: its error over all its scenes
        ax.loglog([max(shown if shown is not None else np.nan, 1e-17)], [r["seconds_per_scene"]], linestyle="none",
                  label=f"{r['path']} ({r['kind']})", mfc=style["color"] if exact is not None else "none",
                  **style)
        if every is not None and exact is not None and every > 2 * max(exact, 1e-17):
            beyond = True
            ax.loglog([max(exact, 1e-17), every], [r["seconds_per_scene"]] * 2, ":", color=style["color"], lw=1)
            ax.loglog([every], [r["seconds_per_scene"]], linestyle="none", marker="o", mfc="none", mew=1.5, ms=9,
                      color=style["color"])
    for j, solver in enumerate(solvers):
        pts = [(g["max_error"], g["seconds_per_scene"]) for g in mod["ode_grid"]
               if g["solver"] == solver and g["max_error"] is not None]
        if pts:
            ax.loglog([max(e, 1e-17) for e, _ in pts], [t for _, t in pts], "--", marker="s", ms=5,
                      color=cmap(len(mod["paths"]) + j), label=f"ODE, {solver}")
    tol = ", ".join(minus_signs(f"{x:g}") for x in rtols)
    ring = "; ring: over all the scenes it handles, where larger" if beyond else ""
    where = f"largest error where the path declares itself exact (dot{ring}; ODE solvers at rtol {tol})"
    measure = subscripts(textwrap.fill(_measure(mod["model"]), 62))
    ax.set_xlabel(textwrap.fill(where, 62) + ", against the reference:\n" + measure, fontsize=FONT["legend"])
    ax.set_ylabel("seconds per scene", fontsize=FONT["label"])
    ax.set_title(f"Work-precision: {mod['model']}", fontsize=FONT["title"])
    ax.tick_params(labelsize=FONT["tick"], which="both")
    # decades only: the minor ticks of axes over ten or more decades drew nothing a reader uses, and they were
    # most of the figure's drawing time (each tick an artist, measured for the layout at each save)
    ax.minorticks_off()
    ax.grid(alpha=0.3, which="major")
    handles, labels = ax.get_legend_handles_labels()
    if beyond:  # the ring's key: a handle of its own, not a line of the axes
        handles.append(Line2D([], [], linestyle="none", marker="o", mfc="none", mew=1.5, ms=9, color="0.3"))
        labels.append("over all scenes, where larger")
    fig.legend(handles, labels, loc="outside lower center", ncols=2, fontsize=FONT["legend"], frameon=False)
    plain_log_labels(fig)
    return fig


def write(report: dict, out: Path) -> list[Path]:
    """bench.json, bench.md and one work-precision figure per model (PNG and PDF)."""
    import matplotlib

    matplotlib.use("Agg")

    import matplotlib.pyplot as plt

    from .report import signals_deferred, staging_folder, write_folder

    out.parent.mkdir(parents=True, exist_ok=True)
    with staging_folder(out.parent, f"{out.name}.figures") as figures:
        return _write(report, out, figures, plt, write_folder, signals_deferred)


def _write(report: dict, out: Path, figures: Path, plt: Any, write_folder: Callable[..., Path],
           signals_deferred: Callable[[], Any]) -> list[Path]:
    """Draw the figures into ``figures``, then write ``out`` whole (``report.write_folder``: a staging folder
    swapped in, so a full disk or a signal leaves the previous benchmark whole; the user's files kept)."""
    from .report import _DPI, figure_style

    written = [out / "bench.json", out / "bench.md"]
    bench_json = json.dumps(report, indent=1) + "\n"
    lines = ["# Work-precision benchmark", "", f"Timer: {report['timer']}. Machine: {report['machine']}.", ""]
    for mod in report.get("models", []):
        lines += [f"## {mod['model']} ({mod['section']})", "",
                  "| path | kind | reference | scenes/s | floor fraction | N = 1 (µs) | max error where exact | "
                  "median | max error, all scenes | failures |", "|---|---|---|---|---|---|---|---|---|---|"]
        for r in mod["paths"]:
            w, a = r["where_exact"], r["all_scenes"]
            lines.append(f"| {r['path']} | {r['kind']} | {r['reference']} | {r['scenes_per_second']:.3g} | "
                         f"{r['floor_fraction']:.2g} | {_us(r['n1_seconds'])} | {_e(w['max_error'])} | "
                         f"{_e(w['median_error'])} | {_e(a['max_error'])} | {a['failures']} |")
        lines += ["", "ODE path, scipy solvers × tolerances (error against the exact path):", "",
                  "| solver | rtol | seconds per scene | median error | max error | failures |",
                  "|---|---|---|---|---|---|"]
        lines += [f"| {g['solver']} | {g['rtol']:g} | {g['seconds_per_scene']:.3g} | {_e(g['median_error'])} | "
                  f"{_e(g['max_error'])} | {g['failures']} |" for g in mod["ode_grid"]]
        lines += ["", "Pareto verdict (per scene class that auto serves):", ""]
        lines += [f"- {v['auto_path']}, {v['regime']} ({v['scenes']} scenes): {v['verdict']}" for v in mod["pareto"]]
        lines.append("")
        with figure_style():  # the figures' sizes and minus sign, as the experiments' (report.STYLE)
            fig = _work_precision_figure(plt, mod, report["config"]["rtols"])
            with signals_deferred():  # never an interruption inside matplotlib's writers
                for ext in ("png", "pdf"):
                    p = figures / f"work-precision-{mod['model']}.{ext}"
                    fig.savefig(p, dpi=_DPI, metadata={"Software": None} if ext == "png" else
                                {"Creator": None, "Producer": None, "CreationDate": None})
                    written.append(out / p.name)
        plt.close(fig)
    if "direct_impact_ode_tolerances" in report:
        lines += ["## §I: the two-phase contact at a grid of tolerances (DOP853, against eq. 7)", "",
                  "| rtol | seconds per scene | max error | mean nfev |", "|---|---|---|---|"]
        lines += [f"| {r['rtol']:g} | {r['seconds_per_scene']:.3g} | {r['max_error']:.2e} | {r['mean_nfev']:.1f} |"
                  for r in report["direct_impact_ode_tolerances"]]
    if "closed_forms_by_hand" in report:
        lines += ["", "## Closed forms against one hand-written numpy expression of the same formula", "",
                  "| model | path (scenes/s) | by hand (scenes/s) | slowdown |", "|---|---|---|---|"]
        lines += [f"| {r['model']} | {r['path_scenes_per_second']:.3g} | {r['hand_scenes_per_second']:.3g} | "
                  f"{r['slowdown']:.2f}× |" for r in report["closed_forms_by_hand"]]
    if "n1" in report:
        lines += ["", "## One scene (N = 1) through `auto`: where the time goes (µs, minimum over repeats)", "",
                  "`paths.solve(model, model.scene(values), \"auto\")` for the model's defaults and typical "
                  "coefficients; the parts are timed apart, so they add up to the total only to within the timer's "
                  "noise.", "", "| model | path | total | scene | dispatch | physics | result assembly |",
                  "|---|---|---|---|---|---|---|"]
        lines += [f"| {name} | {r['path']} | {r['total']:.3g} | {r['scene']:.3g} | {r['dispatch']:.3g} | "
                  f"{r['physics']:.3g} | {r['assembly']:.3g} |" for name, r in report["n1"].items()]
    if "cloth_kinds" in report:
        from .mechanics.slip import CLASS_MIN

        ck = report["cloth_kinds"]
        rate = ck["scenes_per_second"]
        kinds = ", ".join(f"{m * 1000:g} g with MR²/I = {k:g}" for m, k in ck["kinds"])
        lines += ["", f"## §VI on the cloth: {ck['scenes']:,} scenes through `auto`, three batches timed in turns "
                  f"(the fastest of {ck['repeat']} each)", "",
                  f"The same sampled scenes with the model's k = k′ = 5/2; each ball drawn among {len(ck['kinds'])} "
                  f"kinds ({kinds}: a few classes of the slip decay's c, solved class by class from "
                  f"{2 * CLASS_MIN:,} scenes on); k and k′ uniform "
                  "on 1.5–4 per scene (a table of ₂F₁ coefficients, a column per scene).", "",
                  "| batch | scenes/s | over k = k′ |", "|---|---|---|"]
        for key, what in (("homogeneous", "k = k′ = 5/2"), ("kinds", "balls of a few kinds"),
                          ("per_scene", "k, k′ per scene")):
            lines.append(f"| {what} | {rate[key]:.3g} | {rate[key] / rate['homogeneous']:.3f} |")
    if "fits" in report:
        from .fitbench import markdown as fits_markdown

        lines += ["", *fits_markdown(report["fits"])]
    if "make_all" in report:
        ma = report["make_all"]
        lines += ["", f"## `make all` (`{ma['command']}`), median of {ma['repeat']} runs", "",
                  "| run | wall (s) | CPU (s) | each run, wall (s) |", "|---|---|---|---|"]
        for what in ("cold", "cached"):
            each = ", ".join(f"{r['wall']:.2f}" for r in ma[what]["runs"])
            lines.append(f"| {what} | {ma[what]['median_wall']:.2f} | {ma[what]['median_cpu']:.2f} | {each} |")
    if "ode_sweeps" in report:
        sw = report["ode_sweeps"]
        lines += ["", f"## The ODE part: {sw['executor']}, {sw['workers']} worker(s), {sw['wall_seconds']:.3g} s", "",
                  "| kind | scenes | seconds of work | scenes/s per worker |", "|---|---|---|---|"]
        lines += [f"| {kind} | {t['scenes']} | {t['seconds']:.3g} | {t['scenes_per_second_per_worker']:.3g} |"
                  for kind, t in sw["throughput"].items()]
    if "targets" in report:
        from .targets import to_markdown

        lines += ["", *to_markdown(report["targets"], report.get("calibration"), report.get("pooltool"))]
    write_folder(out, {"bench.json": bench_json, "bench.md": "\n".join(lines) + "\n"}, moved=figures)
    return written


def main(argv: list[str]) -> int:
    rep = run(quick="--quick" in argv, progress=lambda s: print(s, file=sys.stderr))
    write(rep, Path("results") / "bench")
    print((Path("results") / "bench" / "bench.md").read_text(encoding="utf-8"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
