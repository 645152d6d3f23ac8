"""``resal bench``: the work-precision benchmark of every model × path."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer
from rich.text import Text

from cli.app import app
from cli.common import (
    _count,
    _fail,
    _known_models,
    _out_folder,
    _print_grouped,
    _write_report,
    err_console,
    out_console,
)
from reproductions.errors import InputError

MAX_JOBS = 256  # as `reproduce --jobs` and `stress --jobs`: a pool forks all its workers at once


def _micro(us: float) -> str:
    """Microseconds in at most 6 characters: 3 significant digits below 1000 (52.9), whole numbers with a thin
    group above (5 070), never an exponent (a referee's milliseconds widened the column past 80)."""
    return f"{us:.3g}" if us < 1000 else f"{us:,.0f}".replace(",", "\u2009")


@app.command()
def bench(
    models: Annotated[list[str] | None, typer.Argument(help="models (default: all; see simulate --list)")] = None,
    quick: Annotated[bool, typer.Option("--quick", help="small batches: a check that ends in seconds")] = False,
    out: Annotated[Path, typer.Option("--out", help="folder for bench.json, bench.md, figures",
                                      parser=_out_folder)] = Path("results/bench"),
    jobs: Annotated[int | None, typer.Option(help=f"processes for the ODE part, 1 to {MAX_JOBS} (default: one per "
                                                  "core; 1: this one)",
                                             parser=_count("--jobs", 1, MAX_JOBS, "a number of processes"))] = None,
    scheduler: Annotated[str | None, typer.Option(help="run the ODE part on this Dask scheduler (tcp://host:port; "
                                                       "pip install 'resal[cluster]')")] = None,
) -> None:
    """Benchmark every model × path: time per scene against error.

    \b
    Examples:
      resal bench wall-impact --quick
      resal bench direct-impact cue-stroke --quick --out bench-two
      resal bench --quick
      resal bench fit --quick

    The work-precision benchmark: scenes per second and the error where a path declares itself exact, for every
    path of every model, and auto's Pareto verdict (wrong if another exact path is faster and as accurate).
    `fit` times `resal fit` on large files of each kind (100 rows with --quick; 1000 and 10 000 without; a fresh
    process each, with its peak memory); the full benchmark includes it. Without --quick it takes minutes.
    The ODE paths and referees run first, one process per core (--jobs) or on a Dask cluster (--scheduler): their
    scenes per second are per worker; the closed forms are then timed alone, in this process.
    """
    from rich.progress import Progress

    from reproductions import bench as bench_mod
    from reproductions.mechanics import registry

    names = _known_models(models, extra=(bench_mod.FITS,))
    models_run, fits = bench_mod.selection(names, quick)
    total = sum(len(registry.MODELS[m].paths) + 1 for m in models_run)
    if fits:
        from reproductions.fitbench import steps

        total += steps(quick)
    try:
        from reproductions.report import ensure_writable

        ensure_writable(out)  # before minutes of work
    except InputError as err:
        _fail(err)
    with Progress(console=err_console, transient=True, disable=not err_console.is_terminal) as bar:
        task = bar.add_task("benchmark", total=total)

        def step(what: str) -> None:
            bar.update(task, advance=1, description=what)

        try:
            rep = bench_mod.run(names, quick=quick, progress=step, jobs=jobs, scheduler=scheduler)
        except InputError as err:
            _fail(err)
    written = _write_report(bench_mod.write, rep, out, "benchmark")
    groups = []
    for mod in rep["models"]:
        wrong = [v for v in mod["pareto"] if v["faster_and_as_accurate"]]
        rows = []
        for r in mod["paths"]:
            e = r["where_exact"]["max_error"]
            n1 = r.get("n1_seconds")
            rows.append(([r["path"], r["kind"], f"{r['scenes_per_second']:.3g}",
                          "—" if n1 is None or not math.isfinite(n1) else _micro(n1 * 1e6),
                          "—" if e is None else f"{e:.2e}",
                          ("wrong" if wrong else "right") if r["path"] == "auto" else ""], ""))
        groups.append((mod["model"], rows))
    _print_grouped("work-precision: scenes per second in a batch; µs for one scene (N = 1); max error where the "
                   "path declares itself exact; auto: wrong if another exact path is faster and as accurate",
                   ("model / path", "kind", "scenes/s", "N=1 µs", "max error", "auto"), groups, right=(2, 3, 4))
    if "make_all" in rep:
        ma = rep["make_all"]
        out_console.print(f"make all (reproduce --all), median of {ma['repeat']}: {ma['cold']['median_wall']:.2f} s "
                          f"recomputing everything, {ma['cached']['median_wall']:.2f} s with nothing changed",
                          highlight=False)
    if "targets" in rep:
        from reproductions.targets import terminal_lines

        out_console.print()
        for ln in terminal_lines(rep["targets"], rep.get("calibration")):
            out_console.print(Text(ln), highlight=False, soft_wrap=True)
    err_console.print(f"wrote {', '.join(str(p) for p in written[:2])} and {len(written) - 2} figure files")
