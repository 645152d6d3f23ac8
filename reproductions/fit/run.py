"""``resal fit``: a user's own CSV in; the paper's coefficients with honest uncertainties out.

Each kind declares its columns (with their dimension, so a header may carry a unit: ``V0_mps``, ``h0_mm``), its
options, the example file in ``examples/`` and the function that fits. The functions are pure: a ``series.Table``
(a CSV file's rows, or a program's arrays) and ``FitOptions`` in, a ``FitOutcome`` (a JSON-ready summary, figure
descriptions, a residual table) out; the command line writes and draws.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from ..errors import InputError
from ..series import Table, header_names, read_table
from .checks import check_g, finish
from .kinds import KINDS, Kind
from .kinds.ballball import fit_ballball
from .kinds.common import FitOptions, FitOutcome
from .kinds.markers import fit_angle_markers
from .kinds.pendulum import fit_pendulum
from .kinds.rebound import fit_rebounds
from .kinds.ricochet import fit_clicks, fit_ricochet

__all__ = ["FITTERS", "KINDS", "FitOptions", "FitOutcome", "Kind", "fit_csv"]


FITTERS: dict[str, Callable[[str, Path | Table, FitOptions], FitOutcome]] = {
    "rebound": fit_rebounds, "cushion": fit_rebounds, "drop": fit_rebounds, "pendulum": fit_pendulum,
    "ricochet": fit_ricochet, "bounces": fit_clicks, "ball-ball": fit_ballball, "markers": fit_angle_markers,
}


# each kind's headers: (required, optional) column sets, without units; a header that is exactly another kind's is
# named as such (a file given to the wrong kind), instead of a list of missing and unknown columns
_SPEED_SETS = ((frozenset({"V0", "V1"}), frozenset()), (frozenset({"u0", "u1"}), frozenset()))
_HEIGHT_SETS = ((frozenset({"h0", "h1"}), frozenset()),)
HEADERS: dict[str, tuple[tuple[frozenset[str], frozenset[str]], ...]] = {
    "rebound": _SPEED_SETS + _HEIGHT_SETS, "cushion": _SPEED_SETS, "drop": _HEIGHT_SETS + _SPEED_SETS,
    "pendulum": ((frozenset({"V0", "V1", "V1p"}), frozenset({"M", "Mp"})),
                 (frozenset({"h0", "h1", "h1p"}), frozenset({"M", "Mp"}))),
    "ricochet": ((frozenset({"x"}), frozenset({"t"})),),
    "bounces": ((frozenset({"t"}), frozenset()),),
    "ball-ball": ((frozenset({"v", "phi"}), frozenset({"cue_speed", "cue_dir", "obj_speed", "obj_dir", "shot"})),),
    "markers": ((frozenset({"series", "psi", "angle"}), frozenset({"figure"})),),
}
_KNOWN = frozenset().union(*(r | o for sets in HEADERS.values() for r, o in sets))


def _fits(kind: str, names: set[str]) -> bool:
    return any(req <= names <= req | opt for req, opt in HEADERS[kind])


def other_kinds(kind: str, src: Table) -> tuple[int, list[str]] | None:
    """(line, kinds) when the header is exactly that of other kinds and not one of ``kind``'s."""
    line, found = header_names(src, _KNOWN)
    if not found or not found <= _KNOWN or _fits(kind, found):
        return None
    others = [k for k in HEADERS if k != kind and _fits(k, found)]
    return (line, others) if others else None


def fit_csv(kind: str, source: Path | Table, opts: FitOptions) -> FitOutcome:
    """Fit the file at ``source`` (or the ``Table`` of a program's arrays) with the estimator of ``kind``: the file
    is read once, and every reader and check works on its table."""
    if kind not in KINDS:
        raise InputError(f"kind '{kind}'", f"expected one of {', '.join(KINDS)}")
    if isinstance(source, Table):
        src = source
    else:
        if not source.exists() and not source.is_symlink():
            raise InputError(str(source), "no such file")
        src = read_table(source)  # a folder, a FIFO, a device, a file too large or not UTF-8: refused here
    other = other_kinds(kind, src)
    if other is not None:
        them = " or ".join(f"`resal fit {k}`" for k in other[1])
        raise InputError(src.at(other[0]), f"this header is that of {them}, not of `resal fit {kind}`, which "
                                           f"expects {KINDS[kind].columns}")
    outcome = FITTERS[kind](kind, src, opts)
    if "g" in KINDS[kind].options and not (kind == "bounces" and opts.h0 is not None):  # with h0, g is fitted
        check_g(outcome.summary, opts.g)
    finish(outcome.summary)
    return outcome
