"""Kind ``cue``: the stroke of an inclined cue and the motion that follows on the cloth (§VII n°14, §II).

Each formula and number of n°14 is a row, checked against the impulse integration of eqs (3)
(``reference.integrate_cue_impulse``); ε′ of the cue is recomputed from Coriolis's data of n°5 (never the
printed 0,27), and the strokes are followed on the cloth with §II to tell direct from retrograde motion.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import Experiment, Node
from ..mechanics import cloth, cue, impact, reference
from .base import Computed, FigureSpec, Reproduction, layer, modern_rows, read_ball, rows_for

QUANTITIES = ("eq5_full_moment", "eq5_own_moment", "eq7_own_moment", "eq7_n1_as_printed", "eq7_n1_original",
              "energy_resal",
              "energy_resal_beyond", "central_stroke", "friction_angle_high", "friction_angle_low", "epsp_cue",
              "criterion_as_printed", "criterion_derived")
COST = 1.5  # CPU seconds of a run with its figures, about: the process pool starts the longest first
MODERN = ("e_tip", "mu_tip", "m_ball/m_cue", "mu_s")


@dataclass(frozen=True)
class Params:
    R: float
    k: float
    M: float
    Mp: float
    V0p: float
    f: float
    eps: float
    mass_ratio_n5: float  # Coriolis's pendulum (n°5): cue/ball mass ratio …
    ratio_struck_n5: float  # … and the measured V1′/V0, from which ε′ of the cue is recomputed
    tip_friction: tuple[float, ...]
    fan_inclinations: tuple[float, ...]  # rad
    fan_heights: tuple[float, ...]  # c/R
    fan_side: float  # b/R
    region_i_max: float  # rad
    g: float  # gravity, for the motion on the cloth after the stroke


def parse(node: Node, base: Path) -> Params:
    R, k, M = read_ball(node, with_mass=True)
    c = node.child("cue", "a mapping with M and V0")
    Mp = c.number("M", "a mass in kg", lo=0.0, lo_open=True)
    V0p = c.number("V0", "a speed in m/s", lo=0.0, lo_open=True)
    c.done()
    f = node.number("f", "a friction coefficient of the cloth", lo=0.0, lo_open=True)
    eps = node.number("eps", "Résal's ε of the ball", lo=0.0, hi=1.0)
    n5 = node.child("coriolis_n5", "a mapping with mass_ratio and V1p_over_V0")
    mr = n5.number("mass_ratio", "the cue/ball mass ratio", lo=0.0, lo_open=True)
    rp = n5.number("V1p_over_V0", "a velocity ratio", lo=0.0, lo_open=True)
    n5.done()
    tips = node.number_list("tip_friction", "friction coefficients")
    fan = node.child("fan", "a mapping with inclinations_deg, heights, side")
    incl = tuple(math.radians(x) for x in fan.number_list("inclinations_deg", "angles in degrees"))
    if any(not 0 <= x < math.pi / 2 for x in incl):
        raise fan.fail("'params.fan.inclinations_deg' must be angles in [0, 90)")
    heights = fan.number_list("heights", "heights c/R")
    side = fan.number("side", "a side offset b/R", lo=-1.0, hi=1.0)
    if any(h * h + side * side >= 1 for h in heights):
        raise fan.fail("'params.fan': every contact point must lie on the ball: (c/R)² + (b/R)² < 1")
    fan.done()
    i_max = math.radians(node.number("region_i_max_deg", "an angle in degrees", lo=0.0, hi=90.0, hi_open=True))
    g = node.number("g", "gravity in m/s²", default=9.81, lo=0.0, lo_open=True)
    node.done()
    return Params(R, k, M, Mp, V0p, f, eps, mr, rp, tips, incl, heights, side, i_max, g)


def epsp_from_n5(p: Params) -> float:
    """ε′ of the cue from Coriolis's pendulum data (n°5) with the ball's ε as in §VII: the second of eqs (8)
    with M = cue, M′ = ball gives M′(1 + ε_cue) + M(1 + ε_ball) = 2M/(V1′/V0)."""
    D_over_ball = float(impact.denominator_from_struck_ratio(p.mass_ratio_n5, p.ratio_struck_n5))
    return D_over_ball - 1.0 - p.mass_ratio_n5 * (1.0 + p.eps)


def _random_strokes(seed: int, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    i = np.radians(rng.uniform(0.0, 80.0, n))
    r = np.sqrt(rng.uniform(0.0, 0.7**2, n))
    th = rng.uniform(0.0, 2 * np.pi, n)
    return i, r * np.cos(th), r * np.sin(th), rng.uniform(0.1, 0.6, n)  # i, b/R, c/R, f


@dataclass(frozen=True)
class Sample:
    """Random off-centre strokes (``_random_strokes``) with the ball's state per unit impulse for Résal's moment
    about Cy (``resal``) and the full one (``exact``), and the angle φ of the cue's axis with the normal (eq. 11)."""

    i: np.ndarray
    b: np.ndarray
    c: np.ndarray
    f: np.ndarray
    per: dict[str, dict[str, np.ndarray]]
    phi: np.ndarray

    def inside(self, f_tip: float) -> np.ndarray:
        """The paper's domain (line 721): the cue's axis inside the tip's friction cone, φ ≤ atan f_tip."""
        return self.phi <= float(cue.miscue_angle(f_tip))


def _sample(p: Params, seed: int, n: int = 4000) -> Sample:
    i, bR, cR, f = _random_strokes(seed, n)
    return _strokes(p, i, bR * p.R, cR * p.R, f)


def _strokes(p: Params, i: np.ndarray, b: np.ndarray, c: np.ndarray, f: np.ndarray) -> Sample:
    per = {m: cue.stroke_per_impulse(i, b, c, R=p.R, k=p.k, f=f, M=p.M, method=m) for m in ("resal", "exact")}
    return Sample(i, b, c, f, per, np.arccos(np.clip(per["resal"]["cos_phi"], -1.0, 1.0)))


def _gain(p: Params, epsp: float, per: dict[str, np.ndarray], b: np.ndarray, *, axis_end: bool) -> np.ndarray:
    """Relative change of vis viva in the stroke, (T1 − M′V′0²)/(M′V′0²), the ball's state after an impulse P being
    P times ``per`` (eqs 7) and ω1 given by eq. (10) with A of (8), ω being the cue speed lost at the greatest
    compression: by eq. (12), equal velocities along the normal at the contact (Résal's), or, with ``axis_end``,
    equal velocities along the cue's axis, the line of the impulse."""
    M, Mp, V0, R, k = p.M, p.Mp, p.V0p, p.R, p.k
    v, w = per["v"], per["w"]
    Q = M * (v[0] ** 2 + v[1] ** 2) + M * R * R / k * np.sum(w**2, axis=0)  # the ball's vis viva per P²
    A = 1.0 + Mp * Q
    if axis_end:
        omega = V0 / (1.0 + Mp * per["d_K_d"])
    else:  # eq. (12): V′ cos φ = −(χa + ηb)/R
        normal = (per["a"] * v[0] + b * v[1]) / R
        omega = V0 * per["cos_phi"] / (per["cos_phi"] - Mp * normal)
    omega1 = 2 * A * omega / (A + p.eps * (A - 1) + epsp)  # eq. (10)
    return (Mp * (V0 - omega1) ** 2 + (Mp * omega1) ** 2 * Q - Mp * V0**2) / (Mp * V0**2)


ENDS = (("resal", False, "resal"), ("resal", True, "axis"), ("exact", False, "moment"), ("exact", True, "both"))


def _energy(p: Params, seed: int, epsp: float) -> dict[str, float]:
    """The vis viva after the stroke by eqs (10)-(12) over random off-centre strokes (§I n°2: it is never gained).
    Where the paper applies them: the cue's axis inside the tip's friction cone (line 721) and the ball sliding on
    the cloth (the premise of eqs 2-8); apart: the strokes of the cone that the cloth holds (row eq7_grip) and those
    beyond the cone (« fausse queue »). ``energy_<tag>``: the largest relative gain (signed: > 0, vis viva gained)
    with Résal's moment and end of compression (resal), the end along the axis (axis), the full moment (moment),
    both (both)."""
    s = _sample(p, seed + 1)
    out: dict[str, float] = {}

    def record(key: str, gain: np.ndarray, mask: np.ndarray) -> None:
        out[key] = float(np.max(gain[mask], initial=-np.inf))
        out[key + "_share"] = float(np.mean(gain[mask] > 1e-12)) if mask.any() else 0.0
        out[key + "_count"] = float(np.sum(mask))

    gains = {(m, e): _gain(p, epsp, s.per[m], s.b, axis_end=e) for m, e, _ in ENDS}
    for name, f_tip in (("", max(p.tip_friction)), ("_narrow", min(p.tip_friction))):
        inside = s.inside(f_tip)
        for m, e, tag in ENDS:
            slides = s.per[m]["slides"]
            record(f"energy_{tag}{name}", gains[m, e], inside & slides)
            record(f"energy_{tag}_grip{name}", gains[m, e], inside & ~slides)
    beyond = ~s.inside(max(p.tip_friction))
    for m, e, tag in ENDS:
        record(f"energy_{tag}_beyond", gains[m, e], beyond)
    g = gains["resal", False]
    out["energy_phi_beyond"] = float(np.degrees(s.phi[beyond][np.argmax(g[beyond])])) if beyond.any() else 0.0
    return out


def _tip_slip(p: Params, s: Sample, method: str) -> np.ndarray:
    """The ball's slip on the tip, over V′0, at the greatest compression as Résal ends it (equal normal velocities at
    the contact, eq. 12), along the projection of the cue's axis on the tangent plane (the slip ω of eq. d), the
    state after an impulse P being P times the state per unit impulse (eqs 7); NaN where (12) gives no positive P."""
    per, R, Mp, V0 = s.per[method], p.R, p.Mp, p.V0p
    v, w = per["v"], per["w"]
    r = np.stack([per["a"], s.b, s.c])
    K = np.stack([v[0], v[1], np.zeros_like(v[0])]) + np.cross(w, r, axis=0)  # contact point's velocity per unit P
    n = r / R
    d = cue.cue_axis(s.i)
    cphi = per["cos_phi"]
    den = cphi - Mp * np.sum(K * n, axis=0)
    P = np.where(den > 0, Mp * V0 * cphi / np.where(den > 0, den, 1.0), np.nan)  # M′ω of eq. (12)
    t = d + cphi * n  # d minus its normal part (d·n = −cos φ), of length sin φ
    sin_phi = np.linalg.norm(t, axis=0)
    slip = np.sum((P * K - (V0 - P / Mp) * d) * t, axis=0) / np.where(sin_phi > 0, sin_phi, 1.0)
    return np.abs(slip) / V0


def checks(p: Params, seed: int, epsp: float) -> dict[str, float]:
    R, k, M = p.R, p.k, p.M
    i, bR, cR, f = _random_strokes(seed, 16)
    worst = {"eq5_full_moment": 0.0, "eq5_own_moment": 0.0, "eq7_own_moment": 0.0, "eq7_n1_as_printed": 0.0,
             "eq7_n1_original": 0.0}
    for ii, b, c, ff in zip(i, bR * R, cR * R, f, strict=True):
        P = 0.5
        for full in (True, False):
            per = cue.stroke_per_impulse(ii, b, c, R=R, k=k, f=ff, M=M, method="exact" if full else "resal")
            y = reference.integrate_cue_impulse(ii, float(per["a"]), b, c, R, k, ff, M, P, moment_a_term=full)
            if not bool(per["slides"]):
                continue  # (5) and (7) assume the ball slides on the cloth
            gamma_int = math.atan2(y[1] + y[2] * R, y[0] - y[3] * R)
            gamma_printed = math.atan(k * b * math.tan(ii) / (k * c - R))  # eq. (5) as printed: tan γ only
            dg = abs((gamma_printed - gamma_int + math.pi / 2) % math.pi - math.pi / 2)  # compared modulo π
            key = "eq5_full_moment" if full else "eq5_own_moment"
            worst[key] = max(worst[key], dg)
            if full:
                continue
            mu = 1.0 / M  # per unit impulse P = M′ω1: μω1 = P/M
            si, ci = math.sin(ii), math.cos(ii)
            cg, sg = math.cos(gamma_int), math.sin(gamma_int)
            printed = np.array([mu * (ci - ff * cg * si), -mu * ff * sg * si,
                                -(k / R**2) * mu * (b + ff * R * cg * si),  # n1 as printed
                                (k / R**2) * mu * (c * ci + ff * R * cg * si), -(k / R**2) * mu * b * ci]) * P
            scale = np.array([1, 1, R, R, R]) / (P / M)
            err = np.abs(printed - y) * scale
            worst["eq7_own_moment"] = max(worst["eq7_own_moment"], float(np.max(err[[0, 1, 3, 4]])))
            worst["eq7_n1_as_printed"] = max(worst["eq7_n1_as_printed"], float(err[2]))
            n1_original = -(k / R**2) * mu * (b + ff * R * sg) * si * P  # n1 as most likely printed in 1883
            worst["eq7_n1_original"] = max(worst["eq7_n1_original"], float(abs(n1_original - y[2]) * R / (P / M)))
    worst.update(_energy(p, seed, epsp))
    # eqs (10)-(12) with Résal's choices, for a central horizontal stroke, against n°5's direct impact, eq. (8), at
    # random pairs ε, ε′: the two are computed by different formulas (cue.cue_stroke, impact.direct_impact)
    e_b, e_c = np.random.default_rng(seed + 2).uniform(0.0, 1.0, (2, 50))
    s0 = cue.cue_stroke(M, p.Mp, p.V0p, 0.0, 0.0, 0.0, R=R, k=k, f=p.f, eps=e_b, epsp=e_c, method="resal")
    d0 = impact.direct_impact(p.Mp, M, p.V0p, 0.0, eps=e_c, epsp=e_b)
    worst["central_stroke"] = float(max(np.max(np.abs(s0.chi1 - d0.V1p)), np.max(np.abs(s0.V1p - d0.V1)))) / p.V0p
    # direct or retrograde: the sign of χ1 (first of eqs 7) against the printed criterion cos γ ≶ f cos i
    ig, cg = np.meshgrid(np.radians(np.linspace(1, 89, 60)), np.linspace(-0.9, 0.9, 41), indexing="ij")
    per = cue.stroke_per_impulse(ig, 0.3 * R, cg * R, R=R, k=k, f=p.f, M=M, method="resal")
    direct = per["v"][0] > 0
    printed_direct = np.cos(per["gamma"]) < p.f * np.cos(ig)
    sl = per["slides"]
    worst["criterion_as_printed"] = float(np.mean(printed_direct[sl] != direct[sl]))
    return worst


def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    epsp = epsp_from_n5(p)
    c = checks(p, exp.seed, epsp)
    k = claims(p, exp.seed, epsp)
    how = "largest discrepancy from the impulse integration of eqs (3) over 16 random strokes"
    computed = {key: Computed(c[key], how) for key in QUANTITIES[:len(QUANTITIES) - len(CLAIMS)] if key in c}
    computed["eq5_full_moment"] = Computed(c["eq5_full_moment"], how, lambda _p: (
        f"eq. (2) omits the moment F a sin i of the cue force about Cy (its line passes through (a, b, c)); with it, "
        f"tan γ = −(k/R) b sin i / (cos i − (k/R)(c cos i + a sin i)) and (5) errs by up to "
        f"{math.degrees(c['eq5_full_moment']):.1f}°"))
    computed["eq7_n1_as_printed"] = Computed(c["eq7_n1_as_printed"], how, lambda _p: (
        "eq. (2) integrates to R²n1/k = −μ(b + fR sin γ) sin i ω1; the printed −μ(b + fR cos γ sin i) ω1 has "
        "cos γ for sin γ and b without sin i (a slip of the original or of the transcription); the likely original "
        "is graded in row eq7_n1_original"))
    computed["eq7_n1_original"] = Computed(c["eq7_n1_original"], (
        "R²n1/k = −μ(b + fR sin γ) sin i ω1, the likely original of the digitised line n1 of eqs (7) (eq. 3 "
        "integrated with γ constant), against the integration of Résal's own eqs (2) over the random sliding strokes "
        "(relative to μω1)"))
    computed.update(_energy_rows(p, c))
    computed["central_stroke"] = Computed(c["central_stroke"], (
        "eqs (10)-(12) with Résal's choices for a central horizontal stroke (i = b = c = 0: cos φ = 1, A = 1 + μ), "
        "against n°5's direct impact, eq. (8), computed apart, at 50 random pairs ε, ε′: the largest difference of "
        "the ball's and the cue's speeds after the stroke, over V′0. A wrong (10) (ω for ω1, another denominator) "
        "would fail it; n°5's ε′ of the cue, which line 212 extends to a stroke given in any manner, is graded in "
        "row epsp"))
    deg = [math.degrees(float(cue.miscue_angle(t))) for t in sorted(p.tip_friction)]
    computed["friction_angle_high"] = Computed(deg[-1], f"atan {max(p.tip_friction):g} in degrees")
    computed["friction_angle_low"] = Computed(deg[0], f"atan {min(p.tip_friction):g} in degrees", lambda pr: (
        f"atan {min(p.tip_friction):g} = {deg[0]:.4f}° = {int(deg[0])}°{(deg[0] % 1) * 60:.1f}′; the printed "
        f"{int(pr)}°{(pr % 1) * 60:.0f}′ is 1.4′ too large (rounded to 10′?)"))
    computed["epsp_cue"] = Computed(epsp, "ε′ of the cue from Coriolis's n°5 data with ε = 0 for the ball",
                                    lambda pr: (
        f"with ε = {p.eps:g} for the ball, Coriolis's data (n°5) give ε′ = {epsp:.4g} for the cue; {pr:g} is n°5's "
        f"value for the ball when the cue's coefficient is 0: §VII swaps the two (see coriolis-pendulum)"))
    computed["criterion_as_printed"] = Computed(c["criterion_as_printed"], (
        "share of sliding strokes (b = 0,3R, c and i on a grid) where the printed criterion disagrees with the sign "
        "of χ1"), lambda _p: (
        f"the printed « cos γ ≶ f cos i » disagrees with the sign of χ1 (first of eqs 7) on "
        f"{c['criterion_as_printed']:.0%} of the grid; the first of eqs (7) gives direct motion iff "
        f"f cos γ tan i < 1, which never disagrees: the printed criterion is garbled; its likely original, "
        f"cos i ≷ f cos γ sin i, is stated in row criterion_derived (with the full moment: rows criterion_full, "
        "criterion_repaired)"))
    computed["criterion_derived"] = Computed(None, (
        "a definition: the criterion as most likely printed, cos i ≷ f cos γ sin i, restates the sign of the first of "
        "eqs (7), χ1 = μ(cos i − f cos γ sin i)ω1 with μω1 > 0, for any value (eqs 7 against the integration of "
        "Résal's eqs 2: row eq7). Its retrograde branch is empty in his own equations: no sliding stroke is retrograde "
        f"(share {k['retro_own_share']:.0%} over i up to 89.9°, c/R in ±0.99), that needs c < −R; retrograde "
        "motion exists only through the omitted moment F a sin i (rows criterion_full, criterion_repaired)"))
    computed.update(_claim_rows(p, k, epsp))
    central = cue.cue_stroke(p.M, p.Mp, p.V0p, 0.0, 0.0, 0.0, R=p.R, k=p.k, f=p.f, eps=p.eps, epsp=epsp)
    ratio = float(central.chi1) / p.V0p
    mu = p.Mp / p.M
    modern = modern_rows(exp.modern, {
        "e_tip": (ratio * (1 + mu) / mu - 1, "Newton's e of a central stroke with ε = 0, ε′ from n°5"),
        "mu_tip": (max(p.tip_friction), "the chalked tip's friction, 0,20-0,50 (footnote of n°14)"),
        "m_ball/m_cue": (1 / mu, "1/μ, « diffère généralement peu de trois unités »"),
        "mu_s": (p.f, "the ball-cloth friction the stroke's motion on the cloth uses (n°7's f)"),
    })
    return Reproduction(exp, rows_for(exp, computed), (), (_figure_fan(p, epsp), _figure_region(p, epsp)), modern,
                        data_note=f"ε = {p.eps:g} (ball), ε′ = {epsp:.6g} (cue, from n°5), f = {p.f:g}, μ = {mu:g}")


def _after(p: Params, epsp: float, i: np.ndarray, cR: np.ndarray, bR: float) -> tuple:
    s = cue.cue_stroke(p.M, p.Mp, p.V0p, i, bR * p.R, cR * p.R, R=p.R, k=p.k, f=p.f, eps=p.eps, epsp=epsp)
    m = cloth.slide(s.chi1, s.eta1, s.n1, s.p1, R=p.R, k=p.k, f=p.f, g=p.g)
    return s, m


def _figure_fan(p: Params, epsp: float) -> FigureSpec:
    """One panel per inclination of the cue; colour: the height of the contact point; dashed: retrograde."""
    panels, retro_at = [], []
    n = len(p.fan_heights)
    colours = [f"viridis:{0.85 * j / max(n - 1, 1):.3f}" for j in range(n)]
    for k, i in enumerate(p.fan_inclinations):
        layers, retro = [], []
        for h, colour in zip(p.fan_heights, colours, strict=True):
            s, m = _after(p, epsp, np.array(i), np.array(h), p.fan_side)
            t = np.linspace(0.0, 1.5 * float(m.t_roll) + 1e-9, 100)
            x, y, _, _ = cloth.state_at(t, s.chi1, s.eta1, s.n1, s.p1, R=p.R, k=p.k, f=p.f, g=p.g)
            back = float(m.vx_roll) < 0
            if back:
                retro.append(h)
            layers.append(layer("line", x, y, label=f"c/R = {h:g}".replace("-", "−") if k == 0 else "", color=colour,
                                style="--" if back else "-"))
            layers.append(layer("points", [float(m.x_roll)], [float(m.y_roll)], color=colour, marker="o"))
        if k == 0:  # the key to the line styles and dots, once
            layers += [layer("line", label="direct", color="0.3"),
                       layer("line", label="retrograde", color="0.3", style="--"),
                       layer("points", label="onset of rolling", color="0.3", marker="o")]
        retro_at.append(retro)
        panels.append(FigureSpec(f"strokes-{k}", f"inclination i = {math.degrees(i):.0f}°", "", "", tuple(layers)))
    said = "; ".join(
        f"at i = {math.degrees(i):.0f}° " + ("none" if not r else "all" if len(r) == n else
                                              "c/R = " + ", ".join(f"{h:g}".replace("-", "−") for h in r))
        for i, r in zip(p.fan_inclinations, retro_at, strict=True))
    return FigureSpec("strokes", "Strokes of an inclined cue, then the cloth (§VII, §II)", "x along the cue (m)",
                      "y (m)", (), caption=(
                          f"c/R ∈ {{{', '.join(f'{h:g}'.replace('-', '−') for h in p.fan_heights)}}} (colour), "
                          f"b/R = {p.fan_side:g}, "
                          f"f = {p.f:g}; dashed: retrograde; dots: onset of rolling"),
                      reading=(
                          f"The path of the ball on the cloth after strokes of the cue at {len(p.fan_inclinations)} "
                          f"inclinations i (one panel each) and {n} heights c/R of the contact point (colours), the "
                          "cue along Ox and hit "
                          f"off centre by b/R = {p.fan_side:g}: Euler's parabola while the ball slides, then the "
                          "straight line once it rolls (dot). Dashed paths end up moving back towards the cue "
                          f"(retrograde): {said}."),
                      panels=tuple(panels), columns=2, sharey=True, legend="below")


def _figure_region(p: Params, epsp: float) -> FigureSpec:
    heights = np.linspace(-0.9, 0.9, 91)
    incl = np.linspace(0.0, p.region_i_max, 86)
    ii, hh = np.meshgrid(incl, heights, indexing="xy")  # rows: c/R, columns: i
    s, m = _after(p, epsp, ii, hh, p.fan_side)
    final = np.asarray(m.vx_roll) / p.V0p
    deg = np.degrees(incl)
    layers = [layer("heatmap", deg, heights, z=final, label="final velocity along Ox / $V′_0$", centre=0.0),
              layer("contour", deg, heights, z=final, label="final velocity 0 (retrograde to its right)", color="k")]
    phi_max = float(cue.miscue_angle(max(p.tip_friction)))
    phi = np.arccos(np.clip(np.asarray(s.cos_phi), -1, 1))  # beyond the tip's friction cone: a miscue
    layers.append(layer("contour", deg, heights, z=phi - phi_max, color="C1", style=":",
                        label=f"miscue outside the dotted band (tip friction {max(p.tip_friction):g})"))
    layers.append(layer("contour", deg, heights, z=np.asarray(s.chi1) / p.V0p,
                        label="$\\chi_1$ = 0 (first of eqs 7)", color="k", style="--"))
    both = (final < 0) & (phi <= phi_max)  # retrograde without a miscue
    inside = ("no retrograde stroke of the grid lies inside it." if not both.any() else
              f"only {both.sum() / max((final < 0).sum(), 1):.0%} of the retrograde strokes lie inside it, with the "
              f"cue at {math.degrees(ii[both].min()):.0f}° or steeper and the contact at c/R ≥ {hh[both].min():.2f}.")
    return FigureSpec("retrograde-region", "Final motion along the cue's direction (negative: retrograde)",
                      "inclination i of the cue (degrees)", "height c/R of the contact point", tuple(layers),
                      caption=f"b/R = {p.fan_side:g}, f = {p.f:g}; stroke with the full moment, then §II",
                      legend="below",
                      reading=(
                          "The velocity with which the ball finally rolls along the cue's direction, over the cue's "
                          "inclination i and the height c/R of the contact point (blue: forward; red: back towards "
                          "the cue, §VII's retrograde motion); on the solid line it ends with no motion along Ox, on "
                          "the dashed one it leaves the cue with none (χ1 = 0), and between the two the stroke sends "
                          "it forward and its spin brings it back. Outside the dotted band the tip "
                          f"would slide on the ball (a miscue, tip friction {max(p.tip_friction):g}): " + inside))


# ---- n°14 claim by claim (issue 13): each printed line against an independent computation ----------------------
CLAIMS = ("eq1_slip", "eq2_as_digitised", "eq2_original", "eq2_moment_y", "eq2_repaired", "eq3_as_digitised",
          "eq3_original", "eq4_constant",
          "eq5_repaired", "eq7_grip", "eq7_full_chi", "eq7_full_eta", "eq7_full_n", "eq7_full_p", "eq7_full_q",
          "eq7_repaired", "eq6_definition", "eqa_lost", "eq8_as_digitised", "eq8_original", "eq8_full_moment",
          "eq8_repaired", "eqb_ball", "eqc_cue",
          "eqd_as_printed", "eq9_as_printed", "eq9p_as_printed", "eq9p_corrected", "eq10_as_digitised",
          "eq10_original", "eq11_as_printed", "eq_normal_velocity", "eq_normal_velocity_7", "eq12_as_derived",
          "cone_no_slip", "criterion_full", "criterion_repaired", "eps_n5_fraction", "eps_n5_original",
          "eps_n5_decimal", "mu_ratio", "tip_friction_range", "f_cloth")


def _scenes(seed: int, n: int, p: Params, *, slides: bool, full: bool, i_max_deg: float = 80.0) -> list[tuple]:
    """Random reachable strokes (cos φ > 0.05) where the ball slides on the cloth (or is held by it)."""
    rng = np.random.default_rng(seed)
    out: list[tuple] = []
    for _ in range(200):
        ii = math.radians(rng.uniform(0.0, i_max_deg))
        r, th = math.sqrt(rng.uniform(0.0, 0.7**2)), rng.uniform(0.0, 2 * math.pi)
        b, c, ff = r * math.cos(th) * p.R, r * math.sin(th) * p.R, rng.uniform(0.1, 0.6)
        per = cue.stroke_per_impulse(ii, b, c, R=p.R, k=p.k, f=ff, M=p.M, method="exact" if full else "resal")
        if float(per["cos_phi"]) > 0.05 and bool(per["slides"]) == slides:
            out.append((ii, float(per["a"]), b, c, ff, per))
            if len(out) == n:
                break
    return out


def _y(p: Params, s: tuple, P: float, full: bool) -> np.ndarray:
    ii, a, b, c, ff, _ = s
    return reference.integrate_cue_impulse(ii, a, b, c, p.R, p.k, ff, p.M, P, moment_a_term=full)


def _gamma_printed(p: Params, ii: float, b: float, c: float) -> float:
    """γ of eq. (5) as printed, tan γ = kb tang i/(kc − R), in the quadrant of Résal's derivation (the slip grows
    along (dχ − R dp, dη + R dn) of his eqs 3: cos γ has the sign of (R − kc) cos i)."""
    return math.atan2(-p.k * b * math.sin(ii), (p.R - p.k * c) * math.cos(ii))


def _gamma_repaired(p: Params, ii: float, a: float, b: float, c: float) -> float:
    """eq. (5) repaired with the full moment: tan γ = kb sin i/(k(c cos i + a sin i) − R cos i), cos γ of the sign of
    R cos i − k(c cos i + a sin i)."""
    si, ci = math.sin(ii), math.cos(ii)
    return math.atan2(-p.k * b * si, p.R * ci - p.k * (c * ci + a * si))


def _eq7_printed(p: Params, ii: float, a: float, b: float, c: float, ff: float, g: float, P: float, *,
                 n1_as_digitised: bool = False, a_term: bool = False) -> np.ndarray:
    """Eqs (7) with μω1 = P/M: (χ1, η1, n1, p1, q1). n1 as most likely printed in 1883, −μ(b + fR sin γ) sin i ω1,
    unless ``n1_as_digitised`` (−μ(b + fR cos γ sin i) ω1); ``a_term`` adds the moment a sin i to p1 (repair)."""
    k, R = p.k, p.R
    si, ci, cg, sg = math.sin(ii), math.cos(ii), math.cos(g), math.sin(g)
    mu_w = P / p.M
    n1 = -(b + ff * R * cg * si) if n1_as_digitised else -(b + ff * R * sg) * si
    p1 = c * ci + (a * si if a_term else 0.0) + ff * R * cg * si
    return np.array([mu_w * (ci - ff * cg * si), -mu_w * ff * sg * si, (k / R**2) * mu_w * n1,
                     (k / R**2) * mu_w * p1, -(k / R**2) * mu_w * b * ci])


def _A(p: Params, ii: float, b: float, c: float, ff: float, g: float, mu: float, *, digitised: bool) -> float:
    """eq. (8): as digitised (k²/R, (b + fR)², (c cos i + R cos γ sin i)²) or as most likely printed in 1883
    (k/R², (b + fR sin γ)², (c cos i + fR cos γ sin i)²)."""
    k, R = p.k, p.R
    si, ci, cg, sg = math.sin(ii), math.cos(ii), math.cos(g), math.sin(g)
    head = (ci - ff * cg * si) ** 2 + ff**2 * sg**2 * si**2
    if digitised:
        return 1 + mu * (head + k**2 / R * ((b + ff * R) ** 2 * si**2 + (c * ci + R * cg * si) ** 2 + b**2 * ci**2))
    return 1 + mu * (head + k / R**2 * ((b + ff * R * sg) ** 2 * si**2 + (c * ci + ff * R * cg * si) ** 2
                                        + b**2 * ci**2))


def _A_repaired(p: Params, ii: float, a: float, b: float, c: float, ff: float, g: float, mu: float) -> float:
    """eq. (8) repaired with the full moment: γ of the repaired (5) and c cos i + a sin i in the second square."""
    k, R = p.k, p.R
    si, ci, cg, sg = math.sin(ii), math.cos(ii), math.cos(g), math.sin(g)
    return 1 + mu * ((ci - ff * cg * si) ** 2 + ff**2 * sg**2 * si**2 + k / R**2 * (
        (b + ff * R * sg) ** 2 * si**2 + (c * ci + a * si + ff * R * cg * si) ** 2 + b**2 * ci**2))


def _ball_vis_viva(p: Params, y: np.ndarray) -> float:
    return p.M * (y[0] ** 2 + y[1] ** 2) + p.M * p.R**2 / p.k * float(y[2:5] @ y[2:5])


def _kinematics(p: Params, s: tuple, y: np.ndarray, Vp: float) -> dict[str, float]:
    """At a state y of the ball and a cue speed V′: the approach speed along the normal, the slip of the ball on the
    cue projected on the tangential projection t of the axis, times |t| = cos ψ (ω cos ψ of eq. d), the slip on the
    cloth |v| (ω′ of eq. d)."""
    ii, a, b, c, _, _ = s
    d = cue.cue_axis(ii)
    nhat = np.array([a, b, c]) / p.R
    wc = cue.ball_point_velocity(*y, np.array([a, b, c]))
    foot = cue.ball_point_velocity(*y, np.array([0.0, 0.0, -p.R]))
    t = d - (d @ nhat) * nhat
    return {"approach": float((Vp * d - wc) @ -nhat), "w_cos_psi": float((wc - Vp * d) @ t),
            "cloth_slip": float(math.hypot(foot[0], foot[1])), "normal_ball": float(wc @ nhat)}


def _material_velocity(v: np.ndarray, w: np.ndarray, r: np.ndarray) -> np.ndarray:
    """The velocity (x, y) of the ball's material point at r from the centre: the derivative at t = 0 of its position
    v t + Rot(ω t) r under the rigid motion (Rodrigues' rotation), taken by a complex step (exact for an analytic
    motion); v: (vx, vy) of the centre, w: (n, p, q), over the batch."""
    h = 1e-30
    norm = np.linalg.norm(w, axis=0)
    axis = w / norm
    theta = 1j * h * norm
    r = np.asarray(r, dtype=float)[:, None]
    turned = (r * np.cos(theta) + np.cross(axis, r, axis=0) * np.sin(theta)
              + axis * np.sum(axis * r, axis=0) * (1 - np.cos(theta)))
    return v + turned[:2].imag / h


def _criterion_boundary(p: Params) -> dict[str, float]:
    """The criterion cos i ≷ f cos γ sin i with γ of the repaired (5), where it says χ1 = 0: over a grid of heights
    c (b = 0.3R, the cloth's f), the inclinations where cos i = f cos γ sin i, and there, on the strokes that slide
    inside the tip's friction cone, χ1 of the integration of eqs (3) with the full moment, relative to μω1 (it
    vanishes where the criterion is right)."""
    from scipy.optimize import brentq

    R, k, M, f, b = p.R, p.k, p.M, p.f, 0.3 * p.R

    def side(i: float, c: float) -> float:
        a = float(cue.contact_point(b, c, R))
        g = math.atan2(-k * b * math.sin(i), R * math.cos(i) - k * (c * math.cos(i) + a * math.sin(i)))
        return math.cos(i) - f * math.cos(g) * math.sin(i)

    incl = np.radians(np.linspace(0.5, 89.5, 361))
    heights = np.linspace(-0.95, 0.95, 191) * R
    ii, cc = np.meshgrid(incl, heights, indexing="ij")
    aa = cue.contact_point(b, cc, R)
    gg = np.arctan2(-k * b * np.sin(ii), R * np.cos(ii) - k * (cc * np.cos(ii) + aa * np.sin(ii)))
    sign = np.sign(np.cos(ii) - f * np.cos(gg) * np.sin(ii))
    worst, count = 0.0, 0
    P = 0.5
    for j, m in zip(*np.nonzero(sign[:-1] != sign[1:]), strict=True):
        c = float(heights[m])
        i = brentq(side, incl[j], incl[j + 1], args=(c,), xtol=1e-15)
        per = cue.stroke_per_impulse(i, b, c, R=R, k=k, f=f, M=M, method="exact")
        if not bool(per["slides"]) or math.acos(min(1.0, float(per["cos_phi"]))) > math.atan(max(p.tip_friction)):
            continue
        y = reference.integrate_cue_impulse(i, float(per["a"]), b, c, R, k, f, M, P)
        worst, count = max(worst, abs(y[0]) / (P / M)), count + 1
    return {"criterion_repaired": worst if count else float("nan"), "criterion_boundary_count": float(count)}


def claims(p: Params, seed: int, epsp: float) -> dict[str, float]:
    from scipy.optimize import brentq

    R, k, M, Mp, V0 = p.R, p.k, p.M, p.Mp, p.V0p
    mu = Mp / M
    rng = np.random.default_rng(seed + 10)
    out: dict[str, float] = {}
    # eq. (1): the slip of the foot (0, 0, −R), the velocity of the ball's material point there, for random states
    st = rng.normal(size=(5, 200)) * np.array([[1], [1], [1 / R], [1 / R], [1 / R]])
    foot = _material_velocity(st[:2], st[2:], np.array([0.0, 0.0, -R]))
    out["eq1_slip"] = float(np.max(np.abs(foot[:2] - np.stack([st[0] - st[3] * R, st[1] + st[2] * R]))))
    # eqs (2), (3): the force and moments per unit F, from vectors (cue force along d, cloth reaction F sin i and
    # friction f F sin i against the slip at the foot), against the printed lines
    n = 400
    ii, g, ff = rng.uniform(0, 1.5, n), rng.uniform(-math.pi, math.pi, n), rng.uniform(0.05, 0.8, n)
    rr, th = np.sqrt(rng.uniform(0, 0.8, n)) * R, rng.uniform(0, 2 * math.pi, n)
    b, c = rr * np.cos(th), rr * np.sin(th)
    a = cue.contact_point(b, c, R)
    si, ci, cg, sg = np.sin(ii), np.cos(ii), np.cos(g), np.sin(g)
    fric = np.stack([-ff * si * cg, -ff * si * sg, 0 * si])
    force = cue.cue_axis(ii) + np.stack([0 * si, 0 * si, si]) + fric
    moment = cue.cue_moment(ii, a, b, c) + np.cross(np.stack([0 * si, 0 * si, -R + 0 * si]), fric, axis=0)
    dig = np.stack([ci - ff * cg * ci, -ff * sg * si, -(b + ff * sg * R) * si / R, -b * ci / R])  # as digitised
    true = np.stack([force[0], force[1], moment[0] / R, moment[2] / R])
    out["eq2_as_digitised"] = float(np.max(np.abs(dig - true)))
    out["eq2_original"] = float(np.max(np.abs(np.stack([ci - ff * cg * si, *dig[1:]]) - true)))
    out["eq2_moment_y"] = float(np.max(np.abs((c * ci + ff * cg * R * si) - moment[1]) / R))
    # eq. (3) = eq. (2) divided by M′dV′ = −F dt: R²/k dp = −μ(c cos i + fR cos γ sin i) dV′ with Résal's moment
    own_my = c * ci + ff * cg * R * si
    dig3 = np.stack([-(ci - ff * cg * si), ff * sg * si, (b + ff * sg * R) * si / R, own_my / R, b * ci / R])
    derived3 = -np.stack([force[0], force[1], moment[0] / R, own_my / R, moment[2] / R])
    out["eq3_as_digitised"] = float(np.max(np.abs(dig3 - derived3)))
    out["eq3_original"] = float(np.max(np.abs(dig3 * np.array([[1], [1], [1], [-1], [1]]) - derived3)))
    # sliding strokes, Résal's own eqs (2) and the full moment; strokes the cloth holds
    own = _scenes(seed + 20, 12, p, slides=True, full=False)
    full = _scenes(seed + 21, 12, p, slides=True, full=True, i_max_deg=88.0)
    P = 0.5
    scale = P / M
    # eq. (4): the slip keeps one direction γ through the stroke
    worst = 0.0
    for s, is_full in [(s, False) for s in own] + [(s, True) for s in full]:
        gs = []
        for frac in (0.05, 0.3, 0.6, 1.0):
            y = _y(p, s, frac * P, is_full)
            gs.append(math.atan2(y[1] + y[2] * R, y[0] - y[3] * R))
        worst = max(worst, max(abs((x - gs[-1] + math.pi) % (2 * math.pi) - math.pi) for x in gs))
    out["eq4_constant"] = worst
    # angular momentum about the foot B: the cloth's forces act there, the cue's along d through (a, b, c)
    breach = {False: 0.0, True: 0.0}
    for s, is_full in [(s, False) for s in own] + [(s, True) for s in full]:
        ii_, a_, b_, c_ = s[:4]
        y = _y(p, s, P, is_full)
        L = (M * np.cross([0.0, 0.0, R], [y[0], y[1], 0.0]) + M * R * R / k * y[2:5]
             - P * np.cross([a_, b_, c_ + R], cue.cue_axis(ii_)))
        breach[is_full] = max(breach[is_full], float(np.linalg.norm(L)) / (P * R))
    out["eq2_repaired"], out["eq2_own_breach"] = breach[True], breach[False]
    # eqs (5), (7) with the full moment, line by line; the repaired forms
    lines = np.zeros(5)
    rep5 = rep7 = a8f = a8r = 0.0
    for s in full:
        ii_, a_, b_, c_, f_, _ = s
        y = _y(p, s, P, True)
        A_int = 1 + Mp * _ball_vis_viva(p, y) / P**2  # as (8) defines A: 1 + the ball's vis viva over M′ω1²
        a8f = max(a8f, abs(_A(p, ii_, b_, c_, f_, _gamma_printed(p, ii_, b_, c_), mu, digitised=False) - A_int)
                  / A_int)
        a8r = max(a8r, abs(_A_repaired(p, ii_, a_, b_, c_, f_, _gamma_repaired(p, ii_, a_, b_, c_), mu) - A_int)
                  / A_int)
        g_int = math.atan2(y[1] + y[2] * R, y[0] - y[3] * R)
        g_rep = _gamma_repaired(p, ii_, a_, b_, c_)
        rep5 = max(rep5, abs((g_rep - g_int + math.pi / 2) % math.pi - math.pi / 2))
        w = np.array([1, 1, R, R, R]) / scale
        pr = _eq7_printed(p, ii_, a_, b_, c_, f_, _gamma_printed(p, ii_, b_, c_), P)
        lines = np.maximum(lines, np.abs(pr - y) * w)
        rep = _eq7_printed(p, ii_, a_, b_, c_, f_, g_rep, P, a_term=True)
        rep7 = max(rep7, float(np.max(np.abs(rep - y) * w)))
    for key, v in zip(("chi", "eta", "n", "p", "q"), lines, strict=True):
        out[f"eq7_full_{key}"] = float(v)
    out["eq5_repaired"], out["eq7_repaired"] = rep5, rep7
    out["eq8_repaired"] = a8r
    # (8) as most likely printed against the full-moment integration where the paper applies it: the strokes of the
    # random sample that slide inside the tip's friction cone (the first 150 of them)
    sample = _sample(p, seed + 1)
    tip = max(p.tip_friction)
    domain = np.flatnonzero(sample.inside(tip) & sample.per["exact"]["slides"])[:150]
    a8f = 0.0
    for j in domain:
        s_ = (float(sample.i[j]), float(sample.per["exact"]["a"][j]), float(sample.b[j]), float(sample.c[j]),
              float(sample.f[j]), None)
        y = _y(p, s_, P, True)
        A_int = 1 + Mp * _ball_vis_viva(p, y) / P**2
        A8 = _A(p, s_[0], s_[2], s_[3], s_[4], _gamma_printed(p, s_[0], s_[2], s_[3]), mu, digitised=False)
        a8f = max(a8f, abs(A8 - A_int) / A_int)
    out["eq8_full_moment"], out["eq8_full_count"] = a8f, float(len(domain))
    # the premise of line 721: inside the cone the cue does not slide on the ball. The slip at the greatest
    # compression as Résal ends it, over the sample's strokes that slide on the cloth inside the cone (eqs 7)
    for method, key in (("resal", "cone_no_slip"), ("exact", "cone_full")):
        mask = sample.inside(tip) & sample.per[method]["slides"]
        slip = _tip_slip(p, sample, method)[mask]
        out[key] = float(np.nanmax(slip, initial=0.0))
        out[key + "_count"] = float(np.sum(np.isfinite(slip)))
        out[key + "_median"] = float(np.nanmedian(slip)) if np.isfinite(slip).any() else 0.0
    # the closed form against the integration of Résal's eqs (3), the greatest compression found on it, on the first 8
    # of these strokes
    check = 0.0
    closed = _tip_slip(p, sample, "resal")
    mask = np.flatnonzero(sample.inside(tip) & sample.per["resal"]["slides"] & np.isfinite(closed))[:8]
    for j in mask:
        s_ = (float(sample.i[j]), float(sample.per["resal"]["a"][j]), float(sample.b[j]), float(sample.c[j]),
              float(sample.f[j]), None)

        def approach(Pc: float, s_: tuple = s_) -> float:
            return _kinematics(p, s_, _y(p, s_, Pc, False), V0 - Pc / Mp)["approach"]

        Pc = brentq(approach, 0.0, 2.5 * Mp * V0, xtol=1e-14 * Mp * V0, rtol=1e-13)
        kin = _kinematics(p, s_, _y(p, s_, Pc, False), V0 - Pc / Mp)
        sin_phi = math.sqrt(max(1 - float(sample.per["resal"]["cos_phi"][j]) ** 2, 1e-300))
        check = max(check, abs(abs(kin["w_cos_psi"]) / sin_phi / V0 - float(closed[j])))
    out["cone_check"], out["cone_check_count"] = check, float(len(mask))
    # the reference stroke of the note: i = 20°, b = 0.3R, c = 0.1R, the cloth's f (it slides)
    ref = (math.radians(20.0), float(cue.contact_point(0.3 * R, 0.1 * R, R)), 0.3 * R, 0.1 * R, p.f, None)
    y_ref = _y(p, ref, P, True)
    out["eq8_ref_full"] = 1 + Mp * _ball_vis_viva(p, y_ref) / P**2
    out["eq8_ref_original"] = _A(p, ref[0], ref[2], ref[3], p.f, _gamma_printed(p, ref[0], ref[2], ref[3]), mu,
                                 digitised=False)
    # eqs (7) where the cloth holds the ball (the friction is then below f F sin i): the sample's strokes inside the
    # tip's friction cone that Résal's eqs (2) do not let slide (the first 24 of them), against his eqs integrated
    worst = 0.0
    held = sample.inside(tip) & ~sample.per["resal"]["slides"]
    for j in np.flatnonzero(held)[:24]:
        s_ = (float(sample.i[j]), float(sample.per["resal"]["a"][j]), float(sample.b[j]), float(sample.c[j]),
              float(sample.f[j]), None)
        y = _y(p, s_, P, False)
        pr = _eq7_printed(p, s_[0], s_[1], s_[2], s_[3], s_[4], _gamma_printed(p, s_[0], s_[2], s_[3]), P)
        worst = max(worst, float(np.max(np.abs(pr - y) * np.array([1, 1, R, R, R]) / scale)))
    out["eq7_grip"], out["grip_count"] = worst, float(min(24, int(np.sum(held))))
    out["grip_share"] = float(np.sum(held) / np.sum(sample.inside(tip)))
    out["grip_in_cone"] = float(np.sum(held))
    out["grip_cone"] = float(np.sum(sample.inside(tip)))
    out["grip_i_central"] = math.degrees(math.atan(1 / ((1 + k) * p.f)))
    # eq. (6), (a), (8), (b), (c): Résal's own moment, sliding strokes, a cue speed lost ω1 = 0.7 V′0
    w1 = 0.7 * V0
    a_err = a8d = a8o = b_err = 0.0
    for s in own:
        ii_, a_, b_, c_, f_, _ = s
        y = _y(p, s, Mp * w1, False)
        Tb = _ball_vis_viva(p, y)
        V1 = V0 - w1  # eq. (6)
        A_int = 1 + Tb / (Mp * w1**2)
        g = _gamma_printed(p, ii_, b_, c_)
        Ao = _A(p, ii_, b_, c_, f_, g, mu, digitised=False)
        a8o = max(a8o, abs(Ao - A_int) / A_int)
        a8d = max(a8d, abs(_A(p, ii_, b_, c_, f_, g, mu, digitised=True) - A_int) / A_int)
        lost = Mp * V0**2 - Mp * V1**2 - Tb
        a_err = max(a_err, abs(Mp * w1 * (2 * V0 - Ao * w1) - lost) / (Mp * V0**2))
        b_err = max(b_err, abs(Mp * (Ao - 1) * w1**2 - Tb) / Tb)  # ε = 1
    out.update(eqa_lost=a_err, eq8_as_digitised=a8d, eq8_original=a8o, eqb_ball=b_err)
    # the greatest compression as Résal ends it (equal normal velocities), found on the integration. (12) and the
    # two lines before it follow from (7): Résal's own eqs (2). (9′) is an energy balance, true only where the
    # cue's moment is that of its force (the full moment: with Résal's, its work is not F·v of the contact point):
    # there, law (6) at the end of the stroke is solved on the integration for ω1 ((9), (10))
    e9p = e9pc = e12 = e10 = e10d = e9 = nv = nv7 = dd = 0.0
    for j, (s, is_full) in enumerate([(s, False) for s in own] + [(s, True) for s in full]):
        ii_, a_, b_, c_, f_, per = s
        si_, ci_ = math.sin(ii_), math.cos(ii_)
        g = _gamma_repaired(p, ii_, a_, b_, c_) if is_full else _gamma_printed(p, ii_, b_, c_)
        cphi = -(a_ * ci_ - c_ * si_) / R  # eq. (11) with the sign the downward cue requires
        om12 = V0 * cphi / (cphi + mu / R * (b_ * f_ * math.sin(g) * si_ - a_ * (ci_ - f_ * math.cos(g) * si_)))
        if not 0 < om12 < 2 * V0:
            continue  # the denominator of (12) is not positive there: the energy row deals with it

        def approach(Pc: float, s: tuple = s, is_full: bool = is_full) -> float:
            return _kinematics(p, s, _y(p, s, Pc, is_full), V0 - Pc / Mp)["approach"]

        Pc = brentq(approach, 0.0, 2.5 * Mp * om12, xtol=1e-14 * Mp * V0, rtol=1e-13)
        om = Pc / Mp
        yc = _y(p, s, Pc, is_full)
        kin = _kinematics(p, s, yc, V0 - om)
        if not is_full:
            e12 = max(e12, abs(om12 - om) / om)
            nv = max(nv, abs(kin["normal_ball"] - (yc[0] * a_ + yc[1] * b_) / R) / V0)
            nv7 = max(nv7, abs(kin["normal_ball"] - mu * ((ci_ - f_ * math.cos(g) * si_) * a_
                                                          - f_ * b_ * math.sin(g) * si_) * om / R) / V0)
            continue
        A = 1 + Mp * _ball_vis_viva(p, yc) / Pc**2  # the ball's vis viva per M′ω², as (8) defines A
        lhs = 2 * V0 - 2 * A * om
        fr_cue, fr_cloth = 2 * kin["w_cos_psi"], 2 * kin["cloth_slip"] * f_ * si_
        e9p = max(e9p, abs(lhs - (fr_cue - fr_cloth)) / V0)  # as printed: 2ω cos ψ − 2ω′ f sin i
        e9pc = max(e9pc, abs(lhs - (-fr_cue + fr_cloth)) / V0)  # the signs of the law (d corrected)
        dd = max(dd, abs(-2 * Mp * f_ * si_ - 2 * Mp * f_ * si_) / abs(2 * Mp * f_ * si_))
        eps_b, eps_c = (p.eps, epsp) if j == len(own) else tuple(np.random.default_rng(seed + 30 + j).uniform(0, 1, 2))
        work = -fr_cue + fr_cloth  # per unit impulse, with the slips at the greatest compression

        def law6(P1: float, s: tuple = s, work: float = work, eps_b: float = eps_b, eps_c: float = eps_c) -> float:
            y1 = _y(p, s, P1, True)
            Tb = _ball_vis_viva(p, y1)
            return (Mp * V0**2 - Mp * (V0 - P1 / Mp) ** 2 - Tb) - eps_b * Tb - eps_c * P1**2 / Mp - work * P1

        P1 = brentq(law6, 1e-9 * Mp * om, 2.5 * Mp * om, xtol=1e-14 * Mp * V0, rtol=1e-13)
        w1_law = P1 / Mp
        w1_10 = 2 * A * om / (A + (A - 1) * eps_b + eps_c)
        e10 = max(e10, abs(w1_10 - w1_law) / w1_law)
        e10d = max(e10d, abs(om - w1_law) / w1_law)
        e9 = max(e9, abs(2 * V0 - (A + eps_b * (A - 1) + eps_c) * w1_law - (fr_cue - fr_cloth)) / V0)
    out.update(eq9p_as_printed=e9p, eq9p_corrected=e9pc, eq12_as_derived=e12, eq10_original=e10,
               eq10_as_digitised=e10d, eq9_as_printed=e9, eq_normal_velocity=nv, eq_normal_velocity_7=nv7,
               eqd_as_printed=dd)
    # eq. (11): cos φ = −d·n̂ against the printed −(a cos i + c sin i)/R
    d_ = cue.cue_axis(ii)
    out["eq11_as_printed"] = float(np.max(np.abs(-(a * ci + c * si) / R - (-(d_ * np.stack([a, b, c])).sum(0) / R))))
    out["eq11_corrected"] = float(np.max(np.abs(-(a * ci - c * si) / R - (-(d_ * np.stack([a, b, c])).sum(0) / R))))
    # the criterion with the full moment: the likely original cos i ≷ f cos γ sin i with γ of (5) as printed, against
    # the sign of χ1 on the grid's sliding strokes (b = 0.3R), inside the tip's friction cone (the paper's domain) and
    # on all the strokes the cue can reach (cos φ > 0)
    ig, cg_ = np.meshgrid(np.radians(np.linspace(1, 89, 60)), np.linspace(-0.9, 0.9, 41), indexing="ij")
    per = cue.stroke_per_impulse(ig, 0.3 * R, cg_ * R, R=R, k=k, f=p.f, M=M, method="exact")
    reach = per["slides"] & (per["cos_phi"] > 0)
    inside = reach & (np.arccos(np.clip(per["cos_phi"], -1.0, 1.0)) <= math.atan(max(p.tip_friction)))
    direct = per["v"][0] > 0
    g_pr = np.arctan2(-k * 0.3 * R * np.sin(ig), (R - k * cg_ * R) * np.cos(ig))
    crit_pr = p.f * np.cos(g_pr) * np.tan(ig) < 1
    out["criterion_full"] = float(np.mean(crit_pr[inside] != direct[inside]))
    out["criterion_full_reach"] = float(np.mean(crit_pr[reach] != direct[reach]))
    out["retro_full_share"] = float(np.mean(~direct[inside]))
    out["retro_full_count"] = float(np.sum(~direct[inside]))
    out["retro_full_inside"] = float(np.sum(inside))
    out["retro_full_share_reach"] = float(np.mean(~direct[reach]))
    out.update(_criterion_boundary(p))
    own_per = cue.stroke_per_impulse(np.radians(np.linspace(0, 89.9, 400))[:, None], 0.0,
                                     np.linspace(-0.99, 0.99, 199)[None, :] * R, R=R, k=k, f=p.f, M=M,
                                     method="resal")
    out["retro_own_share"] = float(np.mean(own_per["v"][0][own_per["slides"]] < 0))
    # the footnote of n°14: n°5's equation 1 + ε + 3(1 + ε′) = 24/5 with ε = 0 gives ε′ (its own labels)
    D = float(impact.denominator_from_struck_ratio(p.mass_ratio_n5, p.ratio_struck_n5))  # M′(1+ε)+M(1+ε′) over M′
    out["eps_n5_fraction"] = out["eps_n5_original"] = out["eps_n5_decimal"] = (D - 1.0) / p.mass_ratio_n5 - 1.0
    return out


QUANTITIES = QUANTITIES + CLAIMS


def _energy_rows(p: Params, c: dict[str, float]) -> dict[str, Computed]:
    """The rows « vis viva never gained » with eqs (10)-(12) (``_energy``): a violation (the largest gain, 0 if none)
    and the worst signed margin (the least loss, negative where vis viva is gained)."""
    tip, narrow = max(p.tip_friction), min(p.tip_friction)
    cone = f"φ ≤ {math.degrees(float(cue.miscue_angle(tip))):.2f}°"

    def share(key: str) -> str:
        return f"{c[key + '_share']:.0%} of {c[key + '_count']:.0f}"

    def loss(key: str) -> str:
        return (f"every stroke loses at least {-c[key]:.1%} of the cue's vis viva" if c[key] < 0 else
                f"{share(key)} gain, up to +{c[key]:.2f}")

    resal = Computed(max(0.0, c["energy_resal"]), (
        "largest relative gain of vis viva with eqs (10)-(12) as printed (Résal's moment about Cy, the compression "
        "ended on equal normal velocities), over the random off-centre strokes (of 4000) where the paper applies "
        f"them: the cue's axis inside the tip's friction cone ({cone}, tip friction {tip:g}, line 721) and the ball "
        "sliding on the cloth (the premise of eqs 2-8)"), lambda _p: (
        f"inside the paper's domain {share('energy_resal')} sliding strokes gain vis viva, up to "
        f"+{c['energy_resal']:.2f} (relative); in the narrowest cone (tip friction {narrow:g}) "
        f"{share('energy_resal_narrow')}, up to +{c['energy_resal_narrow']:.2f}. Eq. (12) ends the compression on "
        "equal normal velocities while the impulse stays along the cue's axis (the premise of line 721, row cone), "
        "and eq. (2) omits the moment F a sin i (row eq2_moment): the friction term 2V′0 − 2Aω of (9′) turns "
        "negative. Neither repair alone suffices: ending the compression along the axis, the line of the impulse, "
        f"with Résal's moment, {share('energy_axis')} sliding strokes still gain, up to +{c['energy_axis']:.2f}; "
        f"restoring the moment with (12) kept, {share('energy_moment')}, up to +{c['energy_moment']:.2f}; with both "
        f"(method 'exact'), {loss('energy_both')}. The strokes of the cone that the cloth holds, outside the "
        f"sliding premise (row eq7_grip): {share('energy_resal_grip')} gain, up to "
        f"+{c['energy_resal_grip']:.2f}; the strokes beyond the cone: row energy_beyond"),
        margin=-c["energy_resal"])
    beyond = Computed(max(0.0, c["energy_resal_beyond"]), (
        "largest relative gain of vis viva with eqs (10)-(12) as printed, over the random off-centre strokes (of "
        f"4000) whose cue axis lies outside the tip's friction cone (φ > {cone[4:]}: « fausse queue », line 721)"),
        lambda _p: (
        "beyond the friction cone, where the paper says no stroke is of use (« fausse queue », line 721), "
        f"{share('energy_resal_beyond')} random strokes gain vis viva, up to ×{1 + c['energy_resal_beyond']:.3g} "
        f"at φ = {c['energy_phi_beyond']:.0f}°, where the denominator of (12) nears zero (the cloth's friction "
        "drives the ball back against the cue). With the full moment and the compression ended along the axis "
        f"(method 'exact'), {loss('energy_both_beyond')}"), margin=-c["energy_resal_beyond"])
    return {"energy_resal": resal, "energy_resal_beyond": beyond}


def _claim_rows(p: Params, k: dict[str, float], epsp: float) -> dict[str, Computed]:
    """The Computed values of the claim-by-claim rows (``claims``), with what explains each disagreement."""
    integ = "largest discrepancy from the impulse integration of eqs (3) (rtol 1e-10)"
    mu_tip = max(p.tip_friction)
    mu = p.Mp / p.M

    def why(text: str) -> Callable[[float], str]:
        return lambda _pr: text

    return {
        "cone_no_slip": Computed(k["cone_no_slip"], (
            "largest slip of the ball on the tip, over V′0, at the greatest compression as Résal ends it (equal normal "
            "velocities, eq. 12), along the projection of the cue's axis on the tangent plane (the slip ω of eq. d), "
            f"over the random strokes (of 4000) that slide on the cloth inside the cone (tip friction {mu_tip:g}), "
            f"Résal's eqs (7); on {k['cone_check_count']:.0f} of them the integration of eqs (3) gives the same slips "
            f"to {k['cone_check']:.0e} V′0"), why(
            f"inside the cone the ball still slips on the tip: up to {k['cone_no_slip']:.2f} V′0 at the greatest "
            f"compression (median {k['cone_no_slip_median']:.2f} V′0, {k['cone_no_slip_count']:.0f} sliding strokes "
            f"of Résal's eqs); with the full moment of F, up to {k['cone_full']:.2f} V′0 "
            f"({k['cone_full_count']:.0f} strokes). The slip ω is the one that (d) and (9) keep: with Coulomb "
            "friction a sliding tip pushes on the edge of its cone, and a tip that does not slide pushes off the axis. "
            "The premise that the force stays on the axis inside the cone is not supported")),
        "mu_ratio": Computed(None, "a measurement: the masses of the cues and balls of 1883, which no premise of the "
                             "paper gives (today's 18 oz cue and 6 oz ball: 3)"),
        "tip_friction_range": Computed(None, "a measurement: the friction of the chalked tip, which no premise of the "
                                     "paper gives"),
        "f_cloth": Computed(None, "a measurement: Coriolis's value of the cloth's friction (n°7), which no premise of "
                            "the paper gives"),
        "eq1_slip": Computed(k["eq1_slip"], (
            "the velocity of the ball's material point at the foot r = (0, 0, −R), the derivative of its position "
            "under the rigid motion (Rodrigues' rotation, complex step), against (χ − pR, η + nR), over 200 random "
            "states (m/s)")),
        "eq2_as_digitised": Computed(k["eq2_as_digitised"], "largest discrepancy per unit F from Newton–Euler", why(
            "the digitised second line reads « M dη/dt = F(cos i − f v_x/v cos i) » and the fourth « dv/dt »; the 1883 "
            "text most likely had M dχ/dt = F(cos i − f (v_x/v) sin i) and M R²/k dn/dt (as eqs 3 use): with these "
            f"the lines agree with Newton–Euler to {k['eq2_original']:.0e} (row eq2_original)")),
        "eq2_original": Computed(k["eq2_original"], (
            "eqs (2) as most likely printed in 1883, M dχ/dt = F(cos i − f (v_x/v) sin i) and M R²/k dn/dt = "
            "−F(b + f (v_y/v) R) sin i with the other lines as digitised: the forces along Cx, Cy and the moments "
            "about Cx, Cz per unit F against Newton–Euler (largest discrepancy; the moment about Cy: row eq2_moment)")),
        "eq2_moment_y": Computed(k["eq2_moment_y"], "moment about Cy per unit F R against r × d", why(
            "the moment of F about Cy is F(c cos i + a sin i + f (v_x/v) R sin i): the printed line omits F a sin i "
            f"(up to {k['eq2_moment_y']:.2f} F R); method 'exact' restores it (repair; next row)")),
        "eq2_repaired": Computed(k["eq2_repaired"], (
            "largest breach of the angular momentum about the foot B (ball + moment of the cue impulse along its axis "
            f"through (a, b, c)) over P R, eqs (2) with the full moment; Résal's own (2) breach it by up to "
            f"{k['eq2_own_breach']:.2f}")),
        "eq3_as_digitised": Computed(k["eq3_as_digitised"], "eqs (2) divided by M′dV′ = −F dt, line by line", why(
            "the fourth line reads « R²/k dp = μ(c cos i + f v′_x/v R sin i) dV′ »: with M′dV′ = −F dt it is "
            "−μ(…) dV′, the sign that (5) and (7) use (with the plus sign the friction terms of (5) do not cancel); "
            "likely an OCR slip. "
            f"With −μ the lines agree to {k['eq3_original']:.0e} (row eq3_original)")),
        "eq3_original": Computed(k["eq3_original"], (
            "eqs (3) as most likely printed in 1883, the fourth line R²/k dp = −μ(c cos i + f (v′_x/v) R sin i) dV′, "
            "against eqs (2) divided by M′dV′ = −F dt with Résal's moment about Cy, line by line (largest "
            "discrepancy)")),
        "eq4_constant": Computed(k["eq4_constant"], (
            "largest change of the slip direction atan2(η + nR, χ − pR) over the stroke (P/P1 = 0.05 … 1), sliding "
            "strokes, Résal's eqs (2) and the full moment (radians)")),
        "eq5_repaired": Computed(k["eq5_repaired"], (
            "tan γ = kb sin i/(k(c cos i + a sin i) − R cos i) against the full-moment integration (modulo π; cos γ "
            "has the sign of R cos i − k(c cos i + a sin i))")),
        "eq6_definition": Computed(None, (
            "a definition: (6) names ω1 the cue's loss of speed, « en posant », and the first of eqs (2), M′dV′/dt = "
            "−F, integrates to ∫F dt = M′ω1 for any stroke: nothing can fail")),
        **{f"eq7_full_{n}": Computed(k[f"eq7_full_{n}"], integ + " with the full moment, relative to μω1", why(
            f"with the moment F a sin i, the line {line} of (7) with γ of the printed (5) errs by up to "
            f"{k[f'eq7_full_{n}']:.2f} μω1 ({what}); method 'exact' uses the repaired γ and p1 (row eq7_repaired)"))
           for n, line, what in (("chi", "χ1", "through γ"), ("eta", "η1", "through γ"),
                                  ("n", "n1 (as most likely printed)", "through γ"),
                                  ("p", "p1", "its term μ a sin i ω1 is missing, and γ"),
                                  ("q", "q1", "the moment −b cos i about Cz is whole"))},
        "eq7_repaired": Computed(k["eq7_repaired"], integ + " with the full moment: γ of the repaired (5), "
                                 "R²p1/k = μ(c cos i + a sin i + fR cos γ sin i) ω1"),
        "eq7_grip": Computed(k["eq7_grip"], integ + ", strokes inside the tip's friction cone where the cloth holds "
                             "the ball", why(
            f"(5) and (7) take the cloth's friction as f F sin i against a slip; where |D| ≤ (1 + k) f sin i the "
            f"cloth holds the foot (no slip, less friction) and (7) errs by up to {k['eq7_grip']:.2f} μω1 (over "
            f"{k['grip_count']:.0f} such strokes). The cloth holds {k['grip_share']:.0%} of the random strokes inside "
            f"the cone ({k['grip_in_cone']:.0f} of {k['grip_cone']:.0f}; i ≤ 80°, f 0.1-0.6): steep cues striking "
            "the ball high, where the paper applies (6) and (7) to every stroke (line 839) and places its retrograde "
            "motion, with the cue strongly inclined on the cloth (line 847, row criterion); a central stroke "
            f"(φ = i) is held beyond i = {k['grip_i_central']:.1f}° at f = {p.f:g}, outside the cone")),
        "eqa_lost": Computed(k["eqa_lost"], "M′ω1(2V′0 − Aω1), A of (8) as most likely printed, against the vis viva "
                             "lost in the integration, over M′V′0²"),
        "eq8_as_digitised": Computed(k["eq8_as_digitised"], "relative discrepancy from 1 + (ball's vis viva)/(M′ω1²)",
                                     why("the digitised (8) has k²/R for k/R² (not homogeneous), (b + fR)² for "
                                         "(b + fR sin γ)² and (c cos i + R cos γ sin i)² for (c cos i + fR cos γ sin "
                                         "i)²; the likely original reproduces (next row)")),
        "eq8_original": Computed(k["eq8_original"], (
            "(8) as most likely printed, A = 1 + μ{(cos i − f cos γ sin i)² + f² sin²γ sin²i + (k/R²)[(b + fR sin γ)² "
            "sin²i + (c cos i + fR cos γ sin i)² + b² cos²i]}, against 1 + (ball's vis viva)/(M′ω1²) of the "
            "integration of Résal's eqs (2); with the full moment c cos i becomes c cos i + a sin i")),
        "eq8_full_moment": Computed(k["eq8_full_moment"], (
            "relative discrepancy of (8) as most likely printed (γ of the printed 5, c cos i) from 1 + (ball's vis "
            f"viva)/(M′ω1²) of the integration with the full moment of F, over {k['eq8_full_count']:.0f} random "
            f"strokes that slide on the cloth inside the tip's friction cone (tip friction {mu_tip:g})"), why(
            f"(8) follows from eqs (7), which omit the moment F a sin i about Cy: against the full-moment mechanics it "
            f"errs by up to {k['eq8_full_moment']:.1%} over {k['eq8_full_count']:.0f} random sliding strokes inside "
            "the cone; in the reference stroke (i = 20°, b = 0.3R, c = 0.1R, "
            f"f = {p.f:g}, μ = {mu:g}) it gives A = {k['eq8_ref_original']:.3f} where the mechanics give "
            f"{k['eq8_ref_full']:.3f}. With γ of the repaired (5) and c cos i + a sin i it agrees (row eq8_repaired)")),
        "eq8_repaired": Computed(k["eq8_repaired"], (
            "(8) repaired, A = 1 + μ{(cos i − f cos γ sin i)² + f² sin²γ sin²i + (k/R²)[(b + fR sin γ)² sin²i + "
            "(c cos i + a sin i + fR cos γ sin i)² + b² cos²i]} with γ of the repaired (5), against the full-moment "
            "integration (relative)")),
        "eqb_ball": Computed(k["eqb_ball"], "M′(A − 1)ω1² against the ball's vis viva (lost velocities, from rest)"),
        "eqc_cue": Computed(None, (
            "a definition: the cue's lost velocity is V′0 − V′1 = ω1 by (6), so the vis viva of its lost velocity is "
            "M′ω1² for any stroke, and (c) is ε′ times it: nothing can fail")),
        "eqd_as_printed": Computed(k["eqd_as_printed"], "relative discrepancy of each printed right-hand side from its "
                                   "left-hand side with ∫F dt = M′ω1 (first of eqs 2)", why(
            "∫F dt = M′ω1 > 0, so −2ω∫F cos ψ dt = −2M′ω cos ψ ω1 and 2ω′∫f F sin i dt = +2M′ω′ f sin i ω1; both "
            "printed right-hand sides have the opposite sign (and the first lacks ω): a sign slip of the original, "
            "carried into (9) and (9′); it cancels in (10)")),
        "eq9_as_printed": Computed(k["eq9_as_printed"], "residual of (9) over V′0, with ω1 from law (6) solved on the "
                                   "integration, ω and ω′ the slips at the greatest compression (full moment)", why(
            "(9) follows from (a)-(d) with (d)'s sign slip: with the law's signs it reads 2V′0 − [A + ε(A − 1) + ε′]ω1 "
            "= −2ω cos ψ + 2ω′ f sin i, which law (6) solved on the integration satisfies (row eq10_original)")),
        "eq9p_as_printed": Computed(k["eq9p_as_printed"], "residual of (9′) over V′0 at the greatest compression",
                                    why("with the signs of the law, 2V′0 − 2Aω = −2ω cos ψ + 2ω′ f sin i (next row); "
                                        "the printed signs come from (d)")),
        "eq9p_corrected": Computed(k["eq9p_corrected"], (
            "2V′0 − 2Aω = −2ω cos ψ + 2ω′ f sin i at the greatest compression found on the full-moment integration "
            "(equal normal velocities), A from its vis viva: an exact energy balance there. With Résal's own moment it "
            "fails (the work of his moment is not that of F at (a, b, c))")),
        "eq10_as_digitised": Computed(k["eq10_as_digitised"], "ω against ω1 of law (6) solved on the integration", why(
            "the digitised (10) reads « ω = 2Aω/(A + (A − 1)ε + ε′) »: the left side is ω1 (the subscript lost); "
            "with ω1 it reproduces (next row)")),
        "eq10_original": Computed(k["eq10_original"], (
            "ω1 = 2Aω/(A + (A − 1)ε + ε′) against law (6) at the end of the stroke (friction terms at the greatest "
            "compression) solved for ω1 on the full-moment integration, random ε, ε′ and the footnote's")),
        "eq11_as_printed": Computed(k["eq11_as_printed"], "largest difference from cos φ = −d·n̂", why(
            "with the cue pointing down (pressure F sin i on the cloth), d = (cos i, 0, −sin i) and cos φ = −(a cos i "
            f"− c sin i)/R (which agrees to {k['eq11_corrected']:.0e}); the printed + c sin i is a sign slip")),
        "eq_normal_velocity": Computed(k["eq_normal_velocity"], "(v + ω × r)·n̂ of the integration against "
                                       "(χa + ηb)/R at the greatest compression, over V′0"),
        "eq_normal_velocity_7": Computed(k["eq_normal_velocity_7"], "the ball's normal velocity at the contact from "
                                         "the integration against μ[(cos i − f cos γ sin i)a − fb sin γ sin i]ω/R"),
        "eq12_as_derived": Computed(k["eq12_as_derived"], (
            "(12), with cos φ of the corrected (11), against the instant of equal normal velocities found on the "
            "integration of Résal's eqs (2) (relative)")),
        "criterion_full": Computed(k["criterion_full"], (
            "share of the grid's strokes (b = 0,3R, c and i on a grid) that slide inside the tip's friction cone where "
            "cos i ≷ f cos γ sin i with γ of the printed (5) misjudges the sign of χ1 with the full moment"), why(
            f"with the moment F a sin i, {k['retro_full_share']:.1%} of the grid's sliding strokes inside the cone are "
            f"retrograde ({k['retro_full_count']:.0f} of {k['retro_full_inside']:.0f}: steep cues striking high), "
            f"and γ of the printed (5) misjudges {k['criterion_full']:.1%}; over all the strokes the cue can reach "
            f"(miscues beyond the cone included) {k['retro_full_share_reach']:.0%} are retrograde and it misjudges "
            f"{k['criterion_full_reach']:.0%}. With the repaired γ the criterion is right (row criterion_repaired)")),
        "criterion_repaired": Computed(k["criterion_repaired"], (
            "cos i ≷ f cos γ sin i with γ of the repaired (5), where it says χ1 = 0 (cos i = f cos γ sin i): over "
            "191 heights c (b = 0,3R, the cloth's f), the strokes there that slide inside the tip's friction cone "
            f"({k['criterion_boundary_count']:.0f}), the largest χ1 of the integration of eqs (3) with the full "
            "moment, relative to μω1")),
        "eps_n5_fraction": Computed(k["eps_n5_fraction"], "n°5: 1 + ε + 3(1 + ε′) = 24/5 with ε = 0", why(
            f"n°5 gives ε′ = 4/15 = {k['eps_n5_fraction']:.4f}; « 1/14 » is an OCR slip of « 4/15 » (0,27 follows "
            "from 4/15, not from 1/14 = 0,071); the likely original is graded in row eps_n5_original")),
        "eps_n5_original": Computed(k["eps_n5_original"], (
            "ε′ = 4/15, the likely original of the digitised « 1/14 », against n°5's equation 1 + ε + 3(1 + ε′) = 24/5 "
            "with ε = 0 (Coriolis's data)")),
        "eps_n5_decimal": Computed(k["eps_n5_decimal"], "4/15 from n°5's equation with ε = 0"),
    }
