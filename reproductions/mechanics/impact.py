"""§I n°3–5 of Résal (1883): the energy-loss law and the direct impact of two bodies.

Notation of the paper: M strikes M′ along the line of centres; V0, V1 (V0′, V1′) are the velocities of
M (M′) before and after the impact; ε, ε′ are Résal's coefficients of the vis viva of the velocities lost
(ε = 0: perfectly elastic, ε = 1: Carnot's inelastic impact). SI units; every function broadcasts over
its arguments, so a leading batch axis evaluates many scenes at once.

Derivation of eqs (7)–(9) from the premises (momentum, eq. (a), and the energy law (6) with J = 0):
write Δ = V0 − V1. Momentum gives V1′ − V0′ = (M/M′) Δ. Substituting in (6) and dividing by MΔ gives
(b): (V0 + V1) − (V0′ + V1′) = εΔ + ε′ (M/M′) Δ, i.e. 2(V0 − V0′) = Δ [1 + ε + (M/M′)(1 + ε′)], whence
Δ = 2M′(V0 − V0′) / D with D = M′(1 + ε) + M(1 + ε′): eq. (7). The code below implements that
derivation, not the printed formula; tests check it against momentum, the law (6) itself, and a direct
integration of a two-phase contact (``reference.integrate_direct_impact``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .paths import PathCode, Regime, codes

__all__ = [
    "DirectImpact",
    "WallImpact",
    "denominator",
    "denominator_from_striker_ratio",
    "denominator_from_struck_ratio",
    "direct_impact",
    "eps_from_height_ratio",
    "eps_from_newton",
    "eps_from_nu",
    "eps_from_velocity_ratio",
    "infinite_mass_impact",
    "newton_restitution",
    "nu_from_eps",
    "velocity_ratio_from_eps",
    "vis_viva_loss",
    "wall_impact",
]


@dataclass(frozen=True)
class DirectImpact:
    """Outcome of a direct impact (§I n°5, eq. 7). Arrays broadcast from the inputs; ``method``, ``path``,
    ``regime`` and ``label`` follow the convention of ``paths``."""

    V1: np.ndarray
    V1p: np.ndarray
    newton_e: np.ndarray
    vis_viva_lost: np.ndarray
    method: str
    path: np.ndarray
    regime: np.ndarray
    label: str


@dataclass(frozen=True)
class WallImpact:
    """Outcome of an impact on an immovable mass (§I n°5, eq. 9)."""

    V1: np.ndarray
    ratio: np.ndarray  # −V1/V0
    method: str
    path: np.ndarray
    regime: np.ndarray
    label: str


def vis_viva_loss(
    M: ArrayLike, U: ArrayLike, eps: ArrayLike, Mp: ArrayLike, Up: ArrayLike, epsp: ArrayLike,
    J_omega: ArrayLike = 0.0,
) -> np.ndarray:
    """Right side of eq. (6), §I n°3: ε M U² + ε′ M′ U′² − 2Jω, the vis viva Σmv² lost (2 × kinetic energy).

    U, U′ are the velocities lost by the translating bodies M, M′; Jω the work term of the tangential
    impulse (zero in a direct impact).
    """
    M, U, eps, Mp, Up, epsp, J_omega = (np.asarray(a, dtype=float) for a in (M, U, eps, Mp, Up, epsp, J_omega))
    return eps * M * U**2 + epsp * Mp * Up**2 - 2.0 * J_omega


def denominator(M: ArrayLike, Mp: ArrayLike, eps: ArrayLike, epsp: ArrayLike) -> np.ndarray:
    """D = M′(1 + ε) + M(1 + ε′), the denominator of eqs (7)–(8), §I n°5."""
    M, Mp, eps, epsp = (np.asarray(a, dtype=float) for a in (M, Mp, eps, epsp))
    return Mp * (1.0 + eps) + M * (1.0 + epsp)


def direct_impact(
    M: ArrayLike, Mp: ArrayLike, V0: ArrayLike, V0p: ArrayLike = 0.0, *, eps: ArrayLike, epsp: ArrayLike,
) -> DirectImpact:
    """Direct impact of M on M′, eq. (7) §I n°5 (eq. (8) when V0′ = 0), derived as in the module docstring."""
    M, Mp, V0, V0p, eps, epsp = (np.asarray(a, dtype=float) for a in (M, Mp, V0, V0p, eps, epsp))
    D = denominator(M, Mp, eps, epsp)
    delta = 2.0 * Mp * (V0 - V0p) / D
    V1 = V0 - delta
    V1p = V0p + (M / Mp) * delta
    lost = M * (V0**2 - V1**2) + Mp * (V0p**2 - V1p**2)
    return DirectImpact(V1=V1, V1p=V1p, newton_e=newton_restitution(M, Mp, eps, epsp), vis_viva_lost=lost,
                        method="exact", path=codes(V1.shape, PathCode.EXACT),
                        regime=codes(V1.shape, Regime.FRICTIONLESS), label="closed form, §I eq. (7)")


def wall_impact(V0: ArrayLike, *, eps: ArrayLike) -> WallImpact:
    """Impact on an immovable mass, eq. (9) §I n°5, as a result of the shared convention."""
    V0, eps = np.broadcast_arrays(np.asarray(V0, dtype=float), np.asarray(eps, dtype=float))
    r = velocity_ratio_from_eps(eps)
    return WallImpact(V1=-r * V0, ratio=r, method="exact", path=codes(V0.shape, PathCode.EXACT),
                      regime=codes(V0.shape, Regime.FRICTIONLESS), label="closed form, §I eq. (9)")


def infinite_mass_impact(V0: ArrayLike, *, eps: ArrayLike) -> np.ndarray:
    """Velocity after striking an immovable mass, eq. (9) §I n°5: V1 = −(1 − ε)/(1 + ε) V0 (limit M′ → ∞ of (8))."""
    return -velocity_ratio_from_eps(eps) * np.asarray(V0, dtype=float)


def velocity_ratio_from_eps(eps: ArrayLike) -> np.ndarray:
    """The ratio −V1/V0 = (1 − ε)/(1 + ε) of an impact on an immovable mass, eq. (9) §I n°5: the yield ν of
    the normal velocity (§III, §IV) and Newton's e of a ball on a wall are this same number."""
    eps = np.asarray(eps, dtype=float)
    return (1.0 - eps) / (1.0 + eps)


nu_from_eps = velocity_ratio_from_eps  # ν = (1 − ε)/(1 + ε): the one ε ↔ ν ↔ e map, eq. (9)


def eps_from_velocity_ratio(ratio: ArrayLike) -> np.ndarray:
    """Inverse of eq. (9), §I n°5: ε = (1 − r)/(1 + r) for a measured r = −V1/V0 in [0, 1]."""
    r = np.asarray(ratio, dtype=float)
    return (1.0 - r) / (1.0 + r)


eps_from_nu = eps_from_velocity_ratio  # ε = (1 − ν)/(1 + ν), the inverse map


def eps_from_height_ratio(height_ratio: ArrayLike) -> np.ndarray:
    """ε from a drop test (§I n°5, marble): free fall gives V = √(2gh), so r = √(h1/h0), then eq. (9)."""
    return eps_from_velocity_ratio(np.sqrt(np.asarray(height_ratio, dtype=float)))


def newton_restitution(M: ArrayLike, Mp: ArrayLike, eps: ArrayLike, epsp: ArrayLike) -> np.ndarray:
    """Newton's e = (V1′ − V1)/(V0 − V0′) implied by eq. (7): e = [M′(1 − ε) + M(1 − ε′)] / D.

    Not in the paper; follows from (7): V1′ − V1 = −(V0 − V0′) + Δ(1 + M/M′). For ε = ε′, or for M′ → ∞,
    e = (1 − ε)/(1 + ε) whatever the masses.
    """
    M, Mp, eps, epsp = (np.asarray(a, dtype=float) for a in (M, Mp, eps, epsp))
    return (Mp * (1.0 - eps) + M * (1.0 - epsp)) / denominator(M, Mp, eps, epsp)


def eps_from_newton(e: ArrayLike) -> np.ndarray:
    """ε = (1 − e)/(1 + e): the common coefficient (ε = ε′) equivalent to Newton's e; same as eq. (9)'s inverse."""
    return eps_from_velocity_ratio(e)


def denominator_from_struck_ratio(M: ArrayLike, ratio_p: ArrayLike) -> np.ndarray:
    """D from a measured V1′/V0 (struck body at rest), second of eqs (8): D = 2M / (V1′/V0)."""
    return 2.0 * np.asarray(M, dtype=float) / np.asarray(ratio_p, dtype=float)


def denominator_from_striker_ratio(Mp: ArrayLike, ratio: ArrayLike) -> np.ndarray:
    """D from a measured V1/V0 (struck body at rest), first of eqs (8): D = 2M′ / (1 − V1/V0)."""
    return 2.0 * np.asarray(Mp, dtype=float) / (1.0 - np.asarray(ratio, dtype=float))
