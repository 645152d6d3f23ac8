"""``resal stress``: every model × path over random scenes beyond the physical range; exit 1 on any failure."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from cli.app import app
from cli.common import _count, _fail, _known_models, _out_folder, _print_grouped, _write_report, err_console
from reproductions.errors import InputError

MAX_JOBS = 256  # as `reproduce --jobs`: a pool forks all its workers at once, so a typo must not fork thousands


@app.command()
def stress(
    models: Annotated[list[str] | None, typer.Argument(help="models (default: all; see simulate --list)")] = None,
    scenes: Annotated[int, typer.Option(help="random scenes per closed-form and exact path",
                                        parser=_count("--scenes", 1, 50_000_000))] = 1_000_000,
    ode_scenes: Annotated[int, typer.Option(help="scenes per ODE path (each one integrated)",
                                            parser=_count("--ode-scenes", 1, 100_000))] = 150,
    referee_scenes: Annotated[int | None, typer.Option(help="scenes per referee (each integrated; every exact path "
                                                            "is judged against them) [default: 1000, at most "
                                                            "--scenes]",
                                                       show_default=False,
                                                       parser=_count("--referee-scenes", 1, 100_000))] = None,
    seed: Annotated[int, typer.Option(help="seed of the random scenes", parser=_count("--seed", 0, 2**63 - 1))] = 12,
    out: Annotated[Path, typer.Option("--out", help="folder for stress.json and stress.md",
                                      parser=_out_folder)] = Path("results/stress"),
    jobs: Annotated[int | None, typer.Option(help=f"processes, 1 to {MAX_JOBS} (default: one per core; 1: this one)",
                                             parser=_count("--jobs", 1, MAX_JOBS, "a number of processes"))] = None,
    scheduler: Annotated[str | None, typer.Option(help="run the chunks on this Dask scheduler (tcp://host:port; "
                                                       "pip install 'resal[cluster]')")] = None,
) -> None:
    """Stress every model × path over random, extreme scenes.

    \b
    Examples:
      resal stress wall-impact --scenes 10000 --ode-scenes 10 --referee-scenes 10
      resal stress --scenes 1000 --ode-scenes 2 --referee-scenes 2

    Every path of every model (or of the models named) runs on random scenes, the physical range and beyond;
    exit status 1 on any failure. The defaults take minutes. The scenes run in chunks on one process per core
    (--jobs), or on a Dask cluster (--scheduler); the same seed gives the same report, but for its timings.
    """
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from reproductions import stress as stress_mod
    from reproductions.mechanics import registry

    names = _known_models(models)
    todo = names or list(registry.MODELS)
    try:
        from reproductions.report import ensure_writable

        ensure_writable(out)  # before minutes of work
    except InputError as err:
        _fail(err)
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=err_console, transient=True, disable=not err_console.is_terminal) as bar:
        task = bar.add_task("stress", total=len(todo) * scenes)

        def step(model: str, k: int) -> None:
            bar.update(task, advance=k, description=f"stress: {model}")

        try:
            rep = stress_mod.run(names, scenes=scenes, ode_scenes=ode_scenes, seed=seed, progress=step,
                                 referee_scenes=referee_scenes, jobs=jobs, scheduler=scheduler)
        except InputError as err:
            _fail(err)
    written = _write_report(stress_mod.write, rep, out, "stress report")
    groups = []
    for mod in rep["models"]:
        rows = []
        for r in mod["rows"]:
            failures = ", ".join(f"{k} in {v:,}" for k, v in r["failures"].items())
            findings = ", ".join(f"{k} in {v['scenes']:,}" for k, v in r["findings"].items())
            note = "; ".join(x for x in (f"failures: {failures}" if failures else "",
                                          f"findings: {findings}" if findings else "") if x)
            rows.append(([r["path"], r["kind"], f"{r['scenes']:,}", str(sum(r["failures"].values()))], note))
        groups.append((mod["model"], rows))
    _print_grouped(f"stress: {rep['verdict']} ({rep['failures']} failure(s)); failures and findings (in how many "
                   "scenes) under their path", ("model / path", "kind", "scenes", "failures"), groups, right=(2, 3))
    err_console.print(f"wrote {', '.join(str(p) for p in written)}")
    if rep["failures"]:
        raise typer.Exit(1)
