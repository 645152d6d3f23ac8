"""The decay of a two-component slip under Coulomb friction, shared by §IV (cushion) and §V–§VI (two balls).

In an impulse variable τ, each slip component falls at its own rate, dφ = −α φ/v dτ, dψ = −β ψ/v dτ, with
v = √(φ² + ψ²): the cushion has α = 1 + k, β = k (§IV n°11, eqs 2); two balls on the cloth α ≠ β (§VI
n°13, eqs 1′–6); two free balls α = β, the slip keeps its direction (§V n°12). Then φ = φ0 U^α,
ψ = ψ0 U^β for U from 1 down, and

    τ(U) = ∫_U^1 u^(β−1) √(ψ0² + φ0² u^(2d)) du,  d = α − β ≥ 0,
         = H(1) − H(U),  H(U) = ψ0 U^β/β · ₂F₁(−1/2, β/(2d); β/(2d) + 1; −(φ0/ψ0)² U^(2d)).

The slip stops (both components together) when τ reaches H(1); after that the contact holds with no
friction. For α < β the roles of φ and ψ swap; α = β, ψ0 = 0 or φ0 = 0 have elementary forms.
"""

from __future__ import annotations

import numpy as np
from scipy.special import hyp2f1

__all__ = ["slip_decay"]


def _H(U: np.ndarray, phi0: np.ndarray, psi0: np.ndarray, beta: np.ndarray, d: np.ndarray) -> np.ndarray:
    c = beta / (2 * d)
    return psi0 * U**beta / beta * hyp2f1(-0.5, c, c + 1, -((phi0 / psi0) ** 2) * U ** (2 * d))


def slip_decay(phi0: np.ndarray, psi0: np.ndarray, alpha: np.ndarray, beta: np.ndarray,
               tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Slip components (|φ1|, |ψ1|) after the impulse τ ≥ 0, from |φ0|, |ψ0| ≥ 0 (module docstring)."""
    phi0, psi0, alpha, beta, tau = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (phi0, psi0, alpha, beta, tau)))
    swap = alpha < beta  # make α ≥ β
    f0, s0 = np.where(swap, psi0, phi0), np.where(swap, phi0, psi0)
    a, b = np.where(swap, beta, alpha), np.where(swap, alpha, beta)
    f1, s1 = np.zeros_like(f0), np.zeros_like(s0)
    only_f = s0 == 0
    f1[only_f] = np.maximum(f0[only_f] - a[only_f] * tau[only_f], 0.0)
    only_s = (f0 == 0) & ~only_f
    s1[only_s] = np.maximum(s0[only_s] - b[only_s] * tau[only_s], 0.0)
    iso = (a == b) & ~only_f & ~only_s  # the slip keeps its direction and falls at the rate α
    v0 = np.hypot(f0[iso], s0[iso])
    shrink = np.maximum(v0 - a[iso] * tau[iso], 0.0) / v0
    f1[iso], s1[iso] = f0[iso] * shrink, s0[iso] * shrink
    gen = ~only_f & ~only_s & ~iso
    if np.any(gen):
        F0, S0, B, D, T = f0[gen], s0[gen], b[gen], a[gen] - b[gen], tau[gen]
        total = _H(np.ones_like(F0), F0, S0, B, D)
        target = total - T
        lo, hi = np.zeros_like(F0), np.ones_like(F0)
        for _ in range(60):  # H increases with U: bisection to double precision
            mid = 0.5 * (lo + hi)
            below = _H(mid, F0, S0, B, D) < target
            lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
        U = np.where(T >= total, 0.0, 0.5 * (lo + hi))
        f1[gen], s1[gen] = F0 * U ** a[gen], S0 * U**B
    return np.where(swap, s1, f1), np.where(swap, f1, s1)
