"""``resal fit``: a user's CSV in, ε or ν with uncertainties and identifiability out."""

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from cli.main import app
from reproductions.mechanics import impact, plane

runner = CliRunner()


def _fit(*args):
    kind, path, *rest = map(str, args)
    res = runner.invoke(app, ["fit", kind, path, "--json", "--no-plot", "--out", str(Path(path).parent / "fit"),
                              *rest])
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


def test_rebound_heights_recover_eps(tmp_path):
    rng = np.random.default_rng(1)
    h0 = rng.uniform(0.2, 1.0, 20)
    h1 = h0 * impact.velocity_ratio_from_eps(0.1) ** 2 * (1 + 0.01 * rng.standard_normal(20))
    f = tmp_path / "drops.csv"
    f.write_text("h0,h1\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(h0.tolist(), h1.tolist(), strict=True)))
    eps = next(x for x in _fit("rebound", f)["fits"] if x["id"] == "eps")
    assert eps["ci95"][0] < 0.1 < eps["ci95"][1]


def test_pendulum_with_one_mass_ratio_reports_the_combination(tmp_path):
    f = tmp_path / "trials.csv"
    r = impact.direct_impact(0.6, 0.2, np.array([1.0, 2.0]), 0.0, eps=0.1, epsp=0.2)
    f.write_text("V0,V1,V1p\n" + "".join(f"{v0},{a!r},{b!r}\n" for v0, a, b in
                                         zip([1.0, 2.0], r.V1.tolist(), r.V1p.tolist(), strict=True)))
    out = _fit("pendulum", f, "--M", 0.6, "--Mp", 0.2)
    assert out["identifiability"][0]["rank"] == 1
    comb = next(x for x in out["fits"] if "+" in x["parameter"])
    assert comb["value"] == pytest.approx(0.1 + 3 * 0.2, rel=1e-6)


def test_ricochet_positions_and_instants(tmp_path):
    r = plane.ricochet(2.0, 0.45, 0.0, R=0.0305, k=2.5, f=0.2, nu=0.75, g=9.80665, n=9)
    rng = np.random.default_rng(3)
    x = r.imprints + rng.normal(0, 3e-4, 10)
    t = np.concatenate([[0.0], np.cumsum(r.times)]) + rng.normal(0, 1e-4, 10)
    f = tmp_path / "imprints.csv"
    f.write_text("x,t\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(x.tolist(), t.tolist(), strict=True)))
    fits = {x["parameter"]: x for x in _fit("ricochet", f)["fits"]}
    for name in ("ν", "ν (acoustic)"):
        assert abs(fits[name]["value"] - 0.75) < 4 * fits[name]["stderr"]
    assert fits["f (positions + instants)"]["identifiable"]


@pytest.mark.parametrize("text, args, message", [
    ("V0,V1\n1,x\n2,-1\n", ["rebound"], "data.csv:2: column 'V1' (#2): expected a number, got 'x'"),
    ("x\n0\n0.1\n", ["ricochet"], "at least 5 imprints"),
    ("V0,V1\n1,-0.5\n2,-1\n", ["cannon"], "kind 'cannon'"),
    ("V0,V1,V1p\n1,0.5,1.2\n", ["pendulum", "--M", "-1"], "--M -1: expected a positive number"),
])
def test_bad_fit_input(tmp_path, text, args, message):
    f = tmp_path / "data.csv"
    f.write_text(text)
    kind, *opts = args
    res = runner.invoke(app, ["fit", kind, str(f), *opts])
    assert res.exit_code == 2 and message in " ".join(res.stderr.split()) and "Traceback" not in res.output


# ---- the kinds of `resal fit`, on the examples and on files made here ---------------------------------------------
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _run(tmp_path, *args):
    out = tmp_path / "out"
    res = runner.invoke(app, ["fit", *map(str, args), "--out", str(out), "--json"])
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout), out


def _by_id(summary):
    return {f["id"]: f for f in summary["fits"]}


@pytest.mark.parametrize("kind, args, truth", [
    ("rebound", (), {"e": 0.8}),
    ("drop", (), {"e": 0.9}),
    ("pendulum", (), {"pendulum.eps": 0.1, "pendulum.epsp": 0.3}),
    ("ricochet", (), {"positions.nu": 0.75, "times.nu": 0.75}),
    ("ball-ball", ("--R", "0.02855"), {"ball-ball.f_bb": 0.06, "ball-ball.e": 0.93}),
    ("bounces", ("--h0", "0.5"), {"bounces.nu": 0.85, "bounces.g": 9.80665}),
])
def test_each_example_gives_back_the_values_that_made_it(tmp_path, kind, args, truth):
    """Within 4 standard errors (a 95 % interval misses one example in twenty: the coverage tests judge those)."""
    s, out = _run(tmp_path, kind, EXAMPLES / f"{kind}.csv", *args)
    fits = _by_id(s)
    for pid, value in truth.items():
        assert abs(fits[pid]["value"] - value) < 4 * fits[pid]["stderr"], (pid, fits[pid])
    assert {"fit.json", "fit.md", "residuals.csv", "fit.png", "fit.pdf"} <= {p.name for p in out.iterdir()}
    assert json.loads((out / "fit.json").read_text())["fits"] == s["fits"]
    assert s["provenance"]["data_sha256"] and "version" in s["provenance"]


def test_the_cushion_example_rejects_a_constant_e_and_finds_hans_law(tmp_path):
    """The example follows Han (2005)'s e(v) = 0.39 + 0.257 v − 0.044 v²: the constant is rejected and the law found
    agrees with Han's within its band over the speeds measured."""
    s, _ = _run(tmp_path, "cushion", EXAMPLES / "cushion.csv")
    sd = s["speed_dependence"]
    assert sd["order"] == 2 and sd["law"]["v_range"] == [0.5, 3.5]
    assert any("reject a constant e" in w["message"] for w in s["warnings"])
    b = sd["law"]["coefficients"]
    for v in (1.0, 2.0, 3.0):
        assert abs(b[0] + b[1] * v + b[2] * v * v - (0.39 + 0.257 * v - 0.044 * v * v)) < 0.03
    paper = s["comparison"]["paper"][0]
    assert paper["value"] == 0.55 and paper["line"] == 220


def _write(path, header, *cols):
    rows = zip(*cols, strict=True)
    path.write_text(header + "\n" + "".join(",".join(repr(float(v)) for v in r) + "\n" for r in rows))
    return path


def test_units_in_the_header_are_converted(tmp_path):
    rng = np.random.default_rng(7)
    h0 = rng.uniform(0.2, 1.0, 8)
    h1 = 0.7 * h0 + rng.normal(0, 0.003, 8)
    a, _ = _run(tmp_path / "m", "drop", _write(tmp_path / "m.csv", "h0,h1", h0, h1), "--sigma", "0.003")
    b, _ = _run(tmp_path / "mm", "drop", _write(tmp_path / "mm.csv", "h0_mm,h1_mm", 1e3 * h0, 1e3 * h1),
                "--sigma", "3")
    ea, eb = _by_id(a)["e"], _by_id(b)["e"]
    assert eb["value"] == pytest.approx(ea["value"], rel=1e-12)
    assert eb["stderr"] == pytest.approx(ea["stderr"], rel=1e-9)  # σ = 3 mm is σ = 0.003 m, not 3 m
    assert a["columns"][0]["note"].startswith("no unit") and b["columns"][0]["unit"] == "mm"


def test_unsigned_speeds_said_in_the_header_or_by_option_fit_as_signed(tmp_path):
    rng = np.random.default_rng(8)
    u0 = rng.uniform(0.5, 3.0, 8)
    u1 = 0.6 * u0 + rng.normal(0, 0.01, 8)
    signed, _ = _run(tmp_path / "a", "cushion", _write(tmp_path / "s.csv", "V0,V1", u0, -u1))
    header, _ = _run(tmp_path / "b", "cushion", _write(tmp_path / "u.csv", "u0_mps,u1_mps", u0, u1))
    option, _ = _run(tmp_path / "c", "cushion", _write(tmp_path / "p.csv", "V0,V1", u0, u1), "--speeds",
                     "unsigned")
    assert _by_id(signed)["e"]["value"] == pytest.approx(0.6, abs=0.01)
    nums = [{k: _by_id(x)["e"][k] for k in ("value", "stderr", "ci95")} for x in (signed, header, option)]
    assert nums[0] == nums[1] == nums[2]
    res = runner.invoke(app, ["fit", "cushion", str(tmp_path / "p.csv"), "--out", str(tmp_path / "d")])
    assert res.exit_code == 2 and "--speeds unsigned" in " ".join(res.stderr.split())
    assert not (tmp_path / "d").exists()  # nothing written


@pytest.mark.parametrize("header, message", [
    ("V0_mm,V1_mm", "column 'V0_mm': unknown unit 'mm' for a speed"),
    ("U0,U1", "names none of the columns of a rebound: expected V0,V1"),
    ("V0;V1", "separated by semicolons: expected commas"),
    ("V0_furlong,V1", "unknown unit 'furlong'"),
    ("V0,V1,V2", "unknown column(s) V2"),
])
def test_bad_units_and_columns_are_named_at_the_header(tmp_path, header, message):
    f = tmp_path / "data.csv"
    f.write_text("# a comment\n" + header + "\n1,-0.5\n2,-1\n")
    res = runner.invoke(app, ["fit", "rebound", str(f), "--out", str(tmp_path / "o")])
    err = " ".join(res.stderr.split())
    assert res.exit_code == 2 and f"{f}:2" in err and message in err and "Traceback" not in res.output
    assert not (tmp_path / "o").exists()


def test_each_kind_has_its_own_help_and_refuses_others_options(tmp_path):
    helps = {k: " ".join(runner.invoke(app, ["fit", k, "--help"]).output.split())
             for k in ("rebound", "drop", "pendulum", "ricochet", "ball-ball")}
    assert "h0,h1" in helps["drop"] and "V1p" in helps["pendulum"] and "--M" in helps["pendulum"]
    assert "--sigma " not in helps["ricochet"] and "--M " not in helps["rebound"]
    # the help wraps at a hyphen when it must (examples/ball-⏎ball.csv): join such breaks to read the path
    assert "examples/ball-ball.csv" in helps["ball-ball"].replace("- ", "-") and "phi_deg" in helps["ball-ball"]
    assert len(set(helps.values())) == len(helps)
    res = runner.invoke(app, ["fit", "drop", str(EXAMPLES / "drop.csv"), "--M", "0.2"])
    assert res.exit_code == 2 and "--M 0.2: not an option of `resal fit drop`" in " ".join(res.stderr.split())


def test_bootstrap_is_seeded_and_refits(tmp_path):
    a, _ = _run(tmp_path / "a", "rebound", EXAMPLES / "rebound.csv", "--bootstrap", "300", "--seed", "5")
    b, _ = _run(tmp_path / "b", "rebound", EXAMPLES / "rebound.csv", "--bootstrap", "300", "--seed", "5")
    c, _ = _run(tmp_path / "c", "rebound", EXAMPLES / "rebound.csv", "--bootstrap", "300", "--seed", "6")
    assert a["fits"] == b["fits"] and a["fits"] != c["fits"]
    e = _by_id(a)["e"]
    lo, hi = e["ci95_bootstrap"]
    assert lo < e["value"] < hi and 0.3 < (hi - lo) / (e["ci95"][1] - e["ci95"][0]) < 3


def test_no_plot_writes_no_figure_and_a_rerun_replaces_the_folder(tmp_path):
    _run(tmp_path, "drop", EXAMPLES / "drop.csv")
    res = runner.invoke(app, ["fit", "drop", str(EXAMPLES / "drop.csv"), "--out", str(tmp_path / "out"),
                              "--no-plot"])
    assert res.exit_code == 0 and "wrote" in res.stdout
    assert not list((tmp_path / "out").glob("*.png"))


def test_pendulum_without_masses_is_refused(tmp_path):
    f = _write(tmp_path / "t.csv", "V0,V1,V1p", [1.0, 2.0], [0.5, 1.0], [1.5, 3.0])
    res = runner.invoke(app, ["fit", "pendulum", str(f), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and "no striking mass" in " ".join(res.stderr.split())


def test_a_given_sigma_that_understates_the_scatter_is_flagged(tmp_path):
    rng = np.random.default_rng(9)
    u0 = rng.uniform(0.5, 3.0, 10)
    f = _write(tmp_path / "r.csv", "u0,u1", u0, 0.6 * u0 + rng.normal(0, 0.05, 10))
    s, _ = _run(tmp_path, "rebound", f, "--sigma", "0.005")
    assert s["goodness"]["reduced_chi2"] > 10
    assert any("scatter exceeds the given σ" in w["message"] for w in s["warnings"])


def test_bounce_instants_in_milliseconds_with_sigma_in_milliseconds(tmp_path):
    t = np.array([0.0, 0.3194, 0.5908, 0.8215, 1.0176, 1.1843, 1.3260, 1.4464])
    # the units of the fit, not its bootstrap (tested in test_bounces_bootstrap_and_fitted_instants): none here
    a, _ = _run(tmp_path / "s", "bounces", _write(tmp_path / "s.csv", "t", t), "--sigma", "0.001", "--bootstrap", "0")
    b, _ = _run(tmp_path / "ms", "bounces", _write(tmp_path / "ms.csv", "t_ms", 1e3 * t), "--sigma", "1",
                "--bootstrap", "0")
    na, nb = _by_id(a)["bounces.nu"], _by_id(b)["bounces.nu"]
    assert nb["value"] == pytest.approx(na["value"], rel=1e-9) and nb["ci95"] == pytest.approx(na["ci95"], rel=1e-6)
    assert 0.0 < na["ci95"][0] < na["value"] < na["ci95"][1] < 1.0


def test_ricochet_f_carries_its_measured_undercoverage(tmp_path):
    """f's interval is the profile likelihood's (fitting.fit_friction), whose coverage the note gives as measured
    (tests/test_fit_coverage_ricochet.py); the Wald warning is gone."""
    s, _ = _run(tmp_path, "ricochet", EXAMPLES / "ricochet.csv")
    f = _by_id(s)["joint-physical.f"]
    assert "profile likelihood" in f["note"] and "93 % of 300" in f["note"]
    assert "WARNING" not in f["note"] and "indicative" not in f["note"]
    assert f["ci95"][0] < f["value"] < f["ci95"][1]


def test_pendulum_heights_example_takes_the_striker_back_from_momentum(tmp_path):
    s, _ = _run(tmp_path, "pendulum", EXAMPLES / "pendulum-heights.csv", "--sigma", "0.5", "--bootstrap", "0")
    fits = _by_id(s)
    for pid, value in (("pendulum.eps", 0.1), ("pendulum.epsp", 0.3)):
        assert abs(fits[pid]["value"] - value) < 4 * fits[pid]["stderr"], fits[pid]
    assert [t["striker_back"] for t in s["per_trial"]] == [False] * 5 + [True] * 5
    assert any("moving back" in w["message"] for w in s["warnings"])


@pytest.mark.parametrize("kind, args", [("drop", {}), ("ball-ball", {"R": 0.02855}), ("bounces", {"h0": 0.5})])
def test_the_bootstrap_reports_its_progress_and_batches_change_nothing(kind, args):
    """Progress after every resample (one at a time) or every batch (ball-ball's batched refits), up to the total;
    and the batched bootstrap draws what the one-at-a-time one would."""
    from reproductions.fit.estimators.trials import bootstrap, bootstrap_many
    from reproductions.fit.run import FitOptions, fit_csv

    seen: list[int] = []
    fit_csv(kind, EXAMPLES / f"{kind}.csv", FitOptions(resamples=120, seed=3, progress=seen.append, **args))
    assert seen[-1] == 120 and seen == sorted(seen) and len(seen) >= 3
    x = np.arange(1.0, 9.0)

    def mean(idx):
        return [float(x[idx].mean())]

    def draw(rng):
        return rng.integers(0, 8, 8)

    one = bootstrap(mean, draw, ("m",), 200, 7)
    many = bootstrap_many(lambda b: [mean(i) for i in b], draw, ("m",), 200, 7, batch=64)
    assert one == many


def test_pendulum_reduced_chi2_judges_a_given_sigma(tmp_path):
    """The example was made with σ = 0.005 m/s: told so, χ²/dof is near 1; told half of it, near 4, and the fit
    warns that its intervals are too narrow."""
    # χ² of the fit, not its bootstrap: none here (the examples' own test runs the default one)
    right, _ = _run(tmp_path / "a", "pendulum", EXAMPLES / "pendulum.csv", "--sigma", "0.005", "--bootstrap", "0")
    wrong, _ = _run(tmp_path / "b", "pendulum", EXAMPLES / "pendulum.csv", "--sigma", "0.0025", "--bootstrap", "0")
    assert 0.3 < right["goodness"]["reduced_chi2"] < 3 and not right["warnings"]
    assert wrong["goodness"]["reduced_chi2"] > 2.5
    assert any(w["code"] == "chi2-exceeds-sigma" for w in wrong["warnings"])


def test_bounces_bootstrap_and_fitted_instants(tmp_path):
    s, out = _run(tmp_path, "bounces", EXAMPLES / "bounces.csv", "--h0", "0.5", "--bootstrap", "200")
    nu = _by_id(s)["bounces.nu"]
    lo, hi = nu["ci95_bootstrap"]
    assert lo < nu["value"] < hi and s["bootstrap"]["resamples"] == 200
    rows = (out / "residuals.csv").read_text().splitlines()[1:]
    resid = [float(r.split(",")[1]) - float(r.split(",")[2]) for r in rows]
    assert max(map(abs, resid)) < 5e-3  # the example's jitter is 1 ms: the fitted instants are the model's
    assert (out / "residuals.png").is_file()


def test_lack_of_fit_is_warned_and_exact_repeats_are_not_a_lack_of_fit(tmp_path):
    """Six speeds, three trials each: e alternating 0.88/0.80 between speeds is a lack of fit the pure-error test sees
    (and Coriolis's constant e is then not 'supported'); exact repeats of a constant e are none."""
    v = np.repeat([0.5, 1.0, 1.5, 2.0, 2.5, 3.0], 3)
    e = np.where(np.repeat(np.arange(6) % 2 == 0, 3), 0.88, 0.80) + np.tile([-0.001, 0.0, 0.001], 6)
    s, _ = _run(tmp_path / "a", "cushion", _write(tmp_path / "lof.csv", "u0,u1", v, e * v))
    assert s["goodness"]["lack_of_fit"]["p"] < 1e-6 and any("lack of fit" in w["message"] for w in s["warnings"])
    assert "reject a constant e" in s["comparison"]["paper"][1]["verdict"]
    p, _ = _run(tmp_path / "b", "cushion", _write(tmp_path / "perfect.csv", "u0,u1", v, 0.8 * v))
    assert p["goodness"]["lack_of_fit"]["p"] == 1.0 and not any("lack of fit" in w["message"] for w in p["warnings"])


def test_a_sigma_the_scatter_contradicts_does_not_invent_a_speed_law(tmp_path):
    rng = np.random.default_rng(11)
    u0 = np.linspace(0.5, 3.5, 12)
    s, _ = _run(tmp_path, "rebound", _write(tmp_path / "r.csv", "u0,u1", u0, 0.8 * u0 + rng.normal(0, 0.02, 12)),
                "--sigma", "0.0002")
    assert s["goodness"]["chi2_p"] < 1e-6 and s["speed_dependence"]["order"] == 0
    assert all(t["test"] == "F" for t in s["speed_dependence"]["tests"])


def test_out_never_replaces_a_folder_of_other_files_and_errors_are_one_line(tmp_path):
    other = tmp_path / "mine"
    other.mkdir()
    (other / "notes.txt").write_text("keep me")
    res = runner.invoke(app, ["fit", "drop", str(EXAMPLES / "drop.csv"), "--out", str(other)])
    assert res.exit_code == 2 and "holds other files" in res.stderr
    assert res.stderr.count("\n") == 1 and (other / "notes.txt").read_text() == "keep me"
    _run(tmp_path / "again", "drop", EXAMPLES / "drop.csv")  # an earlier fit's folder is replaced
    _run(tmp_path / "again", "drop", EXAMPLES / "drop.csv")
