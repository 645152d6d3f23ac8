"""Referee for §VII n°14: the stroke of an inclined cue on a ball resting on the cloth, integrated from Newton's and
Euler's laws in the cue impulse P = ∫F dt, with the end of the stroke from law (6) of §I n°3 evaluated literally
on the integrated state.

Nothing here comes from the paths it checks (``cue``, ``impact``, ``paths``, ``registry``, ``reference``,
``slip``): no slip direction γ (eq. 5), no per-impulse closed form (eq. 7), no A (eq. 8), no eq. (10).

Frame of the paper (§II, §VII): Cx horizontal in the vertical plane of the cue, Cz upward. The cue, of mass M′ and
speed V′ along its axis d = (cos i, 0, −sin i), strikes the ball (mass M, radius R, inertia I = M R²/k, at rest)
at r_c = (a, b, c), a = −√(R² − b² − c²); the foot of the ball is r_B = (0, 0, −R).

Premises of n°14 that the model declares and this referee follows:
* the cue's force F lies along its axis (no percussion on the hands; the axis inside the tip's friction cone, no
  *fausse queue*): the cue–ball impulse is P d on the ball and −P d on the cue, with no separate tangential
  unknown at the tip; the cue moves along its axis only (one velocity component, V′);
* the moment of F about C is the full r_c × d (``exact`` keeps the term a sin i that eq. (2) drops);
* the greatest compression is where the cue and the ball's contact point have the same velocity along the cue
  axis, the line of the impulse (``exact``'s choice; Résal's eq. (12) takes the normal);
* the ball's displacements during the stroke are neglected (r_c, r_B fixed); gravity is negligible.

State y = (χ, η, ζ, n, p, q, Ω, J_x, J_y, N, s_x, s_y): the centre's velocity, the rotation (n, p, q) about
(Cx, Cy, Cz), the cue's speed lost Ω = V′0 − V′ (the state rather than V′ itself: for a ball much lighter than the
cue V′0 − V′ would lose its digits to the subtraction), the cloth's friction impulse J (the ball receives −J),
its normal impulse N, and the foot's slip s. Per unit P, with j = dJ/dP and ν = dN/dP:

    M dv/dP = d + (−j_x, −j_y, ν),      I dω/dP = r_c × d + r_B × (−j_x, −j_y, ν),      M′ dΩ/dP = 1,
    ds/dP = horizontal part of dv/dP + (dω/dP) × r_B        (the kinematics of eq. (1), s = v + ω × r_B).

The slip is integrated beside v and ω (it stays equal to χ − pR, η + nR to rounding), as its components along
the direction e its first slide starts in and across it (e⊥), because Coulomb's law needs its direction, which the
difference χ − pR loses to rounding when the slip grows slowly against the velocities (a stroke near the cone's
edge). The direction's own equation is stiff, a deviation δ decaying as dδ/dP = −|a0| δ/|s| with |s| ∝ P: an
explicit solver chasing rounding across e would take ~30ρ steps, ρ = |j_hold|/(|j_hold| − fν) (unbounded at
the cone's edge). So the slip's rate across e is set to zero where it is below 1e-12 of the size of its terms
(|a0| + βfν), i.e. where it is the rounding of a driving term that lies along e by construction (e = â0 below);
anything larger is kept and integrated. This is not a regularisation: the friction stays f ν s/|s| exactly.

Constraints, as complementarity at the foot B, whose velocity is v + ω × r_B = (χ − pR, η + nR, ζ) (eq. 1):
* normal: ν ≥ 0, the foot's vertical velocity ζ ≥ 0, ν ζ = 0. With ζ = 0 the rate that keeps it so is
  ν* = −M (dζ/dP at ν = 0) = sin i, computed from the vertical equation; ν = ν* if ν* ≥ 0, else ν = 0 and the ball
  leaves the cloth (``cloth_pulls``: the cloth would have had to pull; i < 0, outside the model's range);
* tangential (Coulomb, no regularisation): while the foot slips (s = (χ − pR, η + nR) ≠ 0), j = f ν s/|s|;
  the slip's stop is a terminal event on s·ŝ0 (ŝ0: its direction at the start of the slide). While it holds
  (s = 0), j is the rate that keeps ds/dP = 0: ds/dP = a0 + B j is linear in j, a0 and B are evaluated from the
  equations above, and j = −B⁻¹ a0. It must lie in the cone |j| ≤ f ν; if it does not, the foot slides, in the
  direction of the slip's acceleration under Coulomb friction: B = −(1/M + R²/I)·1 is isotropic (evaluated,
  checked), so ŝ0 = ĵ_hold, and j = f ν ŝ0 (``resumed``). None of the rates depends on the state, so a hold, once
  inside the cone, stays inside it. The ball starts at rest: the stroke starts with the hold test. From rest a
slide grows along ŝ0 for as long as P grows (its rate, (|a0| − βfν) ŝ0, is constant), so in this model the slip
never stops and ``stopped`` is False for every stroke; the stop, hold and resume steps are kept for completeness.

The greatest compression (§I n°2, here along the cue axis) is the terminal event g = V′ − d·(v + ω × r_c) = 0,
direction −1; ω (the brief's name, Résal's eq. 12) = V′0 − V′ there.

End of the stroke from law (6), Σ m v0² − Σ m v² = ε S m U² + ε′ S′ m′ U′² − 2Jω. Its last term is, by its
derivation (eq. 1 of n°3), 2 Σ m U·u: the lost momenta times the velocities u at the greatest compression, which
for rigid bodies is −2 Σ_k Π_k·u_k over every impulse Π_k received since the start, each with the velocity of its
point of application at the greatest compression (subscript c). Here:
  cue on ball  P d at r_c, and −P d on the cue (velocity V′ d):  −P (d·u_c − V′_c) = 0 by the event's definition;
  cloth normal N ẑ at B:  −N ζ_c = 0 (ζ_c = 0 on the cloth);
  cloth friction −J at B:  +J·s_c.
So 2 Σ m U·u = 2 J(P)·s_c: only the cloth's friction, its total impulse so far times the slip at the greatest
compression. The cue's tangential component has no separate term: with the impulse along d and the compression
ended along d, the whole cue–ball term vanishes (Résal's own split, J along the tangent and the normal
velocities equal, gives his −2ω cos ψ M′ω1 instead; the normal part then has no work, here the axial one).
All three terms are kept literally in the code. The law's residual, with the ball starting at rest,

  L(P) = M′Ω(2V′0 − Ω) − T_b − ε T_b − ε′ M′Ω² − 2[P (V′_c − d·u_c) − N ζ_c + J·s_c],

T_b = M|v|² + I|ω|² (the ball's vis viva and its Σ m U²), is ≥ 0 at the greatest compression (zero for ε = ε′ =
1: law (6) with ε = ε′ = 1 is an identity there) and the stroke ends at its first zero beyond (terminal event,
direction −1), or at the greatest compression itself when L(P_c) ≤ 0.

DOP853, rtol 1e-12 by default, atol rtol times each component's own scale (V′0; V′0/R; the reduced impulse
P_s = V′0/(1/M + 1/M′)); the solver's variable is P/P_s (``solve_ivp`` locates events to an absolute 4·2⁻⁵² in its
variable); each phase's horizon doubles until its event is found (bounded).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..budget import bounded, check, solve_ivp

__all__ = ["RefereeCue", "solve"]

MAX_DOUBLINGS = 80  # horizons double from the reduced impulse's scale: 2⁸⁰ covers any impulse a double holds
_NY = 12


@dataclass(frozen=True)
class RefereeCue:
    """The ball and the cue just after the stroke (§VII eqs 6-7), and what the integration saw."""

    chi1: np.ndarray  # centre velocity along Cx
    eta1: np.ndarray  # along Cy
    n1: np.ndarray  # rotation about Cx
    p1: np.ndarray  # about Cy
    q1: np.ndarray  # about Cz
    V1p: np.ndarray  # cue speed after the stroke
    omega1: np.ndarray  # cue speed lost, V0p − V1p (eq. 6)
    omega: np.ndarray  # cue speed lost at the greatest compression
    stopped: np.ndarray  # bool: the slip on the cloth stopped during the stroke
    cloth_pulls: np.ndarray  # bool: the cloth would have had to pull (the ball left it)
    nfev: np.ndarray
    label: str
    resumed: np.ndarray | None = None  # bool: a hold left the friction cone and the foot slid again


def _cross(u: tuple[float, float, float], w: tuple[float, float, float]) -> tuple[float, float, float]:
    return (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])


class _Stroke:
    """One scene: the Newton–Euler rates, the foot's slip, the contact's velocity along d, law (6)."""

    def __init__(self, M: float, Mp: float, V0p: float, i: float, b: float, c: float, R: float, k: float,
                 f: float, eps: float, epsp: float) -> None:
        self.M, self.Mp, self.V0p, self.R, self.f, self.eps, self.epsp = M, Mp, V0p, R, f, eps, epsp
        self.I = M * R * R / k
        self.d = (math.cos(i), 0.0, -math.sin(i))
        self.rc = (-math.sqrt(max(R * R - b * b - c * c, 0.0)), b, c)
        self.rB = (0.0, 0.0, -R)
        self.torque_cue = _cross(self.rc, self.d)
        self.e = (1.0, 0.0)  # the slip's frame (e, e⊥): its states are s·e and s·e⊥ (``_one`` sets it)

    def _newton_euler(self, jx: float, jy: float, nu: float) -> tuple[tuple, tuple, tuple[float, float]]:
        """dv/dP, dω/dP and the foot's slip rate (lab frame) for the cloth's rates j (the ball receives −j), ν."""
        M, inertia, d = self.M, self.I, self.d
        tc, tb = self.torque_cue, _cross(self.rB, (-jx, -jy, nu))
        dv = ((d[0] - jx) / M, (d[1] - jy) / M, (d[2] + nu) / M)
        dw = ((tc[0] + tb[0]) / inertia, (tc[1] + tb[1]) / inertia, (tc[2] + tb[2]) / inertia)
        ds = _cross(dw, self.rB)
        return dv, dw, (dv[0] + ds[0], dv[1] + ds[1])

    def rates(self, jx: float, jy: float, nu: float) -> list[float]:
        """dy/dP for the cloth's friction rate j (the ball receives −j) and normal rate ν."""
        dv, dw, (sx, sy) = self._newton_euler(jx, jy, nu)
        ex, ey = self.e
        return [*dv, *dw, 1.0 / self.Mp, jx, jy, nu, sx * ex + sy * ey, sy * ex - sx * ey]

    def foot(self, y: np.ndarray | list[float]) -> tuple[float, float, float]:
        """Velocity of the ball's foot B: the slip (eq. 1, its integrated state, lab frame) and ζ."""
        ex, ey = self.e
        return y[10] * ex - y[11] * ey, y[10] * ey + y[11] * ex, y[2]

    def axial_gap(self, y: np.ndarray | list[float]) -> float:
        """V′ − d·(v + ω × r_c): the cue's speed less the contact point's along the axis (zero: greatest
        compression)."""
        w = _cross((y[3], y[4], y[5]), self.rc)
        d = self.d
        return (self.V0p - y[6]) - (d[0] * (y[0] + w[0]) + d[1] * (y[1] + w[1]) + d[2] * (y[2] + w[2]))

    def law(self, P: float, y: np.ndarray, yc: np.ndarray) -> float:
        """L(P) of the module docstring: law (6) with the work term at the greatest compression's state yc."""
        M, Mp, V0p, inertia = self.M, self.Mp, self.V0p, self.I
        Om = float(y[6])
        ball = M * float(y[0] ** 2 + y[1] ** 2 + y[2] ** 2) + inertia * float(y[3] ** 2 + y[4] ** 2 + y[5] ** 2)
        lost = Mp * Om * (2 * V0p - Om) - ball
        sx, sy, zc = self.foot(yc)
        work = P * self.axial_gap(yc) - float(y[9]) * zc + float(y[7]) * sx + float(y[8]) * sy
        return lost - self.eps * ball - self.epsp * Mp * Om * Om - 2 * work

    def normal_rate(self, y: np.ndarray) -> tuple[float, bool]:
        """ν from the vertical complementarity, and whether the cloth would have had to pull."""
        if float(y[2]) > 0:  # the ball has left the cloth: the contact is open
            return 0.0, False
        nu_hold = -self.M * self.rates(0.0, 0.0, 0.0)[2]  # keeps the foot's vertical velocity zero
        return (nu_hold, False) if nu_hold >= 0 else (0.0, True)

    def hold_rate(self, nu: float) -> tuple[tuple[float, float], float]:
        """The friction rate that keeps the foot's slip zero, ds/dP = a0 + B j = 0 (linear in j), and β (B = −β·1)."""
        def slip_rate(jx: float, jy: float) -> tuple[float, float]:
            return self._newton_euler(jx, jy, nu)[2]

        a0 = slip_rate(0.0, 0.0)
        ex, ey = slip_rate(1.0, 0.0), slip_rate(0.0, 1.0)
        B = ((ex[0] - a0[0], ey[0] - a0[0]), (ex[1] - a0[1], ey[1] - a0[1]))
        beta = -B[0][0]
        if not (beta > 0 and abs(B[1][1] + beta) <= 1e-12 * beta and abs(B[0][1]) + abs(B[1][0]) <= 1e-12 * beta):
            raise ArithmeticError("referee (cue): the foot's slip response to friction is not isotropic")
        return (a0[0] / beta, a0[1] / beta), beta


@dataclass
class _Phase:
    sliding: bool
    nu: float
    j: tuple[float, float]  # hold: the friction rate; slide: the unit direction ŝ0 of the slide's start
    rate_scale: float = 0.0  # |a0| + β f ν: the size of the terms of the slip's rate


def _one(st: _Stroke, rtol: float) -> tuple[np.ndarray, float, bool, bool, bool, int]:
    M, Mp, V0p, R, f = st.M, st.Mp, st.V0p, st.R, st.f
    y0 = np.zeros(_NY)
    P_scale = V0p / (1.0 / M + 1.0 / Mp)  # the reduced impulse: a scale only
    scale = np.array([V0p] * 3 + [V0p / R] * 3 + [V0p] + [P_scale * (1 + f)] * 3 + [V0p] * 2)
    atol = rtol * scale
    flags = {"stopped": False, "pulls": False, "resumed": False}
    nfev = 0

    def start_phase(y: np.ndarray, after_stop: bool) -> _Phase:
        """At zero slip (the start, or the slip's stop): hold if the hold's rate is inside the cone, else slide."""
        nu, pulls = st.normal_rate(y)
        flags["pulls"] |= pulls
        jh, beta = st.hold_rate(nu)
        jn = math.hypot(*jh)
        if jn <= f * nu:
            return _Phase(False, nu, jh)
        if after_stop:
            flags["resumed"] = True
        return _Phase(True, nu, (jh[0] / jn, jh[1] / jn), beta * (jn + f * nu))

    def run(y: np.ndarray, P: float, ph: _Phase, goal_of) -> tuple[np.ndarray, float, str]:
        """Integrate from (P, y) in phase ``ph`` until the goal event or the slip's stop. The solver's variable is
        x = P/P_scale: ``solve_ivp`` locates events to an *absolute* 4·2⁻⁵² in its variable, far too coarse in P
        itself for a light ball at a low speed (P ~ 1e-13)."""
        nonlocal nfev
        e0 = ph.j
        fnu = f * ph.nu
        if ph.sliding:
            ex, ey = st.e
            rounding = 1e-12 * ph.rate_scale

            def rhs(_x: float, yy: np.ndarray) -> list[float]:
                sp, sq = float(yy[10]), float(yy[11])  # the slip along e and e⊥
                sn = math.hypot(sp, sq)
                if sn > 0:  # opposite the current slip
                    up, uq = sp / sn, sq / sn
                    ux, uy = up * ex - uq * ey, up * ey + uq * ex
                else:  # at zero slip: the direction it starts in
                    ux, uy = e0
                r = st.rates(fnu * ux, fnu * uy, ph.nu)
                if abs(r[11]) <= rounding:  # the rounding of a driving term along e itself (module docstring)
                    r[11] = 0.0
                return [P_scale * q for q in r]
        else:
            fixed = [P_scale * r for r in st.rates(ph.j[0], ph.j[1], ph.nu)]

            def rhs(_x: float, yy: np.ndarray) -> list[float]:
                return fixed

        def stops(_x: float, yy: np.ndarray) -> float:
            sx, sy, _ = st.foot(yy.tolist())
            return sx * e0[0] + sy * e0[1]

        stops.terminal = True  # type: ignore[attr-defined]
        stops.direction = -1  # type: ignore[attr-defined]

        def goal(x: float, yy: np.ndarray) -> float:
            return goal_of(x * P_scale, yy)

        goal.terminal = True  # type: ignore[attr-defined]
        goal.direction = -1  # type: ignore[attr-defined]
        events = [goal, stops] if ph.sliding else [goal]
        x, span = P / P_scale, max(P / P_scale, 1.0)
        for _ in range(MAX_DOUBLINGS):
            sol = check(solve_ivp(bounded(rhs), (x, x + span), y, method="DOP853", rtol=rtol, atol=atol,
                                  events=events))
            nfev += sol.nfev
            if sol.status == 1:
                hits = [(float(t[0]), n) for n, t in enumerate(sol.t_events) if t.size]
                t_hit, n = min(hits)
                return np.array(sol.y_events[n][0]), t_hit * P_scale, ("goal", "stop")[n]
            y, x = np.array(sol.y[:, -1]), float(sol.t[-1])
            span *= 2
        raise ArithmeticError("referee (cue): no end of the phase within 2^80 of the impulse's scale")

    def stage(y: np.ndarray, P: float, ph: _Phase, goal_of) -> tuple[np.ndarray, float, _Phase]:
        while True:
            y, P, what = run(y, P, ph, goal_of)
            if what == "goal":
                return y, P, ph
            flags["stopped"] = True
            ph = start_phase(y, after_stop=True)

    ph = start_phase(y0, after_stop=False)
    if ph.sliding:
        st.e = ph.j  # the slip's states along its first direction and across it
    yc, Pc, ph = stage(y0, 0.0, ph, lambda _P, yy: st.axial_gap(yy))
    y, P = yc, Pc
    if st.law(Pc, yc, yc) > 0:  # restitution, until law (6) balances
        y, P, ph = stage(yc, Pc, ph, lambda PP, yy: st.law(PP, yy, yc))
    return np.concatenate([y, [float(yc[6])]]), P, flags["stopped"], flags["pulls"], flags["resumed"], nfev


def solve(scene: Mapping[str, np.ndarray], rtol: float = 1e-12) -> RefereeCue:
    """§VII n°14 refereed (module docstring). scene: the registry's scene dict for cue-stroke (keys M, Mp, V0p, i,
    b, c, R, k, f, eps, epsp, plus 'ones'); any batch shape."""
    keys = ("M", "Mp", "V0p", "i", "b", "c", "R", "k", "f", "eps", "epsp")
    shape = np.broadcast_shapes(*(np.shape(scene[x]) for x in keys))
    arrays = [np.broadcast_to(np.asarray(scene[x], dtype=float), shape) for x in keys]
    out = np.zeros((*shape, _NY + 1))
    stopped, pulls, resumed = (np.zeros(shape, dtype=bool) for _ in range(3))
    nfev = np.zeros(shape, dtype=int)
    for idx in np.ndindex(shape):
        st = _Stroke(*(float(a[idx]) for a in arrays))
        y, _, stopped[idx], pulls[idx], resumed[idx], nfev[idx] = _one(st, rtol)
        out[idx] = y
    V0p = arrays[2]
    return RefereeCue(chi1=out[..., 0], eta1=out[..., 1], n1=out[..., 3], p1=out[..., 4], q1=out[..., 5],
                      V1p=V0p - out[..., 6], omega1=out[..., 6], omega=out[..., _NY], stopped=stopped,
                      cloth_pulls=pulls, nfev=nfev,
                      label=f"referee: Newton–Euler in the cue impulse, Coulomb cloth as complementarity, law (6) "
                            f"evaluated literally (DOP853, rtol {rtol:g})", resumed=resumed)
