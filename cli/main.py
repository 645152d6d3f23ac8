"""``resal``: list, reproduce and simulate. Parses arguments, calls one library function, renders.

Heavy imports (numpy, scipy, matplotlib) happen inside the commands, so ``resal --help`` stays fast.
Bad input of any kind ends with one message on stderr and exit status 2; every command interrupted by SIGINT,
SIGTERM or SIGHUP stops its workers, removes its staging folders and exits with one line and 128 + the signal
(130, 143, 129); the earlier results are left whole.
"""

from __future__ import annotations

import reproductions.startup  # noqa: F401  (first: a signal during the imports below ends the run in one line)

# isort: split
import json
import math
import os
import shutil
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Annotated, Any, NoReturn

import typer
from rich import box
from rich.console import Console
from rich.padding import Padding
from rich.table import Table
from rich.text import Text

from reproductions.diffing import ABSENT, Difference, SummaryDiff, compare
from reproductions.errors import ComputationError, InputError, Interrupted


def _command_path(ctx: Any) -> str:
    """`resal fit drop`: the command a click context runs, named as the user typed it (a test runner's root too)."""
    names = []
    while ctx is not None and ctx.parent is not None:
        names.append(ctx.info_name)
        ctx = ctx.parent
    return " ".join(["resal", *reversed(names)])


def _usage_error(exc: Exception, given: list[str], ctx: Any = None) -> InputError | None:
    """Click's usage error ``exc`` (an unknown option or command, a missing argument, a value click refused) as one
    ``InputError``; None for any other exception, and for the help a group given nothing prints. ``given``: the
    arguments as typed, to quote an unknown option with its value; ``ctx``: the failing command's context when
    click did not attach it to ``exc``. (typer vendors click in recent versions: the classes are matched by name.)"""
    kinds = {c.__name__ for c in type(exc).__mro__}
    if "UsageError" not in kinds or "NoArgsIsHelpError" in kinds:
        return None
    ctx = getattr(exc, "ctx", None) or ctx
    path = _command_path(ctx)
    if "NoSuchOption" in kinds:
        opt = getattr(exc, "option_name", "") or "option"
        takes = sorted(o for q in (ctx.command.params if ctx is not None else ()) for o in q.opts
                       if o.startswith("--") and o != "--help")
        at = given.index(opt) if opt in given else -1
        where = f"{opt} {given[at + 1]}" if 0 <= at < len(given) - 1 and not given[at + 1].startswith("--") else opt
        guess = list(getattr(exc, "possibilities", None) or ())  # the closest first
        hint = f"; did you mean {' or '.join(guess)}?" if guess else ""
        return InputError(where, f"not an option of `{path}`{hint} (it takes "
                                 f"{', '.join(takes) if takes else 'no option but --help'})")
    if ctx is not None and hasattr(ctx.command, "commands") and "No such command" in str(exc):
        name = next((a for a in given if not a.startswith("-")), "")
        return InputError(f"command '{name}'", f"not a command of `{path}` (expected one of "
                                               f"{', '.join(ctx.command.commands)}; see {path} --help)")
    where = getattr(exc, "option_name", None) or path  # an option given without its value: the option
    return InputError(where, f"{exc.format_message()} (see {path} --help)")  # type: ignore[attr-defined]


class _OneLineGroup(typer.core.TyperGroup):
    """Every usage mistake gets one ``error:`` line and exit 2, as all bad input does, never click's usage screen:
    the group's own options, its command names, and (around each command it runs) the command's own arguments; so
    every command of the app, the ones added later too, behaves the same."""

    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:
        given = list(args)  # click consumes the list
        try:
            return super().parse_args(ctx, args)
        except Exception as exc:
            err = _usage_error(exc, given, ctx)
            if err is None:
                raise
            _fail(err)

    def resolve_command(self, ctx: Any, args: list[str]) -> Any:
        try:
            return super().resolve_command(ctx, args)
        except Exception as exc:
            err = _usage_error(exc, list(args), ctx)
            if err is None:
                raise
            _fail(err)

    def invoke(self, ctx: Any) -> Any:
        given = [*ctx._protected_args, *ctx.args]
        try:
            return super().invoke(ctx)
        except Exception as exc:  # raised while the command parsed its arguments (or, rarely, while it ran)
            cmd = self.get_command(ctx, given[0]) if given else None
            sub = typer.Context(cmd, parent=ctx, info_name=given[0]) if cmd is not None else None
            err = _usage_error(exc, given, sub)
            if err is None:
                raise
            _fail(err)


# plain help (no rich markup): typer then skips its rich formatting imports, and `resal --help` stays under 0.3 s
app = typer.Typer(cls=_OneLineGroup, add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False,
                  rich_markup_mode=None,
                  help="Reproduce H. Résal (1883), 'Commentaire à la théorie mathématique du jeu de billard'.")


def _environ() -> dict[str, str]:
    """The environment Rich sizes its consoles from, without a COLUMNS or LINES that is not a positive width
    (``COLUMNS=0`` made every line, error messages included, vanish): then the terminal's own size, or 80."""
    env = dict(os.environ)
    for k in ("COLUMNS", "LINES"):
        v = env.get(k)
        if v is not None and not (v.isdigit() and int(v) >= 1):
            del env[k]
    if env.get("COLUMNS", "").isdigit() and int(env["COLUMNS"]) < 20:  # narrower than one word and its padding
        env["COLUMNS"] = "20"
    return env


out_console = Console(_environ=_environ())
err_console = Console(stderr=True, _environ=_environ())
VERDICT_STYLE = {"reproduced": "green", "differs": "bold red", "not-checkable": "yellow", "consistent": "green",
                 "inconsistent": "bold red", "fitted": "cyan"}




def _json(obj: Any) -> str:
    """Strict JSON (no NaN or Infinity, which are not JSON): a non-finite number is a bug, so it raises. On a
    stdout that cannot print Unicode, non-ASCII characters are written as JSON escapes."""
    return json.dumps(obj, indent=2, ensure_ascii=_JSON_ASCII[0], allow_nan=False)


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
    if not exps:  # one line naming where it looked, exit 2 (not an empty table)
        d = api.config_dir()
        where = f"{d} ($RESAL_CONFIGS)" if os.environ.get("RESAL_CONFIGS") else str(d)
        _fail(InputError(where, f"no experiments found ({'no *.yaml file there' if d.is_dir() else 'no such folder'})"))
    t = Table(title=f"experiments in {api.config_dir()}")
    for c in ("id", "section", "title", "kind"):
        t.add_column(c)
    for e in exps:
        t.add_row(e.id, e.source.section, e.title, e.kind)
    out_console.print(t)


WIDE_TABLE = 140  # columns: below, a table of many columns folds words mid-word; each row is then a record


def _print_rows(title: str, headers: tuple[str, ...], rows: list[tuple[list[str], str]], lead: tuple[str, ...],
                note_width: int = 60, lines: bool = False,
                record: Callable[[dict[str, str]], list[tuple[str, str]]] | None = None) -> None:
    """Rows of cells (each with its style, for the ``verdict`` cell): a table on a wide console; on a narrow one
    (or piped at 80 columns) a record per row, its ``lead`` cells as a heading and the others as ``label: value``
    lines wrapped at words, so that no word is broken. ``record`` gives those lines from the row's cells by
    header (several cells on one line), instead of one line per non-empty cell."""
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
        pairs = record(by) if record else [(h, by[h]) for h in headers if h not in lead and by[h]]
        for label, value in pairs:
            grid.add_row(f"  {label}", Text(value))
        out_console.print(grid)


def _experiment_record(by: dict[str, str]) -> list[tuple[str, str]]:
    """An experiment's row as a record: where it is printed (section, line), the printed value, the computed one
    with its difference and the reason it differs, the note."""
    where = by["§ / eq."] + (f", line {by['line']}" if by["line"] not in ("", "—") else "")
    more = [f"{label}{by[h]}" for h, label in (("difference", "difference "), ("reason", "reason: "))
            if by[h] not in ("", "—")]
    computed = by["computed"] + (f" ({'; '.join(more)})" if more else "")
    return [(label, text) for label, text in (("where", where), ("printed", by["printed"]), ("computed", computed),
                                              ("note", by["note"])) if text]


def _fit_record(by: dict[str, str]) -> list[tuple[str, str]]:
    """A fit as a record: the value with its standard error and interval on one line, then the note."""
    value = by["value"] + (f" ± {by['std. error']}" if by["std. error"] != "—" else "")
    value += f", 95 % interval {by['95 % interval']}" if by["95 % interval"] != "—" else ""
    value += "" if by["identifiable"] == "yes" or "not identifiable" in by["note"] else " (not identifiable)"
    return [("value", value), ("note", by["note"])] if by["note"] else [("value", value)]


def _render(s: dict[str, Any]) -> None:
    """One experiment's full table (every row), its measured rows and its fits."""
    from reproductions.report import HEADERS, MEASUREMENT_HEADERS, measurement_cells, row_cells

    if s["rows"] or not s.get("measurements"):
        _print_rows(f"{s['experiment']}: {s['title']}", HEADERS,
                    [(row_cells(r), VERDICT_STYLE.get(r["verdict"], "")) for r in s["rows"]], ("verdict", "quantity"),
                    lines=True, record=_experiment_record)
    if s.get("measurements"):
        if s["rows"]:
            out_console.print()
        _print_rows(f"{s['experiment']}: today's measurements against the paper's mechanics (95 %)",
                    MEASUREMENT_HEADERS, [(measurement_cells(m), VERDICT_STYLE.get(m["verdict"], ""))
                                          for m in s["measurements"]], ("verdict", "quantity"), lines=True)
    if s["fits"]:
        out_console.print()
        _print_fits(s["fits"], "fits")


def _print_items(lead: str, items: list[str], indent: str = "") -> None:
    """``lead`` and a comma-separated list, wrapped between items, never inside one ("repair 8", "T (kg·m/s)")."""
    line = indent + lead
    for j, item in enumerate(items):
        item = f" {item}" + ("," if j < len(items) - 1 else "")
        if len(line) + len(item) > out_console.width and line.strip():
            out_console.print(Text(line), highlight=False, soft_wrap=True)
            line = indent + " "
        line += item
    out_console.print(Text(line), highlight=False, soft_wrap=True)


def _render_summary(summaries: list[dict[str, Any]], folders: list[Path]) -> None:
    """Several experiments: one line each (its verdict counts), the totals, the reasons of the differing rows and
    where the folders are. Each experiment's line stays under 80 columns, unfolded, so that it stays greppable."""
    from reproductions.config import MEASUREMENT_VERDICTS
    from reproductions.report import VERDICTS, beyond_counts, measurement_counts, verdict_counts, whose_error

    width = max([5, *(len(s["experiment"]) for s in summaries)])

    def counts_text(rows: list[dict[str, Any]]) -> Text:
        counts, _ = verdict_counts(rows)
        text = Text()
        for j, v in enumerate(VERDICTS):
            text.append(f"{counts[v]:>4} ", style=VERDICT_STYLE[v] if counts[v] else "")
            text.append(v + ("  " if j < len(VERDICTS) - 1 else ""))
        return text

    def measured_text(s: dict[str, Any]) -> Text:
        counts = measurement_counts([s])
        text = Text()
        for j, v in enumerate(v for v in MEASUREMENT_VERDICTS if counts[v]):
            text.append(("" if j == 0 else "  ") + f"{counts[v]:>4} ", style=VERDICT_STYLE[v])
            text.append(v)
        return text

    printed = [s for s in summaries if s["rows"] or not s.get("measurements")]
    measured = [s for s in summaries if s.get("measurements")]
    for s in printed:
        out_console.print(Text(f"{s['experiment']:<{width}} ") + counts_text(s["rows"]), soft_wrap=True,
                          highlight=False)
    rows = [r for s in summaries for r in s["rows"]]
    paper_counts, why = verdict_counts(rows)
    if printed:
        out_console.print(Text(f"{'total':<{width}} ", style="bold") + counts_text(rows)
                          + Text(f" ({sum(paper_counts.values())} claims)"), soft_wrap=True, highlight=False)
    if why:  # whose error: Résal's own, a premise, rounded digits, the digitised text's (issue 35)
        _print_items(f"the {paper_counts['differs']} that differ, by whose error:",
                     [f"{n} {label} ({codes})" for label, n, codes in whose_error(why)])
    beyond = beyond_counts(rows)
    if sum(beyond.values()):  # graded beyond the domain where the paper applies its claims: not the paper's claims
        _print_items(f"beyond the paper's domain, counted apart ({sum(beyond.values())} rows):",
                     [f"{beyond[v]} {v}" for v in VERDICTS if beyond[v]])
    if measured:  # counted apart: a measurement against the mechanics is not a printed claim
        n = sum(len(s["measurements"]) for s in measured)
        out_console.print(Text(f"today's measurements against the paper's mechanics ({n} rows, 95 %):"),
                          highlight=False)
        for s in measured:
            out_console.print(Text(f"{s['experiment']:<{width}} ") + measured_text(s), soft_wrap=True,
                              highlight=False)
    parents = {f.parent for f in folders}
    where = f"{parents.pop() / '<experiment>'}/" if len(parents) == 1 else ", ".join(map(str, folders))
    out_console.print(Text(f"folders: {where}", overflow="ignore"), highlight=False)


def _names(experiments: list[str] | None, all_: bool) -> list[str]:
    """The experiments named, then with --all every other id; none is refused."""
    from reproductions import locate

    names = list(experiments or [])
    if all_:
        names += [i for i in locate.experiment_ids() if i not in names]
    if not names:
        raise InputError("arguments", "name an experiment id, a YAML path, or use --all")
    return names


def _reusable(names: list[str], out: Path, notes: list[str]) -> dict[str, dict[str, Any]]:
    """The summaries of the experiments named by id whose folder in ``out`` was computed from the same config,
    data files and code, with every file resal wrote there as it wrote it (``digest.reuse``): nothing of the
    physics is imported to know it. A folder whose files were changed by hand adds its line to ``notes``."""
    from reproductions import digest, locate

    found, ids = {}, set(locate.experiment_ids())
    for n in names:
        if n in ids and not locate.names_a_file(n):  # named by id (configs/<id>.yaml), as ``api.load`` reads it
            s, why = digest.reuse(out / n, locate.config_dir() / f"{n}.yaml")
            if s is not None and s.get("experiment") == n:
                found[n] = s
            elif why:
                notes.append(f"{why}: computing it again")
    return found


def _load_experiments(names: list[str], out: Path, taken: dict[str, str] | None = None) -> list[Any]:
    """The experiments ``names``, each loaded and validated; two of one id are refused (``taken``: ids already
    written by other names, id → name)."""
    if not names:
        return []
    from reproductions import api, locate
    from reproductions.config import MAX_YAML_BYTES, read_input

    for n in names:  # a folder, a FIFO or a device named in place of a YAML file: said so, never opened blocking
        p = Path(n)
        if locate.path_exists(p) and not p.is_file() and (p.suffix in (".yaml", ".yml")
                                                           or n not in api.experiment_ids()):
            read_input(p, "an experiment file (YAML)", MAX_YAML_BYTES)
    exps = [api.load(n) for n in names]
    seen: dict[str, str] = dict(taken or {})
    for n, e in zip(names, exps, strict=True):
        if e.id in seen:
            raise InputError(n, f"experiment id '{e.id}' is also the id of {seen[e.id]}: both would write "
                                f"{out / e.id}")
        seen[e.id] = n
    return exps


def _print_summaries(experiments: list[str] | None, all_: bool, jobs: int | None) -> None:
    """``reproduce --json`` without ``--out``: run, print the summaries (as summary.json holds them), write
    nothing (a pipe does not expect files in the current folder)."""
    from reproductions import api, report

    try:
        with api.interruptible():
            exps = _load_experiments(_names(experiments, all_), Path("results"))
            jobs = max(1, jobs if jobs is not None else min(os.cpu_count() or 1, len(exps)))
            with err_console.status("running"):
                reps = api.parallel_map(api.run, exps, jobs)
            summaries = [report.summary(r, report.provenance(r)) for r in reps]
    except InputError as err:
        _fail(err)
    except Interrupted as exc:
        err_console.print(Text("error: ", style="bold red") + Text(f"interrupted ({exc.name}); nothing written"),
                          soft_wrap=True)
        _exit_now(128 + exc.signum)
    typer.echo(_json(summaries[0] if len(summaries) == 1 else summaries))


def _in_order(names: list[str], reused: dict[str, Any], exps: list[Any]) -> list[tuple[str, Any]]:
    """(name, experiment or None) in the order named: the reused by name, the others as loaded."""
    it = iter(exps)
    return [(n, None if n in reused else next(it)) for n in names]


def _write_index(out: Path, force: bool, progress: Callable[[str], None]) -> bool:
    """Render the whole-paper files of ``out`` unless they were rendered from the same experiment folders by the
    same code (``digest.edition_digest``) and are all there as resal wrote them; whether they were written. A
    summary left out of them (not resal's, or changed by hand) is named, one line each."""
    from reproductions import digest

    d = digest.edition_digest(p for p in out.iterdir() if p.is_dir() and not p.name.startswith(".")
                              and (p / "summary.json").is_file())
    current, changed = digest.index_current(out, d)
    if not force and current:
        return False
    from reproductions import edition

    if changed and not force and (out / digest.INDEX_FILE).is_file():
        them = "it" if len(changed) == 1 else "them"
        err_console.print(Text(f"{out}: {', '.join(changed)} changed since resal wrote {them}: writing {them} again"),
                          soft_wrap=True, highlight=False)
    progress("writing the reader's edition")
    skipped: list[tuple[Path, str]] = []
    edition.write_index(out, skipped)
    for f, why in skipped:
        err_console.print(Text(f"{f}: {why}; left out of the reader's edition"), soft_wrap=True, highlight=False)
    digest.mark_index(out, d)
    return True


def _replacing_notes(exps: list[Any], out: Path, force: bool) -> list[str]:
    """A line for each experiment folder about to be replaced that holds what the user should hear of: files
    resal wrote that were changed by hand since (``--force`` replaces them), or the results of another config
    with the same id (a user's copy of a shipped experiment)."""
    from reproductions import report

    notes = []
    for e in exps:
        folder = out / e.id
        if not (folder / "summary.json").is_file():
            continue
        changed = report.changed_by_hand(folder) if force else None
        if changed:
            notes.append(f"{folder}: replacing {', '.join(changed)}, changed since resal wrote "
                         f"{'it' if len(changed) == 1 else 'them'} (--force)")
        try:
            before = json.loads((folder / "summary.json").read_text(encoding="utf-8"))["provenance"]["config"]
        except (OSError, ValueError, KeyError, TypeError):
            continue
        if isinstance(before, str) and Path(before).resolve() != Path(e.path).resolve():
            notes.append(f"{folder}: held the results of {before}; replacing them with those of {e.path} (same id "
                         f"'{e.id}'; --out ANOTHER keeps both)")
    return notes


def _seconds(name: str) -> Callable[[str], float]:
    """A parser of option ``name``: a number of seconds in [0, 86400]."""
    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            v = math.nan
        if not 0 <= v <= 86400:
            _fail(InputError(f"{name} {text}", "expected a number of seconds in [0, 86400]"))
        return v
    return parse


@app.command()
def reproduce(
    experiments: Annotated[list[str] | None, typer.Argument(help="experiment ids or YAML paths")] = None,
    all_: Annotated[bool, typer.Option("--all", help="every experiment in configs/")] = False,
    as_json: Annotated[bool, typer.Option("--json", help="print the summary.json of each experiment on stdout "
                                                         "instead of tables; writes no file unless --out is given")
                       ] = False,
    out: Annotated[Path | None, typer.Option("--out", help="results folder (default: results, in the current "
                                                           "folder)", parser=_out_folder)] = None,
    jobs: Annotated[int | None, typer.Option(help=f"processes, 1 to {MAX_JOBS} (default: one per core)",
                                             parser=_count("--jobs", 1, MAX_JOBS, "a number of processes"))] = None,
    verbose: Annotated[bool, typer.Option("--verbose", "-v", help="print every experiment's full table (one "
                                                                  "experiment always does)")] = False,
    force: Annotated[bool, typer.Option("--force", help="recompute every experiment named, even one whose folder "
                                                        "in OUT was computed from the same config, data files and "
                                                        "code (reused otherwise)")] = False,
    wait: Annotated[float, typer.Option("--wait", help="seconds to wait for another run writing into OUT",
                                        parser=_seconds("--wait"))] = 60.0,
) -> None:
    """Run experiments, compare every printed value, write tables and figures into OUT/<experiment>/ and the
    paper's index, table, reader's edition (index.html) and report.pdf into OUT. One experiment prints its full
    table; several, a summary. With --json and no --out, only prints: nothing is written. An experiment whose
    folder was computed from the same config, data files and code is reused, not recomputed (--force)."""
    from reproductions import processes, report

    if as_json and out is None:
        _print_summaries(experiments, all_, jobs)
        return
    out = out if out is not None else Path("results")
    folders: list[Path] = []
    try:
        with processes.interruptible():
            names = _names(experiments, all_)
            notes: list[str] = []
            reused = {} if force else _reusable(names, out, notes)
            # all validated before anything runs or is written
            todo = [n for n in names if n not in reused]
            loaded = list(zip(todo, _load_experiments(todo, out, {n: n for n in reused}), strict=True))
            if not force:  # an experiment named by the path of its file: known only once read
                from reproductions import digest

                for n, e in loaded:
                    s, why = digest.reuse(out / e.id, Path(e.path))
                    if s is not None:
                        reused[n] = s
                    elif why:
                        notes.append(f"{why}: computing it again")
            exps = [e for n, e in loaded if n not in reused]
            notes += _replacing_notes(exps, out, force)
            for line in dict.fromkeys(notes):  # each once, in order
                err_console.print(Text(line), soft_wrap=True, highlight=False)
            report.ensure_writable(out)
            report.clean_stale(out)  # what a killed run (SIGKILL) of ours left behind
            jobs = max(1, jobs if jobs is not None else min(os.cpu_count() or 1, max(1, len(exps))))
            with err_console.status("") as status:
                # run all first: a bad data file stops everything before anything is written; figures are drawn
                # one by one across the processes as their experiment finishes, into a scratch folder
                scratch = None
                try:
                    written: dict[str, Path] = {}
                    if exps:
                        from reproductions import api

                        scratch = report.make_staging(out, "figures")
                        reps = api.run_and_draw(exps, jobs, scratch, status.update)
                    def waiting(pids: list[int]) -> None:
                        who = f"pid {', '.join(map(str, pids))}" if pids else "another resal run"
                        err_console.print(Text(f"waiting for {who}, which is writing into {out} (up to {wait:g} s; "
                                               "--wait SECONDS)"), soft_wrap=True, highlight=False)

                    # another run into the same folder writes before or after, whole
                    with report.locked(out, wait, waiting):
                        for e, r in zip(exps, reps if exps else [], strict=True):
                            processes.checkpoint()
                            written[e.id] = report.write_reproduction(r, out, drawn=scratch / r.experiment.id)
                            folders.append(written[e.id])
                            kept = report.foreign_files(written[e.id])
                            if kept:
                                shown = ", ".join(kept[:6]) + (f" and {len(kept) - 6} more" if len(kept) > 6 else "")
                                err_console.print(Text(f"{written[e.id]}: kept {shown} (not written by resal, "
                                                       "left as they were)"), soft_wrap=True, highlight=False)
                        summaries = [reused[n] if n in reused else
                                     json.loads((written[e.id] / "summary.json").read_text(encoding="utf-8"))
                                     for n, e in _in_order(names, reused, exps)]
                        index = _write_index(out, force, status.update)
                finally:
                    if scratch is not None:
                        shutil.rmtree(scratch, ignore_errors=True)
    except InputError as err:
        _fail(err)
    except OSError as err:  # the environment (a full disk, a file-size limit, a folder gone): exit status 1
        _fail(ComputationError(f"--out {out}", f"cannot write results ({err.strerror or err}); the experiment "
                                               "folders not yet replaced are as they were"))
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
        _render_summary(summaries, [out / s["experiment"] for s in summaries])
    done = ([f"wrote {len(folders)} experiment folder(s)"] if folders else []) + (
        [f"reused {len(reused)} unchanged (--force recomputes them)"] if reused else [])
    edition_files = (f"the reader's edition {out / 'index.html'} (on paper: {out / 'report.pdf'}), with "
                     f"{out / 'index.md'} and {out / 'paper-table'}.{{md,csv,tex}}")
    done.append(f"wrote {edition_files}" if index else f"kept {edition_files}: their inputs are unchanged")
    err_console.print("; ".join(done), soft_wrap=True)


@app.command()
def simulate(
    model: Annotated[str | None, typer.Argument(help="model name; see --list")] = None,
    set_: Annotated[list[str] | None, typer.Option("--set", help="name=value: SI units, angles in degrees, "
                                                                  "vectors as x,y,z")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object (its 'units' give each input's "
                                                         "and output's unit)")] = False,
    list_: Annotated[bool, typer.Option("--list", help="list the models: their parameters (units, ranges, "
                                                       "defaults), paths and outputs")] = False,
    method: Annotated[str, typer.Option(help="solution path: auto (the cheapest exact one for the scene) or a "
                                             "path of the model (see --list)")] = "auto",
) -> None:
    """Run one scene of a mechanics model and print its inputs and outputs, each with its unit (SI; angles in
    degrees, as the inputs are)."""
    from reproductions.models import list_models
    from reproductions.models import simulate as run_scene

    if list_:
        info = list_models()
        if as_json:
            typer.echo(_json(info))
        else:
            _print_models(info)
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
    described = next(m for m in list_models()["models"] if m["model"] == model)
    meaning = {p["name"]: p["doc"] for p in described["parameters"]} | {o["name"]: o["doc"]
                                                                       for o in described["outputs"]}
    out_console.print(Text(result["model"], style="bold") + Text(f": path {result['path_name']}, regime "
                                                                 f"{result['regime_name']}"))
    out_console.print(Text(result["label"]))
    rows = [("in" if side == "inputs" and j == 0 else "out" if j == 0 else "", k,
             _value_text(v, regimes=result["units"][side][k] == "code"), _unit_text(result["units"][side][k]),
             meaning[k], side == "inputs" and j == len(result[side]) - 1)
            for side in ("inputs", "outputs") for j, (k, v) in enumerate(result[side].items())]
    # Names, units and numbers are never cut: on a console too narrow for the table (COLUMNS=20), a line per value
    # that the terminal wraps (a list of values folds between its numbers, so 24 columns suffice for it).
    need = sum(min(max(len(r[i]) for r in rows), 24) for i in range(4)) + 12 + 10
    if out_console.width < need:
        for tag, name, value, unit, what, _ in rows:
            if tag:
                out_console.print(Text("inputs:" if tag == "in" else "outputs:", style="bold"))
            unit = "" if unit == "1" else unit
            out_console.print(Text(f"  {name} = {value} {unit}".rstrip() + f" ({what})"), soft_wrap=True)
        return
    t = _plain_table()
    for c in ("", "name", "value", "unit", "meaning"):
        t.add_column(c, no_wrap=c in ("", "name", "unit"), overflow="fold")
    for *cells, end in rows:
        t.add_row(*cells, end_section=end)
    out_console.print(t)


def _plain_table() -> Table:
    """A table that reads piped: no frame, a rule under the header, two spaces between columns."""
    return Table(box=box.SIMPLE_HEAD, show_edge=False, pad_edge=False, padding=(0, 1), collapse_padding=True)


def _unit_text(unit: str) -> str:
    """A unit as printed: codes and flags need none (their values are names and true/false)."""
    return "" if unit in ("code", "flag") else unit


def _value_text(v: Any, digits: int = 10, regimes: bool = False) -> str:
    """A simulate value as printed: lists flattened (components, or one value per impact), regime codes named."""
    from reproductions.mechanics.paths import Regime

    if v is None:
        return "—"
    if isinstance(v, list):
        return ", ".join(_value_text(x, 6, regimes) for x in _flat(v))
    if isinstance(v, bool):
        return "true" if v else "false"
    if regimes:
        return Regime(v).name.lower().replace("_", "-")
    return f"{v:.{digits}g}" if isinstance(v, float) else str(v)


def _range_cell(p: dict[str, Any]) -> str:
    """A parameter's admissible range, short: "(0, 1]", "> 0", "any"; "whole" for a count."""
    text = p["range"].removeprefix("a number").strip()
    text = text.removeprefix("in ").strip() or "any"
    return f"whole, {text}" if p["integer"] else text


def _default_cell(p: dict[str, Any]) -> str:
    if p["required"]:
        return "required"
    d = p["default"]
    return ",".join([f"{d:g}"] * 3) if p["vector"] else f"{d:g}"


def _print_models(info: dict[str, Any]) -> None:
    """``simulate --list``: per model a heading, its paths, a table of its parameters (name, unit, range,
    default, meaning) and its outputs with their units. Narrow columns never wrap; the meanings wrap at words."""
    out_console.print(Text("models of resal simulate", style="bold"))
    out_console.print(Text(f"units: {info['units']}; a parameter without a default must be given (--set "
                           f"name=value); --list --json gives the same with path and regime codes"))
    for m in info["models"]:
        out_console.print()
        out_console.print(Text(m["model"], style="bold") + Text(f": {m['doc']} ({m['section']})"))
        _print_items("paths (cost):", [f"{p['name']} ({p['cost']})" for p in m["paths"]], indent="  ")
        out_console.print(Padding(Text(f"admits: {m['admits']}"), (0, 0, 0, 2), expand=False))
        t = _plain_table()
        for c in ("parameter", "unit", "range", "default", "meaning"):
            t.add_column(c, no_wrap=c != "meaning", overflow="fold")
        for p in m["parameters"]:
            t.add_row(p["name"], p["unit"], _range_cell(p), _default_cell(p), p["doc"])
        out_console.print(Padding(t, (0, 0, 0, 2), expand=False))
        _print_items("outputs:", [f"{o['name']} ({o['unit']})" for o in m["outputs"]], indent="  ")


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
                ("parameter",), record=_fit_record)


# ---- resal fit <kind> ----------------------------------------------------------------------------------------
class _FitGroup(_OneLineGroup):
    """`resal fit <kind>`: an unknown kind gets our one-line message, not click's usage screen."""

    def resolve_command(self, ctx: Any, args: list[str]) -> Any:
        from reproductions.fit.kinds import KINDS

        if args and not args[0].startswith("-") and args[0] not in KINDS:
            _fail(InputError(f"kind '{args[0]}'", f"expected one of {', '.join(KINDS)}"))
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
                      help="Fit the paper's coefficients to your own measurements (a CSV file): `resal fit <kind> "
                           "data.csv`; `resal fit <kind> --help` gives that kind's columns and an example.")
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
        "M": (Annotated[float | None, typer.Option("--M", parser=_fit_option("M"),
                                                   help="striking mass (kg), if not a column")], None),
        "Mp": (Annotated[float | None, typer.Option("--Mp", parser=_fit_option("Mp"),
                                                    help="struck mass (kg), if not a column")], None),
        "R": (Annotated[float, typer.Option("--R", parser=_fit_option("R"), help="ball radius (m)")], 0.0305),
        "k": (Annotated[float, typer.Option("--k", parser=_fit_option("k"),
                                            help="MR²/I of the ball (2.5: homogeneous sphere)")], 2.5),
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
            help="bound on the fit's wall-clock time, its refits included: past it the fit stops with a message "
                 "(exit 1) and writes nothing")], 120.0),
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


def _print_grouped(title: str, headers: tuple[str, ...], groups: list[tuple[str, list[tuple[list[str], str]]]],
                   right: tuple[int, ...] = ()) -> None:
    """A table of rows grouped under a heading each (a model), the first column indented under it: names are
    codes a user types, so no cell is ever cut or folded; a row's note goes on the lines below it, wrapped at
    words. Fits 80 columns for the bench and the stress reports (their widest codes are 24 characters)."""
    import textwrap

    indent = "  "
    widths = [len(h) for h in headers]
    for name, rows in groups:
        widths[0] = max(widths[0], len(name))
        for cells, _ in rows:
            widths = [max(w, len(c) + (len(indent) if i == 0 else 0)) for i, (w, c) in enumerate(zip(widths, cells,
                                                                                                     strict=True))]

    def line(cells: list[str] | tuple[str, ...]) -> str:
        return "  ".join(c.rjust(w) if i in right else c.ljust(w) for i, (c, w) in
                         enumerate(zip(cells, widths, strict=True))).rstrip()

    out_console.print(Text(title, style="bold"), highlight=False)
    out_console.print(Text(line(headers), style="bold"), highlight=False)
    out_console.print(Text("─" * len(line(headers))), highlight=False)
    for name, rows in groups:
        out_console.print(Text(name, style="bold"), highlight=False)
        for cells, note in rows:
            out_console.print(Text(line([indent + cells[0], *cells[1:]]), overflow="ignore"), highlight=False,
                              soft_wrap=True)
            if note:
                pad = " " * (2 * len(indent))
                for ln in textwrap.wrap(note, max(20, out_console.width - len(pad)), break_long_words=False,
                                        break_on_hyphens=False):
                    out_console.print(Text(pad + ln), highlight=False, soft_wrap=True)


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
) -> None:
    """Work-precision benchmark of every model × path: time per scene against error, and auto's Pareto verdict."""
    from rich.progress import Progress

    from reproductions import bench as bench_mod
    from reproductions.mechanics import registry

    names = _known_models(models)
    total = sum(len(registry.MODELS[m].paths) + 1 for m in (names or registry.MODELS))
    try:
        from reproductions.report import ensure_writable

        ensure_writable(out)  # before minutes of work
    except InputError as err:
        _fail(err)
    with Progress(console=err_console, transient=True, disable=not err_console.is_terminal) as bar:
        task = bar.add_task("benchmark", total=total)

        def step(what: str) -> None:
            bar.update(task, advance=1, description=what)

        rep = bench_mod.run(names, quick=quick, progress=step)
    try:
        written = bench_mod.write(rep, out)
    except InputError as err:
        _fail(err)
    except OSError as err:  # the environment (a full disk): exit status 1, the earlier benchmark whole
        _fail(ComputationError(f"--out {out}", f"cannot write the benchmark ({err.strerror or err}); the earlier "
                                               "one is as it was"))
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
    err_console.print(f"wrote {', '.join(str(p) for p in written[:2])} and {len(written) - 2} figure files")


@app.command()
def stress(
    models: Annotated[list[str] | None, typer.Argument(help="models (default: all; see simulate --list)")] = None,
    scenes: Annotated[int, typer.Option(help="random scenes per closed-form and exact path",
                                        parser=_count("--scenes", 1, 50_000_000))] = 1_000_000,
    ode_scenes: Annotated[int, typer.Option(help="scenes per ODE path (each one integrated)",
                                            parser=_count("--ode-scenes", 1, 100_000))] = 150,
    referee_scenes: Annotated[int, typer.Option(help="scenes per referee (each integrated; every exact path is "
                                                     "judged against them)",
                                                parser=_count("--referee-scenes", 1, 100_000))] = 1_000,
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

        rep = stress_mod.run(names, scenes=scenes, ode_scenes=ode_scenes, seed=seed, progress=step,
                             referee_scenes=referee_scenes)
    try:
        written = stress_mod.write(rep, out)
    except InputError as err:
        _fail(err)
    except OSError as err:  # the environment (a full disk): exit status 1, the earlier report whole
        _fail(ComputationError(f"--out {out}", f"cannot write the stress report ({err.strerror or err}); the "
                                               "earlier one is as it was"))
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


def _read_summary(path: Path) -> dict[str, Any]:
    from reproductions.golden import read_summary

    return read_summary(path / "summary.json" if path.is_dir() else path)


def _diff_side(path: Path) -> tuple[str, Path]:
    """What an argument of ``diff`` is: ("summary", file) for a summary.json or an experiment folder holding
    one; ("results", folder) for a results folder (experiment folders with summary.json, none of its own)."""
    if not path.is_dir():
        return "summary", path  # a missing file gets its message from _read_summary
    if (path / "summary.json").is_file():
        return "summary", path / "summary.json"
    if _experiment_folders(path):
        return "results", path
    raise InputError(str(path), "holds no summary.json: expected a summary.json file, an experiment folder "
                                "(results/<id>) or a results folder (results)")


def _experiment_folders(folder: Path) -> dict[str, Path]:
    """Experiment id → its folder, for every folder of ``folder`` that holds a summary.json (not hidden staging)."""
    try:
        return {d.name: d for d in sorted(folder.iterdir())
                if not d.name.startswith(".") and (d / "summary.json").is_file()}
    except OSError as exc:
        raise InputError(str(folder), f"cannot read ({exc.strerror})") from None


def _compare_files(ref: Path, new: Path, rtol: float | None) -> SummaryDiff:
    """Two summary.json files read (an ``InputError`` for either that is bad input) and compared; neither is kept,
    so comparing two results folders holds one pair of summaries in memory at a time."""
    import gc

    from reproductions import golden

    # the summaries are JSON, acyclic: the cyclic collector would only walk their millions of containers again and
    # again as they are made (a fifth of the time of a large diff)
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        s, t = _read_summary(ref), _read_summary(new)
        return compare(s["experiment"], golden.flatten(s), t["experiment"], golden.flatten(t), rtol)
    finally:
        if was_enabled:
            gc.enable()


_JSON = json.JSONEncoder(ensure_ascii=False).encode


def _json_value(v: Any) -> str:
    """``json.dumps(v, ensure_ascii=False)``; a finite float or an int (nearly every value) by its repr, as json
    spells it, five times faster."""
    if (type(v) is float and math.isfinite(v)) or type(v) is int:
        return repr(v)
    return _JSON(v)


def _plain_width() -> int:
    """The widest line of printable ASCII that rich writes unchanged: the console's width when it writes no style
    (no terminal), else -1 (a terminal's lines all go through rich)."""
    return out_console.width if out_console.color_system is None else -1


def _print_differences(diffs: Sequence[Difference], a: Path, b: Path) -> None:
    """Each difference: its key (and tolerance), then one line per side, its path and its value. A line rich would
    write unchanged goes straight to the console's file, in batches (rich takes ~30 µs a line: minutes for a
    million differences); any other (a terminal's bold, a line to wrap) through rich, in order."""
    width = max(len(str(a)), len(str(b))) + 1
    labels = [f"  {str(side) + ':':<{width}} " for side in (a, b)]
    plain = _plain_width()  # once: rich measures the terminal each time it is asked
    batch: list[str] = []

    def flush() -> None:
        if batch:
            out_console.file.write("\n".join(batch) + "\n")
            batch.clear()

    for d in diffs:
        head = f"{d.key} ({d.tolerance})" if d.tolerance else d.key
        side_a = labels[0] + ("(absent)" if d.ref is ABSENT else _json_value(d.ref))
        side_b = labels[1] + ("(absent)" if d.new is ABSENT else _json_value(d.new))
        whole = head + side_a + side_b
        if (len(head) <= plain and len(side_a) <= plain and len(side_b) <= plain and whole.isascii()
                and whole.isprintable()):
            batch.append(f"{head}\n{side_a}\n{side_b}")
        else:
            for i, line in enumerate((head, side_a, side_b)):
                if len(line) <= plain and line.isascii() and line.isprintable():
                    batch.append(line)
                    continue
                flush()
                if i == 0:
                    out_console.print(Text(d.key, style="bold") + Text(head[len(d.key):]), highlight=False)
                else:  # a path longer than the line stays whole (not folded); the value wraps at its spaces
                    out_console.print(Text(line, overflow="ignore"), highlight=False)
        if len(batch) >= 1000:
            flush()
    flush()


@app.command()
def diff(
    a: Annotated[Path, typer.Argument(help="the reference: a summary.json, an experiment folder (results/<id>) "
                                           "or a results folder (results)")],
    b: Annotated[Path, typer.Argument(help="the one to check, of the same sort as A")],
    rtol: Annotated[float | None, typer.Option(help="one relative tolerance for every number")] = None,
) -> None:
    """Compare the numbers of two experiments' summaries, provenance ignored; or of every experiment two results
    folders both hold (and name those only one holds). Each difference shows both values, each with its path.
    A summary is refused (as bad input) beyond 16 MiB or 1,048,576 quantities, or with a key twice in one JSON
    object or an id twice in one list. Exit status: 0 the same numbers, 1 some differ (or the two are of different
    experiments, or an experiment is in one folder only), 2 bad input."""
    try:
        if rtol is not None and not (math.isfinite(rtol) and 0 <= rtol < 1):
            raise InputError(f"--rtol {rtol:g}", "expected a relative tolerance in [0, 1)")
        (kind_a, fa), (kind_b, fb) = _diff_side(a), _diff_side(b)
        if kind_a != kind_b:
            results, one = (a, b) if kind_a == "results" else (b, a)
            raise InputError(str(results), f"is a results folder and {one} one experiment: give two experiment "
                                           f"folders (or summary.json files), or two results folders")
        if kind_a == "summary":
            pairs = {"": (fa, fb)}
            only_a: list[str] = []
            only_b: list[str] = []
        else:
            ea, eb = _experiment_folders(fa), _experiment_folders(fb)
            pairs = {i: (ea[i] / "summary.json", eb[i] / "summary.json") for i in ea if i in eb}
            only_a, only_b = [i for i in ea if i not in eb], [i for i in eb if i not in ea]
        compared = {i: _compare_files(x, y, rtol) for i, (x, y) in pairs.items()}
    except InputError as err:
        _fail(err)
    differ = bool(only_a or only_b)
    if kind_a == "results":
        out_console.print(Text(f"{len(pairs)} experiment(s) in both {a} and {b}", style="bold"), highlight=False)
    for i, d in compared.items():
        differ |= d.differ
        head = f"{i}: " if i else ""
        where = "" if i else f" in {a} and {b}"
        if not d.same_experiment:
            out_console.print(Text(f"{head}different experiments: {d.ref_experiment} in {pairs[i][0]}, "
                                   f"{d.new_experiment} in {pairs[i][1]}", style="bold red"), highlight=False)
        if d.differences:
            out_console.print(Text(f"{head}{len(d.differences)} of {d.compared} quantities differ{where}",
                                   style="bold red"), highlight=False)
            _print_differences(d.differences, *pairs[i])
        else:
            out_console.print(Text(f"{head}same numbers{where} ({d.compared} quantities)"), highlight=False)
    for only, side in ((only_a, a), (only_b, b)):
        if only:
            out_console.print(Text(f"only in {side}: ", style="bold red") + Text(", ".join(only)), highlight=False)
    if differ:
        raise typer.Exit(1)


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


# where the terminal cannot print Unicode (LANG=C, a latin-1 locale): what a person would write instead
_ASCII = {"ε": "eps", "ν": "nu", "α": "alpha", "β": "beta", "γ": "gamma", "δ": "delta", "θ": "theta", "λ": "lambda",
          "μ": "mu", "π": "pi", "ρ": "rho", "σ": "sigma", "τ": "tau", "φ": "phi", "χ": "chi", "ψ": "psi",
          "ω": "omega", "Δ": "Delta", "Ω": "Omega", "≤": "<=", "≥": ">=", "≈": "~", "≠": "!=", "±": "+/-",
          "×": "x", "·": ".", "−": "-", "–": "-", "—": "--", "…": "...", "′": "'", "″": "''", "«": '"', "»": '"',
          "‘": "'", "’": "'", "“": '"', "”": '"', "→": "->", "←": "<-", "√": "sqrt", "∞": "inf", "°": " deg",
          "²": "^2", "³": "^3", "½": "1/2", "₀": "0", "₁": "1", "₂": "2", "§": "sec.", "µ": "u",
          "\u00a0": " ", "\u202f": " ", "\u2009": " ", "✓": "ok", "✗": "x", "•": "*", "█": "#", "━": "-"}


def _ascii_text(text: str, encoding: str) -> str:
    """``text`` with each character the stream cannot encode written as a person would in ASCII (``_ASCII``, an
    accent dropped), or ``?``."""
    import unicodedata

    out = []
    if "n°" in text and not _encodes("°", encoding):
        text = text.replace("n°", "no.")
    for c in text:
        try:
            c.encode(encoding)
            out.append(c)
        except UnicodeEncodeError:
            alt = _ASCII.get(c) or unicodedata.normalize("NFKD", c).encode("ascii", "ignore").decode() or "?"
            out.append(alt)
    return "".join(out)


def _encodes(text: str, encoding: str) -> bool:
    try:
        text.encode(encoding)
    except (UnicodeEncodeError, LookupError):
        return False
    return True


class _Transliterating:
    """A text stream that writes through ``stream`` what its encoding can hold (``_ascii_text``)."""

    def __init__(self, stream: Any) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        self._stream.write(_ascii_text(text, self._stream.encoding or "ascii"))
        return len(text)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def _cannot_print_unicode(stream: Any) -> bool:
    return not _encodes("ε≤–é", getattr(stream, "encoding", None) or "ascii")


def _streams_for_this_terminal() -> None:
    """Standard output and error in an encoding that cannot print Unicode get ASCII renderings instead of a
    UnicodeEncodeError; JSON on such a stdout is written with \\u escapes (exact, unlike a rendering)."""
    for name in ("stdout", "stderr"):
        stream = getattr(sys, name)
        if stream is not None and _cannot_print_unicode(stream):
            if hasattr(stream, "reconfigure"):
                stream.reconfigure(errors="replace")
            setattr(sys, name, _Transliterating(stream))
            if name == "stdout":
                _JSON_ASCII[0] = True


_JSON_ASCII = [False]


def _last_words(text: str, code: int) -> NoReturn:
    """End the process with one line on stderr (if stderr can still take it) and ``code``, whatever the state of
    stdout: a stdout that cannot be written (a full disk, a closed pipe) is sent to /dev/null first, so that the
    interpreter's own flush at exit prints no traceback."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.__stdout__.fileno() if sys.__stdout__ else 1)
    except (OSError, ValueError, AttributeError):
        pass
    if text:
        try:
            sys.stderr.write(f"error: {text}\n")
            sys.stderr.flush()
        except (OSError, ValueError):
            pass
    os._exit(code)


def main() -> None:
    """The ``resal`` command: every command ends in its result, or one line and an exit status — 2 bad input, 1
    a failure of the environment or of a computation, 128 + n for a signal (SIGINT, SIGTERM, SIGHUP) — never a
    traceback."""
    import errno

    _PROCESS["own"] = True
    _streams_for_this_terminal()
    try:
        from reproductions import processes

        with processes.interruptible():
            try:
                app()
            finally:
                sys.stdout.flush()
    except SystemExit:
        raise
    except Interrupted as exc:
        _last_words(f"interrupted ({exc.name}); earlier results left as they were", 128 + exc.signum)
    except KeyboardInterrupt:
        _last_words("interrupted (SIGINT); earlier results left as they were", 130)
    except BrokenPipeError:  # `resal … | head`: the reader has gone; nothing to say
        _last_words("", 141)
    except OSError as exc:
        if exc.errno in (errno.ENOSPC, errno.EIO, errno.EDQUOT, errno.EFBIG):
            _last_words(f"cannot write ({exc.strerror}): standard output or a file could not take the output", 1)
        _last_words(f"a failure of the environment: {exc.strerror or exc}", 1)
    except MemoryError:
        _last_words("out of memory (a limit on this process's memory? `ulimit -v`)", 1)
    except ImportError as exc:
        _last_words(f"cannot load {exc.name or 'a library'} ({exc}); out of memory, or an incomplete install "
                    "(`make setup`)?", 1)


if __name__ == "__main__":
    main()
