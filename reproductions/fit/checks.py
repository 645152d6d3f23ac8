"""What every ``resal fit`` checks about its own fit before it reports a number.

Each finding is a coded warning, ``{code, message}`` in fit.json's ``warnings`` and a WARNING line on stderr; the
files are still written and ``--strict`` turns any warning into exit status 1. A program reads the code, a person
the message. The checks:

- goodness of fit: reduced χ² against a given σ; an estimated noise against what such a measurement plausibly has;
  the pure-error lack-of-fit test where trials repeat (the kinds compute it, the code is here);
- outliers by leave-one-out: each trial predicted from the others with its 95 % prediction interval
  (``leave_one_out``: the deleted-residual statistics of the linearised fit, exact for a linear model);
- conventions: a transformed reading of the data (directions mirrored, degrees read as radians, columns swapped,
  speeds unsigned) that fits far better is named with the option or header that selects it (``better_reading``);
- plausibility of the inputs: each kind declares the range a billiard or laboratory measurement has, per
  dimension, and a column outside it is named with the unit that would put it inside (``plausible_columns``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from enum import Enum
from typing import Any

import numpy as np

from ..series import UNITS, Series, Table, unit_label
from . import distributions as dist

__all__ = [
    "G_HIGH",
    "G_LOW",
    "PLAUSIBLE",
    "Code",
    "Reading",
    "better_reading",
    "check_g",
    "chi2_given",
    "finish",
    "leave_one_out",
    "loo_entries",
    "name_outliers",
    "noise_plausible",
    "plausible_columns",
    "plausible_ratio",
    "plausible_values",
    "warn",
]


class Code(str, Enum):
    """What a warning is about; the value is what fit.json carries."""

    CHI2 = "chi2-exceeds-sigma"  # a given σ that the residuals contradict
    NOISE = "noise-implausible"  # an estimated noise larger than such a measurement plausibly has
    LACK_OF_FIT = "lack-of-fit"  # repeated trials agree with one another far better than with the model
    SPEED_LAW = "speed-dependence"  # the data reject a constant coefficient
    OUTLIER = "outlier"  # a trial outside the prediction interval from the others
    CONVENTION = "convention"  # another reading of the data fits far better
    UNIT = "implausible-input"  # a column outside what such a measurement can be (a unit missing?)
    AT_BOUND = "at-bound"  # the estimate ended on the edge of its admissible range
    IDENTIFIABILITY = "not-identifiable"  # the data determine only a combination
    ASSUMED = "assumed"  # something the data do not say was taken as said (a direction, a sign)
    DUPLICATE = "duplicate-rows"  # rows repeated exactly: copied twice?
    NO_SCATTER = "no-scatter"  # the residuals are exactly zero: no noise can be estimated, no interval
    SIGMA_LARGE = "sigma-exceeds-scatter"  # a given σ far larger than the residuals: intervals too wide
    RESULT = "implausible-result"  # a fitted quantity known from elsewhere (g) comes out far from what it is
    SECOND_MINIMUM = "second-minimum"  # another set of parameters, far from the estimate, fits almost as well
    SERIES = "series-disagree"  # two series of one experiment do not share the parameters they should
    TIME_BOUND = "time-bound"  # the time bound stopped a check or the bootstrap: the estimate stands, that part not
    BALLS = "unequal-balls"  # balls taken equal, and the data fit far better with a mass ratio other than 1


def warn(summary: dict[str, Any], code: Code, message: str) -> None:
    """Record one finding (no duplicates: the same code and message once)."""
    entry = {"code": code.value, "message": message}
    if entry not in summary["warnings"]:
        summary["warnings"].append(entry)


G_LOW, G_HIGH = 9.76, 9.84  # m/s²: gravity from the equator to the poles and on mountains, with a margin


def check_g(summary: dict[str, Any], g: float) -> None:
    """--g outside what gravity is on Earth (a unit? cm/s²)."""
    if not G_LOW <= g <= G_HIGH:
        hint = "; in cm/s² it would be plausible (--g takes m/s²)" if G_LOW <= g / 100 <= G_HIGH else ""
        warn(summary, Code.UNIT, f"--g {g:g} m/s² is outside {G_LOW:g}–{G_HIGH:g} m/s², gravity anywhere on "
                                 f"Earth{hint}")


def _no_width(f: dict[str, Any]) -> bool:
    ci, v = f.get("ci95") or [None, None], f.get("value")
    return bool(f.get("identifiable") and v is not None and ci[0] is not None and ci[1] is not None
                and ci[1] - ci[0] <= ZERO_WIDTH * max(1.0, abs(v)) and not f.get("at_bound"))


ZERO_WIDTH = 1e-12  # an interval narrower than this (relative) has no width: the residuals are zero
SMALL_CHI2_P = 1e-3  # a given σ is far too large when χ² is this improbably small


def finish(summary: dict[str, Any]) -> None:
    """The checks every kind shares, run on its summary: an interval of no width (zero residuals), a given σ far
    larger than the scatter, an estimate that ended on a bound of its range, unless
    its interval is a profile likelihood's with the bound (then the bound is one of the values the data allow, as
    e = 1 is for a series at e = 0.995; a series far beyond the bound is a kind's own finding, a convention)."""
    flat = [f["parameter"] for f in summary["fits"] if _no_width(f)]
    if flat:
        warn(summary, Code.NO_SCATTER, f"the 95 % interval of {' and of '.join(flat)} has no width: the trials agree "
                                       "exactly (identical, duplicated or rounded values), so no noise can be "
                                       "estimated from them; give the measurement's σ (its reading precision) for an "
                                       "honest interval")
    good = summary.get("goodness") or {}
    if good.get("chi2_p") is not None and good["chi2_p"] > 1.0 - SMALL_CHI2_P:
        warn(summary, Code.SIGMA_LARGE, f"the given σ is far larger than the scatter: reduced χ² = "
                                        f"{good['reduced_chi2']:.3g}, a χ² this small has probability below "
                                        f"{SMALL_CHI2_P:g}; the intervals from σ are too wide (is σ in the "
                                        "data's unit?)")
    for f in summary["fits"]:
        if f.get("at_bound") and not f.get("bound_aware"):
            warn(summary, Code.AT_BOUND, f"{f['parameter']} ended on the {f['at_bound']} bound of its admissible "
                                         "range: the data fit best at or beyond its edge (check the data, their signs "
                                         "and units)")


# --------------------------------------------------------------------------------------------------------------
# plausibility of the inputs

@dataclass(frozen=True)
class Range:
    """What a measurement of one dimension plausibly is, in SI, and in words."""

    low: float
    high: float
    what: str
    typical: float  # a usual value: of several units that fit, the one nearest it is named


# per kind of quantity, in SI; wide enough for any billiard or laboratory measurement, narrow enough that a
# column in another unit falls outside (cm/s read as m/s: 27–340 "m/s"; degrees read as radians: 30 "rad")
PLAUSIBLE: dict[str, Range] = {
    "ball-speed": Range(0.01, 15.0, "a billiard ball's speed (a hard break is 8–12 m/s)", 1.5),
    # 20 m/s: a drop from 20 m, beyond a hard break's 12 m/s; cm/s read as m/s (20–1000 for 0.2–10 m/s) fall outside
    "lab-speed": Range(1e-3, 20.0, "an impact speed in a laboratory rebound", 2.0),
    # 3 m: from there air drag lowers a billiard ball's √(h1/h0) about 1 % below e (terminal speed ≈ 48 m/s);
    # and mm read as m (200–1000 "m") then name mm, not cm
    "drop-height": Range(1e-3, 3.0, "a drop or rebound height in a laboratory", 0.5),
    "pendulum-speed": Range(1e-3, 20.0, "a pendulum's speed at the bottom of its swing", 1.0),
    "mass": Range(1e-3, 50.0, "a ball's or a pendulum bob's mass", 0.3),
    "flight-time": Range(1e-3, 5.0, "a bounce's flight (a drop from 20 m gives one of 4 s)", 0.3),
}


def plausible_columns(s: Series, ranges: dict[str, str], dims: dict[str, str]) -> list[str]:
    """For each column named in ``ranges`` (column → key of ``PLAUSIBLE``), a message when its values (in SI)
    lie outside the plausible range, naming the unit that would put them inside (and, where the header gives no
    unit, the other columns of that dimension without one whose values go with it: a unit left out of one name is
    left out of its partner's); none when all are plausible."""
    out = []
    for col, key in ranges.items():
        if col not in s:
            continue
        si = np.asarray(s[col], dtype=float)
        also = [c for c in s.written if c != col and dims.get(c) == dims.get(col) and s.units.get(c) is None
                and s.units.get(col) is None and _goes_with(s, c, col)]
        group = np.concatenate([np.asarray(s[c], dtype=float) / s.factors.get(c, 1.0) for c in (col, *also)])
        names = tuple(c for c in s.written if c in (col, *also))  # in the header's order
        msg = plausible_values(si, si / s.factors.get(col, 1.0), key, dims.get(col), s.units.get(col),
                               f"column '{s.written[col]}'", s.unit_text.get(col, ""), names, group)
        if msg:
            out.append(msg)
    return out


def _goes_with(s: Series, c: str, col: str) -> bool:
    """Column c's values as written are within a factor 10 of col's (median |c|/|col| in [0.01, 10]): measured with
    it, in its unit."""
    a, b = np.abs(np.asarray(s[c], dtype=float)), np.abs(np.asarray(s[col], dtype=float))
    ok = np.isfinite(a) & np.isfinite(b) & (b > 0)
    return bool(ok.any()) and 0.01 <= float(np.median(a[ok] / b[ok])) <= 10.0


def plausible_values(si: np.ndarray, written: np.ndarray, key: str, dim: str | None, unit: str | None, what: str,
                     unit_text: str, columns: Sequence[str] = (), together: np.ndarray | None = None) -> str | None:
    """A message when the magnitudes ``si`` (SI) lie outside ``PLAUSIBLE[key]``, naming the unit of ``dim`` that
    would put the values as written inside (``together``: those of all ``columns`` at once, so that columns
    written in one unit are told one unit), and the header names that would say it; None when they are plausible
    (or all missing)."""
    ok = np.isfinite(si)
    vals, wr = np.abs(si[ok]), np.abs(np.asarray(written, dtype=float)[ok])
    if vals.size == 0:
        return None
    rng = PLAUSIBLE[key]
    lo, hi = float(vals.min()), float(vals.max())
    if rng.low <= lo and hi <= rng.high:
        return None
    si_text = unit_label(next(iter(UNITS[dim]))) if dim else ""
    span = f"{float(wr.min()):.4g}" + ("" if wr.min() == wr.max() else f" to {float(wr.max()):.4g}")
    told = wr if together is None else np.abs(together[np.isfinite(together)])
    return (f"{what}: {span} {unit_text}, outside {rng.low:g}–"
            f"{rng.high:g} {si_text}, {rng.what}{_unit_hint(told, rng, dim, unit, columns)}")


def _unit_hint(written: np.ndarray, rng: Range, dim: str | None, unit: str | None, columns: Sequence[str] = ()
               ) -> str:
    """'; in cm/s they would be plausible (write the unit in the header: 'u0_cmps', 'u1_cmps')': of the other units
    of the dimension that put the values inside the range, the one that puts their median nearest the range's
    typical value (mm, not cm, for pendulum heights of 110–280)."""
    if dim is None:
        return ""
    a = np.abs(written)
    lo, hi, mid = float(np.min(a)), float(np.max(a)), float(np.median(a))
    fits = [(abs(math.log(max(mid * factor, 1e-300) / rng.typical)), u) for u, factor in UNITS[dim].items()
            if not (u == unit or (unit is None and factor == 1.0))
            and rng.low <= lo * factor and hi * factor <= rng.high]
    if not fits:
        return ""
    u = min(fits)[1]
    names = ", ".join(f"'{c}_{u}'" for c in columns) if columns else f"'_{u}'"
    return f"; in {unit_label(u)} they would be plausible (write the unit in the header: {names})"


def plausible_ratio(s: Series, num: str, den: str, dims: dict[str, str], bounds: tuple[float, float], what: str,
                    typical: tuple[float, float]) -> list[str]:
    """Two columns against each other, each in its declared unit as read (SI): a median ratio |num|/|den| outside
    ``bounds`` (a rebound a hundredth of its impact, heights in a ratio no ball makes) is named, with the unit of
    one column that brings it into ``typical`` (one column's unit written wrong: ``u1_cmps`` over values in m/s);
    and rows whose ratio jumps from the others' by a unit factor (3.6, 100, 1000: some rows in km/h or cm/s) are
    named as a group. ``what`` names the ratio for people ("the rebound over the impact")."""
    if num not in s or den not in s:
        return []
    a, b = np.abs(np.asarray(s[num], dtype=float)), np.abs(np.asarray(s[den], dtype=float))
    ok = np.isfinite(a) & np.isfinite(b) & (a > 0) & (b > 0)
    if not ok.any():
        return []
    r = a[ok] / b[ok]
    med = float(np.median(r))
    if not bounds[0] <= med <= bounds[1]:
        return [f"{what} ({s.written[num]}/{s.written[den]}, each in its header's unit) is {med:.3g} in the median, "
                f"outside {bounds[0]:g}–{bounds[1]:g}{_ratio_hint(s, num, den, dims, med, typical)}"]
    group = _unit_jump(s, num, den, r, np.flatnonzero(ok))
    return [group] if group else []


def _ratio_hint(s: Series, num: str, den: str, dims: dict[str, str], med: float, typical: tuple[float, float]
                ) -> str:
    """'; with u1 in m/s ('u1_mps' in the header) it would be 0.82': the one change of one column's unit that
    brings the ratio nearest the middle of ``typical``, if any does."""
    best = None
    mid = math.sqrt(typical[0] * typical[1])
    for col, other in ((num, den), (den, num)):
        for u, factor in UNITS[dims[col]].items():
            change = factor / s.factors[col]
            if math.isclose(change, 1.0):
                continue
            new = med * change if col == num else med / change
            # the other column's unit first (one header written differently from its partner), then SI
            rank = (0 if u == (s.units.get(other) or next(iter(UNITS[dims[col]]))) else 1 if factor == 1.0 else 2,
                    abs(math.log(new / mid)))
            if typical[0] <= new <= typical[1] and (best is None or rank < best[0]):
                best = (rank, col, u, new)
    if best is None:
        return ""
    _, col, u, new = best
    return (f"; with {s.written[col]} in {unit_label(u)} ('{col}_{u}' in the header) it would be {new:.3g}: is its "
            "unit written wrong?")


def _unit_jump(s: Series, num: str, den: str, r: np.ndarray, rows: np.ndarray) -> str | None:
    """Rows whose ratio is a unit factor (3.6, 10, 100, 1000, 2.54 …) away from the others', the others agreeing
    among themselves far better than that: named as a group, with the pair of units whose factor is nearest."""
    lr = np.log(r)
    dev = lr - float(np.median(lr))
    near = np.abs(dev) > math.log(2.0)
    rest = ~near
    if not near.any() or rest.sum() < max(3, near.sum()) or np.ptp(lr[rest]) > math.log(1.5):
        return None
    size = float(np.median(np.abs(dev[near])))
    factors = [(abs(math.log(f1 / f2) - size), f1 / f2, u1, u2) for dim in ("speed", "length", "time", "mass")
               for u1, f1 in UNITS[dim].items() for u2, f2 in UNITS[dim].items() if f1 / f2 > 2.0]
    miss, F, big, small = min(factors)
    if miss > 0.1 * size:
        return None
    where = s.table.span([s.lines[int(i)] for i in rows[near]])
    return (f"{where}: {s.written[num]}/{s.written[den]} is {math.exp(size):.3g} times "
            f"{'larger' if float(np.median(dev[near])) > 0 else 'smaller'} than on the other rows, the factor "
            f"between {unit_label(big)} and {unit_label(small)} ({F:.4g}): one of the columns there looks like "
            "another unit")


def chi2_given(chi2: float, dof: int) -> tuple[float, float]:
    """Reduced χ² and the p-value of χ² at least this large, when σ was given."""
    return chi2 / max(dof, 1), float(dist.chi2_sf(chi2, max(dof, 1)))


CHI2_P = 0.01  # a given σ is contradicted when χ² this improbable (or worse) is seen


def noise_plausible(summary: dict[str, Any], estimated: float, limit: float, what: str, unit: str) -> None:
    """Warn when an estimated noise exceeds what such a measurement plausibly has (``limit``)."""
    if math.isfinite(estimated) and estimated > limit:
        warn(summary, Code.NOISE, f"the scatter of {what} about the fit is {estimated:.3g} {unit}, more than the "
                                  f"{limit:.3g} {unit} such a measurement plausibly has: the model does not describe "
                                  "these data as read (check the columns' units, signs and conventions)")


# --------------------------------------------------------------------------------------------------------------
# leave-one-out

OUTLIER_LEVEL = 0.05  # family-wise: a trial is named when outside its interval at level 0.05/n (Bonferroni)


def leave_one_out(r: np.ndarray, J: np.ndarray, groups: np.ndarray, *, sigma_known: bool,
                  dof_extra: int = 0) -> dict[str, np.ndarray]:
    """Deleted-residual statistics of a (linearised) weighted least-squares fit, trial by trial.

    ``r`` are the weighted residuals (measured − predicted, each divided by its σ or relative σ), ``J`` their
    Jacobian with respect to the p fitted parameters (of the predictions, weighted), ``groups`` the trial of each
    residual (a trial may measure several quantities). For trial g with residuals G the fit without it changes
    them to e_G = (I − H_GG)⁻¹ r_G, with covariance s²(I − H_GG)⁻¹ (H the hat matrix); Q_g = r_Gᵀ(I − H_GG)⁻¹r_G
    is χ² with |G| degrees of freedom when σ is known, and Q_g/|G| over the scale left without the trial,
    (RSS − Q_g)/(N − p − |G| − dof_extra), is F(|G|, N − p − |G| − dof_extra) when it is estimated. Exact for a
    linear model (Cook & Weisberg 1982, §4.2); the first-order approximation of a refit otherwise.

    Returns per residual ``deleted`` (e, weighted), ``sd`` (its standard deviation, weighted units) and ``q`` (the
    95 % quantile: normal, or Student's t with the degrees of freedom left), and per trial (sorted group labels)
    ``p`` (the probability of a statistic at least as large) and ``stat``. NaN where a trial alone determines a
    parameter (nothing else predicts it)."""
    r = np.asarray(r, dtype=float)
    J = np.asarray(J, dtype=float).reshape(r.size, -1)
    N = r.size
    # hat matrix of the weighted problem, through a thin SVD (rank-safe: drop null directions)
    u, sv, _ = np.linalg.svd(J, full_matrices=False)
    keep = sv > sv.max() * 1e-10 if sv.size else np.zeros(0, bool)
    U = u[:, keep]
    rank = int(keep.sum())
    rss = float(r @ r)
    groups = np.asarray(groups)
    order = np.argsort(groups, kind="stable")  # each trial's residuals, in file order: one pass, not one per trial
    labels, starts = np.unique(groups[order], return_index=True)
    ends = np.append(starts[1:], N)
    deleted = np.full(N, np.nan)
    sd = np.full(N, np.nan)
    q = np.full(N, np.nan)
    pvals = np.full(labels.size, np.nan)
    statv = np.full(labels.size, np.nan)
    Qs, sizes, dfs, scales = (np.full(labels.size, np.nan) for _ in range(4))
    # trials of one residual, all at once (the common case; the loop below costs 50 µs a trial): H_gg is the leverage
    # h = |U_g|², and the trial alone determines a parameter where 1 − h vanishes (to 1e-12, as the cond test below)
    one = np.flatnonzero(ends - starts == 1)
    if one.size:
        i = order[starts[one]]
        a = 1.0 - np.einsum("ij,ij->i", U[i], U[i])
        e = r[i] / np.where(a > 1e-12, a, np.nan)
        Q = r[i] * e
        if sigma_known:
            scale2 = np.ones_like(Q)
        else:
            df = N - rank - 1 - dof_extra
            scale2 = np.maximum(rss - Q, 0.0) / df if df >= 1 else np.full_like(Q, np.nan)
            dfs[one] = np.where(scale2 > 0, df, np.nan)
        live = np.isfinite(Q) & (scale2 > 0)
        k, i, e, Q, a, scale2 = one[live], i[live], e[live], Q[live], a[live], scale2[live]
        Qs[k], sizes[k], scales[k], statv[k] = Q, 1.0, scale2, Q / scale2
        deleted[i] = e
        sd[i] = np.sqrt(scale2 / a)
    for k in np.flatnonzero(ends - starts > 1):
        idx = order[starts[k]:ends[k]]
        H = U[idx] @ U[idx].T
        A = np.eye(idx.size) - H
        if np.linalg.cond(A) > 1e12:  # the trial alone determines a parameter: nothing predicts it
            continue
        Ainv = np.linalg.inv(A)
        e = Ainv @ r[idx]
        Q = float(r[idx] @ e)
        if sigma_known:
            scale2 = 1.0
        else:
            df = N - rank - idx.size - dof_extra
            if df < 1:
                continue
            scale2 = max(rss - Q, 0.0) / df
            if scale2 <= 0:
                continue
            dfs[k] = df
        Qs[k], sizes[k], scales[k] = Q, idx.size, scale2
        statv[k] = Q / scale2
        deleted[idx] = e
        sd[idx] = np.sqrt(np.clip(np.diag(Ainv), 0, None) * scale2)
    done = np.isfinite(Qs)  # the distributions once for all trials (a call per trial costs more than its algebra)
    if sigma_known:
        pvals[done] = dist.chi2_sf(Qs[done], sizes[done])
        quant = np.where(done, float(dist.norm_ppf(0.975)), np.nan)
    else:
        pvals[done] = dist.f_sf(Qs[done] / sizes[done] / scales[done], sizes[done], dfs[done])
        quant = np.full(labels.size, np.nan)
        quant[done] = dist.t_ppf(0.975, dfs[done])
    for k in np.flatnonzero(done):
        q[order[starts[k]:ends[k]]] = quant[k]
    return {"deleted": deleted, "sd": sd, "q": q, "p": pvals, "stat": statv, "labels": labels,
            "rank": np.array(rank)}


def loo_entries(loo: dict[str, np.ndarray], lines: Sequence[int], quantity: Sequence[str], measured: np.ndarray,
                sigma: np.ndarray) -> list[dict[str, Any]]:
    """fit.json's ``leave_one_out``: per measured value, its trial's line, the value predicted by the fit without
    that trial and the 95 % prediction interval (natural units: ``sigma`` is each residual's weight divisor), and
    the trial's p-value."""
    sigma = np.broadcast_to(np.asarray(sigma, dtype=float), np.shape(measured))
    pred = measured - loo["deleted"] * sigma
    half = loo["q"] * loo["sd"] * sigma
    p_of = dict(zip(loo["labels"].tolist(), loo["p"].tolist(), strict=True))
    out = []
    for i in range(len(measured)):
        ok = bool(np.isfinite(pred[i]) and np.isfinite(half[i]))
        out.append({"line": int(lines[i]), "quantity": quantity[i], "measured": float(measured[i]),
                    "predicted": float(pred[i]) if ok else None, "low": float(pred[i] - half[i]) if ok else None,
                    "high": float(pred[i] + half[i]) if ok else None,
                    "p": None if not np.isfinite(p_of[int(lines[i])]) else float(p_of[int(lines[i])])})
    return out


def name_outliers(summary: dict[str, Any], lines: Sequence[int], p: np.ndarray, what: str,
                  table: Table) -> list[int]:
    """Warn of the trials (by their file line) outside their leave-one-out interval at the family-wise level
    ``OUTLIER_LEVEL`` (0.05/n each); returns those lines."""
    p = np.asarray(p, dtype=float)
    n = int(np.isfinite(p).sum())
    if n == 0:
        return []
    cut = OUTLIER_LEVEL / n
    bad = [int(lines[i]) for i in np.flatnonzero(np.isfinite(p) & (p < cut))]
    if bad:
        worst = float(np.nanmin(p))
        warn(summary, Code.OUTLIER, f"{what}(s) on {table.named(bad)} lie outside the interval the "
                                    f"other {what}s predict for them (leave-one-out, smallest p = {worst:.2g}, below "
                                    f"{cut:.2g} = 5 % over {n} {what}s): a misread or mistyped value, or one "
                                    "the model does not describe (see leave_one_out in fit.json)")
    return bad


# --------------------------------------------------------------------------------------------------------------
# conventions

@dataclass(frozen=True)
class Reading:
    """Another reading of the data: its name, how the user selects it, and its fit's misfit (−2 log L, or χ²)."""

    name: str
    how: str  # the option or header that selects it
    misfit: float
    result: str = ""  # what the fit gives when the data are read so, for the message
    code: Code = Code.CONVENTION  # what the warning is about, when this reading is the best


CONVENTION_MARGIN = 10.0  # −2 log L lower by this much (a likelihood ratio of e⁵ ≈ 150) is "far better"


def better_reading(summary: dict[str, Any], as_read: float, others: Sequence[Reading]) -> Reading | None:
    """Warn when another reading of the data fits far better than the one taken; returns the best such reading."""
    best = min(others, key=lambda o: o.misfit, default=None)
    if best is None or not (as_read - best.misfit > CONVENTION_MARGIN):
        return None
    warn(summary, best.code, f"the data fit far better read as {best.name} (−2 log-likelihood "
                             f"{best.misfit:.4g} against {as_read:.4g} as read"
                             f"{'; read so, ' + best.result if best.result else ''}): if so, {best.how}")
    return best
