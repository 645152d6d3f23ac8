"""Today's measurements against the paper's mechanics, in every rendering: a part of their own, their own verdicts,
counted apart from the printed claims (the reader's edition must never add the two)."""

from __future__ import annotations

import copy
import io
import re
import shutil
import subprocess

import pytest

from reproductions import edition, report
from reproductions.edition.model import VERDICT_LABEL
from reproductions.edition.typst import write_pdf

PAPER = {
    "experiment": "marble-drop", "title": "Marble drop", "kind": "rebound",
    "source": {"section": "§I n°5", "page": 72, "equations": ["(9)"]}, "data_note": "",
    "rows": [{"id": "eps", "quantity": "ε of marble", "source": "§I n°5, eq. (9)", "printed": 0.155,
              "printed_text": "0,155", "computed": 0.101, "rel_diff": -0.35, "tolerance": 0.003,
              "tolerance_rule": "half a unit", "verdict": "differs", "note": "a slip", "line": 230,
              "reason": "erratum", "today": None, "config_line": 20, "computes": "eps"}],
    "fits": [], "identifiability": [], "tables": [], "modern": [], "figures": [], "figure_captions": [],
    "notes": [], "question": "What ε?", "findings": [], "provenance": {},
}
MEASURED = {
    "experiment": "modern-head-on", "title": "A head-on collision filmed", "kind": "head_on",
    "source": {"section": "Derby & Fuller 1999", "page": None, "equations": []}, "data_note": "",
    "rows": [], "fits": [], "identifiability": [], "tables": [], "modern": [], "figures": [],
    "figure_captions": [], "notes": [], "question": "Do §VI and §II describe it?", "provenance": {},
    "findings": [{"id": "cue", "category": "measured", "consequence": 4, "text": "The cue ball rolls at 0.251 m/s.",
                  "rows": ["cue_final_speed"], "figure": None, "config_line": 9}],
    "measurements": [
        {"id": "cue_final_speed", "quantity": "cue ball's rolling speed", "source": "Derby & Fuller 1999",
         "unit": "m/s", "measured": 0.251, "measured_text": "0.251 m/s", "uncertainty": "σ = 0.0003 (last digit)",
         "predicted": 0.397, "interval": [0.338, 0.459], "verdict": "inconsistent", "note": "§VI then §II",
         "config_line": 30, "computes": "cue_final_speed"},
        {"id": "target_sliding_time", "quantity": "object ball's sliding time", "source": "Derby & Fuller 1999",
         "unit": "s", "measured": 0.15, "measured_text": "0.150 s", "uncertainty": "σ = 0.0003 (last digit)",
         "predicted": 0.145, "interval": [0.129, 0.165], "verdict": "consistent", "note": "§II",
         "config_line": 40, "computes": "target_sliding_time"},
        {"id": "target_final_speed", "quantity": "object ball's rolling speed", "source": "Derby & Fuller 1999",
         "unit": "m/s", "measured": 0.583, "measured_text": "0.583 m/s", "uncertainty": "σ = 0.0003",
         "predicted": 0.583, "interval": None, "verdict": "fitted", "note": "fixes e", "config_line": 50,
         "computes": "target_final_speed"}],
}


def _edition():
    return edition.build([("marble-drop", copy.deepcopy(PAPER)), ("modern-head-on", copy.deepcopy(MEASURED))])


def test_the_counts_are_apart():
    ed = _edition()
    assert ed.counts == {"reproduced": 0, "differs": 1, "not-checkable": 0}  # the printed claims alone
    assert ed.measurement_counts == {"consistent": 1, "inconsistent": 1, "fitted": 1, "not-checkable": 0}
    assert [s.experiment for s in ed.sections] == ["marble-drop"]
    assert [s.experiment for s in ed.measured_sections] == ["modern-head-on"]
    md = report.index_md([("marble-drop", PAPER), ("modern-head-on", MEASURED)])
    assert "1 printed values and claims" in md and "3 published measurements" in md
    both = [("marble-drop", PAPER), ("modern-head-on", MEASURED)]
    assert [x["row"]["id"] for x in report.paper_rows(both)] == ["eps"]
    assert len(report.paper_rows([("modern-head-on", MEASURED)])) == 0  # no measurement in the paper's table


def test_the_html_has_a_part_of_its_own_with_every_measurement_once():
    html = edition.index_html(_edition())
    assert html.count("The 1883 theory against today's measurements") >= 2  # the part and its link in the nav
    for m in MEASURED["measurements"]:
        assert html.count(f'id="modern-head-on--{m["id"]}"') == 1
    part = html[html.index('id="measured"'):]
    assert '<article class="row ' not in part.split('id="exp-modern-head-on"')[1]  # measurements are not claim cards
    assert "1 inconsistent" in part and "1 consistent" in part and "1 fitted" in part
    assert '<a href="#modern-head-on--cue_final_speed">' in html  # the finding links its measured row
    assert "0.338" in html and "0.459" in html  # the interval shown


def test_the_pdf_sets_every_measurement_and_cites_its_page(tmp_path):
    if shutil.which("pdftotext") is None:
        pytest.skip("pdftotext (poppler-utils) is not installed")
    buf = io.BytesIO()
    write_pdf(_edition(), tmp_path, buf)
    (tmp_path / "report.pdf").write_bytes(buf.getvalue())
    text = subprocess.run(["pdftotext", "-raw", "-enc", "UTF-8", str(tmp_path / "report.pdf"), "-"], check=True,
                          capture_output=True, text=True, encoding="utf-8").stdout
    text = re.sub(r" ([,.;])", r"\1", " ".join(text.split()))  # a badge's margin is no space before a comma
    part = text[text.rindex("The 1883 theory against today's measurements"):]  # the part, not the contents
    assert "3 measurements: 1 consistent, 1 inconsistent, 1 fitted." in part  # apart, by their own verdicts
    for m in MEASURED["measurements"]:  # each its table, its head the id and the verdict
        assert f"{m['source']} {VERDICT_LABEL[m['verdict']]}" in part and f"row {m['id']} ·" in part
        assert m["measured_text"] in part
    assert "measured (p. " in text and "(p. ?" not in text  # the finding cites the page of its measurement


def test_a_summary_and_its_tables_carry_the_measurements():
    md = report.table_md(MEASURED)
    assert "## Today's measurements against the paper's mechanics" in md and "## Printed values" not in md
    assert "[0.338, 0.459]" in md and "inconsistent" in md
    csv = report.table_csv(MEASURED).splitlines()
    assert csv[2].startswith("id,quantity,source,unit,measured") and len(csv) == 6
    tex = report.table_tex(MEASURED)
    assert tex.count(r"\begin{tabular}") == 2
