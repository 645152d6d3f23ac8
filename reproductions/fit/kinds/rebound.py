"""``resal fit rebound | cushion | drop``: Newton's e and Résal's ε from rebounds on an immovable mass.

§I n°5, eq. (9): a ball striking an immovable mass leaves with V1 = −(1 − ε)/(1 + ε)·V0, so the ratio of the
speeds is Newton's e = (1 − ε)/(1 + ε) (the paper's ν of §III); a ball dropped from h0 rises to h1 = e²·h0 (free
fall, V = √(2gh)). The fit is that of ``estimation.fit_ratio`` (speeds: c = e; heights: c = e²) under a noise
model that the data choose or the user gives, with a seeded pairs bootstrap beside it, a test of speed
dependence and, where the data support one, a low-order law e(v) over the speeds measured.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from scipy import special, stats

from ...errors import InputError
from ...mechanics import impact
from ...results import FigureSpec, layer
from ...series import Series, header_names, read_series
from ..checks import Code, warn
from ..estimators.trials import Noise, bootstrap, fit_ratio, select_law, transform_interval
from .common import (
    BOOT_NOTE,
    MIN_BOOT_TRIALS,
    FitOptions,
    FitOutcome,
    base_summary,
    check_sigma,
    columns_read,
    estimate_row,
    paper_value,
    today,
)

BOUND_TOL = 1e-12  # e this close to 0 or 1 sits on the bound of its admissible range
DIMS = {"V0": "speed", "V1": "speed", "u0": "speed", "u1": "speed", "h0": "length", "h1": "length"}
SETS = {"signed": ("V0", "V1"), "unsigned": ("u0", "u1"), "heights": ("h0", "h1")}

# What the paper says that a user's rebounds can be set beside (compared against, never used in the fit).
CORIOLIS_RATIO = ("Coriolis's ratio of the normal speeds after and before a cushion impact (§I n°5)", 0.55, 220)
CORIOLIS_RANGE = ("Coriolis: that ratio 'differs little' from 0.55 for speeds up to 7 m/s (§I n°5)", 7.0, 220)
MARBLE_RATIO = ("Résal: a ball dropped on marble rises to 2/3 of its height, e = √(2/3) (§I n°5)", 2 / 3, 224)


def _which(path: Path, kind: str, speeds: str | None) -> str:
    """Which set of columns the header holds: signed speeds, unsigned speeds or heights."""
    line, names = header_names(path)
    if len(names) > 1 and not {"V0", "V1", "u0", "u1", "h0", "h1"} & names:
        raise InputError(f"{path}:{line}", "the header names none of the columns of a rebound: expected V0,V1 "
                                           "(signed velocities), u0,u1 (speeds) or h0,h1 (heights), each with an "
                                           "optional unit (V0_cmps, h0_mm); names are case-sensitive")
    if {"h0", "h1"} & names:
        found = "heights"
    elif {"u0", "u1"} & names:
        found = "unsigned"
    else:
        found = "signed"
    if kind == "cushion" and found == "heights":
        raise InputError(str(path), "a cushion rebound is measured by speeds (columns V0,V1 or u0,u1), not heights; "
                                    "for drop heights use `resal fit drop`")
    if speeds == "unsigned" and found == "signed":
        found = "unsigned-V"
    if speeds == "signed" and found == "unsigned":
        raise InputError(str(path), "--speeds signed, but the header has u0,u1 (speeds, unsigned): write V0,V1 "
                                    "for signed velocities or leave --speeds out")
    return found


def _read(path: Path, which: str) -> tuple[Series, np.ndarray, np.ndarray]:
    """x (impact: V0 or h0) and y (|V1| or h1) in SI, with the names as written; every impossible row refused."""
    cols = SETS["signed" if which == "unsigned-V" else which]
    s = read_series(path, cols, min_rows=2, positive=(cols[0],), dims=DIMS)
    a, b = s[cols[0]], s[cols[1]]
    wb = s.written[cols[1]]
    for i in range(a.size):
        if which == "heights":
            if b[i] < 0:
                raise InputError(s.at(i), f"column '{wb}': expected a rebound height ≥ 0 (measured up from the "
                                          f"surface), got {b[i]:g} m")
            if b[i] > a[i]:
                raise InputError(s.at(i), f"the rebound h1 = {b[i]:g} m is higher than the drop h0 = {a[i]:g} m: "
                                          "expected h1 ≤ h0 (a ball cannot gain energy in the impact; ε ≥ 0)")
        elif which == "signed":
            if b[i] > 0:
                raise InputError(s.at(i), f"column '{wb}': expected the signed velocity after the impact, ≤ 0 "
                                          f"(opposite V0 = {a[i]:g}), got {b[i]:g}; the file must give signed "
                                          "velocities: write a rebound speed u as V1 = -u, or name the columns "
                                          "u0,u1 (speeds), or pass --speeds unsigned")
        elif b[i] < 0:
            raise InputError(s.at(i), f"column '{wb}': expected a speed ≥ 0 (unsigned, as the header or --speeds "
                                      f"unsigned says), got {b[i]:g}")
        if which != "heights" and abs(b[i]) > a[i]:
            raise InputError(s.at(i), f"the ball leaves at |V1| = {abs(b[i]):g} m/s, faster than it arrived "
                                      f"(V0 = {a[i]:g}): expected |V1| ≤ V0 (ε ≥ 0)")
    return s, a, np.abs(b)


def fit_rebounds(kind: str, path: Path, opts: FitOptions) -> FitOutcome:
    """Fit e (and ε) to the rebounds in ``path``; see the module docstring."""
    which = _which(path, kind, opts.speeds)
    s, x, y = _read(path, which)
    heights = which == "heights"
    p = 2 if heights else 1  # y = e^p · x
    out_col = SETS["heights" if heights else ("unsigned" if which == "unsigned" else "signed")][1]
    factor, unit_text = s.factors[out_col], s.unit_text[out_col]
    sigma_si = None if opts.sigma is None else opts.sigma * factor
    check_sigma(opts.sigma, [x / factor, y / factor], unit_text)
    n = x.size
    fr = fit_ratio(x, y, opts.noise, sigma_si)
    v = np.sqrt(2 * opts.g * x) if heights else x  # impact speed
    e_i = (y / x) ** (1 / p)

    def e_of(c: np.ndarray) -> np.ndarray:
        return np.clip(np.asarray(c, dtype=float), 0.0, None) ** (1 / p)

    e = float(e_of(np.array([fr.value]))[0])
    e_ci, clipped = transform_interval(fr.ci95, e_of, 0.0, 1.0)
    # heights: se(e) = se(c)/(2e) by the delta method; at e = 0 (no rebound at all) that is 0/0, and the half-width
    # of e's interval, mapped from c's, stands in for it
    se_e = fr.stderr if p == 1 else (fr.stderr / (2 * e) if e > 0 else (e_ci[1] - e_ci[0]) / (2 * fr.quantile))
    eps = float(impact.eps_from_newton(e))
    eps_ci, _ = transform_interval(e_ci, impact.eps_from_newton, 0.0, 1.0)
    se_eps = 2 / (1 + e) ** 2 * se_e

    def refit(idx: np.ndarray) -> list[float]:
        if np.unique(idx).size < 2:
            raise ValueError("degenerate resample")
        c = fit_ratio(x[idx], y[idx], fr.noise, sigma_si).value
        ee = float(e_of(np.array([min(c, 1.0)]))[0])
        return [ee, float(impact.eps_from_newton(ee))]

    boot = bootstrap(refit, lambda rng: rng.integers(0, n, n), ("e", "eps"), opts.resamples, opts.seed,
                     opts.progress) if opts.resamples and n >= MIN_BOOT_TRIALS else None
    at_bound = "upper" if e >= 1.0 - BOUND_TOL else ("lower" if e <= BOUND_TOL else None)  # of e; ε's is the other
    eps_bound = {"upper": "lower", "lower": "upper", None: None}[at_bound]
    noise_text = _noise_label(fr.noise, opts.sigma, unit_text, s.written[out_col])
    method = f"weighted least squares on §I eq. (9), {noise_text}"
    fits = [
        estimate_row("e", "e (Newton's restitution)", e, se_e, e_ci, method=method,
                     boot=None if boot is None else boot.ci95[0], clipped=clipped, at_bound=at_bound),
        estimate_row("eps", "ε (Résal, eq. 9: ε = (1 − e)/(1 + e))", eps, se_eps, eps_ci, method=method,
                     boot=None if boot is None else boot.ci95[1], clipped=clipped,
                     at_bound=eps_bound),
    ]
    # speed dependence: the per-trial e against the impact speed, with the weights of the noise model
    w_e = np.asarray(fr.weights) * (p * max(e, 1e-12) ** (p - 1)) ** 2
    # a given σ that the scatter contradicts (χ² p < 1 %) cannot judge a law: the F tests estimate the scale instead
    sigma_holds = fr.noise is Noise.GIVEN and not (fr.chi2_p is not None and fr.chi2_p < 0.01)
    law, tests, laws = select_law(v, e_i, w_e, absolute=sigma_holds)
    summary = base_summary(kind, path, n, columns_read(s, DIMS), opts)
    summary["fits"] = fits
    summary["noise"] = {"model": fr.noise.value, "chosen_by": "--sigma" if opts.sigma is not None else (
        "--noise" if opts.noise is not Noise.AUTO else "likelihood"), "scale": fr.scale,
        "scale_unit": ("1 (relative)" if fr.noise is Noise.PROPORTIONAL else ("m" if heights else "m/s")),
        "loglik": fr.loglik, "dof": fr.dof, "quantile": fr.quantile}
    summary["goodness"] = _goodness(fr, x, y, w=np.asarray(fr.weights))
    lof = summary["goodness"]["lack_of_fit"]
    if lof is not None and lof["p"] < 0.01:
        warn(summary, Code.LACK_OF_FIT, f"lack of fit: trials repeated at one impact speed agree with one another far "
                                   f"better than with a constant e (F = {lof['F']:.3g}, p = {lof['p']:.2g}); e "
                                   "above is an average, not a law of your data")
    # one parameter, linear in the data: determined by any trial (x > 0); the rank and the singular value say so
    sv = math.sqrt(float(np.sum(fr.weights)))
    summary["identifiability"] = [{"data": path.name, "parameters": ["e" if p == 1 else "e²"], "rank": 1,
                                   "singular_values": [sv], "condition_number": 1.0, "null_directions": [],
                                   "identified_combinations": []}]
    summary["speed_dependence"] = {
        "tests": [{"orders": [t.lower, t.higher], "test": t.test, "statistic": t.statistic, "p": t.p}
                  for t in tests],
        "order": law.order,
        "verdict": _law_verdict(law.order, tests),
        "law": None if law.order == 0 else {"coefficients": list(law.coefficients), "stderr": list(law.stderr),
                                            "v_range": list(law.v_range), "text": _law_text(law)},
    }
    if law.order:
        test = _test_text(_against_constant(law.order, tests))
        warn(summary, Code.SPEED_LAW, f"the data reject a constant e ({test}): e above is "
                                   f"the mean over {law.v_range[0]:.3g}–{law.v_range[1]:.3g} m/s; the law "
                                   f"{_law_text(law)} describes them")
    if fr.chi2_p is not None and fr.chi2_p < 0.01:
        warn(summary, Code.CHI2, f"the scatter exceeds the given σ: reduced χ² = {fr.chi2 / fr.dof:.3g} "
                                   f"(p = {fr.chi2_p:.2g}); the interval from σ is too narrow")
    summary["per_trial"] = [{"line": s.lines[i], "impact_speed": float(v[i]), "e": float(e_i[i]),
                             "residual": fr.residuals[i]} for i in range(n)]
    summary["comparison"] = _comparisons(kind, heights, e, e_ci, law, v, tests, lof)
    summary["bootstrap"] = None if boot is None else {"resamples": boot.resamples, "seed": boot.seed,
                                                      "failed": boot.failed, "kind": "pairs (trials resampled)",
                                                      "note": BOOT_NOTE}
    rows = tuple((s.lines[i], float(x[i]), float(y[i]), float(v[i]), float(e_i[i]), fr.residuals[i]) for i in range(n))
    headers = ("line", "h0 (m)" if heights else "V0 (m/s)", "h1 (m)" if heights else "|V1| (m/s)",
               "impact speed (m/s)", "e", "residual (m)" if heights else "residual (m/s)")
    return FitOutcome(summary, _figures(kind, v, e_i, e, e_ci, law, fr, heights, laws),
                      headers, rows)


def _noise_label(noise: Noise, sigma: float | None, unit: str, what: str) -> str:
    if noise is Noise.GIVEN:
        return f"σ = {sigma:g} {unit} on {what} given (normal quantile)"
    if noise is Noise.PROPORTIONAL:
        return f"noise on {what} proportional to the impact, estimated (Student's t)"
    return f"constant noise on {what}, estimated (Student's t)"


def _goodness(fr: Any, x: np.ndarray, y: np.ndarray, w: np.ndarray) -> dict[str, Any]:
    """Reduced χ² (σ given) and, where trials repeat an impact, the pure-error lack-of-fit F test."""
    out: dict[str, Any] = {"reduced_chi2": None if fr.chi2 is None else fr.chi2 / fr.dof, "chi2_p": fr.chi2_p,
                           "lack_of_fit": None}
    levels, inv = np.unique(x, return_inverse=True)
    if 1 < levels.size < x.size:
        q = y / x
        sspe = 0.0
        for k in range(levels.size):
            m = inv == k
            qm = float(np.sum(w[m] * q[m]) / np.sum(w[m]))
            sspe += float(np.sum(w[m] * (q[m] - qm) ** 2))
        sse = float(np.sum(w * (q - fr.value) ** 2))
        df1, df2 = levels.size - 1, x.size - levels.size
        between = max(sse - sspe, 0.0)
        if between <= 1e-12 * max(sse, 1e-300):  # the level means agree to rounding: no lack of fit to see
            F, p_lof = 0.0, 1.0
        elif sspe <= 1e-12 * sse:  # repeats agree exactly while the levels differ: the constant e is rejected
            F, p_lof = 1e300, 0.0
        else:
            F = (between / df1) / (sspe / df2)
            p_lof = float(stats.f.sf(F, df1, df2))
        out["lack_of_fit"] = {"test": "pure error F", "F": F, "df": [df1, df2], "p": p_lof}
    return out


def _test_text(t: Any) -> str:
    name = "F" if t.test == "F" else "Δχ²"
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
