"""The reader's edition as a PDF set by Typst (reproductions.edition.typst): what the printed pages must hold, checked
on the PDF's bytes and on what poppler (pdftotext, pdffonts, pdfinfo, pdftoppm) reads in them. The edition is built
by hand: long French quotations beside their English, formulas (LaTeX spans and the legacy sub- and superscripts),
rows of every verdict, two experiments with vector figures, one of today's measurements; and, in one test, the real
results of ``resal reproduce --all``."""

from __future__ import annotations

import hashlib
import io
import os
import re
import shutil
import subprocess
import sys
import zlib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from reproductions.edition import typst as et
from reproductions.edition.model import (
    VERDICT_LABEL,
    Edition,
    ErrorKind,
    FigureEntry,
    FindingEntry,
    MeasurementEntry,
    RowEntry,
    SectionEntry,
    Span,
    facsimile,
)

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
ENGLISH = [
    "“When a ball rolls without sliding on the cloth, the speed of its centre and its angular speed are linked by a "
    "simple relation; friction then stops acting, except the rolling resistance, which is very small.”",
    "“The impact of two balls being supposed direct, the striking ball stops and the struck ball takes all its "
    "speed, if one sets aside the imperfect elasticity of ivory.”",
    "“One concludes that the path of the centre is a parabola, whose axis is parallel to the initial friction.”",
    "“The cushion sends the ball back at an angle that depends on e and on f; Coriolis assumes the two causes act "
    "independently.”",
]
NOTES = [
    "The printed 0,33 rounds 0.3286…; the premises (e = 0.55, f = 0.2) give it to four digits, and the rounding is "
    "the paper's own. Coriolis (1835, p. 112) prints the same figure with one digit fewer; Résal keeps his value "
    "without comment, which is why the row differs by rounding only and not by substance.",
    "The digitised text reads « 2/5 » where the 1883 page, checked against the scan, has « 2/7 »: a slip of the "
    "OCR, not of Résal. With 2/7 the claim holds to the printed precision; with 2/5 it would differ by 40 %.",
    "Today's value: Mathavan, Jackson & Parkin (2009), doi:10.1119/1.3116835, measured the ball–cushion impact "
    "with high-speed video; see also https://billiards.colostate.edu/faq/physics/ for the same figure.",
    "Dollars stay text, never mathematics: the cost $x$ in 1883 francs, 5 $ and 10 $, and a_b^c written plainly.",
    "",
]
HOSTILE = ("back\\slash #set text(red) $x^2$ *bold* _under_ `raw` <label> @ref [bracket] ~tilde a/b // no comment "
           "/* nor this */ \"quoted\" {brace} 50 % & = head - item + enum")
HOSTILE_ID = "x.y/z <1>_@#"


def _figures(folder: Path, s: int) -> tuple[str, str]:
    """A figure drawn by matplotlib as the experiments draw theirs: a PNG and its vector PDF (no date in either)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.0) if s == 0 else (5.0, 6.5), dpi=100)
    ax = fig.add_subplot()
    x = np.linspace(0, 1, 50)
    ax.plot(x, x ** 2, label="v_y / v_0")
    ax.plot(x, 1 - x, label="ω r / v_0")
    ax.set_xlabel(f"time of case {s} (s)")
    ax.set_ylabel("speed of the centre (m/s)")
    ax.legend()
    (folder / f"exp-{s}").mkdir(parents=True, exist_ok=True)
    png, pdf = f"exp-{s}/figure-{s}.png", f"exp-{s}/figure-{s}.pdf"
    fig.savefig(folder / png, metadata={"Software": None})
    fig.savefig(folder / pdf, metadata={"Creator": None, "Producer": None, "CreationDate": None})
    return png, pdf


def _rich(text: str) -> tuple[Span, ...]:
    return (Span(text),)


def _quantity(k: int) -> tuple[Span, ...]:
    return (Span("the speed "), Span(r"v_y", "math"), Span(f" of the centre after impact {k}, with "),
            Span(r"\omega_0 r^2 = \frac{7}{5} v_0", "math"), Span(" and "), Span("e", "em"), Span(" in "),
            Span("cue_stroke.speed()", "code"))


VERDICTS = ["reproduced", "reproduced", "differs", "not-checkable", "reproduced", "differs"]
REASONS = {"differs": ("rounding", "the printed digits round a value that the premises give more precisely")}


def _row(exp: str, s: int, k: int, page: int | None) -> RowEntry:
    verdict = VERDICTS[(s + k) % len(VERDICTS)]
    reason, label = REASONS.get(verdict, ("", ""))
    rid = f"R{s}.{k}"
    return RowEntry(
        experiment=exp, id=rid, anchor=f"{exp}--{rid}", section=f"§I n°{k + 1}",
        equation=f"eq. ({k + 3})" if k % 2 else "", paper_line=100 + k if k % 3 else None,
        quantity=_quantity(k), printed=_rich(QUOTES[(s + k) % len(QUOTES)]), printed_value="0.33",
        computed="0.328571428571", difference="−0.43 %" if verdict == "differs" else "+0.01 %",
        tolerance="±0.5 %", tolerance_rule="half a unit of the last printed digit", verdict=verdict,
        reason=reason, reason_label=label, note=_rich(NOTES[(s + k) % len(NOTES)]),
        today="e ≈ 0.93 (phenolic resin balls)" if k % 4 == 0 else "",
        config=f"configs/{exp}.yaml:{10 + k}", function=f"reproductions.experiments.kind_{s}.compute_claim",
        evidence=f"{'agrees' if verdict == 'reproduced' else 'differs'}: printed 0.33, computed 0.3286",
        english=_rich(ENGLISH[(s + k) % len(ENGLISH)]) if k % 3 != 2 else (), page=page if k % 5 else None)


def _measured(folder: Path) -> SectionEntry:
    exp = "modern-head-on"
    ms = tuple(MeasurementEntry(
        experiment=exp, id=mid, anchor=f"{exp}--{mid}", quantity=_rich(f"the {mid.replace('_', ' ')}"),
        source="Derby & Fuller 1999", measured=f"0.{251 + k} m/s", uncertainty="σ = 0.0003 (last digit)",
        predicted=f"0.{397 - k}", interval="[0.338, 0.459]" if k < 2 else "—", verdict=verdict,
        note=(Span("§VI then §II: "), Span(r"v = \frac{5}{7} v_0", "math")), config=f"configs/{exp}.yaml:{30 + k}",
        function="reproductions.experiments.headon.run")
        for k, (mid, verdict) in enumerate((("cue_final_speed", "inconsistent"), ("target_sliding_time", "consistent"),
                                            ("target_final_speed", "fitted"))))
    return SectionEntry(
        experiment=exp, title="A head-on collision filmed", source="Derby & Fuller 1999",
        question=_rich("Do §VI and §II describe it?"), figures=(), rows=(), counts={}, folder=exp,
        notes=(_rich("Data: Derby & Fuller (1999), doi:10.1119/1.19260, read off their table 1."),),
        measurements=ms, measurement_counts={"consistent": 1, "inconsistent": 1, "fitted": 1, "not-checkable": 0})


def make_edition(folder: Path, sections: int = 4, rows: int = 11, figures: int = 2, draw: bool = True,
                 measured: bool = True) -> Edition:
    """A realistic edition: ``sections`` experiments of ``rows`` rows; the first ``figures`` with a figure (drawn
    into ``folder`` unless ``draw`` is False: then the files already there are used)."""
    secs, findings = [], []
    for s in range(sections):
        exp = f"exp-{s}"
        figs = ()
        if s < figures:
            png, pdf = _figures(folder, s) if draw else (f"exp-{s}/figure-{s}.png", f"exp-{s}/figure-{s}.pdf")
            figs = (FigureEntry(png, pdf, f"Trajectory of the centre, case {s}",
                                "What is plotted: the speed of the centre against time, as computed and as printed. "
                                "What to look at: the curves meet where the ball starts rolling without sliding.",
                                f"Figure: the speed of the centre against time, case {s}."),)
        row_list = [_row(exp, s, k, 70 + s) for k in range(rows)]
        counts: dict[str, int] = {}
        for r in row_list:
            counts[r.verdict] = counts.get(r.verdict, 0) + 1
        secs.append(SectionEntry(
            experiment=exp, title=f"Experiment {s}: the ball after a stroke of the cue", folder=exp,
            source=f"§{'I' * (s % 3 + 1)} n°{s + 2}, p. {70 + s}",
            question=(Span("Does the speed v"), Span("y", "sub"), Span(" reach 5/7 of v"), Span("0", "sub"),
                      Span(" as Résal says: "), Span(QUOTES[s % len(QUOTES)], "em")),
            figures=figs, rows=tuple(row_list), counts=counts, page=70 + s,
            notes=(_rich("The experiment reads the paper's premises from its config, never from the text."),)))
        findings.append(FindingEntry(
            experiment=exp, id=f"F{s}", category="formula", category_label="a printed formula that cannot be right",
            consequence=5 - s % 5,
            text=(Span(f"Finding {s}: "), Span("the rolling speed "), Span(r"v_r", "math"), Span(" is printed as "),
                  Span(QUOTES[(s + 1) % len(QUOTES)]), Span(" — which the exact mechanics give only when "),
                  Span("f^2", "math"), Span(" is negligible; otherwise the claim fails by several per cent.")),
            rows=(f"{exp}--R{s}.0", f"{exp}--R{s}.1"), figure=figs[0].png if figs else None))
    counts: dict[str, int] = {}
    for sec in secs:
        for v, n in sec.counts.items():
            counts[v] = counts.get(v, 0) + n
    meas = (_measured(folder),) if measured else ()
    if measured:
        findings.append(FindingEntry(
            experiment="modern-head-on", id="cue", category="measured", category_label="measured today",
            consequence=4, text=_rich("The cue ball rolls at 0.251 m/s, not 0.397."),
            rows=("modern-head-on--cue_final_speed",), figure=None))
    return Edition(
        title="Résal 1883, reproduced", subtitle="Commentaire sur la théorie du billard de Coriolis: every number, "
        "computed again", counts=counts, reasons={"rounding": counts.get("differs", 0)},
        findings=tuple(findings), sections=tuple(secs), provenance="resal 0.1.0 · commit 0123456789ab",
        measured_sections=meas, measurement_counts={"consistent": 1, "inconsistent": 1, "fitted": 1} if measured
        else {},
        whose_error=(("printed digits rounded or truncated", counts.get("differs", 0), "rounding"),),
        answer=((Span("Of 44 printed values, most are reproduced from the paper's own premises; "),
                 Span(r"\varepsilon = 0{,}29", "math"), Span(" among them.")),
                _rich("What 1883 got wrong is a handful of rounded digits, never a law."),
                _rich("Today's measurements disagree with the paper's mechanics where the cloth matters.")),
        error_kinds=(ErrorKind("rounding", "printed digits rounded or truncated", counts.get("differs", 0),
                               "the printed digits round what the premises give: no error of substance"),
                     ErrorKind("holds", "Résal right", counts.get("reproduced", 0), "the printed value holds")),
        history=(_rich("Gaspard-Gustave Coriolis published his Théorie mathématique des effets du jeu de billard in "
                       "1835; Henri Résal commented on it in 1883."),
                 _rich("The ricochets are Rozé's experiments, reported by Résal.")),
        top=2)


def _tool(name: str) -> str:
    path = shutil.which(name)
    if path is None:
        pytest.skip(f"{name} (poppler-utils) is not installed")
    return path


def _run(*args: str) -> str:
    return subprocess.run(args, check=True, capture_output=True, text=True, encoding="utf-8").stdout


def _norm(text: str) -> str:
    return " ".join(text.split())


def _flat(text: str) -> str:
    """Text without its whitespace: a line broken anywhere (at a slash, in a table's cell) still matches."""
    return "".join(text.split())


def _plain(rich) -> str:
    return "".join(s.text for s in rich if s.style != "math")


class Rendered:
    def __init__(self, ed: Edition, folder: Path, pdf: bytes):
        self.ed, self.folder, self.pdf = ed, folder, pdf
        self.path = folder / "report.pdf"
        self.path.write_bytes(pdf)
        # -raw: in the order the page draws it, a table's cell by cell (columns side by side stay apart)
        self.pages = _run(_tool("pdftotext"), "-raw", "-enc", "UTF-8", str(self.path), "-").split("\f")[:-1]
        self.text = _norm(" ".join(self.pages))


def _render(ed: Edition, folder: Path) -> Rendered:
    buf = io.BytesIO()
    assert et.write_pdf(ed, folder, buf) is None
    return Rendered(ed, folder, buf.getvalue())


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    folder = tmp_path_factory.mktemp("edition-pdf")
    return _render(make_edition(folder), folder)


def _streams(pdf: bytes) -> bytes:
    """The PDF's bytes with every Flate stream inflated after them (what a reader of the objects sees)."""
    out = [pdf]
    for m in re.finditer(rb"stream\r?\n", pdf):
        try:
            out.append(zlib.decompressobj().decompress(pdf[m.end():m.end() + 4_000_000]))
        except zlib.error:
            continue
    return b"\n".join(out)


# -- 1. contents, bookmarks, metadata, the same bytes ---------------------------------------------------------------
def test_contents_bookmarks_and_metadata(rendered):
    info = _run(_tool("pdfinfo"), str(rendered.path))
    assert re.search(r"^Title:\s+Résal 1883, reproduced$", info, re.M)
    assert re.search(r"^Author:\s+resal$", info, re.M)
    assert "CreationDate" not in info and "ModDate" not in info
    assert b"/CreationDate" not in rendered.pdf and b"/ModDate" not in rendered.pdf
    assert b"/Outlines" in rendered.pdf  # the bookmarks, one per heading
    titles = re.findall(rb"/Title\s*\(([^)]*)\)", rendered.pdf)
    for s in rendered.ed.sections:
        assert any(s.title.encode() in t for t in titles) or s.title.encode("utf-16-be") in rendered.pdf, s.title
    contents = next(p for p in rendered.pages if "Contents" in p)
    for s in (*rendered.ed.sections, *rendered.ed.measured_sections):
        assert s.title in contents
    for part in ("The answer in brief", "How to read the rows", "A historical note", "Provenance"):
        assert part in contents


def test_the_same_edition_gives_the_same_bytes(rendered):
    buf = io.BytesIO()
    et.write_pdf(rendered.ed, rendered.folder, buf)
    assert buf.getvalue() == rendered.pdf


def test_the_same_bytes_in_other_processes(rendered):
    """Nothing in the bytes hangs on the process: not the time, not the hash seed of str (dict and set orders)."""
    code = ("import hashlib, io, sys; from pathlib import Path; sys.path[:0] = [sys.argv[1], sys.argv[2]]; "
            "from test_edition_pdf import make_edition; from reproductions.edition.typst import write_pdf; "
            "ed = make_edition(Path(sys.argv[3]), draw=False); buf = io.BytesIO(); "
            "write_pdf(ed, Path(sys.argv[3]), buf); print(hashlib.sha256(buf.getvalue()).hexdigest()); "
            "print('matplotlib' in sys.modules)")
    root = Path(__file__).resolve().parent
    for seed in ("1", "2"):
        done = subprocess.run([sys.executable, "-c", code, str(root), str(root.parent), str(rendered.folder)],
                              check=True, capture_output=True, text=True, env={**os.environ, "PYTHONHASHSEED": seed})
        digest, mpl = done.stdout.split()
        assert digest == hashlib.sha256(rendered.pdf).hexdigest()
        assert mpl == "False"  # 8: the edition's PDF never imports matplotlib


# -- 2. links: findings to rows, rows to the facsimile, DOIs --------------------------------------------------------
def test_links_to_rows_to_the_facsimile_and_to_dois(rendered):
    data = rendered.pdf
    annots = re.findall(rb"<<[^<>]*/Subtype\s*/Link[^<>]*(?:<<[^<>]*>>[^<>]*)*>>", data)
    assert len(annots) > 50
    internal = [a for a in annots if b"/Dest" in a or b"/GoTo" in a]
    uris = set(re.findall(rb"/URI\s*\(([^)]*)\)", data))
    assert len(internal) >= 2 * len(rendered.ed.sections)  # each finding's rows, the contents
    assert facsimile(70).encode() in uris and facsimile(71).encode() in uris
    assert b"https://doi.org/10.1119/1.3116835" in uris and b"https://doi.org/10.1119/1.19260" in uris
    assert b"https://billiards.colostate.edu/faq/physics/" in uris  # the sentence's own punctuation left out


def test_each_finding_cites_the_page_of_its_rows(rendered):
    def pages_of(row: RowEntry) -> set[int]:
        """The page of a row's last line (its id, in its developers' line) and the one before: its table starts on
        one of them (a row's cells never split, its table may)."""
        tail = f"row {row.id} ·"
        k = next(k for k, p in enumerate(rendered.pages, 1) if tail in _norm(p))
        return {k, k - 1}

    rows = {r.anchor: r for s in rendered.ed.sections for r in s.rows}
    for f in rendered.ed.findings:
        for anchor in f.rows:
            if anchor in rows:
                r = rows[anchor]
                where = r.section + (f", {r.equation}" if r.equation else "")
                cited = re.findall(rf"{re.escape(where)} \(p\. (\d+):", rendered.text)
                assert cited and {int(c) for c in cited} & pages_of(r), anchor
            else:
                assert "measured (p. " in rendered.text
    assert "(p. ?" not in rendered.text


# -- 3. rows as tables ----------------------------------------------------------------------------------------------
def test_rows_are_tables_that_say_everything(rendered):
    text = _flat(rendered.text)
    rows = [r for s in rendered.ed.sections for r in s.rows]
    for r in rows:
        for rich in (r.printed, r.english, r.note):
            assert _flat(_plain(rich)) in text, _plain(rich)[:60]
        for word in (r.computed, r.difference, r.tolerance, r.evidence, r.config, r.function):
            assert _flat(word) in text
    for section in rendered.ed.sections:
        for r in section.rows:  # its head: where, the facsimile's page, the verdict and the reason (its id is in
            head = _norm(et._where(r))  # its developers' line, not the reader's)
            page = r.page if r.page is not None else section.page
            line = next(ln for p in rendered.pages for ln in p.splitlines() if _norm(ln).startswith(head)
                        and VERDICT_LABEL[r.verdict] in ln and f"p. {page} of 1883" in ln)
            assert VERDICT_LABEL[r.verdict] in line and (r.reason in line if r.reason else True), line
    # the tagged PDF: one table per row and measurement, beside the kinds of error and the glossary
    tables = len(re.findall(rb"/S\s*/Table\b", _streams(rendered.pdf)))
    n = len(rows) + sum(len(s.measurements) for s in rendered.ed.measured_sections)
    assert tables >= n + 2


def test_the_parts_come_in_the_readers_order(rendered):
    ed = rendered.ed
    contents = next(k for k, p in enumerate(rendered.pages) if "Contents" in p)

    def first(line_start: str) -> tuple[int, int]:
        for k, page in enumerate(rendered.pages[contents:], contents):
            for j, ln in enumerate(page.splitlines()):
                if _norm(ln).startswith(line_start) and ". . ." not in ln:
                    return k, j
        raise AssertionError(f"not found: {line_start}")

    assert rendered.pages[0].lstrip().startswith(ed.title)  # the title block, the answer, its table, Contents
    assert rendered.pages[0].index("The answer in brief") < rendered.pages[0].index("Contents")
    assert "The claims that differ, by whose error they show" in rendered.pages[0]
    order = [first("What Résal got right and wrong"), first("How to read the rows"), first("A historical note")]
    order += [first(f"{k}. {s.title}") for k, s in enumerate(ed.sections, 1)]
    order += [first("The 1883 theory against today's measurements")]
    order += [first(f"{len(ed.sections) + 1}. {ed.measured_sections[0].title}")]
    order += [first("All findings, continued (3–5)"), first("Provenance")]
    assert order == sorted(order)
    glossary = _norm(" ".join(rendered.pages[order[1][0]:order[2][0] + 1]))
    assert "consequence 1/5 … 5/5" in glossary and "1 (a detail)" in glossary
    assert "changes what the paper teaches" in glossary
    for v in ("reproduced", "differs", "not checkable", "consistent", "inconsistent", "fitted"):
        assert v in glossary
    for a in ed.answer[1:]:
        assert _plain(a) in _norm(rendered.pages[0])
    for h in ed.history:
        assert _norm(_plain(h)) in rendered.text
    top = _norm(" ".join(rendered.pages[:order[1][0] + 1]))
    assert "Finding 0:" in top and "Finding 1:" in top and "Finding 2:" not in top  # the first ``top`` only


def test_every_measurement_in_its_part(rendered):
    part = rendered.text[rendered.text.rindex("The 1883 theory against today's measurements"):]
    for s in rendered.ed.measured_sections:
        for m in s.measurements:
            assert f"{m.source} {VERDICT_LABEL[m.verdict]}" in part and f"row {m.id} ·" in part
            assert m.measured in part and m.predicted in part
    assert "measured (p. " in rendered.text  # a finding links a measurement


# -- 4. figures: vector, floating, a missing one said -----------------------------------------------------------
def test_figures_are_the_vector_pdfs(rendered):
    # matplotlib's text is in the figures: it is text in the PDF only if the figure is its vector PDF, not a PNG
    for s in range(2):
        assert f"time of case {s} (s)" in rendered.text
        assert f"Trajectory of the centre, case {s}." in rendered.text
    assert not re.search(rb"/Subtype\s*/Image", rendered.pdf)  # no raster: every figure had its PDF
    fonts = _run(_tool("pdffonts"), str(rendered.path))
    assert "DejaVuSans" in fonts  # the figures' own font (matplotlib's), embedded with them


def test_a_figure_without_its_pdf_is_its_png_and_a_missing_one_is_said(tmp_path):
    ed = make_edition(tmp_path, sections=2, rows=2, figures=2, measured=False)
    (tmp_path / ed.sections[0].figures[0].pdf).unlink()
    gone = ed.sections[1].figures[0]
    (tmp_path / gone.pdf).unlink()
    (tmp_path / gone.png).unlink()
    r = _render(ed, tmp_path)
    assert re.search(rb"/Subtype\s*/Image", r.pdf)  # the PNG of the first
    assert f"figure missing: {gone.png}" in r.text
    assert "time of case 1 (s)" not in r.text


# -- 5. pages at least 60 % full ------------------------------------------------------------------------------------
def _fill(path: Path, folder: Path) -> list[float]:
    """For each page, how far down its text block (A4, the template's margins: 20 mm at the sides, 18 mm above, 22
    mm below) the lowest ink of anything drawn goes, from 0 to 1: text, rules, table fills and figures alike, read
    off the page rasterised at 30 dpi (pdftotext would not see the figures)."""
    from PIL import Image

    dpi = 30
    subprocess.run([_tool("pdftoppm"), "-gray", "-r", str(dpi), str(path), str(folder / "fill")], check=True)
    mm = dpi / 25.4
    out = []
    for png in sorted(folder.glob("fill-*.pgm"), key=lambda p: int(p.stem.rpartition("-")[2])):
        a = np.asarray(Image.open(png))
        body = a[round(18 * mm):round((297 - 22) * mm), round(20 * mm):round(190 * mm)]
        ink = np.nonzero((body < 200).any(axis=1))[0]
        out.append((ink.max() + 1) / body.shape[0] if len(ink) else 0.0)
        png.unlink()
    return out


def _short_pages(pages: list[str], fill: list[float], headings: list[str]) -> list[tuple[int, float]]:
    """The pages under 60 % full but the last page of a top-level part (the next page opens with a heading of
    level 1) and the document's last page."""
    assert len(pages) == len(fill)
    opens = [any(_norm(p).startswith(h) for h in headings) for p in pages]
    return [(k + 1, round(f, 2)) for k, f in enumerate(fill) if f < 0.6 and k + 1 < len(pages) and not opens[k + 1]]


def _headings(ed: Edition) -> list[str]:
    every = (*ed.sections, *ed.measured_sections)
    return [*(f"{k}. {s.title[:30]}" for k, s in enumerate(every, 1)), "The 1883 theory against today's",
            "All findings", "Provenance"]


def test_every_page_is_at_least_60_percent_full(rendered, tmp_path):
    fill = _fill(rendered.path, tmp_path)
    assert len(fill) > 10
    assert _short_pages(rendered.pages, fill, _headings(rendered.ed)) == []
    assert np.mean(fill) > 0.75


# -- 6. fonts -------------------------------------------------------------------------------------------------------
def test_every_font_is_embedded_and_none_is_the_systems(rendered):
    lines = _run(_tool("pdffonts"), str(rendered.path)).splitlines()[2:]
    assert lines
    for ln in lines:
        cols = ln.split()
        emb = cols[-5]
        assert emb == "yes", ln
    names = " ".join(ln.split()[0] for ln in lines)
    assert "LibertinusSerif" in names and "NewCMMath" in names and "DejaVuSansMono" in names
    assert not re.search(r"Courier|Helvetica|Times-|Arial|Liberation", names)


# -- 7. every character of the edition's text is text, never Typst ------------------------------------------------
def test_hostile_text_comes_out_verbatim(tmp_path):
    ed = make_edition(tmp_path, sections=1, rows=2, figures=0, measured=False)
    s = ed.sections[0]
    r = s.rows[0]
    evil = replace(r, id=HOSTILE_ID, anchor=f"{s.experiment}--{HOSTILE_ID}", note=_rich(HOSTILE),
                   printed=_rich("= " + HOSTILE), english=_rich("- " + HOSTILE), evidence="+ " + HOSTILE,
                   today="// " + HOSTILE, computed="*")
    finding = replace(ed.findings[0], text=_rich(HOSTILE), rows=(evil.anchor,))
    sec = replace(s, rows=(evil, *s.rows[1:]), title=HOSTILE[:40], question=_rich(HOSTILE))
    ed = replace(ed, sections=(sec,), findings=(finding,), title="#" + HOSTILE[:30], answer=(_rich(HOSTILE),),
                 history=(_rich("= " + HOSTILE),), top=1)
    source = et.typst_source(ed, tmp_path)
    assert HOSTILE not in source  # only ever as a string literal, escaped
    rendered = _render(ed, tmp_path)
    text = _flat(rendered.text)
    assert text.count(_flat(HOSTILE)) >= 8  # question, answer, history, finding, note, printed, English, evidence
    assert _flat("= " + HOSTILE) in text and _flat("// " + HOSTILE) in text
    assert _flat(f"row {HOSTILE_ID} ·") in text  # the row's id, in its developers' line; its label made safe
    assert f"{evil.section}{', ' + evil.equation if evil.equation else ''} (p. " in rendered.text  # the finding
    # links it, by its place in the paper (the id is not the reader's)


def test_a_formula_outside_the_subset_is_refused_not_passed_through(tmp_path):
    ed = make_edition(tmp_path, sections=1, rows=1, figures=0, measured=False)
    s = ed.sections[0]
    r = replace(s.rows[0], note=(Span(r"\mathcal{F} = m a", "math"),))
    ed = replace(ed, sections=(replace(s, rows=(r,)),))
    with pytest.raises(ValueError, match=r"\\mathcal"):
        et.typst_source(ed, tmp_path)


# -- 8. no matplotlib in the edition's code -------------------------------------------------------------------------
def test_the_edition_package_imports_no_matplotlib():
    """Read off the code (the run in another process is checked above): no module of the edition imports it."""
    import ast

    root = Path(et.__file__).resolve().parent
    for path in root.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                     [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            assert not [n for n in names if n.split(".")[0] == "matplotlib"], path
    assert not (root.parent / "edition_pdf.py").exists()


# -- odd editions ---------------------------------------------------------------------------------------------------
def test_an_empty_edition_compiles(tmp_path):
    ed = Edition(title="Empty", subtitle="", counts={}, reasons={}, findings=(), sections=(), provenance="")
    r = _render(ed, tmp_path)
    assert r.pdf.startswith(b"%PDF") and len(r.pages) <= 2
    assert "Empty" in r.text and "How to read the rows" in r.text


def test_evidence_outside_the_edition_is_named_without_a_link(tmp_path):
    ed = make_edition(tmp_path, sections=1, rows=2, figures=0, measured=False)
    f = ed.findings[0]
    gone = replace(f, rows=(f"{f.experiment}--nowhere",), figure="exp-0/none.png")
    r = _render(replace(ed, findings=(gone,)), tmp_path)
    assert "nowhere" in r.text and "figure exp-0/none.png" in r.text and "(p. ?" not in r.text


# -- the real edition -----------------------------------------------------------------------------------------------
def test_the_real_edition(reproduced_all, tmp_path):
    """``resal reproduce --all``'s report.pdf: the same bytes again, every row and figure in it, links, fonts, and
    every page at least 60 % full but the last of a part."""
    from reproductions import edition, report

    out, _ = reproduced_all
    ed = edition.build(report._summaries(out))
    buf = io.BytesIO()
    et.write_pdf(ed, out, buf)
    pdf = (out / "report.pdf").read_bytes()
    assert buf.getvalue() == pdf
    r = Rendered.__new__(Rendered)
    r.ed, r.folder, r.pdf, r.path = ed, tmp_path, pdf, out / "report.pdf"
    r.pages = _run(_tool("pdftotext"), "-raw", "-enc", "UTF-8", str(r.path), "-").split("\f")[:-1]
    r.text = _norm(" ".join(r.pages))
    flat = _flat(r.text)
    for s in (*ed.sections, *ed.measured_sections):
        for row in s.rows:
            assert _flat(f"row {row.id} ·") in flat and _flat(et._where(row)) in flat, row.anchor
        for m in s.measurements:
            assert _flat(f"row {m.id} ·") in flat, m.anchor
        for f in s.figures:
            assert _flat(f.title.rstrip(". ") + ".") in flat, f.png
    assert "figure missing" not in r.text
    assert re.search(rb"/Subtype\s*/Link", pdf) and re.search(rb"/URI\s*\(http://www\.numdam\.org/", pdf)
    for ln in _run(_tool("pdffonts"), str(r.path)).splitlines()[2:]:
        assert ln.split()[-5] == "yes", ln
    fill = _fill(r.path, tmp_path)
    assert _short_pages(r.pages, fill, _headings(ed)) == []
