"""Results on disk and the command line: files, schema, determinism, index, JSON outputs."""

import csv
import json

import pytest
from typer.testing import CliRunner

from cli.main import app
from reproductions import api, report

runner = CliRunner()


@pytest.fixture(scope="module")
def written(reproduced_all):
    return reproduced_all[0]


NO_FIGURES = {"impact-law"}  # §I n°2-4: identities and principles checked on sampled configurations; no curve


def test_all_experiments_written_with_tables_figures_and_index(written):
    for eid in api.experiment_ids():
        d = written / eid
        for name in ("summary.json", "table.md", "table.csv", "table.tex"):
            assert (d / name).stat().st_size > 0, name
        s = json.loads((d / "summary.json").read_text())
        assert s["figures"] or eid in NO_FIGURES, eid
        assert all((d / f).stat().st_size > 1000 for f in s["figures"])
        assert {"experiment", "title", "source", "rows", "fits", "figures", "provenance"} <= s.keys()
        assert {"version", "git_commit", "config_sha256", "seed"} <= s["provenance"].keys()
        for r in s["rows"]:
            assert r["verdict"] in ("reproduced", "differs", "not-checkable")
            assert r["verdict"] != "differs" or r["note"]
    index = (written / "index.md").read_text()
    assert all(f"[{eid}]({eid}/table.md)" in index for eid in api.experiment_ids())
    assert not [p for p in written.iterdir() if p.name.startswith(".")]  # no staging leftovers
    # the paper table: every printed value once, in the paper's order (by line; the order itself is checked in
    # test_paper_report.py)
    summaries = [json.loads((written / e / "summary.json").read_text()) for e in api.experiment_ids()]
    table = [ln for ln in (written / "paper-table.md").read_text().splitlines() if ln.startswith("| ")][1:]
    assert len(table) == sum(len(s["rows"]) for s in summaries)
    assert sorted(ln.split(" | ")[0][2:] for ln in table) == sorted(s["experiment"] for s in summaries
                                                                    for _ in s["rows"])
    assert (written / "paper-table.tex").read_text().count(r"\\") == len(table) + 1
    with (written / "paper-table.csv").open(newline="") as fh:
        assert len(list(csv.reader(fh))) == len(table) + 1
    assert (written / "report.pdf").read_bytes().startswith(b"%PDF")


def test_outputs_are_deterministic(tmp_path):
    rep = api.run(api.load("coriolis-pendulum"))
    prov = report.provenance(rep)
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    a = report.write_reproduction(rep, tmp_path / "a", prov)
    b = report.write_reproduction(api.run(api.load("coriolis-pendulum")), tmp_path / "b", prov)
    for name in ("summary.json", "table.md", "table.csv", "table.tex", "pendulum.png", "pendulum.pdf"):
        assert (a / name).read_bytes() == (b / name).read_bytes(), name


def test_reproduce_json_prints_the_summary(tmp_path):
    res = runner.invoke(app, ["reproduce", "marble-drop", "--json", "--out", str(tmp_path)])
    assert res.exit_code == 0
    s = json.loads(res.stdout)
    assert s["experiment"] == "marble-drop"
    import yaml

    printed = yaml.safe_load((api.config_dir() / "marble-drop.yaml").read_text(encoding="utf-8"))["printed"]
    assert [r["id"] for r in s["rows"]] == [p["id"] for p in printed]  # one row per printed entry, in its order
    assert {"eps", "velocity_ratio", "eps_no_rebound"} <= {r["id"] for r in s["rows"]}


def test_reproduce_a_user_yaml_by_path(tmp_path):
    text = (api.config_dir() / "marble-drop.yaml").read_text().replace("id: marble-drop", "id: my-drop")
    text = text.replace("value: 2/3", "value: 0.5")
    cfg = tmp_path / "mine.yaml"
    cfg.write_text(text)
    res = runner.invoke(app, ["reproduce", str(cfg), "--json", "--out", str(tmp_path / "out")])
    assert res.exit_code == 0, res.output
    s = json.loads(res.stdout)
    eps = next(r for r in s["rows"] if r["id"] == "eps")["computed"]
    assert eps == pytest.approx((1 - 0.5**0.5) / (1 + 0.5**0.5))


def test_list_shows_every_experiment():
    res = runner.invoke(app, ["list"])
    assert res.exit_code == 0
    for eid in api.experiment_ids():
        assert eid in res.stdout


def test_simulate_direct_impact_json():
    res = runner.invoke(app, ["simulate", "direct-impact", "--set", "M=3", "--set", "Mp=1", "--set", "V0=1",
                              "--set", "eps=0", "--set", "epsp=0.2667", "--json"])
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    assert out["model"] == "direct-impact" and out["method"] == "auto" and "eq. (7)" in out["label"]
    assert out["path"] == 1 and out["path_name"] == "exact" and out["regime"] == 0  # codes, not prose
    assert out["outputs"]["V1p"] == pytest.approx(6 / (1 + 3 * 1.2667), rel=1e-12)
    assert out["inputs"]["V0p"] == 0.0


def test_simulate_list_names_models_and_parameters():
    import re

    res = runner.invoke(app, ["simulate", "--list"])
    assert res.exit_code == 0
    assert "direct-impact" in res.stdout and "wall-impact" in res.stdout
    assert re.search(r"^\s+epsp\s+1\s+0 ≤ epsp ≤ 1\s+required\s", res.stdout, re.M)  # unit, range, no default


def test_simulate_list_json_gives_every_model_its_paths_and_units():
    from reproductions.mechanics import registry

    res = runner.invoke(app, ["simulate", "--list", "--json"])
    assert res.exit_code == 0
    info = json.loads(res.stdout)
    assert "degrees" in info["units"]
    assert [m["model"] for m in info["models"]] == list(registry.MODELS)
    for m in info["models"]:
        assert m["paths"] and any(p["kind"] == "ode-reference" for p in m["paths"])
        assert all(p["unit"] for p in m["parameters"])
    ric = next(m for m in info["models"] if m["model"] == "ricochet")
    alpha = next(p for p in ric["parameters"] if p["name"] == "alpha0")
    assert alpha["unit"] == "degrees" and alpha["hi"] == pytest.approx(90.0)


def test_diff_finds_a_changed_number_and_accepts_identical(written, tmp_path):
    a = written / "coriolis-cushion" / "summary.json"
    same = runner.invoke(app, ["diff", str(a), str(written / "coriolis-cushion")])
    assert same.exit_code == 0, same.output
    s = json.loads(a.read_text())
    next(r for r in s["rows"] if r["id"] == "eps")["computed"] = 0.3
    b = tmp_path / "b.json"
    b.write_text(json.dumps(s))
    changed = runner.invoke(app, ["diff", str(a), str(b)])
    assert changed.exit_code == 1
    assert "rows.eps.computed" in changed.stdout
    bad = runner.invoke(app, ["diff", str(a), str(tmp_path / "none.json")])
    assert bad.exit_code == 2


def test_parallel_and_sequential_runs_write_the_same_files(tmp_path):
    for jobs in ("1", "2"):
        res = runner.invoke(app, ["reproduce", "marble-drop", "coriolis-cushion", "--jobs", jobs,
                                  "--out", str(tmp_path / jobs)])
        assert res.exit_code == 0, res.output
    for eid in ("marble-drop", "coriolis-cushion"):
        names = sorted(p.name for p in (tmp_path / "1" / eid).iterdir())
        assert names == sorted(p.name for p in (tmp_path / "2" / eid).iterdir())
        assert {"summary.json", "table.md", "table.csv", "table.tex"} < set(names) and any(".png" in n for n in names)
        for name in names:  # figures too: drawn on a pool, they are the same bytes
            assert (tmp_path / "1" / eid / name).read_bytes() == (tmp_path / "2" / eid / name).read_bytes(), name
    for jobs in ("1", "2"):  # no scratch or staging folder left behind
        assert not [p for p in (tmp_path / jobs).iterdir() if p.name.startswith(".")]


def test_input_error_survives_pickling():
    import pickle

    from reproductions.errors import InputError

    err = pickle.loads(pickle.dumps(InputError("data.csv:3", "column 'x': expected a number")))
    assert (err.where, err.message) == ("data.csv:3", "column 'x': expected a number")


@pytest.mark.parametrize("width", [80, 200])
def test_an_experiment_reads_in_an_80_column_terminal_with_no_word_broken(tmp_path, width):
    """At 80 columns each row is a record wrapped at words (a nine-column table broke 'measurement' into
    'measur'/'ement'); at 200 it is the table. Either way every word of every note is printed whole."""
    import re

    from cli import main

    before = main.out_console._width
    main.out_console.width = width
    try:
        res = runner.invoke(app, ["reproduce", "marble-drop", "--out", str(tmp_path)])
    finally:
        main.out_console._width = before
    assert res.exit_code == 0, res.output
    assert max(len(ln.rstrip()) for ln in res.stdout.splitlines()) <= width
    assert ("┃ quantity" in res.stdout) == (width >= main.WIDE_TABLE)
    s = json.loads((tmp_path / "marble-drop" / "summary.json").read_text(encoding="utf-8"))
    printed = set(re.findall(r"[A-Za-zÀ-ÿ]+", res.stdout))
    words = {w for r in s["rows"] for w in re.findall(r"[A-Za-zÀ-ÿ]+", r["note"] + " " + r["quantity"])}
    if width < main.WIDE_TABLE:
        assert words <= printed, sorted(words - printed)
