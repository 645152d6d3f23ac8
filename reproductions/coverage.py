"""Coverage of every interval ``resal fit`` prints, measured: ``python -m reproductions.coverage`` (``make coverage``).

For each kind, at three true values (two near the parameters' bounds, one typical), seeded synthetic series of the
size an experimenter has are written as CSV files and fitted by ``resal fit``'s own code (``fit.run.fit_csv``, every
check included); for each estimate with a printed interval, the fraction of series whose interval holds the value
that generated them. The table is stored in ``reproductions/fit/coverage.json`` (package data): ``resal fit KIND
--help`` and docs/fit.md print it from there, and a test re-runs the first series of each cell to show the table
is the code's as it stands. A series the fit refuses or that gives no interval is counted apart, never as a hit.

Each series' seed is ``SeedSequence([SEED, cell, i])``, so a cell's counts are the same on every machine (an interval
end within rounding of the true value would be needed to move one) and a prefix of the series can be re-run alone.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputError
from .fit.coverage_table import BOOT_B, TABLE, load, markdown
from .fit.estimators.markers import angles
from .fit.estimators.shots import synthetic_shots
from .fit.kinds.common import FitOptions
from .fit.run import fit_csv
from .mechanics import impact, plane

__all__ = ["CELLS", "Cell", "measure", "run_series"]

SEED = 20261206
G = 9.80665


@dataclasses.dataclass(frozen=True)
class Cell:
    """One measured case: ``kind`` fitted on ``series`` synthetic series made by ``make`` at ``truth``; ``boot``
    of them (the first) also with a bootstrap of ``BOOT_B`` resamples."""

    kind: str
    label: str  # the series as people would describe them
    truth: dict[str, float]  # the generating values, by name (for the table)
    make: Callable[[np.random.Generator, dict[str, float]], tuple[str, dict[str, float]]]  # CSV text, true values
    series: int
    boot: int = 0
    options: dict[str, Any] = dataclasses.field(default_factory=dict)


def _csv(header: Sequence[str], *cols: Any) -> str:
    rows = zip(*(np.asarray(c).tolist() for c in cols), strict=True)
    return ",".join(header) + "\n" + "".join(",".join(v if isinstance(v, str) else repr(float(v)) for v in r) + "\n"
                                             for r in rows)


# ---- the kinds' synthetic series -----------------------------------------------------------------------------------
def _rebound(rng: np.random.Generator, p: dict[str, float]) -> tuple[str, dict[str, float]]:
    u0 = rng.uniform(0.5, 4.0, 8)
    u1 = p["e"] * u0 + 0.02 * rng.standard_normal(8)
    return _csv(("u0_mps", "u1_mps"), u0, u1), {"e": p["e"], "eps": impact.eps_from_newton(p["e"])}


def _cushion(rng: np.random.Generator, p: dict[str, float]) -> tuple[str, dict[str, float]]:
    v0 = rng.uniform(0.5, 3.5, 10)
    v1 = -p["e"] * v0 * (1 + 0.02 * rng.standard_normal(10))
    return _csv(("V0_cmps", "V1_cmps"), 100 * v0, 100 * v1), {"e": p["e"], "eps": impact.eps_from_newton(p["e"])}


def _drop(rng: np.random.Generator, p: dict[str, float]) -> tuple[str, dict[str, float]]:
    h0 = rng.uniform(200.0, 1000.0, 8)
    h1 = p["e"] ** 2 * h0 + 2.0 * rng.standard_normal(8)
    return _csv(("h0_mm", "h1_mm"), h0, h1), {"e": p["e"], "eps": impact.eps_from_newton(p["e"])}


PENDULUM_M = (np.repeat([0.6, 0.2], 6), np.full(12, 0.2))  # striker, struck (kg): two mass ratios identify ε and ε′


def _pendulum(rng: np.random.Generator, p: dict[str, float]) -> tuple[str, dict[str, float]]:
    M, Mp = PENDULUM_M
    V0 = rng.uniform(0.5, 2.0, 12)
    r = impact.direct_impact(M, Mp, V0, 0.0, eps=p["eps"], epsp=p["epsp"])
    V1, V1p = (v + 0.005 * rng.standard_normal(12) for v in (r.V1, r.V1p))
    truth = {"pendulum.eps": p["eps"], "pendulum.epsp": p["epsp"]}
    for ratio in (1 / 3, 1.0):  # Newton's e of each mass ratio: (V1′ − V1)/V0 of the noise-free impact
        one = impact.direct_impact(np.array([1.0]), np.array([ratio]), np.array([1.0]), 0.0, eps=p["eps"],
                                   epsp=p["epsp"])
        truth[f"e.ratio{ratio:.6g}"] = float(one.V1p[0] - one.V1[0])
    return _csv(("V0", "V1", "V1p", "M", "Mp"), V0, V1, V1p, M, Mp), truth


RICOCHET_BALL = {"R": 0.0305, "k": 2.5}


def _ricochet(rng: np.random.Generator, p: dict[str, float]) -> tuple[str, dict[str, float]]:
    """8 imprints with their instants, the ivory ball thrown without spin; a0 1.5–2.5 m/s, α0 15–30°, σx 0.3–1 mm,
    σt 0.1–0.5 ms. The fit measures from the first measured imprint and instant, so the origins' true values are
    the first noise-free ones seen from the measured ones."""
    a0, alpha0 = rng.uniform(1.5, 2.5), math.radians(rng.uniform(15.0, 30.0))
    sx, st = rng.uniform(0.3e-3, 1e-3), rng.uniform(0.1e-3, 0.5e-3)
    r = plane.ricochet(a0, alpha0, 0.0, f=p["f"], nu=p["nu"], g=G, n=7, **RICOCHET_BALL)
    x_true = r.imprints[:8]
    t_true = np.concatenate([[0.0], np.cumsum(r.times)])[:8]
    x, t = x_true + sx * rng.standard_normal(8), t_true + st * rng.standard_normal(8)
    truth = {"positions.nu": p["nu"], "positions.A": 2 * a0**2 * math.sin(alpha0) * math.cos(alpha0) / G,
             "positions.u": p["f"] * math.tan(alpha0), "positions.x0": float(x_true[0] - x[0]),
             "times.nu": p["nu"], "times.zeta1": G * float(r.times[0]) / 2, "times.t0": float(t_true[0] - t[0]),
             "joint-physical.f": p["f"]}
    return _csv(("x", "t"), x - x[0], t - t[0]), truth


def _bounces(rng: np.random.Generator, p: dict[str, float]) -> tuple[str, dict[str, float]]:
    """8 clicks of a ball dropped from 0.5 m, 1 ms jitter."""
    h0, n, jitter = 0.5, 8, 1e-3
    fall = math.sqrt(2 * h0 / G)
    T1 = 2 * p["nu"] * fall
    t_true = fall + T1 * (1 - p["nu"] ** np.arange(n)) / (1 - p["nu"])
    t = t_true + jitter * rng.standard_normal(n)
    truth = {"bounces.nu": p["nu"], "bounces.T1": T1, "bounces.t0": float(t_true[0] - t[0])}
    return _csv(("t",), t - t[0]), truth


BALL_R = 0.02855


def _ballball(rng: np.random.Generator, p: dict[str, float]) -> tuple[str, dict[str, float]]:
    """14 shots, 2 % speed noise, 0.5° on directions, the cue ball rolling."""
    c = synthetic_shots(rng, 14, f_bb=p["f"], e=p["e"], R=BALL_R)
    return _csv(("v", "phi", "cue_speed", "cue_dir", "obj_speed", "obj_dir"), c["v"], c["phi"], c["cue_speed"],
                c["cue_dir"], c["obj_speed"], c["obj_dir"]), {"ball-ball.f_bb": p["f"], "ball-ball.e": p["e"]}


def _markers(rng: np.random.Generator, p: dict[str, float]) -> tuple[str, dict[str, float]]:
    """30 markers per series, ψ 8–72°, noise 1.5° on α1 and 0.5° on the throw."""
    rows: list[tuple[str, float, float]] = []
    for s, sd in (("alpha1", 1.5), ("throw", 0.5)):
        psi = np.sort(rng.uniform(8.0, 72.0, 30))
        obs = angles(psi, p["f"], p["e"])[s] + sd * rng.standard_normal(30)
        rows += [(s, float(a), float(b)) for a, b in zip(psi, obs, strict=True)]
    text = "series,psi_deg,angle_deg\n" + "".join(f"{s},{a!r},{b!r}\n" for s, a, b in rows)
    truth = {f"{s}.{q}": p[q] for s in ("joint", "alpha1", "throw") for q in ("f", "e")}
    return text, truth


def _three(kind: str, label: str, make: Callable[..., tuple[str, dict[str, float]]], truths: Sequence[dict],
           series: int, boot: int = 0, **options: Any) -> list[Cell]:
    return [Cell(kind, label, t, make, series, boot, options) for t in truths]


CELLS: tuple[Cell, ...] = tuple([
    *_three("rebound", "8 rebounds, 0.5–4 m/s, noise 0.02 m/s", _rebound,
            [{"e": 0.2}, {"e": 0.8}, {"e": 0.99}], 1000, 300),
    *_three("cushion", "10 signed rebounds in cm/s, 0.5–3.5 m/s, noise 2 %", _cushion,
            [{"e": 0.2}, {"e": 0.75}, {"e": 0.99}], 1000, 300),
    *_three("drop", "8 drops from 0.2–1 m in mm, noise 2 mm", _drop,
            [{"e": 0.3}, {"e": 0.9}, {"e": 0.99}], 1000, 300),
    *_three("pendulum", "12 trials, M′/M = 1/3 and 1, noise 5 mm/s", _pendulum,
            [{"eps": 0.02, "epsp": 0.05}, {"eps": 0.1, "epsp": 0.3}, {"eps": 0.6, "epsp": 0.9}], 1000, 150),
    *_three("ricochet", "8 imprints and instants, σx 0.3–1 mm, σt 0.1–0.5 ms", _ricochet,
            [{"nu": 0.55, "f": 0.05}, {"nu": 0.75, "f": 0.2}, {"nu": 0.95, "f": 0.4}], 400),
    *_three("bounces", "8 clicks from 0.5 m, jitter 1 ms", _bounces,
            [{"nu": 0.5}, {"nu": 0.85}, {"nu": 0.97}], 1000, 100),
    *_three("ball-ball", "14 shots, 2 % on speeds, 0.5° on directions", _ballball,
            [{"f": 0.01, "e": 0.99}, {"f": 0.06, "e": 0.93}, {"f": 0.3, "e": 0.7}], 150, 40, R=BALL_R),
    *_three("markers", "30 markers per series, 1.5° on α1, 0.5° on the throw", _markers,
            [{"f": 0.01, "e": 0.99}, {"f": 0.06, "e": 0.93}, {"f": 0.3, "e": 0.7}], 200),
])


# ---- measuring ----------------------------------------------------------------------------------------------------
def run_series(cell_index: int, i: int, boot: bool, folder: Path) -> dict[str, Any]:
    """Series ``i`` of cell ``cell_index``: per estimate id, whether its 95 % interval (and, with ``boot``, its
    bootstrap interval) holds the true value: 1, 0, or None (no interval given); ``refused`` with the message."""
    cell = CELLS[cell_index]
    rng = np.random.default_rng(np.random.SeedSequence([SEED, cell_index, i]))
    text, truth = cell.make(rng, cell.truth)
    path = folder / f"c{cell_index}-s{i}.csv"
    path.write_text(text, encoding="utf-8")
    opts = FitOptions(resamples=BOOT_B if boot else 0, seed=i, **cell.options)
    try:
        out = fit_csv(cell.kind, path, opts)
    except InputError as err:
        return {"refused": f"{err.where}: {err.message}"}
    finally:
        path.unlink()
    got: dict[str, Any] = {}
    for f in out.summary["fits"]:
        if f["id"] not in truth:
            continue
        v = truth[f["id"]]
        for key, name in (("ci95", "95"), ("ci95_bootstrap", "boot")):
            ci = f.get(key)
            if name == "boot" and not boot:
                continue
            ok = None if ci is None or ci[0] is None or ci[1] is None else int(ci[0] <= v <= ci[1])
            got[f"{f['id']}|{name}"] = ok
    return got


def _chunk(args: tuple[int, int, int, int]) -> list[dict[str, Any]]:
    cell_index, start, stop, boot_n = args
    with tempfile.TemporaryDirectory(prefix="resal-coverage-") as tmp:
        return [run_series(cell_index, i, i < boot_n, Path(tmp)) for i in range(start, stop)]


def measure(cells: Sequence[int] | None = None, workers: int = 2, chunk: int = 25,
            progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """Measure the cells (all by default) on a process pool; the table as stored in ``TABLE``."""
    chosen = list(range(len(CELLS))) if cells is None else list(cells)
    jobs = [(c, s, min(s + chunk, CELLS[c].series), CELLS[c].boot) for c in chosen
            for s in range(0, CELLS[c].series, chunk)]
    results: dict[int, list[dict[str, Any]]] = {c: [] for c in chosen}
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=workers) as pool:
        for done, (job, part) in enumerate(zip(jobs, pool.map(_chunk, jobs), strict=True), 1):
            results[job[0]] += part
            if progress is not None:
                progress(f"coverage: {done}/{len(jobs)} chunks, {time.perf_counter() - t0:.0f} s")
    return {"seed": SEED, "bootstrap_resamples": BOOT_B, "cells": [_tally(c, results[c]) for c in chosen]}


def _tally(cell_index: int, series: list[dict[str, Any]]) -> dict[str, Any]:
    cell = CELLS[cell_index]
    keys = list(dict.fromkeys(k for s in series for k in s if k != "refused"))  # in the order the fit prints
    rows = []
    for key in keys:
        id_, name = key.split("|")
        marks = [s.get(key) for s in series[: cell.boot if name == "boot" else None]]
        given = [m for m in marks if m is not None]
        rows.append({"id": id_, "interval": name, "series": len(marks), "given": len(given), "hits": sum(given),
                     "marks": "".join("-" if m is None else str(m) for m in marks)})
    return {"index": cell_index, "kind": cell.kind, "label": cell.label, "truth": cell.truth,
            "refused": sum("refused" in s for s in series), "rows": rows}


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m reproductions.coverage", description=__doc__.splitlines()[0])
    ap.add_argument("--kind", action="append", help="measure this kind only (repeatable); the others are kept")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=TABLE)
    a = ap.parse_args(argv)
    chosen = [i for i, c in enumerate(CELLS) if a.kind is None or c.kind in a.kind]
    table = measure(chosen, a.workers, progress=lambda m: print(m, file=sys.stderr, flush=True))
    if a.kind is not None and a.out.exists():  # keep the other kinds' cells
        old = {c["index"]: c for c in load(a.out)["cells"] if c["index"] not in chosen}
        table["cells"] = sorted([*old.values(), *table["cells"]], key=lambda c: c["index"])
    a.out.write_text(json.dumps(table, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    print(markdown(table))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
