"""`resal examples` copies the shipped example files of `resal fit` into a folder (default resal-examples), prints
the command that fits each, leaves identical files alone and refuses, in one line and before writing anything, to
overwrite a file that differs. (That the files ship in the wheel, and that the copy works from an installed wheel:
tests/test_wheel.py.)"""

from __future__ import annotations

import shlex
from pathlib import Path

import pytest
from cli_helpers import assert_bad, invoke, snapshot

from reproductions import locate
from reproductions.fit.kinds import KINDS

REPO = Path(__file__).resolve().parent.parent
SHIPPED = {p.name: p.read_bytes() for p in locate.example_files()}


def test_the_shipped_files_are_the_csvs_of_examples_and_their_readme() -> None:
    assert set(SHIPPED) == {p.name for p in (REPO / "examples").glob("*.csv")} | {"README.md"}
    assert {k.example for k in KINDS.values()} <= set(SHIPPED)  # every kind's help names a shipped file
    for name, data in SHIPPED.items():
        if name.endswith(".csv"):
            assert data.startswith(b"# SYNTHETIC data, not measurements"), name


def test_copies_every_file_and_prints_the_fit_of_each(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    r = invoke("examples")
    assert r.exit_code == 0, r.output
    assert snapshot(tmp_path / "resal-examples") == SHIPPED
    lines = r.stdout.splitlines()
    assert lines[0].startswith(f"wrote {len(SHIPPED)} files into resal-examples/"), lines[0]
    commands = [shlex.split(line) for line in lines if line.startswith("  resal fit ")]
    assert commands[0] == ["resal", "fit", "cushion", "resal-examples/cushion.csv"]  # the one the help pages name
    fitted = {Path(c[3]).name for c in commands}
    assert fitted == {n for n in SHIPPED if n.endswith(".csv")}  # a command for every CSV
    assert all(c[2] in KINDS and (tmp_path / c[3]).is_file() for c in commands)
    by_file = {Path(c[3]).name: c for c in commands}
    assert by_file["ball-ball.csv"][4:] == ["--R", "0.02855"] and by_file["bounces.csv"][4:] == ["--h0", "0.5"]
    assert by_file["pendulum-heights.csv"][2] == "pendulum"


def test_a_named_folder_and_a_second_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert invoke("examples", "my dir/sub").exit_code == 0
    assert snapshot(tmp_path / "my dir" / "sub") == SHIPPED
    (tmp_path / "my dir" / "sub" / "drop.csv").unlink()
    r = invoke("examples", "my dir/sub")  # the same files are left alone, a missing one is written again
    assert r.exit_code == 0, r.output
    assert r.stdout.startswith(f"wrote 1 file into my dir/sub/ ({len(SHIPPED) - 1} already there, the same)")
    assert "  resal fit cushion 'my dir/sub/cushion.csv'" in r.stdout.splitlines()  # quoted, to paste
    assert snapshot(tmp_path / "my dir" / "sub") == SHIPPED
    r = invoke("examples", "my dir/sub")
    assert r.exit_code == 0 and "already holds the" in r.stdout.splitlines()[0]


def test_a_different_file_is_refused_and_nothing_is_copied(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    d = tmp_path / "resal-examples"
    d.mkdir()
    (d / "cushion.csv").write_text("V0,V1\n1,-0.5\n", encoding="utf-8")  # the user's own data, say
    before = snapshot(d)
    assert_bad(invoke("examples"), "resal-examples/cushion.csv", "not the shipped example", "resal examples DIR")
    assert snapshot(d) == before


@pytest.mark.parametrize(("make", "arg", "fragments"), [
    ("file", "taken", ("taken", "is a file, not a folder")),
    (None, "", ("DIR ''", "expected a folder")),
    ("folder", "resal-examples", ("resal-examples/README.md", "is a folder")),
])
def test_bad_folders(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, make: str | None, arg: str,
                     fragments: tuple[str, ...]) -> None:
    monkeypatch.chdir(tmp_path)
    if make == "file":
        (tmp_path / arg).write_text("x", encoding="utf-8")
    elif make == "folder":
        (tmp_path / arg / "README.md").mkdir(parents=True)
    before = snapshot(tmp_path)
    assert_bad(invoke("examples", arg), *fragments)
    assert snapshot(tmp_path) == before
