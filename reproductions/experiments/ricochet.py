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
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import Experiment, Node
from ..fitting import FitResult, fit_physical, fit_physical_positions, fit_positions, fit_times
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

STATIC = ("eq6_sliding", "eq6_all_regimes", "eq7_tan_sliding", "range_formula", "eq8_sliding", "eq8_all_regimes",
          "eq9_limit", "angles_decrease", "footnote_drop_ratio")
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
                         f"the figure file ricochet-<id> and the quantity nu.<id>), got '{sid}'", at)
        if sid.lower() in seen:
            raise s.fail(f"'{s.path}.id' repeats the surface id '{seen[sid.lower()]}' (surface ids must be unique, "
                         "ignoring case: each names a figure file and a quantity)", at)
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
    and flight, over random scenes; 'sliding' rows only over scenes where the slip lasts the whole impact."""
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
    # P = a² sin α cos α / g as printed, against the integrated flight (a, α leaving the plane)
    a1 = np.hypot(ref.chi1, ref.zeta1)
    al1 = np.arctan2(ref.zeta1, ref.chi1)
    P_flight, _ = reference.integrate_flight(ref.chi1, ref.zeta1, p.g)
    err_range = np.abs(a1**2 * np.sin(al1) * np.cos(al1) / p.g - P_flight) / np.abs(P_flight)
    # (8) against the ratio of integrated flights: the flight that arrives (χ0, ζ0) and the next one
    P_before, _ = reference.integrate_flight(chi0, -zeta0, p.g)
    ratio_ref = P_flight / P_before
    alpha0 = np.arctan(tan0)
    err8 = np.abs(nu * (1 - f * (1 + nu) * np.tan(alpha0)) - ratio_ref) / np.abs(ratio_ref)
    fwd_all = (chi0 - pR > 0)
    # (9) as the small-angle limit of the exact ratio (spinless ball)
    tiny = 1e-7
    lim9 = np.max(np.abs(plane.range_ratio_exact(tiny, f=f, nu=nu, k=k) - nu) / nu)
    # "à plus forte raison": once f tan α is small, the next angles are smaller still (tan α1 < tan α0)
    a_grid, f_grid, nu_grid = np.meshgrid(np.linspace(1e-3, math.atan(0.05 / 0.5), 40), np.linspace(0.01, 0.5, 40),
                                          np.linspace(0.3, 0.9, 13), indexing="ij")
    small = f_grid * np.tan(a_grid) <= 0.05
    ratio_tan = nu_grid / (1 - f_grid * (1 + nu_grid) * np.tan(a_grid))
    return {
        "eq6_sliding": float(np.max(err6[slide])),
        "eq6_all_regimes": float(np.max(err6)),
        "eq7_tan_sliding": float(np.max(err7[forward])),
        "range_formula": float(np.max(err_range)),
        "eq8_sliding": float(np.max(err8[slide & fwd_all & (ref.chi1 > 0)])),
        "eq8_all_regimes": float(np.max(err8[fwd_all])),
        "eq9_limit": float(lim9),
        "angles_decrease": float(max(0.0, np.max(ratio_tan[small]) - 1.0)),
    }


# ---- the experiment -----------------------------------------------------------------------------------------
def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    checks = formula_checks(p, exp.seed)
    how = "largest relative discrepancy from the integrated impact/flight over 24 random scenes"
    computed: dict[str, Computed] = {k: Computed(v, how) for k, v in checks.items()}
    computed["eq6_all_regimes"] = Computed(checks["eq6_all_regimes"], how, lambda _p: (
        f"eqs (6) assume the slip lasts the whole impact; where it stops (|χ0 − p0R| < f(1 + k)(1 + ν)|ζ0|) the "
        f"contact then rolls and (6) overshoots: largest error {checks['eq6_all_regimes']:.3g} |ζ0|"))
    computed["range_formula"] = Computed(checks["range_formula"], how, lambda _p: (
        "the range of a parabolic flight is 2a² sin α cos α / g; the printed a² sin α cos α / g lacks the factor 2 "
        "(a slip of the original or of the transcription); the ratio (8) is unaffected, the factor cancels"))
    computed["eq8_all_regimes"] = Computed(checks["eq8_all_regimes"], how, lambda _p: (
        f"(8) is exact while the contact slides; where the slip stops during an impact the exact ratio is "
        f"ν(kχ0 + p0R)/((1 + k)χ0) and (8) errs by up to {checks['eq8_all_regimes']:.0%} (see the error map)"))
    computed["angles_decrease"] = Computed(checks["angles_decrease"], (
        "largest tan α1/tan α0 − 1 where f tan α0 ≤ 0,05, for ν in [0,3; 0,9] (Rozé's 0,63–0,85): the angles do "
        "decrease. By the third of eqs (7) the exact condition is f(1 + ν) tan α0 < 1 − ν: it holds because ν < 1, "
        "and fails for ν close to 1 however small f tan α0 is"))
    drop_ratio = math.sqrt(p.drop_height_ratio)
    computed["footnote_drop_ratio"] = Computed(drop_ratio, "√ of n°5's rebound height ratio on marble")

    fits: list[FitRow] = []
    ident: list[dict] = []
    figures: list[FigureSpec] = []
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
            "Rozé's series are not printed; the synthetic series, generated with the printed mean, only "
            "exercises the fit (see the fits)" if s.synthetic is not None else "fit of the measured imprints")
        figures.append(_figure_sequence(p, s, x, shown, t is not None))
        if s.synthetic is not None:
            rows_est += _compare_estimators(p, s, exp.seed + 1000 * (i + 1))
    figures += _figures_error_maps(p)
    tables = ()
    if rows_est:
        tables = (TableSpec("estimators", "ν from imprint positions and from flight times (synthetic, many seeds)",
                            ("surface", "estimator", "true ν", "mean ν̂", "bias", "std. dev.", "RMSE", "seeds"),
                            tuple(rows_est),
                            "Same synthetic series for both estimators in each repetition."),)
        figures.append(_figure_estimators(rows_est))
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


def _figure_sequence(p: Params, s: Surface, x: np.ndarray, fit: FitResult, heights_known: bool) -> FigureSpec:
    nu, f, a0, alpha0 = fit.point
    r = plane.ricochet(a0, alpha0, p.p0_fit, R=p.R, k=p.k, f=f, nu=nu, g=p.g, n=x.size - 1)
    xs, zs = [], []
    for j in range(x.size - 1):  # the centre's parabola between imprints j and j+1
        tt = np.linspace(0.0, r.times[j], 30)
        xs.append(r.imprints[j] + r.chi[j] * tt)
        zs.append(p.R + r.zeta[j] * tt - 0.5 * p.g * tt**2)
    kind = "SYNTHETIC " if s.synthetic is not None else ""
    return FigureSpec(
        f"ricochet-{s.id}", f"Ricochets on {s.name}", "x along the plane (m)", "height of the centre (m)",
        (layer("line", np.concatenate(xs), np.concatenate(zs), label=f"fitted model: ν = {nu:.3f}", color="C0"),
         layer("points", x, np.zeros_like(x), label=f"{kind}imprints ({x.size})", color="C3", marker="|")),
        caption=f"{kind}series; slides at impacts "
                f"{', '.join(str(i + 1) for i in np.nonzero(r.regimes == Regime.SLIDE)[0]) or 'none'}"
                + ("" if heights_known else "; heights illustrative: α0 is not determined by positions alone"))


def _figures_error_maps(p: Params) -> list[FigureSpec]:
    alpha = np.linspace(0.005, p.map_alpha_max, 120)
    f = np.linspace(0.0, p.map_f_max, 100)
    A, F = np.meshgrid(alpha, f, indexing="xy")  # rows: f, columns: α0
    exact = plane.range_ratio_exact(A, f=F, nu=p.map_nu, k=p.k)
    boundary_alpha = np.degrees(np.arctan(1.0 / np.maximum(f * (1 + p.k) * (1 + p.map_nu), 1e-12)))
    keep = boundary_alpha <= np.degrees(p.map_alpha_max)
    out = []
    for name, approx, title in (("error-eq8", plane.range_ratio_resal(A, f=F, nu=p.map_nu), "eq. (8)"),
                                ("error-eq9", plane.range_ratio_small_angle(np.full_like(A, p.map_nu)), "eq. (9)")):
        err = np.clip(np.abs(approx - exact) / np.abs(exact), 1e-6, None)
        out.append(FigureSpec(
            name, f"Relative error of {title} against the exact range ratio (ν = {p.map_nu:g}, no spin)",
            "α0 (degrees)", "f",
            (layer("heatmap", np.degrees(alpha), f, z=np.log10(err), label="log10 relative error"),
             layer("line", boundary_alpha[keep], f[keep], label="slide / grip boundary (first impact)",
                   color="w", style="--")),
            (0.0, float(np.degrees(p.map_alpha_max))), (0.0, p.map_f_max),
            "Left of the dashed line the contact slides during the whole impact, where (8) is exact."))
    return out


def _figure_estimators(rows: list[tuple]) -> FigureSpec:
    layers = []
    for i, name in enumerate(("positions", "flight times")):
        sel = [r for r in rows if r[1] == name]
        xs = np.arange(len(sel)) + (i - 0.5) * 0.15
        layers.append(layer("errorbar", xs, [r[3] - r[2] for r in sel], [r[5] for r in sel],
                            label=f"ν̂ − ν from {name} (mean ± s.d.)", color=f"C{i}", marker="o"))
    layers.append(layer("line", [-0.5, len(rows) / 2 - 0.5], [0, 0], color="0.5", style=":"))
    return FigureSpec("estimators", "Bias and spread of the two ν estimators (synthetic)",
                      "surface: " + ", ".join(r[0] for r in rows if r[1] == "positions"), "ν̂ − ν", tuple(layers))
