"""The reader's edition as a PDF: a Typst source (``typst_source``, pure but for looking at the figures' files) set
with the page, type and blocks of ``templates/report.typ``, compiled by the ``typst`` package (``write_pdf``).

Every text of the edition enters the source as a Typst string literal (``#"…"``), never as markup, so no character
of a summary can be read as Typst; a formula (a span of style "math") enters as Typst math made from its LaTeX
source (``typst_math``). The order is the HTML page's: the title block, the answer in brief and the kinds of error,
the findings that matter, how to read the rows, a historical note, one part per experiment (each from a new page:
its question, notes, figures floating, then its rows, one table each), the 1883 theory against today's
measurements, the other findings, and the provenance. Each finding links to the rows that carry it (and says their
page); each row links to the page of the 1883 facsimile; a DOI or an address in a note is a link. The document has
no date, and Typst's own fonts only (system fonts ignored): the same edition gives the same bytes on any machine."""

from __future__ import annotations

import re
import struct
from pathlib import Path
from typing import BinaryIO

from ..config import FINDINGS, MEASUREMENT_VERDICTS, REASONS
from ..report import VERDICTS
from .formula import plain_number
from .model import (
    CATEGORY,
    FACSIMILE_ITEM,
    VERDICT_LABEL,
    Edition,
    FigureEntry,
    FindingEntry,
    MeasurementEntry,
    Rich,
    RowEntry,
    SectionEntry,
    facsimile,
)
from .typst_math import latex_to_typst
from .words import CONSEQUENCE, MEASURED_INTRO, SYMBOLS, VERDICT_WORDS, template

__all__ = ["figure_label", "row_label", "typst_source", "write_pdf"]







# -- text as Typst ---------------------------------------------------------------------------------------------------
_CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f]")


def _q(text: str) -> str:
    """A Typst string literal: backslashes and quotes escaped, a line break or a tab a space, control characters
    as ``\\u{…}``."""
    text = text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", " ").replace("\r", " ").replace("\t", " ")
    return '"' + _CONTROL.sub(lambda m: f"\\u{{{ord(m.group(0)):x}}}", text) + '"'


def _s(text: str) -> str:
    """Text as content: ``[#"…"]``."""
    return f"[#{_q(text)}]"


# an address or a DOI in prose: a link (trailing punctuation stays prose)
_LINKS = re.compile(r"https?://[^\s<>\"«»]+|\bdoi:\s?10\.\d{4,9}/[^\s<>\"«»]+")


def _trim(found: str) -> str:
    """An address without the punctuation that ends its sentence (a closing bracket it does not open)."""
    found = found.rstrip(".,;:")
    while found and found[-1] in ")]" and found.count(found[-1]) > found.count("(" if found[-1] == ")" else "["):
        found = found[:-1].rstrip(".,;:")
    return found


def _prose(text: str) -> str:
    """Plain text as markup: string literals, with its addresses and DOIs as links."""
    out, at = [], 0
    for m in _LINKS.finditer(text):
        found = _trim(m.group(0))
        if text[at:m.start()]:
            out.append(f"#{_q(text[at:m.start()])}")
        if found.startswith("doi:"):
            out.append(f"#link({_q('https://doi.org/' + found[4:].strip())}, {_q(found)})")
        else:
            out.append(f"#link({_q(found)})")
        at = m.start() + len(found)
    if text[at:]:
        out.append(f"#{_q(text[at:])}")
    return "".join(out)


def _span(text: str, style: str) -> str:
    if style == "math":
        typ = latex_to_typst(text).strip()
        return f"${typ}$" if typ else ""
    if style == "em":
        return f"#emph({_q(text)})"
    if style == "code":
        return f"#raw({_q(text)})"
    if style == "sub":  # the legacy scripts of ``build.readable``, until the formula detector writes LaTeX
        return f"#sub({_q(text)})"
    if style == "sup":
        return f"#super({_q(text)})"
    return _prose(text)


def _rich(rich: Rich | str) -> str:
    """Spans as content (``none`` when there is nothing to say)."""
    if isinstance(rich, str):
        return f"[{_prose(rich)}]" if rich.strip() else "none"
    if not "".join(s.text for s in rich).strip():
        return "none"
    parts = []
    for s in rich:
        try:
            parts.append(_span(s.text, s.style))
        except ValueError as e:
            raise ValueError(f"a formula of the edition cannot be set: {e}") from None
    return "[" + "".join(parts) + "]"


def _label(kind: str, key: str) -> str:
    """A Typst label for any key, one to one: letters, digits and ``-`` kept, anything else ``_<hex>_``."""
    return kind + "-" + "".join(c if (c.isascii() and c.isalnum()) or c == "-" else f"_{ord(c):x}_" for c in key)


def row_label(anchor: str) -> str:
    """The label of a row or a measurement (its anchor ``<experiment>--<row id>``)."""
    return _label("row", anchor)


def figure_label(png: str) -> str:
    """The label of a figure (its PNG, relative to the results folder)."""
    return _label("fig", png)


def _page_of(label: str) -> str:
    """Markup: the page a label stands on, as the document says it."""
    return f"#context locate(label({_q(label)})).page()"


def _fac(page: int | None) -> str:
    """Markup: a link to the 1883 facsimile at a page."""
    return f"#link({_q(facsimile(page))}, {_q(f'p. {page} of 1883')})" if page is not None else ""


# -- the figures ---------------------------------------------------------------------------------------------------
def _png_size(path: Path) -> tuple[int, int] | None:
    """A PNG's width and height in pixels, from its header (None if it is not a readable PNG)."""
    try:
        with path.open("rb") as fh:
            head = fh.read(24)
    except OSError:
        return None
    if len(head) < 24 or head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        return None
    w, h = struct.unpack(">II", head[16:24])
    return (w, h) if w and h else None


def _figure(f: FigureEntry, root: Path, first: bool) -> str:
    """An experiment's figure: the vector PDF when it is there, else the PNG, else a notice that it is missing.
    It floats: the first at the foot of a page (at the head of the section's first page it would stand above the
    section's heading), the others at the head or the foot, whichever is nearer."""
    path = next((p for p in (f.pdf, f.png) if p and (root / p).is_file()), None)
    size = _png_size(root / f.png)
    aspect = f"{size[0] / size[1]:.6f}" if size else "none"
    return (f"#edition-figure({_q('/' + path) if path else 'none'}, {aspect}, {_q(f.png)}, "
            f"{_s(f.title.rstrip('. '))}, {_s(f.caption)}, {_q(f.alt or f.title)}"
            f"{', placement: bottom' if first else ''}) <{figure_label(f.png)}>\n")


# -- pieces ----------------------------------------------------------------------------------------------------------
def _counts(counts: dict[str, int], verdicts: tuple[str, ...] = VERDICTS) -> str:
    """Markup: the verdicts that count any row, as badges ("none" if none does)."""
    return ", ".join(f"#badge({_q(v)}, {_q(f'{counts[v]} {VERDICT_LABEL[v]}')})" for v in verdicts
                     if counts.get(v)) or '#"none"'


def _where(r: RowEntry) -> str:
    return ", ".join(x for x in (r.section, r.equation, f"line {r.paper_line}" if r.paper_line else "") if x)


def _row(r: RowEntry, s: SectionEntry) -> str:
    page = r.page if r.page is not None else s.page
    where = f"[{_fac(page)}]" if page is not None else "[]"
    numbers = (r.printed_value, r.computed, r.difference, r.tolerance)
    found = r.evidence or (f"{VERDICT_LABEL[r.verdict]}: printed {r.printed_value}, computed {r.computed}"
                           if r.printed_value not in ("", "—") else
                           f"{VERDICT_LABEL[r.verdict]}: {r.computed}" if r.computed not in ("", "—") else
                           f"{VERDICT_LABEL[r.verdict]}")
    why = f"{r.reason}: {r.reason_label}" if r.reason_label else r.reason
    fields = {
        "id": _s(_where(r)), "where": where, "verdict": _q(r.verdict), "verdict-label": _q(VERDICT_LABEL[r.verdict]),
        "reason": _q(r.reason) if r.reason else "none", "claim": _rich(r.quantity) if r.quantity else _s("—"),
        "printed": _rich(r.printed) if r.printed else _s("—"), "english": _rich(r.english),
        "numbers": "true" if any(x not in ("", "—") for x in numbers) else "false",
        "printed-value": _s(r.printed_value or "—"), "computed": _s(plain_number(r.computed or "—")),
        "difference": _s(plain_number(r.difference or "—")), "tolerance": _s(plain_number(r.tolerance or "—")),
        "found": _rich(found),
        "why": _rich(why), "rule": _rich(r.tolerance_rule), "note": _rich(r.note), "today": _rich(r.today),
        "defined": f"[row #raw({_q(r.id)}) · #raw({_q(r.config)}) · computed by #raw({_q(r.function)})]",
    }
    for k in ("claim", "printed"):
        if fields[k] == "none":
            fields[k] = _s("—")
    args = ", ".join(f"{k}: {v}" for k, v in fields.items())
    return f"#claim-row(({args})) <{row_label(r.anchor)}>\n"


def _measure(m: MeasurementEntry) -> str:
    fields = {
        "id": _s(m.source or "measured"), "verdict": _q(m.verdict), "verdict-label": _q(VERDICT_LABEL[m.verdict]),
        "quantity": _rich(m.quantity), "measured": _s(m.measured), "source": _rich(m.source),
        "uncertainty": _rich(m.uncertainty or "—"), "predicted": _s(m.predicted), "interval": _s(m.interval),
        "note": _rich(m.note),
        "defined": f"[row #raw({_q(m.id)}) · #raw({_q(m.config)}) · computed by #raw({_q(m.function)})]",
    }
    if fields["quantity"] == "none":
        fields["quantity"] = _s("—")
    if fields["source"] == "none":
        fields["source"] = _s("—")
    args = ", ".join(f"{k}: {v}" for k, v in fields.items())
    return f"#measure-row(({args})) <{row_label(m.anchor)}>\n"


class _Refs:
    """What a finding can link to: the rows, measurements and figures the edition sets."""

    def __init__(self, ed: Edition) -> None:
        every = (*ed.sections, *ed.measured_sections)
        self.rows: dict[str, RowEntry | MeasurementEntry] = {r.anchor: r for s in every for r in s.rows}
        self.rows |= {m.anchor: m for s in ed.measured_sections for m in s.measurements}
        self.figures = {f.png: f for s in every for f in s.figures}
        self.titles = {s.experiment: s.title for s in every}

    def evidence(self, anchor: str) -> str:
        """Markup: a finding's row, linked, with its page and what it found."""
        r = self.rows.get(anchor)
        if r is None:
            return f"#{_q(anchor.partition('--')[2] or anchor)}"
        name = r.section + (f", {r.equation}" if r.equation else "") if isinstance(r, RowEntry) else "measured"
        link = f"#link(label({_q(row_label(anchor))}), {_q(name)}) (p. {_page_of(row_label(anchor))}"
        if isinstance(r, MeasurementEntry):
            interval = f" {r.interval}" if r.interval != "—" else ""
            found = f"measured {r.measured}, predicted {r.predicted}{interval}, {VERDICT_LABEL[r.verdict]}"
        elif r.evidence:
            found = r.evidence + (f" ({r.reason_label})" if r.reason_label else "")
        else:
            said = (f"printed {r.printed_value}, computed {r.computed}, " if r.printed_value != "—" else
                    f"{r.computed}, " if r.computed != "—" else "")
            found = f"{said}{VERDICT_LABEL[r.verdict]}" + (f" ({r.reason_label})" if r.reason_label else "")
        found = plain_number(found)
        return f"{link}: #{_q(found)})"

    def figure(self, png: str) -> str:
        f = self.figures.get(png)
        if f is None:
            return f"figure #{_q(png)}"
        lab = figure_label(png)
        return f"figure #link(label({_q(lab)}), {_q('“' + f.title.rstrip('. ') + '”')}) (p. {_page_of(lab)})"


def _finding(rank: int, f: FindingEntry, refs: _Refs) -> str:
    short, kind = CATEGORY.get(f.category, (f.category, "cat"))
    ev = "; ".join(refs.evidence(a) for a in f.rows)
    if f.figure:
        ev = (ev + "; " if ev else "") + refs.figure(f.figure)
    where = refs.titles.get(f.experiment, f.experiment)
    evidence = f"[#lab[{'rows' if len(f.rows) > 1 else 'row'}]{ev}]" if ev else "none"
    return (f"#finding({rank}, {_q(kind)}, {_q(short)}, {f.consequence}, {_q(where)}, {_rich(f.text)}, "
            f"{evidence})\n")


def _heading(text: str, level: int = 1, numbered: bool = False) -> str:
    numbering = ', numbering: "1."' if numbered else ""
    return f"#heading(level: {level}{numbering})[#{_q(text)}]\n"


def _para(rich: Rich | str) -> str:
    body = _rich(rich)
    return f"#par({body})\n" if body != "none" else ""


# -- the parts -------------------------------------------------------------------------------------------------------
def _front(ed: Edition) -> list[str]:
    total = sum(ed.counts.values())
    counts = [f"#{_q(f'{total} printed values and claims, graded where the paper applies them: ')}",
              _counts(ed.counts)]
    if ed.whose_error:
        groups = "; ".join(f"{n} {label}" for label, n, _ in ed.whose_error)
        counts.append(f"#{_q(f' (of the claims that differ: {groups})')}")
    beyond = sum(ed.beyond_counts.values())
    if beyond:
        counts += [f"#{_q(f'; {beyond} more rows beyond the paper’s domain, counted apart: ')}",
                   _counts(ed.beyond_counts)]
    if ed.measured_sections:
        n = sum(ed.measurement_counts.values())
        counts += [f"#{_q(f'; and, apart, {n} of today’s measurements against the paper’s mechanics: ')}",
                   _counts(ed.measurement_counts, MEASUREMENT_VERDICTS)]
    counts.append('#"."')
    fac = (f"#{_q('The paper as printed: the facsimile of the Journal de mathématiques pures et appliquées at ')}"
           f"#link({_q(FACSIMILE_ITEM)}) #{_q('(NUMDAM).')}")
    out = [f"#title-block({_s(ed.title)}, {_s(ed.subtitle)}, [{''.join(counts)}], [{fac}])\n"]
    if ed.answer or ed.error_kinds or ed.whose_error:
        out.append(_heading("The answer in brief"))
        out += [_para(a) for a in ed.answer]
        if ed.error_kinds:
            cells = [f"{_s(k.label)}, align(right, {_s(str(k.rows))}), {_s(k.meaning)}" for k in ed.error_kinds]
        else:  # the summary's groups of the claims that differ, where the edition has no table of kinds
            cells = [f"{_s(label)}, align(right, {_s(str(n))}), {_s('reasons: ' + codes)}"
                     for label, n, codes in ed.whose_error]
        if cells:
            out.append("#par[#" + _q("The claims that differ, by whose error they show:") + "]\n")
            out.append(f"#plain-table((auto, auto, 1fr), ({_s('kind')}, {_s('rows')}, {_s('meaning')}), "
                       f"{', '.join(cells)})\n")
    out.append('#outline(title: "Contents")\n')
    return out


def _findings_part(ed: Edition, refs: _Refs) -> list[str]:
    """The first ``ed.top`` findings, as the HTML page's summary shows them."""
    top = ed.findings[:ed.top]
    if not top:
        return []
    more = len(ed.findings) - len(top)
    out = [_heading("What Résal got right and wrong"),
           _para("The findings that matter, most consequential first. Each names the rows (and the figure) that carry "
                 "it, with their page; the rows give the printed text, the computed value and the reason."
                 + (f" The first {len(top)} of {len(ed.findings)}; the other {more} follow the experiments."
                    if more else ""))]
    out += [_finding(k, f, refs) for k, f in enumerate(top, 1)]
    return out


def _more_findings(ed: Edition, refs: _Refs) -> list[str]:
    """The findings after the first ``ed.top``."""
    top = len(ed.findings[:ed.top])
    if top >= len(ed.findings):
        return []
    title = f"All findings, continued ({top + 1}–{len(ed.findings)})" if top else "All findings"
    out = ["#place.flush()\n#pagebreak(weak: true)\n", _heading(title),
           _para(f"The findings after the first {top}, in the same order: by consequence, then in the paper's order."
                 if top else "The findings, by consequence, then in the paper's order.")]
    out += [_finding(k, f, refs) for k, f in enumerate(ed.findings[top:], top + 1)]
    return out


def _glossary(ed: Edition) -> list[str]:
    cells: list[str] = []

    def term(t: str, meaning: str) -> None:
        cells.append(f"{t}, {_s(meaning)}")

    for v, t in VERDICT_WORDS:
        if v in VERDICTS or ed.measured_sections:  # a measurement's verdicts only where there are measurements
            term(f"badge({_q(v)}, {_q(VERDICT_LABEL[v])})", t)
    for k, v in REASONS.items():
        if k in ed.reasons:
            term(f"badge(\"cat\", {_q(k)})", f"a reason: {v}")
    for code in dict.fromkeys(f.category for f in ed.findings):
        short, kind = CATEGORY.get(code, (code, "cat"))
        term(f"badge({_q(kind)}, {_q(short)})", f"a finding: {FINDINGS.get(code, code)}")
    term(_s("consequence 1/5 … 5/5"), CONSEQUENCE)
    for k, v in SYMBOLS:
        term(_s(k), v)
    intro = ("Each row of an experiment is one printed value or claim of the paper, set as one table. Its head gives "
             "the row's id, where it stands in the paper (section, equation, line of the digitised text) with a link "
             "to that page of the 1883 facsimile, and its verdict. Then come the claim in words; the text as printed "
             "in 1883, in French, with its English rendering beside it when there is one; the number read from it, "
             "what resal computes, their difference and the tolerance it is judged with; what was found, in words; "
             "the verdict with its reason; the note; today's value where one is known; and where the row is defined "
             "and computed. The badges and words:")
    return [_heading("How to read the rows"), _para(intro),
            f"#plain-table((auto, 1fr), ({_s('term')}, {_s('meaning')}), {', '.join(cells)})\n"]


def _history(ed: Edition) -> list[str]:
    if not ed.history:
        return []
    return [_heading("A historical note"), *(_para(h) for h in ed.history)]


def _section(s: SectionEntry, root: Path, measured: bool, first_of_part: bool = False) -> list[str]:
    out = [] if first_of_part else ["#place.flush()\n#pagebreak(weak: true)\n"]
    out.append(_heading(s.title, 1, numbered=True))
    counts = (f"#{_q(f'{sum(s.counts.values())} claims: ')}{_counts(s.counts)}" if s.rows or not s.measurements
              else "")
    if s.measurements:
        counts += ("; " if counts else "") + (f"#{_q(f'{len(s.measurements)} measurements: ')}"
                                              f"{_counts(s.measurement_counts, MEASUREMENT_VERDICTS)}")
    meta = [f"#{_q(s.source)}", f"#raw({_q(s.experiment)})"]
    if s.page is not None:
        meta.append(f"the facsimile at {_fac(s.page)}")
    meta.append(counts)
    meta.append(f"files: #raw({_q(s.folder + '/table.md')}), #raw({_q(s.folder + '/summary.json')})")
    out.append(f"#meta[{' · '.join(m for m in meta if m)}]\n")
    q = _rich(s.question)
    if q != "none":
        out.append(f"#par[*Question.* #{q}]\n")
    out += [_para(n) for n in s.notes]
    out += [_figure(f, root, k == 0) for k, f in enumerate(s.figures)]
    if s.measurements:
        out.append(_heading(f"Its {len(s.measurements)} measurement{'s' * (len(s.measurements) != 1)}", 2))
        out += [_measure(m) for m in s.measurements]
    if s.rows:
        what = "printed claims" if measured else "rows"
        out.append(_heading(f"Its {len(s.rows)} {what if len(s.rows) != 1 else what[:-1]}", 2))
        out += [_row(r, s) for r in s.rows]
    return out


def _measured_part(ed: Edition, root: Path) -> list[str]:
    if not ed.measured_sections:
        return []
    n = sum(ed.measurement_counts.values())
    out = ["#place.flush()\n#pagebreak(weak: true)\n", _heading("The 1883 theory against today's measurements"),
           _para(MEASURED_INTRO),
           f"#par[#{_q(f'{n} measurements: ')}{_counts(ed.measurement_counts, MEASUREMENT_VERDICTS)}#\".\"]\n"]
    for k, s in enumerate(ed.measured_sections):
        out += _section(s, root, measured=True, first_of_part=k == 0)
    return out


def _provenance(ed: Edition) -> list[str]:
    words = ("This PDF and index.html are rendered from the same edition of the results folder's summaries; the "
             "tables are paper-table.csv, paper-table.md and paper-table.tex beside it. The 1883 paper: ")
    return ["#place.flush()\n", _heading("Provenance"), _para(ed.provenance + "." if ed.provenance else ""),
            f"#par[#{_q(words)}#link({_q(FACSIMILE_ITEM)})#\".\"]\n"]


def typst_source(ed: Edition, root: Path) -> str:
    """The edition as one Typst source: ``templates/report.typ`` then the edition, figures given from ``root`` (the
    results folder: compile with it as Typst's root). Looks only at the figures' files (which exist, their size)."""
    refs = _Refs(ed)
    keywords = ", ".join(_q(k) for k in ("Résal", "billiards", "1883", "reproduction", "Coriolis"))
    out = [template("report.typ"), "\n// -- the edition ----------------------------------------------------------\n",
           f"#set document(title: {_q(ed.title)}, author: (\"resal\",), keywords: ({keywords}), date: none)\n"]
    out += _front(ed)
    out += _findings_part(ed, refs)
    out += _glossary(ed)
    out += _history(ed)
    for s in ed.sections:
        out += _section(s, root, measured=False)
    out += _measured_part(ed, root)
    out += _more_findings(ed, refs)
    out += _provenance(ed)
    return "".join(out)


def write_pdf(ed: Edition, out: Path, fh: BinaryIO) -> None:
    """The edition's PDF into ``fh``: its Typst source compiled with ``out`` (the results folder) as Typst's root,
    so that the figures, given relative to it, resolve; Typst's own fonts only. The PDF is tagged (headings,
    tables, figures' alt text, for a screen reader); should Typst's tagging fail on the pages (an internal error of
    Typst, not of the edition: 0.15 had one, a table's row broken across pages beside a float), the same pages
    untagged."""
    import typst

    source = typst_source(ed, out).encode("utf-8")
    options = {"root": str(out), "format": "pdf", "ignore_system_fonts": True}
    try:
        data = typst.compile(source, **options)
    except typst.TypstError as e:
        if not str(getattr(e, "message", e)).startswith("internal error"):
            raise
        data = typst.compile(source, **options, pdf_tags=False)
    fh.write(data)
