"""Kind ``cloth``: a ball sliding on the cloth, then rolling (§II n°7): each claim and formula as a row,
checked against a direct integration of eqs (2) (``reference.integrate_cloth``)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import Experiment, Node
from ..mechanics import cloth, reference
from ..mechanics.budget import bounded, check, solve_ivp
from .base import Computed, FigureSpec, Reproduction, layer, modern_rows, read_ball, rows_for
from .kinematics import material_point_velocity

_CHECKS = ("slip_direction", "eq4_motion", "eq5_as_printed", "t_roll", "x_roll", "y_roll_as_printed",
           "footnote_point", "coriolis_theorem")
_CLAIMS = ("q_abstraction", "eq1_slip", "eq2_equations", "eq3_ratio", "spins_integral", "eq3_transformed",
           "slip_direction_edges", "euler_parabola", "eq3_frame", "eq4_velocity", "eq5_corrected", "roll_condition",
           "coriolis_height", "coriolis_edges", "t_roll_edges", "y_roll_corrected", "tangent_after")
QUANTITIES = (*_CHECKS, *_CLAIMS, "f_today", "oscillation_centre")
COST = 0.7  # CPU seconds of a run with its figures, about: the process pool starts the longest first
MODERN = ("mu_s", "mu_r")


@dataclass(frozen=True)
class Params:
    R: float
    k: float
    f: float
    g: float
    f_roll: float
    fan_speed: float  # m/s: the figure's balls leave along Ox at this speed
    fan_side_spins: tuple[float, ...]  # rad/s about Ox (n): slip oblique to the velocity, hence parabolas
    fan_top_spin: float  # rad/s about Oy (p)


def parse(node: Node, base: Path) -> Params:
    R, k = read_ball(node)
    f = node.number("f", "a friction coefficient", lo=0.0, lo_open=True)
    g = node.number("g", "gravity in m/s²", lo=0.0, lo_open=True)
    f_roll = node.number("f_roll", "a rolling-resistance coefficient", lo=0.0, default=0.0)
    fan = node.child("fan", "a mapping with speed, side_spins, top_spin")
    speed = fan.number("speed", "a speed in m/s", lo=0.0, lo_open=True)
    spins = fan.number_list("side_spins", "spins in rad/s")
    top = fan.number("top_spin", "a spin in rad/s", default=0.0)
    fan.done()
    node.done()
    return Params(R, k, f, g, f_roll, speed, tuple(spins), top)


def _scenes(seed: int, n: int = 12) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.c_[rng.uniform(-3, 3, n), rng.uniform(-3, 3, n), rng.uniform(-150, 150, n), rng.uniform(-150, 150, n)]


def checks(p: Params, seed: int) -> dict[str, float]:
    """Largest discrepancy of each printed formula of n°7 from the integrated motion, over random launches."""
    R, k, f, g = p.R, p.k, p.f, p.g
    worst = dict.fromkeys(_CHECKS, 0.0)
    for vx, vy, wx, wy in _scenes(seed):
        m = cloth.slide(vx, vy, wx, wy, R=R, k=k, f=f, g=g)
        t1 = float(m.t_roll)
        state, t_ev = reference.integrate_cloth(vx, vy, wx, wy, R, k, f, g, 2 * t1 + 0.1)
        ts = np.linspace(0.0, t1 * 0.999, 25)
        ys = np.array([state(t) for t in ts])
        # the direction of the slip up to 0.9 t1, where it is still a tenth of its initial size: nearer the end the
        # integration's error over the vanishing slip dominates (3e-9 rad at 0.999 t1, 1e-11 at 0.9 t1)
        ud = np.array([state(t) for t in np.linspace(0.0, t1 * 0.9, 25)])
        u = np.c_[ud[:, 2] - ud[:, 5] * R, ud[:, 3] + ud[:, 4] * R]
        ang = np.unwrap(np.arctan2(u[:, 1], u[:, 0]))
        worst["slip_direction"] = max(worst["slip_direction"], float(np.ptp(ang)))
        # the paper's frame: Oy along the slip, α the angle of the centre's velocity with Ox
        ey = np.array([vx - wy * R, vy + wx * R]) / float(m.slip0)
        ex = np.array([ey[1], -ey[0]])
        a = math.hypot(vx, vy)
        alpha = math.atan2(vx * ey[0] + vy * ey[1], vx * ex[0] + vy * ex[1])
        X, Y = ys[:, 0:2] @ ex, ys[:, 0:2] @ ey
        scale = a * t1
        x4, y4 = a * math.cos(alpha) * ts, a * math.sin(alpha) * ts - f * g * ts**2 / 2  # eqs (4)
        worst["eq4_motion"] = max(worst["eq4_motion"], float(np.max(np.hypot(X - x4, Y - y4)) / scale))
        y5 = a * math.tan(alpha) * X - f * g / 2 * (1 + math.tan(alpha) ** 2) * X**2  # eq. (5) as printed
        worst["eq5_as_printed"] = max(worst["eq5_as_printed"], float(np.max(np.abs(y5 - Y)) / scale))
        worst["t_roll"] = max(worst["t_roll"], abs(t_ev - t1) / t1)
        v0 = float(m.slip0)
        end = state(t_ev)
        X1, Y1 = end[0:2] @ ex, end[0:2] @ ey
        x1 = a * v0 * math.cos(alpha) / (f * g * (1 + k))  # printed
        y1 = (a * math.sin(alpha) - v0 / (1 + k)) * v0 / (f * g * (1 + k))  # printed
        worst["x_roll"] = max(worst["x_roll"], abs(x1 - X1) / scale)
        worst["y_roll_as_printed"] = max(worst["y_roll_as_printed"], abs(y1 - Y1) / scale)
        # footnote: the point at height h above C moves at (χ + hp, η − hn); printed: constant along Ox,
        # η0 − hn0 − fgt(1 − kh/R) along Oy (in the slip frame)
        for h in (0.3 * R, R / k, 0.9 * R):
            vel = np.c_[ys[:, 2] + h * ys[:, 5], ys[:, 3] - h * ys[:, 4]]
            Vx, Vy = vel @ ex, vel @ ey
            print_y = Vy[0] - f * g * ts * (1 - k * h / R)
            err = max(float(np.max(np.abs(Vx - Vx[0]))), float(np.max(np.abs(Vy - print_y)))) / a
            worst["footnote_point"] = max(worst["footnote_point"], err)
            if h == R / k:
                drift = float(np.max(np.hypot(Vx - Vx[0], Vy - Vy[0]))) / a
                worst["coriolis_theorem"] = max(worst["coriolis_theorem"], drift)
    return worst


# -- issue 13: every claim of n°7, each checked against what does not use it ---------------------------------------
def edge_scenes(p: Params) -> tuple[tuple[float, ...], ...]:
    """Launches where an « always » of n°7 could fail: (χ0, η0, n0, p0, k, f). A slip of 1e-4 of the speed (nearly
    rolling), a ball spinning in place (a = 0), spins of 900 rad/s, a draw shot (slip along the velocity), a slip
    across the velocity, a thin shell (k = 3/2, the smallest k of a ball of concentric homogeneous layers, n°6) at
    f = 0.6 and a ball heavy at its centre (k = 20) at f = 0.05."""
    R, k, f = p.R, p.k, p.f
    return ((2.0, 0.0, 0.0, (2.0 - 2e-4) / R, k, f), (0.0, 0.0, 120.0, 0.0, k, f), (0.3, -0.2, -900.0, 400.0, k, f),
            (2.0, 0.0, 0.0, -200.0, k, f), (2.0, 0.0, 50.0, 2.0 / R, k, f), (1.5, 1.0, 80.0, -40.0, 1.5, 0.6),
            (-1.0, 2.0, -30.0, 60.0, 20.0, 0.05))


def _frame(vx: float, vy: float, wx: float, wy: float, R: float) -> tuple[np.ndarray, np.ndarray, float]:
    """The paper's axes after line 282: Oy along the initial slip, Ox completing a right-handed (Ox, Oy, Oz)."""
    u = np.array([vx - wy * R, vy + wx * R])
    v0 = float(np.hypot(*u))
    ey = u / v0
    return np.array([ey[1], -ey[0]]), ey, v0


def _integrate_3d(v0: np.ndarray, w0: np.ndarray, R: float, k: float, f: float, g: float, t_end: float,
                  u_reg: float = 0.0, y0: np.ndarray | None = None, t0: float = 0.0) -> object:
    """The ball integrated as a rigid body in space (``cloth.rigid_rhs``): a dense solution on [t0, t_end]. With
    u_reg = 0 (Coulomb's law) it stops where the slip, projected on its initial direction, crosses zero."""
    start = np.r_[0.0, 0.0, R, v0, w0] if y0 is None else y0
    rhs = bounded(lambda _t, y: cloth.rigid_rhs(y, R=R, k=k, f=f, g=g, u_reg=u_reg))
    if u_reg > 0:  # the slip relaxes at (1 + k) f g/u_reg: stiff
        return check(solve_ivp(rhs, (t0, t_end), start, method="Radau", rtol=1e-11, atol=1e-15, dense_output=True,
                               jac=lambda _t, y: cloth.rigid_jac(y, R=R, k=k, f=f, g=g, u_reg=u_reg)))
    u0 = cloth.point_velocity(start[3:6], start[6:9], -R)[:2]

    def stops(_t: float, y: np.ndarray) -> float:
        return float(cloth.point_velocity(y[3:6], y[6:9], -R)[:2] @ u0)

    stops.terminal = True
    return check(solve_ivp(rhs, (t0, t_end), start, method="DOP853", rtol=1e-11, atol=1e-14, dense_output=True,
                           events=stops))


def claims(p: Params, seed: int) -> dict[str, float]:
    """The claims of n°7 that issue 13 adds, each as the largest discrepancy (dimensionless) over the 12 random
    launches of ``checks`` and, for the « always » claims, the ``edge_scenes``. Velocities are relative to
    s = |V0| + R|ω0|, lengths to s·t1, accelerations to f g."""
    R, k0, f0, g = p.R, p.k, p.f, p.g
    rng = np.random.default_rng(seed + 13)
    out = dict.fromkeys(_CLAIMS, 0.0)

    # eq. (1) and eqs (2) at random states, spin q about the vertical included: rigid-body kinematics and
    # Newton–Euler (``cloth.rigid_rhs``) against the paper's components
    for _ in range(200):
        v = np.r_[rng.uniform(-3, 3, 2), 0.0]
        w = rng.uniform(-300, 300, 3)
        k, f = rng.uniform(1.5, 20), rng.uniform(0.01, 1.0)
        s = float(np.hypot(*v[:2]) + R * np.hypot(*w[:2]))
        chi, eta, n, pp = v[0], v[1], w[0], w[1]
        ux, uy = chi - pp * R, eta + n * R  # eq. (1) as printed (n for the digitised text's r)
        c = material_point_velocity(v, w, np.array([0.0, 0.0, -R]))
        out["eq1_slip"] = max(out["eq1_slip"], float(np.max(np.abs([c[0] - ux, c[1] - uy, c[2]]))) / s)
        vv = math.hypot(ux, uy)
        printed2 = np.array([-ux / vv * f * g, -uy / vv * f * g, -uy / vv * f * g * k / R, ux / vv * f * g * k / R])
        d = cloth.rigid_rhs(np.r_[0.0, 0.0, R, v, w], R=R, k=k, f=f, g=g)
        err = np.abs(d[[3, 4, 6, 7]] - printed2) * np.array([1, 1, R / k, R / k]) / (f * g)
        out["eq2_equations"] = max(out["eq2_equations"], float(np.max(err)), abs(float(d[8])) * R / (k * f * g))
        # eq. (3) (first), cross-multiplied so that a vanishing component of the slip divides nothing:
        # dχ/dt (η + nR) − dη/dt (χ − pR) = 0, relative to f g v
        out["eq3_ratio"] = max(out["eq3_ratio"], abs(float(d[3] * uy - d[4] * ux)) / (f * g * vv))

    scenes = [(*sc, k0, f0) for sc in _scenes(seed)]
    for j, (vx, vy, wx, wy, k, f) in enumerate([*scenes, *edge_scenes(p)]):
        edge = j >= len(scenes)
        ex, ey, v0 = _frame(vx, vy, wx, wy, R)
        a = math.hypot(vx, vy)
        s = a + R * math.hypot(wx, wy)
        t1 = v0 / ((1 + k) * f * g)
        state, t_ev = reference.integrate_cloth(vx, vy, wx, wy, R, k, f, g, 2 * t1 + 0.1)
        ts = np.linspace(0.0, 0.999 * t_ev, 41)
        ys = np.array([state(t) for t in ts])
        chi, eta, n, pp = ys[:, 2], ys[:, 3], ys[:, 4], ys[:, 5]
        if edge:
            ud = np.array([state(t) for t in np.linspace(0.0, 0.9 * t_ev, 25)])
            u = np.c_[ud[:, 2] - ud[:, 5] * R, ud[:, 3] + ud[:, 4] * R]
            ang = np.unwrap(np.arctan2(u[:, 1], u[:, 0]))
            out["slip_direction_edges"] = max(out["slip_direction_edges"], float(np.ptp(ang)))
            # in units of s/((1 + k) f g), the time friction takes to change the velocities by s: the slip is a
            # difference of velocities of size s, so an integration error rtol·s moves the event by that much
            # (relative to t1 it would be rtol·s/v0, 1e-7 in the nearly rolling launch)
            out["t_roll_edges"] = max(out["t_roll_edges"], abs(t_ev - t1) * (1 + k) * f * g / s)
        # the integrals after eq. (3): pR = p0R − k(χ − χ0), nR = n0R + k(η − η0)
        e_sp = np.max(np.abs(np.r_[pp * R - (wy * R - k * (chi - vx)), n * R - (wx * R + k * (eta - vy))])) / s
        out["spins_integral"] = max(out["spins_integral"], float(e_sp))
        # eq. (3) transformed: its denominators are the slip's components (their ratio is then v_y/v_x)
        D1, D2 = chi * (1 + k) - k * vx - wy * R, eta * (1 + k) - k * vy + wx * R
        e_tr = np.max(np.abs(np.r_[D1 - (chi - pp * R), D2 - (eta + n * R)])) / s
        out["eq3_transformed"] = max(out["eq3_transformed"], float(e_tr))
        # Euler's theorem: the path is a parabola, x(t) and y(t) quadratic in t (least squares of degree 2)
        res = max(float(np.max(np.abs(np.polyval(np.polyfit(ts, ys[:, i], 2), ts) - ys[:, i]))) for i in (0, 1))
        out["euler_parabola"] = max(out["euler_parabola"], res / (s * t_ev))
        # eqs (3) (second), in the slip frame: χ = χ0, η = η0 − fgt, nR = n0R − fgkt, p = p0
        V, W = ys[:, 2:4], ys[:, 4:6]
        X_, Y_ = V @ ex, V @ ey
        nF, pF = W @ ex, W @ ey
        e3 = np.r_[X_ - X_[0], Y_ - (Y_[0] - f * g * ts), nF * R - (nF[0] * R - f * g * k * ts), (pF - pF[0]) * R]
        out["eq3_frame"] = max(out["eq3_frame"], float(np.max(np.abs(e3))) / s)
        # the onset: 0 = η + nR = η0 + n0R − fg(1 + k)t
        slip = Y_ + nF * R
        e_r = np.max(np.abs(slip - (Y_[0] + nF[0] * R - f * g * (1 + k) * ts))) / s
        out["roll_condition"] = max(out["roll_condition"], float(e_r))
        # the footnote's « si l'on a h = R/k »: the height whose point keeps its velocity, found from the motion
        vel = np.c_[V, np.zeros(len(ts))]
        om = np.c_[W, np.zeros(len(ts))]
        A = (vel - vel[0]).ravel()
        B = (cloth.point_velocity(vel, om, 1.0) - vel - (cloth.point_velocity(vel[0], om[0], 1.0) - vel[0])).ravel()
        h_star = -float(A @ B) / float(B @ B)
        out["coriolis_height"] = max(out["coriolis_height"], abs(h_star - R / k) / R)
        if edge:
            pv = cloth.point_velocity(vel, om, R / k)
            out["coriolis_edges"] = max(out["coriolis_edges"], float(np.max(np.abs(pv - pv[0]))) / s)
        if not edge:
            # eqs (4), first line: dx/dt = a cos α, dy/dt = a sin α − fgt (α the angle of V0 with Ox)
            alpha = math.atan2(vx * ey[0] + vy * ey[1], vx * ex[0] + vy * ex[1])
            e4 = np.r_[X_ - a * math.cos(alpha), Y_ - (a * math.sin(alpha) - f * g * ts)]
            out["eq4_velocity"] = max(out["eq4_velocity"], float(np.max(np.abs(e4))) / s)
            # eq. (5) as derived from (4): y = x tang α − fg (1 + tang² α) x²/(2a²)
            Xp, Yp = ys[:, 0:2] @ ex, ys[:, 0:2] @ ey
            y5 = Xp * math.tan(alpha) - f * g * (1 + math.tan(alpha) ** 2) * Xp**2 / (2 * a**2)
            out["eq5_corrected"] = max(out["eq5_corrected"], float(np.max(np.abs(y5 - Yp))) / (a * t_ev))
            # y1 with the factor 1/2 of fgt²/2: (a sin α − v0/(2(1 + k))) v0/(fg(1 + k))
            end = state(t_ev)
            y1 = (a * math.sin(alpha) - v0 / (2 * (1 + k))) * v0 / (f * g * (1 + k))
            out["y_roll_corrected"] = max(out["y_roll_corrected"], abs(y1 - float(end[0:2] @ ey)) / (a * t1))
        # the spin q about the vertical: it stays constant and changes nothing (3-D integration, q0 = ±250 rad/s
        # against q0 = 0, up to 0.9 t1)
        q0 = 250.0 if j % 2 else -250.0
        with_q = _integrate_3d(np.r_[vx, vy, 0.0], np.r_[wx, wy, q0], R, k, f, g, 0.9 * t_ev)
        no_q = _integrate_3d(np.r_[vx, vy, 0.0], np.r_[wx, wy, 0.0], R, k, f, g, 0.9 * t_ev)
        tq = np.linspace(0.0, 0.9 * t_ev, 25)
        yq, y0 = with_q.sol(tq), no_q.sol(tq)
        dq = max(float(np.max(np.abs(yq[8] - q0))) * R / s, float(np.max(np.abs(yq[0:2] - y0[0:2]))) / (s * t_ev),
                 float(np.max(np.abs(yq[3:8] - y0[3:8]) * np.array([[1], [1], [1], [R], [R]]))) / s)
        out["q_abstraction"] = max(out["q_abstraction"], dq)
        # « à partir de ce point, le centre C décrira la tangente »: the rigid body integrated through the onset
        # with a friction law that needs no switch (regularised over 1e-9 of the initial slip), to 3 t1; the
        # distance of C from the tangent at the onset, relative to s·t1, and the slip after 1.01 t1, relative to v0
        slide3 = _integrate_3d(np.r_[vx, vy, 0.0], np.r_[wx, wy, 0.0], R, k, f, g, 2 * t1 + 0.1)
        t_on = float(slide3.t_events[0][0])
        on = slide3.sol(t_on)
        sol = _integrate_3d(on[3:6], on[6:9], R, k, f, g, 3 * t_on, u_reg=1e-9 * v0, y0=on, t0=t_on)
        tl = np.linspace(t_on, 3 * t_on, 41)
        after = sol.sol(tl)
        d = after[0:2] - on[0:2, None]
        tan = on[3:5] / np.hypot(*on[3:5])
        off = float(np.max(np.abs(d[0] * tan[1] - d[1] * tan[0]))) / (s * t_ev)
        later = after[:, tl >= 1.01 * t_on]
        slip_after = float(np.max(np.hypot(later[3] - later[7] * R, later[4] + later[6] * R))) / v0
        out["tangent_after"] = max(out["tangent_after"], off, slip_after)
    return out


def f_today() -> tuple[float, float, float]:
    """Today's measured range of the ball-cloth sliding friction (modern-values.csv, symbol mu_s): (low, high,
    midpoint) of the union of the sources' ranges."""
    rows = modern_rows(("mu_s",), {"mu_s": (math.nan, "")})
    lo = min(r["low"] for r in rows if r["low"] is not None)
    hi = max(r["high"] for r in rows if r["high"] is not None)
    return lo, hi, 0.5 * (lo + hi)


def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    c = checks(p, exp.seed)
    how = "largest discrepancy from the integrated motion (eqs 2) over 12 random launches, relative to a·t1"
    computed = {key: Computed(v, how) for key, v in c.items()}
    computed["eq5_as_printed"] = Computed(c["eq5_as_printed"], how, lambda _p: (
        "as printed, y = a tang α x − (fg/2)(1 + tang² α) x² is not homogeneous in units; eliminating t between "
        "eqs (4), t = x/(a cos α), gives y = x tang α − fg(1 + tang² α) x²/(2a²), which the integration follows "
        "(row 'eq5_corrected'; the two agree only where a = 1 in the unit of speed): a slip of the derivation (a "
        "kept in the first term, 1/a² lost in the second), "
        "most likely the 1883 original's, since the digitised text reads cleanly there"))
    computed["y_roll_as_printed"] = Computed(c["y_roll_as_printed"], how, lambda _p: (
        "eqs (4) at t1 = v0/(fg(1 + k)) give y1 = (a sin α − v0/(2(1 + k))) v0/(fg(1 + k)) (row "
        "'y1_corrected'): the printed formula lacks the factor 1/2 of the term fgt²/2, a slip of the derivation"))
    cl = claims(p, exp.seed)
    h = float(cloth.centre_of_oscillation(p.R, p.k))
    random = "over 12 random launches"
    edges = "over the edge launches (nearly rolling, spinning in place, 900 rad/s, draw, slip across, k = 3/2 at " \
            "f = 0.6, k = 20 at f = 0.05)"
    both = random + " and " + edges[5:]
    hows = {
        "q_abstraction": "the ball integrated as a rigid body in space with q0 = ±250 rad/s against q0 = 0, to 0.9 t1, "
                         f"{both}: largest change of q (×R/s), of the path (/s·t1) and of the velocities (/s)",
        "eq1_slip": "velocity of the ball's material point at the contact, −R e_z from C (Oz out of the cloth), "
                    "differentiated from its position under the rigid motion (translation and rotation, "
                    "fourth-order central difference, no vector product), against (χ − pR, η + nR), at 200 random "
                    "states (spin q included); relative to |V| + R|ω|",
        "eq2_equations": "Newton–Euler with the torque (−R e_z) × F against eqs (2) (and dq/dt = 0) at 200 random "
                         "states, k in [3/2, 20], f in [0.01, 1]; relative to f g (spins ×R/k)",
        "eq3_ratio": "dχ/dt (η + nR) − dη/dt (χ − pR) from Newton–Euler at 200 random states, relative to f g v "
                     "(cross-multiplied: a vanishing component of the slip divides nothing)",
        "spins_integral": f"pR − (p0R − k(χ − χ0)) and nR − (n0R + k(η − η0)) along the integrated motion, {both}; "
                          "relative to s = |V0| + R|ω0|",
        "eq3_transformed": f"the denominators χ(1 + k) − kχ0 − p0R, η(1 + k) − kη0 + n0R against the slip's components "
                           f"χ − pR, η + nR along the integrated motion, {both}; relative to s",
        "slip_direction_edges": f"radians turned by the slip up to 0.9 t1, {edges}",
        "euler_parabola": f"residual of a least-squares fit of x(t), y(t) by polynomials of degree 2 to the integrated "
                          f"path on [0, 0.999 t1], {both}; relative to s·t1",
        "eq3_frame": f"χ − χ0, η − (η0 − fgt), nR − (n0R − fgkt), (p − p0)R in the slip frame along the integrated "
                     f"motion, {both}; relative to s",
        "eq4_velocity": f"dx/dt − a cos α and dy/dt − (a sin α − fgt) in the slip frame, {random}; relative to s",
        "eq5_corrected": f"y − (x tang α − fg(1 + tang² α) x²/(2a²)) along the integrated path, {random}; "
                         "relative to a·t1",
        "roll_condition": f"η + nR − (η0 + n0R − fg(1 + k)t) in the slip frame, {both}; relative to s",
        "coriolis_height": "the height h whose point v + ω × (h e_z) keeps its velocity best (least squares over the "
                           f"motion to 0.999 t1), against R/k, {both}; relative to R",
        "coriolis_edges": f"largest change of the velocity of the point at R/k above C while sliding, {edges}; "
                          "relative to s",
        "t_roll_edges": f"event time of the integration against v0/(fg(1 + k)), {edges}; in units of "
                        "s/((1 + k) f g)",
        "y_roll_corrected": f"(a sin α − v0/(2(1 + k))) v0/(fg(1 + k)) against the integrated onset, {random}; "
                            "relative to a·t1",
        "tangent_after": "the rigid body integrated through the onset (Coulomb's law to the slip's zero, then a "
                         "friction law regularised over 1e-9 of the initial slip, Radau, to 3 t1), "
                         f"{both}: distance of C from the tangent at the onset (/s·t1) and the slip after 1.01 t1 "
                         "(/v0)",
    }
    computed.update({key: Computed(cl[key], text) for key, text in hows.items()})
    lo, hi, mid = f_today()
    computed["f_today"] = Computed(None, (
        f"a measurement: Coriolis's f, which no premise of the paper gives (today's measured ball-cloth sliding "
        f"friction {lo:g}–{hi:g}, midpoint {mid:g}, modern-values.csv mu_s: the today column)"))
    ks = (p.k, 1.5, 20.0)
    osc = max(abs(cloth.pendulum_centre_height(p.R, k) - p.R / k) / p.R for k in ks)
    computed["oscillation_centre"] = Computed(osc, (
        "the centre of oscillation of the ball hung from its contact point, from the period of the integrated "
        f"pendulum (k = {', '.join(f'{k:g}' for k in ks)}), against the footnote's h = R/k; relative to R. For the "
        f"homogeneous ball h = {h / p.R:.3g} R, {(p.R + h) / (2 * p.R):.3g} of the "
        "diameter above the cloth"))
    modern = modern_rows(exp.modern, {"mu_s": (p.f, "Coriolis's f (n°7)"),
                                      "mu_r": (p.f_roll, "rolling resistance (left aside by the paper)")})
    return Reproduction(exp, rows_for(exp, computed), (), (_figure(p),), modern)


def _figure(p: Params) -> FigureSpec:
    layers = []
    for j, n in enumerate(p.fan_side_spins):
        m = cloth.slide(p.fan_speed, 0.0, n, p.fan_top_spin, R=p.R, k=p.k, f=p.f, g=p.g)
        t = np.linspace(0.0, 2.0 * float(m.t_roll) + 1e-9, 120)
        x, y, _, _ = cloth.state_at(t, p.fan_speed, 0.0, n, p.fan_top_spin, R=p.R, k=p.k, f=p.f, g=p.g, f_roll=p.f_roll)
        layers.append(layer("line", x, y, label=f"$n_0$ = {n:g} rad/s".replace("-", "−"), color=f"C{j % 10}"))
        layers.append(layer("points", [float(m.x_roll)], [float(m.y_roll)], color=f"C{j % 10}", marker="o"))
    top = "no rotation about Oy" if p.fan_top_spin == 0 else f"a rotation p0 = {p.fan_top_spin:g} rad/s about Oy"
    return FigureSpec("trajectories", "Euler's parabolas on the cloth, then the tangent (§II n°7)",
                      "x (m), initial velocity along Ox", "y (m)", tuple(layers), aspect="equal", legend="below",
                      caption=f"a = {p.fan_speed:g} m/s, f = {p.f:g}; equal scales on x and y; dots: onset of rolling, "
                              "at $t_1 = v_0/(fg(1 + k))$",
                      reading=(
                          f"The path of the centre of a ball sent along Ox at {p.fan_speed:g} m/s with {top} and a "
                          f"rotation n0 about Ox (colours), on cloth of friction f = {p.f:g}: Euler's parabola while "
                          "the ball slides, then, from the dot on, the tangent once it rolls. The faster the rotation, "
                          "the more the path bends and the later rolling starts; opposite rotations give mirror "
                          "paths."))
