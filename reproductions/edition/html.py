"""The reader's edition as one HTML page: styles and script from ``templates/``, inline; figures linked beside it."""

from __future__ import annotations

import html
from functools import cache
from importlib import resources
from pathlib import Path

from ..config import MEASUREMENT_VERDICTS, REASONS
from ..report import VERDICTS
from .model import CATEGORY, VERDICT_LABEL, Edition, FigureEntry, MeasurementEntry, Rich, RowEntry, SectionEntry

__all__ = ["index_html", "rich_html"]


@cache
def _template(name: str) -> str:
    """A file of ``templates/``, as text."""
    return resources.files(__package__).joinpath("templates", name).read_text(encoding="utf-8")


# -- HTML -------------------------------------------------------------------------------------------------------
def _h(text: str) -> str:
    return html.escape(text, quote=True)


def rich_html(rich: Rich) -> str:
    """Spans as HTML: sub, sup, em and code elements, the text escaped."""
    tags = {"sub": "sub", "sup": "sup", "em": "em", "code": "code"}
    return "".join(f"<{tags[s.style]}>{_h(s.text)}</{tags[s.style]}>" if s.style in tags else _h(s.text)
                   for s in rich)


_CSS = _template("edition.css")

_JS = _template("edition.js")


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


def _row_html(r: RowEntry) -> str:
    verdict = f'<span class="badge {r.verdict}">{VERDICT_LABEL[r.verdict]}</span>'
    reason = f' <span class="badge cat" title="{_h(r.reason_label)}">{_h(r.reason)}</span>' if r.reason else ""
    where = r.section + (f", {r.equation}" if r.equation else "") + (
        f", line {r.paper_line}" if r.paper_line else "")
    items = [("claim", rich_html(r.quantity)), ("printed", f'<span class="printed">{rich_html(r.printed)}</span>'),
             ("computed", _h(r.computed)), ("difference", _h(r.difference)),
             ("tolerance", _h(r.tolerance) + (f" — {_h(r.tolerance_rule)}" if r.tolerance_rule else "")),
             ("verdict", verdict + reason + (f" — {_h(r.reason_label)}" if r.reason_label else "")),
             ("note", rich_html(r.note))]
    if r.today:
        items.append(("today", _h(r.today)))
    items.append(("defined in", f"<code>{_h(r.config)}</code>; computed by <code>{_h(r.function)}</code>"))
    dl = "".join(f"<dt>{k}</dt><dd>{v}</dd>" for k, v in items)
    return (f'<article class="row v-{r.verdict}" id="{_h(r.anchor)}" data-verdict="{r.verdict}" '
            f'data-reason="{_h(r.reason or "none")}" data-section="{_h(r.section.split(" ")[0])}">'
            f"<h4>{_h(r.id)} <span class=\"sub\">({_h(where)})</span> {verdict}{reason}</h4><dl>{dl}</dl></article>")


def _measure_html(m: MeasurementEntry) -> str:
    verdict = f'<span class="badge {m.verdict}">{VERDICT_LABEL[m.verdict]}</span>'
    items = [("measured", rich_html(m.quantity)), ("published", _h(m.measured) + f" — {_h(m.source)}"),
             ("uncertainty", _h(m.uncertainty)), ("predicted", _h(m.predicted) + (
                 f", 95 % interval {_h(m.interval)}" if m.interval != "—" else "")),
             ("verdict", verdict), ("how", rich_html(m.note)),
             ("defined in", f"<code>{_h(m.config)}</code>; computed by <code>{_h(m.function)}</code>")]
    dl = "".join(f"<dt>{k}</dt><dd>{v}</dd>" for k, v in items)
    return (f'<article class="measure v-{m.verdict}" id="{_h(m.anchor)}" data-verdict="{m.verdict}">'
            f"<h4>{_h(m.id)} {verdict}</h4><dl>{dl}</dl></article>")


def _evidence(anchor: str, r: RowEntry | MeasurementEntry | None) -> str:
    """A finding's row: its link, and what it found (printed → computed, or measured → predicted; verdict)."""
    if r is None:
        return f'<a href="#{_h(anchor)}">{_h(anchor)}</a>'
    if isinstance(r, MeasurementEntry):
        return (f'<a href="#{_h(anchor)}">{_h(r.id)}</a> (measured {_h(r.measured)}, predicted {_h(r.predicted)}'
                f'{" " + _h(r.interval) if r.interval != "—" else ""}, {VERDICT_LABEL[r.verdict]})')
    found = (f"printed {_h(r.printed_value)}, computed {_h(r.computed)}" if r.printed_value != "—" else
             _h(r.computed) if r.computed != "—" else "")
    return (f'<a href="#{_h(anchor)}">{_h(r.id)}</a> ({found + ", " if found else ""}'
            f'{VERDICT_LABEL[r.verdict]}{" · " + _h(r.reason) if r.reason else ""})')


def _figure_html(f: FigureEntry) -> str:
    vector = f' (<a href="{_h(f.pdf)}">PDF</a>)' if f.pdf else ""
    return (f'<figure><a href="{_h(f.png)}"><img src="{_h(f.png)}" alt="{_h(f.alt)}"></a>'
            f"<figcaption><strong>{_h(f.title)}.</strong> {_h(f.caption)}{vector}</figcaption></figure>")


def _counts_html(counts: dict[str, int], verdicts: tuple[str, ...] = VERDICTS) -> str:
    return ", ".join(f'<span class="badge {v}">{counts.get(v, 0)} {VERDICT_LABEL[v]}</span>' for v in verdicts)


_MEASURED_INTRO = ("Published measurements of billiard balls, each against what the paper's mechanics predict "
                   "(§I's law of impact, §V–§VI's friction during the impact, §II's sliding on the cloth), with "
                   "the measurement's uncertainty and the prediction's 95 % interval. These rows judge the 1883 "
                   "theory, not a printed claim: their verdicts, consistent or inconsistent at 95 % (fitted where "
                   "the measurement fixed a parameter), are counted apart from the printed claims above.")


def _section_head(s: SectionEntry, cls: str, counts: str) -> list[str]:
    """An experiment's section up to its rows: title, source and counts, question, notes, figures."""
    out = [f'<section class="{cls}" id="exp-{_h(s.experiment)}"><h2>{_h(s.title)}</h2>',
           f'<p class="sub">{_h(s.source)} · <code>{_h(s.experiment)}</code> · {counts} · '
           f'files: <a href="{_h(s.folder)}/table.md">table.md</a>, '
           f'<a href="{_h(s.folder)}/summary.json">summary.json</a></p>']
    if s.question:
        out.append(f'<p class="question">{rich_html(s.question)}</p>')
    out += [f"<p>{rich_html(n)}</p>" for n in s.notes]
    return out + [_figure_html(f) for f in s.figures]


def _measured_part(ed: Edition) -> list[str]:
    """The 1883 theory against today's measurements: after the paper's experiments, its own counts."""
    if not ed.measured_sections:
        return []
    n = sum(ed.measurement_counts.values())
    out = [f'<section id="measured" class="measured-part"><h2>The 1883 theory against today\'s measurements</h2>'
           f"<p>{_h(_MEASURED_INTRO)}</p><p class=\"counts\">{n} measurements: "
           f"{_counts_html(ed.measurement_counts, MEASUREMENT_VERDICTS)}.</p></section>\n"]
    for s in ed.measured_sections:
        out += _section_head(s, "measured-experiment", _counts_html(s.measurement_counts, MEASUREMENT_VERDICTS))
        out.append(f"<h3>Its {len(s.measurements)} measurements</h3>")
        out += [_measure_html(m) for m in s.measurements]
        if s.rows:
            out.append(f"<h3>Its {len(s.rows)} printed claims</h3>")
            out += [_row_html(r) for r in s.rows]
        out.append("</section>\n")
    return out


# the words and symbols a reader meets in the rows (the paper's notation, §I)
SYMBOLS = (
    ("vis viva", "m v², the “living force” of the period: twice the kinetic energy"),
    ("ε, ε′", "Résal's energy-loss coefficients of the two bodies (§I): the vis viva lost in an impact is "
              "governed by them; ε = 0 loses nothing in the restitution, ε = 1 is a plastic impact"),
    ("e", "Newton's coefficient of restitution; for a ball on a fixed body e = (1 − ε)/(1 + ε) (eq. (9))"),
    ("ν", "the normal-velocity yield: the normal velocity after an impact over the one before (§III–IV)"),
    ("f", "the coefficient of friction between the bodies in contact (ball–cloth, ball–cushion, ball–ball)"),
    ("k", "a ball's moment of inertia is M R²/k: k = 5/2 for a homogeneous sphere"),
    ("discrepancy", "for a printed formula: its largest difference from the exact mechanics (a direct numerical "
                    "integration), in the units the row's note gives; within its tolerance the formula holds"),
)


def _glossary(ed: Edition) -> str:
    verdicts = (("reproduced", "what resal computes from the paper's premises agrees with the printed value within "
                               "its printed digits (or the formula within its tolerance)"),
                ("differs", "it does not; the reason says why"),
                ("not-checkable", "nothing can be computed or compared (a measurement the paper reports, a claim "
                                  "without a number)"))
    items = [f'<dt><span class="badge {v}">{VERDICT_LABEL[v]}</span></dt><dd>{_h(t)}</dd>' for v, t in verdicts]
    items += [f'<dt><span class="badge cat">{_h(k)}</span></dt><dd>{_h(v)}</dd>' for k, v in REASONS.items()
              if k in ed.reasons]
    if ed.measured_sections:  # the verdicts of a measurement against the mechanics, their own words
        items += [f'<dt><span class="badge {v}">{VERDICT_LABEL[v]}</span></dt><dd>{_h(t)}</dd>' for v, t in (
            ("consistent", "a published measurement and the paper's prediction agree at 95 % (the measurement's "
                           "uncertainty and the prediction's interval both counted)"),
            ("inconsistent", "they do not: the paper's mechanics do not describe the measurement"),
            ("fitted", "the measurement fixed a parameter of the prediction, so it tests nothing"))]
    items += [f"<dt>{_h(k)}</dt><dd>{_h(v)}</dd>" for k, v in SYMBOLS]
    return ('<section id="reading"><h2>How to read the rows</h2><p>Each row is one printed value or claim of the '
            "paper: the claim in words, the text as printed, what resal computes, their difference and the tolerance "
            "it is judged with, the verdict and, for a row that differs, its reason. The words:</p>"
            f'<dl class="glossary">{"".join(items)}</dl></section>\n')


def index_html(ed: Edition) -> str:
    """The reader's edition as one HTML page: styles and script inline, figures linked beside it."""
    total = sum(ed.counts.values())
    anchors: dict[str, RowEntry | MeasurementEntry] = {
        r.anchor: r for s in (*ed.sections, *ed.measured_sections) for r in s.rows}
    anchors |= {m.anchor: m for s in ed.measured_sections for m in s.measurements}
    out = ['<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n',
           '<meta name="viewport" content="width=device-width, initial-scale=1">\n',
           f"<title>{_h(ed.title)}</title>\n<style>{_CSS}</style>\n</head>\n<body>\n",
           f"<header><h1>{_h(ed.title)}</h1><p class=\"sub\">{_h(ed.subtitle)}.</p>",
           f'<p class="counts">{total} printed values and claims, graded where the paper applies them: '
           f"{_counts_html(ed.counts)}"
           + (" (of the claims that differ: " + "; ".join(f"{n} {_h(label)}" for label, n, _ in ed.whose_error)
              + ")" if ed.whose_error else "")
           + (f"; {sum(ed.beyond_counts.values())} more rows beyond the paper's domain, counted apart: "
              f"{_counts_html(ed.beyond_counts)}" if sum(ed.beyond_counts.values()) else "")
           + (f'; and, <a href="#measured">apart</a>, {sum(ed.measurement_counts.values())} of today\'s '
              f"measurements against the paper's mechanics: "
              f"{_counts_html(ed.measurement_counts, MEASUREMENT_VERDICTS)}" if ed.measured_sections else "")
           + '. Tables: '
           '<a href="paper-table.csv">paper-table.csv</a> · <a href="paper-table.md">paper-table.md</a> · '
           '<a href="report.pdf">report.pdf</a> (this edition on paper).</p></header>\n<main>\n',
           '<section id="findings"><h2>What Résal got right and wrong</h2>',
           "<p>The findings that matter, most consequential first. Each names the rows (and the figure) that carry "
           "it; the rows below give the printed text, the computed value and the reason.</p>",
           '<ol class="findings">']
    for f in ed.findings:
        ev = "; ".join(_evidence(a, anchors.get(a)) for a in f.rows)
        fig = f' · figure <a href="{_h(f.figure)}">{_h(Path(f.figure).name)}</a>' if f.figure else ""
        short, style = CATEGORY.get(f.category, (f.category, "cat"))
        out.append(f'<li><span class="badge {style}" title="{_h(f.category_label)}">{_h(short)}</span> '
                   f'<span class="rank">consequence {f.consequence}/5</span> {rich_html(f.text)} '
                   f'<span class="evidence">({_h(f.experiment)}: {ev}{fig})</span></li>')
    out.append("</ol></section>\n")
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
    out.append('<div class="filters" id="filters" hidden role="search">'
               + _options("verdict", "verdict", [(v, VERDICT_LABEL[v]) for v in VERDICTS])
               + _options("reason", "reason", [("none", "none (no reason given)"), *((r, r) for r in reasons)])
               + _options("section", "section of the paper", [(x, x) for x in sections])
               + '<span id="f-shown" aria-live="polite"></span></div>\n')
    for s in ed.sections:
        out += _section_head(s, "experiment", _counts_html(s.counts))
        out.append(f'<h3 class="rows-heading">Its {len(s.rows)} rows</h3>')
        out += [_row_html(r) for r in s.rows]
        out.append('<p class="none" hidden>No row of this experiment matches the filters.</p></section>\n')
    out += _measured_part(ed)
    out.append(f'</main>\n<footer><p class="sub">{_h(ed.provenance)}.</p></footer>\n')
    out.append(f"<script>{_JS}</script>\n</body>\n</html>\n")
    return "".join(out)


