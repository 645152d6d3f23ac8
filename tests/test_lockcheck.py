"""requirements.lock and its check (tests/lockcheck.py, run by `make test` before the suite): fake locks that this
environment does and does not meet, the one line it prints, and the real lock against pyproject.toml."""

from __future__ import annotations

import re
import subprocess
import sys
from importlib import metadata
from pathlib import Path

import lockcheck
import pytest

from reproductions.report import code_provenance

REPO = Path(__file__).resolve().parent.parent
CHECK = REPO / "tests" / "lockcheck.py"

HASH = "    --hash=sha256:" + "0" * 64


def _lock(tmp_path: Path, lines: list[str]) -> Path:
    p = tmp_path / "requirements.lock"
    p.write_text("# fake lock\n" + "".join(f"{line} \\\n{HASH}\n    # via resal\n" for line in lines), encoding="utf-8")
    return p


def _check(lock: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(CHECK), str(lock)], capture_output=True, text=True, timeout=60)


def test_a_lock_this_environment_meets_passes(tmp_path: Path) -> None:
    lock = _lock(tmp_path, [f"numpy=={metadata.version('numpy')}", f"PyYAML=={metadata.version('pyyaml')}",
                            'no-such-package-for-py2==1.0 ; python_version < "3"'])
    r = _check(lock)
    assert (r.returncode, r.stdout, r.stderr) == (0, "", "")


def test_a_version_that_differs_stops_with_one_line(tmp_path: Path) -> None:
    have = metadata.version("numpy")
    r = _check(_lock(tmp_path, ["numpy==0.0.1", f"pytest=={metadata.version('pytest')}"]))
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr == f"installed numpy {have} differs from {tmp_path / 'requirements.lock'} (0.0.1): run make setup\n"


def test_a_missing_package_and_several_differences_still_one_line(tmp_path: Path) -> None:
    r = _check(_lock(tmp_path, ["no-such-package-xyz==1.0"]))
    assert r.returncode == 2 and r.stderr.count("\n") == 1
    assert "no-such-package-xyz is not installed" in r.stderr and "pins 1.0: run make setup" in r.stderr
    r = _check(_lock(tmp_path, ["numpy==0.0.1", "scipy==0.0.1", "rich==0.0.1", "typer==0.0.1", "ruff==0.0.1",
                                "no-such-package-xyz==1.0"]))
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert r.stderr.startswith("installed versions differ from ") and "numpy" in r.stderr
    assert r.stderr.rstrip().endswith("and 2 more: run make setup")


def test_not_a_lock(tmp_path: Path) -> None:
    empty = tmp_path / "empty.lock"
    empty.write_text("# nothing pinned\n", encoding="utf-8")
    for lock in (empty, tmp_path / "absent.lock"):
        r = _check(lock)
        assert r.returncode == 2 and r.stderr.count("\n") == 1 and str(lock) in r.stderr


def test_versions_compare_as_versions() -> None:
    assert lockcheck.differences({"x": "1.0"}, {"x": "1.0.0"}) == []
    assert lockcheck.differences({"typing-extensions": "4.0"}, {}) == [("typing-extensions", None, "4.0")]
    assert lockcheck.pins("Typing_Extensions==4.16.0 \\\npydantic[email]==2.1 ; python_version >= '3'\n") == {
        "typing-extensions": "4.16.0", "pydantic": "2.1"}


def _project() -> dict:
    tomllib = pytest.importorskip("tomllib")
    return tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def _name(requirement: str) -> str:
    return lockcheck._norm(re.match(r"[A-Za-z0-9._-]+", requirement).group(0))


def test_the_lock_pins_every_dependency_with_hashes_within_pyprojects_ranges() -> None:
    """Every runtime and test dependency is pinned, each pin carries hashes (pip --require-hashes), and each
    range of pyproject.toml has an upper bound below the next major version."""
    text = (REPO / "requirements.lock").read_text(encoding="utf-8")
    pins = lockcheck.pins(text)
    project = _project()
    wanted = [*project["dependencies"], *project["optional-dependencies"]["test"]]
    assert [r for r in wanted if _name(r) not in pins] == []
    assert [r for r in wanted if ",<" not in r] == [], "each range needs an upper bound"
    blocks = re.split(r"\n(?=[A-Za-z0-9])", text)
    assert all("--hash=sha256:" in b for b in blocks if lockcheck.PIN.match(b))


def test_provenance_records_every_runtime_dependency() -> None:
    deps = code_provenance()["dependencies"]
    assert sorted(lockcheck._norm(n) for n in deps) == sorted(_name(r) for r in _project()["dependencies"])
    assert all(deps[n] == metadata.version(n) for n in deps)


def test_this_environment_is_the_locked_one() -> None:
    """What `make test` checks first, also for a bare `pytest`: the suite and the goldens assume the lock."""
    diffs = lockcheck.differences(lockcheck.pins((REPO / "requirements.lock").read_text(encoding="utf-8")),
                                  lockcheck.installed_versions())
    assert not diffs, lockcheck.message(diffs, "requirements.lock")
