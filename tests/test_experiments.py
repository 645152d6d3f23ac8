"""The §I experiments: verdicts of the printed values, and what the fits say."""

import pytest

from reproductions import api


def _rows(eid):
    rep = api.run(api.load(eid))
    return rep, {r.id: r for r in rep.rows}


def test_pendulum_reproduces_the_paper_reading_and_flags_the_swap():
    rep, rows = _rows("coriolis-pendulum")
    assert rows["combination"].computed == pytest.approx(24 / 5, rel=1e-12)
    assert rows["epsp_fraction"].verdict == "reproduced"
    assert rows["epsp_decimal"].verdict == "reproduced"
    one = rows["n_equations"]  # « un résultat unique »: both eqs (8) give the same D, a single equation
    assert one.verdict == "reproduced" and one.computed < 1e-12
    assert rows["eps_premise"].computed == pytest.approx(0.8, rel=1e-12)
    assert rows["swapped_vii"].verdict == "differs"
    assert rows["swapped_vii"].computed == pytest.approx(6 / (1 + 4 / 15 + 3), rel=1e-12)
    assert abs(rows["momentum_balance"].computed) < 1e-12
    fit_by_name = {f.parameter: f for f in rep.fits}
    assert not fit_by_name["ε (cue)"].identifiable
    assert fit_by_name["ε (cue)"].family_range == pytest.approx((0.0, 0.8), abs=1e-6)
    (ident,) = rep.identifiability
    assert ident["rank"] == 1
    (null,) = ident["null_directions"]
    assert null[0] / null[1] == pytest.approx(-3.0, rel=1e-9)  # ε + 3ε′ unchanged along it
    ends = sorted(map(tuple, ident["family_of_solutions"]["ends"]))
    assert [v for end in ends for v in end] == pytest.approx([0.0, 4 / 15, 0.8, 0.0], abs=1e-9)
    (comb,) = [f for f in rep.fits if "+" in f.parameter]
    assert comb.value == pytest.approx(0.8, rel=1e-6)
    assert comb.ci95[0] < 0.8 < comb.ci95[1]


def test_cushion_eps_is_reproduced_and_the_synthetic_fit_is_labelled():
    rep, rows = _rows("coriolis-cushion")
    assert rows["eps"].computed == pytest.approx(0.45 / 1.55, rel=1e-12)
    assert rows["eps"].verdict == "reproduced"
    series_fit = rep.fits[1]
    assert "SYNTHETIC" in series_fit.note
    assert series_fit.ci95[0] < rows["eps"].computed < series_fit.ci95[1]
    assert "SYNTHETIC" in rep.data_note


def test_marble_eps_differs_with_a_reason():
    _, rows = _rows("marble-drop")
    r = rows["eps"]
    assert r.computed == pytest.approx((1 - (2 / 3) ** 0.5) / (1 + (2 / 3) ** 0.5), rel=1e-12)
    assert r.verdict == "differs"
    assert "slip" in r.note
    assert rows["velocity_ratio"].verdict == "differs" and "truncated" in rows["velocity_ratio"].note
    assert rows["eps_no_rebound"].verdict == "not-checkable"


def test_printed_tolerance_follows_the_printed_digits():
    exp = api.load("coriolis-pendulum")
    p = {x.id: x for x in exp.printed}
    assert p["epsp_decimal"].tolerance == pytest.approx(0.005 / 0.27)
    assert p["epsp_fraction"].tolerance == pytest.approx(1e-9)
    assert p["momentum_balance"].value is None


def test_printed_formulas_agree_with_the_integration_and_a_wrong_one_would_not():
    from reproductions.experiments import pendulum
    from reproductions.experiments.base import Computed, compare

    _, rows = _rows("coriolis-pendulum")
    for rid in ("eq_b", "eq7", "eq8"):
        assert rows[rid].verdict == "reproduced" and rows[rid].printed is None
        assert rows[rid].computed < 1e-7
    p = next(x for x in api.load("coriolis-pendulum").printed if x.id == "eq7")
    # a mis-transcribed (7), with M and M′ swapped in the denominator, is caught by the same check
    M, Mp, V0, eps, epsp = 3.0, 1.0, 1.0, 0.1, 0.4
    good = pendulum._printed_eq7(M, Mp, V0, 0.0, eps, epsp)[1]
    den_swapped = M * (1 + eps) + Mp * (1 + epsp)
    wrong = 2 * M * V0 / den_swapped
    assert compare(p, Computed(abs(wrong - good))).verdict == "differs"


def test_a_formula_row_takes_no_value(tmp_path):
    from reproductions.errors import InputError

    text = (api.config_dir() / "coriolis-cushion.yaml").read_text()
    text = text.replace("    formula: true\n", "    formula: true\n    value: 0\n", 1)
    cfg = tmp_path / "f.yaml"
    cfg.write_text(text)
    with pytest.raises(InputError, match="is a formula"):
        api.load(str(cfg))


def test_user_csv_rebounds_are_fitted(tmp_path):
    import numpy as np

    from reproductions.mechanics import impact

    rng = np.random.default_rng(5)
    V0 = rng.uniform(0.5, 5, 30)
    V1 = impact.infinite_mass_impact(V0, eps=0.35) * (1 + 0.02 * rng.standard_normal(30))
    rows = "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(V0, V1, strict=True))
    (tmp_path / "trials.csv").write_text("V0,V1\n" + rows)
    text = (api.config_dir() / "coriolis-cushion.yaml").read_text()
    text = text.replace("synthetic: {n: 24, low: 0.5, high: 7.0, noise: 0.03}", "csv: trials.csv")
    (tmp_path / "mine.yaml").write_text(text)
    rep = api.run(api.load(str(tmp_path / "mine.yaml")))
    fit = rep.fits[1]
    assert fit.ci95[0] < 0.35 < fit.ci95[1]
    assert fit.stderr < 0.01
    assert "trials.csv" in rep.data_note and "SYNTHETIC" not in rep.data_note


def test_user_csv_with_two_mass_ratios_separates_eps_and_epsp(tmp_path):
    from reproductions.mechanics import impact

    lines = ["V0,V1,V1p,M,Mp"]
    for M, Mp in ((0.6, 0.2), (0.2, 0.4)):
        for V0 in (1.0, 2.0):
            r = impact.direct_impact(M, Mp, V0, 0.0, eps=0.1, epsp=0.25)
            lines.append(f"{V0},{float(r.V1)!r},{float(r.V1p)!r},{M},{Mp}")
    (tmp_path / "trials.csv").write_text("\n".join(lines) + "\n")
    text = (api.config_dir() / "coriolis-pendulum.yaml").read_text()
    text = text.replace("    sigma: 0.01\n", "    series_csv: trials.csv\n    sigma: 0.01\n")
    (tmp_path / "mine.yaml").write_text(text)
    rep = api.run(api.load(str(tmp_path / "mine.yaml")))
    fits = {f.parameter: f for f in rep.fits}
    assert fits["ε (cue)"].identifiable and fits["ε (cue)"].value == pytest.approx(0.1, abs=1e-6)
    assert fits["ε′ (ball)"].identifiable and fits["ε′ (ball)"].value == pytest.approx(0.25, abs=1e-6)
    assert rep.identifiability[0]["rank"] == 2


def test_one_result_is_graded_by_the_two_equations_and_fails_on_ratios_that_do_not_keep_momentum(tmp_path):
    """« on obtient un résultat unique »: a measure that could fail. Ratios that do not keep momentum make the two
    eqs (8) give two values of D (no pair (ε, ε′) fits both), and the row differs."""
    text = (api.config_dir() / "coriolis-pendulum.yaml").read_text()
    text = text.replace("V1p_over_V0: 5/4 ", "V1p_over_V0: 1.3 ")
    (tmp_path / "off.yaml").write_text(text)
    r = {x.id: x for x in api.run(api.load(str(tmp_path / "off.yaml"))).rows}["n_equations"]
    assert r.verdict == "differs"
    assert r.computed == pytest.approx(abs(2 / (5 / 12) - 2 * 3 / 1.3) / (2 * 3 / 1.3), rel=1e-12)


def test_every_kind_declares_its_cost_for_the_pool():
    """The pool starts the longest experiments first (api.run_and_draw): each kind says about how long it runs."""
    from reproductions.experiments import KINDS

    assert all(isinstance(m.COST, float) and m.COST > 0 for m in KINDS.values()), {
        k: getattr(m, "COST", None) for k, m in KINDS.items()}
