"""Oblique ball–ball shots (§VI n°13 impact, then the §II n°7 slide): predictions against an independent path,
physics sanity, recovery of (f_bb, e), per-shot residuals, and the coverage of the reported 95 % intervals."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from reproductions.errors import InputError
from reproductions.fit.estimators import lsq as fitting
from reproductions.fit.estimators import shots as fb
from reproductions.mechanics import cloth, impact, spheres

R = 0.02855
K = 2.5
SIG_SPEED, SIG_DIR = 0.02, math.radians(0.5)


def _roll_by_ode(v: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Velocity of the centre once rolling, from the rigid-body equations on the cloth integrated until the slip
    vanishes (its direction is constant: the event is the slip along its initial direction)."""
    mu, g = 0.2, 9.80665
    u0 = cloth.point_velocity(v, w, -R)[:2]

    def slip(_t: float, y: np.ndarray) -> float:
        return float(cloth.point_velocity(y[3:6], y[6:9], -R)[:2] @ u0)

    slip.terminal = True
    sol = solve_ivp(lambda t, y: cloth.rigid_rhs(y, R=R, k=K, f=mu, g=g), (0.0, 10.0),
                    np.concatenate([np.zeros(3), v, w]), method="DOP853", rtol=1e-12, atol=1e-14, events=slip)
    assert sol.status == 1
    return sol.y[3:5, -1]


def test_prediction_matches_the_ode_impact_and_the_rigid_body_slide():
    v = np.array([0.7, 1.5, 2.8, 1.1])
    phi = np.radians([0.0, 15.0, 40.0, -55.0])
    p = fb.predict_shots(v, phi, f_bb=0.08, e=0.9, R=R, k=K)
    # the alternative: spheres' ODE path for the impact, then Newton–Euler on the cloth by an ODE
    vx, vy = v * np.cos(phi), -v * np.sin(phi)
    z = np.zeros_like(v)
    v0, w0 = np.stack([vx, vy, z], -1), np.stack([-vy / R, vx / R, z], -1)
    eps = impact.eps_from_newton(0.9)
    imp = spheres.two_spheres(0.17, 0.17, R, R, K, K, v0, w0, np.zeros_like(v0), np.zeros_like(v0), f=0.08, eps=eps,
                              epsp=eps, on_cloth=True, method="ode")
    for i in range(v.size):
        for vel, spin, speed, direction in ((imp.v1, imp.w1, p.cue_speed, p.cue_dir),
                                            (imp.v1p, imp.w1p, p.obj_speed, p.obj_dir)):
            roll = _roll_by_ode(vel[i], spin[i])
            assert np.hypot(*roll) == pytest.approx(speed[i], rel=1e-8, abs=1e-10)
            assert phi[i] + math.atan2(roll[1], roll[0]) == pytest.approx(direction[i], abs=1e-8)


def test_head_on_without_friction_and_momentum():
    p = fb.predict_shots(1.3, 0.0, f_bb=0.0, e=0.93, R=R, k=K)
    # head-on, no friction: the line-of-centres speeds V(1 ∓ e)/2, the cue ball keeps its topspin V/R; rolling:
    # cue (k V(1 − e)/2 + V)/(1 + k), object k V(1 + e)/2/(1 + k) (5/7 of its speed)
    assert p.cue_v1[0] == pytest.approx(1.3 * 0.07 / 2, rel=1e-12)
    assert p.obj_v1[0] == pytest.approx(1.3 * 1.93 / 2, rel=1e-12)
    assert p.cue_speed == pytest.approx((K * 1.3 * 0.07 / 2 + 1.3) / (1 + K), rel=1e-12)
    assert p.obj_speed == pytest.approx(K * 1.3 * 1.93 / 2 / (1 + K), rel=1e-12)
    assert p.cue_dir == 0.0 and p.obj_dir == 0.0
    # oblique, frictionless: Newton's e along the line of centres; the object ball leaves along it (at +φ)
    q = fb.predict_shots(1.0, 0.4, f_bb=0.0, e=0.8, R=R, k=K)
    assert q.normal_e == pytest.approx(0.8, rel=1e-12)
    assert q.obj_dir == pytest.approx(0.4, abs=1e-12)
    assert q.cue_dir < 0
    # with friction: horizontal momentum is kept by the impact (the cloth takes vertical impulses only)
    v = np.array([0.5, 1.0, 2.0, 3.0])
    phi = np.radians([0.0, 20.0, 45.0, 70.0])
    r = fb.predict_shots(v, phi, f_bb=0.1, e=0.9, R=R, k=K)
    np.testing.assert_allclose(r.cue_v1[:, :2] + r.obj_v1[:, :2], np.stack([v, 0 * v], -1), atol=1e-12)
    np.testing.assert_allclose(r.cue_v1[:, 2], 0.0, atol=0)
    # law (6) on the cloth (spheres docstring): head on the friction keeps one direction (topspin only) and the slip
    # does not stop at f = 0.1, so the normal ratio is e exactly; a cut turns the slip, which moves it by ~f²·e/100
    assert r.normal_e[0] == pytest.approx(0.9, rel=1e-12)
    assert np.all(np.abs(r.normal_e[1:] - 0.9) < 1e-3)
    # e = 0 (ε = ε′ = 1): §I n°2 ends the impact at the greatest compression, equal normal velocities, any cut
    z = fb.predict_shots(v, phi, f_bb=0.1, e=0.0, R=R, k=K)
    np.testing.assert_allclose(z.normal_e, 0.0, atol=1e-12)
    # friction acts even full-ball: the topspin slips down the object ball, which takes backspin and so less speed
    assert r.obj_speed[0] < K * 1.93 / 2 / (1 + K) * 0.5 * 0.999
    # M and R drop out of the post-slip velocities
    s = fb.predict_shots(v, phi, f_bb=0.1, e=0.9, R=2 * R, k=K, M=0.3)
    np.testing.assert_allclose([s.cue_speed, s.obj_speed, s.cue_dir, s.obj_dir],
                               [r.cue_speed, r.obj_speed, r.cue_dir, r.obj_dir], rtol=1e-9, atol=1e-12)
    # the mirror shot (−φ) mirrors the directions
    m = fb.predict_shots(v, -phi, f_bb=0.1, e=0.9, R=R, k=K)
    np.testing.assert_allclose([m.cue_dir, m.obj_dir], [-r.cue_dir, -r.obj_dir], atol=1e-12)


@pytest.mark.parametrize("sigmas", [(SIG_SPEED, SIG_DIR), (None, None)])
def test_noiseless_shots_give_back_f_and_e(sigmas):
    cols = fb.synthetic_shots(np.random.default_rng(7), 12, f_bb=0.04, e=0.95, R=R, sigma_speed=0.0, sigma_dir=0.0)
    fit = fb.fit_columns(cols, R=R, sigma_speed=sigmas[0], sigma_dir=sigmas[1])
    assert fit.point == pytest.approx((0.04, 0.95), abs=1e-6)
    assert fit.identifiability.rank == 2 and all(e.identifiable for e in fit.estimates)
    res = fb.shot_residuals(fit.point, **cols, R=R)
    assert np.max(np.abs([res.cue_speed, res.cue_dir, res.obj_speed, res.obj_dir])) < 1e-6


def test_shot_residuals_are_predicted_minus_measured():
    cols = fb.synthetic_shots(np.random.default_rng(3), 5, R=R)
    p = fb.predict_shots(cols["v"], cols["phi"], f_bb=0.06, e=0.93, R=R)
    res = fb.shot_residuals((0.06, 0.93), **cols, R=R, sigma_speed=SIG_SPEED, sigma_dir=SIG_DIR)
    np.testing.assert_allclose(res.obj_speed, p.obj_speed - cols["obj_speed"], rtol=1e-12)
    np.testing.assert_allclose(res.cue_dir, p.cue_dir - cols["cue_dir"], rtol=1e-12)
    np.testing.assert_allclose(res.scaled[2], np.log(p.obj_speed / cols["obj_speed"]) / SIG_SPEED, rtol=1e-12)


def test_the_batched_fit_is_least_squares_fits_and_the_report_says_which_shots_count():
    data = [fb.synthetic_shots(np.random.default_rng([1, s]), 14, R=R) for s in range(3)]
    many = fb.fit_many(data, R=R)
    for cols, fit in zip(data, many, strict=True):
        one = fb.fit_columns(cols, R=R)
        assert one.point == pytest.approx(fit.point, abs=1e-8)  # the optimiser stops within 1e-9
        # the same weighted problem handed to least_squares_fit from a distant start: the same optimum and report
        w = 1 / np.repeat([fit.sigma_speed, fit.sigma_dir] * 2, 14)
        shots = fb._Shots(*(a[None] for a in fb._columns(*cols.values(), "relative")), {"R": R, "k": K, "M": 0.17},
                           "relative")
        res, jac = shots.functions(0, w)
        ref = fitting.least_squares_fit(res, (0.3, 0.5), fb.NAMES, fb.BOUNDS, jac=jac)
        assert ref.point == pytest.approx(fit.point, abs=2e-8)
        for a, b in zip(ref.estimates, fit.estimates, strict=True):
            assert a.stderr == pytest.approx(b.stderr, rel=1e-5)
        assert fit.noise == "estimated from residuals" and fit.reweight_converged
        assert fit.dof == 4 * 14 - 2
        assert sum(fit.f_bb_share) == pytest.approx(1.0) and sum(fit.e_share) == pytest.approx(1.0)
        assert set(fit.regime) == {1}  # every contact slips throughout at f_bb ≈ 0.06
        # no shot is idle for f_bb: with natural roll the contact slips at speed v whatever the cut
        assert min(fit.f_bb_share) > 0.1 / 14


def test_inconsistent_inputs_are_refused():
    cols = fb.synthetic_shots(np.random.default_rng(0), 4, R=R)
    with pytest.raises(InputError):
        fb.fit_columns(cols, R=R, sigma_speed=0.02)
    with pytest.raises(InputError):
        fb.fit_shots(cols["v"][:3], cols["phi"], cols["cue_speed"], cols["cue_dir"], cols["obj_speed"],
                     cols["obj_dir"], R=R)
    with pytest.raises(InputError):
        fb.predict_shots(1.0, math.pi / 2, f_bb=0.1, e=0.9, R=R)


def test_a_blank_value_weighs_nothing():
    """With σ given, the optimum with some values not measured is also the optimum when those values are filled in
    with their predictions there: they add no residual and no gradient (their rows are masked, not zero)."""
    cols = fb.synthetic_shots(np.random.default_rng(5), 12, R=R)
    holes = {"cue_dir": [0, 3], "obj_speed": [5], "cue_speed": [7, 8]}
    for c, i in holes.items():
        cols[c][i] = np.nan
    kw = {"R": R, "sigma_speed": 0.02, "sigma_dir": math.radians(0.5)}
    fit = fb.fit_columns(cols, **kw)
    assert fit.n_data == 48 - 5 and fit.n_speed == 21 and fit.n_dir == 22
    p = fb.predict_shots(cols["v"], cols["phi"], f_bb=fit.point[0], e=fit.point[1], R=R)
    filled = {**cols, **{c: np.where(np.isnan(cols[c]), getattr(p, c), cols[c]) for c in holes}}
    again = fb.fit_columns(filled, **kw, x0=(0.2, 0.7))
    assert again.point == pytest.approx(fit.point, abs=1e-7)  # the optimiser stops within 1e-9; 100× margin
    assert again.chi2 == pytest.approx(fit.chi2, rel=1e-6)


SEEDS = 400


@pytest.mark.parametrize("sigmas", [(SIG_SPEED, SIG_DIR), (None, None)], ids=["given-sigma", "estimated-sigma"])
def test_coverage_of_the_95_percent_intervals(sigmas):
    """v 0.5–3 m/s, φ 10°–60°, f_bb 0.06, e 0.93, speeds ×exp(0.02 z), directions +0.5° z: the fraction of
    seeds whose interval covers the generating value lies within [0.92, 0.98] for both parameters."""
    data = [fb.synthetic_shots(np.random.default_rng([2026, s]), 16, R=R) for s in range(SEEDS)]
    fits = fb.fit_many(data, R=R, sigma_speed=sigmas[0], sigma_dir=sigmas[1])
    for name, true in (("f_bb", 0.06), ("e", 0.93)):
        hits = [f.estimate(name).ci95[0] <= true <= f.estimate(name).ci95[1] for f in fits]
        assert 0.92 <= np.mean(hits) <= 0.98, (name, np.mean(hits))
    assert all(f.reweight_converged for f in fits)
