"""The examples of ``resal fit`` as tables a test can change the way a user might get them wrong: a header renamed
(a unit left out, columns swapped), a column scaled (cm/s, degrees, a sign), a cell mistyped; written back with the
example's comment lines, so that the lines a message names are the example's own."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from typer.testing import CliRunner, Result

from cli.main import app
from reproductions.fit.kinds import KINDS

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
Table = tuple[list[str], list[list[str]]]
Change = Callable[[Table], Table]
runner = CliRunner()


def table(example: str) -> tuple[list[str], Table]:
    """The example's comment lines, and its header and rows as text."""
    lines = (EXAMPLES / example).read_text(encoding="utf-8").splitlines()
    data = [ln.split(",") for ln in lines if ln and not ln.startswith("#")]
    return [ln for ln in lines if ln.startswith("#")], (data[0], data[1:])


def header(names: list[str]) -> Change:
    return lambda t: (names, t[1])


def scale(j: int, k: float) -> Change:
    """Column j times k (a unit, a sign)."""
    return lambda t: (t[0], [[*r[:j], repr(float(r[j]) * k), *r[j + 1:]] for r in t[1]])


def rows_scaled(rows: tuple[int, ...], j: int, k: float) -> Change:
    """Column j times k on some rows only (0: the first data row): those rows in another unit."""
    return lambda t: (t[0], [[*r[:j], repr(float(r[j]) * k), *r[j + 1:]] if i in rows else r
                             for i, r in enumerate(t[1])])


def shift(row: int, j: int, by: float) -> Change:
    """One cell mistyped: row ``row`` (0: the first data row), column j, plus ``by``."""
    def f(t: Table) -> Table:
        rows = [list(r) for r in t[1]]
        rows[row][j] = repr(float(rows[row][j]) + by)
        return t[0], rows
    return f


def cell(row: int, j: int, text: str) -> Change:
    """One cell replaced by ``text`` (a dash, NA, nothing)."""
    def f(t: Table) -> Table:
        rows = [list(r) for r in t[1]]
        rows[row][j] = text
        return t[0], rows
    return f


def first_row_only(t: Table) -> Table:
    """Every row the first: trials that agree exactly (read to a coarse precision, or copied)."""
    return t[0], [list(t[1][0]) for _ in t[1]]


def chain(*fs: Change) -> Change:
    def f(t: Table) -> Table:
        for g in fs:
            t = g(t)
        return t
    return f


def same(t: Table) -> Table:
    return t


def line(row: int) -> int:
    """The file line of data row ``row`` of an example (two comment lines and the header come first)."""
    return row + 4


def write(tmp_path: Path, example: str, change: Change) -> Path:
    comments, tab = table(example)
    head, rows = change(tab)
    f = tmp_path / example
    f.write_text("\n".join([*comments, ",".join(head), *(",".join(r) for r in rows)]) + "\n", encoding="utf-8")
    return f


def invoke(tmp_path: Path, kind: str, f: Path, *args: str) -> Result:
    """``resal fit <kind> f --json --no-plot --out <tmp>/out`` (and ``--bootstrap 0`` where the kind has one) and
    the arguments given."""
    boot = ["--bootstrap", "0"] if "bootstrap" in KINDS[kind].options else []
    return runner.invoke(app, ["fit", kind, str(f), "--json", "--no-plot", *boot, "--out", str(tmp_path / "out"),
                               *args])


def ok(tmp_path: Path, kind: str, f: Path, *args: str) -> dict:
    res = invoke(tmp_path, kind, f, *args)
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)
