"""Test-session setup that must run before numpy is imported.

``OPENBLAS_CORETYPE`` forces OpenBLAS's kernel. Forcing one that the processor cannot execute (SkylakeX and later
need AVX-512) kills the process with "Illegal instruction" at the first matrix product, before any test runs.
Such a request cannot be honoured on this machine: it is dropped, with a line in the test header saying so, and
OpenBLAS chooses the kernel this processor supports. A kernel that the processor can run is always honoured.
"""

import os
import platform
import sys
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


@pytest.fixture(scope="session")
def reproduced_all(tmp_path_factory):
    """One ``resal reproduce --all`` for the whole session, (folder, stdout): read it, never change it (a test that
    changes results copies the folder first)."""
    from typer.testing import CliRunner

    from cli.main import app

    out = tmp_path_factory.mktemp("reproduced-all")
    res = CliRunner().invoke(app, ["reproduce", "--all", "--out", str(out)])
    assert res.exit_code == 0, res.output
    return out, res.stdout
