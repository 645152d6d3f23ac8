"""Direct numerical integration of impacts: the truth the closed forms are checked and benchmarked against.

§I n°2 describes an impact as a compression, up to the instant at which the normal velocities are
equal, followed by a restitution. ``integrate_direct_impact`` integrates exactly that: two translating
masses pressed by a contact force that rises linearly with the overlap δ while they approach (stiffness
K) and falls along a stiffer line K/e² while they separate, leaving a permanent set (a Walton-type
hysteretic contact). The restitution phase gives back the fraction e² of the energy stored in
compression, so the relative velocity is reversed with the factor e (Newton's coefficient). Nothing of
eqs (6)–(9) is used here: comparing with ``impact.direct_impact`` at e = ``impact.newton_restitution``
checks the closed form against the equations of motion.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .budget import bounded, check, solve_ivp

__all__ = ["ReferenceImpact", "ReferencePlane", "integrate_cloth", "integrate_cue_impulse",
           "integrate_direct_impact", "integrate_flight", "integrate_plane_impact"]


@dataclass(frozen=True)
class ReferenceImpact:
    """Velocities after the impact and the number of right-hand-side evaluations used."""

    V1: np.ndarray
    V1p: np.ndarray
    nfev: np.ndarray
    method: str


def _one(M: float, Mp: float, V0: float, V0p: float, e: float, rtol: float, atol: float, solver: str = "DOP853"
         ) -> tuple[float, float, int]:
    """One impact. The state is (overlap δ, u, u′), with u = v − V_G and u′ = v′ − V_G the velocities relative to
    the centre of mass, V_G = V0′ + (M/(M + M′))(V0 − V0′) (a Galilean change: the contact force depends on the
    overlap alone). Not the absolute positions and velocities: the relative error control of ``solve_ivp`` on those
    is taken on |V0| or |x|, not on V0 − V0′ (2e-5 of error where |V0| ≈ 10⁵ (V0 − V0′)), the overlap δ = x − x′
    carries the rounding of x, and near the maximal compression u − u′ is lost in the rounding of u and u′ when
    they are large (the restitution of a nearly plastic impact, e|V0 − V0′| below the rounding of V0, never
    started: the separation was missed); about the centre of mass both velocities pass through 0 there.
    Newton for each body, M du/dt = −F, M′ du′/dt = F, with F = Kδ and K = μ (the compression lasts π/2), divided
    through by μ: du/dt = −(M′/(M + M′)) δ, du′/dt = (M/(M + M′)) δ; the two fractions stay within [0, 1] for
    every mass ratio (M′ = ∞: 1 and 0).

    The restitution (stiffness K/e², from the overlap δ_max down to the permanent set δ_max(1 − e²)) runs in its
    own scales: time τ = t/e and the elastic overlap over e, c = (δ − δ_p)/e, which starts at e δ_max (not the
    difference δ_max − δ_p, which the rounding of δ_max swamps once e² < 1e-16) and obeys the compression's
    equations in τ: dc/dτ = u − u′, du/dτ = −(M′/(M + M′)) c, du′/dτ = (M/(M + M′)) c. It lasts π/2 in τ whatever
    e, so neither its span nor its step shrink with e (they did, in t: the budget ran out for nearly plastic
    impacts, e ≲ 1e-5, when the separation event was lost in the rounding)."""
    if V0 <= V0p:  # no approach, no impact
        return V0, V0p, 0
    scale = V0 - V0p
    a, ap = (1.0, 0.0) if math.isinf(Mp) else (Mp / (M + Mp), M / (M + Mp))  # μ/M and μ/M′; M′ = ∞: immovable
    tol = [atol * scale] * 3  # δ is a speed times the time unit
    VG = V0p + ap * scale  # the centre of mass, which the impact does not move

    def motion(_t: float, y: np.ndarray) -> list[float]:
        d, u, up = y.tolist()  # floats: the same arithmetic at a third of the cost of numpy scalars
        return [u - up, -a * d, ap * d]

    def max_compression(_t: float, y: np.ndarray) -> float:
        return (float(y[1]) - float(y[2])) / scale

    max_compression.terminal = True
    max_compression.direction = -1
    # u − u′ crosses 0 at π/2, then again at 3π/2: a step under π/4 cannot step over the first crossing (loose
    # tolerances only: DOP853 at rtol 1e-10 steps less)
    sol = check(solve_ivp(bounded(motion), (0.0, 10.0), [0.0, a * scale, -ap * scale], rtol=rtol, atol=tol,
                          events=max_compression, method=solver, max_step=math.pi / 4))
    if sol.status != 1:
        raise ArithmeticError("the compression did not end (no maximal overlap found)")
    d_max, u, up = sol.y_events[0][0].tolist()
    nfev = sol.nfev
    if e == 0.0:  # nothing is given back: both move on with the common velocity u of §I n°3
        return VG + u, VG + up, nfev

    def separation(_t: float, z: np.ndarray) -> float:
        return float(z[0])  # c itself: e δ_max may be below the smallest normal float

    separation.terminal = True
    separation.direction = -1
    # a quarter period, π/2 in τ; the step bound keeps a step from stepping over the separation and the tension
    # beyond it (the linear spring would pull back)
    sol2 = check(solve_ivp(bounded(motion), (0.0, 10.0), [e * d_max, u, up], rtol=rtol, atol=tol,
                           events=separation, method=solver, max_step=math.pi / 16))
    if sol2.status != 1:
        raise ArithmeticError("the restitution did not end (no separation found)")
    _c, u, up = sol2.y_events[0][0].tolist()
    return VG + u, VG + up, nfev + sol2.nfev


def integrate_direct_impact(
    M: ArrayLike, Mp: ArrayLike, V0: ArrayLike, V0p: ArrayLike, e: ArrayLike, *, rtol: float = 1e-10,
    atol: float = 1e-12, solver: str = "DOP853",
) -> ReferenceImpact:
    """Integrate the two-phase contact (§I n°2) for each scene of the broadcast inputs; e in [0, 1]."""
    arrays = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (M, Mp, V0, V0p, e)))
    shape = arrays[0].shape
    flat = [a.ravel() for a in arrays]
    out = np.array([_one(*(float(a[i]) for a in flat), rtol, atol, solver) for i in range(flat[0].size)]).reshape(
        (*shape, 3))
    return ReferenceImpact(V1=out[..., 0], V1p=out[..., 1], nfev=out[..., 2].astype(int),
                           method=f"ODE, two-phase hysteretic contact ({solver})")


@dataclass(frozen=True)
class ReferencePlane:
    """Velocities after a sphere–plane impact, integrated in the normal-impulse variable (§III n°8, eqs 4)."""

    chi1: np.ndarray
    zeta1: np.ndarray
    p1: np.ndarray
    slip_stopped_at: np.ndarray  # fraction of the normal impulse at which the slip stopped (nan: never)
    method: str


def _plane_one(chi0: float, zeta0: float, p0: float, R: float, k: float, f: float, nu: float, rtol: float,
               solver: str = "DOP853") -> tuple[float, float, float, float]:
    end = (1.0 + nu) * abs(zeta0)  # total normal impulse per unit mass: ζ goes from ζ0 to −νζ0
    v0 = chi0 - p0 * R
    if v0 == 0.0 or f == 0.0 or end == 0.0:
        return chi0, -nu * zeta0, p0, float("nan")
    s = float(np.sign(v0))

    def slide(_pi: float, y: np.ndarray) -> list[float]:  # y = (χ, ζ, pR); eqs (4) with Z dt = M dπ
        return [-s * f, 1.0, s * k * f]

    def stops(_pi: float, y: np.ndarray) -> float:
        return s * (y[0] - y[2])

    stops.terminal = True
    sol = check(solve_ivp(bounded(slide), (0.0, end), [chi0, zeta0, p0 * R], events=stops, rtol=rtol,
                          atol=rtol * abs(zeta0), method=solver))
    y = sol.y[:, -1] if sol.status == 0 else sol.y_events[0][0]
    stopped = float("nan") if sol.status == 0 else float(sol.t_events[0][0] / end)
    if sol.status == 1:  # the slip has stopped: rolling needs no friction, only ζ still changes
        y = np.array([y[0], zeta0 + end, y[2]])
    return float(y[0]), float(y[1]), float(y[2] / R), stopped


def integrate_plane_impact(chi0: ArrayLike, zeta0: ArrayLike, p0: ArrayLike, *, R: ArrayLike, k: ArrayLike,
                           f: ArrayLike, nu: ArrayLike, rtol: float = 1e-11, solver: str = "DOP853"
                           ) -> ReferencePlane:
    """Integrate §III's impulse equations (4) scene by scene, stopping the slip when v_x reaches zero."""
    arrays = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (chi0, zeta0, p0, R, k, f, nu)))
    flat = [a.ravel() for a in arrays]
    out = np.array([_plane_one(*(float(a[i]) for a in flat), rtol, solver) for i in range(flat[0].size)])
    out = out.reshape((*arrays[0].shape, 4))
    return ReferencePlane(out[..., 0], out[..., 1], out[..., 2], out[..., 3],
                          "ODE in the normal impulse, slip stopped by an event (DOP853)")


def integrate_flight(chi: ArrayLike, zeta: ArrayLike, g: ArrayLike, *, rtol: float = 1e-11,
                     solver: str = "DOP853") -> tuple[np.ndarray, np.ndarray]:
    """Range and duration of the flight of the centre under gravity until it is back at its height (§III n°9)."""
    arrays = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (chi, zeta, g)))
    flat = [a.ravel() for a in arrays]
    res = []
    for c, z, gg in zip(*flat, strict=True):
        def rhs(_t: float, y: np.ndarray, gg: float = gg) -> list[float]:
            return [y[2], y[3], 0.0, -gg]

        def lands(_t: float, y: np.ndarray) -> float:
            return y[1]

        lands.terminal = True
        lands.direction = -1
        sol = check(solve_ivp(bounded(rhs), (0.0, 10.0 * z / gg + 1.0), [0.0, 0.0, c, z], events=lands, rtol=rtol,
                        atol=rtol * 1e-3, method=solver, first_step=1e-6 * z / gg))
        res.append((sol.y_events[0][0][0], sol.t_events[0][0]))
    out = np.array(res).reshape((*arrays[0].shape, 2))
    return out[..., 0], out[..., 1]


def integrate_cloth(vx: float, vy: float, wx: float, wy: float, R: float, k: float, f: float, g: float,
                    t_end: float, *, rtol: float = 1e-11, solver: str = "DOP853") -> tuple[object, float]:
    """Integrate §II's eqs (2) (friction opposite the current slip) until the slip vanishes, then roll.

    Returns a callable ``state(t) -> (x, y, vx, vy, wx, wy)`` valid on [0, t_end] and the time at which the
    slip vanished; raises ``ArithmeticError`` if it did not by t_end.
    """
    I_over_M = R * R / k

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        _x, _y, vx_, vy_, wx_, wy_ = y.tolist()  # floats: the same arithmetic, cheaper than numpy scalars
        ux, uy = vx_ - wy_ * R, vy_ + wx_ * R
        u = math.hypot(ux, uy)
        ex, ey = ux / u, uy / u
        return [vx_, vy_, -f * g * ex, -f * g * ey, -f * g * R * ey / I_over_M, f * g * R * ex / I_over_M]

    u0x, u0y = vx - wy * R, vy + wx * R
    u0 = math.hypot(u0x, u0y)

    def stops(_t: float, y: np.ndarray) -> float:  # the slip along its initial direction: crosses 0 cleanly
        return ((y[2] - y[5] * R) * u0x + (y[3] + y[4] * R) * u0y) / u0

    stops.terminal = True
    y0 = [0.0, 0.0, vx, vy, wx, wy]
    if u0 == 0.0:
        t1, sol = 0.0, None
    else:
        sol = check(solve_ivp(bounded(rhs), (0.0, t_end), y0, events=stops, rtol=rtol, atol=1e-14, dense_output=True,
                        method=solver))
        if not sol.t_events[0].size:
            raise ArithmeticError(f"§II: the slip did not stop by t = {t_end:g} s (slip {u0:g} m/s)")
        t1 = float(sol.t_events[0][0])
    end = sol.sol(t1) if sol is not None and t1 == t1 else np.array(y0)

    def state(t: float) -> np.ndarray:
        if sol is not None and (t1 != t1 or t <= t1):
            return sol.sol(t)
        s = np.array(end, dtype=float)  # rolling without resistance: uniform motion, spins constant
        dt = t - (t1 if t1 == t1 else 0.0)
        s[0] += s[2] * dt
        s[1] += s[3] * dt
        return s

    return state, t1


def integrate_cue_impulse(i: float, a: float, b: float, c: float, R: float, k: float, f: float, M: float,
                          P_end: float, *, moment_a_term: bool = True, rtol: float = 1e-10,
                          solver: str = "LSODA") -> np.ndarray:
    """Integrate §VII's eqs (3) in the cue impulse P from a ball at rest, with the cloth friction
    f sin i dP opposite the *current* slip (regularised near zero slip, so a held contact is found, not
    assumed). Returns (χ, η, n, p, q) at P_end. Nothing of eqs (5)–(7) is used."""
    si, ci = math.sin(i), math.cos(i)
    tau = np.array([-b * si, c * ci + (a * si if moment_a_term else 0.0), -b * ci])
    inertia = M * R * R / k
    scale = P_end / M
    delta = 1e-9 * scale

    tau0, tau1, tau2 = tau.tolist()

    def rhs(_P: float, y: np.ndarray) -> np.ndarray:
        chi, eta, n, p, _q = y.tolist()  # floats: the same arithmetic at a third of the cost of numpy scalars
        ux, uy = chi - p * R, eta + n * R
        norm = math.sqrt(ux * ux + uy * uy + delta * delta)
        jx, jy = f * si * ux / norm, f * si * uy / norm
        return np.array([(ci - jx) / M, -jy / M, (tau0 - R * jy) / inertia, (tau1 + R * jx) / inertia, tau2 / inertia])

    sol = check(solve_ivp(bounded(rhs), (0.0, P_end), np.zeros(5), method=solver, rtol=rtol, atol=1e-12 * scale))
    return sol.y[:, -1]
