"""``resal fit markers``: angle markers of oblique collisions against the impact angle ψ → the ball–ball friction f
and Newton's e of §VI n°13, with 95 % profile-likelihood intervals.

Per line: ``series`` (``alpha1``: the cue ball's turn, between its directions before and after the impact; or
``throw``: the object ball's departure from the line of centres, positive forward), ``psi_deg`` (the impact angle, 0
= head-on) and ``angle_deg``, both in degrees, read right after the impact. The cue ball rolls naturally onto a ball
at rest; the prediction is §VI n°13's impact on the cloth with law (6) of §I, ε = ε′ = (1 − e)/(1 + e)
(``estimators.markers``), and the angles depend neither on the speed nor on the balls' size. Each series has its own
σ, estimated from its scatter with a floor of 0.5° (a reading precision; a series more precise than that is not
believed); f and e are fitted to each series present and, with both, jointly, with a likelihood-ratio test of
whether the two series agree. The throw alone fixes f but hardly e (reported as such). A trend of the residuals with
ψ is tested: a constant friction through the impact (§VI's premise) leaves none. Other conventions of the angles
(ψ from the tangent, α1 or the throw from another line, the throw's sign, radians) are refitted and ranked by
likelihood; one far likelier than the file as read is named with the change to make (``_readings``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ...results import FigureSpec, layer
from ...series import Table, as_table, read_markers
from ..checks import Code, Reading, better_reading, warn
from ..estimators import markers as mk
from .common import FitOptions, FitOutcome, base_summary, estimate_row, today

SERIES = ("alpha1", "throw")
RADIANS = 1.6  # psi_deg all below π/2 rad ≈ 1.57: the angles are radians, almost surely
LABELS = {"alpha1": "α1, the cue ball's turn", "throw": "the object ball's throw"}
CORIOLIS_F = ("Coriolis's ball–ball friction « ne paraît pas devoir atteindre 0,03 » (§VI n°13)", 0.03, 610)
METHOD = "profile likelihood (§VI n°13 on the cloth), σ of each series estimated with a 0.5° floor, Δ(−2lnL) = 3.84"


def _rows(key: str, what: str, fit: mk.MarkerFit) -> list[dict[str, Any]]:
    out = []
    for name, value, ci, ident, bound, lims, note in (
            ("f", fit.f, fit.ci_f, fit.f_identified, fit.at_bound_f, mk.F_BOUNDS, "ball–ball friction"),
            ("e", fit.e, fit.ci_e, fit.e_identified, fit.at_bound_e, mk.E_BOUNDS,
             "Newton's e of law (6), ε = (1 − e)/(1 + e): the impact's normal ratio where the friction keeps one "
             "direction; a turning slip moves it by order f²")):
        label = f"{name} ({what})"
        if not ident:
            out.append(estimate_row(f"{key}.{name}", label, None, None, (None, None), method=METHOD,
                                    identifiable=False, note=f"not identifiable: any value in [{lims[0]:g}, "
                                                             f"{lims[1]:g}] fits within the cut"))
            continue
        reach = [s for s, x, b in (("lower", ci[0], lims[0]), ("upper", ci[1], lims[1])) if x == b]
        extra = f"; the 95 % interval reaches the {' and '.join(reach)} bound" if reach else ""
        out.append(estimate_row(f"{key}.{name}", label, value, None, ci, method=METHOD, at_bound=bound,
                                bound_aware=True, note=note + extra))
    return out


def fit_angle_markers(kind: str, source: Path | Table, opts: FitOptions) -> FitOutcome:
    """The fit of ``resal fit markers`` (module docstring)."""
    src = as_table(source)  # a CSV file read once, or a program's arrays
    m = read_markers(src, SERIES, required=())
    model = mk.Model(R=opts.R, k=opts.k)
    parts = {s: mk.Part(*m.series[s], s) for s in SERIES if s in m.series}
    n = sum(p.psi.size for p in parts.values())
    columns = [{"column": c, "quantity": q, "unit": u, "note": ""} for c, q, u in (
        ("series", "alpha1 or throw", "1"), ("psi_deg", "impact angle ψ", "deg"), ("angle_deg", "the angle", "deg"))]
    summary = base_summary(kind, src, n, columns, opts)
    summary["bootstrap"] = None
    psi_max = max(float(p.psi.max()) for p in parts.values())
    if psi_max < RADIANS:  # every impact angle under 1.6°: a file of radians read as degrees, most likely
        warn(summary, Code.UNIT, f"every psi_deg is below {RADIANS:g}° (the largest {psi_max:g}): impact angles in "
                                 "radians written in a column of degrees? The fit reads them as degrees")
    fits = {s: mk.fit_markers([p], model) for s, p in parts.items()}
    joint = mk.fit_markers(list(parts.values()), model) if len(parts) == 2 else None
    _other_readings(summary, parts, model, (joint or next(iter(fits.values()))).m2lnl,
                    radians_said=psi_max < RADIANS)
    for s, f in fits.items():
        summary["fits"] += _rows(s, f"{LABELS[s]} alone", f)
    if joint is not None:
        summary["fits"] = _rows("joint", "both series", joint) + summary["fits"]
        lr, dof, p = mk.agreement(list(fits.values()), joint)
        summary["agreement"] = {"lr": lr, "dof": dof, "p": p,
                                "verdict": "the two series agree on (f, e)" if p >= 0.05 else
                                "the two series do not share one (f, e) (p < 0.05)"}
        if p < 0.05:
            warn(summary, Code.SERIES, f"the two series do not share one (f, e): likelihood ratio {lr:.3g} on {dof} "
                                       f"degrees of freedom, p = {p:.2g}; read the joint fit with care")
    for s, f in [*fits.items(), *([("joint", joint)] if joint is not None else [])]:
        if f.rival is not None:
            rf, re_, d = f.rival
            warn(summary, Code.SECOND_MINIMUM,
                 f"{LABELS.get(s, 'both series')}: a second valley at f = {rf:.3g}, e = {re_:.3g} fits only "
                 f"{d:.2g} worse in −2 ln L (outside the 95 % interval, but the interval's χ² calibration cannot "
                 "exclude it): the markers do not decide between the two")
    best = joint if joint is not None else next(iter(fits.values()))
    trend = {}
    table = []
    for s, part in parts.items():
        pred = mk.angles(part.psi, best.f, best.e, model)[s]
        res = part.obs - pred
        t = mk.slope_test(part.psi, res)
        trend[s] = {"slope_per_10deg": 10 * t.slope, "stderr_per_10deg": 10 * t.stderr, "p": t.p,
                    "verdict": "no trend with ψ" if t.p >= 0.05 else
                    "a trend with ψ (p < 0.05): a constant friction through the impact does not describe it"}
        if t.p < 0.05:
            warn(summary, Code.SPEED_LAW, f"{LABELS[s]}: the residuals trend with ψ ({10 * t.slope:+.2g} ± "
                                          f"{10 * t.stderr:.2g}° per 10°, p = {t.p:.2g}): a constant friction "
                                          "through the impact does not describe these markers")
        table += [(s, float(a), float(b), float(c), float(d)) for a, b, c, d in zip(part.psi, part.obs, pred, res,
                                                                                     strict=True)]
    summary["residual_trend"] = trend
    summary["noise"] = {"model": "one σ per series, estimated (floor 0.5°)",
                        "sigma_deg": dict(zip(parts, best.sigma, strict=True))}
    every = [*fits.values(), *([joint] if joint is not None else [])]
    if any(f.nodes for f in every):
        summary["model_evaluation"] = {
            "psi_nodes": max(f.nodes for f in every),
            "interpolation_error_deg": max(f.interp_error for f in every),
            "note": f"more than {mk.PSI_NODES} markers: the model was evaluated at evenly spaced impact angles and "
                    f"interpolated, within {mk.INTERP_TOL:g}° of the model at every marker at the estimate"}
    comp: dict[str, list] = {"paper": [], "today": []}
    if best.f_identified:
        comp["paper"].append({"claim": CORIOLIS_F[0], "value": CORIOLIS_F[1], "line": CORIOLIS_F[2],
                              "verdict": "your 95 % interval of f lies below it" if best.ci_f[1] < CORIOLIS_F[1]
                              else "your 95 % interval of f does not lie below it"})
        comp["today"] += today(("mu_bb",), best.ci_f, "f")
    if best.e_identified:
        comp["today"] += today(("e_bb",), best.ci_e, "e")
    summary["comparison"] = comp
    return FitOutcome(summary, _figures(parts, best, model), ("series", "psi_deg", "angle_deg", "predicted_deg",
                                                              "residual_deg"), tuple(table))


# The other readings of a file that its markers can judge by likelihood (issue 30, item 3): conventions an
# experimenter may have followed instead of this kind's, each refitted by the same profile likelihood
# (``mk.fit_markers``) and ranked by −2 ln L of the values as written; the likeliest, if far better than the file as
# read (``checks.CONVENTION_MARGIN``), is named with what to change. Each reading maps (series, ψ, written angle)
# to (ψ, angle) as this kind reads them; ``jac`` is d(angle as read)/d(written), whose log enters −2 ln L (angles in
# radians are stretched 57.3 times: without it the stretched residuals would always look worse, or better).
READINGS_MAX = 400  # markers refitted per reading, spread evenly through a longer file (a minute's worth at most)


def _readings() -> tuple[tuple[str, str, tuple[str, ...], Any, float], ...]:
    """(name, how to change the file, the series it concerns, (ψ, written) → (ψ, angle), jac)."""
    deg = 180.0 / np.pi
    return (
        ("ψ measured from the tangent line (psi_deg holding 90° − ψ)", "write 90 − psi_deg in psi_deg (0 = head-on)",
         SERIES, lambda psi, a: (90.0 - psi, a), 1.0),
        ("α1 as the cue ball's direction after the impact measured from the line of centres (ψ + α1)",
         "write angle_deg − psi_deg for the alpha1 markers (the turn from the cue ball's first direction)",
         ("alpha1",), lambda psi, a: (psi, a - psi), 1.0),
        ("the throw signed the other way (positive backward)", "change the sign of the throw markers",
         ("throw",), lambda psi, a: (psi, -a), 1.0),
        ("the throw as the object ball's direction measured from the cue ball's first line (ψ − throw)",
         "write psi_deg − angle_deg for the throw markers (the departure from the line of centres)",
         ("throw",), lambda psi, a: (psi, psi - a), 1.0),
        ("the angles (angle_deg) in radians", "write the angles in degrees (× 180/π)",
         SERIES, lambda psi, a: (psi, a * deg), deg),
    )


def _spread(part: mk.Part, n: int) -> mk.Part:
    """At most ``n`` markers of a series, spread evenly through it."""
    if part.psi.size <= n:
        return part
    idx = np.unique(np.linspace(0, part.psi.size - 1, n).round().astype(int))
    return mk.Part(part.psi[idx], part.obs[idx], part.key)


def _other_readings(summary: dict[str, Any], parts: dict[str, mk.Part], model: mk.Model, as_read: float, *,
                    radians_said: bool) -> None:
    """Warn (``checks.better_reading``) when another reading of ``_readings`` fits the markers far better; the
    readings' misfits go to ``summary["conventions"]`` (−2 ln L of the values as written, lower is likelier)."""
    total = sum(p.psi.size for p in parts.values())
    share = READINGS_MAX / total  # below 1 in a longer file: each series keeps its share (8 markers at least)
    sub = {s: _spread(p, max(8, int(p.psi.size * share))) for s, p in parts.items()} if share < 1 else parts
    if sub is not parts:  # the reading as written is refitted on the same markers as the others
        as_read = mk.fit_markers(list(sub.values()), model).m2lnl
    out, rows = [], []
    for name, how, series, change, jac in _readings():
        if not any(s in sub for s in series) or (radians_said and jac != 1.0):
            continue
        moved, ok = [], True
        for s, p in sub.items():
            psi, a = change(p.psi, p.obs) if s in series else (p.psi, p.obs)
            ok = ok and bool(np.all((psi > 0) & (psi < 90) & (a > -90) & (a <= 90)))
            moved.append(mk.Part(psi, a, s))
        if not ok:  # some marker read so is no angle of this kind: not this reading
            continue
        f = mk.fit_markers(moved, model)
        n_changed = sum(p.psi.size for p in sub.values() if p.key in series)
        misfit = f.m2lnl - 2.0 * n_changed * float(np.log(jac))
        rows.append({"reading": name, "misfit": misfit, "f": f.f, "e": f.e})
        out.append(Reading(name, how, misfit, f"f = {f.f:.3g}, e = {f.e:.3g}"))
    summary["conventions"] = {"as_read": as_read, "readings": rows, "markers": sum(p.psi.size for p in sub.values()),
                              "misfit": "−2 log-likelihood of the markers as written (each series' σ profiled, floor "
                                        "0.5°), the reading's stretch of the angles included"}
    better_reading(summary, as_read, out)


def _figures(parts: dict[str, mk.Part], best: mk.MarkerFit, model: mk.Model) -> tuple[FigureSpec, ...]:
    lo_psi = min(float(p.psi.min()) for p in parts.values())
    hi_psi = max(float(p.psi.max()) for p in parts.values())
    grid = np.linspace(max(lo_psi - 3, 1.0), min(hi_psi + 3, 89.0), 50)
    panels = []
    for s, part in parts.items():
        curve, lo, hi = mk.prediction_band(grid, best, s, model)
        panels.append(FigureSpec(
            f"markers-{s}", LABELS[s], "impact angle ψ (deg, 0 = head-on)", f"{s} (deg)", (
                layer("band", grid, lo, hi, label="95 % band", color="C0"),
                layer("line", grid, curve, label=f"§VI, f = {best.f:.3f}, e = {best.e:.3f}", color="C0"),
                layer("points", part.psi, part.obs, label=f"your markers ({part.psi.size})", color="k",
                      marker="."))))
    return (FigureSpec("markers", "Your angle markers against §VI", "impact angle ψ (deg, 0 = head-on)", "deg", (),
                       panels=tuple(panels), columns=len(panels),
                       reading="Your markers against ψ with §VI's curve at the fitted (f, e) and its pointwise 95 % "
                               "band."),)
