"""Referee for §V n°12 and §VI n°13: two balls, free or resting on the cloth, integrated from Newton's and Euler's
laws in the normal impulse, with the end of the impact from law (6) of §I evaluated literally on the state.

Nothing here comes from ``spheres`` or ``slip`` (tests/test_layers.py): no closed form, no slip decay, no law
rewritten in impulses. The state is the change of every velocity component since the impact began,
y = (Δv, Δw, Δv′, Δw′, J, C), with J = (ξ, T_y, T_z) the impulse M′ has received at the contact and C the
vertical impulses the cloth gave each ball; the independent variable is the normal impulse ξ = ∫X dt (§V eq.
(4): M χ0 − M χ = ξ). Changes, not velocities: a ball 10¹⁰ times heavier than the other changes its velocity by
10⁻¹⁰ of it, which a velocity in floating point would round away before law (6) could weigh it.

Frame of the paper: Ox along the line of centres from C to C′, Oz vertical on the cloth. Contact points R x̂ on M
and −R′ x̂ on M′; the slip of M on M′ there is u = (v + w × R x̂) − (v′ + w′ × (−R′ x̂)), its tangential part
(u_y, u_z). Per unit of ξ the contact force on M is F = −x̂ − f û (Coulomb's friction opposite the current slip
while it slips, §I n°2), and −F on M′:

    M dv/dξ = F + n ẑ,      (M R²/k) dw/dξ = R x̂ × F,
    M′ dv′/dξ = −F + n′ ẑ,  (M′ R′²/k′) dw′/dξ = (−R′ x̂) × (−F),
    dJ/dξ = −F,             dC/dξ = (n, n′).

The cloth (§VI only) acts at each ball's foot, vertical and through the centre (no moment). Its law here is the
one the model declares, Résal's premise of n°13 (« faire abstraction des deux équations de translation
verticale », after Coriolis: the weight brings the ball back at once): the vertical translations are blocked
both ways, n = −F_z and n′ = F_z, i.e. the cloth is a bilateral constraint. A cloth that only pushes
(complementarity n ≥ 0, v_z ≥ 0, n v_z = 0) differs exactly where one of these is negative; ``cloth_pulls`` says
per scene whether that happened (the striking ball with follow: the friction lifts it), so that a reader knows
where the premise, not the integration, decides. Free balls (§V): n = n′ = 0.

The slip's stop is a terminal event on the slip projected on its initial direction (it crosses zero cleanly;
|u| − tiny would chatter). After it the contact holds if the normal impulse alone moves no contact point
tangentially; that rate is computed (not assumed) and must vanish: for spheres F = −x̂ at R x̂ has no moment.

The greatest compression (§I n°2) is the event χ − χ′ = 0 (the contact points' normal velocities are those of
the centres). Its state gives the slip s_c. The impact then ends where law (6) of §I n°3 balances:

    Σ m v0² − Σ m v² = ε S m U² + ε′ S′ m′ U′² − 2Jω,

evaluated literally: the vis viva lost M(v0 − v)·(v0 + v) + (MR²/k)(w0 − w)·(w0 + w) + (the same for M′), the
lost velocities' Σ m U² = M|Δv|² + (MR²/k)|Δw|² (König), and −2Jω = 2 T·s_c, the work of the tangential
impulse received (T on M′, −T on M) with the velocities of the greatest compression (the normal impulse does no
work then, the cloth's none either). Written L(ξ) = loss − ε(…) − ε′(…) − 2T·s_c, L(ξ_c) ≥ 0 and the impact ends
at the first zero of L beyond ξ_c (a terminal event, direction −1); L(ξ_c) ≤ 0 (ε = ε′ = 1) ends it at ξ_c.

DOP853, rtol 1e-13 by default, atol 1e-3·rtol of each component's own scale; the horizon of each phase doubles
until its event is found (bounded).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..budget import bounded, check, solve_ivp

__all__ = ["RefereeSpheres", "solve"]

MAX_DOUBLINGS = 80  # horizons double from ξ_c's scale: 2⁸⁰ covers any impulse a double can hold


@dataclass(frozen=True)
class RefereeSpheres:
    """Velocities after the impact and what the integration saw."""

    v1: np.ndarray
    w1: np.ndarray
    v1p: np.ndarray
    w1p: np.ndarray
    xi_c: np.ndarray  # normal impulse at the greatest compression
    xi: np.ndarray  # normal impulse at the end
    T: np.ndarray  # tangential impulse on M′ (y, z)
    s_c: np.ndarray  # slip at the greatest compression (y, z)
    stopped: np.ndarray  # bool: the slip stopped during the impact
    cloth_pulls: np.ndarray  # bool: a bilateral cloth had to pull a ball down (a pushing cloth would differ)
    nfev: np.ndarray
    label: str


def _rates(y: np.ndarray, s0: tuple[float, float], M: float, Mp: float, R: float, Rp: float, k: float,
           kp: float, f: float, on_cloth: bool) -> tuple[list[float], float, float]:
    """dy/dξ (the module's equations) and the cloth's rates (n, n′) for one state, in floats."""
    uy, uz = _slip(y, s0, R, Rp)
    un = math.hypot(uy, uz)
    Fx = -1.0
    Fy = -f * uy / un if (f and un > 0) else 0.0
    Fz = -f * uz / un if (f and un > 0) else 0.0
    n, npr = (-Fz, Fz) if on_cloth else (0.0, 0.0)
    # R x̂ × F = R(0, −F_z, F_y); (−R′ x̂) × (−F) = R′ x̂ × F = R′(0, −F_z, F_y)
    cw, cwp = k / (M * R), kp / (Mp * Rp)
    rates = [Fx / M, Fy / M, (Fz + n) / M, 0.0, -cw * Fz, cw * Fy,
             -Fx / Mp, -Fy / Mp, (-Fz + npr) / Mp, 0.0, -cwp * Fz, cwp * Fy,
             -Fx, -Fy, -Fz, n, npr]
    return rates, n, npr


def _slip(y: np.ndarray, s0: tuple[float, float], R: float, Rp: float) -> tuple[float, float]:
    """The slip of M on M′: its initial value plus the change the state's velocity changes make,
    w × R x̂ = R(0, w_z, −w_y) and w′ × (−R′ x̂) = −R′(0, w′_z, −w′_y)."""
    _vx, vy, vz, _wx, wy, wz, _pvx, pvy, pvz, _pwx, pwy, pwz = y[:12].tolist()
    return s0[0] + (vy + R * wz) - (pvy - Rp * pwz), s0[1] + (vz - R * wy) - (pvz + Rp * pwy)


def _one(M: float, Mp: float, R: float, Rp: float, k: float, kp: float, v: np.ndarray, w: np.ndarray,
         vp: np.ndarray, wp: np.ndarray, f: float, eps: float, epsp: float, on_cloth: bool, rtol: float
         ) -> tuple[np.ndarray, float, float, np.ndarray, bool, bool, int]:
    base = np.concatenate([v, w, vp, wp])
    y0 = np.zeros(17)
    xi_scale = abs(float(v[0] - vp[0])) / (1 / M + 1 / Mp)  # the compression's impulse, a scale only
    X = xi_scale
    dV = abs(float(v[0] - vp[0])) * (1 + f)  # the changes' scales: the ball's own, from the compression's impulse
    dVp = dV * M / Mp
    scale = np.array([dV] * 3 + [dV / R] * 3 + [dVp] * 3 + [dVp / Rp] * 3 + [xi_scale * (1 + f)] * 5)
    atol = 1e-3 * rtol * scale
    I, Ip = M * R * R / k, Mp * Rp * Rp / kp  # noqa: E741
    s0t = _slip(np.concatenate([base, np.zeros(5)]), (0.0, 0.0), R, Rp)
    s0 = np.array(s0t)
    s0n = float(np.hypot(*s0))
    pulls = False
    nfev = 0

    def law(y: np.ndarray, s_c: np.ndarray) -> float:
        dv, dw, dvp, dwp = y[0:3], y[3:6], y[6:9], y[9:12]
        loss = -(M * float(dv @ (2 * base[0:3] + dv)) + I * float(dw @ (2 * base[3:6] + dw))
                 + Mp * float(dvp @ (2 * base[6:9] + dvp)) + Ip * float(dwp @ (2 * base[9:12] + dwp)))
        lost = M * float(dv @ dv) + I * float(dw @ dw)
        lostp = Mp * float(dvp @ dvp) + Ip * float(dwp @ dwp)
        return loss - eps * lost - epsp * lostp - 2 * float(y[13] * s_c[0] + y[14] * s_c[1])

    def run(y: np.ndarray, xi: float, sliding: bool, target: str, s_c: np.ndarray | None
            ) -> tuple[np.ndarray, float, str]:
        """Integrate from (ξ, y) until the target event (compression or law) or the slip's stop."""
        nonlocal pulls, nfev
        ff = f if sliding else 0.0

        def rhs(_xi: float, yy: np.ndarray) -> list[float]:
            nonlocal pulls
            r, n, npr = _rates(yy, s0t, M, Mp, R, Rp, k, kp, ff, on_cloth)
            if n < 0 or npr < 0:
                pulls = True
            return [x * X for x in r]  # d/dσ, σ = ξ/X

        e0 = s0 / s0n if s0n > 0 else s0

        def stops(_xi: float, yy: np.ndarray) -> float:
            sy, sz = _slip(yy, s0t, R, Rp)
            return sy * float(e0[0]) + sz * float(e0[1])

        stops.terminal = True
        stops.direction = -1

        if target == "compression":
            def goal(_xi: float, yy: np.ndarray) -> float:
                return float(base[0] - base[6]) + float(yy[0] - yy[6])
        else:
            assert s_c is not None

            def goal(_xi: float, yy: np.ndarray) -> float:
                return law(yy, s_c)
        goal.terminal = True
        goal.direction = -1
        events = [goal, stops] if sliding else [goal]
        # the integration runs in σ = ξ/X, of order 1: scipy locates events to an absolute 4 ulp of the
        # independent variable, which in ξ itself (1e-13 kg·m/s for a light ball) would be 0.5 % of it
        span = 1.0
        t0 = xi / X
        for _ in range(MAX_DOUBLINGS):
            sol = check(solve_ivp(bounded(rhs), (t0, t0 + span), y, method="DOP853", rtol=rtol, atol=atol,
                                  events=events))
            nfev += sol.nfev
            if sol.status == 1:
                hit_goal = sol.t_events[0].size > 0
                which = "goal" if hit_goal else "stop"
                if hit_goal and sliding and sol.t_events[1].size and sol.t_events[1][0] < sol.t_events[0][0]:
                    which = "stop"
                i = 0 if which == "goal" else 1
                return np.array(sol.y_events[i][0]), float(sol.t_events[i][0]) * X, which
            y, t0 = np.array(sol.y[:, -1]), float(sol.t[-1])
            span *= 2
        raise ArithmeticError("referee (spheres): no end of the phase within 2^80 of the compression's impulse")

    def hold_check(y: np.ndarray) -> None:
        """After the stop: the normal impulse alone must move no contact point tangentially."""
        r, _, _ = _rates(y, s0t, M, Mp, R, Rp, k, kp, 0.0, on_cloth)
        ry = (r[1] + R * r[5]) - (r[7] - Rp * r[11])
        rz = (r[2] - R * r[4]) - (r[8] + Rp * r[10])
        if math.hypot(ry, rz) > 1e-12 * (1 / M + 1 / Mp):
            raise ArithmeticError("referee (spheres): the normal impulse moves the held contact")

    if float(v[0] - vp[0]) <= 0:
        raise ValueError("referee (spheres): the balls do not approach")
    state = {"sliding": f > 0 and s0n > 0, "stopped": False}

    def phase(y: np.ndarray, xi: float, target: str, s_c: np.ndarray | None) -> tuple[np.ndarray, float]:
        """Up to the target event, holding the contact once the slip stops on the way."""
        while True:
            y, xi, what = run(y, xi, state["sliding"], target, s_c)
            if what == "goal":
                return y, xi
            state["sliding"], state["stopped"] = False, True
            hold_check(y)

    y, xi = phase(y0, 0.0, "compression", None)
    xi_c = xi
    s_c = np.array(_slip(y, s0t, R, Rp))
    if law(y, s_c) > 0:  # restitution, until law (6) balances
        y, xi = phase(y, xi, "law", s_c)
    stopped = state["stopped"]
    return np.concatenate([base + y[:12], y[12:]]), xi_c, xi, s_c, stopped, pulls, nfev


def solve(scene: Mapping[str, np.ndarray], on_cloth: bool, rtol: float = 1e-13) -> RefereeSpheres:
    """The referee over a batch of scenes (the registry's keys M, Mp, R, Rp, k, kp, v, w, vp, wp, f, eps, epsp),
    scene by scene."""
    keys = ("M", "Mp", "R", "Rp", "k", "kp", "f", "eps", "epsp")
    vecs = ("v", "w", "vp", "wp")
    shape = np.broadcast_shapes(*(np.shape(scene[x]) for x in keys),
                                *(np.shape(scene[x])[:-1] for x in vecs))
    sc = [np.broadcast_to(np.asarray(scene[x], dtype=float), shape) for x in keys]
    vc = [np.broadcast_to(np.asarray(scene[x], dtype=float), (*shape, 3)) for x in vecs]
    out = {x: np.zeros((*shape, 3)) for x in ("v1", "w1", "v1p", "w1p")}
    xi_c, xi, nfev = np.zeros(shape), np.zeros(shape), np.zeros(shape, dtype=int)
    T, s_c = np.zeros((*shape, 2)), np.zeros((*shape, 2))
    stopped, pulls = np.zeros(shape, dtype=bool), np.zeros(shape, dtype=bool)
    for idx in np.ndindex(shape):
        M, Mp, R, Rp, k, kp, f, eps, epsp = (float(a[idx]) for a in sc)
        v, w, vp, wp = (np.array(a[idx]) for a in vc)
        y, xc, xe, sC, st, pl, ne = _one(M, Mp, R, Rp, k, kp, v, w, vp, wp, f, eps, epsp, on_cloth, rtol)
        out["v1"][idx], out["w1"][idx], out["v1p"][idx], out["w1p"][idx] = y[0:3], y[3:6], y[6:9], y[9:12]
        xi_c[idx], xi[idx], T[idx], s_c[idx] = xc, xe, y[13:15], sC
        stopped[idx], pulls[idx], nfev[idx] = st, pl, ne
    where = "on the cloth (bilateral, n°13)" if on_cloth else "free"
    return RefereeSpheres(out["v1"], out["w1"], out["v1p"], out["w1p"], xi_c, xi, T, s_c, stopped,
                          pulls & on_cloth, nfev,
                          f"referee: Newton–Euler in the normal impulse {where}, law (6) evaluated literally "
                          f"(DOP853, rtol {rtol:g})")
