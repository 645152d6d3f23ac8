"""The Python entry point (``reproductions.api``: simulate, reproduce, fit) agrees with the command line, takes the
same units, refuses bad input by name, writes nothing, and its example (docs/api.md) runs as written."""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from cli.main import app
from reproductions import api
from reproductions.errors import InputError
from reproductions.mechanics import registry
from reproductions.models import OUTPUTS

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"

# the least each model needs (its coefficients have no default)
NEEDS = {
    "direct-impact": {"eps": 0.1, "epsp": 0.2}, "wall-impact": {"eps": 0.3}, "plane-impact": {"f": 0.2, "nu": 0.8},
    "ricochet": {"f": 0.2, "nu": 0.8}, "cloth-slide": {"f": 0.25}, "cushion-impact": {"j": 0.2, "eps": 0.3},
    "spheres-free": {"v": [2.0, 0.5, 0.0], "f": 0.03, "eps": 0.03, "epsp": 0.03},
    "spheres-cloth": {"v": [2.0, 0.5, 0.0], "f": 0.03, "eps": 0.03, "epsp": 0.03},
    "cue-stroke": {"f": 0.25, "eps": 0.0, "epsp": 0.8},
}


def _cli_json(*args: str) -> dict:
    res = CliRunner().invoke(app, list(args))
    assert res.exit_code == 0, (res.exit_code, res.output)
    return json.loads(res.stdout)


def _set_args(scene: dict) -> list[str]:
    out = []
    for k, v in scene.items():
        out += ["--set", f"{k}={','.join(repr(float(x)) for x in v) if isinstance(v, list) else repr(float(v))}"]
    return out


# ---- the example of docs/api.md ------------------------------------------------------------------------------
def _doc_example() -> str:
    text = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    blocks = text.split("```python\n")
    assert len(blocks) == 2, "docs/api.md holds one python block"
    return blocks[1].split("\n```", 1)[0]


def test_api_doc_example_runs_and_writes_nothing(tmp_path):
    code = _doc_example()
    for call in ("api.simulate(", "api.reproduce(", "api.fit("):
        assert call in code
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    res = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=300)
    assert res.returncode == 0, res.stderr
    assert res.stderr == ""
    out = res.stdout
    assert "m/s" in out  # an output printed with its unit
    assert "differs" in out and "reproduced" in out  # marble-drop's verdicts
    line = next(ln for ln in out.splitlines() if ln.startswith("ε = "))
    value, lo, hi = (float(x) for x in line.replace("ε = ", "").replace(", 95 % interval [", " ").strip("]")
                     .replace(",", " ").split())
    assert lo < value < hi
    assert list(tmp_path.iterdir()) == []


# ---- simulate ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("model", "scene", "method"), [
    ("direct-impact", {"M": 3.0, "Mp": 1.0, "V0": 1.0, "eps": 0.0, "epsp": 0.2667}, "auto"),
    ("ricochet", {"a0": 2.0, "alpha0": 20.0, "f": 0.2, "nu": 0.8, "n": 5}, "auto"),  # alpha0 in degrees
    ("cue-stroke", {"i": 60.0, "c": 0.02, "f": 0.25, "eps": 0.0, "epsp": 0.8}, "resal"),  # i in degrees
    ("cue-stroke", {"i": 35.0, "b": 0.01, "f": 0.25, "eps": 0.1, "epsp": 0.8}, "ode"),  # gamma not computed
    ("spheres-cloth", {"v": [2.0, 0.5, 0.0], "f": 0.03, "eps": 0.03, "epsp": 0.03}, "auto"),  # a 3-vector
    ("cushion-impact", {"chi0": 1.0, "p0": 20.0, "n0": 5.0, "j": 0.2, "eps": 0.3}, "auto"),
])
def test_simulate_agrees_with_the_cli(model, scene, method):
    cli = _cli_json("simulate", model, *_set_args(scene), "--method", method, "--json")
    s = api.simulate(model, method, **scene)
    assert (s.model, s.method, int(s.path), int(s.regime)) == (cli["model"], cli["method"], cli["path"],
                                                               cli["regime"])
    assert list(s.inputs) == list(cli["inputs"]) and list(s.outputs) == list(cli["outputs"])
    assert s.units == {**cli["units"]["inputs"], **cli["units"]["outputs"]}
    for k, v in cli["inputs"].items():
        np.testing.assert_array_equal(s.inputs[k], v, err_msg=k)  # angles in degrees on both sides
    for k, v in cli["outputs"].items():
        if v is None:  # not computed by this path: NaN in the arrays
            assert np.isnan(s.outputs[k]), k
        elif s.units[k] == "degrees":  # the CLI prints them rounded to 15 digits
            np.testing.assert_allclose(s.outputs[k], v, rtol=1e-14, atol=1e-13, err_msg=k)
        else:
            np.testing.assert_array_equal(s.outputs[k], v, err_msg=k)


def test_angles_are_taken_in_degrees():
    s = api.simulate("ricochet", alpha0=30.0, f=0.2, nu=0.8, n=1)
    assert s.units["alpha0"] == "degrees" and float(s.inputs["alpha0"]) == pytest.approx(30.0)
    chi, zeta = float(s.outputs["chi"][0]), float(s.outputs["zeta"][0])  # after the impact: ζ1 = ν a0 sin α0
    assert zeta == pytest.approx(0.8 * 2.0 * math.sin(math.radians(30.0)), rel=1e-12)
    assert chi > 0


def test_a_batch_gives_the_numbers_of_single_scenes():
    p0 = np.array([0.0, 20.0, -15.0, 40.0])
    n0 = np.array([[0.0], [6.0]])  # n0 = 0: the elementary path; n0 ≠ 0: the exact one
    eps = 0.3
    s = api.simulate("cushion-impact", chi0=1.0, p0=p0, n0=n0, j=0.2, eps=eps)
    assert s.path.shape == (2, 4) and set(np.unique(s.path)) == {1, 2}  # both paths ran within the batch
    for i in range(2):
        for j in range(4):
            one = api.simulate("cushion-impact", chi0=1.0, p0=float(p0[j]), n0=float(n0[i, 0]), j=0.2, eps=eps)
            assert (s.path[i, j], s.regime[i, j]) == (one.path, one.regime)
            for k, v in one.outputs.items():
                np.testing.assert_allclose(s.outputs[k][i, j], v, rtol=1e-13, atol=0, err_msg=k)
            assert float(s.inputs["p0"][i, j]) == p0[j]
    v = np.array([[2.0, 0.5, 0.0], [1.0, 0.0, 0.1], [0.5, -0.2, 0.0]])  # three scenes of a vector parameter
    b = api.simulate("spheres-free", v=v, f=0.1, eps=0.2, epsp=0.1)
    assert b.outputs["v1"].shape == (3, 3) and b.outputs["T"].shape == (3, 2)
    for i in range(3):
        one = api.simulate("spheres-free", v=v[i], f=0.1, eps=0.2, epsp=0.1)
        for k, val in one.outputs.items():
            np.testing.assert_allclose(b.outputs[k][i], val, rtol=1e-13, atol=1e-15, err_msg=k)


@pytest.mark.parametrize(("call", "fragments"), [
    (dict(model="direct-impact", eps=0.1, epsp=0.2, Vo=1.0), ["Vo", "unknown parameter", "V0"]),
    (dict(model="direct-impact", eps=0.1), ["epsp", "needs"]),
    (dict(model="direct-impact", eps=1.5, epsp=0.2), ["eps=1.5", "[0, 1]"]),
    (dict(model="direct-impact", eps=np.array([0.1, 0.5, -0.2]), epsp=0.2), ["eps[2]=-0.2", "[0, 1]"]),
    (dict(model="ricochet", alpha0=95.0, f=0.2, nu=0.8), ["alpha0=95", "(0, 90)", "degrees"]),
    (dict(model="ricochet", f=0.2, nu=0.8, n=2.5), ["n=2.5", "whole number"]),
    (dict(model="direct-impact", eps="0.1", epsp=0.2), ["eps", "a number"]),
    (dict(model="spheres-free", v=[1.0, 0.0], f=0.1, eps=0.1, epsp=0.1), ["v=", "3-vector", "(2,)"]),
    (dict(model="direct-impact", eps=[0.1, 0.2], epsp=[0.1, 0.2, 0.3]), ["broadcast", "eps (2,)", "epsp (3,)"]),
    (dict(model="direct-impact", method="resal", eps=0.1, epsp=0.2), ["method 'resal'", "exact, ode"]),
    (dict(model="direct-impakt", eps=0.1), ["direct-impakt", "unknown model"]),
])
def test_bad_input_raises_input_error_naming_it(call, fragments):
    with pytest.raises(InputError) as exc:
        api.simulate(**call)
    for f in fragments:
        assert f in str(exc.value), (f, str(exc.value))


def test_every_output_of_every_model_has_a_unit():
    for name, m in registry.MODELS.items():
        s = api.simulate(name, **NEEDS[name])
        assert set(s.outputs) == set(OUTPUTS[name]), name
        assert all(s.units[k] == OUTPUTS[name][k][0] for k in s.outputs), name
        assert not set(s.inputs) & set(s.outputs), name  # one `units` mapping serves both
        assert set(s.units) == set(s.inputs) | set(s.outputs), name
        for p in m.params:
            assert s.units[p.name] == ("degrees" if p.cli_degrees else p.unit), (name, p.name)


# ---- reproduce -----------------------------------------------------------------------------------------------
def _plain(x):
    return [_plain(v) for v in x] if isinstance(x, (list, tuple)) else x


def test_reproduce_rows_equal_the_cli_summary(tmp_path, monkeypatch):
    summary = _cli_json("reproduce", "marble-drop", "--out", str(tmp_path / "out"), "--json")
    monkeypatch.chdir(tmp_path / "out")
    before = sorted(p for p in (tmp_path / "out").rglob("*"))
    for exp in ("marble-drop", ROOT / "configs" / "marble-drop.yaml"):
        rep = api.reproduce(exp)
        assert rep.experiment.id == "marble-drop"
        rows = [{k: _plain(v) for k, v in dataclasses.asdict(r).items()} for r in rep.rows]
        assert rows == summary["rows"]
        assert {r.verdict for r in rep.rows} >= {"reproduced", "differs"}
        assert rep.figures and all(dataclasses.is_dataclass(f) for f in rep.figures)
    assert sorted(p for p in (tmp_path / "out").rglob("*")) == before  # nothing written


def test_reproduce_refuses_an_unknown_experiment():
    with pytest.raises(InputError, match=r"marble-dorp.*unknown experiment id"):
        api.reproduce("marble-dorp")
    with pytest.raises(InputError, match="no such experiment file"):
        api.reproduce(Path("nowhere/marble-drop.yaml"))


# ---- fit -----------------------------------------------------------------------------------------------------
def _columns(path: Path) -> dict[str, np.ndarray]:
    """A CSV file's columns as arrays (a blank cell: NaN), as a script would hold them."""
    lines = [ln for ln in path.read_text(encoding="utf-8").splitlines() if ln.strip() and not ln.startswith("#")]
    rows = list(csv.reader(lines))
    return {h: np.array([float(r[j]) if r[j].strip() else math.nan for r in rows[1:]]) for j, h in enumerate(rows[0])}


@pytest.mark.parametrize(("kind", "file", "options"), [
    ("rebound", "rebound.csv", {"bootstrap": 300}),
    ("cushion", "cushion.csv", {"bootstrap": 300, "noise": "proportional"}),
    ("pendulum", "pendulum.csv", {"bootstrap": 100}),
    ("ricochet", "ricochet.csv", {}),
])
def test_fit_from_arrays_equals_fit_from_the_csv_file(kind, file, options):
    from_file = api.fit(kind, EXAMPLES / file, **options)
    from_arrays = api.fit(kind, _columns(EXAMPLES / file), **options)
    assert from_arrays.estimates == from_file.estimates
    assert from_arrays.summary["fits"] == from_file.summary["fits"]
    assert from_arrays.n == from_file.n
    assert [w.code for w in from_arrays.warnings] == [w.code for w in from_file.warnings]
    assert from_arrays.summary["file"] == "data"  # no temporary path leaks out


def test_fit_agrees_with_the_cli_and_returns_its_warnings(tmp_path, capsys):
    cli = _cli_json("fit", "cushion", str(EXAMPLES / "cushion.csv"), "--bootstrap", "200", "--seed", "3",
                    "--no-plot", "--out", str(tmp_path / "fit"), "--json")
    capsys.readouterr()
    f = api.fit("cushion", str(EXAMPLES / "cushion.csv"), bootstrap=200, seed=3)
    assert capsys.readouterr() == ("", "")  # nothing printed
    assert f.summary["fits"] == cli["fits"]
    assert [(w.code, w.message) for w in f.warnings] == [(w["code"], w["message"]) for w in cli["warnings"]]
    assert "speed-dependence" in [w.code for w in f.warnings]  # the example's e depends on the speed
    eps = f["eps"]
    assert eps.ci95[0] < eps.value < eps.ci95[1] and eps.unit == "1"


@pytest.mark.parametrize(("call", "fragments"), [
    (dict(kind="rebound", data={"u0": [2.0, 1.0, 1.5], "u1": [1.6, 0.8]}), ["u0: 3", "u1: 2", "one length"]),
    (dict(kind="rebound", data={"u0": [2.0, 1.0, 1.5], "u1": [1.6, math.nan, 1.2]}), ["data row 1", "u1", "NaN"]),
    (dict(kind="rebound", data={"u0": [2.0, 1.0, 1.5], "u2": [1.6, 0.8, 1.2]}),
     ["data header", "missing column(s) u1"]),
    (dict(kind="rebound", data={"u0": [[2.0, 1.0]], "u1": [1.6, 0.8]}), ["column 'u0'", "1-D"]),
    (dict(kind="rebound", data=EXAMPLES / "rebound.csv", R=0.03), ["R=", "not an option of the rebound fit", "sigma"]),
    (dict(kind="ball-ball", data=EXAMPLES / "ball-ball.csv", k=0.4), ["k=0.4", "inverse convention", "k=2.5"]),
    (dict(kind="rebound", data=EXAMPLES / "rebound.csv", sigma=-0.01), ["sigma=-0.01", "positive"]),
    (dict(kind="rebound", data=EXAMPLES / "rebound.csv", noise="gaussian"), ["noise='gaussian'", "proportional"]),
    (dict(kind="rebound", data=EXAMPLES / "rebound.csv", bootstrap=10**9), ["bootstrap=", "100,000"]),
    (dict(kind="rebounds", data=EXAMPLES / "rebound.csv"), ["kind 'rebounds'", "rebound, cushion"]),
    (dict(kind="rebound", data=EXAMPLES / "missing.csv"), ["missing.csv", "no such file"]),
    (dict(kind="rebound", data=[[2.0, 1.6], [1.0, 0.8]]), ["data", "mapping of column name"]),
])
def test_fit_refuses_bad_input_by_name(call, fragments):
    with pytest.raises(InputError) as exc:
        api.fit(**call)
    for f in fragments:
        assert f in str(exc.value), (f, str(exc.value))


# ---- the result types ----------------------------------------------------------------------------------------
def test_results_are_frozen_dataclasses_with_numpy_arrays():
    s = api.simulate("ricochet", f=0.2, nu=np.array([0.6, 0.8]), n=4)
    assert dataclasses.is_dataclass(s)
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.model = "other"  # type: ignore[misc]
    assert all(isinstance(v, np.ndarray) for v in (*s.inputs.values(), *s.outputs.values(), s.path, s.regime))
    assert s.path.dtype.kind == "i" and s.path.shape == (2,) and s.outputs["imprints"].shape == (2, 5)
    assert api.PathCode(int(s.path[0])).name == "EXACT" and s.units["imprints"] == "m"
    f = api.fit("rebound", EXAMPLES / "rebound.csv", bootstrap=0)
    assert dataclasses.is_dataclass(f) and all(dataclasses.is_dataclass(e) for e in f.estimates)
    with pytest.raises(dataclasses.FrozenInstanceError):
        f.kind = "other"  # type: ignore[misc]
    assert f["eps"].ci95_bootstrap is None  # no resample asked for
    with pytest.raises(KeyError, match="has no estimate 'nu'"):
        f["nu"]
    rep = api.reproduce("marble-drop")
    assert dataclasses.is_dataclass(rep) and all(dataclasses.is_dataclass(r) for r in rep.rows)


def test_load_says_what_a_fifo_is(tmp_path):
    import os

    fifo = tmp_path / "pipe.yaml"
    os.mkfifo(fifo)
    with pytest.raises(InputError) as exc:
        api.load(str(fifo))  # must not hang, nor call it missing
    assert "named pipe" in str(exc.value) and str(fifo) in str(exc.value)
