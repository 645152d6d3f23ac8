"""Issue 33: what a run says while it runs, and what a command says when it is done.

``reproduce`` piped says each experiment as it finishes, while the run goes on (not all at the end), on stderr only;
``run_and_draw`` reports each experiment as it finishes and the figures' total only once it is known; ``diff`` of
summaries of two experiments is one line of bad input; ``fit markers`` prints whether its series agree and whether
its residuals trend with ψ; a fit without bootstrap intervals shows no column of dashes for them."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest
from cli_helpers import assert_bad, invoke

from reproductions import api

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
IDS = ["marble-drop", "coriolis-cushion", "coriolis-pendulum"]  # fast ones


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("RESAL_CONFIGS", "COLUMNS")}
    env["PYTHONPATH"] = str(ROOT)
    return env


@pytest.fixture(scope="module")
def piped(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """``reproduce`` of three experiments on one process, stderr a pipe read line by line as it comes: each line
    with whether the process was still running and whether the edition (written last) existed when it was read."""
    out = tmp_path_factory.mktemp("progress") / "res"
    stdout = out.parent / "stdout.txt"
    with stdout.open("w", encoding="utf-8") as fh:
        proc = subprocess.Popen([sys.executable, "-m", "cli.main", "reproduce", *IDS, "--jobs", "1", "--out",
                                 str(out)], cwd=ROOT, env=_env(), stdout=fh, stderr=subprocess.PIPE, text=True)
        lines = []
        try:
            for line in proc.stderr:  # type: ignore[union-attr]
                lines.append((line.rstrip("\n"), proc.poll() is None, (out / "index.html").exists(),
                              time.monotonic()))
            proc.wait(timeout=300)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
    return {"out": out, "code": proc.returncode, "lines": lines, "end": time.monotonic(),
            "stdout": stdout.read_text(encoding="utf-8")}


# -- reproduce, piped: a line per experiment as it finishes ------------------------------------------------------
def test_a_piped_run_says_each_experiment_as_it_finishes(piped: dict) -> None:
    assert piped["code"] == 0, piped["lines"]
    done = [(text, running, edition) for text, running, edition, _ in piped["lines"] if ": done in " in text]
    assert [text.split(":")[0] for text, _, _ in done] == IDS, piped["lines"]  # --jobs 1: in the order named
    for i, (text, _, _) in enumerate(done, 1):
        assert re.fullmatch(rf"[\w-]+: done in \d+\.\d+ s \(.*\d+ reproduced.*\); {i} of {len(IDS)} run", text), text
    text, running, edition = done[0]
    # read while the run went on: the process alive and the edition, which is written after every experiment has
    # run and its figures are drawn, not yet there (a run that said everything at its end fails both)
    assert running and not edition, piped["lines"]


def test_the_piped_run_says_its_figures_and_edition_and_keeps_stdout(piped: dict) -> None:
    texts = [t for t, *_ in piped["lines"]]
    figures = [t for t in texts if t.startswith("figures: ")]
    assert len(figures) == 1 and re.match(r"figures: \d+ drawn; ", figures[0]), texts
    assert any(t.startswith("reader's edition: written in ") for t in texts), texts
    last_done = max(i for i, t in enumerate(texts) if ": done in " in t)
    edition = next(i for i, t in enumerate(texts) if t.startswith("reader's edition: "))
    assert last_done < texts.index(figures[0]) < edition, texts  # each stage said as it ends
    # stdout is the report as before: a line per experiment, then the total; no progress in it
    stdout = piped["stdout"].splitlines()
    assert [ln.split()[0] for ln in stdout[:3]] == IDS and stdout[3].startswith("total")
    assert "done in" not in piped["stdout"]


def test_one_experiment_piped_says_no_progress_line(tmp_path: Path) -> None:
    r = subprocess.run([sys.executable, "-m", "cli.main", "reproduce", "marble-drop", "--jobs", "1", "--out",
                        str(tmp_path / "res")], cwd=ROOT, env=_env(), capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "done in" not in r.stderr and "figures:" not in r.stderr  # its table follows at once; errors stay one line


# -- run_and_draw: each experiment reported as it finishes, the figures' total once known ------------------------
def test_run_and_draw_reports_each_experiment_and_the_real_figure_total(tmp_path: Path) -> None:
    events: list[api.RunProgress] = []
    reps = api.run_and_draw([api.load(i) for i in IDS[:2]], 2, tmp_path, events.append)
    finished = [e for e in events if e.finished is not None]
    assert sorted(e.finished.experiment.id for e in finished) == sorted(IDS[:2])
    assert all(e.seconds is not None and e.seconds > 0 for e in finished)
    assert [e.ran for e in finished] == [1, 2]
    total = sum(len(r.figures) for r in reps)
    assert total > 0
    assert all(e.figures is None for e in events if e.ran < 2)  # never a total that is not the real one
    assert all(e.figures == total for e in events if e.ran == 2)
    assert events[-1].drawn == total and "figures drawn: " in str(events[-1])


# -- diff ----------------------------------------------------------------------------------------------------------
def test_diff_of_two_experiments_is_one_line_exit_2(piped: dict) -> None:
    a, b = piped["out"] / IDS[0], piped["out"] / IDS[1]
    res = invoke("diff", a, b)
    err = assert_bad(res, f"{a} is experiment {IDS[0]}", f"{b} is experiment {IDS[1]}",
                     "compare summaries of one experiment")
    assert err.count("\n") == 1, err
    assert invoke("diff", a, a).exit_code == 0


def test_diff_of_results_folders_names_an_experiment_in_one_only(piped: dict, tmp_path: Path) -> None:
    other = tmp_path / "other"
    other.mkdir()
    for i in IDS[:2]:
        shutil.copytree(piped["out"] / i, other / i)
    res = invoke("diff", piped["out"], other)
    assert res.exit_code == 1, res.output
    assert f"only in {piped['out']}: {IDS[2]}" in " ".join(res.stdout.split())


# -- fit markers: the agreement of the series and the residual trends, as verdicts ---------------------------------
def _markers(tmp_path: Path, alpha1_scale: float = 1.0) -> Path:
    """examples/markers.csv, its α1 markers scaled (1.3: the cue ball's turn no longer matches the throw's f)."""
    out = []
    for ln in (EXAMPLES / "markers.csv").read_text(encoding="utf-8").splitlines():
        if ln.startswith("alpha1,"):
            s, psi, a = ln.split(",")
            ln = f"{s},{psi},{float(a) * alpha1_scale:.3f}"
        out.append(ln)
    path = tmp_path / "markers.csv"
    path.write_text("\n".join(out) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize(("scale", "agree", "overlap", "trend"), [(1.0, "yes", "overlap", "none"),
                                                                   (1.3, "no", "do not overlap", "slope")])
def test_markers_fit_prints_whether_its_series_agree(tmp_path: Path, scale: float, agree: str, overlap: str,
                                                      trend: str) -> None:
    res = invoke("fit", "markers", _markers(tmp_path, scale), "--out", tmp_path / "fit", "--no-plot")
    assert res.exit_code == 0, res.output
    text = " ".join(res.stdout.split())  # lines wrap at 80 columns
    s = json.loads((tmp_path / "fit" / "fit.json").read_text(encoding="utf-8"))
    p = s["agreement"]["p"]
    assert (p >= 0.05) == (agree == "yes")  # what fit.json says, printed
    assert f"series agree: {agree} (p = {p:.2g}, likelihood ratio " in text, text
    assert re.search(rf"f intervals \[[^]]+\] and \[[^]]+\] {overlap}\)", text), text
    t = s["residual_trend"]["alpha1"]
    assert f"residual trend against ψ (alpha1): {trend}" in text and f"p = {t['p']:.2g}" in text
    assert "residual trend against ψ (throw): none" in text
    assert "bootstrap 95 %" not in res.stdout  # the markers fit has no bootstrap: no column of dashes
    assert "series agree: " in (tmp_path / "fit" / "fit.md").read_text(encoding="utf-8")


def test_a_bootstrap_column_only_where_a_bootstrap_ran(tmp_path: Path) -> None:
    data = EXAMPLES / "rebound.csv"
    none = invoke("fit", "rebound", data, "--bootstrap", "0", "--out", tmp_path / "a", "--no-plot")
    some = invoke("fit", "rebound", data, "--bootstrap", "50", "--out", tmp_path / "b", "--no-plot")
    assert none.exit_code == 0 and some.exit_code == 0, none.output + some.output
    assert "bootstrap 95 %" not in none.stdout
    assert "bootstrap 95 %" in some.stdout
    assert "bootstrap 95 %" not in (tmp_path / "a" / "fit.md").read_text(encoding="utf-8")
    assert "bootstrap 95 %" in (tmp_path / "b" / "fit.md").read_text(encoding="utf-8")
