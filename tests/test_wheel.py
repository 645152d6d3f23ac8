"""resal installs anywhere: the wheel carries the experiment files, and an installed resal run from another folder
finds them and reproduces what the checkout reproduces.

The wheel is built from a copy of the sources with this environment's setuptools (no build isolation, so no
network), installed with --no-deps into a fresh virtualenv whose dependencies are this environment's (a .pth line
naming its site-packages: no network either), and run from a temporary folder with no $RESAL_CONFIGS.

The example files of `resal fit` ship too: `resal examples` copies them out of the installed wheel and the first fit
a pip user runs works. And every example of every help page (the lines starting with `resal ` in an "Examples:"
block, for every command and fit kind, walked as tests/test_usage_one_line.py walks them) runs from the installed
wheel, in a fresh folder where `resal examples` ran, with the exit status it states (0 unless its comment says
"exit N"); a page with no Examples block fails test_every_help_page_has_examples. The module is marked `wheel`
(`-m "not wheel"` leaves it out).
"""

from __future__ import annotations

import json
import os
import re
import shlex
import shutil
import site
import subprocess
import sys
import sysconfig
import time
import zipfile
from concurrent.futures import ThreadPoolExecutor
from importlib import metadata
from pathlib import Path

import pytest
import typer.main
from typer.testing import CliRunner

from cli.main import app
from reproductions import api, golden, locate
from reproductions.report import summary

REPO = Path(__file__).resolve().parent.parent
CONFIG_IDS = sorted(p.stem for p in (REPO / "configs").glob("*.yaml"))
SOURCES = ("pyproject.toml", "README.md", "cli", "reproductions", "configs", "examples")  # what the build reads
EXAMPLE_FILES = sorted(p.name for p in (REPO / "examples").iterdir() if p.suffix == ".csv" or p.name == "README.md")

pytestmark = pytest.mark.wheel


def _version(name: str) -> tuple[int, ...]:
    return tuple(int(x) for x in metadata.version(name).split(".")[:2] if x.isdigit())


def _run(args: list[str | Path], cwd: Path, env: dict[str, str], timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run([str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """Build the wheel, make a fresh virtualenv, install the wheel there: the paths of each."""
    if _version("setuptools") < (77, 0):
        pytest.fail(f"setuptools {metadata.version('setuptools')} cannot build this wheel (pyproject.toml needs 77): "
                    "run make setup (requirements.lock pins the build backend)")
    tmp = tmp_path_factory.mktemp("wheel")
    src = tmp / "src"
    src.mkdir()
    for name in SOURCES:  # a copy, so that the build's build/ and *.egg-info stay out of the checkout
        p = REPO / name
        if p.is_dir():
            shutil.copytree(p, src / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        else:
            shutil.copy2(p, src / name)
    env = {k: v for k, v in os.environ.items() if k not in ("RESAL_CONFIGS", "PYTHONPATH", "PIP_REQUIRE_VIRTUALENV")}
    env |= {"PIP_NO_INDEX": "1", "PIP_DISABLE_PIP_VERSION_CHECK": "1", "COLUMNS": "200"}
    dist = tmp / "dist"
    r = _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", dist, src],
             tmp, env)
    assert r.returncode == 0, r.stdout + r.stderr
    wheels = list(dist.glob("resal-*.whl"))
    assert len(wheels) == 1, wheels
    venv = tmp / "venv"
    r = _run([sys.executable, "-m", "venv", "--without-pip", venv], tmp, env)
    assert r.returncode == 0, r.stderr
    py = venv / "bin" / "python"
    purelib = Path(_run([py, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], tmp, env)
                   .stdout.strip())
    r = _run([sys.executable, "-m", "pip", "--python", py, "install", "--no-deps", "-q", wheels[0]], tmp, env)
    assert r.returncode == 0, r.stdout + r.stderr
    # the dependencies: this environment's site-packages, after the fresh one's (a path line: its .pth files, such
    # as the editable install's import hook, are not run, so the checkout stays out of reach)
    ours = {sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"], *site.getsitepackages()}
    (purelib / "zz-resal-test-deps.pth").write_text("".join(f"{p}\n" for p in sorted(ours)), encoding="utf-8")
    work = tmp / "elsewhere"
    work.mkdir()
    return {"wheel": wheels[0], "venv": venv, "purelib": purelib, "work": work, "env": env}  # type: ignore[dict-item]


def test_wheel_ships_the_configs_and_every_module(installed: dict) -> None:
    """The experiment files (and their README), the data file and every module of the tree are in the wheel, at
    the place importlib.resources looks; nothing else of the repository is."""
    names = set(zipfile.ZipFile(installed["wheel"]).namelist())
    yamls = sorted((REPO / "configs").glob("*.yaml"))
    assert yamls
    missing = [f"reproductions/configs/{p.name}" for p in yamls if f"reproductions/configs/{p.name}" not in names]
    assert not missing, f"not in the wheel: {missing}"
    assert {"reproductions/configs/README.md", "reproductions/configs/__init__.py",
            "reproductions/data/modern-values.csv"} <= names
    assert len(EXAMPLE_FILES) >= 10 and "cushion.csv" in EXAMPLE_FILES  # one CSV per kind, and the README
    shipped = [f"reproductions/examples/{n}" for n in EXAMPLE_FILES]
    assert [n for n in shipped if n not in names] == [], "example files missing from the wheel"
    modules = sorted(p.relative_to(REPO).as_posix() for d in ("cli", "reproductions") for p in (REPO / d).rglob("*.py")
                     if "__pycache__" not in p.parts)
    absent = [m for m in modules if m not in names]
    assert not absent, f"modules missing from the wheel (add their package to pyproject.toml's packages): {absent}"
    tops = {n.split("/", 1)[0] for n in names}
    assert tops == {"cli", "reproductions", next(t for t in tops if t.endswith(".dist-info"))}, tops


def test_installed_resal_lists_and_reproduces_from_elsewhere(installed: dict) -> None:
    venv, work, env = installed["venv"], installed["work"], installed["env"]
    py, resal = venv / "bin" / "python", venv / "bin" / "resal"
    r = _run([py, "-c", "import cli, reproductions; from reproductions import api\n"
              "print(reproductions.__file__); print(cli.__file__); print(api.config_dir())"], work, env)
    assert r.returncode == 0, r.stderr
    where = [Path(line) for line in r.stdout.split()]
    assert all(p.is_relative_to(installed["purelib"]) for p in where), f"imported from the checkout? {where}"

    r = _run([resal, "list"], work, env)
    assert r.returncode == 0, r.stderr
    assert len(CONFIG_IDS) == 12
    assert [i for i in CONFIG_IDS if i not in r.stdout] == [], r.stdout

    out = installed["work"].parent / "out"
    r = _run([resal, "reproduce", "marble-drop", "--out", out], work, env, timeout=180)
    assert r.returncode == 0, r.stdout + r.stderr
    got = json.loads((out / "marble-drop" / "summary.json").read_text(encoding="utf-8"))
    prov = got.pop("provenance")
    assert Path(prov["config"]).is_relative_to(installed["purelib"])
    assert prov["git_commit"] is None  # a wheel has no commit to claim
    assert prov["dependencies"] == {n: metadata.version(n) for n in prov["dependencies"]}

    ours = json.loads(json.dumps(summary(api.run(api.load(str(REPO / "configs" / "marble-drop.yaml"))), prov={})))
    ours.pop("provenance")
    assert golden.compare(golden.golden_object(ours), got) == []
    assert got == ours  # same machine, same libraries: rows, verdicts and numbers identical

    # a measurement experiment reads its data file (configs/data/, shipped beside the configs)
    r = _run([resal, "reproduce", "modern-restitution", "--out", out], work, env, timeout=180)
    assert r.returncode == 0, r.stdout + r.stderr
    got = json.loads((out / "modern-restitution" / "summary.json").read_text(encoding="utf-8"))
    data = list(got["provenance"]["digest"]["data"])
    assert len(data) == 1 and Path(data[0]).is_relative_to(installed["purelib"]) and got["measurements"]


def test_installed_resal_with_no_experiments_says_so(installed: dict, tmp_path: Path) -> None:
    """An empty $RESAL_CONFIGS overrides the shipped files: one line naming the folder, exit 2, no empty table."""
    env = installed["env"] | {"RESAL_CONFIGS": str(tmp_path)}
    r = _run([installed["venv"] / "bin" / "resal", "list"], installed["work"], env)
    assert r.returncode == 2, r.stdout + r.stderr
    assert r.stdout == ""
    assert r.stderr.strip().count("\n") == 0 and str(tmp_path) in r.stderr and "no experiments" in r.stderr


def test_checkout_finds_the_repository_configs(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """The editable install (or a bare checkout) reads configs/ of the repository; $RESAL_CONFIGS overrides."""
    monkeypatch.delenv("RESAL_CONFIGS", raising=False)
    assert api.config_dir().resolve() == (REPO / "configs").resolve()
    assert api.experiment_ids() == CONFIG_IDS
    (tmp_path / "mine.yaml").write_text((REPO / "configs" / "marble-drop.yaml").read_text(encoding="utf-8"))
    monkeypatch.setenv("RESAL_CONFIGS", str(tmp_path))
    assert api.config_dir() == tmp_path and api.experiment_ids() == ["mine"]


def test_checkout_finds_the_repository_examples() -> None:
    """In a checkout the example files are read from examples/ (mapped by the editable install, or beside the
    package): the files that `resal examples` copies out are its CSVs and README."""
    assert locate.examples_dir().resolve() == (REPO / "examples").resolve()
    assert [p.name for p in locate.example_files()] == EXAMPLE_FILES


# ---- a pip user's first steps, and every help page's examples, from the installed wheel ------------------------
def _module_run(installed: dict, *args: str | Path, cwd: Path, timeout: float = 300) -> subprocess.CompletedProcess:
    """`python -m cli.main ARGS` with the virtualenv's python, in ``cwd``: the installed wheel, not the checkout."""
    return _run([installed["venv"] / "bin" / "python", "-m", "cli.main", *args], cwd, installed["env"], timeout)


def test_installed_resal_copies_the_examples_and_fits_one(installed: dict, tmp_path: Path) -> None:
    """`resal examples` then the fit its help names, from a fresh folder: the first fit of a pip user works; and
    the experiment files are found (reproduce marble-drop)."""
    r = _run([installed["venv"] / "bin" / "python", "-c", "import cli; print(cli.__file__)"], tmp_path,
             installed["env"])
    assert Path(r.stdout.strip()).resolve().is_relative_to(installed["purelib"].resolve()), r.stdout + r.stderr
    r = _module_run(installed, "examples", cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert sorted(p.name for p in (tmp_path / "resal-examples").iterdir()) == EXAMPLE_FILES
    assert all((tmp_path / "resal-examples" / n).read_bytes() == (REPO / "examples" / n).read_bytes()
               for n in EXAMPLE_FILES)
    assert "resal fit cushion resal-examples/cushion.csv" in r.stdout.splitlines()[2], r.stdout
    r = _module_run(installed, "fit", "cushion", "resal-examples/cushion.csv", "--no-plot", "--out", "fitout",
                    cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert (tmp_path / "fitout" / "fit.json").is_file()
    r = _module_run(installed, "reproduce", "marble-drop", "--out", "res", cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert (tmp_path / "res" / "marble-drop" / "summary.json").is_file()


def _pages() -> dict[str, tuple[str, ...]]:
    """Every help page's command path, by its name (`resal`, `resal fit`, `resal fit cushion` …)."""
    found: dict[str, tuple[str, ...]] = {}

    def walk(cmd: object, path: tuple[str, ...]) -> None:
        found[" ".join(("resal", *path))] = path
        for name, sub in sorted(getattr(cmd, "commands", {}).items()):
            walk(sub, (*path, name))

    walk(typer.main.get_command(app), ())
    return found


PAGES = _pages()
_HEADING = re.compile(r"^(\s*)Examples?:\s*$")


def help_examples(text: str) -> list[str] | None:
    """The commands of a help page's "Examples:" blocks (lines starting with `resal `; a line ending in a backslash
    continues on the next), None when the page has no such block. A block runs from its heading to the first line
    indented no deeper than the heading (the next section), blank lines included."""
    found: list[str] | None = None
    depth: int | None = None
    pending = ""
    for line in text.splitlines():
        m = _HEADING.match(line)
        if m:
            depth, found = len(m.group(1)), found or []
            continue
        if depth is None or not line.strip():
            continue
        if len(line) - len(line.lstrip()) <= depth:
            depth = None
            continue
        s = pending + line.strip()
        if pending or s.startswith("resal "):
            pending = s[:-1].rstrip() + " " if s.endswith("\\") else ""
            if not pending:
                found.append(s)  # type: ignore[union-attr]
    return found


def _help(path: tuple[str, ...]) -> str:
    r = CliRunner().invoke(app, [*path, "--help"], terminal_width=200)
    assert r.exit_code == 0, r.output
    return r.output


def test_help_examples_are_read() -> None:
    text = ("Usage: x\n\n  Does things.\n\n  Examples:\n    resal list\n    # a comment\n    resal reproduce a \\\n"
            "      --out b   # exit 1: why\n\n    resal diff a b\n\nOptions:\n  --help\n")
    assert help_examples(text) == ["resal list", "resal reproduce a --out b   # exit 1: why", "resal diff a b"]
    assert help_examples("Usage: x\n\n  Example: resal fit a b\n") is None


def _small(tokens: list[str], option: str, most: int) -> bool:
    return option in tokens[:-1] and tokens[tokens.index(option) + 1].isdigit() and \
        int(tokens[tokens.index(option) + 1]) <= most


# The examples not run here: each takes minutes (what they do is tested elsewhere, on small batches).
SKIPPED = {
    "reproduce --all": "every experiment, minutes (tests/conftest.py's reproduced_all runs it once per session)",
    "bench without --quick": "the full benchmark, minutes (bench --quick is run)",
    "stress without --scenes ≤ 10000, --ode-scenes ≤ 20 and --referee-scenes ≤ 20": "the default batches, minutes",
}


def _skipped(line: str) -> str | None:
    """Why the example ``line`` is not run (a key of SKIPPED), or None."""
    tokens = shlex.split(line, comments=True)
    cmd = tokens[1] if len(tokens) > 1 else ""
    if cmd == "reproduce" and "--all" in tokens:
        return "reproduce --all"
    if cmd == "bench" and "--quick" not in tokens:
        return "bench without --quick"
    if cmd == "stress" and not (_small(tokens, "--scenes", 10_000) and _small(tokens, "--ode-scenes", 20)
                                and _small(tokens, "--referee-scenes", 20)):
        return next(k for k in SKIPPED if k.startswith("stress"))
    return None


def _expected_exit(line: str) -> int:
    """The exit status an example states in its comment (`# exit 1: …`, `# exit status 2`), else 0."""
    m = re.search(r"#.*?\bexit(?: status)?\s+(\d+)", line)
    return int(m.group(1)) if m else 0


@pytest.fixture(scope="module")
def help_runs(installed: dict) -> dict[str, list[tuple[str, int | None, str, float]]]:
    """Every page's examples run from the installed wheel: per page, in a fresh folder of its own where
    `resal examples` ran first, its lines in order (an example may use what the one before wrote), with `resal`
    standing for `python -m cli.main` of the virtualenv; the pages two at a time. Per page: (line, exit status or
    None when skipped, output or the reason it was skipped, seconds)."""
    root = installed["work"].parent / "pages"
    bindir = root / "bin"
    bindir.mkdir(parents=True)
    (bindir / "resal").write_text(f'#!/bin/sh\nexec {shlex.quote(str(installed["venv"] / "bin" / "python"))} '
                                  '-m cli.main "$@"\n', encoding="utf-8")
    (bindir / "resal").chmod(0o755)
    env = installed["env"] | {"PATH": f"{bindir}{os.pathsep}{installed['env'].get('PATH', '')}"}

    def run_page(i: int, lines: list[str]) -> list[tuple[str, int | None, str, float]]:
        if not lines:
            return []
        cwd = root / f"page{i}"
        cwd.mkdir()
        r = _run(["resal", "examples"], cwd, env)
        assert r.returncode == 0, r.stdout + r.stderr
        done: list[tuple[str, int | None, str, float]] = []
        for line in lines:
            why = _skipped(line)
            if why:
                done.append((line, None, why, 0.0))
                continue
            t0 = time.perf_counter()
            r = _run(["bash", "-o", "pipefail", "-c", line], cwd, env, timeout=600)
            done.append((line, r.returncode, (r.stdout + r.stderr)[-3000:], time.perf_counter() - t0))
        return done

    todo = {name: help_examples(_help(path)) or [] for name, path in PAGES.items()}
    # a page whose lines are the first lines of a longer page reads that page's runs: the same commands in the same
    # order from the same fresh folder (`resal examples` run first) give the same exit statuses
    longer = {name: max((o for o in todo if len(todo[o]) > len(lines) and todo[o][:len(lines)] == lines),
                        key=lambda o: len(todo[o]), default=None) if lines else None for name, lines in todo.items()}
    with ThreadPoolExecutor(2) as pool:
        futures = {name: pool.submit(run_page, i, lines)
                   for i, (name, lines) in enumerate(todo.items()) if longer[name] is None}
        done = {name: f.result() for name, f in futures.items()}
    return {name: done[name] if longer[name] is None else done[longer[name]][:len(todo[name])] for name in todo}


@pytest.mark.parametrize("page", list(PAGES))
def test_every_help_page_has_examples(page: str) -> None:
    """A help page without an Examples block (lines `resal …` under "Examples:") is a defect."""
    assert help_examples(_help(PAGES[page])), f"`{page} --help` has no Examples block with a `resal …` line"


@pytest.mark.parametrize("page", list(PAGES))
def test_help_examples_run_from_the_installed_wheel(page: str, help_runs: dict) -> None:
    runs = help_runs[page]
    if not runs:
        pytest.skip(f"`{page} --help` has no examples to run (test_every_help_page_has_examples fails for it)")
    bad = [f"{line}\n  exit {code}, expected {_expected_exit(line)}:\n{out}" for line, code, out, _ in runs
           if code is not None and code != _expected_exit(line)]
    assert not bad, "\n".join(bad)
