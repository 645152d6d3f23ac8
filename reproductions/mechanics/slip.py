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


NEWTON_MAXITER = 60  # bound on the Newton iteration; a monotone convex iteration needs ~5-8 steps
NEWTON_RTOL = 1e-14  # stop when the step is below this fraction of x, or the residual below it of H(1)
# (H itself is known to a few ulps of hyp2f1, about 1e-15: a tighter test would chase rounding)


def _F(c: np.ndarray, z: np.ndarray) -> np.ndarray:
    """₂F₁(−½, c; c + 1; z) for z ≤ 0. scipy's direct evaluation loses accuracy near c = ½ for z < −1 (4e-4 at
    c = 0.5000001, z = −10; inf at c = ½, z = −1e16); there Pfaff's transformation
    ₂F₁(a, b; c; z) = (1 − z)^(−a) ₂F₁(a, c − b; c; z/(z − 1)) is accurate to 1e-11 (checked against mpmath in
    the tests). Elsewhere the direct form is accurate to a few ulps."""
    pfaff = (np.abs(c - 0.5) < 0.05) & (z < -1.0)
    out = np.empty(np.broadcast_shapes(np.shape(c), np.shape(z)))
    c, z = np.broadcast_arrays(c, z)
    d = ~pfaff
    out[d] = hyp2f1(-0.5, c[d], c[d] + 1, z[d])
    if pfaff.any():
        zp = z[pfaff]
        out[pfaff] = np.sqrt(1 - zp) * hyp2f1(-0.5, 1.0, c[pfaff] + 1, zp / (zp - 1))
    return out


def _H(x: np.ndarray, phi0: np.ndarray, psi0: np.ndarray, beta: np.ndarray, d: np.ndarray) -> np.ndarray:
    """τ(0) − τ(U) = ∫_0^U u^(β−1) √(ψ0² + φ0² u^(2d)) du as a function of x = U^β (module docstring)."""
    c = beta / (2 * d)
    return psi0 * x / beta * _F(c, -((phi0 / psi0) ** 2) * x ** (1 / c))


def _solve_x(F0: np.ndarray, S0: np.ndarray, B: np.ndarray, D: np.ndarray, target: np.ndarray,
             total: np.ndarray) -> np.ndarray:
    """x in (0, 1] with H(x) = target < H(1) = total. In x = U^β, H is increasing and convex
    (dH/dx = √(ψ0² + φ0² x^(2d/β))/β grows with x), so Newton from x = 1 descends monotonically onto the root
    without overshooting: no bracket is needed. Stops when the step is below ``NEWTON_RTOL`` of x or the
    residual below it of H(1); raises if that takes more than ``NEWTON_MAXITER`` steps."""
    x = np.ones_like(F0)
    h = total.copy()
    live = np.ones(x.shape, dtype=bool)
    for _ in range(NEWTON_MAXITER):
        i = np.nonzero(live)[0]
        if i.size == 0:
            return x
        slope = np.sqrt(S0[i] ** 2 + F0[i] ** 2 * x[i] ** (2 * D[i] / B[i])) / B[i]
        step = (h[i] - target[i]) / slope
        xn = np.maximum(x[i] - step, 0.0)
        x[i] = xn
        h[i] = _H(xn, F0[i], S0[i], B[i], D[i])
        done = (np.abs(step) <= NEWTON_RTOL * xn) | (np.abs(h[i] - target[i]) <= NEWTON_RTOL * total[i])
        live[i[done]] = False
    if live.any():
        raise ArithmeticError(f"slip decay: Newton did not converge in {NEWTON_MAXITER} steps for "
                              f"{int(live.sum())} scene(s)")
    return x


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
        stops = T >= total
        x = np.zeros_like(F0)
        go = ~stops & (T > 0)
        x[T <= 0] = 1.0
        if go.any():
            x[go] = _solve_x(F0[go], S0[go], B[go], D[go], total[go] - T[go], total[go])
        f1[gen], s1[gen] = F0 * x ** (a[gen] / B), S0 * x
    return np.where(swap, s1, f1), np.where(swap, f1, s1)
