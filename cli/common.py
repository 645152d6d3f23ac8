"""What several commands share: the consoles, the one-line error (``_fail``), JSON on stdout, the parsers of the
options several commands take, and the renderings of rows that more than one command prints."""

from __future__ import annotations

import json
import os
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any, NoReturn

import typer
from rich import box
from rich.console import Console
from rich.table import Table
from rich.text import Text

from cli.terminal import _JSON_ASCII
from reproductions.errors import ComputationError, InputError, did_you_mean


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


class _Console(Console):
    """A Rich console that prints text as it is, without its automatic highlighting (numbers, words in quotes…:
    only explicit styles are coloured); not writing to a terminal (a pipe, a file), its lines end without the
    spaces that pad a table's cells to their width."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(highlight=False, **kwargs)

    def _render_buffer(self, buffer: Any) -> str:
        text = super()._render_buffer(buffer)
        if not self.is_terminal and " \n" in text:
            text = _PADDING.sub("", text)  # the spaces before each newline; a line still being printed keeps its own
        return text


_PADDING = re.compile(r" +(?=\n)")
out_console = _Console(_environ=_environ())
err_console = _Console(stderr=True, _environ=_environ())


def _json(obj: Any) -> str:
    """Strict JSON (no NaN or Infinity, which are not JSON): a non-finite number is a bug, so it raises. On a
    stdout that cannot print Unicode, non-ASCII characters are written as JSON escapes."""
    return json.dumps(obj, indent=2, ensure_ascii=_JSON_ASCII[0], allow_nan=False)


def _fail(err: InputError) -> NoReturn:
    """One message on stderr; exit 2 for bad input, 1 for a computation that failed on valid input."""
    err_console.print(Text("error: ", style="bold red") + Text(str(err)), soft_wrap=True)  # one line, unwrapped
    raise typer.Exit(1 if isinstance(err, ComputationError) else 2)


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


def _plain_table() -> Table:
    """A table that reads piped: no frame, a rule under the header, two spaces between columns."""
    return Table(box=box.SIMPLE_HEAD, show_edge=False, pad_edge=False, padding=(0, 1), collapse_padding=True)


def _known_models(models: list[str] | None, extra: tuple[str, ...] = ()) -> list[str]:
    """The models named on the command line (none: all), each a model of the registry (or one of ``extra``)."""
    from reproductions.mechanics import registry

    names = list(models or [])
    known = [*registry.MODELS, *extra]
    unknown = [m for m in names if m not in known]
    if unknown:
        _fail(InputError(f"model '{unknown[0]}'", f"unknown model (expected some of: {', '.join(known)})"
                                                  f"{did_you_mean(unknown[0], known)}"))
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


def _write_report(write: Callable[[dict, Path], Any], rep: dict, out: Path, what: str) -> Any:
    """``write(rep, out)`` for ``bench`` and ``stress``: bad input exits 2; the environment (a full disk) exits 1
    saying that the earlier ``what`` is as it was (it is replaced only whole)."""
    try:
        return write(rep, out)
    except InputError as err:
        _fail(err)
    except OSError as err:
        _fail(ComputationError(f"--out {out}", f"cannot write the {what} ({err.strerror or err}); the earlier one is "
                                               "as it was"))
