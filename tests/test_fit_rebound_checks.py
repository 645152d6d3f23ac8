"""``resal fit rebound | cushion | drop | pendulum`` check themselves, and their intervals of e are honest at e ≤ 1.

Their traps are in the corpus, tests/test_fit_traps.py. Here: a refused row's line, each trial predicted from the
others, the interval of e near its bound e = 1, and the errors-in-both fit through the command.
"""

from __future__ import annotations

import math
from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest
from fit_tables import EXAMPLES, header, invoke, line, ok, shift, table, write

from reproductions.fit.estimators.trials import Noise, RatioFit, bounded_interval, fit_ratio
from reproductions.fit.kinds.rebound import fit_rebounds
from reproductions.fit.run import FitOptions


def test_a_refused_row_names_its_file_and_line(tmp_path: Path) -> None:
    f = write(tmp_path, "rebound.csv", header(["V0_mps", "V1_mps"]))
    res = invoke(tmp_path, "rebound", f)
    assert f"{f}:{line(0)}: column 'V1_mps'" in " ".join(res.stderr.split())


# ---- leave-one-out in fit.json ------------------------------------------------------------------------------------
@pytest.mark.parametrize("kind, example, per_trial", [("rebound", "rebound.csv", 1), ("drop", "drop.csv", 1),
                                                      ("cushion", "cushion.csv", 1), ("pendulum", "pendulum.csv", 2)])
def test_each_trial_is_predicted_from_the_others(tmp_path: Path, kind: str, example: str, per_trial: int) -> None:
    """Per trial (and per outcome: V1 and V1′ for a pendulum) the prediction without it and its 95 % interval; on
    the clean example every measured value lies inside its interval's Bonferroni widening (no outlier warning), and
    a mistyped one lies far outside its interval."""
    s = ok(tmp_path / "a", kind, EXAMPLES / example)
    loo = s["leave_one_out"]
    assert len(loo) == per_trial * s["n"] and [e["line"] for e in loo] == sorted(e["line"] for e in loo)
    for e in loo:
        assert e["low"] < e["predicted"] < e["high"] and 0 < e["p"] <= 1, e
    j = 2 if kind == "pendulum" else 1
    by = {"rebound": 0.3, "drop": 30.0, "cushion": -30.0, "pendulum": 0.1}[kind]
    row = 6 if kind == "cushion" else 3
    bad = ok(tmp_path / "b", kind, write(tmp_path, example, shift(row, j, by)))
    mine = [e for e in bad["leave_one_out"] if e["line"] == line(row)]
    assert any(not e["low"] <= e["measured"] <= e["high"] for e in mine), mine
    assert min(e["p"] for e in mine) == min(e["p"] for e in bad["leave_one_out"])


# ---- the interval of e at its bound -------------------------------------------------------------------------------
def _ratio_fit(c: float, se: float) -> RatioFit:
    """A ratio fit, σ given, with this estimate and standard error (two trials placed so)."""
    x = np.array([1.0, 1.0])
    sigma = se * math.sqrt(2.0)  # se = σ/√Σx²
    fr = fit_ratio(x, np.array([c, c]), Noise.GIVEN, sigma)
    assert fr.value == pytest.approx(c) and fr.stderr == pytest.approx(se)
    return fr


def test_far_from_the_bound_the_interval_is_the_usual_one() -> None:
    fr = _ratio_fit(0.8, 0.01)
    bi = bounded_interval(fr)
    assert bi.reaches is None and bi.ci95 == pytest.approx((0.8 - 1.959964 * 0.01, 0.8 + 1.959964 * 0.01), abs=1e-7)


def test_at_or_past_the_bound_the_interval_ends_on_it_and_is_never_empty() -> None:
    """ĉ = 1 + b·se: a Wald interval cut at 1 would be [1 − 1.96 se, 1] at the bound, 0.96 se long one se beyond and
    empty from two beyond. The likelihood-ratio ordering (Feldman & Cousins 1998) gives [1 − 1.96 se, 1] at the
    bound (their 95 % upper limit for a measurement on the boundary) and, beyond it, shorter ones, never empty."""
    se = 0.01
    widths = []
    for beyond in (0.0, 1.0, 2.0, 5.0):
        bi = bounded_interval(_ratio_fit(1.0 + beyond * se, se))
        assert bi.value == 1.0 and bi.ci95[1] == 1.0 and bi.reaches == "upper"
        widths.append((1.0 - bi.ci95[0]) / se)
    assert widths[0] == pytest.approx(1.959964, abs=1e-6)
    assert all(a > b > 0 for a, b in pairwise(widths)), widths


# measured: 1000 seeded series of 8 trials per row (the same seeds at each e): rebound speeds with 2 % noise
# ∝ the speed (noise chosen by the data), drop heights with 4 % noise ∝ the height (2 % of the speed, estimated)
# and with σ = 10 mm given. Coverage in 94.0–94.8 % at every e; the interval reached e = 1 in up to 85 % of them.
BOUND_CASES = [("speeds", None), ("heights", None), ("heights", 10.0)]


@pytest.mark.parametrize("e", [0.95, 0.98, 0.995])
@pytest.mark.parametrize("data, sigma", BOUND_CASES, ids=["speeds", "heights", "heights-sigma"])
def test_e_near_one_is_covered(tmp_path: Path, e: float, data: str, sigma: float | None) -> None:
    """Through the kind (the file read, the bound applied, e's interval mapped from e² by √ for heights): the 95 %
    interval covers e in 93–97 % of 1000 seeded series of 8 trials (±2.9 binomial standard errors)."""
    f = tmp_path / "trials.csv"
    hits, reached, seeds = 0, 0, 1000
    for seed in range(seeds):
        rng = np.random.default_rng(seed)
        if data == "speeds":
            x = rng.uniform(0.5, 4.0, 8)
            y = e * x * (1 + 0.02 * rng.standard_normal(8))
            head, kind = "u0,u1", "rebound"
        else:
            x = rng.uniform(200.0, 1000.0, 8)
            noise = 0.04 * e * e * x if sigma is None else sigma
            y = np.abs(e * e * x + noise * rng.standard_normal(8))
            head, kind = "h0_mm,h1_mm", "drop"
        f.write_text(head + "\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(x.tolist(), y.tolist(), strict=True)))
        est = fit_rebounds(kind, f, FitOptions(sigma=sigma, resamples=0)).summary["fits"][0]
        hits += est["ci95"][0] <= e <= est["ci95"][1]
        reached += est["ci95"][1] == 1.0
    assert 0.93 <= hits / seeds <= 0.97, (data, e, hits / seeds)
    if e == 0.995:
        assert reached / seeds > 0.3  # the bound is in play: the test exercises it


def test_the_bound_is_said_in_the_estimate(tmp_path: Path) -> None:
    f = tmp_path / "elastic.csv"
    f.write_text("u0,u1\n1.0,0.995\n2.0,2.01\n3.0,2.98\n4.0,4.02\n")
    s = ok(tmp_path, "rebound", f)
    e = next(x for x in s["fits"] if x["id"] == "e")
    assert e["ci95"][1] == 1.0 and e["ci95"][0] < e["value"] <= 1.0 and e["clipped"]
    assert "the interval ends there" in e["note"] and "Feldman & Cousins" in e["method"]


# ---- errors in both variables through the command -----------------------------------------------------------------
def test_sigma_in_is_in_the_impact_columns_unit(tmp_path: Path) -> None:
    """--sigma-in 1 on V0_cmps is --sigma-in 0.01 on V0 in m/s (and --sigma likewise on V1)."""
    _, (_, rows) = table("cushion.csv")
    cm = tmp_path / "cm.csv"
    cm.write_text("V0_cmps,V1_cmps\n" + "".join(",".join(r) + "\n" for r in rows))
    m = tmp_path / "m.csv"
    m.write_text("V0,V1\n" + "".join(f"{float(a) / 100!r},{float(b) / 100!r}\n" for a, b in rows))
    a = ok(tmp_path / "a", "cushion", cm, "--sigma-in", "1", "--sigma", "2")
    b = ok(tmp_path / "b", "cushion", m, "--sigma-in", "0.01", "--sigma", "0.02")
    ea, eb = a["fits"][0], b["fits"][0]
    assert ea["value"] == pytest.approx(eb["value"], rel=1e-9) and ea["ci95"] == pytest.approx(eb["ci95"], rel=1e-7)
    assert a["noise"]["errors_in_both"]["sigma_in"] == pytest.approx(0.01, rel=1e-12)
    assert "errors in both variables" in ea["method"] and "σ_in = 1 cm/s on V0_cmps given" in ea["method"]


def test_sigma_in_widens_the_interval_and_without_sigma_says_what_it_assumes(tmp_path: Path) -> None:
    plain = ok(tmp_path / "a", "rebound", EXAMPLES / "rebound.csv", "--sigma", "0.02")
    both = ok(tmp_path / "b", "rebound", EXAMPLES / "rebound.csv", "--sigma", "0.02", "--sigma-in", "0.05")
    w_plain = plain["fits"][0]["ci95"][1] - plain["fits"][0]["ci95"][0]
    w_both = both["fits"][0]["ci95"][1] - both["fits"][0]["ci95"][0]
    assert w_both > 1.5 * w_plain  # V0's noise, ×e, is larger than V1's: the interval must say so
    est = ok(tmp_path / "c", "rebound", EXAMPLES / "rebound.csv", "--sigma-in", "0.01")
    assert est["noise"]["errors_in_both"]["sigma_out_from"] == "moments"
    assert "the ratio σ_in/σ is the estimated one" in est["fits"][0]["method"]


# ---- false alarms: outliers under an unsure noise model, copied rows, no scatter ---------------------------------
def _clean_drops(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """5 drop heights 200–1000 mm × 4 trials, e = 0.9, constant noise of 2 mm on h1."""
    rng = np.random.default_rng(seed)
    x = np.repeat(np.linspace(200.0, 1000.0, 5), 4)
    return x, 0.81 * x + 2.0 * rng.standard_normal(x.size)


def _drop_summary(f: Path, x: np.ndarray, y: np.ndarray, **kw: object) -> dict:
    f.write_text("h0_mm,h1_mm\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(x.tolist(), y.tolist(), strict=True)))
    return fit_rebounds("drop", f, FitOptions(resamples=0, **kw)).summary  # type: ignore[arg-type]


def test_outliers_are_named_only_when_both_noise_models_see_them(tmp_path: Path) -> None:
    """--noise auto takes the proportional model in ~20 % of clean constant-noise series (its margin, on purpose);
    under it the leave-one-out named sound trials at the ends of the range in 14 % of those (6.3 % of all series
    over 1000 seeds). A trial is now named only when it is an outlier under both models: over 150 clean series the
    outlier warning stays ≤ 8 % (measured: 1.2 % of 1000), while a mistyped h1 (+40 mm, 20 σ) is still named."""
    f = tmp_path / "drop.csv"
    seeds = 150
    alarms, proportional = 0, 0
    for seed in range(seeds):
        s = _drop_summary(f, *_clean_drops(seed))
        alarms += any(w["code"] == "outlier" for w in s["warnings"])
        proportional += s["noise"]["model"] == "proportional"
    assert proportional >= 10  # the case that misled the check is exercised
    assert alarms / seeds <= 0.08, alarms
    named = 0
    for seed in range(20):
        x, y = _clean_drops(seed)
        y[9] += 40.0
        s = _drop_summary(f, x, y)
        outl = [w["message"] for w in s["warnings"] if w["code"] == "outlier"]
        named += bool(outl) and "line(s) 11 " in outl[0]
        assert set(s["leave_one_out"][9]["p_by_noise"]) == {"constant", "proportional"}
    assert named == 20, named


def test_a_told_noise_model_judges_outliers_alone(tmp_path: Path) -> None:
    x, y = _clean_drops(0)
    s = _drop_summary(tmp_path / "drop.csv", x, y, noise=Noise.CONSTANT)
    assert all("p_by_noise" not in e for e in s["leave_one_out"])


def test_rows_copied_twice_are_named_not_taken_for_perfect_repeats(tmp_path: Path) -> None:
    """A file whose every row is repeated exactly: the repeats are not pure error that agrees perfectly (no
    'lack-of-fit' with an infinite F), but possible copies, said so."""
    rows = [(1.0, 0.8), (1.5, 1.22), (2.0, 1.58), (2.5, 2.03), (3.0, 2.39), (3.5, 2.83)]
    f = tmp_path / "copied.csv"
    f.write_text("u0,u1\n" + "".join(f"{a},{b}\n" for a, b in rows * 2))
    s = fit_rebounds("rebound", f, FitOptions(resamples=0)).summary
    codes = [w["code"] for w in s["warnings"]]
    assert "duplicate-rows" in codes and "lack-of-fit" not in codes, s["warnings"]
    dup = next(w["message"] for w in s["warnings"] if w["code"] == "duplicate-rows")
    assert "line(s) 8, 9, 10, 11, 12, 13 repeat other rows exactly" in dup  # the header is line 1
    assert "1e+300" not in str(s)
    # repeats that scatter, with an identical pair among them (a coarse reading): not named, and tested
    f.write_text("u0,u1\n1,0.8\n1,0.8\n1,0.81\n2,1.6\n2,1.61\n2,1.62\n3,2.41\n3,2.4\n3,2.42\n")
    s = fit_rebounds("rebound", f, FitOptions(resamples=0)).summary
    assert not s["warnings"] and s["goodness"]["lack_of_fit"]["exact_repeats_left_out"] == 1


def test_no_rebound_at_all_reports_no_speed_law(tmp_path: Path) -> None:
    """Every u1 = 0: every trial's e is 0, no scatter, no evidence of a speed dependence (not 'F = 1e+300')."""
    f = tmp_path / "dead.csv"
    f.write_text("u0,u1\n" + "".join(f"{v},0\n" for v in (1.0, 1.5, 2.0, 2.5, 3.0, 3.5)))
    s = fit_rebounds("rebound", f, FitOptions(resamples=0)).summary
    assert not [w for w in s["warnings"] if w["code"] == "speed-dependence"], s["warnings"]
    sd = s["speed_dependence"]
    assert sd["order"] == 0 and sd["law"] is None and "no evidence" in sd["verdict"]
    assert "1e+300" not in str(s)
