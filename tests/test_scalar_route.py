"""One scene on numpy floats (``paths.Path.scalar``, ``paths._run_one``) against the batch route, bit for bit
(issue 34, item 1).

The scalar route runs the same functions as the batch route, on numpy floats instead of arrays: two free balls
(§V n°12, ``spheres.two_spheres``), the cushion's exact path (§IV n°11, the ₂F₁ kernel ``slip._F`` and the Newton
solve of the slip decay on floats, ``slip._solve_x_one``), ``slip.slip_decay`` itself, and two balls on the cloth
(§VI n°13: the end of the impact's fused Newton iteration, ``spheres._cloth_normal_impulse_one`` with
``slip._WalkOne``). Every model × path on seeded scenes and on scenes built to reach each regime and each branch of
the kernel (Pfaff's series, the split series and its contiguous steps, c ≥ C_BIG, the slip that stops, the roles
of φ and ψ swapped) and of the cloth's iteration (a turning slip or one component, sliding throughout or stopping,
no friction, k ≠ k′, slips 1e5 times the approach speed, the walk restarted cold), the decay on scenes hypothesis
draws, and the cloth's exact path on drawn scenes.
"""


import numpy as np
import pytest
from bitwise import bits as _bits
from bitwise import same as _same
from hypothesis import given, settings
from hypothesis import strategies as st

from reproductions.mechanics import paths, registry, slip
from reproductions.mechanics.paths import PathCode, Regime

# scenes built to reach each regime and branch (values given; the model's defaults for the rest)
CUSHION = [  # §IV: the slip turns (n0 ≠ 0, φ0 ≠ 0), for k = 2c across the kernel's branches
    {"chi0": 1.0, "zeta0": -1.0, "p0": 5.0, "n0": -32.0, "j": 0.2, "eps": 0.3},  # w < 1: Pfaff's series
    {"chi0": 3.0, "zeta0": -0.5, "p0": 0.0, "n0": 2.0, "j": 0.1, "eps": 0.6},  # φ0 ≫ ψ0: the split series
    {"chi0": 3.0, "zeta0": -0.5, "p0": 0.0, "n0": 2.0, "j": 0.1, "eps": 0.6, "k": 1.5},
    {"chi0": 3.0, "zeta0": -0.5, "p0": 0.0, "n0": 2.0, "j": 0.1, "eps": 0.6, "k": 9.0},  # c > 3: contiguous steps
    {"chi0": 3.0, "zeta0": -0.5, "p0": 0.0, "n0": 2.0, "j": 0.1, "eps": 0.6, "k": 40.0},  # c ≥ C_BIG
    {"chi0": -2.0, "zeta0": -2.0, "p0": 10.0, "n0": 80.0, "j": 0.05, "eps": 0.9},  # ψ0 ≫ φ0
    {"chi0": 0.3, "zeta0": -3.0, "p0": 0.0, "n0": 5.0, "j": 0.6, "eps": 0.0},  # the slip stops (GRIP)
    {"chi0": 1.0, "zeta0": -1.0, "p0": 0.0, "n0": 0.0, "j": 0.2, "eps": 0.3},  # n0 = 0: elementary
    {"chi0": 1.0, "zeta0": -1.0, "p0": 32.0, "R": 0.03125, "n0": 0.0, "j": 0.2, "eps": 0.3},  # no slip: χ0 = p0R
    {"chi0": 1.0, "zeta0": -1.0, "p0": 0.0, "n0": 3.0, "j": 0.0, "eps": 0.3},  # no friction
]
SPHERES = [  # §V, §VI: slides, the slip stops, no slip, no friction, head on
    {"v": [1.0, 0.2, 0.0], "f": 0.2, "eps": 0.3, "epsp": 0.4},
    {"v": [2.0, 0.0, 0.0], "w": [0.0, 0.0, 3.0], "f": 0.05, "eps": 0.1, "epsp": 0.2},
    {"v": [2.0, 0.05, 0.0], "f": 0.5, "eps": 0.5, "epsp": 0.5},
    {"v": [2.0, 0.0, 0.0], "f": 0.3, "eps": 0.2, "epsp": 0.7},
    {"v": [1.0, 0.3, 0.0], "w": [5.0, 20.0, -10.0], "vp": [-0.5, 0.1, 0.0], "f": 0.0, "eps": 0.3, "epsp": 0.4},
    {"v": [1.0, 0.3, 0.0], "w": [0.0, -40.0, 10.0], "f": 0.3, "eps": 1.0, "epsp": 1.0, "M": 0.1, "Mp": 0.4},
]
CLOTH = [  # §VI: the end of the impact by the fused Newton iteration (``spheres._cloth_normal_impulse``)
    *SPHERES,
    {"v": [1.0, 0.3, 0.0], "w": [0.0, 10.0, 0.0], "f": 0.2, "eps": 0.3, "epsp": 0.4},  # turning, slides throughout
    {"v": [2.0, 0.05, 0.0], "w": [0.0, 1.0, 0.0], "f": 0.5, "eps": 0.5, "epsp": 0.5},  # turning, the slip stops
    {"v": [2.0, 0.0, 0.0], "w": [0.0, 2.0, 0.0], "f": 0.4, "eps": 0.2, "epsp": 0.7},  # φ0 = 0: ψ alone
    {"v": [1.0, 0.3, 0.0], "w": [0.0, 10.0, 0.0], "f": 0.0, "eps": 0.3, "epsp": 0.4},  # no friction
    {"v": [1.5, 0.4, 0.0], "w": [3.0, 25.0, -8.0], "vp": [-0.2, 0.1, 0.0], "wp": [0.0, -4.0, 2.0],
     "f": 0.25, "eps": 0.6, "epsp": 0.2, "k": 2.0, "kp": 3.5, "M": 0.17, "Mp": 0.3, "R": 0.028},  # k ≠ k′
    {"v": [1.5, 0.1, 0.0], "w": [0.0, 3.0, 0.0], "f": 0.6, "eps": 0.1, "epsp": 0.9, "k": 1.2, "kp": 6.0,
     "M": 0.3, "Mp": 0.05},  # k ≠ k′, the slip stops
    {"v": [0.01, 0.3, 0.0], "w": [0.0, 3e4, -5e4], "f": 0.2, "eps": 0.3, "epsp": 0.4},  # slip 1e5 × the approach
    {"v": [1e-3, 0.0, 0.0], "w": [0.0, -2e5, 1e5], "f": 0.9, "eps": 0.0, "epsp": 1.0, "k": 1.0, "kp": 12.0},
    {"v": [1.0, 0.3, 0.0], "w": [0.0, -40.0, 10.0], "f": 0.3, "eps": 1.0, "epsp": 1.0, "M": 1e-3, "Mp": 1e3},
    {"v": [0.008539510582370628, 0.0, 0.0], "vp": [-0.6707984701082124, -0.49936599652120933, 0.0],  # the walk
     "w": [0.0, -86.09697401894874, -200.16501897089435], "wp": [15.089448296300976, 0.0, 76.29288504024896],
     "f": 0.7869341198000812, "eps": 1.0, "epsp": 0.23780190711984506, "k": 8.050896094954698, "kp": 2.5,
     "M": 1.3911397135412016, "Mp": 0.12946153197172794, "R": 0.02004859085093088,
     "Rp": 0.01670947343368929},  # stops, then ω steps back below the stop: a cold restart at x = 1
]
BUILT = {"cushion-impact": CUSHION, "spheres-free": SPHERES, "spheres-cloth": CLOTH}


def _scenes(m, seed, count):
    """Single scenes (batch () and (1,)) of ``m``: sampled, then the built ones of ``BUILT``."""
    raw = m.sample(np.random.default_rng(seed), count)
    n = len(next(v for k, v in raw.items() if k not in m.static))
    values = [{k: (v if k in m.static else np.asarray(v)[i]) for k, v in raw.items()} for i in range(n)]
    values += BUILT.get(m.name, [])
    for v in values:
        for shape in ((), (1,)):
            one = {}
            for k, x in v.items():
                x = np.asarray(x, dtype=float)
                one[k] = x if (k in m.static or shape == ()) else x.reshape(1, *x.shape)
            yield m.scene(one)


PAIRS = [(m.name, p.name) for m in registry.MODELS.values() for p in m.paths]


@pytest.mark.parametrize("model,path", PAIRS)
def test_each_path_on_one_scene_by_both_routes(model, path):
    m = registry.MODELS[model]
    p = m.path(path)
    count = 2 if p.code in (PathCode.ODE, PathCode.REFERENCE) or model == "ricochet" else 12
    ran = 0
    with np.errstate(all="ignore"):
        for s in _scenes(m, 21, count):
            if not (np.all(m.admissible(s)) and np.all(p.handles(s))):
                continue
            if p.code in (PathCode.ODE, PathCode.REFERENCE) and ran >= 4:
                break
            _same(paths.by_route(m, s, path, "small"), paths.by_route(m, s, path, "general"), f"{model}/{path}")
            ran += 1
    if not ran:
        pytest.skip(f"{path} handles none of the scenes")


@pytest.mark.parametrize("model", list(registry.MODELS))
def test_auto_on_one_scene_by_both_routes(model, monkeypatch):
    """``auto`` on single scenes against the general route; a single scene whose path declares ``scalar`` runs on
    its numpy floats (never the flattened batch)."""
    m = registry.MODELS[model]
    single = paths._auto_single

    def guarded(p, flat, n, batch):
        assert not (p.scalar and n == 1), f"{model}: {p.name} ran on arrays for one scene"
        return single(p, flat, n, batch)

    regimes = set()
    with np.errstate(all="ignore"):
        for s in _scenes(m, 8, 4 if model == "ricochet" else 12):
            want = paths.auto_by_masks(m, s)
            monkeypatch.setattr(paths, "_auto_single", guarded)
            got = paths.solve(m, s, "auto")
            monkeypatch.setattr(paths, "_auto_single", single)
            _same(got, want, f"{model}, one scene")
            regimes.update(np.ravel(got.regime).tolist())
    if model in BUILT:  # the built scenes reach every regime with a slip
        assert {Regime.SLIDE, Regime.GRIP, Regime.NO_SLIP} <= regimes, (model, regimes)


def test_the_cushion_turning_slip_and_two_balls_take_the_scalar_route():
    for name, values, code in (("cushion-impact", CUSHION[0], PathCode.EXACT),
                               ("spheres-free", SPHERES[0], PathCode.EXACT),
                               ("spheres-cloth", SPHERES[0], PathCode.EXACT),
                               ("spheres-cloth", CLOTH[6], PathCode.EXACT)):
        m = registry.MODELS[name]
        p = next(q for q in m.paths if q.code == code)
        assert p.scalar
        res = paths.solve(m, m.scene(values), "auto")
        assert int(res.path) == code and res.label.startswith("auto: 1 by ")


def _decay_both(phi0, psi0, alpha, beta, tau):
    one = slip.slip_decay(*(np.float64(x) for x in (phi0, psi0, alpha, beta, tau)))
    arr = slip.slip_decay(*(np.array([x], dtype=float) for x in (phi0, psi0, alpha, beta, tau)))
    assert all(type(x) is np.float64 for x in one)
    for a, b in zip(one, arr, strict=True):
        np.testing.assert_array_equal(_bits(np.array([a])), _bits(b), err_msg=str((phi0, psi0, alpha, beta, tau)))


@pytest.mark.parametrize("phi0,psi0,alpha,beta", [
    (0.8, 0.9, 3.5, 2.5), (3.0, 0.06, 3.5, 2.5), (0.06, 3.0, 3.5, 2.5), (3.0, 0.06, 2.5, 3.5),  # turning; swapped
    (3.0, 0.06, 41.0, 40.0), (3.0, 0.06, 10.0, 9.0), (3.0, 0.06, 2.5, 1.5), (1e-3, 5.0, 60.0, 0.6),
    (1.0, 0.0, 3.5, 2.5), (0.0, 1.0, 3.5, 2.5), (0.0, 0.0, 3.5, 2.5), (0.6, 0.8, 2.0, 2.0),  # elementary
])
def test_the_decay_of_one_scene_on_floats_is_the_batch_decay(phi0, psi0, alpha, beta):
    total = float(slip.SlipDecay(np.array([phi0]), np.array([psi0]), np.array([alpha]), np.array([beta])).total[0])
    scale = total if np.isfinite(total) else np.hypot(phi0, psi0) / min(alpha, beta)
    for frac in (-0.1, 0.0, 1e-9, 0.3, 0.7, 0.999999, 1.0, 1.5):  # before, at the start, inside, at and past the stop
        _decay_both(phi0, psi0, alpha, beta, frac * scale)


_pos = st.floats(1e-4, 1e3)


@settings(max_examples=300, deadline=None)
@given(phi0=st.one_of(st.just(0.0), _pos), psi0=st.one_of(st.just(0.0), _pos), beta=st.floats(0.3, 60.0),
       ratio=st.one_of(st.just(1.0), st.floats(0.02, 50.0)), frac=st.floats(-0.2, 1.3))
def test_the_decay_on_floats_is_the_batch_decay_on_drawn_scenes(phi0, psi0, beta, ratio, frac):
    alpha = beta * ratio
    scale = np.hypot(phi0, psi0) / min(alpha, beta)
    _decay_both(phi0, psi0, alpha, beta, frac * scale)


def _cloth_values(rng):
    """One drawn scene of two balls on the cloth, over wide ranges: masses, radii, k and k′ apart, slips from
    none to 1e5 times the approach speed, one or both slip components, ε and ε′ at their ends."""
    def vec(scale, zero_z=False):
        x = rng.normal(size=3) * scale * rng.choice([0.0, 1.0, 1.0])
        x[rng.random(3) < 0.25] = 0.0
        if zero_z:
            x[2] = 0.0
        return x.tolist()

    v, vp = vec(1.0, True), vec(1.0, True)
    v[0], vp[0] = abs(v[0]) + 10.0 ** rng.uniform(-3, 0.5), -abs(vp[0])
    return {"v": v, "vp": vp, "w": vec(10.0 ** rng.uniform(-1, 4)), "wp": vec(10.0 ** rng.uniform(-1, 3)),
            "f": float(rng.choice([0.0, rng.uniform(0, 1), 10.0 ** rng.uniform(-4, 0)])),
            "eps": float(rng.choice([0.0, 1.0, rng.uniform()])), "epsp": float(rng.choice([0.0, 1.0, rng.uniform()])),
            "k": float(rng.uniform(1.0, 12.0)), "kp": float(rng.choice([2.5, rng.uniform(1.0, 12.0)])),
            "M": float(10.0 ** rng.uniform(-2, 1)), "Mp": float(10.0 ** rng.uniform(-2, 1)),
            "R": float(rng.uniform(0.01, 0.05)), "Rp": float(rng.uniform(0.01, 0.05))}


@pytest.mark.parametrize("seed", range(4))
def test_the_cloth_end_of_impact_on_floats_is_the_batch_one_on_drawn_scenes(seed):
    """§VI's exact path on one scene: numpy floats (``spheres._cloth_normal_impulse_one``) against the batch of
    one, bit for bit, over drawn scenes; every regime and both kinds of decay (the slip turns, or keeps to one
    component) are reached."""
    m = registry.MODELS["spheres-cloth"]
    rng = np.random.default_rng(1000 + seed)
    regimes, turning = set(), 0
    with np.errstate(all="ignore"):
        for _ in range(60):
            values = _cloth_values(rng)
            for shape in ((), (1,)):
                s = m.scene({k: np.reshape(np.asarray(x, dtype=float), (*shape, *np.shape(x)))
                             for k, x in values.items()})
                if not np.all(m.admissible(s)):
                    continue
                got = paths.by_route(m, s, "exact", "small")
                _same(got, paths.by_route(m, s, "exact", "general"), f"spheres-cloth/exact {values}")
                regimes.update(np.ravel(got.regime).tolist())
            sy = values["v"][1] - values["vp"][1] + values["R"] * values["w"][2] + values["Rp"] * values["wp"][2]
            sz = -values["R"] * values["w"][1] - values["Rp"] * values["wp"][1]
            turning += sy != 0 and sz != 0 and values["f"] > 0
    assert {Regime.SLIDE, Regime.GRIP, Regime.NO_SLIP} <= regimes, regimes
    assert turning >= 10, turning
