"""Kind ``cushion``: a ball against a cushion with friction and side spin (§IV n°11).

Every formula of n°11 is a row, checked against the integration of eqs (2) in the normal impulse
(``cushion.cushion_impact(method="ode")``); the exact closed form and Résal's first-order approximation are
compared over incidence angle and side spin, and the rebound is set beside a modern speed-dependent
cushion law.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import Experiment, Node
from ..mechanics import cushion, impact
from ..mechanics.paths import Regime
from .base import Computed, FigureSpec, Reproduction, layer, modern_rows, read_ball, rows_for

QUANTITIES = ("j_today", "stays_on_cloth", "q_constant", "eq1", "eq2_original", "eq3", "eq4", "eq5", "eq3_in_p",
              "n_of_p", "eq6", "eq7_as_printed", "phi_sign", "eq8_as_printed", "eq8_sign", "eq8_differential",
              "eq9", "dchi", "zeta_integral_sign", "nu_n5", "eq10_as_printed", "eq10_sign", "n0_zero",
              "not_elementary", "small_quantity", "expansion_identity", "eq11_as_printed",
              "approx_error", "approx_error_beyond", "eq11_integrable")
COST = 1.5  # CPU seconds of a run with its figures, about: the process pool starts the longest first
MODERN = ("mu_c", "e_c", "e_c(v)")


@dataclass(frozen=True)
class Params:
    R: float
    k: float
    j: float
    nu: float  # Coriolis's measured normal-velocity ratio (data of n°5)
    eps: float  # the ε it implies by eq. (9) of §I
    speed: float  # m/s, of the ball reaching the cushion (rolling on the cloth)
    modern_e: tuple[float, ...]  # a speed law e(v) = c0 + c1 v + c2 v², from modern-values.csv
    modern_e_vmax: float


def parse(node: Node, base: Path) -> Params:
    R, k = read_ball(node)
    j = node.number("j", "the ball-cushion friction coefficient", lo=0.0)
    nu = node.number("nu", "the measured ratio of normal velocities after/before", lo=0.0, hi=1.0)
    speed = node.number("speed", "a speed in m/s", lo=0.0, lo_open=True)
    law = node.child("modern_law", "a mapping with coefficients and v_max")
    coeffs = law.number_list("coefficients", "polynomial coefficients c0, c1, c2")
    vmax = law.number("v_max", "a speed in m/s", lo=0.0, lo_open=True)
    law.done()
    node.done()
    return Params(R, k, j, nu, float(impact.eps_from_velocity_ratio(nu)), speed, coeffs, vmax)


def _scenes(seed: int, n: int = 40) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    return (rng.uniform(-3, 3, n), -rng.uniform(0.2, 3, n), rng.uniform(-100, 100, n), rng.uniform(-100, 100, n),
            rng.uniform(0.05, 0.5, n))


def checks(p: Params, seed: int) -> dict[str, float]:
    """Largest discrepancy of each printed formula of n°11 from the integration of eqs (2)."""
    chi0, zeta0, p0, n0, j = _scenes(seed)
    R, k = p.R, p.k
    ode = cushion.cushion_impact(chi0, zeta0, p0, n0, R=R, k=k, j=j, eps=p.eps, method="ode")
    a = -zeta0
    phi0, phi1 = chi0 - p0 * R, ode.chi1 - ode.p1 * R
    slide = (ode.regime != Regime.GRIP) & (np.abs(phi1) > 1e-9 * a)
    out = {
        "eq4": np.max(np.abs(ode.chi1 - (chi0 - (R / k) * (ode.p1 - p0))) / a),
        "eq5": np.max(np.abs(phi1 - (chi0 + p0 * R / k - (1 + k) / k * ode.p1 * R)) / a),
        "eq6": np.max(np.abs(ode.n1 * R - n0 * R * np.abs(phi1 / phi0) ** (k / (1 + k)))[slide] / a[slide]),
        "eq9": np.max(np.abs(ode.chi1 - (k * chi0 + p0 * R + phi1) / (1 + k)) / a),
    }
    # (7) and (10) as printed (exponent (1 + k)/2): the slip speed they give against the integrated one
    psi1 = ode.n1 * R
    v_true = np.hypot(phi1, psi1)
    safe = np.where(slide, phi1, 1.0)
    v7 = np.abs(phi1) * np.sqrt(1 + (n0 * R / phi0) ** 2 * np.abs(phi0 / safe) ** ((1 + k) / 2))
    out["eq7_as_printed"] = np.max(np.abs(v7 - v_true)[slide] / a[slide])
    # (10): j(1 + k)(1 + ν)a = ∫_{φ1}^{φ0} √(1 + (n0R/φ0)² (φ0/φ)^e) dφ, evaluated at the integrated φ1
    nu = float(impact.nu_from_eps(p.eps))
    errs = []
    for i in np.nonzero(slide & (np.sign(phi1) == np.sign(phi0)))[0]:
        f0, f1 = abs(phi0[i]), abs(phi1[i])
        x = np.linspace(f1, f0, 4001)
        integrand = np.sqrt(1 + (n0[i] * R / f0) ** 2 * (f0 / x) ** ((1 + k) / 2))
        integral = float(np.sum((integrand[1:] + integrand[:-1]) * np.diff(x)) / 2)
        errs.append(abs(integral - j[i] * (1 + k) * (1 + nu) * a[i]) / a[i])
    out["eq10_as_printed"] = max(errs) if errs else 0.0
    return {key: float(v) for key, v in out.items()}


def grid(p: Params) -> tuple[np.ndarray, ...]:
    """Incidence angles (rad) × side spins p0R/V for a ball rolling on the cloth into the cushion."""
    theta = np.radians(np.linspace(1.0, 85.0, 85))
    spin = np.linspace(-1.0, 1.0, 81)
    T, S = np.meshgrid(theta, spin, indexing="xy")
    chi0, zeta0 = p.speed * np.sin(T), -p.speed * np.cos(T)
    n0 = zeta0 / p.R  # rolling on the cloth: the contact point with the cushion slips vertically at |ζ0|
    return theta, spin, chi0, zeta0, S * p.speed / p.R, n0


def rebound_angle(c: cushion.CushionImpact) -> np.ndarray:
    return np.degrees(np.arctan2(c.chi1, c.zeta1))


def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    c = checks(p, exp.seed)
    how = "largest discrepancy from the integration of eqs (2) over 40 random scenes, relative to |ζ0|"
    computed = {key: Computed(v, how) for key, v in c.items()}
    computed["eq7_as_printed"] = Computed(c["eq7_as_printed"], how, lambda _p: (
        "from (6), (ψ/φ)² = (n0R/φ0)² (φ0/φ)^(2/(1 + k)); the printed exponent (1 + k)/2 is its reciprocal "
        "(in (7), (10) and the expansion (11))"))
    computed["eq10_as_printed"] = Computed(c["eq10_as_printed"], how, lambda _p: (
        "the integral (10) with the printed exponent (1 + k)/2 misses j(1 + k)(1 + ν)a; with 2/(1 + k) it is the "
        "exact closed form used here"))
    with np.errstate(divide="ignore", invalid="ignore"):
        cl = claims(p, exp.seed)
    for key, (value, text) in cl.items():
        if key not in computed:
            computed[key] = Computed(value, text, lambda _p, text=text: text)
    theta, spin, chi0, zeta0, p0, n0 = grid(p)
    exact = cushion.cushion_impact(chi0, zeta0, p0, n0, R=p.R, k=p.k, j=p.j, eps=p.eps, method="exact")
    approx = cushion.cushion_impact(chi0, zeta0, p0, n0, R=p.R, k=p.k, j=p.j, eps=p.eps, method="resal")
    err = np.abs(rebound_angle(approx) - rebound_angle(exact))
    worst = np.unravel_index(np.argmax(err), err.shape)
    where = f"incidence {math.degrees(theta[worst[1]]):.0f}°, side spin p0R/V = {spin[worst[0]]:+.2f}"
    beyond = cl["approx_error_beyond"]
    computed["approx_error_beyond"] = Computed(beyond[0], beyond[1] + (
        f"; the rebound angle errs by up to {err.max():.2f}° ({where})"))
    e_modern = _modern_e(p, p.speed * np.cos(theta))
    modern = modern_rows(exp.modern, {
        "mu_c": (p.j, "Coriolis's j (n°11)"),
        "e_c": (p.nu, "ν, Coriolis's measured ratio (n°5)"),
        "e_c(v)": (p.nu, "constant, against the law at the figure's speeds"),
    })
    return Reproduction(exp, rows_for(exp, computed), (), (
        _figure_error(theta, spin, err), _figure_rebound(p, theta, e_modern)), modern,
        data_note=(f"j = {p.j:g}, ν = {p.nu:g} (ε = {p.eps:.4g} by eq. 9), ball rolling into the cushion at "
                   f"{p.speed:g} m/s"))


def _modern_e(p: Params, v_normal: np.ndarray) -> np.ndarray:
    v = np.minimum(v_normal, p.modern_e_vmax)
    return sum(c * v**i for i, c in enumerate(p.modern_e))


def _figure_error(theta: np.ndarray, spin: np.ndarray, err: np.ndarray) -> FigureSpec:
    i, j = np.unravel_index(np.argmax(err), err.shape)
    at = f"{math.degrees(theta[j]):.0f}°, p0R/V = {spin[i]:+.2f}".replace("-", "−")
    return FigureSpec("approximation-error", "Error of Résal's first-order eq. (11) in the rebound angle",
                      "incidence angle (degrees from the normal)", "side spin $p_0R/V$",
                      (layer("heatmap", np.degrees(theta), spin, z=err, label="|angle (11) − exact angle| (degrees)"),),
                      caption="ball rolling on the cloth into the cushion; exact: the ₂F₁ closed form",
                      reading=(
                          "How many degrees the rebound angle given by Résal's approximate eq. (11) differs from the "
                          "exact one, for a ball rolling into the cushion, over its incidence and its side spin p0R/V "
                          f"(V its speed). The error is at most {err.max():.2g}° ({at}), at small incidence with "
                          "strong spin, and vanishes along the dark diagonal p0R/V = sin(incidence), where the spin "
                          "cancels the slip along the cushion."))


def _figure_rebound(p: Params, theta: np.ndarray, e_modern: np.ndarray) -> FigureSpec:
    zeros = np.zeros_like(theta)
    chi0, zeta0 = p.speed * np.sin(theta), -p.speed * np.cos(theta)
    n0 = zeta0 / p.R
    resal = cushion.cushion_impact(chi0, zeta0, zeros, n0, R=p.R, k=p.k, j=p.j, eps=p.eps, method="exact")
    eps_modern = (1 - e_modern) / (1 + e_modern)
    modern = cushion.cushion_impact(chi0, zeta0, zeros, n0, R=p.R, k=p.k, j=p.j, eps=eps_modern, method="exact")
    frictionless = cushion.cushion_impact(chi0, zeta0, zeros, n0, R=p.R, k=p.k, j=0.0, eps=p.eps, method="exact")
    th = np.degrees(theta)
    return FigureSpec("rebound", f"Rebound angle against incidence, no side spin, V = {p.speed:g} m/s", "incidence "
                      "(degrees from the normal)", "rebound (degrees from the normal)", (
                          layer("line", th, rebound_angle(resal), label=f"§IV exact: j = {p.j:g}, ν = {p.nu:g}"),
                          layer("line", th, rebound_angle(modern), label="same, ν from Han 2005's e(v)", color="C2"),
                          layer("line", th, rebound_angle(frictionless), label="no friction (j = 0)", color="C7",
                                style="--"),
                          layer("line", th, th, label="mirror reflection", color="k", style=":")),
                      (0, 90), (0, 90), caption="Han 2005: e = 0.39 + 0.257 v − 0.044 v², v the normal speed (m/s)",
                      reading=(
                          "The angle from the normal at which a ball rolling without side spin leaves the cushion, "
                          f"against the angle at which it came, at {p.speed:g} m/s. The cushion returns only part of "
                          "the normal speed, so the ball leaves further from the normal than a mirror reflection "
                          f"(dotted); friction (j = {p.j:g}, blue, against grey without) pulls it back towards the "
                          f"normal, and today's measured restitution, above ν = {p.nu:g} except at grazing "
                          "incidence, brings it nearer to the mirror (green)."))


# ---- issue 13: every step and assertion of n°11, checked against an independent computation ----------------
def _states(seed: int, n: int = 200) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Random states of a ball against the cushion (η = 0): v = (χ, 0, ζ), ω = (n, p, q), and j; a seeded
    stream of its own, so that the rows of ``checks`` keep their scenes."""
    rng = np.random.default_rng([seed, 13])
    v = np.c_[rng.uniform(-3, 3, n), np.zeros(n), -rng.uniform(0.1, 3, n)]
    omega = np.c_[rng.uniform(-100, 100, n), rng.uniform(-100, 100, n), rng.uniform(-100, 100, n)]
    return v, omega, rng.uniform(0.05, 0.5, n)


def _wide_scenes(seed: int, n: int = 80) -> tuple[np.ndarray, ...]:
    """Scenes where a sign of φ could turn: slips along the cushion from 1e-4 to 3 m/s against vertical slips
    up to 3 m/s, friction up to 1,5, grazing and normal approach."""
    rng = np.random.default_rng([seed, 457])
    phi0 = rng.choice([-1.0, 1.0], n) * 10 ** rng.uniform(-4, 0.5, n)
    psi0 = rng.choice([-1.0, 1.0], n) * 10 ** rng.uniform(-2, 0.5, n)
    chi0 = rng.uniform(-3, 3, n)
    return chi0, -10 ** rng.uniform(-2, 0.5, n), chi0 - phi0, psi0, rng.uniform(0.05, 1.5, n)


def _integral(f0: float, f1: float, r2: float, e: float) -> float:
    """∫_{f1}^{f0} √(1 + r² (f0/x)^e) dx for 0 < f1 < f0 (the integral of (8)-(10) in |φ|), by quadrature."""
    from scipy.integrate import quad

    return quad(lambda x: math.sqrt(1 + r2 * (f0 / x) ** e), f1, f0, epsabs=0, epsrel=1e-12, limit=200)[0]


def claims(p: Params, seed: int) -> dict[str, tuple[float, str]]:
    """The rows of issue 13 (configs/cushion-impact.yaml), each a (value, how) pair; see the config's rows."""
    R, k, jj = p.R, p.k, p.j
    nu = float(impact.nu_from_eps(p.eps))
    out: dict[str, tuple[float, str]] = {}
    # §IV n°11, l. 409: Coriolis's j against today's measurements
    mu = next(r for r in modern_rows(("mu_c",), {"mu_c": (jj, "")}) if r["low"] is not None)
    mid = (mu["low"] + mu["high"]) / 2
    out["j_today"] = (None, f"a measurement: Coriolis's j, an input of §IV that no premise of the paper gives (today's "
                            f"measured range {mu['low']:g}–{mu['high']:g}, middle {mid:.3g}: the today column)")
    # l. 411: the ball keeps to the cloth. The cushion's friction pushes it vertically by dη = d(nR)/k (eqs 2 with
    # η free): for a ball rolling into the cushion the slip is downward, the push upward, and the cloth cannot pull
    theta, spin, chi0g, zeta0g, p0g, n0g = grid(p)
    ex = cushion.cushion_impact(chi0g, zeta0g, p0g, n0g, R=R, k=k, j=jj, eps=p.eps, method="exact")
    ag = -zeta0g
    eta1 = (ex.n1 - n0g) * R / k
    hop = float(np.max(eta1)) ** 2 / (2 * 9.81)
    out["stays_on_cloth"] = (float(np.max(eta1 / ag)), (
        f"largest upward velocity η1/a the cushion's friction gives a ball rolling into it (incidence 1°–85°, side "
        f"spin ±V/R): j(1 + ν) = {jj * (1 + nu):.3g} head-on, first order in j like the changes n°11 computes, not "
        f"of the order j² it neglects; at V = {p.speed:g} m/s the ball would rise {hop * 100:.1f} cm = "
        f"{hop / R:.2f} R (g = 9.81 m/s²), {float(np.max(eta1)) / 9.81 * 1000:.0f} ms to the top. With the "
        f"contact at the height of the centre nothing holds the ball down; a real cushion's nose, above the "
        f"centre, does"))
    # l. 413, 423, 427, 431: eqs (1)-(3) against Newton and Euler in vectors
    v, om, js = _states(seed)
    u = cushion.contact_velocity(v, om, R)
    phi, psi = v[:, 0] - om[:, 1] * R, om[:, 0] * R
    scale = np.max(np.abs(u))
    om_q0 = om.copy()
    om_q0[:, 2] = 0.0
    F, dom = cushion.rigid_body_rates(v, om, R, k, js)
    q_rate = float(np.max(np.abs(dom[:, 2])) * R / np.max(js))
    q_slip = float(np.max(np.abs(u[:, :2] - cushion.contact_velocity(v, om_q0, R)[:, :2])) / scale)
    out["q_constant"] = (None, (
        f"a definition: an identity true for any state: the cushion's reaction acts at r = −R e_z, and r × F has "
        f"no component along r, so no moment turns q; and q e_z × r = 0, so q does not enter the slip. Over 200 "
        f"random states the rate of q (×R/j) is {q_rate:.3g} and setting q to 0 changes the slip by {q_slip:.3g}"))
    eq1_err = float(np.max(np.abs(u[:, :2] - np.c_[phi, psi])) / scale)
    out["eq1"] = (None, (
        f"a definition: φ, ψ are the components along the cushion and the vertical of the slip v + ω × r of the "
        f"point touching the cushion (r = −R e_z), which n°11 writes in place of n°8's v_x, v_y; that they are "
        f"χ − pR and nR is true for any state (over 200 random states they differ by {eq1_err:.3g}, relative)"))
    vs = np.hypot(phi, psi)
    rates_printed = np.c_[-js * phi / vs, np.ones_like(vs), -js * psi / vs, js * phi / vs]
    rates_true = np.c_[F[:, 0], F[:, 2], dom[:, 0] * R / k, dom[:, 1] * R / k]
    orig = float(np.max(np.abs(rates_true - rates_printed)))
    out["eq2_original"] = (orig, (
        "largest |rate by (2) − rate by Newton and Euler in vectors| per unit normal impulse over 200 random states, "
        "the first equation read M dχ/dt = −(φ/v) fZ: the digitised dy is a glyph of dχ (y is the vertical, "
        "whose velocity η is 0 by the premise, and M dy/dt against a force is not even homogeneous), as in "
        "§V's eqs (2)"))
    lhs3, rhs3 = dom[:, 0] * R / psi, -dom[:, 1] * R / phi
    out["eq3"] = (float(np.max(np.abs(lhs3 - rhs3) / np.maximum(np.abs(lhs3), np.abs(rhs3)))),
                  "largest relative |d(nR)/(nR) + d(pR)/(χ − pR)| from Newton and Euler, 200 random states")
    out["dchi"] = (float(np.max(np.abs(F[:, 0] - (F[:, 0] - dom[:, 1] * R) / (1 + k))) / np.max(js)),
                   "largest |dχ − dφ/(1 + k)| per unit normal impulse (relative to j), Newton and Euler, 200 states")
    # ends and a mid-point of the integrated impact (40 scenes of ``checks``)
    chi0, zeta0, p0, n0, j = _scenes(seed)
    a = -zeta0
    ode = cushion.cushion_impact(chi0, zeta0, p0, n0, R=R, k=k, j=j, eps=p.eps, method="ode")
    phi0, psi0 = chi0 - p0 * R, n0 * R
    phi1, psi1 = ode.chi1 - ode.p1 * R, ode.n1 * R
    slide = (np.sign(phi1) == np.sign(phi0)) & (np.abs(phi1) > 1e-9 * a)
    C = chi0 + p0 * R / k
    F1, dom1 = cushion.rigid_body_rates(np.c_[ode.chi1, 0 * a, ode.zeta1], np.c_[ode.n1, ode.p1, 0 * a], R, k, j)
    lhs, rhs = dom1[:, 0] * R / psi1, dom1[:, 1] * R / ((1 + k) / k * ode.p1 * R - C)
    out["eq3_in_p"] = (float(np.max((np.abs(lhs - rhs) / np.abs(lhs))[slide])),
                       "largest relative discrepancy of d(nR)/(nR) = d(pR)/((1 + k)pR/k − (χ0 + p0R/k)), rates of "
                       "Newton and Euler at the integrated states of 40 random scenes")
    ratio = ((1 + k) / k * ode.p1 * R - C) / ((1 + k) / k * p0 * R - C)
    out["n_of_p"] = (float(np.max(np.abs(ode.n1 * R - n0 * R * np.abs(ratio) ** (k / (1 + k)))[slide] / a[slide])),
                     "largest |n1R − n0R [((1 + k)p1R/k − C)/((1 + k)p0R/k − C)]^(k/(1 + k))|/a against the "
                     "integration, 40 random scenes (the digitised ρ, ρ0 are p, p0)")
    # l. 457: φ keeps the sign of φ0 (so the sign of φ0 chooses ±)
    wc, wz, wp, wn, wj = _wide_scenes(seed)
    wide = cushion.cushion_impact(wc, wz, wp / R, wn / R, R=R, k=k, j=wj, eps=p.eps, method="ode")
    wphi1 = wide.chi1 - wide.p1 * R
    turned = int(np.sum(np.sign(wphi1) * np.sign(wc - wp) < 0))
    out["phi_sign"] = (None, (
        f"a definition: an identity true for any state: by eqs (2) and (1), dφ = dχ − R dp = −j(1 + k)(φ/v) dζ, "
        f"so φ = φ0 exp(−j(1 + k)∫dζ/v) keeps the sign of φ0, and |φ| reaches 0 only with the whole slip v "
        f"(then the ball grips). The integration of 80 scenes (|φ0| 1e-4…3 m/s, |ψ0| 0.01…3 m/s, j 0.05…1.5) "
        f"agrees: {turned} turn, {int(np.sum(wphi1 == 0))} end with the slip stopped"))
    # l. 461: eq. (8), j dζ = ∓√(…) dχ, at the integrated end states, compared as dχ/(j dζ) = −φ/v (bounded by 1,
    # so that a slip nearly stopped does not magnify the integration's error)
    r2 = (psi0 / phi0) ** 2
    safe1 = np.where(slide, phi1, phi0)

    def inverse_root(e: float) -> np.ndarray:  # dχ/(j dζ) by (8): ∓1/√(1 + (n0R/φ0)²(φ0/φ)^e)
        return -np.sign(phi0) / np.sqrt(1 + r2 * np.abs(phi0 / safe1) ** e)

    e_pr, e_der = (1 + k) / 2, 2 / (1 + k)
    true8 = F1[:, 0] / j  # dχ/(j dζ) from Newton and Euler, dζ/dπ = 1
    out["eq8_as_printed"] = (float(np.max(np.abs(inverse_root(e_pr) - true8)[slide])), (
        "largest |dχ/(j dζ) by (8) − by Newton and Euler| at the integrated states of 40 scenes, with the printed "
        "exponent (1 + k)/2 (the digitised μ0, dζ1, dφ read n0, dζ, dχ); dχ/(j dζ) = −φ/v lies in [−1, 1]"))
    out["eq8_sign"] = (float(np.max(np.abs(inverse_root(e_der) - true8)[slide])),
                       "largest |dχ/(j dζ) by (8) − by Newton and Euler| with the derived exponent 2/(1 + k), at the "
                       "integrated states of 40 scenes: the upper sign for φ > 0 is right")
    dphi = (F1[:, 0] - dom1[:, 1] * R) / j  # dφ/(j dζ)
    out["eq8_differential"] = (float(np.max(np.abs(dphi / true8 - 1)[slide])), (
        f"largest |(dφ/(j dζ))/(dχ/(j dζ)) − 1| from Newton and Euler at the same states: the digitised dφ makes "
        f"the right side of (8) (1 + k) times the left. With dχ, as the text next uses (« dχ = dφ/(1 + k) », row "
        f"dchi, then the integral of (8)), (8) agrees to {out['eq8_sign'][0]:.1e} (row eq8_sign)"))
    # l. 473 (a point inside the impact) and l. 483 (the end): the sign of the integral
    half = (1 + nu) * a / 2
    mchi, mp, _ = cushion.state_after_impulse(chi0, p0, n0, half, R=R, k=k, j=j)
    mphi = mchi - mp * R
    mslide = (np.sign(mphi) == np.sign(phi0)) & (np.abs(mphi) > 1e-9 * a)

    def signs(phi_e: np.ndarray, lhs_e: np.ndarray, ok: np.ndarray) -> tuple[float, float]:
        bad, good = [], []
        for i in np.nonzero(ok)[0]:
            integral = np.sign(phi0[i]) * _integral(abs(phi0[i]), abs(phi_e[i]), r2[i], e_der)  # ∫_φ^φ0 dφ
            printed = -np.sign(phi0[i]) * integral  # ∓ ∫_φ^φ0, the upper sign for φ > 0
            bad.append(abs(lhs_e[i] - printed) / a[i])
            good.append(abs(lhs_e[i] + printed) / a[i])
        return max(bad), max(good)

    mid_bad, mid_good = signs(mphi, half * j * (1 + k), mslide)
    end_bad, end_good = signs(phi1, (1 + nu) * a * j * (1 + k), slide)
    out["zeta_integral_fixed"], out["eq10_fixed"] = (mid_good, ""), (end_good, "")
    out["zeta_integral_sign"] = (mid_bad, (
        f"largest |(ζ − ζ0) j(1 + k) − (∓∫_φ^φ0 √(…) dφ)|/a halfway through the impact (ζ − ζ0 = (1 + ν)a/2), 40 "
        f"integrated scenes, quadrature, derived exponent: the printed ∓ makes a positive quantity negative. With "
        f"± (the limits turned, as (11) has it) it agrees to {out['zeta_integral_fixed'][0]:.1e}"))
    out["eq10_sign"] = (end_bad, (
        f"largest |a j(1 + k)(1 + ν) − (∓∫_φ1^φ0 √(…) dφ)|/a at the end of the impact, 40 integrated scenes, "
        f"derived exponent: with the printed ∓ the right side is negative and (10) has no root φ1 between 0 and "
        f"φ0. With ± (as (11) prints) it agrees to {out['eq10_fixed'][0]:.1e}"))
    # l. 477: ν, the ratio of n°5
    out["nu_n5"] = (None, "a measurement: the ratio §IV takes from n°5 (Coriolis's measurement, line 220), from "
                          f"which ε = {p.eps:.4g} by §I eq. (9) (row eps of coriolis-cushion)")
    # l. 485: n0 = 0 solves in closed form; otherwise no elementary solution
    z0 = cushion.cushion_impact(chi0, zeta0, p0, 0 * n0, R=R, k=k, j=j, eps=p.eps, method="ode")
    zphi1 = z0.chi1 - z0.p1 * R
    from10 = phi0 - np.sign(phi0) * j * (1 + k) * (1 + nu) * a  # (10) with n0 = 0: j(1 + k)(1 + ν)a = ±(φ0 − φ1)
    zs = np.sign(from10) == np.sign(phi0)
    out["n0_zero"] = (float(np.max(np.abs(from10 - zphi1)[zs] / a[zs])), (
        f"largest |φ1 from (10) with n0 = 0, φ0 ∓ j(1 + k)(1 + ν)a, − φ1 integrated|/a over the {int(zs.sum())} of 40 "
        f"scenes where the slip lasts; in the other {int((~zs).sum())} it stops during the impact and φ1 = 0 (the "
        f"paper does not say)"))
    elem = [cushion.binomial_integral_is_elementary(0, -e, 0.5) for e in (e_der, e_pr)]

    def nearness(e: float) -> float:  # 1 − 2 × the distance of Chebyshev's exponents to the nearest integer
        q = [0.5, 1 / -e, 1 / -e + 0.5]  # p, (m + 1)/n, (m + 1)/n + p for ∫ φ^0 (1 + c φ^(−e))^½ dφ
        return 1.0 - 2.0 * min(abs(x - round(x)) for x in q)

    out["not_elementary"] = (nearness(e_der), (
        f"Chebyshev's theorem on ∫ φ^m (1 + c φ^n)^p dφ, m = 0, n = −2/(1 + k), p = ½: elementary exactly when p, "
        f"(m + 1)/n = −(1 + k)/2 or (m + 1)/n + p = −k/2 is an integer, i.e. for an integer k. Shown: 1 − 2 × their "
        f"least distance to an integer, 1 when elementary; for k = {k:g} it is {nearness(e_der):.4g} (elementary: "
        f"{elem[0]}), with the printed exponent (1 + k)/2 {nearness(e_pr):.4g} (elementary: {elem[1]})"))
    # l. 487: Résal's small quantity (φ0 − φ)/φ over the figures' scenes (its largest value, at φ = φ1)
    ph0g, ph1g = chi0g - p0g * R, ex.chi1 - ex.p1 * R
    moving = ph1g != 0
    small = np.abs(ph0g - ph1g)[moving] / np.abs(ph1g[moving])
    # first order: dφ = −j(1 + k)(φ/v) dζ over ζ1 − ζ0 = (1 + ν)a, so (φ0 − φ1)/φ1 ≈ j(1 + k)(1 + ν)a/v0, v0 the
    # initial slip speed √(φ0² + ψ0²) (not |φ0|); at 30° without side spin, against the exact path
    first = jj * (1 + k) * (1 + nu) * ag / np.hypot(ph0g, n0g * R)
    i30 = (int(np.argmin(np.abs(spin))), int(np.argmin(np.abs(theta - math.radians(30)))))
    exact30 = float(abs(ph0g[i30] - ph1g[i30]) / abs(ph1g[i30]))
    by_phi0 = float(jj * (1 + k) * (1 + nu) * ag[i30] / abs(ph0g[i30]))
    out["small_quantity"] = (float(np.max(small)), (
        f"largest (φ0 − φ1)/φ1 over the figure's grid (ball rolling into the cushion at {p.speed:g} m/s, incidence "
        f"1°–85°, side spin ±V/R, exact path); it is ≤ j on {np.mean(small <= jj):.1%} of the grid, ≤ 2j on "
        f"{np.mean(small <= 2 * jj):.1%}, median {np.median(small):.2g}; the slip stops (the quantity is "
        f"infinite) on {np.mean(~moving):.2%}. At first order it is j(1 + k)(1 + ν)a/v0, v0 = √(φ0² + ψ0²) the "
        f"initial slip speed (at incidence 30° without side spin {float(first[i30]):.3g}, exactly {exact30:.3g}, "
        f"where j(1 + k)(1 + ν)a/|φ0| would give {by_phi0:.4g}): of order j only where the slip speed is of the "
        f"order of (1 + k)(1 + ν)a = {(1 + k) * (1 + nu):.3g} a or more"))
    # l. 489: the expansion of the power of φ0/φ in (7) to first order in (φ0 − φ)/φ, with the printed exponent,
    # against the power that (6) gives, (φ0/φ)^(2/(1 + k)); the squares the paper neglects are within j²
    x = np.linspace(1e-6, jj, 2001)  # x = (φ0 − φ)/φ, Résal's small quantity, up to j; φ0/φ = 1 + x

    def expansion(e: float) -> np.ndarray:  # 1 + e (φ0 − φ)/φ0, the printed right side
        return 1 + e * x / (1 + x)

    needed = (1 + x) ** e_der
    own = float(np.max(np.abs((1 + x) ** e_pr - expansion(e_pr))))
    out["expansion_identity"] = (float(np.max(np.abs(needed - expansion(e_pr)))), (
        f"largest |(φ0/φ)^(2/(1 + k)) − [1 + ((1 + k)/2)(φ0 − φ)/φ0]| for (φ0 − φ)/φ in (0, j]: the printed "
        f"expansion carries the exponent (1 + k)/2 = {e_pr:g} of the printed (7) where (6) gives 2/(1 + k) = "
        f"{e_der:.4g}, so its first-order term is {e_pr / e_der:.3g} times too large. With 2/(1 + k) the same "
        f"expansion is within {float(np.max(np.abs(needed - expansion(e_der)))):.3g}, inside the j² the paper "
        f"neglects. The first equality's φ0/φ = 1 + (φ0 − φ)/φ0 (for 1 + (φ0 − φ)/φ) and the dropped squares are "
        f"second order in (φ0 − φ)/φ, which the paper neglects, and are not graded here (the printed expansion "
        f"of its own power is within {own:.3g})"))
    # l. 493: (11) as printed is not homogeneous; the repaired form (1/φ0 restored, slip stopped at 0)
    budget = jj * (1 + nu) * ag
    f0g, s0g = np.abs(ph0g), np.abs(n0g * R)
    go = f0g > 0
    in_m = cushion.eq11_as_printed(f0g[go], s0g[go], k, budget[go], e_pr)
    in_cm = cushion.eq11_as_printed(100 * f0g[go], 100 * s0g[go], k, 100 * budget[go], e_pr) / 100
    both = np.isfinite(in_m) & np.isfinite(in_cm)
    out["eq11_as_printed"] = (float(np.max(np.abs(in_m - in_cm)[both] / ag[go][both])), (
        f"largest |φ1(11) in m/s − φ1(11) in cm/s|/a over the figure's grid: the term ((1 + k)/2)(n0²R²/φ0²)(φ − φ0) "
        f"is a velocity added to 1 (the 1/φ0 of the expansion is lost), so the root depends on the unit; "
        f"{int(np.sum(np.isfinite(in_m) != np.isfinite(in_cm)))} scenes have a root in one unit only. Repaired: "
        f"the next two rows"))
    approx = cushion.cushion_impact(chi0g, zeta0g, p0g, n0g, R=R, k=k, j=jj, eps=p.eps, method="resal")
    err = np.hypot(approx.chi1 - ex.chi1, approx.zeta1 - ex.zeta1) / p.speed
    rr = np.where(moving, np.abs(ph0g - ph1g) / np.where(moving, np.abs(ph1g), 1.0), np.inf)
    inside = rr <= jj
    for key, where, what in (("approx_error", inside, "inside the premise's domain, (φ0 − φ1)/φ1 ≤ j"),
                             ("approx_error_beyond", ~inside, "beyond it, (φ0 − φ1)/φ1 > j")):
        w = np.unravel_index(np.argmax(np.where(where, err, -1.0)), err.shape)
        out[key] = (float(np.max(err[where])), (
            f"repaired (11) (1/φ0 restored, slip stopped at 0, printed exponent): largest |v1(11) − v1(exact)|/V "
            f"{what} ({np.mean(where):.1%} of the grid of incidence 1°–85° × side spin ±V/R, V = {p.speed:g} m/s), "
            f"at incidence {math.degrees(theta[w[1]]):.0f}°, side spin p0R/V = {spin[w[0]]:+.2f}; over the whole "
            f"grid {float(err.max()):.2g}. O(j²) with the printed exponent, O(j³) with the derived one"))
    # l. 495: the integral of (11) is elementary
    from scipy.integrate import quad

    diffs = []
    for i in np.nonzero(go.ravel())[0][::97]:
        f0, s0 = f0g.ravel()[i], s0g.ravel()[i]
        rq = (s0 / f0) ** 2
        Ai, Bi = 1 + rq + e_pr * rq, -e_pr * rq / f0
        lo = 0.5 * f0
        anti = 2 / (3 * Bi) * ((Ai + Bi * f0) ** 1.5 - (Ai + Bi * lo) ** 1.5)
        diffs.append(abs(anti - quad(lambda t, Ai=Ai, Bi=Bi: math.sqrt(Ai + Bi * t), lo, f0, epsrel=1e-13)[0]) / f0)
    out["eq11_integrable"] = (float(max(diffs)), (
        f"largest relative |2/(3B) [(A + Bφ)^(3/2)]_φ^φ0 − ∫_φ^φ0 √(A + Bφ) dφ| (quadrature) over {len(diffs)} "
        f"scenes of the grid: the repaired (11) integrates in elementary terms, and its root φ1 is explicit"))
    return out
