"""The registry of every model of the paper and its declared solution paths (see ``paths``).

One place that ``resal simulate``, ``make bench``, ``make stress`` and the invariant tests all read. Each model
lists its parameters (SI units, admissible ranges, defaults: never a value printed in the paper), its paths
(kind, where exact, accuracy, cost) and what the invariant tests need: random admissible scenes, an error
measure, the vis viva before and after, and a mirror symmetry where the model has one. Every model has an
``ode`` path that integrates the equations of motion (in time or in the normal impulse) without its closed forms.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from . import cloth, cue, cushion, impact, plane, reference, spheres
from .inertia import K_MIN, K_SOLID, K_WHY
from .paths import (
    ImpactCheck,
    Kind,
    Model,
    Param,
    Path,
    PathCode,
    Regime,
    always,
    as_floats,
    codes,
)
from .referee import cue as referee_cue
from .referee import cushion as referee_cushion
from .referee import plane as referee_plane
from .referee import spheres as referee_spheres

__all__ = ["MODELS", "model"]

Scene = dict[str, np.ndarray]

_EPS = {"lo": 0.0, "hi": 1.0}
_ULP = float(np.finfo(float).eps)
_NU = {"lo": 0.0, "hi": 1.0, "lo_open": True}
_R = Param("R", "m", "radius of the ball", 0.0305, lo=0.0, lo_open=True)
_K = Param("k", "1", "moment of inertia M R²/k (k = 5/2: a homogeneous ball)", K_SOLID, lo=K_MIN, why=K_WHY)
_G = Param("g", "m/s²", "gravity", 9.81, lo=0.0, lo_open=True)


def _num(x: Any) -> Any:
    """``np.asarray(x)``, a numpy float (one scene on the single-scene route of ``paths.solve``) passing as it is:
    a comparison gives the same numpy bool of either, without the cost of a 0-d array's."""
    return x if x.__class__ is np.float64 else np.asarray(x)


def _everywhere(x: Any) -> Any:
    """True per scene, of the shape of ``x`` (a numpy bool for a numpy float: one scene, as ``_num``)."""
    return np.True_ if x.__class__ is np.float64 else np.ones(np.shape(x), bool)


def _f(doc: str = "sliding friction coefficient") -> Param:
    return Param("f", "1", doc, None, lo=0.0)


# ---- §I: direct impact and impact on an immovable mass -------------------------------------------------------
def _direct_exact(s: Scene) -> impact.DirectImpact:
    return impact.direct_impact(s["M"], s["Mp"], s["V0"], s["V0p"], eps=s["eps"], epsp=s["epsp"])


def _direct_ode(s: Scene, rtol: float = 1e-10, solver: str = "DOP853") -> impact.DirectImpact:
    """The two-phase hysteretic contact of §I n°2 with Newton's e equivalent to (ε, ε′) (the one map between
    them, ``impact.newton_restitution``); nothing of eqs (7)-(9)."""
    e = impact.newton_restitution(s["M"], s["Mp"], s["eps"], s["epsp"])
    r = reference.integrate_direct_impact(s["M"], s["Mp"], s["V0"], s["V0p"], e, rtol=rtol, atol=rtol * 1e-2,
                                          solver=solver)
    M, Mp, V0, V0p = s["M"], s["Mp"], s["V0"], s["V0p"]
    lost = M * (V0**2 - r.V1**2) + Mp * (V0p**2 - r.V1p**2)
    shape = np.shape(r.V1)
    return impact.DirectImpact(r.V1, r.V1p, e, lost, "ode", codes(shape, PathCode.ODE),
                               codes(shape, Regime.FRICTIONLESS), r.method)


def _wall_exact(s: Scene) -> impact.WallImpact:
    return impact.wall_impact(s["V0"], eps=s["eps"])


def _wall_ode(s: Scene, rtol: float = 1e-10, solver: str = "DOP853") -> impact.WallImpact:
    """The contact of §I n°2 against an immovable mass (M′ = ∞), with e = (1 − ε)/(1 + ε)."""
    e = impact.velocity_ratio_from_eps(s["eps"])
    r = reference.integrate_direct_impact(1.0, math.inf, s["V0"], 0.0, e, rtol=rtol, atol=rtol * 1e-2, solver=solver)
    shape = np.shape(r.V1)
    return impact.WallImpact(r.V1, -r.V1 / s["V0"], "ode", codes(shape, PathCode.ODE),
                             codes(shape, Regime.FRICTIONLESS), r.method)


def _direct_sample(rng: np.random.Generator, n: int) -> Scene:
    V0 = rng.uniform(0.5, 3.0, n)
    eps, epsp = rng.uniform(0.0, 1.0, n), rng.uniform(0.0, 1.0, n)
    eps[::4] = epsp[::4] = 1 - 10 ** -rng.uniform(2, 4, eps[::4].size)  # nearly plastic: a short, stiff restitution
    return {"M": rng.uniform(0.1, 5.0, n), "Mp": rng.uniform(0.1, 5.0, n), "V0": V0,
            "V0p": V0 - rng.uniform(0.2, 3.0, n), "eps": eps, "epsp": epsp}


# ---- §III: sphere on a plane, ricochets ------------------------------------------------------------------------
def _plane_args(s: Scene) -> tuple[np.ndarray, ...]:
    return s["chi0"], s["zeta0"], s["p0"], s["R"], s["k"], s["f"], s["nu"]


def _plane(s: Scene, method: str) -> plane.PlaneImpact:
    return plane.plane_impact(s["chi0"], s["zeta0"], s["p0"], R=s["R"], k=s["k"], f=s["f"], nu=s["nu"], method=method)


def _plane_ode(chi0: Any, zeta0: Any, p0: Any, *, R: Any, k: Any, f: Any, nu: Any, method: str = "ode",
               rtol: float = 1e-11, solver: str = "DOP853") -> plane.PlaneImpact:
    """§III's impulse equations (4) integrated with a slip-stop event (``reference.integrate_plane_impact``)."""
    r = reference.integrate_plane_impact(chi0, zeta0, p0, R=R, k=k, f=f, nu=nu, rtol=rtol, solver=solver)
    v0 = np.broadcast_to(np.asarray(chi0, dtype=float) - np.asarray(p0, dtype=float) * R, np.shape(r.chi1))
    regime = np.where(v0 == 0, Regime.NO_SLIP, np.where(np.isnan(r.slip_stopped_at), Regime.SLIDE, Regime.GRIP))
    return plane.PlaneImpact(r.chi1, r.zeta1, r.p1, "ode", codes(np.shape(r.chi1), PathCode.ODE),
                             regime.astype(np.int8), r.method)


def _plane_reference(s: Scene, rtol: float = 1e-13, solver: str = "DOP853") -> plane.PlaneImpact:
    """The referee (``referee.plane``: the free sphere's six velocity components in the normal impulse, the slip's
    stop an event, the end at ζ = −νζ0) as the model's result."""
    r = referee_plane.solve(s, rtol)
    shape = np.shape(r.chi1)
    v0 = np.broadcast_to(np.asarray(s["chi0"], dtype=float) - np.asarray(s["p0"], dtype=float) * s["R"], shape)
    regime = np.where(v0 == 0, Regime.NO_SLIP, np.where(r.stopped, Regime.GRIP, Regime.SLIDE)).astype(np.int8)
    return plane.PlaneImpact(r.chi1, r.zeta1, r.p1, "reference", codes(shape, PathCode.REFERENCE), regime, r.label)


def _plane_resal_exact(s: Scene) -> np.ndarray:
    """Eqs (6) assume the slip lasts the whole impact: exact where it does, or where there is no slip."""
    chi0, zeta0, p0, R, k, f, nu = _plane_args(s)
    return plane.slides_throughout(chi0, zeta0, p0, R=R, k=k, f=f, nu=nu) | (chi0 - p0 * R == 0)


def _plane_sample(rng: np.random.Generator, n: int) -> Scene:
    chi0 = rng.uniform(-3.0, 3.0, n)
    R = np.full(n, 0.0305)
    p0 = rng.uniform(-100.0, 100.0, n)
    p0[::7] = chi0[::7] / R[::7]  # some scenes already rolling
    return {"chi0": chi0, "zeta0": -rng.uniform(0.1, 3.0, n), "p0": p0, "R": R, "k": np.full(n, 2.5),
            "f": rng.uniform(0.0, 0.6, n), "nu": rng.uniform(0.2, 1.0, n)}


def _plane_vis_viva(s: Scene, r: Any) -> tuple[np.ndarray, np.ndarray]:
    I = s["R"] ** 2 / s["k"]  # noqa: E741  (moment of inertia per unit mass)
    return s["chi0"] ** 2 + s["zeta0"] ** 2 + I * s["p0"] ** 2, r.chi1**2 + r.zeta1**2 + I * r.p1**2


def _ricochet_run(s: Scene, method: str) -> plane.Ricochet:
    n = int(s["n"])
    return plane.ricochet(s["a0"], s["alpha0"], s["p0"], R=s["R"], k=s["k"], f=s["f"], nu=s["nu"], g=s["g"], n=n,
                          method=method)


def _ricochet_ode(s: Scene, rtol: float = 1e-11, solver: str = "DOP853") -> plane.Ricochet:
    """Each impact integrated in the normal impulse, each flight integrated in time (``reference``)."""
    n = int(s["n"])
    a0, al, p, R, k, f, nu, g = (np.asarray(s[x], dtype=float) for x in ("a0", "alpha0", "p0", "R", "k", "f",
                                                                           "nu", "g"))
    chi, zeta = a0 * np.cos(al), -a0 * np.sin(al)
    cols: dict[str, list[np.ndarray]] = {"chi": [], "zeta": [], "p": [], "regime": [], "P": [], "T": []}
    for _ in range(n):
        out = _plane_ode(chi, zeta, p, R=R, k=k, f=f, nu=nu, rtol=rtol, solver=solver)
        chi, zeta, p = out.chi1, out.zeta1, out.p1
        P, T = reference.integrate_flight(chi, zeta, g, rtol=rtol, solver=solver)
        for key, v in (("chi", chi), ("zeta", zeta), ("p", p), ("regime", out.regime), ("P", P), ("T", T)):
            cols[key].append(np.asarray(v))
        zeta = -zeta
    st = {key: np.stack(v, axis=-1) for key, v in cols.items()}
    imprints = np.concatenate([np.zeros((*a0.shape, 1)), np.cumsum(st["P"], axis=-1)], axis=-1)
    return plane.Ricochet(st["P"], st["T"], imprints, st["chi"], st["zeta"], st["p"], st["regime"], "ode",
                          codes(a0.shape, PathCode.ODE), st["regime"][..., 0],
                          "ODE: impacts in the normal impulse, flights in time (DOP853)")


def _ricochet_resal_exact(s: Scene) -> np.ndarray:
    r = _ricochet_run(s, "exact")
    return np.all(r.regimes != Regime.GRIP, axis=-1)


def _ricochet_sample(rng: np.random.Generator, n: int) -> Scene:
    return {"a0": rng.uniform(0.5, 3.0, n), "alpha0": rng.uniform(0.1, 1.2, n), "p0": rng.uniform(-50, 50, n),
            "R": np.full(n, 0.0305), "k": np.full(n, 2.5), "f": rng.uniform(0.0, 0.4, n),
            "nu": rng.uniform(0.3, 0.95, n), "g": np.full(n, 9.81), "n": np.array(4.0)}


def _ricochet_vis_viva(s: Scene, r: Any) -> tuple[np.ndarray, np.ndarray]:
    I = s["R"] ** 2 / s["k"]  # noqa: E741
    return (s["a0"] ** 2 + I * s["p0"] ** 2,
            r.chi[..., -1] ** 2 + r.zeta[..., -1] ** 2 + I * r.p[..., -1] ** 2)


# ---- §II: the cloth -------------------------------------------------------------------------------------------
def _cloth_exact(s: Scene) -> cloth.ClothMotion:
    return cloth.slide(s["vx"], s["vy"], s["wx"], s["wy"], R=s["R"], k=s["k"], f=s["f"], g=s["g"])


def _cloth_ode(s: Scene, rtol: float = 1e-11, solver: str = "DOP853") -> cloth.ClothMotion:
    """§II's eqs (2) integrated in time with the friction opposite the current slip, until the slip vanishes
    (an event on the slip projected on its initial direction); nothing of eqs (3)-(5)."""
    keys = ("vx", "vy", "wx", "wy", "R", "k", "f", "g")
    arrays = np.broadcast_arrays(*(np.asarray(s[x], dtype=float) for x in keys))
    shape = arrays[0].shape
    out = np.zeros((*shape, 6))
    for idx in np.ndindex(shape):
        vx, vy, wx, wy, R, k, f, g = (float(a[idx]) for a in arrays)
        u0 = math.hypot(vx - wy * R, vy + wx * R)
        if u0 <= 64 * _ULP * (abs(vx) + abs(vy) + (abs(wx) + abs(wy)) * R):  # no slip, or one lost in the
            out[idx] = (0.0, 0.0, 0.0, vx, vy, 0.0)  # rounding of its terms: no integration can resolve it
            continue
        state, t1 = reference.integrate_cloth(vx, vy, wx, wy, R, k, f, g, 1.01 * u0 / (f * g),  # |du/dt| ≥ fg
                                              rtol=rtol, solver=solver)
        y = state(t1)
        out[idx] = (t1, y[0], y[1], y[2], y[3], u0)
    return cloth.ClothMotion(out[..., 0], out[..., 1], out[..., 2], out[..., 3], out[..., 4], out[..., 5], "ode",
                             codes(shape, PathCode.ODE),
                             np.where(out[..., 5] > 0, Regime.GRIP, Regime.NO_SLIP).astype(np.int8),
                             "ODE of eqs (2), slip-stop event (DOP853)")


def _cloth_sample(rng: np.random.Generator, n: int) -> Scene:
    wy = rng.uniform(-150.0, 150.0, n)
    vx = rng.uniform(-3.0, 3.0, n)
    s = {"vx": vx, "vy": rng.uniform(-3.0, 3.0, n), "wx": rng.uniform(-150.0, 150.0, n), "wy": wy,
         "R": np.full(n, 0.0305), "k": np.full(n, 2.5), "f": rng.uniform(0.05, 0.5, n), "g": np.full(n, 9.81)}
    s["vy"][::5] = -s["wx"][::5] * s["R"][::5]  # some scenes already rolling: no slip, exactly
    s["vx"][::5] = s["wy"][::5] * s["R"][::5]
    return s


def _cloth_scales(s: Scene) -> dict[str, np.ndarray]:
    """Natural scales of §II's outputs from the speed scale V = |v| + |w|R: times V/(fg), lengths V²/(fg),
    speeds V (the time and the path to rolling grow as 1/f)."""
    V = np.hypot(s["vx"], s["vy"]) + np.hypot(s["wx"], s["wy"]) * s["R"]
    fg = np.asarray(s["f"], dtype=float) * np.asarray(s["g"], dtype=float)
    return {"t_roll": V / fg, "x_roll": V * V / fg, "y_roll": V * V / fg, "vx_roll": V, "vy_roll": V}


def _cloth_vis_viva(s: Scene, r: Any) -> tuple[np.ndarray, np.ndarray]:
    I = s["R"] ** 2 / s["k"]  # noqa: E741
    before = s["vx"] ** 2 + s["vy"] ** 2 + I * (s["wx"] ** 2 + s["wy"] ** 2)
    v2 = r.vx_roll**2 + r.vy_roll**2
    return before, v2 * (1 + I / s["R"] ** 2)  # rolling: |w| = |v|/R


# ---- §IV: the cushion ----------------------------------------------------------------------------------------
def _cushion(method: str):
    def run(s: Scene, rtol: float = 1e-11, solver: str = "DOP853") -> cushion.CushionImpact:
        return cushion.cushion_impact(s["chi0"], s["zeta0"], s["p0"], s["n0"], R=s["R"], k=s["k"], j=s["j"],
                                      eps=s["eps"], method=method, rtol=rtol, solver=solver)
    return run


def _cushion_reference(s: Scene, rtol: float = 1e-13, solver: str = "DOP853") -> cushion.CushionImpact:
    """The referee (``referee.cushion``: Newton–Euler in the normal impulse, the cloth bilateral as the model
    declares, the slip's stop an event, the end at ζ = −νζ0) as the model's result."""
    r = referee_cushion.solve(s, rtol)
    shape = np.shape(r.chi1)
    slip0 = np.broadcast_to(np.hypot(np.asarray(s["chi0"]) - np.asarray(s["p0"]) * np.asarray(s["R"]),
                                     np.asarray(s["n0"]) * np.asarray(s["R"])), shape)
    regime = np.where(slip0 == 0, Regime.NO_SLIP, np.where(r.stopped, Regime.GRIP, Regime.SLIDE)).astype(np.int8)
    return cushion.CushionImpact(r.chi1, r.zeta1, r.p1, r.n1, "reference", codes(shape, PathCode.REFERENCE), regime,
                                 r.label)


def _cushion_elementary(s: Scene) -> np.ndarray:
    return cushion.elementary_applies(s["chi0"], s["p0"], s["n0"], s["R"], s["j"])


def _cushion_resal_exact(s: Scene) -> np.ndarray:
    """Eq. (11) linearises a term that vanishes with ψ0 (n0 = 0) or with j: exact there, if φ0 ≠ 0."""
    return (s["chi0"] - s["p0"] * s["R"] != 0) & ((s["n0"] == 0) | (s["j"] == 0))


def _cushion_sample(rng: np.random.Generator, n: int) -> Scene:
    s = {"chi0": rng.uniform(-3.0, 3.0, n), "zeta0": -rng.uniform(0.2, 3.0, n), "p0": rng.uniform(-100, 100, n),
         "n0": rng.uniform(-100.0, 100.0, n), "R": np.full(n, 0.0305), "k": np.full(n, 2.5),
         "j": rng.uniform(0.0, 0.6, n), "eps": rng.uniform(0.0, 1.0, n)}
    s["n0"][::4] = 0.0  # elementary scenes: no rotation about the cushion's direction …
    s["p0"][1::6] = s["chi0"][1::6] / s["R"][1::6]  # … or no slip along it
    return s


def _cushion_vis_viva(s: Scene, r: Any) -> tuple[np.ndarray, np.ndarray]:
    I = s["R"] ** 2 / s["k"]  # noqa: E741
    return (s["chi0"] ** 2 + s["zeta0"] ** 2 + I * (s["p0"] ** 2 + s["n0"] ** 2),
            r.chi1**2 + r.zeta1**2 + I * (r.p1**2 + r.n1**2))


def _flip(s: Scene, *names: str) -> dict[str, np.ndarray]:
    out = dict(s)
    for x in names:
        out[x] = -np.asarray(s[x])
    return out


def _stack(*xs: Any) -> np.ndarray:
    return np.stack(np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in xs)), axis=-1)


def _about_contact(s: Scene, r: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """§III and §IV: the impulses act at the contact, so the angular momentum about it, per unit mass
    χ + pR/k along the slip (the friction changes χ by −F and pR by kF), is conserved."""
    R, k = np.asarray(s["R"], dtype=float), np.asarray(s["k"], dtype=float)
    chi0, p0 = np.asarray(s["chi0"], dtype=float), np.asarray(s["p0"], dtype=float)
    before, after = chi0 + p0 * R / k, r.chi1 + r.p1 * R / k
    scale = np.abs(chi0) + np.abs(p0 * R / k) + np.abs(r.chi1) + np.abs(r.p1 * R / k)
    return before[..., None], np.asarray(after)[..., None], scale


def _ricochet_momentum(s: Scene, r: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """χ + pR/k at every impact (``_about_contact``); the flights change neither χ nor p."""
    R, k = np.asarray(s["R"], dtype=float), np.asarray(s["k"], dtype=float)
    a0, al, p0 = (np.asarray(s[x], dtype=float) for x in ("a0", "alpha0", "p0"))
    chi, p = r.chi[..., -1], r.p[..., -1]
    before, after = a0 * np.cos(al) + p0 * R / k, chi + p * R / k
    return before[..., None], after[..., None], np.abs(a0) + np.abs(p0 * R / k) + np.abs(chi) + np.abs(p * R / k)


def _cloth_momentum(s: Scene, r: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """§II: friction acts at the contact with the cloth, gravity and the reaction pass through it, so the
    horizontal angular momentum about it, v + (R/k) w × e_z per unit mass, is conserved; at the onset of rolling
    w × e_z R = v, i.e. (1 + 1/k) v_roll."""
    R, k = np.asarray(s["R"], dtype=float), np.asarray(s["k"], dtype=float)
    vx, vy, wx, wy = (np.asarray(s[x], dtype=float) for x in ("vx", "vy", "wx", "wy"))
    before = _stack(vx + wy * R / k, vy - wx * R / k)
    after = _stack(r.vx_roll * (1 + 1 / k), r.vy_roll * (1 + 1 / k))
    scale = np.hypot(vx, vy) + np.hypot(wx, wy) * R / k + np.hypot(r.vx_roll, r.vy_roll) * (1 + 1 / k)
    return before, after, scale


# ---- §V-§VI: two balls ---------------------------------------------------------------------------------------
def _spheres(method: str, on_cloth: bool):
    def run(s: Scene, rtol: float = 1e-11, solver: str = "DOP853") -> spheres.SpheresImpact:
        return spheres.two_spheres(s["M"], s["Mp"], s["R"], s["Rp"], s["k"], s["kp"], s["v"], s["w"], s["vp"],
                                   s["wp"], f=s["f"], eps=s["eps"], epsp=s["epsp"], on_cloth=on_cloth, method=method,
                                   rtol=rtol, solver=solver)
    return run


def _spheres_reference(on_cloth: bool):
    def run(s: Scene, rtol: float = 1e-13, solver: str = "DOP853") -> spheres.SpheresImpact:
        """The referee (``referee.spheres``: Newton–Euler in the normal impulse, law (6) evaluated literally) as
        the model's result; ``solver`` is DOP853 always (the referee's own choice)."""
        r = referee_spheres.solve(s, on_cloth, rtol)
        shape = np.shape(r.xi)
        M = np.broadcast_to(np.asarray(s["M"], dtype=float), shape)
        n0 = np.broadcast_to(_spheres_slip(s), shape)
        regime = np.where(n0 == 0, Regime.NO_SLIP, np.where(r.stopped, Regime.GRIP, Regime.SLIDE)).astype(np.int8)
        return spheres.SpheresImpact(r.v1, r.w1, r.v1p, r.w1p, r.xi / M, r.T, r.s_c, np.ones(shape, dtype=bool),
                                     "reference", codes(shape, PathCode.REFERENCE), regime, r.label)
    return run


def _spheres_slip(s: Scene) -> np.ndarray:
    """|s0|, the slip at the contact before the impact (§V eq. (1)), per scene."""
    # (numpy floats of one scene pass as they are: a 0-d array costs numpy's array calls in each product)
    sy, sz = spheres.contact_slip_yz(*as_floats(s["v"], s["w"], s["vp"], s["wp"], s["R"], s["Rp"]))
    return np.hypot(sy, sz)


def _xyz(a: Any, i: int) -> Any:
    """``a[..., i]`` of a vector parameter; of one scene's vector (1-D) its numpy float (``spheres._at``)."""
    a = np.asarray(a)
    return a[i] if a.ndim == 1 else a[..., i]


def _free_resal_exact(s: Scene) -> np.ndarray:
    """§V (8) assumes the balls slide throughout the impact: exact where they do (or without friction)."""
    return (_spheres("exact", False)(s).regime == Regime.SLIDE) | (np.asarray(s["f"]) == 0)


def _cloth_resal_exact(s: Scene) -> np.ndarray:
    """§VI's first order in f is exact without friction, or without slip (|s0| = 0: both components 0, as
    hypot(y, z) is 0 only there). One scene (its numpy floats): the slip only where f ≠ 0, a numpy bool."""
    f = s["f"]
    if f.__class__ is np.float64 and f == 0:
        return np.True_
    sy, sz = spheres.contact_slip_yz(*as_floats(s["v"], s["w"], s["vp"], s["wp"], s["R"], s["Rp"]))
    if f.__class__ is np.float64:
        return (sy == 0) & (sz == 0)
    return (np.asarray(f) == 0) | ((sy == 0) & (sz == 0))


def _spheres_sample(on_cloth: bool):
    def sample(rng: np.random.Generator, n: int) -> Scene:
        v = np.c_[rng.uniform(0.5, 3.0, n), rng.uniform(-1.0, 1.0, n), rng.uniform(-1.0, 1.0, n)]
        vp = np.c_[rng.uniform(-1.0, 0.4, n), rng.uniform(-1.0, 1.0, n), rng.uniform(-1.0, 1.0, n)]
        if on_cloth:
            v[:, 2] = vp[:, 2] = 0.0
        w = rng.uniform(-80.0, 80.0, (n, 3))
        wp = rng.uniform(-80.0, 80.0, (n, 3))
        f = rng.uniform(0.0, 0.3, n)
        f[::6] = 0.0  # frictionless scenes, where Résal's approximations are exact
        return {"M": rng.uniform(0.1, 0.4, n), "Mp": rng.uniform(0.1, 0.4, n), "R": np.full(n, 0.0305),
                "Rp": np.full(n, 0.0305), "k": np.full(n, 2.5), "kp": np.full(n, 2.5), "v": v, "w": w, "vp": vp,
                "wp": wp, "f": f, "eps": rng.uniform(0.0, 1.0, n), "epsp": rng.uniform(0.0, 1.0, n)}
    return sample


def _spheres_momentum(on_cloth: bool):
    """§V: the total momentum, and each ball's angular momentum about the point of contact (the impulses act
    there). §VI: the cloth takes the vertical impulses at the foot of each ball, so only the horizontal momentum
    and the x and z components of those angular momenta are conserved."""
    keep = [0, 1, 3, 5, 6, 8] if on_cloth else list(range(9))

    def momentum(s: Scene, r: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        M, Mp, R, Rp, k, kp = (np.asarray(s[x], dtype=float) for x in ("M", "Mp", "R", "Rp", "k", "kp"))
        ex = np.zeros((*np.shape(M), 3))
        ex[..., 0] = 1.0

        def terms(v: Any, w: Any, vp: Any, wp: Any) -> list[np.ndarray]:
            v, w, vp, wp = (np.asarray(x, dtype=float) for x in (v, w, vp, wp))
            return [M[..., None] * v, Mp[..., None] * vp,  # momenta; then the moments about the contact
                    M[..., None] * np.cross(-R[..., None] * ex, v), (M * R**2 / k)[..., None] * w,
                    Mp[..., None] * np.cross(Rp[..., None] * ex, vp), (Mp * Rp**2 / kp)[..., None] * wp]

        def total(t: list[np.ndarray]) -> np.ndarray:
            return np.concatenate([t[0] + t[1], t[2] + t[3], t[4] + t[5]], axis=-1)[..., keep]

        t0, t1 = terms(s["v"], s["w"], s["vp"], s["wp"]), terms(r.v1, r.w1, r.v1p, r.w1p)
        scale = sum(np.linalg.norm(x, axis=-1) for x in (*t0, *t1))
        return total(t0), total(t1), scale

    return momentum


def _spheres_vis_viva(s: Scene, r: Any) -> tuple[np.ndarray, np.ndarray]:
    def T(M: Any, R: Any, k: Any, v: Any, w: Any) -> np.ndarray:
        return M * np.sum(np.asarray(v) ** 2, axis=-1) + M * R**2 / k * np.sum(np.asarray(w) ** 2, axis=-1)
    before = T(s["M"], s["R"], s["k"], s["v"], s["w"]) + T(s["Mp"], s["Rp"], s["kp"], s["vp"], s["wp"])
    after = T(s["M"], s["R"], s["k"], r.v1, r.w1) + T(s["Mp"], s["Rp"], s["kp"], r.v1p, r.w1p)
    return before, after


_YFLIP_V, _YFLIP_W = np.array([1.0, -1.0, 1.0]), np.array([-1.0, 1.0, -1.0])  # y → −y; w is a pseudovector


def _spheres_mirror(s: Scene) -> dict[str, np.ndarray]:
    out = dict(s)
    for x in ("v", "vp"):
        out[x] = np.asarray(s[x]) * _YFLIP_V
    for x in ("w", "wp"):
        out[x] = np.asarray(s[x]) * _YFLIP_W
    return out


def _spheres_mirrored(r: Any) -> dict[str, np.ndarray]:
    return {"v1": r.v1 * _YFLIP_V, "w1": r.w1 * _YFLIP_W, "v1p": r.v1p * _YFLIP_V, "w1p": r.w1p * _YFLIP_W}


def _spheres_model(on_cloth: bool) -> Model:
    vec = "(m/s, 3-vector: x along the line of centres" + (", z vertical)" if on_cloth else ")")
    params = (
        Param("M", "kg", "mass of the striking ball", 0.21, lo=0.0, lo_open=True),
        Param("Mp", "kg", "mass of the struck ball", 0.21, lo=0.0, lo_open=True),
        Param("R", "m", "radius of the striking ball", 0.0305, lo=0.0, lo_open=True),
        Param("Rp", "m", "radius of the struck ball", 0.0305, lo=0.0, lo_open=True),
        Param("k", "1", "moment of inertia M R²/k of the striking ball", K_SOLID, lo=K_MIN, why=K_WHY),
        Param("kp", "1", "moment of inertia of the struck ball", K_SOLID, lo=K_MIN, why=K_WHY),
        Param("v", "m/s", f"velocity of the striking ball {vec}", None),
        Param("w", "rad/s", "rotation of the striking ball (3-vector)", 0.0),
        Param("vp", "m/s", "velocity of the struck ball (3-vector)", 0.0),
        Param("wp", "rad/s", "rotation of the struck ball (3-vector)", 0.0),
        _f("ball-ball friction"),
        Param("eps", "1", "Résal's ε of the striking ball", None, **_EPS),
        Param("epsp", "1", "Résal's ε′ of the struck ball", None, **_EPS),
    )
    exact_kind = Kind.EXACT_NUMERICAL if on_cloth else Kind.CLOSED_FORM
    paths = (
        Path(PathCode.EXACT, exact_kind, _spheres("exact", on_cloth), always, 1e-12, 3 if on_cloth else 1,
             "slip decay in closed form (₂F₁), normal impulse from law (6) at a fixed point" if on_cloth else
             "closed form, sliding or sticking (law (6) as a quadratic)", scalar=True),
        Path(PathCode.RESAL, Kind.AS_PRINTED, _spheres("resal", on_cloth),
             _cloth_resal_exact if on_cloth else _free_resal_exact, 1e-12, 1,
             "§VI eqs (11)-(15), first order in f" if on_cloth else "§V eqs (5), (8), sliding assumed", scalar=True),
        Path(PathCode.ODE, Kind.ODE, _spheres("ode", on_cloth), always, 1e-8, 1000,
             "slip integrated in the normal impulse (DOP853), normal impulse from law (6)",
             tuned=_spheres("ode", on_cloth), rtol=1e-11, solver="DOP853"),
        Path(PathCode.REFERENCE, Kind.REFEREE, _spheres_reference(on_cloth), always, 1e-9, 2000,
             "referee: every velocity component in the normal impulse, law (6) literally (DOP853)",
             tuned=_spheres_reference(on_cloth), rtol=1e-13, solver="DOP853"),
    )

    def admissible(s: Scene) -> np.ndarray:
        v, vp = s["v"], s["vp"]
        approach = _xyz(v, 0) - _xyz(vp, 0) > 0
        if on_cloth:
            approach &= (_xyz(v, 2) == 0) & (_xyz(vp, 2) == 0)
        return approach

    return Model(
        "spheres-cloth" if on_cloth else "spheres-free", "§VI n°13" if on_cloth else "§V n°12",
        "two balls resting on the cloth, with friction" if on_cloth else "two free spheres with friction",
        params, ("v", "w", "vp", "wp"), paths, ("v1", "w1*R", "v1p", "w1p*Rp"), admissible,
        "the striking ball must approach (v_x > v′_x)" + ("; on the cloth v_z = v′_z = 0" if on_cloth else ""),
        sample=_spheres_sample(on_cloth), scale=lambda s: np.abs(np.asarray(s["v"])[..., 0]
                                                                 - np.asarray(s["vp"])[..., 0]),
        vis_viva=_spheres_vis_viva, mirror=_spheres_mirror, mirrored=_spheres_mirrored,
        momentum=_spheres_momentum(on_cloth), impact=_spheres_impact_check(on_cloth), elastic=_spheres_elastic)


# ---- §VII: the cue -------------------------------------------------------------------------------------------
def _cue(method: str):
    def run(s: Scene) -> cue.CueStroke:
        return cue.cue_stroke(s["M"], s["Mp"], s["V0p"], s["i"], s["b"], s["c"], R=s["R"], k=s["k"], f=s["f"],
                              eps=s["eps"], epsp=s["epsp"], method=method)
    return run


def _cue_ode(s: Scene, rtol: float = 1e-10, solver: str = "LSODA") -> cue.CueStroke:
    """§VII's eqs (3) integrated in the cue impulse P (``reference.integrate_cue_impulse``): once to P = 1 for the
    ball's response per unit impulse (its vis viva per P², and the velocity of the contact point along the cue
    axis), which give ω and ω1 by law (6) as in eqs (9)-(10); then again to P = M′ω1. Nothing of eqs (5)-(7)."""
    keys = ("M", "Mp", "V0p", "i", "b", "c", "R", "k", "f", "eps", "epsp")
    arrays = np.broadcast_arrays(*(np.asarray(s[x], dtype=float) for x in keys))
    shape = arrays[0].shape
    out = np.zeros((*shape, 11))
    for idx in np.ndindex(shape):
        M, Mp, V0p, i, b, c, R, k, f, eps, epsp = (float(a[idx]) for a in arrays)
        a = -math.sqrt(max(R * R - b * b - c * c, 0.0))
        u = reference.integrate_cue_impulse(i, a, b, c, R, k, f, M, 1.0, rtol=rtol, solver=solver)  # per unit P
        v3, w = np.array([u[0], u[1], 0.0]), np.array([u[2], u[3], u[4]])
        Q = M * (u[0] ** 2 + u[1] ** 2) + M * R * R / k * float(w @ w)
        A = 1.0 + Mp * Q
        d = np.array([math.cos(i), 0.0, -math.sin(i)])
        dKd = float((v3 + np.cross(w, [a, b, c])) @ d)
        omega = V0p / (1.0 + Mp * dKd)
        omega1 = 2 * A * omega / (A + eps * (A - 1) + epsp)
        y = reference.integrate_cue_impulse(i, a, b, c, R, k, f, M, Mp * omega1, rtol=rtol, solver=solver)
        slip = math.hypot(y[0] - y[3] * R, y[1] + y[2] * R)
        out[idx] = (*y, V0p - omega1, omega1, omega, A, -(a * math.cos(i) - c * math.sin(i)) / R,
                    slip / max(Mp * omega1 / M, 1e-300))
    gamma = np.full(shape, np.nan)  # the slip direction is not an output of the integration
    regime = np.where(out[..., 10] > 1e-6, Regime.SLIDE, Regime.GRIP).astype(np.int8)
    return cue.CueStroke(out[..., 0], out[..., 1], out[..., 2], out[..., 3], out[..., 4], out[..., 5],
                         out[..., 6], out[..., 7], out[..., 8], gamma, out[..., 9], "ode",
                         codes(shape, PathCode.ODE), regime, "ODE of eqs (3) in the cue impulse (LSODA)")


def _cue_reference(s: Scene, rtol: float = 1e-12, solver: str = "DOP853") -> cue.CueStroke:
    """The referee (``referee.cue``: every velocity component and the cue's speed integrated in the cue impulse,
    the cloth by complementarity, its friction without regularisation, law (6) evaluated literally) as the model's
    result; A and γ, which the integration does not form, are nan; the regime from the foot's slip after."""
    r = referee_cue.solve(s, rtol)
    shape = np.shape(r.chi1)
    R, b, c, i, V0p = (np.broadcast_to(np.asarray(s[x], dtype=float), shape) for x in ("R", "b", "c", "i", "V0p"))
    a = -np.sqrt(np.maximum(R * R - b * b - c * c, 0.0))
    slip = np.hypot(r.chi1 - r.p1 * R, r.eta1 + r.n1 * R)
    regime = np.where(slip > 1e-9 * V0p, Regime.SLIDE, Regime.GRIP).astype(np.int8)
    nan = np.full(shape, np.nan)
    return cue.CueStroke(r.chi1, r.eta1, r.n1, r.p1, r.q1, r.V1p, r.omega1, r.omega, nan, nan,
                         -(a * np.cos(i) - c * np.sin(i)) / R, "reference", codes(shape, PathCode.REFERENCE), regime,
                         r.label)


def _cue_sample(rng: np.random.Generator, n: int) -> Scene:
    i = rng.uniform(0.0, 1.2, n)
    r = 0.0305 * np.sqrt(rng.uniform(0.0, 0.5, n))
    th = rng.uniform(0.0, 2 * np.pi, n)
    b, c = r * np.cos(th), r * np.sin(th)
    i[::5] = b[::5] = c[::5] = 0.0  # central horizontal strokes
    a = -np.sqrt(0.0305**2 - b * b - c * c)
    c = np.where(-(a * np.cos(i) - c * np.sin(i)) > 0, c, np.abs(c))  # where the cue can reach the point
    return {"M": np.full(n, 0.21), "Mp": rng.uniform(0.3, 0.8, n), "V0p": rng.uniform(0.5, 4.0, n), "i": i,
            "b": b, "c": c, "R": np.full(n, 0.0305), "k": np.full(n, 2.5), "f": rng.uniform(0.1, 0.5, n),
            "eps": rng.uniform(0.0, 1.0, n), "epsp": rng.uniform(0.0, 1.0, n)}


def _cue_admissible(s: Scene) -> np.ndarray:
    b, c, R, i = as_floats(s["b"], s["c"], s["R"], s["i"])
    inside = b * b + c * c < R * R
    a = cue.contact_point(b, c, R)
    return inside & (-(a * np.cos(i) - c * np.sin(i)) / R > 0)


def _cue_momentum(s: Scene, r: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """§VII: the cloth's reaction and friction act at the foot B of the ball, the cue's force along its axis
    through the tip; so the ball's angular momentum about B plus the moment about B of the cue's momentum
    (M′V′ along d through the tip) is conserved."""
    M, Mp, R, k, i, b, c = (np.asarray(s[x], dtype=float) for x in ("M", "Mp", "R", "k", "i", "b", "c"))
    a = -np.sqrt(np.maximum(R * R - b * b - c * c, 0.0))
    arm = np.cross(_stack(a, b, c + R), _stack(np.cos(i), 0.0 * i, -np.sin(i)))  # tip about B, × d
    zero = np.zeros_like(r.chi1)
    ball = (M[..., None] * np.cross(_stack(zero, zero, R + zero), _stack(r.chi1, r.eta1, zero))
            + (M * R * R / k)[..., None] * _stack(r.n1, r.p1, r.q1))
    before = (Mp * np.asarray(s["V0p"], dtype=float))[..., None] * arm
    after = ball + (Mp * r.V1p)[..., None] * arm
    scale = np.linalg.norm(before, axis=-1) + np.linalg.norm(ball, axis=-1) + np.abs(Mp * r.V1p) * np.linalg.norm(
        arm, axis=-1)
    return before, after, scale


def _cue_vis_viva(s: Scene, r: Any) -> tuple[np.ndarray, np.ndarray]:
    M, Mp, R, k = (np.asarray(s[x], dtype=float) for x in ("M", "Mp", "R", "k"))
    after = Mp * r.V1p**2 + M * (r.chi1**2 + r.eta1**2) + M * R * R / k * (r.n1**2 + r.p1**2 + r.q1**2)
    return Mp * np.asarray(s["V0p"]) ** 2, after


# ---- impact invariants (``paths.ImpactCheck``): what each declared law implies, from first principles -----------
def _rel(x: Any, scale: Any) -> np.ndarray:
    x, scale = np.asarray(x, dtype=float), np.asarray(scale, dtype=float)
    return np.abs(x) / np.where(scale > 0, scale, 1.0)


# A law evaluated on a returned state in floating point: each velocity is known to an ulp, so the vis viva lost by
# a ball 10⁶ times heavier than the other, or spinning 10³ times faster than the balls approach, is known only to
# ~1e-16 of the vis viva itself. The law's measure weighs the residual against its terms, the normal impact's
# scale, and ROUNDING_FLOOR × the vis viva before and after: a residual of ten ulps of the vis viva measures 1e-9.
ROUNDING_FLOOR = 2e-6


def _lost_vis_viva(M: Any, V0: Any, V1: Any) -> np.ndarray:
    """M(V0 − V1)·(V0 + V1) summed over the last axis if vectors: the vis viva lost, without the cancellation of
    M V0² − M V1² (the paper writes it so, §I n°5 (b))."""
    V0, V1 = np.asarray(V0, dtype=float), np.asarray(V1, dtype=float)
    d = (V0 - V1) * (V0 + V1)
    return np.asarray(M, dtype=float) * (d.sum(axis=-1) if d.ndim and d.shape[-1:] == (3,) else d)


def _direct_impact_check(s: Scene, r: Any) -> ImpactCheck:
    """§I n°5: law (6) with no tangential impulse, M(V0² − V1²) + M′(V0′² − V1′²) = εM(V0 − V1)² + ε′M′(V0′ − V1′)²,
    and the ratio it implies with momentum, 2(M + M′)/(M′(1 + ε) + M(1 + ε′)) − 1."""
    M, Mp, V0, V0p, eps, epsp = (np.asarray(s[x], dtype=float) for x in ("M", "Mp", "V0", "V0p", "eps", "epsp"))
    terms = [_lost_vis_viva(M, V0, r.V1), _lost_vis_viva(Mp, V0p, r.V1p), eps * M * (V0 - r.V1) ** 2,
             epsp * Mp * (V0p - r.V1p) ** 2]
    law = terms[0] + terms[1] - terms[2] - terms[3]
    ratio = 2 * (M + Mp) / (Mp * (1 + eps) + M * (1 + epsp)) - 1
    vis_viva = M * (V0 * V0 + r.V1 * r.V1) + Mp * (V0p * V0p + r.V1p * r.V1p)
    return ImpactCheck(V0 - V0p, r.V1 - r.V1p, ratio, (eps == 1) & (epsp == 1),
                       _rel(law, sum(np.abs(t) for t in terms) + M * (V0 - V0p) ** 2 + ROUNDING_FLOOR * vis_viva))


def _direct_elastic(s: Scene) -> tuple[Scene, dict[str, np.ndarray]]:
    M, Mp, V0, V0p = (np.asarray(s[x], dtype=float) for x in ("M", "Mp", "V0", "V0p"))
    e = dict(s, eps=np.zeros_like(V0), epsp=np.zeros_like(V0))
    return e, {"V1": ((M - Mp) * V0 + 2 * Mp * V0p) / (M + Mp), "V1p": ((Mp - M) * V0p + 2 * M * V0) / (M + Mp)}


def _wall_impact_check(s: Scene, r: Any) -> ImpactCheck:
    """§I eq. (9): law (6) against an immovable mass, V0² − V1² = ε(V0 − V1)²."""
    V0, eps = np.asarray(s["V0"], dtype=float), np.asarray(s["eps"], dtype=float)
    terms = [_lost_vis_viva(1.0, V0, r.V1), eps * (V0 - r.V1) ** 2]
    return ImpactCheck(V0, np.asarray(r.V1, dtype=float), (1 - eps) / (1 + eps), eps == 1,
                       _rel(terms[0] - terms[1], np.abs(terms[0]) + terms[1] + V0 * V0))


def _normal_yield_check(s: Scene, r: Any, nu: np.ndarray, plastic: np.ndarray) -> ImpactCheck:
    """§III, §IV: the declared law is the normal yield, ζ1 = −ν ζ0 (§I n°4's principle)."""
    zeta0 = np.asarray(s["zeta0"], dtype=float)
    return ImpactCheck(-zeta0, -np.asarray(r.zeta1, dtype=float), nu, plastic, _rel(r.zeta1 + nu * zeta0, zeta0))


def _plane_elastic(s: Scene) -> tuple[Scene, dict[str, np.ndarray]]:
    z = np.zeros(np.shape(s["zeta0"]))
    e = dict(s, f=z, nu=z + 1.0)
    return e, {"chi1": np.asarray(s["chi0"], dtype=float), "zeta1": -np.asarray(s["zeta0"], dtype=float),
               "p1": np.asarray(s["p0"], dtype=float)}


def _cushion_elastic(s: Scene) -> tuple[Scene, dict[str, np.ndarray]]:
    z = np.zeros(np.shape(s["zeta0"]))
    e = dict(s, j=z, eps=z)
    return e, {"chi1": np.asarray(s["chi0"], dtype=float), "zeta1": -np.asarray(s["zeta0"], dtype=float),
               "p1": np.asarray(s["p0"], dtype=float), "n1": np.asarray(s["n0"], dtype=float)}


def _spheres_impact_check(on_cloth: bool):
    """§V–§VI: law (6) evaluated literally on the returned state, with the slip at the greatest compression the
    result reports (its work 2T·s_c, T on M′): vis viva lost = ε Σ m U² + ε′ Σ m′ U′² + 2T·s_c. The ratio it
    implies (module docstring of ``spheres``): 2(1 + M/M′)/N − 1 without a tangential impulse (f = 0 or no slip),
    e = (1 − ε)/(1 + ε) when ε = ε′ and the tangential impulse keeps one direction without the slip stopping
    (free balls; on the cloth a slip along y or z alone); elsewhere none."""
    def check_(s: Scene, r: Any) -> ImpactCheck:
        M, Mp, R, Rp, k, kp, f, eps, epsp = (np.asarray(s[x], dtype=float)
                                             for x in ("M", "Mp", "R", "Rp", "k", "kp", "f", "eps", "epsp"))
        v, w, vp, wp = (np.asarray(s[x], dtype=float) for x in ("v", "w", "vp", "wp"))
        I, Ip = M * R * R / k, Mp * Rp * Rp / kp  # noqa: E741
        T = np.asarray(r.T, dtype=float)
        s_c = np.asarray(r.s_c, dtype=float)
        loss = [_lost_vis_viva(M, v, r.v1), _lost_vis_viva(I, w, r.w1), _lost_vis_viva(Mp, vp, r.v1p),
                _lost_vis_viva(Ip, wp, r.w1p)]
        lost = eps * (M * np.sum((v - r.v1) ** 2, -1) + I * np.sum((w - r.w1) ** 2, -1))
        lostp = epsp * (Mp * np.sum((vp - r.v1p) ** 2, -1) + Ip * np.sum((wp - r.w1p) ** 2, -1))
        work = 2 * np.sum(T * s_c, axis=-1)
        law = sum(loss) - lost - lostp - work
        before, after = _spheres_vis_viva(s, r)
        scale = (sum(np.abs(x) for x in loss) + lost + lostp + np.abs(work) + M * (v[..., 0] - vp[..., 0]) ** 2
                 + ROUNDING_FLOOR * (before + after))
        s0 = spheres.contact_slip(v, w, vp, wp, R, Rp)
        s1 = spheres.contact_slip(np.asarray(r.v1), np.asarray(r.w1), np.asarray(r.v1p), np.asarray(r.w1p), R, Rp)
        n0, n1 = np.hypot(s0[..., 0], s0[..., 1]), np.hypot(s1[..., 0], s1[..., 1])
        mu = M / Mp
        none = (f == 0) | (n0 == 0)
        one_way = ((s0[..., 0] == 0) | (s0[..., 1] == 0)) if on_cloth else np.ones(np.shape(f), dtype=bool)
        slid = n1 > 1e-6 * n0  # the slip did not stop (it cannot start again)
        ratio = np.where(none, 2 * (1 + mu) / ((1 + eps) + mu * (1 + epsp)) - 1,
                         np.where((eps == epsp) & one_way & slid, (1 - eps) / (1 + eps), np.nan))
        return ImpactCheck(v[..., 0] - vp[..., 0], r.v1[..., 0] - r.v1p[..., 0], ratio, (eps == 1) & (epsp == 1),
                           _rel(law, scale))
    return check_


def _spheres_elastic(s: Scene) -> tuple[Scene, dict[str, np.ndarray]]:
    M, Mp = np.asarray(s["M"], dtype=float), np.asarray(s["Mp"], dtype=float)
    v, vp = np.array(s["v"], dtype=float), np.array(s["vp"], dtype=float)
    z = np.zeros(np.shape(M))
    e = dict(s, f=z, eps=z, epsp=z)
    v1, v1p = v.copy(), vp.copy()
    v1[..., 0] = ((M - Mp) * v[..., 0] + 2 * Mp * vp[..., 0]) / (M + Mp)
    v1p[..., 0] = ((Mp - M) * vp[..., 0] + 2 * M * v[..., 0]) / (M + Mp)
    return e, {"v1": v1, "w1": np.asarray(s["w"], dtype=float), "v1p": v1p, "w1p": np.asarray(s["wp"], dtype=float)}


def _cue_impact_check(s: Scene, r: Any) -> ImpactCheck:
    """§VII: the compression ends along the cue axis d (the model's premise): the approach is the cue's speed less
    the speed along d of the ball's point under the tip (v + ω × (a, b, c)). Law (6) here involves the slip on the
    cloth at the greatest compression, which the result does not carry: the referee weighs it (nan here)."""
    R, b, c, i, V0p = (np.asarray(s[x], dtype=float) for x in ("R", "b", "c", "i", "V0p"))
    eps, epsp = np.asarray(s["eps"], dtype=float), np.asarray(s["epsp"], dtype=float)
    a = -np.sqrt(np.maximum(R * R - b * b - c * c, 0.0))
    chi, n, p, q = (np.asarray(getattr(r, x), dtype=float) for x in ("chi1", "n1", "p1", "q1"))
    # (ω × r)·d with ω = (n, p, q), r = (a, b, c), d = (cos i, 0, −sin i)
    wx_r = (p * c - q * b, q * a - n * c, n * b - p * a)
    tip = (chi + wx_r[0]) * np.cos(i) - wx_r[2] * np.sin(i)
    nan = np.full(np.shape(chi), np.nan)
    return ImpactCheck(V0p + 0.0 * chi, np.asarray(r.V1p, dtype=float) - tip, nan, (eps == 1) & (epsp == 1), nan)


def _cue_elastic(s: Scene) -> tuple[Scene, dict[str, np.ndarray]]:
    """A central horizontal stroke (i = b = c = 0), no friction, ε = ε′ = 0: the cue and the ball exchange
    momentum as two elastic masses (§I eq. (8) at ε = ε′ = 0); the ball does not turn."""
    M, Mp, V0p = (np.asarray(s[x], dtype=float) for x in ("M", "Mp", "V0p"))
    z = np.zeros(np.shape(M))
    e = dict(s, i=z, b=z, c=z, f=z, eps=z, epsp=z)
    return e, {"chi1": 2 * Mp * V0p / (M + Mp), "eta1": z, "n1": z, "p1": z, "q1": z,
               "V1p": (Mp - M) * V0p / (M + Mp)}


# ---- the registry --------------------------------------------------------------------------------------------
def _build() -> dict[str, Model]:
    models = [
        Model("direct-impact", "§I n°5, eq. (7)", "direct impact of M on M′", (
            Param("M", "kg", "mass of the striking body", 1.0, lo=0.0, lo_open=True),
            Param("Mp", "kg", "mass of the struck body", 1.0, lo=0.0, lo_open=True),
            Param("V0", "m/s", "velocity of M before the impact", 1.0),
            Param("V0p", "m/s", "velocity of M′ before the impact", 0.0),
            Param("eps", "1", "Résal's ε of M (0 elastic, 1 Carnot's inelastic impact)", None, **_EPS),
            Param("epsp", "1", "Résal's ε′ of M′", None, **_EPS),
        ), (), (
            Path(PathCode.EXACT, Kind.CLOSED_FORM, _direct_exact, always, 1e-13, 1, "closed form, eq. (7)",
                 scalar=True),
            Path(PathCode.ODE, Kind.ODE, _direct_ode, always, 1e-8, 1000,
                 "two-phase hysteretic contact integrated in time (DOP853)", tuned=_direct_ode, rtol=1e-10,
                 solver="DOP853"),
        ), ("V1", "V1p"), lambda s: _num(s["V0"]) > _num(s["V0p"]),
            "the bodies must approach (V0 > V′0): separating bodies do not collide",
            sample=_direct_sample, scale=lambda s: np.abs(np.asarray(s["V0"]) - np.asarray(s["V0p"])),
            vis_viva=lambda s, r: (s["M"] * s["V0"] ** 2 + s["Mp"] * s["V0p"] ** 2,
                                   s["M"] * r.V1**2 + s["Mp"] * r.V1p**2),
            momentum=lambda s, r: ((s["M"] * s["V0"] + s["Mp"] * s["V0p"])[..., None],
                                   (s["M"] * r.V1 + s["Mp"] * r.V1p)[..., None],
                                   np.abs(s["M"] * s["V0"]) + np.abs(s["Mp"] * s["V0p"]) + np.abs(s["M"] * r.V1)
                                   + np.abs(s["Mp"] * r.V1p)),
            impact=_direct_impact_check, elastic=_direct_elastic),
        Model("wall-impact", "§I n°5, eq. (9)", "impact on an immovable mass (cushion, slab)", (
            Param("V0", "m/s", "normal velocity before the impact, towards the mass", 1.0, lo=0.0, lo_open=True),
            Param("eps", "1", "Résal's ε of the ball", None, **_EPS),
        ), (), (
            Path(PathCode.EXACT, Kind.CLOSED_FORM, _wall_exact, always, 1e-13, 1, "closed form, eq. (9)", scalar=True),
            Path(PathCode.ODE, Kind.ODE, _wall_ode, always, 1e-8, 1000,
                 "two-phase contact against an immovable mass (DOP853)", tuned=_wall_ode, rtol=1e-10, solver="DOP853"),
        ), ("V1",), lambda s: _num(s["V0"]) > 0, "the ball must approach the mass (V0 > 0)",
            sample=lambda rng, n: {"V0": rng.uniform(0.1, 5.0, n), "eps": rng.uniform(0.0, 1.0, n)},
            scale=lambda s: np.abs(np.asarray(s["V0"])),
            vis_viva=lambda s, r: (np.asarray(s["V0"]) ** 2, r.V1**2), impact=_wall_impact_check,
            elastic=lambda s: (dict(s, eps=np.zeros(np.shape(s["V0"]))), {"V1": -np.asarray(s["V0"], dtype=float)})),
        Model("plane-impact", "§III n°8, eqs (4)-(7)", "a free sphere striking a fixed plane with friction", (
            Param("chi0", "m/s", "tangential velocity of the centre before", 1.0),
            Param("zeta0", "m/s", "normal velocity before, negative: approaching", -1.0, hi=0.0, hi_open=True),
            Param("p0", "rad/s", "rotation before; the contact slips at v_x = χ − pR", 0.0),
            _R, _K, _f(), Param("nu", "1", "yield ν of the normal velocity, ζ1 = −νζ0", None, **_NU),
        ), (), (
            Path(PathCode.EXACT, Kind.CLOSED_FORM, lambda s: _plane(s, "exact"),
                 always, 1e-13, 1, "closed form in both regimes", scalar=True),
            Path(PathCode.RESAL, Kind.AS_PRINTED, lambda s: _plane(s, "resal"),
                 _plane_resal_exact, 1e-13, 1, "eqs (6) as printed: sliding assumed throughout", scalar=True),
            Path(PathCode.ODE, Kind.ODE, lambda s: _plane_ode(s["chi0"], s["zeta0"], s["p0"], R=s["R"], k=s["k"],
                                                              f=s["f"],
                                                             nu=s["nu"]), always, 1e-9, 1000,
                 "impulse equations (4) with a slip-stop event (DOP853)",
                 tuned=lambda s, rtol, solver: _plane_ode(s["chi0"], s["zeta0"], s["p0"], R=s["R"], k=s["k"],
                                                          f=s["f"], nu=s["nu"], rtol=rtol, solver=solver),
                 rtol=1e-11, solver="DOP853"),
            Path(PathCode.REFERENCE, Kind.REFEREE, _plane_reference, always, 1e-9, 2000,
                 "referee: the six velocity components in the normal impulse (DOP853)", tuned=_plane_reference,
                 rtol=1e-13, solver="DOP853"),
        ), ("chi1", "zeta1", "p1*R"), lambda s: _num(s["zeta0"]) < 0,
            "the sphere must approach the plane (ζ0 < 0)", sample=_plane_sample,
            scale=lambda s: np.hypot(s["chi0"], s["zeta0"]) + np.abs(s["p0"] * s["R"]), vis_viva=_plane_vis_viva,
            momentum=_about_contact,
            mirror=lambda s: _flip(s, "chi0", "p0"), mirrored=lambda r: {"chi1": -r.chi1, "zeta1": r.zeta1,
                                                                          "p1": -r.p1},
            impact=lambda s, r: _normal_yield_check(s, r, np.asarray(s["nu"], dtype=float),
                                                    np.zeros(np.shape(s["nu"]), dtype=bool)),
            elastic=_plane_elastic),
        Model("ricochet", "§III n°9", "ricochets on a horizontal plane: impacts and parabolic flights", (
            Param("a0", "m/s", "speed of the centre arriving at the first impact", 2.0, lo=0.0, lo_open=True),
            Param("alpha0", "rad", "its angle below the plane", math.radians(20.0), lo=0.0, hi=math.pi / 2,
                  lo_open=True, hi_open=True, cli_degrees=True),
            Param("p0", "rad/s", "rotation arriving", 0.0), _R, _K, _f(),
            Param("nu", "1", "yield ν of the normal velocity", None, **_NU), _G,
            Param("n", "1", "number of impacts", 12.0, lo=1.0, hi=1000.0, integer=True),
        ), (), (
            Path(PathCode.EXACT, Kind.CLOSED_FORM, lambda s: _ricochet_run(s, "exact"), always, 1e-12, 1,
                 "closed-form impacts, parabolic flights"),
            Path(PathCode.RESAL, Kind.AS_PRINTED, lambda s: _ricochet_run(s, "resal"), _ricochet_resal_exact,
                 1e-12, 1, "impacts by eqs (6) (sliding assumed), parabolic flights"),
            Path(PathCode.ODE, Kind.ODE, _ricochet_ode, always, 1e-8, 1000,
                 "impacts and flights integrated (DOP853)", tuned=_ricochet_ode, rtol=1e-11, solver="DOP853"),
        ), ("ranges", "times", "chi", "zeta", "p*R"), lambda s: np.ones(np.shape(s["a0"]), dtype=bool),
            "every launch (a0 > 0, 0 < α0 < 90°)", static=("n",), sample=_ricochet_sample,
            scale=lambda s: np.asarray(s["a0"]) * (1 + np.asarray(s["a0"]) / np.asarray(s["g"]))
            + np.abs(s["p0"] * s["R"]), vis_viva=_ricochet_vis_viva, momentum=_ricochet_momentum),
        Model("cloth-slide", "§II n°7, eqs (1)-(5)", "a ball sliding on the cloth until it rolls", (
            Param("vx", "m/s", "velocity of the centre along x", 2.0), Param("vy", "m/s", "along y", 0.0),
            Param("wx", "rad/s", "rotation about x, n; the slip is v_y = η + nR", 0.0),
            Param("wy", "rad/s", "rotation about y, p; the slip is v_x = χ − pR", 0.0), _R, _K,
            Param("f", "1", "friction on the cloth", None, lo=0.0, lo_open=True), _G,
        ), (), (
            Path(PathCode.EXACT, Kind.CLOSED_FORM, _cloth_exact, always, 1e-13, 1, "Euler's parabola, eqs (3)-(4)",
                 scalar=True),
            Path(PathCode.ODE, Kind.ODE, _cloth_ode, always, 1e-8, 1000, "eqs (2) integrated in time (DOP853)",
                 tuned=_cloth_ode, rtol=1e-11, solver="DOP853"),
        ), ("t_roll*g", "x_roll*g", "y_roll*g", "vx_roll", "vy_roll"), lambda s: _everywhere(s["vx"]),
            "every initial state", sample=_cloth_sample,
            scale=lambda s: 1 + np.hypot(s["vx"], s["vy"]) + np.hypot(s["wx"], s["wy"]) * s["R"],
            vis_viva=_cloth_vis_viva, momentum=_cloth_momentum, output_scale=_cloth_scales,
            mirror=lambda s: _flip(s, "vy", "wx"),
            mirrored=lambda r: {"t_roll": r.t_roll, "x_roll": r.x_roll, "y_roll": -r.y_roll, "vx_roll": r.vx_roll,
                                "vy_roll": -r.vy_roll}),
        Model("cushion-impact", "§IV n°11, eqs (4)-(11)", "a ball against a cushion, with friction and side spin", (
            Param("chi0", "m/s", "velocity along the cushion", 1.0),
            Param("zeta0", "m/s", "normal velocity, negative: approaching", -1.0, hi=0.0, hi_open=True),
            Param("p0", "rad/s", "side spin about the vertical; the slip is φ = χ − pR", 0.0),
            Param("n0", "rad/s", "rotation about the cushion's direction (rolling in: ζ0/R)", 0.0), _R, _K,
            Param("j", "1", "ball-cushion friction", None, lo=0.0),
            Param("eps", "1", "Résal's ε on the cushion", None, **_EPS),
        ), (), (
            Path(PathCode.ELEMENTARY, Kind.CLOSED_FORM, _cushion("elementary"), _cushion_elementary, 1e-13, 1,
                 "the slip keeps its direction: linear decay", handles=_cushion_elementary,
                 handles_text="n0 = 0, φ0 = χ0 − p0R = 0 or j = 0 (otherwise the slip turns)", scalar=True),
            Path(PathCode.EXACT, Kind.EXACT_NUMERICAL, _cushion("exact"), always, 1e-12, 3,
                 "Résal's integral (10) in closed form (₂F₁), its end by Newton's method", scalar=True),
            Path(PathCode.RESAL, Kind.AS_PRINTED, _cushion("resal"), _cushion_resal_exact, 1e-12, 1,
                 "eq. (11) as printed, exponent (1 + k)/2"),
            Path(PathCode.RESAL_CORRECTED, Kind.CORRECTED, _cushion("resal-corrected"), _cushion_resal_exact,
                 1e-12, 1, "eq. (11) with the derived exponent 2/(1 + k)"),
            Path(PathCode.ODE, Kind.ODE, _cushion("ode"), always, 1e-8, 1000,
                 "eqs (2) integrated in the normal impulse (DOP853)", tuned=_cushion("ode"), rtol=1e-11,
                 solver="DOP853"),
            Path(PathCode.REFERENCE, Kind.REFEREE, _cushion_reference, always, 1e-9, 2000,
                 "referee: every velocity component in the normal impulse, the cloth bilateral (DOP853)",
                 tuned=_cushion_reference, rtol=1e-13, solver="DOP853"),
        ), ("chi1", "zeta1", "p1*R", "n1*R"), lambda s: _num(s["zeta0"]) < 0,
            "the ball must approach the cushion (ζ0 < 0)", sample=_cushion_sample,
            scale=lambda s: np.hypot(s["chi0"], s["zeta0"]) + np.hypot(s["p0"], s["n0"]) * s["R"],
            vis_viva=_cushion_vis_viva, momentum=_about_contact, mirror=lambda s: _flip(s, "chi0", "p0"),
            mirrored=lambda r: {"chi1": -r.chi1, "zeta1": r.zeta1, "p1": -r.p1, "n1": r.n1},
            impact=lambda s, r: _normal_yield_check(s, r, impact.nu_from_eps(np.asarray(s["eps"], dtype=float)),
                                                    np.asarray(s["eps"], dtype=float) == 1),
            elastic=_cushion_elastic),
        _spheres_model(False),
        _spheres_model(True),
        Model("cue-stroke", "§VII n°14, eqs (2)-(12)", "the stroke of an inclined cue, off centre", (
            Param("M", "kg", "mass of the ball", 0.21, lo=0.0, lo_open=True),
            Param("Mp", "kg", "mass of the cue", 0.6, lo=0.0, lo_open=True),
            Param("V0p", "m/s", "speed of the cue before the stroke", 3.0, lo=0.0, lo_open=True),
            Param("i", "rad", "inclination of the cue on the cloth", 0.0, lo=0.0, hi=math.pi / 2, hi_open=True,
                  cli_degrees=True),
            Param("b", "m", "side offset of the contact point", 0.0),
            Param("c", "m", "height of the contact point above the centre", 0.0), _R, _K,
            Param("f", "1", "friction of the ball on the cloth", None, lo=0.0),
            Param("eps", "1", "Résal's ε of the ball", None, **_EPS),
            Param("epsp", "1", "Résal's ε′ of the cue", None, **_EPS),
        ), (), (
            Path(PathCode.EXACT, Kind.CLOSED_FORM, _cue("exact"), always, 1e-13, 1,
                 "eqs (2)-(10) with the full moment, compression ended along the cue axis", scalar=True),
            Path(PathCode.RESAL, Kind.AS_PRINTED, _cue("resal"),
                 lambda s: (np.asarray(s["b"]) == 0) & (np.asarray(s["c"]) == 0) & (np.asarray(s["i"]) == 0),
                 1e-13, 1, "eqs (2)-(12) as printed", scalar=True),
            # 1e-7: the friction is regularised over 1e-9 of the impulse scale; `resal stress` found 3e-8 for a
            # ball 1e6 times lighter than the cue (1e-8 was declared before)
            Path(PathCode.ODE, Kind.ODE, _cue_ode, always, 1e-7, 1000,
                 "eqs (3) integrated in the cue impulse (LSODA, regularised friction)", tuned=_cue_ode, rtol=1e-10,
                 solver="LSODA"),
            Path(PathCode.REFERENCE, Kind.REFEREE, _cue_reference, always, 1e-9, 2000,
                 "referee: every velocity component in the cue impulse, the cloth by complementarity (DOP853)",
                 tuned=_cue_reference, rtol=1e-12, solver="DOP853"),
        ), ("chi1", "eta1", "n1*R", "p1*R", "q1*R", "V1p"), _cue_admissible,
            "the contact point must lie on the ball (b² + c² < R²) where the cue can reach it (cos φ > 0)",
            sample=_cue_sample, scale=lambda s: np.asarray(s["V0p"]), vis_viva=_cue_vis_viva, momentum=_cue_momentum,
            impact=_cue_impact_check, elastic=_cue_elastic,
            mirror=lambda s: _flip(s, "b"),
            mirrored=lambda r: {"chi1": r.chi1, "eta1": -r.eta1, "n1": -r.n1, "p1": r.p1, "q1": -r.q1,
                                "V1p": r.V1p}),
    ]
    return {m.name: m for m in models}


MODELS: dict[str, Model] = _build()


def model(name: str) -> Model:
    """A model by name; ``KeyError`` lists the known ones."""
    if name not in MODELS:
        raise KeyError(f"unknown model '{name}' (expected one of: {', '.join(MODELS)})")
    return MODELS[name]

