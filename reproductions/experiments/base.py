"""What every experiment produces: comparison rows, fits, modern comparisons and figure descriptions.

Figures are described, not drawn: an experiment lists the curves, points and bands to show, and
``report`` renders any such description. A new experiment therefore needs no change to the report.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from ..config import Experiment, Node, Printed
from ..errors import InputError
from ..fitting import Family, FitResult

__all__ = [
    "Computed", "FigureSpec", "FitRow", "Layer", "Reproduction", "Row", "compare", "fit_rows", "modern_rows",
    "read_series",
]


@dataclass(frozen=True)
class Computed:
    """A value resal computed, how, and (optionally) what explains a disagreement with the paper."""

    value: float | None
    how: str = ""
    diagnose: Callable[[float], str] | None = None


@dataclass(frozen=True)
class Row:
    id: str
    quantity: str
    source: str
    printed: float | None
    printed_text: str
    computed: float | None
    rel_diff: float | None
    tolerance: float | None
    tolerance_rule: str
    verdict: str
    note: str


@dataclass(frozen=True)
class FitRow:
    parameter: str
    value: float | None
    stderr: float | None
    ci95: tuple[float | None, float | None]
    method: str
    identifiable: bool
    note: str
    family_range: tuple[float, float] | None = None


@dataclass(frozen=True)
class Layer:
    """One thing drawn: 'line', 'points', 'errorbar' (y ± y2), 'band' (y to y2), 'hband'/'vband' (span),
    'heatmap' (z[i][j] at x[j], y[i]; label names the colour bar)."""

    kind: str
    x: tuple[float, ...] = ()
    y: tuple[float, ...] = ()
    y2: tuple[float, ...] = ()
    z: tuple[tuple[float, ...], ...] = ()
    label: str = ""
    color: str = "C0"
    marker: str = "o"
    style: str = "-"


@dataclass(frozen=True)
class FigureSpec:
    name: str
    title: str
    xlabel: str
    ylabel: str
    layers: tuple[Layer, ...]
    xlim: tuple[float, float] | None = None
    ylim: tuple[float, float] | None = None
    caption: str = ""


@dataclass(frozen=True)
class Reproduction:
    experiment: Experiment
    rows: tuple[Row, ...]
    fits: tuple[FitRow, ...]
    figures: tuple[FigureSpec, ...]
    modern: tuple[dict, ...] = ()
    data_note: str = ""
    identifiability: tuple[dict, ...] = ()
    tables: tuple[TableSpec, ...] = ()


def layer(kind: str, x: Sequence[float] | np.ndarray = (), y: Sequence[float] | np.ndarray = (),
          y2: Sequence[float] | np.ndarray = (), z: np.ndarray | None = None, **kw: str) -> Layer:
    """A ``Layer`` from arrays (stored as tuples of floats, so specs stay hashable and serialisable)."""
    zz = () if z is None else tuple(tuple(map(float, row)) for row in np.asarray(z))
    return Layer(kind, tuple(map(float, np.ravel(x))), tuple(map(float, np.ravel(y))),
                 tuple(map(float, np.ravel(y2))), zz, **kw)


@dataclass(frozen=True)
class TableSpec:
    """A further table of numbers (e.g. an estimator comparison): stored in summary.json, rendered in table.md."""

    name: str
    title: str
    headers: tuple[str, ...]
    rows: tuple[tuple[float | str | None, ...], ...]
    note: str = ""


def compare(p: Printed, c: Computed) -> Row:
    """The verdict for one printed value: reproduced within the printed digits, differs (with why), or not checkable."""
    if p.formula and c.value is not None:
        assert p.tolerance is not None
        ok = abs(c.value) <= p.tolerance
        return Row(p.id, p.quantity, p.source, None, p.text, c.value, None, p.tolerance, p.tolerance_rule,
                   "reproduced" if ok else "differs",
                   c.how if ok else (c.diagnose(0.0) if c.diagnose else "the printed formula disagrees: " + c.how))
    if p.value is None or c.value is None:
        note = c.how if c.value is not None else "resal computes no value for this claim"
        return Row(p.id, p.quantity, p.source, p.value, p.text, c.value, None, p.tolerance, p.tolerance_rule,
                   "not-checkable", note)
    rel = (c.value - p.value) / abs(p.value) if p.value != 0 else c.value - p.value
    assert p.tolerance is not None
    if abs(rel) <= p.tolerance * (1 + 1e-9):
        verdict, note = "reproduced", c.how
    else:
        verdict = "differs"
        note = c.diagnose(p.value) if c.diagnose else "no explanation found: " + c.how
    return Row(p.id, p.quantity, p.source, p.value, p.text, c.value, rel, p.tolerance, p.tolerance_rule, verdict,
               note)


def rows_for(exp: Experiment, computed: dict[str, Computed]) -> tuple[Row, ...]:
    """One row per printed value of the config, in the config's (the paper's) order."""
    return tuple(compare(p, computed[p.computed]) for p in exp.printed)


def fit_rows(fit: FitResult, labels: dict[str, str], method: str, note: str = "",
             only: Sequence[str] | None = None) -> list[FitRow]:
    """Fit results as table rows: every parameter (or those named in ``only``, then without combinations),
    identifiable or with the range of its family, then the identified combinations."""
    out: list[FitRow] = []
    for est in fit.estimates:
        if only is not None and est.name not in only:
            continue
        name = labels.get(est.name, est.name)
        if est.identifiable:
            n = note if fit.noise != "none" else (note + " " if note else "") + \
                "no residual degree of freedom and no sigma: no uncertainty claimed"
            out.append(FitRow(name, est.value, est.stderr, est.ci95, method, True, n.strip()))
        else:
            rng, fam = est.family_range, fit.family
            if rng is not None and fam is not None:
                span = f"any value in [{rng[0]:.4g}, {rng[1]:.4g}] fits ({fam.kind.value} family: {fam.label})"
            elif fam is not None:
                span = f"range not determined ({fam.label})"
            else:
                span = "not determined"
            out.append(FitRow(name, None, None, (None, None), method, False,
                              f"not identifiable: {span}; rank {fit.identifiability.rank} of {len(fit.names)}",
                              rng))
    for comb in fit.combinations if only is None else ():
        terms = " + ".join(
            (f"{c:.6g}·" if not math.isclose(c, 1.0, rel_tol=1e-6) else "") + labels.get(n, n)
            for c, n in zip(comb.coefficients, fit.names, strict=True) if c != 0.0)
        out.append(FitRow(terms, comb.value, comb.stderr, comb.ci95, method, True,
                          ("identified combination; " + note).strip("; ")))
    return out


def identifiability_report(fit: FitResult, labels: dict[str, str], data: str) -> dict:
    """The SVD of the fit's Jacobian at the solution, for ``summary.json``: what the data determine."""
    ident = fit.identifiability
    return {
        "data": data,
        "parameters": [labels.get(n, n) for n in fit.names],
        "n_data": fit.n_data,
        "singular_values": list(ident.singular_values),
        "rank": ident.rank,
        "condition_number": ident.condition_number,
        "null_directions": [list(v) for v in ident.null_directions],
        "identified_combinations": [list(c.coefficients) for c in fit.combinations],
        "point": list(fit.point),
        "canonical": fit.canonical,
        "family_of_solutions": None if fit.family is None else family_report(fit.family),
        "noise": fit.noise,
    }


def family_report(fam: Family) -> dict:
    """A family of solutions for ``summary.json``: how it was obtained, its ends, the ranges, the end check."""
    return {"kind": fam.kind.value, "along": fam.along, "ends": [list(fam.ends[0]), list(fam.ends[1])],
            "ranges": [None if r is None else list(r) for r in fam.ranges], "end_chi2": list(fam.end_chi2),
            "holds": fam.holds, "label": fam.label}


def read_ball(node: Node, with_mass: bool = False) -> tuple[float, ...]:
    """The ``ball`` section shared by the kinds: (R, k), or (R, k, M) with ``with_mass``."""
    ball = node.child("ball", "a mapping with R, k" + (", M" if with_mass else ""))
    out = [ball.number("R", "a radius in m", lo=0.0, lo_open=True),
           ball.number("k", "k of the moment of inertia M R²/k", lo=0.0, lo_open=True)]
    if with_mass:
        out.append(ball.number("M", "a mass in kg", lo=0.0, lo_open=True))
    ball.done()
    return tuple(out)


def modern_rows(symbols: Sequence[str], values: dict[str, tuple[float, str]]) -> tuple[dict, ...]:
    """Rows of ``modern-values.csv`` for the requested symbols, beside the value resal derives."""
    text = resources.files("reproductions").joinpath("data/modern-values.csv").read_text(encoding="utf-8")
    lines = [ln for ln in text.splitlines() if ln and not ln.startswith("#")]
    table = list(csv.DictReader(lines))

    def num(s: str) -> float | None:
        return float(s) if s.strip() else None

    out = []
    for sym in symbols:
        resal_value, what = values[sym]
        for r in table:
            if r["symbol"] == sym:
                out.append({"symbol": sym, "quantity": r["quantity"], "resal": resal_value, "resal_what": what,
                            "low": num(r["low"]), "typ": num(r["typ"]), "high": num(r["high"]),
                            "source": r["source"], "note": r["note"]})
    return tuple(out)


def read_series(path: Path, columns: Sequence[str], optional: Sequence[str] = (), min_rows: int = 1,
                positive: Sequence[str] = ()) -> dict[str, np.ndarray]:
    """A measurement series from a CSV file with a header; every bad row is reported as file:line."""
    where = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(where, f"cannot read the series file ({exc.strerror})") from None
    except UnicodeDecodeError:
        raise InputError(where, "not a UTF-8 text file") from None
    numbered = [(i + 1, ln) for i, ln in enumerate(text.splitlines()) if ln.strip() and not ln.startswith("#")]
    if not numbered:
        raise InputError(where, f"empty series (expected a header with columns {', '.join(columns)})")
    head_line, head = numbered[0]
    header = [h.strip() for h in next(csv.reader([head]))]
    missing = [c for c in columns if c not in header]
    if missing:
        raise InputError(f"{where}:{head_line}", f"missing column(s) {', '.join(missing)} in the header "
                                                 f"(expected {', '.join(columns)})")
    unknown = [h for h in header if h not in columns and h not in optional]
    if unknown:
        raise InputError(f"{where}:{head_line}", f"unknown column(s) {', '.join(unknown)} "
                                                 f"(expected {', '.join([*columns, *optional])})")
    data: dict[str, list[float]] = {h: [] for h in header}
    for line_no, ln in numbered[1:]:
        cells = [c.strip() for c in next(csv.reader([ln]))]
        if len(cells) != len(header):
            raise InputError(f"{where}:{line_no}", f"expected {len(header)} values, got {len(cells)}")
        for h, cell in zip(header, cells, strict=True):
            try:
                v = float(cell)
            except ValueError:
                raise InputError(f"{where}:{line_no}", f"column '{h}': expected a number, got '{cell}'") from None
            if not math.isfinite(v):
                raise InputError(f"{where}:{line_no}", f"column '{h}': expected a finite number, got '{cell}'")
            if h in positive and v <= 0:
                raise InputError(f"{where}:{line_no}", f"column '{h}': expected a positive number, got '{cell}'")
            data[h].append(v)
    if len(numbered) - 1 < min_rows:
        raise InputError(where, f"expected at least {min_rows} data row(s), got {len(numbered) - 1}")
    return {h: np.asarray(v) for h, v in data.items()}
