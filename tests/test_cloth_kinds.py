"""§VI on the cloth, a batch of balls of a few kinds (k, k′ and the masses of a few values, as in a real set of
balls): ``slip.classes`` groups its scenes by the slip decay's c, and ``spheres._cloth_by_class`` solves each group
as a batch of one class (its ₂F₁ coefficients broadcast) instead of one table with a column per scene. The
grouping must be a partition into classes, must change no scene's numbers beyond the rounding of its ₂F₁ (each
scene gets what it gets in a batch of its class: alone where its class has one c), and must keep the referee's
agreement."""

import numpy as np
import pytest

from reproductions.mechanics import paths, registry, slip, spheres

MODEL = registry.model("spheres-cloth")
OUT = ("omega1", "v1", "w1", "v1p", "w1p", "T", "s_c")
# three kinds of ball (mass kg, MR²/I): a set's object balls, a lighter one, a heavier cue ball of another make
KINDS = ((0.170, 2.5), (0.156, 2.5), (0.210, 2.2))


def _values(n, seed=3, kinds=KINDS):
    s = MODEL.sample(np.random.default_rng(seed), n)
    r = np.random.default_rng(seed + 1)
    a, b = r.integers(0, len(kinds), n), r.integers(0, len(kinds), n)
    mass, k = np.array([m for m, _ in kinds]), np.array([k for _, k in kinds])
    return dict(s, M=mass[a], k=k[a], Mp=mass[b], kp=k[b])


def _c(v):
    """c of the slip decay from first principles (§VI: α = M c_y, β = M c_z on the cloth, c = b/(2(a − b)))."""
    al = (1 + v["k"]) + v["M"] / v["Mp"] * (1 + v["kp"])
    be = v["k"] + v["M"] / v["Mp"] * v["kp"]
    a, b = np.maximum(al, be), np.minimum(al, be)
    return b / (2 * (a - b))


def _alpha_beta(v):
    M, Mp, k, kp = (np.asarray(v[x], dtype=float) for x in ("M", "Mp", "k", "kp"))
    return M * ((1 + k) / M + (1 + kp) / Mp), M * (k / M + kp / Mp)  # as spheres.two_spheres builds them


def test_classes_partition_a_batch_of_kinds_into_classes_of_c():
    v = _values(40_000)
    groups = slip.classes(*_alpha_beta(v))
    assert groups is not None
    every = np.sort(np.concatenate(groups))
    assert np.array_equal(every, np.arange(40_000))  # a partition
    c = _c(v)
    mids = []
    for g in groups:
        assert np.all(np.diff(g) > 0)  # each group in the batch's order
        assert np.ptp(c[g]) <= 1e-13 * np.max(c[g])  # one class: its c the same to rounding
        mids.append(float(np.median(c[g])))
    # as many groups as distinct c (to rounding) among the 9 pairs of kinds: c = (k M′ + k′ M)/(2(M + M′)) is
    # symmetric in the two balls, and k = k′ makes it k/2 whatever the masses: 1.25 (4 pairs), 1.1, and two mixed
    distinct = np.unique(np.round(_c({"k": np.repeat([x[1] for x in KINDS], 3), "kp": np.tile([x[1] for x in KINDS], 3),
                                      "M": np.repeat([x[0] for x in KINDS], 3),
                                      "Mp": np.tile([x[0] for x in KINDS], 3)}), 12))
    assert len(groups) == distinct.size == 4
    assert mids == sorted(mids)


@pytest.mark.parametrize("case", ["small", "one class", "every scene its own c", "too many kinds"])
def test_classes_leave_a_batch_whole_where_splitting_would_not_pay(case):
    if case == "small":  # below 2 CLASS_MIN scenes: one call
        v = _values(2 * slip.CLASS_MIN - 1)
    elif case == "one class":  # k = k′: c = k/2 for every mass
        v = dict(_values(3 * slip.CLASS_MIN), k=np.full(3 * slip.CLASS_MIN, 2.5), kp=np.full(3 * slip.CLASS_MIN, 2.5))
    elif case == "every scene its own c":
        n = 3 * slip.CLASS_MIN
        r = np.random.default_rng(9)
        v = dict(_values(n), k=r.uniform(1.5, 4.0, n), kp=r.uniform(1.5, 4.0, n))
    else:  # 8 kinds, 64 pairs, in a batch with fewer than CLASS_MIN scenes per pair on average
        kinds = tuple((0.15 + 0.01 * i, 2.0 + 0.1 * i) for i in range(8))
        v = _values(20 * slip.CLASS_MIN, kinds=kinds)
    assert slip.classes(*_alpha_beta(v)) is None


def test_classes_of_few_scenes_go_together_as_one_table():
    """Three kinds of ball, and a few scenes of a rare fourth: its classes (each under CLASS_FEW scenes) are one
    group, last, left to the table of columns; the frequent classes keep a group each."""
    v = _values(30_000)
    rare = np.arange(0, 30_000, 97)  # 310 scenes: the cue ball of another set
    v["M"][rare], v["k"][rare] = 0.180, 2.3
    groups = slip.classes(*_alpha_beta(v))
    assert groups is not None and len(groups) == 5
    assert np.array_equal(np.sort(np.concatenate(groups)), np.arange(30_000))
    assert all(g.size >= slip.CLASS_FEW for g in groups[:-1])
    assert set(rare.tolist()) <= set(groups[-1].tolist())  # the rare classes, together in the last
    c = _c(v)
    assert np.unique(np.round(c[groups[-1]], 12)).size >= 2  # … several classes in it: a table


def _solve_whole(monkeypatch, scene):
    """The same batch through one table (no grouping): the route before ``slip.classes``."""
    with monkeypatch.context() as mp:
        mp.setattr(spheres, "classes", lambda alpha, beta: None)
        return paths.solve(MODEL, scene, "exact")


def test_a_batch_of_kinds_gives_each_scene_its_numbers_alone_and_the_tables_to_rounding(monkeypatch):
    v = _values(24_000)
    scene = MODEL.scene(v)
    calls = []
    real = spheres._cloth_by_class
    monkeypatch.setattr(spheres, "_cloth_by_class", lambda g, *a: calls.append(len(g)) or real(g, *a))
    grouped = paths.solve(MODEL, scene, "exact")
    assert calls == [4]  # the grouped route ran (the test is not about a batch that was left whole)
    assert bool(np.all(grouped.converged))
    whole = _solve_whole(monkeypatch, scene)
    speed = np.abs(v["v"][:, 0] - v["vp"][:, 0])  # the approach speed, the scale of every output velocity
    for name in ("v1", "v1p"):
        d = np.max(np.abs(getattr(grouped, name) - getattr(whole, name)), axis=-1) / speed
        assert np.max(d) <= 1e-13, name  # the table's columns and the class's broadcast row: ₂F₁'s rounding
    # scene by scene, alone (the one-scene route), spread over the batch and over the kinds: bit for bit where the
    # scene's group has one c (exactly), else within the class's rounding, as in any batch of one class: the group
    # takes the middle of its c, a scene alone its own (the mixed pairs, c computed from (M, k) and (M′, k′) in
    # either order, come out a few ulps apart)
    al, be = _alpha_beta(v)
    a, b = np.maximum(al, be), np.minimum(al, be)
    c = b / (2 * (a - b))  # as ``slip.classes`` computes it
    group = {int(i): g for g in slip.classes(al, be) for i in g}
    exact = rounding = 0
    for i in np.random.default_rng(5).choice(24_000, 80, replace=False):
        one = paths.solve(MODEL, MODEL.scene({k: (x if k in MODEL.static else np.asarray(x)[i].tolist())
                                              for k, x in v.items()}), "exact")
        if np.unique(c[group[int(i)]]).size == 1:
            exact += 1
            for name in OUT:
                assert np.array_equal(np.asarray(getattr(grouped, name))[i], np.asarray(getattr(one, name))), (i, name)
        else:
            rounding += 1
            assert abs(float(grouped.omega1[i]) / float(one.omega1) - 1) <= 8 * np.finfo(float).eps, i
    assert exact >= 10 and rounding >= 20  # both cases met (these draws: 13 and 67)


def test_a_batch_of_kinds_agrees_with_the_referee():
    v = _values(8 * slip.CLASS_MIN, seed=12)
    got = paths.solve(MODEL, MODEL.scene(v), "auto")
    pick = np.random.default_rng(2).choice(v["M"].size, 12, replace=False)
    sub = {k: (x if k in MODEL.static else np.asarray(x)[pick]) for k, x in v.items()}
    ref = paths.solve(MODEL, MODEL.scene(sub), "reference")
    speed = np.abs(sub["v"][:, 0] - sub["vp"][:, 0])
    for name in ("v1", "v1p"):
        d = np.max(np.abs(np.asarray(getattr(got, name))[pick] - getattr(ref, name)), axis=-1) / speed
        assert np.max(d) <= 1e-10, name  # the bench's bound on §VI against the referee
