"""``resal``: list, reproduce and simulate. Parses arguments, calls one library function, renders.

Heavy imports (numpy, scipy, matplotlib) happen inside the commands, so ``resal --help`` stays fast.
Bad input of any kind ends with one message on stderr and exit status 2; `reproduce` interrupted by SIGTERM or
SIGINT stops its workers, removes its staging folders and exits with 128 + the signal (143, 130).
"""

from __future__ import annotations

import json
import math
import os
import shutil
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any, NoReturn

import typer
from rich.console import Console
from rich.table import Table
from rich.text import Text

from reproductions.errors import ComputationError, InputError, Interrupted

# plain help (no rich markup): typer then skips its rich formatting imports, and `resal --help` stays under 0.3 s
app = typer.Typer(add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False, rich_markup_mode=None,
                  help="Reproduce H. Résal (1883), 'Commentaire à la théorie mathématique du jeu de billard'.")
out_console = Console()
err_console = Console(stderr=True)
VERDICT_STYLE = {"reproduced": "green", "differs": "bold red", "not-checkable": "yellow"}


MAX_RADIUS = 1.0  # m: `resal fit ricochet --R`; a radius in millimetres (30.5) is refused, not read as 30 m


def _json(obj: Any) -> str:
    """Strict JSON (no NaN or Infinity, which are not JSON): a non-finite number is a bug, so it raises."""
    return json.dumps(obj, indent=2, ensure_ascii=False, allow_nan=False)


def _fail(err: InputError) -> NoReturn:
    """One message on stderr; exit 2 for bad input, 1 for a computation that failed on valid input."""
    err_console.print(Text("error: ", style="bold red") + Text(str(err)))
    raise typer.Exit(1 if isinstance(err, ComputationError) else 2)


MAX_JOBS = 256  # `reproduce --jobs`: a pool forks all its workers at once, so a typo must not fork thousands


def _out_folder(text: str | Path) -> Path:
    """``--out``: a folder; an empty text (which would mean the current folder) is refused."""
    text = str(text)  # typer hands a default Path through the parser too
    if not text.strip():
        _fail(InputError(f"--out '{text}'", "expected a folder (an empty name would write into the current "
                                            "folder; say --out . if that is what you mean)"))
    return Path(text)


def _count(name: str, lo: int, hi: int, what: str = "") -> Callable[[str], int]:
    """A parser of option ``name``: a whole number in [lo, hi] (every count that sizes work has a bound)."""
    def parse(text: str) -> int:
        try:
            n = int(text)
        except ValueError:
            n = None
        if n is None or not lo <= n <= hi:
            _fail(InputError(f"{name} {text}", f"expected {what + ', ' if what else ''}a whole number in "
                                               f"[{lo:,}, {hi:,}]"))
        return n
    return parse


@app.command("list")
def list_cmd() -> None:
    """List every experiment: id, section, title, kind."""
    from reproductions import api

    try:
        exps = api.list_experiments()
    except InputError as err:
        _fail(err)
    t = Table(title=f"experiments in {api.config_dir()}")
    for c in ("id", "section", "title", "kind"):
        t.add_column(c)
    for e in exps:
        t.add_row(e.id, e.source.section, e.title, e.kind)
    out_console.print(t)


def _render(s: dict[str, Any]) -> None:
    """One experiment's full table (every row) and its fits."""
    from reproductions.report import HEADERS, row_cells

    t = Table(title=f"{s['experiment']}: {s['title']}", show_lines=True, title_justify="left")
    for h in HEADERS:
        t.add_column(h, overflow="fold", max_width=60 if h == "note" else None)
    for r in s["rows"]:
        t.add_row(*(Text(c, style=VERDICT_STYLE.get(r["verdict"], "")) if h == "verdict" else Text(c)
                    for h, c in zip(HEADERS, row_cells(r), strict=True)))
    out_console.print(t)
    if s["fits"]:
        out_console.print(_fits_table(s["fits"], "fits"))


def _render_summary(summaries: list[dict[str, Any]], folders: list[Path]) -> None:
    """Several experiments: one line each (its verdict counts and its folder), then the totals with the reasons
    of the differing rows. Lines are not folded, so that they stay greppable."""
    from reproductions.report import VERDICTS, verdict_counts

    width = max([5, *(len(s["experiment"]) for s in summaries)])

    def counts_text(rows: list[dict[str, Any]]) -> Text:
        counts, _ = verdict_counts(rows)
        text = Text()
        for v in VERDICTS:
            text.append(f"{counts[v]:>4} ", style=VERDICT_STYLE[v] if counts[v] else "")
            text.append(f"{v}  ")
        return text

    for s, folder in zip(summaries, folders, strict=True):
        out_console.print(Text(f"{s['experiment']:<{width}} ") + counts_text(s["rows"]) + Text(str(folder)),
                          soft_wrap=True, highlight=False)
    rows = [r for s in summaries for r in s["rows"]]
    _, why = verdict_counts(rows)
    reasons = ("; differing: " + ", ".join(f"{k} {n}" for k, n in why.items())) if why else ""
    out_console.print(Text(f"{'total':<{width}} ", style="bold") + counts_text(rows) +
                      Text(f"({len(rows)} rows{reasons})"), soft_wrap=True, highlight=False)


@app.command()
def reproduce(
    experiments: Annotated[list[str] | None, typer.Argument(help="experiment ids or YAML paths")] = None,
    all_: Annotated[bool, typer.Option("--all", help="every experiment in configs/")] = False,
    as_json: Annotated[bool, typer.Option("--json", help="print summary.json on stdout instead of tables")] = False,
    out: Annotated[Path, typer.Option("--out", help="results folder", parser=_out_folder)] = Path("results"),
    jobs: Annotated[int | None, typer.Option(help=f"processes, 1 to {MAX_JOBS} (default: one per core)",
                                             parser=_count("--jobs", 1, MAX_JOBS, "a number of processes"))] = None,
    verbose: Annotated[bool, typer.Option("--verbose", "-v", help="print every experiment's full table (one "
                                                                  "experiment always does)")] = False,
) -> None:
    """Run experiments, compare every printed value, write tables and figures into OUT/<experiment>/ and the
    paper's index, table and report.pdf into OUT. One experiment prints its full table; several, a summary."""
    from reproductions import api, report

    folders: list[Path] = []
    try:
        with api.interruptible():
            names = list(experiments or [])
            if all_:
                names += [i for i in api.experiment_ids() if i not in names]
            if not names:
                raise InputError("arguments", "name an experiment id, a YAML path, or use --all")
            exps = [api.load(n) for n in names]  # validate everything before running or writing anything
            seen: dict[str, str] = {}
            for n, e in zip(names, exps, strict=True):
                if e.id in seen:
                    raise InputError(n, f"experiment id '{e.id}' is also the id of {seen[e.id]}: both would "
                                        f"write {out / e.id}")
                seen[e.id] = n
            report.ensure_writable(out)
            report.clean_stale(out)  # what a killed run (SIGKILL) of ours left behind
            jobs = max(1, jobs if jobs is not None else min(os.cpu_count() or 1, len(exps)))
            with err_console.status("") as status:
                # run all first: a bad data file stops everything before anything is written; figures are drawn
                # one by one across the processes as their experiment finishes, into a scratch folder
                scratch = None
                try:
                    scratch = report.make_staging(out, "figures")
                    reps = api.run_and_draw(exps, jobs, scratch, status.update)
                    for r in reps:
                        api.checkpoint()
                        folders.append(report.write_reproduction(r, out, drawn=scratch / r.experiment.id))
                finally:
                    if scratch is not None:
                        shutil.rmtree(scratch, ignore_errors=True)
                summaries = [json.loads((f / "summary.json").read_text(encoding="utf-8")) for f in folders]
                report.write_index(out)
    except InputError as err:
        _fail(err)
    except OSError as err:
        _fail(InputError(f"--out {out}", f"cannot write results ({err.strerror or err})"))
    except Interrupted as exc:
        done = (f"{out}: {len(folders)} experiment folder(s) replaced whole, nothing else changed" if folders
                else f"{out} left as it was")
        err_console.print(Text("error: ", style="bold red") + Text(f"interrupted ({exc.name}); {done}"),
                          soft_wrap=True)
        _exit_now(128 + exc.signum)
    if as_json:
        obj = summaries[0] if len(summaries) == 1 else summaries
        typer.echo(_json(obj))
        return
    if verbose or len(summaries) == 1:
        for s in summaries:
            _render(s)
    else:
        _render_summary(summaries, folders)
    err_console.print(f"wrote {len(summaries)} experiment(s), {out / 'index.md'}, "
                      f"{out / 'paper-table'}.{{md,csv,tex}} and {out / 'report.pdf'}", soft_wrap=True)


@app.command()
def simulate(
    model: Annotated[str | None, typer.Argument(help="model name; see --list")] = None,
    set_: Annotated[list[str] | None, typer.Option("--set", help="name=value: SI units, angles in degrees, "
                                                                  "vectors as x,y,z")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object")] = False,
    list_: Annotated[bool, typer.Option("--list", help="list the models, their parameters and paths")] = False,
    method: Annotated[str, typer.Option(help="solution path: auto (the cheapest exact one for the scene) or a "
                                             "path of the model (see --list)")] = "auto",
) -> None:
    """Run one scene of a mechanics model and print its outputs."""
    from reproductions.models import list_models
    from reproductions.models import simulate as run_scene

    if list_:
        info = list_models()
        if as_json:
            typer.echo(_json(info))
            return
        t = Table(title=f"models ({info['units']})")
        for c in ("model", "what", "parameters (default; * must be given)", "paths (cost)"):
            t.add_column(c, overflow="fold")
        for m in info["models"]:
            params = ", ".join(f"{p['name']}*" if p["required"] else
                               f"{p['name']}={p['default']:g}" if not p["vector"] else f"{p['name']}={p['default']}"
                               for p in m["parameters"])
            t.add_row(m["model"], f"{m['doc']} ({m['section']})", params,
                      ", ".join(f"{p['name']} ({p['cost']})" for p in m["paths"]))
        out_console.print(t)
        return
    try:
        if model is None:
            raise InputError("arguments", "name a model (see resal simulate --list)")
        result = run_scene(model, list(set_ or []), method)
    except InputError as err:
        _fail(err)
    if as_json:
        typer.echo(_json(result))
        return
    t = Table(title=f"{result['model']}: {result['label']} (path {result['path_name']}, "
                    f"regime {result['regime_name']})")
    t.add_column("name")
    t.add_column("value")
    for k, v in result["inputs"].items():
        t.add_row(f"in  {k}", ", ".join(f"{x:.10g}" for x in v) if isinstance(v, list) else f"{v:.10g}")
    for k, v in result["outputs"].items():
        if isinstance(v, list):
            text = ", ".join(f"{x:.6g}" if isinstance(x, float) else str(x) for x in _flat(v))
        else:
            text = f"{v:.10g}" if isinstance(v, float) else str(v)
        t.add_row(f"out {k}", Text(text))
    out_console.print(t)


def _flat(v: list[Any]) -> list[Any]:
    return [y for x in v for y in (_flat(x) if isinstance(x, list) else [x])]


def _fits_table(fits: list[dict[str, Any]], title: str) -> Table:
    f = Table(title=title, title_justify="left")
    for h in ("parameter", "value", "std. error", "95 % interval", "identifiable", "note"):
        f.add_column(h, overflow="fold", max_width=60 if h == "note" else None)
    for x in fits:
        ci = x["ci95"]
        f.add_row(Text(x["parameter"]), "—" if x["value"] is None else f"{x['value']:.6g}",
                  "—" if x["stderr"] is None else f"{x['stderr']:.3g}",
                  "—" if ci[0] is None else f"[{ci[0]:.4g}, {ci[1]:.4g}]", "yes" if x["identifiable"] else "no",
                  Text(x["note"]))
    return f


@app.command()
def fit(
    kind: Annotated[str, typer.Argument(help="rebound (V0,V1 | h0,h1), pendulum (V0,V1,V1p[,M,Mp]), ricochet (x[,t])")],
    csv_file: Annotated[Path, typer.Argument(help="your measurements, a CSV file with a header")],
    M: Annotated[float, typer.Option("--M", help="pendulum: striking mass (kg), if not a column")] = 0.6,
    Mp: Annotated[float, typer.Option("--Mp", help="pendulum: struck mass (kg), if not a column")] = 0.2,
    R: Annotated[float, typer.Option("--R", help="ricochet: ball radius (m)")] = 0.0305,
    sigma: Annotated[float | None, typer.Option(help="known std. dev. of each measurement")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object")] = False,
) -> None:
    """Fit ε or ν, with standard errors, 95 % intervals and what the data determine, from your own CSV."""
    from reproductions.userfit import fit_csv

    try:
        for name, value, what in (("--M", M, "a mass in kg"), ("--Mp", Mp, "a mass in kg"),
                                  ("--sigma", sigma, "a standard deviation")):
            if value is not None and not (math.isfinite(value) and value > 0):
                raise InputError(f"{name} {value:g}", f"expected a positive number ({what}, finite)")
        if not (math.isfinite(R) and 0 < R <= MAX_RADIUS):
            raise InputError(f"--R {R:g}", f"expected a ball radius in metres, in (0, {MAX_RADIUS:g}]")
        result = fit_csv(kind, csv_file, M=M, Mp=Mp, R=R, sigma=sigma)
    except InputError as err:
        _fail(err)
    if as_json:
        typer.echo(_json(result))
        return
    out_console.print(_fits_table(result["fits"], f"{kind}: {result['file']} ({result['n']} rows)"))
    for i in result["identifiability"]:
        sv = ", ".join(f"{v:.3g}" for v in i["singular_values"])
        out_console.print(Text(f"{i['data']}: rank {i['rank']} of {len(i['parameters'])} (singular values {sv})"))


def _known_models(models: list[str] | None) -> list[str]:
    """The models named on the command line (none: all), each a model of the registry."""
    from reproductions.mechanics import registry

    names = list(models or [])
    unknown = [m for m in names if m not in registry.MODELS]
    if unknown:
        _fail(InputError(f"model '{unknown[0]}'", f"unknown model (expected some of: {', '.join(registry.MODELS)})"))
    return names


@app.command()
def bench(
    models: Annotated[list[str] | None, typer.Argument(help="models (default: all; see simulate --list)")] = None,
    quick: Annotated[bool, typer.Option("--quick", help="small batches: a check that ends in seconds")] = False,
    out: Annotated[Path, typer.Option("--out", help="folder for bench.json, bench.md, figures",
                                      parser=_out_folder)] = Path("results/bench"),
) -> None:
    """Work-precision benchmark of every model × path: time per scene against error, and auto's Pareto verdict."""
    from rich.progress import Progress

    from reproductions import bench as bench_mod
    from reproductions.mechanics import registry

    names = _known_models(models)
    total = sum(len(registry.MODELS[m].paths) + 1 for m in (names or registry.MODELS))
    with Progress(console=err_console, transient=True) as bar:
        task = bar.add_task("benchmark", total=total)

        def step(what: str) -> None:
            bar.update(task, advance=1, description=what)

        rep = bench_mod.run(names, quick=quick, progress=step)
    try:
        written = bench_mod.write(rep, out)
    except OSError as err:
        _fail(InputError(f"--out {out}", f"cannot write the benchmark ({err.strerror or err})"))
    t = Table(title="work-precision (scenes per second; max error where the path declares itself exact)")
    for c in ("model", "path", "kind", "scenes/s", "max error", "auto"):
        t.add_column(c)
    for mod in rep["models"]:
        wrong = [v for v in mod["pareto"] if v["faster_and_as_accurate"]]
        for r in mod["paths"]:
            e = r["where_exact"]["max_error"]
            t.add_row(mod["model"], r["path"], r["kind"], f"{r['scenes_per_second']:.3g}",
                      "—" if e is None else f"{e:.2e}", ("wrong" if wrong else "right") if r["path"] == "auto" else "")
    out_console.print(t)
    err_console.print(f"wrote {', '.join(str(p) for p in written[:2])} and {len(written) - 2} figure files")


@app.command()
def stress(
    models: Annotated[list[str] | None, typer.Argument(help="models (default: all; see simulate --list)")] = None,
    scenes: Annotated[int, typer.Option(help="random scenes per closed-form and exact path",
                                        parser=_count("--scenes", 1, 50_000_000))] = 1_000_000,
    ode_scenes: Annotated[int, typer.Option(help="scenes per ODE path (each one integrated)",
                                            parser=_count("--ode-scenes", 1, 100_000))] = 150,
    seed: Annotated[int, typer.Option(help="seed of the random scenes", parser=_count("--seed", 0, 2**63 - 1))] = 12,
    out: Annotated[Path, typer.Option("--out", help="folder for stress.json and stress.md",
                                      parser=_out_folder)] = Path("results/stress"),
) -> None:
    """Stress every model × path over random scenes beyond the physical range; exit 1 on any failure."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from reproductions import stress as stress_mod
    from reproductions.mechanics import registry

    names = _known_models(models)
    todo = names or list(registry.MODELS)
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=err_console, transient=True) as bar:
        task = bar.add_task("stress", total=len(todo) * scenes)

        def step(model: str, k: int) -> None:
            bar.update(task, advance=k, description=f"stress: {model}")

        rep = stress_mod.run(names, scenes=scenes, ode_scenes=ode_scenes, seed=seed, progress=step)
    try:
        written = stress_mod.write(rep, out)
    except OSError as err:
        _fail(InputError(f"--out {out}", f"cannot write the stress report ({err.strerror or err})"))
    t = Table(title=f"stress: {rep['verdict']} ({rep['failures']} failure(s))")
    for c in ("model", "path", "kind", "scenes", "failures", "findings"):
        t.add_column(c)
    for mod in rep["models"]:
        for r in mod["rows"]:
            t.add_row(r["model"], r["path"], r["kind"], f"{r['scenes']:,}",
                      ", ".join(f"{k}: {v}" for k, v in r["failures"].items()) or "none",
                      ", ".join(f"{k}: {v['scenes']:,}" for k, v in r["findings"].items()))
    out_console.print(t)
    err_console.print(f"wrote {', '.join(str(p) for p in written)}")
    if rep["failures"]:
        raise typer.Exit(1)


def _read_summary(path: Path) -> dict[str, Any]:
    f = path / "summary.json" if path.is_dir() else path
    try:
        obj = json.loads(f.read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputError(str(f), f"cannot read ({exc.strerror})") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(str(f), f"not a summary.json file ({exc})") from None
    from reproductions.golden import summary_problem

    problem = summary_problem(obj)
    if problem:
        raise InputError(str(f), f"not a summary.json file: {problem}")
    return obj


@app.command()
def diff(
    a: Annotated[Path, typer.Argument(help="summary.json (or its folder): the reference")],
    b: Annotated[Path, typer.Argument(help="summary.json (or its folder): the one to check")],
    rtol: Annotated[float | None, typer.Option(help="one relative tolerance for every number")] = None,
) -> None:
    """Compare the numbers of two summaries, provenance ignored; exit 1 when they differ."""
    from reproductions import golden

    try:
        if rtol is not None and not (math.isfinite(rtol) and 0 <= rtol < 1):
            raise InputError(f"--rtol {rtol:g}", "expected a relative tolerance in [0, 1)")
        ref, new = _read_summary(a), _read_summary(b)
    except InputError as err:
        _fail(err)
    g = golden.golden_object(ref)
    if rtol is not None:
        for v in g["values"].values():
            v["rtol"] = rtol
    diffs = golden.compare(g, new)
    for d in diffs:
        out_console.print(Text(d))
    if diffs:
        raise typer.Exit(1)
    out_console.print(f"same numbers ({len(g['values'])} quantities)")


_PROCESS = {"own": False}  # True when this module's main() runs the process (not a test's CliRunner)


def _exit_now(code: int) -> NoReturn:
    """End an interrupted run. The cleanup (workers terminated, staging removed) has run; the process pool's
    queue threads may still be blocked on a pipe that no terminated worker will read, and the interpreter's exit
    would join them forever (a SIGTERM run once hung in CI): the process itself exits at once. Under a test's
    CliRunner, an ordinary exit."""
    if _PROCESS["own"]:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    raise typer.Exit(code)


def main() -> None:
    _PROCESS["own"] = True
    app()


if __name__ == "__main__":
    main()
