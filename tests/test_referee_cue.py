"""§VII n°14: the referee (Newton–Euler in the cue impulse, Coulomb cloth as complementarity, law (6) of §I n°3
evaluated literally) against the closed form ``exact``, and the physics its own output must obey."""

import ast
import math
from pathlib import Path

import numpy as np
import pytest

from reproductions import stress
from reproductions.mechanics import paths, registry
from reproductions.mechanics.referee import cue as referee

SEED = 20240614
MODEL = registry.model("cue-stroke")
KEYS = ("M", "Mp", "V0p", "i", "b", "c", "R", "k", "f", "eps", "epsp")


@pytest.fixture(scope="module")
def sample():
    s = MODEL.scene(MODEL.sample(np.random.default_rng(SEED), 200))
    return s, referee.solve(s)


@pytest.fixture(scope="module")
def wide():
    s, _ = stress.wide_scenes(MODEL, np.random.default_rng(SEED), 200)
    return s, referee.solve(s)


def _contact_along_axis(s, r):
    """d·(v + ω × r_c) from the outputs: the ball's contact point along the cue axis (the ball stays on the cloth)."""
    i, b, c, R = (np.asarray(s[x], dtype=float) for x in ("i", "b", "c", "R"))
    a = -np.sqrt(R * R - b * b - c * c)
    v = np.stack([r.chi1, r.eta1, np.zeros_like(r.chi1)], axis=-1)
    w = np.stack([r.n1, r.p1, r.q1], axis=-1)
    u = v + np.cross(w, np.stack([a, b, c], axis=-1))
    return u[..., 0] * np.cos(i) - u[..., 2] * np.sin(i)


@pytest.mark.parametrize("which", ["sample", "wide"])
def test_referee_agrees_with_the_exact_path(which, request):
    s, r = request.getfixturevalue(which)
    exact = paths.solve(MODEL, s, "exact")
    err = MODEL.error(s, r, exact)
    assert np.all(np.isfinite(err)) and err.max() < 1e-9, (which, float(err.max()), int(err.argmax()))
    assert not r.stopped.any() and not r.cloth_pulls.any()  # from rest the slip only grows; i ≥ 0 pushes the cloth


def test_light_ball_at_low_speed():
    """A ball 1e6 times lighter than the cue at 2 µm/s: the cue impulse is ~1e-13, below the absolute event
    tolerance solve_ivp would use on P itself (the referee integrates in P over its scale). Checked against the
    direct impact of §I eq. (8) (central horizontal stroke, derived in the next test)."""
    s = MODEL.scene({"M": 2.6746639785448287e-07, "Mp": 0.38578172893815466, "V0p": 1.8676347633116657e-06,
                     "i": 0.0, "b": 0.0, "c": 0.0, "R": 0.010320898580143846, "k": 6.725360115400736, "f": 0.0,
                     "eps": 0.40546801630318163, "epsp": 0.05524100569728163})
    r = referee.solve(s)
    M, Mp, V0, eps, epsp = (float(s[x]) for x in ("M", "Mp", "V0p", "eps", "epsp"))
    den = M * (1 + epsp) + Mp * (1 + eps)
    assert abs(float(r.chi1) - 2 * Mp * V0 / den) <= 1e-12 * V0
    assert abs(float(r.V1p) - V0 * (1 - 2 * M / den)) <= 1e-12 * V0


@pytest.mark.parametrize("rho", [1e3, 1e6, -1e3])
def test_strokes_at_the_edge_of_the_cloths_friction_cone(rho):
    """f within 1/ρ of the value where the foot just holds (ρ < 0: just inside the cone): the slip's direction is
    stiff there (module docstring of the referee); the referee stays cheap and agrees with ``exact``."""
    i, b, c, R, k = 0.5, 0.01, 0.01, 0.0305, 2.5
    a = -math.sqrt(R * R - b * b - c * c)
    tau = (-b * math.sin(i), c * math.cos(i) + a * math.sin(i))
    D = math.hypot(math.cos(i) - k / R * tau[1], k / R * tau[0])  # |j_hold| (1 + k), Résal's eq. (5) geometry
    f = D / (1 + k) / math.sin(i) * (1 - 1 / rho)
    s = MODEL.scene({"M": 0.21, "Mp": 0.6, "V0p": 3.0, "i": i, "b": b, "c": c, "R": R, "k": k, "f": f, "eps": 0.3,
                     "epsp": 0.27})
    r = referee.solve(s)
    assert float(MODEL.error(s, r, paths.solve(MODEL, s, "exact"))) < 1e-12 and int(r.nfev) < 2000


def test_central_horizontal_stroke_is_the_direct_impact():
    """f = 0 (or i = 0: no pressure on the cloth), b = c = i = 0: the cue M′ (ε′) strikes the ball M (ε) at rest.
    Momentum M′(V′0 − V′1) = M V1 and law (6) without tangential impulse, M′(V′0² − V′1²) − M V1² = ε M V1² +
    ε′ M′(V′0 − V′1)²; dividing by M′(V′0 − V′1) = M V1: V′0 + V′1 − V1 = ε V1 + ε′(V′0 − V′1), whence
    V′0 − V′1 = 2 M V′0/(M(1 + ε′) + M′(1 + ε)): V′1 = V′0 [1 − 2M/(M(1 + ε′) + M′(1 + ε))], V1 = 2M′V′0/(…)
    (§I eq. (8) with the striking body the cue)."""
    rng = np.random.default_rng(SEED)
    n = 40
    s = MODEL.scene({"M": 10 ** rng.uniform(-3, 1, n), "Mp": 10 ** rng.uniform(-3, 1, n),
                     "V0p": 10 ** rng.uniform(-3, 1, n), "i": 0.0, "b": 0.0, "c": 0.0, "R": 0.0305, "k": 2.5,
                     "f": np.where(np.arange(n) % 2 == 0, 0.0, 0.3), "eps": rng.uniform(0, 1, n),
                     "epsp": rng.uniform(0, 1, n)})
    r = referee.solve(s)
    M, Mp, V0, eps, epsp = (np.asarray(s[x], dtype=float) for x in ("M", "Mp", "V0p", "eps", "epsp"))
    den = M * (1 + epsp) + Mp * (1 + eps)
    np.testing.assert_allclose(r.chi1, 2 * Mp * V0 / den, rtol=1e-12, atol=0)
    np.testing.assert_allclose(r.V1p, V0 * (1 - 2 * M / den), rtol=0, atol=1e-12 * V0.max())
    assert np.all(np.abs(r.V1p - V0 * (1 - 2 * M / den)) <= 1e-12 * V0)
    for x in (r.eta1, r.n1, r.p1, r.q1):
        assert np.all(x == 0)


@pytest.mark.parametrize("which", ["sample", "wide"])
def test_momentum_about_the_foot_is_conserved(which, request):
    s, r = request.getfixturevalue(which)
    before, after, scale = registry._cue_momentum(s, r)
    assert np.all(np.linalg.norm(after - before, axis=-1) <= 1e-12 * scale)


@pytest.mark.parametrize("which", ["sample", "wide"])
def test_no_vis_viva_is_gained(which, request):
    s, r = request.getfixturevalue(which)
    before, after = registry._cue_vis_viva(s, r)
    assert np.all(after <= before * (1 + 1e-12))


def test_elastic_factors_one_end_at_equal_velocities_along_the_axis(sample):
    """ε = ε′ = 1 (no restitution): the stroke ends at the greatest compression, where the cue's speed equals the
    contact point's along the cue axis (the model's premise; law (6) is an identity there)."""
    s0, _ = sample
    s = MODEL.scene({**{x: s0[x] for x in KEYS}, "eps": 1.0, "epsp": 1.0})
    r = referee.solve(s)
    V0 = np.asarray(s["V0p"], dtype=float)
    assert np.all(np.abs(r.V1p - _contact_along_axis(s, r)) <= 1e-12 * V0)
    assert np.all(np.abs(r.omega1 - r.omega) <= 1e-12 * V0)


def test_restitution_ends_after_the_greatest_compression(sample):
    s, r = sample
    V0 = np.asarray(s["V0p"], dtype=float)
    assert np.all(r.omega1 >= r.omega * (1 - 1e-12)) and np.all(r.omega > 0)
    assert np.all(r.V1p <= _contact_along_axis(s, r) + 1e-12 * V0)  # the cue no faster than the contact point


@pytest.mark.parametrize("which", ["sample", "wide"])
def test_cloth_friction_inside_its_cone(which, request):
    """The cloth's friction impulse J = P (cos i, 0) − M v (momentum, P = M′ω1) is at most f times its normal
    impulse P sin i (Coulomb), and equals it where the foot still slips at the end (slip along J)."""
    s, r = request.getfixturevalue(which)
    M, Mp, i, f, R = (np.asarray(s[x], dtype=float) for x in ("M", "Mp", "i", "f", "R"))
    P = Mp * r.omega1
    J = np.hypot(P * np.cos(i) - M * r.chi1, -M * r.eta1)
    bound = f * P * np.sin(i)
    assert np.all(J <= bound + 1e-11 * P)
    slip = np.hypot(r.chi1 - r.p1 * R, r.eta1 + r.n1 * R)
    V0 = np.asarray(s["V0p"], dtype=float)
    slides = slip > 1e-9 * V0
    assert np.all(np.abs(J - bound)[slides] <= 1e-11 * P[slides])
    assert slides.any() and (~slides).any()  # both the sliding and the held foot are exercised


def test_a_cue_pointing_up_would_need_a_pulling_cloth():
    """Outside the model (i < 0): the cloth cannot hold the ball down; the referee flags it and lets the ball
    leave the cloth (no pressure, no friction), the momentum then being the cue's along the horizontal."""
    s = {"M": np.array([0.21, 0.21]), "Mp": 0.6, "V0p": 3.0, "i": np.array([-0.3, 0.3]), "b": 0.0,
         "c": np.array([0.02, 0.0]), "R": 0.0305, "k": 2.5, "f": 0.3, "eps": 0.0, "epsp": 0.27}
    r = referee.solve(s)
    assert r.cloth_pulls.tolist() == [True, False]
    assert math.isclose(0.21 * r.chi1[0], 0.6 * r.omega1[0] * math.cos(-0.3), rel_tol=1e-12)


def test_referee_imports_nothing_but_budget():
    tree = ast.parse(Path(referee.__file__).read_text())
    project = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level or (node.module or "").startswith("reproductions"):
                project.add((node.level, node.module))
            else:
                assert node.module.split(".")[0] in {"__future__", "collections", "dataclasses", "math", "numpy",
                                                     "scipy", "typing"}, node.module
        elif isinstance(node, ast.Import):
            for alias in node.names:
                assert alias.name.split(".")[0] in {"math", "numpy", "scipy", "dataclasses"}, alias.name
    assert project == {(2, "budget")}
