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
