"""A hostile environment (issue 23): an output folder that cannot be written, a full disk, two runs writing one
results folder at the same moment, and runs interrupted by SIGTERM or SIGKILL at random points.

Each case asserts the exit status (1 for the environment, 2 for an argument that cannot work, 143 for SIGTERM),
one ``error:`` line on stderr and no traceback, and that the earlier results are intact: the files' hashes
before and after, or, where a run may finish, one whole result, the earlier or the new, and no staging left.
Every run is a real process (``python -m cli.main``) reproducing the cheapest experiment, marble-drop, with
``--jobs 1``. A full disk is a file-size limit (``RLIMIT_FSIZE``, with SIGXFSZ ignored): every write beyond it
fails with EFBIG, for root too.
"""

from __future__ import annotations

import hashlib
import os
import random
import resource
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from reproductions.golden import read_summary

ROOT = Path(__file__).resolve().parent.parent
EXPERIMENT = "marble-drop"
STAGING = ".resal-"


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "RESAL_CONFIGS"}
    env["PYTHONPATH"] = str(ROOT)
    return env


def _cmd(*args: object) -> list[str]:
    return [sys.executable, "-m", "cli.main", *map(str, args)]


def _reproduce(out: Path) -> list[str]:
    return _cmd("reproduce", EXPERIMENT, "--jobs", "1", "--force", "--out", out)  # writes whatever is there


def _run(args: list[str], limit: int | None = None) -> subprocess.CompletedProcess[str]:
    def fsize() -> None:  # a full disk: writes beyond `limit` bytes fail with EFBIG (not a SIGXFSZ death)
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return subprocess.run(args, cwd=ROOT, env=_env(), capture_output=True, text=True, timeout=60,
                          preexec_fn=fsize if limit is not None else None)


def hashes(folder: Path) -> dict[str, str | None]:
    """Every file (its SHA-256) and folder (None) under ``folder``, hidden ones included."""
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else None
            for p in sorted(folder.rglob("*"))}


def _one_error_line(stderr: str, *fragments: str) -> str:
    assert "Traceback" not in stderr, stderr
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), stderr
    for f in fragments:
        assert f in lines[0], (f, lines[0])
    return lines[0]


def _staging(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob(f"{STAGING}*"))


def _whole(out: Path, names: set[str]) -> None:
    """``out`` is one whole result: every file a run writes, no staging, the summary readable."""
    assert _staging(out) == [], _staging(out)
    assert set(hashes(out)) == names, set(hashes(out)) ^ names
    assert read_summary(out / EXPERIMENT / "summary.json")["experiment"] == EXPERIMENT  # what `resal diff` reads


@pytest.fixture(scope="module")
def baseline(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("hostile") / "res"
    r = _run(_reproduce(out))
    assert r.returncode == 0, r.stderr
    assert (out / EXPERIMENT / "summary.json").is_file() and (out / "index.html").is_file()
    return out


@pytest.fixture()
def earlier(baseline: Path, tmp_path: Path) -> Path:
    """A private copy of the baseline results, the earlier results a hostile run must leave intact."""
    out = tmp_path / "res"
    shutil.copytree(baseline, out)
    return out


# -- an output folder that cannot be written --------------------------------------------------------------------
def test_out_under_a_regular_file(earlier: Path, tmp_path: Path) -> None:
    """A parent that is a regular file stops root too: refused before any work (exit 2), nothing changed."""
    before = hashes(tmp_path)
    r = _run(_reproduce(earlier / "index.md" / "sub"))
    assert r.returncode == 2, r.stderr
    _one_error_line(r.stderr, f"--out {earlier / 'index.md' / 'sub'}", "cannot create the output folder")
    assert hashes(tmp_path) == before


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0,
                    reason="root writes into a read-only folder; the unwritable cases run as root are the "
                           "regular-file parent and the file-size limit (full disk)")
def test_out_read_only(earlier: Path) -> None:
    before = hashes(earlier)
    earlier.chmod(0o555)
    try:
        r = _run(_reproduce(earlier))
    finally:
        earlier.chmod(0o755)
    assert r.returncode == 2, r.stderr
    _one_error_line(r.stderr, f"--out {earlier}", "not a writable directory")
    assert hashes(earlier) == before


# -- a full disk ------------------------------------------------------------------------------------------------
def test_reproduce_on_a_full_disk(earlier: Path) -> None:
    before = hashes(earlier)
    r = _run(_reproduce(earlier), limit=4000)
    assert r.returncode == 1, r.stderr
    _one_error_line(r.stderr, f"--out {earlier}", "cannot write results", "File too large")
    assert hashes(earlier) == before


def test_fit_on_a_full_disk(tmp_path: Path) -> None:
    data, out = tmp_path / "rebounds.csv", tmp_path / "fit"
    data.write_text("V0,V1\n1.0,-0.55\n2.0,-1.1\n3.0,-1.66\n", encoding="utf-8")
    first = _run(_cmd("fit", "rebound", data, "--no-plot", "--out", out))
    assert first.returncode == 0, first.stderr
    before = hashes(tmp_path)
    r = _run(_cmd("fit", "rebound", data, "--no-plot", "--out", out), limit=100)
    assert r.returncode == 1, r.stderr
    _one_error_line(r.stderr, f"--out {out}", "File too large")
    assert hashes(tmp_path) == before


# -- two runs into one folder -----------------------------------------------------------------------------------
def test_two_runs_into_one_folder_at_once(earlier: Path) -> None:
    names = set(hashes(earlier))
    runs = [subprocess.Popen(_reproduce(earlier), cwd=ROOT, env=_env(), stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True) for _ in range(2)]
    results = [p.communicate(timeout=60) for p in runs]
    for p, (_, err) in zip(runs, results, strict=True):
        assert p.returncode == 0, err
        assert "Traceback" not in err
    _whole(earlier, names)


# -- interruptions --------------------------------------------------------------------------------------------
_DELAYS = [round(random.Random(23 + i).uniform(0.4, 1.8), 2) for i in range(2)]  # seconds after the start


@pytest.mark.parametrize("delay", _DELAYS)
def test_sigterm_at_a_random_point(earlier: Path, delay: float) -> None:
    before = hashes(earlier)
    p = subprocess.Popen(_reproduce(earlier), cwd=ROOT, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    time.sleep(delay)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=60)
    if p.returncode == 0:  # it had finished: the new results, whole
        _whole(earlier, set(before))
        return
    assert p.returncode in (143, -signal.SIGTERM), (p.returncode, err)
    if p.returncode == 143:  # handled (before the handler was installed, Python dies of the signal, silently)
        _one_error_line(err, "interrupted (SIGTERM)")
    assert "Traceback" not in err
    after = hashes(earlier)
    assert _staging(earlier) == []
    if after != before:  # the experiment folder was replaced whole before the signal; nothing else half-written
        _whole(earlier, set(before))


@pytest.mark.parametrize("delay", _DELAYS)
def test_sigkill_at_a_random_point_then_the_next_run_repairs(earlier: Path, delay: float) -> None:
    names = set(hashes(earlier))
    p = subprocess.Popen(_reproduce(earlier), cwd=ROOT, env=_env(), stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)
    time.sleep(delay)
    p.kill()
    p.wait(timeout=60)
    # at once: the experiment folder is whole (the earlier or the new), or set aside whole between two renames
    visible = earlier / EXPERIMENT
    if not visible.is_dir():
        assert any(s.endswith(f".{EXPERIMENT}.old") for s in _staging(earlier)), _staging(earlier)
    else:
        assert {f.name for f in visible.iterdir()} == {n.split("/", 1)[1] for n in names
                                                       if n.startswith(f"{EXPERIMENT}/")}
    r = _run(_reproduce(earlier))  # the next run removes the killed run's staging and writes whole
    assert r.returncode == 0, r.stderr
    _whole(earlier, names)
