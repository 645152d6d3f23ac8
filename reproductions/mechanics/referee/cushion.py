"""Referee for §IV n°11 of Résal (1883), the ball against a cushion: Newton–Euler's laws for every velocity
component of the ball, integrated in the normal impulse, sharing no code (and no equation of n°11 beyond its
premises) with the paths of ``reproductions.mechanics.cushion`` that it checks.

Frame (§IV n°11, l. 409, as ``cushion``'s docstring declares it): Ox along the cushion, Oy normal to the cloth,
upward, Oz normal to the cushion, pointing from the cushion into the table, so that the ball approaches with
ζ0 < 0. SI units. The centre moves at v = (χ, η, ζ) (m/s), the ball turns at ω = (ω_x, ω_y, ω_z) = (n, p, q)
(rad/s): n about Ox (the cushion's direction), p about Oy (side spin), q about Oz (the normal). The cushion
touches the ball at r = −R e_z from the centre (at the height of the centre), the cloth at r_b = −R e_y.

Contact velocity on the cushion, u = v + ω × r = (χ − pR, η + nR, ζ): its tangential part u_t = (u_x, u_y) is
the slip of eq. (1), φ = χ − pR and ψ = nR where η = 0; u_z = ζ is the normal velocity.

Per unit normal impulse π = (1/M)∫Z dt (m/s) the cushion exerts F = e_z + f_t, with Coulomb's friction
f_t = −j u_t/|u_t| while the contact slips (eqs (2): jZ opposing the slip). The cloth is bilateral here, as the
model declares (η = 0 blocked both ways, the paper's premise l. 411): its reaction N e_y at r_b is the impulse
that cancels the vertical component of the cushion's friction on the centre, N = −F·e_y, and it may be negative:
the cloth then pulls the ball down, which a real cloth cannot (``cloth_pulls`` reports it per scene). The cloth's
friction during the impact is left out, as the paper leaves it out. Newton and Euler, per unit mass, with the
moment of inertia R²/k (M R²/k):

    dv/dπ = F + N e_y,        (R²/k) dω/dπ = r × F + r_b × (N e_y),        dΠ/dπ = N (the cloth's impulse).

With r = −R e_z, r × F = (R F_y, −R F_x, 0); r_b × e_y = 0. So q never changes and η stays 0; the rates
dχ/dπ = −jφ/v, d(pR)/dπ = kjφ/v, d(nR)/dπ = −kjψ/v (v = |u_t|) of eqs (2) follow from these and are not
written here: the code evaluates the vector forms above.

Slip phase: ``solve_ivp`` DOP853 (rtol 1e-13, absolute tolerances rtol·1e-2 of the scene's speed scale
V = |v0| + |ω0|R, over R for the rotations), with a terminal event on the slip projected on its direction at the
start of the segment, u_t · e0 (never |u_t| − tiny: the right-hand side is discontinuous at u_t = 0). The slip
keeps its quadrant while it slows, so the projection crosses zero once, where the slip stops. When the slip turns
(small k: φ dies long before ψ), the projection weights the last component by ψ0/|u_t0| and the integration
error of φ = χ − pR (a difference of two velocities, ~rtol·|χ|) can fire the event early; a segment whose residual
slip exceeds 10·rtol·V is therefore restarted from there, projected on its new direction, until the residual is
below that or stops shrinking (by half at least): the floor of the event's location on the dense output.

Stick phase: once the slip has stopped, the tangential impulse rate f_t that keeps u_t = 0 solves
du_t/dπ = A f_t + b = 0, with b the slip rate under the normal push alone and A the slip rate per unit
tangential impulse (here A = diag(1 + k, k)). The normal push acts along r, so it has no moment and moves no
contact point tangentially: b = 0 and f_t = 0, no friction is needed. The code computes b, A and f_t from the
rates above and checks that f_t lies in Coulomb's cone |f_t| ≤ j, rather than assume it.

End of the impact: the law the model declares (§I eq. (9), §IV): the normal velocity is returned in the ratio
ν = (1 − ε)/(1 + ε), the impact ends when ζ = −ν ζ0. As dζ/dπ = F·e_z = 1, that is π_end = −(1 + ν) ζ0 ≥ 0: the
cushion only pushes (the normal impulse rate is 1 ≥ 0 throughout).

Outputs as ``cushion.CushionImpact``: χ1 = v_x, ζ1 = v_z (= ν a), p1 = ω_y, n1 = ω_x.

Angular momentum about the cushion's contact c, per unit mass, L = (R²/k)ω + R e_z × v = ((R²/k)n − Rη,
(R²/k)p + Rχ, (R²/k)q): the cushion's impulse acts at c and the cloth's is vertical, so along Oy χ + pR/k is
conserved (``registry._about_contact``); along Ox the cloth's impulse Π at the foot of the ball ((0, −R, R) from c)
has the moment −RΠ: n1R/k = n0R/k − Π1 (η0 = η1 = 0), and n grows exactly where the cloth pulls (Π < 0).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..budget import bounded, check, solve_ivp

__all__ = ["RefereeCushion", "solve"]

_NAMES = ("chi0", "zeta0", "p0", "n0", "R", "k", "j", "eps")
_MAX_SEGMENTS = 20  # restarts of the slip phase after an early stop event (each shrinks the slip by far)


@dataclass(frozen=True)
class RefereeCushion:
    """After the impact, per scene; ``stopped``: the slip stopped during it; ``cloth_pulls``: the cloth had to pull
    the ball down (a negative vertical reaction) at some instant; ``nfev``: right-hand-side evaluations."""

    chi1: np.ndarray
    zeta1: np.ndarray
    p1: np.ndarray
    n1: np.ndarray
    stopped: np.ndarray
    cloth_pulls: np.ndarray
    nfev: np.ndarray
    label: str


def _cross(a: tuple[float, float, float], b: tuple[float, float, float]) -> tuple[float, float, float]:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


class _Ball:
    """Newton–Euler's rates of one ball against the cushion (module docstring); state y = (v, ω, Π)."""

    def __init__(self, R: float, k: float, j: float) -> None:
        self.R, self.k, self.j = R, k, j
        self.r = (0.0, 0.0, -R)  # centre → cushion contact
        self.rb = (0.0, -R, 0.0)  # centre → cloth contact

    def contact_velocity(self, y: np.ndarray | list[float]) -> tuple[float, float, float]:
        """u = v + ω × r at the cushion contact."""
        w = _cross((y[3], y[4], y[5]), self.r)
        return (y[0] + w[0], y[1] + w[1], y[2] + w[2])

    def rates(self, y: np.ndarray | list[float], ft: tuple[float, float]) -> list[float]:
        """dy/dπ under the normal push e_z, a tangential impulse rate ``ft`` at the contact and the cloth's reaction."""
        F = (ft[0], ft[1], 1.0)
        N = -F[1]  # the bilateral cloth cancels the vertical push on the centre
        m = _cross(self.r, F)
        mb = _cross(self.rb, (0.0, N, 0.0))
        c = self.k / (self.R * self.R)
        return [F[0], F[1] + N, F[2], c * (m[0] + mb[0]), c * (m[1] + mb[1]), c * (m[2] + mb[2]), N]

    def friction(self, y: np.ndarray | list[float]) -> tuple[float, float]:
        """Coulomb's f_t = −j u_t/|u_t| (none where the contact does not slip)."""
        ux, uy, _ = self.contact_velocity(y)
        s = math.hypot(ux, uy)
        return (0.0, 0.0) if s == 0.0 else (-self.j * ux / s, -self.j * uy / s)

    def sliding(self, _pi: float, y: np.ndarray) -> list[float]:
        return self.rates(y.tolist(), self.friction(y.tolist()))  # floats: numpy's scalars cost more

    def stick_friction(self, y: np.ndarray | list[float]) -> tuple[tuple[float, float], float]:
        """The tangential impulse rate that keeps the slip at zero, and |b|, the slip rate under the normal push."""
        def slip_rate(ft: tuple[float, float]) -> np.ndarray:
            d = self.rates(y, ft)
            return np.array(self.contact_velocity([*d[:6], 0.0])[:2])  # u is linear in (v, ω)

        b = slip_rate((0.0, 0.0))
        A = np.column_stack([slip_rate((1.0, 0.0)) - b, slip_rate((0.0, 1.0)) - b])
        ft = np.linalg.solve(A, -b)
        return (float(ft[0]), float(ft[1])), float(np.hypot(*b))


def _one(chi0: float, zeta0: float, p0: float, n0: float, R: float, k: float, j: float, eps: float,
         rtol: float) -> tuple[float, float, float, float, bool, bool, int, float]:
    """One scene: (χ1, ζ1, p1, n1, stopped, cloth_pulls, nfev, Π1), Π1 the cloth's vertical impulse (m/s)."""
    if zeta0 > 0:
        raise ValueError(f"the ball must approach the cushion (ζ0 ≤ 0), got ζ0 = {zeta0!r}")
    nu = (1.0 - eps) / (1.0 + eps)
    pi_end = -(1.0 + nu) * zeta0  # ζ0 + π_end = −νζ0: dζ/dπ = 1
    ball = _Ball(R, k, j)
    y = [chi0, 0.0, zeta0, n0, p0, 0.0, 0.0]
    V = math.hypot(chi0, zeta0) + math.hypot(n0, p0) * R
    if V == 0.0:
        return chi0, zeta0, p0, n0, False, False, 0, 0.0
    atol = rtol * 1e-2 * V
    atols = [atol] * 3 + [atol / R] * 3 + [atol]
    stop_tol = 10 * rtol * V
    pi, nfev, stopped, pulls, last = 0.0, 0, False, False, math.inf
    psi0 = ball.contact_velocity(y)[1]
    for _ in range(_MAX_SEGMENTS):
        ux, uy, _ = ball.contact_velocity(y)
        s = math.hypot(ux, uy)
        if pi >= pi_end or s == 0.0 or j == 0.0:
            break
        e0 = (ux / s, uy / s)

        def slip_along_e0(_pi: float, yy: np.ndarray, e0: tuple[float, float] = e0) -> float:
            u = ball.contact_velocity(yy)
            return u[0] * e0[0] + u[1] * e0[1]

        slip_along_e0.terminal = True
        slip_along_e0.direction = -1
        sol = check(solve_ivp(bounded(ball.sliding), (pi, pi_end), y, method="DOP853", rtol=rtol, atol=atols,
                              events=slip_along_e0))
        nfev += sol.nfev
        # N < 0 where the contact slips, its vertical slip still of its first sign (a step that ends just past the
        # stop, its slip a rounding's width the other way, is not a pull)
        pulls = pulls or any(ball.sliding(0.0, yy)[6] < 0 for yy in sol.y.T
                             if math.hypot(*(u := ball.contact_velocity(yy.tolist()))[:2]) > stop_tol
                             and u[1] * psi0 > 0)
        if sol.status == 1:
            pi, y = float(sol.t_events[0][0]), sol.y_events[0][0].tolist()
            ux, uy, _ = ball.contact_velocity(y)
            residual = math.hypot(ux, uy)
            if residual <= stop_tol or residual > 0.5 * last:  # stopped, or a restart gained nothing: the floor
                stopped = True
                break
            last = residual  # the event fired on the rounding of φ: go on, projected on the slip's new direction
            continue
        pi, y = pi_end, sol.y[:, -1].tolist()
        break
    else:
        raise ArithmeticError(f"the slip did not stop within {_MAX_SEGMENTS} segments")
    if stopped and pi < pi_end:
        ft, b = ball.stick_friction(y)
        if b > 1e-12 or math.hypot(*ft) > j:
            raise ArithmeticError(f"the contact cannot stick: slip rate {b:g} under the push, friction {ft} > j")
        sol = check(solve_ivp(bounded(lambda _pi, yy: ball.rates(yy.tolist(), ft)), (pi, pi_end), y,
                              method="DOP853", rtol=rtol, atol=atols))
        nfev += sol.nfev
        y = sol.y[:, -1].tolist()
    elif pi < pi_end:  # no slip at first, or no friction: only the normal push acts
        sol = check(solve_ivp(bounded(lambda _pi, yy: ball.rates(yy.tolist(), (0.0, 0.0))), (pi, pi_end), y,
                              method="DOP853", rtol=rtol, atol=atols))
        nfev += sol.nfev
        y = sol.y[:, -1].tolist()
    return y[0], y[2], y[4], y[3], stopped, pulls, nfev, y[6]


def solve(scene: Mapping[str, np.ndarray], rtol: float = 1e-13) -> RefereeCushion:
    """scene: the registry's scene dict for the model (keys chi0, zeta0, p0, n0, R, k, j, eps, plus 'ones');
    any batch shape; loops scene by scene."""
    arrays = np.broadcast_arrays(*(np.asarray(scene[x], dtype=float) for x in _NAMES),
                                 np.asarray(scene.get("ones", True)))
    shape = arrays[0].shape
    chi1, zeta1, p1, n1 = (np.empty(shape) for _ in range(4))
    stopped, pulls = np.zeros(shape, dtype=bool), np.zeros(shape, dtype=bool)
    nfev = np.zeros(shape, dtype=int)
    for idx in np.ndindex(shape):
        out = _one(*(float(a[idx]) for a in arrays[:8]), rtol=rtol)
        chi1[idx], zeta1[idx], p1[idx], n1[idx], stopped[idx], pulls[idx], nfev[idx], _ = out
    return RefereeCushion(chi1, zeta1, p1, n1, stopped, pulls, nfev,
                          f"referee: Newton–Euler in the normal impulse (DOP853, rtol {rtol:g}, slip-stop event)")
