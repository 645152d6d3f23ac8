"""``resal fit rebound | cushion | drop``: Newton's e and Résal's ε from rebounds on an immovable mass.

§I n°5, eq. (9): a ball striking an immovable mass leaves with V1 = −(1 − ε)/(1 + ε)·V0, so the ratio of the
speeds is Newton's e = (1 − ε)/(1 + ε) (the paper's ν of §III); a ball dropped from h0 rises to h1 = e²·h0 (free
fall, V = √(2gh)). The fit is that of ``trials.fit_ratio`` (speeds: c = e; heights: c = e²) under a noise model
that the data choose or the user gives, or ``trials.fit_ratio_both`` when the impact is measured with a known σ
too (``--sigma-in``); the 95 % interval respects 0 ≤ e ≤ 1 (``trials.bounded_interval``).
Beside it: a seeded pairs bootstrap, a test of speed dependence and, where the data support one, a low-order law
e(v); and the checks of ``fit.checks``: χ² against a given σ or the scatter against a plausible one, lack of fit,
each trial predicted from the others, the inputs' plausible ranges, and refusals that name the other reading.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import InputError
from ...lazy import lazy
from ...mechanics import impact
from ...results import FigureSpec, layer
from ...series import Series, Table, as_table, header_names, read_series, unit_label
from .. import distributions as dist
from ..checks import (
    CHI2_P,
    Code,
    Reading,
    better_reading,
    leave_one_out,
    loo_entries,
    name_outliers,
    noise_plausible,
    plausible_columns,
    plausible_ratio,
    warn,
)
from ..estimators.trials import (
    AUTO_MARGIN,
    Noise,
    RatioFit,
    bootstrap,
    bounded_interval,
    fit_ratio,
    fit_ratio_both,
    poly_law,
    select_law,
    transform_interval,
)
from .common import (
    MIN_BOOT_TRIALS,
    FitOptions,
    FitOutcome,
    G,
    base_summary,
    boot_note,
    check_sigma,
    columns_read,
    estimate_row,
    paper_value,
    today,
)

special = lazy("scipy.special", globals())

BOUND_TOL = 1e-12  # e this close to 0 or 1 sits on the bound of its admissible range
DIMS = {"V0": "speed", "V1": "speed", "u0": "speed", "u1": "speed", "h0": "length", "h1": "length"}
SETS = {"signed": ("V0", "V1"), "unsigned": ("u0", "u1"), "heights": ("h0", "h1")}

# What the paper says that a user's rebounds can be set beside (compared against, never used in the fit).
CORIOLIS_RATIO = ("Coriolis's ratio of the normal speeds after and before a cushion impact (§I n°5)", 0.55, 220)
CORIOLIS_RANGE = ("Coriolis: that ratio 'differs little' from 0.55 for speeds up to 7 m/s (§I n°5)", 7.0, 220)
MARBLE_RATIO = ("Résal: a ball dropped on marble rises to 2/3 of its height, e = √(2/3) (§I n°5)", 2 / 3, 224)


def _which(src: Table, kind: str, speeds: str | None) -> str:
    """Which set of columns the header holds: signed speeds, unsigned speeds or heights."""
    line, names = header_names(src, {c for cols in SETS.values() for c in cols})
    if len(names) > 1 and not {"V0", "V1", "u0", "u1", "h0", "h1"} & names:
        raise InputError(src.at(line), "the header names none of the columns of a rebound: expected V0,V1 "
                                           "(signed velocities), u0,u1 (speeds) or h0,h1 (heights), each with an "
                                           "optional unit (V0_cmps, h0_mm); names are case-sensitive")
    if {"h0", "h1"} & names:
        found = "heights"
    elif {"u0", "u1"} & names:
        found = "unsigned"
    else:
        found = "signed"
    if kind == "cushion" and found == "heights":
        raise InputError(src.where, "a cushion rebound is measured by speeds (columns V0,V1 or u0,u1), not heights; "
                                    "for drop heights use `resal fit drop`")
    if speeds is not None and found == "heights":
        raise InputError(f"--speeds {speeds}", f"the file gives heights (h0,h1, {src.at(line)}): --speeds says how "
                                               "to read speed columns; leave it out")
    if speeds == "unsigned" and found == "signed":
        found = "unsigned-V"
    if speeds == "signed" and found == "unsigned":
        raise InputError(src.where, "--speeds signed, but the header has u0,u1 (speeds, unsigned): write V0,V1 "
                                    "for signed velocities or leave --speeds out")
    return found


def _check_options(opts: FitOptions, which: str) -> None:
    """Options that contradict one another, or the file, are refused (one message): none is silently ignored."""
    if opts.sigma is not None and opts.noise is not Noise.AUTO:
        raise InputError(f"--noise {opts.noise.value}", f"--sigma {opts.sigma:g} gives the outcome's noise already "
                                                        "(σ on each trial): leave --noise out, or leave --sigma out "
                                                        f"to have a {opts.noise.value} noise estimated")
    if opts.sigma_in is not None and opts.noise is Noise.PROPORTIONAL:
        raise InputError("--noise proportional", f"--sigma-in {opts.sigma_in:g} fits errors in both variables with "
                                                 "a constant noise on each (σ_in on the impact, σ on the outcome): "
                                                 "a proportional noise is not supported with it; leave one out")
    if which != "heights" and opts.g != G:
        raise InputError(f"--g {opts.g:g}", "the file gives speeds, and g serves only to turn drop heights into "
                                            "impact speeds: leave --g out")


# A measured rebound may exceed its measured impact by its noise when e is near 1: a row is refused when it does so
# by more than 5 σ (σ and σ_in given) or, without σ, by 8 % of the impact speed (4 σ of a 2 % speed measurement;
# (1.08)² − 1 of a drop height).
EXCESS_SIGMAS = 5.0
EXCESS_SLACK = 0.08


def _read(src: Table, which: str, sigma: float | None = None, sigma_in: float | None = None
          ) -> tuple[Series, np.ndarray, np.ndarray]:
    """x (impact: V0 or h0) and y (|V1| or h1) in SI, with the names as written; every impossible row refused,
    naming the option or header that would read it otherwise. ``sigma``, ``sigma_in``: the outcome's and the
    impact's σ as given (their columns' units), for the excess a row's noise allows."""
    cols = SETS["signed" if which == "unsigned-V" else which]
    signed = which == "signed"
    heights = which == "heights"
    # a signed V0 ≤ 0 is refused below, with the hint of a mirrored axis
    s = read_series(src, cols, min_rows=2, positive=() if signed else (cols[0],), dims=DIMS)
    a, b = s[cols[0]], s[cols[1]]
    wa, wb = s.written[cols[0]], s.written[cols[1]]
    n = a.size
    if signed:
        for i in range(n):
            if a[i] <= 0:
                hint = "V0 is the impact velocity, > 0 towards the obstacle (the paper's convention)"
                if np.all(a < 0) and np.all(b >= 0):  # every row signed the other way: mirrored, or swapped
                    hint = (f"every '{wa}' is negative and every '{wb}' positive and larger: the columns may be "
                            "swapped (swap the two names in the header)" if np.all(b > -a) else
                            f"every '{wa}' is negative and every '{wb}' positive: the axis points away from the "
                            "obstacle; negate both columns, or give speeds (name the columns u0,u1, or pass "
                            "--speeds unsigned)")
                j = list(s.written).index(cols[0]) + 1
                raise InputError(s.at(i), f"column '{wa}' (#{j}): expected a positive number, got "
                                          f"{a[i] / s.factors[cols[0]]:g}; {hint}")
    if sigma is not None:
        tol = np.full(n, EXCESS_SIGMAS * math.hypot(sigma * s.factors[cols[1]],
                                                     (sigma_in or 0.0) * s.factors[cols[0]]))
        allowed = f"{EXCESS_SIGMAS:g} σ of the noise"
    else:
        slack = (1 + EXCESS_SLACK) ** (2 if heights else 1) - 1
        tol = slack * a + EXCESS_SIGMAS * (sigma_in or 0.0) * s.factors[cols[0]]
        allowed = f"{slack:.0%} of {'h0' if heights else 'V0'} (give --sigma to judge by the noise)"
    over = np.abs(b) > a
    swap_hint = (f"{int(over.sum())} of {n} rows exceed it: the columns may be swapped (the impact goes under "
                 f"'{wa}', the rebound under '{wb}': swap the two names in the header)"
                 + ("" if over.all() else ", or this row mistyped"))
    fa, fb = s.factors[cols[0]], s.factors[cols[1]]
    if fa != fb and np.all(np.abs(b) / fb <= (1 + EXCESS_SLACK) * a / fa):  # as written, in one unit, they rebound
        ua, ub = s.units.get(cols[0]), s.units.get(cols[1])
        fix = (f"if both are in {unit_label(ua)}, name the rebound '{cols[1]}_{ua}'" if ua and not ub else
               f"if both are in {unit_label(ub)}, name the impact '{cols[0]}_{ub}'" if ub and not ua else
               "if both are in one unit, write that unit in both names")
        swap_hint = (f"the two columns are read in different units ('{wa}': {s.unit_text[cols[0]]}, '{wb}': "
                     f"{s.unit_text[cols[1]]}), and in one unit every row would rebound slower than it arrived: "
                     f"{fix}")
    for i in range(n):
        if heights:
            if b[i] < 0:
                raise InputError(s.at(i), f"column '{wb}': expected a rebound height ≥ 0 (measured up from the "
                                          f"surface), got {b[i]:g} m")
            if b[i] > a[i] + tol[i]:
                raise InputError(s.at(i), f"the rebound h1 = {b[i]:g} m is higher than the drop h0 = {a[i]:g} m: "
                                          f"expected h1 ≤ h0 (a ball cannot gain energy in the impact; ε ≥ 0), "
                                          f"here beyond {allowed}; {swap_hint}")
        elif signed:
            if b[i] > 0:
                raise InputError(s.at(i), f"column '{wb}': expected the signed velocity after the impact, ≤ 0 "
                                          f"(opposite V0 = {a[i]:g}), got {b[i]:g}; the file must give signed "
                                          "velocities: write a rebound speed u as V1 = -u, or name the columns "
                                          "u0,u1 (speeds), or pass --speeds unsigned")
        elif b[i] < 0:
            said, other = (("--speeds unsigned", "leave --speeds unsigned out") if which == "unsigned-V" else
                           ("the header u0,u1", "name the columns V0,V1"))
            raise InputError(s.at(i), f"column '{wb}': expected a speed ≥ 0 (unsigned, as {said} says), got "
                                      f"{b[i]:g}; for signed velocities (V1 ≤ 0) {other}")
        if not heights and abs(b[i]) > a[i] + tol[i]:
            raise InputError(s.at(i), f"the ball leaves at |V1| = {abs(b[i]):g} m/s, faster than it arrived "
                                      f"(V0 = {a[i]:g}): expected |V1| ≤ V0 (ε ≥ 0), here beyond {allowed}; "
                                      f"{swap_hint}")
    return s, a, np.abs(b)


def _check_sigma_in(sigma_in: float | None, x_written: np.ndarray, unit: str, col: str) -> None:
    """A given σ of the impact: positive, finite, between 1e-12 and 1e6 times the largest impact (its unit)."""
    if sigma_in is None:
        return
    if not (math.isfinite(sigma_in) and sigma_in > 0):
        raise InputError(f"--sigma-in {sigma_in:g}", "expected a positive number, finite (a standard deviation)")
    scale = float(np.max(np.abs(x_written)))
    if not 1e-12 * scale <= sigma_in <= 1e6 * scale:
        raise InputError(f"--sigma-in {sigma_in:g}", f"expected a standard deviation of column '{col}' in "
                                                     f"[{1e-12 * scale:.3g}, {1e6 * scale:.3g}] {unit}")


def _fit(x: np.ndarray, y: np.ndarray, noise: Noise, sigma: float | None, sigma_in: float | None) -> RatioFit:
    """The ratio fit, with errors in both variables when the impact's σ is given."""
    if sigma_in is not None:
        return fit_ratio_both(x, y, sigma_in, sigma)
    return fit_ratio(x, y, noise, sigma)


def fit_rebounds(kind: str, source: Path | Table, opts: FitOptions) -> FitOutcome:
    """Fit e (and ε) to the rebounds of ``src``; see the module docstring."""
    src = as_table(source)  # a CSV file read once, or a program's arrays
    which = _which(src, kind, opts.speeds)
    _check_options(opts, which)
    s, x, y = _read(src, which, opts.sigma, opts.sigma_in)
    heights = which == "heights"
    p = 2 if heights else 1  # y = e^p · x
    in_col, out_col = SETS["heights" if heights else ("unsigned" if which == "unsigned" else "signed")]
    factor, unit_text = s.factors[out_col], s.unit_text[out_col]
    sigma_si = None if opts.sigma is None else opts.sigma * factor
    sigma_in_si = None if opts.sigma_in is None else opts.sigma_in * s.factors[in_col]
    check_sigma(opts.sigma, [x / factor, y / factor], unit_text)
    _check_sigma_in(opts.sigma_in, x / s.factors[in_col], s.unit_text[in_col], s.written[in_col])
    n = x.size
    fr = _fit(x, y, opts.noise, sigma_si, sigma_in_si)
    bi = bounded_interval(fr, 0.0, 1.0)
    v = np.sqrt(2 * opts.g * x) if heights else x  # impact speed
    e_i = (y / x) ** (1 / p)

    def e_of(c: np.ndarray) -> np.ndarray:
        return np.clip(np.asarray(c, dtype=float), 0.0, None) ** (1 / p)

    e = float(e_of(np.array([bi.value]))[0])
    e_ci, _ = transform_interval(bi.ci95, e_of, 0.0, 1.0)
    clipped = bi.reaches is not None
    # heights: se(e) = se(c)/(2e) by the delta method; at e = 0 (no rebound at all) that is 0/0, and the half-width
    # of e's interval, mapped from c's, stands in for it
    se_e = fr.stderr if p == 1 else (fr.stderr / (2 * e) if e > 0 else (e_ci[1] - e_ci[0]) / (2 * fr.quantile))
    eps = float(impact.eps_from_newton(e))
    eps_ci, _ = transform_interval(e_ci, impact.eps_from_newton, 0.0, 1.0)
    se_eps = 2 / (1 + e) ** 2 * se_e

    def refit(idx: np.ndarray) -> list[float]:
        if np.unique(idx).size < 2:
            raise ValueError("degenerate resample")
        c = _fit(x[idx], y[idx], fr.noise, sigma_si, sigma_in_si).value
        ee = float(e_of(np.array([min(c, 1.0)]))[0])
        return [ee, float(impact.eps_from_newton(ee))]

    boot = bootstrap(refit, lambda rng: rng.integers(0, n, n), ("e", "eps"), opts.resamples, opts.seed,
                     opts.progress) if opts.resamples and n >= MIN_BOOT_TRIALS else None
    # of e, where the unbounded fit ended (at or beyond the edge); ε's bound is the other
    at_bound = "upper" if fr.value >= 1.0 - BOUND_TOL else ("lower" if fr.value <= BOUND_TOL else None)
    eps_bound = {"upper": "lower", "lower": "upper", None: None}[at_bound]
    noise_text = _noise_label(fr, opts, unit_text, s, in_col, out_col)
    how = "maximum likelihood with errors in both variables" if fr.sigma_x is not None else "weighted least squares"
    method = f"{how} on §I eq. (9), {noise_text}; 95 % interval: {INTERVAL_TEXT}"
    note = _bound_note(bi.reaches, heights) if clipped else ""
    fits = [
        estimate_row("e", "e (Newton's restitution)", e, se_e, e_ci, method=method,
                     boot=None if boot is None else boot.ci95[0], clipped=clipped, at_bound=at_bound, note=note,
                     bound_aware=True),
        estimate_row("eps", "ε (Résal, eq. 9: ε = (1 − e)/(1 + e))", eps, se_eps, eps_ci, method=method,
                     boot=None if boot is None else boot.ci95[1], clipped=clipped,
                     at_bound=eps_bound, note=note, bound_aware=True),
    ]
    # speed dependence: the per-trial e against the impact speed, with the weights of the noise model
    w_e = np.asarray(fr.weights) * (p * max(e, 1e-12) ** (p - 1)) ** 2
    # a given σ that the scatter contradicts (χ² p < 1 %) cannot judge a law: the F tests estimate the scale instead
    sigma_holds = fr.noise is Noise.GIVEN and not (fr.chi2_p is not None and fr.chi2_p < CHI2_P)
    law, tests, laws = select_law(v, e_i, w_e, absolute=sigma_holds)
    flat = _no_scatter(e_i)
    if flat:  # every trial gives the same e: each law fits exactly, and no F test has a scale to judge by
        law, tests = laws[0], [dataclasses.replace(t, statistic=0.0, p=1.0) for t in tests]
    summary = base_summary(kind, src, n, columns_read(s, DIMS), opts)
    summary["fits"] = fits
    summary["noise"] = _noise_summary(fr, opts, heights, s.unit_text[in_col])
    summary["goodness"] = _goodness(fr, x, y, w=np.asarray(fr.weights))
    lof = summary["goodness"]["lack_of_fit"]
    _duplicates(summary, s, x, y)
    if lof is not None and lof["p"] < 0.01:
        said = (f"F = {lof['F']:.3g}, p = {lof['p']:.2g}" if lof["F"] is not None else
                "the repeats agree exactly while the impact speeds' means differ")
        warn(summary, Code.LACK_OF_FIT, f"lack of fit: trials repeated at one impact speed agree with one another "
                                        f"far better than with a constant e ({said}); e above is an average, not "
                                        "a law of your data")
    # one parameter, linear in the data: determined by any trial (x > 0); the rank and the singular value say so
    sv = math.sqrt(float(np.sum(fr.weights))) if math.isfinite(float(np.sum(fr.weights))) else math.inf
    summary["identifiability"] = [{"data": src.name, "parameters": ["e" if p == 1 else "e²"], "rank": 1,
                                   "singular_values": [sv if math.isfinite(sv) else None], "condition_number": 1.0,
                                   "null_directions": [], "identified_combinations": []}]
    summary["speed_dependence"] = {
        "tests": [{"orders": [t.lower, t.higher], "test": t.test,
                   "statistic": t.statistic if _finite(t.statistic) else None, "p": t.p} for t in tests],
        "order": law.order,
        "verdict": (f"every trial gives the same e = {float(e_i[0]):.4g} (no scatter): no evidence of a speed "
                    "dependence" if flat else _law_verdict(law.order, tests)),
        "law": None if law.order == 0 else {"coefficients": list(law.coefficients), "stderr": list(law.stderr),
                                            "v_range": list(law.v_range), "text": _law_text(law)},
    }
    if law.order:
        test = _test_text(_against_constant(law.order, tests))
        warn(summary, Code.SPEED_LAW, f"the data reject a constant e ({test}): e above is "
                                      f"the mean over {law.v_range[0]:.3g}–{law.v_range[1]:.3g} m/s; the law "
                                      f"{_law_text(law)} describes them")
    _check_fit(summary, s, fr, x, y, heights, in_col, out_col, (law, v, e_i, w_e, sigma_holds),
               _judging_models(fr, opts))
    summary["per_trial"] = [{"line": s.lines[i], "impact_speed": float(v[i]), "e": float(e_i[i]),
                             "residual": fr.residuals[i]} for i in range(n)]
    summary["comparison"] = _comparisons(kind, heights, e, e_ci, law, v, tests, lof)
    summary["bootstrap"] = None if boot is None else {"resamples": boot.resamples, "seed": boot.seed,
                                                      "failed": boot.failed, "kind": "pairs (trials resampled)",
                                                      "note": boot_note(kind)}
    rows = tuple((s.lines[i], float(x[i]), float(y[i]), float(v[i]), float(e_i[i]), fr.residuals[i]) for i in range(n))
    headers = ("line", "h0 (m)" if heights else "V0 (m/s)", "h1 (m)" if heights else "|V1| (m/s)",
               "impact speed (m/s)", "e", "residual (m)" if heights else "residual (m/s)")
    return FitOutcome(summary, _figures(kind, v, e_i, e, e_ci, law, fr, heights, laws),
                      headers, rows)


# the interval of e (and of ε, mapped), as the method line says it
INTERVAL_TEXT = "profile likelihood within 0 ≤ e ≤ 1, ordered by likelihood ratio (Feldman & Cousins 1998)"
# measured (tests/test_fit_rebound_checks.py): 1000 seeded series of 8 trials at each e, speeds with 2 % noise and
# heights with 4 % noise or σ = 10 mm given: 94.0–94.8 %
BOUND_COVERAGE = "it covered 94–95 % of 1000 synthetic series of 8 trials at e = 0.95, 0.98 and 0.995"
NOISE_REL_LIMIT = 0.25  # a scatter of the outcome beyond 25 % of its size is no rebound measurement
NOISE_FLOOR = 0.1  # … of its size, or of a tenth of the impact when the rebound is slower (measured to resolution)


def _bound_note(reaches: str | None, heights: bool) -> str:
    end = {"upper": "up to e = 1 (ε = 0)", "lower": "down to e = 0 (ε = 1)",
           "both": "anywhere in 0 ≤ e ≤ 1"}[reaches or "upper"]
    return f"the data admit {'e² = h1/h0' if heights else 'e'} {end}: the interval ends there ({BOUND_COVERAGE})"


def _check_fit(summary: dict[str, Any], s: Series, fr: RatioFit, x: np.ndarray, y: np.ndarray, heights: bool,
               in_col: str, out_col: str, by_law: tuple[Any, np.ndarray, np.ndarray, np.ndarray, bool],
               models: tuple[Noise, ...] = ()) -> None:
    """The fit checks itself (``fit.checks``): χ² against a given σ, the scatter against a plausible one, each trial
    predicted from the others (by the law e(v) when the data reject a constant e), the impacts' plausible range."""
    out_name = "h1" if heights else "|V1|"
    unit = s.unit_text[out_col]
    factor = s.factors[out_col]
    contradicted = fr.chi2_p is not None and fr.chi2_p < CHI2_P
    if contradicted:
        warn(summary, Code.CHI2, f"the scatter exceeds the given σ: reduced χ² = {fr.chi2 / fr.dof:.3g} "
                                 f"(p = {fr.chi2_p:.2g}); the interval from σ is too narrow")
    elif fr.noise is not Noise.GIVEN:
        size = max(float(np.median(y)), NOISE_FLOOR * float(np.median(x)))
        if fr.noise is Noise.PROPORTIONAL:  # sd(yᵢ) = s·xᵢ: relative to the outcome, s/c
            noise_plausible(summary, 100 * fr.scale / max(fr.value, NOISE_FLOOR), 100 * NOISE_REL_LIMIT,
                            f"{out_name} (relative to itself)", "%")
        else:
            noise_plausible(summary, fr.scale / factor, NOISE_REL_LIMIT * size / factor, out_name, unit)
    if fr.sigma_x is not None and fr.noise is not Noise.GIVEN and fr.common_scale < 1.0:
        chi2 = fr.dof * fr.common_scale**2  # S(ĉ) with σ = 0: χ² with n − 1 degrees of freedom if σ_in is right
        p_low = float(dist.chi2_cdf(chi2, fr.dof))
        if p_low < 0.01:
            warn(summary, Code.ASSUMED, f"σ_in = {summary['noise']['errors_in_both']['sigma_in_as_given']} on "
                                        f"{s.written[in_col]} is more than the scatter about the fit allows (χ² = "
                                        f"{chi2:.3g} with {fr.dof} degrees of freedom, P(χ² ≤ it) = {p_low:.2g}): σ "
                                        f"on {s.written[out_col]} was taken as 0 and both scaled by "
                                        f"{fr.common_scale:.3g}, so their ratio is assumed, not measured; check "
                                        "--sigma-in")
    if fr.value > 1.0 and fr.stderr > 0:  # e above 1 beyond its noise: the impact and the rebound exchanged?
        better_reading(summary, fr.deviance(1.0) - fr.deviance(fr.value), [Reading(
            f"the columns swapped ({'e² = h0/h1' if heights else 'e = V0/|V1|'} = {1 / fr.value:.4g} ≤ 1)",
            f"swap the two names in the header ({s.written[in_col]}, {s.written[out_col]})", 0.0)])
    summary["leave_one_out"] = _leave_one_out(summary, s, fr, x, y, heights, by_law, not contradicted, models)
    for msg in plausible_columns(s, {in_col: "drop-height" if heights else "lab-speed"}, DIMS):
        warn(summary, Code.UNIT, msg)
    # against each other: a rebound faster than ten times or slower than a hundredth of its impact (squared for
    # heights) is no rebound, whatever units the header declares
    bounds, typical = ((1e-4, 100.0), (0.0025, 1.0)) if heights else ((0.01, 10.0), (0.05, 1.0))
    for msg in plausible_ratio(s, out_col, in_col, DIMS, bounds, "the rebound over the impact", typical):
        warn(summary, Code.UNIT, msg)


def _judging_models(fr: RatioFit, opts: FitOptions) -> tuple[Noise, ...]:
    """The noise models under which a trial must lie outside its interval to be named an outlier: both when the
    data chose one (``--noise auto``: the margin favours the proportional model on purpose, and under the wrong one
    sound trials at the ends of the range look far off), the one the user told (``--noise``); none beyond the fit's
    own when σ is given (``--sigma``, ``--sigma-in``)."""
    if opts.sigma is not None or fr.sigma_x is not None:
        return ()
    return (Noise.CONSTANT, Noise.PROPORTIONAL) if opts.noise is Noise.AUTO else (opts.noise,)


def _model_weights(noise: Noise, x: np.ndarray) -> np.ndarray:
    """The weights of the per-trial ratio (or e) under a noise model: constant on the outcome (xᵢ²), proportional
    to the impact (1)."""
    return np.ones_like(x) if noise is Noise.PROPORTIONAL else x * x


def _loo_p_law(order: int, v: np.ndarray, e_i: np.ndarray, w: np.ndarray, lines: np.ndarray) -> np.ndarray:
    """Each trial's leave-one-out p about the law e(v) of this order, fitted with weights ``w`` (scale estimated)."""
    law = poly_law(v, e_i, w, order)
    sw = np.sqrt(w)
    X = np.vander(v, order + 1, increasing=True)
    return leave_one_out(sw * (e_i - law(v)), sw[:, None] * X, lines, sigma_known=False)["p"]


def _loo_p_ratio(x: np.ndarray, y: np.ndarray, noise: Noise, lines: np.ndarray) -> np.ndarray:
    """Each trial's leave-one-out p about the constant ratio fitted under ``noise`` (scale estimated)."""
    alt = fit_ratio(x, y, noise)
    sd = x / np.sqrt(np.asarray(alt.weights))
    return leave_one_out(np.asarray(alt.residuals) / sd, x / sd, lines, sigma_known=False)["p"]


def _leave_one_out(summary: dict[str, Any], s: Series, fr: RatioFit, x: np.ndarray, y: np.ndarray, heights: bool,
                   by_law: tuple[Any, np.ndarray, np.ndarray, np.ndarray, bool], sigma_holds: bool,
                   models: tuple[Noise, ...] = ()) -> list[dict[str, Any]]:
    """Each trial's outcome predicted from the other trials, with its 95 % prediction interval (``checks.
    leave_one_out``, exact for these linear fits): by the constant c (weighted residuals (yᵢ − c xᵢ)/σᵢ,
    σᵢ = xᵢ/√wᵢ), or by the law e(v) when one was taken (its weighted polynomial fit, mapped to y = eᵖ·x).
    A σ that the scatter contradicts is not used: the scale is then estimated. The interval is the fit's noise
    model's; a trial's p is the largest over ``models`` too (``_judging_models``), so that it is named an outlier
    only when it is one whichever of those noise models holds."""
    law, v, e_i, w_e, law_absolute = by_law
    lines = np.asarray(s.lines)
    n = x.size
    p = 2 if heights else 1
    name = "h1" if heights else "|V1|"
    w = np.asarray(fr.weights)
    ok = bool(np.all(np.isfinite(w)) and np.all(w > 0) and np.all(np.isfinite(w_e)) and np.all(w_e > 0))
    by_model: dict[str, np.ndarray] = {}
    if law.order and ok:
        if not law_absolute:  # the law's own noise model: the constant-c fit's was chosen against a constant e
            w_e = (_model_weights(models[0], x) if len(models) == 1 else _law_weights(law.order, v, e_i, x))
            law = poly_law(v, e_i, w_e, law.order)
            if len(models) > 1:
                by_model = {m.value: _loo_p_law(law.order, v, e_i, _model_weights(m, x), lines) for m in models}
        sw = np.sqrt(w_e)
        X = np.vander(v, law.order + 1, increasing=True)
        loo = leave_one_out(sw * (e_i - law(v)), sw[:, None] * X, lines, sigma_known=law_absolute)
        loo["p"] = _largest(loo["p"], by_model)
        entries = loo_entries(loo, lines, [name] * n, e_i, 1 / sw)
        for en, xi, yi in zip(entries, x, y, strict=True):
            en["measured"] = float(yi)
            for k in ("predicted", "low", "high"):
                if en[k] is not None:
                    en[k] = float(max(en[k], 0.0) ** p * xi)
    else:
        sd = x / np.sqrt(w) if ok else np.ones_like(x)
        res = np.asarray(fr.residuals)
        loo = leave_one_out(res / sd, x / sd, lines, sigma_known=fr.noise is Noise.GIVEN and sigma_holds)
        if ok and len(models) > 1:
            by_model = {m.value: _loo_p_ratio(x, y, m, lines) for m in models}
        loo["p"] = _largest(loo["p"], by_model)
        entries = loo_entries(loo, lines, [name] * n, y, sd)
    p_of = {m: dict(zip(loo["labels"].tolist(), pm.tolist(), strict=True)) for m, pm in by_model.items()}
    for en in entries:
        en["unit"] = "m" if heights else "m/s"
        if p_of:
            en["p_by_noise"] = {m: (float(pm[en["line"]]) if math.isfinite(pm[en["line"]]) else None)
                                for m, pm in p_of.items()}
    name_outliers(summary, lines, loo["p"], "trial", s.table)
    return entries


def _largest(p: np.ndarray, by_model: dict[str, np.ndarray]) -> np.ndarray:
    """Per trial the largest p of the fit's own and of each noise model's (NaN, not judged, where any is)."""
    out = np.asarray(p, dtype=float)
    for pm in by_model.values():
        out = np.maximum(out, pm)
    return out


def _law_weights(order: int, v: np.ndarray, e_i: np.ndarray, x: np.ndarray) -> np.ndarray:
    """The weights of the per-trial e about a law e(v), of the likelier noise model (as ``trials.fit_ratio``
    chooses for a constant): constant noise on the outcome (wᵢ = xᵢ²) or proportional to the impact (wᵢ = 1)."""
    best, best_ll = np.ones_like(x), -math.inf
    for w, margin in ((np.ones_like(x), AUTO_MARGIN), (x * x, 0.0)):
        r = e_i - poly_law(v, e_i, w, order)(v)
        s2 = max(float(np.mean(w * r * r)), 1e-300)
        ll = -0.5 * x.size * math.log(s2) + 0.5 * float(np.sum(np.log(w))) + margin
        if ll > best_ll:
            best, best_ll = w, ll
    return best


def _noise_summary(fr: RatioFit, opts: FitOptions, heights: bool, in_unit: str) -> dict[str, Any]:
    out: dict[str, Any] = {
        "model": fr.noise.value,
        "chosen_by": "--sigma" if opts.sigma is not None else (
            "--sigma-in (constant noise on both)" if opts.sigma_in is not None else
            "--noise" if opts.noise is not Noise.AUTO else "likelihood"),
        "scale": fr.scale,
        "scale_unit": ("1 (relative)" if fr.noise is Noise.PROPORTIONAL else ("m" if heights else "m/s")),
        "loglik": fr.loglik, "dof": fr.dof, "quantile": fr.quantile}
    if fr.sigma_x is not None:
        out["errors_in_both"] = {"sigma_in": fr.sigma_x, "sigma_out": fr.sigma_y, "unit": "m" if heights else "m/s",
                                 "sigma_in_as_given": f"{opts.sigma_in:g} {in_unit}",
                                 "sigma_out_from": "--sigma" if opts.sigma is not None else "moments",
                                 "common_scale": fr.common_scale, "iterations": fr.iterations}
    return out


def _noise_label(fr: RatioFit, opts: FitOptions, unit: str, s: Series, in_col: str, out_col: str) -> str:
    what = s.written[out_col]
    if fr.sigma_x is not None:
        given_in = f"σ_in = {opts.sigma_in:g} {s.unit_text[in_col]} on {s.written[in_col]} given"
        if opts.sigma is not None:
            return f"{given_in}, σ = {opts.sigma:g} {unit} on {what} given (normal quantile)"
        return (f"{given_in} and taken as exact, σ on {what} estimated by moments (Σr²/(n − 1) − c²σ_in², at "
                f"least 0), so the ratio σ_in/σ is the estimated one and their common scale is estimated too "
                f"({fr.common_scale:.3g}; Student's t)")
    if fr.noise is Noise.GIVEN:
        return f"σ = {opts.sigma:g} {unit} on {what} given (normal quantile)"
    if fr.noise is Noise.PROPORTIONAL:
        return f"noise on {what} proportional to the impact, estimated (Student's t)"
    return f"constant noise on {what}, estimated (Student's t)"


def _exact_repeats(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Whether each row repeats an earlier row exactly, impact and outcome (a row copied twice, or a repeat
    that read the same to the last digit)."""
    seen: set[tuple[float, float]] = set()
    out = np.zeros(x.size, bool)
    for i, key in enumerate(zip(x.tolist(), y.tolist(), strict=True)):
        out[i] = key in seen
        seen.add(key)
    return out


def _duplicates(summary: dict[str, Any], s: Series, x: np.ndarray, y: np.ndarray) -> None:
    """Warn of rows that repeat others exactly when that looks like a copy: every row has an identical twin, or
    the repeats of an impact agree only through them (at every impact measured more than once, all its rows are
    identical). A few identical rows among repeats that otherwise scatter are what a reading to a coarse
    resolution gives, and are not named."""
    again = _exact_repeats(x, y)
    if not again.any():
        return
    _, inv, counts = np.unique(x, return_inverse=True, return_counts=True)
    _, twins = np.unique(np.stack([x, y]), axis=1, return_counts=True)
    if twins.min() < 2 and any(np.ptp(y[inv == k]) > 0 for k in np.flatnonzero(counts > 1)):
        return
    lines = [s.lines[i] for i in np.flatnonzero(again)]
    lof = summary["goodness"]["lack_of_fit"]
    out = " (the lack-of-fit test leaves them out)" if lof is not None and "exact_repeats_left_out" in lof else ""
    warn(summary, Code.DUPLICATE, f"the rows on {s.table.named(lines)} repeat other rows exactly (impact and "
                                  f"outcome): copied twice? they are counted as separate trials{out}")


def _goodness(fr: Any, x: np.ndarray, y: np.ndarray, w: np.ndarray) -> dict[str, Any]:
    """Reduced χ² (σ given) and, where trials repeat an impact, the pure-error lack-of-fit F test. Rows that repeat
    another exactly (impact and outcome: possibly copied) are left out of that test, so that a file copied twice
    does not look like repeats that agree perfectly (with them out, c is refitted to what is left; no test when no
    repeat is left), unless the impacts' means agree anyway (then there is no lack of fit, whatever the copies)."""
    out: dict[str, Any] = {"reduced_chi2": None if fr.chi2 is None else fr.chi2 / fr.dof, "chi2_p": fr.chi2_p,
                           "lack_of_fit": _pure_error(x, y, w, fr.value)}
    again = _exact_repeats(x, y)
    lof = out["lack_of_fit"]
    if again.any() and not (lof is not None and lof["F"] == 0.0):
        keep = ~again
        c = float(np.sum(w[keep] * y[keep] / x[keep]) / np.sum(w[keep]))
        lof = out["lack_of_fit"] = _pure_error(x[keep], y[keep], w[keep], c)
        if lof is not None:
            lof["exact_repeats_left_out"] = int(again.sum())
    return out


def _pure_error(x: np.ndarray, y: np.ndarray, w: np.ndarray, c: float) -> dict[str, Any] | None:
    """The pure-error lack-of-fit F test of the constant ratio c (None when no impact repeats); an infinite F (the
    repeats agree exactly while the impacts' means differ) is None, said in a note."""
    levels, inv = np.unique(x, return_inverse=True)
    if not 1 < levels.size < x.size:
        return None
    q = y / x
    sspe = 0.0
    for k in range(levels.size):
        m = inv == k
        qm = float(np.sum(w[m] * q[m]) / np.sum(w[m]))
        sspe += float(np.sum(w[m] * (q[m] - qm) ** 2))
    sse = float(np.sum(w * (q - c) ** 2))
    df1, df2 = levels.size - 1, x.size - levels.size
    between = max(sse - sspe, 0.0)
    if between <= 1e-12 * max(sse, 1e-300):  # the level means agree to rounding: no lack of fit to see
        return {"test": "pure error F", "F": 0.0, "df": [df1, df2], "p": 1.0}
    if sspe <= 1e-12 * sse:  # repeats agree exactly while the levels differ: F is infinite
        return {"test": "pure error F", "F": None, "df": [df1, df2], "p": 0.0,
                "note": "the repeats agree exactly while the impacts' means differ (F infinite)"}
    F = (between / df1) / (sspe / df2)
    return {"test": "pure error F", "F": F, "df": [df1, df2], "p": float(dist.f_sf(F, df1, df2))}


def _finite(v: float | None) -> bool:
    """A statistic that can be printed as a number (the estimators mark an infinite one 1e300)."""
    return v is not None and math.isfinite(v) and abs(v) < 1e300


def _no_scatter(e_i: np.ndarray) -> bool:
    """Every trial gives the same e (to rounding): there is no scatter to judge a speed dependence by."""
    return bool(np.ptp(e_i) <= 1e-12 * float(np.max(np.abs(e_i))))


def _test_text(t: Any) -> str:
    name = "F" if t.test == "F" else "Δχ²"
    if not _finite(t.statistic):
        return f"the higher order fits exactly, {name} infinite, p = {t.p:.2g}"
    return f"{name} = {t.statistic:.3g}, p = {t.p:.2g}"


def _against_constant(order: int, tests: list) -> Any:
    """The test of the constant against the law taken (order > 0), or the strongest test against it."""
    against = [t for t in tests if t.lower == 0]
    if order:
        return next(t for t in against if t.higher == order)
    return min(against, key=lambda t: t.p)


def _law_verdict(order: int, tests: list) -> str:
    if not tests:
        return "too few trials or speeds to test a speed dependence"
    t = _against_constant(order, tests)
    if order == 0:
        return (f"no evidence against a constant e (strongest test, constant against order {t.higher}: "
                f"{_test_text(t)})")
    return f"the data reject a constant e (constant against order {order}: {_test_text(t)})"


def _law_text(law: Any) -> str:
    terms = [f"{law.coefficients[0]:.4g}"]
    for j, c in enumerate(law.coefficients[1:], start=1):
        terms.append(f"{'+' if c >= 0 else '−'} {abs(c):.4g} v{'' if j == 1 else '²'}")
    return f"e(v) = {' '.join(terms)} (v in m/s, {law.v_range[0]:.3g} ≤ v ≤ {law.v_range[1]:.3g})"


def _comparisons(kind: str, heights: bool, e: float, ci: tuple[float, float], law: Any,
                 v: np.ndarray, tests: list, lof: dict | None) -> dict[str, Any]:
    paper = []
    if kind in ("cushion", "rebound"):
        paper.append(paper_value(CORIOLIS_RATIO[0], CORIOLIS_RATIO[1], CORIOLIS_RATIO[2], ci, "e"))
        if float(v.max()) <= CORIOLIS_RANGE[1]:
            if law.order or (lof is not None and lof["p"] < 0.01):
                said = "your data reject a constant e there"
            elif tests or lof is not None:
                said = "your data show no evidence against a constant e there"
            else:
                said = "your data cannot test it (too few trials or speeds)"
            paper.append({"claim": CORIOLIS_RANGE[0], "value": CORIOLIS_RANGE[1], "line": CORIOLIS_RANGE[2],
                          "verdict": f"your speeds lie in that range; {said}"})
    if kind in ("drop", "rebound"):
        er = math.sqrt(MARBLE_RATIO[1])
        paper.append(paper_value(MARBLE_RATIO[0], er, MARBLE_RATIO[2], ci, "e"))
    symbols = {"cushion": ("e_c",), "drop": ("e_t",), "rebound": ("e_c", "e_t")}[kind]
    modern = today(symbols, ci, "e")
    return {"paper": paper, "today": modern}


def _figures(kind: str, v: np.ndarray, e_i: np.ndarray, e: float, ci: tuple[float, float], law: Any, fr: Any,
             heights: bool, laws: list) -> tuple[FigureSpec, ...]:
    lo, hi = float(v.min()), float(v.max())
    pad = 0.05 * (hi - lo if hi > lo else hi)
    grid = np.linspace(max(lo - pad, 0.0), hi + pad, 101)
    layers = [layer("points", v, e_i, label="per trial: e = |V1|/V0" if not heights else "per trial: e = √(h1/h0)"),
              layer("band", [grid[0], grid[-1]], [ci[0], ci[0]], [ci[1], ci[1]], color="C1",
                    label="constant e: 95 % interval"),
              layer("line", [grid[0], grid[-1]], [e, e], color="C1", label=f"constant e = {e:.4g}")]
    if law.order:
        blo, bhi = law.band(grid, 1.96 if fr.noise is Noise.GIVEN else float(_t(law.dof)))
        layers += [layer("band", grid, blo, bhi, color="C2", label="e(v): 95 % band"),
                   layer("line", grid, law(grid), color="C2", label=f"e(v), order {law.order}")]
    if kind in ("cushion", "rebound"):
        layers.append(layer("line", [grid[0], grid[-1]], [CORIOLIS_RATIO[1]] * 2, color="C3", style="--",
                            label="Coriolis 0.55 (§I n°5)"))
    fit_fig = FigureSpec("fit", f"resal fit {kind}: e against the impact speed", "impact speed v (m/s)",
                         "Newton's e", tuple(layers),
                         caption=f"noise model: {fr.noise.value}; {len(v)} trials")
    res = np.asarray(fr.residuals)
    res_layers = [layer("points", v, res, label="residual of the constant-e fit"),
                  layer("line", [grid[0], grid[-1]], [0.0, 0.0], color="0.4", style=":")]
    res_fig = FigureSpec("residuals", f"resal fit {kind}: residuals against the impact speed",
                         "impact speed v (m/s)", "h1 − e²·h0 (m)" if heights else "|V1| − e·V0 (m/s)",
                         tuple(res_layers), caption="a trend says the constant e does not describe the data")
    return fit_fig, res_fig


def _t(dof: int) -> float:
    return float(special.stdtrit(max(dof, 1), 0.975))
