"""The §VI cloth's batch route after its speed-ups (issue 34, item 2): what each shortcut must leave unchanged.

- ``slip._series`` tests its truncation on every 4th row only (``slip._first``): the same rows as a test on
  every row, for classes and for columns of mixed c (c ≥ C_BIG included);
- ``slip._int_power`` (v^m* by products) and ``spheres._norm`` (|s| scaled) agree with np.power and np.hypot to an
  ulp or two, the same on numpy floats as on arrays;
- ``SlipWalk.settle`` with a table of coefficients per walk (k ≠ k′) compacts late: each walk's numbers are those
  it has alone, bit for bit; the walk's quadratic step settles where ``SlipDecay.at`` (plain Newton) does;
- ``_F`` on a column per element picks the branch per element, w = 1 exactly included;
- the end of impact on the cloth (``_cloth_guess``, ``_root_step``): homogeneous (k = k′) and heterogeneous batches
  give each scene what it gets alone (the scalar route) to rounding, and agree with the referee;
- ``slip._split_sum``'s powers by square roots where c0 is a multiple of ¼ (``_quarter_power``, ``_class_series``
  snapping a class to 5/4) are its exponentials' to a few ulps;
- the walk settled on its step left (``slip.WALK_ACCEPT``) moves the results by less than the iteration's
  tolerance, 1e-14, and leaves the outputs continuous across the regime boundary where ``resal stress`` found a
  jump of 4e-8 when ω too was accepted on a predicted last step;
- ``paths._scatter`` (rows as opaque items) and ``paths._roomy_heap`` change no byte.
"""

import numpy as np
import pytest

from reproductions import stress
from reproductions.mechanics import paths, registry, slip, spheres


def _rows_testing_every_row(c: np.ndarray) -> tuple[int, int]:
    """(Pfaff's rows, the split series' rows) of ``_series`` with its truncation tested at every row (the rule as
    written in its comments, kept here independently of ``_first``)."""
    big = c >= slip.C_BIG
    weight = np.where(big, 1.0 / c, 2 * np.sqrt(2.0))
    t, n_p = np.ones(c.shape), slip.N_PFAFF
    for n in range(slip.N_PFAFF - 1):
        t = t * ((n - 0.5) / (n + c + 1))
        if np.all(weight * np.abs(t) * np.where(big, n + 1 + c, 0.5 ** (n + 1)) <= 2.0**-56):
            n_p = n + 2
            break
    j = np.where(big, 0.0, np.maximum(np.ceil(c - slip.C_SERIES), 0.0))
    c0 = np.where(big, slip.C_SERIES, c - j)
    mstar, w2 = np.floor(c0 + 1), 2 ** (c0 + 1) * (c0 + 0.5)
    b, top, n_g = np.ones(c.shape), float(np.max(c0 + 1)), slip.N_SPLIT
    for m in range(slip.N_SPLIT):
        gm = np.where(mstar == m, 0.0, b / np.where(mstar == m, 1.0, m - c0 - 0.5))
        if m > top and float(np.max(w2 * np.abs(gm))) * 0.5**m <= 2.0**-56:
            n_g = m + 1
            break
        b = b * ((m + 1 - c0) / (m + 1))
    return n_p, n_g


@pytest.mark.parametrize("c", [np.array([1.25]), np.array([1e-9]), np.array([0.5]), np.array([2.9999999]),
                               np.array([3.0]), np.array([7.5]), np.array([15.5]), np.array([16.0]),
                               np.array([400.0]), np.linspace(0.75, 2.0, 301), np.array([0.3, 5.0, 17.0, 90.0])])
def test_series_truncation_tested_every_4th_row_ends_where_every_row_would(c):
    s = slip._series(c)
    assert (s.p.shape[0], s.g.shape[0]) == _rows_testing_every_row(c)


def test_series_truncation_mixed_columns_drawn():
    rng = np.random.default_rng(5)
    for _ in range(20):
        c = 10.0 ** rng.uniform(-3, 2.5, rng.integers(1, 50))
        s = slip._series(c)
        assert (s.p.shape[0], s.g.shape[0]) == _rows_testing_every_row(c)


@pytest.mark.parametrize("m", [1.0, 2.0, 3.0, 4.0])
def test_int_power_is_np_power_to_an_ulp_or_two_and_the_same_on_floats(m):
    v = np.random.default_rng(int(m)).uniform(1e-6, 0.5, 2000)
    got = slip._int_power(v, np.array([m]))
    assert np.max(np.abs(got / np.power(v, m) - 1)) <= 4 * np.finfo(float).eps
    mixed = np.random.default_rng(7).integers(1, 5, v.size).astype(float)
    assert np.max(np.abs(slip._int_power(v, mixed) / np.power(v, mixed) - 1)) <= 4 * np.finfo(float).eps
    one = slip._int_power(np.float64(v[3]), np.float64(m))
    assert one.__class__ is np.float64 and one == slip._int_power(v[3:4], np.array([m]))[0]


def test_norm_is_hypot_to_an_ulp_or_two_without_overflow_or_underflow():
    rng = np.random.default_rng(2)
    p = 10.0 ** rng.uniform(-250, 250, 5000)
    q = p * 10.0 ** rng.uniform(-20, 20, 5000)
    q[::7], p[::11] = 0.0, 0.0
    got, ref = spheres._norm(p, q), np.hypot(p, q)
    assert np.all((got == 0) == (ref == 0))
    assert np.max(np.abs(got[ref > 0] / ref[ref > 0] - 1)) <= 4 * np.finfo(float).eps
    assert spheres._norm(np.float64(0.0), np.float64(0.0)) == 0.0
    assert spheres._norm(np.float64(p[5]), np.float64(q[5])) == got[5]


def _hetero_decays(n: int, seed: int) -> tuple[slip.SlipDecay, np.ndarray]:
    """Decays of two balls on the cloth with k ≠ k′ (a column of coefficients per scene)."""
    rng = np.random.default_rng(seed)
    k, kp, mu = rng.uniform(1.5, 4.0, n), rng.uniform(1.5, 4.0, n), 10.0 ** rng.uniform(-1, 1, n)
    alpha, beta = (1 + k) + (1 + kp) * mu, k + kp * mu
    dec = slip.SlipDecay(rng.uniform(0.01, 3.0, n), rng.uniform(0.01, 3.0, n), alpha, beta)
    return dec, rng.uniform(0.0, 1.1, n) * dec.total


def test_a_table_walk_settles_each_walk_as_it_would_alone():
    dec, tau = _hetero_decays(400, 8)
    assert dec.series.p.shape[-1] == 400  # a table: the late compaction
    p, q, x, h = slip.SlipWalk(dec, dec.everyone, np.ones(tau.size), dec.total).settle(tau)
    for i in range(0, 400, 23):
        alone = slip.SlipWalk(dec, np.array([i]), np.ones(1), dec.total[[i]])
        assert alone.series.p.shape[-1] == 1
        got = alone.settle(tau[[i]])
        assert [a[0] for a in got] == [p[i], q[i], x[i], h[i]], i


def test_the_quadratic_walk_settles_where_the_newton_solve_does_on_tables():
    dec, tau = _hetero_decays(3000, 9)
    phi, psi, _ = dec.at(tau, dec.everyone)
    p, q, _, _ = slip.SlipWalk(dec, dec.everyone, np.ones(tau.size), dec.total).settle(tau)
    scale = np.hypot(dec.f0, dec.s0)
    assert np.max(np.abs(p - phi) / scale) < 1e-13 and np.max(np.abs(q - psi) / scale) < 1e-13


def test_F_on_a_column_per_element_picks_each_branch_w_one_included():
    c = np.array([0.8, 1.25, 1.9, 0.8, 1.25, 1.9, 2.5, 17.0])
    w = np.array([1.0, 1.0, 1.0, np.nextafter(1.0, 2), np.nextafter(1.0, 0), 7.0, 0.25, 40.0])
    got = slip._F(None, -w, slip._series(c))
    for i in range(c.size):
        one = slip._F(None, -w[i:i + 1], slip._class_series(float(c[i])))[0]
        assert got[i] == pytest.approx(one, rel=1e-15, abs=0), (c[i], w[i])
    # w = 1 is Pfaff's series (w ≤ 1), its neighbour above the split series: continuous to rounding
    assert got[0] == pytest.approx(slip._F(None, -np.array([np.nextafter(1.0, 2)]), slip._class_series(0.8))[0],
                                   rel=1e-14)


def _cloth_batch(n: int, hetero: bool, seed: int) -> dict:
    m = registry.MODELS["spheres-cloth"]
    s = m.sample(np.random.default_rng(seed), n)
    if hetero:
        rng = np.random.default_rng(seed + 1)
        s["k"], s["kp"] = rng.uniform(1.5, 4.0, n), rng.uniform(1.5, 4.0, n)
    return s


@pytest.mark.parametrize("hetero", [False, True])
def test_batches_give_each_scene_what_it_gets_alone(hetero):
    """Homogeneous (k = k′: one class of c) and heterogeneous batches against the scalar route scene by scene."""
    m = registry.MODELS["spheres-cloth"]
    s = _cloth_batch(60, hetero, 21)
    batch = paths.solve(m, m.scene(s), "exact")
    worst = 0.0
    for i in range(60):
        one = m.scene({k: (v if k in m.static else np.asarray(v)[i]) for k, v in s.items()})
        alone = paths.solve(m, one, "exact")
        for name in ("v1", "w1", "v1p", "w1p"):
            scale = abs(float(s["v"][i][0] - s["vp"][i][0])) * (1.0 if name[0] == "v" else 1 / 0.0305)
            worst = max(worst, float(np.max(np.abs(getattr(batch, name)[i] - getattr(alone, name)))) / scale)
        assert bool(batch.converged[i]) and bool(alone.converged)
    assert worst < 1e-12


@pytest.mark.parametrize("hetero", [False, True])
def test_batches_agree_with_the_referee(hetero):
    m = registry.MODELS["spheres-cloth"]
    s = _cloth_batch(24, hetero, 31)
    scene = m.scene(s)
    got = paths.solve(m, scene, "auto")
    assert float(np.max(m.error(scene, got, paths.solve(m, scene, "reference")))) < 1e-10


def test_F_on_a_laid_out_table_is_both_series_on_every_element_bit_for_bit():
    """``_F_blocks``: the columns laid out by series (``_layout``), elements whose w crossed 1 either way since
    (both kinds of misfit), c ≥ C_BIG among them: the same numbers as both series on every element."""
    rng = np.random.default_rng(12)
    n = 500
    c = np.where(rng.random(n) < 0.05, rng.uniform(16.0, 40.0, n), rng.uniform(0.3, 6.0, n))
    r2 = 10.0 ** rng.uniform(-2, 2, n)
    order, cut = slip._layout(c, r2)
    assert 0 < cut < n and np.all(np.diff((~((r2 <= 1) | (c >= slip.C_BIG)))[order].astype(int)) >= 0)
    table = slip._series(c[order])
    w = r2 * np.where(rng.random(n) < 0.8, rng.uniform(0.05, 1.0, n), rng.uniform(1.0, 3.0, n))  # some w > r2
    w[::17] = 1.0
    got = slip._F(None, -w, table, (order, cut))
    col = np.empty(n, dtype=np.intp)
    col[order] = np.arange(n)
    plain = slip._F(None, -w, slip._take(table, col))  # the table in the elements' order, no layout
    assert np.array_equal(got, plain)


def test_a_walk_on_some_scenes_of_a_table_is_each_walk_alone():
    dec, tau = _hetero_decays(300, 13)
    idx = np.flatnonzero(np.random.default_rng(1).random(300) < 0.6)[::-1].copy()  # a subset, out of order
    walk = slip.SlipWalk(dec, idx, np.ones(idx.size), dec.total[idx])
    p, q, x, h = walk.settle(tau[idx])
    for j in range(0, idx.size, 17):
        i = idx[j]
        got = slip.SlipWalk(dec, np.array([i]), np.ones(1), dec.total[[i]]).settle(tau[[i]])
        assert [a[0] for a in got] == [p[j], q[j], x[j], h[j]], i


@pytest.mark.parametrize("e4", list(range(-13, 14)))
def test_quarter_power_is_np_power_to_an_ulp_or_two(e4):
    """``slip._quarter_power`` (x^(e4/4) by √ and ∜) against np.power, arrays and numpy floats alike."""
    x = 10.0 ** np.random.default_rng(e4 + 20).uniform(-12, 12, 3000)
    got = slip._quarter_power(x, e4)
    assert np.max(np.abs(got / np.power(x, e4 / 4) - 1)) <= 6 * np.finfo(float).eps
    one = slip._quarter_power(np.float64(x[7]), e4)
    assert one.__class__ is np.float64 and one == got[7]


@pytest.mark.parametrize("c", [0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.25, 2.5, 3.0, 5.25])
def test_split_sum_by_square_roots_is_the_exponentials_to_rounding(c, monkeypatch):
    """``_split_sum`` on a c that is a multiple of ¼ (powers by square roots) against the same series with its
    powers by exp and log (``_quarters`` switched off): F to a few ulps, w from 1 to 1e300."""
    s = slip._class_series(c)
    assert slip._quarters(s.c - s.j, s.estar) is not None
    w = np.concatenate([1 + np.linspace(0, 1e-6, 50), 10.0 ** np.linspace(0, 300, 3000)])
    fast = slip._split_sum(w, s)
    one = slip._split_sum(np.float64(w[100]), slip._class_scalars(c))
    monkeypatch.setattr(slip, "_quarters", lambda c0, es: None)
    slow = slip._split_sum(w, s)
    assert np.max(np.abs(fast / slow - 1)) <= 8 * np.finfo(float).eps
    assert one == pytest.approx(slow[100], rel=8 * np.finfo(float).eps, abs=0)


def test_class_series_snaps_to_a_quarter_within_a_class_rounding_only():
    """k = k′ = 5/2 on the cloth gives c = 5/4 to some ulps: the class's series is at 5/4 itself (square roots);
    a c farther than a class's rounding keeps its own value (exponentials)."""
    near = 1.25 + 4 * np.spacing(1.25)
    assert float(slip._class_series(near).c[0]) == 1.25
    far = 1.25 + 1e-12
    s = slip._class_series(far)
    assert float(s.c[0]) == far and slip._quarters(s.c - s.j, s.estar) is None
    assert float(slip._class_series(1e-300).c[0]) == 1e-300  # (no quarter at 0)


@pytest.mark.parametrize("hetero", [False, True])
def test_the_walks_early_end_moves_results_below_the_tolerance(hetero, monkeypatch):
    """The walk settled on its step left (``slip.WALK_ACCEPT``) against the walk with that switched off (steps
    until ``_solved``): ω1 to 1e-14 of itself, the velocities to 1e-14 of the approach speed."""
    m = registry.MODELS["spheres-cloth"]
    s = _cloth_batch(3000, hetero, 41)
    scene = m.scene(s)
    fast = paths.solve(m, scene, "auto")
    monkeypatch.setattr(slip, "WALK_ACCEPT", 0.0)
    slow = paths.solve(m, scene, "auto")
    assert fast.converged.all() and slow.converged.all()
    assert np.max(np.abs(fast.omega1 - slow.omega1) / np.abs(slow.omega1)) <= 1e-14
    scale = np.abs(s["v"][:, 0] - s["vp"][:, 0])[:, None]
    for name, r in (("v1", 1.0), ("w1", 0.0305), ("v1p", 1.0), ("w1p", 0.0305)):
        assert np.max(np.abs(getattr(fast, name) - getattr(slow, name)) * r / scale) <= 1e-14, name
    # and one scene (the scalar route) stops where its batch does, to rounding
    for i in range(0, 3000, 311):
        one = m.scene({k: (v if k in m.static else np.asarray(v)[i]) for k, v in s.items()})
        alone = paths.solve(m, one, "auto")
        assert float(alone.omega1) == pytest.approx(float(slow.omega1[i]), rel=1e-14, abs=0)


def test_scatter_of_rows_is_fancy_assignment():
    """``paths._scatter`` (rows moved as opaque items) puts the same bytes as ``out[idx] = v``."""
    rng = np.random.default_rng(3)
    n = 1000
    idx = np.flatnonzero(rng.random(n) < 0.7)
    for v in (rng.random((idx.size, 3)), rng.random((idx.size, 2)), rng.random(idx.size) < 0.5,
              rng.integers(0, 3, idx.size).astype(np.int8), rng.random((idx.size, 3))[:, :2]):
        out, want = np.zeros((n, *v.shape[1:]), v.dtype), np.zeros((n, *v.shape[1:]), v.dtype)
        paths._scatter(out, idx, v)
        want[idx] = v
        assert out.tobytes() == want.tobytes()


def test_the_roomy_heap_changes_no_number():
    m = registry.MODELS["spheres-cloth"]
    scene = m.scene(_cloth_batch(500, False, 5))
    before = paths.solve(m, scene, "auto")
    paths._roomy_heap()
    after = paths.solve(m, scene, "auto")
    assert paths._heap[0]
    for name in ("v1", "w1", "v1p", "w1p", "omega1"):
        assert getattr(before, name).tobytes() == getattr(after, name).tobytes()


def test_no_jump_at_the_regime_boundaries_stress_bisected():
    """``resal stress spheres-cloth --scenes 20000 --seed 14``'s boundary pairs, bisected to 2⁻⁵² apart: continuous
    to 1e-9 on both sides for the exact path and auto, all converged. An ω accepted on a step predicted to be the
    last (cubic convergence assumed) broke this by 4e-8 where G has a kink (the slip stopping at the impact's end);
    before ``spheres._cloth_bisect``, the iteration itself cycled there (not-converged)."""
    rep = stress.run(["spheres-cloth"], scenes=20_000, ode_scenes=2, referee_scenes=5, seed=14, jobs=1)
    rows = {r["path"]: r for r in rep["models"][0]["rows"]}
    for path in ("exact", "auto"):
        assert rows[path]["boundary_pairs"] > 100 and not rows[path]["failures"], (path, rows[path]["failures"])
