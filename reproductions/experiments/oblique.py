"""Kind ``oblique_markers``: §VI's two balls on the cloth (n°13, eqs (1)–(9), with law (6) of §I) against published
angle markers of oblique collisions (Doménech-Carbó 2023: the cue ball's turn α1 and δ2 against the impact angle ψ).

A cue ball in natural roll strikes a ball at rest; ``fit.estimators.markers`` predicts the angles right after the
impact and fits the ball–ball friction f and Newton's e (ε = ε′ = (1 − e)/(1 + e), §I eq. (9)) by profile
likelihood: to α1 alone, to δ2 alone, and to both. The rows then judge the mechanics, not the paper's print: do the
two series agree on (f, e), which reading of δ2 fits (the object ball's throw, the separation's departure from 90°,
the cue ball's from the tangent line), do the residuals trend with ψ (a constant f through the impact, §VI's
premise, would leave none), and how do the fitted f and e compare with today's values (μ(v) at the impact's slip
speeds; e of pool balls) and with Coriolis's f < 0.03 that the paper adopts (§VI n°13, l. 610)?
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import Experiment, Node
from ..fit import distributions as dist
from ..fit.estimators import markers as mk
from ..fit.estimators import shots
from ..results import modern_table
from ..series import Markers, read_markers
from .base import (
    Comparison,
    FigureSpec,
    FitRow,
    Reproduction,
    layer,
    measurement_rows,
    modern_rows,
    rows_for,
)

QUANTITIES = ("series_agree", "alpha1_shape", "throw_shape", "throw_halves", "delta2_throw", "delta2_separation",
              "delta2_cue", "f_vs_modern", "f_vs_coriolis", "e_vs_modern")
COST = 1.75  # CPU seconds of a run with its figures, about: the process pool starts the longest first
MODERN = ("mu_bb", "mu_bb(v)", "e_bb")
READINGS = {"throw": "(a) the throw: the object ball's departure from the line of centres",
            "sep_dev": "(b) 90° − the separation angle",
            "cue_dev": "(c1) the cue ball's departure from the smooth elastic tangent line, 90° − ψ − α1"}
CORIOLIS_F = 0.03  # « ne paraît pas devoir atteindre 0,03 » (§VI n°13, l. 610)


@dataclass(frozen=True)
class Params:
    data: Path
    model: mk.Model
    speed_range: tuple[float, float]
    floor: float
    split: float  # degrees: the throw's markers are fitted apart below and above it
    mu_law: tuple[float, float, float]


def parse(node: Node, base: Path) -> Params:
    data = base / node.string("data")
    ball = node.child("ball", "a mapping with R, k, M")
    R = ball.number("R", "a radius in m", lo=0.0, lo_open=True)
    k = ball.number("k", "k of the moment of inertia M R²/k", lo=0.0, lo_open=True)
    M = ball.number("M", "a mass in kg", lo=0.0, lo_open=True)
    ball.done()
    speed = node.number("speed", "the launch speed in m/s", lo=0.0, lo_open=True)
    rng = node.number_list("speed_range", "speeds in m/s")
    if len(rng) != 2 or not 0 < rng[0] <= speed <= rng[1]:
        raise node.fail("'params.speed_range' must be [low, high] in m/s around the speed, 0 < low ≤ speed ≤ high",
                        node._mapping()["speed_range"])
    floor = node.number("floor_deg", "the digitisation error of a marker in degrees", lo=0.0, lo_open=True, hi=10.0)
    split = node.number("split_deg", "an impact angle in degrees", lo=0.0, lo_open=True, hi=90.0, hi_open=True)
    law = node.number_list("modern_friction_law", "coefficients a, b, c of μ(v) = a + b exp(−c v)")
    if len(law) != 3:
        raise node.fail("'params.modern_friction_law' must have exactly three coefficients a, b, c",
                        node._mapping()["modern_friction_law"])
    node.done()
    read_markers(data, ("alpha1", "delta2"))  # a bad or missing file stops the run before any work
    return Params(data, mk.Model(speed, R, M, k), (rng[0], rng[1]), floor, split, (law[0], law[1], law[2]))


def _mu(law: tuple[float, float, float], v: np.ndarray | float) -> np.ndarray:
    a, b, c = law
    return a + b * np.exp(-c * np.asarray(v, dtype=float))


def _p(p: float) -> str:
    return f"{p:.2f}" if p >= 0.1 else f"{p:.2g}" if p >= 0.001 else f"{p:.1g}"


def _ci(x: tuple[float, float], d: int = 3) -> str:
    return f"[{x[0]:.{d}f}, {x[1]:.{d}f}]"


def f_stop_head_on(e: float, model: mk.Model) -> float:
    """The friction above which a natural-roll cue ball's slip on the object ball (vertical, v) stops during a
    head-on impact (§VI, law (6)): the slip decays at f(k + k′)/M per unit of normal impulse (the cloth blocks the
    vertical translations, c_z = k/M + k′/M′) and the impulse is M v (1 + e)/2, so f = 2/((k + k′)(1 + e))."""
    return 2.0 / (2 * model.k * (1 + e))


def _rival(f: mk.MarkerFit, model: mk.Model) -> str:
    """A local minimum of the profile outside the interval, said where the fit is reported, with what makes the
    profile uneven there: beyond the f at which the cue ball's slip stops during the impact, α1 changes fast with f
    and the markers cross that boundary one by one."""
    if f.rival is None:
        return ""
    rf, re_, d = f.rival
    return (f"; beyond f = {f_stop_head_on(f.e, model):.3f}, where the cue ball's slip stops during a head-on "
            f"impact, the profile rises steeply and unevenly: a local minimum at f = {rf:.3g}, e = {re_:.3g} fits "
            f"{d:.2g} worse in −2 ln L (outside the 95 % interval)")


def _fit_row(fid: str, label: str, value: float, ci: tuple[float, float], identified: bool, at_bound: str | None,
             bounds: tuple[float, float], note: str) -> FitRow:
    method = "profile likelihood, σ of each series profiled (floor 0.5°), Δ(−2lnL) = 3.84"
    if not identified:
        return FitRow(fid, label, None, None, (None, None), method, False,
                      f"not identifiable: any value in [{bounds[0]:g}, {bounds[1]:g}] fits within the cut; " + note,
                      bounds)
    reach = [side for side, x, b in (("lower", ci[0], bounds[0]), ("upper", ci[1], bounds[1])) if x == b]
    extra = (f"; the 95 % interval reaches the {' and '.join(reach)} bound of the parameter" if reach else "")
    warn = (f"; the best value lies on the {at_bound} bound ({bounds[0 if at_bound == 'lower' else 1]:g})"
            if at_bound else "")
    return FitRow(fid, label, value, None, ci, method, True, note + warn + extra, at_bound=at_bound)


def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    m = read_markers(p.data, ("alpha1", "delta2"))
    model, floor = p.model, p.floor
    (pa, oa), (pd, od) = m.series["alpha1"], m.series["delta2"]
    alpha, throw = mk.Part(pa, oa, "alpha1"), mk.Part(pd, od, "throw")

    def fit(parts: list[mk.Part]) -> mk.MarkerFit:
        return mk.fit_markers(parts, model, floor=floor)

    fa, ft, fj = fit([alpha]), fit([throw]), fit([alpha, throw])
    readings = {"throw": ft, **{key: fit([mk.Part(pd, od, key)]) for key in ("sep_dev", "cue_dev")}}
    lr, dof, p_lr = mk.agreement([fa, ft], fj)

    def residuals(f: mk.MarkerFit, part: mk.Part) -> np.ndarray:
        return part.obs - mk.angles(part.psi, f.f, f.e, model)[part.key]

    sl_a, sl_t = mk.slope_test(pa, residuals(fj, alpha)), mk.slope_test(pd, residuals(fj, throw))
    sl_read = {k: mk.slope_test(pd, residuals(f, mk.Part(pd, od, k))) for k, f in readings.items()}
    low, high = pd < p.split, pd >= p.split
    halves = [mk.fit_f_fixed_e(mk.Part(pd[w], od[w], "throw"), fj.e, model, floor=floor) for w in (low, high)]
    (f_lo, ci_lo), (f_hi, ci_hi) = halves
    s_diff = math.hypot((ci_lo[1] - ci_lo[0]) / 3.92, (ci_hi[1] - ci_hi[0]) / 3.92)

    # today's μ(v) at the slip speeds of these impacts (§V n°12 eq. (1): the slip at the contact), over the launch
    # speeds of the bench; the slip starts at the launch speed (natural roll) and ends lower
    grid_psi = np.linspace(float(min(pa.min(), pd.min())), float(max(pa.max(), pd.max())), 9)
    slips = []
    for v in p.speed_range:
        s0, s1 = mk.slip_speeds(grid_psi, fj.f, fj.e, mk.Model(v, model.R, model.M, model.k))
        slips.append((s0, s1))
    s0, s1 = mk.slip_speeds(grid_psi, fj.f, fj.e, model)
    mean_slip = 0.5 * (s0 + s1)
    all_slips = np.concatenate([np.ravel(x) for pair in slips for x in pair] + [s0, s1])
    mu_lo, mu_hi = float(_mu(p.mu_law, all_slips.max())), float(_mu(p.mu_law, all_slips.min()))
    mu_mean = _mu(p.mu_law, mean_slip)
    e_rows = [r for r in modern_table() if r["symbol"] == "e_bb"]
    e_vals = [float(x) for r in e_rows for x in (r["low"], r["typ"], r["high"]) if x is not None]
    e_lo, e_hi = (min(e_vals), max(e_vals)) if e_vals else (0.89, 0.98)

    def slope_cmp(s: mk.SlopeTest, n: int, what: str) -> Comparison:
        ok = s.p >= 0.05
        return Comparison(s.slope * 10, f"{s.slope * 10:+.2f}°/10° over {n} markers", f"± {s.stderr * 10:.2f}°/10° "
                          "(1σ, least squares)", 0.0, None, "consistent" if ok else "inconsistent",
                          f"slope of the residuals against ψ, {what}: {s.slope * 10:+.3f} ± {s.stderr * 10:.3f}°/10°, "
                          f"p = {_p(s.p)}; a constant f (§VI) predicts none, so p < 0.05 is inconsistent.")

    def reading_cmp(key: str) -> Comparison:
        f, s = readings[key], sl_read[key]
        worse = f.m2lnl - ft.m2lnl
        bad = s.p < 0.05 or worse > mk.CUT
        return Comparison(
            s.slope * 10, f"δ2 read as {READINGS[key]}: residual slope {s.slope * 10:+.2f}°/10°",
            f"± {s.stderr * 10:.2f}°/10° (1σ)", 0.0, None, "inconsistent" if bad else "consistent",
            f"fitted alone: f = {f.f:.3f}, e = {f.e:.3f}{' (at its bound)' if f.at_bound_e else ''}"
            + (f" {_ci(f.ci_e)}" if f.e_identified else "") + f", rms "
            f"{f.sigma[0]:.2f}°, −2lnL {f.m2lnl:.1f} against {ft.m2lnl:.1f} for the throw (a) (Δ = {worse:.1f}); "
            f"residual slope p = {_p(s.p)}"
            + (f"; its e interval and that of α1 alone, {fa.e:.3f} {_ci(fa.ci_e)}, do not overlap: the same impacts "
               "cannot have both" if f.e_identified and fa.e_identified
               and (f.ci_e[0] > fa.ci_e[1] or f.ci_e[1] < fa.ci_e[0]) else "") + ".")

    overlap_e = (max(fj.ci_e[0], e_lo), min(fj.ci_e[1], e_hi))
    # the normal ratio of the impacts at the joint fit, over the markers' ψ (law (6): e where the slip keeps one
    # direction, head on; the cut turns it on the cloth)
    ratio = shots.predict_shots(model.speed, np.radians(grid_psi), f_bb=fj.f, e=fj.e, R=model.R, k=model.k,
                                M=model.M).normal_e
    inside_e = e_lo <= fj.ci_e[0] and fj.ci_e[1] <= e_hi
    comparisons = {
        "series_agree": Comparison(
            lr, f"Λ = {lr:.2f}", f"χ² with {dof} degrees of freedom if the series share (f, e)", 0.0,
            (0.0, float(dist.chi2_ppf(0.95, dof))), "consistent" if p_lr >= 0.05 else "inconsistent",
            f"Λ = −2lnL of the joint fit ({fj.m2lnl:.2f}) − those of α1 alone ({fa.m2lnl:.2f}) and the throw alone "
            f"({ft.m2lnl:.2f}); p = {_p(p_lr)}."),
        "alpha1_shape": slope_cmp(sl_a, pa.size, f"α1 at the joint fit (σ̂ {fj.sigma[0]:.2f}°)"),
        "throw_shape": slope_cmp(sl_t, pd.size, f"δ2 as throw at the joint fit (σ̂ {fj.sigma[1]:.2f}°)"),
        "throw_halves": Comparison(
            f_lo - f_hi, f"f = {f_lo:.3f} {_ci(ci_lo)} for ψ < {p.split:g}° against {f_hi:.4f} {_ci(ci_hi, 4)} for "
                         f"ψ ≥ {p.split:g}°", f"± {s_diff:.3f} (1σ, from the two 95 % intervals)", 0.0, None,
            "consistent" if abs(f_lo - f_hi) <= 1.96 * s_diff else "inconsistent",
            f"f fitted to each part of the throw's markers, e fixed at the joint {fj.e:.3f}: the difference "
            f"{f_lo - f_hi:+.3f} is {abs(f_lo - f_hi) / s_diff:.1f}σ; a constant f gives 0."),
        "delta2_throw": Comparison(
            sl_read["throw"].slope * 10, f"δ2 read as {READINGS['throw']}: residual slope "
                                         f"{sl_read['throw'].slope * 10:+.2f}°/10°",
            f"± {sl_read['throw'].stderr * 10:.2f}°/10° (1σ)", 0.0, None,
            "consistent" if sl_read["throw"].p >= 0.05 else "inconsistent",
            f"fitted alone: f = {ft.f:.3f} {_ci(ft.ci_f)}, e unconstrained; rms {ft.sigma[0]:.2f}°, −2lnL "
            f"{ft.m2lnl:.1f}, the best of the readings; residual slope p = {_p(sl_read['throw'].p)}."),
        "delta2_separation": reading_cmp("sep_dev"),
        "delta2_cue": reading_cmp("cue_dev"),
        "f_vs_modern": Comparison(
            float(np.mean(mu_mean)), f"μ(v) = {mu_lo:.3f}–{mu_hi:.3f} over the slip speeds of the impact "
                                     f"({all_slips.min():.2f}–{all_slips.max():.2f} m/s)",
            f"μ(v) at the mean slip {float(mu_mean.min()):.3f}–{float(mu_mean.max()):.3f}; launch speed "
            f"{p.speed_range[0]:g}–{p.speed_range[1]:g} m/s", fj.f, fj.ci_f,
            "inconsistent" if fj.ci_f[0] > mu_hi or fj.ci_f[1] < mu_lo else "consistent",
            f"f of the joint fit {fj.f:.3f} {_ci(fj.ci_f)} against today's μ(v) = {p.mu_law[0]:g} + {p.mu_law[1]:g} "
            f"exp(−{p.mu_law[2]:g} v) at the slips of §VI's impact (onset = launch speed, natural roll; end "
            f"{s1.min():.2f}–{s1.max():.2f} m/s): f is {fj.f / mu_mean.max():.1f}–{fj.f / mu_mean.min():.1f} × μ at "
            "the mean slip; inconsistent when the intervals do not overlap. The bench is PVC, not a pool table."),
        "f_vs_coriolis": Comparison(
            CORIOLIS_F, "f < 0.03 (Coriolis, adopted by the paper)", "a bound, no uncertainty printed", fj.f,
            fj.ci_f, "inconsistent" if fj.ci_f[0] > CORIOLIS_F else "consistent",
            f"the fitted f {fj.f:.3f} {_ci(fj.ci_f)} is {fj.f / CORIOLIS_F:.1f} × the paper's bound."),
        "e_vs_modern": Comparison(
            None, f"e = {e_lo:.2f}–{e_hi:.2f} (pool and snooker balls today)", "a range of sources", fj.e, fj.ci_e,
            "consistent" if overlap_e[0] <= overlap_e[1] else "inconsistent",
            f"e of the joint fit {fj.e:.3f} {_ci(fj.ci_e)} "
            + ((f"lies inside today's range {e_lo:.2f}–{e_hi:.2f}" if inside_e else
                f"overlaps today's range only at {overlap_e[0]:.3f}–{overlap_e[1]:.3f}")
               + ", above the typical "
               + " and ".join(f"{r['typ']:g} ({str(r['source']).split(',')[0]})" for r in e_rows if r["typ"])
               if overlap_e[0] <= overlap_e[1] else
               "does not overlap today's range")
            + f". e is the normal ratio of the impact where the friction keeps one direction (law (6)); at the fit "
              f"the ratio runs {float(ratio.min()):.4f}–{float(ratio.max()):.4f} over ψ = {grid_psi[0]:.0f}–"
              f"{grid_psi[-1]:.0f}° (the cut turns the slip on the cloth)."),
    }
    fits = [
        _fit_row("joint.f", "f (α1 + δ2 as throw)", fj.f, fj.ci_f, fj.f_identified, fj.at_bound_f, mk.F_BOUNDS,
                 f"both series, {pa.size} + {pd.size} markers; σ̂ {fj.sigma[0]:.2f}° and {fj.sigma[1]:.2f}°"),
        _fit_row("joint.e", "e (α1 + δ2 as throw)", fj.e, fj.ci_e, fj.e_identified, fj.at_bound_e, mk.E_BOUNDS,
                 "Newton's e of law (6), ε = (1 − e)/(1 + e)"),
        _fit_row("alpha1.f", "f (α1 alone)", fa.f, fa.ci_f, fa.f_identified, fa.at_bound_f, mk.F_BOUNDS,
                 f"{pa.size} markers, σ̂ {fa.sigma[0]:.2f}°; f and e trade along a valley" + _rival(fa, model)),
        _fit_row("alpha1.e", "e (α1 alone)", fa.e, fa.ci_e, fa.e_identified, fa.at_bound_e, mk.E_BOUNDS,
                 "friction and e < 1 both lower α1"),
        _fit_row("throw.f", "f (δ2 as throw alone)", ft.f, ft.ci_f, ft.f_identified, ft.at_bound_f, mk.F_BOUNDS,
                 f"{pd.size} markers, σ̂ {ft.sigma[0]:.2f}°"),
        _fit_row("throw.e", "e (δ2 as throw alone)", ft.e, ft.ci_e, ft.e_identified, ft.at_bound_e, mk.E_BOUNDS,
                 "the throw hardly depends on e"),
        _fit_row("throw_low.f", f"f (throw, ψ < {p.split:g}°, e fixed)", f_lo, ci_lo, True, None, mk.F_BOUNDS,
                 f"{int(low.sum())} markers, e = {fj.e:.3f} of the joint fit"),
        _fit_row("throw_high.f", f"f (throw, ψ ≥ {p.split:g}°, e fixed)", f_hi, ci_hi, True, None, mk.F_BOUNDS,
                 f"{int(high.sum())} markers, e = {fj.e:.3f} of the joint fit"),
    ]
    modern = modern_rows(exp.modern, {"mu_bb": (fj.f, "f of the joint fit"),
                                      "mu_bb(v)": (fj.f, "f of the joint fit, slips 0.4–0.85 m/s"),
                                      "e_bb": (fj.e, "e of the joint fit")})
    figures = _figures(m, model, fj, fa, readings, (sl_a, sl_t), alpha, throw)
    note = (f"Doménech-Carbó 2023, {pa.size} α1 and {pd.size} δ2 markers ({p.data.name}); §VI n°13 impact with a "
            f"natural-roll cue ball; each series' σ profiled with a {floor:g}° floor")
    return Reproduction(exp, rows_for(exp, {}), tuple(fits), figures, modern, data_note=note,
                        measurements=measurement_rows(exp, comparisons))


def _figures(m: Markers, model: mk.Model, fj: mk.MarkerFit, fa: mk.MarkerFit, readings: dict[str, mk.MarkerFit],
             slopes: tuple[mk.SlopeTest, mk.SlopeTest], alpha: mk.Part, throw: mk.Part) -> tuple[FigureSpec, ...]:
    grid = np.linspace(5.0, 75.0, 57)
    fit_label = f"§VI, joint fit f = {fj.f:.3f}, e = {fj.e:.3f}"
    ca, lo_a, hi_a = mk.prediction_band(grid, fj, "alpha1", model)
    ct, lo_t, hi_t = mk.prediction_band(grid, fj, "throw", model)
    alone = mk.angles(grid, fa.f, fa.e, model)["alpha1"]
    fig_a = FigureSpec(
        "oblique-alpha1", "The cue ball's turn α1 against the impact angle ψ", "impact angle ψ (degrees, 0 = head-on)",
        "$\\alpha_1$ (degrees)", (
            layer("band", grid, lo_a, hi_a, label="95 % band of the joint fit", color="C0"),
            layer("line", grid, 90 - grid, label="smooth elastic balls: 90° − ψ", color="C7", style=":"),
            layer("line", grid, alone, label=f"$\\alpha_1$ alone: f = {fa.f:.3f}, e = {fa.e:.3f}", color="C2",
                  style="--"),
            layer("line", grid, ca, label=fit_label, color="C0"),
            layer("errorbar", alpha.psi, alpha.obs, np.full(alpha.psi.size, 0.5),
                  label=f"Doménech-Carbó 2023 ({alpha.psi.size} markers, ±0.5°)", color="k", marker=".")),
        legend="below",
        reading=("The angle the cue ball turns through at the impact, against the impact angle ψ: the markers, "
                 "Résal's §VI with the (f, e) fitted to both series (line and its 95 % band), the fit to α1 "
                 "alone (dashed) and smooth elastic balls (dotted). Friction and e < 1 both pull α1 a little "
                 "below 90° − ψ; the markers scatter by about 1.7° around the curve."))
    sep = readings["sep_dev"]
    cue = readings["cue_dev"]
    fig_d = FigureSpec(
        "oblique-delta2", "δ2 against ψ: which angle is it?", "impact angle ψ (degrees, 0 = head-on)",
        "$\\delta_2$ (degrees)", (
            layer("band", grid, lo_t, hi_t, label="95 % band of the joint fit", color="C0"),
            layer("line", grid, ct, label=f"(a) throw, {fit_label}", color="C0"),
            layer("line", grid, mk.angles(grid, sep.f, sep.e, model)["sep_dev"],
                  label=f"(b) 90° − separation, best fit f = {sep.f:.3f}, e = {sep.e:.3f}", color="C3", style="--"),
            layer("line", grid, mk.angles(grid, cue.f, cue.e, model)["cue_dev"],
                  label=f"(c1) 90° − ψ − $\\alpha_1$, best fit f = {cue.f:.3f}, e = {cue.e:.3f}", color="C2",
                  style="--"),
            layer("errorbar", throw.psi, throw.obs, np.full(throw.psi.size, 0.5),
                  label=f"Doménech-Carbó 2023 ({throw.psi.size} markers, ±0.5°)", color="k", marker=".")),
        ylim=(-0.2, 8.0), legend="below",
        reading=("The δ2 markers against ψ with three readings of them, each with its best (f, e): the object ball's "
                 "throw off the line of centres (a, solid, with the joint fit's band), 90° minus the separation "
                 "angle (b) and the cue ball's departure from the tangent line (c1), dashed. "
                 f"(a) and (b) both follow the markers' rise (−2 ln L {readings['throw'].m2lnl:.1f} and "
                 f"{sep.m2lnl:.1f}); (c1) does not ({cue.m2lnl:.1f}): its kink is where, with its large f, the contact "
                 "stops slipping during the impact (at smaller ψ)."))
    panels = []
    for part, s, title in ((alpha, slopes[0], "$\\alpha_1$"), (throw, slopes[1], "$\\delta_2$ read as throw")):
        res = part.obs - mk.angles(part.psi, fj.f, fj.e, model)[part.key]
        line = np.mean(res) + s.slope * (grid - np.mean(part.psi))
        panels.append(FigureSpec(
            f"residuals-{part.key}",
            f"{title}: trend {s.slope * 10:+.2f} ± {s.stderr * 10:.2f}° per 10°, p = {_p(s.p)}",
            "", "", (
                layer("hband", (), [-0.5, 0.5], color="C7"),
                layer("points", part.psi, res, color="k", marker="."),
                layer("line", grid, line, color="C3"))))
    fig_r = FigureSpec(
        "oblique-residuals", "Residuals of the joint fit against ψ", "impact angle ψ (degrees, 0 = head-on)",
        "measured − §VI (degrees)", (), panels=tuple(panels), columns=1,
        reading=("What the joint fit leaves, marker by marker (dots), against ψ, with the least-squares line through "
                 "them (red) and the ±0.5° digitisation error (grey): a constant friction through the impact (§VI) "
                 "leaves no trend. α1 shows none; the throw's residuals fall with ψ "
                 f"(p = {_p(slopes[1].p)}), the sign of a friction that is larger at the slower slips of small ψ."))
    return fig_a, fig_d, fig_r
