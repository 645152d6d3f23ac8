"""§III physics: the sphere–plane impact in both regimes and the ricochets, against direct integration."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from reproductions.mechanics import plane, reference
from reproductions.mechanics.paths import Regime


def _scenes(n, seed):
    rng = np.random.default_rng(seed)
    return (rng.uniform(-4, 4, n), -rng.uniform(0.05, 3, n), rng.uniform(-100, 100, n), 0.03,
            rng.choice([2.5, 1.5, 5 / 3], n), rng.uniform(0, 0.8, n), rng.uniform(0.05, 1.0, n))


def _kw(args):
    return dict(zip(("R", "k", "f", "nu"), args[3:], strict=True))


def test_closed_form_matches_the_impulse_integration_in_both_regimes():
    args = _scenes(300, 1)
    exact = plane.plane_impact(*args[:3], **_kw(args))
    ref = reference.integrate_plane_impact(*args[:3], **_kw(args))
    assert 0.2 < (exact.regime == Regime.SLIDE).mean() < 0.8  # both regimes are exercised
    np.testing.assert_allclose(exact.chi1, ref.chi1, atol=1e-10)
    np.testing.assert_allclose(exact.zeta1, ref.zeta1, atol=1e-10)
    np.testing.assert_allclose(exact.p1 * 0.03, ref.p1 * 0.03, atol=1e-10)
    # the integration stops the slip exactly where the closed form says it stops
    assert np.array_equal(np.isnan(ref.slip_stopped_at), (exact.regime == Regime.SLIDE))


def test_resal_eqs_6_are_exact_only_while_the_contact_slides():
    args = _scenes(300, 2)
    exact = plane.plane_impact(*args[:3], **_kw(args))
    resal = plane.plane_impact(*args[:3], **_kw(args), method="resal")
    s = exact.regime == Regime.SLIDE
    np.testing.assert_allclose(resal.chi1[s], exact.chi1[s], atol=1e-12)
    assert np.all(np.abs(resal.chi1[~s] - exact.chi1[~s]) > 0)


def test_outcome_is_continuous_across_the_slide_grip_boundary():
    zeta0, R, k, f, nu = -1.0, 0.03, 2.5, 0.3, 0.7
    boundary = f * (1 + k) * (1 + nu) * abs(zeta0)  # χ0 at which the slip stops exactly at the end
    chi0 = boundary * np.array([1 - 1e-9, 1.0, 1 + 1e-9])
    out = plane.plane_impact(chi0, zeta0, 0.0, R=R, k=k, f=f, nu=nu)
    assert list(out.regime == Regime.SLIDE) == [False, True, True]
    assert np.ptp(out.chi1) < 1e-8 and np.ptp(out.p1 * R) < 1e-8


@given(st.floats(-5, 5), st.floats(-5, -0.01), st.floats(-100, 100), st.floats(0, 1), st.floats(0.01, 1))
def test_energy_is_never_gained_and_the_slip_never_reverses(chi0, zeta0, p0, f, nu):
    R, k = 0.03, 2.5
    out = plane.plane_impact(chi0, zeta0, p0, R=R, k=k, f=f, nu=nu)
    # kinetic energy per unit mass, translation + rotation (I = M R²/k)
    T0 = chi0**2 + zeta0**2 + (p0 * R) ** 2 / k
    T1 = out.chi1**2 + out.zeta1**2 + (out.p1 * R) ** 2 / k
    assert T1 <= T0 * (1 + 1e-12) + 1e-12
    v0, v1 = chi0 - p0 * R, out.chi1 - out.p1 * R
    assert v0 * v1 >= -1e-9 * (abs(v0) + 1)  # friction stops the slip, it never reverses it


def test_ricochet_matches_impacts_and_flights_integrated_one_by_one():
    a0, alpha0, p0, R, k, f, nu, g, n = 2.0, math.radians(25), 10.0, 0.03, 2.5, 0.25, 0.75, 9.81, 8
    r = plane.ricochet(a0, alpha0, p0, R=R, k=k, f=f, nu=nu, g=g, n=n)
    chi, zeta, p = a0 * math.cos(alpha0), -a0 * math.sin(alpha0), p0
    x = 0.0
    for j in range(n):
        out = reference.integrate_plane_impact(chi, zeta, p, R=R, k=k, f=f, nu=nu)
        chi, zeta, p = float(out.chi1), float(out.zeta1), float(out.p1)
        P, T = reference.integrate_flight(chi, zeta, g)
        assert float(P) == pytest.approx(r.ranges[j], rel=1e-9)
        assert float(T) == pytest.approx(r.times[j], rel=1e-9)
        x += float(P)
        zeta = -zeta
    assert x == pytest.approx(r.imprints[-1], rel=1e-9)
    slides = r.regimes == Regime.SLIDE
    assert slides[0] and not slides[-1]  # this scene starts sliding and ends rolling


def test_spinless_closed_form_of_the_ranges_matches_the_ricochet():
    rng = np.random.default_rng(4)
    for _ in range(50):
        a0, alpha0, f, nu = rng.uniform(0.5, 4), rng.uniform(0.05, 1.2), rng.uniform(0, 0.6), rng.uniform(0.1, 1)
        r = plane.ricochet(a0, alpha0, 0.0, R=0.03, k=2.5, f=f, nu=nu, g=9.81, n=10)
        A = 2 * a0**2 * math.sin(alpha0) * math.cos(alpha0) / 9.81
        np.testing.assert_allclose(plane.ricochet_ranges_spinless(nu, A, f * math.tan(alpha0), 2.5, 10), r.ranges,
                                   rtol=1e-10, atol=1e-14)


def test_range_ratio_8_is_exact_while_sliding_and_9_is_its_small_angle_limit():
    alpha = np.radians(np.linspace(1, 60, 60))
    f, nu, k = 0.2, 0.8, 2.5
    exact = plane.range_ratio_exact(alpha, f=f, nu=nu, k=k)
    slides = f * (1 + k) * (1 + nu) * np.tan(alpha) <= 1
    np.testing.assert_allclose(plane.range_ratio_resal(alpha, f=f, nu=nu)[slides], exact[slides], rtol=1e-12)
    assert np.all(np.abs(plane.range_ratio_resal(alpha, f=f, nu=nu)[~slides] - exact[~slides]) > 1e-3)
    # gripping regime: the ball leaves rolling, χ1 = kχ0/(1 + k)
    np.testing.assert_allclose(exact[~slides], nu * k / (1 + k), rtol=1e-12)
    assert plane.range_ratio_exact(1e-8, f=f, nu=nu, k=k) == pytest.approx(float(plane.range_ratio_small_angle(nu)))


def test_plane_impact_rejects_an_unknown_method():
    with pytest.raises(ValueError, match="method"):
        plane.plane_impact(1.0, -1.0, 0.0, R=0.03, k=2.5, f=0.2, nu=0.8, method="fast")


def _scene_3d(rng):
    return (np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), -rng.uniform(0.1, 3)]), rng.uniform(-3, 3, 3),
            rng.uniform(0, 0.6), rng.uniform(0.3, 1.0))


def test_the_3d_vector_impact_agrees_with_the_closed_form_in_axes_along_the_slip():
    """§III n°8: the Newton–Euler impact in three dimensions keeps the slip's direction (so (3) holds in axes along
    it), ignores q, and then gives the closed form of both regimes."""
    rng = np.random.default_rng(11)
    regimes = set()
    for _ in range(40):
        v0, Rw0, f, nu = _scene_3d(rng)
        out = plane.integrate_impact_3d(v0, Rw0, k=2.5, f=f, nu=nu)
        assert out.turn < 1e-10
        u = plane.slip_velocity(v0, Rw0)
        c, s = u[:2] / np.hypot(*u[:2])
        rot = np.array([[c, s], [-s, c]])
        chi0, eta0 = rot @ v0[:2]
        n0R, p0R = rot @ Rw0[:2]
        ref = plane.plane_impact(chi0, v0[2], p0R, R=1.0, k=2.5, f=f, nu=nu)
        chi1, eta1 = rot @ out.v1[:2]
        n1R, p1R = rot @ out.Rw1[:2]
        assert chi1 == pytest.approx(float(ref.chi1), abs=1e-9) and p1R == pytest.approx(float(ref.p1), abs=1e-9)
        assert eta1 == pytest.approx(eta0, abs=1e-9) and n1R == pytest.approx(n0R, abs=1e-9)  # eqs (3)
        assert out.v1[2] == pytest.approx(-nu * v0[2]) and out.Rw1[2] == Rw0[2]  # ζ1 = −νζ0; q constant
        no_q = plane.integrate_impact_3d(v0, Rw0 * [1, 1, 0], k=2.5, f=f, nu=nu)
        np.testing.assert_allclose(no_q.v1, out.v1, atol=1e-9)
        regimes.add(int(ref.regime))
    assert regimes == {int(Regime.SLIDE), int(Regime.GRIP)}


def test_the_vector_rates_are_the_likely_original_eqs_2_not_the_digitised_ones():
    """The digitised (2) swaps v_x and v_y in its last two lines; §II's (2) and (3)-(4) need them as computed."""
    v, Rw, f, k = np.array([1.0, 0.5, -1.0]), np.array([0.3, -0.2, 0.7]), 0.2, 2.5
    u = plane.slip_velocity(v, Rw)
    np.testing.assert_allclose(u[:2], [v[0] - Rw[1], v[1] + Rw[0]], atol=1e-15)  # eq (1): χ − pR, η + nR
    dv, dw = plane.impact_rates(v, Rw, k=k, f=f)
    ux, uy = u[:2] / np.hypot(*u[:2])
    np.testing.assert_allclose(dv, [-ux * f, -uy * f, 1.0], atol=1e-15)
    np.testing.assert_allclose(dw[:2], [-uy * f * k, ux * f * k], atol=1e-15)  # n with v_y, p with v_x
    assert abs(dw[0] - (-ux * f * k)) > 0.1 and abs(dw[1] - uy * f * k) > 0.1  # the digitised lines are off


def test_side_spin_about_the_line_of_flight_moves_the_ricochets_out_of_their_plane():
    a0, al = 2.0, 0.4
    v0 = [a0 * math.cos(al), 0.0, -a0 * math.sin(al)]
    flat, _ = plane.ricochet_3d(v0, [0.0, -0.5, 0.0], k=2.5, f=0.2, nu=0.8, g=9.81, n=5)
    side, _ = plane.ricochet_3d(v0, [1.0, -0.5, 0.0], k=2.5, f=0.2, nu=0.8, g=9.81, n=5)
    assert np.all(flat[:, 1] == 0.0)
    assert abs(side[-1, 1]) > 0.05 * abs(side[-1, 0])
    # in the plane the 3-D ricochet is the closed-form one
    r = plane.ricochet(a0, al, -0.5, R=1.0, k=2.5, f=0.2, nu=0.8, g=9.81, n=5)
    np.testing.assert_allclose(flat[:, 0], r.imprints, rtol=1e-9)
