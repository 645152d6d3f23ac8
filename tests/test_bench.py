"""`resal bench --quick`: the report's shape, and every path's error where it declares itself exact within its
declared accuracy (speed is measured by the benchmark, never asserted in a test)."""

import json
import os

import pytest
from typer.testing import CliRunner

from cli.main import app
from reproductions.mechanics import registry


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    res = CliRunner().invoke(app, ["bench", "--quick", "--out", str(out)])
    assert res.exit_code == 0, res.output
    return out, json.loads((out / "bench.json").read_text(encoding="utf-8"))


def test_bench_reports_every_model_and_path_with_its_figures(report):
    out, rep = report
    assert [m["model"] for m in rep["models"]] == list(registry.MODELS)
    for mod in rep["models"]:
        m = registry.MODELS[mod["model"]]
        assert [r["path"] for r in mod["paths"]] == [p.name for p in m.paths] + ["auto"]
        for r in mod["paths"]:
            assert r["scenes_timed"] > 0 and r["seconds_per_scene"] > 0 and r["reference"] != r["path"]
            assert r["n1_seconds"] > 0  # one scene timed through every path that handles the first of them
            assert r["all_scenes"]["failures"] == 0
        assert mod["pareto"] and all(v["verdict"] for v in mod["pareto"])
        for ext in ("png", "pdf"):
            assert (out / f"work-precision-{mod['model']}.{ext}").stat().st_size > 0
    assert "## cushion-impact" in (out / "bench.md").read_text(encoding="utf-8")
    assert len(rep["direct_impact_ode_tolerances"]) == 5
    for mod in rep["models"]:  # every ODE path over scipy solvers and tolerances, against the exact path
        assert {g["solver"] for g in mod["ode_grid"]} == set(rep["config"]["solvers"])
        assert all(g["max_error"] is not None and g["max_error"] < 1e-3 for g in mod["ode_grid"]), mod["model"]
    assert {r["model"] for r in rep["closed_forms_by_hand"]} == {"direct-impact", "plane-impact", "cloth-slide"}
    assert list(rep["n1"]) == list(registry.MODELS)  # one scene's time split, the path auto chose named
    for name, r in rep["n1"].items():
        assert r["path"] in [p.name for p in registry.MODELS[name].paths]
        assert min(r["total"], r["scene"], r["run"], r["assembly"]) > 0 and r["dispatch"] >= 0


def test_bench_reports_issue_34s_figures_from_its_own_measurements(report):
    """Each figure of the targets' table is the number measured elsewhere in the same report (not a second
    measurement that could disagree with it), and bench.md shows the table and the calibration."""
    out, rep = report
    got = {t["what"]: t for t in rep["targets"]}
    assert got["one scene: cushion-impact"]["now"] == rep["n1"]["cushion-impact"]["total"]
    assert got["one scene: two balls on the cloth"]["now"] == rep["n1"]["spheres-cloth"]["total"]
    cloth = next(m for m in rep["models"] if m["model"] == "spheres-cloth")
    auto = next(r for r in cloth["paths"] if r["path"] == "auto")
    batch = next(t for w, t in got.items() if w.startswith("§VI cloth: batch"))
    assert batch["now"] == auto["scenes_per_second"] and batch["met"] == (auto["scenes_per_second"] >= 1e6)
    rate = rep["cloth_kinds"]["scenes_per_second"]  # heterogeneous batches: their rate over the homogeneous one's
    for key, what in (("kinds", "§VI cloth: balls of 3 kinds ÷ k = k′"),
                      ("per_scene", "§VI cloth: k, k′ per scene ÷ k = k′")):
        assert got[what]["now"] == rate[key] / rate["homogeneous"] and got[what]["met"] == (got[what]["now"] >= 1)
    assert got["make all, cold (median)"]["now"] is None  # --quick does not time make all
    assert min(rep["calibration"].values()) > 0
    md = (out / "bench.md").read_text(encoding="utf-8")
    assert "## Issue 34's targets, as measured here" in md and "Calibration of this machine" in md
    assert "## The ODE part:" in md
    assert "## §VI on the cloth: " in md and "| balls of a few kinds | " in md  # the three batches' rates


def test_bench_files_get_the_mode_of_the_users_umask(report):
    out, _ = report
    umask = os.umask(0)  # read it: set, then restore at once (the test runs in the main thread)
    os.umask(umask)
    files = sorted(out.iterdir())
    assert files and all(p.is_file() for p in files)
    assert {p.name: oct(p.stat().st_mode & 0o7777) for p in files} == {p.name: oct(0o666 & ~umask) for p in files}


def test_every_path_is_as_accurate_as_it_declares_where_it_declares_itself_exact(report):
    _, rep = report
    for mod in rep["models"]:
        m = registry.MODELS[mod["model"]]
        for r in mod["paths"]:
            if r["path"] == "auto" or r["where_exact"]["scenes"] == 0:
                continue
            tol = max(m.path(r["path"]).accuracy, m.path(r["reference"]).accuracy)
            assert r["where_exact"]["max_error"] <= tol, (mod["model"], r["path"])


def test_the_hand_written_formulas_are_the_paths_formulas():
    """The bench's bare expressions compute what the paths compute (else the slowdown compares unlike things)."""
    import numpy as np

    from reproductions import bench
    from reproductions.mechanics import paths

    fields = {"direct-impact": ("V1", "V1p"), "plane-impact": ("chi1", "zeta1", "p1"),
              "cloth-slide": ("t_roll", "x_roll", "y_roll")}
    for name, fn in bench.BY_HAND.items():
        m = registry.MODELS[name]
        s = m.scene(m.sample(np.random.default_rng(0), 50))
        res = paths.solve(m, s, "exact")
        for f, v in zip(fields[name], fn(s), strict=True):
            np.testing.assert_allclose(v, getattr(res, f), rtol=1e-13, atol=1e-15, err_msg=f"{name}: {f}")


def test_bench_refuses_an_unknown_model():
    res = CliRunner().invoke(app, ["bench", "nope", "--quick"])
    assert res.exit_code == 2 and "unknown model" in res.stderr


def test_make_all_is_timed_recomputed_and_reused(monkeypatch, tmp_path):
    """The full benchmark times `resal reproduce --all` cold and cached (whether the cached run reuses is
    tests/test_cache.py's); here on a config folder of one cheap experiment, once each."""
    import shutil

    from reproductions import api, bench

    configs = tmp_path / "configs"
    configs.mkdir()
    shutil.copy(api.config_dir() / "marble-drop.yaml", configs)
    monkeypatch.setenv("RESAL_CONFIGS", str(configs))
    t = bench.make_all_times(repeat=1)
    assert t["repeat"] == 1 and set(t) >= {"cold", "cached"}
    for what in ("cold", "cached"):
        (run,) = t[what]["runs"]
        assert run["wall"] > 0 and run["cpu"] > 0 and t[what]["median_wall"] == run["wall"]
