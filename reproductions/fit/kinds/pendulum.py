"""``resal fit pendulum``: ε and ε′ (and Newton's e) from impacts of two pendulums, §I n°5 eqs (8).

The struck body hangs at rest; per trial the striker's speed V0 before and both speeds V1, V1′ after (signed,
along the striker's motion) are measured, with the masses M (striker) and M′ (struck). Eqs (8) give
V1 = V0 − 2M′V0/D and V1′ = 2MV0/D, D = M′(1 + ε) + M(1 + ε′): with one mass ratio only D is determined (rank 1,
reported as such); two or more mass ratios separate ε and ε′. Newton's e = (V1′ − V1)/V0 is model-free, per
trial, and averaged per mass ratio. Every trial must keep momentum within its noise (``series``). The fit checks
itself (``fit.checks``): χ² against a given σ or the scatter against a plausible one, each trial's two speeds
predicted from the other trials (leave-one-out), and the masses' and speeds' plausible ranges.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np

from ...errors import InputError
from ...lazy import lazy
from ...mechanics import impact
from ...results import FigureSpec, layer
from ...series import Series, Table, as_table, check_pendulum_trials, header_names, read_series
from .. import distributions as dist
from ..checks import (
    CHI2_P,
    PLAUSIBLE,
    Code,
    leave_one_out,
    loo_entries,
    name_outliers,
    noise_plausible,
    plausible_columns,
    plausible_ratio,
    warn,
)
from ..estimators.lsq import FitResult, fit_direct_impact, numeric_jacobian
from ..estimators.trials import bootstrap, with_estimated_scale
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
    identifiability,
    rows_from_fit,
)

special = lazy("scipy.special", globals())

DIMS = {"V0": "speed", "V1": "speed", "V1p": "speed", "M": "mass", "Mp": "mass"}
LABELS = {"eps": "ε (striking body)", "epsp": "ε′ (struck body)"}


DIMS_H = {"h0": "length", "h1": "length", "h1p": "length", "M": "mass", "Mp": "mass"}


def fit_pendulum(kind: str, source: Path | Table, opts: FitOptions) -> FitOutcome:
    src = as_table(source)  # a CSV file read once, or a program's arrays
    heights = "h0" in header_names(src, ("V0", "V1", "V1p", "h0", "h1", "h1p", "M", "Mp"))[1]
    if heights:
        s = read_series(src, ("h0", "h1", "h1p"), optional=("M", "Mp"), min_rows=2, positive=("h0", "M", "Mp"),
                        nonnegative=("h1", "h1p"), dims=DIMS_H)
    else:
        s = read_series(src, ("V0", "V1", "V1p"), optional=("M", "Mp"), min_rows=2, positive=("V0", "M", "Mp"),
                        dims=DIMS)
    n = len(s.lines)
    if not heights and opts.g != G:
        raise InputError(f"--g {opts.g:g}", "the file gives speeds, and g serves only to turn release and rise "
                                            "heights into speeds: leave --g out")
    for name, col, opt in (("striking", "M", opts.M), ("struck", "Mp", opts.Mp)):
        if col not in s and opt is None:
            raise InputError(src.where, f"no {name} mass: give a column {col} (kg, or {col}_g) or --{col} on the "
                                        "command line")
        if col in s and opt is not None:
            raise InputError(f"--{col} {opt:g}", f"the file has a column {col} already: leave --{col} out")
    M = s["M"] if "M" in s else np.full(n, float(opts.M or 0.0))
    Mp = s["Mp"] if "Mp" in s else np.full(n, float(opts.Mp or 0.0))
    cols = ("h0", "h1", "h1p") if heights else ("V0", "V1", "V1p")
    factor, unit = s.factors[cols[1]], s.unit_text[cols[1]]
    check_sigma(opts.sigma, [s[c] / factor for c in cols], unit)
    sigma_in = None if opts.sigma is None else opts.sigma * factor
    backwards = np.zeros(n, dtype=bool)
    res_sigma: np.ndarray | float | None = sigma_in
    if heights:
        # bottom speeds from the release and rise heights, V = √(2 g h) (the bob's energy, §I n°5's pendulums)
        V0, a1, V1p = (np.sqrt(2 * opts.g * s[c]) for c in cols)
        # a rise height gives the striker's speed, not its direction: the direction that keeps momentum better
        back = np.abs(M * V0 + M * a1 - Mp * V1p) < np.abs(M * V0 - M * a1 - Mp * V1p)
        backwards = back & (a1 > 0)
        V1 = np.where(backwards, -a1, a1)
        # a height's σ becomes a speed's by dV/dh = g/V (floored at √(2gσ) where the height is within σ of zero);
        # the release's enters each residual through ∂V1/∂V0 = V1/V0 and ∂V1′/∂V0 = V1′/V0 (eqs 8)
        # without σ the weights are relative (their scale is estimated): any σ far below the heights serves
        unit_sigma = 1e-6 * float(np.max(s["h0"])) if sigma_in is None else sigma_in
        floor = math.sqrt(2 * opts.g * unit_sigma)

        def sd(v: np.ndarray) -> np.ndarray:
            return opts.g * unit_sigma / np.maximum(np.abs(v), floor)

        s0 = sd(V0)
        res_sigma = np.concatenate([np.hypot(sd(V1), V1 / V0 * s0), np.hypot(sd(V1p), V1p / V0 * s0)])
        speeds = Series({"V0": V0, "V1": V1, "V1p": V1p})
        speeds.table, speeds.where, speeds.lines = s.table, s.where, s.lines
        check_pendulum_trials(speeds, M, Mp, None if sigma_in is None else float(np.max(res_sigma)))
    else:
        V0, V1, V1p = s["V0"], s["V1"], s["V1p"]
        check_pendulum_trials(s, M, Mp, sigma_in)  # momentum kept and bodies apart, within the noise
    sigma = res_sigma
    fit = _fit(M, Mp, V0, V1, V1p, sigma, heights and sigma_in is None)
    rank = fit.identifiability.rank

    def refit(idx: np.ndarray) -> list[float]:
        sig = sigma if not isinstance(sigma, np.ndarray) else np.concatenate([sigma[:n][idx], sigma[n:][idx]])
        f = _fit(M[idx], Mp[idx], V0[idx], V1[idx], V1p[idx], sig, heights and sigma_in is None)
        if f.identifiability.rank < rank:
            raise ValueError("degenerate resample")
        if rank == 2:
            return list(f.point)
        return [f.combinations[0].value]

    names = ("eps", "epsp") if rank == 2 else ("combination0",)
    boot = bootstrap(refit, lambda rng: rng.integers(0, n, n), names, opts.resamples, opts.seed,
                     opts.progress) if opts.resamples and n >= MIN_BOOT_TRIALS else None
    method = "least squares on §I eqs (8), bounds [0, 1], " + (
        f"σ = {opts.sigma:g} {unit} on each height given" if heights and sigma_in is not None else
        f"σ = {opts.sigma:g} {unit} given" if sigma_in is not None else
        "noise estimated (Student's t)") + (
        "; speeds at the bottom √(2gh) from the heights, each residual weighted by the height's noise carried "
        "through (dV/dh = g/V), and the striker's direction after the impact taken from momentum" if heights else "")
    fits = rows_from_fit(fit, "pendulum", LABELS, method, boot if rank == 2 else None)
    if rank < 2 and boot is not None:
        for r in fits:
            if r["id"] == "pendulum.combination0":
                r["ci95_bootstrap"] = list(boot.ci95[0])
    # Newton's e: per trial, model-free; per mass ratio, its mean with a Student-t interval
    e_i = (V1p - V1) / V0
    ratio, groups = _ratio_groups(Mp / M)
    for r, m in groups:
        k = int(m.sum())
        mean = float(e_i[m].mean())
        if k > 1:
            se = float(e_i[m].std(ddof=1) / math.sqrt(k))
            q = float(special.stdtrit(k - 1, 0.975)) if sigma_in is None or heights else float(special.ndtri(0.975))
            if sigma_in is not None and not heights:
                # var eᵢ = 2σ²/V0ᵢ² (σ on V1 and on V1′), so the mean's se is σ √2 √(Σ 1/V0ᵢ²)/k
                se = sigma_in * math.sqrt(2.0 * float(np.sum(1.0 / V0[m] ** 2))) / k
            ci: tuple[float | None, float | None] = (mean - q * se, mean + q * se)
        else:
            se, ci = None, (None, None)
        spread = "" if np.ptp(ratio[m]) == 0 else f"; M′/M from {ratio[m].min():.6g} to {ratio[m].max():.6g}"
        fits.append(estimate_row(f"e.ratio{r:g}", f"e (Newton, M′/M = {r:.4g})", mean, se, ci,
                                 method="mean of (V1′ − V1)/V0 per trial", note=f"{k} trial(s){spread}"))
    point = np.asarray(fit.point)
    pred = impact.direct_impact(M, Mp, V0, 0.0, eps=point[0], epsp=point[1])
    summary = base_summary(kind, src, n, columns_read(s, DIMS_H if heights else DIMS), opts)
    summary["fits"] = fits
    summary["identifiability"] = [identifiability(fit, LABELS, src.name)]
    summary["noise"] = {"model": "given" if sigma_in is not None else (
        "from the heights, scale estimated" if heights else "constant"), "dof": fit.dof}
    r_all = np.concatenate([pred.V1 - V1, pred.V1p - V1p])
    summary["goodness"] = {"reduced_chi2": None, "chi2_p": None}
    if sigma_in is not None and fit.dof > 0:
        chi2 = float(np.sum((r_all / np.broadcast_to(np.asarray(sigma), r_all.shape)) ** 2))
        p_chi2 = float(dist.chi2_sf(chi2, fit.dof))
        summary["goodness"] = {"reduced_chi2": chi2 / fit.dof, "chi2_p": p_chi2}
        if p_chi2 < CHI2_P:
            warn(summary, Code.CHI2, f"the scatter exceeds the given σ: reduced χ² = {chi2 / fit.dof:.3g} "
                                       f"(p = {p_chi2:.2g}); the intervals from σ are too narrow")
    _check_fit(summary, s, opts, fit, (M, Mp, V0, V1, V1p), sigma, sigma_in is not None, heights)
    imbalance = M * V0 - M * V1 - Mp * V1p
    if backwards.any():
        warn(summary, Code.ASSUMED, f"the striker's rise heights give no direction: in {int(backwards.sum())} of {n} "
                                   "trial(s) it was taken as moving back after the impact, the direction that keeps "
                                   "momentum (per_trial: striker_back)")
    summary["per_trial"] = [{"line": s.lines[i], "M": float(M[i]), "Mp": float(Mp[i]), "e": float(e_i[i]),
                             "striker_back": bool(backwards[i]),
                             "momentum_imbalance": float(imbalance[i]),
                             "residual_V1": float(pred.V1[i] - V1[i]), "residual_V1p": float(pred.V1p[i] - V1p[i])}
                            for i in range(n)]
    if rank < 2:
        warn(summary, Code.IDENTIFIABILITY, "one mass ratio: only the combination M′ε + Mε′ is determined; "
                                            "trials with a second mass ratio separate ε and ε′")
    summary["bootstrap"] = None if boot is None else {"resamples": boot.resamples, "seed": boot.seed,
                                                      "failed": boot.failed, "kind": "pairs (trials resampled)",
                                                      "note": boot_note(kind)}
    headers = ("line", "M (kg)", "M′ (kg)", "V0 (m/s)", "V1 (m/s)", "V1′ (m/s)", "e", "M V0 − M V1 − M′ V1′ (kg·m/s)")
    rows = tuple((s.lines[i], float(M[i]), float(Mp[i]), float(V0[i]), float(V1[i]), float(V1p[i]), float(e_i[i]),
                  float(imbalance[i])) for i in range(n))
    grid = np.linspace(0.0, float(V0.max()) * 1.05, 50)
    figs = []
    for r, m in groups:
        g = impact.direct_impact(float(M[m][0]), float(Mp[m][0]), grid, 0.0, eps=point[0], epsp=point[1])
        figs += [layer("points", V0[m], V1[m], color="C0", label=f"V1, M′/M = {r:.3g}"),
                 layer("points", V0[m], V1p[m], color="C1", marker="s", label=f"V1′, M′/M = {r:.3g}"),
                 layer("line", grid, g.V1, color="C0"), layer("line", grid, g.V1p, color="C1")]
    fig = FigureSpec("fit", "resal fit pendulum: speeds after the impact, measured and fitted (§I eqs 8)",
                     "V0 (m/s)", "velocity after the impact (m/s)", tuple(figs))
    res = FigureSpec("residuals", "resal fit pendulum: residuals against V0", "V0 (m/s)",
                     "predicted − measured (m/s)",
                     (layer("points", V0, pred.V1 - V1, label="V1"),
                      layer("points", V0, pred.V1p - V1p, color="C1", marker="s", label="V1′"),
                      layer("line", [0.0, float(V0.max())], [0.0, 0.0], color="0.4", style=":")))
    return FitOutcome(summary, (fig, res), headers, rows)


RATIO_GAP = 0.01  # a relative gap between sorted mass ratios that starts a new group (masses weighed to ~0.1 %)


def _ratio_groups(ratio: np.ndarray) -> tuple[np.ndarray, list[tuple[float, np.ndarray]]]:
    """The trials grouped by mass ratio for Newton's e and the figure: sorted ratios closer than ``RATIO_GAP``
    (relative) to their neighbour are one group (masses weighed trial by trial differ in their last digits; one
    group per trial would print a row and draw a curve per trial). A group of one exact ratio is named by it (12
    digits), another by its median to 4 digits, its range said in the row's note. The fit itself takes each trial's
    masses as given."""
    exact = np.round(ratio, 12)
    order = np.argsort(exact, kind="stable")
    srt = exact[order]
    starts = np.concatenate([[0], np.flatnonzero(np.diff(srt) > RATIO_GAP * srt[1:]) + 1, [srt.size]])
    groups = []
    for a, b in itertools.pairwise(starts.tolist()):
        m = np.zeros(exact.size, dtype=bool)
        m[order[a:b]] = True
        one = srt[a] == srt[b - 1]
        groups.append((float(srt[a]) if one else float(f"{float(np.median(srt[a:b])):.4g}"), m))
    return exact, groups


NOISE_REL_LIMIT = 0.25  # a scatter of the speeds after the impact beyond 25 % of their size is no measurement
NOISE_FLOOR = 0.1  # … of their size, or of a tenth of the impact speed when they are slower


def _check_fit(summary: dict, s: Series, opts: FitOptions, fit: FitResult, data: tuple[np.ndarray, ...],
               sigma: np.ndarray | float | None, sigma_given: bool, heights: bool) -> None:
    """The fit checks itself (``fit.checks``): each trial's V1 and V1′ predicted from the other trials (the
    linearised deleted residuals, both speeds of a trial left out together), the scatter against a plausible one
    when it is estimated, and the masses' and impact speeds' plausible ranges."""
    M, Mp, V0, V1, V1p = data
    n = V0.size

    def predict(theta: np.ndarray) -> np.ndarray:
        out = impact.direct_impact(M, Mp, V0, 0.0, eps=theta[0], epsp=theta[1])
        return np.concatenate([out.V1, out.V1p])

    measured = np.concatenate([V1, V1p])
    sd = np.broadcast_to(np.asarray(1.0 if sigma is None else sigma, dtype=float), measured.shape)
    r = (measured - predict(np.asarray(fit.point))) / sd
    J = numeric_jacobian(predict, fit.point) / sd[:, None]
    lines = np.asarray(s.lines)
    groups = np.concatenate([lines, lines])
    # a σ that the scatter contradicts (χ² p < 1 %) is not used: the scale is then estimated
    held = sigma_given and not any(w["code"] == Code.CHI2.value for w in summary["warnings"])
    loo = leave_one_out(r, J, groups, sigma_known=held)
    entries = loo_entries(loo, groups, ["V1"] * n + ["V1p"] * n, measured, sd)
    for e in entries:
        e["unit"] = "m/s"
    summary["leave_one_out"] = sorted(entries, key=lambda e: e["line"])
    name_outliers(summary, lines, loo["p"], "trial", s.table)
    if not sigma_given and fit.dof > 0:
        res = measured - predict(np.asarray(fit.point))
        size = max(float(np.median(np.maximum(np.abs(V1), np.abs(V1p)))), NOISE_FLOOR * float(np.median(V0)))
        noise_plausible(summary, math.sqrt(float(res @ res) / fit.dof), NOISE_REL_LIMIT * size,
                        "the speeds after the impact (V1, V1′)", "m/s")
    cols = {"M": "mass", "Mp": "mass", ("h0" if heights else "V0"): "drop-height" if heights else "pendulum-speed"}
    for msg in plausible_columns(s, cols, DIMS_H if heights else DIMS):
        warn(summary, Code.UNIT, msg)
    # the struck body against the striker: a hundredth as fast, or ten times faster (squared for heights), is no
    # impact of two pendulums whatever the units declared
    bounds, typical = ((1e-4, 100.0), (0.0025, 4.0)) if heights else ((0.01, 10.0), (0.05, 2.0))
    num, den = ("h1p", "h0") if heights else ("V1p", "V0")
    for msg in plausible_ratio(s, num, den, DIMS_H if heights else DIMS, bounds,
                               "the struck body's speed over the striker's" if not heights else
                               "the struck body's rise over the striker's drop", typical):
        warn(summary, Code.UNIT, msg)
    rng = PLAUSIBLE["mass"]
    for name, value in (("M", opts.M), ("Mp", opts.Mp)):
        if value is not None and not rng.low <= value <= rng.high:
            hint = "; in g it would be plausible (--{name} takes kg)" if rng.low <= value * 1e-3 <= rng.high else ""
            warn(summary, Code.UNIT, f"--{name} {value:g} kg is outside {rng.low:g}–{rng.high:g} kg, {rng.what}"
                                     f"{hint.format(name=name)}")


def _fit(M: np.ndarray, Mp: np.ndarray, V0: np.ndarray, V1: np.ndarray, V1p: np.ndarray,
         sigma: np.ndarray | float | None, relative: bool) -> FitResult:
    """Eqs (8) fitted; ``relative``: ``sigma`` gives only the residuals' relative sizes, their scale estimated."""
    fit = fit_direct_impact(M, Mp, V0, V1, V1p, sigma)
    if not relative:
        return fit
    pred = impact.direct_impact(M, Mp, V0, 0.0, eps=fit.point[0], epsp=fit.point[1])
    r = np.concatenate([pred.V1 - V1, pred.V1p - V1p]) / np.asarray(sigma)
    return with_estimated_scale(fit, float(r @ r), (0.0, 0.0), (1.0, 1.0))
