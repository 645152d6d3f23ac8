"""Least-squares estimates of the paper's coefficients, with uncertainties and an identifiability report.

``least_squares_fit`` is generic: a residual function, bounds, optional measurement standard deviations.
It always inspects the Jacobian at the solution (singular values, numerical rank, null directions),
because scipy's ``curve_fit``/``least_squares`` return a point without a word when the data determine
only a combination of the parameters. When they do, it reports the identified combinations with their
uncertainties and the family of solutions along the null direction, clipped to the bounds.

Uncertainties: with ``sigma`` given, the covariance is (JᵀWJ)⁻¹ (absolute sigma) and intervals use the
normal quantile; without it, the noise is estimated from the residuals, s² = RSS/(m − rank), and
intervals use Student's t with m − rank degrees of freedom. With no degree of freedom left and no
sigma, no uncertainty is claimed.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy import optimize, stats

from .mechanics import impact

__all__ = [
    "Combination",
    "Estimate",
    "FitResult",
    "Identifiability",
    "fit_direct_impact",
    "fit_rebound",
    "least_squares_fit",
]

RANK_RTOL = 1e-7  # singular values below this fraction of the largest count as zero (finite-difference J)


@dataclass(frozen=True)
class Identifiability:
    """What the data determine: the SVD of the (weighted) Jacobian at the solution."""

    singular_values: tuple[float, ...]
    rank: int
    null_directions: tuple[tuple[float, ...], ...]
    condition_number: float | None


@dataclass(frozen=True)
class Estimate:
    """One parameter: value and uncertainty when identifiable, else the range of the solution family."""

    name: str
    value: float | None
    stderr: float | None
    ci95: tuple[float | None, float | None]
    identifiable: bool
    family_range: tuple[float, float] | None


@dataclass(frozen=True)
class Combination:
    """A combination Σ cᵢ θᵢ that the data determine although the θᵢ themselves are not."""

    coefficients: tuple[float, ...]
    value: float
    stderr: float | None
    ci95: tuple[float | None, float | None]


@dataclass(frozen=True)
class FitResult:
    names: tuple[str, ...]
    point: tuple[float, ...]
    estimates: tuple[Estimate, ...]
    combinations: tuple[Combination, ...]
    identifiability: Identifiability
    family: tuple[tuple[float, ...], tuple[float, ...]] | None  # end points of the solution segment
    n_data: int
    dof: int
    residual_rms: float
    noise: str  # "given sigma" | "estimated from residuals" | "none"

    def estimate(self, name: str) -> Estimate:
        return self.estimates[self.names.index(name)]


def _jacobian(fun: Callable[[np.ndarray], np.ndarray], x: np.ndarray) -> np.ndarray:
    """Central differences; the residual functions here are smooth and defined outside the bounds too."""
    f0 = fun(x)
    J = np.empty((f0.size, x.size))
    for j in range(x.size):
        h = 1e-6 * max(1.0, abs(x[j]))
        xp, xm = x.copy(), x.copy()
        xp[j] += h
        xm[j] -= h
        J[:, j] = (fun(xp) - fun(xm)) / (2.0 * h)
    return J


def _interval(value: float, se: float | None, q: float | None) -> tuple[float | None, float | None]:
    if se is None or q is None:
        return (None, None)
    return (value - q * se, value + q * se)


def _segment(x: np.ndarray, n: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """End points of {x + t n} inside the box [lo, hi]."""
    t_lo, t_hi = -np.inf, np.inf
    for xi, ni, a, b in zip(x, n, lo, hi, strict=True):
        if abs(ni) < 1e-12:
            continue
        t1, t2 = (a - xi) / ni, (b - xi) / ni
        t_lo, t_hi = max(t_lo, min(t1, t2)), min(t_hi, max(t1, t2))
    return x + t_lo * n, x + t_hi * n


def least_squares_fit(
    residuals: Callable[[np.ndarray], np.ndarray],
    x0: Sequence[float],
    names: Sequence[str],
    bounds: tuple[Sequence[float], Sequence[float]],
    sigma: np.ndarray | float | None = None,
    jac: Callable[[np.ndarray], np.ndarray] | None = None,
) -> FitResult:
    """Minimise Σ (rᵢ/σᵢ)² within bounds, then report uncertainties and identifiability (see module doc).

    ``jac`` (the Jacobian of the unweighted residuals) is optional; without it, central differences.
    """
    lo, hi = (np.asarray(b, dtype=float) for b in bounds)
    w = None if sigma is None else 1.0 / np.asarray(sigma, dtype=float)

    def weighted(x: np.ndarray) -> np.ndarray:
        r = np.asarray(residuals(x), dtype=float)
        return r if w is None else r * w

    def weighted_jac(x: np.ndarray) -> np.ndarray:
        assert jac is not None
        J = np.asarray(jac(x), dtype=float)
        return J if w is None else J * np.broadcast_to(w, (J.shape[0],))[:, None]

    sol = optimize.least_squares(weighted, np.asarray(x0, dtype=float), bounds=(lo, hi), method="trf",
                                 jac=weighted_jac if jac is not None else "2-point",
                                 xtol=1e-14, ftol=1e-14, gtol=1e-14)
    x = sol.x
    r = weighted(x)
    J = weighted_jac(x) if jac is not None else _jacobian(weighted, x)
    _, s, Vt = np.linalg.svd(J, full_matrices=True)
    s_full = np.zeros(x.size)
    s_full[: s.size] = s
    rank = int(np.sum(s_full > RANK_RTOL * s_full[0])) if s_full[0] > 0 else 0
    m = r.size
    dof = m - rank
    rss = float(r @ r)
    if w is not None:
        s2, q, noise = 1.0, float(stats.norm.ppf(0.975)), "given sigma"
    elif dof > 0:
        s2, q, noise = rss / dof, float(stats.t.ppf(0.975, dof)), "estimated from residuals"
    else:
        s2, q, noise = None, None, "none"
    V = Vt.T
    Vr, Vn = V[:, :rank], V[:, rank:]
    cov = None if s2 is None or rank == 0 else (Vr / s_full[:rank] ** 2) @ Vr.T * s2
    ident = Identifiability(
        singular_values=tuple(float(v) for v in s_full),
        rank=rank,
        null_directions=tuple(tuple(float(v) for v in _canonical(Vn[:, k])) for k in range(Vn.shape[1])),
        condition_number=float(s_full[0] / s_full[rank - 1]) if rank else None,
    )
    family = None
    if Vn.shape[1] == 1:
        a, b = _segment(x, Vn[:, 0], lo, hi)
        family = (tuple(float(v) for v in a), tuple(float(v) for v in b))
    estimates = []
    for i, name in enumerate(names):
        identifiable = bool(np.all(np.abs(Vn[i, :]) < 1e-6)) if Vn.size else True
        if identifiable:
            se = None if cov is None else float(np.sqrt(max(cov[i, i], 0.0)))
            estimates.append(Estimate(name, float(x[i]), se, _interval(float(x[i]), se, q), True, None))
        else:
            rng = None if family is None else tuple(sorted((family[0][i], family[1][i])))
            estimates.append(Estimate(name, None, None, (None, None), False, rng))
    combos = []
    if 0 < rank < x.size:
        for k in range(rank):
            c = _canonical(Vr[:, k])
            value = float(c @ x)
            se = None if cov is None else float(np.sqrt(max(c @ cov @ c, 0.0)))
            combos.append(Combination(tuple(float(v) for v in c), value, se, _interval(value, se, q)))
    return FitResult(
        names=tuple(names), point=tuple(float(v) for v in x), estimates=tuple(estimates),
        combinations=tuple(combos), identifiability=ident, family=family, n_data=m, dof=dof,
        residual_rms=float(np.sqrt(np.mean(np.asarray(residuals(x), dtype=float) ** 2))), noise=noise,
    )


def _canonical(v: np.ndarray) -> np.ndarray:
    """Scale a direction so that its smallest non-negligible coefficient is +1 (reads as ε + 3ε′)."""
    v = np.where(np.abs(v) < 1e-9 * np.max(np.abs(v)), 0.0, v)
    nz = v[v != 0.0]
    return v / nz[np.argmin(np.abs(nz))]


def fit_direct_impact(
    M: np.ndarray, Mp: np.ndarray, V0: np.ndarray, V1: np.ndarray, V1p: np.ndarray,
    sigma: float | None = None,
) -> FitResult:
    """Fit (ε, ε′) of eqs (8), §I n°5, to measured velocities after the impact (struck body at rest).

    Residuals are the predicted minus the measured V1 and V1′ of every trial. With a single mass ratio
    the two equations depend on (ε, ε′) only through D = M′(1 + ε) + M(1 + ε′): rank 1, whatever the
    number of trials.
    """
    M, Mp, V0, V1, V1p = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (M, Mp, V0, V1, V1p)))

    def res(theta: np.ndarray) -> np.ndarray:
        out = impact.direct_impact(M, Mp, V0, 0.0, theta[0], theta[1])
        return np.concatenate([out.V1 - V1, out.V1p - V1p])

    def jac(theta: np.ndarray) -> np.ndarray:
        # V1 = V0 − 2M′V0/D, V1′ = 2M V0/D, with ∂D/∂ε = M′ and ∂D/∂ε′ = M
        D = impact.denominator(M, Mp, theta[0], theta[1])
        g1, g2 = 2 * Mp * V0 / D**2, -2 * M * V0 / D**2
        return np.block([[np.c_[g1 * Mp, g1 * M]], [np.c_[g2 * Mp, g2 * M]]])

    return least_squares_fit(res, [0.5, 0.5], ["eps", "epsp"], ([0.0, 0.0], [1.0, 1.0]), sigma, jac)


def fit_rebound(V0: np.ndarray, V1: np.ndarray, sigma: float | None = None) -> FitResult:
    """Fit ε of eq. (9), §I n°5, to rebounds on an immovable mass: residuals −(1−ε)/(1+ε)·V0 − V1."""
    V0, V1 = (np.asarray(a, dtype=float) for a in (V0, V1))

    def res(theta: np.ndarray) -> np.ndarray:
        return impact.infinite_mass_impact(V0, theta[0]) - V1

    def jac(theta: np.ndarray) -> np.ndarray:
        return (2.0 * V0 / (1.0 + theta[0]) ** 2)[:, None]  # d/dε of −(1 − ε)/(1 + ε)·V0

    return least_squares_fit(res, [0.5], ["eps"], ([0.0], [1.0]), sigma, jac)
