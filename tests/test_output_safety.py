"""resal deletes only what it wrote, and reuses only what it wrote (issue 31).

Every folder resal writes carries ``manifest.json`` (each file it wrote, with its SHA-256). A rerun, ``--force``
or a new fit into an earlier fit's folder replaces those files and carries every other entry (a user's notes, a
folder of theirs) into the new folder, byte for byte, and says so. The cache reuses a folder only when every file of
its manifest still has the bytes resal wrote; a file changed by hand makes that experiment computed again, named in
one line. A summary.json that is not resal's is named in one line and never breaks a run. Runs are real processes
(``python -m cli.main``) reproducing the cheapest experiment, marble-drop.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from reproductions import digest, report

ROOT = Path(__file__).resolve().parent.parent
EXP = "marble-drop"


def _env(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("RESAL_CONFIGS", "COLUMNS")}
    env["PYTHONPATH"] = str(ROOT)
    env.update(extra)
    return env


def _run(*args: object, timeout: float = 120, **env: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "cli.main", *map(str, args)], cwd=ROOT, env=_env(**env),
                          capture_output=True, text=True, timeout=timeout)


def _sha(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


def _no_traceback(r: subprocess.CompletedProcess[str]) -> None:
    assert "Traceback" not in r.stderr and "Traceback" not in r.stdout, r.stderr


@pytest.fixture(scope="module")
def baseline(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("safety") / "res"
    r = _run("reproduce", EXP, "--jobs", "1", "--out", out)
    assert r.returncode == 0, r.stderr
    return out


@pytest.fixture()
def res(baseline: Path, tmp_path: Path) -> Path:
    out = tmp_path / "res"
    shutil.copytree(baseline, out, symlinks=True)
    return out


def test_the_manifest_lists_every_file_resal_wrote_with_its_bytes(res: Path) -> None:
    folder = res / EXP
    listed = report.read_manifest(folder)
    assert listed is not None
    on_disk = {p.name for p in folder.iterdir()} - {report.MANIFEST}
    assert set(listed) == on_disk  # nothing written unlisted, nothing listed unwritten
    assert all(listed[n] == _sha(folder / n) for n in listed)
    assert report.changed_by_hand(folder) == [] and report.foreign_files(folder) == []


@pytest.mark.parametrize("force", [False, True], ids=["changed-config", "force"])
def test_a_rewrite_keeps_the_users_files_byte_for_byte_and_says_so(res: Path, force: bool) -> None:
    folder = res / EXP
    (folder / "notes.md").write_text("my notes on the marble\n", encoding="utf-8")
    (folder / "mine").mkdir()
    (folder / "mine" / "photo.dat").write_bytes(os.urandom(1000))
    (folder / "link").symlink_to("notes.md")
    before = {p.relative_to(folder): _sha(p) for p in [folder / "notes.md", folder / "mine" / "photo.dat"]}
    if force:
        r = _run("reproduce", EXP, "--jobs", "1", "--out", res, "--force")
    else:  # the same experiment from a copy of its config: recomputed because its config path differs
        cfg = res.parent / f"{EXP}.yaml"
        shutil.copy(ROOT / "configs" / f"{EXP}.yaml", cfg)
        r = _run("reproduce", cfg, "--jobs", "1", "--out", res)
        assert "held the results of" in r.stderr and str(cfg) in r.stderr  # a shipped id taken over: said
    assert r.returncode == 0, r.stderr
    assert {p.relative_to(folder): _sha(p) for p in [folder / "notes.md", folder / "mine" / "photo.dat"]} == before
    assert os.readlink(folder / "link") == "notes.md"
    assert "kept link, mine, notes.md (not written by resal" in r.stderr
    assert report.foreign_files(folder) == ["link", "mine", "notes.md"]
    assert not any(p.name.startswith(".resal-") for p in res.iterdir())


def test_a_users_file_under_a_name_resal_now_writes_is_kept_aside(tmp_path: Path) -> None:
    folder = tmp_path / "f"
    report.write_folder(folder, {"a.txt": "resal's a\n"})
    (folder / "b.txt").write_text("the user's b\n", encoding="utf-8")  # not in the manifest: the user's
    report.write_folder(folder, {"a.txt": "resal's a, again\n", "b.txt": "resal's b\n"})
    assert (folder / "b.txt").read_text() == "resal's b\n"
    assert (folder / "b.txt.yours").read_text() == "the user's b\n"
    assert report.foreign_files(folder) == ["b.txt.yours"]
    # a file resal wrote and no longer writes is removed (it was resal's): only the manifest's files are replaced
    report.write_folder(folder, {"a.txt": "only a\n"})
    assert sorted(p.name for p in folder.iterdir()) == ["a.txt", "b.txt.yours", report.MANIFEST]


def test_a_fit_into_an_earlier_fit_folder_keeps_the_notes_added_to_it(tmp_path: Path) -> None:
    data, out = tmp_path / "rebounds.csv", tmp_path / "fit"
    data.write_text("V0,V1\n1.0,-0.55\n2.0,-1.1\n3.0,-1.66\n", encoding="utf-8")
    assert _run("fit", "rebound", data, "--no-plot", "--out", out).returncode == 0
    (out / "lab-notes.txt").write_text("ball 3 was chipped\n", encoding="utf-8")
    r = _run("fit", "rebound", data, "--no-plot", "--out", out)
    assert r.returncode == 0, r.stderr
    assert (out / "lab-notes.txt").read_text() == "ball 3 was chipped\n"
    assert "kept lab-notes.txt" in r.stderr


@pytest.mark.parametrize("what", ["summary-number", "table", "figure"])
def test_a_file_changed_by_hand_is_not_reused_but_computed_again_and_named(res: Path, what: str) -> None:
    folder = res / EXP
    original = {n: _sha(folder / n) for n in report.read_manifest(folder)}
    if what == "summary-number":  # the attack: one computed value set by hand
        s = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
        row = next(r for r in s["rows"] if isinstance(r.get("computed"), float))
        row["computed"] = 123.456
        (folder / "summary.json").write_text(json.dumps(s, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
        name = "summary.json"
    elif what == "table":
        (folder / "table.md").write_text("| a hand-edited table |\n", encoding="utf-8")
        name = "table.md"
    else:
        name = next(n for n in original if n.endswith(".png"))
        (folder / name).write_bytes(b"not a png")
    r = _run("reproduce", EXP, "--jobs", "1", "--out", res)
    assert r.returncode == 0, r.stderr
    _no_traceback(r)
    assert f"{folder}: {name} changed since resal wrote it: computing it again" in r.stderr
    assert "123.456" not in r.stdout
    # recomputed: every file as resal writes it (figures and tables are deterministic; the summary's provenance
    # holds the same commit and digest, so its bytes come back too)
    assert {n: _sha(folder / n) for n in report.read_manifest(folder)} == original
    again = _run("reproduce", EXP, "--jobs", "1", "--out", res)
    assert "reused 1 unchanged" in again.stderr and "changed since" not in again.stderr


def test_reuse_verifies_outputs_without_the_cli(res: Path) -> None:
    cfg = ROOT / "configs" / f"{EXP}.yaml"
    summary, why = digest.reuse(res / EXP, cfg)
    assert summary is not None and why is None
    (res / EXP / "table.csv").write_text("x\n", encoding="utf-8")
    summary, why = digest.reuse(res / EXP, cfg)
    assert summary is None and "table.csv changed since resal wrote it" in why
    (res / EXP / report.MANIFEST).unlink()  # no manifest: nothing can be verified, so nothing is reused
    assert digest.reuse(res / EXP, cfg) == (None, None)


@pytest.mark.parametrize("content", ["{}", "[1, 2]", '{"experiment": "x", "rows": "none"}', "not json"],
                         ids=["empty-object", "a-list", "wrong-types", "not-json"])
def test_a_summary_that_is_not_resals_is_named_in_one_line_and_never_breaks_a_run(res: Path, content: str) -> None:
    (res / "stray").mkdir()
    (res / "stray" / "summary.json").write_text(content, encoding="utf-8")
    for args in (("reproduce", EXP, "--jobs", "1", "--out", res), ("reproduce", EXP, "--jobs", "1", "--out", res,
                                                                    "--force")):
        r = _run(*args)
        assert r.returncode == 0, r.stderr
        _no_traceback(r)
        named = [ln for ln in r.stderr.splitlines() if str(res / "stray" / "summary.json") in ln]
        assert len(named) <= 1
    # the edition was written (at least once) and the stray folder left out of it, by name
    assert "stray" not in (res / "index.md").read_text(encoding="utf-8")
    assert (res / "stray" / "summary.json").read_text(encoding="utf-8") == content  # not ours: never touched


def test_a_hand_edited_edition_file_is_written_again(res: Path) -> None:
    html = res / "index.html"
    good = _sha(html)
    with html.open("a", encoding="utf-8") as fh:
        fh.write("<!-- edited -->\n")
    r = _run("reproduce", EXP, "--jobs", "1", "--out", res)
    assert r.returncode == 0, r.stderr
    assert f"{res}: index.html changed since resal wrote it: writing it again" in r.stderr
    assert _sha(html) == good


def test_a_run_waits_for_a_held_folder_with_a_word_and_gives_up_after_wait(res: Path) -> None:
    fd = os.open(res, os.O_RDONLY)  # this test process holds the folder's lock, as a stopped run would
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        before = {p: _sha(p) for p in res.rglob("*") if p.is_file()}
        t0 = time.monotonic()
        r = _run("reproduce", EXP, "--jobs", "1", "--out", res, "--force", "--wait", "2")
        assert time.monotonic() - t0 < 90
    finally:
        os.close(fd)
    assert r.returncode == 1, r.stderr
    _no_traceback(r)
    assert f"waiting for pid {os.getpid()}, which is writing into {res}" in r.stderr
    last = [ln for ln in r.stderr.splitlines() if ln.strip()][-1]
    assert last.startswith(f"error: --out {res}: another resal run (pid {os.getpid()}) has held this folder")
    assert "--wait SECONDS" in last
    assert {p: _sha(p) for p in res.rglob("*") if p.is_file()} == before


@pytest.mark.parametrize("target", ["missing", "loop"])
def test_an_out_link_that_leads_nowhere_is_named_as_such(tmp_path: Path, target: str) -> None:
    link = tmp_path / "out"
    if target == "missing":
        link.symlink_to(tmp_path / "nowhere")
    else:
        (tmp_path / "other").symlink_to(link)
        link.symlink_to(tmp_path / "other")
    for args in (("reproduce", EXP, "--out", link), ("fit", "rebound", ROOT / "examples" / "rebound.csv",
                                                     "--out", link), ("bench", "--quick", "--out", link)):
        r = _run(*args)
        assert r.returncode == 2, r.stderr
        lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
        assert len(lines) == 1 and "is a symbolic link" in lines[0], r.stderr
        assert ("does not exist" if target == "missing" else "loops back on itself") in lines[0]
