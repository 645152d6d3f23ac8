"""§II n°7 of Résal (1883): a ball sliding on the cloth with friction f, then rolling.

Frame of the paper: xOy the cloth, Oz upward; χ, η the velocity of the centre, n = ω_x and p = ω_y the
rotations about the horizontal axes (q = ω_z plays no part). The contact point slips at (eq. 1)
v_x = χ − pR, v_y = η + nR. With the friction f M g opposite the slip û and the moment of inertia M R²/k,
eqs (2) give dv/dt = −(1 + k) f g û: the slip keeps its direction and its speed falls linearly, so the
centre describes Euler's parabola (eqs 3–5) until the slip vanishes at t1 = v0/((1 + k) f g), and then
rolls along the tangent. After rolling starts the paper stops; here an optional rolling resistance f_r
decelerates the centre at f_r g until it stops (f_r = 0: uniform motion, the paper's case).

Coriolis's theorem (footnote of n°7): the point of the vertical through C at height R/k above C keeps a
constant velocity; a horizontal stroke at that height gives immediate rolling.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .budget import solve_ivp
from .paths import PathCode, Regime, batch_arrays, codes, pick

__all__ = ["ClothMotion", "centre_of_oscillation", "pendulum_centre_height", "point_velocity", "rigid_jac", "rigid_rhs",
           "slide", "state_at"]
_REGIMES = np.array([Regime.NO_SLIP, Regime.GRIP], dtype=np.int8)  # by whether the ball slips at first


@dataclass(frozen=True)
class ClothMotion:
    """Onset of rolling for each scene: time, place (from the start) and velocity of the centre."""

    t_roll: np.ndarray
    x_roll: np.ndarray
    y_roll: np.ndarray
    vx_roll: np.ndarray
    vy_roll: np.ndarray
    slip0: np.ndarray  # initial slip speed v0
    method: str
    path: np.ndarray
    regime: np.ndarray  # GRIP: slides, then rolls; NO_SLIP: already rolling
    label: str


def _slip(vx: np.ndarray, vy: np.ndarray, wx: np.ndarray, wy: np.ndarray, R: np.ndarray) -> tuple[np.ndarray, ...]:
    ux, uy = vx - wy * R, vy + wx * R  # eq. (1)
    u = np.hypot(ux, uy)
    safe = pick(u > 0, u, 1.0)
    return ux / safe, uy / safe, u


def slide(vx: ArrayLike, vy: ArrayLike, wx: ArrayLike, wy: ArrayLike, *, R: ArrayLike, k: ArrayLike, f: ArrayLike,
          g: ArrayLike) -> ClothMotion:
    """Time, place and velocity at which rolling starts (§II n°7: t1 = v0/(fg(1 + k)) and the point of the
    parabola reached then). A ball already rolling (v0 = 0) skips the sliding phase: t1 = 0."""
    vx, vy, wx, wy, R, k, f, g = batch_arrays(vx, vy, wx, wy, R, k, f, g)
    ex, ey, u = _slip(vx, vy, wx, wy, R)
    t1 = u / ((1 + k) * f * g)
    t1_2 = t1 * t1  # what numpy computes for t1**2
    x1 = vx * t1 - 0.5 * f * g * ex * t1_2
    y1 = vy * t1 - 0.5 * f * g * ey * t1_2
    return ClothMotion(t1, x1, y1, vx - f * g * ex * t1, vy - f * g * ey * t1, u, "exact",
                       codes(np.shape(u), PathCode.EXACT), np.asarray(_REGIMES[(u > 0).astype(np.intp)]),
                       "closed form, §II eqs (3)-(4)")


def state_at(t: ArrayLike, vx: ArrayLike, vy: ArrayLike, wx: ArrayLike, wy: ArrayLike, *, R: ArrayLike,
             k: ArrayLike, f: ArrayLike, g: ArrayLike, f_roll: ArrayLike = 0.0
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Position (x, y) and velocity (vx, vy) of the centre at times t (from the start, at the origin).

    The parameters broadcast into a batch of scenes; the times form trailing axes: the result has the
    shape batch + t.shape (a 1-D t gives one trajectory per scene). Sliding: Euler's parabola; rolling: the
    tangent, decelerated by f_roll·g until the ball stops (an addition the paper leaves aside).
    """
    t = np.asarray(t, dtype=float)
    m = slide(vx, vy, wx, wy, R=R, k=k, f=f, g=g)
    params = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (vx, vy, wx, wy, R, k, f, g, f_roll)))
    extra = (None,) * t.ndim
    vx, vy, wx, wy, R, k, f, g, fr = (a[(..., *extra)] for a in params)
    t1, x1, y1, wx1, wy1 = (np.broadcast_to(a, params[0].shape)[(..., *extra)] for a in
                            (m.t_roll, m.x_roll, m.y_roll, m.vx_roll, m.vy_roll))
    ex, ey, _ = _slip(vx, vy, wx, wy, R)
    ts = np.minimum(t, t1)
    xs = vx * ts - 0.5 * f * g * ex * ts**2
    ys = vy * ts - 0.5 * f * g * ey * ts**2
    vxs, vys = vx - f * g * ex * ts, vy - f * g * ey * ts
    # rolling: speed s1 falls at f_roll g; it stops at s1/(f_roll g)
    s1 = np.hypot(wx1, wy1)
    dx, dy = np.where(s1 > 0, wx1 / np.where(s1 > 0, s1, 1), 0.0), np.where(s1 > 0, wy1 / np.where(s1 > 0, s1, 1), 0.0)
    tr = np.maximum(t - t1, 0.0)
    stop = np.where(fr > 0, s1 / np.where(fr > 0, fr * g, 1.0), np.inf)
    tr = np.minimum(tr, stop)
    dist = s1 * tr - 0.5 * fr * g * tr**2
    speed = np.where(t - t1 >= stop, 0.0, s1 - fr * g * tr)
    rolling = t > t1
    x = np.where(rolling, x1 + dx * dist, xs)
    y = np.where(rolling, y1 + dy * dist, ys)
    return x, y, np.where(rolling, dx * speed, vxs), np.where(rolling, dy * speed, vys)


def centre_of_oscillation(R: ArrayLike, k: ArrayLike = 2.5) -> np.ndarray:
    """Height above the centre of the point whose velocity stays constant while sliding (footnote of n°7):
    the point of the vertical at height h moves at (χ + hp, η − hn), whose derivative is −fg û (1 − kh/R),
    zero for h = R/k; a horizontal stroke at that height gives v = Rω, immediate rolling."""
    return np.asarray(R, dtype=float) / np.asarray(k, dtype=float)


# -- the ball as a rigid body in three dimensions (checks of n°7's premises and of eqs (1)-(2)) -----------------


def _cross(a0: Any, a1: Any, a2: Any, b0: Any, b1: Any, b2: Any) -> tuple[Any, Any, Any]:
    """The vector product a × b by components (floats, or arrays of one shape): written out, since ``np.cross``
    costs some 30 µs a call and the integrations of n°7 call it twice per right-hand side."""
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


def point_velocity(v: ArrayLike, w: ArrayLike, h: ArrayLike) -> np.ndarray:
    """Velocity of the point of the vertical through C at height h above C (h = −R: the contact point), from the
    kinematics of a rigid body, v + ω × (h e_z); v and ω are 3-vectors on the last axis. Nothing of eq. (1) or of
    the footnote of n°7 is used: comparing checks them."""
    v, w = np.asarray(v, dtype=float), np.asarray(w, dtype=float)
    h = np.asarray(h, dtype=float)
    c = _cross(w[..., 0], w[..., 1], w[..., 2], 0.0 * h, 0.0 * h, h)  # ω × (h e_z)
    return v + np.stack(np.broadcast_arrays(*c), axis=-1)


def rigid_rhs(state: ArrayLike, *, R: float, k: float, f: float, g: float, u_reg: float = 0.0) -> np.ndarray:
    """Newton–Euler equations of a ball of radius R and moment of inertia M R²/k about every diameter, resting on
    the cloth (normal reaction M g) and rubbed at its contact point by Coulomb friction f M g opposite the slip.
    ``state`` = (position, velocity of C, rotation ω), 9 numbers; the torque is (−R e_z) × F, written with the
    vector product, not with the paper's components, so that eqs (2) are checked, not copied. ``u_reg`` > 0 makes
    the friction f M g u/√(|u|² + u_reg²), smooth: a rolling ball then stays rolling without the switch of an event
    (the check of « le centre C décrira la tangente »); u_reg = 0 is the sliding law itself. On floats (the state
    read once): a right-hand side costs 1.3 µs, not 34 with numpy's vector products on 3-vectors."""
    _x, _y, _z, vx, vy, vz, wx, wy, wz = np.asarray(state, dtype=float).tolist()
    cx, cy, _cz = _cross(wx, wy, wz, 0.0, 0.0, -R)  # ω × (−R e_z)
    ux, uy = vx + cx, vy + cy  # the contact point does not move vertically: v_z = 0 on the cloth
    scale = math.sqrt(ux * ux + uy * uy + u_reg * u_reg)
    fx, fy = (-f * g * ux / scale, -f * g * uy / scale) if scale > 0 else (0.0, 0.0)  # per unit mass
    tx, ty, tz = _cross(0.0, 0.0, -R, fx, fy, 0.0)  # the torque (−R e_z) × F per unit mass
    return np.array([vx, vy, vz, fx, fy, 0.0, tx * k / R**2, ty * k / R**2, tz * k / R**2])


def rigid_jac(state: ArrayLike, *, R: float, k: float, f: float, g: float, u_reg: float) -> np.ndarray:
    """Jacobian of ``rigid_rhs`` with u_reg > 0, for the implicit solver of the stiff rolling phase (a difference
    quotient steps over the regularisation's width and stalls Newton's iteration)."""
    s = np.asarray(state, dtype=float)
    u = point_velocity(s[3:6], s[6:9], -R)[:2]
    S = float(np.sqrt(u @ u + u_reg**2))
    dF_du = -f * g * (np.eye(2) / S - np.outer(u, u) / S**3)
    du_ds = np.zeros((2, 9))
    du_ds[0, 3], du_ds[0, 7], du_ds[1, 4], du_ds[1, 6] = 1.0, -R, 1.0, R  # u = (χ − R ω_y, η + R ω_x)
    dF = dF_du @ du_ds
    J = np.zeros((9, 9))
    J[0:3, 3:6] = np.eye(3)
    J[3:5] = dF
    J[6] = k / R * dF[1]  # torque (−R e_z) × F = (R F_y, −R F_x, 0), over R²/k
    J[7] = -k / R * dF[0]
    return J


def pendulum_centre_height(R: float, k: float, amplitude: float = 1e-4) -> float:
    """Height above C of the centre of oscillation of the ball hung from its contact point (a compound pendulum
    pivoting about the horizontal axis through the foot): the length L of the simple pendulum with the same small
    oscillations, L = I_foot/(M R), minus R, with I_foot = M R²/k + M R² (Huygens's parallel axes). Solved here as
    the period of the pendulum equation integrated at a small amplitude, L = g (T/2π)², corrected to first order in
    the amplitude (T = T₀ (1 + θ₀²/16)); the footnote of n°7 names this point h = R/k."""
    g = 9.81
    omega2 = g * R / (R**2 / k + R**2)

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        return [y[1], -omega2 * np.sin(y[0])]

    def down(_t: float, y: np.ndarray) -> float:
        return y[0]

    down.direction = -1.0
    quarter = 0.5 * np.pi / np.sqrt(omega2)
    sol = solve_ivp(rhs, (0.0, 8 * quarter), [amplitude, 0.0], events=down, rtol=1e-12, atol=1e-18, method="DOP853")
    T = 4.0 * float(sol.t_events[0][0]) / (1.0 + amplitude**2 / 16.0)
    return g * (T / (2 * np.pi)) ** 2 - R
