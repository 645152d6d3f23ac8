"""§II and §VII: closed forms against direct integration, the stroke's invariants, the experiments' verdicts."""

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from cli.main import app
from reproductions import api
from reproductions.mechanics import cloth, cue, impact, reference

R, K = 0.0305, 2.5


def test_cloth_closed_form_matches_integration_sliding_and_rolling():
    rng = np.random.default_rng(2)
    worst = 0.0
    for _ in range(10):
        vx, vy = rng.uniform(-3, 3, 2)
        wx, wy = rng.uniform(-150, 150, 2)
        m = cloth.slide(vx, vy, wx, wy, R=R, k=K, f=0.25, g=9.81)
        t1 = float(m.t_roll)
        state, t_ev = reference.integrate_cloth(vx, vy, wx, wy, R, K, 0.25, 9.81, 3 * t1)
        assert t_ev == pytest.approx(t1, rel=1e-8)
        ts = np.linspace(0, 2.5 * t1, 11)
        x, y, u, v = cloth.state_at(ts, vx, vy, wx, wy, R=R, k=K, f=0.25, g=9.81)
        ref = np.array([state(t) for t in ts])
        worst = max(worst, float(np.max(np.abs(ref[:, :4] - np.c_[x, y, u, v]))))
    assert worst < 1e-9


def test_cloth_state_is_vectorised_over_scenes_and_times():
    vx = np.array([1.0, 2.0, 0.5])
    x, *_ = cloth.state_at(np.linspace(0, 1, 5), vx, 0.0, 30.0, 0.0, R=R, k=K, f=0.25, g=9.81)
    assert x.shape == (3, 5)
    for j in range(3):
        xj, *_ = cloth.state_at(np.linspace(0, 1, 5), vx[j], 0.0, 30.0, 0.0, R=R, k=K, f=0.25, g=9.81)
        np.testing.assert_allclose(x[j], xj, rtol=1e-14)


def test_rolling_resistance_stops_the_ball_and_a_rolling_ball_skips_sliding():
    m = cloth.slide(1.0, 0.0, 0.0, 1.0 / R, R=R, k=K, f=0.25, g=9.81)  # v = Rω: already rolling
    assert float(m.t_roll) < 1e-15
    x, _, vx, _ = cloth.state_at(np.array([0.0, 1.0, 100.0]), 1.0, 0.0, 0.0, 1.0 / R, R=R, k=K, f=0.25, g=9.81,
                                 f_roll=0.01)
    stop = 1.0 / (0.01 * 9.81)
    assert vx[-1] == 0.0 and x[-1] == pytest.approx(0.5 * stop, rel=1e-12)


def test_coriolis_centre_of_oscillation_gives_immediate_rolling():
    h = float(cloth.centre_of_oscillation(R, K))
    M, P = 0.21, 0.4
    for height, rolls in ((h, True), (0.8 * h, False), (1.2 * h, False)):
        # a horizontal impulse P at `height` above the centre: v = P/M, ω_y = P·height·k/(M R²)
        m = cloth.slide(P / M, 0.0, 0.0, P * height * K / (M * R**2), R=R, k=K, f=0.25, g=9.81)
        assert (float(m.t_roll) < 1e-12) == rolls
    # and the stroke model of §VII agrees: a horizontal cue at that height leaves no slip on the cloth
    s = cue.cue_stroke(M, 0.63, 3.0, 0.0, 0.0, h, R=R, k=K, f=0.25, eps=0.0, epsp=0.8)
    assert float(s.chi1 - s.p1 * R) == pytest.approx(0.0, abs=1e-12)


def test_cue_closed_form_matches_the_impulse_integration_in_both_cloth_regimes():
    rng = np.random.default_rng(3)
    regimes = set()
    for _ in range(25):
        i = math.radians(rng.uniform(0, 85))
        b, c = rng.uniform(-0.7, 0.7, 2) * R
        f = rng.uniform(0.05, 0.8)
        for method, full in (("exact", True), ("resal", False)):
            per = cue.stroke_per_impulse(i, b, c, R=R, k=K, f=f, M=0.21, method=method)
            y = reference.integrate_cue_impulse(i, float(per["a"]), b, c, R, K, f, 0.21, 0.4, moment_a_term=full)
            closed = np.r_[per["v"], per["w"]] * 0.4
            np.testing.assert_allclose(y, closed, atol=1e-6 * 0.4 / 0.21 / R)
            regimes.add(bool(per["slides"]))
    assert regimes == {True, False}


def test_cue_exact_path_never_gains_energy_and_resal_path_does():
    rng = np.random.default_rng(4)
    n = 2000
    i = np.radians(rng.uniform(0, 80, n))
    rad = np.sqrt(rng.uniform(0, 0.49, n))
    th = rng.uniform(0, 2 * np.pi, n)
    b, c = R * rad * np.cos(th), R * rad * np.sin(th)
    M, Mp, V = 0.21, 0.63, 3.0
    gains = {}
    for method in ("exact", "resal"):
        s = cue.cue_stroke(M, Mp, V, i, b, c, R=R, k=K, f=0.25, eps=0.0, epsp=0.8, method=method)
        T1 = Mp * s.V1p**2 + M * (s.chi1**2 + s.eta1**2) + M * R * R / K * (s.n1**2 + s.p1**2 + s.q1**2)
        gains[method] = T1 / (Mp * V**2) - 1
    assert gains["exact"].max() <= 1e-12
    assert (gains["resal"] > 1e-6).mean() > 0.2


def test_central_stroke_is_the_direct_impact_of_n5():
    s = cue.cue_stroke(0.21, 0.63, 3.0, 0.0, 0.0, 0.0, R=R, k=K, f=0.25, eps=0.1, epsp=0.3)
    d = impact.direct_impact(0.63, 0.21, 3.0, 0.0, eps=0.3, epsp=0.1)
    assert float(s.chi1) == pytest.approx(float(d.V1p), rel=1e-12)
    assert float(s.V1p) == pytest.approx(float(d.V1), rel=1e-12)


def test_experiments_verdicts():
    rows = {r.id: r for r in api.run(api.load("cloth-slide")).rows}
    for rid in ("eq3", "eq4", "t1", "x1", "tangent", "footnote", "coriolis"):
        assert rows[rid].verdict == "reproduced", rid
    assert rows["eq5"].verdict == "differs" and rows["y1"].verdict == "differs"
    rows = {r.id: r for r in api.run(api.load("cue-stroke")).rows}
    for rid in ("eq5_own", "eq7", "angle_high"):
        assert rows[rid].verdict == "reproduced", rid
    assert rows["central"].verdict == "reproduced" and rows["central"].computed > 0
    for rid in ("eq6", "eqc", "criterion_derived"):
        assert rows[rid].verdict == "not-checkable" and rows[rid].note.startswith("a definition: "), rid
    for rid in ("eq5", "eq7_n1", "energy", "angle_low", "epsp", "criterion"):
        assert rows[rid].verdict == "differs" and rows[rid].note, rid
    assert rows["epsp"].computed == pytest.approx(0.8, rel=1e-12)


@pytest.mark.parametrize("args, message", [
    (["cloth-slide", "--set", "f=0"], "'f' must be a number > 0"),
    (["cue-stroke", "--set", "i=90"], "'i' must be a number in [0, 90) (degrees)"),
    (["cue-stroke", "--set", "i=-5"], "'i' must be a number in [0, 90) (degrees)"),
    (["cue-stroke", "--set", "b=0.03", "--set", "c=0.02"], "the contact point must lie on the ball"),
    (["cue-stroke", "--set", "i=80", "--set", "c=-0.025"], "where the cue can reach it"),
    (["cloth-slide", "--method", "resal"], "cloth-slide has no path 'resal'"),
])
def test_bad_scene_input(args, message):
    coefficients = {"cloth-slide": ["--set", "f=0.25"],
                    "cue-stroke": ["--set", "f=0.25", "--set", "eps=0", "--set", "epsp=0.8"]}[args[0]]
    res = CliRunner().invoke(app, ["simulate", args[0], *coefficients, *args[1:]])
    assert res.exit_code == 2 and message in " ".join(res.stderr.split())
    assert "Traceback" not in res.output


def test_a_ball_already_rolling_is_the_trivial_answer_not_nan():
    res = CliRunner().invoke(app, ["simulate", "cloth-slide", "--set", "vx=0", "--set", "f=0.25", "--json"])
    assert res.exit_code == 0
    import json

    out = json.loads(res.stdout)
    assert out["outputs"]["t_roll"] == 0.0 and out["regime_name"] == "no-slip"  # a code, not a note
