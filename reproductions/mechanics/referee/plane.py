"""A referee for §III n°8 of Résal (1883): a free sphere striking a fixed plane, from Newton–Euler's laws alone.

It shares no code with the paths it checks (``plane``, ``reference``, ``registry``): it imports only ``budget``.

Frame and scene (SI units; the registry's ``plane-impact`` scene): z along the outward normal of the plane, x along
the tangential velocity χ0 of the centre; the centre's velocity v = (χ, η, ζ) in m/s, ζ0 < 0 while approaching;
the rotation ω = (n, p, q) in rad/s; radius R (m), moment of inertia M R²/k about any diameter, Coulomb friction f,
yield ν of the normal velocity. The scene has η0 = 0, n0 = q0 = 0 and ω0 = (0, p0, 0). The contact point is at
r = −R ẑ from the centre, so the slip (velocity of the body's point in contact) is

    u = v + ω × r,     u_x = χ − pR,  u_y = η + nR   (Résal's eq. 1),

and its tangential part u_t = u − (u·ẑ)ẑ.

Impulse variable. During the impact the plane acts on the sphere at the contact by a normal force Z ẑ, Z ≥ 0 (the
plane pushes, never pulls), and a tangential friction F; gravity and every finite force are negligible. The normal
impulse per unit mass π = (1/M)∫Z dt is then non-decreasing in time, and strictly increasing while the bodies are
pressed, so it serves as the independent variable: dπ/dπ = 1 > 0 is the statement Z ≥ 0. Writing F dt = M λ dπ
(λ tangential, |λ| ≤ f by Coulomb), Newton for the centre and Euler about it give, for the six velocity components,

    dv/dπ = ẑ + λ,                                  (Newton, 3 components)
    dω/dπ = (k/R²) r × (ẑ + λ),                      (Euler, I = M R²/k, 3 components)

integrated in vector form by scipy's ``solve_ivp`` (DOP853, rtol 1e-13, atol rtol × the scene's speed scale for
v and that over R for ω), in s = π/|ζ0| (the impulse in units of the approach speed, so that the events' absolute
root tolerance is relative to the scene).

Phase 1, sliding (u_t ≠ 0): Coulomb's law, friction opposite the current slip, full magnitude, no regularisation:
λ = −f u_t/|u_t|, û recomputed from the state at every evaluation (the 3-D slip is free to turn). Terminal event:
the slip projected on its initial direction, u_t·ê0, crosses zero (the slip stops; it does not turn here, so the
projection crosses cleanly where |u_t| itself only touches zero). A trial stage of the solver that lands on
an exactly zero slip, where û is undefined, gets the friction of phase 2 (Coulomb's law is set-valued there).

Phase 2, sticking (u_t = 0): the tangential impulse rate λ that keeps du_t/dπ = 0 solves the linear system the
vector equations give, du_t/dπ = A λ + b, where b and the 2×2 A are evaluated from the equations above (with
λ = 0, e_x, e_y), not written down. It is computed, checked to lie in Coulomb's cone |λ| ≤ f (else the contact
could not stick and the computation stops with an ``ArithmeticError``), and used. Here r ∥ ẑ, so b = 0 and λ = 0:
rolling needs no friction at all, which the referee finds rather than assumes.

End of the impact, the law the model declares (n°8): ζ1 = −ν ζ0; a terminal event on ζ + ν ζ0 crossing zero
upwards, in whichever phase it happens. Outputs: χ1, ζ1 and p1 (the components along x, z of v and along y of ω).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..budget import bounded, check, solve_ivp

__all__ = ["RefereePlane", "solve", "stick_rate"]

LABEL = "referee: Newton–Euler for v and ω in the normal impulse, Coulomb slip, stop event, stick (DOP853)"
_SPAN = 4.0  # in s = π/|ζ0|: past any end of the impact (ζ reaches −νζ0 at s = 1 + ν ≤ 2); a guard


@dataclass(frozen=True)
class RefereePlane:
    """Velocities after the impact; ``stopped``: the slip stopped during the impact (the stop event fired);
    ``nfev``: right-hand-side evaluations of the two phases."""

    chi1: np.ndarray
    zeta1: np.ndarray
    p1: np.ndarray
    stopped: np.ndarray  # bool
    nfev: np.ndarray
    label: str


Vec = tuple[float, float, float]
_NORMAL: Vec = (0.0, 0.0, 1.0)


def _cross(a: Vec, b: Vec) -> Vec:
    """a × b on float triples (``np.cross`` costs some 30 µs a call; the right-hand side calls this twice)."""
    return a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]


def _tangential(u: Vec) -> Vec:
    """u − (u·ẑ) ẑ."""
    un = u[0] * _NORMAL[0] + u[1] * _NORMAL[1] + u[2] * _NORMAL[2]
    return u[0] - un * _NORMAL[0], u[1] - un * _NORMAL[1], u[2] - un * _NORMAL[2]


def _slip(y: list[float], r: Vec) -> Vec:
    """The tangential slip u_t of the contact point: v + ω × r, its normal part removed."""
    c = _cross((y[3], y[4], y[5]), r)
    return _tangential((y[0] + c[0], y[1] + c[1], y[2] + c[2]))


def _rates(lam: Vec, r: Vec, k: float, R: float) -> list[float]:
    """(dv/dπ, dω/dπ) for the tangential impulse rate λ, six numbers: Newton, dv/dπ = ẑ + λ, and Euler about the
    centre, dω/dπ = (k/R²) r × (ẑ + λ), per unit normal impulse and per unit mass."""
    push = (_NORMAL[0] + lam[0], _NORMAL[1] + lam[1], _NORMAL[2] + lam[2])
    turn = _cross(r, push)
    g = k / (R * R)
    return [push[0], push[1], push[2], g * turn[0], g * turn[1], g * turn[2]]


def stick_rate(k: float, R: float, f: float) -> Vec:
    """The tangential impulse rate λ (per unit normal impulse) that keeps the slip at zero, from the vector
    equations: du_t/dπ = A λ + b, A and b evaluated by the equations at λ = 0, e_x, e_y (affine in λ), λ = −A⁻¹b.
    Raises ``ArithmeticError`` outside Coulomb's cone |λ| ≤ f."""
    r = (0.0, 0.0, -R)

    def slip_rate(lam: Vec) -> np.ndarray:  # the slip's rate is the slip of the rates: u is linear in (v, ω)
        return np.array(_slip(_rates(lam, r, k, R), r)[:2])

    b = slip_rate((0.0, 0.0, 0.0))
    A = np.column_stack([slip_rate((1.0, 0.0, 0.0)) - b, slip_rate((0.0, 1.0, 0.0)) - b])
    lx, ly = np.linalg.solve(A, -b).tolist()
    if math.hypot(lx, ly) > f:
        raise ArithmeticError(f"sticking needs a tangential impulse rate ({lx}, {ly}) beyond Coulomb's cone f = {f}")
    return lx, ly, 0.0


def _one(chi0: float, zeta0: float, p0: float, R: float, k: float, f: float, nu: float, rtol: float
         ) -> tuple[float, float, float, bool, int]:
    y0 = [chi0, 0.0, zeta0, 0.0, p0, 0.0]  # v0 = (χ0, 0, ζ0), ω0 = (0, p0, 0)
    r = (0.0, 0.0, -R)  # the contact point from the centre
    S = math.hypot(chi0, zeta0) + abs(p0 * R)  # the scene's speed scale
    J = abs(zeta0)  # impulse unit: π = J s
    atol = [rtol * S] * 3 + [rtol * S / R] * 3
    lam_stick = stick_rate(k, R, f)  # zero here: computed, checked in Coulomb's cone, and used below

    def ends(_s: float, y: np.ndarray) -> float:  # the declared law: ζ reaches −νζ0
        return (float(y[2]) + nu * zeta0) / J

    ends.terminal = True
    ends.direction = 1
    nfev = 0
    stopped = False
    ux, uy, uz = _slip(y0, r)
    s0 = 0.0
    if ux != 0.0 or uy != 0.0 or uz != 0.0:
        n0 = math.sqrt(ux * ux + uy * uy + uz * uz)
        e0 = (ux / n0, uy / n0, uz / n0)

        def sliding(_s: float, y: np.ndarray) -> list[float]:
            u = _slip(y.tolist(), r)
            n = math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
            # Coulomb: −f û; at an exactly zero slip (a trial stage at the stop) the friction that keeps it zero
            lam = (-f * u[0] / n, -f * u[1] / n, -f * u[2] / n) if n > 0.0 else lam_stick
            return [J * x for x in _rates(lam, r, k, R)]

        def stops(_s: float, y: np.ndarray) -> float:
            u = _slip(y.tolist(), r)
            return (u[0] * e0[0] + u[1] * e0[1] + u[2] * e0[2]) / S

        stops.terminal = True
        stops.direction = -1
        sol = check(solve_ivp(bounded(sliding), (0.0, _SPAN), np.array(y0), method="DOP853", rtol=rtol, atol=atol,
                              events=(stops, ends)))
        nfev += sol.nfev
        if sol.status != 1:
            raise ArithmeticError("the impact did not end within the impulse span")
        if sol.t_events[1].size:  # ended while sliding (both at once: the end wins, nothing is left to do)
            y = sol.y_events[1][0]
            return float(y[0]), float(y[2]), float(y[4]), False, nfev
        y0, s0 = sol.y_events[0][0].tolist(), float(sol.t_events[0][0])
        stopped = True
    rate = [J * x for x in _rates(lam_stick, r, k, R)]

    def sticking(_s: float, _y: np.ndarray) -> list[float]:
        return rate

    sol = check(solve_ivp(bounded(sticking), (s0, _SPAN), np.array(y0), method="DOP853", rtol=rtol, atol=atol,
                          events=ends))
    nfev += sol.nfev
    if sol.status != 1:
        raise ArithmeticError("the impact did not end within the impulse span")
    y = sol.y_events[0][0]
    return float(y[0]), float(y[2]), float(y[4]), stopped, nfev


def solve(scene: Mapping[str, np.ndarray], rtol: float = 1e-13) -> RefereePlane:
    """scene: the registry's scene dict for plane-impact (keys chi0, zeta0, p0, R, k, f, nu, plus 'ones'); any batch
    shape"""
    names = ("chi0", "zeta0", "p0", "R", "k", "f", "nu")
    arrays = np.broadcast_arrays(*(np.asarray(scene[x], dtype=float) for x in names),
                                 np.asarray(scene.get("ones", True), dtype=float))
    shape = arrays[0].shape
    flat = [a.ravel() for a in arrays[:-1]]
    rows = [_one(*(float(a[i]) for a in flat), rtol) for i in range(flat[0].size)]
    out = np.array([row[:3] for row in rows], dtype=float).reshape((*shape, 3))
    stopped = np.array([row[3] for row in rows], dtype=bool).reshape(shape)
    nfev = np.array([row[4] for row in rows], dtype=int).reshape(shape)
    return RefereePlane(chi1=out[..., 0], zeta1=out[..., 1], p1=out[..., 2], stopped=stopped, nfev=nfev, label=LABEL)
