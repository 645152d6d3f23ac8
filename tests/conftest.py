"""Test-session setup that must run before numpy is imported.

``OPENBLAS_CORETYPE`` forces OpenBLAS's kernel. Forcing one that the processor cannot execute (SkylakeX and later
need AVX-512) kills the process with "Illegal instruction" at the first matrix product, before any test runs.
Such a request cannot be honoured on this machine: it is dropped, with a line in the test header saying so, and
OpenBLAS chooses the kernel this processor supports. A kernel that the processor can run is always honoured.
"""

import contextlib
import fcntl
import os
import platform
import sys
import tempfile
from pathlib import Path

import pytest

AVX512_KERNELS = {"skylakex", "cooperlake", "sapphirerapids"}
_DROPPED: list[str] = []
SCREENSHOTS: list[str] = []  # files a test saved for people to look at, listed at the end of the run


def _cpu_flags() -> set[str]:
    info = Path("/proc/cpuinfo")
    if not info.is_file():
        return set()
    for line in info.read_text(errors="replace").splitlines():
        if line.startswith("flags"):
            return set(line.split(":", 1)[1].split())
    return set()


_core = os.environ.get("OPENBLAS_CORETYPE", "")
if (_core.lower() in AVX512_KERNELS and platform.machine().lower() in ("x86_64", "amd64")
        and "avx512f" not in _cpu_flags() and "numpy" not in sys.modules):
    _DROPPED.append(_core)
    del os.environ["OPENBLAS_CORETYPE"]


def _message() -> str:
    return (f"OPENBLAS_CORETYPE={_DROPPED[0]} ignored: this processor has no AVX-512, so that kernel cannot run "
            "here; OpenBLAS chose its own")


def pytest_report_header(config):
    return _message() if _DROPPED else None


def pytest_terminal_summary(terminalreporter):  # also under -q, where the header is not shown
    if _DROPPED:
        terminalreporter.write_line(_message())
    for path in SCREENSHOTS:
        terminalreporter.write_line(f"screenshot for people to look at: {path}")


@contextlib.contextmanager
def _held(lock: Path):
    """An exclusive lock on the file ``lock`` (created), held for the block: between pytest-xdist workers."""
    with open(lock, "a+") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def _shared_root(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The folder every worker of this session sees (the parent of the workers' own base folders under xdist)."""
    base = tmp_path_factory.getbasetemp()
    worker = os.environ.get("PYTEST_XDIST_WORKER")
    # xdist gives each worker <session folder>/popen-<worker>; anything else: this worker's own folder
    return base.parent if worker and base.name == f"popen-{worker}" else base


@pytest.fixture(scope="session")
def reproduced_all(tmp_path_factory):
    """One ``resal reproduce --all`` for the whole session, (folder, stdout): read it, never change it (a test that
    changes results copies the folder first). Under pytest-xdist the first worker that asks runs it and the others
    wait for it and read the same folder (one run of every experiment, not one per worker)."""
    from typer.testing import CliRunner

    from cli.main import app

    root = _shared_root(tmp_path_factory)
    out, said = root / "reproduced-all", root / "reproduced-all.stdout"
    with _held(root / "reproduced-all.lock"):
        if not said.is_file():  # into a folder of its own, renamed once whole: a failed run leaves nothing to read
            work = Path(tempfile.mkdtemp(prefix="reproduced-all.", dir=root))
            res = CliRunner().invoke(app, ["reproduce", "--all", "--out", str(work)])
            assert res.exit_code == 0, res.output
            work.rename(out)
            said.write_text(res.stdout.replace(str(work), str(out)), encoding="utf-8")
    return out, said.read_text(encoding="utf-8")


@pytest.fixture(scope="session")
def runs():
    """Every experiment run once in this process, by id (``api.run``): read them, never change them."""
    from reproductions import api

    return {eid: api.run(api.load(eid)) for eid in api.experiment_ids()}


# Modules that take the longest, started first: pytest-xdist hands whole files to the workers in collection order, and
# a long file started last leaves the other core idle while it runs. Measured (seconds of test time, 2 workers).
FIRST = ("test_wheel", "test_userfit", "test_verdict_rules", "test_hostile_environment", "test_fit_coverage_ricochet",
         "test_fit_rebound_checks", "test_output_safety", "test_stress", "test_fit_ballball_checks",
         "test_paper_report", "test_golden_stability", "test_fit_coverage_table")


def pytest_collection_modifyitems(items):
    rank = {name: i for i, name in enumerate(FIRST)}
    items.sort(key=lambda it: rank.get(it.path.stem, len(FIRST)))  # stable: the rest keep their order
