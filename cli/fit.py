"""``resal fit <kind>``: the fit commands, one per kind of ``reproductions.fit.kinds``, each with the options its
kind declares, registered on ``app`` as the group ``fit``."""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.text import Text

from cli.app import _OneLineGroup, _usage_error, app
from cli.common import _count, _fail, _json, _out_folder, _print_rows, err_console, out_console
from reproductions.errors import ComputationError, InputError, did_you_mean


class _FitGroup(_OneLineGroup):
    """`resal fit <kind>`: an unknown kind gets our one-line message, not click's usage screen."""

    def resolve_command(self, ctx: Any, args: list[str]) -> Any:
        from reproductions.fit.kinds import KINDS

        if args and not args[0].startswith("-") and args[0] not in KINDS:
            _fail(InputError(f"kind '{args[0]}'", f"expected one of {', '.join(KINDS)}"
                                                  f"{did_you_mean(args[0], KINDS)}"))
        return super().resolve_command(ctx, args)


class _FitCommand(typer.core.TyperCommand):
    """`resal fit <kind>`: --sigma given to the ricochet fit is told why it has no use there; every other usage
    mistake is told by the group, as for every command (``_OneLineGroup``)."""

    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:
        given = list(args)  # click consumes the list
        try:
            return super().parse_args(ctx, args)
        except Exception as exc:
            err = _usage_error(exc, given, ctx)
            if err is None:
                raise
            if self.name == "ricochet" and type(exc).__name__ == "NoSuchOption" and exc.option_name == "--sigma":
                err = InputError(err.where, "not used by the ricochet fit, which estimates the noise of positions and "
                                            "instants from their residuals: leave it out"
                                            + err.message[err.message.index(" (it takes"):])
            _fail(err)


fit_app = typer.Typer(cls=_FitGroup, no_args_is_help=True, rich_markup_mode=None,
                      help="Fit the paper's coefficients to your own measurements (CSV).\n\n"
                           "\b\nExamples:\n"
                           "  resal examples\n"
                           "  resal fit rebound resal-examples/rebound.csv\n"
                           "  resal fit drop resal-examples/drop.csv --bootstrap 0 --out drop-fit\n"
                           "  resal fit cushion --help\n\n"
                           "`resal examples` copies an example file (synthetic data, labelled so) for each kind into "
                           "resal-examples/; `resal fit KIND --help` gives the columns that kind reads.")
app.add_typer(fit_app, name="fit")


def _fit_option(name: str) -> Callable[[str], Any]:
    """The parser of the fit option ``name``: ``reproductions.fit.options.check``, as ``api.fit`` checks it."""
    from reproductions.fit import options

    flag = "--" + name.replace("_", "-")

    def parse(text: str) -> Any:
        try:
            return options.check(name, text, lambda t: f"{flag} {t}")
        except InputError as err:
            _fail(err)
    return parse


def _fit_options() -> dict[str, tuple[Any, Any]]:
    """Every option a kind may take: name → (annotation, default)."""
    from reproductions.fit import kinds as fitkinds

    return {
        "sigma": (Annotated[float | None, typer.Option(
            "--sigma", parser=_fit_option("sigma"),
            help="known standard deviation of each measured outcome (V1, h1, V1p, the clicks t…), in the data's own "
                 "unit as the header gives it (V1_cmps: cm/s; no unit: SI)")], None),
        "sigma_in": (Annotated[float | None, typer.Option(
            "--sigma-in", parser=_fit_option("sigma_in"),
            help="known standard deviation of each measured impact (V0, u0 or h0), in its column's unit as the "
                 "header gives it: the fit then takes errors in both variables (effective variance); without "
                 "--sigma the outcome's σ is estimated")], None),
        "noise": (Annotated[str, typer.Option(
            "--noise", parser=_fit_option("noise"),
            help="how the outcome scatters: constant, proportional (to the impact), or auto (the likelier of the "
                 "two, by the data); not with --sigma, which gives it")], "auto"),
        "speeds": (Annotated[str | None, typer.Option(
            "--speeds", parser=_fit_option("speeds"),
            help="read V0,V1 as signed velocities (V1 ≤ 0, the default) or as unsigned speeds")], None),
        "g": (Annotated[float, typer.Option("--g", parser=_fit_option("g"),
                                            help="gravity (m/s²)")], 9.80665),
        "M": (Annotated[float | None, typer.Option(
            "--M", parser=_fit_option("M"), help="striking mass: pendulum, if not a column; ball-ball, the cue "
                                                 "ball's (with --Mp; default equal balls). kg, or with a unit: 170g, "
                                                 "6oz")], None),
        "Mp": (Annotated[float | None, typer.Option(
            "--Mp", parser=_fit_option("Mp"), help="struck mass (the object ball's in ball-ball): kg, or with a "
                                                   "unit")], None),
        "R": (Annotated[float, typer.Option("--R", parser=_fit_option("R"),
                                            help="ball radius (the cue ball's in ball-ball): m, or with a unit: "
                                                 "28.575mm")], 0.0305),
        "Rp": (Annotated[float | None, typer.Option("--Rp", parser=_fit_option("Rp"),
                                                    help="the object ball's radius (default the cue ball's)")], None),
        "k": (Annotated[float, typer.Option("--k", parser=_fit_option("k"),
                                            help="MR²/I of the ball (2.5: homogeneous sphere)")], 2.5),
        "kp": (Annotated[float | None, typer.Option("--kp", parser=_fit_option("kp"),
                                                    help="MR²/I of the object ball (default the cue ball's)")], None),
        "h0": (Annotated[float | None, typer.Option("--h0", parser=_fit_option("h0"),
                                                    help="drop height (m), released at rest: then g is fitted too")],
               None),
        "sigma_speed": (Annotated[float | None, typer.Option(
            "--sigma-speed", parser=_fit_option("sigma_speed"),
            help="ball-ball: known relative standard deviation of the measured speeds (0.02 = 2 %)")], None),
        "sigma_dir": (Annotated[float | None, typer.Option(
            "--sigma-dir", parser=_fit_option("sigma_dir"),
            help="ball-ball: known standard deviation of the measured directions, in their column's unit")], None),
        "max_seconds": (Annotated[float, typer.Option(
            "--max-seconds", parser=_fit_option("max_seconds"),
            help="bound on the fit's wall-clock time, its refits included: reached before the estimate, the fit "
                 "stops (exit 1, nothing written); after it, the estimate is written with a time-bound warning "
                 "naming what was not done (the bootstrap: how many resamples ran)")], 120.0),
        "bootstrap": (Annotated[int, typer.Option(
            "--bootstrap", parser=_count("--bootstrap", 0, fitkinds.MAX_RESAMPLES, "a number of resamples"),
            help="bootstrap resamples, each refitted (0: none)")], 1000),
    }


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
    example = _example(name, kind.example)
    help_text = (f"{kind.title}.\n\n\b\nExamples:\n  resal examples\n  {example}\n\n"
                 f"`resal examples` copies the example file (synthetic data, labelled so) into resal-examples/.\n\n"
                 f"Columns: {kind.columns} {UNITS_HELP}" + _coverage_help(name))
    fit_app.command(name, cls=_FitCommand, help=help_text, short_help=_SUMMARY.get(name))(command)


def _coverage_help(kind: str) -> str:
    """The measured coverage of the kind's intervals (``reproductions/fit/coverage.json``): its sentence wrapped by
    click, its table kept as laid out (``\\b``)."""
    from reproductions.fit.coverage_table import help_lines

    lines = help_lines(kind)
    if not lines:
        return ""
    return "\n\n" + lines[0] + "\n\n\b\n" + "\n".join(lines[2:])


# each kind's line in `resal fit --help`: whole, in 63 columns (the kinds' titles run to 89)
_SUMMARY = {"rebound": "e and ε from rebounds on an immovable mass.",
            "cushion": "e and ε from perpendicular cushion rebounds.",
            "drop": "e and ε from a ball dropped on a slab.",
            "pendulum": "ε, ε′ and e from two-pendulum impacts.",
            "ricochet": "ν (and f where identifiable) from ricochet imprints.",
            "bounces": "ν (and g) from the instants of a ball bouncing in place.",
            "ball-ball": "Ball–ball friction f and e from oblique shots.",
            "markers": "Ball–ball friction f and e from angle markers of collisions."}


def _example(name: str, file: str) -> str:
    """`resal fit <name>` on its example file as `resal examples` copies it (into resal-examples/), with the
    options the file's first line asks for ("(use --R 0.02855)")."""
    import re
    import shlex

    from reproductions import locate

    try:
        with (locate.examples_dir() / file).open(encoding="utf-8") as f:
            first = f.readline()
    except OSError:
        first = ""
    options = [o for m in re.findall(r"\(use (--[^)]*)\)", first) for o in m.split()]
    return shlex.join(["resal", "fit", name, f"resal-examples/{file}", *options])


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
        source = _table(csv_file)
        if not isinstance(source, Path):
            _say_size(name, csv_file, len(source.rows), resamples, kw.get("max_seconds"))
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
            outcome = fit_csv(name, source, opts)
        try:
            outcome.summary["provenance"] = provenance(csv_file, opts)
        except OSError as err:
            raise ComputationError(str(csv_file), f"cannot be read again after the fit ({err.strerror or err}): "
                                                  "was it deleted or moved while resal ran? nothing written") from None
        folder = write_fit(outcome, out, plot=plot)
        from reproductions.report import foreign_files

        kept = foreign_files(folder)
    except InputError as err:
        _fail(err)
    except (ArithmeticError, ValueError) as err:
        _fail(ComputationError(str(csv_file), f"the fit failed: {err}"))
    except OSError as err:  # the environment (a full disk, a file-size limit): exit status 1, the folder as it was
        _fail(ComputationError(f"--out {out}", f"cannot write the output folder ({err.strerror or err})"))
    if as_json:
        typer.echo(_json(outcome.summary))
    else:
        _print_fit(outcome.summary, folder)
    if kept:
        err_console.print(Text(f"{folder}: kept {', '.join(kept)} (not written by resal, left as they were)"),
                          soft_wrap=True, highlight=False)
    _print_warnings(outcome.summary["warnings"])
    if strict and outcome.summary["warnings"]:
        err_console.print(Text(f"--strict: {len(outcome.summary['warnings'])} warning(s): exit status 1"),
                          soft_wrap=True)
        raise typer.Exit(1)


def _table(csv_file: Path) -> Any:
    """The file's rows, read once (``series.Table``) for the size line and the fit; the path itself where it
    cannot be read, for ``fit_csv`` to say why."""
    from reproductions.series import read_table

    try:
        return read_table(csv_file)
    except (InputError, OSError):
        return csv_file


def _say_size(name: str, csv_file: Path, rows: int, resamples: int, max_seconds: float | None) -> None:
    """Before a fit that will take minutes, one line on stderr: the rows, what the kind fits in a minute, the time
    to expect (the checks of the fit, not the bootstrap, which the progress bar shows)."""
    from reproductions.fit.kinds import KINDS

    rate = KINDS[name].per_minute
    if not rate:
        return
    if rows <= rate:
        return
    minutes = rows / rate
    boot = f"; then {resamples} bootstrap refits of the same size (--bootstrap 0 skips them)" if resamples else ""
    bound = (f"; past --max-seconds {max_seconds:g}, which stops a fit with no estimate yet: give more time, as "
             f"--max-seconds {60 * math.ceil(2 * minutes):g}" if max_seconds is not None and 60 * minutes > max_seconds
             else "")
    plural = "" if round(minutes) == 1 else "s"
    err_console.print(Text(f"{csv_file}: {rows} rows, more than the {rate} a {name} fit handles in a minute on two "
                           f"cores: expect about {minutes:.0f} minute{plural}{boot}{bound}"), soft_wrap=True,
                      highlight=False)


def _print_warnings(warnings: list[dict[str, str]]) -> None:
    """Each finding of the fit's checks on stderr, one line each: ``WARNING [code]: message``."""
    for w in warnings:
        err_console.print(Text("WARNING", style="bold yellow") + Text(f" [{w['code']}]: {w['message']}"),
                          soft_wrap=True)


def _check_fit_out(out: Path, data: Path) -> None:
    """``resal fit --out``: a folder that is new, or holds an earlier fit (fit.json), never the data's own folder
    or the current one (the folder is swapped whole; the files in it that resal did not write are carried over);
    nothing is created before the fit has succeeded."""
    where = f"--out {out}"
    from reproductions.report import dangling_link

    dangling = dangling_link(out)
    if dangling:
        _fail(InputError(where, dangling))
    if out.exists() and not out.is_dir():
        _fail(InputError(where, "exists and is not a folder: expected a folder for the fit's files"))
    target = out.resolve()
    if target == Path.cwd().resolve() or target in Path.cwd().resolve().parents:
        _fail(InputError(where, "is the current folder (or holds it): the fit swaps its output folder whole; "
                                "name a new folder"))
    if data.exists() and target in data.resolve().parents:
        _fail(InputError(where, f"holds the data file {data}: the fit swaps its output folder whole; name "
                                "another folder"))
    if out.is_dir() and any(out.iterdir()) and not (out / "fit.json").is_file():
        _fail(InputError(where, "holds other files and no fit.json (not an earlier resal fit output): name a new "
                                "folder, or one that holds an earlier fit"))
    probe = out
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir() or not os.access(probe, os.W_OK | os.X_OK):
        _fail(InputError(where, f"cannot be created: {probe} is not a writable folder"))


def _print_fit(s: dict[str, Any], folder: Path) -> None:
    def ci(c: list | None) -> str:
        return "—" if not c or c[0] is None else f"[{c[0]:.4g}, {c[1]:.4g}]"

    from reproductions.fit.report import fit_lines, has_bootstrap

    boot = has_bootstrap(s)  # no column of dashes where no bootstrap ran
    rows = [([f["parameter"], "—" if f["value"] is None else f"{f['value']:.6g}",
              "—" if f["stderr"] is None else f"{f['stderr']:.3g}", ci(f["ci95"]),
              *([ci(f.get("ci95_bootstrap"))] if boot else []), f["note"]], "") for f in s["fits"]]
    _print_rows(f"resal fit {s['kind']}: {s['file']} ({s['n']} rows)",
                ("parameter", "value", "std. error", "95 % interval", *(("bootstrap 95 %",) if boot else ()), "note"),
                rows, ("parameter",), note_width=50)

    lines = fit_lines(s, warnings=False)  # on stderr, after the table
    lines.append(f"wrote {folder}/")
    for ln in lines:
        out_console.print(Text(ln))


def _register_fit_commands() -> None:
    from reproductions.fit.kinds import KINDS

    for name in KINDS:
        _fit_command(name)


_register_fit_commands()
