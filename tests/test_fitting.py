"""Fits: recovery, honest uncertainties (coverage), and the identifiability report on rank-deficient data."""

import numpy as np
import pytest

from reproductions.fit.estimators import lsq as fitting
from reproductions.mechanics import impact


def test_one_mass_ratio_determines_only_a_combination():
    M, Mp = 3.0, 1.0
    V0 = np.array([1.0, 2.0, 2.8])
    r = impact.direct_impact(M, Mp, V0, 0.0, eps=0.1, epsp=0.2)
    fit = fitting.fit_direct_impact(M, Mp, V0, r.V1, r.V1p)
    assert fit.identifiability.rank == 1
    assert not any(e.identifiable for e in fit.estimates)
    (null,) = fit.identifiability.null_directions
    assert Mp * null[0] + M * null[1] == pytest.approx(0.0, abs=1e-6)  # moving along it leaves D unchanged
    (comb,) = fit.combinations
    assert comb.coefficients[1] / comb.coefficients[0] == pytest.approx(M / Mp, rel=1e-6)
    assert comb.value == pytest.approx(0.1 + 3 * 0.2, rel=1e-8)
    a, b = fit.family.ends
    assert fit.family.holds  # the model depends on a linear combination: the tangent segment is exact
    for end in (a, b):  # both ends of the family lie on the bounds and reproduce the data
        assert min(end) == pytest.approx(0.0, abs=1e-9)
        out = impact.direct_impact(M, Mp, V0, 0.0, eps=end[0], epsp=end[1])
        np.testing.assert_allclose(out.V1p, r.V1p, rtol=1e-8)


def test_two_mass_ratios_separate_eps_and_epsp():
    M = np.array([3.0, 3.0, 1.0, 1.0])
    Mp = np.array([1.0, 1.0, 2.0, 2.0])
    V0 = np.array([1.0, 2.0, 1.0, 2.0])
    r = impact.direct_impact(M, Mp, V0, 0.0, eps=0.15, epsp=0.35)
    fit = fitting.fit_direct_impact(M, Mp, V0, r.V1, r.V1p)
    assert fit.identifiability.rank == 2
    assert fit.estimate("eps").value == pytest.approx(0.15, abs=1e-7)
    assert fit.estimate("epsp").value == pytest.approx(0.35, abs=1e-7)
    assert fit.combinations == ()


def test_rebound_interval_covers_the_truth_about_95_percent():
    truth, hits, n_seeds = 0.29, 0, 300
    for seed in range(n_seeds):
        rng = np.random.default_rng(seed)
        V0 = rng.uniform(0.5, 7.0, 15)
        V1 = impact.infinite_mass_impact(V0, eps=truth) + 0.05 * rng.standard_normal(15)
        lo, hi = fitting.fit_rebound(V0, V1).estimate("eps").ci95
        hits += lo <= truth <= hi
    assert 0.91 <= hits / n_seeds <= 0.99


def test_given_sigma_scales_the_standard_error():
    V0 = np.array([1.0, 2.0, 3.0])
    V1 = impact.infinite_mass_impact(V0, eps=0.3)
    se1 = fitting.fit_rebound(V0, V1, sigma=0.01).estimate("eps").stderr
    se2 = fitting.fit_rebound(V0, V1, sigma=0.02).estimate("eps").stderr
    assert se2 == pytest.approx(2 * se1, rel=1e-6)


def test_no_degree_of_freedom_and_no_sigma_claims_no_uncertainty():
    fit = fitting.fit_rebound(np.array([2.0]), impact.infinite_mass_impact(np.array([2.0]), eps=0.4))
    est = fit.estimate("eps")
    assert est.value == pytest.approx(0.4, abs=1e-9)
    assert fit.dof == 0 and fit.noise == "none"
    assert est.stderr is None and est.ci95 == (None, None)


def test_collinear_linear_model_is_reported_rank_deficient():
    x = np.full(6, 2.0)  # the design cannot tell the intercept from the slope
    y = 1.0 + 0.5 * x + np.array([0.01, -0.02, 0.0, 0.02, -0.01, 0.0])
    fit = fitting.least_squares_fit(lambda t: t[0] + t[1] * x - y, [0.0, 0.0], ["a", "b"], ([-5, -5], [5, 5]))
    assert fit.identifiability.rank == 1
    (comb,) = fit.combinations
    assert comb.coefficients == pytest.approx((1.0, 2.0), rel=1e-6)
    assert comb.value == pytest.approx(y.mean(), rel=1e-8)
    assert comb.stderr is not None and comb.stderr > 0


def test_analytic_jacobians_match_finite_differences():
    M, Mp = np.array([3.0, 1.0]), np.array([1.0, 2.0])
    V0 = np.array([1.0, 2.0])
    r = impact.direct_impact(M, Mp, V0, 0.0, eps=0.2, epsp=0.3)
    fit = fitting.fit_direct_impact(M, Mp, V0, r.V1, r.V1p)

    def res(t):
        out = impact.direct_impact(M, Mp, V0, 0.0, eps=t[0], epsp=t[1])
        return np.concatenate([out.V1 - r.V1, out.V1p - r.V1p])

    J_fd = fitting._jacobian(res, np.array(fit.point))
    s_fd = np.linalg.svd(J_fd, compute_uv=False)
    np.testing.assert_allclose(fit.identifiability.singular_values, s_fd, rtol=1e-6)


def _product_fit(x0):
    """y = a·b·x: only the product is determined; the solutions form a hyperbola, a curved family."""
    x = np.linspace(0.5, 2.0, 9)
    y = 1.5 * x + 0.01 * np.sin(7 * x)  # fixed 'noise'
    return fitting.least_squares_fit(lambda t: t[0] * t[1] * x - y, x0, ["a", "b"], ([0.1, 0.1], [4.0, 2.0]))


def test_a_rank_deficient_fit_reports_one_canonical_point_whatever_the_start():
    # in this box the distance to the centre has one minimum along the hyperbola (where it has several, the
    # iteration finds the one whose basin holds the optimum: rounding cannot move it, a distant start can)
    fits = [_product_fit(x0) for x0 in ([0.3, 1.9], [3.9, 0.4], [1.0, 1.0], [1.0 + 1e-9, 1.0])]
    for f in fits[1:]:
        assert f.point == pytest.approx(fits[0].point, rel=1e-9)
        assert f.identifiability.null_directions[0] == pytest.approx(fits[0].identifiability.null_directions[0],
                                                                     rel=1e-9)
    f = fits[0]
    assert "NOT converged" not in f.canonical
    # the canonical point: the tangent is orthogonal to the line from the box centre, in box-scaled coordinates
    a, b = f.point
    w, c = np.array([3.9, 1.9]), np.array([2.05, 1.05])
    tangent = np.array([a, -b]) / w  # along a·b = const, in coordinates scaled by the box widths
    assert tangent @ ((np.array([a, b]) - c) / w) == pytest.approx(0.0, abs=1e-9)
    assert f.identifiability.null_directions[0][int(np.argmax(np.abs(f.identifiability.null_directions[0])))] == 1.0


def test_a_linearised_family_that_leaves_the_solutions_says_so():
    f = _product_fit([1.0, 1.0])
    fam = f.family
    assert fam.kind is fitting.FamilyKind.LINEARISED
    assert not fam.holds and max(fam.end_chi2) > fitting.FAMILY_CHI2  # the hyperbola curves away from its tangent
    assert all(e.family_range is None for e in f.estimates)  # no range claimed from a failed linearisation


def test_orient_is_invariant_to_scale_and_sign():
    v = np.array([0.2, -3.0, 1e-14, 1.0])
    assert fitting.orient(v) == pytest.approx([-0.2 / 3, 1.0, 0.0, -1 / 3])
    np.testing.assert_allclose(fitting.orient(-7.0 * v), fitting.orient(v), rtol=1e-15)
