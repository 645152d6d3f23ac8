"""A results folder is reused when what made it has not changed (its config, data files and code: ``digest``), and
recomputed when anything of that changed; a reused folder and a recomputed one are the same bytes."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from reproductions import api, digest
from tests.cli_helpers import invoke, snapshot

CHEAP = ("marble-drop", "coriolis-cushion")  # two experiments of a fraction of a second each


@pytest.fixture
def configs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A configs folder of its own (``$RESAL_CONFIGS``) holding copies of the cheap experiments."""
    d = tmp_path / "configs"
    d.mkdir()
    for i in CHEAP:
        shutil.copy(api.config_dir() / f"{i}.yaml", d)
    monkeypatch.setenv("RESAL_CONFIGS", str(d))
    return d


def _mtimes(folder: Path) -> dict[str, int]:
    return {str(p.relative_to(folder)): p.stat().st_mtime_ns for p in folder.rglob("*")}


def _run(out: Path, *args: str) -> str:
    r = invoke("reproduce", *CHEAP, "--out", out, *args)
    assert r.exit_code == 0, r.output
    return r.stderr


def test_an_unchanged_run_reuses_everything_and_a_forced_run_gives_the_same_bytes(configs: Path, tmp_path: Path):
    out = tmp_path / "out"
    first = _run(out)
    assert "wrote 2 experiment folder(s)" in first and "reused" not in first
    before, times = snapshot(out), _mtimes(out)
    again = _run(out)
    assert "reused 2 unchanged" in again and "wrote 2" not in again
    assert "kept the reader's edition" in " ".join(again.split())
    assert _mtimes(out) == times  # nothing rewritten, not even the index
    forced = tmp_path / "forced"
    _run(forced, "--force")
    assert snapshot(forced) == before
    _run(out, "--force")
    assert snapshot(out) == before and _mtimes(out) != times  # recomputed, to the same bytes


def test_the_digest_is_in_the_provenance_and_names_the_data_files(configs: Path, tmp_path: Path):
    out = tmp_path / "out"
    _run(out)
    prov = json.loads((out / "marble-drop" / "summary.json").read_text())["provenance"]
    rec = prov["digest"]
    assert rec["code"] == digest.code_digest() and rec["data"] == {}
    assert rec["inputs"] == digest.experiment_digest(prov["config_sha256"], {}, rec["code"])


def test_a_changed_config_recomputes_that_experiment_only(configs: Path, tmp_path: Path):
    out = tmp_path / "out"
    _run(out)
    times = _mtimes(out)
    cfg = configs / "marble-drop.yaml"
    cfg.write_text(cfg.read_text() + "\n# a comment changes the bytes, so the digest\n")
    err = _run(out)
    assert "wrote 1 experiment folder(s)" in err and "reused 1 unchanged" in err
    now = _mtimes(out)
    assert all(now[k] == v for k, v in times.items() if k.startswith("coriolis-cushion"))
    assert now["marble-drop/summary.json"] != times["marble-drop/summary.json"]
    # the summary changed (its config hash), so the whole-paper files are rendered again
    assert now["index.html"] != times["index.html"]


def test_a_changed_data_file_recomputes(configs: Path, tmp_path: Path):
    """A config that names a CSV: editing the CSV (not the config) recomputes its experiment."""
    cfg = configs / "coriolis-cushion.yaml"
    text = cfg.read_text()
    start = text.index("    synthetic: {")
    cfg.write_text(text[:start] + "    csv: trials.csv\n" + text[text.index("\n", start) + 1:])
    data = configs / "trials.csv"
    data.write_text("V0,V1\n1.0,-0.55\n2.0,-1.12\n3.0,-1.64\n4.0,-2.21\n")
    out = tmp_path / "out"
    _run(out)
    rec = json.loads((out / "coriolis-cushion" / "summary.json").read_text())["provenance"]["digest"]
    assert rec["data"] == {str(data): digest.file_sha256(data)}
    assert "reused 2 unchanged" in _run(out)
    data.write_text("V0,V1\n1.0,-0.55\n2.0,-1.12\n3.0,-1.64\n4.0,-2.20\n")
    err = _run(out)
    assert "wrote 1 experiment folder(s)" in err and "reused 1 unchanged" in err
    data.unlink()  # a data file gone: recomputed, and the run says what is missing
    r = invoke("reproduce", "coriolis-cushion", "--out", out)
    assert r.exit_code == 2 and "trials.csv" in r.stderr


def test_a_folder_missing_a_file_or_a_digest_is_recomputed(configs: Path, tmp_path: Path):
    out = tmp_path / "out"
    _run(out)
    (out / "marble-drop" / "table.md").unlink()
    s = out / "coriolis-cushion" / "summary.json"
    summary = json.loads(s.read_text())
    del summary["provenance"]["digest"]  # written by a resal that recorded none
    s.write_text(json.dumps(summary))
    assert "wrote 2 experiment folder(s)" in _run(out)
    assert (out / "marble-drop" / "table.md").is_file()


def test_a_changed_figure_of_an_experiment_renders_the_index_again(configs: Path, tmp_path: Path):
    out = tmp_path / "out"
    _run(out)
    index = (out / "index.html").stat().st_mtime_ns
    (out / "report.pdf").unlink()  # a whole-paper file missing: rendered again, the experiments reused
    err = " ".join(_run(out).split())
    assert "reused 2 unchanged" in err and "wrote the reader's edition" in err
    assert (out / "report.pdf").is_file() and (out / "index.html").stat().st_mtime_ns != index


def _package_copy(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    pkg = tmp_path / "reproductions"
    shutil.copytree(digest.PACKAGE, pkg, ignore=shutil.ignore_patterns("__pycache__", "configs"))
    monkeypatch.setattr(digest, "PACKAGE", pkg)
    digest.code_digest.cache_clear()
    return pkg


def test_the_code_digest_follows_what_the_experiments_import(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    """Editing the physics (imported by every kind) changes it; editing the reader's edition (which no experiment
    imports) does not, but changes the edition's own digest."""
    pkg = _package_copy(tmp_path, monkeypatch)
    try:
        closure = digest.import_closure(digest.EXPERIMENT_ROOTS)
        assert {"reproductions.mechanics.impact", "reproductions.experiments.ricochet", "reproductions.config",
                "reproductions.fit.estimators.lsq"} <= closure.keys()
        assert not {"reproductions.edition", "reproductions.bench", "reproductions.api"} & closure.keys()
        code, edition = digest.code_digest(), digest.code_digest(digest.EDITION_ROOTS)
        with open(pkg / "edition" / "html.py", "a") as fh:
            fh.write("\n# an edit\n")
        digest.code_digest.cache_clear()
        assert digest.code_digest() == code and digest.code_digest(digest.EDITION_ROOTS) != edition
        edition = digest.code_digest(digest.EDITION_ROOTS)
        with open(pkg / "edition" / "templates" / "edition.css", "a") as fh:  # a template is the edition's code
            fh.write("\n/* an edit */\n")
        digest.code_digest.cache_clear()
        assert digest.code_digest() == code and digest.code_digest(digest.EDITION_ROOTS) != edition
        with open(pkg / "mechanics" / "impact.py", "a") as fh:
            fh.write("\n# an edit\n")
        digest.code_digest.cache_clear()
        assert digest.code_digest() != code
        (pkg / "data" / "modern-values.csv").write_text("changed\n")
        digest.code_digest.cache_clear()
        assert digest.code_digest() != code
    finally:
        digest.code_digest.cache_clear()


def test_an_import_inside_a_function_is_followed(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    pkg = _package_copy(tmp_path, monkeypatch)
    try:
        (pkg / "lazy.py").write_text('def f():\n    """A docstring whose line reads as an import:\n'
                                     '    from .edition import nothing\n    """\n'
                                     "    from .mechanics import (\n        cue,\n        spheres)\n")
        found = digest._imports("reproductions.lazy", pkg / "lazy.py")
        assert found == {"reproductions", "reproductions.mechanics", "reproductions.mechanics.cue",
                         "reproductions.mechanics.spheres",
                         "reproductions.edition"}  # the docstring's line adds a module: never one lost
    finally:
        digest.code_digest.cache_clear()
