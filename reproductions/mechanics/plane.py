"""§III n°8–9 of Résal (1883): a free sphere striking a fixed plane with friction, and ricochets.

Notation of the paper (n°8): x along the slip of the contact point, z normal to the plane and outward;
χ, ζ the components of the centre's velocity (ζ0 < 0 while approaching), p the rotation about the third
axis, with the contact point slipping at v_x = χ − pR (eq. 1); moment of inertia M R²/k (k = 5/2 for a
homogeneous ball); f the sliding friction; ν the yield of the normal velocity, ζ1 = −ν ζ0 (n°8).

Derivation in the normal-impulse variable π = (1/M)∫Z dt, which runs from 0 to (1 + ν)|ζ0| (eq. 4 with
ζ1 = −νζ0): while the contact slides, dχ = −s f dπ, d(pR) = s k f dπ with s = sign(v_x), so
dv_x = −s f (1 + k) dπ. Résal assumes the slip lasts the whole impact, which holds iff

    |χ0 − p0 R| ≥ f (1 + k)(1 + ν) |ζ0|                       (slide condition, not in the paper)

and then gives eqs (6). Otherwise the slip stops at π* = |v_x0| / (f(1 + k)); from there the contact point
rolls (keeping v_x = 0 needs no friction at all, so Coulomb's bound is never reached) and the outcome is
v_x1 = 0: χ1 = (kχ0 + p0R)/(1 + k), p1R = χ1. Both regimes are one formula,

    Δv_x = −s · min(|v_x0|, f(1 + k)(1 + ν)|ζ0|),   Δχ = Δv_x/(1 + k),   Δ(pR) = −k Δv_x/(1 + k),

continuous across the boundary. ``reference.integrate_plane_impact`` integrates the impulse equations
numerically as the check.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .paths import PathCode, Regime, as_floats, codes, minimum, pick, result

__all__ = [
    "PlaneImpact",
    "Ricochet",
    "plane_impact",
    "range_ratio_exact",
    "range_ratio_resal",
    "range_ratio_small_angle",
    "ricochet",
    "ricochet_ranges_spinless",
    "slides_throughout",
    "spinless_launch",
]

METHODS = ("exact", "resal")
_LABELS = {"resal": "Résal's eqs (6), §III n°8 (sliding assumed)",
           "exact": "closed form, both regimes (slide / slip stops then rolls)"}
_CODES = {m: PathCode[m.upper()] for m in METHODS}


@dataclass(frozen=True)
class PlaneImpact:
    """Velocities after the impact; ``regime``: SLIDE (the contact slid during the whole impact), GRIP (the slip
    stopped, then the contact rolled) or NO_SLIP (v_x0 = 0)."""

    chi1: np.ndarray
    zeta1: np.ndarray
    p1: np.ndarray
    method: str
    path: np.ndarray
    regime: np.ndarray
    label: str


_NO_SLIP, _SLIDE, _GRIP = (np.int8(r) for r in (Regime.NO_SLIP, Regime.SLIDE, Regime.GRIP))


def plane_regime(v0: np.ndarray, sliding: np.ndarray) -> np.ndarray:
    """The ``Regime`` of a plane impact from the initial slip and the slide condition (int8; one scene as numpy
    floats: numpy's int8)."""
    return pick(v0 == 0, _NO_SLIP, pick(sliding, _SLIDE, _GRIP))


def _arrays(*args: ArrayLike) -> list[np.ndarray]:
    return as_floats(*args)  # numpy floats (one scene: the small-batch route of ``paths.solve``) pass as they are


def slides_throughout(chi0: ArrayLike, zeta0: ArrayLike, p0: ArrayLike, *, R: ArrayLike, k: ArrayLike, f: ArrayLike,
                      nu: ArrayLike) -> np.ndarray:
    """True where the slip lasts the whole impact, |χ0 − p0R| ≥ f(1 + k)(1 + ν)|ζ0| (module docstring)."""
    chi0, zeta0, p0, R, k, f, nu = _arrays(chi0, zeta0, p0, R, k, f, nu)
    return np.abs(chi0 - p0 * R) >= f * (1 + k) * (1 + nu) * np.abs(zeta0)


def plane_impact(chi0: ArrayLike, zeta0: ArrayLike, p0: ArrayLike, *, R: ArrayLike, k: ArrayLike, f: ArrayLike,
                 nu: ArrayLike, method: str = "exact") -> PlaneImpact:
    """Impact of a sphere on a fixed plane (§III n°8).

    ``method="resal"``: eqs (6) as derived by Résal, sliding assumed throughout (wrong where the slip stops).
    ``"exact"``: the outcome in both regimes (module docstring). ζ0 must be negative (approaching); ζ1 = −ν ζ0
    in every path. The ODE path is ``reference.integrate_plane_impact``; ``registry`` chooses among them.
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    chi0, zeta0, p0, R, k, f, nu = _arrays(chi0, zeta0, p0, R, k, f, nu)
    chi1, zeta1, p1, v0, sliding = _impact(chi0, zeta0, p0, R, k, f, nu, method)
    shape = chi1.shape
    if v0.shape != shape:
        v0 = np.broadcast_to(v0, shape)
    return result(PlaneImpact, chi1=chi1, zeta1=zeta1, p1=p1, method=method, path=codes(shape, _CODES[method]),
                  regime=np.asarray(plane_regime(v0, sliding)), label=_LABELS[method])


def _impact(chi0: np.ndarray, zeta0: np.ndarray, p0: np.ndarray, R: np.ndarray, k: np.ndarray, f: np.ndarray,
            nu: np.ndarray, method: str) -> tuple[np.ndarray, ...]:
    """The arithmetic of ``plane_impact`` on float arrays: (χ1, ζ1, p1, v_x0, sliding)."""
    v0 = chi0 - p0 * R
    budget = f * (1 + k) * (1 + nu) * np.abs(zeta0)  # the change of v_x that sliding friction can make
    size = np.abs(v0)
    sliding = size >= budget
    if method == "resal":  # eqs (6): χ1 = χ0 + f(1 + ν)ζ0, p1R = p0R − fk(1 + ν)ζ0, for v_x0 > 0
        s = np.sign(v0)
        chi1 = chi0 + s * f * (1 + nu) * zeta0
        pR1 = p0 * R - s * f * k * (1 + nu) * zeta0
    else:
        dv = -np.sign(v0) * minimum(size, budget)
        chi1 = chi0 + dv / (1 + k)
        pR1 = p0 * R - k * dv / (1 + k)
    return chi1, -nu * zeta0, pR1 / R, v0, sliding


def range_ratio_resal(alpha0: ArrayLike, *, f: ArrayLike, nu: ArrayLike) -> np.ndarray:
    """Eq. (8), §III n°9: P1/P0 = ν[1 − f(1 + ν) tan α0]; exact while the contact slides."""
    alpha0, f, nu = _arrays(alpha0, f, nu)
    return nu * (1 - f * (1 + nu) * np.tan(alpha0))


def range_ratio_small_angle(nu: ArrayLike) -> np.ndarray:
    """Eq. (9), §III n°9: P1/P0 = ν, for f tan α0 ≪ 1; exact once the ball rolls (v_x = 0 at impact)."""
    return np.asarray(nu, dtype=float)


def range_ratio_exact(alpha0: ArrayLike, *, f: ArrayLike, nu: ArrayLike, k: ArrayLike,
                      spin: ArrayLike = 0.0) -> np.ndarray:
    """P1/P0 = ν χ1/χ0 for a ball arriving at angle α0 with spin p0R = spin·a0, in both regimes.

    P0 is the range of the flight that ends at this impact (same χ0, and |ζ0| by symmetry of the
    parabola), P1 that of the next flight; both are 2χζ/g (§III n°9).
    """
    alpha0, f, nu, k, spin = _arrays(alpha0, f, nu, k, spin)
    chi0, zeta0 = np.cos(alpha0), -np.sin(alpha0)
    out = plane_impact(chi0, zeta0, spin, R=1.0, k=k, f=f, nu=nu, method="exact")
    return nu * out.chi1 / chi0


@dataclass(frozen=True)
class Ricochet:
    """A sequence of n impacts and n flights (§III n°9). Arrays have shape (batch..., n) or (batch..., n+1)."""

    ranges: np.ndarray  # P_j: range of the flight after impact j
    times: np.ndarray  # T_j: its duration
    imprints: np.ndarray  # positions of the n impacts and of the landing after the last flight, first at 0
    chi: np.ndarray  # χ after each impact
    zeta: np.ndarray  # ζ after each impact
    p: np.ndarray  # p after each impact
    regimes: np.ndarray  # the Regime of each impact
    method: str
    path: np.ndarray
    regime: np.ndarray  # the Regime of the first impact
    label: str


def ricochet(a0: ArrayLike, alpha0: ArrayLike, p0: ArrayLike, *, R: ArrayLike, k: ArrayLike, f: ArrayLike,
             nu: ArrayLike, g: ArrayLike, n: int, method: str = "exact",
             impact: Callable[..., PlaneImpact] | None = None) -> Ricochet:
    """Ricochets on a horizontal plane (§III n°9): impacts by ``plane_impact``, parabolic flights between.

    (a0, α0, p0) describe the ball arriving at the first impact: χ0 = a0 cos α0, ζ0 = −a0 sin α0. A flight
    keeps χ and p (no air), reverses ζ, lasts T = 2ζ/g and covers P = 2χζ/g. Vectorised over the batch.
    ``impact`` replaces ``plane_impact`` (the ODE path passes the integrated impact).
    """
    a0, alpha0, p0, R, k, f, nu, g = np.broadcast_arrays(*_arrays(a0, alpha0, p0, R, k, f, nu, g))
    if impact is None and method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    chi, zeta, p = a0 * np.cos(alpha0), -a0 * np.sin(alpha0), p0
    cols: dict[str, list[np.ndarray]] = {"chi": [], "zeta": [], "p": [], "regime": [], "P": [], "T": []}
    label = "" if impact is not None or n == 0 else _LABELS[method]
    for _ in range(n):
        if impact is None:  # plane_impact's arithmetic without its wrapping (the fits call this 10³ times)
            chi, zeta, p, v0, sliding = _impact(chi, zeta, p, R, k, f, nu, method)
            regime = plane_regime(v0, sliding)
        else:
            out = impact(chi, zeta, p, R=R, k=k, f=f, nu=nu, method=method)
            label, chi, zeta, p, regime = out.label, out.chi1, out.zeta1, out.p1, out.regime
        cols["chi"].append(chi)
        cols["zeta"].append(zeta)
        cols["p"].append(p)
        cols["regime"].append(regime)
        cols["T"].append(2 * zeta / g)
        cols["P"].append(2 * chi * zeta / g)
        zeta = -zeta  # lands with the normal velocity reversed
    st = {key: np.stack(v, axis=-1) for key, v in cols.items()}
    imprints = np.concatenate([np.zeros((*a0.shape, 1)), np.cumsum(st["P"], axis=-1)], axis=-1)
    return Ricochet(ranges=st["P"], times=st["T"], imprints=imprints, chi=st["chi"], zeta=st["zeta"], p=st["p"],
                    regimes=st["regime"], method=method, path=codes(a0.shape, PathCode[method.upper()]),
                    regime=st["regime"][..., 0], label=label + "; parabolic flights")


def ricochet_ranges_spinless(nu: ArrayLike, A: ArrayLike, u: ArrayLike, k: ArrayLike, n: int) -> np.ndarray:
    """Ranges P_0 … P_{n−1} of the flights after n impacts of a ball arriving without spin (§III n°9).

    Closed form of ``ricochet`` with p0 = 0, in the only combinations the ranges depend on: A = 2χ_in ζ_in/g
    (the range of the arriving flight, 2a0² sin α0 cos α0/g) and u = f tan α0. Impact j meets |ζ| = ν^j ζ_in;
    while sliding, each impact lowers v_x by (1 + k) f (1 + ν) ν^j ζ_in and χ by 1/(1 + k) of that; once the
    slip stops the ball rolls and χ stays k/(1 + k) χ_in (the slip then needs no friction). Hence
    P_j = A ν^(j+1) max(1 − u(1 + ν)S_j, k/(1 + k)), S_j = 1 + ν + … + ν^j. f and α0 enter only through u:
    from ranges alone, f is not identifiable.
    """
    nu, A, u, k = _arrays(nu, A, u, k)
    j = np.arange(n)
    nu_, A_, u_, k_ = (np.asarray(a)[..., None] for a in (nu, A, u, k))
    S = np.cumsum(nu_ ** j, axis=-1) if n else np.zeros((*nu_.shape[:-1], 0))
    c = np.maximum(1 - u_ * (1 + nu_) * S, k_ / (1 + k_))
    return A_ * nu_ ** (j + 1) * c


def spinless_launch(A: ArrayLike, u: ArrayLike, g: ArrayLike, alpha0: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """(f, a0) of the launches at angle α0 whose spinless ricochets have the combinations (A, u) (§III n°9).

    The inverse of A = a0² sin 2α0 / g and u = f tan α0 (``ricochet_ranges_spinless``): f = u / tan α0 and
    a0 = √(gA / sin 2α0). Every α0 in (0, π/2) gives the same ranges: this is the exact family of solutions of
    a fit of positions alone; a0 is smallest at α0 = π/4.
    """
    A, u, g, alpha0 = _arrays(A, u, g, alpha0)
    return u / np.tan(alpha0), np.sqrt(g * A / np.sin(2 * alpha0))


# ---- §III n°8 in three dimensions: the vector equations of motion, independent of eqs (1)–(7) -----------------
# The contact point is at r = −R ẑ from the centre (z normal to the plane, outward, §II n°7). With the velocity v of
# the centre and Rω (ω the rotation), the slip of the contact point is u = v + ω × r; per unit normal impulse
# π = (1/M)∫Z dt, Newton and Euler give dv/dπ = ẑ − f û and d(Rω)/dπ = (k/R) r × (−f û) = k f ẑ × û while the
# contact slides (û the unit horizontal slip; moment of inertia M R²/k). Nothing of the paper's component
# equations is used: comparing with them checks (1)–(5).
@dataclass(frozen=True)
class Impact3D:
    """A sphere–plane impact integrated in three dimensions (``integrate_impact_3d``)."""

    v1: np.ndarray  # velocity of the centre after the impact, (χ, η, ζ)
    Rw1: np.ndarray  # R times the rotation after the impact, (nR, pR, qR)
    turn: float  # largest sine of the angle between the slip and its initial direction while it slides
    stopped_at: float  # fraction of the normal impulse at which the slip stopped (nan: it slid throughout)


def _cross(a0: Any, a1: Any, a2: Any, b0: Any, b1: Any, b2: Any) -> tuple[Any, Any, Any]:
    """The vector product a × b in components (floats, or arrays of one shape): written out, since ``np.cross``
    costs some 30 µs a call and the right-hand side below calls it twice per evaluation."""
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


_CONTACT = (0.0, 0.0, -1.0)  # the contact point from the centre, in units of R
_NORMAL = (0.0, 0.0, 1.0)  # ẑ, the outward normal of the plane


def slip_velocity(v: ArrayLike, Rw: ArrayLike) -> np.ndarray:
    """Velocity of the contact point, v + ω × (−R ẑ), from the vector product (§III n°8; the check of eq. 1)."""
    v, Rw = _arrays(v, Rw)
    w = np.moveaxis(Rw, -1, 0)
    return v + np.stack(np.broadcast_arrays(*_cross(w[0], w[1], w[2], *_CONTACT)), axis=-1)


def impact_rates(v: ArrayLike, Rw: ArrayLike, *, k: float, f: float) -> tuple[np.ndarray, np.ndarray]:
    """(dv/dπ, d(Rω)/dπ) while the contact slides, from Newton–Euler in vector form (the check of eqs 2 and 4)."""
    u = slip_velocity(v, Rw)
    uh = u * np.array([1.0, 1.0, 0.0])
    unit = uh / np.linalg.norm(uh, axis=-1, keepdims=True)
    e = np.moveaxis(unit, -1, 0)
    z = np.broadcast_to(_NORMAL, np.shape(unit))
    return z - f * unit, k * f * np.stack(np.broadcast_arrays(*_cross(*_NORMAL, e[0], e[1], e[2])), axis=-1)


def _impact_rhs(k: float, f: float) -> Callable[[float, np.ndarray], np.ndarray]:
    """``impact_rates`` for one state y = (v, Rω) of ``solve_ivp``, in floats: the same vector equations, term by
    term, at a tenth of the cost of the array version (the integration calls it some 120 times per impact)."""
    def rhs(_pi: float, y: np.ndarray) -> np.ndarray:
        vx, vy, _vz, wx, wy, wz = y.tolist()
        cx, cy, _cz = _cross(wx, wy, wz, *_CONTACT)
        ux, uy = vx + cx, vy + cy  # the slip v + ω × (−R ẑ), horizontal part
        norm = math.hypot(ux, uy)
        ex, ey = ux / norm, uy / norm
        tx, ty, tz = _cross(*_NORMAL, ex, ey, 0.0)
        return np.array([_NORMAL[0] - f * ex, _NORMAL[1] - f * ey, _NORMAL[2], k * f * tx, k * f * ty, k * f * tz])

    return rhs


def integrate_impact_3d(v0: ArrayLike, Rw0: ArrayLike, *, k: float, f: float, nu: float, rtol: float = 1e-11,
                        samples: int = 64) -> Impact3D:
    """One impact of a sphere on a fixed plane in three dimensions, integrated in the normal impulse (§III n°8).

    The slip is stopped by an event on its projection on the initial direction (it crosses zero cleanly); from there
    the contact rolls and needs no friction, so only ζ still changes. ζ0 = v0[2] < 0; ζ1 = −ν ζ0 (n°8's ν).
    """
    from scipy.integrate import solve_ivp

    from .budget import bounded, check

    v0, Rw0 = (np.array(a, dtype=float) for a in _arrays(v0, Rw0))
    end = (1.0 + nu) * abs(v0[2])
    u0 = slip_velocity(v0, Rw0)[:2]
    scale = max(float(np.max(np.abs(np.concatenate([v0, Rw0])))), abs(v0[2]))
    if f == 0.0 or end == 0.0 or np.hypot(*u0) <= 1e-14 * scale:  # no slip, or one lost in the rounding of v + Rω
        return Impact3D(v0 + np.array([0.0, 0.0, end]), Rw0, 0.0, float("nan"))
    e0x, e0y = (u0 / np.linalg.norm(u0)).tolist()

    def stops(_pi: float, y: np.ndarray) -> float:
        vx, vy, _vz, wx, wy, wz = y.tolist()
        cx, cy, _cz = _cross(wx, wy, wz, *_CONTACT)
        return (vx + cx) * e0x + (vy + cy) * e0y

    stops.terminal = True
    stops.direction = -1
    sol = check(solve_ivp(bounded(_impact_rhs(k, f)), (0.0, end), np.concatenate([v0, Rw0]), events=stops,
                          rtol=rtol, atol=rtol * scale, method="DOP853", dense_output=True))
    stop = float(sol.t_events[0][0]) if sol.status == 1 else end
    ts = np.linspace(0.0, 0.9 * stop if sol.status == 1 else stop, samples)  # the slip's direction while it lasts
    ys = sol.sol(ts).T
    uh = slip_velocity(ys[:, :3], ys[:, 3:])[:, :2]
    turn = float(np.max(np.abs(uh[:, 0] * e0y - uh[:, 1] * e0x) / np.linalg.norm(uh, axis=1)))
    y = sol.y_events[0][0] if sol.status == 1 else sol.y[:, -1]
    v1, Rw1 = y[:3].copy(), y[3:].copy()
    if sol.status == 1:
        v1[2] = v0[2] + end
    return Impact3D(v1, Rw1, turn, float(stop / end) if sol.status == 1 else float("nan"))


def ricochet_3d(v0: ArrayLike, Rw0: ArrayLike, *, k: float, f: float, nu: float, g: float, n: int,
                rtol: float = 1e-11) -> tuple[np.ndarray, np.ndarray]:
    """n impacts and flights in three dimensions (§III n°9): the horizontal positions of the n + 1 imprints (first
    at the origin) and the velocity after each impact. A flight keeps the horizontal velocity and the rotation (no
    air) and returns the centre to its height after 2ζ/g."""
    v, Rw = (np.array(a, dtype=float) for a in _arrays(v0, Rw0))
    pos = [np.zeros(2)]
    vel = []
    for _ in range(n):
        out = integrate_impact_3d(v, Rw, k=k, f=f, nu=nu, rtol=rtol)
        v, Rw = out.v1, out.Rw1
        vel.append(v.copy())
        pos.append(pos[-1] + v[:2] * 2.0 * v[2] / g)
        v = v * np.array([1.0, 1.0, -1.0])
    return np.array(pos), np.array(vel)
