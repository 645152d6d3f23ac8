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

__all__ = ["SlipDecay", "slip_decay"]


NEWTON_MAXITER = 60  # bound on the Newton iteration; a monotone convex iteration needs ~5-8 steps
NEWTON_RTOL = 1e-14  # stop when the step is below this fraction of x, or the residual below it of H(1)
# (H itself is known to a few ulps of hyp2f1, about 1e-15: a tighter test would chase rounding)
NEWTON_FLOOR = 1e-9  # Pfaff's branch knows H to ~1e-12 only: a step that stops shrinking below this has reached
# the noise of H (it cycles there: 2 of 1e6 scenes of ``make stress`` with mass ratios of 1e6)


_DEGENERATE = 1e-5  # |c − ½| below which Pfaff's form itself fails (c − a − b → 1): 1e-6 off at 1e-12
_NODES = 1e-4 * np.arange(-2.0, 3.0)  # interpolation nodes in c − ½ (at ½ itself scipy is exact)


def _pfaff(c: np.ndarray, z: np.ndarray) -> np.ndarray:
    return np.sqrt(1 - z) * hyp2f1(-0.5, 1.0, c + 1, z / (z - 1))


def _F(c: np.ndarray, z: np.ndarray) -> np.ndarray:
    """₂F₁(−½, c; c + 1; z) for z ≤ 0. scipy's direct evaluation loses accuracy near c = ½ for z < −1 (4e-4 at
    c = 0.5000001, z = −10; inf at c = ½, z = −1e16); there Pfaff's transformation
    ₂F₁(a, b; c; z) = (1 − z)^(−a) ₂F₁(a, c − b; c; z/(z − 1)) is accurate to 1e-14, except within 1e-5 of
    c = ½, where its own c − a − b tends to the integer 1 and scipy cancels (1e-6 off at c − ½ = 1e-12, against
    mpmath in the tests). There F, smooth in c, is interpolated from five nodes c − ½ ∈ {0, ±1e-4, ±2e-4}, where
    scipy is accurate (exact at ½). Elsewhere the direct form is accurate to a few ulps."""
    out = np.empty(np.broadcast_shapes(np.shape(c), np.shape(z)))
    c, z = np.broadcast_arrays(c, z)
    pfaff = (np.abs(c - 0.5) < 0.05) & (z < -1.0)
    near = pfaff & (np.abs(c - 0.5) < _DEGENERATE)
    pfaff &= ~near
    d = ~pfaff & ~near
    out[d] = hyp2f1(-0.5, c[d], c[d] + 1, z[d])
    if pfaff.any():
        out[pfaff] = _pfaff(c[pfaff], z[pfaff])
    if near.any():
        zn, t = z[near], c[near] - 0.5
        acc = np.zeros(zn.shape)
        for j, xj in enumerate(_NODES):  # Lagrange's form on the five nodes
            w = np.ones(zn.shape)
            for m, xm in enumerate(_NODES):
                if m != j:
                    w *= (t - xm) / (xj - xm)
            acc += w * _pfaff(np.full(zn.shape, 0.5 + xj), zn)
        out[near] = acc
    return out


def _H(x: np.ndarray, phi0: np.ndarray, psi0: np.ndarray, beta: np.ndarray, d: np.ndarray) -> np.ndarray:
    """τ(0) − τ(U) = ∫_0^U u^(β−1) √(ψ0² + φ0² u^(2d)) du as a function of x = U^β (module docstring)."""
    c = beta / (2 * d)
    return psi0 * x / beta * _F(c, -((phi0 / psi0) ** 2) * x ** (1 / c))


def _solve_x(F0: np.ndarray, S0: np.ndarray, B: np.ndarray, D: np.ndarray, target: np.ndarray,
             total: np.ndarray, x0: np.ndarray | None = None) -> np.ndarray:
    """x in (0, 1] with H(x) = target, 0 < target < H(1) = total, by Newton's method on G(y) = ln H(e^y) − ln
    target, y = ln x. G is increasing and convex (its slope x H′(x)/H(x), the elasticity of H, grows from 1 near
    x = 0 to 1 + 2d/β where φ dominates), so Newton from y = 0 descends monotonically onto the root without
    overshooting, and where H is a power of x (a slip dominated by one component, mass ratios far from 1) it
    lands in one step; Newton in x itself then crawls (a factor 1 − 1/m per step for H ∝ x^m: 66 steps for a
    mass ratio of 1e6 on the cloth). Stops when the step moves x by less than ``NEWTON_RTOL`` of itself or the
    residual is below it of H(1), or when a step below ``NEWTON_FLOOR`` fails to halve (Newton converges
    quadratically until the noise of H stops it); raises past ``NEWTON_MAXITER`` steps. A start ``x0`` left of
    the root costs one step more: by convexity the first step lands right of it."""
    if x0 is None:
        x, h = np.ones_like(F0), total.copy()
    else:
        x = np.where(np.isfinite(x0) & (x0 > 0), np.minimum(x0, 1.0), 1.0)  # a slip that stopped: start at 1
        h = _H(x, F0, S0, B, D)
        cold = ~(h > 0)  # H underflowed at a tiny start: the logarithm needs H > 0
        x[cold], h[cold] = 1.0, total[cold]
    live = np.ones(x.shape, dtype=bool)
    last = np.full(x.shape, np.inf)  # the previous step's size
    for _ in range(NEWTON_MAXITER):
        i = np.nonzero(live)[0]
        if i.size == 0:
            return x
        slope = np.sqrt(S0[i] ** 2 + F0[i] ** 2 * x[i] ** (2 * D[i] / B[i])) / B[i]  # dH/dx
        elasticity = x[i] * slope / h[i]  # dG/dy
        step = (np.log(h[i]) - np.log(target[i])) / elasticity
        xn = np.minimum(x[i] * np.exp(-step), 1.0)
        x[i] = xn
        h[i] = _H(xn, F0[i], S0[i], B[i], D[i])
        size = np.abs(step)
        done = ((size <= NEWTON_RTOL) | (np.abs(h[i] - target[i]) <= NEWTON_RTOL * total[i])
                | ((size <= NEWTON_FLOOR) & (size >= 0.5 * last[i])))  # stalled at the noise of H
        last[i] = size
        live[i[done]] = False
    if live.any():
        raise ArithmeticError(f"slip decay: Newton did not converge in {NEWTON_MAXITER} steps for "
                              f"{int(live.sum())} scene(s)")
    return x


class SlipDecay:
    """The decay of given initial slips, for several impulses τ: H(1) is computed once, and each solve may start
    from the x of a previous one (the §VI fixed point calls it repeatedly with nearby τ). 1-D arrays."""

    def __init__(self, phi0: np.ndarray, psi0: np.ndarray, alpha: np.ndarray, beta: np.ndarray) -> None:
        phi0, psi0, alpha, beta = np.broadcast_arrays(*(np.asarray(x, dtype=float).ravel()
                                                        for x in (phi0, psi0, alpha, beta)))
        self.swap = alpha < beta
        self.f0, self.s0 = np.where(self.swap, psi0, phi0), np.where(self.swap, phi0, psi0)
        self.a, self.b = np.where(self.swap, beta, alpha), np.where(self.swap, alpha, beta)
        self.only_f = self.s0 == 0
        self.only_s = (self.f0 == 0) & ~self.only_f
        self.iso = (self.a == self.b) & ~self.only_f & ~self.only_s
        self.gen = ~self.only_f & ~self.only_s & ~self.iso
        self.total = np.full(self.f0.shape, np.nan)
        g = self.gen
        self.total[g] = _H(np.ones(int(g.sum())), self.f0[g], self.s0[g], self.b[g], self.a[g] - self.b[g])

    def at(self, tau: np.ndarray, idx: np.ndarray, x0: np.ndarray | None = None
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(|φ1|, |ψ1|, x) for the scenes ``idx`` after the impulses ``tau``; x = U^β where the slip turns
        (nan elsewhere); ``x0`` a start for the Newton solve (nan: none)."""
        f0, s0, a, b, T = self.f0[idx], self.s0[idx], self.a[idx], self.b[idx], np.asarray(tau, dtype=float)
        f1, s1 = np.zeros_like(f0), np.zeros_like(s0)
        x = np.full(f0.shape, np.nan)
        o = self.only_f[idx]
        f1[o] = np.maximum(f0[o] - a[o] * T[o], 0.0)
        o = self.only_s[idx]
        s1[o] = np.maximum(s0[o] - b[o] * T[o], 0.0)
        o = self.iso[idx]
        v0 = np.hypot(f0[o], s0[o])
        shrink = np.maximum(v0 - a[o] * T[o], 0.0) / v0
        f1[o], s1[o] = f0[o] * shrink, s0[o] * shrink
        g = self.gen[idx]
        if g.any():
            F0, S0, B, D, Tg, total = f0[g], s0[g], b[g], a[g] - b[g], T[g], self.total[idx][g]
            xg = np.zeros_like(F0)
            xg[Tg <= 0] = 1.0
            go = (Tg < total) & (Tg > 0)
            if go.any():
                start = None if x0 is None else np.asarray(x0)[g][go]
                if start is not None and not np.all(np.isfinite(start)):
                    start = np.where(np.isfinite(start), start, 1.0)
                xg[go] = _solve_x(F0[go], S0[go], B[go], D[go], total[go] - Tg[go], total[go], start)
            f1[g], s1[g] = F0 * xg ** (a[g] / B), S0 * xg
            x[g] = xg
        sw = self.swap[idx]
        return np.where(sw, s1, f1), np.where(sw, f1, s1), x


def slip_decay(phi0: np.ndarray, psi0: np.ndarray, alpha: np.ndarray, beta: np.ndarray,
               tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Slip components (|φ1|, |ψ1|) after the impulse τ ≥ 0, from |φ0|, |ψ0| ≥ 0 (module docstring)."""
    arrays = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (phi0, psi0, alpha, beta, tau)))
    shape = arrays[0].shape
    f1, s1, _ = SlipDecay(*arrays[:4]).at(arrays[4].ravel(), np.arange(arrays[0].size))
    return f1.reshape(shape), s1.reshape(shape)
