"""Kind ``rebound``: a ball striking an immovable mass (§I n°5, eq. (9)): cushion, marble slab.

The datum is either the velocity ratio −V1/V0 (Coriolis's cushion) or the rebound height ratio h1/h0
(the ball dropped on marble); ε follows from the inverse of eq. (9). An optional series of trials, a
user's CSV or a synthetic one generated from the model with a seeded noise, is fitted by least squares.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import Experiment, Node
from ..fit.estimators.lsq import FitResult, fit_rebound
from ..mechanics import impact
from ..series import read_rebounds
from .base import (
    Computed,
    FigureSpec,
    FitRow,
    Reproduction,
    fit_rows,
    identifiability_report,
    layer,
    modern_rows,
    rows_for,
)

QUANTITIES = ("eq9_limit", "eps", "velocity_ratio", "eps_no_rebound", "eps_series", "measured_datum", "free_fall")
COST = 0.45  # CPU seconds of a run with its figures, about: the process pool starts the longest first
MODERN = ("e_c", "e_c(v)", "e_t")
MAX_TRIALS = 10_000  # a synthetic series: far more trials than any measured one, still fitted in a blink
G = 9.80665  # only to turn drop heights into speeds; every ratio here is independent of g


@dataclass(frozen=True)
class Synthetic:
    n: int
    low: float
    high: float
    noise: float  # relative standard deviation of each measured rebound


@dataclass(frozen=True)
class Params:
    quantity: str  # "velocity_ratio" or "height_ratio"
    value: float
    half_unit: float | None  # half a unit of the measurement's last printed digit, when printed in decimals
    speed_max: float | None
    synthetic: Synthetic | None
    series: Path | None


def parse(node: Node, base: Path) -> Params:
    m = node.child("measured", "a mapping with quantity and value")
    quantity = m.string("quantity", choices=("velocity_ratio", "height_ratio"))
    value, exact, raw, vnode = m.number_node("value", "a ratio in [0, 1]")
    if not 0.0 <= value <= 1.0:
        raise m.fail(f"'{m.path}.value' must be a ratio in [0, 1], got {raw}", vnode)
    half = None
    if not exact and "." in raw:
        half = 0.5 * 10.0 ** -len(raw.strip().split(".")[1])
    speed_max = m.number("speed_max", "a speed in m/s", lo=0.0, lo_open=True) if m.has("speed_max") else None
    m.done()
    synthetic = series = None
    if node.has("series"):
        s = node.child("series", "a mapping with either synthetic or csv")
        if s.has("csv") == s.has("synthetic"):
            raise s.fail(f"'{s.path}' must have exactly one of 'csv' (a file) or 'synthetic' (a generator)")
        if s.has("csv"):
            series = base / s.string("csv")
            read_rebounds(series, heights=quantity == "height_ratio")  # a bad file stops the run before any work
        else:
            g = s.child("synthetic", "a mapping with n, low, high, noise")
            n = g.integer("n", "a number of trials", lo=2, hi=MAX_TRIALS)
            low = g.number("low", "the smallest speed (m/s) or drop height (m)", lo=0.0, lo_open=True)
            high = g.number("high", "the largest speed (m/s) or drop height (m)", lo=low)
            noise = g.number("noise", "a relative standard deviation", lo=0.0, hi=1.0)
            g.done()
            synthetic = Synthetic(n, low, high, noise)
        s.done()
    node.done()
    return Params(quantity, value, half, speed_max, synthetic, series)


def _speed_ratio(p: Params, value: float) -> float:
    return math.sqrt(value) if p.quantity == "height_ratio" else value


def _series(p: Params, seed: int) -> tuple[np.ndarray, np.ndarray, str] | None:
    """(V0, V1, label) of the trials: speeds directly, or from drop heights by free fall."""
    cols = ("V0", "V1") if p.quantity == "velocity_ratio" else ("h0", "h1")
    if p.series is not None:
        s = read_rebounds(p.series, heights=p.quantity == "height_ratio")  # refuses h1 < 0, h1 > h0, V1 > 0
        a, b, label = s[cols[0]], s[cols[1]], f"measured series ({p.series.name})"
    elif p.synthetic is not None:
        syn = p.synthetic
        rng = np.random.default_rng(seed)
        a = np.sort(rng.uniform(syn.low, syn.high, syn.n))
        # the noise is clipped at −100 %, so that a synthetic rebound never changes sign (only for noise near 1)
        b = (-p.value if p.quantity == "velocity_ratio" else p.value) * a * np.maximum(
            1 + syn.noise * rng.standard_normal(syn.n), 0.0)
        label = f"SYNTHETIC series: model with r = {p.value:.4g}, {syn.noise:.0%} noise, seed {seed}"
    else:
        return None
    if p.quantity == "height_ratio":
        return np.sqrt(2 * G * a), -np.sqrt(2 * G * b), label
    return a, b, label


def _slips(r: float, printed: float, tol: float) -> list[str]:
    """Arithmetic slips that would turn the ratio r into the printed ε (to the printed digits)."""
    candidates = {
        "(1 − r)/(2 − r), a slip in the denominator": (1 - r) / (2 - r),
        "(1 − r²)/(1 + r²), the height ratio taken for the velocity ratio": (1 - r * r) / (1 + r * r),
        "(2 − √3)/√3, i.e. r taken as √3 − 1": 2 / math.sqrt(3) - 1,
    }
    return [f"{k} = {v:.4f}" for k, v in candidates.items() if abs(v - printed) <= tol * abs(printed)]


def eq9_limit_check(seed: int, n: int = 64, mass_ratio: float = 1e12) -> float:
    """Largest |V1(9) − V1(8)| / V0 between eq. (9) as printed and eq. (8) with M′ = 10¹² M, over random
    (ε, ε′): the paper obtains (9) as that limit, in which ε′ drops out."""
    rng = np.random.default_rng(seed)
    V0 = rng.uniform(0.5, 7.0, n)
    eps, epsp = rng.uniform(0.0, 1.0, (2, n))
    printed = -(1 - eps) / (1 + eps) * V0  # eq. (9) as printed, transcribed only to be compared
    limit = impact.direct_impact(1.0, mass_ratio, V0, 0.0, eps=eps, epsp=epsp).V1
    return float(np.max(np.abs(printed - limit) / V0))


def free_fall_check(seed: int, n: int = 16) -> float:
    """Largest |√(h1/h0) − (−V1/V0)| between the rebound height ratio of a drop integrated in time (fall from h0,
    rebound at −r V0, rise to the apex) and the velocity ratio r, over random r and h0 (§I n°5, marble): the
    step from 'aux 2/3 de la hauteur' to (1 − ε)/(1 + ε) = √(2/3)."""
    rng = np.random.default_rng(seed + 3)
    r = rng.uniform(0.05, 1.0, n)
    h0 = rng.uniform(0.05, 2.0, n)
    return float(np.max(np.abs(np.sqrt(impact.drop_rebound_height_ratio(h0, r, G)) - r)))


def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    r = _speed_ratio(p, p.value)
    eps = float(impact.eps_from_velocity_ratio(r))
    kind = "rebound height ratio" if p.quantity == "height_ratio" else "velocity ratio −V1/V0"

    def why_eps(printed: float) -> str:
        needed = float(impact.eps_from_velocity_ratio(printed))  # the map is its own inverse
        tol = next(x.tolerance for x in exp.printed if x.computed == "eps") or 0.0
        slips = _slips(r, printed, tol)
        text = (f"eq. (9) with r = {r:.4f} gives ε = {eps:.4f}; the printed {printed:g} needs r = {needed:.4f} "
                f"(height ratio {needed**2:.3f})")
        return text + ("; it matches " + " or ".join(slips) if slips else "; no simple slip found")

    def why_ratio(printed: float) -> str:
        for d in range(1, 5):
            if math.isclose(math.floor(r * 10**d) / 10**d, printed, rel_tol=1e-12):
                return f"√ of the ratio is {r:.4f}: truncated, not rounded, to {d} decimals (rounds to {round(r, d)})"
        return f"√ of the ratio is {r:.4f}"

    data = _series(p, exp.seed)
    fit: FitResult | None = fit_rebound(data[0], data[1]) if data else None
    computed = {
        "eq9_limit": Computed(eq9_limit_check(exp.seed), "largest |(9) − (8) at M′ = 10¹² M| / V0 over 64 random "
                                                           "(ε, ε′)"),
        "eps": Computed(eps, f"inverse of eq. (9) with the {kind} {p.value:.6g}", why_eps),
        "velocity_ratio": Computed(r, "√ of the height ratio (free fall)" if p.quantity == "height_ratio"
                                   else "the measured ratio", why_ratio),
        "eps_no_rebound": Computed(float(impact.eps_from_velocity_ratio(0.0)),
                                   "eq. (9) with no rebound: ε = 1, Carnot's inelastic impact (eq. 4); the paper "
                                   "explains it by vibration, which ε absorbs (end of n°3)"),
        "eps_series": Computed(None if fit is None else fit.point[0], "least-squares fit of the series"),
        "measured_datum": Computed(None, "a measurement, the datum of this experiment"),
        "free_fall": Computed(free_fall_check(exp.seed), "largest |√(h1/h0) − r| over 16 drops integrated in time "
                                                         "(rebound at r times the impact speed)"),
    }
    fits: list[FitRow] = []
    if p.half_unit is not None:
        lo, hi = (float(impact.eps_from_velocity_ratio(_speed_ratio(p, p.value + s * p.half_unit))) for s in (1, -1))
        fits.append(FitRow("printed-ratio.eps", "ε", eps, None, (None, None), "inverse of eq. (9)", True,
                           f"the ratio is printed to ±{p.half_unit:g}: ε ∈ [{lo:.4f}, {hi:.4f}] from rounding alone"))
    else:
        fits.append(FitRow("printed-ratio.eps", "ε", eps, None, (None, None), "inverse of eq. (9)", True,
                           "the ratio is printed as a fraction, with no stated uncertainty"))
    if fit is not None and data is not None:
        fits += fit_rows(fit, "series", {"eps": "ε"}, "least squares on eq. (9)", f"{data[2]}; n = {fit.n_data}")
    modern = modern_rows(exp.modern, {
        "e_c": (r, "−V1/V0 measured by Coriolis"),
        "e_c(v)": (r, "Coriolis: about constant up to 7 m/s"),
        "e_t": (r, "√(h1/h0) on marble"),
    })
    figures = [_figure_ratio(p, r, eps, exp)]
    if data is not None and fit is not None:
        figures.append(_figure_series(data, fit, r, p))
    ident = () if fit is None or data is None else (identifiability_report(fit, "series", {"eps": "ε"}, data[2]),)
    return Reproduction(exp, rows_for(exp, computed), tuple(fits), tuple(figures), modern,
                        data_note="" if data is None else data[2], identifiability=ident)


def _printed_eps(exp: Experiment) -> float | None:
    return next((x.value for x in exp.printed if x.computed == "eps"), None)


def _figure_ratio(p: Params, r: float, eps: float, exp: Experiment) -> FigureSpec:
    printed = _printed_eps(exp)
    if p.quantity == "velocity_ratio":
        x = np.linspace(0.0, 1.0, 201)
        layers = [layer("line", x, impact.eps_from_velocity_ratio(x), label="ε = (1 − r)/(1 + r), eq. (9)"),
                  layer("points", [r], [eps], label=f"computed: r = {r:.3g} ⇒ ε = {eps:.4f}", color="C3")]
        if printed is not None:
            layers.append(layer("points", [r], [printed], label=f"printed ε = {printed:g}", color="C1", marker="x"))
        band = ""
        for m in modern_rows(("e_c",), {"e_c": (r, "")}) if "e_c" in exp.modern else ():
            if m["low"] is not None and m["high"] is not None:
                layers.append(layer("vband", [m["low"], m["high"]], label=f"modern cushion e: {m['source'][:40]}",
                                    color="C2"))
                lo, hi = (float(impact.eps_from_velocity_ratio(x)) for x in (m["high"], m["low"]))
                band = (f"; the green band, today's measured restitution of cushions ({m['low']:g} to "
                        f"{m['high']:g}), means ε from {lo:.2f} to {hi:.2f}")
        said = "" if printed is None else f" (printed {printed:g})"
        return FigureSpec("eps-vs-ratio", "ε against the measured velocity ratio (eq. 9)",
                          "velocity ratio $r = -V_1/V_0$", "Résal's ε", tuple(layers), (0, 1), (0, 1),
                          reading=(
                              "Résal's coefficient ε against the measured ratio r of the rebound speed to the impact "
                              "speed, from eq. (9): ε = (1 − r)/(1 + r), 0 for a perfect rebound and 1 for none. "
                              f"Coriolis's ratio {r:.3g} gives ε = {eps:.4f}{said}" + band + "."))
    e = np.linspace(0.0, 1.0, 201)
    layers = [layer("line", e, impact.velocity_ratio_from_eps(e) ** 2, label="$h_1/h_0$ = ((1 − ε)/(1 + ε))², eq. (9)"),
              layer("points", [eps], [p.value], label=f"computed: ε = {eps:.4f}", color="C3")]
    if printed is not None:
        layers.append(layer("points", [printed], [p.value], label=f"printed: ε = {printed:g}", color="C1", marker="x"))
        layers.append(layer("points", [printed], [float(impact.velocity_ratio_from_eps(printed)) ** 2],
                            label="what the printed ε predicts", color="C1", marker="s"))
    off = "" if printed is None else (
        f"; the printed ε = {printed:g} (cross) lies off the curve and would give "
        f"{float(impact.velocity_ratio_from_eps(printed)) ** 2:.3f} (square)")
    return FigureSpec("height-vs-eps", "Rebound height ratio against ε (eq. 9)", "Résal's ε",
                      "rebound height ratio $h_1/h_0$", tuple(layers), (0, 1), (0, 1),
                      reading=(
                          "How high a ball dropped on a slab rebounds, as a fraction of its drop height, against "
                          "Résal's ε: with free fall, eq. (9) gives h1/h0 = ((1 − ε)/(1 + ε))². The paper's rebound "
                          f"to {p.value:.3g} of the height gives ε = {eps:.4f} (dot)" + off + "."))


def _figure_series(data: tuple[np.ndarray, np.ndarray, str], fit: FitResult, r: float, p: Params) -> FigureSpec:
    """The series and its fit: the speeds (upper panel), and each point's ratio −V1/V0 (lower panel), where the
    fit's ratio and its 95 % interval stand out from the points' scatter (on the speeds they are one line)."""
    V0, V1, label = data
    est = fit.estimates[0]
    x = np.linspace(0.0, float(V0.max()) * 1.05, 50)
    ratio = float(-impact.infinite_mass_impact(1.0, eps=est.value))
    speeds = [layer("points", V0, -V1, label="SYNTHETIC series" if "SYNTHETIC" in label.upper() else "measured series",
                    color="C0"),
              layer("line", x, ratio * x, label=f"fit: ε = {est.value:.4f}", color="C3")]
    ratios = [layer("points", V0, -V1 / V0, color="C0"),
              layer("line", [0.0, x[-1]], [ratio, ratio], color="C3")]
    band = ""
    if est.ci95[0] is not None and est.ci95[1] is not None:
        lo, hi = (float(-impact.infinite_mass_impact(1.0, eps=e)) for e in (est.ci95[1], est.ci95[0]))
        speeds.append(layer("band", x, lo * x, hi * x, label="95 % interval of ε", color="C3"))
        ratios.append(layer("band", [0.0, x[-1]], [lo, lo], [hi, hi], color="C3"))
        band = f" and its 95 % interval (shaded: a ratio from {lo:.4f} to {hi:.4f})"
    speeds.append(layer("line", x, r * x, label=f"paper's ratio {r:.4g}", color="C7", style="--"))
    ratios.append(layer("line", [0.0, x[-1]], [r, r], color="C7", style="--"))
    what = ("Synthetic rebound speeds generated with the paper's ratio (Coriolis's measurements are not printed)"
            if "SYNTHETIC" in label.upper() else "Measured rebound speeds")
    return FigureSpec("series", "Rebound speed against impact speed", "impact speed $V_0$ (m/s)", "",
                      (), caption=label, legend="below", heights=(2.0, 1.3), panels=(
                          FigureSpec("series-speeds", "", "", "rebound speed $-V_1$ (m/s)", tuple(speeds)),
                          FigureSpec("series-ratio", "", "", "ratio $-V_1/V_0$", tuple(ratios))),
                      reading=(
                          f"{what}, against the impact speed, with the straight line of eq. (9) fitted to them "
                          f"(ε = {est.value:.4f}){band} and the paper's ratio {r:.4g} (dashed). A ratio that does "
                          "not depend on the speed, as Coriolis found, puts the points on one line through the "
                          "origin; the lower panel shows each point's ratio, where the fit is a level line."))
