"""``slip.SlipWalk`` (the §VI end of impact's one-step-per-iteration walk of the slip decay, n°13) against
``SlipDecay.at`` (``_solve_x`` to convergence): the same slip after the same impulse, and the walk's convergence."""

import numpy as np

from reproductions.mechanics import slip


def _decays(n: int, seed: int) -> tuple[slip.SlipDecay, np.ndarray]:
    rng = np.random.default_rng(seed)
    phi0, psi0 = rng.uniform(0.01, 5.0, n), rng.uniform(0.01, 5.0, n)
    beta = rng.uniform(0.5, 40.0, n)
    alpha = beta * rng.uniform(1.05, 30.0, n)
    return slip.SlipDecay(phi0, psi0, alpha, beta), rng.uniform(0.0, 1.2, n)


def test_the_walk_settles_where_the_newton_solve_does():
    dec, frac = _decays(2000, 3)
    tau = frac * dec.total  # past H(1) for some: the slip stops
    phi, psi, _ = dec.at(tau, dec.everyone)
    walk = slip.SlipWalk(dec, dec.everyone, np.ones(dec.total.size), dec.total)
    p, q, x, h = walk.settle(tau)
    scale = np.hypot(dec.f0, dec.s0)
    assert np.max(np.abs(p - phi) / scale) < 1e-13 and np.max(np.abs(q - psi) / scale) < 1e-13
    stopped = tau >= dec.total
    assert np.all(p[stopped] == 0) and np.all(q[stopped] == 0) and np.all(x[stopped] == 0)
    assert np.all(h[~stopped] > 0)


def test_a_walk_follows_a_moving_impulse_from_a_warm_start():
    dec, frac = _decays(500, 4)
    tau = 0.5 * frac * dec.total
    _, _, x, h = slip.SlipWalk(dec, dec.everyone, np.ones(tau.size), dec.total).settle(tau)
    walk = slip.SlipWalk(dec, dec.everyone, x, h)
    moved = tau * 1.01
    for _ in range(slip.NEWTON_MAXITER):
        p, q, settled = walk.advance(moved)
        if settled.all():
            break
    phi, psi, _ = dec.at(moved, dec.everyone)
    assert settled.all()
    scale = np.hypot(dec.f0, dec.s0)
    assert np.max(np.abs(p - phi) / scale) < 1e-13 and np.max(np.abs(q - psi) / scale) < 1e-13
