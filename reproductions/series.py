"""Measurement series from CSV files (a user's own data), read with a clear message for every bad row."""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .config import comma_problem, comma_readings, decode_text, read_input, shorten, underflows
from .errors import InputError

__all__ = ["MAX_IMPRINTS", "MAX_MARKERS", "MIN_IMPRINTS", "MIN_MARKERS", "UNITS", "Markers", "Series", "Table",
           "as_table", "check_imprints", "check_pendulum_trials", "header_names", "read_imprints", "read_markers",
           "read_rebounds", "read_series", "read_table", "si_unit", "table_from_columns", "unit_label"]

MAX_CSV_BYTES = 16 << 20  # 16 MiB: a series of 10⁵ rows (a ball-ball table of 10⁵ shots at full precision is 5–7 MB);
# a larger file is refused before it is parsed
MIN_IMPRINTS = 5  # a ricochet series: fewer imprints cannot tell ν from the launch
MAX_IMPRINTS = 100  # Rozé counted up to 12; after 100 impacts at ν ≤ 0.8 a flight is 1e-10 of the first
MIN_MARKERS = 5  # angle markers per series: a fit of two parameters and a σ, and a slope, need a few more than three
MAX_MARKERS = 100_000  # a CSV file of 10⁵ markers is about 3 MB; fitted in the time of 2048 (``PSI_NODES``)
MAX_SPAN = 20.0  # m: the longest ricochet series taken as metres (a ball thrown onto a slab, not a field)
MAX_SPEED = 50.0  # m/s: the fastest launch the ricochet fits admit (fitting.PHYSICAL_BOUNDS)
MOMENTUM_SIGMAS = 5.0  # a pendulum trial is refused when it breaks momentum by more than 5 σ of the imbalance
MOMENTUM_SLACK = 0.10  # without σ: by more than 10 % of M V0 (or V1 exceeds V1′ by more than 10 % of V0)

# a cell beyond these magnitudes is a typing or export slip whatever its unit (a fit would overflow on it)
MIN_MAGNITUDE, MAX_MAGNITUDE = 1e-12, 1e12

# Units a header may carry (``V0_mps``): per dimension, the SI unit first, then each unit's factor to SI.
UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "in": 0.0254, "ft": 0.3048},
    "speed": {"mps": 1.0, "cmps": 1e-2, "mmps": 1e-3, "kmph": 1 / 3.6, "fps": 0.3048, "ips": 0.0254},
    "time": {"s": 1.0, "ms": 1e-3, "us": 1e-6},
    "mass": {"kg": 1.0, "g": 1e-3},
    "angle": {"rad": 1.0, "deg": math.pi / 180},
    "ratio": {"1": 1.0},
}
UNIT_NAMES = {"mps": "m/s", "cmps": "cm/s", "mmps": "mm/s", "kmph": "km/h", "fps": "ft/s", "ips": "in/s",
              "um": "µm", "us": "µs", "1": "1"}


def si_unit(dim: str) -> str:
    """The SI unit of a dimension, as people write it (m/s, not mps)."""
    u = next(iter(UNITS[dim]))
    return UNIT_NAMES.get(u, u)


def unit_label(unit: str) -> str:
    return UNIT_NAMES.get(unit, unit)


def _parse_header(written: list[str], known: Sequence[str], dims: dict[str, str] | None,
                  where: str) -> tuple[list[str], dict[str, str | None]]:
    """Column names and units of a header: ``V0`` (no unit: SI) or, with ``dims``, ``V0_<unit>``."""
    names, units = [], {}
    for w in written:
        base, unit = w, None
        if dims is not None and w not in known and "_" in w and w.rsplit("_", 1)[0] in known:
            base, unit = w.rsplit("_", 1)
            dim = dims.get(base)
            if dim is None:
                raise InputError(where, f"column '{w}': '{base}' takes no unit (write '{base}')")
            if unit not in UNITS[dim]:
                raise InputError(where, f"column '{w}': unknown unit '{unit}' for a {dim} (expected one of "
                                        f"{', '.join(UNITS[dim])}, e.g. '{base}_{next(iter(UNITS[dim]))}')")
        if base in units:
            raise InputError(where, f"column '{w}': '{base}' appears twice in the header")
        names.append(base)
        units[base] = unit
    return names, units


def _no_empty_name(written: list[str], expected: Sequence[str], where: str) -> None:
    """A header without an empty column name (``V0,V1,``: a trailing comma, or ``V0,,V1``)."""
    if "" in written:
        j = written.index("")
        why = "a trailing comma?" if j == len(written) - 1 else "two commas in a row?"
        raise InputError(where, f"an empty column name, column #{j + 1} ({why}): expected the column names "
                                f"{', '.join(expected)}, separated by single commas")


def _factor(dims: dict[str, str] | None, name: str, unit: str | None) -> float:
    return 1.0 if unit is None or dims is None else UNITS[dims[name]][unit]


@dataclass(frozen=True)
class Table:
    """A series as read, before any column is interpreted: from a CSV file (``read_table``) or from a program's
    arrays (``table_from_columns``, the Python API), the one object every reader and check works on. Rows keep the
    line they came from; for arrays the header is line 1 and row i is line i + 2, named "data row i"."""

    where: str  # the file's path as given, or "data"
    name: str  # the file's name (a label's), or "data"
    head_line: int  # 0: no header (an empty file)
    head: str  # the header line as written
    header: list[str]
    rows: list[tuple[int, list[str]]]  # (line, cells stripped)
    arrays: bool = False

    def at(self, line: int) -> str:
        """A place in the series as a message names it: ``file:line``, or ``data header`` / ``data row i``."""
        if not self.arrays:
            return f"{self.where}:{line}"
        return f"{self.where} header" if line == self.head_line else f"{self.where} row {line - 2}"

    def span(self, lines: Sequence[int]) -> str:
        """'lines 7–9, 12' of a file; 'rows 5–7, 10' of arrays (their indices)."""
        if self.arrays:
            return f"rows {_runs([ln - 2 for ln in lines])}"
        return f"lines {_runs(list(lines))}"

    def named(self, lines: Sequence[int]) -> str:
        """'line(s) 7, 12' of a file; 'row(s) 5, 10' of arrays (their indices)."""
        if self.arrays:
            return f"row(s) {', '.join(str(ln - 2) for ln in lines)}"
        return f"line(s) {', '.join(map(str, lines))}"

    def shown(self, cell: str) -> str:
        """A cell quoted in a message: an array's NaN is its empty cell."""
        return "NaN" if self.arrays and not cell else shorten(cell)


def _runs(numbers: list[int]) -> str:
    """'7–9, 12': consecutive numbers as ranges."""
    out, start = [], None
    for i, ln in enumerate(numbers):
        if start is None:
            start = ln
        if i + 1 == len(numbers) or numbers[i + 1] != ln + 1:
            out.append(f"{start}" if start == ln else f"{start}–{ln}")
            start = None
    return ", ".join(out)


def read_table(path: Path) -> Table:
    """The rows of a CSV file: ``read_text``'s checks, lines that are empty or start with ``#`` skipped (before
    the header too), cells split as CSV and stripped."""
    text = read_text(path)
    numbered = [(i + 1, ln) for i, ln in enumerate(text.splitlines()) if ln.strip() and not ln.startswith("#")]
    if not numbered:
        return Table(str(path), path.name, 0, "", [], [])
    # line by line, as a person reads them: an unclosed quote is that row's mistake, never a field that runs on
    header = [h.strip() for h in next(csv.reader([numbered[0][1]]))]
    rows = [(n, [c.strip() for c in next(csv.reader([ln]))]) for n, ln in numbered[1:]]
    return Table(str(path), path.name, numbered[0][0], numbered[0][1], header, rows)


def table_from_columns(header: Sequence[str], columns: Sequence[Sequence[str]], where: str = "data") -> Table:
    """Arrays as a table: ``columns`` of cells as text, one list per header name, all of one length (a NaN is
    the empty cell: "not measured" where a kind allows it). The caller checks the names and the numbers."""
    n = len(columns[0]) if columns else 0
    rows = [(i + 2, [c[i] for c in columns]) for i in range(n)]
    return Table(where, where, 1, ",".join(header), list(header), rows, arrays=True)


def as_table(source: Path | Table) -> Table:
    return source if isinstance(source, Table) else read_table(Path(source))


class Series(dict):
    """Columns of a CSV series (name → array), with ``where`` (the file) and ``lines`` (each row's line)."""

    table: Table
    where: str
    lines: list[int]
    units: dict[str, str | None]  # per column: the unit written in the header, None when read as SI
    written: dict[str, str]  # per column: the header as written (``V0_mps``)
    factors: dict[str, float]  # per column: the factor that took its values to SI
    unit_text: dict[str, str]  # per column: its unit as people write it (cm/s; the SI unit when none was written)

    def at(self, row: int) -> str:
        return self.table.at(self.lines[row])


def read_series(source: Path | Table, columns: Sequence[str], optional: Sequence[str] = (), min_rows: int = 1,
                positive: Sequence[str] = (), dims: dict[str, str] | None = None,
                nonnegative: Sequence[str] = (), blank: Sequence[str] = (), labels: Sequence[str] = ()) -> Series:
    """A measurement series from a CSV file with a header, or a ``Table`` of arrays; every bad row is reported as
    file:line (data row i). Lines that are empty or start with ``#`` are skipped (before the header too); a UTF-8
    byte-order mark is accepted.

    With ``dims`` (column → dimension, a key of ``UNITS``) a header may carry a unit, ``V0_mps``, ``h0_mm``,
    ``t_ms``: the values are converted to SI and ``units`` records, per column, the unit as written (None: no
    unit, read in SI). A unit unknown, or of another dimension, is refused at the header.

    In the columns named in ``blank`` an empty cell means "not measured" and is read as NaN (never 0); in the
    others it is refused like any cell that is not a number. The optional columns named in ``labels`` hold text
    (a shot's id), kept as written, never read as numbers."""
    tab = as_table(source)
    where = tab.where
    if not tab.head_line:
        raise InputError(where, f"empty series (expected a header with columns {', '.join(columns)})")
    head_line, head, written = tab.head_line, tab.head, tab.header
    if len(written) == 1 and len(columns) + len(optional) > 1:
        for sep, name in ((";", "semicolons"), ("\t", "tabs")):
            if sep in head:
                raise InputError(tab.at(head_line), f"the header is separated by {name}: expected commas "
                                                    f"(as {','.join(p.strip() for p in head.split(sep))}), "
                                                    "and in every row")
    optional = [*optional, *labels]
    _no_empty_name(written, [*columns, *optional], tab.at(head_line))
    header, units = _parse_header(written, [*columns, *optional], dims, tab.at(head_line))
    missing = [c for c in columns if c not in header]
    if missing:
        raise InputError(tab.at(head_line), f"missing column(s) {', '.join(missing)} in the header "
                                                 f"(expected {', '.join(columns)})")
    unknown = [w for h, w in zip(header, written, strict=True) if h not in columns and h not in optional]
    if unknown:
        raise InputError(tab.at(head_line), f"unknown column(s) {', '.join(unknown)} "
                                                 f"(expected {', '.join([*columns, *optional])})")
    data: dict[str, list[Any]] = {h: [] for h in header}
    for line_no, cells in tab.rows:
        if len(header) == 1 and len(cells) == 2 and comma_readings(",".join(cells)):  # 0,512: a decimal comma
            raise InputError(tab.at(line_no), f"column '{written[0]}': expected one number, got "
                                                   f"'{shorten(','.join(cells))}': {comma_problem(','.join(cells))}")
        if len(cells) != len(header):
            trailing = " (the last one empty: a trailing comma?)" if len(cells) > len(header) and not cells[-1] else ""
            raise InputError(tab.at(line_no), f"expected {len(header)} values, got {len(cells)}{trailing}")
        for j, (h, w, cell) in enumerate(zip(header, written, cells, strict=True)):
            col = f"column '{w}' (#{j + 1})" if len(header) > 1 else f"column '{w}'"
            shown = tab.shown(cell)  # a cell of a thousand digits is quoted by its start and its length
            if h in labels:
                data[h].append(cell)
                continue
            if not cell and h in blank:
                data[h].append(math.nan)
                continue
            if "," in cell:  # a quoted cell, "1,000": never read as 1 or 1000 by a guess
                raise InputError(tab.at(line_no), f"{col}: expected one number, got '{shown}': "
                                                       f"{comma_problem(cell)}")
            try:
                v = float(cell)
            except ValueError:
                empty = " or an empty cell (not measured)" if h in blank else ""
                raise InputError(tab.at(line_no), f"{col}: expected a number{empty}, got '{shown}'") from None
            if not math.isfinite(v):
                raise InputError(tab.at(line_no), f"{col}: expected a finite number, got '{shown}'")
            if (v != 0 or underflows(cell, v)) and not MIN_MAGNITUDE <= abs(v) <= MAX_MAGNITUDE:
                zero = " (it underflows to 0 in floating point)" if v == 0 else ""
                raise InputError(tab.at(line_no), f"{col}: {shown} is no measurement in any unit{zero}: expected "
                                                       f"a magnitude between {MIN_MAGNITUDE:g} and {MAX_MAGNITUDE:g} "
                                                       "(or 0)")
            if h in positive and v <= 0:
                raise InputError(tab.at(line_no), f"{col}: expected a positive number, got '{shown}'")
            if h in nonnegative and v < 0:
                raise InputError(tab.at(line_no), f"{col}: expected a number ≥ 0, got '{shown}'")
            data[h].append(v * _factor(dims, h, units[h]))
    if len(tab.rows) < min_rows:
        raise InputError(where, f"expected at least {min_rows} data row(s), got {len(tab.rows)}")
    out = Series({h: np.asarray(v) for h, v in data.items()})
    out.table, out.where, out.lines = tab, where, [n for n, _ in tab.rows]
    out.units, out.written = units, dict(zip(header, written, strict=True))
    out.factors = {h: _factor(dims, h, units[h]) for h in header}
    out.unit_text = {h: unit_label(units[h]) if units[h] is not None else
                     (si_unit(dims[h]) if dims and h in dims else "1") for h in header}
    return out


def read_text(path: Path) -> str:
    """A series file's text: a regular file of at most ``MAX_CSV_BYTES``, UTF-8 (a byte-order mark dropped), no NUL
    byte, no line longer than ``config.MAX_LINE``; anything else is refused with the file (and line) named."""
    data = read_input(path, "a CSV file", MAX_CSV_BYTES, "cannot read the series file")
    return decode_text(data, str(path), "a CSV file")


def header_names(source: Path | Table, known: Collection[str] = ()) -> tuple[int, set[str]]:
    """The header's line and its column names without their units (``V0_mps`` → ``V0``, ``obj_dir_deg`` →
    ``obj_dir``; ``cue_speed`` kept: a suffix is a known unit, or follows a ``known`` column name, so that
    ``V0_furlong`` is V0 with a unit ``read_series`` then refuses), to tell which set of columns a file holds;
    (0, ∅) when the file cannot be read (``read_series`` then says why)."""
    try:
        tab = as_table(source)
    except InputError:
        return 0, set()
    return tab.head_line, {_without_unit(h, known) for h in tab.header if h}


def _without_unit(name: str, known: Collection[str]) -> str:
    base, _, unit = name.rpartition("_")
    if name in known or not base:
        return name
    return base if base in known or any(unit in units for units in UNITS.values()) else name


def read_rebounds(source: Path | Table, heights: bool) -> Series:
    """Rebounds on an immovable mass (§I eq. (9)): columns ``V0,V1`` (signed velocities, m/s: V0 > 0 towards the
    mass, V1 ≤ 0 after the impact, away from it) or ``h0,h1`` (drop and rebound heights, m). A rebound faster or
    higher than the impact would need ε < 0; a positive V1 is a speed given without its sign. Both are refused."""
    cols = ("h0", "h1") if heights else ("V0", "V1")
    s = read_series(source, cols, min_rows=2, positive=(cols[0],))
    a, b = s[cols[0]], s[cols[1]]
    for i in range(a.size):
        if heights and b[i] < 0:
            raise InputError(s.at(i), f"column 'h1': expected a rebound height ≥ 0 (m, measured up from the "
                                      f"surface), got {b[i]:g}")
        if heights and b[i] > a[i]:
            raise InputError(s.at(i), f"the rebound h1 = {b[i]:g} m is higher than the drop h0 = {a[i]:g} m: "
                                      "expected h1 ≤ h0 (a ball cannot gain energy in the impact; ε ≥ 0)")
        if not heights and b[i] > 0:
            raise InputError(s.at(i), f"column 'V1': expected the signed velocity after the impact, ≤ 0 (opposite "
                                      f"V0 = {a[i]:g}), got {b[i]:g}; the file must give signed velocities, so "
                                      "write a rebound speed u as V1 = -u")
        if not heights and -b[i] > a[i]:
            raise InputError(s.at(i), f"the ball leaves at |V1| = {-b[i]:g} m/s, faster than it arrived "
                                      f"(V0 = {a[i]:g}): expected |V1| ≤ V0 (ε ≥ 0)")
    return s


def check_pendulum_trials(s: Series, M: np.ndarray, Mp: np.ndarray, sigma: float | None) -> None:
    """Two-pendulum trials (§I eqs (8), struck body at rest) that no (ε, ε′) can describe are refused: eqs (8)
    conserve momentum, M V0 = M V1 + M′ V1′, and keep the bodies apart, V1 ≤ V1′. A trial may break either by
    its noise: with σ given (each velocity's standard deviation), by ``MOMENTUM_SIGMAS`` σ of the imbalance,
    σ √(2M² + M′²), and of V1 − V1′, σ √2; without σ, by ``MOMENTUM_SLACK`` of M V0 and of V0."""
    V0, V1, V1p = s["V0"], s["V1"], s["V1p"]
    for i in range(V0.size):
        m, mp = float(M[i]), float(Mp[i])
        imbalance = m * V0[i] - m * V1[i] - mp * V1p[i]
        if sigma is not None:
            tol_p = MOMENTUM_SIGMAS * sigma * math.sqrt(2 * m * m + mp * mp)
            tol_v = MOMENTUM_SIGMAS * sigma * math.sqrt(2.0)
            allowed = allowed_v = f"{MOMENTUM_SIGMAS:g} σ of the noise, σ = {sigma:g}"
        else:
            tol_p, tol_v = MOMENTUM_SLACK * m * V0[i], MOMENTUM_SLACK * V0[i]
            allowed = f"{MOMENTUM_SLACK:.0%} of M V0 (give --sigma to judge by the noise)"
            allowed_v = f"{MOMENTUM_SLACK:.0%} of V0"
        if abs(imbalance) > tol_p:
            raise InputError(s.at(i), f"the trial breaks momentum: M V0 − M V1 − M′ V1p = {imbalance:.4g} kg·m/s "
                                      f"(M = {m:g}, M′ = {mp:g}), beyond {allowed}; expected M V0 = M V1 + M′ V1p "
                                      "(signed velocities in m/s; are the masses right, or the columns V1 and V1p "
                                      "swapped?)")
        if V1[i] - V1p[i] > tol_v:
            raise InputError(s.at(i), f"V1 = {V1[i]:g} exceeds V1p = {V1p[i]:g}: the striking body would pass "
                                      f"through the struck one; expected V1 ≤ V1p (it exceeds it by more than "
                                      f"{allowed_v})")


def check_imprints(x: np.ndarray, where: str, t: np.ndarray | None = None, row: Callable[[int], str] | None = None,
                   unit: str | None = None) -> None:
    """A ricochet series: ``MIN_IMPRINTS`` to ``MAX_IMPRINTS`` imprints, strictly increasing, in metres (spanning
    at most ``MAX_SPAN``), and with instants (seconds) that increase and give a launch of at most ``MAX_SPEED``.
    ``row`` (imprint index → its place, ``Series.at``) lets a bad imprint be named as file:line; ``unit``: the
    unit the header gave x (None: metres), for the advice on a span too long."""

    def at(i: int) -> str:
        return row(i) if row is not None else where

    if x.size < MIN_IMPRINTS:
        raise InputError(where, f"expected at least {MIN_IMPRINTS} imprints, got {x.size}")
    if x.size > MAX_IMPRINTS:
        raise InputError(where, f"expected at most {MAX_IMPRINTS} imprints, got {x.size}")
    bad = np.nonzero(np.diff(x) <= 0)[0]
    if bad.size:
        raise InputError(at(bad[0] + 1), f"imprint positions must increase; imprint {bad[0] + 2} is not beyond "
                                         f"imprint {bad[0] + 1} ({x[bad[0] + 1]:g} ≤ {x[bad[0]]:g})")
    span = float(x[-1] - x[0])
    if span > MAX_SPAN:
        raise InputError(where, f"the imprints span {span:g} m: expected positions in metres, a ricochet series "
                                f"spanning at most {MAX_SPAN:g} m{_span_hint(span, unit)}")
    if t is None:
        return
    bad = np.nonzero(np.diff(t) <= 0)[0]
    if bad.size:
        raise InputError(at(bad[0] + 1), f"impact instants t must increase; t = {t[bad[0] + 1]:g} s is not after "
                                         f"{t[bad[0]]:g} s")
    speed = span / float(t[-1] - t[0])
    if speed > MAX_SPEED:
        raise InputError(where, f"the imprints and instants give a mean speed of {speed:.4g} m/s along the plane, "
                                f"more than the {MAX_SPEED:g} m/s of the fastest launch the fit admits: expected x "
                                "in metres and t in seconds")
    first = float(t[1] - t[0])
    if 9.80665 * first / 2 > MAX_SPEED:
        raise InputError(at(1), f"the first flight lasts {first:g} s, which would need a normal speed of "
                                f"{9.80665 * first / 2:.4g} m/s (more than {MAX_SPEED:g}): expected t in seconds")


MIN_SPAN = 0.02  # m: a series shorter than this (a few imprints of a 61 mm ball) is no ricochet to measure


def _span_hint(span: float, unit: str | None) -> str:
    """'; in cm they would span 1.3 m: write the unit in the header (x_cm)': each smaller metric unit that puts a
    span too long for metres (``span``, SI, as read in ``unit``) between ``MIN_SPAN`` and ``MAX_SPAN``; where two
    do, both, and that positions alone cannot tell them apart (the fit scales with them). None fits: nothing (a
    hint followed must lead to a plausible file)."""
    have = UNITS["length"].get(unit or "m", 1.0)
    written = span / have
    fits = [(u, written * factor) for u, factor in UNITS["length"].items()
            if u in ("cm", "mm") and factor < have and MIN_SPAN <= written * factor <= MAX_SPAN]
    if not fits:
        return ""
    spans = ", ".join(f"in {unit_label(u)} they would span {m:.3g} m" for u, m in fits)
    headers = " or ".join(f"x_{u}" for u, _ in fits)
    if len(fits) == 1:
        return f"; {spans}: write the unit in the header ({headers})"
    return (f"; {spans}: write the unit you measured in, in the header ({headers}); the positions alone cannot tell "
            "which (the fit's f depends on it)")


def read_imprints(source: Path | Table) -> tuple[np.ndarray, np.ndarray | None]:
    """A ricochet series (column x in m, optional t in s; a header may give their units, x_mm, t_ms), both
    measured from the first imprint."""
    d = read_series(source, ("x",), optional=("t",), min_rows=1, dims={"x": "length", "t": "time"})
    x, t = d["x"], d.get("t")
    check_imprints(x, d.where, t, d.at, d.units.get("x"))
    return x - x[0], None if t is None else t - t[0]


@dataclass(frozen=True)
class Markers:
    """Angle markers against ψ (degrees), per series, with the file and line of each."""

    series: dict[str, tuple[np.ndarray, np.ndarray]]
    where: str


def read_markers(source: Path | Table, allowed: tuple[str, ...], required: tuple[str, ...] | None = None,
                 min_markers: int = MIN_MARKERS) -> Markers:
    """Markers from a CSV with a header ``series,psi_deg,angle_deg`` (an optional last column ``figure`` is
    ignored): series one of ``allowed``, ψ in (0°, 90°), the angle a finite number of degrees in (−90°, 90°]; at
    least ``min_markers`` of each series of ``required`` (default: all allowed) and of each series present. Every
    bad row is refused with its file:line."""
    tab = as_table(source)
    where = tab.where
    if not tab.head_line:
        raise InputError(where, "empty file (expected a header series,psi_deg,angle_deg and one marker per line)")
    head_line, header = tab.head_line, tab.header
    _no_empty_name(header, ("series", "psi_deg", "angle_deg"), tab.at(head_line))
    if header[:3] != ["series", "psi_deg", "angle_deg"] or len(header) > 4 or header[3:] not in ([], ["figure"]):
        raise InputError(tab.at(head_line), f"the header must be series,psi_deg,angle_deg (optionally ,figure), "
                                            f"got {','.join(header)[:80]}")
    out: dict[str, list[tuple[float, float]]] = {}
    for line, cells in tab.rows:
        if len(cells) != len(header):
            raise InputError(tab.at(line), f"expected {len(header)} values, got {len(cells)}")
        name = cells[0]
        if name not in allowed:
            raise InputError(tab.at(line), f"series must be one of {', '.join(allowed)}, got '{name[:40]}'")
        try:
            psi, ang = float(cells[1]), float(cells[2])
        except ValueError:
            raise InputError(tab.at(line), "psi_deg and angle_deg must be numbers (degrees)") from None
        for j, v in ((1, psi), (2, ang)):
            if underflows(cells[j], v):
                raise InputError(tab.at(line), f"{header[j]}: {cells[j][:40]} is no angle in any unit (it "
                                                    f"underflows to {v!r} in floating point): expected 0 or degrees")
        if not (math.isfinite(psi) and 0.0 < psi < 90.0):
            raise InputError(tab.at(line), f"psi_deg must be an impact angle in (0, 90) degrees (0 = head-on), "
                                                f"got {cells[1][:40]}")
        if not (math.isfinite(ang) and -90.0 < ang <= 90.0):
            raise InputError(tab.at(line), f"angle_deg must be an angle in (−90, 90] degrees, got {cells[2][:40]}")
        out.setdefault(name, []).append((psi, ang))
        if sum(map(len, out.values())) > MAX_MARKERS:
            raise InputError(tab.at(line), f"more than {MAX_MARKERS} markers")
    if not out:
        raise InputError(tab.at(head_line), "a header and no marker: expected one marker per line after it")
    need = [s for s in allowed if s in (allowed if required is None else required) or s in out]
    short = [f"{s} ({len(out.get(s, []))})" for s in need if len(out.get(s, [])) < min_markers]
    if short:
        raise InputError(where, f"at least {min_markers} markers of each series are needed to fit (f, e), σ and a "
                                f"trend; too few: {', '.join(short)}")
    series = {}
    for s, v in out.items():
        a = np.array(sorted(v))
        series[s] = (a[:, 0], a[:, 1])
    return Markers(series, where)
