"""The cheap parts of one scene's route through ``paths.solve`` (issue 34, item 1): the helpers that stand for numpy's
calls on numpy floats (``paths.maximum``, ``paths.minimum``, ``paths.codes`` of one scene), the result assembly
without the frozen ``__init__`` (``paths.result``) and the short route of ``Model.scene`` for one scene. Each must
give what the call it replaces gives: the same numbers to the bit, types, dtypes and flags."""

import dataclasses
import itertools

import numpy as np
import pytest
from bitwise import same as _same

from reproductions.mechanics import cue, cushion, impact, paths, plane, registry, timing

SPECIAL = [0.0, -0.0, 1.0, -1.0, 2.5, -2.5, 5e-324, -5e-324, np.inf, -np.inf, np.nan, -np.nan]


@pytest.mark.parametrize("mine,numpys", [(paths.maximum, np.maximum), (paths.minimum, np.minimum)])
def test_maximum_and_minimum_are_numpys_own_choice(mine, numpys):
    """On numpy floats, ±0 ties and nan from either side included; arrays and mixed arguments go to numpy."""
    for a, b in itertools.product(SPECIAL, repeat=2):
        want = numpys(np.float64(a), np.float64(b))
        got = mine(np.float64(a), np.float64(b))
        assert type(got) is type(want) is np.float64, (a, b)
        assert np.asarray(got).tobytes() == np.asarray(want).tobytes(), (a, b, got, want)
    x = np.array(SPECIAL)
    for a, b in ((x, x[::-1]), (x, np.float64(0.0)), (np.float64(-0.0), x), (np.asarray(1.0), np.float64(2.0))):
        want, got = numpys(a, b), mine(a, b)
        assert type(got) is type(want) and np.asarray(got).tobytes() == np.asarray(want).tobytes()


def test_codes_of_one_scene_is_a_new_array_as_np_full_gives():
    for code in (*paths.PathCode, *paths.Regime):
        got, want = paths.codes((), code), np.full((), int(code), dtype=np.int8)
        assert type(got) is np.ndarray and got.dtype == want.dtype and got.shape == () and got == want
        assert got.flags.writeable and got.flags.owndata
        assert paths.codes((), code) is not got
    a = paths.codes((), paths.PathCode.EXACT)
    a[...] = 9  # the caller's own array: another call is not changed
    assert paths.codes((), paths.PathCode.EXACT) == paths.PathCode.EXACT
    assert paths.codes((2,), paths.Regime.GRIP).tolist() == [2, 2]


RESULTS = [impact.DirectImpact, impact.WallImpact, plane.PlaneImpact, cushion.CushionImpact, cue.CueStroke]


@pytest.mark.parametrize("kind", RESULTS)
def test_result_builds_what_the_dataclass_init_builds(kind):
    values = {f.name: (f"text {i}" if f.type == "str" else np.full(2, float(i)))
              for i, f in enumerate(dataclasses.fields(kind))}
    got, want = paths.result(kind, **values), kind(**values)
    assert type(got) is kind and got.__dict__.keys() == want.__dict__.keys()
    assert list(got.__dict__) == [f.name for f in dataclasses.fields(kind)]
    _same(got, want, kind.__name__)
    with pytest.raises(dataclasses.FrozenInstanceError):
        got.method = "x"
    assert repr(got) == repr(want)


def _cheap(m):
    return [p for p in m.paths if p.cost < 1000]


@pytest.mark.parametrize("name", list(registry.MODELS))
def test_every_result_carries_its_fields_in_their_order(name):
    """The results ``paths.result`` assembles have every field of their dataclass, nothing else, in order: on one
    scene (both routes, numpy floats and arrays) and on a batch, by every closed-form path that handles them."""
    m = registry.MODELS[name]
    raw = m.sample(np.random.default_rng(3), 8)
    scenes = [m.scene(raw)] + [m.scene({k: (v if k in m.static else np.asarray(v)[i]) for k, v in raw.items()})
                               for i in range(8)]
    checked = 0
    with np.errstate(all="ignore"):
        for s in scenes:
            for p in _cheap(m):
                if not (np.all(p.handles(s)) and np.all(m.admissible(s))):
                    continue
                for res in (paths.solve(m, s, p.name), paths.by_route(m, s, p.name, "small"), paths.solve(m, s)):
                    assert list(res.__dict__) == [f.name for f in dataclasses.fields(res)], (name, p.name)
                    checked += 1
    assert checked


@pytest.mark.parametrize("name", list(registry.MODELS))
def test_the_scene_of_one_scene_is_the_scene_the_general_route_builds(name):
    """``Model.scene`` for numbers only: every parameter in the declared order after ONES, the defaults the plan's
    own shared arrays, the numbers given as 0-d float arrays, a caller's 0-d array as a read-only view of it."""
    m = registry.MODELS[name]
    plan = m._plan
    values = timing.n1_scene(m)
    given = next(k for k in (p.name for p in m.params) if k not in m.vectors and k not in m.static)
    own = np.array(float(values.get(given, plan.defaults[given])))  # a writeable 0-d array of the caller
    for vals in (values, dict(values, **{given: own}), dict(values, **{given: 3})):
        s = m.scene(vals)
        assert list(s) == [paths.ONES, *(p.name for p in m.params)]
        assert s[paths.ONES].shape == () and s[paths.ONES].dtype == bool and bool(s[paths.ONES])
        for p in m.params:
            a = s[p.name]
            assert type(a) is np.ndarray and a.dtype == np.float64
            assert a.shape == ((3,) if p.name in m.vectors else ())
            if p.name not in vals and p.name not in m.vectors and p.name not in m.static:
                assert a is plan.defaults[p.name]
            if p.name == given and vals.get(given) is own:
                assert a is not own and a.base is own and not a.flags.writeable
                assert own.flags.writeable  # the caller's array itself stays writeable
        one = m.scene({k: np.reshape(np.asarray(v, dtype=float), (1, *np.shape(v))) if k not in m.static else v
                       for k, v in vals.items()})
        for k in s:  # the batch of one holds the same numbers
            assert np.array_equal(np.reshape(one[k], np.shape(s[k])), s[k])
