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
    err_console.print(Text("error: ", style="bold red") + Text(str(err)), soft_wrap=True)  # one line, unwrapped
    raise typer.Exit(1 if isinstance(err, ComputationError) else 2)


MAX_JOBS = 256  # `reproduce --jobs`: a pool forks all its workers at once, so a typo must not fork thousands


def _out_folder(text: str | Path) -> Path:
    """``--out``: a folder; an empty text (which would mean the current folder) is refused."""
    text = str(text)  # typer hands a default Path through the parser too
    if text.startswith("-"):
        _fail(InputError(f"--out {text}", "expected a folder, got an option (was the folder left out?)"))
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


WIDE_TABLE = 140  # columns: below, a table of many columns folds words mid-word; each row is then a record


def _print_rows(title: str, headers: tuple[str, ...], rows: list[tuple[list[str], str]], lead: tuple[str, ...],
                note_width: int = 60, lines: bool = False) -> None:
    """Rows of cells (each with its style, for the ``verdict`` cell): a table on a wide console; on a narrow one
    (or piped at 80 columns) a record per row, its ``lead`` cells as a heading and the others as ``label: value``
    lines wrapped at words, so that no word is broken."""
    if out_console.width >= WIDE_TABLE:
        t = Table(title=title, show_lines=lines, title_justify="left")
        for h in headers:
            t.add_column(h, overflow="fold", max_width=note_width if h == "note" else None)
        for cells, style in rows:
            t.add_row(*(Text(c, style=style if h == "verdict" else "") for h, c in zip(headers, cells, strict=True)))
        out_console.print(t)
        return
    out_console.print(Text(title, style="bold"))
    for cells, style in rows:
        by = dict(zip(headers, cells, strict=True))
        head = Text()
        for h in lead:
            head += Text(f"[{by[h]}] ", style=style) if h == "verdict" else Text(by[h], style="bold")
        out_console.print()
        out_console.print(head)
        grid = Table.grid(padding=(0, 1))
        grid.add_column(style="dim", no_wrap=True)
        grid.add_column(overflow="fold")
        for h in headers:
            if h not in lead and by[h]:
                grid.add_row(f"  {h}", Text(by[h]))
        out_console.print(grid)


def _render(s: dict[str, Any]) -> None:
    """One experiment's full table (every row) and its fits."""
    from reproductions.report import HEADERS, row_cells

    _print_rows(f"{s['experiment']}: {s['title']}", HEADERS,
                [(row_cells(r), VERDICT_STYLE.get(r["verdict"], "")) for r in s["rows"]], ("verdict", "quantity"),
                lines=True)
    if s["fits"]:
        out_console.print()
        _print_fits(s["fits"], "fits")


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
    paper's index, table, reader's edition (index.html) and report.pdf into OUT. One experiment prints its full
    table; several, a summary."""
    from reproductions import api, edition, report

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
                edition.write_index(out)
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
    err_console.print(f"wrote {len(summaries)} experiment(s) and the reader's edition {out / 'index.html'} (on "
                      f"paper: {out / 'report.pdf'}), with {out / 'index.md'} and "
                      f"{out / 'paper-table'}.{{md,csv,tex}}", soft_wrap=True)


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


def _print_fits(fits: list[dict[str, Any]], title: str) -> None:
    rows = []
    for x in fits:
        ci = x["ci95"]
        rows.append(([x["parameter"], "—" if x["value"] is None else f"{x['value']:.6g}",
                      "—" if x["stderr"] is None else f"{x['stderr']:.3g}",
                      "—" if ci[0] is None else f"[{ci[0]:.4g}, {ci[1]:.4g}]", "yes" if x["identifiable"] else "no",
                      x["note"]], ""))
    _print_rows(title, ("parameter", "value", "std. error", "95 % interval", "identifiable", "note"), rows,
                ("parameter",))


# ---- resal fit <kind> ----------------------------------------------------------------------------------------
class _FitGroup(typer.core.TyperGroup):
    """`resal fit <kind>`: an unknown kind gets our one-line message, not click's usage screen."""

    def resolve_command(self, ctx: Any, args: list[str]) -> Any:
        from reproductions.fit.kinds import KINDS

        if args and not args[0].startswith("-") and args[0] not in KINDS:
            _fail(InputError(f"kind '{args[0]}'", f"expected one of {', '.join(KINDS)}"))
        return super().resolve_command(ctx, args)


class _FitCommand(typer.core.TyperCommand):
    """`resal fit <kind>`: an option that this kind does not take gets one line saying so and what it takes."""

    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:
        given = list(args)  # click consumes the list
        try:
            return super().parse_args(ctx, args)
        except Exception as exc:  # click's NoSuchOption (typer vendors click in recent versions: matched by name)
            if type(exc).__name__ != "NoSuchOption":
                if hasattr(exc, "format_message") and hasattr(exc, "exit_code"):  # any other usage error
                    _fail(InputError(f"resal fit {self.name}", f"{exc.format_message()} (see resal fit "
                                                              f"{self.name} --help)"))
                raise
            takes = ", ".join(sorted(o for p in self.params for o in p.opts if o.startswith("--") and o != "--help"))
            why = ("not used by the ricochet fit, which estimates the noise of positions and instants from their "
                   "residuals: leave it out" if self.name == "ricochet" and exc.option_name == "--sigma" else
                   f"not an option of `resal fit {self.name}`")
            where = exc.option_name
            at = given.index(where) if where in given else -1
            if 0 <= at < len(given) - 1 and not given[at + 1].startswith("--"):
                where = f"{where} {given[at + 1]}"
            _fail(InputError(where, f"{why} (it takes {takes})"))


fit_app = typer.Typer(cls=_FitGroup, no_args_is_help=True, rich_markup_mode=None,
                      help="Fit the paper's coefficients to your own measurements (a CSV file): `resal fit <kind> "
                           "data.csv`; `resal fit <kind> --help` gives that kind's columns and an example.")
app.add_typer(fit_app, name="fit")

_NOISES = ("auto", "constant", "proportional")


def _positive(name: str, what: str) -> Callable[[str], float]:
    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            v = math.nan
        if not (math.isfinite(v) and v > 0):
            _fail(InputError(f"{name} {text}", f"expected a positive number ({what}, finite)"))
        return v
    return parse


K_MIN = 1.5  # MR²/I of a sphere: a thin shell's 1.5 is the least any spherically symmetric ball can have


def _k_ratio(text: str) -> float:
    """--k, MR²/I: at least 1.5 (a thin shell; a homogeneous ball 2.5); 0.4 is I/MR², the other convention."""
    v = _positive("--k", "MR²/I, 2.5 for a solid ball")(text)
    if v < K_MIN:
        hint = f" (--k {1 / v:.3g}?)" if 1 / v >= K_MIN else ""
        _fail(InputError(f"--k {text}", f"expected MR²/I ≥ {K_MIN:g} (a thin shell; a solid ball 2.5): {text} reads "
                                        f"as I/MR², the inverse convention{hint}"))
    return v


def _choice(name: str, choices: tuple[str, ...]) -> Callable[[str], str]:
    def parse(text: str) -> str:
        if text not in choices:
            _fail(InputError(f"{name} {text}", f"expected one of {', '.join(choices)}"))
        return text
    return parse


def _fit_options() -> dict[str, tuple[Any, Any]]:
    """Every option a kind may take: name → (annotation, default)."""
    from reproductions.fit import kinds as fitkinds

    return {
        "sigma": (Annotated[float | None, typer.Option(
            "--sigma", parser=_positive("--sigma", "a standard deviation"),
            help="known standard deviation of each measured outcome (V1, h1, V1p, the clicks t…), in the data's own "
                 "unit as the header gives it (V1_cmps: cm/s; no unit: SI)")], None),
        "sigma_in": (Annotated[float | None, typer.Option(
            "--sigma-in", parser=_positive("--sigma-in", "a standard deviation"),
            help="known standard deviation of each measured impact (V0, u0 or h0), in its column's unit as the "
                 "header gives it: the fit then takes errors in both variables (effective variance); without "
                 "--sigma the outcome's σ is estimated")], None),
        "noise": (Annotated[str, typer.Option(
            "--noise", parser=_choice("--noise", _NOISES),
            help="how the outcome scatters: constant, proportional (to the impact), or auto (the likelier of the "
                 "two, by the data); not with --sigma, which gives it")], "auto"),
        "speeds": (Annotated[str | None, typer.Option(
            "--speeds", parser=_choice("--speeds", ("signed", "unsigned")),
            help="read V0,V1 as signed velocities (V1 ≤ 0, the default) or as unsigned speeds")], None),
        "g": (Annotated[float, typer.Option("--g", parser=_positive("--g", "gravity in m/s²"),
                                            help="gravity (m/s²)")], 9.80665),
        "M": (Annotated[float | None, typer.Option("--M", parser=_positive("--M", "a mass in kg"),
                                                   help="striking mass (kg), if not a column")], None),
        "Mp": (Annotated[float | None, typer.Option("--Mp", parser=_positive("--Mp", "a mass in kg"),
                                                    help="struck mass (kg), if not a column")], None),
        "R": (Annotated[float, typer.Option("--R", parser=_radius, help="ball radius (m)")], 0.0305),
        "k": (Annotated[float, typer.Option("--k", parser=_k_ratio,
                                            help="MR²/I of the ball (2.5: homogeneous sphere)")], 2.5),
        "h0": (Annotated[float | None, typer.Option("--h0", parser=_positive("--h0", "a height in m"),
                                                    help="drop height (m), released at rest: then g is fitted too")],
               None),
        "sigma_speed": (Annotated[float | None, typer.Option(
            "--sigma-speed", parser=_positive("--sigma-speed", "a relative standard deviation"),
            help="ball-ball: known relative standard deviation of the measured speeds (0.02 = 2 %)")], None),
        "sigma_dir": (Annotated[float | None, typer.Option(
            "--sigma-dir", parser=_positive("--sigma-dir", "a standard deviation of an angle"),
            help="ball-ball: known standard deviation of the measured directions, in their column's unit")], None),
        "max_seconds": (Annotated[float, typer.Option(
            "--max-seconds", parser=_positive("--max-seconds", "a time in seconds"),
            help="bound on the fit's wall-clock time, its refits included: past it the fit stops with a message "
                 "(exit 1) and writes nothing")], 120.0),
        "bootstrap": (Annotated[int, typer.Option(
            "--bootstrap", parser=_count("--bootstrap", 0, fitkinds.MAX_RESAMPLES, "a number of resamples"),
            help="bootstrap resamples, each refitted (0: none)")], 1000),
    }


def _radius(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    if not (math.isfinite(v) and 0 < v <= MAX_RADIUS):
        _fail(InputError(f"--R {text}", f"expected a ball radius in metres, in (0, {MAX_RADIUS:g}]"))
    return v


def _fit_command(name: str) -> None:
    """Register `resal fit <name>`, with the options its kind declares."""
    import inspect

    from reproductions.fit.kinds import KINDS, UNITS_HELP

    kind = KINDS[name]
    P = inspect.Parameter
    params = [
        P("csv_file", P.POSITIONAL_OR_KEYWORD,
          annotation=Annotated[Path, typer.Argument(metavar="DATA.csv",
                                                  help="your measurements, a CSV file with a header")]),
        P("out", P.KEYWORD_ONLY, default=None, annotation=Annotated[Path | None, typer.Option(
            "--out", parser=_out_folder, help=f"folder for fit.json, fit.md, residuals.csv and the figures "
                                              f"(default results/fit/{name}-<file name>)")]),
        P("as_json", P.KEYWORD_ONLY, default=False,
          annotation=Annotated[bool, typer.Option("--json", help="print fit.json on stdout")]),
        P("plot", P.KEYWORD_ONLY, default=True,
          annotation=Annotated[bool, typer.Option("--plot/--no-plot", help="draw the figures (PNG and PDF)")]),
        P("seed", P.KEYWORD_ONLY, default=0, annotation=Annotated[int, typer.Option(
            "--seed", parser=_count("--seed", 0, 2**32 - 1, "a seed"), help="seed of the bootstrap")]),
        P("strict", P.KEYWORD_ONLY, default=False, annotation=Annotated[bool, typer.Option(
            "--strict", help="exit with status 1 when the fit warns of anything (the files are still written)")]),
    ]
    defs = _fit_options()
    for opt in kind.options:
        ann, default = defs[opt]
        params.append(P(opt, P.KEYWORD_ONLY, default=default, annotation=ann))

    def command(**kw: Any) -> None:
        _run_fit(name, kw)

    command.__signature__ = inspect.Signature(params)  # type: ignore[attr-defined]
    command.__doc__ = kind.title
    epilog = (f"Columns: {kind.columns} {UNITS_HELP} Example: resal fit {name} examples/{kind.example} "
              "(synthetic data, labelled so).")
    fit_app.command(name, cls=_FitCommand, help=f"{kind.title}.", epilog=epilog)(command)


def _run_fit(name: str, kw: dict[str, Any]) -> None:
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn

    from reproductions.fit.estimators.trials import Noise
    from reproductions.fit.report import provenance, write_fit
    from reproductions.fit.run import FitOptions, fit_csv

    csv_file: Path = kw.pop("csv_file")
    out = kw.pop("out") or Path("results") / "fit" / f"{name}-{csv_file.stem}"
    as_json, plot, seed, strict = kw.pop("as_json"), kw.pop("plot"), kw.pop("seed"), kw.pop("strict")
    resamples = kw.pop("bootstrap", 0)
    noise = Noise(kw.pop("noise", "auto"))
    try:
        _check_fit_out(out, csv_file)
        with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), console=err_console,
                      transient=True, disable=not err_console.is_terminal) as bar:
            task = bar.add_task("bootstrap" if resamples else "fit", total=resamples or None)

            class _Bar:
                """The bar's progress; its label follows the fit's stage (fit, conventions, bootstrap …)."""

                def __call__(self, done: int) -> None:
                    bar.update(task, completed=done)

                def stage(self, what: str, total: int) -> None:
                    bar.update(task, description=what, total=total, completed=0)

            opts = FitOptions(noise=noise, resamples=resamples, seed=seed, progress=_Bar(), **kw)
            outcome = fit_csv(name, csv_file, opts)
        outcome.summary["provenance"] = provenance(csv_file, opts)
        folder = write_fit(outcome, out, plot=plot)
    except InputError as err:
        _fail(err)
    except (ArithmeticError, ValueError) as err:
        _fail(ComputationError(str(csv_file), f"the fit failed: {err}"))
    except OSError as err:
        _fail(InputError(f"--out {out}", f"cannot write the output folder ({err.strerror or err})"))
    if as_json:
        typer.echo(_json(outcome.summary))
    else:
        _print_fit(outcome.summary, folder)
    _print_warnings(outcome.summary["warnings"])
    if strict and outcome.summary["warnings"]:
        err_console.print(Text(f"--strict: {len(outcome.summary['warnings'])} warning(s): exit status 1"),
                          soft_wrap=True)
        raise typer.Exit(1)


def _print_warnings(warnings: list[dict[str, str]]) -> None:
    """Each finding of the fit's checks on stderr, one line each: ``WARNING [code]: message``."""
    for w in warnings:
        err_console.print(Text("WARNING", style="bold yellow") + Text(f" [{w['code']}]: {w['message']}"),
                          soft_wrap=True)


def _check_fit_out(out: Path, data: Path) -> None:
    """``resal fit --out``: a folder that is new, or holds an earlier fit (fit.json), never the data's own folder
    or the current one (the whole folder is replaced); nothing is created before the fit has succeeded."""
    where = f"--out {out}"
    if out.exists() and not out.is_dir():
        _fail(InputError(where, "exists and is not a folder: expected a folder for the fit's files"))
    target = out.resolve()
    if target == Path.cwd().resolve() or target in Path.cwd().resolve().parents:
        _fail(InputError(where, "is the current folder (or holds it): the fit replaces its output folder whole; "
                                "name a new folder"))
    if data.exists() and target in data.resolve().parents:
        _fail(InputError(where, f"holds the data file {data}: the fit replaces its output folder whole; name "
                                "another folder"))
    if out.is_dir() and any(out.iterdir()) and not (out / "fit.json").is_file():
        _fail(InputError(where, "holds other files (not an earlier resal fit output, which has fit.json): the fit "
                                "replaces its output folder whole; name a new folder"))
    probe = out
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir() or not os.access(probe, os.W_OK | os.X_OK):
        _fail(InputError(where, f"cannot be created: {probe} is not a writable folder"))


def _print_fit(s: dict[str, Any], folder: Path) -> None:
    def ci(c: list | None) -> str:
        return "—" if not c or c[0] is None else f"[{c[0]:.4g}, {c[1]:.4g}]"

    rows = [([f["parameter"], "—" if f["value"] is None else f"{f['value']:.6g}",
              "—" if f["stderr"] is None else f"{f['stderr']:.3g}", ci(f["ci95"]), ci(f.get("ci95_bootstrap")),
              f["note"]], "") for f in s["fits"]]
    _print_rows(f"resal fit {s['kind']}: {s['file']} ({s['n']} rows)",
                ("parameter", "value", "std. error", "95 % interval", "bootstrap 95 %", "note"), rows, ("parameter",),
                note_width=50)
    from reproductions.fit.report import fit_lines

    lines = fit_lines(s, warnings=False)  # on stderr, after the table
    lines.append(f"wrote {folder}/")
    for ln in lines:
        out_console.print(Text(ln))


def _register_fit_commands() -> None:
    from reproductions.fit.kinds import KINDS

    for name in KINDS:
        _fit_command(name)


_register_fit_commands()


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
