"""The reader's edition as a PDF (reproductions.edition_pdf): what a printed page must hold, checked on the layout the
renderer returns and on the PDF bytes. The edition is built by hand: long French quotations, formulas with sub- and
superscripts, 44 rows, two figures drawn with matplotlib."""

from __future__ import annotations

import hashlib
import io
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from matplotlib.figure import Figure

from reproductions import edition_pdf as ep
from reproductions.edition.model import Edition, FigureEntry, FindingEntry, RowEntry, SectionEntry, Span

QUOTES = [
    "« Lorsqu'une bille roule sans glisser sur le tapis, la vitesse de son centre et sa vitesse angulaire sont "
    "liées par une relation simple ; le frottement cesse alors d'agir, sauf la résistance au roulement, qui est "
    "très-faible et que nous négligerons dans ce qui va suivre, comme l'a fait Coriolis dans sa Théorie "
    "mathématique des effets du jeu de billard. »",
    "« Le choc de deux billes étant supposé direct, la bille choquante s'arrête et la bille choquée prend toute sa "
    "vitesse, si l'on fait abstraction de l'élasticité imparfaite de l'ivoire ; l'expérience montre qu'il n'en est "
    "pas tout à fait ainsi. »",
    "« On en conclut que la trajectoire du centre est une parabole, dont l'axe est parallèle à la direction du "
    "frottement initial, et qui se raccorde tangentiellement à la droite suivie ensuite par la bille. »",
    "« La bande renvoie la bille sous un angle qui dépend du coefficient de restitution e et du frottement f de la "
    "bille contre le drap ; Coriolis admet que ces deux causes agissent indépendamment l'une de l'autre. »",
]
NOTES = [
    "The printed 0,33 rounds 0.3286…; the premises (e = 0.55, f = 0.2) give it to four digits, and the rounding is "
    "the paper's own. Coriolis (1835, p. 112) prints the same figure with one digit fewer; Résal keeps his value "
    "without comment, which is why the row differs by rounding only and not by substance.",
    "The digitised text reads « 2/5 » where the 1883 page, checked against the scan, has « 2/7 »: a slip of the "
    "OCR, not of Résal. With 2/7 the claim holds to the printed precision; with 2/5 it would differ by 40 %.",
    "See the scan at https://gallica.bnf.fr/ark:/12148/bpt6k3062c/f77.item.r=Resal+billard+1883+theorie+mathematique"
    "+des+effets+du+jeu+de+billard+Coriolis+annales+des+mines.zoom for the original page: the line is legible.",
    "Dollars stay text, never mathematics: the cost $x$ in 1883 francs, 5 $ and 10 $, and a_b^c written plainly.",
    "",
]


def _rich(text: str) -> tuple[Span, ...]:
    return (Span(text),)


def _formula(k: int) -> tuple[Span, ...]:
    return (Span("the speed v"), Span("y", "sub"), Span(f" of the centre after impact {k}, with ω"), Span("0", "sub"),
            Span("r"), Span("2", "sup"), Span(" = 7/5 · v"), Span("0", "sub"), Span(" and "),
            Span("e", "em"), Span(" in "), Span("cue_stroke.speed()", "code"))


def _png(folder: Path, name: str, width: float, height: float) -> str:
    fig = Figure(figsize=(width, height), dpi=100)
    ax = fig.add_subplot()
    x = np.linspace(0, 1, 50)
    ax.plot(x, x ** 2, label="v_y / v_0")
    ax.plot(x, 1 - x, label="ω r / v_0")
    ax.set_title(name)
    ax.legend()
    (folder / "figs").mkdir(parents=True, exist_ok=True)
    fig.savefig(folder / "figs" / f"{name}.png", metadata={"Software": None})
    return f"figs/{name}.png"


VERDICTS = ["reproduced", "reproduced", "differs", "not-checkable", "reproduced", "differs"]
REASONS = {"differs": ("rounding", "the printed digits round a value that the premises give more precisely")}


def make_edition(folder: Path, sections: int = 4, rows: int = 11, figures: int = 2) -> Edition:
    """A realistic edition: ``sections`` experiments of ``rows`` rows each; the first ``figures`` with a figure."""
    secs, findings = [], []
    for s in range(sections):
        exp = f"exp-{s}"
        figs = ()
        if s < figures:
            png = _png(folder, f"figure-{s}", 6.4 if s == 0 else 5.0, 4.0 if s == 0 else 6.5)
            figs = (FigureEntry(png, "", f"Trajectory of the centre, case {s}",
                                "What is plotted: the speed of the centre against time, as computed and as printed. "
                                "What to look at: the curves meet where the ball starts rolling without sliding.",
                                f"alt text {s}"),)
        row_list = []
        for k in range(rows):
            verdict = VERDICTS[(s + k) % len(VERDICTS)]
            reason, label = REASONS.get(verdict, ("", ""))
            rid = f"R{s}.{k}"
            row_list.append(RowEntry(
                experiment=exp, id=rid, anchor=f"{exp}--{rid}", section=f"§I n°{k + 1}",
                equation=f"eq. ({k + 3})" if k % 2 else "", paper_line=100 + k if k % 3 else None,
                quantity=_formula(k), printed=_rich(QUOTES[(s + k) % len(QUOTES)]), printed_value="0.33",
                computed="0.328571428571", difference="−0.43 %" if verdict == "differs" else "+0.01 %",
                tolerance="±0.5 %", tolerance_rule="half a unit of the last printed digit", verdict=verdict,
                reason=reason, reason_label=label, note=_rich(NOTES[(s + k) % len(NOTES)]),
                today="e ≈ 0.93 (phenolic resin balls)" if k % 4 == 0 else "",
                config=f"configs/{exp}.yaml:{10 + k}", function=f"reproductions.experiments.kind_{s}.compute_claim"))
        counts = {}
        for r in row_list:
            counts[r.verdict] = counts.get(r.verdict, 0) + 1
        secs.append(SectionEntry(
            experiment=exp, title=f"Experiment {s}: the ball after a stroke of the cue, and its rolling", folder=exp,
            source=f"§{'I' * (s % 3 + 1)} n°{s + 2}, p. {70 + s}",
            question=(Span("Does the speed v"), Span("y", "sub"), Span(" reach 5/7 of v"), Span("0", "sub"),
                      Span(" as Résal says: "), Span(QUOTES[s % len(QUOTES)], "em")),
            figures=figs, rows=tuple(row_list), counts=counts,
            notes=(_rich("The experiment reads the paper's premises from its config, never from the text."),)))
        findings.append(FindingEntry(
            experiment=exp, id=f"F{s}", category="formula", category_label="a printed formula that cannot be right",
            consequence=5 - s % 5,
            text=(Span(f"Finding {s}: "), Span("the rolling speed v"), Span("r", "sub"), Span(" is printed as "),
                  Span(QUOTES[(s + 1) % len(QUOTES)]), Span(" — which the exact mechanics give only when f"),
                  Span("2", "sup"), Span(" is negligible; otherwise the claim fails by several per cent.")),
            rows=(f"{exp}--R{s}.0", f"{exp}--R{s}.1"), figure=figs[0].png if figs else None))
    counts: dict[str, int] = {}
    for sec in secs:
        for v, n in sec.counts.items():
            counts[v] = counts.get(v, 0) + n
    return Edition(title="Résal 1883, reproduced", subtitle="Commentaire sur la théorie du billard de Coriolis: "
                   "every number, computed again", counts=counts, reasons={"rounding": counts.get("differs", 0)},
                   findings=tuple(findings), sections=tuple(secs), provenance="resal 0.1.0 · commit 0123456789ab")


def _norm(text: str) -> str:
    return " ".join(text.split())


def _rich_text(rich) -> str:
    return _norm("".join(s.text for s in rich))


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    out = tmp_path_factory.mktemp("edition-pdf")
    ed = make_edition(out)
    buf = io.BytesIO()
    layout = ep.write_pdf(ed, out, buf)
    return ed, out, layout, buf.getvalue()


def test_every_line_fits_the_text_width_by_the_same_metrics(rendered):
    _, _, layout, _ = rendered
    m = ep.metrics()
    lines = list(layout.lines())
    assert len(lines) > 400
    for line in lines:
        assert line.x >= ep.LEFT - 1e-6, line.text
        assert line.x + line.width <= ep.LEFT + ep.TEXT_WIDTH + 1e-6, line.text
        for run in line.runs:  # the runs, measured again, are where the layout says, and inside the margins
            assert run.width == pytest.approx(m.width(run.text, run.face, run.size), abs=1e-6)
            assert run.x + run.width <= ep.LEFT + ep.TEXT_WIDTH + 1e-6, line.text
        assert sum(r.width for r in line.runs) <= line.width + 1e-6


def test_the_metrics_agree_with_the_shaping_that_draws_the_text(rendered):
    _, _, layout, _ = rendered
    m = ep.metrics()
    fonts = {}
    for line in list(layout.lines())[:300]:
        for run in line.runs:
            font = fonts.get(run.face)
            if font is None:
                font = fonts[run.face] = matplotlib.ft2font.FT2Font(m.paths[run.face])
                font.set_size(100, 72)
            kw = {"features": list(ep._FONT_FEATURES)} if matplotlib.__version_info__ >= (3, 11) else {}
            font.set_text(run.text, 0.0, flags=ep._NO_HINTING, **kw)
            shaped = font.get_width_height()[0] / 64 * run.size / 100
            assert shaped == pytest.approx(run.width, abs=0.02 + 0.001 * run.width), run.text


def test_nothing_is_cut(rendered):
    ed, _, layout, _ = rendered
    text = _norm(layout.text())
    for section in ed.sections:
        assert _rich_text(section.question) in text
        for row in section.rows:
            for rich in (row.note, row.printed, row.quantity):
                assert _rich_text(rich) in text, _rich_text(rich)[:60]
            assert _norm(f"{row.config} · {row.function}") in text
        for fig in section.figures:
            assert _norm(fig.caption) in text
    for finding in ed.findings:
        assert _rich_text(finding.text) in text
    source = "".join(_rich_text(r.note) + _rich_text(r.printed) for s in ed.sections for r in s.rows)
    assert layout.text().count("…") == source.count("…") + "".join(_rich_text(f.text) for f in ed.findings).count("…")


def test_a_word_longer_than_a_line_is_broken_by_characters_only(rendered):
    _, _, layout, _ = rendered
    lines = list(layout.lines())
    broken = [k for k, line in enumerate(lines) if line.joins == ""]
    assert broken, "the long address of the fixture should have been broken"
    for k in broken:
        assert lines[k].text.split()[-1] in NOTES[2].replace(" ", "")
        assert " " not in lines[k + 1].text.split(" ")[0]
    words = [w for line in lines for w in line.text.split()]  # no other word split: every normal word stays whole
    assert "tangentiellement" in words and "indépendamment" in words


def test_no_line_outside_the_text_block(rendered):
    _, _, layout, _ = rendered
    for page in layout.pages:
        for line in page.lines:
            assert line.bottom >= ep.BOTTOM - 1e-6, (page.number, line.text)
            assert line.top <= ep.TOP + 1e-6, (page.number, line.text)
        for fig in page.figures:
            assert fig.y >= ep.BOTTOM - 1e-6 and fig.y + fig.height <= ep.TOP + 1e-6
            assert ep.LEFT - 1e-6 <= fig.x and fig.x + fig.width <= ep.LEFT + ep.TEXT_WIDTH + 1e-6
        ys = [line.y for line in page.lines]
        assert ys == sorted(ys, reverse=True), "lines are placed top to bottom in reading order"
        assert page.footer.y < ep.BOTTOM


def test_a_heading_is_never_the_last_line_of_a_page(rendered):
    ed, _, layout, _ = rendered
    headings = 0
    for page in layout.pages:
        assert page.items, page.number
        last = page.items[-1]
        assert not (isinstance(last, ep.PlacedLine) and last.style in ("block-heading", "part-heading", "h2")), \
            (page.number, last.text)
        headings += sum(line.style == "block-heading" for line in page.lines)
    assert headings >= sum(len(s.rows) for s in ed.sections) + len(ed.findings)


def test_row_headings_say_id_verdict_and_reason_in_colour(rendered):
    ed, _, layout, _ = rendered
    heads = {line.anchor: line for line in layout.lines() if line.anchor}
    for row in (r for s in ed.sections for r in s.rows):
        line = heads[row.anchor]
        assert line.text.startswith(f"{row.id} · {row.verdict}")
        assert (f"({row.reason})" in line.text) == bool(row.reason)
        verdict = next(r for r in line.runs if r.text.strip() == row.verdict)
        assert verdict.colour == ep.VERDICT_COLOURS[row.verdict] and verdict.face == "bold"


def test_subscripts_are_smaller_and_lower_in_line(rendered):
    _, _, layout, _ = rendered
    found = 0
    for line in layout.lines():
        for k, run in enumerate(line.runs):
            if run.style in ("sub", "sup") and k:
                prev = line.runs[k - 1]
                assert run.size < line.size
                assert (run.y < line.y) if run.style == "sub" else (run.y > line.y)
                assert run.x == pytest.approx(prev.x + prev.width)  # in line with the text before it
                found += 1
    assert found > 50


def test_fonts_are_embedded_truetype_and_no_base14(rendered):
    *_, pdf = rendered
    assert pdf.startswith(b"%PDF")
    assert b"/FontFile2" in pdf
    assert re.search(rb"/BaseFont\s*/[A-Z]{6}\+DejaVuSans|/BaseFont\s*/DejaVuSans", pdf)
    base14 = rb"Courier|Helvetica|Times-|Symbol|ZapfDingbats"
    assert not re.search(rb"/BaseFont\s*/(?:[A-Z]{6}\+)?(?:" + base14 + rb")", pdf)
    assert not re.search(rb"/(?:Creator|Producer|CreationDate)\b", pdf)


def test_the_same_edition_gives_the_same_bytes(rendered):
    ed, out, layout, pdf = rendered
    buf = io.BytesIO()
    again = ep.write_pdf(ed, out, buf)
    assert buf.getvalue() == pdf
    assert again == layout


def test_figures_stand_in_their_experiments_part(rendered):
    ed, _, layout, _ = rendered
    order: list[tuple[str, str]] = []  # ("heading", experiment) or ("figure", png), in reading order
    for page in layout.pages:
        for item in page.items:
            if isinstance(item, ep.PlacedFigure):
                order.append(("figure", item.png))
            elif item.style == "part-heading" and item.part and ("heading", item.part) not in order:
                order.append(("heading", item.part))  # its first line: a long title wraps
    heads = [k for k, (kind, _) in enumerate(order) if kind == "heading"]
    assert [order[k][1] for k in heads] == [s.experiment for s in ed.sections]
    placed = 0
    for n, section in enumerate(ed.sections):
        end = heads[n + 1] if n + 1 < len(heads) else len(order)
        inside = [png for kind, png in order[heads[n]:end] if kind == "figure"]
        assert inside == [f.png for f in section.figures]
        placed += len(inside)
    assert placed == 2
    for fig in (f for p in layout.pages for f in p.figures):  # scaled to the text width, its aspect kept
        img = matplotlib.image.imread(rendered[1] / fig.png)
        assert fig.width <= ep.TEXT_WIDTH + 1e-6
        assert fig.height / fig.width == pytest.approx(img.shape[0] / img.shape[1], rel=1e-6)


def test_findings_come_first_and_cite_the_pages_of_their_evidence(rendered):
    ed, _, layout, _ = rendered
    first_part = next(p.number for p in layout.pages for line in p.lines if line.part)
    finding_pages = {p.number for p in layout.pages for line in p.lines if line.style == "finding"}
    assert finding_pages and max(finding_pages) <= first_part
    row_page = {line.anchor: p.number for p in layout.pages for line in p.lines if line.anchor}
    fig_page = {f.png: p.number for p in layout.pages for f in p.figures}
    text = _norm(layout.text())
    for f in ed.findings:
        for anchor in f.rows:
            assert f"{anchor.partition('--')[2]} (p. {row_page[anchor]})" in text
        if f.figure:
            assert f"(p. {fig_page[f.figure]})" in text
    assert "p. ?" not in text


def test_pages_are_numbered_in_the_footer(rendered):
    _, _, layout, pdf = rendered
    total = len(layout.pages)
    assert [p.number for p in layout.pages] == list(range(1, total + 1))
    for page in layout.pages:
        assert page.footer.text.endswith(f"page {page.number} of {total}")
        assert page.footer.x + page.footer.width <= ep.LEFT + ep.TEXT_WIDTH + 1e-6
    assert len(re.findall(rb"/Type\s*/Page\b(?!s)", pdf)) == total


def test_rc_params_do_not_leak(tmp_path):
    before = dict(matplotlib.rcParams)
    ep.write_pdf(make_edition(tmp_path, sections=1, rows=2), tmp_path, io.BytesIO())
    assert dict(matplotlib.rcParams) == before


def test_a_missing_figure_is_said_not_hidden(tmp_path):
    ed = make_edition(tmp_path, sections=1, rows=3)
    (tmp_path / ed.sections[0].figures[0].png).unlink()
    layout = ep.write_pdf(ed, tmp_path, io.BytesIO())
    assert not any(p.figures for p in layout.pages)
    assert f"[figure not found: {ed.sections[0].figures[0].png}]" in layout.text()


def test_an_empty_edition_is_one_page(tmp_path):
    ed = Edition(title="Empty", subtitle="", counts={}, reasons={}, findings=(), sections=(), provenance="")
    buf = io.BytesIO()
    layout = ep.write_pdf(ed, tmp_path, buf)
    assert len(layout.pages) == 1 and buf.getvalue().startswith(b"%PDF")


def test_layout_is_pure_and_keeps_row_blocks_whole(tmp_path):
    ed = make_edition(tmp_path, sections=2, rows=30, figures=0)
    a, b = ep.layout_edition(ed, {}), ep.layout_edition(ed, {})
    assert a == b
    where: dict[str, set[int]] = {}
    anchor = ""
    for page in a.pages:
        for line in page.lines:
            anchor = line.anchor or (anchor if line.style == "labelled" else "")
            if anchor:
                where.setdefault(anchor, set()).add(page.number)
    assert len(where) == 60 and all(len(pages) == 1 for pages in where.values())


def _tool(name: str) -> str:
    path = shutil.which(name)
    if path is None:
        pytest.skip(f"{name} (poppler-utils) is not installed")
    return path


def test_the_text_of_the_pdf_can_be_extracted(rendered, tmp_path):
    ed, _, _, pdf = rendered
    (tmp_path / "e.pdf").write_bytes(pdf)
    text = subprocess.run([_tool("pdftotext"), "-enc", "UTF-8", str(tmp_path / "e.pdf"), "-"], check=True,
                          capture_output=True, text=True).stdout
    text = _norm(text)
    rows = [r for s in ed.sections for r in s.rows]
    for row in rows:
        if "https://" not in _rich_text(row.note):  # that one is broken by characters at a line's end
            assert _rich_text(row.note) in text
        assert _rich_text(row.printed) in text
    assert _norm(f"{ed.counts['reproduced']} reproduced") in text


def _raster(tool: str, pdf: bytes, folder: Path, page: int) -> np.ndarray:
    (folder / "p.pdf").write_bytes(pdf)
    subprocess.run([tool, "-png", "-r", "60", "-f", str(page), "-l", str(page), str(folder / "p.pdf"),
                    str(folder / "p")], check=True)
    png = next(folder.glob("p-*.png"))
    img = matplotlib.image.imread(png)
    png.unlink()
    return img


def test_the_public_drawing_path_draws_the_same_pages(rendered, tmp_path, monkeypatch):
    """Where matplotlib's PDF internals are not as expected, every run goes through ``renderer.draw_text``: the
    same fonts, embedded, and (when poppler is there to look) the same pixels."""
    ed, out, layout, fast = rendered
    monkeypatch.setattr(ep._PdfText, "of", classmethod(lambda cls, *a: None))
    buf = io.BytesIO()
    assert ep.write_pdf(ed, out, buf) == layout
    slow = buf.getvalue()
    assert slow != fast and b"/FontFile2" in slow
    assert not re.search(rb"/BaseFont\s*/(?:[A-Z]{6}\+)?(?:Courier|Helvetica|Times-|Symbol|ZapfDingbats)", slow)
    tool = _tool("pdftoppm")
    for page in (1, 3):
        a, b = _raster(tool, fast, tmp_path, page), _raster(tool, slow, tmp_path, page)
        assert a.shape == b.shape
        # the same glyphs at the same places: only anti-aliasing differs (kerning rounded apart: ≤ 1/64 pt a pair)
        assert np.abs(a - b).max() < 0.4, page


def test_the_same_bytes_in_other_processes(rendered):
    """Nothing in the bytes hangs on the process: not the time, not the hash seed of str (dict and set orders)."""
    _, out, _, pdf = rendered
    code = ("import hashlib, io, sys; from pathlib import Path; sys.path[:0] = [sys.argv[1], sys.argv[2]]; "
            "from test_edition_pdf import make_edition; from reproductions import edition_pdf as ep; "
            "ed = make_edition(Path(sys.argv[3])); buf = io.BytesIO(); ep.write_pdf(ed, Path(sys.argv[3]), buf); "
            "print(hashlib.sha256(buf.getvalue()).hexdigest())")
    root = Path(__file__).resolve().parent
    for seed in ("1", "2"):
        done = subprocess.run([sys.executable, "-c", code, str(root), str(root.parent), str(out)], check=True,
                              capture_output=True, text=True, env={**os.environ, "PYTHONHASHSEED": seed})
        assert done.stdout.strip() == hashlib.sha256(pdf).hexdigest()


def test_evidence_outside_the_edition_gets_no_page(tmp_path):
    ed = make_edition(tmp_path, sections=1, rows=2)
    f = ed.findings[0]
    gone = FindingEntry(f.experiment, f.id, f.category, f.category_label, f.consequence, f.text,
                        (f"{f.experiment}--nowhere",), "figs/none.png")
    ed = Edition(ed.title, ed.subtitle, ed.counts, ed.reasons, (gone,), ed.sections, ed.provenance)
    text = _norm(ep.write_pdf(ed, tmp_path, io.BytesIO()).text())
    assert "row nowhere; figure “figs/none.png”" in text and "p. ?" not in text
