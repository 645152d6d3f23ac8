"""Property tests (hypothesis) of the invariants ``resal stress`` checks, on scenes hypothesis draws and shrinks.

For every model, scenes are drawn parameter by parameter from the declared units and ranges (speeds and spins
over 1e-6 … 1e3, masses over 1e-6 … 1e6, coefficients including their ends). Every path that is exact for the
scene must give finite outputs, conserve the model's momenta to 1e-12 and never gain vis viva; ``auto`` must
give the numbers of the path it names; mirror-symmetric models must be symmetric. Sized for ``make test``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from reproductions import stress
from reproductions.mechanics import paths, registry
from reproductions.mechanics.paths import Kind

EXAMPLES = 25
SETTINGS = settings(max_examples=EXAMPLES, deadline=None,
                    suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
MODELS = list(registry.MODELS)


def _magnitude(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi).map(lambda e: 10.0**e)


def _signed(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.one_of(st.just(0.0), st.tuples(st.sampled_from([-1.0, 1.0]), _magnitude(lo, hi)).map(
        lambda t: t[0] * t[1]))


def _value(p: paths.Param) -> st.SearchStrategy[float]:
    if p.integer:
        return st.integers(int(p.lo or 1), min(int(p.hi or 6), 6)).map(float)
    if p.unit == "kg":
        return _magnitude(-6, 6)
    if p.unit == "m":
        return _magnitude(-3, 1)
    if p.unit == "m/s²":
        return st.floats(1.0, 30.0)
    if p.unit == "rad" and p.lo is not None and p.hi is not None:
        return st.floats(p.lo, p.hi, exclude_min=p.lo_open, exclude_max=p.hi_open)
    if p.unit in ("m/s", "rad/s"):
        if p.hi == 0.0:  # an approach velocity
            return _magnitude(-6, 3).map(lambda x: -x)
        if p.lo == 0.0:
            return _magnitude(-6, 3)
        return _signed(-6, 3 if p.unit == "m/s" else 5)
    if p.name in ("k", "kp"):
        return st.one_of(st.just(p.lo), st.just(2.5), st.floats(p.lo, 10.0))  # from a thin shell, the least k
    if p.lo == 0.0 and p.hi == 1.0:
        return st.floats(0.0, 1.0, exclude_min=p.lo_open).filter(lambda x: x > 0 or not p.lo_open)
    if p.lo == 0.0:  # f, j
        return st.one_of(st.just(1e-9 if p.lo_open else 0.0), st.floats(1e-6, 10.0))
    raise AssertionError(f"no strategy for {p.name} ({p.unit})")


def draw_scene(data: st.DataObject, m: paths.Model) -> dict[str, np.ndarray]:
    values: dict[str, object] = {}
    for p in m.params:
        if p.name in m.vectors:
            values[p.name] = [data.draw(_signed(-6, 3 if p.unit == "m/s" else 5), label=f"{p.name}[{i}]")
                              for i in range(3)]
        else:
            values[p.name] = data.draw(_value(p), label=p.name)
    if m.name == "spheres-cloth":  # the balls rest on the cloth
        values["v"][2] = values["vp"][2] = 0.0
    if m.name == "cue-stroke":  # the contact point on the ball: a fraction of R
        R = values["R"]
        r, th = data.draw(st.floats(0.0, 0.95), label="offset"), data.draw(st.floats(0.0, 2 * math.pi), label="th")
        values["b"], values["c"] = R * r * math.cos(th), R * r * math.sin(th)
    s = m.scene({k: np.asarray(v, dtype=float)[None, ...] for k, v in values.items()})
    if "n" in m.static:
        s["n"] = np.asarray(values["n"], dtype=float).reshape(())
    assume(bool(stress._admissible_values(m, s)[0]))
    return s


def _fast_paths(m: paths.Model) -> list[paths.Path]:
    return [p for p in m.paths if p.kind is not Kind.ODE]


@pytest.mark.parametrize("name", MODELS)
@SETTINGS
@given(data=st.data())
def test_exact_paths_are_finite_conserve_momentum_and_never_gain(name, data):
    m = registry.MODELS[name]
    s = draw_scene(data, m)
    for p in [*_fast_paths(m), None]:
        if p is not None and not bool(np.asarray(p.handles(s))[0]):
            continue
        r = paths.solve(m, s, "auto" if p is None else p.name)
        exact_here = p is None or p.kind in stress.EXACT_KINDS or bool(np.asarray(p.exact_when(s))[0])
        for o in m.outputs:
            assert np.all(np.isfinite(np.asarray(getattr(r, o.partition("*")[0]), dtype=float))), (o, p)
        if not exact_here:
            continue
        if m.momentum is not None:
            before, after, scale = m.momentum(s, r)
            err = float(np.max(np.abs(after - before)) / max(float(np.ravel(scale)[0]), 1e-300))
            assert err <= stress.MOMENTUM_RTOL, (p and p.name, err)
        if m.vis_viva is not None:
            before, after = m.vis_viva(s, r)
            b, a = float(np.ravel(before)[0]), float(np.ravel(after)[0])
            assert a <= b * (1 + stress.GAIN_RTOL) + 1e-300, (p and p.name, b, a)


@pytest.mark.parametrize("name", [n for n, m in registry.MODELS.items() if m.mirror is not None])
@SETTINGS
@given(data=st.data())
def test_mirror_symmetry(name, data):
    m = registry.MODELS[name]
    s = draw_scene(data, m)
    r = paths.solve(m, s, "auto")
    back = m.mirrored(paths.solve(m, m.mirror(s), "auto"))
    speed = float(np.ravel(m.scale(s))[0])
    spin = speed / float(np.ravel(s["R"])[0])  # rotations (p, n, q, w…) compare on the scale speed / R
    for k, v in back.items():
        atol = 1e-12 * (spin if k.startswith(("w", "p", "n", "q")) else speed)
        np.testing.assert_allclose(np.asarray(v, dtype=float), np.asarray(getattr(r, k), dtype=float), rtol=1e-9,
                                   atol=atol, err_msg=k)


@pytest.mark.parametrize("name", MODELS)
@settings(SETTINGS, max_examples=10)
@given(data=st.data())
def test_auto_gives_the_numbers_of_the_path_it_names(name, data):
    m = registry.MODELS[name]
    s = draw_scene(data, m)
    r = paths.solve(m, s, "auto")
    code = int(np.ravel(r.path)[0])
    p = next(q for q in m.paths if int(q.code) == code)
    again = paths.solve(m, s, p.name)
    for o in m.outputs:
        name_ = o.partition("*")[0]
        np.testing.assert_array_equal(np.asarray(getattr(r, name_)), np.asarray(getattr(again, name_)))
