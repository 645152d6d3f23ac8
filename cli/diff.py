"""``resal diff``: the numbers of two experiments' summaries compared, or of every experiment two results folders
both hold."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.text import Text

from cli.app import app
from cli.common import _fail, out_console
from reproductions.diffing import ABSENT, Difference, SummaryDiff, compare
from reproductions.errors import InputError


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


def _compare_files(ref: Path, new: Path, rtol: float | None, names: tuple[Path, Path] | None = None) -> SummaryDiff:
    """Two summary.json files read (an ``InputError`` for either that is bad input) and compared; neither is kept,
    so comparing two results folders holds one pair of summaries in memory at a time. With ``names`` (the two
    arguments as given), summaries of two different experiments are bad input: their quantities are not the same
    ones, and listing them all would bury the one thing that matters."""
    import gc

    from reproductions import golden

    # the summaries are JSON, acyclic: the cyclic collector would only walk their millions of containers again and
    # again as they are made (a fifth of the time of a large diff)
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        s, t = _read_summary(ref), _read_summary(new)
        if names is not None and s["experiment"] != t["experiment"]:
            raise InputError("different experiments", f"{names[0]} is experiment {s['experiment']}, {names[1]} is "
                                                      f"experiment {t['experiment']}: compare summaries of one "
                                                      f"experiment")
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
    """Compare the numbers of two summaries, or of two results folders.

    \b
    Examples:
      resal reproduce coriolis-pendulum --out before
      resal reproduce coriolis-pendulum --out after
      resal diff before/coriolis-pendulum after/coriolis-pendulum
      resal diff before after --rtol 1e-9

    Compares the numbers of two experiments' summaries, provenance ignored; or of every experiment two results
    folders both hold (and names those only one holds). Each difference shows both values, each with its path.
    A summary is refused (as bad input) beyond 16 MiB or 1,048,576 quantities, or with a key twice in one JSON
    object or an id twice in one list. Exit status: 0 the same numbers, 1 some differ (or an experiment is in one
    folder only, or one folder name holds different experiments in the two), 2 bad input (two summaries of
    different experiments included: there is nothing to compare).
    """
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
        compared = {i: _compare_files(x, y, rtol, None if i else (a, b)) for i, (x, y) in pairs.items()}
    except InputError as err:
        _fail(err)
    differ = bool(only_a or only_b)
    if kind_a == "results":
        out_console.print(Text(f"{len(pairs)} experiment(s) in both {a} and {b}", style="bold"), highlight=False)
    for i, d in compared.items():
        differ |= d.differ
        head = f"{i}: " if i else ""
        where = "" if i else f" in {a} and {b}"
        if not d.same_experiment:  # (two results folders: one folder name, two experiments) one line, no list
            out_console.print(Text(f"{head}different experiments: {d.ref_experiment} in {pairs[i][0]}, "
                                   f"{d.new_experiment} in {pairs[i][1]}", style="bold red"), highlight=False)
        elif d.differences:
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
