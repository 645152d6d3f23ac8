"""One scene of the two-ball models (§V n°12, §VI n°13) through ``paths.solve(…, "auto")`` (issue 34, item 1): the
cheapest path that does not take the scene (Résal's §VI approximation, exact only without friction or slip) is
judged on the scene's numpy floats and the next path runs on them, without the batch route's arrays; the helpers
that stand for numpy's calls on one scene give numpy's own numbers; ``Model.scene``'s one-scene route for models
with vectors builds what its general route builds."""

import numpy as np
import pytest
from bitwise import same as _same

from reproductions.mechanics import paths, registry, spheres

SPECIAL = [0.0, -0.0, 1.0, -1.0, 2.5, -2.5, 5e-324, -5e-324, np.inf, -np.inf, np.nan, -np.nan]
VALUES = [
    {"v": [1.0, 0.2, 0.0], "f": 0.2, "eps": 0.3, "epsp": 0.4},  # Résal's §VI path is not exact: the exact path
    {"v": [1.0, 0.2, 0.0], "f": 0.0, "eps": 0.3, "epsp": 0.4},  # no friction: Résal's path is exact
    {"v": [1.0, 0.0, 0.0], "f": 0.2, "eps": 0.3, "epsp": 0.4},  # no slip: Résal's path is exact
    {"v": [1.5, 0.4, 0.0], "w": [3.0, 25.0, -8.0], "wp": [0.0, -4.0, 2.0], "f": 0.25, "eps": 0.6, "epsp": 0.2},
]


@pytest.mark.parametrize("model", ["spheres-free", "spheres-cloth"])
@pytest.mark.parametrize("values", VALUES)
def test_one_scene_takes_no_batch_arrays_and_gives_the_batch_numbers(model, values, monkeypatch):
    m = registry.MODELS[model]
    for shape in ((), (1,)):
        s = m.scene({k: np.reshape(np.asarray(x, dtype=float), (*shape, *np.shape(x))) for k, x in values.items()})
        want = paths.auto_by_masks(m, s)

        def flat(*_args, **_kw):
            raise AssertionError("one scene flattened into batch arrays")

        monkeypatch.setattr(paths, "_flatten", flat)
        got = paths.solve(m, s, "auto")
        monkeypatch.undo()
        _same(got, want, f"{model} {values} {shape}")
        assert got.label.startswith("auto: 1 by ")


def test_sign_is_numpys_own():
    for x in SPECIAL:
        got, want = spheres._sign(np.float64(x)), np.sign(np.float64(x))
        assert type(got) is type(want) is np.float64
        assert np.asarray(got).tobytes() == np.asarray(want).tobytes(), x


def test_the_bracket_test_of_one_scene_is_the_arrays_test():
    for nxt in SPECIAL:
        for lo, hi in ((-1.0, 1.0), (0.0, 3.0), (-np.inf, np.inf), (np.nan, 1.0)):
            one = spheres._inside(np.float64(nxt), np.float64(lo), np.float64(hi))
            arr = spheres._inside(np.array([nxt]), np.array([lo]), np.array([hi]))
            assert bool(one) == bool(arr[0]), (nxt, lo, hi)


@pytest.mark.parametrize("model", ["spheres-free", "spheres-cloth"])
def test_one_scene_with_vectors_is_the_scene_of_the_general_route(model):
    """The one-scene route of ``Model.scene`` against a batch of one taken back to shape (): the same keys in the
    same order, values, dtypes and shapes; read-only views of the caller's arrays; defaults shared."""
    m = registry.MODELS[model]
    w = np.array([0.0, 1.0, 2.0])
    values = {"v": [1.0, 0.2, 0.0], "w": w, "wp": 0.0, "M": np.float64(0.3), "f": 0.2, "eps": 0.3, "epsp": 0.4}
    s = m.scene(values)
    batch = m.scene({k: np.reshape(np.asarray(x, dtype=float), (1, *np.shape(x))) for k, x in values.items()})
    assert list(s) == list(batch)
    for k, a in s.items():
        b = batch[k]
        assert type(a) is np.ndarray and a.dtype == b.dtype and a.shape == b.shape[1:], k
        np.testing.assert_array_equal(a, b[0])
    assert np.shares_memory(s["w"], w) and not s["w"].flags.writeable
    assert s["vp"] is m.scene(values)["vp"] and not s["vp"].flags.writeable


def _bytes(x):
    return np.asarray(x, dtype=float).tobytes()


def test_hypot_of_one_scene_is_numpys_own():
    """``spheres._hypot`` on numpy floats (the magnitude itself where one of them is ±0) against ``np.hypot``."""
    values = [*SPECIAL, 3.0, -4.0, 1e-310, -1e300, 1.7976931348623157e308]
    for a in values:
        for b in values:
            with np.errstate(all="ignore"):
                got, want = spheres._hypot(np.float64(a), np.float64(b)), np.hypot(np.float64(a), np.float64(b))
            assert type(got) is type(want) is np.float64
            assert _bytes(got) == _bytes(want), (a, b)
    rng = np.random.default_rng(3)
    x = rng.standard_normal(2000) * 10.0 ** rng.uniform(-310, 300, 2000)
    for a in x:
        for b in (0.0, -0.0):
            assert _bytes(spheres._hypot(np.float64(a), np.float64(b))) == _bytes(np.hypot(a, b)), a
            assert _bytes(spheres._hypot(np.float64(b), np.float64(a))) == _bytes(np.hypot(b, a)), a


def test_norm_quiet_and_ends_of_one_scene_are_the_arrays_own():
    """``_norm``'s inline choice of the larger and the smaller, and the stop tests ``_quiet`` and ``_ends`` taken
    in turn, on numpy floats, against the same functions on arrays (every pair of special values)."""
    values = [0.0, -0.0, 1.0, 2.5, 1e-320, 1e300, np.inf, np.nan]
    for p in values:
        for q in values:
            with np.errstate(all="ignore"):
                one = spheres._norm(np.float64(p), np.float64(q))
                arr = spheres._norm(np.array([p]), np.array([q]))[0]
            assert type(one) is np.float64 and _bytes(one) == _bytes(arr), (p, q)
            g, noise = np.float64(p) - 1.0, np.float64(q)
            assert bool(spheres._quiet(g, noise)) == bool(spheres._quiet(np.array([g]), np.array([noise]))[0])
            for quiet in (False, True):
                args = (np.float64(p), np.float64(q), quiet, np.float64(q), np.float64(p))
                with np.errstate(all="ignore"):
                    want = spheres._ends(*(np.array([a]) for a in args))[0]
                    got = spheres._ends(*args)
                assert bool(got) == bool(want), (p, q, quiet)


def test_root_step_and_guess_of_one_scene_take_the_arrays_branch():
    """``_root_step`` and ``_cloth_guess`` compute only the branch they take on numpy floats: the arrays' numbers."""
    values = [-2.0, -0.0, 0.0, 0.5, 3.0]
    for g in values:
        for slope in values:
            for curve in values:
                with np.errstate(all="ignore"):
                    one = spheres._root_step(np.float64(g), np.float64(slope), np.float64(curve))
                    arr = spheres._root_step(np.array([g]), np.array([slope]), np.array([curve]))[0]
                assert _bytes(one) == _bytes(arr), (g, slope, curve)
    rng = np.random.default_rng(5)
    coef = tuple(rng.uniform(0.1, 2.0, 5))
    for _ in range(200):
        x = rng.uniform(-1.0, 1.0, 10)  # G(ω_c), ω_c, the slip's a_c, b_c, Y_c, Z_c, Δ, f, α, β
        x[0] = -abs(x[0])  # G(ω_c) < 0
        x[2:4] = abs(x[2:4]) * (rng.random(2) > 0.2)  # a stopped slip too
        hi = x[1] + 5.0
        with np.errstate(all="ignore"):
            one = spheres._cloth_guess(*map(np.float64, x), tuple(map(np.float64, coef)), np.float64(hi))
            arr = spheres._cloth_guess(*(np.array([a]) for a in x), tuple(np.array([c]) for c in coef),
                                       np.array([hi]))[0]
        assert type(one) is np.float64 and _bytes(one) == _bytes(arr), x


def test_the_exactness_of_resals_cloth_path_is_f_zero_or_no_slip_one_scene_and_batch():
    """``registry._cloth_resal_exact`` (f = 0, or both slip components 0; one scene: the slip only where f ≠ 0)
    against its definition, f = 0 or hypot of the slip = 0, on special values of every slip term, in a batch and
    scene by scene (numpy bools there)."""
    m = registry.MODELS["spheres-cloth"]
    rng = np.random.default_rng(8)
    n = 4000
    pick = lambda *shape: rng.choice(SPECIAL, size=shape)  # noqa: E731
    vals = {"v": np.c_[rng.uniform(0.5, 2.0, n), pick(n), np.zeros(n)], "w": pick(n, 3),
            "vp": np.c_[np.zeros(n), pick(n), np.zeros(n)], "wp": pick(n, 3), "f": rng.choice([0.0, -0.0, 0.2], n),
            "eps": np.full(n, 0.3), "epsp": np.full(n, 0.4)}
    s = m.scene(vals)
    with np.errstate(invalid="ignore"):  # (inf − inf in the slip: nan, not 0)
        sy, sz = spheres.contact_slip_yz(s["v"], s["w"], s["vp"], s["wp"], s["R"], s["Rp"])
        want = (np.asarray(s["f"]) == 0) | (np.hypot(sy, sz) == 0)
        assert want.any() and not want.all()
        assert np.array_equal(registry._cloth_resal_exact(s), want)
        for i in range(0, n, 7):
            one = paths._one(m, m.scene({k: v[i] for k, v in vals.items()}))
            got = registry._cloth_resal_exact(one)
            assert got.__class__ is np.bool_ and got == want[i], i
