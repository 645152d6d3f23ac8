"""One reader (issue 30, item 7): a CSV file and a program's arrays become the same ``series.Table``, and every
reader and check works on it. Arrays are never written to a file, and their places are named as the caller knows
them (``data row i``, ``rows 7–9``), never as the lines of a file the caller never saw."""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np
import pytest

from reproductions import api, locate
from reproductions.errors import InputError
from reproductions.fit.kinds import KINDS
from reproductions.series import read_series, read_table, table_from_columns

NUMERIC = ("rebound", "cushion", "drop", "pendulum", "ricochet", "bounces", "ball-ball")


def _columns(kind: str) -> dict[str, np.ndarray]:
    tab = read_table(locate.examples_dir() / KINDS[kind].example)
    return {h: np.array([float(r[j]) for _, r in tab.rows]) for j, h in enumerate(tab.header)}


@pytest.mark.parametrize("kind", NUMERIC)
def test_arrays_and_their_file_give_the_same_fit(kind: str) -> None:
    """The example file's columns as arrays: every estimate and interval identical to the file's (the numbers
    are the same floats: each cell as repr writes it reads back exactly)."""
    opts = {"bootstrap": 0} if "bootstrap" in KINDS[kind].options else {}
    if kind == "ball-ball":
        opts["R"] = 0.02855
    from_file = api.fit(kind, locate.examples_dir() / KINDS[kind].example, **opts)
    from_arrays = api.fit(kind, _columns(kind), **opts)
    assert [(e.id, e.value, e.ci95) for e in from_arrays.estimates] == \
        [(e.id, e.value, e.ci95) for e in from_file.estimates]
    assert [w.code for w in from_arrays.warnings] == [w.code for w in from_file.warnings]
    assert from_arrays.summary["file"] == "data"


def test_arrays_are_never_written(monkeypatch) -> None:
    def refuse(*a: object, **k: object) -> None:
        raise AssertionError("a file was written for arrays")

    monkeypatch.setattr(tempfile, "TemporaryDirectory", refuse)
    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    monkeypatch.setattr(Path, "write_text", refuse)
    monkeypatch.setattr(Path, "write_bytes", refuse)
    fit = api.fit("rebound", _columns("rebound"), bootstrap=0)
    assert 0.79 < fit["e"].value < 0.81


def test_a_bad_array_cell_is_named_by_its_index() -> None:
    cols = _columns("rebound")
    cols["u1_mps"][3] = math.nan
    with pytest.raises(InputError) as err:
        api.fit("rebound", cols)
    assert err.value.where == "data row 3" and "got 'NaN'" in err.value.message, (err.value.where, err.value.message)


def test_a_unit_jump_in_arrays_names_their_rows() -> None:
    """Rows 9–11 (indices) typed in km/h among m/s: the group is named by index, as the arrays are."""
    rng = np.random.default_rng(4)
    u0 = rng.uniform(0.5, 4.0, 14)
    u1 = 0.8 * u0 + 0.01 * rng.standard_normal(14)
    u1[9:12] /= 3.6
    fit = api.fit("rebound", {"u0_mps": u0, "u1_mps": u1}, bootstrap=0)
    text = " ".join(w.message for w in fit.warnings)
    assert "rows 9–11:" in text and "lines" not in text, text


def test_the_table_of_arrays_is_the_table_of_their_file(tmp_path: Path) -> None:
    f = tmp_path / "s.csv"
    f.write_text("# a comment\nV0,V1\n1.5,-1.2\n\n2.0,-1.6\n", encoding="utf-8")
    a, b = read_series(f, ("V0", "V1")), read_series(table_from_columns(["V0", "V1"], [["1.5", "2.0"],
                                                                                      ["-1.2", "-1.6"]]), ("V0", "V1"))
    assert all(np.array_equal(a[k], b[k]) for k in ("V0", "V1"))
    assert (a.at(1), b.at(1)) == (f"{f}:5", "data row 1")
    assert (read_table(f).head_line, read_table(f).rows[1][0]) == (2, 5)
