"""Kind ``ricochet``: a ball thrown at a fixed plane, its impacts and parabolic flights (§III n°8–10).

Rozé measured the positions of up to 12 imprints left by an ivory ball; the paper prints only his mean ν
per surface. Each surface here carries a series of imprint positions (and, optionally, impact instants
for the acoustic method): a user's CSV, or a synthetic series generated from the model with a seeded
noise and labelled SYNTHETIC. ν (and f, where the data determine it) is fitted from the positions, and ν
again from the flight times; both estimators are compared over many seeds.
"""

from __future__ import annotations

import math
import re
import textwrap
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import Experiment, Node
from ..fit.estimators.lsq import FitResult, fit_physical, fit_physical_positions, fit_positions, fit_times
from ..mechanics import plane, reference
from ..mechanics.paths import Regime
from ..series import MAX_IMPRINTS, MIN_IMPRINTS, read_imprints
from .base import (
    Computed,
    FigureSpec,
    FitRow,
    Reproduction,
    TableSpec,
    fit_rows,
    identifiability_report,
    layer,
    read_ball,
    rows_for,
)
from .kinematics import material_point_velocity

STATIC = ("eq1_slip", "q_constant", "eq2_as_printed", "eq2_original", "slip_direction", "eq3_frame",
          "eq4_as_printed", "eq4_original", "eq5_sliding", "eq5_slip_stops", "eq6_sliding", "eq6_slip_stops",
          "eq7_tan_sliding", "eq7_components_sliding", "eq7_tan_slip_stops", "vertical_plane", "range_formula",
          "range_ratio", "eq8_sliding", "eq8_slip_stops", "eq9_limit", "eq9_premise", "eq9_beyond",
          "angles_decrease", "angles_decrease_roze", "mean_ratio", "ligneous_layer", "footnote_drop_ratio")
COST = 3.4  # CPU seconds of a run with its figures, about: the process pool starts the longest first
MODERN = ("e_t",)
MAX_SEEDS = 1000  # repetitions of the estimator comparison: 40 take about a second; 1000 pin the bias to 0.3 %
SURFACE_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]*")


def quantities(p: Params) -> tuple[str, ...]:
    return STATIC + tuple(f"nu.{s.id}" for s in p.surfaces)


@dataclass(frozen=True)
class Synthetic:
    nu: float
    f: float
    a0: float
    alpha0: float  # rad
    p0: float
    imprints: int
    noise_x: float  # m, standard deviation of each imprint position
    noise_t: float  # s, standard deviation of each impact instant


@dataclass(frozen=True)
class Surface:
    id: str
    name: str
    synthetic: Synthetic | None
    csv: Path | None


@dataclass(frozen=True)
class Params:
    R: float
    k: float
    g: float
    p0_fit: float  # spin assumed before the first impact when fitting positions
    surfaces: tuple[Surface, ...]
    seeds: int  # synthetic repetitions for the estimator comparison
    drop_height_ratio: float  # n°5's marble drop, for the footnote of n°10
    map_alpha_max: float  # rad
    map_f_max: float
    map_nu: float


def _synthetic(n: Node) -> Synthetic:
    s = Synthetic(
        nu=n.number("nu", "a yield ν", lo=0.0, hi=1.0, lo_open=True),
        f=n.number("f", "a friction coefficient", lo=0.0),
        a0=n.number("a0", "a speed in m/s", lo=0.0, lo_open=True),
        alpha0=math.radians(n.number("alpha0_deg", "an angle in degrees", lo=0.0, hi=90.0, lo_open=True,
                                     hi_open=True)),  # 90° is along the normal: tan α0 = ∞ in the ranges
        p0=n.number("p0", "a spin in rad/s", default=0.0),
        imprints=n.integer("imprints", "a number of imprints", lo=MIN_IMPRINTS, hi=MAX_IMPRINTS),
        noise_x=n.number("noise_x", "a standard deviation in m", lo=0.0),
        noise_t=n.number("noise_t", "a standard deviation in s", lo=0.0),
    )
    n.done()
    return s


def parse(node: Node, base: Path) -> Params:
    R, k = read_ball(node)
    g = node.number("g", "gravity in m/s²", lo=0.0, lo_open=True)
    p0_fit = node.number("p0_fit", "a spin in rad/s", default=0.0)
    surfaces = []
    seen: dict[str, str] = {}
    for s in node.children("surfaces"):
        sid = s.string("id")
        at = s._mapping()["id"]
        if not SURFACE_ID.fullmatch(sid):
            raise s.fail(f"'{s.path}.id' must be a plain name (letters, digits, hyphens, underscores; it names "
                         f"a panel of the figure ricochets and the quantity nu.<id>), got '{sid}'", at)
        if sid.lower() in seen:
            raise s.fail(f"'{s.path}.id' repeats the surface id '{seen[sid.lower()]}' (surface ids must be unique, "
                         "ignoring case: each names a panel of a figure and a quantity)", at)
        seen[sid.lower()] = sid
        name = s.string("name")
        if s.has("csv") == s.has("synthetic"):
            raise s.fail(f"'{s.path}' must have exactly one of 'csv' (imprint positions) or 'synthetic'")
        syn = _synthetic(s.child("synthetic")) if s.has("synthetic") else None
        csv = base / s.string("csv") if s.has("csv") else None
        if csv is not None:
            read_imprints(csv)  # a bad file stops the run before any work
        s.done()
        surfaces.append(Surface(sid, name, syn, csv))
    if not surfaces:
        raise node.fail(f"'{node.path}.surfaces' must list at least one surface")
    seeds = node.integer("seeds", "a number of synthetic repetitions", lo=1, hi=MAX_SEEDS)
    drop = node.number("drop_height_ratio", "a height ratio in (0, 1]", lo=0.0, hi=1.0, lo_open=True)
    m = node.child("error_map", "a mapping with alpha_max_deg, f_max, nu")
    amax = math.radians(m.number("alpha_max_deg", "an angle in degrees", lo=0.0, hi=89.0, lo_open=True))
    fmax = m.number("f_max", "a friction coefficient", lo=0.0, lo_open=True)
    mnu = m.number("nu", "a yield ν", lo=0.0, hi=1.0, lo_open=True)
    m.done()
    node.done()
    return Params(R, k, g, p0_fit, tuple(surfaces), seeds, drop, amax, fmax, mnu)


# ---- data ---------------------------------------------------------------------------------------------------
def simulate_series(p: Params, s: Synthetic, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Imprint positions and impact instants (both from the first imprint) with seeded measurement noise."""
    r = plane.ricochet(s.a0, s.alpha0, s.p0, R=p.R, k=p.k, f=s.f, nu=s.nu, g=p.g, n=s.imprints - 1)
    x = r.imprints[: s.imprints]
    t = np.concatenate([[0.0], np.cumsum(r.times)])[: s.imprints]
    x = x + s.noise_x * rng.standard_normal(x.size)
    t = t + s.noise_t * rng.standard_normal(t.size)
    return x - x[0], t - t[0]


def load_series(s: Surface) -> tuple[np.ndarray, np.ndarray | None]:
    assert s.csv is not None
    return read_imprints(s.csv)


# ---- the printed formulas against the integration -----------------------------------------------------------
def _scenes(seed: int, n: int = 24) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    chi0 = rng.uniform(0.2, 4.0, n)
    zeta0 = -rng.uniform(0.1, 3.0, n)
    pR = rng.uniform(-2.0, 2.0, n)
    f = rng.uniform(0.0, 0.5, n)
    nu = rng.uniform(0.3, 1.0, n)
    return chi0, zeta0, pR, f, nu


def formula_checks(p: Params, seed: int) -> dict[str, float]:
    """Largest discrepancy of each printed formula of n°8–9 from the integrated impact (impulse variable)
    and flight, over random scenes; 'sliding' rows only over scenes where the slip lasts the whole impact,
    'slip_stops' rows only over those where it stops during the impact."""
    chi0, zeta0, pR, f, nu = _scenes(seed)
    R, k = p.R, p.k
    p0 = pR / R
    ref = reference.integrate_plane_impact(chi0, zeta0, p0, R=R, k=k, f=f, nu=nu)
    slide = plane.slides_throughout(chi0, zeta0, p0, R=R, k=k, f=f, nu=nu)
    s = np.sign(chi0 - pR)
    # eqs (6) as printed, in the frame where x is along the slip (so χ, p flip with s)
    chi1_6 = s * (s * chi0 + f * (1 + nu) * zeta0)
    pR1_6 = s * (s * pR - f * k * (1 + nu) * zeta0)
    err6 = np.maximum(np.abs(chi1_6 - ref.chi1), np.abs(pR1_6 - ref.p1 * R)) / np.abs(zeta0)
    # eq (7), third line: tan α1 = ν tan α0 / (1 − f(1 + ν) tan α0), with α the acute angles to Ox
    tan0 = np.abs(zeta0) / np.abs(chi0)
    tan1_7 = nu * tan0 / (1 - f * (1 + nu) * tan0)
    tan1_ref = np.abs(ref.zeta1) / np.abs(ref.chi1)
    forward = slide & (s > 0) & (ref.chi1 > 0)  # (7) takes Ox along the slip and χ1 > 0
    err7 = np.abs(tan1_7 - tan1_ref) / tan1_ref
    # eq (7), first two lines: a1 cos α1 = a0 cos α0 − f(1 + ν) a0 sin α0, a1 sin α1 = ν a0 sin α0 (a0 = |(χ0, ζ0)|)
    a0 = np.hypot(chi0, zeta0)
    cos0, sin0 = np.abs(chi0) / a0, np.abs(zeta0) / a0
    err7c = np.maximum(np.abs(a0 * cos0 - f * (1 + nu) * a0 * sin0 - s * ref.chi1),
                       np.abs(nu * a0 * sin0 - ref.zeta1)) / np.abs(zeta0)
    # P = a² sin α cos α / g as printed, against the integrated flight (a, α leaving the plane)
    a1 = np.hypot(ref.chi1, ref.zeta1)
    al1 = np.arctan2(ref.zeta1, ref.chi1)
    P_flight, _ = reference.integrate_flight(ref.chi1, ref.zeta1, p.g)
    err_range = np.abs(a1**2 * np.sin(al1) * np.cos(al1) / p.g - P_flight) / np.abs(P_flight)
    err_range_fixed = np.abs(2 * a1**2 * np.sin(al1) * np.cos(al1) / p.g - P_flight) / np.abs(P_flight)
    # (8) against the ratio of integrated flights: the flight that arrives (χ0, ζ0) and the next one
    P_before, _ = reference.integrate_flight(chi0, -zeta0, p.g)
    ratio_ref = P_flight / P_before
    # the ratio as printed, a1² sin α1 cos α1 / (a0² sin α0 cos α0): the missing factor 2 cancels
    al0 = np.arctan2(-zeta0, chi0)
    err_ratio = np.abs(a1**2 * np.sin(al1) * np.cos(al1) / (a0**2 * np.sin(al0) * np.cos(al0)) - ratio_ref) / \
        np.abs(ratio_ref)
    # the same as digitised, with α for a (α1² sin α1 cos α1 / (α0² sin α0 cos α0))
    err_ratio_digitised = np.abs(al1**2 * np.sin(al1) * np.cos(al1) / (al0**2 * np.sin(al0) * np.cos(al0))
                                 - ratio_ref) / np.abs(ratio_ref)
    alpha0 = np.arctan(tan0)
    err8 = np.abs(nu * (1 - f * (1 + nu) * np.tan(alpha0)) - ratio_ref) / np.abs(ratio_ref)
    fwd_all = (chi0 - pR > 0)
    # (9) as the small-angle limit of the exact ratio (spinless ball)
    tiny = 1e-7
    lim9 = np.max(np.abs(plane.range_ratio_exact(tiny, f=f, nu=nu, k=k) - nu) / nu)
    return {
        "eq6_sliding": float(np.max(err6[slide])),
        "eq6_slip_stops": float(np.max(err6[~slide])),
        "eq7_tan_sliding": float(np.max(err7[forward])),
        "eq7_components_sliding": float(np.max(err7c[forward])),
        "eq7_tan_slip_stops": float(np.max(err7[~slide & (s > 0) & (ref.chi1 > 0)])),
        "range_formula": float(np.max(err_range)),
        "range_corrected": float(np.max(err_range_fixed)),
        "range_ratio_original": float(np.max(err_ratio[chi0 > 0])),
        "range_ratio": float(np.max(err_ratio_digitised[chi0 > 0])),
        "eq8_sliding": float(np.max(err8[slide & fwd_all & (ref.chi1 > 0)])),
        "eq8_slip_stops": float(np.max(err8[~slide & fwd_all])),
        "eq9_limit": float(lim9),
    }


# ---- n°8 in three dimensions: eqs (1)–(5) against the vector equations of motion -------------------------------
def _rotate(xy: np.ndarray, theta: float) -> np.ndarray:
    """Horizontal components in axes turned by θ (the new Ox along the direction θ)."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([c * xy[0] + s * xy[1], -s * xy[0] + c * xy[1]])


def checks_3d(p: Params, seed: int, n: int = 24) -> dict[str, float]:
    """Largest discrepancy of eqs (1)–(5) of n°8 and of n°9's plane of motion from ``plane.integrate_impact_3d`` (the
    Newton–Euler equations in vector form) over random scenes in three dimensions: velocity (χ, η, ζ0 < 0) and
    rotation (n, p, q) in any direction, f in [0, 0,5], ν in [0,3, 1]; all discrepancies relative to |ζ0|."""
    rng = np.random.default_rng(seed + 8)
    k, R = p.k, p.R
    worst = dict.fromkeys(("eq1_slip", "q_constant", "eq2_as_printed", "eq2_original", "slip_direction", "eq3_frame",
                           "eq4_original", "eq5_sliding", "eq5_slip_stops"), 0.0)
    slid = stopped = 0
    for _ in range(n):
        v0 = np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), -rng.uniform(0.1, 3.0)])
        Rw0 = rng.uniform(-3, 3, 3)
        f, nu = rng.uniform(0.0, 0.5), rng.uniform(0.3, 1.0)
        z0 = abs(v0[2])
        # (1) v_x = χ − pR, v_y = η + nR, against the velocity of the material point at the contact, −R ẑ from C
        u = plane.slip_velocity(v0, Rw0)
        printed1 = np.array([v0[0] - Rw0[1], v0[1] + Rw0[0]])
        moving = material_point_velocity(v0, Rw0 / R, np.array([0.0, 0.0, -R]))
        worst["eq1_slip"] = max(worst["eq1_slip"], float(np.max(np.abs(printed1 - moving[:2]))) / z0)
        # (2) as digitised and as most likely printed, against the vector rates (per unit normal impulse Z dt/M)
        dv, dw = plane.impact_rates(v0, Rw0, k=k, f=f)
        ux, uy = u[:2] / np.hypot(*u[:2])
        digitised = [(-ux * f, dv[0]), (-uy * f, dv[1]), (R, dw[0]),  # line 3: M dn/dt = Z, i.e. d(nR)/dπ = R
                     (-ux * f * k, dw[0]), (uy * f * k, dw[1])]  # lines 4–5 with v_x and v_y swapped
        original = [(-ux * f, dv[0]), (-uy * f, dv[1]), (1.0, dv[2]), (-uy * f * k, dw[0]), (ux * f * k, dw[1])]
        worst["eq2_as_printed"] = max(worst["eq2_as_printed"], max(abs(a - b) for a, b in digitised))
        worst["eq2_original"] = max(worst["eq2_original"], max(abs(a - b) for a, b in original))
        # (4) as most likely printed: in axes along the slip, dχ/dπ = −f, dζ/dπ = 1, (R/k) d(p)/dπ · R = f
        th = math.atan2(u[1], u[0])
        dvr, dwr = _rotate(dv[:2], th), _rotate(dw[:2], th)
        worst["eq4_original"] = max(worst["eq4_original"], abs(dvr[0] + f), abs(dv[2] - 1.0), abs(dwr[1] / k - f),
                                    abs(dvr[1]), abs(dwr[0]))
        # the impact itself
        out = plane.integrate_impact_3d(v0, Rw0, k=k, f=f, nu=nu)
        no_q = plane.integrate_impact_3d(v0, Rw0 * np.array([1, 1, 0]), k=k, f=f, nu=nu)
        worst["q_constant"] = max(worst["q_constant"], abs(out.Rw1[2] - Rw0[2]) / z0,
                                  float(np.max(np.abs(out.v1 - no_q.v1))) / z0,
                                  float(np.max(np.abs(out.Rw1[:2] - no_q.Rw1[:2]))) / z0)
        worst["slip_direction"] = max(worst["slip_direction"], out.turn)
        # (3) and (5) in axes along the initial slip
        chi0, eta0 = _rotate(v0[:2], th)
        n0R, p0R = _rotate(Rw0[:2], th)
        chi1, eta1 = _rotate(out.v1[:2], th)
        n1R, p1R = _rotate(out.Rw1[:2], th)
        worst["eq3_frame"] = max(worst["eq3_frame"], abs(eta1 - eta0) / z0, abs(n1R - n0R) / z0)
        dz = out.v1[2] - v0[2]
        err5 = max(abs(chi1 - (chi0 - f * dz)), abs(p1R - (p0R + f * k * dz))) / z0
        if math.isnan(out.stopped_at):
            slid += 1
            worst["eq5_sliding"] = max(worst["eq5_sliding"], err5)
        else:
            stopped += 1
            worst["eq5_slip_stops"] = max(worst["eq5_slip_stops"], err5)
    assert slid and stopped, "the scenes must exercise both regimes"
    return worst


def vertical_plane(p: Params, seed: int, side_spin: bool, n: int = 8) -> float:
    """n°9: launched with η = 0 in axes along the slip (then n = 0 too: v_y = η + nR = 0), the centre stays in one
    vertical plane; with a rotation n about the line of flight (η = 0 but v_y = nR ≠ 0) it does not. Largest
    sideways distance of the imprints from the launch plane, relative to the distance covered, over 6 ricochets of
    ``n`` launches, each along a random azimuth of the fixed plane (n°8's Ox is any horizontal axis along the slip)
    and with a random rotation q about the normal (which n°8 leaves aside)."""
    rng = np.random.default_rng(seed + 9)
    worst = 0.0
    for _ in range(n):
        a0, alpha0 = rng.uniform(1.0, 4.0), rng.uniform(0.1, 1.2)
        f, nu = rng.uniform(0.05, 0.5), rng.uniform(0.5, 0.95)
        pR, qR = rng.uniform(-1.0, 1.0) * a0, rng.uniform(-1.0, 1.0) * a0
        nR = rng.uniform(0.2, 1.0) * a0 * rng.choice([-1, 1]) if side_spin else 0.0
        th = rng.uniform(0.0, 2.0 * math.pi)
        c, s = math.cos(th), math.sin(th)
        # the launch of n°9's axes (x along the flight, n about it, p about the horizontal normal), turned by θ
        v0 = [a0 * math.cos(alpha0) * c, a0 * math.cos(alpha0) * s, -a0 * math.sin(alpha0)]
        Rw0 = [nR * c - pR * s, nR * s + pR * c, qR]
        pos, _ = plane.ricochet_3d(v0, Rw0, k=p.k, f=f, nu=nu, g=p.g, n=6)
        side = np.abs(-s * pos[:, 0] + c * pos[:, 1])
        worst = max(worst, float(np.max(side)) / float(np.hypot(*pos[-1])))
    return worst


# ---- n°9–10: the premise of (9), the angles of the following ricochets, Rozé's means ----------------------------
NU_HARD = (0.5, 0.9)  # ν of an ivory ball on hard bodies, the range sampled for n°10's claims
IMPRINTS = 12  # n°10: « empreintes dont le nombre s'est élevé jusqu'à 12 »


def premise_9(p: Params) -> tuple[float, float, float]:
    """(largest relative error of (9) per unit of the neglected f tan α0 where f tan α0 ≤ 0,05; the f tan α0 that
    keeps (9) within 0,5 % at the error map's ν; largest relative error of (9) for α0 ≤ 60°, f ≤ 0,5, ν in [0,3, 1])."""
    a, f, nu = np.meshgrid(np.radians(np.linspace(0.05, 60, 240)), np.linspace(0.005, 0.5, 100),
                           np.linspace(0.3, 1.0, 15), indexing="ij")
    u = f * np.tan(a)
    err = np.abs(plane.range_ratio_small_angle(nu) - plane.range_ratio_exact(a, f=f, nu=nu, k=p.k)) / \
        plane.range_ratio_exact(a, f=f, nu=nu, k=p.k)
    small = u <= 0.05
    # (9) within 0,5 % (Rozé's two digits) at the error map's ν while sliding: u(1 + ν)/(1 − u(1 + ν)) = 0,005
    u_two_digits = 0.005 / 1.005 / (1.0 + p.map_nu)
    return float(np.max(err[small] / u[small])), u_two_digits, float(np.max(err))


def angles_claim(p: Params, nu_range: tuple[float, float]) -> tuple[float, float]:
    """n°9's « à plus forte raison »: tan α1 ≤ tan α0 where f tan α0 ≤ 0,05 (exact impacts: the slip may stop), over
    ν in the range. (how far the claim fails: the largest tan α1/tan α0 − 1, 0 where it holds; its worst signed
    margin, 1 − the largest tan α1/tan α0: > 0 where it holds, < 0 where it fails)."""
    u, f, nu = np.meshgrid(np.linspace(1e-4, 0.05, 60), np.linspace(0.01, 0.5, 40), np.linspace(*nu_range, 21),
                           indexing="ij")
    a = np.arctan(u / f)  # every launch with f tan α0 ≤ 0,05, its edge included
    out = plane.plane_impact(np.cos(a), -np.sin(a), 0.0, R=1.0, k=p.k, f=f, nu=nu)
    worst = float(np.max((out.zeta1 / out.chi1) / np.tan(a)))
    return max(0.0, worst - 1.0), 1.0 - worst


def slip_stop_threshold(p: Params, nu: float, impacts: int) -> float:
    """The f tan α0 beyond which the slip of a ball thrown without spin stops within ``impacts`` impacts: by (6) each
    sliding impact lowers the slip χ − pR by f(1 + k)(1 + ν)|ζ| and |ζ| falls by ν from one impact to the next, so the
    slip χ0 lasts while χ0 > f(1 + k)(1 + ν)|ζ0|(1 − ν^n)/(1 − ν)."""
    return (1.0 - nu) / ((1.0 + p.k) * (1.0 + nu) * (1.0 - nu**impacts))


def mean_ratio_bias(p: Params, spin: float, u_max: float | None = None) -> float:
    """Largest relative bias of Rozé's estimate, the mean of the ratios of consecutive distances between 12
    imprints, against ν, over launches α0 in [1°, 60°] (only where f tan α0 ≤ ``u_max``, if given), f in [0,01, 0,5],
    ν in NU_HARD, and a spin before the first impact p0R in [−spin, spin]·a0 (noise-free, exact impacts)."""
    spins = np.linspace(-spin, spin, 5) if spin else np.array([0.0])
    a, f, nu, s = np.meshgrid(np.radians(np.linspace(1, 60, 60)), np.linspace(0.01, 0.5, 50),
                              np.linspace(*NU_HARD, 9), spins, indexing="ij")
    r = plane.ricochet(1.0, a, s, R=1.0, k=p.k, f=f, nu=nu, g=p.g, n=IMPRINTS - 1)
    ratios = r.ranges[..., 1:] / r.ranges[..., :-1]
    bias = np.abs(ratios.mean(axis=-1) - nu) / nu
    return float(np.max(bias if u_max is None else bias[f * np.tan(a) <= u_max]))


# ---- the experiment -----------------------------------------------------------------------------------------
def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    checks = formula_checks(p, exp.seed)
    how = "largest relative discrepancy from the integrated impact/flight over 24 random scenes"
    computed: dict[str, Computed] = {k: Computed(v, how) for k, v in checks.items()}
    c3 = checks_3d(p, exp.seed)
    how3 = "largest discrepancy from the vector equations of motion (Newton–Euler, integrated in three dimensions) " \
        "over 24 random scenes, relative to |ζ0|"
    computed.update({key: Computed(v, how3) for key, v in c3.items()})
    computed["eq1_slip"] = Computed(c3["eq1_slip"], (
        "largest discrepancy of (χ − pR, η + nR) from the velocity of the ball's material point at the contact, "
        "differentiated from its position under the rigid motion (translation and rotation, fourth-order central "
        "difference, no vector product), over 24 random scenes with rotations in any direction; relative to |ζ0|"))
    computed["eq2_as_printed"] = Computed(c3["eq2_as_printed"], how3, lambda _p: (
        f"as digitised, the third of (2) reads M dn/dt = Z and the last two swap v_x and v_y (dn/dt with v_x, dp/dt "
        f"with v_y): off by up to {c3['eq2_as_printed']:.3g} per unit impulse. The original most likely printed "
        "M dζ/dt = Z, (MR²/k) dn/dt = −(v_y/v) fZR, (MR²/k) dp/dt = (v_x/v) fZR, as §II's (2) (line 266) and as "
        "(3)–(4) need: row eq2_original"))
    computed["eq4_as_printed"] = Computed(c3["eq4_original"], how3 + (
        "; the digitised M dx/dt = −fZ, M dz/dt = Z read dx, dz for dχ, dζ (single glyphs, unambiguous: position "
        "rates against forces would not be homogeneous, and (3) and (5) use the velocities), graded as "
        "M dχ/dt = −fZ, M dζ/dt = Z"))
    # where the paper applies (5)–(8) and the slip stops: n°9 applies them to every ricochet of a ball thrown at any
    # angle, and to the following ricochets; a ball thrown without spin on a surface of the error map's ν
    nu_m = p.map_nu
    u_first, u_within = 1.0 / ((1.0 + p.k) * (1.0 + nu_m)), slip_stop_threshold(p, nu_m, IMPRINTS - 1)
    where_stops = (
        f"; the paper applies (5)–(8) to every ricochet, at any angle, and n°10 to Rozé's: thrown without spin on a "
        f"surface of ν = {nu_m:g} the slip stops at the first impact once f tan α0 > {u_first:.3g} (α0 > "
        f"{math.degrees(math.atan(u_first / 0.2)):.0f}° for f = 0,2) and within Rozé's {IMPRINTS} imprints once "
        f"f tan α0 > {u_within:.3g}")
    computed["eq5_slip_stops"] = Computed(c3["eq5_slip_stops"], how3 + ", where the slip stops", lambda _p: (
        f"(5) integrates (4), i.e. assumes the contact slides during the whole impact; where the slip stops "
        f"(|v_x0| < f(1 + k)(1 + ν)|ζ0|) the contact then rolls without friction and (5) overshoots by up to "
        f"{c3['eq5_slip_stops']:.3g} |ζ0|" + where_stops))
    computed["eq6_slip_stops"] = Computed(checks["eq6_slip_stops"], how + ", where the slip stops", lambda _p: (
        f"eqs (6) assume the slip lasts the whole impact; where it stops (|χ0 − p0R| < f(1 + k)(1 + ν)|ζ0|) the "
        f"contact then rolls and (6) overshoots: largest error {checks['eq6_slip_stops']:.3g} |ζ0|" + where_stops))
    computed["eq7_tan_slip_stops"] = Computed(checks["eq7_tan_slip_stops"], how + ", where the slip stops", lambda _p: (
        f"the third of (7) follows from the first two, which assume the slip lasts the whole impact; where it stops "
        f"the ball leaves rolling, tan α1 = ν(1 + k) tan α0 / k without f, and (7) errs by up to "
        f"{checks['eq7_tan_slip_stops']:.3g} (relative)" + where_stops))
    vp = vertical_plane(p, exp.seed, side_spin=False)
    vps = vertical_plane(p, exp.seed, side_spin=True)
    computed["vertical_plane"] = Computed(vp, (
        "largest sideways distance of 6 imprints from the launch plane over the distance covered, 8 random launches "
        "(each along a random azimuth, with spins p about the horizontal normal to the flight and q about the "
        "normal), integrated in three dimensions. n°8 takes Ox along the slip, so η = 0 means v_y = η + nR = 0, "
        "n = 0: a launch with η = 0 but a rotation n about the line of flight, which these axes exclude, drifts "
        f"sideways at every impact (up to {vps:.3g} of the distance covered, nR up to a0)"))
    computed["range_formula"] = Computed(checks["range_formula"], how, lambda _p: (
        "the range of a parabolic flight is 2a² sin α cos α / g (= a² sin 2α / g): the printed a² sin α cos α / g "
        "lacks the factor 2 in P0, P1 and their ratio alike, a slip of the 1883 original (the ratio (8) is "
        f"unaffected, the factor cancels); with it the integrated flight agrees to {checks['range_corrected']:.1e}. "
        "The digitised α0² for a0² (also 'α0, α0' for 'a0, α0' above it) is an OCR slip"))
    computed["range_ratio"] = Computed(checks["range_ratio_original"], how + (
        "; the digitised α1², α0² are the glyphs of the speeds a1², a0² (as 'α0, α0' for 'a0, α0' two lines up; "
        "read as angles the ratio would be off by up to " f"{checks['range_ratio']:.3g}" "): graded as "
        "a1² sin α1 cos α1 / (a0² sin α0 cos α0), whose missing factor 2 (row range) cancels"))
    computed["eq8_slip_stops"] = Computed(checks["eq8_slip_stops"], how + ", where the slip stops", lambda _p: (
        f"(8) is exact while the contact slides; where the slip stops during an impact the exact ratio is "
        f"ν(kχ0 + p0R)/((1 + k)χ0) and (8) errs by up to {checks['eq8_slip_stops']:.0%} (see the error map)"
        + where_stops))
    per_u, u2, beyond9 = premise_9(p)
    computed["eq9_premise"] = Computed(per_u, (
        f"largest relative error of (9) against the exact ratio, per unit of the neglected f tan α0, where "
        f"f tan α0 ≤ 0,05 (ν in [0,3, 1], no spin): (9) errs by (1 + ν) f tan α0/(1 − (1 + ν) f tan α0) while the "
        f"contact slides, of the order of the neglected quantity as the premise says, but up to twice it: to hold "
        f"to Rozé's two digits (0,5 % at ν = {p.map_nu:g}) it needs f tan α0 ≤ {u2:.2g}, α0 ≤ "
        f"{math.degrees(math.atan(u2 / 0.2)):.1f}° for f = 0,2"))
    computed["eq9_beyond"] = Computed(beyond9, "largest relative error of (9) for α0 ≤ 60°, f ≤ 0,5, ν in [0,3, 1]",
                                      lambda _p: (
        f"beyond its premise (9) errs by up to {beyond9:.0%}: where the slip stops in the impact the ball leaves "
        "rolling and P1/P0 = νk/(1 + k). Once the ball arrives rolling (v_x = 0), (9) is exact at any angle: the "
        "impact needs no friction"))
    ang, ang_margin = angles_claim(p, (0.3, 1.0))
    computed["angles_decrease"] = Computed(ang, "largest tan α1/tan α0 − 1 (exact impacts) where f tan α0 ≤ 0,05, "
                                                "for ν in [0,3, 1]", lambda _p: (
        f"by the third of (7), tan α1 < tan α0 iff f(1 + ν) tan α0 < 1 − ν: f tan α0 must be small against 1 − ν, "
        f"not against 1; for ν close to 1 the angles grow (tan α1/tan α0 − 1 up to {ang:.3g} where f tan α0 ≤ 0,05), "
        "however small f tan α0 is"), margin=ang_margin)
    # where the paper applies it: Rozé's surfaces, the ν of this experiment's synthetic surfaces (else NU_HARD)
    nus = [s.synthetic.nu for s in p.surfaces if s.synthetic is not None]
    nu_roze = (min(nus), max(nus)) if nus else NU_HARD
    roze, roze_margin = angles_claim(p, nu_roze)
    computed["angles_decrease_roze"] = Computed(roze, (
        f"largest tan α1/tan α0 − 1 (exact impacts) where f tan α0 ≤ 0,05, for ν in [{nu_roze[0]:g}, {nu_roze[1]:g}] "
        f"(the surfaces of this experiment, Rozé's): the angles decrease, tan α1/tan α0 at most {1 - roze_margin:.4g} "
        f"(a margin of {roze_margin:.2g}); by the third of (7) the margin vanishes at f tan α0 = (1 − ν)/(1 + ν), "
        f"{(1 - nu_roze[1]) / (1 + nu_roze[1]):.3g} at ν = {nu_roze[1]:g}"), margin=roze_margin)
    # n°10: Rozé's mean ratio, as the launch (spin, angle) and the reading of « relativement peu » make it
    grid = (f"noise-free exact ricochets, {IMPRINTS} imprints, f in [0,01, 0,5], ν in [{NU_HARD[0]:g}, "
            f"{NU_HARD[1]:g}], a spin p0R in [−0,5, 0,5] a0 or none")
    mr = {(spin, u): mean_ratio_bias(p, spin, u) for spin in (0.0, 0.5) for u in (u2, 0.05, None)}
    computed["mean_ratio"] = Computed(None, (
        "a modelling choice: n°10 says neither how Rozé threw the ball (its spin, its angle) nor how near ν "
        "« relativement peu » is, and the outcome turns on them. Largest bias of the mean ratio of consecutive "
        f"distances against ν ({grid}): where f tan α0 ≤ {u2:.2g} (so that (9) holds to Rozé's two digits, row "
        f"eq9_premise) {mr[0.0, u2]:.2%} without spin, {mr[0.5, u2]:.2%} with; where f tan α0 ≤ 0,05 "
        f"{mr[0.0, 0.05]:.2%} without spin, {mr[0.5, 0.05]:.2%} with; for α0 up to 60° {mr[0.0, None]:.2%} without "
        f"spin, {mr[0.5, None]:.2%} with. Thrown without spin the slip stops within a few impacts, after which each "
        "ratio is ν exactly, and the mean is never above ν; thrown with back spin the ball slides on, each ratio "
        "ν[1 − f(1 + ν) tang α] by (8)"))
    computed["ligneous_layer"] = Computed(None, (
        "a measurement: the inference rests on Rozé's measured figures alone (paper on marble 0,65, fir 0,63, bare "
        "marble 0,80–0,85); resal has no model of a plane made of a covering sheet on a different body, and the "
        "figures are not reproducible without his series"))
    drop_ratio = math.sqrt(p.drop_height_ratio)
    computed["footnote_drop_ratio"] = Computed(None, (
        f"a measurement: the footnote compares two measurements, Rozé's ν on polished marble and the velocity ratio "
        f"of n°5's drop test on marble, √ of its height ratio = {drop_ratio:.4f}; no premise gives either, and how "
        "near « diffère peu » asks them to be is no computation (the printed √(2/3) = 0,81 itself is graded once, "
        "in row velocity_ratio of marble-drop)"))

    fits: list[FitRow] = []
    ident: list[dict] = []
    figures: list[FigureSpec] = []
    sequences: list[tuple[Surface, np.ndarray, FitResult, bool]] = []
    rows_est: list[tuple] = []
    for i, s in enumerate(p.surfaces):
        if s.synthetic is not None:
            x, t = simulate_series(p, s.synthetic, np.random.default_rng(exp.seed + i))
            label = (f"SYNTHETIC ({s.name}): model with ν = {s.synthetic.nu:g}, f = {s.synthetic.f:g}, "
                     f"{x.size} imprints, σx = {s.synthetic.noise_x * 1e3:g} mm, seed {exp.seed + i}")
        else:
            x, t = load_series(s)
            label = f"measured ({s.name}): {s.csv.name if s.csv else ''}, {x.size} imprints"
        fx = fit_positions(x, k=p.k)
        labels = {"nu": f"ν [{s.id}]", "A": f"A = 2a0² sin α0 cos α0/g [{s.id}] (m)", "u": f"f tan α0 [{s.id}]"}
        fits += fit_rows(fx, f"{s.id}.positions", labels, "least squares on imprint positions (closed form, spinless)",
                         label)
        ident.append(identifiability_report(fx, f"{s.id}.positions", labels,
                                            f"imprint positions, closed form, {s.id}"))
        # f from ranges alone: the physical parameters (ν, f, a0, α0) against the positions
        phys = {"nu": "ν", "f": "f", "a0": "a0", "alpha0": "α0"}
        fp = fit_physical_positions(x, fx, R=p.R, k=p.k, g=p.g) if p.p0_fit == 0.0 else \
            fit_physical(x, None, fx, R=p.R, k=p.k, g=p.g, p0=p.p0_fit)
        ident.append(identifiability_report(fp, f"{s.id}.positions-physical", phys,
                                            f"imprint positions, physical parameters, {s.id}"))
        fits += fit_rows(fp, f"{s.id}.positions-physical", {"f": f"f [{s.id}], positions only"},
                         "exact family from the closed-form fit, physical parameters",
                         "f enters the ranges only through f tan α0", only=("f",))
        shown = fp
        if t is not None:
            ft = fit_times(t, g=p.g)
            fits += fit_rows(ft, f"{s.id}.times",
                             {"nu": f"ν [{s.id}, acoustic]", "zeta1": f"ζ1 [{s.id}, acoustic] (m/s)"},
                             "least squares on impact instants", label)
            fj = fit_physical(x, t, fx, R=p.R, k=p.k, g=p.g, p0=p.p0_fit)
            ident.append(identifiability_report(fj, f"{s.id}.joint-physical", phys,
                                                f"imprint positions and instants, {s.id}"))
            fits += fit_rows(fj, f"{s.id}.joint-physical", {"f": f"f [{s.id}], positions + instants"},
                             "least squares, physical parameters, "
                             "residuals scaled by each series' estimated noise", label, only=("f",))
            shown = fj
        computed[f"nu.{s.id}"] = Computed(
            None if s.synthetic is not None else fx.estimate("nu").value,
            "a measurement: Rozé's mean ν on this surface; his series are not printed, and the synthetic series, "
            "generated with the mean of the params, only "
            "exercises the fit (see the fits)" if s.synthetic is not None else "fit of the measured imprints")
        sequences.append((s, x, shown, t is not None))
        if s.synthetic is not None:
            rows_est += _compare_estimators(p, s, exp.seed + 1000 * (i + 1))
    figures.append(_figure_ricochets(p, sequences))
    # the error maps' line of Rozé's two digits: the tolerance of row eq9_beyond (0,5 %, as premise_9)
    figures += _figures_error_maps(p, next((x.tolerance for x in exp.printed if x.computed == "eq9_beyond"
                                            and x.tolerance), 0.005))
    tables = ()
    if rows_est:
        tables = (TableSpec("estimators", "ν from imprint positions and from flight times (synthetic, many seeds)",
                            ("surface", "estimator", "true ν", "mean ν̂", "bias", "std. dev.", "RMSE", "seeds"),
                            tuple(rows_est),
                            "Same synthetic series for both estimators in each repetition."),)
        figures.append(_figure_estimators(rows_est, {s.id: s.name for s in p.surfaces}))
    return Reproduction(exp, rows_for(exp, computed), tuple(fits), tuple(figures), (),
                        data_note="; ".join(s.name + (" (SYNTHETIC)" if s.synthetic else "") for s in p.surfaces),
                        identifiability=tuple(ident), tables=tables)


def _compare_estimators(p: Params, s: Surface, seed: int) -> list[tuple]:
    assert s.synthetic is not None
    est: dict[str, list[float]] = {"positions": [], "flight times": []}
    for r in range(p.seeds):
        x, t = simulate_series(p, s.synthetic, np.random.default_rng(seed + r))
        est["positions"].append(fit_positions(x, k=p.k).point[0])
        est["flight times"].append(fit_times(t, g=p.g).point[0])
    out = []
    for name, v in est.items():
        a = np.asarray(v)
        bias = float(a.mean() - s.synthetic.nu)
        out.append((s.id, name, s.synthetic.nu, float(a.mean()), bias, float(a.std(ddof=1)),
                    float(np.sqrt(np.mean((a - s.synthetic.nu) ** 2))), p.seeds))
    return out


def _panel_sequence(p: Params, s: Surface, x: np.ndarray, fit: FitResult) -> tuple[FigureSpec, str]:
    """One surface's panel of the figure ``ricochets`` (the fitted path of the centre over the imprints) and the
    words of the reading about it."""
    nu, f, a0, alpha0 = fit.point
    r = plane.ricochet(a0, alpha0, p.p0_fit, R=p.R, k=p.k, f=f, nu=nu, g=p.g, n=x.size - 1)
    xs, zs = [], []
    for j in range(x.size - 1):  # the centre's parabola between imprints j and j+1
        tt = np.linspace(0.0, r.times[j], 30)
        xs.append(r.imprints[j] + r.chi[j] * tt)
        zs.append(p.R + r.zeta[j] * tt - 0.5 * p.g * tt**2)
    slides = np.nonzero(r.regimes == Regime.SLIDE)[0] + 1
    ranges = np.diff(x)
    n_slide = slides.size
    regimes = ("grips at every impact" if n_slide == 0 else "slides at every impact" if n_slide == r.regimes.size
               else f"slides at impact{'s' if n_slide > 1 else ''} {', '.join(map(str, slides))} and grips at the "
                    "others")
    where = ("slides at every impact" if n_slide == r.regimes.size else "grips at every impact" if n_slide == 0 else
             f"slides at {', '.join(map(str, slides))}")
    kind = "SYNTHETIC " if s.synthetic is not None else ""
    panel = FigureSpec(
        f"ricochet-{s.id}", f"{s.name}\n$\\nu$ = {nu:.3f}; {where}", "", "",
        (layer("line", np.concatenate(xs), np.concatenate(zs), label="fitted model: path of the centre", color="C0"),
         layer("points", x, np.zeros_like(x), label=f"{kind}imprints", color="C3", marker="|")))
    words = (f"on {s.name}, ν = {nu:.3f}, the ranges falling from {ranges[0] * 100:.1f} cm to "
             f"{ranges[-1] * 100:.1f} cm over {x.size} imprints, and the contact {regimes}")
    return panel, words


def _figure_ricochets(p: Params, shown: list[tuple[Surface, np.ndarray, FitResult, bool]]) -> FigureSpec:
    """The fitted ricochets of every surface, a panel each, two panels a row."""
    panels, words = zip(*(_panel_sequence(p, s, x, fit) for s, x, fit, _ in shown), strict=True)
    synthetic = all(s.synthetic is not None for s, *_ in shown)
    guessed = [s.name for s, _, _, heights_known in shown if not heights_known]
    caption = ("SYNTHETIC series (Rozé's are not printed)" if synthetic else
               "imprints measured" if not any(s.synthetic is not None for s, *_ in shown) else
               "measured and SYNTHETIC series")
    caption += "; slides at: the impacts where the contact slides"
    if guessed:
        caption += "; heights illustrative where only positions are known"
    origin = "; synthetic, since Rozé's series are not printed" if synthetic else ""
    return FigureSpec(
        "ricochets", f"Ricochets on {len(shown)} surface{'s' if len(shown) > 1 else ''}, fitted to their imprints",
        "x along the plane (m)", "height of the centre (m)", (), caption=caption, panels=tuple(panels), columns=2,
        sharey=True, legend="below",
        reading=(f"The path of the ball's centre over each surface (one panel each), drawn by the model fitted to the "
                 f"imprints (red ticks{origin}). Each flight is shorter than the one before, by a factor close to "
                 "the fitted ν: " + "; ".join(words) + "."
                 + ("" if not guessed else f" The heights of {', '.join(guessed)} only illustrate, since positions "
                                           "alone do not fix α0.")))


def _figures_error_maps(p: Params, tolerance: float) -> list[FigureSpec]:
    """The relative error of (8) and of (9) over α0 and f, with the line where it reaches ``tolerance``. (9)'s on
    logarithmic axes: its error grows as f tan α0, and only there does the corner where it holds show."""
    tol = f"{tolerance * 100:g} %"
    texts = {
        "error-eq8": (
            f"ν = {p.map_nu:g}, no spin. Left of the dashed line the contact slides through the impact and (8) is "
            "exact (drawn at the floor $10^{-6}$).",
            "How far Résal's eq. (8), P1/P0 = ν[1 − f(1 + ν) tan α0], is from the exact ratio of two successive "
            "ranges, over the incidence α0 and the friction f (colour: the relative error, on a logarithmic scale). "
            "Where the contact slides through the impact (left of the dashed line) it is exact; beyond, where the "
            f"contact grips, its error jumps past {tol} (Rozé's two digits, red line) and grows with α0 and f."),
        "error-eq9": (
            f"ν = {p.map_nu:g}, no spin; both axes logarithmic. Left of the dashed line (9) errs by about the dropped "
            f"term $f(1 + \\nu)\\tan\\alpha_0$; right of it (grip) by 1/k = {1 / p.k:.2g}.",
            "How far eq. (9), P1/P0 = ν, is from the exact ratio of two successive ranges, over the incidence α0 "
            "and the friction f, both on logarithmic scales (colour: the relative error). It holds to Rozé's two "
            f"digits ({tol}) only below the red line, where f tan α0 is small, the premise Résal states; the error "
            f"reaches 5 % on the dotted line, and where the contact grips (right of the dashed line) a ball without "
            f"spin keeps only k/(1 + k) of its horizontal speed and (9) errs by 1/k = {1 / p.k:.2g}."),
    }
    out = []
    for name, title in (("error-eq8", "eq. (8)"), ("error-eq9", "eq. (9)")):
        if name == "error-eq8":
            alpha, f, scale = np.linspace(0.005, p.map_alpha_max, 120), np.linspace(0.0, p.map_f_max, 100), "linear"
        else:
            alpha = np.radians(np.geomspace(0.1, np.degrees(p.map_alpha_max), 120))
            f, scale = np.geomspace(0.002, p.map_f_max, 100), "log"
        A, F = np.meshgrid(alpha, f, indexing="xy")  # rows: f, columns: α0
        exact = plane.range_ratio_exact(A, f=F, nu=p.map_nu, k=p.k)
        approx = (plane.range_ratio_resal(A, f=F, nu=p.map_nu) if name == "error-eq8" else
                  plane.range_ratio_small_angle(np.full_like(A, p.map_nu)))
        err = np.clip(np.abs(approx - exact) / np.abs(exact), 1e-6, None)
        boundary_alpha = np.degrees(np.arctan(1.0 / np.maximum(f * (1 + p.k) * (1 + p.map_nu), 1e-12)))
        keep = boundary_alpha <= np.degrees(p.map_alpha_max)
        deg = np.degrees(alpha)
        layers = [layer("heatmap", deg, f, z=err, label="relative error", norm="log"),
                  layer("contour", deg, f, z=np.log(err / tolerance), label=f"error {tol} (Rozé's two digits)",
                        color="C3")]
        if name == "error-eq9":
            layers.append(layer("contour", deg, f, z=np.log(err / 0.05), label="error 5 %", color="C3", style=":"))
        layers.append(layer("line", boundary_alpha[keep], f[keep], label="slide / grip boundary (first impact)",
                            color="k", style="--"))
        caption, reading = texts[name]
        lims = ((0.0, float(np.degrees(p.map_alpha_max))), (0.0, p.map_f_max)) if scale == "linear" else \
            ((float(deg[0]), float(deg[-1])), (float(f[0]), float(f[-1])))
        out.append(FigureSpec(
            name, f"Relative error of {title} against the exact range ratio", "$\\alpha_0$ (degrees)", "f",
            tuple(layers), *lims, caption, reading, legend="below", xscale=scale, yscale=scale))
    return out


def _figure_estimators(rows: list[tuple], names: dict[str, str]) -> FigureSpec:
    layers = []
    surfaces = [r[0] for r in rows if r[1] == "positions"]
    for i, name in enumerate(("positions", "flight times")):
        sel = [r for r in rows if r[1] == name]
        xs = np.arange(len(sel)) + (i - 0.5) * 0.15
        layers.append(layer("errorbar", xs, [r[3] - r[2] for r in sel], [r[5] for r in sel],
                            label=f"ν̂ − ν from {name} (mean ± s.d.)", color=f"C{i}", marker="o"))
    layers.append(layer("line", [-0.5, len(surfaces) - 0.5], [0, 0], color="0.5", style=":"))
    sd = {name: max(r[5] for r in rows if r[1] == name) for name in ("positions", "flight times")}
    worst = max((r for r in rows if r[1] == "positions"), key=lambda r: r[5])
    return FigureSpec("estimators", "Bias and spread of the two ν estimators (synthetic)",
                      f"surface (synthetic series, {rows[0][7]} seeds each)", "ν̂ − ν", tuple(layers),
                      (-0.5, len(surfaces) - 0.5),
                      xticklabels=tuple(textwrap.fill(names.get(sid, sid), 10) for sid in surfaces),
                      reading=f"For each surface, the error of ν fitted to {rows[0][7]} synthetic series generated "
                              "with a known ν: the dot is the mean error (the bias), the bar one standard deviation. "
                              f"Flight times give ν with a spread of at most {sd['flight times']:.1g}; imprint "
                              f"positions alone scatter up to {sd['positions']:.1g} ({names.get(worst[0], worst[0])}).")
