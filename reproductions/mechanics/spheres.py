"""§V n°12 and §VI n°13 of Résal (1883): the impact of two spheres with friction f, free or resting on the
cloth.

Frame of the paper: Ox along the line of centres, from C towards C′; M strikes M′ with normal impulse
ξ = ∫X dt = M ω1 (ω1 = χ0 − χ1, eq. 4). Vectors here are (x, y, z) arrays on the last axis: velocities v,
v′ and rotations w, w′ of the centres; for §VI, Oz is vertical and the balls cannot leave the cloth. The slip
of M on M′ at the contact is s = (η − η′ + Rq + R′q′, ζ − ζ′ − Rp − R′p′) (eq. 1), q = w_z, p = w_y.

A tangential impulse T (on M′; −T on M) changes the slip by −(c_y T_y, c_z T_z) with
c = (1 + k)/M + (1 + k′)/M′ for free balls (both components: the slip keeps its direction, as Résal
proves), and c_y = (1 + k)/M + (1 + k′)/M′, c_z = k/M + k′/M′ on the cloth, where the vertical translation
is blocked (the direction then turns during the impact, eqs 7–9 of n°13). Under friction the components
decay as in ``slip.slip_decay`` with α = M c_y, β = M c_z and τ = f ξ/M; the slip may stop.

Normal impulse, from Résal's law (6) of §I, derived for these bodies. For a rigid body the sum over its
molecules Σ m U² of the squared lost velocities is M|ΔV|² + (MR²/k)|Δw|² (König), and Σ m U·u of §I eq. (1) is
the work of the impulses the body receives, estimated with the velocities u at the greatest compression. M
receives −(ξ x̂ + T) at its contact, M′ receives ξ x̂ + T; on the cloth each ball also receives the cloth's
vertical impulse at its foot, which does no work at the greatest compression (the foot moves only
horizontally) but is what keeps the centre from moving vertically. So Σ m U·u over both balls is T·s_c ≥ 0 (the
normal relative velocity vanishes at the greatest compression; s_c is the slip of M on M′ then, and T on M′ drags
it along the slip: Résal's −Jω, a loss) and, with
ΔV = −(ξ, T_y, T_z)/M for M (T_z dropped on the cloth) and Δw = (k/MR)(0, T_z, −T_y),

    Σ m U² = (ξ² + (1 + k) T_y² + k_z T_z²)/M,   k_z = 1 + k for a free ball, k_z = k on the cloth

(the cloth lets the vertical friction impulse turn the ball, never move its centre). Law (6) then reads

    (1 + ε)(ξ² + (1 + k)T_y² + k_z T_z²)/M + (1 + ε′)(ξ² + (1 + k′)T_y² + k′_z T_z²)/M′
        = 2[ξ ξ_c (1/M + 1/M′) + c_y T_y T_cy + c_z T_z T_cz],                                     (L)

with ξ_c, T_c the impulses at the greatest compression (the identity of §I n°3 with the velocities of the
greatest compression; at ε = ε′ = 1, ξ = ξ_c solves (L): §I n°2's impact without restitution ends there). In
ω = ξ/M (ω1 = χ0 − χ1, ω_c = (χ0 − χ0′)/(1 + M/M′)) and the slip lost Y = |s0_y| − |s_y|, Z = |s0_z| − |s_z|
(T_y = Y/c_y, T_z = Z/c_z: each component of the slip decays without changing sign),

    G(ω) = N ω² − 2Δω + A_y Y² + A_z Z² − 2(Y Y_c + Z Z_c)/(M c·) = 0,   N = (1 + ε) + (M/M′)(1 + ε′),
    A_y = [(1 + ε)(1 + k) + (M/M′)(1 + ε′)(1 + k′)]/(M c_y)²,  A_z the same with k_z, k′_z and c_z,

Δ = χ0 − χ0′. G(ω_c) = Σ(ε − 1)(…) ≤ 0, and on ω ≥ ω_c every term of G′ is ≥ 0 (Nω − Δ ≥ 0, Y ≥ Y_c,
A_y ≥ 1/(M c_y)), N ω − Δ > 0: G increases, so (L) has one root beyond the greatest compression. Free balls: the
slip keeps its direction, T = λ ξ ŝ0, and (L) is ω1 S_ε(λ) = 2Δ + 2λ(|s0| − |s_c|), S_ε(λ) =
[1 + λ²(1 + k)](1 + ε) + (M/M′)[1 + λ²(1 + k′)](1 + ε′): while the balls slide throughout (λ = f) this is
exactly Résal's eq. (8) of §V; when the slip stops during the restitution it is a quadratic in ω1 (λ =
|s0|/(c M ω1)). While the slip keeps its direction and does not stop, T_e/ξ_e = T_c/ξ_c and (L) gives
ξ = 2ξ_c/(1 + ε) for ε = ε′: the normal velocity is returned in the ratio e = (1 − ε)/(1 + ε) whatever f. On the
cloth a slip with both components turns, T_e is not along T_c, and the normal ratio differs from e by a term of
order f². That is the ``exact`` path: the slip decay in closed form (``slip.SlipDecay``) and the root of G by
Newton's method in a bracket [ω_c, ω_hi], ω_hi = [Δ + √(Δ² + 2N C)]/N, C = |s0_y|²/(M c_y) + |s0_z|²/(M c_z)
(G ≥ Nω² − 2Δω − 2C). The ``ode`` path solves the same (L) with the slip integrated (DOP853) instead of its
closed form; the ``reference`` path (``referee.spheres``) integrates every velocity component and evaluates
law (6) literally on the state, sharing nothing with either.

Earlier versions applied on the cloth the free balls' S_ε(λ) with λ = |T|/ξ and the work 2λ(|s0| − |s_c|):
the vertical friction impulse counted as moving the centres (1 + k instead of k) and the work of magnitudes
instead of the projection T·(s0 − s_c); head on at ε = ε′ = 1 the balls were still approaching after the impact.

``resal``: §V eqs (5) and (8) (sliding assumed throughout) for free balls; §VI eqs (11)–(15) on the cloth
(first order in f: constant slip direction, ω1 = 2ω/(1 + ε)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .budget import bounded, check
from .paths import PathCode, Regime, as_floats, batch_arrays, codes, maximum, minimum, pick, result
from .slip import _TURNS, SlipDecay, SlipWalk, _DecayOne, _WalkOne, classes, slip_decay

__all__ = ["METHODS", "SpheresImpact", "contact_slip", "two_spheres"]

METHODS = ("exact", "resal", "ode")


@dataclass(frozen=True)
class SpheresImpact:
    v1: np.ndarray
    w1: np.ndarray
    v1p: np.ndarray
    w1p: np.ndarray
    omega1: np.ndarray  # χ0 − χ1
    T: np.ndarray  # tangential impulse on M′ (y, z components)
    s_c: np.ndarray  # slip of M on M′ at the greatest compression (y, z), the velocities law (6)'s work is taken at
    converged: np.ndarray  # the §VI end of impact (Newton, Brent) converged (True where there is none)
    method: str
    path: np.ndarray
    regime: np.ndarray  # SLIDE: slips throughout; GRIP: the slip stops; NO_SLIP: none at first
    label: str


_NO_SLIP, _GRIP, _SLIDE = Regime.NO_SLIP, Regime.GRIP, Regime.SLIDE  # (an enum's attribute costs a microsecond)
_CODE = {m: PathCode[m.upper()] for m in METHODS}  # (so does looking a member up by name)
_F64 = np.float64
_ZERO, _ONE, _MINUS_ONE = np.float64(0.0), np.float64(1.0), np.float64(-1.0)
_TINY, _INF = np.float64(1e-300), np.float64(np.inf)
# np.sign of a numpy float ±0, where numpy gives both the same number (else None: ``_sign`` asks numpy each time)
_SIGN_OF_ZERO = np.sign(_ZERO) if np.sign(_ZERO).tobytes() == np.sign(-_ZERO).tobytes() else None


def _stack(*xs: Any) -> np.ndarray:
    """``np.stack(xs, axis=-1)``; for one scene as numpy floats (``paths.Path.scalar``) the array of them, without
    ``np.stack``'s fixed cost (the same numbers, placed alike)."""
    for x in xs:  # (a loop: cheaper than ``all`` over a generator)
        if x.__class__ is not _F64:
            return np.stack(xs, axis=-1)
    return np.array(xs)


def _sign(x: np.ndarray) -> np.ndarray:
    """``np.sign(x)``; of a nonzero numpy float its ±1 without the ufunc's fixed cost (±0 and nan: numpy's own)."""
    if x.__class__ is _F64:
        if x > 0:
            return _ONE
        if x < 0:
            return _MINUS_ONE
        if x == 0 and _SIGN_OF_ZERO is not None:
            return _SIGN_OF_ZERO
    return np.sign(x)


def _hypot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.hypot(a, b)``; of numpy floats one of them ±0 and the other not nan, the other's magnitude itself, as
    the C library's hypot gives it (C99 F.10.4.3: hypot(x, ±0) is fabs(x), and hypot is symmetric), without the
    ufunc's cost (a nan's sign is numpy's to give: it goes to ``np.hypot``)."""
    if a.__class__ is _F64 and b.__class__ is _F64:
        if b == 0 and a == a:
            return abs(a)
        if a == 0 and b == b:
            return abs(b)
    return np.hypot(a, b)


def _parts(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The x, y, z components of vectors on the last axis (``_at``)."""
    if x.ndim == 1:
        return x[0], x[1], x[2]
    return x[..., 0], x[..., 1], x[..., 2]


def _at(x: np.ndarray, i: int) -> np.ndarray:
    """``x[..., i]``; of one scene's vector (1-D, ``paths.Path.scalar``) its numpy float, not a 0-d array (whose
    arithmetic costs numpy's array calls; the same numbers)."""
    return x[i] if x.ndim == 1 else x[..., i]


def _fit(x: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """A copy of ``x`` broadcast to ``shape`` (``np.broadcast_to``'s fixed cost skipped where it has it)."""
    return x.copy() if np.shape(x) == shape else np.broadcast_to(x, shape).copy()


def _slip(vy: np.ndarray, vz: np.ndarray, wy: np.ndarray, wz: np.ndarray, pvy: np.ndarray, pvz: np.ndarray,
          pwy: np.ndarray, pwz: np.ndarray, R: np.ndarray, Rp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Slip of M on M′ at the contact, eq. (1) of n°12, from the velocity components: (s_y, s_z)."""
    return vy - pvy + R * wz + Rp * pwz, vz - pvz - R * wy - Rp * pwy


def contact_slip_yz(v: np.ndarray, w: np.ndarray, vp: np.ndarray, wp: np.ndarray, R: np.ndarray,
                    Rp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``contact_slip``'s components (s_y, s_z), eq. (1) of n°12, not stacked."""
    if v.ndim == w.ndim == vp.ndim == wp.ndim == 1:  # one scene's vectors: their numpy floats (``_at``)
        return _slip(v[1], v[2], w[1], w[2], vp[1], vp[2], wp[1], wp[2], R, Rp)
    return _slip(_at(v, 1), _at(v, 2), _at(w, 1), _at(w, 2), _at(vp, 1), _at(vp, 2), _at(wp, 1), _at(wp, 2), R, Rp)


def contact_slip(v: np.ndarray, w: np.ndarray, vp: np.ndarray, wp: np.ndarray, R: np.ndarray,
                 Rp: np.ndarray) -> np.ndarray:
    """Slip of M on M′ at the contact, eq. (1) of n°12, as (y, z) on the last axis."""
    return _stack(*contact_slip_yz(v, w, vp, wp, R, Rp))


def _apply(M: np.ndarray, Mp: np.ndarray, R: np.ndarray, Rp: np.ndarray, k: np.ndarray, kp: np.ndarray,
           v: tuple[np.ndarray, ...], w: tuple[np.ndarray, ...], vp: tuple[np.ndarray, ...],
           wp: tuple[np.ndarray, ...], xi: np.ndarray, Ty: np.ndarray, Tz: np.ndarray, on_cloth: bool,
           one: bool = False) -> tuple[np.ndarray, ...]:
    """Velocities after the normal impulse ξ and the tangential impulse T (on M′), eqs (2), (2′): the impulse
    −(ξ x̂ + T) on M at R x̂ and ξ x̂ + T on M′ at −R′ x̂, T = (0, T_y, T_z); the moments R x̂ × (−T) and
    (−R′ x̂) × T are both R(0, T_z, −T_y) (R′ for M′). On the cloth the cloth takes the vertical impulses.
    Component by component (v, w, v′, w′ as their x, y, z): one scene's numpy floats build no arrays but the
    results (``paths.Path.scalar``); the same numbers as the vectors' sums."""
    zero = _ZERO if xi.__class__ is _F64 else np.zeros_like(xi)
    (vx, vy, vz), (wx, wy, wz), (pvx, pvy, pvz), (pwx, pwy, pwz) = v, w, vp, wp
    c, cp = k / (M * R), kp / (Mp * Rp)  # the rotation per unit moment, times R (R′)
    if one and xi.__class__ is _F64 and Ty.__class__ is _F64 and Tz.__class__ is _F64:  # ``_stack``'s array
        v1 = np.array((vx + -xi / M, vy + -Ty / M, vz + (zero if on_cloth else -Tz / M)))
        v1p = np.array((pvx + xi / Mp, pvy + Ty / Mp, pvz + (zero if on_cloth else Tz / Mp)))
        mTy = -Ty
        return (v1, np.array((wx + c * zero, wy + c * Tz, wz + c * mTy)), v1p,
                np.array((pwx + cp * zero, pwy + cp * Tz, pwz + cp * mTy)))
    v1 = _stack(vx + -xi / M, vy + -Ty / M, vz + (zero if on_cloth else -Tz / M))
    v1p = _stack(pvx + xi / Mp, pvy + Ty / Mp, pvz + (zero if on_cloth else Tz / Mp))
    mTy = -Ty  # the moment's components (0, T_z, −T_y)
    return (v1, _stack(wx + c * zero, wy + c * Tz, wz + c * mTy), v1p,
            _stack(pwx + cp * zero, pwy + cp * Tz, pwz + cp * mTy))


def two_spheres(M: ArrayLike, Mp: ArrayLike, R: ArrayLike, Rp: ArrayLike, k: ArrayLike, kp: ArrayLike,
                v: ArrayLike, w: ArrayLike, vp: ArrayLike, wp: ArrayLike, *, f: ArrayLike, eps: ArrayLike,
                epsp: ArrayLike, on_cloth: bool = False, method: str = "exact", rtol: float = 1e-11,
                solver: str = "DOP853") -> SpheresImpact:
    """The impact of §V (free balls) or §VI (``on_cloth``) by the chosen path (module docstring); v, w, vp,
    wp have the vector on the last axis; the other inputs broadcast over the batch. M must approach M′."""
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    v, w, vp, wp = as_floats(v, w, vp, wp)
    M, Mp, R, Rp, k, kp, f, eps, epsp = batch_arrays(M, Mp, R, Rp, k, kp, f, eps, epsp)
    batch = M.shape
    one = M.__class__ is _F64  # one scene as numpy floats (``paths.Path.scalar``)
    if one and v.ndim == w.ndim == vp.ndim == wp.ndim == 1:  # (its vectors: 3 numbers each, batch ())
        vc, wc, vpc, wpc = (v[0], v[1], v[2]), (w[0], w[1], w[2]), (vp[0], vp[1], vp[2]), (wp[0], wp[1], wp[2])
    else:
        one = False
        if not v.shape[:-1] == w.shape[:-1] == vp.shape[:-1] == wp.shape[:-1] == batch:
            batch = np.broadcast_shapes(v.shape[:-1], w.shape[:-1], vp.shape[:-1], wp.shape[:-1], batch)
            v, w, vp, wp = (np.broadcast_to(x, (*batch, 3)) for x in (v, w, vp, wp))
            M, Mp, R, Rp, k, kp, f, eps, epsp = (np.broadcast_to(x, batch)
                                                 for x in (M, Mp, R, Rp, k, kp, f, eps, epsp))
    if not one:  # (one scene: its components taken above)
        vc, wc, vpc, wpc = _parts(v), _parts(w), _parts(vp), _parts(wp)  # the components
    mu = M / Mp
    approach = vc[0] - vpc[0]
    omega = approach / (1 + mu)  # speed lost by M at the greatest compression
    s0y, s0z = _slip(vc[1], vc[2], wc[1], wc[2], vpc[1], vpc[2], wpc[1], wpc[2], R, Rp)  # eq. (1)
    s0n = _hypot(s0y, s0z)
    cy = (1 + k) / M + (1 + kp) / Mp
    cz = (k / M + kp / Mp) if on_cloth else cy

    coef = _law_coefficients(M, mu, k, kp, eps, epsp, cy, cz, on_cloth)

    if method == "resal":
        if on_cloth:  # §VI (11)-(15): first order in f
            omega1 = 2 * omega * (1 + mu) / ((1 + eps) + mu * (1 + epsp))
        else:  # §V (8): sliding throughout
            S = 1 + f * f * (1 + k) + mu * (1 + f * f * (1 + kp))
            omega1 = 2 * omega * S / _law6_S(f, k, kp, eps, epsp, mu)
        xi = M * omega1
        size = pick(s0n > 0, s0n, 1.0)
        uy, uz = s0y / size, s0z / size  # the slip's direction
        fxi = f * xi
        Ty, Tz = fxi * uy, fxi * uz
        # the premise (the balls slide throughout) fails where this slip change would reverse the slip: there
        # the slip really stops (for free balls the same criterion as the exact path's)
        s1y, s1z = s0y - cy * Ty, s0z - cz * Tz
        stops = (s1y * s0y + s1z * s0z < 0) & (s0n > 0)
        fMo = f * M * omega
        s_c = _stack(s0y - fMo * (cy * uy), s0z - fMo * (cz * uz))
        converged = np.True_ if one else np.ones(batch, dtype=bool)
        label = ("Résal's §VI eqs (11)-(15), first order in f" if on_cloth
                 else "Résal's §V eqs (5), (8), sliding assumed throughout")
        if stops.any():
            label += f"; premise fails where the slip stops ({int(stops.sum())} of {stops.size} scene(s))"
    elif method == "ode":
        s0 = _stack(s0y, s0z)
        omega1, s1, s_c, converged = _ode_impact(s0, approach, omega, M, cy, cz, f, coef, rtol, solver)
        xi = M * omega1
        label = ("ODE of the slip in the normal impulse (DOP853), normal impulse from law (6) solved on its dense "
                 "output (Brent)")
        Ty, Tz = (s0y - s1[..., 0]) / cy, (s0z - s1[..., 1]) / cz
        stops = (np.hypot(s1[..., 0], s1[..., 1]) <= 1e-9 * np.maximum(s0n, 1e-300)) & (s0n > 0)
    else:
        converged = np.True_ if one else np.ones(batch, dtype=bool)
        final = None  # on the cloth: the slip after, from the end of the fixed point
        if not on_cloth:
            w_c = maximum(s0n - f * cy * M * omega, _ZERO)
            shrink = w_c / pick(s0n > 0, s0n, 1.0)
            s_c = _stack(s0y * shrink, s0z * shrink)
            omega1 = (2 * approach + 2 * f * s0n - 2 * f * w_c) / _law6_S(f, k, kp, eps, epsp, mu)
            stick = f * cy * M * omega1 > s0n  # the slip stops during the restitution
            # quadratic α ω1² − 2Δ ω1 + β = 0 with λ = |s0|/(c M ω1)
            alpha = (1 + eps) + mu * (1 + epsp)
            lam0 = s0n / (cy * M)
            beta = lam0 * lam0 * ((1 + k) * (1 + eps) + mu * (1 + kp) * (1 + epsp)) \
                - 2 * s0n * (s0n - w_c) / (cy * M)
            disc = maximum(approach * approach - alpha * beta, _ZERO)
            omega1 = pick(stick, (approach + np.sqrt(disc)) / alpha, omega1)
        else:
            impulse = _cloth_normal_impulse_one if one else _cloth_normal_impulse  # (one scene: its floats')
            omega1, converged, s_c, final = impulse(s0y, s0z, approach, omega, M, cy, cz, f, coef)
        xi = M * omega1
        if final is None:
            a1, b1 = slip_decay(abs(s0y), abs(s0z), M * cy, M * cz, f * omega1)
        elif one:
            a1, b1 = final
        else:
            a1, b1 = (x.reshape(batch) for x in final)
        s1y, s1z = _sign(s0y) * a1, _sign(s0z) * b1
        label = ("exact: slip decay in closed form (₂F₁), normal impulse from law (6) by Newton's method"
                 if on_cloth else "exact: closed form, sliding or sticking (law (6) as a quadratic)")
        Ty, Tz = (s0y - s1y) / cy, (s0z - s1z) / cz
        stops = (_hypot(s1y, s1z) <= 1e-12 * maximum(s0n, _TINY)) & (s0n > 0)
    v1, w1, v1p, w1p = _apply(M, Mp, R, Rp, k, kp, vc, wc, vpc, wpc, xi, Ty, Tz, on_cloth, one)
    if s0n.__class__ is _F64:  # one scene: its regime's code itself (``paths.codes``), as the masks below give it
        regime = codes((), _NO_SLIP if s0n == 0 else _GRIP if stops else _SLIDE)
    else:
        regime = np.where(s0n == 0, _NO_SLIP, np.where(stops, _GRIP, _SLIDE)).astype(np.int8)
    if not one:  # (one scene: s_c is a new array, converged a numpy bool that ``paths._run_one`` makes an array)
        s_c, converged = _fit(s_c, (*batch, 2)), _fit(converged, batch)
    T = np.array((Ty, Tz)) if one and Ty.__class__ is _F64 and Tz.__class__ is _F64 else _stack(Ty, Tz)
    return result(SpheresImpact, v1=v1, w1=w1, v1p=v1p, w1p=w1p, omega1=omega1, T=T, s_c=s_c,
                  converged=converged, method=method, path=codes(batch, _CODE[method]), regime=regime, label=label)


def _law6_S(lam: np.ndarray, k: np.ndarray, kp: np.ndarray, eps: np.ndarray, epsp: np.ndarray,
            mu: np.ndarray) -> np.ndarray:
    """S_ε(λ) of law (6) with λ = |T|/ξ (module docstring; §V eq. (8), §VI)."""
    lam2 = lam * lam  # (x * x, not x**2: numpy's scalar power calls the C library's pow; ``paths.Path.scalar``)
    return (1 + lam2 * (1 + k)) * (1 + eps) + mu * (1 + lam2 * (1 + kp)) * (1 + epsp)


def _law_coefficients(M: np.ndarray, mu: np.ndarray, k: np.ndarray, kp: np.ndarray, eps: np.ndarray,
                      epsp: np.ndarray, cy: np.ndarray, cz: np.ndarray, on_cloth: bool
                      ) -> tuple[np.ndarray, ...]:
    """N, A_y, A_z, B_y = 1/(M c_y), B_z = 1/(M c_z) of G(ω), law (L) of the module docstring (§I eq. (6) for
    these bodies; k_z = k on the cloth, 1 + k free)."""
    k1, kp1 = 1 + k, 1 + kp
    kz, kpz = (k, kp) if on_cloth else (k1, kp1)
    e1, me1 = 1 + eps, mu * (1 + epsp)  # (each computed once: the same numbers)
    N = e1 + me1
    By, Bz = 1 / (M * cy), 1 / (M * cz)
    Ay = (e1 * k1 + me1 * kp1) * By * By
    Az = (e1 * kz + me1 * kpz) * Bz * Bz
    return N, Ay, Az, By, Bz


def law6_G(om: np.ndarray, Y: np.ndarray, Z: np.ndarray, Yc: np.ndarray, Zc: np.ndarray, approach: np.ndarray,
           coef: tuple[np.ndarray, ...]) -> np.ndarray:
    """G(ω) of law (L) (module docstring), from the slip lost Y, Z after ω and Y_c, Z_c at the greatest
    compression; zero at the end of the impact."""
    N, Ay, Az, By, Bz = coef
    return N * om * om - 2 * approach * om + Ay * Y * Y + Az * Z * Z - 2 * (By * Y * Yc + Bz * Z * Zc)


_ULP = float(np.finfo(float).eps)
NEWTON_RTOL = 1e-14  # convergence of the §VI end of impact, relative to ω1
NEWTON_MAXITER = 100


def _cloth_normal_impulse(s0y: np.ndarray, s0z: np.ndarray, approach: np.ndarray, omega: np.ndarray,
                          M: np.ndarray, cy: np.ndarray, cz: np.ndarray, f: np.ndarray, coef: tuple[np.ndarray, ...]
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """ω1 on the cloth (§VI): the root of G(ω) (law (L), module docstring) beyond the greatest compression ω_c,
    with the slip decay in closed form, by Newton's method (G′ from the decay's rates, dY/dω = f M c_y |s_y|/|s|;
    G″ too, ``_root_step``: Halley's order) from ``_cloth_guess`` (G with the slip continued at its rates from ω_c)
    safeguarded by the bracket [ω_c, ω_hi] (bisection where a step leaves it). One iteration moves both unknowns:
    the slip's x (``slip.SlipWalk``: one step of the decay towards τ = f ω, its residual corrected to first
    order) and ω; it stops when the slip has converged for ω and a step is below ``NEWTON_RTOL`` of ω, or G is at
    its own rounding, or the bracket is that narrow (bounded by ``NEWTON_MAXITER``; a scene still moving then is
    finished by ``_cloth_bisect``). The iteration runs on the scenes still moving, its arrays compacted as scenes
    finish. ``s0y``, ``s0z``: the slip before (eq. (1)).
    Returns ω1, per scene whether it converged, the slip at the greatest compression (y, z, signed), and the
    magnitudes of the slip after (y, z)."""
    if approach.__class__ is np.float64:  # one scene as numpy floats (``paths.Path.scalar``)
        return _cloth_normal_impulse_one(s0y, s0z, approach, omega, M, cy, cz, f, coef)
    al, be = np.ravel(M * cy), np.ravel(M * cz)  # the slip decay's α, β (once: the grouping, the decay, the rates)
    groups = classes(al, be)
    if groups is not None:  # balls of a few kinds: each kind's scenes a batch of one class (``slip.classes``)
        return _cloth_by_class(groups, (s0y, s0z, approach, omega, M, cy, cz, f), coef)
    shape = approach.shape
    sy, sz = np.sign(s0y).ravel(), np.sign(s0z).ravel()
    a0, b0 = np.abs(s0y).ravel(), np.abs(s0z).ravel()
    f, approach, om_c = (np.ravel(x) for x in (f, approach, omega))
    coef = tuple(np.ravel(x) for x in coef)
    N, Ay, Az, By, Bz = coef
    dec = SlipDecay(a0, b0, al, be)
    # the slip at the greatest compression: the general decays walked from x = 1 to τ = f ω_c, the others elementary
    gi = np.flatnonzero(dec.gen) if dec.special else dec.everyone
    start = SlipWalk(dec, gi, np.ones(gi.size), dec.total[gi])
    ac, bc, xc, hc = np.empty(a0.size), np.empty(a0.size), np.full(a0.size, np.nan), np.full(a0.size, np.nan)
    ac[gi], bc[gi], xc[gi], hc[gi] = start.settle(f[gi] * om_c[gi])
    if dec.special:
        sp = np.flatnonzero(~dec.gen)
        ac[sp], bc[sp], _ = dec.at(f[sp] * om_c[sp], sp)
    Yc, Zc = a0 - ac, b0 - bc
    hi0 = _cloth_high(a0, b0, approach, N, By, Bz)
    g_c = law6_G(om_c, Yc, Zc, Yc, Zc, approach, coef)
    done = g_c >= 0  # ε = ε′ = 1 (to rounding): the impact ends at the greatest compression
    omega1, a1, b1, converged = om_c.copy(), ac.copy(), bc.copy(), done.copy()

    ix = np.flatnonzero(~done)  # the scenes still moving; the arrays below are theirs
    cols = (a0, b0, Yc, Zc, approach, f, al, be, N, Ay, Az, By, Bz, om_c, hi0, g_c, ac, bc)
    if ix.size == done.size:  # every scene (ε, ε′ < 1): the arrays as they are (lo and hi are updated in place)
        A0, B0, YC, ZC, D, F, AL, BE, n_, ay, az, by, bz, lo, hi, gc, acx, bcx = cols
        lo, hi = lo.copy(), hi.copy()
    else:
        A0, B0, YC, ZC, D, F, AL, BE, n_, ay, az, by, bz, lo, hi, gc, acx, bcx = (c[ix] for c in cols)
    with np.errstate(divide="ignore", invalid="ignore"):
        om = _cloth_guess(gc, lo, acx, bcx, YC, ZC, D, F, AL, BE, (n_, ay, az, by, bz), hi)
    gen = dec.gen[ix]
    wi = np.flatnonzero(gen) if dec.special else slice(None)  # the general decays, walked; the others elementary
    walk = SlipWalk(dec, ix[wi], xc[ix[wi]], hc[ix[wi]])
    alive = np.ones(ix.size, dtype=bool)  # not yet written out (finished scenes stay until a compaction)
    # compact below 90 % alive; below half where the walk carries a column of coefficients per scene (k ≠ k′:
    # gathering that table costs more than stepping finished scenes on, which changes no other scene's numbers)
    packing = 0.5 if walk.series is not None and walk.series.p.shape[-1] > 1 else 0.9
    p1 = q1 = dY = dZ = om
    for _ in range(NEWTON_MAXITER):
        if ix.size == 0:
            break
        tau = F * om
        if dec.special:
            p1, q1, settled = np.empty(ix.size), np.empty(ix.size), np.ones(ix.size, dtype=bool)
            p1[wi], q1[wi], settled[wi] = walk.advance(tau[wi])
            sp = np.flatnonzero(~gen)
            p1[sp], q1[sp], _ = dec.at(tau[sp], ix[sp])
        else:
            p1, q1, settled = walk.advance(tau)
        with np.errstate(divide="ignore", invalid="ignore"):
            g, noise, dY, dZ, nxt = _cloth_newton(om, p1, q1, A0, B0, YC, ZC, D, F, AL, BE, (n_, ay, az, by, bz))
        # the bracket moves where the slip has converged for ω (there G is known to its rounding)
        np.maximum(lo, om, out=lo, where=settled & (g < 0))
        np.minimum(hi, om, out=hi, where=settled & (g > 0))
        out = ~_inside(nxt, lo, hi)
        if out.any():
            nxt[out] = _bisect(lo[out], hi[out])
        # converged; or G at its own rounding (a slip 10⁵ times the approach speed loses that many digits in
        # Y = |s0| − |s|, and the steps then wander at 1e-12 of ω): the root is as known as G lets it be
        quiet = settled & _quiet(g, noise)
        if quiet.any():
            nxt[quiet] = om[quiet]
        fin = alive & settled & _ends(nxt, om, quiet, lo, hi)
        if fin.any():
            k = np.flatnonzero(fin)
            j = ix[k]
            omega1[j], converged[j] = nxt[k], True
            a1[j], b1[j] = _cloth_final(p1[k], q1[k], dY[k], dZ[k], nxt[k] - om[k])
            alive[k] = False
        om = nxt
        if alive.sum() < packing * ix.size:  # compaction
            k = np.flatnonzero(alive)
            if dec.special:
                rank = np.cumsum(gen) - 1
                walk.keep(rank[k[gen[k]]])
                gen = gen[k]
                wi = np.flatnonzero(gen)
            else:
                walk.keep(k)
            ix, om, alive = ix[k], om[k], alive[k]
            A0, B0, YC, ZC, D, F, AL, BE, n_, ay, az, by, bz, lo, hi = (
                c[k] for c in (A0, B0, YC, ZC, D, F, AL, BE, n_, ay, az, by, bz, lo, hi))
            p1, q1 = p1[k], q1[k]
    for k in np.flatnonzero(alive):  # over NEWTON_MAXITER: bisection on the settled slip (``_cloth_bisect``)
        j = ix[k]
        omega1[j], converged[j], (a1[j], b1[j]) = _cloth_bisect(
            om[k], lo[k], hi[k], A0[k], B0[k], YC[k], ZC[k], D[k], F[k], AL[k], BE[k],
            (n_[k], ay[k], az[k], by[k], bz[k]))
    s_c = np.stack([sy * ac, sz * bc], axis=-1).reshape(*shape, 2)
    return omega1.reshape(shape), converged.reshape(shape), s_c, (a1, b1)


def _cloth_by_class(groups: list[np.ndarray], args: tuple[np.ndarray, ...], coef: tuple[np.ndarray, ...]
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """``_cloth_normal_impulse`` (§VI n°13) group by group (``slip.classes``: the scenes of one class of the slip
    decay's c each, the rare classes together last), its outputs put back in the batch's order: a way of computing,
    nothing of the paper's. Each scene's numbers are those of its group's batch (the iteration is scene by scene,
    its compactions only gather): its own alone where the group has one c, else within its class's rounding."""
    shape = args[2].shape
    flat, cf = [np.ravel(x) for x in args], [np.ravel(x) for x in coef]
    n = flat[0].size
    omega1, converged, s_c = np.empty(n), np.empty(n, dtype=bool), np.empty((n, 2))
    a1, b1 = np.empty(n), np.empty(n)
    for i in groups:
        o, c, s, (p, q) = _cloth_normal_impulse(*(x[i] for x in flat), tuple(x[i] for x in cf))
        omega1[i], converged[i], s_c[i], a1[i], b1[i] = o, c, s, p, q
    return omega1.reshape(shape), converged.reshape(shape), s_c.reshape(*shape, 2), (a1, b1)


def _cloth_high(a0: np.ndarray, b0: np.ndarray, approach: np.ndarray, N: np.ndarray, By: np.ndarray,
                Bz: np.ndarray) -> np.ndarray:
    """ω_hi of ``_cloth_normal_impulse``'s bracket: the root of G with the whole slip lost, widened by 1e-12."""
    C = By * a0 * a0 + Bz * b0 * b0
    return (approach + np.sqrt(approach * approach + 2 * N * C)) / N * (1 + 1e-12)


def _cloth_guess(g_c: np.ndarray, om_c: np.ndarray, ac: np.ndarray, bc: np.ndarray, Yc: np.ndarray, Zc: np.ndarray,
                 D: np.ndarray, F: np.ndarray, AL: np.ndarray, BE: np.ndarray, coef: tuple[np.ndarray, ...],
                 hi: np.ndarray) -> np.ndarray:
    """``_cloth_normal_impulse``'s start, in the bracket [ω_c, hi]: the root beyond ω_c of G (law (L)) with the slip
    continued from the greatest compression at its rates there (Y = Y_c + t dY/dω, Z likewise, t = ω − ω_c, the
    rates of ``_cloth_newton``), G = G(ω_c) + b t + a t², G(ω_c) < 0; written without cancellation. A start only
    (the frictionless root 2Δ/N, the start before, ignores the slip's work): a departure for speed, the Newton
    iteration that follows and its tests are unchanged."""
    n_, ay, az, by, bz = coef
    n = _norm(ac, bc)
    if n.__class__ is _F64:  # one scene: the branch itself
        rate = F / n if n > 0 else 0.0
    else:
        rate = pick(n > 0, F / pick(n > 0, n, 1.0), 0.0)  # a slip that has stopped has no rate
    dY, dZ = AL * ac * rate, BE * bc * rate
    a = n_ + ay * dY * dY + az * dZ * dZ
    b = 2 * (n_ * om_c - D + (ay - by) * Yc * dY + (az - bz) * Zc * dZ)
    sq = np.sqrt(b * b - 4 * a * g_c)
    if b.__class__ is _F64:  # one scene: only the branch taken (the array route computes both, warnings off)
        t = -2 * g_c / (b + sq) if b >= 0 else (sq - b) / (2 * a)
    else:
        t = pick(b >= 0, -2 * g_c / (b + sq), (sq - b) / (2 * a))
    return minimum(maximum(om_c + t, om_c), hi)


def _cloth_newton(om: np.ndarray, p1: np.ndarray, q1: np.ndarray, A0: np.ndarray, B0: np.ndarray, YC: np.ndarray,
                  ZC: np.ndarray, D: np.ndarray, F: np.ndarray, AL: np.ndarray, BE: np.ndarray,
                  coef: tuple[np.ndarray, ...]) -> tuple[np.ndarray, ...]:
    """One step of ``_cloth_normal_impulse`` at ω with the slip (p1, q1) at τ = f ω: G, its rounding, the decay's
    rates dY/dω, dZ/dω and the next ω (``_root_step``, G″ included; unguarded: the caller keeps it in the
    bracket)."""
    n_, ay, az, by, bz = coef
    Y, Z = A0 - p1, B0 - q1
    g = law6_G(om, Y, Z, YC, ZC, D, coef)
    # G's rounding: a few ulps of the sum of its terms' magnitudes (and of Y, Z, which cancel |s0| − |s|)
    noise = 8 * _ULP * (n_ * om * om + 2 * D * om + ay * (Y * Y + 2 * A0 * Y) + az * (Z * Z + 2 * B0 * Z)
                        + 2 * (by * (Y + A0) * YC + bz * (Z + B0) * ZC))
    n = _norm(p1, q1)
    if n.__class__ is np.float64:  # one scene (``paths.Path.scalar``): a slip that has stopped has no rate
        if n > 0:
            rate = F / n
            per = rate / n
        else:
            rate = per = _ZERO
    else:
        rate = F / n
        per = rate / n
        if not (n > 0).all():  # a slip that has stopped: no rate (masks only where needed: cheaper)
            k = ~(n > 0)
            rate[k], per[k] = 0.0, 0.0
    dY, dZ = AL * p1 * rate, BE * q1 * rate  # dY/dω, dZ/dω: the decay's rates
    ey, ez = ay * Y - by * YC, az * Z - bz * ZC
    slope = 2 * (n_ * om - D + ey * dY + ez * dZ)
    # G″ from the rates' own derivatives (dp/dω = −dY, dq/dω = −dZ): Y″ = dY (Q − α rate), Z″ = dZ (Q − β rate),
    # Q = rate (α p² + β q²)/|s|², α = M c_y, β = M c_z
    Q = (AL * p1 * p1 + BE * q1 * q1) * per
    curve = 2 * (n_ + ay * dY * dY + az * dZ * dZ + ey * dY * (Q - AL * rate) + ez * dZ * (Q - BE * rate))
    if slope.__class__ is np.float64 and not slope != 0:  # (one scene: no warning where the array route has none)
        with np.errstate(divide="ignore", invalid="ignore"):
            return g, noise, dY, dZ, om - _root_step(g, slope, curve)
    return g, noise, dY, dZ, om - _root_step(g, slope, curve)


def _root_step(g: np.ndarray, slope: np.ndarray, curve: np.ndarray) -> np.ndarray:
    """The step δ (ω → ω − δ) to the root nearest ω of the quadratic model G − G′δ + ½G″δ² (Halley's order: cubic
    convergence, an iteration fewer than Newton's from ``_cloth_guess``), written 2G/(G′ + √(G′² − 2GG″)) without
    cancellation; Newton's G/G′ where the model has no root or G′ ≤ 0. Only the path to the root differs from
    Newton's: the same root, bracket and tests."""
    disc = slope * slope - 2 * g * curve
    if disc.__class__ is _F64:  # one scene: only the branch taken (the array route computes both, warnings off)
        if disc > 0 and slope > 0:
            return 2 * g / (slope + np.sqrt(maximum(disc, _ZERO)))
        return g / slope
    return pick((disc > 0) & (slope > 0), 2 * g / (slope + np.sqrt(maximum(disc, _ZERO))), g / slope)


def _norm(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """|s| = √(p² + q²) of a slip's magnitudes p, q ≥ 0, scaled by the larger against overflow and underflow (to
    an ulp or two of np.hypot, at a fifth of its cost); 0 for no slip."""
    if p.__class__ is _F64 and q.__class__ is _F64:  # one scene: ``maximum``'s and ``minimum``'s choices, inline
        if p > q or p != p:
            m, lo = p, (p if p != p else q)
        elif p < q:
            m, lo = q, p
        else:
            m = lo = q
        r = lo / (_ONE if m == 0 else m)  # (m + (m == 0): 1 where m is ±0, else m itself)
        return m * np.sqrt(1 + r * r)
    m = maximum(p, q)
    r = minimum(p, q) / (m + (m == 0))
    return m * np.sqrt(1 + r * r)


def _inside(nxt: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Whether a Newton iterate is finite and strictly inside the bracket."""
    if nxt.__class__ is _F64:  # one scene: comparisons, without ``np.isfinite``'s fixed cost (nan compares false)
        return -_INF < nxt < _INF and nxt > lo and nxt < hi
    return np.isfinite(nxt) & (nxt > lo) & (nxt < hi)


def _bisect(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    return 0.5 * (lo + hi)


def _quiet(g: np.ndarray, noise: np.ndarray) -> np.ndarray:
    """G at its own rounding (``_cloth_normal_impulse``)."""
    if g.__class__ is _F64:  # one scene: the same tests, in turn
        return abs(g) <= noise or g == 0
    return (abs(g) <= noise) | (g == 0)


def _ends(nxt: np.ndarray, om: np.ndarray, quiet: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """``_cloth_normal_impulse``'s stop (where the slip has converged for ω): a step below ``NEWTON_RTOL`` of ω,
    G at its rounding, or the bracket that narrow. (Not a step predicted to be the last from the convergence so
    far: next to the slip's stop at the impact's end, where G has a kink, the convergence is not of the order
    assumed, and such a stop left ω1 4e-8 off, a jump that ``resal stress`` found at the regime boundary.)"""
    if nxt.__class__ is _F64:  # one scene: the same tests, in turn
        return abs(nxt - om) <= NEWTON_RTOL * abs(nxt) or quiet or hi - lo <= NEWTON_RTOL * hi
    return (abs(nxt - om) <= NEWTON_RTOL * abs(nxt)) | quiet | (hi - lo <= NEWTON_RTOL * hi)


def _cloth_final(p1: np.ndarray, q1: np.ndarray, dY: np.ndarray, dZ: np.ndarray, step: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The slip after, corrected to first order for the last step of ω."""
    return p1 - dY * step, q1 - dZ * step


FALLBACK_MAXITER = 200  # halvings of ``_cloth_bisect``: from [lo, hi] to NEWTON_RTOL of ω1 takes
# log2(hi/lo) + 47 of them (2^-47 < 1e-14), hi/lo at most ω_hi/ω_c: 200 cover ω_hi/ω_c up to 2^150


def _cloth_bisect(om: np.float64, lo: np.float64, hi: np.float64, a0: np.float64, b0: np.float64, Yc: np.float64,
                  Zc: np.float64, D: np.float64, F: np.float64, AL: np.float64, BE: np.float64,
                  coef: tuple[np.float64, ...]) -> tuple[np.float64, np.bool_, tuple[np.float64, np.float64]]:
    """The end of the impact for a scene that ``_cloth_normal_impulse``'s iteration leaves unconverged after
    ``NEWTON_MAXITER`` steps, as numpy floats (both routes call it, scene by scene: the same numbers). That
    iteration moves the slip's walk one step per step of ω, and its bracket only where the walk has settled; where
    the root lies just short of the slip's stop (SLIDE next to GRIP), a step overshoots past the stop, the walk
    restarts from x = 1 at the next ω, one step from there corrects the slip to negative magnitudes, and G comes out
    with the wrong sign: the steps cycle, and the bracket's lower end never moves. Here G (law (L), ``law6_G``) is
    taken with the slip settled at each ω (``_cloth_slip_at``), from the iteration's last iterate ``om``, and the
    iteration's bracket [lo, hi] (moved only on settled values) is halved down to the iteration's own test, below
    ``NEWTON_RTOL`` of ω: G increases on it (module docstring), so this converges within ``FALLBACK_MAXITER``
    halvings. (Not stopped where G is within its rounding bound: a midpoint lands anywhere in that band, which is
    wide where the slip dwarfs the approach speed, and the halvings narrow it further.) Returns ω1, whether it
    converged, and the magnitudes of the slip after (y, z) at ω1."""
    dec = _DecayOne(a0, b0, AL, BE)
    x, h = _ONE, (dec.total if dec.kind == _TURNS else _ZERO)  # a walk's start: x = 1, H(1)
    om = minimum(maximum(om, lo), hi)
    for _ in range(FALLBACK_MAXITER):
        p, q, x, h = _cloth_slip_at(dec, x, h, F * om)
        g = law6_G(om, a0 - p, b0 - q, Yc, Zc, D, coef)
        if g == 0 or hi - lo <= NEWTON_RTOL * hi:
            return om, np.True_, (p, q)
        if g < 0:
            lo = om
        elif g > 0:
            hi = om
        else:  # nan: no sign to bisect on
            break
        om = _bisect(lo, hi)
    p, q, _, _ = _cloth_slip_at(dec, x, h, F * om)
    return om, np.False_, (p, q)  # G nan, or a cap below the halvings the bracket needs: not converged


def _cloth_slip_at(dec: _DecayOne, x: np.float64, h: np.float64, tau: np.float64
                   ) -> tuple[np.float64, np.float64, np.float64, np.float64]:
    """The magnitudes of the slip (y, z) after the impulse τ, settled as ``_cloth_normal_impulse_one`` settles the
    slip at the greatest compression (a turning slip: ``slip._WalkOne.settle`` from x and its H, its last step's
    residual corrected to first order; else the elementary decay), and the walk's x and H, a start for the next."""
    if dec.kind != _TURNS:
        p, q = dec.elementary(tau)
        return p, q, x, h
    return _WalkOne(dec, x, h).settle(tau)


def _cloth_normal_impulse_one(s0y: np.float64, s0z: np.float64, approach: np.float64, omega: np.float64, M: np.float64,
                              cy: np.float64, cz: np.float64, f: np.float64, coef: tuple[np.float64, ...]
                              ) -> tuple[np.float64, np.bool_, np.ndarray, tuple[np.float64, np.float64]]:
    """``_cloth_normal_impulse`` for one scene as numpy floats (``paths.Path.scalar``): the same formulas
    (``slip._DecayOne``, ``slip._WalkOne``, ``_cloth_high``, ``law6_G``, ``_cloth_guess``, ``_cloth_newton``, the
    bracket's tests), the same tests, bracket and limits, its masks as branches; the same numbers."""
    sy, sz = _sign(s0y), _sign(s0z)
    a0, b0 = abs(s0y), abs(s0z)
    N, _, _, By, Bz = coef
    AL, BE = M * cy, M * cz
    dec = _DecayOne(a0, b0, AL, BE)
    turns = dec.kind == _TURNS
    if turns:  # the slip at the greatest compression: walked from x = 1 to τ = f ω_c
        ac, bc, xc, hc = _WalkOne(dec, np.float64(1.0), dec.total).settle(f * omega)
    else:
        ac, bc = dec.elementary(f * omega)
    s_c = np.array((sy * ac, sz * bc))  # (``_stack`` of its numpy floats)
    Yc, Zc = a0 - ac, b0 - bc
    hi = _cloth_high(a0, b0, approach, N, By, Bz)
    g_c = law6_G(omega, Yc, Zc, Yc, Zc, approach, coef)
    if g_c >= 0:  # the impact ends at the greatest compression
        return omega, np.True_, s_c, (ac, bc)
    lo = omega
    om = _cloth_guess(g_c, lo, ac, bc, Yc, Zc, approach, f, AL, BE, coef, hi)
    walk = _WalkOne(dec, xc, hc) if turns else None
    p1 = q1 = om
    for _ in range(NEWTON_MAXITER):
        tau = f * om
        if walk is not None:
            p1, q1, settled = walk.advance(tau)
        else:
            (p1, q1), settled = dec.elementary(tau), True
        g, noise, dY, dZ, nxt = _cloth_newton(om, p1, q1, a0, b0, Yc, Zc, approach, f, AL, BE, coef)
        if settled:  # the bracket moves where the slip has converged for ω
            if g < 0:
                lo = maximum(lo, om)
            elif g > 0:
                hi = minimum(hi, om)
        if not _inside(nxt, lo, hi):
            nxt = _bisect(lo, hi)
        quiet = settled and _quiet(g, noise)
        if quiet:
            nxt = om
        if settled and _ends(nxt, om, quiet, lo, hi):
            return nxt, np.True_, s_c, _cloth_final(p1, q1, dY, dZ, nxt - om)
        om = nxt
    om, ok, final = _cloth_bisect(om, lo, hi, a0, b0, Yc, Zc, approach, f, AL, BE, coef)  # over NEWTON_MAXITER
    return om, ok, s_c, final


def _slip_ode(y0: np.ndarray, a_: float, b_: float, tau_max: float, rtol: float, solver: str) -> Any:
    """ds = −(α s_y, β s_z)/|s| dτ integrated over [0, τ_max] with a stop event: the slip as a function of τ
    (the solver's dense output, zero after the stop)."""
    from scipy.integrate import solve_ivp

    scale = float(np.hypot(*y0))

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        y0_, y1_ = y.tolist()  # floats: numpy's scalars cost 5× more per right-hand side
        n = max(float(np.hypot(y0_, y1_)), 1e-300)
        return [-a_ * y0_ / n, -b_ * y1_ / n]

    def stops(_t: float, y: np.ndarray, e0: np.ndarray = y0 / scale) -> float:
        return float(y @ e0)  # the slip along its initial direction: crosses zero cleanly when it stops

    stops.terminal = True
    sol = check(solve_ivp(bounded(rhs), (0.0, tau_max), y0, method=solver, rtol=rtol, atol=1e-14 * scale,
                          events=stops, dense_output=True))
    end = float(sol.t[-1])

    def slip_at(tau: float) -> np.ndarray:
        return np.zeros(2) if tau >= end and sol.status == 1 else sol.sol(min(tau, end))

    return slip_at


def _law6_ode_G(om: float, slip_at: Any, f: float, a0: float, b0: float, Yc: float, Zc: float, D: float,
                coef: tuple[float, ...]) -> float:
    """G(ω) of law (L) with the slip read off the integration (``_ode_impact``)."""
    s = slip_at(f * om)
    return float(law6_G(om, a0 - abs(float(s[0])), b0 - abs(float(s[1])), Yc, Zc, D, coef))


def _ode_impact(s0: np.ndarray, approach: np.ndarray, omega: np.ndarray, M: np.ndarray, cy: np.ndarray,
                cz: np.ndarray, f: np.ndarray, coef: tuple[np.ndarray, ...], rtol: float, solver: str
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The ODE path, scene by scene and independent of the slip's closed form: the slip integrated in the normal
    impulse (one integration per scene, to ω_hi of ``_cloth_normal_impulse``), and law (L) solved for ω1 in
    [ω_c, ω_hi] by Brent's method with the slip read off the integration's dense output. Returns ω1, the slip
    after, the slip at the greatest compression, and per scene whether Brent converged."""
    from scipy.optimize import brentq

    shape = np.shape(approach)
    coef = tuple(np.broadcast_to(x, shape) for x in coef)
    omega1 = np.zeros(shape)
    s1 = np.array(s0, dtype=float, copy=True)
    s_c = np.array(s0, dtype=float, copy=True)
    converged = np.ones(shape, dtype=bool)
    for idx in np.ndindex(shape):
        y0 = np.asarray(s0[idx], dtype=float)
        Mi, cyi, czi, fi, Di, wc = (float(x[idx]) for x in (M, cy, cz, f, approach, omega))
        ci = tuple(float(x[idx]) for x in coef)
        N, _, _, By, Bz = ci
        a0, b0 = abs(float(y0[0])), abs(float(y0[1]))
        if (a0 == 0 and b0 == 0) or fi == 0:  # no friction impulse: G = Nω² − 2Δω
            omega1[idx] = max(2 * Di / N, wc)
            continue
        hi = (Di + math.sqrt(Di * Di + 2 * N * (By * a0 * a0 + Bz * b0 * b0))) / N * (1 + 1e-12)
        slip_at = _slip_ode(y0, Mi * cyi, Mi * czi, fi * hi, rtol, solver)
        sc = slip_at(fi * wc)
        Yc, Zc = a0 - abs(float(sc[0])), b0 - abs(float(sc[1]))
        s_c[idx] = sc

        args = (slip_at, fi, a0, b0, Yc, Zc, Di, ci)
        if _law6_ode_G(wc, *args) >= 0:
            om, ok = wc, True
        else:
            om, info = brentq(_law6_ode_G, wc, hi, args=args, xtol=1e-15 * hi, rtol=1e-14, maxiter=200,
                              full_output=True)
            ok = info.converged
        omega1[idx], converged[idx] = om, ok
        s1[idx] = slip_at(fi * om)
    return omega1, s1, s_c, converged


def newton_euler_rates(M: float, Mp: float, R: float, Rp: float, k: float, kp: float, y: np.ndarray, f: float,
                       on_cloth: bool = False) -> np.ndarray:
    """d/dξ of the state y = (v, w, v′, w′) (12 on the last axis) of §V eqs (2), (2′) / §VI eqs (2), (2′), from
    Newton's and Euler's laws in vector form, not from the paper's component equations: the force on M per unit
    of the normal impulse ξ = ∫X dt is −x̂ − f u/|u| (u the slip of its contact point R x̂ on that of M′ at −R′x̂,
    tangential part), applied at R x̂ (moment of inertia M R²/k); M′ takes the opposite at −R′ x̂. On the cloth
    (§VI) its reaction at the foot, vertical and through the centre, cancels the vertical translations only
    (the friction on the cloth is neglected, as Coriolis does, n°13). A vanished slip gives no friction."""
    y = np.asarray(y, dtype=float)
    if y.ndim == 1:
        return _rates_one(M, Mp, R, Rp, k, kp, y, f, on_cloth)
    v, w, vp, wp = y[..., 0:3], y[..., 3:6], y[..., 6:9], y[..., 9:12]
    ex = np.zeros_like(v)
    ex[..., 0] = 1.0
    u = v + _cross(w, R * ex) - vp - _cross(wp, -Rp * ex)
    u[..., 0] = 0.0
    un = np.sqrt((u**2).sum(-1, keepdims=True))
    F = -ex - f * u / np.where(un > 0, un, 1.0)
    dv, dvp = F / M, -F / Mp
    if on_cloth:
        dv[..., 2] = 0.0
        dvp[..., 2] = 0.0
    dw = k / (M * R * R) * _cross(R * ex, F)
    dwp = kp / (Mp * Rp * Rp) * _cross(-Rp * ex, -F)
    return np.concatenate([dv, dw, dvp, dwp], axis=-1)


def _rates_one(M: float, Mp: float, R: float, Rp: float, k: float, kp: float, y: np.ndarray, f: float,
               on_cloth: bool) -> np.ndarray:
    """``newton_euler_rates`` for one state, in floats (the ODE calls it 10⁵ times): the same vector laws with the
    cross products by x̂ written out (w × R x̂ = R(0, w_z, −w_y), R x̂ × F = R(0, −F_z, F_y))."""
    _, vy, vz, _, wy, wz, _, pvy, pvz, _, pwy, pwz = y.tolist()  # floats; the x rates do not enter
    uy = vy + R * wz - pvy + Rp * pwz  # slip of M's contact point R x̂ on M′'s at −R′ x̂, tangential part
    uz = vz - R * wy - pvz - Rp * pwy
    un = math.hypot(uy, uz)
    Fx, Fy, Fz = -1.0, (-f * uy / un if un > 0 else 0.0), (-f * uz / un if un > 0 else 0.0)
    c, cp = k / (M * R), kp / (Mp * Rp)
    return np.array([Fx / M, Fy / M, 0.0 if on_cloth else Fz / M, 0.0, -c * Fz, c * Fy,
                     -Fx / Mp, -Fy / Mp, 0.0 if on_cloth else -Fz / Mp, 0.0, -cp * Fz, cp * Fy])


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b on the last axis, written out: ``np.cross`` costs 30 µs a call, most of an ODE step here."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


@dataclass(frozen=True)
class RigidImpact:
    """One scene integrated in the normal impulse: ``state(ξ)`` is (v, w, v′, w′) as 12 numbers, ``rates(ξ)``
    their derivatives; ``xi_stop`` is the impulse at which the slip stops (inf if it does not within the range)."""

    state: Any
    rates: Any
    xi_stop: float


def rigid_body_impulse(M: float, Mp: float, R: float, Rp: float, k: float, kp: float, v: ArrayLike, w: ArrayLike,
                       vp: ArrayLike, wp: ArrayLike, f: float, xi_max: float, on_cloth: bool = False,
                       rtol: float = 1e-13) -> RigidImpact:
    """One impact of §V (free) or §VI (``on_cloth``) integrated over the normal impulse ξ ∈ [0, ξ_max] from
    ``newton_euler_rates`` (DOP853, dense output), independent of every closed form and of law (6): a reference
    for the paper's derivation steps, eqs (1)–(10) of n°12–13. After the slip stops only the normal impulse
    acts (it moves no contact point tangentially), so the state is continued in closed form there."""
    from scipy.integrate import solve_ivp

    y0 = np.concatenate([np.asarray(x, dtype=float) for x in (v, w, vp, wp)])
    s0 = contact_slip(y0[0:3], y0[3:6], y0[6:9], y0[9:12], R, Rp)
    scale = float(np.max(np.abs(y0[[0, 1, 2, 6, 7, 8]]))) + float(np.max(np.abs(y0[[3, 4, 5, 9, 10, 11]]))) * R
    if f == 0 or float(np.hypot(*s0)) == 0:
        sol_end, status, sol = 0.0, 1, None
    else:
        def rhs(_t: float, y: np.ndarray) -> np.ndarray:
            return newton_euler_rates(M, Mp, R, Rp, k, kp, y, f, on_cloth)

        def stops(_t: float, y: np.ndarray) -> float:
            s = contact_slip(y[0:3], y[3:6], y[6:9], y[9:12], R, Rp)
            return float(s @ s0)

        stops.terminal = True
        sol = check(solve_ivp(bounded(rhs), (0.0, xi_max), y0, method="DOP853", rtol=rtol,
                              atol=1e-14 * scale, events=stops, dense_output=True))
        sol_end, status = float(sol.t[-1]), sol.status
    normal = newton_euler_rates(M, Mp, R, Rp, k, kp, y0, 0.0, on_cloth)  # rates under the normal impulse alone

    def state(xi: float) -> np.ndarray:
        if sol is not None and xi <= sol_end:
            return sol.sol(xi)
        base = y0 if sol is None else sol.sol(sol_end)
        return base + (xi - sol_end) * normal

    def rates(xi: float) -> np.ndarray:
        sliding = sol is not None and xi < sol_end
        return newton_euler_rates(M, Mp, R, Rp, k, kp, state(xi), f if sliding else 0.0, on_cloth)

    return RigidImpact(state, rates, sol_end if status == 1 else math.inf)
