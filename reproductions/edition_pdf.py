"""The reader's edition → a PDF for print and archive (A4 portrait), from the same ``Edition`` as the HTML.

Two steps. ``layout_edition`` is pure: it wraps every text at word boundaries by the real advance widths of the
embedded faces (``Metrics``: DejaVu Sans, shipped with matplotlib, with its pair kerning) and paginates the flow
into ``Layout``: pages of placed lines (each made of runs: a face, a size, a colour, a baseline shift) and placed
figures. ``write_pdf`` reads the figures, lays out and draws the layout with matplotlib's PDF backend: TrueType
fonts subset and embedded (``pdf.fonttype`` 42), each glyph at the advance and kerning it was measured with (no
ligatures), no time stamp, no software version, so the same edition always gives the same bytes.

Rules of the layout: the findings first (a header with the counts, then the ranked findings, each with the page of
its rows and figure); then one part per experiment, each from a new page: its heading, its source, its question,
its figures (scaled to the text width, caption below), then its rows as blocks (a bold heading line, then
labelled lines with a hanging indent). A line never runs past the margin; a word longer than a line is broken
by characters only then; a page break never splits a line; a heading is never the last line of a page; a row
block that fits in a third of a page is never split.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import BinaryIO

import matplotlib
import matplotlib.colors
import matplotlib.image
import numpy as np
from matplotlib import font_manager, ft2font
from matplotlib.artist import Artist
from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure
from matplotlib.font_manager import FontProperties
from matplotlib.text import Text
from matplotlib.transforms import Affine2D

from .edition.model import Edition, FigureEntry, FindingEntry, MeasurementEntry, Rich, RowEntry, SectionEntry

__all__ = [
    "BOTTOM", "DESCENT", "LEFT", "PAGE_HEIGHT", "PAGE_WIDTH", "TEXT_WIDTH", "TOP",
    "Layout", "Metrics", "Page", "PlacedFigure", "PlacedLine", "Run", "layout_edition", "metrics", "write_pdf",
]

# A4 portrait, in PostScript points; the text block is what lies between the margins
PAGE_WIDTH, PAGE_HEIGHT = 595.2756, 841.8898
LEFT = 56.69  # 20 mm, both sides
TEXT_WIDTH = PAGE_WIDTH - 2 * LEFT
TOP = PAGE_HEIGHT - 56.69  # the top of the first line's box
BOTTOM = 62.0  # no line's box goes below this; the footer lives under it
FOOTER_BASELINE = 36.0
BODY_HEIGHT = TOP - BOTTOM
DESCENT = 0.3  # a line's box ends this many sizes below its baseline (DejaVu Sans descends 0.24 em)
LEADING = 1.32  # baseline to baseline, in sizes

INK, GREY = "#000000", "#4a4a4a"
VERDICT_COLOURS = {"reproduced": "#1b5e20", "differs": "#a01818", "not-checkable": "#8a5200"}
VERDICT_WORDS = {"reproduced": "reproduced", "differs": "differ", "not-checkable": "not checkable"}
# a measurement against the mechanics: its own verdicts (config.MEASUREMENT_VERDICTS), counted apart
MEASURE_COLOURS = {"consistent": "#1b5e20", "inconsistent": "#a01818", "fitted": "#0b3d6b",
                   "not-checkable": "#8a5200"}

_FACE_FILES = {
    "regular": "DejaVuSans.ttf", "bold": "DejaVuSans-Bold.ttf", "oblique": "DejaVuSans-Oblique.ttf",
    "bold-oblique": "DejaVuSans-BoldOblique.ttf", "mono": "DejaVuSansMono.ttf", "mono-bold": "DejaVuSansMono-Bold.ttf",
}
_FONT_FEATURES = ("-liga", "-clig")  # drawn glyph by glyph, as measured
_BREAK = re.compile(r"[ \t\n\r\f\v]+")  # where a line may break: not at a no-break space
_SCRIPT_SCALE = 0.7
_SCRIPT_SHIFT = {"": 0.0, "sub": -0.2, "sup": 0.36}  # in sizes of the surrounding text
_NO_HINTING = ft2font.LoadFlags.NO_HINTING if hasattr(ft2font, "LoadFlags") else ft2font.LOAD_NO_HINTING
_UNFITTED = ft2font.Kerning.UNFITTED if hasattr(ft2font, "Kerning") else ft2font.KERNING_UNFITTED
_REF = 100.0  # the size at which the faces are measured; widths scale linearly (no hinting)

_RC = {
    "pdf.fonttype": 42, "pdf.use14corefonts": False, "pdf.compression": 6, "text.usetex": False,
    "font.family": "sans-serif", "font.sans-serif": ["DejaVu Sans"],
    "figure.dpi": 72, "savefig.dpi": 72, "image.interpolation": "none",
}


# ---------------------------------------------------------------------------------------------------- metrics


def _face_path(face: str) -> str:
    path = Path(matplotlib.get_data_path()) / "fonts" / "ttf" / _FACE_FILES[face]
    if path.is_file():
        return str(path)
    bold, style = ("bold" if "bold" in face else "normal"), ("oblique" if "oblique" in face else "normal")
    family = "DejaVu Sans Mono" if face.startswith("mono") else "DejaVu Sans"
    return font_manager.findfont(FontProperties(family=family, weight=bold, style=style), fallback_to_default=False)


class Metrics:
    """Advance widths of the faces the PDF embeds, with their pair kerning: ``width(text, face, size)`` in points
    is where the next glyph would start if ``text`` were drawn in one piece (ligatures off)."""

    def __init__(self) -> None:
        self.paths = {face: _face_path(face) for face in _FACE_FILES}
        self._fonts: dict[str, ft2font.FT2Font] = {}
        self._adv: dict[str, dict[str, float]] = {face: {} for face in _FACE_FILES}
        self._gid: dict[str, dict[str, int]] = {face: {} for face in _FACE_FILES}
        self._kern: dict[str, dict[tuple[int, int], float]] = {face: {} for face in _FACE_FILES}
        self._cache: dict[tuple[str, str], float] = {}

    def _font(self, face: str) -> ft2font.FT2Font:
        font = self._fonts.get(face)
        if font is None:
            font = self._fonts[face] = ft2font.FT2Font(self.paths[face])
            font.set_size(_REF, 72)
        return font

    def glyph(self, face: str, ch: str) -> int:
        """The glyph of ``ch`` in ``face`` (its cmap's; 0, the missing glyph, if it has none)."""
        gid = self._gid[face].get(ch)
        if gid is None:
            font = self._font(face)
            gid = self._gid[face][ch] = font.get_char_index(ord(ch))
            self._adv[face][ch] = font.load_char(ord(ch), flags=_NO_HINTING).linearHoriAdvance / 65536 / _REF
        return gid

    def kerning(self, face: str, left: int, right: int) -> float:
        """The pair kerning of two glyphs of ``face``, at 1 pt."""
        k = self._kern[face].get((left, right))
        if k is None:
            k = self._kern[face][(left, right)] = self._font(face).get_kerning(left, right, _UNFITTED) / 64 / _REF
        return k

    def _unit_width(self, text: str, face: str) -> float:
        adv, gid, kern = self._adv[face], self._gid[face], self._kern[face]
        total, prev = 0.0, -1
        for ch in text:
            g = gid.get(ch)
            if g is None:
                g = self.glyph(face, ch)
            total += adv[ch]
            if prev >= 0:
                k = kern.get((prev, g))
                total += self.kerning(face, prev, g) if k is None else k
            prev = g
        return total

    def width(self, text: str, face: str, size: float) -> float:
        """The advance width of ``text`` in ``face`` at ``size`` points."""
        key = (text, face)
        w = self._cache.get(key)
        if w is None:
            if len(self._cache) > 500_000:  # a long-lived process: the strings of past editions go
                self._cache.clear()
            w = self._cache[key] = self._unit_width(text, face)
        return w * size


@lru_cache(maxsize=1)
def metrics() -> Metrics:
    """The one ``Metrics`` of the process (its tables fill as text is measured)."""
    return Metrics()


# ---------------------------------------------------------------------------------------------------- layout data


@dataclass(frozen=True)
class Run:
    """Text of one face, size and colour on a line: ``y`` is its own baseline (shifted for a sub/superscript)."""

    text: str
    x: float
    y: float
    width: float
    size: float
    face: str
    colour: str
    style: str  # the span's style: "" | "sub" | "sup" | "em" | "code"


@dataclass(frozen=True)
class PlacedLine:
    """A line on a page: ``x``/``y`` are its left end and baseline (points from the page's bottom-left corner),
    ``width`` its extent, ``size`` its text size and ``style`` its role ("title", "part", "block-heading", …).
    ``joins`` says how its text continues on the next line: " " (same paragraph), "" (a word broken by
    characters) or "\\n" (the paragraph ends)."""

    text: str
    x: float
    y: float
    width: float
    size: float
    style: str
    runs: tuple[Run, ...]
    part: str  # the experiment it belongs to, "" for the findings
    joins: str = "\n"
    anchor: str = ""  # a row block's heading: the row's anchor

    @property
    def bottom(self) -> float:
        """The bottom of the line's box."""
        return self.y - DESCENT * self.size

    @property
    def top(self) -> float:
        """The top of the line's box."""
        return self.y - DESCENT * self.size + LEADING * self.size


@dataclass(frozen=True)
class PlacedFigure:
    """A figure's image: ``x``/``y`` its lower-left corner, in points."""

    png: str  # relative to the results folder, as in the edition
    x: float
    y: float
    width: float
    height: float
    part: str


@dataclass(frozen=True)
class Page:
    number: int
    items: tuple[PlacedLine | PlacedFigure, ...]  # in reading order
    footer: PlacedLine

    @property
    def lines(self) -> tuple[PlacedLine, ...]:
        """The page's lines, in reading order (the footer apart)."""
        return tuple(i for i in self.items if isinstance(i, PlacedLine))

    @property
    def figures(self) -> tuple[PlacedFigure, ...]:
        """The page's figures, in reading order."""
        return tuple(i for i in self.items if isinstance(i, PlacedFigure))


@dataclass(frozen=True)
class Layout:
    pages: tuple[Page, ...]
    passes: int = 1  # layouts made until the page references of the findings stood still

    def lines(self) -> Iterator[PlacedLine]:
        """Every line but the footers, in reading order."""
        for page in self.pages:
            yield from page.lines

    def text(self) -> str:
        """The edition's text as laid out: lines joined as they continue ("" inside a word broken by characters)."""
        return "".join(line.text + line.joins for line in self.lines())


# ---------------------------------------------------------------------------------------------------- flow


@dataclass(frozen=True)
class _Fmt:
    face: str = "regular"
    colour: str = INK
    style: str = ""  # the span style it came from


@dataclass
class _Line:
    runs: list[tuple[str, _Fmt, float, float]]  # text, format, x offset from the left margin, width
    size: float
    role: str
    part: str
    joins: str = "\n"
    anchor: str = ""
    keep_with_next: bool = False
    space_before: float = 0.0

    @property
    def height(self) -> float:
        return LEADING * self.size


@dataclass
class _Fig:
    png: str
    width: float
    height: float
    part: str
    keep_with_next: bool = True
    space_before: float = 0.0


@dataclass
class _Block:
    items: list[_Line | _Fig]
    keep_together: bool = False
    space_before: float = 0.0
    new_page: bool = False


Pieces = list[tuple[str, _Fmt]]


def _size(fmt: _Fmt, size: float) -> float:
    return size * _SCRIPT_SCALE if fmt.style in ("sub", "sup") else size


def _span_fmt(style: str, base: _Fmt) -> _Fmt:
    bold = "bold" in base.face
    if style == "em":
        return _Fmt("bold-oblique" if bold else "oblique", base.colour, "em")
    if style == "code":
        return _Fmt("mono-bold" if bold else "mono", base.colour, "code")
    if style in ("sub", "sup"):
        return _Fmt(base.face, base.colour, style)
    return base


def _pieces(rich: Rich | str, base: _Fmt) -> Pieces:
    if isinstance(rich, str):
        return [(rich, base)]
    return [(span.text, _span_fmt(span.style, base)) for span in rich]


class _Typesetter:
    """Breaks pieces of formatted text into lines that fit a width, measured with ``Metrics``."""

    def __init__(self, m: Metrics) -> None:
        self.m = m

    def piece_width(self, text: str, fmt: _Fmt, size: float) -> float:
        return self.m.width(text, fmt.face, _size(fmt, size))

    @staticmethod
    def words(pieces: Pieces) -> list[Pieces]:
        words: list[Pieces] = []
        cur: Pieces = []
        for text, fmt in pieces:
            parts = _BREAK.split(text)
            for k, part in enumerate(parts):
                if k and cur:  # a break lay before this part
                    words.append(cur)
                    cur = []
                if part:
                    if cur and cur[-1][1] == fmt:
                        cur[-1] = (cur[-1][0] + part, fmt)
                    else:
                        cur.append((part, fmt))
        if cur:
            words.append(cur)
        return words

    def word_width(self, word: Pieces, size: float) -> float:
        return sum(self.piece_width(t, f, size) for t, f in word)

    def runs(self, words: Sequence[Pieces], base: _Fmt, size: float,
             x0: float) -> tuple[list[tuple[str, _Fmt, float, float]], float]:
        merged: list[list] = []  # [text, fmt]
        for k, word in enumerate(words):
            if k:
                last = merged[-1][1]
                sp = last if last.style not in ("sub", "sup") else base
                if sp == last:
                    merged[-1][0] += " "
                else:
                    merged.append([" ", sp])
            for text, fmt in word:
                if merged and merged[-1][1] == fmt:
                    merged[-1][0] += text
                else:
                    merged.append([text, fmt])
        out, x = [], x0
        for text, fmt in merged:
            w = self.piece_width(text, fmt, size)
            out.append((text, fmt, x, w))
            x += w
        return out, x - x0

    def split_word(self, word: Pieces, avail: float, size: float) -> tuple[Pieces, Pieces]:
        """The longest head of ``word`` (at least one character) that fits ``avail``, and the rest."""
        chars = [(ch, fmt) for text, fmt in word for ch in text]
        lo, hi = 1, len(chars) - 1  # the head keeps ≥ 1 character, the rest too
        while lo < hi:  # the largest n whose head fits (widths grow with n, kerning apart)
            mid = (lo + hi + 1) // 2
            if self.word_width(self._join(chars[:mid]), size) <= avail:
                lo = mid
            else:
                hi = mid - 1
        return self._join(chars[:lo]), self._join(chars[lo:])

    @staticmethod
    def _join(chars: Sequence[tuple[str, _Fmt]]) -> Pieces:
        out: Pieces = []
        for ch, fmt in chars:
            if out and out[-1][1] == fmt:
                out[-1] = (out[-1][0] + ch, fmt)
            else:
                out.append((ch, fmt))
        return out

    def paragraph(self, pieces: Pieces, base: _Fmt, size: float, x0: float, width: float, role: str, part: str,
                  first: Sequence[tuple[str, _Fmt, float, float]] = ()) -> list[_Line]:
        """``pieces`` wrapped to ``width`` from ``x0``; ``first`` are runs (a label) put before the first line."""
        words = self.words(pieces)
        widths = [self.word_width(w, size) for w in words]
        space = self.piece_width(" ", base, size)
        lines: list[_Line] = []
        i = 0
        while i < len(words):
            if widths[i] > width:  # a word longer than a line: broken by characters, the last resort
                head, rest = self.split_word(words[i], width, size)
                runs, _ = self.runs([head], base, size, x0)
                lines.append(_Line(runs, size, role, part, joins=""))
                words[i], widths[i] = rest, self.word_width(rest, size)
                continue
            j, acc = i + 1, widths[i]
            while j < len(words) and acc + space + widths[j] <= width:
                acc += space + widths[j]
                j += 1
            while True:
                runs, w = self.runs(words[i:j], base, size, x0)
                if w <= width + 1e-9 or j == i + 1:
                    break
                j -= 1
            lines.append(_Line(runs, size, role, part, joins=" "))
            i = j
        if not lines:
            lines.append(_Line([], size, role, part))
        lines[-1].joins = "\n"
        if first:
            lines[0].runs = [*first, *lines[0].runs]
        return lines


@dataclass(frozen=True)
class _Sizes:
    title: float = 20.0
    subtitle: float = 12.0
    part: float = 15.0
    h2: float = 12.0
    heading: float = 10.0
    body: float = 9.0
    caption: float = 8.0
    footer: float = 8.0


_S = _Sizes()
_ROW_LABELS = ("claim", "printed", "computed", "difference", "tolerance", "why", "today", "note", "defined in",
               "measured", "published", "uncertainty", "predicted", "how")
_MEASURED_INTRO = ("Published measurements of billiard balls, each against what the paper's mechanics predict, with "
                   "the measurement's uncertainty and the prediction's 95 % interval. These rows judge the 1883 "
                   "theory, not a printed claim: their verdicts (consistent or inconsistent at 95 %; fitted where the "
                   "measurement fixed a parameter) are counted apart from the claims.")


def _plain(rich: Rich) -> str:
    return "".join(span.text for span in rich)


def _count_pieces(counts: Mapping[str, int], bold: bool = False,
                  colours: Mapping[str, str] = VERDICT_COLOURS) -> Pieces:
    base = _Fmt("bold" if bold else "regular")
    out: Pieces = []
    order = [k for k in colours if k in counts] + sorted(k for k in counts if k not in colours)
    for k, verdict in enumerate(order):
        if k:
            out.append((" · ", base))
        out.append((f"{counts[verdict]} ", base))
        words = VERDICT_WORDS.get(verdict, verdict) if colours is VERDICT_COLOURS else verdict
        out.append((words, _Fmt(base.face, colours.get(verdict, INK))))
    return out


class _Flow:
    """The edition as blocks of unplaced lines and figures, in reading order."""

    def __init__(self, ed: Edition, sizes: Mapping[str, tuple[int, int]], refs: Mapping[str, int], m: Metrics):
        self.ed, self.sizes, self.refs, self.ts = ed, sizes, refs, _Typesetter(m)
        self.blocks: list[_Block] = []
        every = (*ed.sections, *ed.measured_sections)
        self.known = {"row:" + r.anchor for s in every for r in s.rows}
        self.known |= {"row:" + m.anchor for s in ed.measured_sections for m in s.measurements}
        self.known |= {"fig:" + f.png for s in every for f in s.figures if f.png in sizes}
        labels = (*_ROW_LABELS, "question", "evidence", *ed.reasons)
        self.label_w = max(self.ts.piece_width(lab, _Fmt(), _S.body) for lab in labels) + 8.0

    # -- helpers
    def para(self, rich: Rich | str, size: float, role: str, part: str, base: _Fmt = _Fmt(),
             indent: float = 0.0) -> list[_Line]:
        return self.ts.paragraph(_pieces(rich, base), base, size, LEFT + indent, TEXT_WIDTH - indent, role, part)

    def labelled(self, label: str, pieces: Pieces, part: str, size: float = _S.body) -> list[_Line]:
        lab = _Fmt("regular", GREY)
        first = [(label, lab, LEFT, self.ts.piece_width(label, lab, size))]
        x0 = LEFT + self.label_w
        return self.ts.paragraph(pieces, _Fmt(), size, x0, TEXT_WIDTH - self.label_w, "labelled", part, first)

    def ref(self, key: str) -> str:
        """" (p. 7)": the page of a row or figure of the edition ("?" until a first layout has placed it)."""
        if key not in self.known:
            return ""
        return f" (p. {self.refs.get(key, '?')})"

    # -- parts
    def build(self) -> list[_Block]:
        self.front()
        for rank, finding in enumerate(self.ed.findings, 1):
            self.finding(rank, finding)
        for number, section in enumerate(self.ed.sections, 1):
            self.section(number, section)
        if self.ed.measured_sections:  # the 1883 theory against today's measurements: a part of its own
            self.measured_part()
            for number, section in enumerate(self.ed.measured_sections, len(self.ed.sections) + 1):
                self.section(number, section)
        return self.blocks

    def measured_part(self) -> None:
        ed = self.ed
        h = self.para("The 1883 theory against today's measurements", _S.part, "part-heading", "", _Fmt("bold"))
        for ln in h:
            ln.keep_with_next = True
        items: list[_Line | _Fig] = [*h, *self.para(_MEASURED_INTRO, _S.body, "body", "")]
        n = sum(ed.measurement_counts.values())
        items += self.ts.paragraph([(f"{n} measurements: ", _Fmt()),
                                    *_count_pieces(ed.measurement_counts, colours=MEASURE_COLOURS)],
                                   _Fmt(), 11.0, LEFT, TEXT_WIDTH, "counts", "")
        self.blocks.append(_Block(items, new_page=True))

    def front(self) -> None:
        ed = self.ed
        items: list[_Line | _Fig] = self.para(ed.title, _S.title, "title", "", _Fmt("bold"))
        if ed.subtitle:
            items += self.para(ed.subtitle, _S.subtitle, "subtitle", "")
        total = sum(ed.counts.values())
        counts = [(f"{total} claims graded: ", _Fmt()), *_count_pieces(ed.counts)]
        line = self.ts.paragraph(counts, _Fmt(), 11.0, LEFT, TEXT_WIDTH, "counts", "")
        line[0].space_before = 10
        items += line
        if ed.measured_sections:  # counted apart: a measurement against the mechanics is not a printed claim
            n = sum(ed.measurement_counts.values())
            items += self.ts.paragraph([(f"Apart from them, {n} of today's measurements against the paper's "
                                         "mechanics: ", _Fmt()),
                                        *_count_pieces(ed.measurement_counts, colours=MEASURE_COLOURS)],
                                       _Fmt(), 11.0, LEFT, TEXT_WIDTH, "counts", "")
        if sum(ed.beyond_counts.values()):  # counted apart: they grade no claim where the paper applies it
            items += self.ts.paragraph([(f"Apart from them, {sum(ed.beyond_counts.values())} rows beyond the paper's "
                                         "domain: ", _Fmt()), *_count_pieces(ed.beyond_counts)],
                                       _Fmt(), 11.0, LEFT, TEXT_WIDTH, "counts", "")
        if ed.whose_error:
            head = self.para("Whose error the claims that differ show:", _S.body, "body", "", _Fmt("bold"))
            head[0].space_before = 6
            head[-1].keep_with_next = True
            items += head
            for label, n, codes in ed.whose_error:
                items += self.labelled(f"{n} row{'s' if n != 1 else ''}", [(f"{label} ({codes})", _Fmt())], "")
        if ed.provenance:
            prov = self.para(ed.provenance, _S.caption, "provenance", "", _Fmt("regular", GREY))
            prov[0].space_before = 6
            items += prov
        self.blocks.append(_Block(items))
        if ed.findings:
            h = self.para("Findings, by consequence", _S.part, "part-heading", "", _Fmt("bold"))
            for ln in h:
                ln.keep_with_next = True
            self.blocks.append(_Block(h, space_before=16))

    def finding(self, rank: int, f: FindingEntry) -> None:
        title = next((s.title for s in (*self.ed.sections, *self.ed.measured_sections)
                      if s.experiment == f.experiment), f.experiment)
        head = self.para(f"{rank}. {f.category_label} — consequence {f.consequence}/5 · {title}", _S.heading,
                         "block-heading", "", _Fmt("bold"))
        for ln in head:
            ln.keep_with_next = True
        items: list[_Line | _Fig] = [*head, *self.para(f.text, _S.body, "finding", "")]
        evidence: list[str] = []
        if f.rows:
            rows = ", ".join(f"{a.partition('--')[2] or a}{self.ref('row:' + a)}" for a in f.rows)
            evidence.append(f"row{'s' if len(f.rows) > 1 else ''} {rows}")
        if f.figure:
            fig = self._figure_entry(f.figure)
            name = fig.title if fig is not None and fig.title else f.figure
            evidence.append(f"figure “{name}”{self.ref('fig:' + f.figure)}")
        if evidence:
            items += self.labelled("evidence", [("; ".join(evidence), _Fmt())], "")
        self.blocks.append(_Block(items, keep_together=True, space_before=8))

    def _figure_entry(self, png: str) -> FigureEntry | None:
        return next((fig for s in (*self.ed.sections, *self.ed.measured_sections) for fig in s.figures
                     if fig.png == png), None)

    def section(self, number: int, s: SectionEntry) -> None:
        part = s.experiment
        head = self.para(f"{number}. {s.title}", _S.part, "part-heading", part, _Fmt("bold"))
        meta = self.para(" · ".join(x for x in (s.source, f"experiment {s.experiment}") if x), _S.body, "meta", part,
                         _Fmt("regular", GREY))
        tally = (self.ts.paragraph([(f"{sum(s.counts.values())} claims: ", _Fmt()), *_count_pieces(s.counts)],
                                   _Fmt(), _S.body, LEFT, TEXT_WIDTH, "meta", part)
                 if s.rows or not s.measurements else [])
        if s.measurements:
            tally += self.ts.paragraph([(f"{len(s.measurements)} measurements: ", _Fmt()),
                                        *_count_pieces(s.measurement_counts, colours=MEASURE_COLOURS)],
                                       _Fmt(), _S.body, LEFT, TEXT_WIDTH, "meta", part)
        for ln in [*head, *meta, *tally]:
            ln.keep_with_next = True
        items: list[_Line | _Fig] = [*head, *meta, *tally]
        if s.question:
            q = self.labelled("question", _pieces(s.question, _Fmt()), part)
            q[0].space_before = 4
            items += q
        for note in s.notes:
            n = self.para(note, _S.body, "body", part)
            n[0].space_before = 4
            items += n
        self.blocks.append(_Block(items, new_page=True))
        for k, fig in enumerate(s.figures, 1):
            self.figure(number, k, fig, part)
        if s.measurements:
            self.h2(f"Measurements ({len(s.measurements)})", part)
            for m in s.measurements:
                self.measurement(m, part)
        if s.rows:
            self.h2(f"Claims ({len(s.rows)})", part)
            for row in s.rows:
                self.row(row, part)

    def h2(self, title: str, part: str) -> None:
        """A heading within an experiment, kept with what follows it."""
        h = self.para(title, _S.h2, "h2", part, _Fmt("bold"))
        for ln in h:
            ln.keep_with_next = True
        self.blocks.append(_Block(h, space_before=10))

    def figure(self, number: int, k: int, fig: FigureEntry, part: str) -> None:
        size = self.sizes.get(fig.png)
        cap_base = _Fmt("regular", "#222222")
        caption: Pieces = [(f"Figure {number}.{k}. ", _Fmt("bold", "#222222"))]
        if fig.title:
            caption.append((fig.title.rstrip(". ") + ". ", _Fmt("bold", "#222222")))
        caption.append((fig.caption, cap_base))
        cap = self.ts.paragraph(caption, cap_base, _S.caption, LEFT, TEXT_WIDTH, "caption", part)
        items: list[_Line | _Fig]
        if size is None or not size[0] or not size[1]:
            missing = self.para(f"[figure not found: {fig.png}]", _S.body, "missing-figure", part,
                                _Fmt("oblique", VERDICT_COLOURS["differs"]))
            missing[-1].keep_with_next = True
            items = [*missing, *cap]
        else:
            w_px, h_px = size
            max_h = 0.62 * BODY_HEIGHT
            w, h = TEXT_WIDTH, TEXT_WIDTH * h_px / w_px
            if h > max_h:
                w, h = w * max_h / h, max_h
            items = [_Fig(fig.png, w, h, part, space_before=2), *cap]
            cap[0].space_before = 4
        self.blocks.append(_Block(items, keep_together=True, space_before=10))

    def measurement(self, m: MeasurementEntry, part: str) -> None:
        bold = _Fmt("bold")
        head: Pieces = [(f"{m.id} · ", bold), (m.verdict, _Fmt("bold", MEASURE_COLOURS.get(m.verdict, INK)))]
        lines = self.ts.paragraph(head, bold, _S.heading, LEFT, TEXT_WIDTH, "block-heading", part)
        for ln in lines:
            ln.keep_with_next = True
            ln.anchor = m.anchor
        items: list[_Line | _Fig] = list(lines)
        items += self.labelled("measured", _pieces(m.quantity, _Fmt()), part)
        items += self.labelled("published", [(m.measured, _Fmt()), (f" — {m.source}", _Fmt("regular", GREY))], part)
        items += self.labelled("uncertainty", [(m.uncertainty or "—", _Fmt())], part)
        pred = m.predicted + (f", 95 % interval {m.interval}" if m.interval != "—" else "")
        items += self.labelled("predicted", [(pred, _Fmt())], part)
        if _plain(m.note).strip():
            items += self.labelled("how", _pieces(m.note, _Fmt()), part)
        code = _Fmt("mono", GREY, "code")
        items += self.labelled("defined in", [(m.config, code), (" · ", _Fmt("regular", GREY)), (m.function, code)],
                               part)
        height = sum(i.height for i in items)
        self.blocks.append(_Block(items, keep_together=height <= BODY_HEIGHT / 3, space_before=7))

    def row(self, r: RowEntry, part: str) -> None:
        bold = _Fmt("bold")
        head: Pieces = [(f"{r.id} · ", bold), (r.verdict, _Fmt("bold", VERDICT_COLOURS.get(r.verdict, INK)))]
        if r.reason:
            head.append((f" ({r.reason})", bold))
        lines = self.ts.paragraph(head, bold, _S.heading, LEFT, TEXT_WIDTH, "block-heading", part)
        for ln in lines:
            ln.keep_with_next = True
            ln.anchor = r.anchor
        items: list[_Line | _Fig] = list(lines)
        where = ", ".join(x for x in (r.section, r.equation, f"line {r.paper_line}" if r.paper_line else "") if x)
        claim = _pieces(r.quantity, _Fmt()) + ([(f" — {where}", _Fmt("regular", GREY))] if where else [])
        items += self.labelled("claim", claim, part)
        printed = _pieces(r.printed, _Fmt())
        if r.printed_value and r.printed_value != "—":
            printed.append((f" — read as {r.printed_value}", _Fmt("regular", GREY)))
        items += self.labelled("printed", printed, part)
        items += self.labelled("computed", [(r.computed or "—", _Fmt())], part)
        items += self.labelled("difference", [(r.difference or "—", _Fmt())], part)
        tol = r.tolerance or "—"
        items += self.labelled("tolerance", [(f"{tol} ({r.tolerance_rule})" if r.tolerance_rule else tol, _Fmt())],
                               part)
        if r.reason_label:
            items += self.labelled("why", [(r.reason_label, _Fmt())], part)
        if r.today:
            items += self.labelled("today", [(r.today, _Fmt())], part)
        if _plain(r.note).strip():
            items += self.labelled("note", _pieces(r.note, _Fmt()), part)
        code = _Fmt("mono", GREY, "code")
        items += self.labelled("defined in", [(r.config, code), (" · ", _Fmt("regular", GREY)), (r.function, code)],
                               part)
        height = sum(i.height for i in items)
        self.blocks.append(_Block(items, keep_together=height <= BODY_HEIGHT / 3, space_before=7))


# ---------------------------------------------------------------------------------------------------- pagination


def _item_height(item: _Line | _Fig) -> float:
    return item.height


def _groups(items: Sequence[_Line | _Fig]) -> Iterator[list[_Line | _Fig]]:
    """Chains of items each kept with the next (a heading and the first line after it)."""
    cur: list[_Line | _Fig] = []
    for item in items:
        cur.append(item)
        if not item.keep_with_next:
            yield cur
            cur = []
    if cur:
        yield cur


def _merge_kept(blocks: Sequence[_Block]) -> Iterator[_Block]:
    """A block that ends with a heading is joined to the block that follows it."""
    pending: _Block | None = None
    for block in blocks:
        if pending is not None:
            block = _Block([*pending.items, *block.items], block.keep_together, pending.space_before,
                           pending.new_page or block.new_page)
        if block.items and block.items[-1].keep_with_next:
            pending = block
        else:
            pending = None
            yield block
    if pending is not None:
        yield pending


def _paginate(blocks: Sequence[_Block]) -> list[list[tuple[_Line | _Fig, float]]]:
    """Each page's items with the top of their box; a line is placed whole, a heading kept with what follows."""
    pages: list[list[tuple[_Line | _Fig, float]]] = [[]]
    y = TOP

    def new_page() -> None:
        nonlocal y
        if pages[-1]:
            pages.append([])
        y = TOP

    def height(items: Sequence[_Line | _Fig], first_space: bool) -> float:
        return sum(_item_height(i) + (i.space_before if k or first_space else 0.0) for k, i in enumerate(items))

    for block in _merge_kept(blocks):
        if block.new_page:
            new_page()
        top_space = block.space_before if pages[-1] else 0.0
        if block.keep_together:
            h = height(block.items, False)
            if h <= BODY_HEIGHT and y - top_space - h < BOTTOM - 1e-9:
                new_page()
                top_space = 0.0
        y -= top_space
        for group in _groups(block.items):
            need = height(group, bool(pages[-1]) and y < TOP)
            if y - need < BOTTOM - 1e-9 and pages[-1] and need <= BODY_HEIGHT:
                new_page()
            for item in group:
                space = item.space_before if pages[-1] and y < TOP else 0.0
                if y - space - item.height < BOTTOM - 1e-9 and pages[-1]:
                    new_page()  # only for a group taller than a page
                    space = 0.0
                y -= space
                pages[-1].append((item, y))
                y -= item.height
    return pages


def _place(item: _Line | _Fig, top: float) -> PlacedLine | PlacedFigure:
    if isinstance(item, _Fig):
        x = LEFT + (TEXT_WIDTH - item.width) / 2
        return PlacedFigure(item.png, x, top - item.height, item.width, item.height, item.part)
    baseline = top - item.height + DESCENT * item.size
    runs = []
    for text, fmt, x, w in item.runs:
        size = _size(fmt, item.size)
        runs.append(Run(text, x, baseline + _SCRIPT_SHIFT.get(fmt.style, 0.0) * item.size, w, size, fmt.face,
                        fmt.colour, fmt.style))
    x0 = runs[0].x if runs else LEFT
    width = (runs[-1].x + runs[-1].width - x0) if runs else 0.0
    text = _line_text(item.runs)
    return PlacedLine(text, x0, baseline, width, item.size, item.role, tuple(runs), item.part, item.joins, item.anchor)


def _line_text(runs: Sequence[tuple[str, _Fmt, float, float]]) -> str:
    out = ""
    for k, (text, _fmt, x, _w) in enumerate(runs):
        if k and x > runs[k - 1][2] + runs[k - 1][3] + 1e-6 and not out.endswith(" "):
            out += " "  # a gap (the label column) reads as a space
        out += text
    return out


def _footer(ed: Edition, number: int, total: int, m: Metrics) -> PlacedLine:
    fmt = _Fmt("regular", GREY)
    text = f"{ed.title} · page {number} of {total}"
    if m.width(text, fmt.face, _S.footer) > TEXT_WIDTH:
        text = f"page {number} of {total}"
    w = m.width(text, fmt.face, _S.footer)
    x = LEFT + TEXT_WIDTH - w
    run = Run(text, x, FOOTER_BASELINE, w, _S.footer, fmt.face, fmt.colour, "")
    return PlacedLine(text, x, FOOTER_BASELINE, w, _S.footer, "footer", (run,), "")


def _refs(pages: Sequence[Page]) -> dict[str, int]:
    refs: dict[str, int] = {}
    for page in pages:
        for item in page.items:
            if isinstance(item, PlacedFigure):
                refs.setdefault("fig:" + item.png, page.number)
            elif item.anchor:
                refs.setdefault("row:" + item.anchor, page.number)
    return refs


def layout_edition(ed: Edition, image_sizes: Mapping[str, tuple[int, int]], m: Metrics | None = None) -> Layout:
    """Lay the edition out on A4 pages (pure: no I/O). ``image_sizes`` maps a figure's png to its pixel size
    (width, height); a figure without one is laid out as a line saying it is missing. Laid out again until the
    page numbers the findings cite are those where their rows and figures land (at most four times)."""
    m = m or metrics()
    refs: dict[str, int] = {}
    passes = 0
    while True:
        passes += 1
        placed = _paginate(_Flow(ed, image_sizes, refs, m).build())
        total = len(placed)
        pages = tuple(Page(n, tuple(_place(item, top) for item, top in items), _footer(ed, n, total, m))
                      for n, items in enumerate(placed, 1))
        found = _refs(pages)
        if found == refs or passes == 4:
            return Layout(pages, passes)
        refs = found


# ---------------------------------------------------------------------------------------------------- drawing


def _read_image(path: Path) -> np.ndarray | None:
    """A figure's PNG as 8-bit RGB, flattened on white (smaller, and the same on every viewer). Read by Pillow, as
    bytes: matplotlib's ``imread`` gives floats, three times slower to decode and converted back to bytes when the
    PDF embeds them."""
    if not path.is_file():
        return None
    from PIL import Image

    with Image.open(path) as im:
        img = np.asarray(im.convert("RGBA"))
    if np.all(img[..., 3] == 255):
        return np.ascontiguousarray(img[..., :3])
    alpha = img[..., 3:4].astype(np.uint16)
    return ((img[..., :3] * alpha + 255 * (255 - alpha) + 127) // 255).astype(np.uint8)


def _num(v: float) -> bytes:
    text = f"{v:.3f}".rstrip("0").rstrip(".")
    return (text if text not in ("-0", "") else "0").encode()


class _PdfText:
    """Writes runs straight into matplotlib's PDF content stream: the glyphs of the faces ``Metrics`` measured, at
    the advances and pair kerning it measured, through the backend's own font tracking (so the fonts are subset
    and embedded as TrueType with their ToUnicode maps, as for any text). Drawing ~150 000 glyphs through
    ``Text`` artists, which shape every string again, takes ten times as long. ``None`` from ``of`` when the
    backend lacks what it needs: then the runs are drawn with ``renderer.draw_text``."""

    def __init__(self, file, m: Metrics) -> None:
        self.file, self.m = file, m
        self.tracker = file._character_tracker
        self.codes: dict[tuple[str, str], tuple[bytes, bytes]] = {}

    @classmethod
    def of(cls, renderer, m: Metrics, cache: dict) -> _PdfText | None:
        file = getattr(renderer, "file", None)
        if file is None or not hasattr(font_manager, "FontPath") or matplotlib.rcParams["pdf.fonttype"] != 42:
            return None
        tracker = getattr(file, "_character_tracker", None)
        if tracker is None or not hasattr(tracker, "track_glyph") or not hasattr(file, "fontName"):
            return None
        if cache.get("file") is not file:
            cache.clear()
            cache["file"], cache["writer"] = file, cls(file, m)
        return cache["writer"]

    def code(self, face: str, ch: str) -> tuple[bytes, bytes]:
        key = (face, ch)
        got = self.codes.get(key)
        if got is None:
            font = self.m._font(face)
            gid = self.m.glyph(face, ch)
            subset, code = self.tracker.track_glyph(font, ch, gid)
            name = self.file.fontName(font_manager.FontPath(font.fname, font.face_index), subset)
            got = self.codes[key] = (b"/" + name.name, b"%04x" % code)
        return got

    def draw(self, runs: Iterable[Run]) -> None:
        out: list[bytes] = []
        for run in runs:
            if not run.text:
                continue
            r, g, b = matplotlib.colors.to_rgb(run.colour)
            out += [b"q ", _num(r), b" ", _num(g), b" ", _num(b), b" rg BT 1 0 0 1 ", _num(run.x), b" ",
                    _num(run.y), b" Tm\n"]
            size = _num(run.size)
            font, prev, tj = b"", -1, []
            for ch in run.text:
                name, hexcode = self.code(run.face, ch)
                gid = self.m.glyph(run.face, ch)
                if prev >= 0:
                    k = self.m.kerning(run.face, prev, gid)
                    if k:
                        tj.append(b">" + _num(-1000 * k) + b"<")
                if name != font:
                    if tj:
                        out += [b"[<", *tj, b">] TJ\n"]
                        tj = []
                    out += [name, b" ", size, b" Tf\n"]
                    font = name
                tj.append(hexcode)
                prev = gid
            if tj:
                out += [b"[<", *tj, b">] TJ\n"]
            out.append(b"ET Q\n")
        self.file.write(b"".join(out).replace(b"<>", b""))


class _Picture(Artist):
    """A figure's pixels placed in the box (x, y, width, height), in points from the page's bottom-left corner:
    drawn by the renderer's ``draw_image`` with the box as its transform, so the PDF holds the PNG's own pixels,
    scaled by the viewer (an Axes and ``imshow`` would do the same, at ten times the cost per figure)."""

    def __init__(self, img: np.ndarray, box: tuple[float, float, float, float]) -> None:
        super().__init__()
        self.img, self.box = img, box

    def draw(self, renderer) -> None:
        x, y, w, h = self.box
        gc = renderer.new_gc()
        renderer.draw_image(gc, x, y, self.img[::-1], Affine2D().scale(w, h))  # the renderer's rows: bottom up
        gc.restore()


class _TextLayer(Artist):
    """A page's lines (and footer) drawn as one artist."""

    def __init__(self, runs: Sequence[Run], m: Metrics, cache: dict) -> None:
        super().__init__()
        self.runs, self.m, self.cache = runs, m, cache

    def draw(self, renderer) -> None:
        fast = _PdfText.of(renderer, self.m, self.cache)
        if fast is not None:
            fast.draw(self.runs)
            return
        props = self.cache.setdefault("props", {})
        stub = Text(fontfeatures=_FONT_FEATURES) if hasattr(Text, "set_fontfeatures") else None
        gc = renderer.new_gc()
        for run in self.runs:
            prop = props.get((run.face, run.size))
            if prop is None:
                prop = props[(run.face, run.size)] = FontProperties(fname=self.m.paths[run.face], size=run.size)
            gc.set_foreground(run.colour)
            renderer.draw_text(gc, run.x, run.y, run.text, prop, 0.0, ismath=False, mtext=stub)
        gc.restore()


def _draw_page(fig: Figure, page: Page, images: Mapping[str, np.ndarray], m: Metrics, cache: dict) -> None:
    runs: list[Run] = []
    for item in page.items:
        if isinstance(item, PlacedFigure):
            fig.add_artist(_Picture(images[item.png], (item.x, item.y, item.width, item.height)))
        else:
            runs += item.runs
    runs += page.footer.runs
    fig.add_artist(_TextLayer(runs, m, cache))


def write_pdf(ed: Edition, out: Path, fh: BinaryIO) -> Layout:
    """Render ``ed`` to ``fh`` as an A4 PDF, its figures read from ``out / fig.png``; return the layout drawn.
    Deterministic: the same edition and figures always give the same bytes."""
    images: dict[str, np.ndarray] = {}
    for section in (*ed.sections, *ed.measured_sections):
        for fig in section.figures:
            if fig.png not in images:
                img = _read_image(Path(out) / fig.png)
                if img is not None:
                    images[fig.png] = img
    sizes = {png: (img.shape[1], img.shape[0]) for png, img in images.items()}
    m = metrics()
    layout = layout_edition(ed, sizes, m)
    cache: dict = {}
    with matplotlib.rc_context(_RC), PdfPages(fh, metadata={"Creator": None, "Producer": None,
                                                            "CreationDate": None}) as pdf:
        for page in layout.pages:
            fig = Figure(figsize=(PAGE_WIDTH / 72, PAGE_HEIGHT / 72), dpi=72, facecolor="white")
            _draw_page(fig, page, images, m, cache)
            pdf.savefig(fig)
    return layout
