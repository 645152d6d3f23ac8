"""``resal fit``: a user's own CSV in; the paper's coefficients with honest uncertainties out.

Each kind declares its columns (with their dimension, so a header may carry a unit: ``V0_mps``, ``h0_mm``), its
options, the example file in ``examples/`` and the function that fits. The functions are pure: a path and
``FitOptions`` in, a ``FitOutcome`` (a JSON-ready summary, figure descriptions, a residual table) out; the command
line writes and draws.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from ..errors import InputError
from .checks import finish
from .kinds import KINDS, Kind
from .kinds.ballball import fit_ballball
from .kinds.common import FitOptions, FitOutcome
from .kinds.pendulum import fit_pendulum
from .kinds.rebound import fit_rebounds
from .kinds.ricochet import fit_clicks, fit_ricochet

__all__ = ["FITTERS", "KINDS", "FitOptions", "FitOutcome", "Kind", "fit_csv"]


FITTERS: dict[str, Callable[[str, Path, FitOptions], FitOutcome]] = {
    "rebound": fit_rebounds, "cushion": fit_rebounds, "drop": fit_rebounds, "pendulum": fit_pendulum,
    "ricochet": fit_ricochet, "bounces": fit_clicks, "ball-ball": fit_ballball,
}


def fit_csv(kind: str, path: Path, opts: FitOptions) -> FitOutcome:
    """Fit the file at ``path`` with the estimator of ``kind``."""
    if kind not in KINDS:
        raise InputError(f"kind '{kind}'", f"expected one of {', '.join(KINDS)}")
    if path.is_dir():
        raise InputError(str(path), "is a folder: expected a CSV file")
    if not path.is_file():
        raise InputError(str(path), "no such file")
    outcome = FITTERS[kind](kind, path, opts)
    finish(outcome.summary)
    return outcome
