"""The sphere–plane impact of §III n°8 against its referee (Newton–Euler for the six velocity components, integrated
in the normal impulse from scratch), and the referee's own physics."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

from reproductions import stress
from reproductions.mechanics import paths, registry
from reproductions.mechanics.referee import plane as referee

SEED = 20261
MODEL = registry.model("plane-impact")
SOURCE = Path(referee.__file__)
AGREE = 1e-9  # in the model's error measure
GRIP = 2  # paths.Regime.GRIP


def _scenes() -> dict[str, dict[str, np.ndarray]]:
    return {"sample": MODEL.scene(MODEL.sample(np.random.default_rng(SEED), 300)),
            "wide": stress.wide_scenes(MODEL, np.random.default_rng(SEED), 300)[0]}


@pytest.fixture(scope="module")
def runs() -> dict[str, tuple[dict[str, np.ndarray], referee.RefereePlane]]:
    """The referee once per scene set (its integrations are the cost of this file)."""
    return {name: (s, referee.solve(s)) for name, s in _scenes().items()}


@pytest.mark.parametrize("name", ["sample", "wide"])
def test_exact_path_agrees_with_the_referee(runs, name: str) -> None:
    s, r = runs[name]
    exact = paths.solve(MODEL, s, "exact")
    err = MODEL.error(s, r, exact)
    i = int(np.argmax(err))
    assert np.all(np.isfinite(err))
    assert err[i] <= AGREE, (float(err[i]), {k: float(np.asarray(v)[i]) for k, v in s.items()})
    # the slip stopped where the closed form says the contact grips (away from the boundary, where either may hold)
    v0 = np.abs(s["chi0"] - s["p0"] * s["R"])
    budget = s["f"] * (1 + s["k"]) * (1 + s["nu"]) * np.abs(s["zeta0"])
    clear = np.abs(v0 - budget) > 1e-9 * (v0 + budget)
    assert np.array_equal(r.stopped[clear], (np.asarray(exact.regime) == GRIP)[clear])


def test_referee_tells_the_printed_formula_from_the_exact_one(runs) -> None:
    """Eqs (6) as printed assume sliding throughout: where the slip stops the referee must disagree with them."""
    s, r = runs["sample"]
    resal = paths.solve(MODEL, s, "resal")
    grips = r.stopped
    assert grips.sum() > 30
    assert np.all(MODEL.error(s, r, resal)[grips] > 1e-6)


@pytest.mark.parametrize("name", ["sample", "wide"])
def test_normal_yield(runs, name: str) -> None:
    """ζ1 = −ν ζ0, the law the model declares (n°8), reached by the end event."""
    s, r = runs[name]
    assert np.all(np.abs(r.zeta1 + s["nu"] * s["zeta0"]) <= 1e-12 * np.abs(s["zeta0"]))


@pytest.mark.parametrize("name", ["sample", "wide"])
def test_angular_momentum_about_the_contact(runs, name: str) -> None:
    s, r = runs[name]
    before, after, scale = MODEL.momentum(s, r)
    assert np.all(np.abs(after - before).max(axis=-1) <= stress.MOMENTUM_RTOL * scale)


@pytest.mark.parametrize("name", ["sample", "wide"])
def test_no_vis_viva_gained(runs, name: str) -> None:
    s, r = runs[name]
    before, after = MODEL.vis_viva(s, r)
    assert np.all(after <= before * (1 + stress.GAIN_RTOL))


def test_frictionless_is_the_textbook_impact() -> None:
    """f = 0: the tangential velocity and the rotation are untouched, ζ1 = −νζ0."""
    raw = MODEL.sample(np.random.default_rng(SEED + 1), 40)
    raw["f"] = np.zeros(40)
    s = MODEL.scene(raw)
    r = referee.solve(s)
    scale = MODEL.scale(s)
    assert np.all(np.abs(r.chi1 - s["chi0"]) <= 1e-14 * scale)
    assert np.all(np.abs((r.p1 - s["p0"]) * s["R"]) <= 1e-14 * scale)
    assert np.all(np.abs(r.zeta1 + s["nu"] * s["zeta0"]) <= 1e-12 * np.abs(s["zeta0"]))
    assert not r.stopped.any()


def test_rolling_needs_no_friction() -> None:
    """The stick phase's tangential impulse rate, solved from the vector equations, is zero for any k and R."""
    for k in (0.5, 1.0, 2.5, 10.0):
        for R in (1e-3, 0.0305, 10.0):
            assert referee.stick_rate(k, R, 0.0) == (0.0, 0.0, 0.0)


def test_batch_shape_and_one_scene() -> None:
    raw = MODEL.sample(np.random.default_rng(SEED + 2), 6)
    s = MODEL.scene({k: v.reshape(2, 3) for k, v in raw.items()})
    r = referee.solve(s)
    assert r.chi1.shape == r.zeta1.shape == r.p1.shape == r.stopped.shape == r.nfev.shape == (2, 3)
    assert r.stopped.dtype == bool
    one = referee.solve(MODEL.scene({k: float(v[0]) for k, v in raw.items()}))
    assert one.chi1.shape == ()
    assert float(one.chi1) == float(r.chi1[0, 0]) and float(one.p1) == float(r.p1[0, 0])


def test_referee_imports_nothing_of_the_project_but_budget() -> None:
    tree = ast.parse(SOURCE.read_text())
    allowed = {"__future__", "math", "dataclasses", "collections.abc", "numpy", "scipy.integrate"}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                assert alias.name.split(".")[0] in {"math", "dataclasses", "numpy", "scipy"}, alias.name
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                assert (node.level, node.module) == (2, "budget"), ast.dump(node)
            elif node.module not in allowed:
                assert node.module == "reproductions.mechanics.budget", node.module
    calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call) and getattr(n.func, "id", "") == "__import__"]
    assert not calls
