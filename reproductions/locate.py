"""Where the experiment files are: standard library only, so that a run which finds nothing to recompute
(``digest``) does not import the physics."""

from __future__ import annotations

import os
from importlib import resources
from pathlib import Path

__all__ = ["config_dir", "experiment_ids", "names_a_file"]


def config_dir() -> Path:
    """Where the experiment files are: ``$RESAL_CONFIGS`` when set; else the package ``reproductions.configs`` found
    by importlib.resources (the repository's ``configs/`` folder, which the wheel ships and the editable install maps,
    pyproject.toml); else, in a checkout that was never installed, the ``configs/`` folder beside this package."""
    env = os.environ.get("RESAL_CONFIGS")
    if env:
        return Path(env)
    try:
        shipped = resources.files("reproductions.configs")
    except ModuleNotFoundError:
        shipped = None
    if isinstance(shipped, Path) and shipped.is_dir():
        return shipped
    return Path(__file__).resolve().parent.parent / "configs"


def experiment_ids() -> list[str]:
    """The ids of the experiments in :func:`config_dir` (its ``*.yaml`` files), sorted; none when it is missing."""
    d = config_dir()
    return sorted(p.stem for p in d.glob("*.yaml")) if d.is_dir() else []


def names_a_file(name: str) -> bool:
    """Whether an experiment argument is the path of a file rather than an id: a YAML name, or anything there but a
    folder (a folder named like an id, results/marble-drop, is not taken for a file)."""
    p = Path(name)
    return p.suffix in (".yaml", ".yml") or (p.exists() and not p.is_dir())
