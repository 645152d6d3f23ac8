"""modern-head-on: one filmed head-on collision (Derby & Fuller 1999) against §VI then §II."""

from pathlib import Path

import numpy as np
import pytest

from reproductions import api
from reproductions.config import load_experiment
from reproductions.errors import InputError
from reproductions.experiments import KINDS, headon

CONFIGS = Path(__file__).resolve().parent.parent / "configs"
DATA = CONFIGS / "data" / "derby-fuller-1999.csv"


@pytest.fixture(scope="module")
def pub():
    return headon.read_published(DATA, headon.REQUIRED)


@pytest.fixture(scope="module")
def rep():
    return api.run(api.load("modern-head-on"))


def test_the_published_numbers_own_identities(pub):
    M, V = pub["ball_mass"].value, pub["incident_speed"].value
    # momentum before: M V is the published value to its printed digit
    assert abs(M * V - pub["momentum_before"].value) <= pub["momentum_before"].digit / 2
    # momentum after 'once both roll' is not M (v_cf + v_tf) of the published final speeds
    after = M * (pub["cue_final_speed"].value + pub["target_final_speed"].value)
    assert after == pytest.approx(0.1420, abs=5e-5)
    assert pub["momentum_after"].value - after > 0.008
    # the energy left once both roll is at most (v_cf² + v_tf²)/V² (rolling adds energy to that, the cue ball's
    # topspin before the impact adds to the denominator's): a loss of 0.58 or more, not 0.17
    left = (pub["cue_final_speed"].value ** 2 + pub["target_final_speed"].value ** 2) / V**2
    assert left == pytest.approx(0.42, abs=5e-3)
    assert 1 - left > 3 * pub["kinetic_energy_loss"].value
    # §II's kinematics of the data alone: the speeds right after the impact break momentum by ~16 %
    v1 = pub["cue_final_speed"].value - pub["cue_sliding_acceleration"].value * pub["cue_sliding_time"].value
    v1p = pub["target_final_speed"].value - pub["target_sliding_acceleration"].value * pub["target_sliding_time"].value
    assert (v1 + v1p) / V == pytest.approx(0.844, abs=1e-3)


def test_published_uncertainties(pub):
    assert pub["cue_sliding_acceleration"].sigma == 0.31  # stated standard error
    assert pub["cue_sliding_time"].digit == pytest.approx(0.001)
    assert pub["cue_sliding_time"].sigma == pytest.approx(0.001 / np.sqrt(12))
    assert pub["kinetic_energy_loss"].digit == pytest.approx(0.01)


def test_inferred_spin_and_e_reproduce_the_object_balls_final_speed_and_the_cue_balls_slip(pub):
    ball = headon.Ball(pub["ball_mass"].value, pub["ball_diameter"].value / 2, 2.5, 9.81)
    V = np.array([0.98, 0.975, 0.985])
    f = np.array([0.03, 0.055, 0.08])
    mug = np.array([1.93, 1.80, 2.05])
    a_c, t_c = np.array([3.13, 2.9, 3.3]), np.array([0.09, 0.0895, 0.0905])
    v_tf = np.array([0.583, 0.5825, 0.5835])
    s, e = headon.infer(ball, V, f, mug, a_c, t_c, v_tf)
    out = headon.predict(ball, V, s, e, f, mug)
    assert out["target_final_speed"] == pytest.approx(v_tf, abs=1e-6)
    assert out["cue_slip"] == pytest.approx(-(1 + 2.5) * a_c * t_c, abs=1e-6)
    assert np.all(s > 1.0)  # more topspin than natural roll
    assert np.all((0.6 < e) & (e < 0.9))
    # §II: the cue ball, slipping backwards on the cloth, is sped up for |u1|/((1 + k) μ g)
    assert out["cue_sliding_time"] == pytest.approx(a_c * t_c / mug, rel=1e-6)


def test_f_acts_head_on_through_the_topspin(pub):
    """The cue ball's topspin makes its contact slip downwards on the object ball: f gives the object ball backspin."""
    ball = headon.Ball(pub["ball_mass"].value, pub["ball_diameter"].value / 2, 2.5, 9.81)
    out = headon.predict(ball, 0.98, 1.0, 0.93, np.array([0.0, 0.08]), 1.93)
    assert out["Rw1p"][0] == pytest.approx(0.0, abs=1e-12)
    assert out["Rw1p"][1] < 0
    assert out["target_final_speed"][1] < out["target_final_speed"][0]
    # momentum is kept in the impact whatever f
    assert out["v1"] + out["v1p"] == pytest.approx(np.full(2, 0.98), rel=1e-12)


def test_verdict_logic_on_constructed_cases():
    rng = np.random.default_rng(0)
    inside = headon.judge(rng.normal(1.0, 0.1, 4000), rng.normal(1.05, 0.01, 4000))
    assert inside[0] == "consistent" and inside[1][0] < 0 < inside[1][1]
    disjoint = headon.judge(rng.normal(1.0, 0.01, 4000), rng.normal(2.0, 0.01, 4000))
    assert disjoint[0] == "inconsistent" and disjoint[1][1] < 0
    # the measurement's own uncertainty counts: a sharp prediction inside a wide measurement is consistent
    assert headon.judge(np.full(4000, 1.0), rng.normal(1.1, 0.1, 4000))[0] == "consistent"


def test_the_verdict_table(rep):
    rows = {m.id: m for m in rep.measurements}
    expected = {"mu_common": "inconsistent", "cue_sliding_time": "not-checkable",
                "target_sliding_time": "not-checkable", "cue_final_speed": "not-checkable",
                "target_final_speed": "fitted", "e_vs_modern": "inconsistent", "momentum_before": "not-checkable",
                "momentum_after": "not-checkable", "kinetic_energy_loss": "not-checkable",
                "impact_momentum": "not-checkable"}
    assert {k: rows[k].verdict for k in expected} == expected
    # a not-checkable row says why: a definition (it cannot fail) or a modelling choice of ours (both readings)
    prefix = {"momentum_before": "a definition: ", "impact_momentum": "a definition: "}
    for k, v in expected.items():
        if v == "not-checkable":
            assert rows[k].note.startswith(prefix.get(k, "a modelling choice: ")), (k, rows[k].note)
    # head on the slip is vertical only: law (6) returns the normal velocity in the ratio e (spheres docstring), so
    # the e the object ball's speed needs is the impact's normal ratio, draw by draw
    assert rows["e_vs_modern"].predicted == pytest.approx(0.763, abs=0.005)
    assert "normal velocities 0.763 [0.718, 0.810]" in rows["e_vs_modern"].note
    # both readings are shown where the reading decides: (A) spin from the cue ball's acceleration, (B) natural roll
    cue = rows["cue_final_speed"].note
    assert "(A)" in cue and "(B)" in cue and "0.397 [0.336, 0.460]" in cue and "e = 0.874" in cue
    assert "f = 0.111" in cue
    assert "mu_common restated" in rows["cue_sliding_time"].note
    tgt = rows["target_sliding_time"].note
    assert ": consistent" in tgt and ": inconsistent" in tgt and "rounding bound" in tgt
    for m in rep.measurements:
        if m.interval is not None and m.predicted is not None:
            assert m.interval[0] <= m.predicted <= m.interval[1]
        if "half its last printed digit" in m.uncertainty:
            assert "a rounding bound" in m.uncertainty and "not a measurement error" in m.uncertainty
    fits = {f.id: f for f in rep.fits}
    assert fits["design-a.s"].value == pytest.approx(1.25, abs=0.03)
    assert "infers" in fits["design-a.s"].note
    assert fits["design-a.mu"].value == pytest.approx(0.1968, abs=5e-4)
    assert not fits["prior.f"].identifiable
    assert fits["natural-roll.e"].value == pytest.approx(0.874, abs=5e-4)
    assert fits["natural-roll.f"].value == pytest.approx(0.111, abs=5e-4)
    assert {f.name for f in rep.figures} == {"head-on-speeds", "head-on-verdicts"}
    assert all(f.reading for f in rep.figures)


def test_natural_roll_fits_both_final_speeds(pub):
    """Reading B: s = 1, e and f solved for both published final speeds at the published incident speed."""
    ball = headon.Ball(pub["ball_mass"].value, pub["ball_diameter"].value / 2, 2.5, 9.81)
    e, f = headon.fit_natural_roll(ball, np.array([0.98]), np.array([0.251]), np.array([0.583]))
    c, t = headon.rolling_speeds(ball, 0.98, 1.0, e, f)
    assert c == pytest.approx([0.251], abs=1e-9) and t == pytest.approx([0.583], abs=1e-9)
    assert e[0] == pytest.approx(0.8743, abs=1e-4) and f[0] == pytest.approx(0.1113, abs=1e-4)
    # head on, while the vertical slip lasts: v1′ = V (1 + e)/2 and R ω1′ = −k f V (1 + e)/2, so the object ball
    # rolls at k V (1 + e)(1 − f)/(2 (1 + k)), the cue ball at (k V (1 − e)/2 + V − k f V (1 + e)/2)/(1 + k)
    k, V = 2.5, 0.98
    assert t[0] == pytest.approx(k * V * (1 + e[0]) * (1 - f[0]) / (2 * (1 + k)), rel=1e-9)
    assert c[0] == pytest.approx((k * V * (1 - e[0]) / 2 + V - k * f[0] * V * (1 + e[0]) / 2) / (1 + k), rel=1e-9)
    with pytest.raises(ValueError):
        headon.fit_natural_roll(ball, np.array([0.98]), np.array([0.9]), np.array([0.9]))


def test_the_run_is_seeded(rep):
    again = api.run(api.load("modern-head-on"))
    assert [m.interval for m in again.measurements] == [m.interval for m in rep.measurements]


def _config_with(tmp_path, csv_text):
    data = tmp_path / "data"
    data.mkdir()
    (data / "derby-fuller-1999.csv").write_text(csv_text, encoding="utf-8")
    cfg = tmp_path / "modern-head-on.yaml"
    cfg.write_text((CONFIGS / "modern-head-on.yaml").read_text(encoding="utf-8"), encoding="utf-8")
    return cfg, data / "derby-fuller-1999.csv"


def test_a_missing_quantity_is_refused_naming_the_file(tmp_path):
    lines = DATA.read_text(encoding="utf-8").splitlines()
    cfg, csv = _config_with(tmp_path, "\n".join(ln for ln in lines if not ln.startswith("cue_final_speed")) + "\n")
    with pytest.raises(InputError) as err:
        load_experiment(cfg, KINDS)
    assert err.value.where.startswith(f"{csv}:")
    assert "cue_final_speed" in err.value.message


def test_a_bad_value_is_refused_at_its_line(tmp_path):
    text = DATA.read_text(encoding="utf-8").replace("incident_speed,0.98,", "incident_speed,fast,")
    cfg, csv = _config_with(tmp_path, text)
    line = next(i + 1 for i, ln in enumerate(text.splitlines()) if ln.startswith("incident_speed"))
    with pytest.raises(InputError) as err:
        load_experiment(cfg, KINDS)
    assert err.value.where == f"{csv}:{line}"


def carried_numbers_hold(rep) -> list[str]:
    """The numbers (with a decimal point) each finding quotes that none of its rows carries (measured, predicted,
    interval ends, and the numbers written in its published text, uncertainty and note), within the rounding of the
    written digits."""
    import re

    rows = {m.id: m for m in rep.measurements}
    bad = []
    for f in rep.experiment.findings:
        vals = set()
        for r in f.rows:
            m = rows[r]
            vals |= {abs(v) for v in (m.measured, m.predicted, *(m.interval or ())) if v is not None}
            for text in (m.measured_text, m.uncertainty, m.note):
                vals |= {float(t) for t in re.findall(r"\d+(?:\.\d+)?", text)}
        for tok in re.findall(r"(?<![\w.])\d+\.\d+", f.text):
            half = 0.5 * 10.0 ** -len(tok.split(".")[1]) * (1 + 1e-9)
            if not any(abs(v - float(tok)) <= half for v in vals):
                bad.append(f"{f.id}: {tok}")
    return bad


def test_the_findings_quote_only_their_rows_values(rep):
    assert carried_numbers_hold(rep) == []
