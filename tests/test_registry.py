"""One invariant test over the registry: every model × every path (the pattern of pooltool's cushion tests).

For each pair: finite outputs; a batch gives the numbers of its scenes one by one; paths of an exact kind never
gain vis viva; mirror symmetry where the model declares one; where a path declares itself exact it agrees with
the ODE reference to the declared accuracies; ``auto`` equals, scene by scene, the path it reports.
"""

import dataclasses

import numpy as np
import pytest

from reproductions.mechanics import paths, registry
from reproductions.mechanics.paths import Kind, PathCode, PathError

PAIRS = [(m.name, p.name) for m in registry.MODELS.values() for p in m.paths]
EXACT_KINDS = (Kind.CLOSED_FORM, Kind.EXACT_NUMERICAL, Kind.ODE)
N = 12


def _scenes(model, seed=0, n=N):
    return model.scene(model.sample(np.random.default_rng(seed), n))


def _handled(model, path, scene):
    keep = np.asarray(path.handles(scene), dtype=bool)
    return {k: (v if k in model.static else v[keep]) for k, v in scene.items()}, keep


def _arrays(res):
    return {f.name: getattr(res, f.name) for f in dataclasses.fields(res)
            if isinstance(getattr(res, f.name), np.ndarray)}


@pytest.fixture(scope="module")
def solved():
    out = {}
    for m in registry.MODELS.values():
        s = _scenes(m)
        for p in m.paths:
            sub, _ = _handled(m, p, s)
            out[m.name, p.name] = (sub, paths.solve(m, sub, p.name))
    return out


def test_every_model_has_an_ode_path_and_a_path_exact_everywhere():
    assert {"direct-impact", "wall-impact", "plane-impact", "ricochet", "cloth-slide", "cushion-impact",
            "spheres-free", "spheres-cloth", "cue-stroke"} <= set(registry.MODELS)
    for m in registry.MODELS.values():
        assert any(p.code is PathCode.ODE and p.kind is Kind.ODE for p in m.paths), m.name
        assert len({p.code for p in m.paths}) == len(m.paths), m.name
        for prm in m.params:
            assert prm.unit and prm.doc, (m.name, prm.name)


@pytest.mark.parametrize("model,path", PAIRS)
def test_outputs_are_finite_and_carry_the_convention(model, path, solved):
    m = registry.MODELS[model]
    s, res = solved[model, path]
    assert res.method == path and isinstance(res.label, str) and res.label
    n = np.shape(s[paths.ONES])
    assert res.path.shape == n and np.all(res.path == m.path(path).code)
    assert res.regime.shape == n and set(np.unique(res.regime)) <= {int(r) for r in paths.Regime}
    for spec in m.outputs:
        v = np.asarray(getattr(res, spec.partition("*")[0]))
        assert np.all(np.isfinite(v)), (model, path, spec)


@pytest.mark.parametrize("model,path", PAIRS)
def test_a_batch_gives_the_numbers_of_its_scenes_one_by_one(model, path, solved):
    m = registry.MODELS[model]
    s, res = solved[model, path]
    for i in range(min(4, np.shape(s[paths.ONES])[0])):
        one = {k: (v if k in m.static else v[i:i + 1]) for k, v in s.items()}
        r1 = paths.solve(m, one, path)
        for name, arr in _arrays(res).items():
            np.testing.assert_allclose(getattr(r1, name)[0], arr[i], rtol=1e-12, atol=1e-14,
                                       err_msg=f"{model}/{path}: {name}, scene {i}")


@pytest.mark.parametrize("model,path", PAIRS)
def test_exact_paths_never_gain_vis_viva(model, path, solved):
    m = registry.MODELS[model]
    p = m.path(path)
    if m.vis_viva is None or p.kind not in EXACT_KINDS:
        pytest.skip("no energy balance declared, or an approximation (the paper's may gain: see cue-stroke)")
    s, res = solved[model, path]
    before, after = m.vis_viva(s, res)
    assert np.all(after <= before * (1 + max(p.accuracy, 1e-12) * 10)), (after - before) / before


@pytest.mark.parametrize("model,path", PAIRS)
def test_mirror_symmetry(model, path, solved):
    m = registry.MODELS[model]
    if m.mirror is None:
        pytest.skip(f"{model} declares no mirror symmetry")
    s, res = solved[model, path]
    back = m.mirrored(paths.solve(m, m.mirror(s), path))
    scale = np.asarray(m.scale(s), dtype=float)
    for name, v in back.items():
        d = np.abs(np.asarray(v) - np.asarray(getattr(res, name)))
        d = d.reshape(*scale.shape, -1).max(axis=-1) if d.ndim > scale.ndim else d
        assert np.all(d <= 1e-9 * (1 + scale)), (model, path, name, d.max())


@pytest.mark.parametrize("model,path", PAIRS)
def test_where_a_path_declares_itself_exact_it_agrees_with_the_ode(model, path, solved):
    m = registry.MODELS[model]
    p = m.path(path)
    if p.code is PathCode.ODE:
        pytest.skip("the reference itself")
    s, _ = solved[model, path]
    exact = np.asarray(p.exact_when(s), dtype=bool)
    if not exact.any():
        pytest.skip(f"{path} declares itself exact for none of these scenes")
    sub = {k: (v if k in m.static else v[exact]) for k, v in s.items()}
    mine = paths.solve(m, sub, path)
    ode = paths.solve(m, sub, "ode")
    err = m.error(sub, mine, ode)
    tol = max(p.accuracy, m.path("ode").accuracy)
    assert err.max() <= tol, f"{model}/{path}: largest error {err.max():.3g} > declared {tol:g}"
    np.testing.assert_array_equal(mine.regime, ode.regime)


@pytest.mark.parametrize("model", list(registry.MODELS))
def test_auto_equals_the_path_it_reports_scene_by_scene(model):
    m = registry.MODELS[model]
    s = _scenes(m, seed=3)
    auto = paths.solve(m, s, "auto")
    assert auto.method == "auto"
    for code in np.unique(auto.path):
        p = next(q for q in m.paths if q.code == code)
        sel = auto.path == code
        sub = {k: (v if k in m.static else v[sel]) for k, v in s.items()}
        assert np.all(p.exact_when(sub)) and np.all(p.handles(sub))
        ref = paths.solve(m, sub, p.name)
        for name, arr in _arrays(ref).items():
            if name != "path":
                np.testing.assert_array_equal(getattr(auto, name)[sel], arr, err_msg=f"{model}: {name}")
        cheaper = [q for q in m.paths if q.cost < p.cost]
        for q in cheaper:  # no cheaper path declared itself exact there
            assert not np.any(np.asarray(q.handles(sub)) & np.asarray(q.exact_when(sub))), (model, q.name)


def test_auto_skips_what_a_scene_does_not_need():
    """The cushion's elementary form serves the scenes without rotation about the cushion, the ₂F₁ form the rest."""
    m = registry.MODELS["cushion-impact"]
    auto = paths.solve(m, _scenes(m), "auto")
    assert set(np.unique(auto.path)) == {PathCode.ELEMENTARY, PathCode.EXACT}


def test_a_path_outside_its_region_and_an_unknown_path_are_refused():
    m = registry.MODELS["cushion-impact"]
    s = m.scene({"chi0": 1.0, "zeta0": -1.0, "p0": 5.0, "n0": -32.0, "j": 0.2, "eps": 0.3})
    with pytest.raises(PathError, match=r"elementary.*handles only n0 = 0"):
        paths.solve(m, s, "elementary")
    with pytest.raises(PathError, match="no path 'euler'"):
        paths.solve(m, s, "euler")
    d = registry.MODELS["direct-impact"]
    with pytest.raises(PathError, match="separating bodies"):
        paths.solve(d, d.scene({"V0": 1.0, "V0p": 2.0, "eps": 0.1, "epsp": 0.1}), "exact")


def test_no_printed_coefficient_is_a_default():
    for m in registry.MODELS.values():
        for prm in m.params:
            if prm.name in ("eps", "epsp", "nu", "f", "j"):
                assert prm.default is None, (m.name, prm.name)


@pytest.mark.parametrize("eps", [0.99, 0.999, 0.9995, 0.9999])
def test_the_direct_impact_ode_holds_its_accuracy_for_nearly_plastic_impacts(eps):
    """Its restitution lasts (π/2)·e: longer steps used to jump over the separation (error 9e-8 at ε = 0.999)."""
    m = registry.MODELS["direct-impact"]
    s = m.scene({"M": [1.0, 3.0, 0.2], "Mp": [1.0, 0.5, 4.0], "V0": 1.0, "V0p": 0.0, "eps": eps, "epsp": eps})
    err = m.error(s, paths.solve(m, s, "exact"), paths.solve(m, s, "ode"))
    assert err.max() <= m.path("ode").accuracy


def test_every_ode_path_can_be_rerun_at_another_tolerance_and_solver():
    for m in registry.MODELS.values():
        p = m.path("ode")
        assert p.tuned is not None and p.rtol and p.solver, m.name
        s = _scenes(m, seed=4, n=2)
        default = paths.solve(m, s, "ode")
        again = p.tuned(s, p.rtol, p.solver)  # the declared tolerance and solver are what `run` uses
        for spec in m.outputs:
            name = spec.partition("*")[0]
            np.testing.assert_array_equal(getattr(again, name), getattr(default, name), err_msg=m.name)
        loose = p.tuned(s, 1e-6, "RK45")
        assert m.error(s, loose, default).max() < 1e-3, m.name


def test_an_ode_that_would_run_on_stops_with_a_clear_error(monkeypatch):
    """Every integration is bounded (LSODA at rtol 1e-12 chatters on the cushion's discontinuous friction and ran
    for minutes in the benchmark): past the budget it raises, and the benchmark counts a failure."""
    from reproductions.mechanics import budget

    m = registry.MODELS["cushion-impact"]
    s = m.scene({"chi0": 1.2, "zeta0": -0.8, "p0": 20.0, "n0": -30.0, "j": 0.4, "eps": 0.3})
    assert m.error(s, paths.solve(m, s, "ode"), paths.solve(m, s, "exact")).max() < 1e-8
    monkeypatch.setattr(budget, "MAX_RHS", 20)
    with pytest.raises(budget.ODEBudgetExceeded, match="more than 20 right-hand-side evaluations"):
        paths.solve(m, s, "ode")
