"""The result types every layer shares: comparison rows, fit rows, figure and table descriptions, reproductions.

Figures are described, not drawn: an experiment lists the curves, points and bands to show, and
``report`` renders any such description. A new experiment therefore needs no change to the report. The
reporting layer and ``resal fit`` read these types without importing any experiment.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from importlib import resources
from typing import TYPE_CHECKING

from .config import Experiment

if TYPE_CHECKING:  # annotations only: importing the estimators imports scipy.optimize (0.4 s)
    import numpy as np

    from .fit.estimators.lsq import Estimate, Family, FitResult

__all__ = [
    "DOMAINS", "Computed", "FigureSpec", "FitRow", "Layer", "Reproduction", "Row", "TableSpec", "family_report",
    "fit_rows",
    "identifiability_report", "layer", "modern_table",
]


def modern_table() -> list[dict[str, str | float | None]]:
    """Today's measured values of the coefficients (``data/modern-values.csv``, with sources), numbers parsed."""
    text = resources.files("reproductions").joinpath("data/modern-values.csv").read_text(encoding="utf-8")
    lines = [ln for ln in text.splitlines() if ln and not ln.startswith("#")]
    out: list[dict[str, str | float | None]] = []
    for r in csv.DictReader(lines):
        row: dict[str, str | float | None] = dict(r)
        for key in ("low", "typ", "high"):
            row[key] = float(r[key]) if r[key].strip() else None
        out.append(row)
    return out


@dataclass(frozen=True)
class Computed:
    """A value resal computed, how, and (optionally) what explains a disagreement with the paper."""

    value: float | None
    how: str = ""
    diagnose: Callable[[float], str] | None = None
    # a "never"/"always" claim measured by its violations (0 when it holds): the worst signed margin by which it held
    # (> 0) or failed (< 0), in the claim's own units, so that a check that could fail shows how near it came
    margin: float | None = None


# where a row grades its claim: where the paper applies it, or beyond (a row `<id>_beyond`, counted apart)
DOMAINS = ("paper", "beyond")


@dataclass(frozen=True)
class Row:
    id: str
    quantity: str
    source: str
    printed: float | None
    printed_text: str
    # the project's English rendering of ``printed_text`` (None where it is ""); keyword-only, so that it stands
    # next to ``printed_text`` in summary.json without moving the positional fields
    english: str | None = field(default=None, kw_only=True)
    computed: float | None
    rel_diff: float | None
    tolerance: float | None
    tolerance_rule: str
    verdict: str
    note: str
    line: int | None = None  # where the claim is printed: line of the digitised text
    reason: str | None = None  # a code of ``config.REASONS`` for a row that differs
    today: str | None = None  # a modern symbol standing beside it
    config_line: int | None = None  # the line of the config file where the printed entry starts
    computes: str | None = None  # the kind's quantity the row is compared with (the config's `computed:`)
    margin: float | None = None  # a never/always claim's worst signed margin (``Computed.margin``)
    domain: str = "paper"  # a code of DOMAINS: where the paper applies the claim, or beyond it (counted apart)


@dataclass(frozen=True)
class Comparison:
    """What a kind computes for one published measurement (``config.Measured``): the measured value as published
    with its uncertainty, the prediction of the paper's mechanics with its 95 % interval, and the verdict, a code
    of ``config.MEASUREMENT_VERDICTS`` decided by the kind (which holds both distributions)."""

    measured: float | None
    measured_text: str  # as published, with its unit
    uncertainty: str  # its standard error and where it comes from ("published", "half the last digit, uniform")
    predicted: float | None
    interval: tuple[float, float] | None  # 95 % of the prediction
    verdict: str
    how: str  # how the prediction was made, and why the verdict


@dataclass(frozen=True)
class MeasurementRow:
    """One published measurement against the paper's mechanics: a row of its own kind, never counted with the
    printed claims' rows."""

    id: str
    quantity: str
    source: str
    unit: str
    measured: float | None
    measured_text: str
    uncertainty: str
    predicted: float | None
    interval: tuple[float, float] | None
    verdict: str
    note: str
    config_line: int | None = None
    computes: str | None = None


@dataclass(frozen=True)
class FitRow:
    """One fitted quantity. ``id`` is a stable code (``<fit>.<parameter>``) that programs and goldens key on;
    ``parameter`` is its label for people."""

    id: str
    parameter: str
    value: float | None
    stderr: float | None
    ci95: tuple[float | None, float | None]
    method: str
    identifiable: bool
    note: str
    family_range: tuple[float, float] | None = None
    at_bound: str | None = None  # code: "lower" or "upper" when the fit ended on that bound of the parameter


@dataclass(frozen=True)
class Layer:
    """One thing drawn: 'line', 'points', 'errorbar' (y ± y2), 'band' (y to y2), 'hband'/'vband' (span),
    'heatmap' (z[i][j] at x[j], y[i]; label names the colour bar), 'contour' (the curve z = 0 on the grid of
    x[j], y[i], interpolated: smooth, not a staircase of cells). ``color`` is a matplotlib colour or
    ``<colour map>:<t>``, t in [0, 1]: a colour taken from that map (an ordered family of curves)."""

    kind: str
    x: tuple[float, ...] = ()
    y: tuple[float, ...] = ()
    y2: tuple[float, ...] = ()
    z: tuple[tuple[float, ...], ...] = ()
    label: str = ""
    color: str = "C0"
    marker: str = "o"
    style: str = "-"
    centre: float | None = None  # heatmap of a signed quantity: a diverging colour map, this value its middle
    norm: str = "linear"  # heatmap: "log", its colours on a logarithmic scale of z (all z > 0)


@dataclass(frozen=True)
class FigureSpec:
    name: str
    title: str
    xlabel: str
    ylabel: str
    layers: tuple[Layer, ...]
    xlim: tuple[float, float] | None = None
    ylim: tuple[float, float] | None = None
    caption: str = ""  # a subtitle drawn in the figure
    reading: str = ""  # for the reader's edition: what is plotted and what to look at (one or two sentences)
    xticklabels: tuple[str, ...] = ()  # categories: labels of the ticks at x = 0, 1, 2, …
    yticklabels: tuple[str, ...] = ()  # the same along y
    # several panels: the figure is these (its own layers then empty), in a grid of ``columns`` columns, all
    # sharing the x axis (and the y axis when ``sharey``); of each panel, its title heads it, and its xlabel and
    # ylabel (the figure's when empty), layers, limits and tick labels are drawn; ``heights``: relative row heights
    panels: tuple[FigureSpec, ...] = ()
    columns: int = 1
    sharey: bool = False
    heights: tuple[float, ...] = ()
    legend: str = "best"  # where the key goes: a matplotlib location in each panel, or "below": one, under the axes
    yscale: str = "linear"  # or "log"
    xscale: str = "linear"  # or "log"
    aspect: str = "auto"  # "equal": a unit of x as long as a unit of y (paths in a plane drawn undistorted)


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
    measurements: tuple[MeasurementRow, ...] = ()  # published measurements against the mechanics (config.measured)


def layer(kind: str, x: Sequence[float] | np.ndarray = (), y: Sequence[float] | np.ndarray = (),
          y2: Sequence[float] | np.ndarray = (), z: np.ndarray | None = None, **kw: str | float) -> Layer:
    """A ``Layer`` from arrays (stored as tuples of floats, so specs stay hashable and serialisable)."""
    import numpy as np  # here: reading results (`make all` with nothing changed) needs no numpy (0.16 s)

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


def fit_rows(fit: FitResult, key: str, labels: dict[str, str], method: str, note: str = "",
             only: Sequence[str] | None = None) -> list[FitRow]:
    """Fit results as table rows: every parameter (or those named in ``only``, then without combinations),
    identifiable or with the range of its family, then the identified combinations. Row ids are
    ``<key>.<parameter>`` and ``<key>.combination<k>``."""
    out: list[FitRow] = []
    for est in fit.estimates:
        if only is not None and est.name not in only:
            continue
        name = labels.get(est.name, est.name)
        if est.identifiable:
            n = note if fit.noise != "none" else (note + " " if note else "") + \
                "no residual degree of freedom and no sigma: no uncertainty claimed"
            out.append(FitRow(f"{key}.{est.name}", name, est.value, est.stderr, est.ci95, method, True,
                              "; ".join(t for t in (_bound_note(est, name), n.strip()) if t), at_bound=est.at_bound))
        else:
            rng, fam = est.family_range, fit.family
            if rng is not None and fam is not None:
                span = f"any value in [{rng[0]:.4g}, {rng[1]:.4g}] fits ({fam.kind.value} family: {fam.label})"
            elif fam is not None:
                span = f"range not determined ({fam.label})"
            else:
                span = "not determined"
            out.append(FitRow(f"{key}.{est.name}", name, None, None, (None, None), method, False,
                              f"not identifiable: {span}; rank {fit.identifiability.rank} of {len(fit.names)}",
                              rng))
    for i, comb in enumerate(fit.combinations if only is None else ()):
        terms = " + ".join(
            (f"{c:.6g}·" if not math.isclose(c, 1.0, rel_tol=1e-6) else "") + labels.get(n, n)
            for c, n in zip(comb.coefficients, fit.names, strict=True) if c != 0.0)
        out.append(FitRow(f"{key}.combination{i}", terms, comb.value, comb.stderr, comb.ci95, method, True,
                          ("identified combination; " + note).strip("; ")))
    return out


def _bound_note(est: Estimate, label: str) -> str:
    """What a table says of an estimate that ended on a bound, or whose interval was cut at one."""
    parts = []
    if est.at_bound is not None:
        parts.append(f"WARNING: the fit ended on the {est.at_bound} bound of {label}: the data fit best at or beyond "
                     "the edge of its admissible range (check the data, their signs and units)")
    if est.clipped:
        parts.append("95 % interval cut at the admissible range (the normal approximation does not hold at a bound)")
    return "; ".join(parts)


def identifiability_report(fit: FitResult, key: str, labels: dict[str, str], data: str) -> dict:
    """The SVD of the fit's Jacobian at the solution, for ``summary.json``: what the data determine."""
    ident = fit.identifiability
    return {
        "id": key,
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
