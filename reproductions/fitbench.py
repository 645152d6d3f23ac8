"""``resal fit`` on large files: time and peak memory per kind and size (a section of ``resal bench``).

Each kind's example file (``examples/``) is replicated to N rows, every value jittered by a relative 1e-4 from a
seeded generator (no two rows alike; the same file on every machine), and fitted by ``fit.run.fit_csv`` (its checks
included, no bootstrap) in a fresh Python process, so that the peak resident memory (``ru_maxrss``) is that fit's:
the process's peak after its imports is reported beside it, and their difference is what the fit itself held.
Sizes stop at what the kind fits in a minute (``Kind.per_minute``); ricochet and bounces series hold tens of rows
(ν^n of a real ball is below any clock's resolution after about fifty impacts), so they are not sized here.
"""

from __future__ import annotations

import json
import os
import random
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

__all__ = ["KINDS", "markdown", "one", "replicate", "run", "sizes", "steps"]

KINDS = ("rebound", "cushion", "drop", "pendulum", "ball-ball", "markers")
OPTIONS = {"ball-ball": {"R": 0.02855}}  # the example file's own line asks for it
SEED = 1


def replicate(kind: str, n: int) -> str:
    """The kind's example file's rows repeated to ``n`` rows, each number times (1 + 1e-4·U(−1, 1))."""
    from .fit.kinds import KINDS as FIT_KINDS
    from .locate import examples_dir
    from .series import read_table

    tab = read_table(examples_dir() / FIT_KINDS[kind].example)
    rows = [cells for _, cells in tab.rows]
    rng = random.Random(SEED)
    out = [tab.head]
    for i in range(n):
        cells = []
        for c in rows[i % len(rows)]:
            try:
                cells.append(f"{float(c) * (1 + 1e-4 * rng.uniform(-1, 1)):.9g}")
            except ValueError:  # a label (the markers' series)
                cells.append(c)
        out.append(",".join(cells))
    return "\n".join(out) + "\n"


def _child(kind: str, path: str) -> None:
    """In the fresh process: import, note the peak, fit, print the figures as JSON."""
    import resource

    from .fit.kinds.common import FitOptions
    from .fit.run import fit_csv
    from .lazy import HEAVY, preload

    preload(*HEAVY)  # imported at first use by the fits: the imports are not the fit's time or memory
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t0 = time.perf_counter()
    fit_csv(kind, Path(path), FitOptions(resamples=0, **OPTIONS.get(kind, {})))
    seconds = time.perf_counter() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(json.dumps({"seconds": seconds, "peak_mb": peak / 1024, "after_imports_mb": base / 1024}))


def one(kind: str, n: int) -> dict[str, Any]:
    """Fit ``n`` replicated rows of ``kind`` in a fresh process: seconds, peak memory, memory after the imports."""
    with tempfile.TemporaryDirectory(prefix="resal-fitbench-") as tmp:
        path = Path(tmp) / f"{kind}-{n}.csv"
        path.write_text(replicate(kind, n), encoding="utf-8")
        env = {**os.environ, "PYTHONWARNINGS": "ignore"}
        r = subprocess.run([sys.executable, "-m", "reproductions.fitbench", kind, str(path)], capture_output=True,
                           text=True, env=env, check=False)
    if r.returncode != 0:
        return {"kind": kind, "rows": n, "error": (r.stderr.strip().splitlines() or ["?"])[-1]}
    got = json.loads(r.stdout.strip().splitlines()[-1])
    return {"kind": kind, "rows": n, **got, "fit_mb": got["peak_mb"] - got["after_imports_mb"]}


def run(sizes: Sequence[int] = (1000, 10_000), kinds: Sequence[str] = KINDS,
        progress: Callable[[str], None] | None = None) -> list[dict[str, Any]]:
    """Every kind at every size it fits within a minute (``Kind.per_minute``)."""
    from .fit.kinds import KINDS as FIT_KINDS

    out = []
    for kind in kinds:
        for n in sizes:
            if n > FIT_KINDS[kind].per_minute:
                continue
            if progress:
                progress(f"resal fit {kind}: {n:,} rows")
            out.append(one(kind, n))
    return out


def sizes(quick: bool) -> tuple[int, ...]:
    return (100,) if quick else (1000, 10_000)


def steps(quick: bool) -> int:
    """How many fits ``run(sizes(quick))`` makes (for a progress bar)."""
    from .fit.kinds import KINDS as FIT_KINDS

    return sum(n <= FIT_KINDS[k].per_minute for k in KINDS for n in sizes(quick))


def markdown(rows: Sequence[dict[str, Any]]) -> list[str]:
    lines = ["## `resal fit` on large files (checks included, no bootstrap; a fresh process each)", "",
             "| kind | rows | seconds | peak memory (MB) | after imports (MB) | the fit's own (MB) |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['kind']} | {r['rows']:,} | failed: {r['error']} | | | |")
        else:
            lines.append(f"| {r['kind']} | {r['rows']:,} | {r['seconds']:.2f} | {r['peak_mb']:.0f} | "
                         f"{r['after_imports_mb']:.0f} | {r['fit_mb']:.0f} |")
    return lines


if __name__ == "__main__":
    _child(sys.argv[1], sys.argv[2])
