"""``resal diff``: duplicated keys and ids refused, different experiments a difference, the work linear in the
quantities, the size bounded, and the fast writing of differences the same text rich writes."""

from __future__ import annotations

import copy
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from cli_helpers import assert_bad, invoke
from typer.testing import CliRunner, Result

from cli import common
from cli import diff as diff_cmd
from cli.main import app
from reproductions import diffing, golden


def summary(n: int = 2, experiment: str = "x", shift: float = 0.0) -> dict[str, Any]:
    """A summary with ``n`` rows, an identifiability entry with a family, a table and a modern symbol."""
    return {
        "experiment": experiment,
        "rows": [{"id": f"r{i}", "printed": 1.0 + i + shift, "computed": 1.0 + i + shift, "rel_diff": 0.0,
                  "tolerance": 0.01, "verdict": "reproduced"} for i in range(n)],
        "fits": [],
        "identifiability": [{"id": "fit", "rank": 1, "null_directions": [[1.0, 0.0]], "parameters": ["a", "b"],
                             "point": [1.0, 2.0],
                             "family_of_solutions": {"kind": "line", "along": "a", "holds": True, "ends": [0, 1],
                                                     "ranges": [[0, 1]]}}],
        "tables": [{"name": "t", "rows": [[1.0, 2.0]]}],
        "modern": [{"symbol": "e", "resal": 0.5}],
        "figures": [],
    }


def write(path: Path, obj: Any) -> Path:
    path.write_text(json.dumps(obj), encoding="utf-8")
    return path


def one_line_error(res: Result, *fragments: str) -> str:
    err = assert_bad(res, *fragments)
    assert err.count("\n") == 1, err
    return err


# -- duplicated keys and ids: bad input, exit 2 ------------------------------------------------------------------
def test_a_key_twice_deep_in_the_json_is_refused_naming_it(tmp_path: Path) -> None:
    good = write(tmp_path / "a.json", summary())
    text = json.dumps(summary())
    # the family of solutions, four levels down, says "holds" twice: json.loads would keep the last silently
    twice = text.replace('"holds": true', '"holds": false, "holds": true', 1)
    assert twice != text
    bad = tmp_path / "b.json"
    bad.write_text(twice, encoding="utf-8")
    for args in ((good, bad), (bad, good)):
        one_line_error(invoke("diff", *args), f"{bad}: ", "'holds' appears twice")


def test_a_key_twice_in_a_row_names_the_row(tmp_path: Path) -> None:
    good = write(tmp_path / "a.json", summary())
    bad = tmp_path / "b.json"
    bad.write_text(json.dumps(summary()).replace('"computed": 2.0', '"computed": 2.0, "computed": 7.0', 1),
                   encoding="utf-8")
    one_line_error(invoke("diff", good, bad), f"{bad}: ", "'computed' appears twice", "id 'r1'")


def test_a_top_level_key_twice_is_refused(tmp_path: Path) -> None:
    good = write(tmp_path / "a.json", summary())
    bad = tmp_path / "b.json"
    bad.write_text(json.dumps(summary())[:-1] + ', "rows": []}', encoding="utf-8")
    one_line_error(invoke("diff", good, bad), f"{bad}: ", "'rows' appears twice")


@pytest.mark.parametrize(("section", "field"), [("rows", "id"), ("tables", "name"), ("identifiability", "id")])
def test_an_id_twice_is_refused_naming_it(tmp_path: Path, section: str, field: str) -> None:
    s = summary()
    s[section].append(copy.deepcopy(s[section][0]))
    twice = s[section][0][field]
    good, bad = write(tmp_path / "a.json", summary()), write(tmp_path / "b.json", s)
    one_line_error(invoke("diff", good, bad), f"{bad}: ", f"{section}[{len(s[section]) - 1}]", repr(twice),
                   "unique")
    one_line_error(invoke("diff", bad, good), f"{bad}: ")


def test_a_row_id_twice_with_the_same_numbers_is_still_refused(tmp_path: Path) -> None:
    """The attack: a second row r0 with other numbers, compared with itself, said "same numbers"."""
    s = summary()
    s["rows"].append({**s["rows"][0], "computed": 99.0})
    bad = write(tmp_path / "b.json", s)
    one_line_error(invoke("diff", bad, bad), f"{bad}: ", "'r0'")


def test_a_modern_symbol_repeats_per_source_but_with_one_resal_value(tmp_path: Path) -> None:
    """Summaries resal writes list a modern symbol once per source (ball-ball has e_bb three times)."""
    s = summary()
    s["modern"].append({"symbol": "e", "resal": 0.5, "source": "another"})
    same = write(tmp_path / "a.json", s)
    res = invoke("diff", same, same)
    assert res.exit_code == 0, res.output
    s["modern"][1]["resal"] = 0.6
    bad = write(tmp_path / "b.json", s)
    one_line_error(invoke("diff", same, bad), f"{bad}: ", "modern[1]", "'e'", "another resal value")


# -- different experiments: two summaries, bad input (exit 2, one line); two results folders, a difference ---------
def test_two_summaries_of_different_experiments_are_one_line_of_bad_input(tmp_path: Path) -> None:
    a = write(tmp_path / "a.json", summary(experiment="ball-ball"))
    b = write(tmp_path / "b.json", summary(experiment="cue-stroke", shift=1.0))  # numbers differ too: not listed
    one_line_error(invoke("diff", a, b), f"{a} is experiment ball-ball, {b} is experiment cue-stroke",
                   "compare summaries of one experiment")
    assert invoke("diff", a, a).exit_code == 0


def test_different_experiments_in_two_results_folders_differ(tmp_path: Path) -> None:
    for side, eid, shift in (("a", "ball-ball", 0.0), ("b", "cue-stroke", 1.0)):
        (tmp_path / side / "x").mkdir(parents=True)
        write(tmp_path / side / "x" / "summary.json", summary(experiment=eid, shift=shift))
    res = invoke("diff", tmp_path / "a", tmp_path / "b")
    assert res.exit_code == 1, res.output
    assert "x: different experiments: ball-ball" in res.stdout
    assert "quantities differ" not in res.stdout  # the one line, not the quantities of two experiments


def test_the_exit_statuses_are_in_the_help() -> None:
    text = " ".join(invoke("diff", "--help").stdout.split())
    assert "Exit status: 0 the same numbers, 1 some differ" in text and "2 bad input" in text
    assert "different experiments" in text
    assert f"{golden.MAX_SUMMARY_BYTES >> 20} MiB or {golden.MAX_SUMMARY_QUANTITIES:,} quantities" in text


# -- the size is bounded before the quantities are made ------------------------------------------------------------
def test_more_quantities_than_the_bound_are_refused_naming_it(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    a = write(tmp_path / "a.json", summary(n=3))
    monkeypatch.setattr(golden, "MAX_SUMMARY_QUANTITIES", 10)
    one_line_error(invoke("diff", a, a), f"{a}: ", "24 quantities to compare: expected at most 10")


def test_the_bound_counts_a_table_row_as_a_quantity() -> None:
    s = summary(n=0)
    s["tables"][0]["rows"] = [0] * 1000
    assert golden.quantity_count(s) >= len(golden.flatten(s)) >= 1000
    assert golden.quantity_count(summary(n=5)) >= len(golden.flatten(summary(n=5)))


# -- values flatten cannot use: bad input, not a traceback ---------------------------------------------------------
@pytest.mark.parametrize(("change", "fragment"), [
    (lambda s: s["tables"][0].update(rows=5), "tables[0].rows must be a list"),
    (lambda s: s["identifiability"][0].update(rank=None), "identifiability[0].rank must be a number"),
    (lambda s: s["identifiability"][0].update(parameters=3), "identifiability[0].parameters must be a list"),
    (lambda s: s["rows"][0].update(printed=None, tolerance="abc"), "rows[0].tolerance must be null or a number"),
    (lambda s: s["rows"][0].update(printed=None, tolerance=10 ** 400), "rows[0].tolerance"),
    (lambda s: s["rows"][0].update(printed=None, tolerance=-1), "rows[0].tolerance must be null or a number ≥ 0"),
    (lambda s: s.update(experiment=["x"]), "'experiment' must be a string"),
])
def test_a_value_of_the_wrong_type_is_bad_input(tmp_path: Path, change: Callable[[dict], None], fragment: str) -> None:
    s = summary()
    change(s)
    bad = write(tmp_path / "b.json", s)
    one_line_error(invoke("diff", write(tmp_path / "a.json", summary()), bad), f"{bad}: ", fragment)


def test_odd_values_are_compared_not_crashed_on(tmp_path: Path) -> None:
    s = summary()
    s["rows"][0]["computed"] = 10 ** 400  # beyond float range
    s["identifiability"][0]["null_directions"] = [1, "a"]  # no vectors
    a = write(tmp_path / "a.json", s)
    assert invoke("diff", a, a).exit_code == 0
    t = copy.deepcopy(s)
    t["rows"][0]["computed"] = 10 ** 400 + 1  # within rtol 1e-9
    t["identifiability"][0]["null_directions"] = [1, "b"]
    res = invoke("diff", a, write(tmp_path / "b.json", t))
    assert res.exit_code == 1, res.output
    assert "identifiability.fit.null_directions" in res.stdout and "rows.r0.computed" not in res.stdout


# -- the comparison: the golden test, and linear ------------------------------------------------------------------
def test_diff_judges_each_quantity_as_golden_compare_does() -> None:
    ref = summary(n=5)
    new = copy.deepcopy(ref)
    new["rows"][1]["computed"] *= 1 + 1e-6  # beyond rtol 1e-9
    new["rows"][2]["computed"] *= 1 + 1e-12  # within
    new["rows"][3]["verdict"] = "differs"
    new["identifiability"][0]["null_directions"] = [[-2.0, 0.0]]  # the same line
    new["tables"][0]["rows"] = [[1.0, 2.1]]
    del new["rows"][4]
    new["modern"].append({"symbol": "mu", "resal": 0.2})
    d = diffing.compare(ref["experiment"], golden.flatten(ref), new["experiment"], golden.flatten(new))
    lines = golden.compare(golden.golden_object(ref), new)
    assert [x.key for x in d.differences] == [ln.split(": ")[0] for ln in lines]
    assert [x.key for x in d.differences] == [
        "rows.r1.computed", "rows.r3.verdict", *(f"rows.r4.{k}" for k in ("computed", "printed", "rel_diff",
                                                                          "tolerance", "verdict")),
        "tables.t.0", "modern.mu.resal"]
    assert d.differences[-1].ref is diffing.ABSENT and d.differences[-1].tolerance == ""
    assert d.differences[2].new is diffing.ABSENT
    assert d.compared == len(golden.flatten(ref).keys() | golden.flatten(new).keys())
    assert d.differ and d.same_experiment


def _calls(f: Callable[[], object]) -> int:
    """Python and C function calls made by ``f()``: a count of work that, unlike a clock, does not vary."""
    n = 0

    def count(frame: object, event: str, arg: object) -> None:
        nonlocal n
        n += 1

    sys.setprofile(count)
    try:
        f()
    finally:
        sys.setprofile(None)
    return n


def _every_value_changed(n: int, tmp_path: Path) -> tuple[Path, Path]:
    return (write(tmp_path / f"a{n}.json", summary(n)), write(tmp_path / f"b{n}.json", summary(n, shift=0.5)))


@pytest.mark.parametrize("columns", [20, 400])
def test_diff_is_linear_in_the_differences(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, columns: int) -> None:
    """A summary four times longer, every value changed, costs about four times the calls, through the whole
    command (it once searched the list of differences for each key: sixteen times). Both ways a line can go are
    measured alone: at 20 columns every line goes through rich, at 400 none does. (With the runner's own folder
    and width, the share of lines long enough for rich grew with n and with the length of the temporary path,
    which differs from machine to machine: the count measured that share, not the comparison.)"""
    small, large = 150, 600
    monkeypatch.setattr(common.out_console, "_width", columns)  # the console was sized at import
    monkeypatch.chdir(tmp_path)
    runs = {n: tuple(p.relative_to(tmp_path) for p in _every_value_changed(n, tmp_path)) for n in (small, large)}

    def run(n: int) -> None:
        res = CliRunner().invoke(app, ["diff", *map(str, runs[n])])
        assert res.exit_code == 1 and f"rows.r{n - 1}.printed" in res.stdout, res.output

    run(small)  # imports and caches warmed first
    calls = {n: _calls(lambda n=n: run(n)) for n in (small, large)}
    assert calls[large] < 4.5 * calls[small], calls


def test_golden_compare_and_diffing_compare_are_linear() -> None:
    ref = {n: summary(n) for n in (200, 800)}
    new = {n: summary(n, shift=0.5) for n in (200, 800)}
    for f in (lambda n: golden.compare(golden.golden_object(ref[n]), new[n]),
              lambda n: diffing.compare("x", golden.flatten(ref[n]), "x", golden.flatten(new[n]))):
        calls = {n: _calls(lambda n=n, f=f: f(n)) for n in ref}
        assert calls[800] < 4.2 * calls[200], calls


# -- the differences written as rich writes them, faster -----------------------------------------------------------
def test_differences_are_written_as_rich_writes_them(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Lines that fit go straight to the file; the text must be what rich alone writes: lines at the console's
    width exactly and one more, a path longer than the line, values that wrap, non-ASCII and wide characters."""
    ref, new = summary(n=0), summary(n=0)
    for i in range(30):  # heads of 45 to 104 characters, around the 80 columns
        rid = "r" + "x" * (2 * i)
        ref["rows"].append({"id": rid, "printed": 1.0, "computed": "a b " * i, "rel_diff": [0.1] * i,
                            "tolerance": None, "verdict": "é" if i % 3 else "漢字"})
        new["rows"].append({"id": rid, "printed": 2.0, "computed": "c d " * i, "rel_diff": [0.2] * i,
                            "tolerance": 1e-3, "verdict": "\t" if i % 2 else "x"})
    deep = tmp_path / ("folder-with-a-long-name-" * 3)
    deep.mkdir()
    monkeypatch.chdir(tmp_path)
    pairs = [(write(Path("a.json"), ref), write(Path("b.json"), new)),
             (write(deep / "a.json", ref), write(Path("b.json"), new))]
    for a, b in pairs:
        for width in (80, 100):
            fast = _run_at(width, a, b)
            monkeypatch.setattr(diff_cmd, "_plain_width", lambda: -1)  # every line through rich
            slow = _run_at(width, a, b)
            monkeypatch.undo()
            monkeypatch.chdir(tmp_path)
            assert fast == slow
            assert fast.count("\n") > 200


def _run_at(width: int, a: Path, b: Path) -> str:
    before = common.out_console._width
    common.out_console.width = width
    try:
        res = CliRunner(env={"COLUMNS": str(width)}).invoke(app, ["diff", str(a), str(b)])
    finally:
        common.out_console._width = before
    assert res.exit_code == 1, res.output
    return res.stdout
