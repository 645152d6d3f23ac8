"""The functions the CLI calls: find experiments, run them, write them. No argument parsing, no rendering."""

from __future__ import annotations

import os
from pathlib import Path

from .config import Experiment, load_experiment
from .errors import InputError
from .experiments import KINDS
from .experiments.base import Reproduction

__all__ = ["config_dir", "experiment_ids", "list_experiments", "load", "run"]


def config_dir() -> Path:
    """``$RESAL_CONFIGS``, else the ``configs/`` folder of the source tree, else ``./configs``."""
    env = os.environ.get("RESAL_CONFIGS")
    if env:
        return Path(env)
    here = Path(__file__).resolve().parent.parent / "configs"
    return here if here.is_dir() else Path("configs")


def experiment_ids() -> list[str]:
    d = config_dir()
    return sorted(p.stem for p in d.glob("*.yaml")) if d.is_dir() else []


def load(name_or_path: str) -> Experiment:
    """An experiment by id (``configs/<id>.yaml``) or by the path of a YAML file."""
    p = Path(name_or_path)
    if p.suffix in (".yaml", ".yml") or p.is_file():
        if not p.is_file():
            raise InputError(name_or_path, "no such experiment file")
        return load_experiment(p)
    ids = experiment_ids()
    if name_or_path not in ids:
        raise InputError(f"experiment '{name_or_path}'",
                         f"unknown experiment id (expected one of: {', '.join(ids) or 'none found'}, "
                         "or the path of a YAML file)")
    return load_experiment(config_dir() / f"{name_or_path}.yaml")


def list_experiments() -> list[Experiment]:
    return [load(i) for i in experiment_ids()]


def run(exp: Experiment) -> Reproduction:
    """Run one experiment: physics, fits and comparisons, no I/O but reading its data files."""
    return KINDS[exp.kind].run(exp)
