"""Usage mistakes and the environment end like every other bad input: one ``error:`` line on stderr, exit 2.

Every command of the app, found by walking the typer app's registered commands and groups (so a command added
later is covered without a line here), refuses an option it does not have in one line naming the command; and a
``$RESAL_CONFIGS`` that names no folder is told as such, naming the variable.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import typer.main
from cli_helpers import invoke

from cli.main import app
from reproductions import locate
from reproductions.errors import InputError


def _commands() -> list[tuple[str, ...]]:
    """The command path of the app itself, of every command and group it registers, and of theirs."""
    found: list[tuple[str, ...]] = []

    def walk(cmd: object, path: tuple[str, ...]) -> None:
        found.append(path)
        for name, sub in sorted(getattr(cmd, "commands", {}).items()):
            walk(sub, (*path, name))

    walk(typer.main.get_command(app), ())
    return found


COMMANDS = _commands()


def test_the_walk_finds_the_registered_commands() -> None:
    registered = {c.name or c.callback.__name__ for c in app.registered_commands}  # type: ignore[union-attr]
    registered |= {g.name for g in app.registered_groups}  # type: ignore[misc]
    top = {p[0] for p in COMMANDS if len(p) == 1}
    assert top == {"list", "reproduce", "simulate", "bench", "stress", "diff", "examples", "fit"}
    assert len(top) == len(registered)
    assert ("fit", "rebound") in COMMANDS and ("fit", "markers") in COMMANDS


@pytest.mark.parametrize("path", COMMANDS, ids=[" ".join(p) or "resal" for p in COMMANDS])
def test_an_unknown_option_is_one_error_line(path: tuple[str, ...]) -> None:
    result = invoke(*path, "--no-such-option")
    assert result.exit_code == 2, (result.output, repr(result.exception))
    assert result.stdout == ""
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: --no-such-option: "), result.stderr
    assert f"not an option of `{' '.join(('resal', *path))}`" in lines[0], lines[0]
    assert "Usage:" not in result.stderr and "Traceback" not in result.stderr


@pytest.mark.parametrize("args", [("diff",), ("simulate", "direct-impact", "--set"), ("fit", "rebound"),
                                  ("reproduse",), ("bench", "--quik")])
def test_other_usage_mistakes_are_one_error_line(args: tuple[str, ...]) -> None:
    result = invoke(*args)
    assert result.exit_code == 2 and result.stdout == ""
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("error: "), result.stderr


@pytest.mark.parametrize("args", [(), ("fit",), ("bench", "--help")])
def test_help_is_still_help(args: tuple[str, ...]) -> None:
    result = invoke(*args)
    assert "Usage: " in result.output and "error:" not in result.output


# ---- $RESAL_CONFIGS ----------------------------------------------------------------------------------------------
def test_a_relative_configs_folder_is_taken_from_the_current_folder(tmp_path: Path,
                                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "one.yaml").write_text("id: one\n", encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("RESAL_CONFIGS", "mine")
    assert locate.config_dir() == tmp_path / "mine" and locate.experiment_ids() == ["one"]


@pytest.mark.parametrize(("value", "what"), [("a-file.yaml", "is a file, not a folder"),
                                              ("no-such-folder", "no such folder")])
def test_a_configs_path_that_is_no_folder_names_the_variable(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                             value: str, what: str) -> None:
    (tmp_path / "a-file.yaml").write_text("id: x\n", encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    for given in (value, str(tmp_path / value)):  # relative, and absolute
        monkeypatch.setenv("RESAL_CONFIGS", given)
        with pytest.raises(InputError) as exc:
            locate.experiment_ids()
        assert exc.value.where == f"$RESAL_CONFIGS={given}" and what in exc.value.message
        assert ("taken from the current folder" in exc.value.message) == (given == value)
        result = invoke("list")
        assert result.exit_code == 2 and result.stderr.count("\n") == 1
        assert result.stderr.startswith(f"error: $RESAL_CONFIGS={given}: {what}"), result.stderr
