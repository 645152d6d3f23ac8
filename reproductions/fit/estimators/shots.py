"""Oblique ball–ball shots on the cloth: predict the post-slip rolling motion of both balls, fit (f_bb, e).

The shot. The cue ball rolls without slipping on the cloth (natural roll, §II n°7: the contact point on the cloth
is at rest: ω_x = −v_y/R, ω_y = v_x/R, no side spin) at speed v and strikes the object ball,
at rest, with cut angle φ: the angle between the cue ball's velocity and the line of centres (φ = 0 full ball).
The impact is §VI n°13 of Résal (two equal balls resting on the cloth, ball–ball friction f_bb, vertical
translation blocked by the cloth, cloth friction neglected during the impact as Coriolis does), solved by
``spheres.two_spheres(on_cloth=True)`` with Résal's energy-loss law (6) of §I, ε = ε′ = (1 − e)/(1 + e)
(``impact.eps_from_newton``). Law (6) gives the normal ratio e exactly wherever the friction keeps one
direction and the slip does not stop (full ball: the topspin's slip is vertical only); a cut turns the slip on
the cloth and moves the ratio off e by a term of order f² (0.93 to 0.93004 over cuts of 0–85° for e = 0.93,
f_bb = 0.06); a slip that stops during the impact (large f_bb) raises it (``ShotPrediction.normal_e`` reports it).
Then each ball slides on the cloth (§II n°7, ``cloth.slide``) until it
rolls: the slip keeps its direction, v(t) = v0 − f g û t, u(t) = u0 − (1 + k) f g û t, so the rolling velocity is
v0 − u0/(1 + k), independent of the cloth's friction and of g (they set only when and where rolling starts). The
post-slip velocities depend neither on M nor on R (spin enters as R ω, impulses as T/M): only on v, φ, f_bb, e, k.

Frames and signs. Lab frame: X along the cue ball's incoming velocity, Z up, Y = Z × X (to the left seen from
above). φ > 0 puts the line of centres at +φ from X (counter-clockwise seen from above): the object ball leaves
near +φ and the cue ball on the negative side. Directions are angles from X, counter-clockwise positive, in
(−π, π]; φ < 0 is the mirror image. The impact frame of spheres.py (Ox along the line of centres) is the lab frame
turned by φ about Z.

What determines f_bb. With natural roll the cue ball's contact point on the object ball slips at speed v whatever
φ: sideways (v sin φ, the "throw" component) and downwards (v cos φ, from the topspin). So friction acts at every
cut, full-ball hits included: the vertical friction impulse takes topspin from the cue ball and gives the object
ball backspin, which the slide on the cloth turns into a loss of speed. The per-shot information shares of
``BallBallFit`` say which shots carry the information on f_bb; a shot whose contact stops slipping during the
impact (``Regime.GRIP``, large f_bb) says nothing about f_bb beyond a lower bound.

Noise. Outcome speeds and directions are measured with different noises; v and φ are taken as exact. Speed
errors are relative by default (residual ln(predicted/measured), σ a fraction) or absolute (m/s); direction
errors absolute (rad). Without given σ, one σ per kind is estimated from the residuals, with the degrees of freedom
each kind uses (the leverages of its rows), by iterated reweighting; the final report takes the residuals scaled
by those σ with noise estimated from them (Student's t, m − 2 degrees of freedom). Any outcome may be missing (NaN:
not measured, e.g. a published table of speeds without directions): its residual row is masked out (it weighs
nothing and counts in no degree of freedom); the speeds alone determine (f_bb, e) (rank 2), and so do the
directions alone.

e's interval. e lies in [0, 1] and ball–ball impacts have e = 0.92–0.98, so its 95 % interval is the profile
likelihood's with that bound (``_profile_e``, with ``fit_many(profile=True)``): the e at which the fit, f
re-minimised, is worse by the cut, χ²₁'s 3.84 for a given σ, or, each kind's noise profiled out, a cut calibrated
on the t/F distributions of the kinds' own scale estimates (``_profile_cut``); not a Wald interval cut at 1.

Solver. The point is found by Levenberg–Marquardt run on many data sets at once (``fit_many``: one batched
prediction per iteration); the report is ``fitting.analyse`` at that point, the code ``least_squares_fit`` reports
with (the test checks the point and errors against ``least_squares_fit``), which is called itself where the rank is
short (it then moves to the canonical point of the family). Every loop has an iteration cap and a convergence test,
and a ``deadline`` bounds the whole in wall-clock time (``OverBudget``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, fields, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from ...errors import ComputationError, InputError
from ...lazy import lazy
from ...mechanics import cloth, impact, spheres
from .. import distributions as dist
from .lsq import FitResult, analyse, least_squares_fit

special = lazy("scipy.special", globals())

__all__ = ["QUANTITIES", "BallBallFit", "OverBudget", "ShotPrediction", "ShotResiduals", "WeightedRows", "ball_tilt",
           "fit_columns", "fit_many", "fit_shots", "predict_shots", "shot_residuals", "synthetic_shots",
           "weighted_rows", "wrap_angle"]

NAMES = ("f_bb", "e")
BOUNDS = ((0.0, 0.0), (1.0, 1.0))
SpeedNoise = Literal["relative", "absolute"]
REWEIGHT_RTOL = 1e-3  # the per-kind σ iteration stops when σ_speed/σ_dir moves less than this, relatively
REWEIGHT_MAXITER = 10
JAC_STEP = 1e-6  # finite-difference step in f_bb and e


@dataclass(frozen=True)
class ShotPrediction:
    """Predicted outcome of each shot (batch axis of v and φ). Lab frame (module docstring): speeds in m/s,
    directions in rad from the cue ball's incoming direction, counter-clockwise positive; vectors (X, Y, Z) on the
    last axis, velocities in m/s and spins in rad/s, immediately after the impact."""

    cue_speed: np.ndarray  # post-slip (rolling) speed of the cue ball
    cue_dir: np.ndarray
    obj_speed: np.ndarray  # post-slip (rolling) speed of the object ball
    obj_dir: np.ndarray
    cue_v1: np.ndarray  # right after the impact, before the slide on the cloth
    cue_w1: np.ndarray
    obj_v1: np.ndarray
    obj_w1: np.ndarray
    normal_e: np.ndarray  # normal restitution of the impact, (obj − cue)·x̂ / (v cos φ): e when f_bb = 0
    regime: np.ndarray  # spheres' Regime per shot: SLIDE (the contact slips throughout), GRIP (the slip stops)
    converged: np.ndarray  # the §VI normal-impulse fixed point converged


def _lab(vec: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Impact-frame vectors (x along the line of centres) to the lab frame: a turn by φ about Z."""
    c, s = np.cos(phi), np.sin(phi)
    x, y = vec[..., 0], vec[..., 1]
    return np.stack([c * x - s * y, s * x + c * y, vec[..., 2]], axis=-1)


def wrap_angle(a: np.ndarray) -> np.ndarray:
    """Angles to (−π, π]."""
    return np.pi - np.mod(np.pi - a, 2 * np.pi)


def predict_shots(v: ArrayLike, phi: ArrayLike, *, f_bb: ArrayLike, e: ArrayLike, R: ArrayLike, k: ArrayLike = 2.5,
                  M: ArrayLike = 0.17, Rp: ArrayLike | None = None, kp: ArrayLike | None = None,
                  Mp: ArrayLike | None = None, method: str = "exact") -> ShotPrediction:
    """Post-slip speeds and directions of both balls for cue-ball speeds v (m/s, natural roll) and cut angles φ
    (rad); f_bb, e and the balls broadcast with them. The cue ball: mass M, radius R, k = MR²/I; the object ball:
    Mp, Rp, kp, each the cue ball's when None (equal balls). §VI n°13 impact (``spheres.two_spheres``, ``method``
    its path), then §II n°7 slide to rolling (``cloth.slide``, each ball with its own R and k); the cloth's friction
    drops out of the result (module docstring). Only M/M′ and, where they differ, R/R′ matter.

    Departure from §VI where the radii differ: the line of centres of two balls resting on the cloth then tilts by
    asin((R − R′)/(R + R′)); §VI (and this prediction) takes it horizontal, the cloth holding both balls down
    (``ball_tilt`` gives the angle neglected)."""
    Rp, kp, Mp = (R if Rp is None else Rp), (k if kp is None else kp), (M if Mp is None else Mp)
    v, phi, f_bb, e, M, Mp, R, Rp, k, kp = np.broadcast_arrays(
        *(np.asarray(a, dtype=float) for a in (v, phi, f_bb, e, M, Mp, R, Rp, k, kp)))
    if np.any(v <= 0) or np.any(np.abs(phi) >= np.pi / 2):
        raise InputError("predict_shots", "needs v > 0 and |φ| < π/2 (the cue ball must approach the object ball)")
    vx, vy = v * np.cos(phi), -v * np.sin(phi)  # impact frame: the line of centres at +φ from the velocity
    zero = np.zeros_like(v)
    v0 = np.stack([vx, vy, zero], axis=-1)
    w0 = np.stack([-vy / R, vx / R, zero], axis=-1)  # natural roll: v_x − R ω_y = 0, v_y + R ω_x = 0 (§II eq. 1)
    rest = np.zeros_like(v0)
    eps = impact.eps_from_newton(e)
    imp = spheres.two_spheres(M, Mp, R, Rp, k, kp, v0, w0, rest, rest, f=f_bb, eps=eps, epsp=eps, on_cloth=True,
                              method=method)
    out = []
    for vel, spin, r, kk in ((imp.v1, imp.w1, R, k), (imp.v1p, imp.w1p, Rp, kp)):
        # f = g = 1: the rolling velocity does not depend on them
        roll = cloth.slide(vel[..., 0], vel[..., 1], spin[..., 0], spin[..., 1], R=r, k=kk, f=1.0, g=1.0)
        out.append((np.hypot(roll.vx_roll, roll.vy_roll), wrap_angle(phi + np.arctan2(roll.vy_roll, roll.vx_roll))))
    (cs, cd), (os_, od) = out
    normal_e = (imp.v1p[..., 0] - imp.v1[..., 0]) / vx
    return ShotPrediction(cs, cd, os_, od, _lab(imp.v1, phi), _lab(imp.w1, phi), _lab(imp.v1p, phi),
                          _lab(imp.w1p, phi), normal_e, imp.regime, imp.converged)


def ball_tilt(R: float, Rp: float) -> float:
    """The angle (rad) by which the line of centres of two balls resting on the cloth rises from the cue ball
    (radius R) to the object ball (R′): asin((R′ − R)/(R + R′)); 0 for equal balls, which §VI treats."""
    return math.asin((Rp - R) / (R + Rp))


@dataclass(frozen=True)
class ShotResiduals:
    """Predicted minus measured per shot: speeds in m/s, directions in rad (wrapped to (−π, π]); ``scaled`` is
    the (4, n) array the fit weighs (rows cue speed, cue direction, object speed, object direction), in units of
    σ when σ are given: relative speeds as ln(predicted/measured). NaN where the quantity was not measured."""

    cue_speed: np.ndarray
    cue_dir: np.ndarray
    obj_speed: np.ndarray
    obj_dir: np.ndarray
    scaled: np.ndarray


def _raw(pred: ShotPrediction, obs: np.ndarray, speed_noise: SpeedNoise) -> np.ndarray:
    """(4, n) residuals before division by σ: speeds relative (log) or absolute, directions wrapped (NaN where
    ``obs`` is NaN: not measured)."""
    p = np.stack([pred.cue_speed, pred.cue_dir, pred.obj_speed, pred.obj_dir])
    r = p - obs
    if speed_noise == "relative":
        r[[0, 2]] = np.log(p[[0, 2]] / obs[[0, 2]])
    r[[1, 3]] = wrap_angle(r[[1, 3]])
    return r


def shot_residuals(theta: tuple[float, float], v: ArrayLike, phi: ArrayLike, cue_speed: ArrayLike,
                   cue_dir: ArrayLike, obj_speed: ArrayLike, obj_dir: ArrayLike, *, R: float, k: float = 2.5,
                   M: float = 0.17, Rp: float | None = None, kp: float | None = None, Mp: float | None = None,
                   sigma_speed: float | None = None, sigma_dir: float | None = None,
                   speed_noise: SpeedNoise = "relative") -> ShotResiduals:
    """Per-shot prediction errors at θ = (f_bb, e), e.g. ``fit.point`` of ``fit_shots``; the balls as
    ``predict_shots`` takes them."""
    v, phi, obs = _columns(v, phi, cue_speed, cue_dir, obj_speed, obj_dir, speed_noise)
    pred = predict_shots(v, phi, f_bb=theta[0], e=theta[1], R=R, k=k, M=M, Rp=Rp, kp=kp, Mp=Mp)
    d = np.stack([pred.cue_speed, pred.cue_dir, pred.obj_speed, pred.obj_dir]) - obs
    d[[1, 3]] = wrap_angle(d[[1, 3]])
    scaled = _raw(pred, obs, speed_noise)
    if sigma_speed is not None or sigma_dir is not None:
        sig = [1.0 if s is None else s for s in (sigma_speed, sigma_dir)]
        scaled = scaled / np.array([sig[0], sig[1], sig[0], sig[1]])[:, None]
    return ShotResiduals(d[0], d[1], d[2], d[3], scaled)


def _columns(v: ArrayLike, phi: ArrayLike, cue_speed: ArrayLike, cue_dir: ArrayLike, obj_speed: ArrayLike,
             obj_dir: ArrayLike, speed_noise: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """v, φ and the (4, n) outcomes (cue speed, cue direction, object speed, object direction); an outcome may be
    NaN (not measured), v and φ may not, and every shot must measure something."""
    cols = [np.asarray(c, dtype=float).ravel() for c in (v, phi, cue_speed, cue_dir, obj_speed, obj_dir)]
    n = cols[0].size
    if any(c.size != n for c in cols):
        raise InputError("fit_shots", "v, phi and the four measured columns must have one value per shot")
    if not (np.all(np.isfinite(cols[0])) and np.all(np.isfinite(cols[1]))):
        raise InputError("fit_shots", "v and phi must be finite in every shot")
    obs = np.stack(cols[2:])
    if np.any(np.isinf(obs)):
        raise InputError("fit_shots", "a measured outcome must be finite (NaN: not measured)")
    none = np.flatnonzero(~np.isfinite(obs).any(axis=0))
    if none.size:
        raise InputError("fit_shots", f"shot {int(none[0])} has no measured outcome")
    if speed_noise not in ("relative", "absolute"):
        raise InputError("fit_shots", f"speed_noise must be 'relative' or 'absolute', got {speed_noise!r}")
    if speed_noise == "relative" and (np.any(cols[2] <= 0) or np.any(cols[4] <= 0)):
        raise InputError("fit_shots", "relative speed errors need measured speeds > 0")
    return cols[0], cols[1], obs


def _ball_arrays(balls: Mapping[str, ArrayLike], D: int) -> dict[str, np.ndarray]:
    """The balls of D data sets, each quantity one value per data set (the object ball's the cue ball's where
    None)."""
    same = {"Rp": "R", "kp": "k", "Mp": "M"}
    out = {}
    for key in ("R", "k", "M", "Rp", "kp", "Mp"):
        value = balls[key] if balls.get(key) is not None else balls[same[key]]
        out[key] = np.broadcast_to(np.asarray(value, dtype=float), (D,))
    return out


class OverBudget(ComputationError):
    """The fit ran past its wall-clock bound (``deadline``); whoever called says what was being fitted."""

    def __reduce__(self) -> tuple[type, tuple[str, str]]:
        return (OverBudget, (self.where, self.message))


def _stencil(x: np.ndarray) -> np.ndarray:
    """Per parameter value, the shift of the central-difference stencil: −1 or +1 where x ± h leaves [0, 1]."""
    return np.where(x + JAC_STEP > 1.0, -1.0, np.where(x - JAC_STEP < 0.0, 1.0, 0.0))


def _derivative(r0: np.ndarray, lo: np.ndarray, hi: np.ndarray, s: np.ndarray) -> np.ndarray:
    """d r/dx from r at x, x + (s − 1) h and x + (s + 1) h: central, or one-sided of second order at a bound."""
    c = s[:, None]
    central = (hi - lo) / (2 * JAC_STEP)
    fwd = (-3 * r0 + 4 * hi - lo) / (2 * JAC_STEP)  # s = +1: points x, x + 2h
    bwd = (3 * r0 - 4 * lo + hi) / (2 * JAC_STEP)  # s = −1: points x − 2h, x
    return np.where(c > 0, fwd, np.where(c < 0, bwd, central))


class _Shots:
    """D data sets of n shots each, evaluated together: one batched prediction gives, for every data set, the raw
    residuals at its θ and the finite-difference Jacobian there (``two_spheres`` costs about as much for a few
    scenes as for a few hundred). Per data set, the last evaluations are memoised for ``fitting.analyse``.
    Outcomes not measured (NaN) give residual rows of 0 (and Jacobian rows of 0): they weigh nothing.
    Past ``deadline`` (``time.monotonic``) every evaluation raises ``OverBudget``."""

    def __init__(self, v: np.ndarray, phi: np.ndarray, obs: np.ndarray, balls: Mapping[str, ArrayLike],
                 speed_noise: SpeedNoise, deadline: float | None = None) -> None:
        self.v, self.phi, self.obs, self.noise = v, phi, obs, speed_noise
        self.D, self.n = v.shape
        self.balls = _ball_arrays(balls, self.D)
        self.mask = np.isfinite(obs).reshape(self.D, 4 * self.n)  # rows: cue speed, cue dir, obj speed, obj dir
        self.deadline = deadline
        self.memo: list[dict[bytes, tuple[np.ndarray, np.ndarray, np.ndarray]]] = [{} for _ in range(self.D)]

    def eval(self, theta: np.ndarray, idx: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Raw residuals (len(idx), 4n), Jacobian (len(idx), 4n, 2) and regimes (len(idx), n) of the data sets
        ``idx`` at their θ (len(idx), 2)."""
        theta = np.asarray(theta, dtype=float).reshape(-1, 2)
        need = [i for i, d in enumerate(idx) if theta[i].tobytes() not in self.memo[d]]
        if need:
            self._compute(theta[need], np.asarray(idx)[need])
        got = [self.memo[d][theta[i].tobytes()] for i, d in enumerate(idx)]
        return tuple(np.array([g[j] for g in got]) for j in range(3))  # type: ignore[return-value]

    def points(self, P: np.ndarray, idx: np.ndarray) -> tuple[np.ndarray, ShotPrediction]:
        """Raw residuals (m, K, 4n), 0 where not measured, of data sets ``idx`` (m) at K points each, P (m, K, 2)."""
        if self.deadline is not None and time.monotonic() > self.deadline:
            raise OverBudget("fit_shots", "over its time bound")
        m, K, n = len(idx), P.shape[1], self.n
        shape = (m, K, n)
        pred = predict_shots(np.broadcast_to(self.v[idx][:, None], shape), np.broadcast_to(self.phi[idx][:, None],
                             shape), f_bb=np.broadcast_to(P[..., 0:1], shape), e=np.broadcast_to(P[..., 1:2], shape),
                             **{b: a[idx][:, None, None] for b, a in self.balls.items()})
        obs = np.broadcast_to(self.obs[idx][:, None], (m, K, 4, n)).transpose(2, 0, 1, 3)  # (4, m, K, n)
        r = _raw(pred, obs, self.noise).transpose(1, 2, 0, 3).reshape(m, K, 4 * n)
        return np.where(self.mask[idx][:, None, :], r, 0.0), pred

    def _compute(self, theta: np.ndarray, idx: np.ndarray) -> None:
        m, n = len(idx), self.n
        # central differences, the stencil shifted inside [0, 1] at a bound: points θ + (s ∓ 1) h e_j
        s = _stencil(theta)  # (m, 2)
        pts = [theta]
        for j in range(2):
            for d in (-1.0, 1.0):
                p = theta.copy()
                p[:, j] += (s[:, j] + d) * JAC_STEP
                pts.append(p)
        r, pred = self.points(np.stack(pts, axis=1), idx)  # (m, 5, 4n)
        J = np.empty((m, 4 * n, 2))
        for j in range(2):
            J[:, :, j] = _derivative(r[:, 0], r[:, 1 + 2 * j], r[:, 2 + 2 * j], s[:, j])
        for i, d in enumerate(idx):
            if len(self.memo[d]) > 32:
                self.memo[d].clear()
            self.memo[d][theta[i].tobytes()] = (r[i, 0], J[i], pred.regime[i, 0].copy())

    def along_f(self, f: np.ndarray, e: np.ndarray, idx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Raw residuals (m, 4n) of data sets ``idx`` at (f, e) and their derivative in f (e held)."""
        s = _stencil(f)
        F = np.stack([f, f + (s - 1) * JAC_STEP, f + (s + 1) * JAC_STEP], axis=1)
        r, _ = self.points(np.stack([F, np.broadcast_to(e[:, None], F.shape)], axis=-1), idx)
        return r[:, 0], _derivative(r[:, 0], r[:, 1], r[:, 2], s)

    def functions(self, d: int, w: np.ndarray | None = None) -> tuple[Callable[[np.ndarray], np.ndarray],
                                                                      Callable[[np.ndarray], np.ndarray]]:
        """Residuals and Jacobian of data set d (times the weights w, if given), its measured rows only, for
        ``fitting``."""
        scale = np.ones(4 * self.n) if w is None else w
        keep = self.mask[d]

        def res(theta: np.ndarray) -> np.ndarray:
            return (self.eval(theta, np.array([d]))[0][0] * scale)[keep]

        def jac(theta: np.ndarray) -> np.ndarray:
            return (self.eval(theta, np.array([d]))[1][0] * scale[:, None])[keep]

        return res, jac


LM_MAXITER = 100
LM_XTOL = 1e-9  # the iteration stops when a proposed step moves θ less than this,
LM_FTOL = 1e-12  # or an accepted one lowers the cost by less than this fraction (the predictions' rounding, ~1e-13
# relative, makes the cost rough below that: steps of 1e-9 there are a walk in its noise)


def _solve(shots: _Shots, x0: np.ndarray, w: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """Minimise Σ (w r)² over θ ∈ [0, 1]² for the data sets ``idx`` together: Levenberg–Marquardt with the step
    projected on the box, one batched prediction per iteration (the trial points of all data sets at once); at
    most ``LM_MAXITER`` iterations, each testing convergence."""
    x = np.array(x0, dtype=float)
    r, J, _ = shots.eval(x, idx)
    r, J = r * w, J * w[..., None]
    cost = np.sum(r**2, axis=1)
    lam = np.full(len(idx), 1e-3)
    live = np.ones(len(idx), dtype=bool)
    for _ in range(LM_MAXITER):
        if not live.any():
            break
        L = np.nonzero(live)[0]
        A = np.einsum("dmi,dmj->dij", J[L], J[L])
        g = np.einsum("dmi,dm->di", J[L], r[L])
        diag = np.einsum("dii->di", A)
        Ad = A + (lam[L, None] * diag + 1e-15 * diag.sum(axis=1, keepdims=True) + 1e-300)[..., None] * np.eye(2)
        xt = np.clip(x[L] - np.linalg.solve(Ad, g[..., None])[..., 0], 0.0, 1.0)
        step = np.max(np.abs(xt - x[L]), axis=1)
        rt, Jt, _ = shots.eval(xt, idx[L])
        rt, Jt = rt * w[L], Jt * w[L][..., None]
        ct = np.sum(rt**2, axis=1)
        ok = ct <= cost[L]
        flat = ok & (cost[L] - ct <= LM_FTOL * cost[L])
        A_ = L[ok]
        x[A_], r[A_], J[A_], cost[A_] = xt[ok], rt[ok], Jt[ok], ct[ok]
        lam[L] = np.where(ok, np.maximum(lam[L] / 10, 1e-12), lam[L] * 10)
        live[L] = (step > LM_XTOL) & ~flat & (lam[L] < 1e6)
    return x


def _shares(Jw: np.ndarray, n: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Per-shot shares of the profiled information on each parameter: the column of one parameter minus its
    regression on the other, squared and summed over each shot's four rows (they add up to the profiled
    information exactly)."""
    out = []
    for j in range(2):
        a, b = Jw[:, j], Jw[:, 1 - j]
        bb = float(b @ b)
        resid = a - (float(a @ b) / bb) * b if bb > 0 else a
        per = (resid**2).reshape(4, n).sum(axis=0)
        tot = float(per.sum())
        out.append(tuple(float(x) for x in (per / tot if tot > 0 else np.full(n, math.nan))))
    return out[0], out[1]


KIND_ROWS = ([0, 2], [1, 3])  # the residual rows of each kind of measurement: speeds, directions


def _kind_counts(mask: np.ndarray, n: int) -> np.ndarray:
    """(D, 2) number of measured values per kind (speeds, directions) from the (D, 4n) mask."""
    mk = mask.reshape(-1, 4, n)
    return np.stack([mk[:, rows].sum(axis=(1, 2)) for rows in KIND_ROWS], axis=1)


def _kind_sigmas(r: np.ndarray, Jw: np.ndarray, mask: np.ndarray, n: int, floor: np.ndarray) -> np.ndarray:
    """One σ per kind (speeds: rows 0 and 2; directions: 1 and 3) from raw residuals r (D, 4n), each over its
    degrees of freedom: its measured rows minus the sum of their leverages (the hat matrix of the weighted J,
    (D, 4n, 2)). A kind not measured gets 1 (it weighs nothing). Returns (D, 2)."""
    Q, _ = np.linalg.qr(Jw)
    lev = (Q**2).sum(axis=2).reshape(-1, 4, n)
    rr = (r**2).reshape(-1, 4, n)
    counts = _kind_counts(mask, n)
    out = []
    for j, rows in enumerate(KIND_ROWS):
        dof = np.maximum(counts[:, j] - lev[:, rows].sum(axis=(1, 2)), 1e-12)
        sig = np.maximum(np.sqrt(rr[:, rows].sum(axis=(1, 2)) / dof), floor[:, j])
        out.append(np.where(counts[:, j] > 0, sig, 1.0))
    return np.stack(out, axis=1)


def _row_sigma(sig: np.ndarray, n: int) -> np.ndarray:
    """(D, 2) σ per kind to (D, 4n) per residual row (rows: cue speed, cue dir, obj speed, obj dir)."""
    return np.repeat(sig[:, [0, 1, 0, 1]], n, axis=1)


@dataclass(frozen=True)
class BallBallFit(FitResult):
    """``FitResult`` of (f_bb, e) with what the shots add. ``sigma_speed``/``sigma_dir``: the σ used (given, or
    estimated: a fraction for relative speed errors, else m/s; rad; NaN for a kind not measured).
    ``f_bb_share``/``e_share``: each shot's share of the information on that parameter with the other profiled
    out (Σ = 1; a shot with a share near 0 does not determine it). ``regime``: per shot at the estimate,
    ``Regime.SLIDE`` (1) or ``GRIP`` (2: the contact stops slipping during the impact, that shot does not see
    f_bb). ``n_speed``/``n_dir``: the values measured of each kind; ``rss_speed``/``rss_dir``: their raw residual
    sums of squares at the point (log ratios; rad²); ``chi2``: Σ (residual/σ)² with the σ used.
    ``e_profile``: the 95 % interval of e from the profile likelihood (``profile_e``), when asked for."""

    sigma_speed: float = math.nan
    sigma_dir: float = math.nan
    speed_noise: str = "relative"
    reweight_iterations: int = 0
    reweight_converged: bool = True
    f_bb_share: tuple[float, ...] = ()
    e_share: tuple[float, ...] = ()
    regime: tuple[int, ...] = ()
    n_speed: int = 0
    n_dir: int = 0
    rss_speed: float = math.nan
    rss_dir: float = math.nan
    chi2: float = math.nan
    e_profile: tuple[float, float] | None = None

    def misfit(self) -> float:
        """−2 log-likelihood with each kind's noise estimated, Σ_k n_k ln(RSS_k/n_k) (constants dropped): it
        compares fits of different readings of the same data (the same number of values of each kind)."""
        out = 0.0
        for nk, rss in ((self.n_speed, self.rss_speed), (self.n_dir, self.rss_dir)):
            if nk:
                out += nk * math.log(max(rss, nk * RSS_FLOOR) / nk)
        return out


RSS_FLOOR = 1e-24  # per value: the rounding of the predictions (~1e-12 relative), squared; keeps ln finite


def fit_shots(v: ArrayLike, phi: ArrayLike, cue_speed: ArrayLike, cue_dir: ArrayLike, obj_speed: ArrayLike,
              obj_dir: ArrayLike, *, R: float, k: float = 2.5, M: float = 0.17, sigma_speed: float | None = None,
              sigma_dir: float | None = None, speed_noise: SpeedNoise = "relative",
              x0: tuple[float, float] = (0.05, 0.9), **kw: Any) -> BallBallFit:
    """Fit (f_bb, e) in [0, 1]² to measured post-slip speeds (m/s) and directions (rad, lab convention of the
    module docstring) of both balls; the report (uncertainties, identifiability) is ``fitting``'s. NaN in an
    outcome: not measured (masked out of the residuals).

    ``sigma_speed`` (a fraction of the speed for ``speed_noise="relative"``, m/s for "absolute") and ``sigma_dir``
    (rad) given (each kind measured needs its σ): residuals over σ, normal 95 % intervals. Both omitted: σ per
    kind estimated from the residuals (leverage-corrected), refitting with those weights until their ratio
    settles; the report then estimates the common scale from the weighted residuals (Student's t, m − 2 degrees
    of freedom). ``kw``: those of ``fit_many`` (``Rp``, ``kp``, ``Mp``, ``profile``, ``deadline``,
    ``canonical``)."""
    cols = {"v": v, "phi": phi, "cue_speed": cue_speed, "cue_dir": cue_dir, "obj_speed": obj_speed,
            "obj_dir": obj_dir}
    return fit_many([cols], R=R, k=k, M=M, sigma_speed=sigma_speed, sigma_dir=sigma_dir, speed_noise=speed_noise,
                    x0=x0, **kw)[0]


def _parse(datasets: Sequence[Mapping[str, ArrayLike]], speed_noise: SpeedNoise
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    parsed = [_columns(d["v"], d["phi"], d["cue_speed"], d["cue_dir"], d["obj_speed"], d["obj_dir"], speed_noise)
              for d in datasets]
    if len({p[0].size for p in parsed}) != 1 or parsed[0][0].size == 0:
        raise InputError("fit_shots", "the data sets must have the same number of shots, at least one")
    return tuple(np.stack([p[j] for p in parsed]) for j in range(3))  # type: ignore[return-value]


def _given_sigmas(sigma_speed: float | None, sigma_dir: float | None, counts: np.ndarray) -> np.ndarray | None:
    """The given σ as (speed, direction), 1 standing in for a kind not measured; None when none is given."""
    if sigma_speed is None and sigma_dir is None:
        return None
    out = []
    for name, sig, measured in (("sigma_speed", sigma_speed, counts[:, 0].any()),
                                ("sigma_dir", sigma_dir, counts[:, 1].any())):
        if sig is None and measured:
            raise InputError("fit_shots", "give sigma_speed and sigma_dir for every kind of value measured, or "
                                          "neither (then both are estimated)")
        if sig is not None and not (math.isfinite(sig) and sig > 0):
            raise InputError("fit_shots", f"{name} must be > 0")
        out.append(1.0 if sig is None else float(sig))
    return np.array(out)


def fit_many(datasets: Sequence[Mapping[str, ArrayLike]], *, R: ArrayLike, k: ArrayLike = 2.5,
             M: ArrayLike = 0.17, Rp: ArrayLike | None = None, kp: ArrayLike | None = None, Mp: ArrayLike | None = None,
             sigma_speed: float | None = None, sigma_dir: float | None = None, speed_noise: SpeedNoise = "relative",
             x0: tuple[float, float] = (0.05, 0.9), profile: bool = False, canonical: bool = True,
             deadline: float | None = None) -> list[BallBallFit]:
    """``fit_shots`` on several data sets of equal size (columns as ``synthetic_shots`` returns), their predictions
    computed together: the same result as one ``fit_shots`` per data set, much faster for many. The balls as
    ``predict_shots`` takes them, each a number or one per data set (a scan over the mass ratio is one call).

    ``profile``: also e's profile-likelihood interval (``BallBallFit.e_profile``). ``canonical=False``: a
    rank-deficient fit is reported where the optimiser stopped, not moved to the canonical point of its family
    (a refit that keeps only full-rank points needs no more, and the move is slow). ``deadline``
    (``time.monotonic``): past it, ``OverBudget``."""
    if not datasets:
        return []
    v, phi, obs = _parse(datasets, speed_noise)
    shots = _Shots(v, phi, obs, {"R": R, "k": k, "M": M, "Rp": Rp, "kp": kp, "Mp": Mp}, speed_noise, deadline)
    D, n = v.shape
    counts = _kind_counts(shots.mask, n)
    given_sig = _given_sigmas(sigma_speed, sigma_dir, counts)
    idx = np.arange(D)
    x = np.tile(np.asarray(x0, dtype=float), (D, 1))
    its = np.zeros(D, dtype=int)
    conv = np.ones(D, dtype=bool)
    if given_sig is not None:
        sig = np.tile(given_sig, (D, 1))
        x = _solve(shots, x, 1.0 / _row_sigma(sig, n), idx)
    else:
        # per-kind σ by iterated reweighting (only their ratio moves the estimate); the start is a guess
        scale = 1.0 if speed_noise == "relative" else np.nanmedian(obs[:, [0, 2]], axis=(1, 2))
        sig = np.stack([np.broadcast_to(0.02 * scale, (D,)), np.full(D, math.radians(0.5))], axis=1)
        floor = 1e-12 * np.stack([np.broadcast_to(scale, (D,)), np.ones(D)], axis=1)
        conv[:] = False
        live = idx.copy()
        for it in range(1, REWEIGHT_MAXITER + 1):
            w = 1.0 / _row_sigma(sig[live], n)
            x[live] = _solve(shots, x[live], w, live)
            r, J, _ = shots.eval(x[live], live)
            new = _kind_sigmas(r, J * w[..., None], shots.mask[live], n, floor[live])
            moved = np.abs((new[:, 0] / new[:, 1]) / (sig[live, 0] / sig[live, 1]) - 1.0)
            sig[live], its[live] = new, it
            done = moved <= REWEIGHT_RTOL
            conv[live[done]] = True
            live = live[~done]
            if live.size == 0:
                break
        x = _solve(shots, x, 1.0 / _row_sigma(sig, n), idx)  # the optimum for the final weights
    out = []
    for d in range(D):
        ws = 1.0 / _row_sigma(sig[d:d + 1], n)[0]
        keep = shots.mask[d]
        given = given_sig is not None
        res, jac = shots.functions(d, None if given else ws)
        s = ws[keep] if given else None  # given σ: fitting weighs; estimated: the residuals come scaled, s² from them
        fit = analyse(res, x[d], NAMES, BOUNDS, sigma=None if s is None else 1.0 / s, jac=jac)
        if fit.identifiability.rank < 2 and canonical:  # a family: least_squares_fit moves to its canonical point
            fit = least_squares_fit(res, x[d], NAMES, BOUNDS, sigma=None if s is None else 1.0 / s, jac=jac)
        xf = np.asarray(fit.point)
        rd, Jd, reg = shots.eval(xf[None], np.array([d]))
        f_share, e_share = _shares(Jd[0] * ws[:, None], n)
        rr = rd[0].reshape(4, n) ** 2
        base = {f.name: getattr(fit, f.name) for f in fields(FitResult)}
        reported = np.where(counts[d] > 0, sig[d], math.nan)
        out.append(BallBallFit(**base, sigma_speed=float(reported[0]), sigma_dir=float(reported[1]),
                               speed_noise=speed_noise, reweight_iterations=int(its[d]),
                               reweight_converged=bool(conv[d]), f_bb_share=f_share, e_share=e_share,
                               regime=tuple(int(g) for g in reg[0]), n_speed=int(counts[d, 0]),
                               n_dir=int(counts[d, 1]), rss_speed=float(rr[KIND_ROWS[0]].sum()),
                               rss_dir=float(rr[KIND_ROWS[1]].sum()), chi2=float(np.sum((rd[0] * ws) ** 2))))
    if profile:
        ok = np.array([f.identifiability.rank == 2 for f in out])
        if ok.any():
            ci = _profile_e(shots, np.array([f.point for f in out])[ok], sig[ok], np.flatnonzero(ok),
                            given_sig is not None, [out[d] for d in np.flatnonzero(ok)])
            for j, d in enumerate(np.flatnonzero(ok)):
                out[d] = replace(out[d], e_profile=(float(ci[j, 0]), float(ci[j, 1])))
    return out


# --------------------------------------------------------------------------------------------------------------
# e's interval from the profile likelihood, with the bound e ≤ 1

PROFILE_LEVEL = 0.95
PROFILE_XTOL = 1e-6  # the ends of e's interval are found to this (absolute; e's errors are ≥ 1e-3)
PROFILE_MAXITER = 60  # bound on the search for the ends (bracketing doublings, then regula falsi)
INNER_MAXITER = 40  # bound on the minimisation over f at a fixed e (Gauss–Newton with halving)
INNER_XTOL = 1e-9  # it stops when a step moves f less than this


CUT_NODES = 64  # per kind: the quantiles of its χ² over which the cut's probability is averaged (midpoint rule)
CUT_NEWTON = 30  # bound on the Newton steps of z²(c, X) (quadratic from a warm start: 3 or 4 do)
CUT_MAXITER = 40  # bound on the search for the cut c


def _profile_cut(n: np.ndarray, nu: np.ndarray, share: np.ndarray, given: bool) -> float:
    """The rise of χ² (σ given) or of −2 log L with each kind's noise profiled out that bounds the 95 % set.

    σ given: χ²₁'s 3.84. Noise estimated: moving e from ê raises each kind's residual sum of squares by its
    share s_k of the information on e (f profiled out) times σ_k² Z², Z standard normal, over RSS_k = σ_k² X_k,
    X_k ~ χ²(ν_k) (ν_k: its values less their leverages), so that the rise is Σ_k n_k ln(1 + s_k Z²/X_k). For one
    kind this is n ln(1 + F/ν), F ~ F(1, ν), exact for a linear model: the cut is n ln(1 + t²_ν/ν). For two, the
    cut is the 95 % quantile of that sum: P(rise ≤ c) = E_X[P(Z² ≤ z²(c, X))], averaged over ``CUT_NODES``
    quantiles of each X_k, and solved for c by regula falsi."""
    if given:
        return float(dist.chi2_ppf(PROFILE_LEVEL, 1))
    use = (n > 0) & (share > 1e-12)
    nk, nuk, sk = n[use].astype(float), np.maximum(nu[use], 1.0), share[use] / share[use].sum()
    if nk.size == 1:
        t = float(dist.t_ppf(0.5 + PROFILE_LEVEL / 2, nuk[0]))
        return float(nk[0] * math.log1p(t * t / nuk[0]))
    q = (np.arange(CUT_NODES) + 0.5) / CUT_NODES
    X = np.stack(np.meshgrid(*(dist.chi2_ppf(q, v) for v in nuk), indexing="ij"), axis=-1).reshape(-1, nk.size)
    a = sk / X  # (nodes, K): the rise is Σ n_k ln(1 + a_k z²)
    z = np.zeros(X.shape[0])

    def excess(c: float) -> float:
        """P(rise ≤ c) − 0.95; z²(c, X) by Newton from the last root (the rise is increasing and concave in z²)."""
        nonlocal z
        z = np.maximum(z, c / (a @ nk)) if not z.any() else z
        for _ in range(CUT_NEWTON):
            g = np.log1p(a * z[:, None]) @ nk - c
            dz = g / ((a / (1 + a * z[:, None])) @ nk)
            z = np.maximum(z - dz, 0.0)
            if np.max(np.abs(dz)) <= 1e-10 * max(c, 1.0):
                break
        return float(np.mean(special.erf(np.sqrt(z / 2)))) - PROFILE_LEVEL  # the χ²₁ distribution function

    # regula falsi (Illinois) on c: the single-kind cuts bracket it (the rise of one kind is the extreme)
    lo = float(dist.chi2_ppf(PROFILE_LEVEL, 1))
    hi = 4.0 * lo
    glo, ghi = excess(lo), excess(hi)
    side = 0
    for _ in range(CUT_MAXITER):
        c = hi - ghi * (hi - lo) / (ghi - glo)
        gc = excess(c)
        if abs(gc) < 1e-7 or hi - lo < 1e-7:
            return c
        if gc < 0:
            lo, glo = c, gc
            ghi = ghi / 2 if side == -1 else ghi
            side = -1
        else:
            hi, ghi = c, gc
            glo = glo / 2 if side == 1 else glo
            side = 1
    return c


def _objective(r: np.ndarray, w2: np.ndarray, counts: np.ndarray, n: int, given: bool) -> np.ndarray:
    """χ² = Σ w² r² (σ given), or Σ_k n_k ln RSS_k (noise per kind profiled out), per row of r (m, 4n)."""
    if given:
        return np.sum(w2 * r * r, axis=1)
    rr = (r * r).reshape(-1, 4, n)
    out = np.zeros(r.shape[0])
    for j, rows in enumerate(KIND_ROWS):
        nk = counts[:, j]
        out += np.where(nk > 0, nk * np.log(np.maximum(rr[:, rows].sum(axis=(1, 2)), np.maximum(nk, 1) * RSS_FLOOR)),
                        0.0)
    return out


def _min_over_f(shots: _Shots, f0: np.ndarray, e: np.ndarray, idx: np.ndarray, w2: np.ndarray, counts: np.ndarray,
                given: bool) -> tuple[np.ndarray, np.ndarray]:
    """min over f ∈ [0, 1] of the objective at fixed e, for each (data set idx[i], e[i]) together: Gauss–Newton
    steps (per-kind weights n_k/RSS_k when the noise is profiled), halved until the objective does not rise; at
    most ``INNER_MAXITER`` evaluations. Returns (f, objective)."""
    n = shots.n
    f = np.clip(np.asarray(f0, dtype=float), 0.0, 1.0)
    r, J = shots.along_f(f, e, idx)
    obj = _objective(r, w2, counts, n, given)
    step = np.zeros_like(f)
    trial = np.ones(f.size, dtype=bool)  # a new Gauss–Newton step is due
    live = np.ones(f.size, dtype=bool)
    for _ in range(INNER_MAXITER):
        if trial.any():
            T = np.flatnonzero(trial & live)
            if given:
                ww = w2[T]
            else:
                rss = (r[T] ** 2).reshape(-1, 4, n)
                ww = np.zeros((T.size, 4, n))
                for j, rows in enumerate(KIND_ROWS):
                    nk = counts[T, j]
                    val = nk / np.maximum(rss[:, rows].sum(axis=(1, 2)), np.maximum(nk, 1) * RSS_FLOOR)
                    ww[:, rows] = val[:, None, None]
                ww = ww.reshape(T.size, 4 * n)
            g = np.sum(ww * J[T] * r[T], axis=1)
            H = np.sum(ww * J[T] ** 2, axis=1)
            step[T] = np.where(H > 0, -g / np.where(H > 0, H, 1.0), 0.0)
            trial[:] = False
        L = np.flatnonzero(live)
        ft = np.clip(f[L] + step[L], 0.0, 1.0)
        moved = np.abs(ft - f[L])
        done = moved <= INNER_XTOL
        live[L[done]] = False
        L, ft = L[~done], ft[~done]
        if L.size == 0:
            break
        rt, Jt = shots.along_f(ft, e[L], idx[L])
        ot = _objective(rt, w2[L], counts[L], n, given)
        ok = ot <= obj[L]
        A = L[ok]
        f[A], r[A], J[A], obj[A] = ft[ok], rt[ok], Jt[ok], ot[ok]
        trial[A] = True
        step[L[~ok]] *= 0.5
    return f, obj


def _profile_e(shots: _Shots, x: np.ndarray, sig: np.ndarray, idx: np.ndarray, given: bool,
               fits: Sequence[FitResult]) -> np.ndarray:
    """The 95 % interval of e, (m, 2), for data sets ``idx`` with optima x (m, 2): {e ∈ [0, 1] : profile rise ≤
    the cut} (``_profile_cut``), f minimised at each e within [0, 1]. Each end is bracketed from the Wald guess
    outward (doubling) and then found by regula falsi (Illinois) on √rise − √cut, nearly linear in e; an end
    whose bound lies inside the set is the bound. All ends of all data sets advance together."""
    m, n = len(idx), shots.n
    counts = _kind_counts(shots.mask[idx], n)
    w2 = np.where(shots.mask[idx], 1.0 / _row_sigma(sig, n) ** 2, 0.0)
    f_hat, e_hat = x[:, 0].copy(), x[:, 1].copy()
    se = np.array([fit.estimate("e").stderr or 0.0 for fit in fits])
    # the valley of the objective: f − f̂ = −(A_fe/A_ff)(e − ê), A = Jᵀ W J at the optimum (the start of f at e)
    _, Jx, _ = shots.eval(x, idx)
    Jw = Jx * np.sqrt(w2)[..., None]
    A = np.einsum("dmi,dmj->dij", Jw, Jw)
    slope = np.where(A[:, 0, 0] > 0, -A[:, 0, 1] / np.where(A[:, 0, 0] > 0, A[:, 0, 0], 1.0), 0.0)
    # per kind: the information on e with f profiled out, and the degrees of freedom of its noise estimate
    a_e = ((Jw[..., 1] + slope[:, None] * Jw[..., 0]) ** 2).reshape(m, 4, n)
    lev = (np.linalg.qr(Jw)[0] ** 2).sum(axis=2).reshape(m, 4, n)
    info = np.stack([a_e[:, rows].sum(axis=(1, 2)) for rows in KIND_ROWS], axis=1)
    share = info / np.maximum(info.sum(axis=1, keepdims=True), np.finfo(float).tiny)
    nu = counts - np.stack([lev[:, rows].sum(axis=(1, 2)) for rows in KIND_ROWS], axis=1)
    cut = np.array([_profile_cut(counts[i], nu[i], share[i], given) for i in range(m)])
    # the reference: the minimum of the profile at ê (≤ the objective at the fit's point)
    _, obj0 = _min_over_f(shots, f_hat, e_hat, idx, w2, counts, given)
    # jobs: (data set i, side ±1); state: inside point a (rise < cut), outside point b (rise ≥ cut) once found
    side = np.tile([-1.0, 1.0], m)
    job = np.repeat(np.arange(m), 2)
    bound = np.where(side > 0, 1.0, 0.0)
    a = e_hat[job].copy()
    ha = -np.sqrt(cut[job])
    b = np.full(job.size, np.nan)
    hb = np.full(job.size, np.nan)
    end = np.full(job.size, np.nan)
    last = np.zeros(job.size, dtype=int)  # Illinois: which end was kept twice in a row
    width = np.maximum(2.0 * se[job], 1e-3)
    cand = np.clip(a + side * width, 0.0, 1.0)
    at_bound = np.abs(e_hat[job] - bound) <= 1e-12
    end[at_bound] = bound[at_bound]
    live = ~at_bound
    for _ in range(PROFILE_MAXITER):
        L = np.flatnonzero(live)
        if L.size == 0:
            break
        i = job[L]
        _, oL = _min_over_f(shots, f_hat[i] + slope[i] * (cand[L] - e_hat[i]), cand[L], idx[i], w2[i], counts[i],
                             given)
        h = np.sqrt(np.maximum(oL - obj0[i], 0.0)) - np.sqrt(cut[i])
        for q, jb in enumerate(L):
            c, hc = cand[jb], h[q]
            if np.isnan(b[jb]):  # still bracketing
                if hc < 0:
                    if abs(c - bound[jb]) <= 1e-12:
                        end[jb], live[jb] = bound[jb], False
                        continue
                    a[jb], ha[jb] = c, hc
                    width[jb] *= 2.0
                    cand[jb] = float(np.clip(e_hat[job[jb]] + side[jb] * width[jb], 0.0, 1.0))
                    continue
                b[jb], hb[jb] = c, hc
            elif hc < 0:
                a[jb], ha[jb] = c, hc
                hb[jb] = hb[jb] / 2 if last[jb] == -1 else hb[jb]
                last[jb] = -1
            else:
                b[jb], hb[jb] = c, hc
                ha[jb] = ha[jb] / 2 if last[jb] == 1 else ha[jb]
                last[jb] = 1
            if abs(b[jb] - a[jb]) <= PROFILE_XTOL or abs(hc) <= 1e-9:
                end[jb], live[jb] = (c if abs(hc) <= 1e-9 else 0.5 * (a[jb] + b[jb])), False
                continue
            cand[jb] = a[jb] - ha[jb] * (b[jb] - a[jb]) / (hb[jb] - ha[jb])
    end[live] = np.where(np.isnan(b[live]), a[live], 0.5 * (a[live] + np.nan_to_num(b[live])))  # not converged
    return end.reshape(m, 2)



QUANTITIES = ("cue_speed", "cue_dir", "obj_speed", "obj_dir")  # the residual rows' order, per kind of outcome


@dataclass(frozen=True)
class WeightedRows:
    """The measured values of one data set at θ, one row each (the weighted problem the fit solved):
    ``quantity`` (index into ``QUANTITIES``), ``shot``, ``r`` the residual over its σ (ln(predicted/measured)/σ
    for relative speed errors), ``J`` its Jacobian in (f_bb, e), ``sigma``, ``measured`` and ``predicted``
    (m/s; rad)."""

    quantity: np.ndarray
    shot: np.ndarray
    r: np.ndarray
    J: np.ndarray
    sigma: np.ndarray
    measured: np.ndarray
    predicted: np.ndarray
    speed_noise: str = "relative"

    def value(self, z: np.ndarray) -> np.ndarray:
        """The prediction whose weighted residual against each row's measured value is z: measured × exp(σ z)
        for relative speeds, measured + σ z otherwise (e.g. a leave-one-out prediction from its deleted
        residual)."""
        rel = (self.speed_noise == "relative") & np.isin(self.quantity, (0, 2))
        return np.where(rel, self.measured * np.exp(self.sigma * z), self.measured + self.sigma * z)


def weighted_rows(cols: Mapping[str, ArrayLike], theta: Sequence[float], *, sigma_speed: float, sigma_dir: float,
                  R: float, k: float = 2.5, M: float = 0.17, Rp: float | None = None, kp: float | None = None,
                  Mp: float | None = None, speed_noise: SpeedNoise = "relative") -> WeightedRows:
    """``WeightedRows`` of the data set ``cols`` (NaN: not measured) at θ = (f_bb, e) with these σ (a kind not
    measured may have any); the balls as ``predict_shots`` takes them."""
    v, phi, obs = _parse([cols], speed_noise)
    balls = {"R": R, "k": k, "M": M, "Rp": Rp, "kp": kp, "Mp": Mp}
    shots = _Shots(v, phi, obs, balls, speed_noise)
    n = shots.n
    r, J, _ = shots.eval(np.asarray(theta, dtype=float)[None], np.array([0]))
    keep = shots.mask[0]
    sig = _row_sigma(np.array([[sigma_speed, sigma_dir]], dtype=float), n)[0]
    quantity, shot = np.divmod(np.arange(4 * n), n)
    pred = predict_shots(v[0], phi[0], f_bb=theta[0], e=theta[1], **balls)
    p = np.stack([pred.cue_speed, pred.cue_dir, pred.obj_speed, pred.obj_dir]).reshape(-1)
    return WeightedRows(quantity[keep], shot[keep], (r[0] / sig)[keep], (J[0] / sig[:, None])[keep], sig[keep],
                        obs[0].reshape(-1)[keep], p[keep], speed_noise)


def synthetic_shots(rng: np.random.Generator, n: int, *, f_bb: float = 0.06, e: float = 0.93, R: float = 0.02855,
                    k: float = 2.5, M: float = 0.17, Rp: float | None = None, kp: float | None = None,
                    Mp: float | None = None, v_range: tuple[float, float] = (0.5, 3.0),
                    phi_range_deg: tuple[float, float] = (10.0, 60.0), sigma_speed: float = 0.02,
                    sigma_dir: float = math.radians(0.5), speed_noise: SpeedNoise = "relative"
                    ) -> dict[str, np.ndarray]:
    """n synthetic shots: v uniform in ``v_range`` (m/s), φ uniform in ``phi_range_deg`` (degrees, stored in rad),
    outcomes predicted at (f_bb, e) with noise: speeds × exp(σ z) (relative) or + σ z (absolute, m/s), directions
    + σ_dir z (rad); the balls as ``predict_shots`` takes them. Columns: v, phi, cue_speed, cue_dir, obj_speed,
    obj_dir (SI)."""
    v = rng.uniform(*v_range, n)
    phi = np.radians(rng.uniform(*phi_range_deg, n))
    p = predict_shots(v, phi, f_bb=f_bb, e=e, R=R, k=k, M=M, Rp=Rp, kp=kp, Mp=Mp)
    z = rng.standard_normal((4, n))
    if speed_noise == "relative":
        cs, os_ = p.cue_speed * np.exp(sigma_speed * z[0]), p.obj_speed * np.exp(sigma_speed * z[2])
    else:
        cs, os_ = p.cue_speed + sigma_speed * z[0], p.obj_speed + sigma_speed * z[2]
    return {"v": v, "phi": phi, "cue_speed": cs, "cue_dir": wrap_angle(p.cue_dir + sigma_dir * z[1]), "obj_speed": os_,
            "obj_dir": wrap_angle(p.obj_dir + sigma_dir * z[3])}


def fit_columns(cols: Mapping[str, np.ndarray], **kw: object) -> BallBallFit:
    """``fit_shots`` on a dict of columns as ``synthetic_shots`` returns (keyword arguments passed on)."""
    return fit_shots(cols["v"], cols["phi"], cols["cue_speed"], cols["cue_dir"], cols["obj_speed"], cols["obj_dir"],
                     **kw)  # type: ignore[arg-type]
