"""YAML experiment files → frozen dataclasses, with errors that name the file, the line and what was expected.

The common part of every config (id, kind, title, source, printed values, seed) is read here; the
``params`` section is read by the experiment kind's own ``parse`` function through the same ``Node``
reader, so every kind gets the same checks: unknown keys are errors, numbers are numbers (PyYAML reads
``1e-3`` as a string; it is accepted here, as is a fraction such as ``7/12``), ranges are enforced.

A printed value is only ever compared against: ``printed`` entries are never handed to the physics.
"""

from __future__ import annotations

import hashlib
import math
import os
import re
import stat
import sys
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any, Protocol

import yaml

from .errors import InputError

__all__ = [
    "BEYOND_QUANTITY",
    "BEYOND_SUFFIX",
    "MAX_DEPTH",
    "MAX_LINE",
    "MAX_NODES",
    "MAX_YAML_BYTES",
    "REASONS",
    "REASON_GROUPS",
    "REASON_GROUP_LABELS",
    "Experiment",
    "Kind",
    "Node",
    "Printed",
    "Source",
    "comma_problem",
    "comma_readings",
    "decode_text",
    "load_experiment",
    "parse_number",
    "printable",
    "read_input",
    "reason_group",
    "shorten",
    "underflows",
]

# Limits on what a reader takes in, checked before any parsing (configs/README.md, "File limits"): the largest
# experiment file is 25 kB, its longest line 237 characters, its deepest nesting 6 levels.
MAX_YAML_BYTES = 1 << 20  # 1 MiB
MAX_LINE = 10_000  # characters in one line of a YAML or CSV file
MAX_ID_CHARS = 100  # an experiment id names a folder: 255 bytes less the staging name's ~40
MAX_DEPTH = 32  # nested mappings and lists in a YAML or JSON document
MAX_NODES = 100_000  # values of a YAML document, every alias counted as the whole value it stands for
_FILE_TYPES = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a named pipe (FIFO)"), (stat.S_ISCHR, "a device"),
               (stat.S_ISBLK, "a device"), (stat.S_ISSOCK, "a socket"))


def read_input(path: str | os.PathLike[str], what: str, limit: int, unreadable: str | None = None) -> bytes:
    """The bytes of the regular file ``path``, read once, at most ``limit`` of them. A folder, a FIFO, a device
    (``/dev/zero``) or a socket is refused by the type of the opened file (opened without blocking, so a FIFO
    cannot hang the reader), a larger file by its size, before anything is parsed. ``unreadable`` starts the
    message when the file cannot be opened or read (default: "cannot read <what>")."""
    where = str(path)
    unreadable = unreadable or f"cannot read {what}"
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except IsADirectoryError:
        raise InputError(where, f"is a folder: expected {what}") from None
    except OSError as exc:
        try:  # a socket cannot be opened at all: say what it is
            mode = os.stat(path).st_mode
        except OSError:
            mode = stat.S_IFREG
        kind = next((name for test, name in _FILE_TYPES if test(mode)), None)
        if kind is not None:
            raise InputError(where, f"is {kind}: expected {what}, a regular file") from None
        raise InputError(where, f"{unreadable} ({exc.strerror or exc})") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            kind = next((name for test, name in _FILE_TYPES if test(st.st_mode)), "not a regular file")
            raise InputError(where, f"is {kind}: expected {what}, a regular file")
        if st.st_size > limit:
            raise InputError(where, f"is {st.st_size:,} bytes: expected {what} of at most {limit:,} bytes")
        os.set_blocking(fd, True)
        chunks, size = [], 0
        while size <= limit:
            chunk = os.read(fd, min(1 << 20, limit + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        if size > limit:  # it grew while being read
            raise InputError(where, f"is more than {limit:,} bytes: expected {what} of at most {limit:,} bytes")
        return b"".join(chunks)
    except OSError as exc:
        raise InputError(where, f"{unreadable} ({exc.strerror or exc})") from None
    finally:
        os.close(fd)


def decode_text(data: bytes, where: str, what: str, max_line: int | None = MAX_LINE) -> str:
    """UTF-8 text (a leading byte-order mark dropped) without NUL bytes and, with ``max_line``, without a line
    longer than that; every other encoding (UTF-16, with or without its mark, Latin-1 …) is named and refused."""
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise InputError(where, f"not a UTF-8 text file: UTF-16 (it starts with a UTF-16 byte-order mark); "
                                f"expected {what} in UTF-8 (save it as UTF-8)")
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    nul = data.find(b"\0")
    if nul >= 0:
        head = data[:64]
        if len(head) >= 4 and (head[1::2].count(0) >= len(head) // 4 or head[0::2].count(0) >= len(head) // 4):
            raise InputError(where, f"not a UTF-8 text file: UTF-16 without a byte-order mark (every other byte "
                                    f"is 0); expected {what} in UTF-8 (save it as UTF-8)")
        line = data.count(b"\n", 0, nul) + 1
        raise InputError(f"{where}:{line}", f"not a UTF-8 text file: a NUL byte (byte {nul + 1} of the file); "
                                            f"expected {what}, UTF-8 text (a binary file?)")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        byte = data[exc.start]
        raise InputError(f"{where}:{line}", f"not a UTF-8 text file: byte 0x{byte:02X} (byte {exc.start + 1} of "
                                            f"the file) is not UTF-8; expected {what} in UTF-8 (Latin-1 or "
                                            "Windows-1252? save it as UTF-8)") from None
    if max_line is not None:
        for i, ln in enumerate(text.split("\n")):
            if len(ln) > max_line:
                raise InputError(f"{where}:{i + 1}", f"a line of {len(ln):,} characters: expected {what} with "
                                                     f"lines of at most {max_line:,} characters")
    return text

_FRACTION = re.compile(r"^\s*([+-]?\d+)\s*/\s*(\d+)\s*$")


def parse_number(text: Any) -> tuple[float, bool] | None:
    """A float from a YAML scalar or string; also ``"7/12"`` fractions, and ``"0,02"`` (a decimal comma where it is
    the only reading: ``"1,000"`` may be 1000 or 1.0 and is None, as ``comma_problem`` tells). Returns (value,
    exact) or None."""
    if isinstance(text, bool) or text is None:
        return None
    try:  # an integer beyond a float (10**400), or of more digits than Python converts, is no number here
        if isinstance(text, int):
            return float(text), True
        if isinstance(text, float):
            return text, False
        if isinstance(text, str):
            m = _FRACTION.match(text)
            if m:
                den = int(m.group(2))
                return (float(Fraction(int(m.group(1)), den)), True) if den else None
            if "," in text:  # a decimal comma only where it is the one reading (0,02); 1,000 is not guessed at
                if [what for what, _ in comma_readings(text)] != ["a decimal comma"]:
                    return None
                text = text.replace(",", ".")
            return float(text.strip()), False
    except (ValueError, OverflowError):
        return None
    return None


_GROUPED = re.compile(r"[+-]?[1-9]\d{0,2}(?:,\d{3})+(?:\.\d*)?(?:[eE][+-]?\d+)?")  # 1,000 · 12,345.5 · 1,000e3
_DECIMAL_COMMA = re.compile(r"[+-]?\d+,\d+(?:[eE][+-]?\d+)?")  # 0,5 · 1,000 · 2,5e-3
_MANTISSA_DIGIT = re.compile(r"^[^eE]*[1-9]")  # a nonzero digit before the exponent, if any


def comma_readings(text: str) -> list[tuple[str, str]]:
    """The ways ``text`` reads as one number with a comma: (``"a thousands separator"``, the number without it)
    and (``"a decimal comma"``, the number with a point); ``1,000`` has both, ``0,5`` one, ``1,5,3`` none."""
    t = text.strip()
    readings = []
    if _GROUPED.fullmatch(t):
        readings.append(("a thousands separator", t.replace(",", "")))
    if _DECIMAL_COMMA.fullmatch(t):
        x = float(t.replace(",", "."))
        readings.append(("a decimal comma", repr(x) if math.isfinite(x) else t.replace(",", ".")))
    return readings


def comma_problem(text: str) -> str:
    """Why ``text``, given for one number, is refused for its comma: the readings it has (``comma_readings``),
    each written out, and what to write instead. resal never picks one: ``1,000`` is 1000 to one reader and 1.0
    to another."""
    readings = comma_readings(text)
    if len(readings) == 2:
        (a, x), (b, y) = readings
        return f"{a} ({x}) or {b} ({y})? write {x} or {y}"
    if readings:
        (what, x), = readings
        return f"{what}? write {x} ({'no separator' if 'thousands' in what else 'a decimal point'})"
    return "a comma separates only the x,y,z of a vector"


def printable(text: str) -> str:
    """``text`` on one line: every character that is not printable (a newline, a control character) escaped as
    Python writes it (``\\n``), so that a message quoting it stays one line."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def underflows(text: str, value: float) -> bool:
    """Whether the literal ``text``, read as ``value``, is nonzero but fell below the smallest normal double
    (2.2e-308): ``1e-400`` reads as 0, ``5e-324`` as a subnormal; either way no measurement in any unit, and the
    nonzero value written is lost (refused, as a subnormal is, never taken as 0)."""
    return abs(value) < sys.float_info.min and _MANTISSA_DIGIT.match(text.strip()) is not None


class Node:
    """A position in a parsed YAML document: reads typed values and remembers which keys were used."""

    def __init__(self, file: str, node: yaml.Node, path: str = "") -> None:
        self.file = file
        self.node = node
        self.path = path
        self._used: set[str] = set()

    # -- places -------------------------------------------------------------------------------------------
    def where(self, node: yaml.Node | None = None) -> str:
        n = node if node is not None else self.node
        return f"{self.file}:{n.start_mark.line + 1}"

    def _name(self, key: str) -> str:
        return f"{self.path}.{key}" if self.path else key

    def fail(self, message: str, node: yaml.Node | None = None) -> InputError:
        return InputError(self.where(node), message)

    # -- structure ----------------------------------------------------------------------------------------
    def _mapping(self) -> dict[str, yaml.Node]:
        if not isinstance(self.node, yaml.MappingNode):
            raise self.fail(f"'{self.path or 'document'}' must be a mapping of keys to values")
        out: dict[str, yaml.Node] = {}
        for k, v in self.node.value:
            if not isinstance(k, yaml.ScalarNode):
                raise self.fail("keys must be plain names", k)
            if k.value in out:
                raise self.fail(f"key '{self._name(k.value)}' appears twice", k)
            out[k.value] = v
        return out

    def has(self, key: str) -> bool:
        return key in self._mapping()

    def _get(self, key: str, expected: str) -> yaml.Node:
        m = self._mapping()
        if key not in m:
            raise self.fail(f"missing required key '{self._name(key)}' (expected {expected})")
        self._used.add(key)
        return m[key]

    def child(self, key: str, expected: str = "a mapping") -> Node:
        n = self._get(key, expected)
        if not isinstance(n, yaml.MappingNode):
            raise self.fail(f"'{self._name(key)}' must be {expected}", n)
        return Node(self.file, n, self._name(key))

    def children(self, key: str, expected: str = "a list of mappings") -> Iterator[Node]:
        n = self._get(key, expected)
        if not isinstance(n, yaml.SequenceNode):
            raise self.fail(f"'{self._name(key)}' must be {expected}", n)
        for i, item in enumerate(n.value):
            if not isinstance(item, yaml.MappingNode):
                raise self.fail(f"'{self._name(key)}[{i}]' must be a mapping", item)
            yield Node(self.file, item, f"{self._name(key)}[{i}]")

    def done(self) -> None:
        """Every key of this mapping must have been read: an unknown key is a typo or a misplaced value."""
        for key, _ in self._mapping().items():
            if key not in self._used:
                knode = next(k for k, _ in self.node.value if k.value == key)
                raise self.fail(f"unknown key '{self._name(key)}'", knode)

    # -- scalars ------------------------------------------------------------------------------------------
    def _scalar(self, key: str, expected: str) -> yaml.ScalarNode:
        n = self._get(key, expected)
        if not isinstance(n, yaml.ScalarNode):
            raise self.fail(f"'{self._name(key)}' must be {expected}", n)
        return n

    def string(self, key: str, default: str | None = None, choices: tuple[str, ...] | None = None,
               empty: bool = False) -> str:
        """A text (non-empty unless ``empty``), or one of ``choices``."""
        if default is not None and not self.has(key):
            return default
        expected = "a text" if choices is None else "one of " + ", ".join(choices)
        n = self._scalar(key, expected)
        value = n.value
        if choices is not None and value not in choices:
            raise self.fail(f"'{self._name(key)}' must be {expected}, got '{shorten(value)}'", n)
        if not value.strip() and not empty:
            raise self.fail(f"'{self._name(key)}' must be a non-empty text", n)
        return value

    def number_node(self, key: str, what: str = "a number") -> tuple[float, bool, str, yaml.ScalarNode]:
        """(value, exact, raw text, node) of a numeric scalar."""
        n = self._scalar(key, what)
        value = _construct(n, self.file, self._name(key))
        parsed = parse_number(value)
        if parsed is None and isinstance(value, str) and "," in value:
            raise self.fail(f"'{self._name(key)}' must be {what}, got '{shorten(n.value)}': {comma_problem(value)}", n)
        if parsed is None or not math.isfinite(parsed[0]):
            raise self.fail(f"'{self._name(key)}' must be {what}, got '{shorten(n.value)}'", n)
        return parsed[0], parsed[1], n.value, n

    def number(
        self, key: str, what: str = "a number", *, default: float | None = None, lo: float | None = None,
        hi: float | None = None, lo_open: bool = False, hi_open: bool = False,
    ) -> float:
        if default is not None and not self.has(key):
            return default
        value, _, raw, n = self.number_node(key, what)
        bad = (lo is not None and (value < lo or (lo_open and value == lo))) or (
            hi is not None and (value > hi or (hi_open and value == hi)))
        if bad:
            lo_s = "" if lo is None else ("(" if lo_open else "[") + f"{lo:g}"
            hi_s = "" if hi is None else f"{hi:g}" + (")" if hi_open else "]")
            rng = f"in {lo_s}, {hi_s}" if lo is not None and hi is not None else (
                f"{'>' if lo_open else '≥'} {lo:g}" if lo is not None else f"{'<' if hi_open else '≤'} {hi:g}")
            raise self.fail(f"'{self._name(key)}' must be {what} {rng}, got {shorten(raw)}", n)
        return value

    def integer(self, key: str, what: str = "an integer", *, default: int | None = None, lo: int = 0,
                hi: int | None = None) -> int:
        """A whole number in [lo, hi]; ``1e3`` (which PyYAML reads as a text) is accepted as 1000. Every count that
        sizes work (trials, imprints, repetitions) has an ``hi``, so that a typo cannot make a run hang."""
        if default is not None and not self.has(key):
            return default
        n = self._scalar(key, what)
        value = _construct(n, self.file, self._name(key))
        rng = f"≥ {lo}" if hi is None else f"in [{lo}, {hi}]"
        if not isinstance(value, int) or isinstance(value, bool):
            parsed = parse_number(value) if isinstance(value, str | float) else None
            if parsed is None or not math.isfinite(parsed[0]) or parsed[0] != int(parsed[0]):
                raise self.fail(f"'{self._name(key)}' must be {what}, a whole number {rng}, "
                                f"got '{shorten(n.value)}'", n)
            value = int(parsed[0])
        if value < lo or (hi is not None and value > hi):
            raise self.fail(f"'{self._name(key)}' must be {what} {rng}, got {shorten(n.value)}", n)
        return value

    def boolean(self, key: str, default: bool) -> bool:
        if not self.has(key):
            return default
        n = self._scalar(key, "true or false")
        value = _construct(n, self.file, self._name(key))
        if not isinstance(value, bool):
            raise self.fail(f"'{self._name(key)}' must be true or false, got '{shorten(n.value)}'", n)
        return value

    def number_list(self, key: str, what: str = "numbers") -> tuple[float, ...]:
        n = self._get(key, f"a list of {what}")
        if not isinstance(n, yaml.SequenceNode) or not n.value:
            raise self.fail(f"'{self._name(key)}' must be a non-empty list of {what}", n)
        out = []
        for item in n.value:
            value = _construct(item, self.file, self._name(key)) if isinstance(item, yaml.ScalarNode) else None
            parsed = parse_number(value)
            if parsed is None or not math.isfinite(parsed[0]):
                raise self.fail(f"'{self._name(key)}' must be a list of {what}, "
                                f"got '{shorten(getattr(item, 'value', ''))}'", item)
            out.append(parsed[0])
        return tuple(out)

    def string_list(self, key: str, default: tuple[str, ...] = ()) -> tuple[str, ...]:
        if not self.has(key):
            return default
        n = self._get(key, "a list of texts")
        if not isinstance(n, yaml.SequenceNode) or not all(isinstance(i, yaml.ScalarNode) for i in n.value):
            raise self.fail(f"'{self._name(key)}' must be a list of texts", n)
        return tuple(i.value for i in n.value)


def _construct(n: yaml.ScalarNode, file: str, name: str) -> Any:
    """The Python value of a scalar; a value PyYAML cannot build (a bad date, a bad tag) is an input error."""
    try:
        return yaml.SafeLoader("").construct_object(n, deep=True)
    except (yaml.YAMLError, ValueError, TypeError, OverflowError) as exc:
        why = exc.problem if isinstance(exc, yaml.MarkedYAMLError) and exc.problem else str(exc)
        if "integer string conversion" in why:  # Python reads at most 4300 digits (sys.get_int_max_str_digits)
            digits = sum(c.isdigit() for c in n.value)
            why = f"an integer of {digits:,} digits, expected a number of at most {_MAX_DIGITS:,} digits"
        tag = "" if n.tag.startswith("tag:yaml.org,2002:") else f" {n.tag}"
        raise InputError(f"{file}:{n.start_mark.line + 1}",
                         f"'{name}' cannot be read from '{tag.strip()}{' ' if tag else ''}{shorten(n.value)}': "
                         f"{why}") from None


_MAX_DIGITS = 4300  # Python's default limit on the digits of an integer read from text


def shorten(value: Any, width: int = 40) -> str:
    """A value as a message quotes it: whole when short, else its start and its length."""
    text = str(value)
    return text if len(text) <= width else f"{text[:width - 10]}… ({len(text):,} characters)"


@dataclass(frozen=True)
class Source:
    section: str
    page: int | None
    equations: tuple[str, ...]


@dataclass(frozen=True)
class Printed:
    """A value printed in the paper, to be compared with what resal computes (never used as an input)."""

    id: str
    computed: str  # which computed quantity it is compared with
    quantity: str
    source: str
    value: float | None
    text: str
    tolerance: float | None
    tolerance_rule: str
    where: str
    formula: bool = False  # a printed formula: ``computed`` is then its largest discrepancy from the reference
    line: int | None = None  # the line of the digitised text (../shared/paper/resal-1883.md) that holds the claim
    reason: str | None = None  # why the claim as printed differs (a code of REASONS); None: it is reproduced
    today: str | None = None  # a symbol of the modern values standing beside the claim
    english: str | None = None  # the project's English rendering of ``text``; None where ``text`` is ""


# why a claim as printed differs from what its premises give: the codes a `reason:` may take
REASONS = {
    "rounding": "the printed digits round a value that the premises give more precisely",
    "ocr": "a slip of the digitised text (the row's note gives the likely original)",
    "erratum": "a slip of the 1883 original (the row's note gives the corrected value, derived)",
    "assumption": "an assumption of the paper's that its own premises or the exact mechanics do not support",
    "repair": "the printed formula is wrong as it stands; a second row grades the repaired form",
    "beyond": "the claim fails beyond the domain where the paper applies it (a row `<id>_beyond`); the in-domain row "
              "`<id>` stands beside it",
}

# whose error a differing row shows (issue 35): the groups every total is split into, in this order. A reader must
# not read "N differ" as "Résal was wrong N times": the digitised text's slips are not the paper's, the digits it
# rounds are no error, and what fails beyond the paper's domain is counted apart from the paper's claims.
REASON_GROUPS = {
    "paper": ("erratum", "repair"),  # Résal's own slips and formulas that cannot be right as printed
    "premise": ("assumption",),  # premises that fail where the paper applies them
    "rounding": ("rounding",),  # printed digits that round or truncate the value the premises give
    "digitised": ("ocr",),  # slips of the digitised text, not of the 1883 original
    "beyond": ("beyond",),  # beyond the paper's domain: counted apart from the paper's totals
}
REASON_GROUP_LABELS = {
    "paper": "Résal's errata and formulas that cannot be right",
    "premise": "premises that fail where the paper applies them",
    "rounding": "printed digits rounded or truncated",
    "digitised": "slips of the digitised text, not of 1883",
    "beyond": "beyond the paper's domain",
}
BEYOND_SUFFIX = "_beyond"  # the id of a row grading a claim beyond the paper's domain
BEYOND_QUANTITY = "beyond the paper's domain"  # how its quantity starts


def reason_group(reason: str | None) -> str | None:
    """The group of ``REASON_GROUPS`` a reason code belongs to (None for a row without reason)."""
    return next((g for g, codes in REASON_GROUPS.items() if reason in codes), None)


# the verdict of a measured value against what the paper's mechanics predict (never a printed claim's verdict:
# the two are counted apart). consistent/inconsistent: at 95 %, the measurement's uncertainty and the prediction's
# interval both counted; fitted: the measurement fixed a parameter, so it tests nothing; not-checkable: no prediction
MEASUREMENT_VERDICTS = ("consistent", "inconsistent", "fitted", "not-checkable")


@dataclass(frozen=True)
class Measured:
    """A published measurement that the experiment's kind predicts from the paper's mechanics; the measured value
    itself is read from the experiment's data file (never from this entry), and its verdict is one of
    ``MEASUREMENT_VERDICTS``."""

    id: str
    computed: str  # which of the kind's comparisons it is
    quantity: str
    source: str  # the article (and its table or figure)
    unit: str
    where: str
    note: str = ""


# what a finding of the reader's edition says about the paper: the codes a `category:` may take
FINDINGS = {
    "erratum": "a slip of the 1883 original",
    "formula": "a printed formula that cannot be right as it stands",
    "premise": "a premise that fails where the paper applies it",
    "beyond": "what the mechanics show that the paper does not say",
    "holds": "what Résal got right",
    "measured": "what today's measurements say of the paper's mechanics",
}


@dataclass(frozen=True)
class Finding:
    """One sentence for the reader's edition, with the rows (and optionally the figure) that carry it."""

    id: str
    category: str  # a code of FINDINGS
    consequence: int  # 1 (a detail) … 5 (changes what the paper teaches): the first screen ranks by it
    text: str
    rows: tuple[str, ...]  # printed (or measured) ids of the same experiment
    figure: str | None  # a figure name of the experiment (without extension)
    where: str


@dataclass(frozen=True)
class Experiment:
    id: str
    kind: str
    title: str
    source: Source
    printed: tuple[Printed, ...]
    params: Any
    seed: int
    modern: tuple[str, ...]
    path: str
    sha256: str
    notes: tuple[str, ...] = field(default=())
    question: str = ""  # the question the experiment answers, for the reader's edition
    findings: tuple[Finding, ...] = field(default=())
    measured: tuple[Measured, ...] = field(default=())  # published measurements against the paper's mechanics


def _finding(node: Node, printed_ids: set[str]) -> Finding:
    fid = node.string("id")
    category = node.string("category", choices=tuple(FINDINGS))
    consequence = node.integer("consequence", "an integer from 1 (a detail) to 5 (changes what the paper teaches)",
                               lo=1)
    if consequence > 5:
        raise node.fail(f"'{node.path}.consequence' must be from 1 to 5, got {consequence}",
                        node._mapping()["consequence"])
    text = node.string("text")
    rows = node.string_list("rows")
    if not rows:
        raise node.fail(f"'{node.path}.rows' must name at least one printed id that carries the finding")
    unknown = [r for r in rows if r not in printed_ids]
    if unknown:
        raise node.fail(f"'{node.path}.rows' names {', '.join(unknown)}, which are not printed or measured ids of "
                        "this file",
                        node._mapping()["rows"])
    figure = node.string("figure") if node.has("figure") else None
    node.done()
    return Finding(fid, category, consequence, text, rows, figure, node.where())


def _id_computed(node: Node, quantities: tuple[str, ...], what: str) -> tuple[str, str]:
    """An entry's id and the kind's ``what`` it names (``computed:``, by default its id), refused at its line when
    the kind computes no such thing."""
    eid = node.string("id")
    computed = node.string("computed", default=eid)
    if computed not in quantities:
        at = node._mapping().get("computed", node.node)
        raise node.fail(f"'{node.path}.computed' names no {what} this kind computes: '{computed}' "
                        f"(expected one of {', '.join(quantities)})", at)
    return eid, computed


def _measured(node: Node, quantities: tuple[str, ...]) -> Measured:
    mid, computed = _id_computed(node, quantities, "comparison")
    out = Measured(mid, computed, node.string("quantity"), node.string("source"), node.string("unit", default=""),
                   node.where(), node.string("note", default=""))
    node.done()
    return out


def _tolerance(value: float, exact: bool, raw: str) -> tuple[float, str]:
    """Relative tolerance allowed by the printed digits: half a unit of the last printed digit."""
    if exact:
        return 1e-9, "exact fraction: 1e-9"
    text = raw.strip().replace(",", ".").lstrip("+-")
    mantissa = re.split(r"[eE]", text)[0]
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    exponent = int(re.split(r"[eE]", text)[1]) if re.search(r"[eE]", text) else 0
    half_unit = 0.5 * 10.0 ** (exponent - decimals)
    return half_unit / abs(value) if value else half_unit, f"half a unit of the last printed digit ({half_unit:g})"


def _printed(node: Node, quantities: tuple[str, ...]) -> Printed:
    pid, computed = _id_computed(node, quantities, "quantity")
    quantity = node.string("quantity")
    source = node.string("source")
    text = node.string("text", empty=True)  # "": the paper prints nothing for it (an implicit premise, our repair)
    english = _english(node, pid, text)
    if node.has("value") and _construct(node._mapping()["value"], node.file, f"{node.path}.value") is not None:
        value, exact, raw, _ = node.number_node("value", "a number or a fraction such as 4/15")
        try:
            tol, rule = _tolerance(value, exact, raw)
        except OverflowError:  # 0e400: a zero whose printed exponent no tolerance can follow
            raise node.fail(f"'{node.path}.value' {shorten(raw)}: expected a number as the paper prints it (an "
                            "exponent within ±300)", node._mapping()["value"]) from None
    else:
        node._used.add("value")
        value, tol, rule = None, None, "no printed number"
    formula = node.boolean("formula", default=False)
    if formula and (value is not None or not node.has("tolerance")):
        raise node.fail(f"'{node.path}' is a formula: it takes no 'value' and needs a 'tolerance' on the "
                        "discrepancy, with its 'tolerance_rule'")
    if node.has("tolerance"):
        tol = node.number("tolerance", "a relative tolerance", lo=0.0, lo_open=True)
        rule = node.string("tolerance_rule")
    line = node.integer("line", "a line number of the digitised text", default=None, lo=1) if node.has(
        "line") else None
    reason = node.string("reason", choices=tuple(REASONS)) if node.has("reason") else None
    today = node.string("today") if node.has("today") else None
    beyond_id, beyond_quantity = pid.endswith(BEYOND_SUFFIX), quantity.startswith(BEYOND_QUANTITY)
    if beyond_id != beyond_quantity:
        raise node.fail(f"'{node.path}': a row grading a claim beyond the paper's domain has an id ending in "
                        f"'{BEYOND_SUFFIX}' and a quantity starting « {BEYOND_QUANTITY} », both or neither (id "
                        f"'{pid}')")
    if reason is not None and (reason == "beyond") != beyond_id:
        raise node.fail(f"'{node.path}.reason' {reason}: the reason 'beyond' is the reason of a row beyond the "
                        f"paper's domain (id ending in '{BEYOND_SUFFIX}'), and such a row has no other",
                        node._mapping()["reason"])
    node.done()
    return Printed(pid, computed, quantity, source, value, text, tol, rule, node.where(), formula, line, reason,
                   today, english)


def _english(node: Node, pid: str, text: str) -> str | None:
    """A printed row's ``english``: the project's rendering of its ``text`` (formulas as printed, the words
    translated), required where the text quotes the paper and refused where the paper prints nothing."""
    if text.strip():
        if not node.has("english"):
            raise node.fail(f"missing required key '{node.path}.english' (row '{pid}': expected an English rendering "
                            "of its 'text', a non-empty text: the French words translated, formulas as printed)")
        english = node.string("english", empty=True)
        if not english.strip():
            raise node.fail(f"'{node.path}.english' is empty (row '{pid}'): expected an English rendering of its "
                            "'text', a non-empty text", node._mapping()["english"])
        return english
    if node.has("english"):
        raise node.fail(f"'{node.path}.english' without a 'text' (row '{pid}'): a row whose 'text' is \"\" quotes "
                        "nothing, so it has no English rendering; expected no 'english' key",
                        node._mapping()["english"])
    return None


class Kind(Protocol):
    """What an experiment kind offers the loader: its schema (``parse``), the quantities it computes and the
    modern values it can stand beside. ``reproductions.experiments.KINDS`` maps names to such modules."""

    MODERN: tuple[str, ...]

    def parse(self, node: Node, base: Path) -> Any: ...


def _check_structure(text: str, file: str, loader: type = yaml.SafeLoader) -> None:
    """Refuse a document nested deeper than ``MAX_DEPTH`` or holding more than ``MAX_NODES`` values once its aliases
    are expanded (a "billion laughs" of nested aliases is a few lines long), reading the parser's events: the
    parser keeps no recursion, and an alias is counted by the size of its anchor, not expanded."""
    sizes: dict[str, int] = {}
    stack: list[tuple[str | None, int]] = []
    total = 0
    for ev in yaml.parse(text, Loader=loader):
        if isinstance(ev, yaml.AliasEvent):
            total += sizes.get(ev.anchor, 1)
        elif isinstance(ev, yaml.ScalarEvent):
            total += 1
            if ev.anchor:
                sizes[ev.anchor] = 1
        elif isinstance(ev, yaml.CollectionStartEvent):
            total += 1
            stack.append((ev.anchor, total))
            if len(stack) > MAX_DEPTH:
                raise InputError(f"{file}:{ev.start_mark.line + 1}", f"nested more than {MAX_DEPTH} levels deep: "
                                                                     f"expected an experiment file of at most "
                                                                     f"{MAX_DEPTH} levels of mappings and lists")
        elif isinstance(ev, yaml.CollectionEndEvent) and stack:
            anchor, start = stack.pop()
            if anchor:
                sizes[anchor] = total - start + 1
        if total > MAX_NODES:
            raise InputError(f"{file}:{ev.start_mark.line + 1}", f"more than {MAX_NODES:,} values once its aliases "
                                                                 "are expanded (an alias bomb?): expected an "
                                                                 "experiment file of plain values")


_FAST_LOADER = getattr(yaml, "CSafeLoader", None)  # libyaml's parser, when PyYAML was built with it


def _compose(text: str, file: str) -> Any:
    """The document's node tree, its depth and aliases checked first on the parser's events (before the recursive
    composer). By libyaml's parser where PyYAML has it (ten times faster); a document it refuses is read again by
    PyYAML's own, so that what a malformed file is told does not depend on how PyYAML was built."""
    if _FAST_LOADER is not None:
        try:
            _check_structure(text, file, _FAST_LOADER)
            return yaml.compose(text, Loader=_FAST_LOADER)
        except yaml.YAMLError:
            pass
    _check_structure(text, file)
    return yaml.compose(text, Loader=yaml.SafeLoader)


def load_experiment(path: str | Path, kinds: Mapping[str, Any]) -> Experiment:
    """Read and validate one experiment file of one of ``kinds`` (name → ``Kind``); raises ``InputError`` naming
    file:line on any problem. The kinds are handed in, so that configuration never imports the experiments."""
    KINDS = kinds
    p = Path(path)
    file = str(path)
    raw = read_input(p, "an experiment file (YAML)", MAX_YAML_BYTES, "cannot read the experiment file")
    text = decode_text(raw, file, "an experiment file (YAML)")
    try:
        doc = _compose(text, file)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark else 1
        message = f"malformed YAML: {exc.problem or exc.context}"
        if exc.problem and exc.context and exc.context_mark and exc.context_mark.line + 1 != line:
            message += f" ({exc.context} started at line {exc.context_mark.line + 1})"
        lines = text.split("\n")
        if "expected ':'" in message and line <= len(lines) and len(lines[line - 1]) > 1024:
            message += " (expected a key of at most 1024 characters)"  # YAML's bound on a plain key
        raise InputError(f"{file}:{line}", message) from None
    except yaml.YAMLError as exc:
        raise InputError(file, f"malformed YAML: {exc}") from None
    except RecursionError:  # not reached within MAX_DEPTH; kept so that no document ends in a traceback
        raise InputError(file, f"nested too deeply: expected at most {MAX_DEPTH} levels") from None
    if doc is None:
        raise InputError(f"{file}:1", "empty file (expected an experiment: id, kind, title, source, params, printed)")
    root = Node(file, doc)
    eid = root.string("id")
    if not re.fullmatch(r"[a-z0-9][a-z0-9-]*", eid):
        raise root.fail(f"'id' must be lower-case letters, digits and hyphens, got '{eid}'")
    if len(eid) > MAX_ID_CHARS:  # it names the results folder, and a staging folder's name carries it too
        raise root.fail(f"'id' is {len(eid)} characters, too long for a folder name (a file system allows 255 "
                        f"bytes, and resal's staging name adds its own): expected at most {MAX_ID_CHARS}, got "
                        f"'{shorten(eid)}'")
    kind = root.string("kind", choices=tuple(sorted(KINDS)))
    module = KINDS[kind]
    title = root.string("title")
    src = root.child("source", "a mapping with section, page, equations")
    source = Source(src.string("section"), src.integer("page", "a page number", default=0) or None,
                    src.string_list("equations"))
    src.done()
    seed = root.integer("seed", "a non-negative integer seed", default=0)
    modern = root.string_list("modern")
    unknown = [m for m in modern if m not in module.MODERN]
    if unknown:
        raise root.fail(f"'modern' lists {', '.join(unknown)}, which kind '{kind}' cannot compare "
                        f"(expected some of {', '.join(module.MODERN)})", root._mapping()["modern"])
    params = module.parse(root.child("params"), p.parent)
    quantities = module.quantities(params) if hasattr(module, "quantities") else module.QUANTITIES
    measured = tuple(_measured(n, quantities) for n in root.children("measured")) if root.has("measured") else ()
    printed = (tuple(_printed(n, quantities) for n in root.children("printed"))
               if root.has("printed") or not measured else ())  # an experiment of measurements alone may print none
    for x in printed:
        if x.today is not None and x.today not in modern:
            raise InputError(x.where, f"'today' names '{x.today}', which is not in this file's 'modern' list "
                                      f"({', '.join(modern) or 'empty'}): expected one of its symbols")
    seen: set[str] = set()
    for x in (*printed, *measured):
        if x.id in seen:
            what = "printed ids" if isinstance(x, Printed) else "printed and measured ids"
            raise InputError(x.where, f"{what} must be unique; repeated: {x.id}")
        seen.add(x.id)
    notes = root.string_list("notes")
    question = root.string("question", default="")
    findings = tuple(_finding(n, seen) for n in root.children("findings")) if root.has("findings") else ()
    fids = [f.id for f in findings]
    if len(set(fids)) != len(fids):
        raise root.fail(f"finding ids must be unique; repeated: {sorted({f for f in fids if fids.count(f) > 1})}")
    root.done()
    return Experiment(eid, kind, title, source, printed, params, seed, modern, file,
                      hashlib.sha256(raw).hexdigest(), notes, question, findings, measured)
