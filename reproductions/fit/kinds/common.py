"""What every kind of ``resal fit`` shares: its options, its outcome, estimate rows and today's values."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import InputError
from ...results import FigureSpec, modern_table
from ...series import Series, Table, si_unit, unit_label
from .. import coverage_table
from ..estimators.lsq import Estimate, FitResult
from ..estimators.trials import Bootstrap, Noise

G = 9.80665  # m/s², standard gravity (the user may give their own with --g)
DEFAULT_RESAMPLES = 1000
MIN_BOOT_TRIALS = 3  # fewer trials have too few distinct resamples for a bootstrap to say anything


def boot_note(kind: str) -> str:
    """The bootstrap line's note: the percentile interval's coverage as measured for this kind
    (``fit/coverage.json``, ``resal fit KIND --help``); no other kind's figure is ever quoted."""
    got = coverage_table.boot_range(kind)
    measured = (f"it covered {got} of synthetic series at three true values (resal fit {kind} --help)"
                if got is not None else "its coverage is not measured for this kind")
    return f"a percentile interval, beside the reported one: {measured}; the 95 % interval is the one to quote"


@dataclass(frozen=True)
class FitOptions:
    """The command line's options, in SI where they carry a unit (``sigma`` stays in the data's unit)."""

    sigma: float | None = None
    sigma_in: float | None = None  # rebound: σ of the impact (V0 or h0), in its column's unit; errors in both
    noise: Noise = Noise.AUTO
    speeds: str | None = None  # "signed" | "unsigned" | None (the header says)
    M: float | None = None  # pendulum: the masses when not columns; ball-ball: the cue ball's (None: equal balls)
    Mp: float | None = None
    R: float = 0.0305
    k: float = 2.5
    Rp: float | None = None  # ball-ball: the object ball's radius and MR²/I (None: the cue ball's)
    kp: float | None = None
    g: float = G
    h0: float | None = None
    sigma_speed: float | None = None  # ball-ball: relative noise of the measured speeds
    sigma_dir: float | None = None  # ball-ball: noise of the measured directions, in their column's unit
    resamples: int = DEFAULT_RESAMPLES
    seed: int = 0
    progress: Callable[[int], None] | None = None  # called after each bootstrap resample; where it also has a
    # method stage(name: str, total: int), a fit of several stages (ball-ball) announces each through it
    max_seconds: float = 120.0  # wall-clock bound of one fit, its refits included (ball-ball): past it before the
    # estimate, an error; after it, the estimate with a time-bound warning (what was not done)


@dataclass(frozen=True)
class FitOutcome:
    """A fit's answer: ``summary`` (JSON-ready), the figures to draw, the residual table (rows of cells)."""

    summary: dict[str, Any]
    figures: tuple[FigureSpec, ...] = ()
    residual_headers: tuple[str, ...] = ()
    residual_rows: tuple[tuple[Any, ...], ...] = field(default_factory=tuple)


def estimate_row(pid: str, label: str, value: float | None, stderr: float | None,
                 ci95: tuple[float | None, float | None], *, method: str, identifiable: bool = True,
                 boot: tuple[float, float] | None = None, at_bound: str | None = None, clipped: bool = False,
                 note: str = "", unit: str = "1", bound_aware: bool = False) -> dict[str, Any]:
    """One estimate as ``summary.json`` holds it. ``bound_aware``: its interval is a profile likelihood's that
    takes the bound into account, so an estimate on the bound is no contradiction (``checks.finish``)."""
    notes = []
    if at_bound is not None:
        notes.append(f"the fit ended on the {at_bound} bound of {label}: the data fit best at or beyond the "
                     "edge of its admissible range (check the data, their signs and units)")
    if clipped:
        notes.append("95 % interval cut at the admissible range")
    if note:
        notes.append(note)
    return {"id": pid, "parameter": label, "value": value, "stderr": stderr, "unit": unit,
            "ci95": list(ci95), "ci95_bootstrap": None if boot is None else list(boot),
            "identifiable": identifiable, "at_bound": at_bound, "clipped": clipped, "bound_aware": bound_aware,
            "method": method,
            "note": "; ".join(notes)}


def rows_from_fit(fit: FitResult, key: str, labels: dict[str, str], method: str,
                  boot: Bootstrap | None = None, units: dict[str, str] | None = None,
                  only: Sequence[str] | None = None) -> list[dict[str, Any]]:
    """The estimates of a least-squares fit (``fitting.FitResult``), identified combinations included."""
    out = []
    units = units or {}
    for est in fit.estimates:
        if only is not None and est.name not in only:
            continue
        b = None
        if boot is not None and est.name in boot.names:
            b = boot.ci95[boot.names.index(est.name)]
        out.append(_estimate(est, key, labels, method, b, units.get(est.name, "1"), fit))
    for i, comb in enumerate(fit.combinations if only is None else ()):
        terms = " + ".join((f"{c:.6g}·" if not math.isclose(c, 1.0, rel_tol=1e-6) else "") + labels.get(n, n)
                           for c, n in zip(comb.coefficients, fit.names, strict=True) if c != 0.0)
        out.append(estimate_row(f"{key}.combination{i}", terms, comb.value, comb.stderr, comb.ci95, method=method,
                                note="the combination the data determine"))
    return out


def _estimate(est: Estimate, key: str, labels: dict[str, str], method: str, boot: tuple[float, float] | None,
              unit: str, fit: FitResult) -> dict[str, Any]:
    label = labels.get(est.name, est.name)
    if est.identifiable:
        note = "" if fit.noise != "none" else "no residual degree of freedom and no σ: no uncertainty claimed"
        return estimate_row(f"{key}.{est.name}", label, est.value, est.stderr, est.ci95, method=method, boot=boot,
                            at_bound=est.at_bound, clipped=est.clipped, note=note, unit=unit)
    rng = est.family_range
    span = f"any value in [{rng[0]:.4g}, {rng[1]:.4g}] fits" if rng is not None else "not determined"
    return estimate_row(f"{key}.{est.name}", label, None, None, (None, None), method=method, identifiable=False,
                        note=f"not identifiable: {span} (rank {fit.identifiability.rank} of {len(fit.names)})",
                        unit=unit)


def identifiability(fit: FitResult, labels: dict[str, str], data: str) -> dict[str, Any]:
    """Rank, singular values and null directions of the fit's Jacobian: what the data determine."""
    ident = fit.identifiability
    return {"data": data, "parameters": [labels.get(n, n) for n in fit.names], "rank": ident.rank,
            "singular_values": list(ident.singular_values), "condition_number": ident.condition_number,
            "null_directions": [list(v) for v in ident.null_directions],
            "identified_combinations": [list(c.coefficients) for c in fit.combinations]}


def columns_read(s: Series, dims: dict[str, str]) -> list[dict[str, Any]]:
    """Per column: the header as written, its unit, and whether it was read in SI for want of a unit."""
    out = []
    for name, written in s.written.items():
        unit = s.units.get(name)
        dim = dims.get(name, "ratio")
        out.append({"column": written, "quantity": name,
                    "unit": unit_label(unit) if unit is not None else si_unit(dim),
                    "note": "" if unit is not None or dim == "ratio" else f"no unit in the header: read in SI "
                                                                          f"({si_unit(dim)})"})
    return out


def check_sigma(sigma: float | None, data: Sequence[np.ndarray], unit: str) -> None:
    """A given σ between 1e-12 and 1e6 times the largest measured value (in that value's unit)."""
    if sigma is None:
        return
    if not (math.isfinite(sigma) and sigma > 0):
        raise InputError(f"--sigma {sigma:g}", "expected a positive number, finite (a standard deviation)")
    scale = max(float(np.max(np.abs(d))) for d in data)
    lo, hi = 1e-12 * scale, 1e6 * scale
    if not lo <= sigma <= hi:
        raise InputError(f"--sigma {sigma:g}", f"expected a standard deviation in [{lo:.3g}, {hi:.3g}], i.e. 1e-12 "
                                               f"to 1e6 times the largest measured value ({scale:g}), in {unit}")


def today(symbols: Sequence[str], interval: tuple[float, float], what: str) -> list[dict[str, Any]]:
    """Today's measured values (``modern-values.csv``) of ``symbols``, each said to lie inside the fitted 95 %
    interval, to overlap it, or to lie outside it."""
    out = []
    lo, hi = interval
    for r in modern_table():
        if r["symbol"] not in symbols:
            continue
        a = r["low"] if r["low"] is not None else r["typ"]
        b = r["high"] if r["high"] is not None else r["typ"]
        if a is None or b is None:
            verdict = "a law, not a value: see the speed comparison"
        elif a <= hi and b >= lo:
            verdict = "within your 95 % interval" if a == b else "overlaps your 95 % interval"
        else:
            verdict = f"outside your 95 % interval of {what}"
        out.append({"quantity": r["quantity"], "symbol": r["symbol"], "low": r["low"], "typ": r["typ"],
                    "high": r["high"], "source": r["source"], "note": r["note"], "verdict": verdict})
    return out


def paper_value(label: str, value: float, line: int, interval: tuple[float, float], what: str) -> dict[str, Any]:
    """A value of the paper beside the fit (compared against, never used): inside or outside the 95 % interval."""
    inside = interval[0] <= value <= interval[1]
    return {"claim": label, "value": value, "line": line,
            "verdict": f"within your 95 % interval of {what}" if inside else f"outside your 95 % interval of {what}"}


def base_summary(kind: str, src: Table, n: int, columns: list[dict[str, Any]], opts: FitOptions) -> dict[str, Any]:
    return {"kind": kind, "file": src.where, "n": int(n), "columns": columns, "fits": [], "warnings": [],
            "bootstrap": {"resamples": opts.resamples, "seed": opts.seed}}
