"""Is this environment the locked one? `make test` runs this before the suite: the goldens were made with the
versions of requirements.lock, so a run with other versions stops here, with one line, rather than failing golden
tests far down. `python tests/lockcheck.py [LOCK]`: exit 0 when every pin of LOCK that applies to this Python is
installed at its version, else exit 2 with one line on stderr naming what differs (tests/test_lockcheck.py)."""

from __future__ import annotations

import re
import sys
from importlib import metadata
from pathlib import Path

PIN = re.compile(r"^([A-Za-z0-9][A-Za-z0-9._-]*)(?:\[[^\]]*\])?==([^\s;\\]+)\s*(?:;([^\\#]*))?")


def _norm(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def _applies(marker: str | None) -> bool:
    if not marker or not marker.strip():
        return True
    try:
        from packaging.markers import Marker
    except ImportError:  # no packaging: take the pin as applying, and so check it
        return True
    return Marker(marker.strip()).evaluate()


def pins(text: str) -> dict[str, str]:
    """Name (normalised) → version of every ``name==version`` line of a pip-compile lock that applies here."""
    out = {}
    for line in text.splitlines():
        m = PIN.match(line)
        if m and _applies(m.group(3)):
            out[_norm(m.group(1))] = m.group(2)
    return out


def _same(a: str, b: str) -> bool:
    try:
        from packaging.version import Version
    except ImportError:
        return a == b
    try:
        return Version(a) == Version(b)
    except ValueError:
        return a == b


def differences(locked: dict[str, str], installed: dict[str, str]) -> list[tuple[str, str | None, str]]:
    """(name, installed version or None, locked version) for each pin not met, in the lock's order."""
    return [(n, installed.get(n), v) for n, v in locked.items() if n not in installed or not _same(installed[n], v)]


def installed_versions() -> dict[str, str]:
    return {_norm(d.metadata["Name"]): d.version for d in metadata.distributions() if d.metadata["Name"]}


def message(diffs: list[tuple[str, str | None, str]], lock: str) -> str:
    """One line: what differs from the lock, and what to do."""
    if len(diffs) == 1:
        name, have, want = diffs[0]
        if have is None:
            return f"{name} is not installed, {lock} pins {want}: run make setup"
        return f"installed {name} {have} differs from {lock} ({want}): run make setup"
    shown = ", ".join(f"{n} {h or 'missing'} (locked {w})" for n, h, w in diffs[:4])
    more = f" and {len(diffs) - 4} more" if len(diffs) > 4 else ""
    return f"installed versions differ from {lock}: {shown}{more}: run make setup"


def main(argv: list[str]) -> int:
    lock = Path(argv[0] if argv else "requirements.lock")
    if not lock.is_file():
        print(f"{lock}: no such lock file", file=sys.stderr)
        return 2
    locked = pins(lock.read_text(encoding="utf-8"))
    if not locked:
        print(f"{lock}: no name==version line: not a lock", file=sys.stderr)
        return 2
    diffs = differences(locked, installed_versions())
    if diffs:
        print(message(diffs, str(lock)), file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
