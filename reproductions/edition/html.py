"""The reader's edition as one HTML page: styles and script from ``templates/``, inline; figures linked beside it."""

from __future__ import annotations

import html
import re

from ..config import FINDINGS, MEASUREMENT_VERDICTS, REASONS
from ..report import VERDICTS
from .build import plain, readable
from .formula import mathml, plain_number
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
from .words import CONSEQUENCE, MEASURED_INTRO, SYMBOLS, VERDICT_WORDS, template

__all__ = ["index_html", "rich_html"]





# -- HTML -------------------------------------------------------------------------------------------------------
def _h(text: str) -> str:
    return html.escape(text, quote=True)


_DOI = re.compile(r"doi:\s?(10\.\d{4,9}/[^\s,;:)]+[^\s,;:).])")


def _prose(text: str) -> str:
    """Prose escaped, its DOIs as links, its e-notation numbers as a reader writes them."""
    out, at = [], 0
    text = plain_number(text)
    for m in _DOI.finditer(text):
        out.append(_h(text[at:m.start()]))
        out.append(f'<a href="https://doi.org/{_h(m.group(1))}">{_h(m.group(0))}</a>')
        at = m.end()
    out.append(_h(text[at:]))
    return _link_ids("".join(out))


# the rows a note may name by their id, while one experiment is rendered: id → (anchor, words for a reader)
_ROW_LINKS: dict[str, tuple[str, str]] = {}
_ALL_LINKS: dict[str, str] = {}  # every anchor of the edition → its words (a row of another experiment)
_OTHER = re.compile(r"(?<![\w#-])([a-z][a-z0-9_]*) of ([a-z]+(?:-[a-z]+)+)(?![\w-])")
_ID = re.compile(r"(?<![\w#-])([a-z][a-z0-9]*(?:_[a-z0-9]+)+|[a-z]+\d+[a-z0-9]*)(?![\w-])")


def _link_ids(escaped: str) -> str:
    """A row named by its id in a note becomes a link to it, its words in place of the id."""
    if _ALL_LINKS:
        escaped = _OTHER.sub(lambda m: f'<a href="#{_h(m.group(2))}--{_h(m.group(1))}">'
                             f"{_ALL_LINKS[m.group(2) + '--' + m.group(1)]} of {m.group(2)}</a>"
                             if m.group(2) + "--" + m.group(1) in _ALL_LINKS else m.group(0), escaped)
    if not _ROW_LINKS:
        return escaped

    def one(m: re.Match) -> str:
        hit = _ROW_LINKS.get(m.group(1))
        return f'<a href="#{_h(hit[0])}">{hit[1]}</a>' if hit else m.group(0)

    return _ID.sub(one, escaped)


def rich_html(rich: Rich) -> str:
    """Spans as HTML: a formula as MathML (from its LaTeX), em and code elements, prose escaped (a row named by
    its id linked to it)."""
    out = []
    for s in rich:
        if s.style == "math":
            out.append(mathml(s.text))
        elif s.style in ("em", "code"):
            out.append(f"<{s.style}>{_h(s.text)}</{s.style}>")
        elif s.style in ("sub", "sup"):
            out.append(f"<{s.style}>{_h(s.text)}</{s.style}>")
        else:
            out.append(_prose(s.text))
    return "".join(out)


def _text(text: str) -> str:
    """A plain string of the model (a value with its unit, a caption) with its formulas typeset."""
    return rich_html(readable(text))


_CSS = template("edition.css")
_JS = template("edition.js")


def _roman(section: str) -> tuple[int, str]:
    """§IV → 4: the order of the paper's sections (anything else after them)."""
    values = {"I": 1, "V": 5, "X": 10, "L": 50, "C": 100}
    digits = [values.get(c, 0) for c in section.lstrip("§")]
    if not digits or 0 in digits:
        return (10 ** 6, section)
    return (sum(-d if i + 1 < len(digits) and d < digits[i + 1] else d for i, d in enumerate(digits)), section)


def _options(name: str, label: str, values: list[tuple[str, str]]) -> str:
    opts = "".join(f'<option value="{_h(v)}">{_h(t)}</option>' for v, t in values)
    return (f'<label for="f-{name}">{_h(label)}<select id="f-{name}"><option value="">all</option>{opts}</select>'
            "</label>")


def _badge(verdict: str) -> str:
    return f'<span class="badge {verdict}">{VERDICT_LABEL[verdict]}</span>'


def _dev(items: list[tuple[str, str]]) -> str:
    """The developer's details of a card: ids, files, functions and raw numbers, collapsed."""
    dl = "".join(f"<dt>{_h(k)}</dt><dd><code>{_h(v)}</code></dd>" for k, v in items if v and v != "—")
    return f'<details class="dev"><summary>for developers</summary><dl>{dl}</dl></details>'


def _page_link(page: int | None) -> str:
    if page is None:
        return f'<a href="{_h(FACSIMILE_ITEM)}">the facsimile</a>'
    return (f'<a href="{_h(facsimile(page))}" title="the facsimile of 1883 (NUMDAM) at the page where this section '
            f'starts">1883, from p.&nbsp;{page}</a>')


def _tolerance(r: RowEntry) -> str:
    if r.tolerance in ("", "—"):
        return ""
    rule = f" ({_prose(r.tolerance_rule)})" if r.tolerance_rule and r.tolerance_rule != "—" else ""
    return _prose(r.tolerance) + rule


def _row_html(r: RowEntry) -> str:
    where = r.section + (f", {r.equation}" if r.equation else "")
    reason = f' <span class="reason">{_h(r.reason_label)}</span>' if r.reason_label else ""
    items = [("as printed", f'<span class="printed" lang="fr">{rich_html(r.printed)}</span>')]
    if r.english:
        items.append(("in English", rich_html(r.english)))
    items.append(("found", _prose(r.evidence)))
    tol = _tolerance(r)
    if tol:
        items.append(("judged with", tol))
    items.append(("how", rich_html(r.note)))
    if r.today:
        items.append(("today", _text(r.today)))
    dl = "".join(f"<dt>{k}</dt><dd>{v}</dd>" for k, v in items)
    dev = _dev([("row", r.id), ("defined in", r.config), ("computed by", r.function), ("computed", r.computed),
                ("difference", r.difference), ("tolerance", r.tolerance),
                ("digitised text", f"line {r.paper_line}" if r.paper_line else "")])
    return (f'<article class="row v-{r.verdict}" id="{_h(r.anchor)}" data-verdict="{r.verdict}" '
            f'data-reason="{_h(r.reason or "none")}" data-section="{_h(r.section.split(" ")[0])}" data-part="paper">'
            f'<h4>{rich_html(r.quantity)}</h4><p class="where">{_badge(r.verdict)}{reason} · {_h(where)} · '
            f"{_page_link(r.page)}</p><dl>{dl}</dl>{dev}</article>")


def _measure_html(m: MeasurementEntry) -> str:
    predicted = _text(m.predicted) + (f", 95 % interval {_text(m.interval)}"
                                       if m.interval not in ("—", "") and m.interval != f"[{m.predicted}, "
                                       f"{m.predicted}]" else "")
    items = [("published", _text(m.measured) + f" ({_prose(m.source)})"), ("uncertainty", _text(m.uncertainty)),
             ("predicted", predicted), ("how", rich_html(m.note))]
    dl = "".join(f"<dt>{k}</dt><dd>{v}</dd>" for k, v in items if v)
    dev = _dev([("row", m.id), ("defined in", m.config), ("computed by", m.function)])
    return (f'<article class="measure v-{m.verdict}" id="{_h(m.anchor)}" data-verdict="{m.verdict}" '
            f'data-reason="none" data-section="today" data-part="measured">'
            f"<h4>{rich_html(m.quantity)}</h4><p class=\"where\">{_badge(m.verdict)}</p><dl>{dl}</dl>{dev}</article>")


def _evidence(anchor: str, r: RowEntry | MeasurementEntry | None) -> str:
    """A finding's row in words: where it is and what it found, linked to its card."""
    if r is None:
        return f'<a href="#{_h(anchor)}">a row</a>'
    if isinstance(r, MeasurementEntry):
        return (f'<a href="#{_h(anchor)}">{rich_html(r.quantity)}</a>: measured {_text(r.measured)}, predicted '
                f"{_text(r.predicted)}, {VERDICT_LABEL[r.verdict]}")
    where = r.section + (f", {r.equation}" if r.equation else "")
    return f'<a href="#{_h(anchor)}">{_h(where)}</a>: {_prose(r.evidence)}'


def _finding_html(f: FindingEntry, anchors: dict[str, RowEntry | MeasurementEntry]) -> str:
    ev = "; ".join(_evidence(a, anchors.get(a)) for a in f.rows)
    fig = f' · <a href="{_h(f.figure)}">its figure</a>' if f.figure else ""
    short, style = CATEGORY.get(f.category, (f.category, "cat"))
    return (f'<li data-category="{_h(f.category)}" id="finding-{_h(f.experiment)}-{_h(f.id)}">'
            f'<span class="badge {style}">{_h(short)}</span> <span class="rank">consequence {f.consequence} of 5'
            f"</span> {rich_html(f.text)} <span class=\"evidence\">Evidence: {ev}{fig}.</span></li>")


def _figure_html(f: FigureEntry) -> str:
    vector = f' <a href="{_h(f.pdf)}">Vector PDF</a>.' if f.pdf else ""
    title = f.title if f.title[-1:] in ".?!" else f.title + "."
    return (f'<figure><a href="{_h(f.png)}"><img src="{_h(f.png)}" alt="{_h(f.alt)}"></a>'
            f"<figcaption><strong>{_text(title)}</strong> {_text(f.caption)}{vector}</figcaption></figure>")


def _counts_html(counts: dict[str, int], verdicts: tuple[str, ...] = VERDICTS) -> str:
    return ", ".join(f'<span class="badge {v}">{counts[v]} {VERDICT_LABEL[v]}</span>' for v in verdicts
                     if counts.get(v))





def _links(s: SectionEntry) -> dict[str, tuple[str, str]]:
    """The rows of an experiment a note may name: id → (anchor, the row's place and claim in words)."""
    out = {}
    for r in s.rows:
        where = _h(r.section + (f", {r.equation}" if r.equation else ""))
        claim = rich_html(r.quantity) if len(plain(r.quantity)) <= 60 else ""
        out[r.id] = (r.anchor, where + (f" ({claim})" if claim else ""))
    for m in s.measurements:
        out[m.id] = (m.anchor, rich_html(m.quantity))
    return out


def _section_head(s: SectionEntry, cls: str, counts: str) -> list[str]:
    """An experiment's section up to its rows: title, source and counts, question, notes, figures."""
    out = [f'<section class="{cls}" id="exp-{_h(s.experiment)}"><h2>{_h(s.title)}</h2>',
           f'<p class="sub">{_h(s.source.split(",")[0])} · {_page_link(s.page)} · {counts}</p>']
    if s.question:
        out.append(f'<p class="question">{rich_html(s.question)}</p>')
    out += [f"<p>{rich_html(n)}</p>" for n in s.notes]
    out += [_figure_html(f) for f in s.figures]
    out.append(f'<details class="dev"><summary>for developers</summary><p>experiment <code>{_h(s.experiment)}'
               f'</code>; files <a href="{_h(s.folder)}/table.md">table.md</a>, '
               f'<a href="{_h(s.folder)}/summary.json">summary.json</a></p></details>')
    return out


def _measured_part(ed: Edition) -> list[str]:
    """The 1883 theory against today's measurements: after the paper's experiments, its own counts."""
    if not ed.measured_sections:
        return []
    n = sum(ed.measurement_counts.values())
    out = [f'<section id="measured" class="measured-part"><h2>The 1883 theory against today\'s measurements</h2>'
           f"<p>{_h(MEASURED_INTRO)}</p><p class=\"counts\">{n} measurements: "
           f"{_counts_html(ed.measurement_counts, MEASUREMENT_VERDICTS)}.</p></section>\n"]
    for s in ed.measured_sections:
        _ROW_LINKS.clear()
        _ROW_LINKS.update(_links(s))
        out += _section_head(s, "measured-experiment", _counts_html(s.measurement_counts, MEASUREMENT_VERDICTS))
        out.append(f'<h3 class="rows-heading">Its {len(s.measurements)} measurements</h3>')
        out += [_measure_html(m) for m in s.measurements]
        if s.rows:
            out.append(f'<h3 class="rows-heading">Its {len(s.rows)} printed claims</h3>')
            out += [_row_html(r) for r in s.rows]
        out.append('<p class="none" hidden>Nothing of this experiment matches the filters.</p></section>\n')
    return out





def _key_html() -> str:
    """How to read the findings: their badges and the consequence scale, before the first finding."""
    cats = "".join(f'<li><span class="badge {style}">{_h(short)}</span> {_h(FINDINGS[code])}</li>'
                   for code, (short, style) in CATEGORY.items() if code in FINDINGS)
    return (f'<div class="key" id="key"><p>{_h(CONSEQUENCE)} The label before each finding says what '
            f"kind it is:</p><ul class=\"cats\">{cats}</ul></div>")


def _glossary(ed: Edition) -> str:
    verdicts = [v for v in VERDICT_WORDS if v[0] in VERDICTS or ed.measured_sections]
    items = [f"<dt>{_badge(v)}</dt><dd>{_h(t)}</dd>" for v, t in verdicts]
    items += [f"<dt>{_h(k)}</dt><dd>{_prose(v)}</dd>" for k, v in SYMBOLS]
    return ('<section id="reading"><h2>How to read the rows</h2><p>Each row is one printed value or claim of the '
            "paper: the claim in words, the French as printed with our English beside it, what was found (the "
            "value resal computes from the paper's premises against the printed one), the tolerance it is judged "
            "with, and how it was computed. A row that differs says why: a slip of 1883, a formula wrong as "
            "printed, a premise that fails, rounded digits, or a slip of the digitised text. The words:</p>"
            f'<dl class="glossary">{"".join(items)}</dl></section>\n')


def _answer_html(ed: Edition) -> list[str]:
    out = ['<section id="answer" aria-labelledby="answer-h"><h2 id="answer-h">The answer in brief</h2>']
    out += [f"<p>{rich_html(a)}</p>" for a in ed.answer]
    if ed.error_kinds:
        rows = "".join(f'<tr><th scope="row">{_h(k.label)}</th><td class="n">{k.rows}</td><td>{_h(k.meaning)}</td>'
                       "</tr>" for k in ed.error_kinds)
        out.append('<table class="kinds"><caption>The claims that differ, by whose error they show</caption>'
                   '<thead><tr><th scope="col">kind</th><th scope="col">rows</th><th scope="col">what it means'
                   f"</th></tr></thead><tbody>{rows}</tbody></table>")
    out.append("</section>\n")
    return out


def index_html(ed: Edition) -> str:
    """The reader's edition as one HTML page: styles and script inline, figures linked beside it."""
    anchors: dict[str, RowEntry | MeasurementEntry] = {
        r.anchor: r for s in (*ed.sections, *ed.measured_sections) for r in s.rows}
    anchors |= {m.anchor: m for s in ed.measured_sections for m in s.measurements}
    top, rest = ed.findings[:ed.top], ed.findings[ed.top:]
    out = ['<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n',
           '<meta name="viewport" content="width=device-width, initial-scale=1">\n',
           f"<title>{_h(ed.title)}</title>\n<style>{_CSS}</style>\n</head>\n<body>\n",
           f"<header><h1>{_h(ed.title)}</h1><p class=\"sub\">{_h(ed.subtitle)}. The paper itself: "
           f'<a href="{_h(FACSIMILE_ITEM)}">the facsimile at NUMDAM</a>. On paper: '
           '<a href="report.pdf">report.pdf</a>.</p></header>\n<main>\n']
    out += _answer_html(ed)
    out.append(f'<section id="findings"><h2>The {len(top)} findings that matter most</h2>{_key_html()}'
               '<ol class="findings">')
    out += [_finding_html(f, anchors) for f in top]
    out.append("</ol>")
    if rest:
        out.append(f'<details id="more-findings"><summary>The other {len(rest)} findings</summary>'
                   f'<ol class="findings" start="{len(top) + 1}">')
        out += [_finding_html(f, anchors) for f in rest]
        out.append("</ol></details>")
    out.append("</section>\n")
    if ed.history:
        out.append('<section id="history"><h2>Coriolis, Résal and Rozé</h2>'
                   + "".join(f"<p>{rich_html(h)}</p>" for h in ed.history) + "</section>\n")
    out.append('<nav aria-label="Experiments"><h2>The experiments, in the paper\'s order</h2><ul>')
    out += [f'<li><a href="#exp-{_h(s.experiment)}">{_h(s.title)}</a> ({_h(s.source)})</li>' for s in ed.sections]
    out.append("</ul>")
    if ed.measured_sections:
        out.append('<h3><a href="#measured">The 1883 theory against today\'s measurements</a></h3><ul>')
        out += [f'<li><a href="#exp-{_h(s.experiment)}">{_h(s.title)}</a> ({_h(s.source)})</li>'
                for s in ed.measured_sections]
        out.append("</ul>")
    out.append("</nav>\n")
    out.append(_glossary(ed))
    reasons = sorted({r.reason for s in ed.sections for r in s.rows if r.reason})
    sections = sorted({r.section.split(" ")[0] for s in ed.sections for r in s.rows}, key=_roman)
    verdicts = [*VERDICTS, *(MEASUREMENT_VERDICTS if ed.measured_sections else ())]
    out.append('<div class="filters" id="filters" hidden role="search">'
               + _options("part", "part", [("paper", "the paper's claims"), ("measured", "today's measurements")])
               + _options("verdict", "verdict", [(v, VERDICT_LABEL[v]) for v in dict.fromkeys(verdicts)])
               + _options("reason", "reason", [("none", "none (no reason given)"),
                                               *((r, REASONS.get(r, r)[:40]) for r in reasons)])
               + _options("section", "section of the paper", [(x, x) for x in sections])
               + _options("category", "findings", [(c, CATEGORY[c][0]) for c in CATEGORY if c in FINDINGS])
               + '<span id="f-shown" aria-live="polite"></span></div>\n')
    try:
        for s in (*ed.sections, *ed.measured_sections):
            _ALL_LINKS.update(dict(_links(s).values()))
        for s in ed.sections:
            _ROW_LINKS.update(_links(s))
            out += _section_head(s, "experiment", _counts_html(s.counts))
            out.append(f'<h3 class="rows-heading">Its {len(s.rows)} rows</h3>')
            out += [_row_html(r) for r in s.rows]
            out.append('<p class="none" hidden>No row of this experiment matches the filters.</p></section>\n')
            _ROW_LINKS.clear()
        out += _measured_part(ed)
    finally:
        _ROW_LINKS.clear()
        _ALL_LINKS.clear()
    out.append(f'</main>\n<footer><details class="dev"><summary>provenance</summary><p>{_h(ed.provenance)}.'
               '</p><p>Tables: <a href="paper-table.csv">paper-table.csv</a> · <a href="paper-table.md">'
               "paper-table.md</a>.</p></details></footer>\n")
    out.append(f"<script>{_JS}</script>\n</body>\n</html>\n")
    return "".join(out)
