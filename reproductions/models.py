"""Single scenes for ``resal simulate``: each model declares its parameters (names in the paper's notation,
SI units, defaults, admissible ranges) and maps validated inputs to the physics."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from .config import parse_number
from .errors import InputError
from .mechanics import cloth, cue, cushion, impact, plane, spheres

__all__ = ["MODELS", "Model", "Param", "simulate"]


@dataclass(frozen=True)
class Param:
    name: str
    default: float
    doc: str
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False

    def check(self, value: float) -> str | None:
        if not math.isfinite(value):
            return "a finite number"
        if self.lo is not None and (value < self.lo or (self.lo_open and value == self.lo)):
            return self.range_text()
        if self.hi is not None and (value > self.hi or (self.hi_open and value == self.hi)):
            return self.range_text()
        return None

    def range_text(self) -> str:
        if self.lo is not None and self.hi is not None:
            return f"a number in {'(' if self.lo_open else '['}{self.lo:g}, {self.hi:g}{')' if self.hi_open else ']'}"
        if self.lo is not None:
            return f"a number {'>' if self.lo_open else '≥'} {self.lo:g}"
        return "a number"


@dataclass(frozen=True)
class Model:
    name: str
    doc: str
    params: tuple[Param, ...]
    run: Callable[..., tuple[str, dict[str, Any]]]


def _direct(v: dict[str, float]) -> tuple[str, dict[str, float]]:
    r = impact.direct_impact(v["M"], v["Mp"], v["V0"], v["V0p"], v["eps"], v["epsp"])
    return r.method, {"V1": float(r.V1), "V1p": float(r.V1p), "newton_e": float(r.newton_e),
                      "kinetic_energy_lost": 0.5 * float(r.vis_viva_lost)}


def _wall(v: dict[str, float]) -> tuple[str, dict[str, float]]:
    V1 = float(impact.infinite_mass_impact(v["V0"], v["eps"]))
    return "closed form, §I eq. (9)", {"V1": V1, "ratio": float(impact.velocity_ratio_from_eps(v["eps"]))}


def _plane(v: dict[str, float], method: str = "auto") -> tuple[str, dict[str, Any]]:
    if v["zeta0"] >= 0:
        raise InputError(f"--set zeta0={v['zeta0']:g}",
                         "ζ0 must be negative: the sphere approaches the plane (§III n°8)")
    r = plane.plane_impact(v["chi0"], v["zeta0"], v["p0"], v["R"], v["k"], v["f"], v["nu"], method)
    return r.method, {"chi1": float(r.chi1), "zeta1": float(r.zeta1), "p1": float(r.p1),
                      "regime": "slides throughout (Résal's eqs (6))" if bool(r.sliding) else
                      "slip stops, then rolls"}


def _ricochet(v: dict[str, float]) -> tuple[str, dict[str, Any]]:
    n = int(v["n"])
    if n != v["n"]:
        raise InputError(f"--set n={v['n']:g}", "n must be a whole number of impacts")
    r = plane.ricochet(v["a0"], math.radians(v["alpha0"]), v["p0"], v["R"], v["k"], v["f"], v["nu"], v["g"], n)
    return r.method, {"ranges": [float(x) for x in r.ranges], "times": [float(x) for x in r.times],
                      "imprints": [float(x) for x in r.imprints],
                      "sliding": [bool(x) for x in r.sliding]}


def _cloth(v: dict[str, float]) -> tuple[str, dict[str, Any]]:
    m = cloth.slide(v["vx"], v["vy"], v["wx"], v["wy"], v["R"], v["k"], v["f"], v["g"])
    out: dict[str, Any] = {"t_roll": float(m.t_roll), "x_roll": float(m.x_roll), "y_roll": float(m.y_roll),
                           "vx_roll": float(m.vx_roll), "vy_roll": float(m.vy_roll)}
    if float(m.slip0) == 0.0:
        out["note"] = "the ball already rolls (no slip): no sliding phase, the trivial answer"
    return m.method, out


def _cue(v: dict[str, float], method: str = "auto") -> tuple[str, dict[str, Any]]:
    b, c, R = v["b"], v["c"], v["R"]
    if b * b + c * c >= R * R:
        raise InputError(f"--set b={b:g} --set c={c:g}", f"the contact point must lie on the ball: b² + c² < R² "
                                                           f"(R = {R:g})")
    i = math.radians(v["i"])
    s = cue.cue_stroke(v["M"], v["Mp"], v["V0p"], i, b, c, R, v["k"], v["f"], v["eps"], v["epsp"], method)
    if float(s.cos_phi) <= 0:
        raise InputError(f"--set c={c:g} --set i={v['i']:g}", "the cue cannot reach that point of the ball "
                                                               "(its axis would meet the ball elsewhere first)")
    phi = math.degrees(math.acos(min(1.0, float(s.cos_phi))))
    return s.method, {"chi1": float(s.chi1), "eta1": float(s.eta1), "n1": float(s.n1), "p1": float(s.p1),
                      "q1": float(s.q1), "V1p": float(s.V1p), "gamma_deg": math.degrees(float(s.gamma)),
                      "phi_deg": phi, "slides_on_cloth": bool(s.slides_on_cloth),
                      "miscue_if_tip_friction_below": math.tan(math.radians(phi))}


def _cushion(v: dict[str, float], method: str = "auto") -> tuple[str, dict[str, Any]]:
    if v["zeta0"] >= 0:
        raise InputError(f"--set zeta0={v['zeta0']:g}", "ζ0 must be negative: the ball approaches the cushion")
    c = cushion.cushion_impact(v["chi0"], v["zeta0"], v["p0"], v["n0"], v["R"], v["k"], v["j"], v["eps"], method)
    return c.method, {"chi1": float(c.chi1), "zeta1": float(c.zeta1), "p1": float(c.p1), "n1": float(c.n1),
                      "rebound_deg": math.degrees(math.atan2(float(c.chi1), float(c.zeta1))),
                      "regime": "slip stops during the impact" if bool(c.slip_stops) else "slides throughout"}


def _ball_ball(v: dict[str, float], method: str = "auto") -> tuple[str, dict[str, Any]]:
    R, Rp, d = v["R"], v["Rp"], v["d"]
    if abs(d - (R + Rp)) > 1e-9 * (R + Rp):
        raise InputError(f"--set d={d:g}", f"the balls must touch: the distance between centres must be R + R′ = "
                                           f"{R + Rp:g} m")
    cut = math.radians(v["cut"])
    V = v["V"]
    vel = [V * math.cos(cut), V * math.sin(cut), 0.0]
    w = [-vel[1] / R * v["roll"], vel[0] / R * v["roll"], v["side"]]
    on_cloth = v["cloth"] != 0
    s = spheres.two_spheres(v["M"], v["Mp"], R, Rp, v["k"], v["k"], vel, w, [0.0] * 3, [0.0] * 3, v["f"], v["eps"],
                            v["eps"], on_cloth=on_cloth, method=method)
    v1, v1p = s.v1.tolist(), s.v1p.tolist()
    return s.method, {"v1": v1, "w1": s.w1.tolist(), "v1p": v1p, "w1p": s.w1p.tolist(),
                      "object_ball_angle_deg": math.degrees(math.atan2(v1p[1], v1p[0])),
                      "cue_ball_angle_deg": math.degrees(math.atan2(v1[1], v1[0])),
                      "regime": "slip stops during the impact" if bool(s.slip_stops) else "slides throughout"}


_EPS = dict(lo=0.0, hi=1.0)
_NU = dict(lo=0.0, hi=1.0, lo_open=True)
_BALL = (Param("R", 0.0305, "radius of the ball (m)", lo=0.0, lo_open=True),
         Param("k", 2.5, "moment of inertia M R²/k (k = 5/2: homogeneous)", lo=0.0, lo_open=True),
         Param("f", 0.2, "sliding friction on the plane", lo=0.0),
         Param("nu", 0.8, "yield ν of the normal velocity, ζ1 = −ν ζ0", **_NU))
MODELS: dict[str, Model] = {
    "direct-impact": Model("direct-impact", "direct impact of M on M′ (§I n°5, eq. 7)", (
        Param("M", 1.0, "mass of the striking body (kg)", lo=0.0, lo_open=True),
        Param("Mp", 1.0, "mass of the struck body (kg)", lo=0.0, lo_open=True),
        Param("V0", 1.0, "velocity of M before the impact (m/s)"),
        Param("V0p", 0.0, "velocity of M′ before the impact (m/s)"),
        Param("eps", 0.0, "Résal's ε of M", **_EPS),
        Param("epsp", 0.0, "Résal's ε′ of M′", **_EPS),
    ), _direct),
    "wall-impact": Model("wall-impact", "impact on an immovable mass: cushion, slab (§I n°5, eq. 9)", (
        Param("V0", 1.0, "normal velocity before the impact (m/s)"),
        Param("eps", 0.29, "Résal's ε of the ball", **_EPS),
    ), _wall),
    "plane-impact": Model("plane-impact", "sphere striking a fixed plane with friction (§III n°8)", (
        Param("chi0", 1.0, "tangential velocity of the centre before (m/s)"),
        Param("zeta0", -1.0, "normal velocity before, negative: approaching (m/s)"),
        Param("p0", 0.0, "rotation before (rad/s); slip v_x = χ − pR"),
        *_BALL,
    ), _plane),
    "ricochet": Model("ricochet", "ricochets on a horizontal plane (§III n°9)", (
        Param("a0", 2.0, "speed of the centre arriving at the first impact (m/s)", lo=0.0, lo_open=True),
        Param("alpha0", 20.0, "its angle below the plane (degrees)", lo=0.0, hi=90.0, lo_open=True, hi_open=True),
        Param("p0", 0.0, "rotation arriving (rad/s)"),
        *_BALL,
        Param("g", 9.81, "gravity (m/s²)", lo=0.0, lo_open=True),
        Param("n", 12.0, "number of impacts", lo=1.0, hi=1000.0),
    ), _ricochet),
    "cushion-impact": Model("cushion-impact", "ball against a cushion, friction and side spin (§IV n°11); "
                            "--method exact|resal|resal-corrected|ode", (
        Param("chi0", 1.0, "velocity along the cushion (m/s)"),
        Param("zeta0", -1.0, "normal velocity, negative: approaching (m/s)"),
        Param("p0", 0.0, "side spin about the vertical (rad/s); slip φ = χ − pR"),
        Param("n0", -32.8, "rotation about the cushion's direction (rad/s); rolling: ζ0/R"),
        Param("R", 0.0305, "radius (m)", lo=0.0, lo_open=True),
        Param("k", 2.5, "moment of inertia M R²/k", lo=0.0, lo_open=True),
        Param("j", 0.20, "ball-cushion friction (Coriolis: 0.20)", lo=0.0),
        Param("eps", 0.29, "Résal's ε on the cushion (n°5: 0.29)", **_EPS),
    ), _cushion),
    "ball-ball": Model("ball-ball", "a ball cutting a ball at rest, with friction (§V free, §VI on the cloth); "
                       "--method exact|resal|ode", (
        Param("V", 2.0, "speed of the striking ball (m/s)", lo=0.0, lo_open=True),
        Param("cut", 30.0, "cut angle: its velocity against the line of centres (degrees)", lo=0.0, hi=90.0,
              hi_open=True),
        Param("roll", 1.0, "1: rolling on the cloth, 0: stunned (no rotation)"),
        Param("side", 0.0, "side spin about the vertical (rad/s)"),
        Param("M", 0.21, "mass of the striking ball (kg)", lo=0.0, lo_open=True),
        Param("Mp", 0.21, "mass of the ball at rest (kg)", lo=0.0, lo_open=True),
        Param("R", 0.0305, "radius of the striking ball (m)", lo=0.0, lo_open=True),
        Param("Rp", 0.0305, "radius of the ball at rest (m)", lo=0.0, lo_open=True),
        Param("d", 0.061, "distance between the centres at the impact (m)", lo=0.0, lo_open=True),
        Param("k", 2.5, "moment of inertia M R²/k of both", lo=0.0, lo_open=True),
        Param("f", 0.03, "ball-ball friction (Coriolis: below 0.03)", lo=0.0),
        Param("eps", 0.026, "Résal's ε = ε′ of the balls", **_EPS),
        Param("cloth", 1.0, "1: balls on the cloth (§VI), 0: free spheres (§V)", lo=0.0, hi=1.0),
    ), _ball_ball),
    "cloth-slide": Model("cloth-slide", "ball sliding on the cloth until it rolls (§II n°7)", (
        Param("vx", 2.0, "velocity of the centre along x (m/s)"),
        Param("vy", 0.0, "along y (m/s)"),
        Param("wx", 0.0, "rotation about x, n (rad/s); slip v_y = η + nR"),
        Param("wy", 0.0, "rotation about y, p (rad/s); slip v_x = χ − pR"),
        Param("R", 0.0305, "radius (m)", lo=0.0, lo_open=True),
        Param("k", 2.5, "moment of inertia M R²/k", lo=0.0, lo_open=True),
        Param("f", 0.25, "friction on the cloth (Coriolis: 0.25)", lo=0.0, lo_open=True),
        Param("g", 9.81, "gravity (m/s²)", lo=0.0, lo_open=True),
    ), _cloth),
    "cue-stroke": Model("cue-stroke", "stroke of an inclined cue (§VII n°14); --method resal: as printed", (
        Param("M", 0.21, "mass of the ball (kg)", lo=0.0, lo_open=True),
        Param("Mp", 0.63, "mass of the cue (kg); μ = Mp/M", lo=0.0, lo_open=True),
        Param("V0p", 3.0, "speed of the cue before the stroke (m/s)", lo=0.0, lo_open=True),
        Param("i", 0.0, "inclination of the cue on the cloth (degrees)", lo=0.0, hi=90.0, hi_open=True),
        Param("b", 0.0, "side offset of the contact point (m)"),
        Param("c", 0.0, "height of the contact point above the centre (m)"),
        Param("R", 0.0305, "radius (m)", lo=0.0, lo_open=True),
        Param("k", 2.5, "moment of inertia M R²/k", lo=0.0, lo_open=True),
        Param("f", 0.25, "friction of the ball on the cloth", lo=0.0),
        Param("eps", 0.0, "Résal's ε of the ball", **_EPS),
        Param("epsp", 0.8, "Résal's ε′ of the cue (from n°5's data with ε = 0; the paper writes 0,27)", **_EPS),
    ), _cue),
}


def simulate(model: str, assignments: list[str], method: str = "auto") -> dict[str, Any]:
    """Run one scene; ``assignments`` are ``name=value`` strings. Raises ``InputError`` on bad input."""
    if model not in MODELS:
        raise InputError(f"model '{model}'", f"unknown model (expected one of: {', '.join(MODELS)})")
    m = MODELS[model]
    values = {p.name: p.default for p in m.params}
    for a in assignments:
        name, sep, text = a.partition("=")
        name = name.strip()
        where = f"--set {a}"
        if not sep:
            raise InputError(where, "expected name=value")
        param = next((p for p in m.params if p.name == name), None)
        if param is None:
            raise InputError(where, f"unknown parameter '{name}' for {model} "
                                    f"(expected one of: {', '.join(p.name for p in m.params)})")
        parsed = parse_number(text)
        if parsed is None:
            raise InputError(where, f"'{name}' must be a number, got '{text}'")
        problem = param.check(parsed[0])
        if problem:
            raise InputError(where, f"'{name}' must be {problem}, got {text}")
        values[name] = parsed[0]
    if method != "auto" and model not in ("cue-stroke", "plane-impact", "cushion-impact", "ball-ball"):
        raise InputError(f"--method {method}", f"{model} has a single solution path (use --method auto)")
    allowed = {"cushion-impact": cushion.METHODS, "ball-ball": spheres.METHODS}.get(model, ("auto", "exact", "resal"))
    if method not in allowed:
        raise InputError(f"--method {method}", f"expected one of {', '.join(allowed)}")
    label, outputs = m.run(values, method) if method != "auto" else m.run(values)
    return {"model": model, "method": label, "inputs": values, "outputs": outputs}
