"""The two routes of ``paths.solve(…, "auto")`` give the same numbers, bit for bit (issue 22).

The small-batch route runs the one path that serves every scene once, without masks or merge, and for a single
scene of a path that declares ``scalar`` runs it on the scene's numpy floats (numpy's scalar arithmetic, not its
array loops). The general route lets each path take, cheapest first, the scenes left to it. Both run the same
functions, so they must agree exactly: every model × every path, single scenes (batch shape () and (1,)) and
batches, then ``auto`` itself, and the refusals.
"""


import numpy as np
import pytest
from bitwise import same as _same

from reproductions.mechanics import paths, registry
from reproductions.mechanics.paths import PathCode, PathError

PAIRS = [(m.name, p.name) for m in registry.MODELS.values() for p in m.paths]


def _singles(m, values, shape):
    """Each scene of the sampled ``values`` alone, with the batch shape () or (1,)."""
    n = len(next(v for k, v in values.items() if k not in m.static))
    for i in range(n):
        one = {}
        for k, v in values.items():
            v = np.asarray(v)
            if k in m.static:
                one[k] = v
            elif shape == ():
                one[k] = v[i].tolist() if k in m.vectors else float(v[i])
            else:
                one[k] = v[i:i + 1]
        yield m.scene(one)


def _sample(m, p, n, seed=11):
    """``n`` sampled scenes of ``m`` that ``p`` handles (the values, before ``Model.scene``)."""
    raw = m.sample(np.random.default_rng(seed), 4 * n)
    keep = np.asarray(p.handles(m.scene(raw)), dtype=bool)
    idx = np.flatnonzero(keep)[:n]
    return {k: (v if k in m.static else np.asarray(v)[idx]) for k, v in raw.items()}


@pytest.mark.parametrize("model,path", PAIRS)
def test_each_path_gives_the_same_numbers_by_both_routes(model, path):
    m = registry.MODELS[model]
    p = m.path(path)
    count = 2 if p.code is PathCode.ODE else 6
    values = _sample(m, p, count)
    if not len(next(v for k, v in values.items() if k not in m.static)):
        pytest.skip(f"{path} handles none of the sampled scenes")
    for shape in ((), (1,)):
        for s in _singles(m, values, shape):
            small = paths.by_route(m, s, path, "small")
            _same(small, paths.by_route(m, s, path, "general"), f"{model}/{path}, one scene, batch {shape}")
            assert small.path.shape == shape
    batch = m.scene(values)
    _same(paths.by_route(m, batch, path, "small"), paths.by_route(m, batch, path, "general"), f"{model}/{path}")


@pytest.mark.parametrize("model", list(registry.MODELS))
def test_auto_gives_the_same_numbers_by_both_routes(model):
    m = registry.MODELS[model]
    values = m.sample(np.random.default_rng(5), 8)
    for shape in ((), (1,)):
        for s in _singles(m, values, shape):
            _same(paths.solve(m, s, "auto"), paths.auto_by_masks(m, s), f"{model}, one scene, batch {shape}")
    batch = m.scene(values)
    _same(paths.solve(m, batch, "auto"), paths.auto_by_masks(m, batch), f"{model}, a batch")


@pytest.mark.parametrize("model", [m.name for m in registry.MODELS.values()
                                   if min(m.paths, key=lambda q: q.cost).scalar])
def test_a_single_scene_takes_the_small_route_and_extreme_ones_agree(model, monkeypatch):
    """Scenes at the edges of floating point (overflowing products, tiny and huge values) give the same infinities
    and NaNs on numpy's scalars as on its arrays; and the general route is not used for them."""
    m = registry.MODELS[model]
    first = min(m.paths, key=lambda q: q.cost)
    raw = m.sample(np.random.default_rng(9), 24)
    s = m.scene(raw)
    keep = np.flatnonzero(np.asarray(first.handles(s), dtype=bool) & np.asarray(first.exact_when(s), dtype=bool))[:6]
    values = {k: (v if k in m.static else np.asarray(v)[keep]) for k, v in raw.items()}
    with np.errstate(all="ignore"):
        expected = [paths.auto_by_masks(m, s) for s in _singles(m, values, ())]
        extreme = []
        for factor in (1e-300, 1e160, 1e300):
            for s in _singles(m, {k: np.asarray(v) * factor for k, v in values.items()}, ()):
                if np.all(m.admissible(s)) and np.all(first.handles(s)) and np.all(first.exact_when(s)):
                    extreme.append((s, paths.auto_by_masks(m, s)))
        monkeypatch.setattr(paths, "_auto_general", lambda *a: pytest.fail("the general route ran"))
        for s, want in zip(_singles(m, values, ()), expected, strict=True):
            _same(paths.solve(m, s, "auto"), want, model)
        for s, want in extreme:
            _same(paths.solve(m, s, "auto"), want, f"{model}, extreme")


def test_the_cushion_leaves_the_small_route_where_its_elementary_form_does_not_apply():
    m = registry.MODELS["cushion-impact"]
    s = m.scene({"chi0": 1.0, "zeta0": -1.0, "p0": 5.0, "n0": -32.0, "j": 0.2, "eps": 0.3})
    auto = paths.solve(m, s, "auto")
    assert int(auto.path) == PathCode.EXACT and auto.label.startswith("auto: 1 by closed form (₂F₁")
    _same(auto, paths.auto_by_masks(m, s), "cushion, a turning slip")


def test_refusals_are_the_same_on_the_small_route():
    d = registry.MODELS["direct-impact"]
    for s in (d.scene({"V0": 1.0, "V0p": 2.0, "eps": 0.1, "epsp": 0.1}),
              d.scene({"V0": [1.0], "V0p": [2.0], "eps": 0.1, "epsp": 0.1})):
        with pytest.raises(PathError, match=r"^direct-impact: 1 scene\(s\) outside the model: the bodies must "
                                            r"approach \(V0 > V′0\): separating bodies do not collide$"):
            paths.solve(d, s, "auto")
    c = registry.MODELS["cue-stroke"]
    with pytest.raises(PathError, match=r"^cue-stroke: 1 scene\(s\) outside the model: the contact point"):
        paths.solve(c, c.scene({"b": 0.03, "c": 0.02, "f": 0.2, "eps": 0.1, "epsp": 0.1}), "auto")
    m = registry.MODELS["cushion-impact"]
    s = m.scene({"chi0": 1.0, "zeta0": -1.0, "p0": 5.0, "n0": -32.0, "j": 0.2, "eps": 0.3})
    with pytest.raises(PathError, match=r"elementary.*handles only n0 = 0"):
        paths.solve(m, s, "elementary")
    with pytest.raises(ValueError, match="route must be"):
        paths.by_route(m, s, "exact", "fast")


def test_n1_times_reports_every_model_and_its_parts():
    from reproductions.mechanics import timing

    rows = timing.n1_times(["direct-impact", "cushion-impact"], repeat=3)
    assert set(rows) == {"direct-impact", "cushion-impact"}
    for row in rows.values():
        assert {"path", "total", "scene", "solve", "run", "dispatch", "assembly", "physics"} <= set(row)
        assert all(row[k] >= 0 for k in row if k != "path")
    assert rows["cushion-impact"]["path"] == "elementary"
