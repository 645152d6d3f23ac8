"""Kind ``cue``: the stroke of an inclined cue and the motion that follows on the cloth (§VII n°14, §II).

Each formula and number of n°14 is a row, checked against the impulse integration of eqs (3)
(``reference.integrate_cue_impulse``); ε′ of the cue is recomputed from Coriolis's data of n°5 (never the
printed 0,27), and the strokes are followed on the cloth with §II to tell direct from retrograde motion.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import Experiment, Node
from ..mechanics import cloth, cue, impact, reference
from .base import Computed, FigureSpec, Reproduction, layer, modern_rows, read_ball, rows_for

QUANTITIES = ("eq5_full_moment", "eq5_own_moment", "eq7_own_moment", "eq7_n1_as_printed", "energy_resal",
              "central_stroke", "friction_angle_high", "friction_angle_low", "epsp_cue", "criterion_as_printed",
              "criterion_derived")
MODERN = ("e_tip", "mu_tip", "m_ball/m_cue")


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


def checks(p: Params, seed: int, epsp: float) -> dict[str, float]:
    R, k, M = p.R, p.k, p.M
    i, bR, cR, f = _random_strokes(seed, 16)
    worst = {"eq5_full_moment": 0.0, "eq5_own_moment": 0.0, "eq7_own_moment": 0.0, "eq7_n1_as_printed": 0.0}
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
    # energy: Résal's eq. (12) against the vis viva, over many random off-centre strokes
    i, bR, cR, f = _random_strokes(seed + 1, 4000)
    gains = {}
    for method in ("resal", "exact"):
        s = cue.cue_stroke(M, p.Mp, p.V0p, i, bR * R, cR * R, R=R, k=k, f=f, eps=p.eps, epsp=epsp, method=method)
        T0 = p.Mp * p.V0p**2
        T1 = (p.Mp * s.V1p**2 + M * (s.chi1**2 + s.eta1**2) + M * R * R / k * (s.n1**2 + s.p1**2 + s.q1**2))
        gains[method] = (T1 - T0) / T0
    worst["energy_resal"] = float(max(0.0, np.max(gains["resal"])))
    worst["energy_share"] = float(np.mean(gains["resal"] > 1e-12))
    worst["energy_exact"] = float(max(0.0, np.max(gains["exact"])))
    # a central horizontal stroke is n°5's direct impact, eq. (8)
    s0 = cue.cue_stroke(M, p.Mp, p.V0p, 0.0, 0.0, 0.0, R=R, k=k, f=p.f, eps=p.eps, epsp=epsp)
    d0 = impact.direct_impact(p.Mp, M, p.V0p, 0.0, eps=epsp, epsp=p.eps)
    worst["central_stroke"] = max(abs(float(s0.chi1 - d0.V1p)), abs(float(s0.V1p - d0.V1))) / p.V0p
    # direct or retrograde: the sign of χ1 (first of eqs 7) against the printed criterion cos γ ≶ f cos i
    ig, cg = np.meshgrid(np.radians(np.linspace(1, 89, 60)), np.linspace(-0.9, 0.9, 41), indexing="ij")
    per = cue.stroke_per_impulse(ig, 0.3 * R, cg * R, R=R, k=k, f=p.f, M=M, method="resal")
    direct = per["v"][0] > 0
    printed_direct = np.cos(per["gamma"]) < p.f * np.cos(ig)
    derived_direct = p.f * np.cos(per["gamma"]) * np.tan(ig) < 1
    sl = per["slides"]
    worst["criterion_as_printed"] = float(np.mean(printed_direct[sl] != direct[sl]))
    worst["criterion_derived"] = float(np.mean(derived_direct[sl] != direct[sl]))
    return worst


def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    epsp = epsp_from_n5(p)
    c = checks(p, exp.seed, epsp)
    how = "largest discrepancy from the impulse integration of eqs (3) over 16 random strokes"
    computed = {key: Computed(c[key], how) for key in QUANTITIES if key in c}
    computed["eq5_full_moment"] = Computed(c["eq5_full_moment"], how, lambda _p: (
        f"eq. (2) omits the moment F a sin i of the cue force about Cy (its line passes through (a, b, c)); with it, "
        f"tan γ = −(k/R) b sin i / (cos i − (k/R)(c cos i + a sin i)) and (5) errs by up to "
        f"{math.degrees(c['eq5_full_moment']):.1f}°"))
    computed["eq7_n1_as_printed"] = Computed(c["eq7_n1_as_printed"], how, lambda _p: (
        "eq. (2) integrates to R²n1/k = −μ(b + fR sin γ) sin i ω1; the printed −μ(b + fR cos γ sin i) ω1 has "
        "cos γ for sin γ and b without sin i (a slip of the original or of the transcription)"))
    computed["energy_resal"] = Computed(c["energy_resal"], "largest relative gain of vis viva over 4000 random "
                                        "off-centre strokes, with eqs (10)-(12)", lambda _p: (
        f"eq. (12) ends the compression on equal normal velocities while the impulse is along the axis: the "
        f"friction term 2V′0 − 2Aω of (9′) turns negative and {c['energy_share']:.0%} of random off-centre strokes "
        f"gain vis viva (up to ×{1 + c['energy_resal']:.3g}, where the denominator of (12) nears zero: the cloth's "
        f"friction drives the ball back against the cue). Ending the compression along the axis instead "
        f"(method 'exact') never gains (largest {c['energy_exact']:.1e})"))
    computed["central_stroke"] = Computed(c["central_stroke"], "a central horizontal stroke against n°5's eq. (8)")
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
        f"f cos γ tan i < 1, which never disagrees (row below): the printed criterion is garbled"))
    computed["criterion_derived"] = Computed(c["criterion_derived"], "f cos γ tan i < 1 against the sign of χ1")
    central = cue.cue_stroke(p.M, p.Mp, p.V0p, 0.0, 0.0, 0.0, R=p.R, k=p.k, f=p.f, eps=p.eps, epsp=epsp)
    ratio = float(central.chi1) / p.V0p
    mu = p.Mp / p.M
    modern = modern_rows(exp.modern, {
        "e_tip": (ratio * (1 + mu) / mu - 1, "Newton's e of a central stroke with ε = 0, ε′ from n°5"),
        "mu_tip": (max(p.tip_friction), "the chalked tip's friction, 0,20-0,50 (footnote of n°14)"),
        "m_ball/m_cue": (1 / mu, "1/μ, « μ diffère généralement peu de trois unités »"),
    })
    return Reproduction(exp, rows_for(exp, computed), (), (_figure_fan(p, epsp), _figure_region(p, epsp)), modern,
                        data_note=f"ε = {p.eps:g} (ball), ε′ = {epsp:.6g} (cue, from n°5), f = {p.f:g}, μ = {mu:g}")


def _after(p: Params, epsp: float, i: np.ndarray, cR: np.ndarray, bR: float) -> tuple:
    s = cue.cue_stroke(p.M, p.Mp, p.V0p, i, bR * p.R, cR * p.R, R=p.R, k=p.k, f=p.f, eps=p.eps, epsp=epsp)
    m = cloth.slide(s.chi1, s.eta1, s.n1, s.p1, R=p.R, k=p.k, f=p.f, g=p.g)
    return s, m


def _figure_fan(p: Params, epsp: float) -> FigureSpec:
    layers = []
    seen = set()
    for i in p.fan_inclinations:
        for h in p.fan_heights:
            s, m = _after(p, epsp, np.array(i), np.array(h), p.fan_side)
            t = np.linspace(0.0, 1.5 * float(m.t_roll) + 1e-9, 100)
            x, y, _, _ = cloth.state_at(t, s.chi1, s.eta1, s.n1, s.p1, R=p.R, k=p.k, f=p.f, g=p.g)
            retro = float(m.vx_roll) < 0
            kind = "retrograde" if retro else "direct"
            label = "" if kind in seen else f"{kind} (final motion along Ox)"
            seen.add(kind)
            layers.append(layer("line", x, y, label=label, color="C3" if retro else "C0"))
            layers.append(layer("points", [float(m.x_roll)], [float(m.y_roll)], color="k", marker="."))
    return FigureSpec("strokes", "Strokes of an inclined cue, then the cloth (§VII, §II)", "x along the cue (m)",
                      "y (m)", tuple(layers), caption=(
                          f"i ∈ {{{', '.join(f'{math.degrees(x):.0f}°' for x in p.fan_inclinations)}}}, "
                          f"c/R ∈ {{{', '.join(f'{h:g}' for h in p.fan_heights)}}}, b/R = {p.fan_side:g}; "
                          "dots: onset of rolling"))


def _figure_region(p: Params, epsp: float) -> FigureSpec:
    heights = np.linspace(-0.9, 0.9, 91)
    incl = np.linspace(0.0, p.region_i_max, 86)
    ii, hh = np.meshgrid(incl, heights, indexing="xy")  # rows: c/R, columns: i
    s, m = _after(p, epsp, ii, hh, p.fan_side)
    final = np.asarray(m.vx_roll) / p.V0p
    first = []  # the printed criterion's boundary: χ1 = 0 (first of eqs 7)
    for row, h in zip(np.asarray(s.chi1), heights, strict=True):
        neg = np.nonzero(row < 0)[0]
        if neg.size:
            first.append((math.degrees(incl[neg[0]]), h))
    layers = [layer("heatmap", np.degrees(incl), heights, z=final, label="final velocity along Ox / V′0")]
    phi_max = float(cue.miscue_angle(max(p.tip_friction)))
    ok = np.arccos(np.clip(np.asarray(s.cos_phi), -1, 1)) <= phi_max  # inside the tip's friction cone
    edges = [(math.degrees(incl[np.nonzero(row)[0][-1]]), h) for row, h in zip(ok, heights, strict=True) if row.any()]
    if edges:
        layers.append(layer("line", [x for x, _ in edges], [y for _, y in edges], color="C1", style=":",
                            label=f"fausse queue beyond (right of) this line, tip friction {max(p.tip_friction):g}"))
    if first:
        layers.append(layer("line", [x for x, _ in first], [y for _, y in first], label="χ1 = 0 (first of eqs 7)",
                            color="w", style="--"))
    return FigureSpec("retrograde-region", "Final motion along the cue's direction (negative: retrograde)",
                      "inclination i of the cue (degrees)", "height c/R of the contact point", tuple(layers),
                      caption=f"b/R = {p.fan_side:g}, f = {p.f:g}; stroke with the full moment, then §II")
