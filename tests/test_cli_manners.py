"""The command line's manners (clig.dev), as a user sees them (issue 33):

- ``resal --version`` names resal's version, its git commit in a checkout, and Python's, numpy's and scipy's;
- every help page shows an Examples block (commands that start with ``resal``) before its arguments and options;
- ``resal --help`` and ``resal fit --help`` list each command by a whole summary that fits its line at 80 columns;
- arguments read in capitals in the usage lines (``resal diff [OPTIONS] A B``);
- a name that is nearly right (an experiment id, a model, a kind of fit, a command, an option) gets "did you mean";
- output is plain: no automatic highlighting of numbers on a terminal; piped, no ANSI codes and no line ending in
  spaces (a table's cells padded to their width).

Help pages are found by walking the app's commands, as ``test_usage_one_line`` does, so a command added later is
covered without a line here.
"""

from __future__ import annotations

import io
import os
import platform
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import typer.main
from cli_helpers import invoke
from typer.testing import CliRunner

from cli import common
from cli.main import app
from reproductions import __version__

ROOT = Path(__file__).resolve().parent.parent
ANSI = re.compile(r"\x1b\[")


def _env(**extra: str) -> dict[str, str]:
    """The environment of a child ``resal``: this checkout's code, 80 columns, no colour forced."""
    env = {k: v for k, v in os.environ.items() if k not in ("FORCE_COLOR", "TTY_COMPATIBLE", "NO_COLOR")}
    env.update(PYTHONPATH=str(ROOT), COLUMNS="80", **extra)
    return env


def resal(*args: object, cwd: Path, **env: str) -> subprocess.CompletedProcess[str]:
    """``resal …`` as a child process whose stdout and stderr are pipes."""
    return subprocess.run([sys.executable, "-m", "cli.main", *map(str, args)], cwd=cwd, env=_env(**env),
                          capture_output=True, text=True, encoding="utf-8", timeout=300)


def _commands() -> list[tuple[tuple[str, ...], Any]]:
    """(path, click command) of the app itself, of every command and group it registers, and of theirs."""
    found: list[tuple[tuple[str, ...], Any]] = []

    def walk(cmd: Any, path: tuple[str, ...]) -> None:
        found.append((path, cmd))
        for name, sub in sorted(getattr(cmd, "commands", {}).items()):
            walk(sub, (*path, name))

    walk(typer.main.get_command(app), ())
    return found


COMMANDS = _commands()
PATHS = [p for p, _ in COMMANDS]
IDS = [" ".join(p) or "resal" for p in PATHS]


def help_page(*path: str) -> str:
    result = CliRunner(env={"COLUMNS": "80"}).invoke(app, [*path, "--help"])
    assert result.exit_code == 0, result.output
    return result.stdout


# ---- --version --------------------------------------------------------------------------------------------------
def _git_commit() -> str | None:
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        return None
    r = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True)
    return r.stdout.strip() or None


def test_version_names_resal_its_commit_python_numpy_and_scipy(tmp_path: Path) -> None:
    import numpy
    import scipy

    r = resal("--version", cwd=tmp_path)  # piped, from another folder
    assert r.returncode == 0 and r.stderr == "", r.stderr
    lines = r.stdout.splitlines()
    assert lines[0] == f"resal {__version__}"
    assert f"Python {platform.python_version()}" in lines
    assert f"numpy {numpy.__version__}" in lines and f"scipy {scipy.__version__}" in lines
    commit = _git_commit()
    if commit is not None:  # a checkout: its commit, abbreviated
        assert any(ln.startswith(f"commit {commit[:12]}") for ln in lines), lines
    else:
        assert not any(ln.startswith("commit") for ln in lines), lines
    assert not ANSI.search(r.stdout) and not re.search(r" $", r.stdout, re.M)


def test_version_is_an_option_of_resal_only() -> None:
    assert invoke("--version").exit_code == 0
    assert "not an option of `resal list`" in invoke("list", "--version").stderr


# ---- examples first ---------------------------------------------------------------------------------------------
def examples(page: str) -> list[str]:
    """The command lines of a help page's Examples block (its lines indented under "Examples:")."""
    m = re.search(r"^\s*Examples:\n((?:[ \t]+\S.*\n?)+)", page, re.M)
    assert m, page
    return [ln.strip() for ln in m.group(1).splitlines()]


def _resolve(words: list[str]) -> tuple[tuple[str, ...], Any]:
    """The command an example runs (the longest command path its words start with) and that command."""
    by_path = dict(COMMANDS)
    path: tuple[str, ...] = ()
    for w in words:
        if (*path, w) not in by_path:
            break
        path = (*path, w)
    return path, by_path[path]


@pytest.mark.parametrize("path", PATHS, ids=IDS)
def test_every_help_page_shows_examples_before_its_options(path: tuple[str, ...]) -> None:
    page = help_page(*path)
    start = page.index("Examples:")
    for section in ("Arguments:", "Options:", "Commands:"):
        if section in page:
            assert start < page.index(section), (section, page)
    lines = examples(page)
    assert lines and all(re.match(r"resal( |$)", ln) for ln in lines), lines
    if path:  # the page's own command among them (a group's: one of its commands)
        assert any(ln.split()[1:1 + len(path)] == list(path) for ln in lines), (path, lines)
    for ln in lines:
        assert len(ln) + 4 <= 80, ln  # as printed, indented, it fits 80 columns


@pytest.mark.parametrize("path", PATHS, ids=IDS)
def test_examples_name_real_commands_and_their_options(path: tuple[str, ...]) -> None:
    """Each example names a command of the app and only options that command takes (or --help)."""
    for ln in examples(help_page(*path)):
        words = shlex.split(ln)[1:]
        where, cmd = _resolve(words)
        assert where, ln
        rest = words[len(where):]
        if getattr(cmd, "commands", None):  # a group: an example of it ends in --help (or names no command)
            assert rest in ([], ["--help"]), ln
            continue
        takes = {o for p in cmd.params for o in [*p.opts, *p.secondary_opts]} | {"--help"}
        for w in rest:
            if w.startswith("--"):
                assert w.split("=")[0] in takes, (ln, w, sorted(takes))


def test_fit_examples_use_the_folder_resal_examples_writes() -> None:
    for path, _ in COMMANDS:
        if len(path) == 2 and path[0] == "fit":
            lines = examples(help_page(*path))
            assert lines[0] == "resal examples", lines
            data = shlex.split(lines[1])[3]
            assert data.startswith("resal-examples/") and (ROOT / "examples" / Path(data).name).is_file(), data


# ---- whole summaries --------------------------------------------------------------------------------------------
def _summary(cmd: Any) -> str:
    if cmd.short_help:
        return " ".join(cmd.short_help.split())
    first = (cmd.help or "").strip().split("\n\n", 1)[0]
    return " ".join(w for w in first.split() if w != "\b")


@pytest.mark.parametrize("path", [p for p, c in COMMANDS if getattr(c, "commands", None)],
                         ids=[" ".join(p) or "resal" for p, c in COMMANDS if getattr(c, "commands", None)])
def test_each_command_is_listed_by_a_whole_summary_on_one_line(path: tuple[str, ...]) -> None:
    page = help_page(*path)
    listed = page.split("Commands:\n", 1)[1].splitlines()
    group = dict(COMMANDS)[path]
    rows = {m.group(1): m.group(2) for ln in listed if (m := re.match(r"^  (\S+)\s+(.*)$", ln))}
    assert set(rows) == set(group.commands), (rows, page)
    assert all(re.match(r"^  \S", ln) for ln in listed if ln.strip()), ("a summary wraps", page)
    for name, text in rows.items():
        assert text == _summary(group.commands[name]), (name, text)  # whole: not cut at "§I eq." nor "..."
        assert text.endswith(".") and not text.endswith("..."), (name, text)
    assert all(len(ln) <= 80 for ln in listed), page


# ---- usage lines -------------------------------------------------------------------------------------------------
def test_diff_usage_names_its_arguments_a_and_b() -> None:
    usage = help_page("diff").splitlines()[0]
    assert re.search(r" diff \[OPTIONS\] A B$", usage), usage
    assert "Missing argument 'B'" in invoke("diff", "x").stderr


@pytest.mark.parametrize("path", PATHS, ids=IDS)
def test_usage_lines_name_arguments_in_capitals(path: tuple[str, ...]) -> None:
    usage = help_page(*path).splitlines()[0]
    assert "{" not in usage and "}" not in usage, usage
    after = usage.split("[OPTIONS]", 1)[1].split()
    for piece in after:
        assert re.fullmatch(r"\[?[A-Z][A-Z_]*(\.[a-z]+)?\]?(\.\.\.)?|COMMAND|\[ARGS\]\.\.\.", piece), usage


# ---- near misses ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("args", "hint", "kept"), [
    (("reproduce", "marbel-drop"), "did you mean marble-drop?", "unknown experiment id (expected one of"),
    (("simulate", "direct-impakt"), "did you mean direct-impact?", "unknown model (expected one of"),
    (("simulate", "direct-impact", "--method", "exatc"), "did you mean exact?", "has no path 'exatc'"),
    (("simulate", "direct-impact", "--set", "epss=0.1"), "did you mean eps?", "unknown parameter 'epss'"),
    (("bench", "wall-impakt"), "did you mean wall-impact?", "unknown model (expected some of"),
    (("fit", "cushon", "data.csv"), "did you mean cushion?", "expected one of rebound, cushion"),
    (("reproduse",), "did you mean reproduce?", "not a command of `resal`"),
    (("stress", "--sed", "3"), "did you mean --seed", "not an option of `resal stress`"),
])
def test_a_near_miss_gets_did_you_mean(args: tuple[str, ...], hint: str, kept: str) -> None:
    r = invoke(*args)
    assert r.exit_code == 2 and r.stdout == "", r.output
    assert r.stderr.count("\n") == 1 and r.stderr.startswith("error: "), r.stderr
    assert hint in r.stderr and kept in r.stderr, r.stderr


@pytest.mark.parametrize("args", [("reproduce", "zzzz-qqqq"), ("simulate", "nothing-like-it"), ("fit", "xyz", "a.csv")])
def test_a_name_nowhere_near_gets_no_guess(args: tuple[str, ...]) -> None:
    r = invoke(*args)
    assert r.exit_code == 2 and "did you mean" not in r.stderr, r.stderr


def test_the_api_says_it_too() -> None:
    from reproductions import api
    from reproductions.errors import InputError

    with pytest.raises(InputError, match=r"unknown model .*; did you mean wall-impact\?$"):
        api.simulate("wall-impactt", eps=0.3)
    with pytest.raises(InputError, match=r"; did you mean coriolis-pendulum\?$"):
        api.load("coriolis-pendulm")


# ---- plain, unpadded output -------------------------------------------------------------------------------------
def test_the_consoles_do_not_highlight_on_a_terminal(tmp_path: Path) -> None:
    """On a terminal (forced here), numbers in plain text are not coloured: only explicit styles are."""
    r = resal("simulate", "direct-impact", "--set", "eps=0.5", "--set", "epsp=0.5", cwd=tmp_path,
              TTY_COMPATIBLE="1", FORCE_COLOR="1", TERM="xterm-256color")
    assert r.returncode == 0, r.stderr
    assert ANSI.search(r.stdout), "no style at all: the terminal was not forced"
    assert not re.search(r"\x1b\[[0-9;]*m[-+]?\d", r.stdout), r.stdout  # a coloured number


def test_a_console_that_is_not_a_terminal_writes_no_padding() -> None:
    from rich.table import Table

    buf = io.StringIO()
    console = common._Console(file=buf, width=60, force_terminal=False)
    t = Table(title="padded")
    t.add_column("a")
    t.add_column("b")
    t.add_row("1", "a longer cell")
    t.add_row("22", "x")
    console.print(t)
    console.print("a ", end="")  # a line still being written keeps its spaces
    console.print("b")
    text = buf.getvalue()
    assert "\n" in text and not re.search(r" +$", text, re.M), text.replace(" ", "·")
    assert text.endswith("a b\n") and "│ 22 │ x" in text


PIPED = [
    ("list",),
    ("simulate", "--list"),
    ("simulate", "direct-impact", "--set", "eps=0.5", "--set", "epsp=0.5"),
    ("fit", "rebound", ROOT / "examples" / "rebound.csv", "--no-plot", "--out", "fit-out"),
]


@pytest.mark.parametrize("args", PIPED, ids=[" ".join(map(str, a[:2])) for a in PIPED])
def test_piped_output_is_plain_and_unpadded(tmp_path: Path, args: tuple[object, ...]) -> None:
    r = resal(*args, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip(), r.stderr
    assert not ANSI.search(r.stdout) and not ANSI.search(r.stderr)
    padded = [ln for ln in r.stdout.splitlines() if ln != ln.rstrip()]
    assert not padded, [ln.replace(" ", "·") for ln in padded[:5]]
