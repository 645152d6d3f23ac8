"""The findings of the reader's edition (``question:`` and ``findings:`` of each config) against the rows that carry
them, on one ``resal reproduce --all``.

A finding is one sentence for the first screen of results/index.html; it must say what its rows say. So each
category asks something of its rows' verdicts (configs/README.md, "Findings"), and every number the sentence quotes
with a decimal point or as a percentage must be one that its rows carry (printed, computed, relative difference or
note), within the rounding of its written digits: a finding cannot quote a number that no row gives.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest
from cli_helpers import assert_bad, invoke

from reproductions import api
from reproductions.config import FINDINGS

CONFIGS = Path(__file__).resolve().parent.parent / "configs"
EXPERIMENTS = api.list_experiments()
IDS = [e.id for e in EXPERIMENTS]

# what each category asks of the rows a finding names (the codes of config.FINDINGS)
NEEDS = {
    "erratum": "at least one of its rows differs with reason erratum",
    "formula": "at least one of its rows differs with reason repair or erratum",
    "premise": "at least one of its rows differs with reason assumption",
    "beyond": "at least one of its rows differs (what the paper does not say shows as a claim it fails)",
    "holds": "every row it names is reproduced",
    "measured": "it names only measured rows (today's measurements against the mechanics), not printed claims",
}

# numbers a finding may quote without a row carrying them, each with its reason; empty on purpose: keep it short
ALLOWED_NUMBERS: dict[float, str] = {}

# in a finding: a number with a decimal point, or a percentage (decimal points only: the text is English)
_TEXT_NUMBER = re.compile(r"(?<![\w.])(\d+\.\d+|\d+)(\s?%)?")
# in a row's printed text or note: French decimal commas too, and exponents
_ROW_NUMBER = re.compile(r"\d+(?:[.,]\d+)?(?:[eE][+-]?\d+)?")


def _quoted(text: str) -> list[tuple[float, int, bool, str]]:
    """The numbers a finding quotes that the check covers: (value, decimals, percentage, as written)."""
    out = []
    for m in _TEXT_NUMBER.finditer(text):
        digits, pct = m.group(1), bool(m.group(2))
        if "." not in digits and not pct:
            continue  # an integer: an equation, a section, a count
        decimals = len(digits.split(".")[1]) if "." in digits else 0
        out.append((float(digits), decimals, pct, m.group(0)))
    return out


def _carried(row: dict) -> set[float]:
    """Every number a row carries, unsigned: printed, computed, relative difference (also in %), and the numbers
    written in its printed text and note; of a measured row, the measurement, the prediction and its interval, and
    the numbers written in its published text, uncertainty and note."""
    vals: set[float] = set()
    for v in row.get("interval") or ():
        if isinstance(v, int | float) and math.isfinite(v):
            vals.add(abs(float(v)))
    for k in ("measured_text", "uncertainty"):
        for tok in _ROW_NUMBER.findall(row.get(k) or ""):
            vals.add(float(tok.replace(",", ".")))
    for k in ("printed", "computed", "rel_diff", "measured", "predicted"):
        v = row.get(k)
        if isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v):
            vals.add(abs(float(v)))
    if isinstance(row.get("rel_diff"), int | float):
        vals.add(abs(100.0 * row["rel_diff"]))
    for k in ("printed_text", "note"):
        for tok in _ROW_NUMBER.findall(row.get(k) or ""):
            vals.add(float(tok.replace(",", ".")))
    return vals


def _matches(value: float, decimals: int, pct: bool, carried: set[float]) -> bool:
    """Is ``value``, written with ``decimals`` decimals, the rounding of a carried number (a percentage also of a
    carried fraction times 100)?"""
    half = 0.5 * 10.0 ** -decimals * (1 + 1e-9) + 1e-12
    candidates = carried | ({100.0 * c for c in carried} if pct else set())
    return any(abs(c - value) <= half for c in candidates)


# -- the configs, as loaded -----------------------------------------------------------------------------------------
@pytest.mark.parametrize("exp", EXPERIMENTS, ids=IDS)
def test_every_experiment_asks_a_question_and_has_findings(exp):
    assert exp.question.strip(), f"{exp.id}: no question"
    assert exp.question.rstrip().endswith("?"), f"{exp.id}: the question is not a question: {exp.question!r}"
    assert exp.findings, f"{exp.id}: no findings"
    for f in exp.findings:
        assert f.category in FINDINGS and 1 <= f.consequence <= 5, f
        assert len(f.text) <= 300, f"{exp.id}/{f.id}: {len(f.text)} characters (at most 300)"
        assert not re.search(r"\\[a-z]+|\$", f.text), f"{exp.id}/{f.id}: LaTeX in the text"
        assert not re.search(r"\d,\d", f.text), f"{exp.id}/{f.id}: a decimal comma in the text"


def test_consequence_ranks_reach_both_ends():
    cons = [f.consequence for e in EXPERIMENTS for f in e.findings]
    assert sum(c >= 4 for c in cons) >= 3, f"fewer than three findings of consequence ≥ 4: {sorted(cons)}"
    assert min(cons) <= 2, f"no finding of small consequence: {sorted(cons)}"
    paper = [f for e in EXPERIMENTS for f in e.findings if f.category != "measured"]
    assert 25 <= len(paper) <= 40, f"{len(paper)} findings on the paper's claims (aim: 25-40)"
    assert len(cons) - len(paper) <= 12, f"{len(cons) - len(paper)} findings on today's measurements (aim: ≤ 12)"
    ids = [(e.id, f.id) for e in EXPERIMENTS for f in e.findings]
    assert len(set(ids)) == len(ids)


def test_every_category_is_used():
    used = {f.category for e in EXPERIMENTS for f in e.findings}
    assert used == set(FINDINGS), f"unused categories: {set(FINDINGS) - used}"
    assert set(NEEDS) == set(FINDINGS)


# -- against the run ------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def summaries(reproduced_all):
    folder, _ = reproduced_all
    return {i: json.loads((folder / i / "summary.json").read_text(encoding="utf-8")) for i in IDS}


def _findings(summaries):
    for eid in IDS:
        s = summaries[eid]
        rows = {r["id"]: r for r in (*s["rows"], *s.get("measurements", ()))}
        for f in s["findings"]:
            yield eid, s, rows, f


def test_the_summary_carries_the_question_and_findings(summaries):
    for e in EXPERIMENTS:
        s = summaries[e.id]
        assert s["question"] == e.question
        assert [f["id"] for f in s["findings"]] == [f.id for f in e.findings]
        assert [f["text"] for f in s["findings"]] == [f.text for f in e.findings]


def test_rows_and_figures_exist(summaries):
    bad = []
    for eid, s, rows, f in _findings(summaries):
        bad += [f"{eid}/{f['id']}: no row {r}" for r in f["rows"] if r not in rows]
        if f["figure"] is not None and f"{f['figure']}.png" not in s["figures"]:
            bad.append(f"{eid}/{f['id']}: no figure {f['figure']}.png (figures: {s['figures']})")
    assert not bad, "\n".join(bad)


def _category_problem(category: str, rows: list[dict]) -> str | None:
    differs = [r for r in rows if r["verdict"] == "differs"]
    measured = [r for r in rows if "measured_text" in r]
    if measured and category != "measured":
        return f"{category} cannot rest on measured rows ({', '.join(r['id'] for r in measured)}): use 'measured'"
    ok = {
        "erratum": any(r["reason"] == "erratum" for r in differs),
        "formula": any(r["reason"] in ("repair", "erratum") for r in differs),
        "premise": any(r["reason"] == "assumption" for r in differs),
        "beyond": bool(differs),
        "holds": all(r["verdict"] == "reproduced" for r in rows),
        "measured": len(measured) == len(rows),
    }[category]
    if ok:
        return None
    return f"{category} needs {NEEDS[category]}; its rows: " + ", ".join(
        f"{r['id']} {r['verdict']}" + (f"/{r['reason']}" if r.get("reason") else "") for r in rows)


def test_each_category_rests_on_its_rows(summaries):
    bad = []
    for eid, _, rows, f in _findings(summaries):
        problem = _category_problem(f["category"], [rows[r] for r in f["rows"]])
        if problem:
            bad.append(f"{eid}/{f['id']}: {problem}")
    assert not bad, "\n".join(bad)


def test_every_quoted_number_is_carried_by_a_row(summaries):
    bad = []
    for eid, _, rows, f in _findings(summaries):
        carried = set().union(*(_carried(rows[r]) for r in f["rows"]))
        for value, decimals, pct, written in _quoted(f["text"]):
            if value in ALLOWED_NUMBERS or _matches(value, decimals, pct, carried):
                continue
            bad.append(f"{eid}/{f['id']}: '{written}' is in none of the rows {f['rows']}")
    assert not bad, "\n".join(bad)


# -- the check itself -----------------------------------------------------------------------------------------------
def test_the_number_check_parses_and_rounds():
    assert [(v, d, p) for v, d, p, _ in _quoted("ε = 0.1010 on 2/3, 83% of eq. (9), 5.8 %, n°5, 1883")] == [
        (0.1010, 4, False), (83.0, 0, True), (5.8, 1, True)]
    row = {"printed": 0.155, "computed": 0.10102, "rel_diff": -0.348, "printed_text": "ε = 0,155",
           "note": "errs by up to 83% (1,55 m/s; 2.2e-10)"}
    carried = _carried(row)
    assert _matches(0.1010, 4, False, carried) and _matches(0.155, 3, False, carried)
    assert _matches(1.55, 2, False, carried) and _matches(83, 0, True, carried) and _matches(34.8, 1, True, carried)
    assert not _matches(0.102, 3, False, carried) and not _matches(0.17, 2, False, carried)
    assert not _matches(0.5, 1, True, carried)
    assert _category_problem("holds", [{"id": "a", "verdict": "differs", "reason": "ocr"}])
    assert _category_problem("erratum", [{"id": "a", "verdict": "differs", "reason": "ocr"}])
    assert _category_problem("formula", [{"id": "a", "verdict": "differs", "reason": "repair"}]) is None
    m = {"id": "m", "verdict": "inconsistent", "measured_text": "0.251 m/s", "uncertainty": "σ = 0.0003",
         "measured": 0.251, "predicted": 0.397, "interval": [0.338, 0.459]}
    assert _category_problem("measured", [m]) is None and _category_problem("beyond", [m])
    assert _category_problem("measured", [m, {"id": "a", "verdict": "differs", "reason": "ocr"}])
    assert _matches(0.338, 3, False, _carried(m)) and _matches(0.0003, 4, False, _carried(m))


# -- the loader refuses a finding that names a missing row -----------------------------------------------------------
def test_a_finding_naming_a_missing_row_is_refused(tmp_path):
    text = (CONFIGS / "marble-drop.yaml").read_text(encoding="utf-8")
    old = "    rows: [eps, free_fall]\n"
    assert text.count(old) == 1, "marble-drop's first finding names rows [eps, free_fall]"
    bad = text.replace(old, "    rows: [eps, no_such_row]\n")
    line = bad[: bad.index("no_such_row")].count("\n") + 1
    cfg = tmp_path / "marble-drop.yaml"
    cfg.write_text(bad, encoding="utf-8")
    out = tmp_path / "out"
    res = invoke("reproduce", cfg, "--out", out)
    assert_bad(res, f"{cfg}:{line}", "no_such_row", "not printed or measured ids of this file")
    assert not out.exists() or not any(out.iterdir())
