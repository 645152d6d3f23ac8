"""``resal list`` in the reader's edition's order, one line per experiment; ``resal simulate --list`` grouped and
compact, ranges in the unit typed; ``simulate``'s warning of radians typed for degrees, its 6 significant digits
(``--digits``), and the names of the path and regime codes beside them in ``api.simulate``."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from typer.testing import CliRunner, Result

from cli import main
from cli.main import app
from reproductions import api, edition, models, report
from reproductions.fit.kinds import markers
from reproductions.mechanics.paths import PathCode, Regime

WIDTH = 80
DIRECT = ["simulate", "direct-impact", "--set", "M=3", "--set", "Mp=1", "--set", "V0=1", "--set", "eps=0",
          "--set", "epsp=0.2667"]
RICOCHET = ["simulate", "ricochet", "--set", "f=0.2", "--set", "nu=0.8"]


def run(*args: str, width: int = WIDTH) -> Result:
    """One command with the output console ``width`` columns wide (as a pipe is 80)."""
    before = main.out_console._width
    main.out_console.width = width
    try:
        return CliRunner(env={"COLUMNS": str(width)}).invoke(app, list(args))
    finally:
        main.out_console._width = before


# -- resal list ---------------------------------------------------------------------------------------------------
def _edition_order() -> list[str]:
    """The experiments in the order the reader's edition shows them: summaries as ``report._summaries`` sorts a
    results folder, through ``edition.build`` (the paper's part, then today's measurements)."""
    def summary(e: api.Experiment) -> dict:
        measurements = [{"id": m.id, "quantity": "q", "source": "s", "unit": "1", "measured": 1.0,
                         "measured_text": "1", "uncertainty": "", "predicted": 1.0, "interval": None,
                         "verdict": "consistent", "note": "", "config_line": 1, "computes": m.id} for m in e.measured]
        return {"experiment": e.id, "title": e.title, "kind": e.kind, "rows": [], "figures": [], "notes": [],
                "source": {"section": e.source.section, "page": e.source.page, "equations": []}, "question": "",
                "findings": [], "provenance": {}, "measurements": measurements, "modern": []}

    found = sorted(((e.id, summary(e)) for e in api.list_experiments()),  # a folder's listing: by name
                   key=lambda x: report.paper_order(x[1]["source"]["page"], x[1]["experiment"]))
    ed = edition.build(found)
    return [s.experiment for s in ed.sections + ed.measured_sections]


def test_list_is_in_the_editions_order_a_line_each_within_80_columns(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("RESAL_CONFIGS", raising=False)
    res = run("list")
    assert res.exit_code == 0, res.output
    lines = res.stdout.splitlines()
    ids = api.experiment_ids()
    rows = [ln for ln in lines if ln.split(" ", 1)[0] in ids]
    shown = [ln.split(" ", 1)[0] for ln in rows]
    assert shown == _edition_order()  # one line per experiment, in the edition's order
    assert shown != sorted(ids)  # not the alphabetical order of before
    assert shown[0] == "impact-law" and shown.index("cue-stroke") < shown.index("modern-restitution")
    assert all(len(ln) <= WIDTH for ln in lines[:-1]), [ln for ln in lines if len(ln) > WIDTH]
    assert lines[-1] == str(api.config_dir())  # the config folder on a line of its own, after the list
    assert len(lines) == len(ids) + 4  # the header, the heading of today's measurements, two lines of folder
    for e in api.list_experiments():  # its section, and its title whole or cut at a word with "…"
        row = next(ln for ln in rows if ln.startswith(e.id + " "))
        assert e.source.section in row
        title = row.split("  ")[-1].strip()
        assert title == e.title or (title.endswith("…") and e.title.startswith(title[:-1].rstrip())
                                    and e.title[len(title[:-1].rstrip())] in " ,;:"), (title, e.title)
    assert any(ln.endswith("…") for ln in rows)  # at 80 columns some titles are too long for a line
    wide = run("list", width=200)
    assert not any(ln.endswith("…") for ln in wide.stdout.splitlines())  # a wide console shows them whole


# -- resal simulate --list ----------------------------------------------------------------------------------------
def test_simulate_list_is_compact_without_trailing_spaces_in_degrees() -> None:
    res = run("simulate", "--list")
    assert res.exit_code == 0, res.output
    lines = res.stdout.splitlines()
    assert len(lines) <= 150  # 150 lines at 80 columns (175, padded to 80 columns, before)
    assert [ln for ln in lines if ln != ln.rstrip()] == []
    assert all(len(ln) <= WIDTH for ln in lines), [ln for ln in lines if len(ln) > WIDTH]
    assert "π" not in res.stdout  # an angle is typed in degrees: 90, not π/2
    assert re.search(r"^  alpha0\s+degrees\s+0 < alpha0 < 90\s+20\s+its angle below the plane$", res.stdout, re.M)
    assert re.search(r"^  i\s+degrees\s+0 ≤ i < 90\s+0\s", res.stdout, re.M)
    info = json.loads(run("simulate", "--list", "--json").stdout)
    for m in info["models"]:  # a heading line per model: its name, section and paths
        head = next(ln for ln in lines if ln.startswith(m["model"] + "  "))
        assert m["section"] in head and "paths: " + m["paths"][0]["name"] in head
        for p in m["parameters"]:  # a line per parameter, its name first
            assert re.search(rf"^  {re.escape(p['name'])}\s+{re.escape(p['unit'])}\s", res.stdout, re.M), p["name"]


def test_simulate_list_json_keeps_its_structure() -> None:
    info = json.loads(run("simulate", "--list", "--json").stdout)
    assert set(info) == {"units", "path_codes", "regime_codes", "models"}
    for m in info["models"]:
        assert set(m) == {"model", "section", "doc", "admits", "parameters", "paths", "outputs"}
    alpha0 = next(p for m in info["models"] if m["model"] == "ricochet" for p in m["parameters"]
                  if p["name"] == "alpha0")
    assert (alpha0["lo"], alpha0["hi"], alpha0["unit"]) == (0.0, 90.0, "degrees")
    assert alpha0["range"] == "a number in (0, 90)"


# -- the radians warning ------------------------------------------------------------------------------------------
def test_the_bound_is_fits() -> None:
    assert models.RADIANS == markers.RADIANS


def test_radians_typed_for_degrees_are_warned_of() -> None:
    res = run(*RICOCHET, "--set", "alpha0=0.35")
    assert res.exit_code == 0, res.output
    assert res.stderr.startswith("warning: ") and res.stderr.count("\n") == 1, res.stderr
    assert "alpha0=0.35" in res.stderr and "degrees" in res.stderr and "alpha0=20.05" in res.stderr
    out = json.loads(run(*RICOCHET, "--set", "alpha0=0.35", "--json").stdout)
    assert [w["code"] for w in out["warnings"]] == ["implausible-input"]
    assert out["inputs"]["alpha0"] == 0.35  # read as degrees all the same


@pytest.mark.parametrize("args", [[*RICOCHET, "--set", "alpha0=20"], RICOCHET,  # degrees; none given
                                  ["simulate", "cue-stroke", "--set", "i=0", "--set", "f=0.25", "--set", "eps=0",
                                   "--set", "epsp=0.8"]])  # 0: as likely degrees as radians
def test_no_warning_for_degrees(args: list[str]) -> None:
    res = run(*args)
    assert res.exit_code == 0, res.output
    assert res.stderr == ""
    assert json.loads(run(*args, "--json").stdout)["warnings"] == []


# -- digits -------------------------------------------------------------------------------------------------------
def _value(out: str, name: str) -> str:
    return re.search(rf"^\s*(?:in|out)?\s+{name}\s+(\S+)", out, re.M).group(1)


def test_six_digits_unless_asked_and_json_whole() -> None:
    full = json.loads(run(*DIRECT, "--json").stdout)["outputs"]
    v = full["vis_viva_lost"]
    assert len(repr(v).replace("0.", "").lstrip("0")) > 10  # a number with more digits than shown
    default = run(*DIRECT).stdout
    assert _value(default, "vis_viva_lost") == f"{v:.6g}" and _value(default, "V1") == f"{full['V1']:.6g}"
    three = run(*DIRECT, "--digits", "3").stdout
    assert _value(three, "vis_viva_lost") == f"{v:.3g}" != f"{v:.6g}"
    assert _value(run(*DIRECT, "--digits", "17").stdout, "vis_viva_lost") == f"{v:.17g}"
    lists = run(*RICOCHET, "--digits", "3").stdout  # a list's numbers too
    first = json.loads(run(*RICOCHET, "--json").stdout)["outputs"]["ranges"][0]
    assert _value(lists, "ranges") == f"{first:.3g},"
    for bad in ("0", "18"):
        res = run(*DIRECT, "--digits", bad)
        assert res.exit_code == 2 and res.stderr.startswith(f"error: --digits {bad}:"), res.stderr


# -- names beside codes -------------------------------------------------------------------------------------------
def test_api_simulate_names_its_codes() -> None:
    one = api.simulate("ricochet", f=0.2, nu=0.8)
    assert one.path_name.shape == one.path.shape == ()
    assert str(one.path_name) == PathCode(int(one.path)).name.lower() == "exact"
    assert str(one.regime_name) == Regime(int(one.regime)).name.lower().replace("_", "-")
    cli = json.loads(run(*RICOCHET, "--json").stdout)
    assert (str(one.path_name), str(one.regime_name)) == (cli["path_name"], cli["regime_name"])
    batch = api.simulate("cushion-impact", p0=np.array([0.0, 20.0, 20.0]), j=np.array([0.0, 0.2, 0.2]), eps=0.3,
                         chi0=np.array([1.0, 1.0, 1.0]))
    assert batch.path_name.shape == batch.path.shape == (3,) and batch.regime_name.shape == (3,)
    assert list(batch.path_name) == [PathCode(int(c)).name.lower().replace("_", "-") for c in batch.path]
    assert list(batch.regime_name) == [Regime(int(c)).name.lower().replace("_", "-") for c in batch.regime]
    assert len(set(batch.regime_name)) > 1  # the names follow each scene's code
    resal = api.simulate("cushion-impact", "resal-corrected", j=0.2, eps=0.3)
    assert str(resal.path_name) == "resal-corrected" and int(resal.path) == PathCode.RESAL_CORRECTED
