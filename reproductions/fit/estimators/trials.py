"""Estimators for a user's own trials: a ratio y = c·x with a noise model, its speed law, and the bootstrap.

A rebound (§I eq. (9)) gives |V1| = e·V0 and a drop h1 = e²·h0: one ratio c per series, with trials taken at
several impact speeds. How each trial's outcome y scatters decides the weights and hence the interval:

- ``CONSTANT``: sd(yᵢ) = s, the same for every trial (a speed gate's resolution);
- ``PROPORTIONAL``: sd(yᵢ) = s·xᵢ (a relative error, or a scatter of the material that grows with speed);
- ``GIVEN``: sd(yᵢ) = σ, given by the experimenter in the data's own unit.

s is estimated from the residuals (Student's t with n − p degrees of freedom); a given σ is taken as exact
(normal quantile) and the reduced χ² says whether it was right. ``AUTO`` picks, of the first two, the noise model
of greater likelihood (both have one scale parameter, so their maximised likelihoods compare directly), with a
margin in favour of the proportional model (``AUTO_MARGIN``), whose interval stays honest when it is wrong.

Every trial gives its own ratio qᵢ = yᵢ/xᵢ with variance ∝ 1/wᵢ (wᵢ = xᵢ² for constant noise, 1 for proportional
noise), so the fit of c is a weighted mean, and a law c(v) = b₀ + b₁v + b₂v² is a weighted polynomial fit of the
qᵢ against the impact speed v: nested orders are compared by an F test (χ² difference when σ is given).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import Any

import numpy as np
from scipy import special, stats

from .lsq import FitResult

__all__ = ["Bootstrap", "Noise", "PolyLaw", "RatioFit", "bootstrap", "bootstrap_many", "fit_ratio", "poly_law",
           "select_law", "transform_interval", "with_estimated_scale"]

# AUTO takes the constant model only when it is the likelier by a factor e³ ≈ 20: a wrong CONSTANT (the scatter
# does grow with speed) gives intervals that cover 84–90 % with 8 trials, while a wrong PROPORTIONAL (the mean of the
# per-trial ratios) stays honest, 95–97 %. Measured over 1000 seeds per case, 5–15 trials (tests/test_fit_coverage).
AUTO_MARGIN = 3.0
LAW_ALPHA = 0.05  # a higher order of the speed law is taken when the F test rejects the lower at this level
MAX_LAW_ORDER = 2  # a low-order law: constant, linear or quadratic in the impact speed
MIN_LAW_DOF = 2  # a law of order d needs n ≥ d + 1 + MIN_LAW_DOF trials to be tested


class Noise(str, Enum):
    """How the measured outcome scatters (see the module docstring); ``AUTO`` picks by likelihood."""

    AUTO = "auto"
    CONSTANT = "constant"
    PROPORTIONAL = "proportional"
    GIVEN = "given"


@dataclass(frozen=True)
class RatioFit:
    """c of y = c·x: estimate, standard error, 95 % interval (unclipped), and how the noise was judged."""

    value: float
    stderr: float
    ci95: tuple[float, float]
    noise: Noise
    scale: float  # s (estimated, in y's unit for CONSTANT, relative for PROPORTIONAL) or the given σ
    dof: int
    quantile: float  # Student's t (noise estimated) or the normal quantile (σ given)
    weights: tuple[float, ...]  # per trial, of its ratio qᵢ = yᵢ/xᵢ (absolute when σ is given)
    residuals: tuple[float, ...]  # yᵢ − c·xᵢ, in y's unit
    loglik: dict[str, float]  # maximised log-likelihood of each noise model considered
    chi2: float | None = None  # Σ ((yᵢ − c·xᵢ)/σ)² when σ is given
    chi2_p: float | None = None  # P(χ²_{n−1} ≥ chi2): small when σ understates the scatter


def _weights(x: np.ndarray, noise: Noise, sigma: float | None) -> np.ndarray:
    if noise is Noise.PROPORTIONAL:
        return np.ones_like(x)
    if noise is Noise.GIVEN:
        assert sigma is not None
        return (x / sigma) ** 2
    return x**2


def _loglik(x: np.ndarray, y: np.ndarray, noise: Noise) -> float:
    """The Gaussian log-likelihood of y = c·x under ``noise`` at its maximum over c and s."""
    w = _weights(x, noise, None)
    q = y / x
    c = float(np.sum(w * q) / np.sum(w))
    r = y - c * x
    n = x.size
    if noise is Noise.PROPORTIONAL:
        s2 = float(np.mean((r / x) ** 2))
        return -0.5 * n * math.log(2 * math.pi * max(s2, 1e-300)) - float(np.sum(np.log(x))) - 0.5 * n
    s2 = float(np.mean(r**2))
    return -0.5 * n * math.log(2 * math.pi * max(s2, 1e-300)) - 0.5 * n


def fit_ratio(x: np.ndarray, y: np.ndarray, noise: Noise = Noise.AUTO, sigma: float | None = None) -> RatioFit:
    """Fit c of y = c·x (x > 0) by weighted least squares under ``noise`` (``GIVEN`` needs ``sigma``)."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    n = x.size
    if n < 2:
        raise ValueError("a ratio fit needs at least two trials")
    ll = {m.value: _loglik(x, y, m) for m in (Noise.CONSTANT, Noise.PROPORTIONAL)}
    if sigma is not None:
        noise = Noise.GIVEN
    elif noise is Noise.GIVEN:
        raise ValueError("the GIVEN noise model needs sigma")
    elif noise is Noise.AUTO:
        noise = Noise.CONSTANT if ll["constant"] - ll["proportional"] > AUTO_MARGIN else Noise.PROPORTIONAL
    w = _weights(x, noise, sigma)
    q = y / x
    c = float(np.sum(w * q) / np.sum(w))
    r = y - c * x
    dof = n - 1
    wrss = float(np.sum(w * (q - c) ** 2))
    if noise is Noise.GIVEN:
        se, quant, scale = math.sqrt(1.0 / float(np.sum(w))), float(special.ndtri(0.975)), float(sigma or 0.0)
        chi2, chi2_p = wrss, float(stats.chi2.sf(wrss, dof))
    else:
        s2 = wrss / dof
        se, quant, scale = math.sqrt(s2 / float(np.sum(w))), float(special.stdtrit(dof, 0.975)), math.sqrt(s2)
        chi2 = chi2_p = None
    return RatioFit(c, se, (c - quant * se, c + quant * se), noise, scale, dof, quant,
                    tuple(map(float, w)), tuple(map(float, r)), ll, chi2, chi2_p)


@dataclass(frozen=True)
class PolyLaw:
    """q(v) = Σ bⱼ vʲ fitted to per-trial values qᵢ with weights wᵢ; covariance from the residuals or absolute."""

    order: int
    coefficients: tuple[float, ...]  # b₀, b₁, …
    stderr: tuple[float, ...]
    cov: tuple[tuple[float, ...], ...]
    rss: float  # Σ wᵢ (qᵢ − q(vᵢ))²
    dof: int
    v_range: tuple[float, float]  # the impact speeds it was fitted over: the range it holds over

    def __call__(self, v: np.ndarray) -> np.ndarray:
        return np.polyval(self.coefficients[::-1], np.asarray(v, dtype=float))

    def band(self, v: np.ndarray, quantile: float) -> tuple[np.ndarray, np.ndarray]:
        """The pointwise confidence band q(v) ± quantile·se(q(v))."""
        v = np.asarray(v, dtype=float)
        X = np.vander(v, self.order + 1, increasing=True)
        se = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", X, np.asarray(self.cov), X), 0.0))
        mid = self(v)
        return mid - quantile * se, mid + quantile * se


def poly_law(v: np.ndarray, q: np.ndarray, w: np.ndarray, order: int, absolute: bool = False) -> PolyLaw:
    """Weighted least squares of qᵢ on 1, vᵢ, …, vᵢ^order; ``absolute``: the weights are 1/σᵢ² (σ given)."""
    v, q, w = (np.asarray(a, dtype=float) for a in (v, q, w))
    X = np.vander(v, order + 1, increasing=True)
    sw = np.sqrt(w)
    A, b = X * sw[:, None], q * sw
    coef, *_ = np.linalg.lstsq(A, b, rcond=None)
    r = b - A @ coef
    rss = float(r @ r)
    dof = v.size - order - 1
    s2 = 1.0 if absolute else (rss / dof if dof > 0 else math.nan)
    cov = np.linalg.pinv(A.T @ A) * s2
    return PolyLaw(order, tuple(map(float, coef)), tuple(float(math.sqrt(max(c, 0.0))) for c in np.diag(cov)),
                   tuple(tuple(map(float, row)) for row in cov), rss, dof, (float(v.min()), float(v.max())))


@dataclass(frozen=True)
class LawTest:
    """Order d against d + 1: the statistic (F, or Δχ² when σ is given) and its p-value."""

    lower: int
    higher: int
    statistic: float
    p: float
    test: str  # "F" or "chi2"


def _nested_test(lo: PolyLaw, hi: PolyLaw, absolute: bool) -> LawTest:
    """Order ``lo.order`` against ``hi.order``: F = (ΔRSS/Δp)/(RSS_hi/dof_hi), or Δχ² with Δp degrees of freedom
    when the weights are absolute."""
    dp = hi.order - lo.order
    drop = max(lo.rss - hi.rss, 0.0)
    if absolute:
        return LawTest(lo.order, hi.order, drop, float(stats.chi2.sf(drop, dp)), "chi2")
    if hi.rss <= 0:
        return LawTest(lo.order, hi.order, 1e300, 0.0, "F")
    F = (drop / dp) / (hi.rss / hi.dof)
    return LawTest(lo.order, hi.order, float(F), float(stats.f.sf(F, dp, hi.dof)), "F")


def select_law(v: np.ndarray, q: np.ndarray, w: np.ndarray, absolute: bool = False
               ) -> tuple[PolyLaw, list[LawTest], list[PolyLaw]]:
    """A law in the impact speed, of order ≤ ``MAX_LAW_ORDER``, where the data reject a constant.

    The constant is tested against the linear and against the quadratic law (F tests of nested weighted fits; Δχ²
    when the weights are absolute), each at ``LAW_ALPHA``/2 (Bonferroni: two alternatives), so that a law that
    rises and falls, with no linear trend, is found too. When a constant is rejected, the quadratic is taken if
    it beats the linear at ``LAW_ALPHA``, else the linear if it beats the constant, else the quadratic. Returns
    the law, the tests (constant vs linear, constant vs quadratic, linear vs quadratic, those the data allow)
    and every law fitted."""
    v = np.asarray(v, dtype=float)
    n = v.size
    laws = [poly_law(v, q, w, 0, absolute)]
    for d in range(1, MAX_LAW_ORDER + 1):
        if n < d + 1 + MIN_LAW_DOF or np.unique(v).size <= d:
            break
        laws.append(poly_law(v, q, w, d, absolute))
    tests = [_nested_test(laws[0], hi, absolute) for hi in laws[1:]]
    if len(laws) > 2:
        tests.append(_nested_test(laws[1], laws[2], absolute))
    rejected = [t for t in tests if t.lower == 0 and t.p < LAW_ALPHA / 2]
    if not rejected:
        return laws[0], tests, laws
    if len(laws) > 2 and tests[-1].p < LAW_ALPHA:
        return laws[2], tests, laws
    if tests[0].p < LAW_ALPHA / 2:
        return laws[1], tests, laws
    return laws[-1], tests, laws


def transform_interval(ci: tuple[float, float], fun: Callable[[np.ndarray], np.ndarray], lo: float, hi: float
                       ) -> tuple[tuple[float, float], bool]:
    """The image of an interval under a monotone ``fun``, after cutting it to [lo, hi] (the admissible range of
    the argument): the ends sorted, and whether the cut was needed."""
    a, b = max(ci[0], lo), min(ci[1], hi)
    clipped = (a, b) != ci
    ya, yb = (float(v) for v in fun(np.array([a, b])))
    return (min(ya, yb), max(ya, yb)), clipped


@dataclass(frozen=True)
class Bootstrap:
    """A seeded bootstrap: each resample refitted; percentile intervals per estimate."""

    names: tuple[str, ...]
    resamples: int
    seed: int
    ci95: tuple[tuple[float, float], ...]
    stderr: tuple[float, ...]
    failed: int  # resamples whose refit failed (degenerate draws), left out


def bootstrap(refit: Callable[[Any], Sequence[float]], draw: Callable[[np.random.Generator], Any],
              names: Sequence[str], resamples: int, seed: int,
              progress: Callable[[int], None] | None = None) -> Bootstrap:
    """Draw ``resamples`` data sets with ``draw`` (a seeded generator), refit each with ``refit`` (a ValueError
    or ArithmeticError marks a degenerate draw, counted as failed), and report 2.5 / 97.5 % percentiles.
    ``progress(k)`` is called after each resample."""

    def refit_many(batch: list[Any]) -> list[Sequence[float] | None]:
        out: list[Sequence[float] | None] = []
        for data in batch:
            try:
                out.append(refit(data))
            except (ValueError, ArithmeticError):
                out.append(None)
        return out

    return bootstrap_many(refit_many, draw, names, resamples, seed, progress, batch=1)


def bootstrap_many(refit_many: Callable[[list[Any]], list[Sequence[float] | None]],
                   draw: Callable[[np.random.Generator], Any], names: Sequence[str], resamples: int, seed: int,
                   progress: Callable[[int], None] | None = None, batch: int = 50) -> Bootstrap:
    """``bootstrap`` for a refit that takes ``batch`` data sets at once (None for a failed one): the same draws
    from the same seed, whatever the batch."""
    rng = np.random.default_rng(seed)
    out, failed, done = [], 0, 0
    while done < resamples:
        chunk = [draw(rng) for _ in range(min(batch, resamples - done))]
        for est in refit_many(chunk):
            e = None if est is None else np.asarray(est, dtype=float)
            if e is not None and np.all(np.isfinite(e)):
                out.append(e)
            else:
                failed += 1
        done += len(chunk)
        if progress is not None:
            progress(done)
    if len(out) < max(10, resamples // 2):
        raise ArithmeticError(f"the bootstrap refit failed on {failed} of {resamples} resamples")
    arr = np.array(out)
    lo, hi = np.percentile(arr, [2.5, 97.5], axis=0)
    return Bootstrap(tuple(names), resamples, seed, tuple(zip(map(float, lo), map(float, hi), strict=True)),
                     tuple(map(float, arr.std(axis=0, ddof=1))), failed)


def with_estimated_scale(fit: FitResult, weighted_rss: float, lo: Sequence[float], hi: Sequence[float]) -> FitResult:
    """A fit made with relative standard deviations (known up to one common factor, given as if absolute), reported
    with that factor estimated from its weighted residuals: s² = RSS_w/dof, standard errors × s, Student's t with
    the fit's degrees of freedom, intervals cut at [lo, hi]."""
    if fit.dof <= 0:
        raise ValueError("no degree of freedom left to estimate the noise")
    s = math.sqrt(weighted_rss / fit.dof)
    q = float(special.stdtrit(fit.dof, 0.975))
    est = []
    for e, a, b in zip(fit.estimates, lo, hi, strict=True):
        if e.stderr is None or e.value is None:
            est.append(e)
            continue
        se = e.stderr * s
        ci = (max(e.value - q * se, a), min(e.value + q * se, b))
        est.append(dataclasses.replace(e, stderr=se, ci95=ci, clipped=ci != (e.value - q * se, e.value + q * se)))
    combos = []
    for c in fit.combinations:
        if c.stderr is None:
            combos.append(c)
            continue
        cc = np.asarray(c.coefficients)
        clo = float(np.sum(np.minimum(cc * np.asarray(lo), cc * np.asarray(hi))))  # the combination's range
        chi = float(np.sum(np.maximum(cc * np.asarray(lo), cc * np.asarray(hi))))  # over the box [lo, hi]
        se = c.stderr * s
        combos.append(dataclasses.replace(c, stderr=se, ci95=(max(c.value - q * se, clo), min(c.value + q * se, chi))))
    return dataclasses.replace(fit, estimates=tuple(est), combinations=tuple(combos),
                               noise="estimated from residuals (relative weights given)")
