"""``fit.distributions`` against ``scipy.stats``, which it stands in for (without importing it): equal bit for bit
inside the support, and the same conventions at its edges (below it, at its ends, at ±∞, NaN, degrees of freedom
that are not > 0, probabilities outside [0, 1]). The grids hold every edge; hypothesis draws the rest."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import scipy.stats as st
from hypothesis import given, settings
from hypothesis import strategies as hs

from reproductions.fit import distributions as d

X = np.array([-np.inf, -3.0, -1e-300, -0.0, 0.0, 1e-300, 1e-8, 0.3, 1.0, 3.841458820694124, 7.5, 40.0, 1e4, 1e300,
              np.inf, np.nan])
DF = np.array([-1.0, 0.0, 1e-3, 0.5, 1.0, 2.0, 3.0, 7.5, 30.0, 1e6, np.nan])
Q = np.array([-0.1, -0.0, 0.0, 1e-300, 1e-12, 0.025, 0.5, 0.95, 0.975, 1 - 1e-12, 1.0, 1.1, np.nan])


def _same(a: object, b: object) -> None:
    """Equal bit for bit (NaN equal to NaN; +0 and −0 equal), of the same shape and the same kind (a numpy scalar
    for a scalar)."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    assert np.array_equal(a, b, equal_nan=True), (a[~((a == b) | (np.isnan(a) & np.isnan(b)))],
                                                  b[~((a == b) | (np.isnan(a) & np.isnan(b)))])


@pytest.mark.parametrize(("ours", "theirs"), [(d.chi2_sf, st.chi2.sf), (d.chi2_cdf, st.chi2.cdf),
                                              (d.t_sf, st.t.sf)], ids=["chi2_sf", "chi2_cdf", "t_sf"])
def test_tails_equal_scipy_stats_on_a_grid_of_edges(ours, theirs) -> None:
    x, df = np.meshgrid(X, DF)
    _same(ours(x, df), theirs(x, df))
    for xi in X:  # scalars: a numpy scalar back, as scipy.stats gives
        for di in DF:
            r = ours(xi, di)
            assert np.ndim(r) == 0
            _same(r, theirs(xi, di))


@pytest.mark.parametrize(("ours", "theirs"), [(d.chi2_ppf, st.chi2.ppf), (d.t_ppf, st.t.ppf)],
                         ids=["chi2_ppf", "t_ppf"])
def test_quantiles_equal_scipy_stats_on_a_grid_of_edges(ours, theirs) -> None:
    q, df = np.meshgrid(Q, DF)
    _same(ours(q, df), theirs(q, df))


def test_normal_quantile_and_f_tail_equal_scipy_stats() -> None:
    _same(d.norm_ppf(Q), st.norm.ppf(Q))
    _same(d.norm_ppf(0.975), st.norm.ppf(0.975))
    x, dfn, dfd = np.meshgrid(X, DF, DF)
    _same(d.f_sf(x, dfn, dfd), st.f.sf(x, dfn, dfd))


@settings(max_examples=300, deadline=None)
@given(x=hs.floats(0, 1e3), df=hs.floats(1e-2, 1e3), q=hs.floats(0, 1), dfn=hs.floats(0.1, 100),
       dfd=hs.floats(0.1, 100))
def test_inside_the_support_equal_bit_for_bit(x: float, df: float, q: float, dfn: float, dfd: float) -> None:
    _same(d.chi2_sf(x, df), st.chi2.sf(x, df))
    _same(d.chi2_cdf(x, df), st.chi2.cdf(x, df))
    _same(d.chi2_ppf(q, df), st.chi2.ppf(q, df))
    _same(d.t_ppf(q, df), st.t.ppf(q, df))
    _same(d.norm_ppf(q), st.norm.ppf(q))
    _same(d.f_sf(x, dfn, dfd), st.f.sf(x, dfn, dfd))


def _line_cases() -> list[tuple[np.ndarray, np.ndarray]]:
    rng = np.random.default_rng(7)
    x = rng.uniform(-40, 40, 25)
    return [(x, 0.3 * x + rng.normal(0, 2, 25)),  # a trend in noise
            (x, rng.normal(0, 2, 25)),  # none
            (x, 2.0 - 0.5 * x),  # exact: r = −1, p = 0
            (x, np.full(25, 4.0)),  # every y the same: r, stderr and p NaN
            (x[:3], np.array([1.0, 2.0, 1.5]))]  # the fewest points: one degree of freedom


@pytest.mark.parametrize("case", range(5))
def test_the_line_is_linregress(case: int) -> None:
    x, y = _line_cases()[case]
    ours, theirs = d.line(x, y), st.linregress(x, y)
    _same([ours.slope, ours.stderr, ours.pvalue], [theirs.slope, theirs.stderr, theirs.pvalue])


def test_the_line_refuses_what_has_no_slope_test() -> None:
    with pytest.raises(ValueError, match="identical"):
        d.line([1.0, 1.0, 1.0], [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="at least 3 points"):
        d.line([1.0, 2.0], [1.0, 2.0])


def test_scipy_stats_is_not_imported_by_them() -> None:
    """The reason the module exists: using every function leaves ``scipy.stats`` unimported."""
    code = ("import sys; from reproductions.fit import distributions as d; d.chi2_sf(1.0, 2); d.chi2_cdf(1.0, 2); "
            "d.chi2_ppf(0.5, 2); d.t_ppf(0.975, 3); d.t_sf(1.0, 3); d.norm_ppf(0.975); d.f_sf(1.0, 2, 3); "
            "d.line([1, 2, 3], [1, 3, 2]); print('scipy.stats' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
