"""``resal reproduce``: run experiments (or reuse their unchanged folders), write their folders and the paper's
edition, and print an experiment's full table or a summary of several."""

from __future__ import annotations

import json
import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.text import Text

from cli.app import app
from cli.common import _count, _fail, _json, _out_folder, _print_items, _print_rows, err_console, out_console
from cli.terminal import _exit_now
from reproductions.errors import ComputationError, InputError, Interrupted

VERDICT_STYLE = {"reproduced": "green", "differs": "bold red", "not-checkable": "yellow", "consistent": "green",
                 "inconsistent": "bold red", "fitted": "cyan"}
MAX_JOBS = 256  # `reproduce --jobs`: a pool forks all its workers at once, so a typo must not fork thousands


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


def _seconds_text(seconds: float) -> str:
    return f"{seconds:.2f} s" if seconds < 10 else f"{seconds:.1f} s"


class _RunProgress:
    """A run's progress, on stderr only (stdout is the report). On a terminal, a bar per stage: the experiments run
    (N of them), the figures drawn (their total once every experiment has run and said what it draws) and the
    reader's edition being written; the bars are gone once the run ends. Elsewhere (a pipe, a CI log, ``make all |
    tee log``), a run of several experiments says each one as it finishes, with its running time and its
    verdicts, then when the figures and the edition are done, each line flushed at once: a log shows where the
    time goes, as it goes. (A run of one experiment prints its own table at once: no such line.)"""

    def __init__(self, experiments: int) -> None:
        import time

        from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

        self.clock = time.monotonic
        self.start = self.clock()
        self.experiments = experiments
        self.lines = not err_console.is_terminal and experiments > 1
        # the count: "k/N", "k/?" while the total is not known yet, nothing for the edition (one step)
        self.bars = Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.fields[count]}"),
                             TimeElapsedColumn(), console=err_console, transient=True,
                             disable=not err_console.is_terminal)
        self.running = (self.bars.add_task("running experiments", total=experiments, count=f"0/{experiments}")
                        if experiments else None)
        self.drawing: Any = None
        self.writing: Any = None
        self.ran = self.to_draw = 0
        self.figures_said = False
        self.edition_start = 0.0

    def __enter__(self) -> _RunProgress:
        self.bars.__enter__()
        return self

    def __exit__(self, *exc: Any) -> None:
        self.bars.__exit__(*exc)

    def _say(self, line: str) -> None:
        err_console.print(Text(line), soft_wrap=True, highlight=False)
        err_console.file.flush()

    def experiment_done(self, rep: Any, seconds: float) -> None:
        """An experiment has run (``rep``, its ``Reproduction``), in ``seconds``."""
        self.ran += 1
        if self.running is not None:
            self.bars.update(self.running, completed=self.ran, count=f"{self.ran}/{self.experiments}")
        if self.lines:
            from reproductions.report import verdict_counts

            counts, _ = verdict_counts({"verdict": r.verdict, "domain": r.domain} for r in rep.rows)
            measured: dict[str, int] = {}
            for m in rep.measurements:
                measured[m.verdict] = measured.get(m.verdict, 0) + 1
            said = [", ".join(f"{n} {v}" for v, n in counts.items() if n)]
            said.append(f"measured: {', '.join(f'{n} {v}' for v, n in measured.items())}" if measured else "")
            said_text = "; ".join(x for x in said if x) or "no claims"
            self._say(f"{rep.experiment.id}: done in {_seconds_text(seconds)} ({said_text}); "
                      f"{self.ran} of {self.experiments} run")

    def __call__(self, p: Any) -> None:
        """A ``api.RunProgress`` of ``run_and_draw``: an experiment run, or a figure drawn."""
        if p.finished is not None:
            self.experiment_done(p.finished, p.seconds)
            self.to_draw += len(p.finished.figures)
        total = p.figures  # None until every experiment has run
        if self.drawing is None and (self.to_draw or total):
            self.drawing = self.bars.add_task("drawing figures", total=total, count="")
        if self.drawing is not None:
            self.bars.update(self.drawing, completed=p.drawn, total=total,
                             count=f"{p.drawn}/{'?' if total is None else total}")
        if self.lines and total and p.drawn == total and not self.figures_said:
            self.figures_said = True
            self._say(f"figures: {total} drawn; experiments run and figures drawn in "
                      f"{_seconds_text(self.clock() - self.start)}")

    def edition(self, what: str) -> None:
        """The reader's edition is being written (``what`` says so)."""
        self.writing = self.bars.add_task(what, total=None, count="")
        self.edition_start = self.clock()

    def edition_done(self) -> None:
        if self.writing is not None and self.lines:
            self._say(f"reader's edition: written in {_seconds_text(self.clock() - self.edition_start)}")


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
            with _RunProgress(len(exps)) as progress:
                reps = api.parallel_map(api.run, exps, jobs,
                                        finished=lambda _i, rep, seconds: progress.experiment_done(rep, seconds))
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
    """Run experiments and check every value the paper prints.

    \b
    Examples:
      resal reproduce coriolis-pendulum
      resal reproduce marble-drop cue-stroke --out my-results
      resal reproduce coriolis-pendulum --json
      resal reproduce --all

    Each experiment runs, every printed value is compared, and tables and figures are written into
    OUT/<experiment>/, with the paper's index, table, reader's edition (index.html) and report.pdf into OUT. One
    experiment prints its full table; several, a summary. With --json and no --out, only prints: nothing is
    written. An experiment whose folder was computed from the same config, data files and code is reused, not
    recomputed (--force).
    """
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
            with _RunProgress(len(exps)) as progress:
                # run all first: a bad data file stops everything before anything is written; figures are drawn
                # one by one across the processes as their experiment finishes, into a scratch folder
                scratch = None
                try:
                    written: dict[str, Path] = {}
                    if exps:
                        from reproductions import api

                        with report.signals_deferred():  # made and known together: `finally` removes it
                            scratch = report.make_staging(out, "figures")
                        reps = api.run_and_draw(exps, jobs, scratch, progress)
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
                        index = _write_index(out, force, progress.edition)
                        if index:
                            progress.edition_done()
                finally:
                    if scratch is not None:
                        report.remove_staging(scratch)
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
