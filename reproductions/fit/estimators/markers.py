"""Angle markers of oblique collisions against ψ: the cue ball's turn α1 and the object ball's throw, and (f, e)
fitted to them by profile likelihood.

The scene (Doménech-Carbó 2023's bench, and any like it). A cue ball in natural roll (§II n°7: the contact point on
the surface at rest, no side spin) strikes an identical ball at rest with impact angle ψ (0 = head-on): ψ is the
cut angle of ``shots.predict_shots``. The impact is Résal's §VI n°13 (p. 88–93, eqs (1)–(9)): two balls resting on
the cloth, ball–ball friction f that turns during the impact, vertical translations blocked by the cloth, the
cloth's own friction neglected during the impact (as Coriolis does, quoted l. 608), the normal impulse from the
energy-loss law (6) of §I with ε = ε′ = (1 − e)/(1 + e) (eq. (9) of §I, l. 216), which gives Newton's e exactly when
f = 0. ``predict_shots`` solves it (``spheres.two_spheres(on_cloth=True)``) and then slides each ball to rolling
(§II n°7, ``cloth.slide``).

The angles (degrees), read right after the impact in the lab frame (X along the incoming velocity, the line of
centres at +ψ):
- ``alpha1``: the cue ball's turn, −atan2(v1_y, v1_x); 90° − ψ for smooth elastic balls.
- ``throw``: ψ − θ2, θ2 the object ball's direction: its departure from the line of centres (0 for smooth balls).
- ``sep_dev``: 90° − (α1 + θ2), the separation's departure from 90°; for smooth balls atan((1 − e)/(2 tan ψ)).
- ``cue_dev``: 90° − ψ − α1, the cue ball's departure from the smooth elastic tangent line.
- ``throw_rolled``: the object ball's departure from the line of centres once it rolls (after §II).
Coulomb friction and law (6) are homogeneous of degree 1 in the velocities, so none of these depends on the speed.

The likelihood. A marker's residual r = measured − model (degrees) is Gaussian with one σ per series, profiled out
with a floor (the digitisation error): σ̂² = max(RSS/n, floor²), −2 ln L = Σ_series [n ln σ̂² + RSS/σ̂²] (constants
dropped). The 95 % interval of f (of e) is the set where its profile, the other parameter re-minimised, stays within
``cut`` = 3.841 (χ²₁, Wilks) of the minimum; an interval that reaches a bound of the parameter says so.

The solver. The model is evaluated on whole (f, e) grids × all ψ in one batched call: a coarse grid over the bounds
locates the region within the cut; a uniform local grid over that region is refined (shrunk or widened, at most
``MAX_ZOOM`` times) until the region lies inside it, off its edges unless they are bounds, and spans at least
``MIN_SPAN`` of its steps; −2 ln L on that grid is then interpolated by a bicubic spline onto a grid ``UPSAMPLE``
times finer, on which the minimum and both profiles are read. Everything is a finite number of batched calls.
Beyond ``PSI_NODES`` markers the model is evaluated at that many impact angles evenly spread over the markers' range
and interpolated linearly in ψ (a departure from evaluating §VI at each marker, for speed: 10⁵ markers cost what
2048 do); at the estimate the interpolation is compared with the model at every marker, and the fit is redone with
four times the nodes while it errs by more than ``INTERP_TOL`` (0.01°, a fiftieth of the floor).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ...lazy import lazy
from ...mechanics import spheres
from .. import distributions as dist
from .shots import predict_shots

interpolate = lazy("scipy.interpolate", globals())

__all__ = ["ANGLES", "CUT", "FLOOR", "INTERP_TOL", "PSI_NODES", "MarkerFit", "Model", "Part", "SlopeTest", "agreement",
           "angles", "fit_f_fixed_e", "fit_markers", "m2lnl", "prediction_band", "slip_speeds", "slope_test"]

ANGLES = ("alpha1", "throw", "sep_dev", "cue_dev", "throw_rolled")
CUT = 3.841458820694124  # scipy.dist.chi2_ppf(0.95, 1) (tested): one parameter profiled (Wilks)
FLOOR = 0.5  # degrees: the digitisation error, the floor of each series' σ
F_BOUNDS = (0.0, 0.6)
E_BOUNDS = (0.05, 1.0)
RIVAL = 10.0  # −2 ln L within this of the minimum: a second valley that the χ² calibration of the cut cannot dismiss
N_LOCAL = 25  # points per parameter of the local grid
MAX_ZOOM = 5  # refinements of the local grid
MIN_SPAN = 10  # steps of the local grid the 95 % region must span (unless it spans the bounds)
UPSAMPLE = 8
_F_COARSE = np.linspace(0.0, 0.6, 25)
_E_COARSE = np.array([0.05, 0.2, 0.35, 0.5, 0.62, 0.72, 0.8, 0.86, 0.9, 0.93, 0.95, 0.965, 0.975, 0.985, 0.993, 1.0])


@dataclass(frozen=True)
class Model:
    """The bench: launch speed (m/s; the angles do not depend on it), ball radius (m), mass (kg), k (I = M R²/k)."""

    speed: float = 0.80
    R: float = 0.0305
    M: float = 0.205
    k: float = 2.5


def _turn(vec: np.ndarray, phi: np.ndarray) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    x, y = vec[..., 0], vec[..., 1]
    return np.stack([c * x - s * y, s * x + c * y, vec[..., 2]], axis=-1)


def angles(psi_deg: np.ndarray | Sequence[float] | float, f: np.ndarray | float, e: np.ndarray | float,
           model: Model = Model()) -> dict[str, np.ndarray]:
    """The angles of ``ANGLES`` (degrees) for impact angles ψ (degrees), broadcasting ψ against f and e: one
    batched call of the §VI impact (module docstring)."""
    psi = np.radians(np.asarray(psi_deg, dtype=float))
    p = predict_shots(model.speed, psi, f_bb=f, e=e, R=model.R, k=model.k, M=model.M)
    psi_d = np.degrees(np.broadcast_to(psi, p.cue_dir.shape))
    alpha1 = -np.degrees(np.arctan2(p.cue_v1[..., 1], p.cue_v1[..., 0]))
    theta2 = np.degrees(np.arctan2(p.obj_v1[..., 1], p.obj_v1[..., 0]))
    return {"alpha1": alpha1, "throw": psi_d - theta2, "sep_dev": 90.0 - (alpha1 + theta2),
            "cue_dev": 90.0 - psi_d - alpha1, "throw_rolled": psi_d - np.degrees(p.obj_dir)}


def slip_speeds(psi_deg: np.ndarray, f: float, e: float, model: Model = Model()) -> tuple[np.ndarray, np.ndarray]:
    """Relative slip speed of the balls at their contact (m/s, eq. (1) of §V n°12) at the onset of the impact and at
    its end: today's μ(v) is a law of that speed. With natural roll the onset slip is the launch speed at every ψ."""
    psi = np.radians(np.asarray(psi_deg, dtype=float))
    p = predict_shots(model.speed, psi, f_bb=f, e=e, R=model.R, k=model.k, M=model.M)
    back = [_turn(x, -psi) for x in (p.cue_v1, p.cue_w1, p.obj_v1, p.obj_w1)]  # to the impact frame
    s1 = spheres.contact_slip(*back, model.R, model.R)
    return np.full(psi.shape, model.speed), np.hypot(s1[..., 0], s1[..., 1])


def m2lnl(res: np.ndarray, floor: float = FLOOR) -> np.ndarray:
    """−2 ln L of one series (residuals on the last axis), its σ profiled with the floor: σ̂² = max(RSS/n, floor²),
    n ln σ̂² + RSS/σ̂²."""
    n = res.shape[-1]
    rss = np.sum(res**2, axis=-1)
    s2 = np.maximum(rss / n, floor**2)
    return n * np.log(s2) + rss / s2


@dataclass(frozen=True)
class Part:
    """One series of markers: ψ and the measured angle (degrees), and the model angle it is compared with."""

    psi: np.ndarray
    obs: np.ndarray
    key: str


@dataclass(frozen=True)
class MarkerFit:
    """(f, e) at the minimum of −2 ln L, their 95 % profile intervals, and where they reach a bound."""

    f: float
    e: float
    m2lnl: float
    ci_f: tuple[float, float]
    ci_e: tuple[float, float]
    at_bound_f: str | None  # "lower" / "upper": the best value lies on that bound
    at_bound_e: str | None
    f_identified: bool  # False when the interval is the whole admissible range
    e_identified: bool
    sigma: tuple[float, ...]  # σ̂ of each part at the minimum (degrees)
    zooms: int  # refinements of the local grid used
    region: np.ndarray = field(repr=False)  # (m, 2): model-evaluated (f, e) pairs within the cut of the minimum
    # another valley of the likelihood outside the intervals: (f, e, its −2 ln L above the minimum), when it lies
    # within RIVAL of the minimum (α1 is not monotonic in f: where the slip stops during the impact it turns back)
    rival: tuple[float, float, float] | None = None
    interp_error: float = 0.0  # degrees: the model interpolated in ψ against the model, at the estimate (0: exact)
    nodes: int = 0  # the impact angles the model was evaluated at (0: at every marker)


CHUNK = 2**16  # (f, e) pairs × markers evaluated at once: 0.5 MB per array, ~50 MB in all, whatever the markers


PSI_NODES = 2048  # beyond this many markers, the model is evaluated at this many ψ and interpolated (``_total``)
INTERP_TOL = 0.01  # degrees: the largest interpolation error accepted at the fit (a fiftieth of ``FLOOR``)


def _psi_nodes(psi: np.ndarray, nodes: int | None) -> np.ndarray | None:
    """The impact angles the model is evaluated at when the markers outnumber ``nodes``: ``nodes`` of them, evenly
    spaced over the markers' range; None (every marker evaluated) otherwise."""
    if nodes is None or psi.size <= nodes or float(psi.max()) <= float(psi.min()):
        return None
    return np.linspace(float(psi.min()), float(psi.max()), nodes)


def _interpolated(a: dict[str, np.ndarray], grid: np.ndarray, psi: np.ndarray) -> dict[str, np.ndarray]:
    """The angles at ``grid`` (last axis) linearly interpolated to ``psi``."""
    i = np.clip(np.searchsorted(grid, psi, side="right") - 1, 0, grid.size - 2)
    w = (psi - grid[i]) / (grid[i + 1] - grid[i])
    return {k: v[..., i] * (1.0 - w) + v[..., i + 1] * w for k, v in a.items()}


def _total(parts: Sequence[Part], f: np.ndarray, e: np.ndarray, model: Model, floor: float,
           nodes: int | None = None) -> np.ndarray:
    """−2 ln L at each (f, e) pair: batched calls over all the markers of all parts, as many pairs at a time as keep
    pairs × markers within ``CHUNK`` (a grid of 625 pairs × 10 000 markers once held 4.5 GB of intermediates; each
    pair's value is computed alone, so the chunks change no bit of it).

    With more markers than ``nodes``, the model is evaluated at ``nodes`` impact angles spread over the markers'
    range and interpolated linearly to each marker (``fit_markers`` checks the error at its estimate): the cost is
    then that of ``nodes`` markers whatever their number (10⁵ markers in the time of 2048)."""
    psi = np.concatenate([p.psi for p in parts])
    grid = _psi_nodes(psi, nodes)
    fr, er = np.ravel(f), np.ravel(e)
    out = np.zeros(fr.size)
    step = max(1, CHUNK // max(psi.size, 1))
    for lo in range(0, fr.size, step):
        hi = min(lo + step, fr.size)
        if grid is None:
            a = angles(psi[None, :], fr[lo:hi, None], er[lo:hi, None], model)
        else:
            a = _interpolated(angles(grid[None, :], fr[lo:hi, None], er[lo:hi, None], model), grid, psi)
        start = 0
        for p in parts:
            stop = start + p.psi.size
            out[lo:hi] += m2lnl(p.obs[None, :] - a[p.key][:, start:stop], floor)
            start = stop
    return out.reshape(np.shape(f))


def _grid(box: tuple[tuple[float, float], tuple[float, float]], n: int) -> tuple[np.ndarray, np.ndarray]:
    return np.linspace(*box[0], n), np.linspace(*box[1], n)


def _next_box(fs: np.ndarray, es: np.ndarray, inside: np.ndarray,
              bounds: tuple[tuple[float, float], tuple[float, float]]) -> tuple[tuple, bool]:
    """The next local box from the region within the cut on the grid (fs × es): widened where the region touches
    an edge that is not a bound, shrunk (to the region ± 2 steps) where it spans fewer than MIN_SPAN steps; and
    whether the grid was already good (no change needed)."""
    new, ok = [], True
    for axis, (g, (lo_b, hi_b)) in enumerate(zip((fs, es), bounds, strict=True)):
        idx = np.nonzero(inside.any(axis=1 - axis))[0]
        step, width = g[1] - g[0], g[-1] - g[0]
        lo, hi = g[idx[0]], g[idx[-1]]
        touch_lo, touch_hi = idx[0] == 0 and g[0] > lo_b, idx[-1] == g.size - 1 and g[-1] < hi_b
        if touch_lo or touch_hi:
            ok = False
            lo = max(lo_b, g[0] - width) if touch_lo else max(lo_b, lo - 2 * step)
            hi = min(hi_b, g[-1] + width) if touch_hi else min(hi_b, hi + 2 * step)
        elif idx[-1] - idx[0] < MIN_SPAN and not (g[0] <= lo_b and g[-1] >= hi_b and idx.size == g.size):
            ok = False
            lo, hi = max(lo_b, lo - 2 * step), min(hi_b, hi + 2 * step)
        else:
            lo, hi = g[0], g[-1]
        new.append((float(lo), float(hi)))
    return tuple(new), ok


def _interval(x: np.ndarray, prof: np.ndarray, lmin: float, cut: float) -> tuple[float, float]:
    """Where a profile (on the fine grid x) crosses lmin + cut, linearly interpolated: the outermost crossings, so
    that a set within the cut made of several pieces (a second valley, e.g. where the slip stops during the impact
    at large f) is reported by its hull; an end of x where the profile does not cross."""
    g = prof - lmin - cut
    inside = np.nonzero(g <= 0)[0]
    if inside.size == 0:  # only if lmin lies below the whole profile by more than the cut: the profile's minimum
        inside = np.array([int(np.argmin(prof))])
    out = []
    for j, b in ((inside[0], inside[0] - 1), (inside[-1], inside[-1] + 1)):
        if not 0 <= b < x.size:
            out.append(float(x[j]))
        else:
            out.append(float(x[j] + (x[b] - x[j]) * (-g[j]) / (g[b] - g[j])))
    return out[0], out[1]


def fit_markers(parts: Sequence[Part], model: Model = Model(), *, floor: float = FLOOR, cut: float = CUT,
                f_bounds: tuple[float, float] = F_BOUNDS, e_bounds: tuple[float, float] = E_BOUNDS,
                nodes: int | None = PSI_NODES) -> MarkerFit:
    """(f, e) of §VI fitted to one or more series of markers by profile likelihood (module docstring).

    More than ``nodes`` markers: the model is interpolated between ``nodes`` impact angles (``_total``); at the
    estimate, the interpolation is compared with the model at every marker, and while it errs by more than
    ``INTERP_TOL`` the fit is redone with four times the nodes (at most until every marker is evaluated: exact).
    ``MarkerFit.interp_error`` is the error at the estimate returned (0 when exact)."""
    n = sum(p.psi.size for p in parts)
    while True:
        fit = _fit_markers(parts, model, floor, cut, f_bounds, e_bounds, nodes)
        if nodes is None or n <= nodes or fit.interp_error <= INTERP_TOL:
            return fit
        nodes = 4 * nodes if 4 * nodes < n else None


def _fit_markers(parts: Sequence[Part], model: Model, floor: float, cut: float, f_bounds: tuple[float, float],
                 e_bounds: tuple[float, float], nodes: int | None) -> MarkerFit:
    bounds = (f_bounds, e_bounds)
    fc = np.unique(np.clip(_F_COARSE * (f_bounds[1] / F_BOUNDS[1]), *f_bounds))
    ec = np.unique(np.clip(_E_COARSE, *e_bounds))
    FC, EC = np.meshgrid(fc, ec, indexing="ij")
    LC = _total(parts, FC, EC, model, floor, nodes)
    near = LC - LC.min() <= cut + 2.0
    fi, ei = np.nonzero(near.any(1))[0], np.nonzero(near.any(0))[0]
    box = ((float(fc[max(fi[0] - 1, 0)]), float(fc[min(fi[-1] + 1, fc.size - 1)])),
           (float(ec[max(ei[0] - 1, 0)]), float(ec[min(ei[-1] + 1, ec.size - 1)])))
    zooms = 0
    while True:
        fs, es = _grid(box, N_LOCAL)
        F, E = np.meshgrid(fs, es, indexing="ij")
        L = _total(parts, F, E, model, floor, nodes)
        inside = L - L.min() <= cut
        new, ok = _next_box(fs, es, inside, bounds)
        if ok or zooms == MAX_ZOOM:
            break
        box, zooms = new, zooms + 1
    spline = interpolate.RectBivariateSpline(fs, es, L, kx=3, ky=3)
    ff = np.linspace(fs[0], fs[-1], (N_LOCAL - 1) * UPSAMPLE + 1)
    ef = np.linspace(es[0], es[-1], (N_LOCAL - 1) * UPSAMPLE + 1)
    LF = np.maximum(spline(ff, ef), L.min() - 1.0)  # an overshoot of the spline cannot make a false minimum
    i, j = np.unravel_index(int(np.argmin(LF)), LF.shape)
    f_hat, e_hat = float(ff[i]), float(ef[j])
    lmin = float(_total(parts, np.array([f_hat]), np.array([e_hat]), model, floor, nodes)[0])
    if L.min() < lmin:  # the spline's minimum is no better than the best point evaluated: keep that point
        a, b = np.unravel_index(int(np.argmin(L)), L.shape)
        f_hat, e_hat, lmin = float(fs[a]), float(es[b]), float(L.min())
    ci_f = _interval(ff, LF.min(axis=1), lmin, cut)
    ci_e = _interval(ef, LF.min(axis=0), lmin, cut)

    def bound(x: float, lo_hi: tuple[float, float]) -> str | None:
        return "lower" if x <= lo_hi[0] else "upper" if x >= lo_hi[1] else None

    psi = np.concatenate([p.psi for p in parts])
    a = angles(psi, f_hat, e_hat, model)
    grid = _psi_nodes(psi, nodes)
    err = 0.0
    if grid is not None:  # the interpolation against the model at every marker, at the estimate
        approx = _interpolated(angles(grid, f_hat, e_hat, model), grid, psi)
        err = max(float(np.max(np.abs(approx[p.key][s:s + p.psi.size] - a[p.key][s:s + p.psi.size])))
                  for p, s in zip(parts, np.cumsum([0, *(q.psi.size for q in parts)])[:-1].tolist(), strict=True))
    sig, start = [], 0
    for p in parts:
        r = p.obs - a[p.key][start:start + p.psi.size]
        start += p.psi.size
        sig.append(float(max(np.sqrt(np.mean(r**2)), floor)))
    return MarkerFit(f_hat, e_hat, lmin, ci_f, ci_e, bound(f_hat, f_bounds), bound(e_hat, e_bounds),
                     not (ci_f[0] <= f_bounds[0] and ci_f[1] >= f_bounds[1]),
                     not (ci_e[0] <= e_bounds[0] and ci_e[1] >= e_bounds[1]), tuple(sig), zooms,
                     np.stack([F[L - lmin <= cut], E[L - lmin <= cut]], axis=-1), _rival(fc, ec, LC, lmin, ci_f),
                     err, 0 if grid is None else grid.size)


def _rival(fc: np.ndarray, ec: np.ndarray, LC: np.ndarray, lmin: float,
           ci_f: tuple[float, float]) -> tuple[float, float, float] | None:
    """The best local minimum of the coarse profile in f (over the whole admissible box) that lies outside f's
    interval by more than one coarse step, if it is within ``RIVAL`` of the minimum: a second valley."""
    prof = LC.min(axis=1)
    step = fc[1] - fc[0] if fc.size > 1 else 0.0
    best = None
    for i in range(fc.size):
        left = prof[i - 1] if i > 0 else np.inf
        right = prof[i + 1] if i + 1 < fc.size else np.inf
        outside = fc[i] < ci_f[0] - step or fc[i] > ci_f[1] + step
        if outside and prof[i] <= left and prof[i] <= right and prof[i] - lmin <= RIVAL:
            if best is None or prof[i] < prof[best]:
                best = i
    if best is None:
        return None
    return float(fc[best]), float(ec[int(np.argmin(LC[best]))]), float(prof[best] - lmin)


def fit_f_fixed_e(part: Part, e: float, model: Model = Model(), *, floor: float = FLOOR, cut: float = CUT,
                  f_bounds: tuple[float, float] = F_BOUNDS) -> tuple[float, tuple[float, float]]:
    """f alone, e held fixed: its value and 95 % profile interval on one series (the same likelihood), from a
    coarse grid over the bounds, then a grid 1/40 as fine over the region within the cut (twice at most)."""
    xs = np.linspace(*f_bounds, 61)
    for _ in range(3):
        L = _total([part], xs, np.full_like(xs, e), model, floor)
        k = np.nonzero(L - L.min() <= cut)[0]
        lo, hi = xs[max(k[0] - 1, 0)], xs[min(k[-1] + 1, xs.size - 1)]
        if k[-1] - k[0] >= 20:
            break
        xs = np.linspace(lo, hi, 81)
    best = int(np.argmin(L))
    return float(xs[best]), _interval(xs, L, float(L[best]), cut)


def agreement(separate: Sequence[MarkerFit], joint: MarkerFit) -> tuple[float, int, float]:
    """Likelihood ratio of the joint fit against the separate ones: Λ = −2lnL_joint − Σ −2lnL_separate, its degrees
    of freedom (2 per extra fit: f and e) and its χ² p-value. A small p: the series do not share (f, e)."""
    lr = max(joint.m2lnl - sum(s.m2lnl for s in separate), 0.0)
    dof = 2 * (len(separate) - 1)
    return float(lr), dof, float(dist.chi2_sf(lr, dof))


@dataclass(frozen=True)
class SlopeTest:
    slope: float  # degrees per degree of ψ
    stderr: float
    p: float


def slope_test(psi: np.ndarray, res: np.ndarray) -> SlopeTest:
    """Least-squares line of the residuals against ψ: a trend means the model's shape, not only its level, is off
    (here: a constant friction f through the impact, §VI, is not enough)."""
    r = dist.line(psi, res)
    return SlopeTest(float(r.slope), float(r.stderr), float(r.pvalue))


def prediction_band(psi_deg: np.ndarray, fit: MarkerFit, key: str,
                    model: Model = Model()) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The model curve at the fit and its pointwise 95 % band: the range of the prediction over the (f, e) pairs
    within the cut of the minimum (a profile-likelihood interval of the predicted angle at each ψ)."""
    pairs = np.vstack([fit.region, [[fit.f, fit.e]]])
    a = angles(np.asarray(psi_deg)[None, :], pairs[:, :1], pairs[:, 1:], model)[key]
    return a[-1], a.min(axis=0), a.max(axis=0)
