"""The reader's edition as data: findings first, then one section per experiment, built from the summaries of a
results folder. ``html`` and ``typst`` render the same object, so the browser and the paper
say the same thing. No I/O here but reading the summaries' own files' names."""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["CATEGORY", "FACSIMILE_ITEM", "FACSIMILE_PDF", "VERDICT_LABEL", "Edition", "ErrorKind", "FigureEntry",
           "FindingEntry", "MeasurementEntry", "Rich", "RowEntry", "SectionEntry", "Span", "facsimile"]


@dataclass(frozen=True)
class Span:
    """A run of text: ``style`` is "" (plain), "math" (``text`` is one formula's LaTeX source: the one source the
    HTML's MathML and the PDF's Typst math are both made from), "em" or "code"."""

    text: str
    style: str = ""


Rich = tuple[Span, ...]  # prose with its formulas


@dataclass(frozen=True)
class FindingEntry:
    experiment: str
    id: str
    category: str  # a code of config.FINDINGS
    category_label: str  # its words, for people
    consequence: int  # 1 … 5, the rank's key
    text: Rich
    rows: tuple[str, ...]  # anchors of the rows that carry it ("<experiment>--<row id>")
    figure: str | None  # the figure's PNG, relative to the results folder


@dataclass(frozen=True)
class RowEntry:
    experiment: str
    id: str
    anchor: str  # "<experiment>--<row id>", unique in the edition
    section: str  # "§I n°5"
    equation: str  # "eq. (9)" or ""
    paper_line: int | None  # line of the digitised text
    quantity: Rich
    printed: Rich  # the paper's own writing, as printed
    printed_value: str  # the number read from it, or "—"
    computed: str
    difference: str  # "+1.23 %" (relative), "Δ = +0.8 (absolute: printed 0)", "discrepancy 2e-16", or "—"
    tolerance: str  # "±0.5 %" or "≤ 1e-9 (discrepancy)" or "—"
    tolerance_rule: str
    verdict: str  # reproduced | differs | not-checkable
    reason: str  # a code of config.REASONS, or ""
    reason_label: str
    note: Rich
    today: str  # today's value beside it, or ""
    config: str  # "configs/<id>.yaml:<line>"
    function: str  # "reproductions.experiments.<kind module>.<function>" that computes it
    evidence: str = ""  # what was found, in words: "agrees to 15 digits", "differs: printed 0.155, computed 0.101"
    english: Rich = ()  # the project's English rendering of ``printed`` (the French as printed)
    page: int | None = None  # the page of 1883 the row's section starts on (the facsimile's page)


@dataclass(frozen=True)
class MeasurementEntry:
    """A published measurement against the paper's mechanics (never counted with the printed claims)."""

    experiment: str
    id: str
    anchor: str  # "<experiment>--<row id>", unique in the edition
    quantity: Rich
    source: str  # the article
    measured: str  # as published, with its unit
    uncertainty: str
    predicted: str
    interval: str  # "[lo, hi]" at 95 %, or "—"
    verdict: str  # a code of config.MEASUREMENT_VERDICTS
    note: Rich
    config: str  # "configs/<id>.yaml:<line>"
    function: str


@dataclass(frozen=True)
class FigureEntry:
    png: str  # relative to the results folder
    pdf: str  # the vector version, relative to the results folder ("" if none)
    title: str
    caption: str  # what is plotted and what to look at
    alt: str  # the alt text


@dataclass(frozen=True)
class SectionEntry:
    experiment: str
    title: str
    source: str  # "§I n°5, p. 72"
    question: Rich
    figures: tuple[FigureEntry, ...]
    rows: tuple[RowEntry, ...]
    counts: dict[str, int]  # verdict → number of rows
    folder: str  # the experiment's folder, relative to the results folder
    notes: tuple[Rich, ...] = field(default=())
    measurements: tuple[MeasurementEntry, ...] = field(default=())
    measurement_counts: dict[str, int] = field(default_factory=dict)  # verdict → measured rows
    page: int | None = None  # the page of 1883 the section starts on


@dataclass(frozen=True)
class ErrorKind:
    """A line of the summary's table: a kind of error, how many rows show it, and what it means."""

    code: str  # a group of config.REASON_GROUPS, or "beyond" / "holds"
    label: str
    rows: int
    meaning: str


@dataclass(frozen=True)
class Edition:
    title: str
    subtitle: str
    counts: dict[str, int]  # verdict → rows, over the whole paper
    reasons: dict[str, int]  # reason → rows that differ
    findings: tuple[FindingEntry, ...]  # ranked: consequence, then paper order
    sections: tuple[SectionEntry, ...]  # the paper's order
    provenance: str  # version and commit, one line
    # the 1883 theory against today's measurements: experiments of published measurements, apart from the paper's
    measured_sections: tuple[SectionEntry, ...] = field(default=())
    measurement_counts: dict[str, int] = field(default_factory=dict)  # verdict → measured rows, all experiments
    beyond_counts: dict[str, int] = field(default_factory=dict)  # verdict → rows beyond the paper's domain (apart)
    whose_error: tuple[tuple[str, int, str], ...] = ()  # (label, rows, reason codes): report.whose_error
    answer: tuple[Rich, ...] = ()  # three sentences: what holds, what 1883 got wrong, what today's data say
    error_kinds: tuple[ErrorKind, ...] = ()  # the summary's table
    history: tuple[Rich, ...] = ()  # a short historical note: Coriolis 1835, Résal 1883, Rozé
    top: int = 10  # the findings the summary shows; the rest one click away


# the public facsimile: NUMDAM's scan of J. Math. Pures Appl. (3) 9 (1883), 65–98 (the digitised text's own first
# page names the item; the article's PDF opens with NUMDAM's cover page, so page p of 1883 is page p − 63 of it)
FACSIMILE_ITEM = "http://www.numdam.org/item?id=JMPA_1883_3_9_65_0"
FACSIMILE_PDF = "http://www.numdam.org/article/JMPA_1883_3_9_65_0.pdf"
FIRST_PAGE, LAST_PAGE = 65, 98


def facsimile(page: int | None) -> str:
    """The facsimile at a page of 1883 (its item page when the page is unknown or outside 65–98)."""
    if page is None or not FIRST_PAGE <= page <= LAST_PAGE:
        return FACSIMILE_ITEM
    return f"{FACSIMILE_PDF}#page={page - FIRST_PAGE + 2}"


# a finding's category, short (its badge; the long words of config.FINDINGS are its title) and its badge's colours
CATEGORY = {"erratum": ("slip of 1883", "differs"), "formula": ("formula wrong", "formula"),
            "premise": ("premise fails", "premise"), "beyond": ("not in the paper", "beyond"),
            "holds": ("Résal right", "reproduced"), "measured": ("measured today", "beyond")}
VERDICT_LABEL = {"reproduced": "reproduced", "differs": "differs", "not-checkable": "not checkable",
                 "consistent": "consistent", "inconsistent": "inconsistent", "fitted": "fitted"}
