"""§I physics: eqs (6)–(9) against momentum, the energy law itself, the premises, and a direct integration."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from reproductions.mechanics import impact, reference

mass = st.floats(0.01, 100.0)
vel = st.floats(-10.0, 10.0)
coef = st.floats(0.0, 1.0)


@given(mass, mass, vel, vel, coef, coef)
def test_momentum_is_conserved(M, Mp, V0, V0p, eps, epsp):
    r = impact.direct_impact(M, Mp, V0, V0p, eps=eps, epsp=epsp)
    assert M * r.V1 + Mp * r.V1p == pytest.approx(M * V0 + Mp * V0p, rel=1e-12, abs=1e-9)


@given(mass, mass, vel, vel, coef, coef)
def test_outcome_satisfies_the_energy_law_6(M, Mp, V0, V0p, eps, epsp):
    r = impact.direct_impact(M, Mp, V0, V0p, eps=eps, epsp=epsp)
    lhs = M * (V0**2 - r.V1**2) + Mp * (V0p**2 - r.V1p**2)
    rhs = impact.vis_viva_loss(M, V0 - r.V1, eps, Mp, r.V1p - V0p, epsp)
    scale = M * V0**2 + Mp * V0p**2 + 1e-12
    assert lhs == pytest.approx(rhs, abs=1e-10 * scale)
    assert lhs >= -1e-10 * scale  # energy is never gained for ε, ε′ in [0, 1]


@given(mass, mass, vel, vel)
def test_limits_elastic_and_carnot(M, Mp, V0, V0p):
    elastic = impact.direct_impact(M, Mp, V0, V0p, eps=0.0, epsp=0.0)
    scale = M * V0**2 + Mp * V0p**2 + 1e-12
    assert float(elastic.vis_viva_lost) == pytest.approx(0.0, abs=1e-10 * scale)
    carnot = impact.direct_impact(M, Mp, V0, V0p, eps=1.0, epsp=1.0)
    assert float(carnot.V1) == pytest.approx(float(carnot.V1p), abs=1e-9 * (abs(V0) + abs(V0p) + 1))


@given(mass, mass, vel, vel, coef)
def test_equal_coefficients_match_the_per_body_premise_of_n3(M, Mp, V0, V0p, eps):
    """n°3: each body regains φ1 = n φ0 from the common velocity u of greatest compression, ε = (1−n)/(1+n)."""
    u = (M * V0 + Mp * V0p) / (M + Mp)
    n = (1 - eps) / (1 + eps)
    r = impact.direct_impact(M, Mp, V0, V0p, eps=eps, epsp=eps)
    assert float(r.V1) == pytest.approx(u - n * (V0 - u), abs=1e-9 * (abs(V0) + abs(V0p) + 1))
    assert float(r.V1p) == pytest.approx(u - n * (V0p - u), abs=1e-9 * (abs(V0) + abs(V0p) + 1))
    assert float(r.newton_e) == pytest.approx(n)


def test_newton_e_is_the_relative_velocity_ratio():
    rng = np.random.default_rng(3)
    M, Mp = rng.uniform(0.1, 5, (2, 50))
    V0, V0p = rng.uniform(-3, 3, (2, 50))
    eps, epsp = rng.uniform(0, 1, (2, 50))
    r = impact.direct_impact(M, Mp, V0, V0p, eps=eps, epsp=epsp)
    np.testing.assert_allclose((r.V1p - r.V1) / (V0 - V0p), r.newton_e, rtol=1e-10)


def test_infinite_mass_limit_is_eq_9():
    eps = np.linspace(0, 1, 11)
    big = impact.direct_impact(1.0, 1e12, 2.0, 0.0, eps=eps, epsp=0.3)
    np.testing.assert_allclose(big.V1, impact.infinite_mass_impact(2.0, eps=eps), rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(impact.newton_restitution(1.0, 1e12, eps, 0.7), (1 - eps) / (1 + eps), atol=1e-10)


def test_inverse_maps_round_trip():
    eps = np.linspace(0, 1, 21)
    np.testing.assert_allclose(impact.eps_from_velocity_ratio(impact.velocity_ratio_from_eps(eps)), eps, atol=1e-15)
    np.testing.assert_allclose(impact.eps_from_height_ratio(impact.velocity_ratio_from_eps(eps) ** 2), eps,
                               atol=1e-12)
    M, Mp, e1, e2 = 3.0, 1.0, 0.1, 0.2
    r = impact.direct_impact(M, Mp, 1.0, 0.0, eps=e1, epsp=e2)
    D = impact.denominator(M, Mp, e1, e2)
    assert impact.denominator_from_struck_ratio(M, r.V1p) == pytest.approx(D)
    assert impact.denominator_from_striker_ratio(Mp, r.V1) == pytest.approx(D)


def test_batch_equals_scene_by_scene():
    rng = np.random.default_rng(7)
    args = [rng.uniform(0.1, 3, 40), rng.uniform(0.1, 3, 40), rng.uniform(-2, 2, 40), rng.uniform(-2, 2, 40),
            rng.uniform(0, 1, 40), rng.uniform(0, 1, 40)]
    batch = impact.direct_impact(*args[:4], eps=args[4], epsp=args[5])
    for i in range(0, 40, 7):
        one = impact.direct_impact(*(a[i] for a in args[:4]), eps=args[4][i], epsp=args[5][i])
        assert float(one.V1) == batch.V1[i]
        assert float(one.V1p) == batch.V1p[i]


def test_closed_form_matches_direct_integration():
    """Eq. (7) against the two-phase contact integrated numerically (§I n°2), at Newton's e implied by (7)."""
    rng = np.random.default_rng(11)
    n = 12
    M, Mp = rng.uniform(0.1, 5, (2, n))
    V0 = rng.uniform(0.5, 3, n)
    V0p = V0 - rng.uniform(0.2, 3, n)  # always approaching
    eps, epsp = rng.uniform(0, 0.9, (2, n))
    closed = impact.direct_impact(M, Mp, V0, V0p, eps=eps, epsp=epsp)
    ode = reference.integrate_direct_impact(M, Mp, V0, V0p, closed.newton_e)
    np.testing.assert_allclose(ode.V1, closed.V1, rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(ode.V1p, closed.V1p, rtol=1e-8, atol=1e-9)


def test_direct_integration_of_carnot_and_no_approach():
    ode = reference.integrate_direct_impact(3.0, 1.0, 1.0, 0.0, 0.0)
    assert float(ode.V1) == pytest.approx(0.75, rel=1e-9)
    assert float(ode.V1p) == pytest.approx(0.75, rel=1e-9)
    apart = reference.integrate_direct_impact(1.0, 1.0, 0.0, 1.0, 0.5)  # receding: no impact
    assert (float(apart.V1), float(apart.V1p), int(apart.nfev)) == (0.0, 1.0, 0)


def test_paper_reading_reproduces_coriolis_ratios():
    """With n°5's reading (ε = 0 for the cue, ε′ = 4/15 for the ball), eqs (8) give back the measured ratios."""
    r = impact.direct_impact(3.0, 1.0, 1.0, 0.0, eps=0.0, epsp=4 / 15)
    assert float(r.V1) == pytest.approx(7 / 12, rel=1e-14)
    assert float(r.V1p) == pytest.approx(5 / 4, rel=1e-14)


def test_stress_sweep_over_extreme_inputs_is_stable():
    from reproductions import stress

    res = stress.sweep()
    assert res["non_finite"] == 0
    assert res["max_momentum_rel_error"] < 1e-12
    assert res["max_energy_law_rel_error"] < 1e-12
    assert res["max_energy_gained_rel"] < 1e-12


@given(mass, mass, coef)
def test_newton_correspondence_round_trips_for_equal_coefficients(M, Mp, eps):
    e = impact.newton_restitution(M, Mp, eps, eps)
    assert float(impact.eps_from_newton(e)) == pytest.approx(eps, abs=1e-12)
