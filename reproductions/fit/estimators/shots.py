"""Oblique ball–ball shots on the cloth: predict the post-slip rolling motion of both balls, fit (f_bb, e).

The shot. The cue ball rolls without slipping on the cloth (natural roll, §II n°7: the contact point on the cloth
is at rest: ω_x = −v_y/R, ω_y = v_x/R, no side spin) at speed v and strikes the object ball,
at rest, with cut angle φ: the angle between the cue ball's velocity and the line of centres (φ = 0 full ball).
The impact is §VI n°13 of Résal (two equal balls resting on the cloth, ball–ball friction f_bb, vertical
translation blocked by the cloth, cloth friction neglected during the impact as Coriolis does), solved by
``spheres.two_spheres(on_cloth=True)`` with Résal's energy-loss law (6) of §I, ε = ε′ = (1 − e)/(1 + e)
(``impact.eps_from_newton``). Without friction this gives Newton's normal restitution e exactly; with friction the
normal impulse follows law (6) with the friction work, and the normal restitution is below e (0.923–0.928 for
e = 0.93, f_bb = 0.06; ``ShotPrediction.normal_e`` reports it): e is the paper's coefficient, not a measured ratio.
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
by those σ with noise estimated from them (Student's t, m − 2 degrees of freedom).

Solver. The point is found by Levenberg–Marquardt run on many data sets at once (``fit_many``: one batched
prediction per iteration); the report is ``fitting.analyse`` at that point, the code ``least_squares_fit`` reports
with (the test checks the point and errors against ``least_squares_fit``), which is called itself where the rank is
short (it then moves to the canonical point of the family).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from ...errors import InputError
from ...mechanics import cloth, impact, spheres
from .lsq import FitResult, analyse, least_squares_fit

__all__ = ["BallBallFit", "ShotPrediction", "ShotResiduals", "fit_columns", "fit_many", "fit_shots", "predict_shots",
           "shot_residuals", "synthetic_shots"]

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


def _wrap(a: np.ndarray) -> np.ndarray:
    """Angles to (−π, π]."""
    return np.pi - np.mod(np.pi - a, 2 * np.pi)


def predict_shots(v: ArrayLike, phi: ArrayLike, *, f_bb: ArrayLike, e: ArrayLike, R: float, k: float = 2.5,
                  M: float = 0.17, method: str = "exact") -> ShotPrediction:
    """Post-slip speeds and directions of both balls for cue-ball speeds v (m/s, natural roll) and cut angles φ
    (rad); f_bb and e broadcast with them. §VI n°13 impact (``spheres.two_spheres``, ``method`` its path), then
    §II n°7 slide to rolling (``cloth.slide``); the cloth's friction drops out of the result (module docstring)."""
    v, phi, f_bb, e = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (v, phi, f_bb, e)))
    if np.any(v <= 0) or np.any(np.abs(phi) >= np.pi / 2):
        raise InputError("predict_shots", "needs v > 0 and |φ| < π/2 (the cue ball must approach the object ball)")
    vx, vy = v * np.cos(phi), -v * np.sin(phi)  # impact frame: the line of centres at +φ from the velocity
    zero = np.zeros_like(v)
    v0 = np.stack([vx, vy, zero], axis=-1)
    w0 = np.stack([-vy / R, vx / R, zero], axis=-1)  # natural roll: v_x − R ω_y = 0, v_y + R ω_x = 0 (§II eq. 1)
    rest = np.zeros_like(v0)
    eps = impact.eps_from_newton(e)
    imp = spheres.two_spheres(M, M, R, R, k, k, v0, w0, rest, rest, f=f_bb, eps=eps, epsp=eps, on_cloth=True,
                              method=method)
    out = []
    for vel, spin in ((imp.v1, imp.w1), (imp.v1p, imp.w1p)):
        # f = g = 1: the rolling velocity does not depend on them
        roll = cloth.slide(vel[..., 0], vel[..., 1], spin[..., 0], spin[..., 1], R=R, k=k, f=1.0, g=1.0)
        out.append((np.hypot(roll.vx_roll, roll.vy_roll), _wrap(phi + np.arctan2(roll.vy_roll, roll.vx_roll))))
    (cs, cd), (os_, od) = out
    normal_e = (imp.v1p[..., 0] - imp.v1[..., 0]) / vx
    return ShotPrediction(cs, cd, os_, od, _lab(imp.v1, phi), _lab(imp.w1, phi), _lab(imp.v1p, phi),
                          _lab(imp.w1p, phi), normal_e, imp.regime, imp.converged)


@dataclass(frozen=True)
class ShotResiduals:
    """Predicted minus measured per shot: speeds in m/s, directions in rad (wrapped to (−π, π]); ``scaled`` is
    the (4, n) array the fit weighs (rows cue speed, cue direction, object speed, object direction), in units of
    σ when σ are given: relative speeds as ln(predicted/measured)."""

    cue_speed: np.ndarray
    cue_dir: np.ndarray
    obj_speed: np.ndarray
    obj_dir: np.ndarray
    scaled: np.ndarray


def _raw(pred: ShotPrediction, obs: np.ndarray, speed_noise: SpeedNoise) -> np.ndarray:
    """(4, n) residuals before division by σ: speeds relative (log) or absolute, directions wrapped."""
    p = np.stack([pred.cue_speed, pred.cue_dir, pred.obj_speed, pred.obj_dir])
    r = p - obs
    if speed_noise == "relative":
        r[[0, 2]] = np.log(p[[0, 2]] / obs[[0, 2]])
    r[[1, 3]] = _wrap(r[[1, 3]])
    return r


def shot_residuals(theta: tuple[float, float], v: ArrayLike, phi: ArrayLike, cue_speed: ArrayLike,
                   cue_dir: ArrayLike, obj_speed: ArrayLike, obj_dir: ArrayLike, *, R: float, k: float = 2.5,
                   M: float = 0.17, sigma_speed: float | None = None, sigma_dir: float | None = None,
                   speed_noise: SpeedNoise = "relative") -> ShotResiduals:
    """Per-shot prediction errors at θ = (f_bb, e), e.g. ``fit.point`` of ``fit_shots``."""
    v, phi, obs = _columns(v, phi, cue_speed, cue_dir, obj_speed, obj_dir, speed_noise)
    pred = predict_shots(v, phi, f_bb=theta[0], e=theta[1], R=R, k=k, M=M)
    d = np.stack([pred.cue_speed, pred.cue_dir, pred.obj_speed, pred.obj_dir]) - obs
    d[[1, 3]] = _wrap(d[[1, 3]])
    scaled = _raw(pred, obs, speed_noise)
    if sigma_speed is not None and sigma_dir is not None:
        scaled = scaled / np.array([sigma_speed, sigma_dir, sigma_speed, sigma_dir])[:, None]
    return ShotResiduals(d[0], d[1], d[2], d[3], scaled)


def _columns(v: ArrayLike, phi: ArrayLike, cue_speed: ArrayLike, cue_dir: ArrayLike, obj_speed: ArrayLike,
             obj_dir: ArrayLike, speed_noise: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    cols = [np.asarray(c, dtype=float).ravel() for c in (v, phi, cue_speed, cue_dir, obj_speed, obj_dir)]
    n = cols[0].size
    if any(c.size != n for c in cols):
        raise InputError("fit_shots", "v, phi and the four measured columns must have one value per shot")
    if not all(np.all(np.isfinite(c)) for c in cols):
        raise InputError("fit_shots", "every value must be finite")
    if speed_noise not in ("relative", "absolute"):
        raise InputError("fit_shots", f"speed_noise must be 'relative' or 'absolute', got {speed_noise!r}")
    if speed_noise == "relative" and (np.any(cols[2] <= 0) or np.any(cols[4] <= 0)):
        raise InputError("fit_shots", "relative speed errors need measured speeds > 0")
    return cols[0], cols[1], np.stack(cols[2:])


class _Shots:
    """D data sets of n shots each, evaluated together: one batched prediction gives, for every data set, the raw
    residuals at its θ and the finite-difference Jacobian there (``two_spheres`` costs about as much for a few
    scenes as for a few hundred). Per data set, the last evaluations are memoised for ``fitting.analyse``."""

    def __init__(self, v: np.ndarray, phi: np.ndarray, obs: np.ndarray, R: float, k: float, M: float,
                 speed_noise: SpeedNoise) -> None:
        self.v, self.phi, self.obs, self.R, self.k, self.M, self.noise = v, phi, obs, R, k, M, speed_noise
        self.D, self.n = v.shape
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

    def _compute(self, theta: np.ndarray, idx: np.ndarray) -> None:
        m, n = len(idx), self.n
        # central differences, the stencil shifted inside [0, 1] at a bound: points θ + (s ∓ 1) h e_j
        s = np.where(theta + JAC_STEP > 1.0, -1.0, np.where(theta - JAC_STEP < 0.0, 1.0, 0.0))  # (m, 2)
        pts = [theta]
        for j in range(2):
            for d in (-1.0, 1.0):
                p = theta.copy()
                p[:, j] += (s[:, j] + d) * JAC_STEP
                pts.append(p)
        P = np.stack(pts, axis=1)  # (m, 5, 2)
        shape = (m, 5, n)
        pred = predict_shots(np.broadcast_to(self.v[idx][:, None], shape), np.broadcast_to(self.phi[idx][:, None],
                             shape), f_bb=np.broadcast_to(P[..., 0:1], shape), e=np.broadcast_to(P[..., 1:2], shape),
                             R=self.R, k=self.k, M=self.M)
        obs = np.broadcast_to(self.obs[idx][:, None], (m, 5, 4, n)).transpose(2, 0, 1, 3)  # (4, m, 5, n)
        r = _raw(pred, obs, self.noise).transpose(1, 2, 0, 3).reshape(m, 5, 4 * n)
        J = np.empty((m, 4 * n, 2))
        for j in range(2):
            lo, hi = r[:, 1 + 2 * j], r[:, 2 + 2 * j]  # at θ + (s − 1) h and θ + (s + 1) h
            c = s[:, j][:, None]
            central = (hi - lo) / (2 * JAC_STEP)
            fwd = (-3 * r[:, 0] + 4 * hi - lo) / (2 * JAC_STEP)  # s = +1: points θ, θ + 2h
            bwd = (3 * r[:, 0] - 4 * lo + hi) / (2 * JAC_STEP)  # s = −1: points θ − 2h, θ
            J[:, :, j] = np.where(c > 0, fwd, np.where(c < 0, bwd, central))
        for i, d in enumerate(idx):
            if len(self.memo[d]) > 32:
                self.memo[d].clear()
            self.memo[d][theta[i].tobytes()] = (r[i, 0], J[i], pred.regime[i, 0].copy())

    def functions(self, d: int, w: np.ndarray | None = None) -> tuple[Callable[[np.ndarray], np.ndarray],
                                                                      Callable[[np.ndarray], np.ndarray]]:
        """Residuals and Jacobian of data set d (times the weights w, if given) for ``fitting``."""
        scale = np.ones(4 * self.n) if w is None else w

        def res(theta: np.ndarray) -> np.ndarray:
            return self.eval(theta, np.array([d]))[0][0] * scale

        def jac(theta: np.ndarray) -> np.ndarray:
            return self.eval(theta, np.array([d]))[1][0] * scale[:, None]

        return res, jac


LM_MAXITER = 100
LM_XTOL = 1e-9  # the iteration stops when a proposed step moves θ less than this,
LM_FTOL = 1e-12  # or an accepted one lowers the cost by less than this fraction (the predictions' rounding, ~1e-13
# relative, makes the cost rough below that: steps of 1e-9 there are a walk in its noise)


def _solve(shots: _Shots, x0: np.ndarray, w: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """Minimise Σ (w r)² over θ ∈ [0, 1]² for the data sets ``idx`` together: Levenberg–Marquardt with the step
    projected on the box, one batched prediction per iteration (the trial points of all data sets at once)."""
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


def _kind_sigmas(r: np.ndarray, Jw: np.ndarray, n: int, floor: float) -> np.ndarray:
    """One σ per kind (speeds: rows 0 and 2; directions: 1 and 3) from raw residuals r (D, 4n), each over its
    degrees of freedom: its 2n rows minus the sum of their leverages (the hat matrix of the weighted J, (D, 4n, 2)).
    Returns (D, 2)."""
    Q, _ = np.linalg.qr(Jw)
    lev = (Q**2).sum(axis=2).reshape(-1, 4, n)
    rr = (r**2).reshape(-1, 4, n)
    out = []
    for rows in ([0, 2], [1, 3]):
        dof = np.maximum(2 * n - lev[:, rows].sum(axis=(1, 2)), 1e-12)
        out.append(np.sqrt(rr[:, rows].sum(axis=(1, 2)) / dof))
    return np.maximum(np.stack(out, axis=1), floor)


def _row_sigma(sig: np.ndarray, n: int) -> np.ndarray:
    """(D, 2) σ per kind to (D, 4n) per residual row (rows: cue speed, cue dir, obj speed, obj dir)."""
    return np.repeat(sig[:, [0, 1, 0, 1]], n, axis=1)


@dataclass(frozen=True)
class BallBallFit(FitResult):
    """``FitResult`` of (f_bb, e) with what the shots add. ``sigma_speed``/``sigma_dir``: the σ used (given, or
    estimated: a fraction for relative speed errors, else m/s; rad). ``f_bb_share``/``e_share``: each shot's share
    of the information on that parameter with the other profiled out (Σ = 1; a shot with a share near 0 does not
    determine it). ``regime``: per shot at the estimate, ``Regime.SLIDE`` (1) or ``GRIP`` (2: the contact stops
    slipping during the impact, that shot does not see f_bb)."""

    sigma_speed: float = math.nan
    sigma_dir: float = math.nan
    speed_noise: str = "relative"
    reweight_iterations: int = 0
    reweight_converged: bool = True
    f_bb_share: tuple[float, ...] = ()
    e_share: tuple[float, ...] = ()
    regime: tuple[int, ...] = ()


def fit_shots(v: ArrayLike, phi: ArrayLike, cue_speed: ArrayLike, cue_dir: ArrayLike, obj_speed: ArrayLike,
              obj_dir: ArrayLike, *, R: float, k: float = 2.5, M: float = 0.17, sigma_speed: float | None = None,
              sigma_dir: float | None = None, speed_noise: SpeedNoise = "relative",
              x0: tuple[float, float] = (0.05, 0.9)) -> BallBallFit:
    """Fit (f_bb, e) in [0, 1]² to measured post-slip speeds (m/s) and directions (rad, lab convention of the
    module docstring) of both balls; the report (uncertainties, identifiability) is ``fitting``'s.

    ``sigma_speed`` (a fraction of the speed for ``speed_noise="relative"``, m/s for "absolute") and ``sigma_dir``
    (rad) given: residuals over σ, normal 95 % intervals. Both omitted: σ per kind estimated from the residuals
    (leverage-corrected), refitting with those weights until their ratio settles; the report then estimates the
    common scale from the weighted residuals (Student's t, m − 2 degrees of freedom)."""
    cols = {"v": v, "phi": phi, "cue_speed": cue_speed, "cue_dir": cue_dir, "obj_speed": obj_speed,
            "obj_dir": obj_dir}
    return fit_many([cols], R=R, k=k, M=M, sigma_speed=sigma_speed, sigma_dir=sigma_dir, speed_noise=speed_noise,
                    x0=x0)[0]


def fit_many(datasets: Sequence[Mapping[str, ArrayLike]], *, R: float, k: float = 2.5, M: float = 0.17,
             sigma_speed: float | None = None, sigma_dir: float | None = None, speed_noise: SpeedNoise = "relative",
             x0: tuple[float, float] = (0.05, 0.9)) -> list[BallBallFit]:
    """``fit_shots`` on several data sets of equal size (columns as ``synthetic_shots`` returns), their predictions
    computed together: the same result as one ``fit_shots`` per data set, much faster for many."""
    if (sigma_speed is None) != (sigma_dir is None):
        raise InputError("fit_shots", "give both sigma_speed and sigma_dir, or neither (then both are estimated)")
    if sigma_speed is not None and not (sigma_speed > 0 and sigma_dir is not None and sigma_dir > 0):
        raise InputError("fit_shots", "sigma_speed and sigma_dir must be > 0")
    if not datasets:
        return []
    parsed = [_columns(d["v"], d["phi"], d["cue_speed"], d["cue_dir"], d["obj_speed"], d["obj_dir"], speed_noise)
              for d in datasets]
    if len({p[0].size for p in parsed}) != 1 or parsed[0][0].size == 0:
        raise InputError("fit_shots", "the data sets must have the same number of shots, at least one")
    v, phi, obs = (np.stack([p[j] for p in parsed]) for j in range(3))
    shots = _Shots(v, phi, obs, R, k, M, speed_noise)
    D, n = v.shape
    idx = np.arange(D)
    x = np.tile(np.asarray(x0, dtype=float), (D, 1))
    its = np.zeros(D, dtype=int)
    conv = np.ones(D, dtype=bool)
    if sigma_speed is not None and sigma_dir is not None:
        sig = np.tile([sigma_speed, sigma_dir], (D, 1)).astype(float)
        x = _solve(shots, x, 1.0 / _row_sigma(sig, n), idx)
    else:
        # per-kind σ by iterated reweighting (only their ratio moves the estimate); the start is a guess
        scale = 1.0 if speed_noise == "relative" else np.median(obs[:, [0, 2]], axis=(1, 2))
        sig = np.stack([np.broadcast_to(0.02 * scale, (D,)), np.full(D, math.radians(0.5))], axis=1)
        floor = 1e-12 * np.stack([np.broadcast_to(scale, (D,)), np.ones(D)], axis=1)
        conv[:] = False
        live = idx.copy()
        for it in range(1, REWEIGHT_MAXITER + 1):
            w = 1.0 / _row_sigma(sig[live], n)
            x[live] = _solve(shots, x[live], w, live)
            r, J, _ = shots.eval(x[live], live)
            new = _kind_sigmas(r, J * w[..., None], n, floor[live])
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
        given = sigma_speed is not None
        res, jac = shots.functions(d, None if given else ws)
        s = ws if given else None  # given σ: fitting weighs; estimated: the residuals come scaled, s² from them
        fit = analyse(res, x[d], NAMES, BOUNDS, sigma=None if s is None else 1.0 / s, jac=jac)
        if fit.identifiability.rank < 2:  # a family of solutions: least_squares_fit moves to its canonical point
            fit = least_squares_fit(res, x[d], NAMES, BOUNDS, sigma=None if s is None else 1.0 / s, jac=jac)
        xf = np.asarray(fit.point)
        _, Jd, reg = shots.eval(xf[None], np.array([d]))
        f_share, e_share = _shares(Jd[0] * ws[:, None], n)
        base = {f.name: getattr(fit, f.name) for f in fields(FitResult)}
        out.append(BallBallFit(**base, sigma_speed=float(sig[d, 0]), sigma_dir=float(sig[d, 1]),
                               speed_noise=speed_noise, reweight_iterations=int(its[d]),
                               reweight_converged=bool(conv[d]), f_bb_share=f_share, e_share=e_share,
                               regime=tuple(int(g) for g in reg[0])))
    return out


def synthetic_shots(rng: np.random.Generator, n: int, *, f_bb: float = 0.06, e: float = 0.93, R: float = 0.02855,
                    k: float = 2.5, v_range: tuple[float, float] = (0.5, 3.0),
                    phi_range_deg: tuple[float, float] = (10.0, 60.0), sigma_speed: float = 0.02,
                    sigma_dir: float = math.radians(0.5), speed_noise: SpeedNoise = "relative"
                    ) -> dict[str, np.ndarray]:
    """n synthetic shots: v uniform in ``v_range`` (m/s), φ uniform in ``phi_range_deg`` (degrees, stored in rad),
    outcomes predicted at (f_bb, e) with noise: speeds × exp(σ z) (relative) or + σ z (absolute, m/s), directions
    + σ_dir z (rad). Columns: v, phi, cue_speed, cue_dir, obj_speed, obj_dir (SI)."""
    v = rng.uniform(*v_range, n)
    phi = np.radians(rng.uniform(*phi_range_deg, n))
    p = predict_shots(v, phi, f_bb=f_bb, e=e, R=R, k=k)
    z = rng.standard_normal((4, n))
    if speed_noise == "relative":
        cs, os_ = p.cue_speed * np.exp(sigma_speed * z[0]), p.obj_speed * np.exp(sigma_speed * z[2])
    else:
        cs, os_ = p.cue_speed + sigma_speed * z[0], p.obj_speed + sigma_speed * z[2]
    return {"v": v, "phi": phi, "cue_speed": cs, "cue_dir": _wrap(p.cue_dir + sigma_dir * z[1]), "obj_speed": os_,
            "obj_dir": _wrap(p.obj_dir + sigma_dir * z[3])}


def fit_columns(cols: Mapping[str, np.ndarray], **kw: object) -> BallBallFit:
    """``fit_shots`` on a dict of columns as ``synthetic_shots`` returns (keyword arguments passed on)."""
    return fit_shots(cols["v"], cols["phi"], cols["cue_speed"], cols["cue_dir"], cols["obj_speed"], cols["obj_dir"],
                     **kw)  # type: ignore[arg-type]
