"""The few distribution functions the fits and the measured experiments use — χ², Student's t, the normal and F
tails and quantiles, and the least-squares line's slope test — computed by the ``scipy.special`` functions that
``scipy.stats`` itself calls for them (χ²: ``chdtrc``, ``chdtr``, ``gammaincinv``; t: ``stdtr``, ``stdtrit``;
normal: ``ndtri``; F: ``fdtrc``), without importing ``scipy.stats``: that import took 0.3 s of the start of
``make all`` (the parent imports what its workers will need before forking them, one core waiting meanwhile).

The values are those of ``scipy.stats`` bit for bit inside the support, and its conventions at the edges: a tail
of 1 below the support and 0 at +∞, a quantile of the support's ends at 0 and 1, NaN for a probability outside
[0, 1], for degrees of freedom that are not > 0, and for NaN (``tests/test_distributions.py`` compares them with
``scipy.stats`` over grids that include every edge)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..lazy import lazy

special = lazy("scipy.special", globals())

__all__ = ["Line", "chi2_cdf", "chi2_ppf", "chi2_sf", "f_sf", "line", "norm_ppf", "t_ppf", "t_sf"]


def _out(v: np.ndarray) -> Any:
    """A 0-d result as a numpy scalar (as ``scipy.stats`` returns it), an array as it is."""
    return v[()] if v.ndim == 0 else v


def _df_ok(*df: Any) -> np.ndarray:
    ok = np.asarray(True)
    for d in df:
        ok = ok & (np.asarray(d, dtype=float) > 0)
    return ok


def chi2_sf(x: Any, df: Any) -> Any:
    """P(χ²_df > x): ``scipy.stats.chi2.sf``."""
    x, df = np.asarray(x, dtype=float), np.asarray(df, dtype=float)
    with np.errstate(invalid="ignore"):
        v = np.where(x <= 0, 1.0, special.chdtrc(df, np.maximum(x, 0.0)))
    return _out(np.where(_df_ok(df) & ~np.isnan(x), v, np.nan))


def chi2_cdf(x: Any, df: Any) -> Any:
    """P(χ²_df ≤ x): ``scipy.stats.chi2.cdf``."""
    x, df = np.asarray(x, dtype=float), np.asarray(df, dtype=float)
    with np.errstate(invalid="ignore"):
        v = np.where(x <= 0, 0.0, special.chdtr(df, np.maximum(x, 0.0)))
    return _out(np.where(_df_ok(df) & ~np.isnan(x), v, np.nan))


def _quantile(q: np.ndarray, ok: np.ndarray, lo: float, inner: Any) -> Any:
    with np.errstate(invalid="ignore"):
        v = np.where(q == 0, lo, np.where(q == 1, np.inf, inner))
    return _out(np.where(ok & (q >= 0) & (q <= 1), v, np.nan))


def chi2_ppf(q: Any, df: Any) -> Any:
    """The q quantile of χ²_df: ``scipy.stats.chi2.ppf`` (2 γ⁻¹(df/2, q), as it computes it)."""
    q, df = np.asarray(q, dtype=float), np.asarray(df, dtype=float)
    return _quantile(q, _df_ok(df), 0.0, 2 * special.gammaincinv(df / 2, q))


def t_ppf(q: Any, df: Any) -> Any:
    """The q quantile of Student's t with df degrees of freedom: ``scipy.stats.t.ppf``."""
    q, df = np.asarray(q, dtype=float), np.asarray(df, dtype=float)
    return _quantile(q, _df_ok(df), -np.inf, special.stdtrit(df, q))


def t_sf(x: Any, df: Any) -> Any:
    """P(T_df > x): ``scipy.stats.t.sf``."""
    x, df = np.asarray(x, dtype=float), np.asarray(df, dtype=float)
    return _out(np.where(_df_ok(df), special.stdtr(df, -x), np.nan))


def norm_ppf(q: Any) -> Any:
    """The q quantile of the standard normal: ``scipy.stats.norm.ppf``."""
    q = np.asarray(q, dtype=float)
    return _quantile(q, np.asarray(True), -np.inf, special.ndtri(q))


def f_sf(x: Any, dfn: Any, dfd: Any) -> Any:
    """P(F_{dfn, dfd} > x): ``scipy.stats.f.sf``."""
    x, dfn, dfd = (np.asarray(a, dtype=float) for a in (x, dfn, dfd))
    with np.errstate(invalid="ignore"):
        v = np.where(x <= 0, 1.0, special.fdtrc(dfn, dfd, np.maximum(x, 0.0)))
    return _out(np.where(_df_ok(dfn, dfd) & ~np.isnan(x), v, np.nan))


@dataclass(frozen=True)
class Line:
    """The least-squares line of y on x: its slope, the slope's standard error, and the two-sided p-value of a
    zero slope (Student's t with n − 2 degrees of freedom), as ``scipy.stats.linregress`` gives them."""

    slope: float
    stderr: float
    pvalue: float


_TINY = 1.0e-20  # linregress's guard of r = ±1 in the t statistic


def line(x: Any, y: Any) -> Line:
    """``scipy.stats.linregress(x, y)``'s slope, stderr and pvalue, by its own formulas: the biased covariance
    matrix, r clipped to [−1, 1] (NaN when every y is the same), t = r √(df / ((1 − r + tiny)(1 + r + tiny))).
    At least three points and two distinct x: ``ValueError`` otherwise."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    n = x.size
    if n != y.size or n < 3:
        raise ValueError(f"a line's slope test needs at least 3 points (x and y of one length), got {n} and {y.size}")
    ssxm, ssxym, _, ssym = np.cov(x, y, bias=True).flat
    if ssxm == 0.0:
        raise ValueError("cannot fit a line if all x values are identical")
    slope = ssxym / ssxm
    if ssym == 0.0:  # every y the same: linregress's r is NaN (ssxym is then 0), and so are stderr and p
        r = np.nan if ssxym == 0 else 0.0
    else:
        r = min(max(ssxym / np.sqrt(ssxm * ssym), -1.0), 1.0)
    df = n - 2
    stderr = np.sqrt((1 - r**2) * ssym / ssxm / df)
    t = r * np.sqrt(df / ((1.0 - r + _TINY) * (1.0 + r + _TINY)))
    return Line(float(slope), float(stderr), float(2 * t_sf(abs(t), df)))
