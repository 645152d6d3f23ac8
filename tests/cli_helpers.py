"""Asserting helpers shared by the bad-input tests: one ``error:`` message, exit 2, nothing else changed."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner, Result

from cli.main import app


def squash(s: str) -> str:
    """Rich wraps long messages at the console width: compare them with all whitespace removed."""
    return "".join(s.split())


def invoke(*args: object) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


def assert_bad(result: Result, *fragments: str) -> str:
    """Exit 2, one ``error:`` message on stderr containing every fragment, nothing on stdout, no traceback."""
    assert result.exit_code == 2, (result.exit_code, result.output, repr(result.exception))
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    assert "Traceback" not in result.output
    assert result.stdout == ""
    err = result.stderr
    assert err.startswith("error: "), err
    assert err.count("error:") == 1, err
    for f in fragments:
        assert squash(f) in squash(err), f"{f!r} not in {err!r}"
    return err


def snapshot(folder: Path) -> dict[str, bytes | None]:
    """Every file (its bytes) and folder (None) under ``folder``, hidden ones included."""
    return {str(p.relative_to(folder)): (p.read_bytes() if p.is_file() else None) for p in folder.rglob("*")}
