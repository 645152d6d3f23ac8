"""§VII n°14 of Résal (1883): the stroke of a cue inclined to the cloth, hitting the ball off centre.

Frame of the paper (§II): Cx horizontal in the vertical plane of the cue, Cz upward, Cy completing it; the
cue (mass M′, speed V′ along its axis) points along d = (cos i, 0, −sin i) and strikes the ball (mass M,
radius R, moment of inertia M R²/k, at rest) at the point (a, b, c) of its surface, a < 0. Premises of
n°14: the force F of the cue lies along its axis (no percussion on the hands, no sliding of the tip: the
axis lies inside the tip's friction cone, else *fausse queue*); the ball does not leave the cloth, which
takes the pressure F sin i and opposes the slip with f F sin i.

Derivation in the cue impulse P = ∫F dt (eqs 2–3). The moment of F about C is r × d P =
(−b sin i, c cos i + a sin i, −b cos i) P. The slip on the cloth, u = (χ − pR, η + nR), grows from zero as
du = (dP/M)[D − (1 + k) j], with D = (cos i − (k/R)(c cos i + a sin i), −(k/R) b sin i) and j the cloth
friction per unit P. It keeps the direction of D (Résal's constant γ, eq. 5) and j = f sin i D̂ while
|D| > (1 + k) f sin i; otherwise the cloth holds the contact (j = D/(1 + k), no slip). Everything after the
stroke is linear in P (eq. 7). P itself follows from Résal's law (6) written at the end of the stroke and at
the greatest compression (ε = ε′ = 1), the friction terms being the same (eqs 9, 9′, 10): ω1 = 2Aω/(A +
ε(A − 1) + ε′), with A − 1 the ball's vis viva over M′ω1², and ω the cue speed lost at the greatest
compression, when the cue and the contact point have the same normal velocity (eqs 11–12).

Where this departs from the printed text (``method="resal"`` keeps Résal's choices, ``"exact"`` does not):
1. Résal's eq. (2) gives the moment about Cy as F c cos i, without the term F a sin i, and his eq. (5) for γ
   follows from that; ``exact`` keeps the term.
2. Eq. (12) ends the compression when the cue and the contact point have the same velocity along the
   *normal*, while the impulse acts along the *axis*. For an off-centre stroke this makes the cue give the
   ball more vis viva than it loses: with i = 0, ε = 0 and an offset s = √(b² + c²)/R, A ω = V′0 (1 + μ(1 +
   k s²))/(1 + μ) > V′0, and the friction term of (9′), 2V′0 − 2Aω, turns negative. ``exact`` ends the
   compression when the relative velocity along the line of the impulse vanishes, which gives the ball's
   effective mass along the axis, ω = V′0/(1 + M′ d·K·d) (K: the ball's velocity at the contact per unit
   impulse, cloth friction included); energy is then never gained (tests).
3. Eq. (11) prints cos φ = −(a cos i + c sin i)/R; with the cue pointing down, as the pressure F sin i on the
   cloth requires, it is −(a cos i − c sin i)/R, used by both paths.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["CueStroke", "ball_point_velocity", "contact_point", "cue_axis", "cue_moment", "cue_stroke", "miscue_angle",
           "stroke_per_impulse"]

from .paths import PathCode, Regime, as_floats, batch_arrays, codes, maximum, pick, result

METHODS = ("exact", "resal")
_REGIMES = np.array([Regime.GRIP, Regime.SLIDE], dtype=np.int8)  # by whether the ball slides on the cloth
_GRIP, _SLIDE = _REGIMES  # (numpy's int8: one scene's regime, chosen with ``pick``)
_CODES = {m: PathCode[m.upper()] for m in METHODS}
_ZERO = np.float64(0.0)


@dataclass(frozen=True)
class CueStroke:
    """State of the ball just after the stroke, the cue's speed after, and the stroke's geometry."""

    chi1: np.ndarray  # centre velocity along Cx
    eta1: np.ndarray  # along Cy
    n1: np.ndarray  # rotation about Cx (ω_x)
    p1: np.ndarray  # about Cy (ω_y)
    q1: np.ndarray  # about Cz (ω_z)
    V1p: np.ndarray  # cue speed after the stroke
    omega1: np.ndarray  # cue speed lost, eq. (6)
    omega: np.ndarray  # cue speed lost at the greatest compression, eq. (12)
    A: np.ndarray  # eq. (8)
    gamma: np.ndarray  # direction of the slip on the cloth, eq. (5)
    cos_phi: np.ndarray  # angle of the cue axis with the normal at the contact, eq. (11)
    method: str
    path: np.ndarray
    regime: np.ndarray  # SLIDE: the ball slides on the cloth during the stroke; GRIP: the cloth holds it
    label: str


def contact_point(b: ArrayLike, c: ArrayLike, R: ArrayLike) -> np.ndarray:
    """a of the contact point (a, b, c) on the back of the ball: a = −√(R² − b² − c²)."""
    b, c, R = as_floats(b, c, R)
    return -np.sqrt(maximum(R * R - b * b - c * c, _ZERO))


def miscue_angle(f_tip: ArrayLike) -> np.ndarray:
    """The friction angle of the tip, atan f_tip (footnote of n°14): beyond it, *fausse queue*."""
    return np.arctan(np.asarray(f_tip, dtype=float))


def stroke_per_impulse(i: ArrayLike, b: ArrayLike, c: ArrayLike, *, R: ArrayLike, k: ArrayLike, f: ArrayLike,
                       M: ArrayLike, method: str = "exact") -> dict[str, np.ndarray]:
    """Velocity, rotation and slip of the ball per unit cue impulse P (eqs 3, 5, 7), arrays over the batch."""
    per = _per_impulse(i, b, c, R=R, k=k, f=f, M=M, method=method, slip=True)
    return {"a": per["a"], "v": np.stack(per["v"]), "w": np.stack(per["w"]), "u": np.stack(per["u"]),
            "gamma": per["gamma"], "slides": per["slides"], "cos_phi": per["cos_phi"], "d_K_d": per["d_K_d"]}


def _per_impulse(i: ArrayLike, b: ArrayLike, c: ArrayLike, *, R: ArrayLike, k: ArrayLike, f: ArrayLike,
                 M: ArrayLike, method: str, slip: bool = False) -> dict[str, Any]:
    """``stroke_per_impulse`` with the vectors as tuples of their components (eqs 3, 5, 7), which ``cue_stroke``
    reads without stacking them; the products of vectors written out as ``np.cross`` computes them. The slip on
    the cloth per unit P (``u``, eq. 7), which ``cue_stroke`` does not read, only with ``slip``."""
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    i, b, c, R, k, f, M = batch_arrays(i, b, c, R, k, f, M)
    a = contact_point(b, c, R)
    si, ci = np.sin(i), np.cos(i)
    # the moment of F about C, eq. (2): (tx, ty, tz)
    tx, ty, tz = -b * si, c * ci + (0.0 if method == "resal" else a * si), -b * ci
    kR = k / R
    Dx, Dy = ci - kR * ty, kR * tx
    Dn = np.hypot(Dx, Dy)
    safe = pick(Dn > 0, Dn, 1.0)
    fric = f * si
    k1 = 1 + k
    slides = Dn > k1 * fric
    jn = pick(slides, fric, Dn / k1)
    jx, jy = jn * (Dx / safe), jn * (Dy / safe)  # the cloth's friction impulse per unit P
    vx, vy = (ci - jx) / M, -jy / M
    zero = 0.0  # the zero components of (v, 0) and d: a number, which broadcasts as np.zeros_like(jx) would
    kI = k / (M * R * R)
    wx, wy, wz = kI * (tx + R * -jy), kI * (ty + R * jx), kI * (tz + R * zero)
    u = ((Dx - k1 * jx) / M, (Dy - k1 * jy) / M) if slip else None
    # velocity of the ball's point of contact with the cue per unit P, (v, 0) + w × (a, b, c), along d
    cx, cy, cz = vx + (wy * c - wz * b), vy + (wz * a - wx * c), zero + (wx * b - wy * a)
    d_K_d = cx * ci + cy * zero + cz * -si
    return {"a": a, "v": (vx, vy), "w": (wx, wy, wz), "u": u, "gamma": np.arctan2(Dy, Dx), "slides": slides,
            "cos_phi": -(a * ci - c * si) / R, "d_K_d": d_K_d}


def cue_stroke(M: ArrayLike, Mp: ArrayLike, V0p: ArrayLike, i: ArrayLike, b: ArrayLike, c: ArrayLike, *,
               R: ArrayLike, k: ArrayLike, f: ArrayLike, eps: ArrayLike, epsp: ArrayLike,
               method: str = "exact") -> CueStroke:
    """The stroke of §VII n°14 (module docstring): ``exact`` or ``resal`` (as printed)."""
    path = method
    per = _per_impulse(i, b, c, R=R, k=k, f=f, M=M, method=path)
    M, Mp, V0p, R, k, eps, epsp = batch_arrays(M, Mp, V0p, R, k, eps, epsp)
    (vx, vy), (wx, wy, wz) = per["v"], per["w"]
    # the ball's vis viva per P² (x * x: what numpy computes for x**2)
    Q = M * (vx * vx + vy * vy) + (M * R * R / k) * (wx * wx + wy * wy + wz * wz)
    A = 1.0 + Mp * Q
    if path == "resal":  # eq. (12): equal velocities along the normal at the greatest compression
        n_hat_dot_v = (per["a"] * vx + np.asarray(b, dtype=float) * vy) / R
        omega = V0p * per["cos_phi"] / (per["cos_phi"] - Mp * n_hat_dot_v)
    else:  # equal velocities along the line of the impulse (the cue axis d)
        omega = V0p / (1.0 + Mp * per["d_K_d"])
    omega1 = 2 * A * omega / (A + eps * (A - 1) + epsp)  # eq. (10)
    P = Mp * omega1
    label = ("Résal's eqs (2)-(12) as printed (moment about Cy without a sin i; compression ended along the "
             "normal)" if path == "resal" else
             "closed form, §VII eqs (2)-(10) with the full moment of F, compression ended along the cue axis")
    regime = np.asarray(pick(per["slides"], _SLIDE, _GRIP))
    return result(CueStroke, chi1=P * vx, eta1=P * vy, n1=P * wx, p1=P * wy, q1=P * wz, V1p=V0p - omega1,
                  omega1=omega1, omega=omega, A=A, gamma=per["gamma"], cos_phi=per["cos_phi"], method=method,
                  path=codes(omega1.shape, _CODES[method]), regime=regime, label=label)


def cue_axis(i: ArrayLike) -> np.ndarray:
    """The unit vector d = (cos i, 0, −sin i) along which the cue moves and pushes (§VII n°14: the pressure on the
    cloth is F sin i, so the cue points down); leading axis: the components."""
    i = np.asarray(i, dtype=float)
    return np.stack([np.cos(i), np.zeros_like(i), -np.sin(i)])


def cue_moment(i: ArrayLike, a: ArrayLike, b: ArrayLike, c: ArrayLike) -> np.ndarray:
    """Moment about the centre C of a unit force along the cue axis through the contact point (a, b, c):
    r × d = (−b sin i, c cos i + a sin i, −b cos i) (the full moment of eq. 2, with the term a sin i)."""
    i, a, b, c = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (i, a, b, c)))
    return np.cross(np.stack([a, b, c]), cue_axis(i), axis=0)


def ball_point_velocity(chi: ArrayLike, eta: ArrayLike, n: ArrayLike, p: ArrayLike, q: ArrayLike,
                        r: ArrayLike) -> np.ndarray:
    """Velocity of the ball's material point at r (from the centre) for a centre velocity (χ, η, 0) and a rotation
    (n, p, q): v + ω × r. The foot of the ball, r = (0, 0, −R), gives the slip of eq. (1)."""
    chi, eta, n, p, q = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (chi, eta, n, p, q)))
    r = np.asarray(r, dtype=float)
    v = np.stack([chi, eta, np.zeros_like(chi)])
    return v + np.cross(np.stack([n, p, q]), r, axis=0)
