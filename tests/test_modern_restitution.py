"""modern-restitution: published restitutions and a mean separation angle (Sudo & Shibata 2002) against §I and §VI."""

import math
from pathlib import Path

import numpy as np
import pytest

from reproductions import api
from reproductions.config import load_experiment
from reproductions.errors import InputError
from reproductions.experiments import KINDS, restitution
from reproductions.mechanics import impact, spheres

CONFIGS = Path(__file__).resolve().parent.parent / "configs"
DATA = CONFIGS / "data" / "sudo-shibata-2002.csv"


@pytest.fixture(scope="module")
def rep():
    return api.run(api.load("modern-restitution"))


def test_eps_from_the_published_restitutions():
    """§I eq. (9) inverted: ε = (1 − e)/(1 + e); a wall impact with it gives the ratio back, and eq. (7) with ε = ε′
    gives Newton's e back for equal balls."""
    assert float(restitution.eps_of(0.856)) == pytest.approx(0.144 / 1.856, rel=1e-12)
    assert float(restitution.eps_of(0.856)) == pytest.approx(0.0776, abs=5e-5)
    assert float(restitution.eps_of(0.745)) == pytest.approx(0.1461, abs=5e-5)
    assert float(impact.wall_impact(1.0, eps=restitution.eps_of(0.856)).V1) == pytest.approx(-0.856, rel=1e-12)
    eps = restitution.eps_of(0.897)
    assert float(impact.newton_restitution(1.0, 1.0, eps, eps)) == pytest.approx(0.897, rel=1e-12)
    # the paper's cushion: Coriolis's 0.55 → the printed ε = 0,29
    assert float(restitution.eps_of(0.55)) == pytest.approx(0.29, abs=5e-3)


def test_smooth_separation_closed_form_against_two_spheres():
    R, M, e = 0.028586, 0.16862, 0.897
    psi = np.radians([10.0, 30.0, 60.0])
    th = restitution.theta_spheres(psi, e, 0.0, R, M, 2.5)
    assert th == pytest.approx(restitution.theta_smooth(psi, e), abs=1e-8)
    assert restitution.theta_smooth(psi, 1.0) == pytest.approx(np.full(3, 90.0), abs=1e-12)
    # independent of the ball (free balls, a stun shot, give the same smooth angle)
    eps = float(restitution.eps_of(e))
    v0 = np.stack([np.cos(psi), -np.sin(psi), 0 * psi], -1)
    imp = spheres.two_spheres(1.0, 1.0, 1.0, 1.0, 2.5, 2.5, v0, 0 * v0, 0 * v0, 0 * v0, f=0.0, eps=eps, epsp=eps)
    sep = np.degrees(np.arctan2(imp.v1p[:, 1], imp.v1p[:, 0]) - np.arctan2(imp.v1[:, 1], imp.v1[:, 0]))
    assert sep == pytest.approx(restitution.theta_smooth(psi, e), abs=1e-8)


def test_mean_over_shots():
    assert restitution.mean_over_b(lambda s: restitution.theta_smooth(s, 1.0), 400) == pytest.approx(90.0)
    # ⟨θ⟩ = ∫ θ(ψ) cos ψ dψ: checked by a plain midpoint rule in ψ
    n = 200_000
    psi = (np.arange(n) + 0.5) * (math.pi / 2) / n
    ref = float(np.sum(restitution.theta_smooth(psi, 0.897) * np.cos(psi)) * (math.pi / 2) / n)
    got = restitution.mean_over_b(lambda s: restitution.theta_smooth(s, 0.897), 400)
    assert got == pytest.approx(ref, abs=1e-3)
    assert got == pytest.approx(79.19, abs=0.01)


def test_the_rows(rep):
    rows = {m.id: m for m in rep.measurements}
    expected = {"eps_cushion_low": "inconsistent", "eps_cushion_all": "inconsistent", "eps_constant": "inconsistent",
                "eps_ball_ball": "consistent", "contact_time": "not-checkable", "separation_mean": "not-checkable",
                "transverse_momentum": "not-checkable"}
    assert {k: rows[k].verdict for k in expected} == expected
    assert rows["eps_cushion_low"].measured == pytest.approx(0.0776, abs=5e-5)
    assert rows["eps_cushion_low"].predicted == pytest.approx(0.29, abs=5e-3)
    # no error is published: every uncertainty is a rounding bound, and the verdicts say so
    for k in ("eps_cushion_low", "eps_cushion_all", "eps_constant", "eps_ball_ball", "contact_time",
              "separation_mean"):
        assert "a rounding bound" in rows[k].uncertainty and "not a measurement error" in rows[k].uncertainty, k
    for k in ("eps_cushion_low", "eps_cushion_all", "eps_constant", "eps_ball_ball"):
        assert "rounding bound" in rows[k].note, k
    assert "0.040" in rows["eps_constant"].note  # the regressions' error that would make them agree
    assert rows["contact_time"].note.startswith("a definition: ")
    assert rows["transverse_momentum"].note.startswith("a definition: ")
    # the separation angle: a prediction for each spread of shots, no verdict on one choice
    sep = rows["separation_mean"]
    assert sep.note.startswith("a modelling choice: ")
    assert sep.predicted is None and sep.interval is None
    for number in ("79.19°, 77.10°, 76.44°", "82.54°, 80.11°, 79.32°", "85.28°, 82.99°, 82.26°", "e = 0.963",
                   "inside their range"):
        assert number in sep.note, number
    table = {t.name: t for t in rep.tables}["separation-by-spread"]
    assert table.headers == ("spread of shots", "smooth", "f = 0.06", "f = 0.08")
    assert [r[1] for r in table.rows] == pytest.approx([79.19, 82.54, 85.28], abs=0.01)
    assert {f.name for f in rep.figures} == {"separation-angle", "cushion-eps"}
    assert all(f.reading for f in rep.figures)


def test_spread_means_against_a_midpoint_rule():
    """⟨θ⟩ over a spread: ψ uniform on [10°, 70°] and u = sin ψ uniform on [0, 1), against plain midpoint rules."""
    exp = api.load("modern-restitution")
    p = exp.params
    R, M = p.get("ball_diameter").value / 2, p.get("ball_mass").value
    n = 20_000
    for spread, lo, hi in (("cut_angle", 10.0, 70.0), ("impact_parameter", 0.0, 90.0)):
        sp = restitution.Spread(spread, lo, hi)
        psi, w = restitution.spread_nodes(sp, p.nodes)
        assert float(np.sum(w)) == pytest.approx(1.0, abs=1e-12)
        got = float(restitution.theta_spheres(psi, 0.897, 0.06, R, M, p.k) @ w)
        if spread == "cut_angle":
            mid = np.radians(lo + (np.arange(n) + 0.5) * (hi - lo) / n)
        else:
            mid = np.arcsin((np.arange(n) + 0.5) / n)
        ref = float(np.mean(restitution.theta_spheres(mid, 0.897, 0.06, R, M, p.k)))
        assert got == pytest.approx(ref, abs=2e-3)


def test_a_missing_quantity_is_refused_naming_the_file(tmp_path):
    data = tmp_path / "data"
    data.mkdir()
    csv = data / "sudo-shibata-2002.csv"
    csv.write_text("\n".join(ln for ln in DATA.read_text(encoding="utf-8").splitlines()
                             if not ln.startswith("separation_angle_mean")) + "\n", encoding="utf-8")
    cfg = tmp_path / "modern-restitution.yaml"
    cfg.write_text((CONFIGS / "modern-restitution.yaml").read_text(encoding="utf-8"), encoding="utf-8")
    with pytest.raises(InputError) as err:
        load_experiment(cfg, KINDS)
    assert err.value.where.startswith(f"{csv}:")
    assert "separation_angle_mean" in err.value.message


def test_the_findings_quote_only_their_rows_values(rep):
    from test_modern_head_on import carried_numbers_hold

    assert carried_numbers_hold(rep) == []


def test_gauss_legendre_nodes_and_weights():
    for n in (20, 400):
        x, w = restitution._gauss(n)
        ref_x, ref_w = np.polynomial.legendre.leggauss(n)
        assert x == pytest.approx(ref_x, abs=1e-13)
        assert w == pytest.approx(ref_w, abs=1e-12)
