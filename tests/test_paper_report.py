"""The paper as a whole (issue 13): paper-table.{md,csv,tex} in the paper's order, index.md with the verdict totals,
report.pdf (its text, as poppler reads it, holds every experiment, row and figure; the edition compiled again gives
the file's bytes), and the short summary that `reproduce --all` prints. The PDF's own rendering is tested in
test_edition_pdf.py."""

import csv
import json
import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from cli import main
from cli.main import app
from reproductions import api, edition, report
from reproductions.config import REASONS
from reproductions.edition.model import VERDICT_LABEL

runner = CliRunner()


# -- report.pdf through the text poppler reads in it -------------------------------------------------------------
def _pdf_pages(out: Path) -> list[str]:
    """The text of out/report.pdf, page by page (pdftotext -raw: in the order the page draws it, a table's cells one
    by one), after checking that the edition of out's summaries gives the file's bytes again."""
    import io
    import shutil
    import subprocess

    from reproductions.edition.typst import write_pdf

    if shutil.which("pdftotext") is None:
        pytest.skip("pdftotext (poppler-utils) is not installed")
    buf = io.BytesIO()
    write_pdf(edition.build(report._summaries(out)), out, buf)
    assert buf.getvalue() == (out / "report.pdf").read_bytes()
    text = subprocess.run(["pdftotext", "-raw", "-enc", "UTF-8", str(out / "report.pdf"), "-"], check=True,
                          capture_output=True, text=True, encoding="utf-8").stdout
    return text.split("\f")[:-1]


def _heading_lines(pages: list[str]) -> list[str]:
    return [" ".join(ln.split()) for page in pages for ln in page.splitlines()]


def _row_heads(pages: list[str], rid: str, experiment: str = "") -> list[str]:
    """The lines of the page a row's table ends on (its developers' line names its id and config: ``row <id> ·
    configs/<experiment>.yaml``) and of the page before, where its head (place in the paper, verdict, reason)
    stands: a table may break, its cells never."""
    tail = f"row {rid} · configs/{experiment}" if experiment else f"row {rid} ·"
    k = next(k for k, page in enumerate(pages) if tail in " ".join(page.split()))
    return _heading_lines(pages[max(0, k - 1):k + 1])


# -- the real experiments ----------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def written(reproduced_all):
    out, stdout = reproduced_all
    summaries = [json.loads((out / e / "summary.json").read_text()) for e in api.experiment_ids()]
    return out, summaries, stdout


def test_reproduce_all_prints_one_short_summary(written):
    """One line per experiment (id and verdict counts, under 80 columns), the totals of the paper's claims, the
    differing claims by whose error they show (wrapped between groups, every line under 80 columns), the rows beyond
    the paper's domain counted apart, and where the experiments' folders are."""
    out, summaries, stdout = written
    lines = [ln for ln in stdout.splitlines() if ln.strip()]
    printed = [s for s in summaries if s["rows"]]  # the experiments of printed claims; the others come after
    measured = [s for s in summaries if s.get("measurements")]
    assert printed and measured and not [s for s in printed if s in measured]
    for s, ln in zip(printed, lines, strict=False):
        counts, _ = report.verdict_counts(s["rows"])
        assert ln.split()[0] == s["experiment"] and len(ln) <= 80, ln
        assert [int(n) for n in re.findall(r"(\d+) (?:reproduced|differs|not-checkable)", ln)] == \
            [counts[v] for v in report.VERDICTS], ln
    total, why = report.verdict_counts([r for s in summaries for r in s["rows"]])
    totals = lines[len(printed)]
    assert totals.startswith("total") and f"({sum(total.values())} claims)" in totals
    assert [int(n) for n in re.findall(r"(\d+) (?:reproduced|differs|not-checkable)", totals)] == \
        [total[v] for v in report.VERDICTS]
    head = next(i for i, ln in enumerate(lines) if ln.startswith("today's measurements"))
    assert all(len(ln) <= 80 for ln in lines[len(printed) + 1:head]), lines[len(printed) + 1:head]
    reasons = " ".join(" ".join(lines[len(printed) + 1:head]).split())
    assert reasons.startswith(f"the {total['differs']} that differ, by whose error:")
    assert all(f"{k} {n}" in reasons for k, n in why.items())
    assert sum(n for _, n, _ in report.whose_error(why)) == total["differs"]
    beyond = report.beyond_counts([r for s in summaries for r in s["rows"]])
    assert f"beyond the paper's domain, counted apart ({sum(beyond.values())} rows):" in reasons
    # the measurements apart: their own heading, a line per experiment with its own verdicts, no printed verdict
    assert f"({sum(len(s['measurements']) for s in measured)} rows, 95 %)" in lines[head]
    for s, ln in zip(measured, lines[head + 1:], strict=False):
        counts = report.measurement_counts([s])
        assert ln.split()[0] == s["experiment"] and len(ln) <= 80, ln
        assert {v: int(n) for n, v in re.findall(r"(\d+) (consistent|inconsistent|fitted|not-checkable)", ln)} == \
            {v: n for v, n in counts.items() if n}, ln
    assert lines[-1] == f"folders: {out / '<experiment>'}/"


def test_one_experiment_or_verbose_prints_the_full_tables(tmp_path, monkeypatch):
    monkeypatch.setattr(main.out_console, "width", 250)  # a wide terminal: the table's words stay whole
    one = runner.invoke(app, ["reproduce", "marble-drop", "--out", str(tmp_path)])
    assert one.exit_code == 0, one.output
    assert "quantity" in one.stdout and "reason" in one.stdout and "0,155" in one.stdout
    two = runner.invoke(app, ["reproduce", "marble-drop", "coriolis-cushion", "--verbose", "--out", str(tmp_path)])
    assert two.exit_code == 0, two.output
    assert two.stdout.count("quantity") == 2 and "0,155" in two.stdout
    short = runner.invoke(app, ["reproduce", "marble-drop", "coriolis-cushion", "--out", str(tmp_path)])
    assert short.exit_code == 0 and "quantity" not in short.stdout
    assert len(short.stdout.splitlines()) == 5  # two experiments, the totals, the reasons, the folders


def test_the_paper_table_is_in_the_papers_order(written):
    out, summaries, _ = written
    with (out / "paper-table.csv").open(newline="", encoding="utf-8") as fh:
        table = list(csv.DictReader(fh))
    assert len(table) == sum(len(s["rows"]) for s in summaries)
    assert [c for c in table[0]] == list(report.PAPER_CSV)
    lines = [int(r["line"]) for r in table if r["line"]]
    assert lines == sorted(lines)
    assert all(r["line"] for r in table[:len(lines)])  # rows without a line come after those with one
    order = [s["experiment"] for _, s in report._summaries(out)]
    tail = [order.index(r["experiment"]) for r in table[len(lines):]]
    assert tail == sorted(tail)
    by_key = {(s["experiment"], r["id"]): r for s in summaries for r in s["rows"]}
    for r in table:
        row = by_key[(r["experiment"], r["id"])]
        assert (r["verdict"], r["reason"] or None, r["printed"]) == (row["verdict"], row["reason"],
                                                                       row["printed_text"])
        assert r["section"].startswith("§")
        assert row["verdict"] != "reproduced" or not r["reason"]
    md = [ln for ln in (out / "paper-table.md").read_text().splitlines() if ln.startswith("| ")]
    assert md[0].split(" | ")[:6] == ["| experiment", "section", "n°", "equation", "line", "id"]
    assert "today's value" in md[0] and len(md) == len(table) + 1


def test_the_index_gives_the_totals_then_each_experiment_with_its_figures_and_tables(written):
    out, summaries, _ = written
    index = (out / "index.md").read_text()
    total, _ = report.verdict_counts([r for s in summaries for r in s["rows"]])
    head = index.split("## Experiments")[0]
    assert (f"**{total['reproduced']} reproduced**, **{total['differs']} differ**, "
            f"**{total['not-checkable']} not checkable**") in head
    for s in summaries:
        eid = s["experiment"]
        section = index.split(f"### [{eid}]({eid}/table.md)")[1].split("\n### ")[0]
        counts, _ = report.verdict_counts(s["rows"])
        if s["rows"]:
            assert f"{counts['reproduced']} reproduced, {counts['differs']} differs" in section
        if s.get("measurements"):  # its own verdicts, never as printed claims
            m = report.measurement_counts([s])
            assert "measurements: " + ", ".join(f"{m[v]} {v}" for v in m) in section
            assert "reproduced" not in section.split("Tables:")[0] or s["rows"]
        for name in ("table.md", "table.csv", "table.tex", "summary.json"):
            assert f"({eid}/{name})" in section
        pngs = [f for f in s["figures"] if f.endswith(".png")]
        assert all(f"![{eid}/{f}]({eid}/{f})" in section for f in pngs)
    for target in re.findall(r"\]\(([^)]+)\)", index):  # every link and image resolves, relative to index.md
        assert (out / target).is_file(), target


def test_report_pdf_holds_every_experiment_row_and_figure(written):
    out, summaries, _ = written
    data = (out / "report.pdf").read_bytes()
    assert data.startswith(b"%PDF") and b"/CreationDate" not in data and b"/Producer" not in data
    assert re.search(rb"/FontFile[23]?\b", data) and b"/Courier" not in data  # embedded fonts, no base-14 font
    pages = _pdf_pages(out)
    assert len(pages) == len(re.findall(rb"/Type\s*/Page(?!s)", data))
    for s in summaries:  # each row's table: its head gives its verdict and reason, its last line its id
        for r in s["rows"]:
            want = [VERDICT_LABEL[r["verdict"]]] + ([r["reason"]] if r["reason"] else [])
            lines = _row_heads(pages, r["id"], s["experiment"])
            assert any(ln.startswith("§") and all(w in ln for w in want) for ln in lines), \
                (s["experiment"], r["id"])
    # each figure in its experiment's part: after its heading's page, before the next experiment's
    ed = edition.build(report._summaries(out))
    every = (*ed.sections, *ed.measured_sections)
    # an experiment's part starts on the page of its line of source and id (below its heading; not in the contents)
    starts = [next(k for k, p in enumerate(pages) if f"{sec.source} · {sec.experiment} ·" in " ".join(p.split()))
              for sec in every]
    for n, sec in enumerate(every):
        inside = " ".join(" ".join(pages[starts[n]:starts[n + 1] if n + 1 < len(starts) else None]).split())
        for f in sec.figures:
            assert f"{f.title.rstrip('. ')}." in inside, (sec.experiment, f.png)
    n_png = sum(f.endswith(".png") for s in summaries for f in s["figures"])
    assert n_png == sum(len(sec.figures) for sec in every) and "figure missing" not in " ".join(pages)


# -- hand-made summaries: the order, the columns, today's values, totals per reason, atomic writing -----------------
def _png(path: Path, title: str) -> None:
    from PIL import Image, PngImagePlugin

    info = PngImagePlugin.PngInfo()
    info.add_text("Title", title)
    Image.new("RGB", (40, 30), (200, 30, 30)).save(path, pnginfo=info)


def _row(rid: str, source: str, line: int | None, verdict: str, reason: str | None = None,
         today: str | None = None) -> dict:
    return {"id": rid, "quantity": f"claim {rid} with ε′ and ν", "source": source, "printed": 0.5,
            "printed_text": f"{rid} = 0,5", "computed": 0.5, "rel_diff": 0.0, "tolerance": 0.01,
            "tolerance_rule": "", "verdict": verdict, "note": "why" if verdict == "differs" else "", "line": line,
            "reason": reason, "today": today}


MODERN = [{"symbol": "e_c", "quantity": "ball-cushion restitution", "resal": 0.55, "resal_what": "ν", "low": 0.6,
           "typ": None, "high": 0.9, "source": "Alciatore FAQ", "note": ""},
          {"symbol": "e_c", "quantity": "ball-cushion restitution", "resal": 0.55, "resal_what": "ν", "low": None,
           "typ": 0.818, "high": None, "source": "Mathavan, Jackson & Parkin 2009, Am. J. Phys. 77, 788", "note": ""}]


@pytest.fixture
def hand_made(tmp_path):
    out = tmp_path / "out"
    exps = {
        "alpha": (70, [_row("a1", "§II n°7, eq. (3)", 300, "reproduced"),
                       _row("a2", "§II n°7", None, "differs"),
                       _row("a3", "§IV n°11, eqs (5), (8)", 100, "differs", "erratum", today="e_c")]),
        "beta": (65, [_row("b1", "§I n°5, eq. (b)", 200, "differs", "rounding"),
                      _row("b2", "somewhere in the footnotes", None, "not-checkable"),
                      _row("b3", "§III n°8-10", 200, "reproduced", today="mu_x")]),
    }
    for eid, (page, rows) in exps.items():
        d = out / eid
        d.mkdir(parents=True)
        _png(d / f"{eid}-fig.png", f"the figure of {eid}")
        s = {"experiment": eid, "title": f"Experiment {eid}", "kind": "x",
             "source": {"section": "§I", "page": page, "equations": []}, "rows": rows, "fits": [],
             "modern": MODERN, "figures": [f"{eid}-fig.png", f"{eid}-fig.pdf"]}
        (d / "summary.json").write_text(json.dumps(s, ensure_ascii=False))
    return out


@pytest.mark.parametrize(("source", "parsed"), [
    ("§II n°7, eq. (3)", ("§II", "7", "eq. (3)")),
    ("§V n°12, eqs (5), (8)", ("§V", "12", "eqs (5), (8)")),
    ("§III n°10, footnote", ("§III", "10", "footnote")),
    ("§III n°8-10", ("§III", "8-10", "")),
    ("§VII n°14", ("§VII", "14", "")),
    ("§V n°12, §VI n°13", ("§V n°12, §VI n°13", "", "")),
    ("Coriolis 1835, p. 12", ("Coriolis 1835, p. 12", "", "")),
])
def test_a_source_gives_section_number_and_equation_or_stays_whole(source, parsed):
    assert report.parse_source(source) == parsed


def test_todays_value_comes_from_the_experiments_modern_entries():
    assert report.today_value("e_c", MODERN) == "0.6–0.9 (Alciatore FAQ); 0.818 (Mathavan 2009)"
    assert report.today_value(None, MODERN) == ""
    assert "mu_x" in report.today_value("mu_x", MODERN)


def test_hand_made_summaries_give_the_papers_order_and_totals(hand_made):
    out = hand_made
    edition.write_index(out)
    with (out / "paper-table.csv").open(newline="", encoding="utf-8") as fh:
        table = list(csv.DictReader(fh))
    # by line (ties in experiment order: beta's page comes first), then the rows without a line, experiment order
    assert [(r["experiment"], r["id"]) for r in table] == [
        ("alpha", "a3"), ("beta", "b1"), ("beta", "b3"), ("alpha", "a1"), ("beta", "b2"), ("alpha", "a2")]
    a3 = table[0]
    assert (a3["section"], a3["n"], a3["equation"], a3["line"], a3["reason"]) == ("§IV", "11", "eqs (5), (8)", "100",
                                                                                  "erratum")
    assert a3["today"] == "0.6–0.9 (Alciatore FAQ); 0.818 (Mathavan 2009)" and a3["today_symbol"] == "e_c"
    assert table[4]["section"] == "somewhere in the footnotes" and table[4]["n"] == ""
    index = (out / "index.md").read_text()
    head = index.split("## Experiments")[0]
    assert "**2 reproduced**, **3 differ**, **1 not checkable**" in head
    assert f"| erratum | 1 | {REASONS['erratum']} |" in head and "| none given | 1 |" in head
    assert "![alpha/alpha-fig.png](alpha/alpha-fig.png)" in index
    tex = (out / "paper-table.tex").read_text()
    assert tex.count(r"\\") == len(table) + 1 and r"\§IV" not in tex and "§IV" in tex

    pages = _pdf_pages(out)
    for rid, verdict, reason in (("a3", "differs", "erratum"), ("b1", "differs", "rounding"),
                                 ("a2", "differs", None), ("b2", "not checkable", None)):
        assert any(verdict in ln and (reason or "") in ln for ln in _row_heads(pages, rid)), rid


def test_the_report_is_the_same_bytes_twice_and_written_whole(hand_made, monkeypatch):
    out = hand_made
    edition.write_index(out)
    first = (out / "report.pdf").read_bytes()
    edition.write_index(out)
    assert (out / "report.pdf").read_bytes() == first

    def broken(ed, out, fh):
        fh.write(b"%PDF-half")
        raise RuntimeError("interrupted while writing")

    from reproductions.edition import typst

    monkeypatch.setattr(typst, "write_pdf", broken)
    with pytest.raises(RuntimeError):
        edition.write_index(out)
    assert (out / "report.pdf").read_bytes() == first
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")]
