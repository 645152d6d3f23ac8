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
import json
import os
import random
import resource
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
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
# seconds after the run has installed its handlers; RESAL_SIGNAL_REPEATS=17 gives 51 runs (the issue's "50 times
# in a row"), the suite runs 2 per signal
_DELAYS = [round(random.Random(23 + i).uniform(0.0, 1.8), 2) for i in range(int(os.environ.get(
    "RESAL_SIGNAL_REPEATS", "2")))]
_STOP = [signal.SIGTERM, signal.SIGINT, signal.SIGHUP]


@contextmanager
def _cpu_contention() -> Iterator[None]:
    """One busy process per core for the block: CI runs on loaded machines, and a signal must end a run cleanly
    wherever it lands (a SIGTERM inside matplotlib's PDF writer once gave exit 1 and a traceback, only under load)."""
    burners = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(os.cpu_count() or 2)]
    try:
        yield
    finally:
        for b in burners:
            b.kill()
            b.wait()


def _as_from_a_terminal() -> None:
    """In the child before it runs: SIGINT, SIGTERM and SIGHUP at their defaults, as a terminal's shell starts a
    command. Under ``nohup`` (or a CI runner that ignores SIGHUP) the test's own process ignores them, a child
    inherits that, and resal rightly keeps a signal ignored from the start: the signal tests would then test
    nothing (a run that finished counts as a pass)."""
    for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(s, signal.SIG_DFL)


def _handlers_installed(pid: int, timeout: float = 30.0) -> None:
    """Wait until process ``pid`` catches SIGTERM (Linux: bit 15 of SigCgt in /proc/<pid>/status): before that,
    Python itself is starting up, and no program can answer a signal there with anything but dying."""
    status = Path(f"/proc/{pid}/status")
    if not status.exists():  # not Linux: a fixed allowance for the start-up
        time.sleep(0.4)
        return
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        try:
            caught = next(int(ln.split()[1], 16) for ln in status.read_text().splitlines() if ln.startswith("SigCgt"))
        except (OSError, StopIteration):
            return
        if caught & (1 << (signal.SIGTERM - 1)):
            return
        time.sleep(0.005)


@pytest.mark.parametrize("sig", _STOP, ids=[s.name for s in _STOP])
@pytest.mark.parametrize("delay", _DELAYS)
def test_a_signal_at_a_random_point_under_cpu_contention(earlier: Path, delay: float, sig: signal.Signals) -> None:
    """SIGTERM, SIGINT and SIGHUP end a run the same way wherever they land, on a loaded machine: one line,
    128 + n, no traceback, no staging left, and the results folder the earlier one or one whole new result."""
    before = hashes(earlier)
    with _cpu_contention():
        p = subprocess.Popen(_reproduce(earlier), cwd=ROOT, env=_env(), stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, preexec_fn=_as_from_a_terminal)
        _handlers_installed(p.pid)
        time.sleep(delay)
        p.send_signal(sig)
        _, err = p.communicate(timeout=120)
    if p.returncode == 0:  # it had finished: the new results, whole
        _whole(earlier, set(before))
        return
    assert p.returncode == 128 + sig, (p.returncode, err)
    _one_error_line(err, f"interrupted ({sig.name})")
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


# -- the environment faults of issue 31 ------------------------------------------------------------------------
def _bench(out: Path) -> list[str]:
    return _cmd("bench", "--quick", "direct-impact", "--out", out)


@pytest.fixture(scope="module")
def earlier_bench(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("bench") / "bench"
    r = subprocess.run(_bench(out), cwd=ROOT, env=_env(), capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    (out / "my-notes.txt").write_text("the machine was busy\n", encoding="utf-8")
    return out


def test_bench_on_a_full_disk_leaves_the_earlier_benchmark_whole(earlier_bench: Path, tmp_path: Path) -> None:
    out = tmp_path / "bench"
    shutil.copytree(earlier_bench, out)
    before = hashes(out)

    def fsize() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (4000, 4000))

    r = subprocess.run(_bench(out), cwd=ROOT, env=_env(), capture_output=True, text=True, timeout=300,
                       preexec_fn=fsize)
    assert r.returncode == 1, r.stderr  # the environment, not the input
    _one_error_line(r.stderr, f"--out {out}", "cannot write the benchmark", "File too large")
    assert hashes(out) == before
    assert _staging(out.parent) == []


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP], ids=["SIGINT", "SIGTERM", "SIGHUP"])
def test_bench_interrupted_says_so_and_leaves_the_earlier_benchmark_whole(earlier_bench: Path, tmp_path: Path,
                                                                         sig: signal.Signals) -> None:
    out = tmp_path / "bench"
    shutil.copytree(earlier_bench, out)
    before = hashes(out)
    p = subprocess.Popen(_bench(out), cwd=ROOT, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, preexec_fn=_as_from_a_terminal)
    _handlers_installed(p.pid)
    time.sleep(0.5)
    p.send_signal(sig)
    _, err = p.communicate(timeout=300)
    assert p.returncode == 128 + sig, (p.returncode, err)
    _one_error_line(err, f"interrupted ({sig.name})")
    assert hashes(out) == before
    assert _staging(out.parent) == []


def _rebound_csv(folder: Path) -> Path:
    data = folder / "rebounds.csv"
    data.write_text("V0,V1\n1.0,-0.55\n2.0,-1.1\n3.0,-1.66\n", encoding="utf-8")
    return data


@pytest.mark.parametrize("encoding", ["ascii", "latin-1"])
def test_a_terminal_that_cannot_print_unicode_gets_ascii_renderings(tmp_path: Path, encoding: str) -> None:
    env = {**_env(), "PYTHONIOENCODING": encoding, "LANG": "C", "LC_ALL": "C"}
    data = _rebound_csv(tmp_path)
    commands = [_cmd("simulate", "direct-impact", "--set", "eps=0.5", "--set", "epsp=0.5"),
                _cmd("simulate", "--list"),
                _cmd("simulate", "direct-impact", "--set", "eps=0.5", "--set", "epsp=0.5", "--json"),
                _cmd("reproduce", EXPERIMENT, "--jobs", "1", "--out", tmp_path / "res"),
                _cmd("fit", "rebound", data, "--no-plot", "--out", tmp_path / "fit"),
                _cmd("simulate", "no-such-model")]
    for args in commands:
        r = subprocess.run(args, cwd=ROOT, env=env, capture_output=True, timeout=300)
        out, err = r.stdout.decode(encoding), r.stderr.decode(encoding)  # what the terminal can show, exactly
        assert "Traceback" not in err and "UnicodeEncodeError" not in err, err
        if args[-1] == "no-such-model":
            assert r.returncode == 2 and err.startswith("error: "), err
            continue
        assert r.returncode == 0, err
        assert out.strip()
        if "--json" in args:  # JSON stays exact: escapes, not renderings
            assert r.stdout.isascii() and json.loads(out)
        if encoding == "ascii" and "--list" in args:
            assert "eps" in out and "sec.I" in out  # ε and § written as a person would


def test_a_standard_output_that_cannot_be_written_is_one_line_and_exit_1() -> None:
    with open("/dev/full", "w") as full:
        r = subprocess.run(_cmd("simulate", "--list"), cwd=ROOT, env=_env(), stdout=full, stderr=subprocess.PIPE,
                           text=True, timeout=180)
    assert r.returncode == 1, r.stderr
    _one_error_line(r.stderr, "cannot write", "No space left on device")


@pytest.mark.parametrize("columns", ["0", "-3", "abc", "5"])
def test_a_nonsense_columns_never_silences_a_command(columns: str) -> None:
    env = {**_env(), "COLUMNS": columns}
    r = subprocess.run(_cmd("simulate", "no-such-model"), cwd=ROOT, env=env, capture_output=True, text=True,
                       timeout=180)
    assert r.returncode == 2
    assert r.stderr.startswith("error: model 'no-such-model'") and "unknown model" in r.stderr
    ok = subprocess.run(_cmd("simulate", "direct-impact", "--set", "eps=0.5", "--set", "epsp=0.5"), cwd=ROOT,
                        env=env, capture_output=True, text=True, timeout=180)
    assert ok.returncode == 0 and "vis_viva_lost" in ok.stdout.replace("\n", "").replace(" ", ""), ok.stderr


def test_a_memory_limit_ends_in_one_line_not_a_traceback() -> None:
    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (300 * 2**20, 300 * 2**20))

    r = subprocess.run(_cmd("simulate", "direct-impact", "--set", "eps=0.5", "--set", "epsp=0.5"), cwd=ROOT,
                       env=_env(), capture_output=True, text=True, timeout=180, preexec_fn=limit)
    assert "Traceback" not in r.stderr, r.stderr
    if r.returncode != 0:  # where 300 MB is too little to load numpy and scipy
        assert r.returncode == 1, r.stderr
        line = _one_error_line(r.stderr)  # numpy's or scipy's import fails: ImportError or MemoryError, by where
        assert "cannot load" in line or "out of memory" in line, line
