"""The bad-input corpus (``tests/bad_inputs/cases.yaml``): every mistake gets one clear error.

Each case is run through the command line (typer's runner on ``cli.main.app``; with its ``env``, if it has one,
set) and must end with exit status
2, exactly one message on stderr that starts ``error: <where>:`` (the file:line, the file or the argument) and
says what was expected, nothing on stdout, no traceback, and a results folder left byte for byte as it was
(a private copy, per case, of one folder written by a successful ``resal reproduce coriolis-cushion``).

The inputs the corpus once held by mistake are accepted now, and tested as such below: a CSV with a UTF-8
byte-order mark, a comment line before the header of ``resal fit rebound``. So are the fits that end on a
parameter bound, which say so and keep their intervals inside the bounds.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import socket
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from cli_helpers import assert_bad, invoke, snapshot, squash

from reproductions.mechanics import impact

CORPUS = Path(__file__).resolve().parent / "bad_inputs"
MANIFEST = CORPUS / "cases.yaml"
MIN_CASES = 50


def _cases() -> list[dict[str, Any]]:
    return yaml.safe_load(MANIFEST.read_text(encoding="utf-8"))["cases"]


CASES = _cases()


@pytest.fixture(autouse=True)
def _default_configs(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("RESAL_CONFIGS", raising=False)


@pytest.fixture(scope="module")
def baseline(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A results folder written by one successful ``resal reproduce coriolis-cushion`` (shared by every case)."""
    out = tmp_path_factory.mktemp("corpus-baseline") / "res"
    result = invoke("reproduce", "coriolis-cushion", "--out", out)
    assert result.exit_code == 0, (result.output, repr(result.exception))
    assert (out / "coriolis-cushion" / "summary.json").is_file() and (out / "index.md").is_file()
    return out


def _fill(text: Any, out: Path) -> str:
    return str(text).replace("{case}", str(CORPUS)).replace("{out}", str(out))


# -- the manifest itself --------------------------------------------------------------------------------------
def test_corpus_has_enough_distinct_cases() -> None:
    ids = [c["id"] for c in CASES]
    assert len(ids) >= MIN_CASES, f"{len(ids)} cases, expected at least {MIN_CASES}"
    assert len(set(ids)) == len(ids), sorted({i for i in ids if ids.count(i) > 1})
    for c in CASES:
        assert set(c) - {"env"} == {"id", "what", "args", "where", "expect"}, c["id"]
        assert re.fullmatch(r"[a-z0-9][a-z0-9-]*", c["id"]), c["id"]
        assert c["what"].strip() and c["where"].strip() and c["expect"], c["id"]
    # distinct mistakes: no two cases run the same command line or expect the same message
    lines = [(*map(str, c["args"]), *sorted(c.get("env", {}).items())) for c in CASES]
    assert len(set(lines)) == len(lines)
    messages = [(c["where"], tuple(map(str, c["expect"]))) for c in CASES]
    assert len(set(messages)) == len(messages)
    # and every command of the CLI that takes input has its share
    commands = {str(c["args"][0]) for c in CASES}
    assert {"reproduce", "fit", "simulate", "diff", "bench"} <= commands


def _referenced(case: dict[str, Any]) -> set[Path]:
    """The corpus files a case uses: those on its command line, and the series files its YAML names."""
    out: set[Path] = set()
    for a in case["args"]:
        a = str(a)
        if a.startswith("{case}/"):
            p = CORPUS / a.removeprefix("{case}/")
            out.add(p)
            if p.suffix == ".yaml" and p.is_file():
                lines = p.read_bytes().decode("utf-8", errors="replace").splitlines()
                text = "\n".join(ln.split("#")[0] for ln in lines)  # not the files comments suggest
                out |= {p.parent / m for m in re.findall(r"\b(?:csv|series_csv):\s*([\w./-]+)", text)}
    return out


def test_every_file_in_the_corpus_is_used() -> None:
    used = set().union(*(_referenced(c) for c in CASES))
    files = {p for p in CORPUS.rglob("*") if p.is_file() and p != MANIFEST}
    assert files, "the corpus folder holds no input files"
    unused = sorted(str(p.relative_to(CORPUS)) for p in files - used)
    assert not unused, f"files no case uses: {unused}"


def test_the_files_the_cases_miss_on_purpose_are_missing() -> None:
    """A case about a missing file names it in its id or 'what'; every other referenced file exists."""
    for c in CASES:
        for p in _referenced(c):
            if not p.exists():
                assert "missing" in c["id"] or "not exist" in c["what"], (c["id"], p)


# -- every case: one clear error, nothing written --------------------------------------------------------------
@pytest.mark.parametrize("case", CASES, ids=[c["id"] for c in CASES])
def test_bad_input(case: dict[str, Any], baseline: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    out = tmp_path / "res"
    shutil.copytree(baseline, out)
    before = snapshot(out)
    for name, value in case.get("env", {}).items():  # an environment variable the mistake is in ($RESAL_CONFIGS)
        monkeypatch.setenv(name, _fill(value, out))
    assert "coriolis-cushion/summary.json" in before and "index.md" in before
    args = [_fill(a, out) for a in case["args"]]
    where = _fill(case["where"], out)
    err = assert_bad(invoke(*args), *(_fill(f, out) for f in case["expect"]))
    assert squash(err).startswith(squash(f"error: {where}:")), f"the message must start with {where!r}: {err!r}"
    assert snapshot(out) == before, "the results folder changed"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"], "something was written beside the results"


# -- inputs too big, or of a kind, to keep in the corpus folder: made per run ------------------------------------
# (reader, the command line before the file, what the message names). A file over the size limit is made sparse
# (``truncate``: no disk used), so the test shows it is refused by its size, never read; a FIFO with no writer
# would hang a reader that opened it blocking; a socket can be opened by no reader at all.
MADE = {"yaml": (("reproduce",), "an experiment file (YAML)", 1 << 20),
        "csv": (("fit", "rebound"), "a CSV file", 16 << 20),
        "json": (("diff", "{out}/coriolis-cushion/summary.json"), "a summary.json file", 16 << 20)}


def _made(kind: str, ext: str, folder: Path) -> tuple[Path, list[str]]:
    path = folder / f"made.{ext}"
    if kind == "oversize":
        with path.open("wb") as fh:
            fh.truncate(MADE[ext][2] + 1)
        return path, [f"is {MADE[ext][2] + 1:,} bytes", f"expected {MADE[ext][1]} of at most {MADE[ext][2]:,} bytes"]
    if kind == "fifo":
        os.mkfifo(path)
        return path, ["is a named pipe (FIFO)", f"expected {MADE[ext][1]}, a regular file"]
    with socket.socket(socket.AF_UNIX) as sock:
        sock.bind(str(path))
    return path, [f"expected {MADE[ext][1]}"]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs and sockets are POSIX")
@pytest.mark.parametrize("kind", ["oversize", "fifo", "socket"])
@pytest.mark.parametrize("ext", list(MADE))
def test_made_bad_input(kind: str, ext: str, baseline: Path, tmp_path: Path) -> None:
    out = tmp_path / "res"
    shutil.copytree(baseline, out)
    before = snapshot(out)
    made = tmp_path / "made"
    made.mkdir()
    path, expect = _made(kind, ext, made)
    args = [_fill(a, out) for a in MADE[ext][0]] + [str(path)]
    extra = ["--out", str(out)] if ext == "yaml" else (["--no-plot", "--out", str(out / "fit")] if ext == "csv" else [])
    err = assert_bad(invoke(*args, *extra), *expect)
    assert squash(err).startswith(squash(f"error: {path}:")), err
    assert snapshot(out) == before, "the results folder changed"


def test_the_corpus_covers_the_classes_of_issue_23() -> None:
    """Structure, numbers and text, for each reader: configs (reproduce), CSV (fit) and summaries (diff)."""
    ids = {c["id"] for c in CASES}
    for reader in ("yaml", "csv", "diff"):
        for what in ("nested", "line-20000", "1e30", "inf", "nan", "digits", "utf16-with-bom", "utf16-without-bom",
                     "nul-byte", "middle", "dev-zero", "alias-bomb", "subnormal"):
            if (reader, what) in {("csv", "nested"), ("csv", "alias-bomb"), ("diff", "alias-bomb"),
                                  ("diff", "line-20000"), ("diff", "1e30"), ("diff", "inf"), ("diff", "nan"),
                                  ("diff", "subnormal"), ("diff", "utf16-without-bom"), ("yaml", "1e30"),
                                  ("csv", "1e30")}:
                continue  # no such structure in the format, or a value JSON and YAML read as a number
            assert any(i.startswith(reader) and what in i for i in ids), (reader, what)


# -- once in the corpus, now accepted ----------------------------------------------------------------------------
def _fit_json(kind: str, path: Path, *args: object) -> dict[str, Any]:
    result = invoke("fit", kind, path, *args, "--json", "--no-plot", "--out", path.parent / "fit-out")
    assert result.exit_code == 0, (result.output, repr(result.exception))
    assert all(ln.startswith("WARNING [") for ln in result.stderr.splitlines()), result.stderr  # warnings only
    return json.loads(result.stdout)


def _eps(out: dict[str, Any]) -> dict[str, Any]:
    return next(f for f in out["fits"] if f["id"] == "eps")


REBOUNDS = "V0,V1\n1.0,-0.55\n2.0,-1.1\n3.0,-1.66\n"


@pytest.mark.parametrize("prefix", ["\ufeff", "# rebounds on the cushion, m/s\n\n", "\ufeff# a BOM, then a comment\n"],
                         ids=["bom", "comment-before-header", "bom-and-comment"])
def test_fit_rebound_reads_the_header_past_a_bom_and_comments(tmp_path: Path, prefix: str) -> None:
    plain, marked = tmp_path / "plain.csv", tmp_path / "marked.csv"
    plain.write_text(REBOUNDS, encoding="utf-8")
    marked.write_text(prefix + REBOUNDS, encoding="utf-8")
    a, b = _fit_json("rebound", plain), _fit_json("rebound", marked)
    assert a["fits"] == b["fits"] and b["n"] == 3
    assert _eps(b)["value"] == pytest.approx(impact.eps_from_velocity_ratio(0.5522), abs=2e-3)


def test_fit_rebound_heights_after_a_comment(tmp_path: Path) -> None:
    """The rebound kind used to sniff the header from the first line: a comment there made h0,h1 read as V0,V1."""
    f = tmp_path / "drops.csv"
    f.write_text("# drops on marble, m\nh0,h1\n1.0,0.66\n0.5,0.34\n0.8,0.53\n", encoding="utf-8")
    eps = _eps(_fit_json("rebound", f))
    assert eps["value"] == pytest.approx(impact.eps_from_velocity_ratio(np.sqrt(0.664)), abs=5e-3)


def test_config_csv_with_a_bom_is_accepted(tmp_path: Path) -> None:
    text = (Path(__file__).resolve().parent.parent / "configs" / "coriolis-cushion.yaml").read_text(encoding="utf-8")
    old = "    synthetic: {n: 24, low: 0.5, high: 7.0, noise: 0.03}"
    assert text.count(old) == 1
    cfg, csv = tmp_path / "bom-cushion.yaml", tmp_path / "data.csv"
    cfg.write_text(text.replace(old, "    csv: data.csv").replace("id: coriolis-cushion", "id: bom-cushion"),
                   encoding="utf-8")
    csv.write_bytes(b"\xef\xbb\xbf" + REBOUNDS.encode())
    result = invoke("reproduce", cfg, "--json", "--out", tmp_path / "out")
    assert result.exit_code == 0, (result.output, repr(result.exception))
    assert csv.name in json.loads(result.stdout)["data_note"]


def test_rebound_without_any_bounce_is_accepted(tmp_path: Path) -> None:
    """V1 = 0 (the ball stays: ε = 1, Carnot's impact) and h1 = 0 are measurements, not mistakes."""
    f = tmp_path / "dead.csv"
    f.write_text("h0,h1\n1.0,0\n0.5,0\n", encoding="utf-8")
    eps = _eps(_fit_json("rebound", f))
    assert eps["value"] == pytest.approx(1.0, abs=1e-6)
    assert eps["at_bound"] == "upper"  # and it says so


def test_printed_json_is_strict() -> None:
    """Every JSON resal prints parses under a reader that refuses NaN and Infinity."""
    def strict(text: str) -> Any:
        return json.loads(text, parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}"))

    for args in (("simulate", "--list", "--json"),
                 ("simulate", "direct-impact", "--set", "eps=0.1", "--set", "epsp=0.1", "--set", "V0=1e150", "--json")):
        result = invoke(*args)
        assert result.exit_code == 0, (result.output, repr(result.exception))
        strict(result.stdout)


# -- fits that end on a bound say so -------------------------------------------------------------------------
def test_rebound_fit_on_the_elastic_bound_says_so_and_keeps_its_interval_in_range(tmp_path: Path) -> None:
    f = tmp_path / "elastic.csv"
    f.write_text("V0,V1\n1.0,-1.0\n2.0,-2.0\n3.0,-3.0\n", encoding="utf-8")
    eps = _eps(_fit_json("rebound", f, "--sigma", "0.01"))
    assert eps["value"] == pytest.approx(0.0, abs=1e-9)
    assert eps["at_bound"] == "lower"
    assert eps["ci95"][0] == 0.0 and 0.0 < eps["ci95"][1] < 0.01
    assert "lower bound" in eps["note"] and "cut at the admissible range" in eps["note"]
    table = invoke("fit", "rebound", f, "--sigma", "0.01", "--no-plot", "--out", tmp_path / "fit-table")
    assert table.exit_code == 0
    # e = 1 is a value the data allow, and the interval is the profile likelihood's with the bound: the table says
    # it ended on the bound, and that is no warning; the warning is that trials exactly on the line make a χ² of 0,
    # which a σ of 0.01 does not give
    assert "bound" in table.stdout and "at-bound" not in table.stderr
    assert [ln.split("]")[0] for ln in table.stderr.splitlines()] == ["WARNING [sigma-exceeds-scatter"]


def test_rebound_fit_inside_the_bounds_has_no_warning(tmp_path: Path) -> None:
    f = tmp_path / "cushion.csv"
    f.write_text(REBOUNDS, encoding="utf-8")
    eps = _eps(_fit_json("rebound", f))
    assert eps["at_bound"] is None and "WARNING" not in eps["note"]
    assert 0.0 < eps["ci95"][0] < eps["value"] < eps["ci95"][1] < 1.0


def test_pendulum_fit_on_a_bound_says_so(tmp_path: Path) -> None:
    """Two mass ratios (so ε and ε′ are both determined), and struck speeds 1 % above what ε = ε′ = 0 allows:
    the fit ends on both lower bounds and cuts both intervals there."""
    M, Mp, V0 = np.array([0.6, 0.6, 0.2, 0.2]), np.array([0.2, 0.2, 0.6, 0.6]), np.array([1.0, 2.0, 1.0, 2.0])
    r = impact.direct_impact(M, Mp, V0, 0.0, eps=0.0, epsp=0.0)
    rows = "".join(f"{a},{b!r},{c!r},{m},{mp}\n" for a, b, c, m, mp in
                   zip(V0.tolist(), r.V1.tolist(), (1.01 * r.V1p).tolist(), M.tolist(), Mp.tolist(), strict=True))
    f = tmp_path / "trials.csv"
    f.write_text("V0,V1,V1p,M,Mp\n" + rows, encoding="utf-8")
    fits = {x["id"]: x for x in _fit_json("pendulum", f, "--sigma", "0.01", "--bootstrap", "0")["fits"]}
    for key in ("pendulum.eps", "pendulum.epsp"):
        x = fits[key]
        assert x["identifiable"] and x["at_bound"] == "lower", x
        assert x["ci95"][0] == 0.0 <= x["value"] <= x["ci95"][1], x
        assert "the fit ended on the lower bound" in x["note"]
