"""Where the experiment files are: standard library only, so that a run which finds nothing to recompute
(``digest``) does not import the physics."""

from __future__ import annotations

import os
from importlib import resources
from pathlib import Path

from .errors import InputError

__all__ = ["ENV", "config_dir", "example_files", "examples_dir", "experiment_ids", "names_a_file", "path_exists"]

ENV = "RESAL_CONFIGS"  # the environment variable naming a folder of experiment files, in place of the shipped ones


def config_dir() -> Path:
    """Where the experiment files are: ``$RESAL_CONFIGS`` when set; else the package ``reproductions.configs`` found
    by importlib.resources (the repository's ``configs/`` folder, which the wheel ships and the editable install maps,
    pyproject.toml); else, in a checkout that was never installed, the ``configs/`` folder beside this package.

    ``$RESAL_CONFIGS`` must name an existing folder; a relative path is taken from the current folder (and returned
    absolute, so that messages name the folder meant). A file, or a path where nothing is, raises ``InputError``
    naming the variable: it is never read as a folder with no experiments."""
    env = os.environ.get(ENV)
    if env:
        return _env_folder(env)
    return _package_folder("reproductions.configs", "configs")


def examples_dir() -> Path:
    """Where the example files of ``resal fit`` are (synthetic CSVs, one per kind): the package
    ``reproductions.examples`` found by importlib.resources (the repository's ``examples/`` folder, which the wheel
    ships and the editable install maps, pyproject.toml); else, in a checkout that was never installed (or whose
    editable install predates the mapping), the ``examples/`` folder beside this package."""
    return _package_folder("reproductions.examples", "examples")


def _package_folder(package: str, folder: str) -> Path:
    """The folder of the data package ``package`` found by importlib.resources, else the repository's ``folder``
    beside this package (a checkout never installed)."""
    try:
        shipped = resources.files(package)
    except ModuleNotFoundError:
        shipped = None
    if isinstance(shipped, Path) and shipped.is_dir():
        return shipped
    return Path(__file__).resolve().parent.parent / folder


def example_files() -> list[Path]:
    """The example files that ``resal examples`` copies out: the CSVs of :func:`examples_dir` and its README.md,
    sorted by name (not its Python files: ``__init__.py``, and ``generate.py``, which writes the CSVs in a
    checkout). None when the folder is missing."""
    d = examples_dir()
    if not d.is_dir():
        return []
    return sorted(p for p in d.iterdir() if p.is_file() and (p.suffix == ".csv" or p.name == "README.md"))


def _env_folder(env: str) -> Path:
    """The folder ``$RESAL_CONFIGS`` names (a relative path: from the current folder), or ``InputError`` saying
    what is wrong with it."""
    folder = Path(os.path.abspath(env))
    if folder.is_dir():
        return folder
    where = f"${ENV}={env}"
    meant = "" if Path(env).is_absolute() else f" (a relative path, taken from the current folder: {folder})"
    expected = "expected the folder of your experiment files (*.yaml), or leave it unset for the shipped ones"
    if folder.exists():
        raise InputError(where, f"is a file, not a folder{meant}: {expected}")
    raise InputError(where, f"no such folder{meant}: {expected}")


def experiment_ids() -> list[str]:
    """The ids of the experiments in :func:`config_dir` (its ``*.yaml`` files), sorted; none when the shipped folder
    is missing (a ``$RESAL_CONFIGS`` that is no folder raises ``InputError``)."""
    d = config_dir()
    return sorted(p.stem for p in d.glob("*.yaml")) if d.is_dir() else []


def names_a_file(name: str) -> bool:
    """Whether an experiment argument is the path of a file rather than an id: a YAML name, or anything there but a
    folder (a folder named like an id, results/marble-drop, is not taken for a file)."""
    p = Path(name)
    return p.suffix in (".yaml", ".yml") or (path_exists(p) and not p.is_dir())


def path_exists(p: Path) -> bool:
    """``p.exists()``, False for a name too long for a path (ENAMETOOLONG, which ``exists`` raises): such a name
    names no file (nor an id)."""
    try:
        return p.exists()
    except OSError:
        return False
