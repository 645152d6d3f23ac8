"""Least-squares estimates of the paper's coefficients, with uncertainties and an identifiability report.

``least_squares_fit`` is generic: a residual function, bounds, optional measurement standard deviations.
It always inspects the Jacobian at the solution (singular values, numerical rank, null directions),
because scipy's ``curve_fit``/``least_squares`` return a point without a word when the data determine
only a combination of the parameters. When they do, the report says only what the data determine, in a form
that rounding cannot move (where an optimiser stops along a family of equal solutions is set by rounding):

- a canonical point: the point of the family nearest the centre of the bounds (``_canonical_point``);
- null directions oriented canonically (``orient``: largest component +1);
- a ``Family`` that is either exact (given by the caller from the model's structure, through ``analyse``) or
  the linearisation at the canonical point, checked by the χ² at its ends and withheld when it fails;
- the identified combinations with their uncertainties.

Uncertainties: with ``sigma`` given, the covariance is (JᵀWJ)⁻¹ (absolute sigma) and intervals use the
normal quantile; without it, the noise is estimated from the residuals, s² = RSS/(m − rank), and
intervals use Student's t with m − rank degrees of freedom. With no degree of freedom left and no
sigma, no uncertainty is claimed.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from enum import Enum

import numpy as np

from ...lazy import lazy
from ...mechanics import impact, plane

optimize = lazy("scipy.optimize", globals())
special = lazy("scipy.special", globals())

__all__ = [
    "Combination",
    "Estimate",
    "Family",
    "FamilyKind",
    "FitResult",
    "Identifiability",
    "analyse",
    "bounce_instants",
    "fit_bounces",
    "fit_direct_impact",
    "fit_friction",
    "fit_imprints",
    "fit_physical",
    "fit_physical_positions",
    "fit_positions",
    "fit_rebound",
    "fit_times",
    "least_squares_fit",
    "numeric_jacobian",
    "orient",
    "synthetic_bounces",
    "synthetic_imprints",
]

RANK_RTOL = 1e-7  # singular values below this fraction of the largest count as zero (finite-difference J)
FAMILY_CHI2 = 1.0  # a linearised family holds if its ends fit within Δχ² ≤ 1 (one σ on the unknown parameter)
CANONICAL_MAXITER = 50  # bound on the iteration that moves a rank-deficient solution to its canonical point
CANONICAL_XTOL = 1e-12  # relative to the box width: convergence of that iteration


class FamilyKind(str, Enum):
    """How a family of equally good solutions was obtained."""

    EXACT = "exact"  # in closed form, from the model's own structure (every point fits exactly as well)
    LINEARISED = "linearised"  # the tangent segment at the canonical point, checked by the fit at its ends


@dataclass(frozen=True)
class Family:
    """The solutions of a rank-deficient fit along its one null direction, within the bounds.

    ``ranges[i]`` is the interval parameter i spans on the family (None where the data determine it);
    ``end_chi2`` the increase of χ² (in units of the noise variance) at each end over the canonical point:
    zero to rounding for an exact family, and checked against ``FAMILY_CHI2`` for a linearisation.
    """

    kind: FamilyKind
    along: str  # the parameter that runs along the family
    ends: tuple[tuple[float, ...], tuple[float, ...]]
    ranges: tuple[tuple[float, float] | None, ...]
    end_chi2: tuple[float, float]
    holds: bool
    label: str = ""


@dataclass(frozen=True)
class Identifiability:
    """What the data determine: the SVD of the (weighted) Jacobian at the (canonical) solution."""

    singular_values: tuple[float, ...]
    rank: int
    null_directions: tuple[tuple[float, ...], ...]  # oriented by ``orient``: largest component +1
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
    at_bound: str | None = None  # "lower" or "upper": the fit ended on that bound of the parameter
    clipped: bool = False  # the 95 % interval was cut at a bound (it is then no longer symmetric)


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
    point: tuple[float, ...]  # the optimum; when the rank is short, the canonical point of the family
    estimates: tuple[Estimate, ...]
    combinations: tuple[Combination, ...]
    identifiability: Identifiability
    family: Family | None
    n_data: int
    dof: int
    residual_rms: float
    noise: str  # "given sigma" | "estimated from residuals" | "none"
    canonical: str = ""  # how the point was made canonical when the rank is short (for people)

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


def numeric_jacobian(fun: Callable[[np.ndarray], np.ndarray], x: Sequence[float]) -> np.ndarray:
    """Central differences of ``fun`` at ``x``: for the leave-one-out check of a fit whose model has no analytic
    Jacobian here (``fit.checks.leave_one_out``)."""
    return _jacobian(fun, np.asarray(x, dtype=float))


def bounce_instants(nu: float, T1: float, t0: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The instants t_i = t0 + T1 (1 − ν^i)/(1 − ν), i = 0 … n − 1 (§III n°9), and their Jacobian in (ν, T1, t0)."""
    S = _bounce_sums(nu, n)
    return t0 + T1 * S, np.c_[T1 * _bounce_dsums(nu, n), S, np.ones(n)]


def _interval(value: float, se: float | None, q: float | None) -> tuple[float | None, float | None]:
    if se is None or q is None:
        return (None, None)
    return (value - q * se, value + q * se)


BOUND_RTOL = 1e-6  # an estimate this close to a bound (relative to the box width, or to 1) ended on it


def _at_bound(v: float, lo: float, hi: float) -> str | None:
    """'lower' or 'upper' when the estimate sits on that bound (the optimiser stops about 1e-10 inside)."""
    width = hi - lo if math.isfinite(hi - lo) else 1.0
    if math.isfinite(lo) and v - lo <= BOUND_RTOL * width:
        return "lower"
    if math.isfinite(hi) and hi - v <= BOUND_RTOL * width:
        return "upper"
    return None


def _clip(ci: tuple[float | None, float | None], lo: float, hi: float) -> tuple[tuple[float | None, float | None],
                                                                              bool]:
    """The interval cut to the admissible range [lo, hi], and whether it was cut."""
    a, b = ci
    if a is None or b is None:
        return ci, False
    ca, cb = max(a, lo), min(b, hi)
    return (ca, cb), (ca, cb) != (a, b)


def _segment(x: np.ndarray, n: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[float, float]:
    """The interval of t for which x + t n stays inside the box [lo, hi]."""
    t_lo, t_hi = -np.inf, np.inf
    scale = np.max(np.abs(n))
    for xi, ni, a, b in zip(x, n, lo, hi, strict=True):
        if abs(ni) <= 1e-12 * scale:
            continue
        t1, t2 = (a - xi) / ni, (b - xi) / ni
        t_lo, t_hi = max(t_lo, min(t1, t2)), min(t_hi, max(t1, t2))
    return float(t_lo), float(t_hi)


def orient(v: np.ndarray) -> np.ndarray:
    """A direction in canonical form: scaled so that its largest-magnitude component is +1 (the first one on a
    tie). Components below 1e-12 of it are set to 0. Unlike 'smallest component = 1', no threshold decides
    which component normalises, so rounding cannot swap it; only the sign can flip, at an exact tie."""
    v = np.asarray(v, dtype=float)
    i = int(np.argmax(np.abs(v)))
    out = v / v[i]
    return np.where(np.abs(out) < 1e-12, 0.0, out)


def _canonical(v: np.ndarray) -> np.ndarray:
    """A determined combination scaled for reading: its smallest non-negligible coefficient +1 (ε + 3ε′)."""
    v = orient(v)
    nz = v[np.abs(v) >= 1e-6]
    return v / nz[np.argmin(np.abs(nz))]


@dataclass(frozen=True)
class _Problem:
    """A weighted least-squares problem: residuals r(θ)/σ, their Jacobian, the bounds."""

    fun: Callable[[np.ndarray], np.ndarray]
    jac: Callable[[np.ndarray], np.ndarray] | None
    lo: np.ndarray
    hi: np.ndarray

    def J(self, x: np.ndarray) -> np.ndarray:
        return self.jac(x) if self.jac is not None else _jacobian(self.fun, x)

    def solve(self, x0: np.ndarray, free: np.ndarray | None = None) -> np.ndarray:
        """Minimise over the parameters where ``free`` (all by default), the others held at x0."""
        if free is None:
            free = np.ones(x0.size, dtype=bool)
        base = x0.copy()

        def full(z: np.ndarray) -> np.ndarray:
            out = base.copy()
            out[free] = z
            return out

        def fun(z: np.ndarray) -> np.ndarray:
            return self.fun(full(z))

        def jac_free(z: np.ndarray) -> np.ndarray:
            return self.J(full(z))[:, free]

        jac = jac_free if self.jac is not None else "2-point"
        z0 = np.clip(x0[free], self.lo[free], self.hi[free])
        sol = optimize.least_squares(fun, z0, bounds=(self.lo[free], self.hi[free]), method="trf", jac=jac,
                                     xtol=1e-14, ftol=1e-14, gtol=1e-14)
        return full(sol.x)


def _null_space(J: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """The singular values of the m×p Jacobian ``J`` (padded with zeros to p), its right singular vectors as
    columns (all p of them: the null directions are the last) and its numerical rank. Memory and time linear in
    m: for m ≥ p the thin SVD (U is m×p, never m×m, which took 4 GB for 4000 ball-ball shots and killed the fit
    of 10 000); its V is the same p×p matrix as the full SVD's."""
    m, p = J.shape
    _, s, Vt = np.linalg.svd(J, full_matrices=m < p)  # m < p: a short J, V must still be p×p
    s_full = np.zeros(J.shape[1])
    s_full[: s.size] = s
    rank = int(np.sum(s_full > RANK_RTOL * s_full[0])) if s_full[0] > 0 else 0
    return s_full, Vt.T, rank


def _canonical_point(pb: _Problem, x: np.ndarray) -> tuple[np.ndarray, str]:
    """Move a solution along a one-dimensional family to the point nearest the centre of the box.

    In coordinates scaled by the box widths, the canonical point is where the family's tangent is orthogonal to
    the line from the box centre (the nonlinear analogue of the minimum-norm least-squares solution). Each step
    projects the centre on the tangent at the current point, fixes the parameter with the largest tangent
    component there and refits the others (a full-rank problem); it stops when that parameter moves less than
    ``CANONICAL_XTOL`` of its width, or says it did not converge after ``CANONICAL_MAXITER`` steps. Where the
    distance along the family has several minima, this is the one whose basin holds the optimum: a rounding-level
    change cannot move it, a distant start can (it is canonical for the fit, not unique for the model).
    """
    finite = np.isfinite(pb.lo) & np.isfinite(pb.hi)
    width = np.where(finite, pb.hi - pb.lo, 1.0)
    centre = np.where(finite, 0.5 * (pb.lo + pb.hi), 0.0)
    zlo, zhi = (pb.lo - centre) / width, (pb.hi - centre) / width
    for _ in range(CANONICAL_MAXITER):
        _, V, _ = _null_space(pb.J(x))
        ns = V[:, -1] / width  # the tangent in coordinates scaled by the box widths
        ns /= np.linalg.norm(ns)
        z = (x - centre) / width
        t_lo, t_hi = _segment(z, ns, zlo, zhi)
        t = min(max(-float(ns @ z), t_lo), t_hi)
        i = int(np.argmax(np.abs(ns)))
        target = x + t * ns * width
        free = np.ones(x.size, dtype=bool)
        free[i] = False
        x_new = pb.solve(target, free)
        moved = abs(x_new[i] - x[i]) / width[i]
        x = x_new
        if moved <= CANONICAL_XTOL:
            return x, "point of the family nearest the centre of the bounds"
    return x, (f"point of the family nearest the centre of the bounds: NOT converged in {CANONICAL_MAXITER} steps; "
               "the reported point may depend on rounding")


def least_squares_fit(
    residuals: Callable[[np.ndarray], np.ndarray],
    x0: Sequence[float],
    names: Sequence[str],
    bounds: tuple[Sequence[float], Sequence[float]],
    sigma: np.ndarray | float | None = None,
    jac: Callable[[np.ndarray], np.ndarray] | None = None,
) -> FitResult:
    """Minimise Σ (rᵢ/σᵢ)² within bounds, then report uncertainties and identifiability (see module doc).

    ``jac`` (the Jacobian of the unweighted residuals) is optional; without it, central differences. When the
    rank is short by one, the solution is moved to its canonical point (``_canonical_point``) and the family is
    the linearisation there, checked at its ends; use ``analyse`` with an exact family where one is known.
    """
    pb = _weighted(residuals, bounds, sigma, jac)
    x = pb.solve(np.asarray(x0, dtype=float))
    rank = _null_space(pb.J(x))[2]
    how = ""
    if rank == x.size - 1:
        x, how = _canonical_point(pb, x)
    return _analyse(pb, residuals, x, names, sigma, None, how)


def _weighted(residuals: Callable[[np.ndarray], np.ndarray], bounds: tuple[Sequence[float], Sequence[float]],
              sigma: np.ndarray | float | None, jac: Callable[[np.ndarray], np.ndarray] | None) -> _Problem:
    lo, hi = (np.asarray(b, dtype=float) for b in bounds)
    w = None if sigma is None else 1.0 / np.asarray(sigma, dtype=float)

    def weighted(x: np.ndarray) -> np.ndarray:
        r = np.asarray(residuals(x), dtype=float)
        return r if w is None else r * w

    def weighted_jac(x: np.ndarray) -> np.ndarray:
        assert jac is not None
        J = np.asarray(jac(x), dtype=float)
        return J if w is None else J * np.broadcast_to(w, (J.shape[0],))[:, None]

    return _Problem(weighted, weighted_jac if jac is not None else None, lo, hi)


def analyse(
    residuals: Callable[[np.ndarray], np.ndarray],
    x: Sequence[float],
    names: Sequence[str],
    bounds: tuple[Sequence[float], Sequence[float]],
    sigma: np.ndarray | float | None = None,
    jac: Callable[[np.ndarray], np.ndarray] | None = None,
    family: Family | None = None,
    canonical: str = "",
) -> FitResult:
    """The report of ``least_squares_fit`` at a solution known otherwise (e.g. in closed form from a fit of the
    combinations the data determine), with an exact ``family`` where the model gives one."""
    pb = _weighted(residuals, bounds, sigma, jac)
    return _analyse(pb, residuals, np.asarray(x, dtype=float), names, sigma, family, canonical)


def _analyse(pb: _Problem, residuals: Callable[[np.ndarray], np.ndarray], x: np.ndarray, names: Sequence[str],
             sigma: np.ndarray | float | None, family: Family | None, canonical: str) -> FitResult:
    r = pb.fun(x)
    s_full, V, rank = _null_space(pb.J(x))
    m = r.size
    dof = m - rank
    rss = float(r @ r)
    if sigma is not None:
        s2, q, noise = 1.0, float(special.ndtri(0.975)), "given sigma"  # the normal quantile
    elif dof > 0:
        s2, q, noise = rss / dof, float(special.stdtrit(dof, 0.975)), "estimated from residuals"  # Student's t
    else:
        s2, q, noise = None, None, "none"
    Vr, Vn = V[:, :rank], V[:, rank:]
    cov = None if s2 is None or rank == 0 else (Vr / s_full[:rank] ** 2) @ Vr.T * s2
    nulls = tuple(orient(Vn[:, k]) for k in range(Vn.shape[1]))
    ident = Identifiability(
        singular_values=tuple(float(v) for v in s_full),
        rank=rank,
        null_directions=tuple(tuple(float(v) for v in d) for d in nulls),
        condition_number=float(s_full[0] / s_full[rank - 1]) if rank else None,
    )
    if family is None and len(nulls) == 1:
        family = _linearised_family(pb, x, nulls[0], names, rss, s2, float(s_full[0]))
    estimates = []
    for i, name in enumerate(names):
        if family is not None:  # the family knows: a parameter is determined iff it does not vary along it
            identifiable = family.ranges[i] is None
        else:
            identifiable = bool(np.all(np.abs(Vn[i, :]) < 1e-6)) if Vn.size else True
        if identifiable:
            se = None if cov is None else float(np.sqrt(max(cov[i, i], 0.0)))
            ci, clipped = _clip(_interval(float(x[i]), se, q), float(pb.lo[i]), float(pb.hi[i]))
            estimates.append(Estimate(name, float(x[i]), se, ci, True, None,
                                      _at_bound(float(x[i]), float(pb.lo[i]), float(pb.hi[i])), clipped))
        else:
            rng = family.ranges[i] if family is not None and family.holds else None
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
        canonical=canonical,
    )


def _linearised_family(pb: _Problem, x: np.ndarray, n: np.ndarray, names: Sequence[str], rss: float,
                       s2: float | None, s_max: float) -> Family:
    """The segment x + t n within the bounds, with the χ² increase at both ends: it holds if both are ≤
    ``FAMILY_CHI2`` in units of the noise variance, or, where the data are exact (no noise to measure), of the
    rounding of the residuals, taken as (1e-10 · largest singular value · |x|)²."""
    t_lo, t_hi = _segment(x, n, pb.lo, pb.hi)
    ends = (x + t_lo * n, x + t_hi * n)
    unit = max(s2 or 0.0, (1e-10 * s_max * max(float(np.linalg.norm(x)), 1.0)) ** 2, np.finfo(float).tiny)
    d = tuple(float((np.sum(pb.fun(e) ** 2) - rss) / unit) for e in ends)
    moving = np.abs(n) > 0
    ranges = tuple((float(min(ends[0][i], ends[1][i])), float(max(ends[0][i], ends[1][i]))) if moving[i] else None
                   for i in range(x.size))
    along = names[int(np.argmax(np.abs(n)))]
    ends_t = (tuple(float(v) for v in ends[0]), tuple(float(v) for v in ends[1]))
    holds = max(d) <= FAMILY_CHI2
    return Family(FamilyKind.LINEARISED, along, ends_t, ranges, d, holds,
                  "tangent segment at the canonical point" + ("" if holds else
                                                               f": does NOT hold, Δχ² = {max(d):.3g} at an end"))


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
        out = impact.direct_impact(M, Mp, V0, 0.0, eps=theta[0], epsp=theta[1])
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
        return impact.infinite_mass_impact(V0, eps=theta[0]) - V1

    def jac(theta: np.ndarray) -> np.ndarray:
        return (2.0 * V0 / (1.0 + theta[0]) ** 2)[:, None]  # d/dε of −(1 − ε)/(1 + ε)·V0

    return least_squares_fit(res, [0.5], ["eps"], ([0.0], [1.0]), sigma, jac)


# ---- §III ricochets: ν (and f where the data determine it) from imprint positions and impact instants ----------
def _positions_jac(th: np.ndarray, k: float, n: int) -> np.ndarray:
    """∂/∂(ν, A, u) of the imprint positions x_1 … x_n of ``plane.ricochet_ranges_spinless`` (analytic)."""
    nu, A, u = th
    j = np.arange(n)
    S = np.cumsum(nu**j)
    dS = np.cumsum(j * nu ** np.maximum(j - 1, 0))
    slide = 1 - u * (1 + nu) * S > k / (1 + k)
    c = np.where(slide, 1 - u * (1 + nu) * S, k / (1 + k))
    dc_dnu = np.where(slide, -u * (S + (1 + nu) * dS), 0.0)
    dc_du = np.where(slide, -(1 + nu) * S, 0.0)
    w = nu ** (j + 1)
    return np.cumsum(np.c_[A * ((j + 1) * nu**j * c + w * dc_dnu), w * c, A * w * dc_du], axis=0)


@functools.lru_cache(maxsize=32)
def _position_grid(k: float, n: int) -> tuple[np.ndarray, ...]:
    """The (ν, u) start grid of ``fit_positions`` and its unit-A position shapes: the same for every series of
    n + 1 imprints (computed once, not per fit)."""
    nu_g, u_g = np.meshgrid(np.linspace(0.05, 1.0, 96), np.linspace(0.0, 1.0, 101), indexing="ij")
    shape = plane.ricochet_ranges_spinless(nu_g, 1.0, u_g, k, n).cumsum(axis=-1)
    norm2 = np.maximum(np.einsum("...j,...j->...", shape, shape), 1e-300)
    for a in (nu_g, u_g, shape, norm2):
        a.flags.writeable = False
    return nu_g, u_g, shape, norm2


def fit_positions(x: np.ndarray, *, k: float) -> FitResult:
    """Fit (ν, A, u) of the spinless ricochet closed form to imprint positions measured from the first imprint.

    A = 2a0² sin α0 cos α0/g and u = f tan α0 are all that the ranges depend on
    (``plane.ricochet_ranges_spinless``); the kink where the slip stops makes the cost multimodal, so the fit
    starts from the best point of a (ν, u) grid, A solved exactly there since the positions are linear in A.
    """
    n = x.size - 1

    def res(th: np.ndarray) -> np.ndarray:
        return np.cumsum(plane.ricochet_ranges_spinless(th[0], th[1], th[2], k, n)) - x[1:]

    def jac(th: np.ndarray) -> np.ndarray:
        return _positions_jac(th, k, n)

    # A enters linearly: profile it out on a (ν, u) grid to find the basin of the global minimum, then polish.
    # With A = (s·x)/(s·s) for the grid's shapes s, the cost Σ(A s − x)² is |x|² − (s·x)²/(s·s).
    nu_g, u_g, shape, norm2 = _position_grid(float(k), n)
    sx = np.einsum("...j,j->...", shape, x[1:])
    A_g = sx / norm2
    i = np.unravel_index(np.argmax(sx * A_g), sx.shape)
    return least_squares_fit(res, [nu_g[i], A_g[i], u_g[i]], ["nu", "A", "u"],
                             ([1e-3, 1e-6, 0.0], [1.0, 100.0, 5.0]), jac=jac)


def _sigma_hat(fit: FitResult) -> float:
    """The noise estimated from a fit's residuals, s = √(RSS/(m − rank))."""
    return fit.residual_rms * math.sqrt(fit.n_data / max(fit.dof, 1))


PHYSICAL = ("nu", "f", "a0", "alpha0")
PHYSICAL_BOUNDS = ((1e-3, 0.0, 1e-3, 1e-3), (1.0, 2.0, 50.0, 1.5))  # ν, f, a0 (m/s), α0 (rad)


def fit_physical_positions(x: np.ndarray, start: FitResult, *, R: float, k: float, g: float) -> FitResult:
    """The physical parameters (ν, f, a0, α0) that imprint positions alone determine, from the fit of (ν, A, u).

    A spinless ball's ranges depend on (ν, A, u) only (``plane.ricochet_ranges_spinless``), so the solutions
    form the exact family f = u / tan α0, a0 = √(gA / sin 2α0) (``plane.spinless_launch``) over the α0 that keep
    (f, a0, α0) within ``PHYSICAL_BOUNDS``. Its canonical point is the slowest launch, α0 = π/4 (or the nearest
    admissible α0). Nothing here depends on where an optimiser stops: the family is a closed form of the
    well-conditioned (ν, A, u). Residuals are scaled by the noise the (ν, A, u) fit estimates.
    For a ball thrown without spin (``fit_physical`` takes a given spin).
    """
    nu, A, u = start.point
    n = x.size - 1
    lo, hi = PHYSICAL_BOUNDS
    c = g * A / hi[2] ** 2  # a0 ≤ a0_max  ⇔  sin 2α0 ≥ gA / a0_max²  (a0 ≥ lo[2] holds: gA ≥ g·1e-6 > lo[2]²)
    if c > 1.0:
        raise ValueError(f"no launch within a0 ≤ {hi[2]:g} m/s makes ranges this long (A = {A:g} m)")
    a_lo = max(lo[3], math.atan(u / hi[1]), 0.5 * math.asin(c))  # f = u / tan α0 ≤ f_max
    a_hi = min(hi[3], 0.5 * (math.pi - math.asin(c)))
    alphas = np.array([a_lo, a_hi, min(max(math.pi / 4, a_lo), a_hi)])
    f_, a0_ = plane.spinless_launch(A, u, g, alphas)
    pts = [np.array([nu, f_[i], a0_[i], alphas[i]]) for i in range(3)]
    sx = max(_sigma_hat(start), 1e-9)

    def phi(th: np.ndarray) -> np.ndarray:
        _, f, a0, al = th
        return np.array([th[0], a0**2 * math.sin(2 * al) / g, f * math.tan(al)])

    def res(th: np.ndarray) -> np.ndarray:
        ph = phi(th)
        return (np.cumsum(plane.ricochet_ranges_spinless(ph[0], ph[1], ph[2], k, n)) - x[1:]) / sx

    def jac(th: np.ndarray) -> np.ndarray:  # chain rule through A = a0² sin 2α0/g, u = f tan α0
        _, f, a0, al = th
        D = np.array([[1.0, 0.0, 0.0, 0.0],
                      [0.0, 0.0, 2 * a0 * math.sin(2 * al) / g, 2 * a0**2 * math.cos(2 * al) / g],
                      [0.0, math.tan(al), 0.0, f / math.cos(al) ** 2]])
        return _positions_jac(phi(th), k, n) @ D / sx

    def res_model(th: np.ndarray) -> np.ndarray:  # the check: the ricochet model itself, not the closed form
        r = plane.ricochet(th[2], th[3], 0.0, R=R, k=k, f=th[1], nu=th[0], g=g, n=n)
        return (r.imprints[1:] - x[1:]) / sx

    rss = float(np.sum(res_model(pts[2]) ** 2))
    d = tuple(float(np.sum(res_model(e) ** 2) - rss) for e in pts[:2])
    ranges = (None, (float(min(f_[:2])), float(max(f_[:2]))),
              (float(min(a0_)), float(max(a0_))), (float(a_lo), float(a_hi)))
    fam = Family(FamilyKind.EXACT, "alpha0", (tuple(map(float, pts[0])), tuple(map(float, pts[1]))), ranges, d,
                 max(d) <= FAMILY_CHI2,
                 f"f = {u:.4g}/tan α0 and a0 = √({g * A:.4g} m²/s²/sin 2α0) for α0 in [{a_lo:.4g}, {a_hi:.4g}] rad "
                 f"(bounds f ≤ {hi[1]:g}, a0 ≤ {hi[2]:g} m/s, α0 ≤ {hi[3]:g} rad)")
    return analyse(res, pts[2], PHYSICAL, PHYSICAL_BOUNDS, sigma=1.0, jac=jac, family=fam,
                   canonical="the slowest launch of the family (α0 = π/4 if admissible)")


def fit_physical(x: np.ndarray, t: np.ndarray | None, start: FitResult, *, R: float, k: float, g: float,
                 p0: float = 0.0) -> FitResult:
    """Fit the physical parameters (ν, f, a0, α0) of ``plane.ricochet`` to the positions, and to the impact
    instants too when given: the identifiability report then says whether f is determined.

    Starts from the closed-form fit (at α0 = 0.3 rad, any point of its family, or at the α0 the instants
    give); residuals are scaled by the noise each series' own fit estimates, so metres and seconds mix.
    """
    nu, A, u = start.point
    alpha = 0.3
    st = None
    if t is not None:  # the instants give the normal speed, hence the angle: start near the answer
        ft = fit_times(t, g=g)
        st = max(_sigma_hat(ft), 1e-9)
        zeta_in = ft.point[1] / nu
        alpha = math.atan2(zeta_in, A * g / (2 * zeta_in))
    x0 = [nu, u / math.tan(alpha), math.sqrt(A * g / (2 * math.sin(alpha) * math.cos(alpha))), alpha]
    n = x.size - 1
    sx = max(_sigma_hat(start), 1e-9)

    def res(th: np.ndarray) -> np.ndarray:
        r = plane.ricochet(th[2], th[3], p0, R=R, k=k, f=th[1], nu=th[0], g=g, n=n)
        out = (r.imprints[1:] - x[1:]) / sx
        if t is None:
            return out
        return np.concatenate([out, (np.cumsum(r.times) - t[1:]) / st])

    return least_squares_fit(res, x0, PHYSICAL, PHYSICAL_BOUNDS, sigma=1.0)


def fit_times(t: np.ndarray, *, g: float, origin: str = "first", sigma: float | None = None) -> FitResult:
    """Fit (ν, ζ1) to impact instants (the acoustic method): flights last T_j = 2ν^j ζ1/g (§III n°9).

    ``origin="first"`` (the default, as the experiments print it): the instants are measured from the first, taken
    as exact; its jitter then enters every residual and the Wald interval of ν covers ~90 % (not 95 %).
    ``origin="fitted"``: the first instant t0 is a parameter too (``fit_bounces`` with ζ1 = g T1/2), parameters
    (ν, ζ1, t0), ν's interval the profile-likelihood one; ``sigma`` (s, the timing jitter) only then.
    """
    if origin == "fitted":
        fb = fit_bounces(t, g=g, sigma=sigma)
        nu, T1, t0 = fb.point
        n = np.asarray(t).size
        tt = np.asarray(t, dtype=float)

        def res_z(th: np.ndarray) -> np.ndarray:
            return th[2] + 2.0 * th[1] / g * _bounce_sums(th[0], n) - tt

        def jac_z(th: np.ndarray) -> np.ndarray:
            return np.c_[2.0 * th[1] / g * _bounce_dsums(th[0], n), 2.0 / g * _bounce_sums(th[0], n), np.ones(n)]

        span = float(tt[-1] - tt[0])
        fz = analyse(res_z, [nu, g * T1 / 2.0, t0], ["nu", "zeta1", "t0"],
                     ([1e-3, 1e-9, float(tt[0]) - span], [1.0, 5.0 * g * span, float(tt[0]) + span]), sigma, jac_z)
        return dataclasses.replace(fz, estimates=(fb.estimates[0], *fz.estimates[1:]))
    if origin != "first":
        raise ValueError(f"origin must be 'first' or 'fitted', got {origin!r}")
    if sigma is not None:
        raise ValueError("sigma is taken only with origin='fitted'")
    T = np.diff(t)
    nu0 = float(np.clip(np.median(T[1:] / T[:-1]), 0.05, 0.99))
    j = np.arange(T.size)

    def res(th: np.ndarray) -> np.ndarray:
        return np.cumsum(2 * th[1] * th[0] ** j / g) - t[1:]

    def jac(th: np.ndarray) -> np.ndarray:
        dnu = np.cumsum(2 * th[1] * j * th[0] ** np.maximum(j - 1, 0) / g)
        dz = np.cumsum(2 * th[0] ** j / g)
        return np.c_[dnu, dz]

    return least_squares_fit(res, [nu0, g * T[0] / 2], ["nu", "zeta1"], ([1e-3, 1e-6], [1.0, 100.0]), jac=jac)


# ---- §III n°9, the acoustic method with the origin unknown: a ball bouncing in place ---------------------------
BOUNCE_NU_GRID = np.linspace(0.01, 1.0, 496)  # the start grid of ν for ``fit_bounces`` (profile of the linear part)


def _bounce_sums(nu: np.ndarray | float, n: int) -> np.ndarray:
    """S_i = 1 + ν + … + ν^(i−1) = (1 − ν^i)/(1 − ν) for i = 0 … n − 1 (S_0 = 0), vectorised over ν (last axis i);
    summed rather than divided so that ν → 1 is exact."""
    nu_ = np.asarray(nu, dtype=float)[..., None]
    return np.concatenate([np.zeros((*nu_.shape[:-1], 1)), np.cumsum(nu_ ** np.arange(n - 1), axis=-1)], axis=-1)


def _bounce_dsums(nu: float, n: int) -> np.ndarray:
    """dS_i/dν = Σ_{j<i} j ν^(j−1)."""
    j = np.arange(n - 1)
    return np.concatenate([[0.0], np.cumsum(j * nu ** np.maximum(j - 1, 0))])


def _bounce_profile(t: np.ndarray, nu: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each ν: the residual sum of squares with (t0, T1) solved exactly (the instants are linear in them),
    and that T1 and t0 (variable projection)."""
    S = _bounce_sums(nu, t.size)
    Sc = S - S.mean(axis=-1, keepdims=True)
    tc = t - t.mean()
    ss = np.maximum(np.einsum("...i,...i->...", Sc, Sc), 1e-300)
    st = Sc @ tc
    T1 = st / ss
    return tc @ tc - st * T1, T1, t.mean() - T1 * S.mean(axis=-1)


def _profile_set(grid: np.ndarray, prof: np.ndarray, level: float, refine: Callable[[float], float],
                 best: float | None, lo: float, hi: float) -> tuple[float, float]:
    """The hull [a, b] of {θ : prof(θ) ≤ level} from a grid of the profile and its optimum ``best``: each end
    found by root finding on the profile ``refine`` between the outermost point inside (a grid point or ``best``)
    and the next grid point outside by ``refine`` (or the bound, where the set reaches it). The grid's profile is
    an upper bound of the exact one, so a point the grid puts outside may be inside: the walk goes on outward
    through the grid until ``refine`` says outside (at most the grid's length: it ends)."""
    inside = np.nonzero(prof <= level)[0]
    if best is None:  # the estimate is not identifiable (a short rank): the grid's best point stands in for it
        best = float(grid[int(np.argmin(prof))])

    def end(a: float, beyond: np.ndarray, bound: float) -> float:  # a inside; beyond: the grid outward, in order
        for i, b in enumerate((*beyond.tolist(), bound)):
            if refine(b) > level:
                # the optimum on the edge of the grid's set (ν = 1): no crossing between (a point the walk reached
                # is inside by ``refine`` already: only the first a is asked)
                if i == 0 and refine(a) > level:
                    return a
                return float(optimize.brentq(lambda v: refine(v) - level, min(a, b), max(a, b), xtol=1e-13,
                                             rtol=1e-11))
            a = b
        return bound

    left = min(float(grid[inside[0]]), best) if inside.size else best
    right = max(float(grid[inside[-1]]), best) if inside.size else best
    return end(left, grid[grid < left][::-1], lo), end(right, grid[grid > right], hi)


def _profile_level(rss_min: float, dof: int, sigma: float | None) -> float | None:
    """The profile-likelihood threshold of a 95 % interval on one parameter: RSS ≤ RSS_min + σ² z² with σ given,
    RSS ≤ RSS_min (1 + t²/dof) with σ estimated (the F(1, dof) test, exact for a model linear in the others)."""
    if sigma is not None:
        return rss_min + sigma**2 * float(special.ndtri(0.975)) ** 2
    if dof <= 0:
        return None
    return rss_min * (1.0 + float(special.stdtrit(dof, 0.975)) ** 2 / dof)


def fit_bounces(t: np.ndarray, *, g: float = 9.80665, h0: float | None = None, sigma: float | None = None,
                interval: str = "profile") -> FitResult:
    """Fit (ν, T1, t0) to the instants of the impacts of a ball bouncing in place (an audio recording's clicks),
    the origin unknown: t_i = t0 + T1 (1 − ν^i)/(1 − ν), i = 0 … n − 1.

    §III n°8–9: each impact returns the normal velocity times ν (ζ_{i+1} = ν ζ_i), and a flight lasts 2ζ/g, so
    flight i lasts T1 ν^i; t0 is the true instant of the first click, fitted like the rest, not taken as exact
    (``fit_times`` measures from the first instant, whose jitter then enters every residual). ``sigma``: the
    constant timing jitter (s), given, or estimated from the residuals with n − 3 degrees of freedom (Student t).

    With ``h0`` (m), the ball released at rest from that height above its first impact, it arrives at √(2 g h0)
    and leaves at ν√(2 g h0), so T1 = 2ν √(2 h0/g): g = 8 ν² h0/T1² is determined, and the parameters are then
    (ν, g, t0) (a reparametrisation: the same optimum and the same ν). The uncertainty of h0 is not included
    (it adds a relative σ_h0/h0 to g's).

    ``interval="profile"`` (default): the 95 % interval of ν is the profile-likelihood set (the instants are
    linear in t0 and T1, solved exactly for each ν), {ν : RSS(ν) ≤ RSS_min(1 + t²/dof)}, or RSS_min + σ²z² with
    σ given; its hull is reported, refined by root finding. ``"wald"``: ± q·stderr from the Jacobian. The other
    parameters' intervals are Wald's. Needs at least 4 instants (3 with ``sigma``).
    """
    t = np.asarray(t, dtype=float)
    n = t.size
    if n < 3 or np.any(np.diff(t) <= 0):
        raise ValueError("expected at least 3 strictly increasing impact instants")
    if interval not in ("profile", "wald"):
        raise ValueError(f"interval must be 'profile' or 'wald', got {interval!r}")
    span = float(t[-1] - t[0])
    rss, T1g, t0g = _bounce_profile(t, BOUNCE_NU_GRID)
    ok = T1g > 0
    i = int(np.argmin(np.where(ok, rss, np.inf)))
    lo = [1e-3, 1e-9, float(t[0]) - span]
    hi = [1.0, 10.0 * span, float(t[0]) + span]

    def res(th: np.ndarray) -> np.ndarray:
        return th[2] + th[1] * _bounce_sums(th[0], n) - t

    def jac(th: np.ndarray) -> np.ndarray:
        return np.c_[th[1] * _bounce_dsums(th[0], n), _bounce_sums(th[0], n), np.ones(n)]

    fit = least_squares_fit(res, [BOUNCE_NU_GRID[i], T1g[i], t0g[i]], ["nu", "T1", "t0"], (lo, hi), sigma, jac)
    if h0 is not None:
        if not h0 > 0:
            raise ValueError(f"h0 must be a drop height > 0 (m), got {h0!r}")
        nu, T1, t0 = fit.point
        c = 2.0 * math.sqrt(2.0 * h0)  # T1 = c ν/√g

        def res_g(th: np.ndarray) -> np.ndarray:
            return th[2] + c * th[0] / math.sqrt(th[1]) * _bounce_sums(th[0], n) - t

        def jac_g(th: np.ndarray) -> np.ndarray:
            T = c * th[0] / math.sqrt(th[1])
            S = _bounce_sums(th[0], n)
            return np.c_[T * _bounce_dsums(th[0], n) + c / math.sqrt(th[1]) * S, -T / (2 * th[1]) * S, np.ones(n)]

        fit = analyse(res_g, [nu, 8.0 * nu**2 * h0 / T1**2, t0], ["nu", "g", "t0"],
                      ([lo[0], 1e-3, lo[2]], [hi[0], 1e4, hi[2]]), sigma, jac_g)
    if interval == "wald":
        return fit
    def profile(v: float) -> float:
        return float(_bounce_profile(t, np.array([v]))[0][0])

    level = _profile_level(profile(fit.point[0]), fit.dof, sigma)
    if level is None:
        return fit
    e = fit.estimates[0]
    ci = _profile_set(BOUNCE_NU_GRID, np.where(ok, rss, np.inf), level, profile, e.value, lo[0], hi[0])
    est = dataclasses.replace(e, ci95=ci, clipped=ci[0] <= lo[0] or ci[1] >= hi[0])
    return dataclasses.replace(fit, estimates=(est, *fit.estimates[1:]))


def synthetic_bounces(rng: np.random.Generator, n: int, *, nu: float, h0: float, jitter: float,
                      g: float = 9.80665, t_start: float = 0.0) -> dict[str, np.ndarray]:
    """Columns of a synthetic recording of n clicks (§III n°9): a ball released at rest from h0 (m) at t_start (s),
    first impact after √(2 h0/g), flights 2ν^(i+1)√(2 h0/g), each instant jittered by N(0, jitter²) (s).
    Returns ``i`` (the impact's index, from 0) and ``t`` (s)."""
    T1 = 2.0 * nu * math.sqrt(2.0 * h0 / g)
    t = t_start + math.sqrt(2.0 * h0 / g) + T1 * _bounce_sums(nu, n)
    return {"i": np.arange(n), "t": t + jitter * rng.standard_normal(n)}


# ---- §III n°9–10, imprint positions with the origin unknown and a profile-likelihood interval of ν ---------------
IMPRINT_GRID_NU = np.linspace(0.02, 1.0, 491)
IMPRINT_GRID_CELLS = 4_000_000  # bound on (ν, u) grid points × imprints (memory of the cached shapes)


@functools.lru_cache(maxsize=8)
def _imprint_grid(k: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The u grid and the centred unit-A imprint shapes (0, P_0, P_0 + P_1, …) on the (ν, u) grid of
    ``fit_imprints``. u spans [0, 1/(1 + k)]: beyond it the slip stops at the first impact whatever ν, and every
    u gives the same ranges (``plane.ricochet_ranges_spinless``)."""
    nu_count = IMPRINT_GRID_NU.size
    u_g = np.linspace(0.0, 1.0 / (1.0 + k), int(np.clip(IMPRINT_GRID_CELLS // (nu_count * (n + 1)), 41, 401)))
    shape = _imprint_shapes(IMPRINT_GRID_NU[:, None], u_g[None, :], k, n)
    shape.flags.writeable = False
    return u_g, shape


def _imprint_shapes(nu: np.ndarray, u: np.ndarray, k: float, n: int) -> np.ndarray:
    """Centred unit-A imprint positions (0, P_0, …, P_0 + … + P_{n−1}) minus their mean, over broadcast ν, u."""
    nu_, u_ = np.broadcast_arrays(np.asarray(nu, dtype=float), np.asarray(u, dtype=float))
    s = plane.ricochet_ranges_spinless(nu_, 1.0, u_, k, n).cumsum(axis=-1)
    s = np.concatenate([np.zeros((*s.shape[:-1], 1)), s], axis=-1)
    return s - s.mean(axis=-1, keepdims=True)


def _profiled_rss(shape: np.ndarray, xc: np.ndarray) -> np.ndarray:
    """RSS with A and the origin x0 solved exactly (positions are linear in both); +inf where A ≤ 0."""
    sx = shape @ xc
    ss = np.maximum(np.einsum("...j,...j->...", shape, shape), 1e-300)
    return np.where(sx > 0, xc @ xc - sx * sx / ss, np.inf)


def fit_imprints(x: np.ndarray, *, k: float, sigma: float | None = None, interval: str = "profile",
                 profiles: Sequence[str] = ("nu", "A", "u")) -> FitResult:
    """Fit (ν, A, u, x0) of the spinless ricochet closed form (§III n°9, ``plane.ricochet_ranges_spinless``) to
    imprint positions x_0 … x_n, the origin x0 fitted: x_i = x0 + P_0 + … + P_{i−1} (i = 0 … n).

    ``fit_positions`` measures from the first imprint, takes it as exact, and reports Wald intervals; with a
    kink where the slip stops (the model is not smooth in u and ν there) those cover ν only ~83 % of the time for
    8 imprints. Here the 95 % interval of ν is, by default, the profile-likelihood set: for each ν, A and x0 are
    solved exactly and u is minimised over a grid then polished; {ν : RSS(ν) ≤ RSS_min(1 + t²/dof)} (σ estimated
    from the residuals, dof = n + 1 − 4) or RSS_min + σ²z² (``sigma`` given, m), its hull reported.
    ``interval="wald"`` gives ± q·stderr. A and u get profile-likelihood sets too (A's: ``_imprint_A_set``), x0
    a Wald interval; ``profiles`` names the parameters whose profile sets are computed (the others keep Wald's: A's
    set costs four fifths of the fit, so a caller that reads only ν may leave it out).
    """
    x = np.asarray(x, dtype=float)
    n = x.size - 1
    if n < 3:
        raise ValueError("expected at least 4 imprints")
    if interval not in ("profile", "wald"):
        raise ValueError(f"interval must be 'profile' or 'wald', got {interval!r}")
    u_g, shape = _imprint_grid(float(k), n)
    xc = x - x.mean()
    rss = _profiled_rss(shape, xc)
    prof_u = np.argmin(rss, axis=1)
    prof = rss[np.arange(rss.shape[0]), prof_u]
    i = int(np.argmin(prof))
    s_best = shape[i, prof_u[i]]
    A0 = float(s_best @ xc / (s_best @ s_best))
    x00 = float(x.mean() + A0 * s_best[0])  # x0 = mean(x) − A·mean(s) and s_0 = 0, s centred: mean(s) = −s_best[0]
    span = float(x[-1] - x[0]) + 1.0

    def res(th: np.ndarray) -> np.ndarray:
        P = plane.ricochet_ranges_spinless(th[0], th[1], th[2], k, n)
        return th[3] + np.concatenate([[0.0], np.cumsum(P)]) - x

    def jac(th: np.ndarray) -> np.ndarray:
        return np.c_[np.r_[np.zeros((1, 3)), _positions_jac(th[:3], k, n)], np.ones(n + 1)]

    fit = least_squares_fit(res, [IMPRINT_GRID_NU[i], A0, u_g[prof_u[i]], x00], ["nu", "A", "u", "x0"],
                            ([1e-3, 1e-6, 0.0, float(x[0]) - span], [1.0, 100.0, 5.0, float(x[0]) + span]), sigma, jac)
    if interval == "wald":
        return fit

    def profile(v: float) -> float:  # ν fixed, u minimised
        return _grid_polished_min(u_g, lambda w: _profiled_rss(_imprint_shapes(v, w, k, n), xc))

    def profile_u(w: float) -> float:  # u fixed, ν minimised
        return _grid_polished_min(IMPRINT_GRID_NU, lambda v: _profiled_rss(_imprint_shapes(v, w, k, n), xc))

    rss_min = min(profile(fit.point[0]), float(np.sum(res(np.asarray(fit.point)) ** 2)))
    level = _profile_level(rss_min, fit.dof, sigma)
    if level is None:
        return fit
    unknown = set(profiles) - {"nu", "A", "u"}
    if unknown:
        raise ValueError(f"profiles must name nu, A or u, got {sorted(unknown)}")
    est, est_A, est_u = fit.estimates[:3]
    if "nu" in profiles:
        ci = _profile_set(IMPRINT_GRID_NU, prof, level, profile, est.value, 1e-3, 1.0)
        est = dataclasses.replace(est, ci95=ci, clipped=ci[0] <= 1e-3 or ci[1] >= 1.0)
    if "u" in profiles:
        # u: beyond 1/(1 + k) the slip stops at the first impact and every u gives the same ranges, so a set that
        # reaches the grid's last u runs on to the box's bound (5), reported clipped
        ci_u = _profile_set(u_g, np.min(rss, axis=0), level, profile_u, est_u.value, 0.0, 5.0)
        est_u = dataclasses.replace(est_u, ci95=ci_u, clipped=ci_u[0] <= 0.0 or ci_u[1] >= 5.0)
    if "A" in profiles:
        ci_A = _imprint_A_set(shape, xc, u_g, k, n, level, est_A.value)
        est_A = dataclasses.replace(est_A, ci95=ci_A, clipped=ci_A[0] <= 1e-6 or ci_A[1] >= 100.0)
    return dataclasses.replace(fit, estimates=(est, est_A, est_u, *fit.estimates[3:]))


def _grid_polished_min(grid: np.ndarray, rss: Callable[..., np.ndarray]) -> float:
    """min of ``rss`` (vectorised over its argument) over one parameter: on ``grid``, then polished by a bounded
    scalar minimisation between the best point's neighbours (never above the grid's best)."""
    r = rss(grid)
    j = int(np.argmin(r))
    a, b = grid[max(j - 1, 0)], grid[min(j + 1, grid.size - 1)]
    if not np.isfinite(r[j]) or a == b:
        return float(r[j])
    sol = optimize.minimize_scalar(lambda v: float(rss(v)), bounds=(a, b), method="bounded",
                                   options={"xatol": 1e-12})
    return float(min(sol.fun, r[j]))


A_RIDGE_MOVES = 40  # bound on the moves of the polish box along the ridge of (ν, u) (``_imprint_A_set``)
A_WALK_MAX = 60  # bound on the doublings of the outward walk of an end of A's interval (each doubles the step)


def _imprint_A_set(shape: np.ndarray, xc: np.ndarray, u_g: np.ndarray, k: float, n: int, level: float,
                   best: float | None) -> tuple[float, float]:
    """The profile-likelihood 95 % set of A (``fit_imprints``), its hull: {A : min over (ν, u, x0) of RSS ≤ level}.

    The positions are linear in A and x0, so on each cell of the (ν, u) grid RSS(A) = |xc|² − 2A s·xc + A²|s|²
    (x0 solved exactly) and the cell's part of the set is between the roots of a quadratic: the grid's hull is
    closed-form. Each end is then walked outward with the exact profile (ν, u polished by Nelder–Mead from the grid's
    best cell at that A), step doubling until it leaves the set, and found by ``brentq``. The Wald interval of A
    covered 42–62 % of synthetic series of 8 imprints (the kink where the slip stops, and A's strong tie to ν);
    this one's coverage: ``reproductions/fit/coverage.json`` (38/40 and 36/40 in a first check)."""
    xx = float(xc @ xc)
    sx = shape @ xc
    ss = np.einsum("...j,...j->...", shape, shape)
    nu_g = IMPRINT_GRID_NU

    def refine(a: float) -> float:
        q = xx - 2.0 * a * sx + a * a * ss
        i, j = np.unravel_index(int(np.argmin(q)), q.shape)

        def cost(p: np.ndarray) -> float:
            s_ = _imprint_shapes(p[0], p[1], k, n)
            return float(xx - 2.0 * a * (s_ @ xc) + a * a * (s_ @ s_))

        # the minimum lies on a narrow ridge of (ν, u): a box of ±2 cells, moved along the ridge while the
        # solution sits on its edge (each move strictly lowers the cost; at most A_RIDGE_MOVES)
        x0, best = np.array([float(nu_g[i]), float(u_g[j])]), float(q[i, j])
        dnu, du = float(nu_g[1] - nu_g[0]), float(u_g[1] - u_g[0])
        for _ in range(A_RIDGE_MOVES):
            box = [(max(x0[0] - 2 * dnu, float(nu_g[0])), min(x0[0] + 2 * dnu, float(nu_g[-1]))),
                   (max(x0[1] - 2 * du, 0.0), min(x0[1] + 2 * du, float(u_g[-1])))]
            sol = optimize.minimize(cost, x0, method="Nelder-Mead", bounds=box,
                                    options={"xatol": 1e-12, "fatol": 1e-15 * max(xx, 1e-300), "maxiter": 2000})
            edge = any(min(v - a, b - v) < 1e-9 * (b - a) and (a, b) != lim
                       for v, (a, b), lim in zip(sol.x, box, ((float(nu_g[0]), float(nu_g[-1])),
                                                             (0.0, float(u_g[-1]))), strict=True))
            improved = sol.fun < best
            best = min(best, float(sol.fun))
            if not (edge and improved):
                break
            x0 = np.asarray(sol.x, dtype=float)
        return best

    disc = sx * sx - ss * (xx - level)
    inside = (disc >= 0) & (sx > 0)
    root = np.sqrt(np.where(inside, disc, 0.0))
    lo = float(np.min(((sx - root) / ss)[inside])) if inside.any() else (best or 1e-6)
    hi = float(np.max(((sx + root) / ss)[inside])) if inside.any() else (best or 1e-6)
    if best is not None:
        lo, hi = min(lo, best), max(hi, best)
    lo, hi = max(lo, 1e-6), min(hi, 100.0)
    step0 = max(hi - lo, 1e-9 * max(hi, 1e-6))

    def end(a: float, direction: float, bound: float) -> float:  # a inside: walk out, then the crossing
        step = step0 / 8
        if refine(a) >= level:  # the grid's end sits on the level (to rounding): the exact profile agrees there
            return a
        for _ in range(A_WALK_MAX):
            b = a + direction * step
            if (b - bound) * direction >= 0:
                b = bound
            if refine(b) > level:
                return float(optimize.brentq(lambda v: refine(v) - level, min(a, b), max(a, b), xtol=1e-13,
                                             rtol=1e-11))
            if b == bound:
                return bound
            a, step = b, 2.0 * step
        raise RuntimeError(f"A's interval: the outward walk did not leave the set in {A_WALK_MAX} doublings")

    return end(lo, -1.0, 1e-6), end(hi, 1.0, 100.0)


def synthetic_imprints(rng: np.random.Generator, n: int, *, nu: float, f: float, a0: float, alpha0: float,
                       R: float, k: float, g: float, sigma_x: float, sigma_t: float,
                       p0: float = 0.0) -> dict[str, np.ndarray]:
    """Columns of a synthetic ricochet series (§III n°9, ``plane.ricochet``): n imprints ``x`` (m) and their
    instants ``t`` (s), each jittered by N(0, σ²) and given from the first measured imprint, as a CSV of
    ``series.read_imprints`` holds them. (a0, α0, p0): the ball arriving at the first impact."""
    r = plane.ricochet(a0, alpha0, p0, R=R, k=k, f=f, nu=nu, g=g, n=n - 1)
    x = r.imprints[:n] + sigma_x * rng.standard_normal(n)
    t = np.concatenate([[0.0], np.cumsum(r.times)])[:n] + sigma_t * rng.standard_normal(n)
    return {"x": x - x[0], "t": t - t[0]}


# ---- §III n°9–10, f from positions and instants: both origins fitted, a profile-likelihood interval --------------
FRICTION_BOUNDS = (0.0, 2.0)  # the range of f searched (that of ``PHYSICAL_BOUNDS``)
FRICTION_STEP = 1.25  # the ratio of successive f of the outward walk of the profile
FRICTION_XTOL = 1e-3  # the ends of the interval: relative tolerance of the root polish


def _joint_model(th: np.ndarray, k: float, g: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Imprint positions x_0 … x_n and instants t_0 … t_n of a spinless ricochet in (ν, A, u, ζ_in, x0, t0)
    (§III n°9): x_i = x0 + P_0 + … + P_{i−1} (``plane.ricochet_ranges_spinless``) and t_i = t0 + (2νζ_in/g) S_i,
    S_i = 1 + ν + … + ν^(i−1), since flight j lasts 2ν^(j+1)ζ_in/g."""
    nu, A, u, z, x0, t0 = th
    P = plane.ricochet_ranges_spinless(nu, A, u, k, n)
    return x0 + np.concatenate([[0.0], np.cumsum(P)]), t0 + 2.0 * nu * z / g * _bounce_sums(nu, n + 1)


def _joint_jac(th: np.ndarray, k: float, g: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """∂/∂(ν, A, u, ζ_in, x0, t0) of ``_joint_model``'s positions and instants."""
    nu, z = th[0], th[3]
    Jx = np.zeros((n + 1, 6))
    Jx[1:, :3] = _positions_jac(th[:3], k, n)
    Jx[:, 4] = 1.0
    S, dS = _bounce_sums(nu, n + 1), _bounce_dsums(nu, n + 1)
    Jt = np.zeros((n + 1, 6))
    Jt[:, 0] = 2.0 * z / g * (S + nu * dS)
    Jt[:, 3] = 2.0 * nu / g * S
    Jt[:, 5] = 1.0
    return Jx, Jt


def _joint_problem(x: np.ndarray, t: np.ndarray, sx: float, st: float, k: float, g: float,
                   f: float | None) -> tuple[Callable[[np.ndarray], np.ndarray], Callable[[np.ndarray], np.ndarray]]:
    """Weighted residuals and Jacobian of the joint fit: in (ν, A, u, ζ_in, x0, t0) when ``f`` is None, else in
    (ν, A, ζ_in, x0, t0) with u = f tan α0 = 2fζ_in²/(gA) (tan α0 = ζ_in/χ_in and A = 2χ_in ζ_in/g)."""
    n = x.size - 1

    def full(p: np.ndarray) -> np.ndarray:
        if f is None:
            return p
        nu, A, z, x0, t0 = p
        return np.array([nu, A, 2.0 * f * z * z / (g * A), z, x0, t0])

    def res(p: np.ndarray) -> np.ndarray:
        xm, tm = _joint_model(full(p), k, g, n)
        return np.concatenate([(xm - x) / sx, (tm - t) / st])

    def jac(p: np.ndarray) -> np.ndarray:
        th = full(p)
        Jx, Jt = _joint_jac(th, k, g, n)
        J = np.r_[Jx / sx, Jt / st]
        if f is None:
            return J
        u = th[2]  # chain rule: ∂u/∂A = −u/A, ∂u/∂ζ_in = 2u/ζ_in
        return np.c_[J[:, 0], J[:, 1] - J[:, 2] * u / th[1], J[:, 3] + J[:, 2] * 2.0 * u / th[3], J[:, 4], J[:, 5]]

    return res, jac


def _solve(res: Callable[[np.ndarray], np.ndarray], jac: Callable[[np.ndarray], np.ndarray], p0: np.ndarray,
           lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, float]:
    sol = optimize.least_squares(res, np.clip(p0, lo, hi), jac=jac, bounds=(lo, hi), method="trf",
                                 xtol=1e-12, ftol=1e-12, gtol=1e-12)
    return sol.x, float(sol.fun @ sol.fun)


def _friction_quantile(J: np.ndarray, th: np.ndarray, g: float, m: int, dof_x: float, dof_t: float) -> float:
    """The 97.5 % quantile of Student's t with the Welch–Satterthwaite degrees of freedom of f's variance, which
    the two series share: with the weighted Jacobian J (positions in its first m rows) at θ = (ν, A, u, ζ_in, x0,
    t0), the shares w_x + w_t = 1 of Var f = ∇fᵀ(JᵀJ)⁻¹∇f that each series' noise makes, and
    ν_eff = 1/(w_x²/dof_x + w_t²/dof_t) (the dof of σx and σt; infinite for a given σ: the normal quantile)."""
    _, A, u, z, _, _ = th
    f = u * g * A / (2.0 * z * z)
    v = np.linalg.pinv(J.T @ J) @ np.array([0.0, f / A, g * A / (2.0 * z * z), -2.0 * f / z, 0.0, 0.0])
    vx, vt = float(np.sum((J[:m] @ v) ** 2)), float(np.sum((J[m:] @ v) ** 2))
    wx = vx / (vx + vt) if vx + vt > 0 else 1.0
    inv = wx**2 / dof_x + (1.0 - wx) ** 2 / dof_t
    return float(special.ndtri(0.975)) if inv == 0 else float(special.stdtrit(1.0 / inv, 0.975))


def fit_friction(x: np.ndarray, t: np.ndarray, *, R: float, k: float, g: float,
                 sigma_x: float | None = None, sigma_t: float | None = None,
                 interval: str = "profile") -> FitResult:
    """Fit the physical parameters of a spinless ricochet and both origins, (ν, f, a0, α0, x0, t0), to imprint
    positions x_0 … x_n and impact instants t_0 … t_n (§III n°9–10, ``plane.ricochet`` with p0 = 0), with a
    profile-likelihood 95 % interval of f.

    ``fit_physical`` takes the first imprint and the first instant as exact and reports Wald intervals; with the
    kink where the slip stops (the model is not smooth in f there) its interval of f covers ~76 % of the time
    for 8 imprints. Here the first position and the first instant are fitted like the others, and the
    positions and instants are weighted by the noise levels their own origin-fitted fits estimate (σx from
    ``fit_imprints``, n + 1 − 4 degrees of freedom; σt from ``fit_bounces``, n + 1 − 3). The spinless model is
    computed in the closed form (ν, A, u, ζ_in): A = 2a0² sin α0 cos α0/g, u = f tan α0, ζ_in = a0 sin α0,
    hence f = u g A/(2ζ_in²). R does not enter a spinless ricochet; it is used by the check on
    ``plane.ricochet`` through which the reported Jacobian is taken.

    ``interval="profile"`` (default): the 95 % interval of f is the hull of the profile-likelihood set
    {f : RSS(f) ≤ RSS_min + q²}, RSS(f) the weighted RSS minimised over (ν, A, ζ_in, x0, t0) at fixed f
    (u = 2fζ_in²/(gA)). Since σx and σt are estimates (few degrees of freedom each), q is Student's t with the
    Welch–Satterthwaite degrees of freedom of f's variance (``_friction_quantile``); the normal quantile when
    both σ are given (``sigma_x`` in m, ``sigma_t`` in s). Where the set lies is read from the (ν, u) grid of
    ``fit_imprints`` (every cell a fit with f free), which finds all its parts: f = 0 and the f at which the slip
    stops at the first impact give ranges of the same shape, and every larger f fits as well (the interval
    then reaches the bound 2, ``clipped``). Each end is then walked outward from the outermost cell inside by
    the exact profile, warm-started, and polished by root finding (relative ``FRICTION_XTOL``).
    ``"wald"``: ± t·stderr. The other parameters' intervals are Wald's. Measured coverage of f's interval
    (tests/test_fit_coverage_ricochet.py, 8 imprints): 93 % over 300 seeds (94 % over 598 more); needs
    increasing instants and at least 5 imprints (the noise of positions needs a degree of freedom).
    """
    x, t = np.asarray(x, dtype=float), np.asarray(t, dtype=float)
    n = x.size - 1
    if t.shape != x.shape or n < 4:
        raise ValueError("expected as many instants as imprints, at least 5 of each")
    if interval not in ("profile", "wald"):
        raise ValueError(f"interval must be 'profile' or 'wald', got {interval!r}")
    fi = fit_imprints(x, k=k, interval="wald")
    fb = fit_bounces(t, g=g, interval="wald")
    given = sigma_x is not None and sigma_t is not None
    sx = sigma_x if sigma_x is not None else max(_sigma_hat(fi), 1e-12)
    st = sigma_t if sigma_t is not None else max(_sigma_hat(fb), 1e-12)
    spx, spt = float(x[-1] - x[0]) + 1.0, float(t[-1] - t[0]) + 1.0
    lo = np.array([1e-3, 1e-6, 0.0, 1e-6, float(x[0]) - spx, float(t[0]) - spt])
    hi = np.array([1.0, 100.0, 5.0, 100.0, float(x[0]) + spx, float(t[0]) + spt])
    res, jac = _joint_problem(x, t, sx, st, k, g, None)
    # f free, the positions depend on (ν, u) and the instants on ν only, each linear in the rest: the joint RSS on
    # the (ν, u) grid of ``fit_imprints``, whose best point starts the polish (the kink makes the cost multimodal)
    u_g, shape = _imprint_grid(float(k), n)
    xc = x - x.mean()
    rss_t, T1_g, t0_g = _bounce_profile(t, IMPRINT_GRID_NU)
    cost = _profiled_rss(shape, xc) / sx**2 + np.where(T1_g > 0, rss_t, np.inf)[:, None] / st**2
    i, j = np.unravel_index(int(np.argmin(cost)), cost.shape)
    s_best = shape[i, j]
    A_g = float(s_best @ xc / (s_best @ s_best))
    nu_g = float(IMPRINT_GRID_NU[i])
    start = np.array([nu_g, A_g, u_g[j], g * T1_g[i] / (2.0 * nu_g), float(x.mean() + A_g * s_best[0]), t0_g[i]])
    best = _solve(res, jac, start, lo, hi)
    th, rss_min = best
    nu, A, u, z, x0, t0 = th
    chi = g * A / (2.0 * z)
    phys = [nu, u * chi / z, math.hypot(chi, z), math.atan2(z, chi), x0, t0]

    def res_model(q: np.ndarray) -> np.ndarray:  # the ricochet model itself, not the closed form
        r = plane.ricochet(q[2], q[3], 0.0, R=R, k=k, f=q[1], nu=q[0], g=g, n=n)
        return np.concatenate([(q[4] + r.imprints - x) / sx, (q[5] + np.r_[0.0, np.cumsum(r.times)] - t) / st])

    plo, phi = PHYSICAL_BOUNDS
    fit = analyse(res_model, phys, (*PHYSICAL, "x0", "t0"),
                  ([*plo, lo[4], lo[5]], [*phi, hi[4], hi[5]]), sigma=1.0 if given else None)
    if interval == "wald" or fit.dof <= 0:
        return fit
    level = rss_min + _friction_quantile(jac(th), th, g, x.size,
                                          math.inf if sigma_x is not None else float(fi.dof),
                                          math.inf if sigma_t is not None else float(fb.dof)) ** 2
    f_lo, f_hi = FRICTION_BOUNDS
    # The grid's cells are joint fits with f free: each has its f = u g A/(2ζ_in²) and an RSS above the profile's
    # at that f. The cells inside the level show where the set lies, all its parts (f = 0 and the f at which the
    # slip stops at the first impact give ranges of the same shape, ν^(j+1) scaled, so the set may be in two);
    # the exact profile then takes each end outward from the outermost cell inside.
    z_g = g * T1_g / (2.0 * IMPRINT_GRID_NU)
    with np.errstate(divide="ignore", invalid="ignore"):
        A_all = np.einsum("...j,j->...", shape, xc) / np.maximum(np.einsum("...j,...j->...", shape, shape), 1e-300)
        f_all = u_g[None, :] * g * A_all / (2.0 * z_g[:, None] ** 2)
    inside = (cost <= level) & np.isfinite(f_all) & (f_all >= 0)
    qlo, qhi = lo[[0, 1, 3, 4, 5]], hi[[0, 1, 3, 4, 5]]
    q_hat = th[[0, 1, 3, 4, 5]]

    def profile(f: float, warm: np.ndarray) -> tuple[float, np.ndarray]:
        r, jc = _joint_problem(x, t, sx, st, k, g, f)
        q, v = _solve(r, jc, warm, qlo, qhi)
        return v, q

    def cell(a: int, b: int) -> np.ndarray:  # (ν, A, ζ_in, x0, t0) of a grid cell
        return np.array([IMPRINT_GRID_NU[a], A_all[a, b], z_g[a], float(x.mean() + A_all[a, b] * shape[a, b, 0]),
                         t0_g[a]])

    def end(f_in: float, q_in: np.ndarray, up: bool) -> float:
        """Walk from f_in (inside) outward by ``FRICTION_STEP`` to the first f outside, then the root between."""
        while True:
            f_out = min(max(f_in, 1e-3) * FRICTION_STEP, f_hi) if up else (f_in / FRICTION_STEP
                                                                           if f_in > 1e-3 else f_lo)
            v, q = profile(f_out, q_in)
            if v > level:
                break
            if f_out in (f_lo, f_hi):
                return f_out
            f_in, q_in = f_out, q

        def root(w: float) -> float:  # √ΔRSS is near linear in f: few steps of the root finder
            return math.sqrt(max(profile(w, q_in)[0] - rss_min, 0.0)) - math.sqrt(level - rss_min)

        try:
            return float(optimize.brentq(root, f_in, f_out, xtol=FRICTION_XTOL * max(f_in, 1e-3),
                                         rtol=FRICTION_XTOL))
        except ValueError:  # f_in not inside after all (a start clipped to the bounds): the end is there
            return f_in

    f_hat = phys[1]
    rolled = inside & (u_g[None, :] * (1.0 + IMPRINT_GRID_NU[:, None]) * (1.0 + k) >= 1.0)
    ends = []
    for up in (False, True):
        if up and (rolled.any() or 2.0 * f_hat * th[3] ** 2 / (g * th[1]) * (1 + th[0]) * (1 + k) >= 1.0):
            ends.append(f_hi)  # the slip stops at the first impact: every larger f fits as well
            continue
        f_in, q_in = f_hat, q_hat
        if inside.any():
            a, b = np.unravel_index(int(np.argmax(np.where(inside, f_all, -np.inf)) if up else
                                        np.argmin(np.where(inside, f_all, np.inf))), f_all.shape)
            if (f_all[a, b] > f_hat) if up else (f_all[a, b] < f_hat):
                f_in, q_in = float(f_all[a, b]), profile(float(f_all[a, b]), cell(a, b))[1]
        ends.append(f_lo if not up and f_in <= f_lo else end(f_in, q_in, up))
    ci = (ends[0], ends[1])
    e = fit.estimate("f")
    est = dataclasses.replace(e, ci95=ci, clipped=ci[0] <= f_lo or ci[1] >= f_hi)
    return dataclasses.replace(fit, estimates=tuple(est if x_.name == "f" else x_ for x_ in fit.estimates))
