"""``resal fit``: a user's CSV in, ε or ν with uncertainties and identifiability out."""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from cli.main import app
from reproductions.mechanics import impact, plane

runner = CliRunner()


def _fit(*args):
    res = runner.invoke(app, ["fit", *map(str, args), "--json"])
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


def test_rebound_heights_recover_eps(tmp_path):
    rng = np.random.default_rng(1)
    h0 = rng.uniform(0.2, 1.0, 20)
    h1 = h0 * impact.velocity_ratio_from_eps(0.1) ** 2 * (1 + 0.01 * rng.standard_normal(20))
    f = tmp_path / "drops.csv"
    f.write_text("h0,h1\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(h0.tolist(), h1.tolist(), strict=True)))
    (eps,) = _fit("rebound", f)["fits"]
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
    ("V0,V1\n1,x\n2,-1\n", ["rebound"], "data.csv:2: column 'V1': expected a number, got 'x'"),
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
