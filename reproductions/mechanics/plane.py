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

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .paths import PathCode, Regime, codes

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


def plane_regime(v0: np.ndarray, sliding: np.ndarray) -> np.ndarray:
    """The ``Regime`` of a plane impact from the initial slip and the slide condition."""
    return np.where(v0 == 0, Regime.NO_SLIP, np.where(sliding, Regime.SLIDE, Regime.GRIP)).astype(np.int8)


def _arrays(*args: ArrayLike) -> list[np.ndarray]:
    return [np.asarray(a, dtype=float) for a in args]


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
    v0 = chi0 - p0 * R
    budget = f * (1 + k) * (1 + nu) * np.abs(zeta0)  # the change of v_x that sliding friction can make
    sliding = np.abs(v0) >= budget
    if method == "resal":  # eqs (6): χ1 = χ0 + f(1 + ν)ζ0, p1R = p0R − fk(1 + ν)ζ0, for v_x0 > 0
        s = np.sign(v0)
        chi1 = chi0 + s * f * (1 + nu) * zeta0
        pR1 = p0 * R - s * f * k * (1 + nu) * zeta0
        label, code = "Résal's eqs (6), §III n°8 (sliding assumed)", PathCode.RESAL
    else:
        dv = -np.sign(v0) * np.minimum(np.abs(v0), budget)
        chi1 = chi0 + dv / (1 + k)
        pR1 = p0 * R - k * dv / (1 + k)
        label, code = "closed form, both regimes (slide / slip stops then rolls)", PathCode.EXACT
    shape = np.shape(chi1)
    return PlaneImpact(chi1=chi1, zeta1=-nu * zeta0, p1=pR1 / R, method=method, path=codes(shape, code),
                       regime=plane_regime(np.broadcast_to(v0, shape), sliding), label=label)


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
    chi, zeta, p = a0 * np.cos(alpha0), -a0 * np.sin(alpha0), p0
    cols: dict[str, list[np.ndarray]] = {"chi": [], "zeta": [], "p": [], "regime": [], "P": [], "T": []}
    label = ""
    for _ in range(n):
        out = (impact or plane_impact)(chi, zeta, p, R=R, k=k, f=f, nu=nu, method=method)
        label = out.label
        chi, zeta, p = out.chi1, out.zeta1, out.p1
        cols["chi"].append(chi)
        cols["zeta"].append(zeta)
        cols["p"].append(p)
        cols["regime"].append(out.regime)
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
