"""resal installs anywhere: the wheel carries the experiment files, and an installed resal run from another folder
finds them and reproduces what the checkout reproduces.

The wheel is built from a copy of the sources with this environment's setuptools (no build isolation, so no
network), installed with --no-deps into a fresh virtualenv whose dependencies are this environment's (a .pth line
naming its site-packages: no network either), and run from a temporary folder with no $RESAL_CONFIGS.
"""

from __future__ import annotations

import json
import os
import shutil
import site
import subprocess
import sys
import sysconfig
import zipfile
from importlib import metadata
from pathlib import Path

import pytest

from reproductions import api, golden
from reproductions.report import summary

REPO = Path(__file__).resolve().parent.parent
CONFIG_IDS = sorted(p.stem for p in (REPO / "configs").glob("*.yaml"))
SOURCES = ("pyproject.toml", "README.md", "cli", "reproductions", "configs")  # what the build reads


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
