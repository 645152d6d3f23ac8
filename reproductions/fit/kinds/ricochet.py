"""``resal fit ricochet`` and ``resal fit bounces``: ν (and f, g where identifiable), §III n°8-10.

Ricochet: imprint positions (and optionally impact instants) of a ball skipping along a plane; both origins are
fitted (``fitting.fit_imprints``, ``fit_times(origin="fitted")``), and ν's interval is the profile likelihood's.
Bounces: the impact instants of a ball bouncing in place (an audio recording's clicks), the origin fitted
(``fitting.fit_bounces``); with the drop height, g as well.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...errors import InputError
from ...mechanics import plane
from ...results import FigureSpec, layer
from ...series import UNITS, Series, Table, as_table, check_imprints, read_series, unit_label
from ..checks import (
    CHI2_P,
    G_HIGH,
    G_LOW,
    Code,
    chi2_given,
    leave_one_out,
    loo_entries,
    name_outliers,
    noise_plausible,
    plausible_values,
    warn,
)
from ..estimators.lsq import (
    FitResult,
    bounce_instants,
    fit_bounces,
    fit_friction,
    fit_imprints,
    fit_times,
    numeric_jacobian,
)
from ..estimators.trials import bootstrap
from .common import (
    FitOptions,
    FitOutcome,
    base_summary,
    boot_note,
    check_sigma,
    columns_read,
    identifiability,
    rows_from_fit,
    today,
)

DIMS = {"x": "length", "t": "time"}
# measured over 300 seeded series of 8 imprints with instants (tests/test_fit_coverage_ricochet.py)
F_NOTE = ("f's 95 % interval is the profile likelihood's (both origins fitted, positions and instants weighted by "
          "their own noise, Student's t with Welch–Satterthwaite degrees of freedom); it covered the true f in 93 % "
          "of 300 synthetic series of 8 imprints (Wald's covered 76 %)")
MIN_CLICKS = 5  # three parameters and two degrees of freedom for the noise
# the scatter such measurements plausibly have about the §III model: imprints marked on paper or a slab are read to a
# few millimetres, so 2 cm is already a misread series or a ball that is not ricocheting as §III says; a click's onset
# in a recording is sharp to a millisecond, and a real ball's ν drifting with speed adds a few ms: 20 ms is not that
NOISE_X = 0.02  # m
NOISE_T = 0.02  # s


def fit_ricochet(kind: str, source: Path | Table, opts: FitOptions) -> FitOutcome:
    src = as_table(source)  # a CSV file read once, or a program's arrays
    if opts.sigma is not None:
        raise InputError(f"--sigma {opts.sigma:g}", "not used by the ricochet fit, which estimates the noise of "
                                                    "positions and instants from their residuals: leave it out")
    s = read_series(src, ("x",), optional=("t",), min_rows=1, dims=DIMS)
    x, t = s["x"], s.get("t")
    check_imprints(x, src.where, t, s.at, s.units.get("x"))
    x = x - x[0]
    t = None if t is None else t - t[0]
    fi = fit_imprints(x, k=opts.k)
    labels = {"nu": "ν", "A": "A = 2a0² sin α0 cos α0/g (m)", "u": "f tan α0", "x0": "x0, the first imprint (m)"}
    fits = rows_from_fit(fi, "positions", labels, "least squares on imprint positions (§III, spinless), origin "
                         "fitted; ν's interval: profile likelihood", units={"A": "m", "x0": "m"})
    ident = [identifiability(fi, labels, f"{src.name}: positions")]
    if t is not None:
        ft = fit_times(t, g=opts.g, origin="fitted")
        fits += rows_from_fit(ft, "times", {"nu": "ν (acoustic)", "zeta1": "ζ1 (m/s)", "t0": "t0 (s)"},
                              "least squares on impact instants, origin fitted; ν's interval: profile likelihood",
                              units={"zeta1": "m/s", "t0": "s"})
        fj = fit_friction(x, t, R=opts.R, k=opts.k, g=opts.g)  # (ν, f, a0, α0, x0, t0), f's profile interval
        fits += rows_from_fit(fj, "joint-physical", {"f": "f (positions + instants)"},
                              "least squares, physical parameters, both origins fitted; f's interval: profile "
                              "likelihood", only=("f",))
        fe = fj.estimate("f")
        for r in fits:
            if r["id"] == "joint-physical.f":
                extra = F_NOTE if r["value"] is not None else (
                    f"profile-likelihood 95 % set of f: [{fe.ci95[0]:.4g}, {fe.ci95[1]:.4g}]"
                    if fe.ci95[0] is not None and fe.ci95[1] is not None else "")
                r["note"] = "; ".join(t_ for t_ in (r["note"], extra) if t_)
        ident.append(identifiability(fj, {"nu": "ν", "f": "f", "a0": "a0", "alpha0": "α0", "x0": "x0", "t0": "t0"},
                                     f"{src.name}: positions and instants"))
    summary = base_summary(kind, src, x.size, columns_read(s, DIMS), opts)
    summary["fits"] = fits
    summary["identifiability"] = ident
    summary["bootstrap"] = None
    nu_, A_, u_, x0_ = fi.point
    P = plane.ricochet_ranges_spinless(nu_, A_, u_, opts.k, x.size - 1)
    model = x0_ + np.concatenate([[0.0], np.cumsum(P)])
    _check_series(summary, s, x, model, fi, opts.k, t, ft if t is not None else None, opts.g)
    flights = np.arange(1, x.size)
    fig = FigureSpec("fit", "resal fit ricochet: the range of each flight, measured and fitted",
                     "flight number", "range (m)",
                     (layer("points", flights, np.diff(x), label="measured (between imprints)"),
                      layer("line", flights, P, color="C1", label=f"fitted, ν = {nu_:.4g} (§III, spinless)")),
                     caption="while the ball slides, friction shortens each range more than ν; once it rolls, by ν")
    res = FigureSpec("residuals", "resal fit ricochet: residuals of the imprint positions", "imprint number",
                     "measured − fitted x (m)",
                     (layer("points", np.arange(x.size), x - model, label="imprints"),
                      layer("line", [0.0, float(x.size - 1)], [0.0, 0.0], color="0.4", style=":")))
    return FitOutcome(summary, (fig, res), ("line", "x (m)", "fitted x (m)") + (("t (s)",) if t is not None else ()),
                      tuple((s.lines[i], float(x[i]), float(model[i]), *(() if t is None else (float(t[i]),)))
                            for i in range(x.size)))


def fit_clicks(kind: str, source: Path | Table, opts: FitOptions) -> FitOutcome:
    src = as_table(source)  # a CSV file read once, or a program's arrays
    s = read_series(src, ("t",), min_rows=MIN_CLICKS, dims={"t": "time"})
    t = s["t"]
    bad = np.nonzero(np.diff(t) <= 0)[0]
    if bad.size:
        raise InputError(s.at(int(bad[0]) + 1), f"column '{s.written['t']}': impact instants must increase; "
                                                f"{t[bad[0] + 1]:g} s is not after {t[bad[0]]:g} s")
    factor, unit = s.factors["t"], s.unit_text["t"]
    check_sigma(opts.sigma, [t / factor - t[0] / factor], unit)
    sigma = None if opts.sigma is None else opts.sigma * factor
    fb = fit_bounces(t - t[0], g=opts.g, h0=opts.h0, sigma=sigma)
    labels = {"nu": "ν (normal-velocity yield = e)", "T1": "T1, the first flight (s)", "t0": "t0, first click (s)",
              "g": "g (m/s²)"}
    method = "least squares on impact instants, origin fitted; ν's interval: profile likelihood; " + (
        f"σ = {opts.sigma:g} {unit} given" if sigma is not None else "jitter estimated (Student's t)")
    fits = rows_from_fit(fb, "bounces", labels, method, units={"T1": "s", "t0": "s", "g": "m/s²"})
    nu = next(r for r in fits if r["id"] == "bounces.nu")
    summary = base_summary(kind, src, t.size, columns_read(s, {"t": "time"}), opts)
    summary["fits"] = fits
    summary["identifiability"] = [identifiability(fb, labels, src.name)]
    if nu["value"] is not None:
        summary["comparison"] = {"paper": [], "today": today(("e_t",), tuple(nu["ci95"]), "ν")}
    tt = t - t[0]
    model = _instants(fb, t.size, opts.h0)
    resid = tt - model
    dof = t.size - 3
    names = ("nu", "g") if opts.h0 is not None else ("nu",)

    def draw(rng: np.random.Generator) -> np.ndarray:
        # residual bootstrap: the fitted instants plus resampled residuals, inflated for the 3 fitted parameters
        return model + rng.choice(resid, t.size) * math.sqrt(t.size / dof)

    def refit(ts: np.ndarray) -> list[float]:
        if np.any(np.diff(ts) <= 0):
            raise ValueError("a resample whose instants do not increase")
        f = fit_bounces(ts, g=opts.g, h0=opts.h0, sigma=sigma)
        return [float(f.point[f.names.index(n)]) for n in names]

    boot = bootstrap(refit, draw, names, opts.resamples, opts.seed, opts.progress) if opts.resamples else None
    if boot is not None:
        for r in fits:
            key = r["id"].split(".")[-1]
            if key in boot.names:
                r["ci95_bootstrap"] = list(boot.ci95[boot.names.index(key)])
    summary["bootstrap"] = None if boot is None else {"resamples": boot.resamples, "seed": boot.seed,
                                                      "failed": boot.failed,
                                                      "kind": "residuals (resampled onto the fitted instants)",
                                                      "note": boot_note(kind)}
    _check_clicks(summary, s, tt, model, fb, opts.h0, sigma)
    flights = np.diff(t)
    k = np.arange(flights.size)
    fitted = np.diff(model)
    figs = (FigureSpec("fit", "resal fit bounces: flight durations, measured and fitted", "flight number",
                       "duration (s)", (layer("points", k, flights, label="measured (between clicks)"),
                                        layer("line", k, fitted, color="C1",
                                              label=f"fitted: T1 ν^i, ν = {fb.point[0]:.4g} (§III n°9)"))),
            FigureSpec("residuals", "resal fit bounces: residuals of the click instants", "click number",
                       "measured − fitted instant (s)",
                       (layer("points", np.arange(t.size), resid, label="clicks"),
                        layer("line", [0.0, float(t.size - 1)], [0.0, 0.0], color="0.4", style=":"))))
    return FitOutcome(summary, figs, ("line", "t (s)", "fitted t (s)"),
                      tuple((s.lines[i], float(t[i]), float(model[i] + t[0])) for i in range(t.size)))


def _instants(fb: FitResult, n: int, h0: float | None) -> np.ndarray:
    """t_i = t0 + T1 (1 − ν^i)/(1 − ν) at the fit's point (§III n°9), T1 = 2ν√(2 h0/g) when g was fitted."""
    p = dict(zip(fb.names, fb.point, strict=True))
    return bounce_instants(p["nu"], _first_flight(fb, h0), p["t0"], n)[0]


def _first_flight(fb: FitResult, h0: float | None) -> float:
    """T1 at the fit's point: fitted, or, when g was (ν, g, t0), T1 = 2ν√(2h0/g) (§III n°9)."""
    p = dict(zip(fb.names, fb.point, strict=True))
    return p["T1"] if "T1" in p else 2 * p["nu"] * math.sqrt(2 * float(h0 or 0.0) / p["g"])


def _imprint_model(th: np.ndarray, k: float, n: int) -> np.ndarray:
    """x_i = x0 + P_0 + … + P_{i−1}, the spinless closed form (§III n°9) at θ = (ν, A, u, x0)."""
    P = plane.ricochet_ranges_spinless(th[0], th[1], th[2], k, n - 1)
    return th[3] + np.concatenate([[0.0], np.cumsum(P)])


STEEPEST = math.radians(60.0)  # a first flight leaving the plane steeper than this is no ricochet (a ball that skims)


def _check_rise(summary: dict, s: Series, zeta1: float, along: float) -> None:
    """The instants give the first flight's normal speed ζ1 (through g), the positions its speed along the plane:
    a flight steeper than ``STEEPEST`` is a ball hopping in place, not a ricochet, or positions in a unit larger
    than the header says (the advice on a span too long names two units where positions alone cannot tell them;
    the instants can). Names each larger unit that makes the flight a skim between 5° and 45°."""
    if not (along > 0 and math.atan2(zeta1, along) > STEEPEST):
        return
    have = UNITS["length"].get(s.units.get("x") or "m", 1.0)
    tan = zeta1 / along
    units = [u for u, factor in UNITS["length"].items() if u in ("m", "cm", "mm") and factor > have
             and math.tan(math.radians(5.0)) <= tan * have / factor <= 1.0]
    hint = ("; read in " + " or ".join(f"{unit_label(u)} (x_{u})" for u in units) + " it would skim at "
            + " or ".join(f"{math.degrees(math.atan(tan * have / UNITS['length'][u])):.2g}°" for u in units)
            if units else "")
    warn(summary, Code.UNIT, f"the first flight leaves the plane at {math.degrees(math.atan(tan)):.3g}° (its normal "
                             f"speed {zeta1:.3g} m/s from the instants, {along:.3g} m/s along the plane from the "
                             f"positions): a ricochet skims; are the positions in a larger unit than the header says "
                             f"(column '{s.written['x']}'){hint}?")


def _check_series(summary: dict, s: dict, x: np.ndarray, model: np.ndarray, fi: FitResult, k: float,
                  t: np.ndarray | None, ft: FitResult | None, g: float) -> None:
    """A ricochet series checks itself: each imprint (and instant) predicted from the others (leave-one-out),
    the scatter against what such measurements plausibly have."""
    n = x.size
    J = numeric_jacobian(lambda th: _imprint_model(th, k, n), fi.point)
    r = x - model
    lines = np.asarray(s.lines)
    loo = leave_one_out(r, J, lines, sigma_known=False)
    entries = loo_entries(loo, lines, ["x"] * n, x + s["x"][0], np.ones(n))
    for e in entries:
        e["unit"] = "m"
    name_outliers(summary, lines, loo["p"], "imprint", s.table)
    if fi.dof > 0:
        noise_plausible(summary, float(np.sqrt(r @ r / fi.dof)), NOISE_X, "the imprint positions", "m")
    if t is not None:
        msg = plausible_values(np.diff(t), np.diff(s["t"]) / s.factors["t"], "flight-time", "time", s.units.get("t"),
                               f"the flights between the imprints' instants (column '{s.written['t']}')",
                               s.unit_text["t"], ("t",))
        if msg:
            warn(summary, Code.UNIT, msg)
        assert ft is not None  # the instants' fit, made beside the positions'
        nu, zeta1, t0 = ft.point
        _check_rise(summary, s, float(zeta1), float((x[1] - x[0]) / (t[1] - t[0])))
        mt, Jt = bounce_instants(nu, 2.0 * zeta1 / g, t0, n)
        Jt = Jt.copy()
        Jt[:, 1] *= 2.0 / g  # d/dζ1 of T1 = 2ζ1/g
        rt = t - mt
        loo_t = leave_one_out(rt, Jt, lines, sigma_known=False)
        te = loo_entries(loo_t, lines, ["t"] * n, t + s["t"][0], np.ones(n))
        for e in te:
            e["unit"] = "s"
        entries += te
        name_outliers(summary, lines, loo_t["p"], "instant", s.table)
        if ft.dof > 0:
            noise_plausible(summary, float(np.sqrt(rt @ rt / ft.dof)), NOISE_T, "the impact instants", "s")
    summary["leave_one_out"] = entries


def _check_clicks(summary: dict, s: dict, tt: np.ndarray, model: np.ndarray, fb: FitResult, h0: float | None,
                  sigma: float | None) -> None:
    """Clicks check themselves: flights of a plausible duration (milliseconds read as seconds?), each click
    predicted from the others (leave-one-out), the jitter against what a recording plausibly has."""
    n = tt.size
    flights = np.diff(tt)
    msg = plausible_values(flights, flights / s.factors["t"], "flight-time", "time", s.units.get("t"),
                           f"the flights between the clicks (column '{s.written['t']}')", s.unit_text["t"], ("t",))
    if msg:
        warn(summary, Code.UNIT, msg)
    p = dict(zip(fb.names, fb.point, strict=True))
    _, J = bounce_instants(p["nu"], _first_flight(fb, h0), p["t0"], n)
    r = tt - model
    lines = np.asarray(s.lines)
    sig = 1.0 if sigma is None else sigma
    held = sigma is not None
    if sigma is not None and fb.dof > 0:
        red, p_chi2 = chi2_given(float(np.sum((r / sigma) ** 2)), fb.dof)
        summary["goodness"] = {"reduced_chi2": red, "chi2_p": p_chi2}
        if p_chi2 < CHI2_P:  # a σ the scatter contradicts would make every click an outlier: the scale is estimated
            held = False
            warn(summary, Code.CHI2, f"the scatter exceeds the given σ: reduced χ² = {red:.3g} (p = {p_chi2:.2g}); "
                                     "the intervals from σ are too narrow (is σ in the clicks' unit, "
                                     f"{s.unit_text['t']}?)")
    loo = leave_one_out(r / sig, J / sig, lines, sigma_known=held)
    summary["leave_one_out"] = loo_entries(loo, lines, ["t"] * n, tt + s["t"][0], np.full(n, sig))
    name_outliers(summary, lines, loo["p"], "click", s.table)
    if sigma is None and fb.dof > 0:
        noise_plausible(summary, float(np.sqrt(r @ r / fb.dof)), NOISE_T, "the click instants", "s")
    if h0 is not None:
        msg = plausible_values(np.array([h0]), np.array([h0]), "drop-height", "length", None, f"--h0 {h0:g}", "m")
        if msg:
            warn(summary, Code.UNIT, msg.replace("(write the unit in the header, '_mm')", "(--h0 takes metres)")
                 .replace("(write the unit in the header, '_cm')", "(--h0 takes metres)"))
        g_row = next((f for f in summary["fits"] if f["id"] == "bounces.g"), None)
        if g_row is not None and g_row["ci95"][0] is not None and not (
                g_row["ci95"][0] <= G_HIGH and g_row["ci95"][1] >= G_LOW):
            warn(summary, Code.RESULT, f"g = {g_row['value']:.4g} m/s² (95 %: {g_row['ci95'][0]:.4g}–"
                                       f"{g_row['ci95'][1]:.4g}) is not gravity, {G_LOW:g}–{G_HIGH:g} m/s² anywhere "
                                       "on Earth: --h0 (the drop height, in metres) or the clicks' unit is wrong")

