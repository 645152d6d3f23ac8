"""The comparison behind ``resal diff`` and the golden files: two sets of quantities in, their differences out.

Pure (no files, no printing) and below every other module (it imports none of the project): ``golden`` flattens
a summary into quantities (``golden.flatten``: key → (value, rtol, atol, tolerance class)) and judges a golden
file with ``agrees``; ``resal diff`` flattens both summaries and renders ``compare``'s ``SummaryDiff``.

Linear in the number of quantities: each side is one dict keyed by quantity, and each quantity of either side is
looked up in the other's (never searched for) and judged once; sorting the reference's keys (the order of a
golden file) adds a log factor. ``golden.read_summary`` bounds the quantities (``MAX_SUMMARY_QUANTITIES``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from functools import partial
from typing import Any, NamedTuple

__all__ = ["ABSENT", "Difference", "SummaryDiff", "agrees", "compare"]

Quantity = tuple[Any, float, float, str]  # (value, rtol, atol, tolerance class), as golden.flatten makes them


class _Absent:
    """The value of a quantity that one side does not have."""

    def __repr__(self) -> str:
        return "ABSENT"


ABSENT: Any = _Absent()
_NUMBERS = frozenset((int, float))  # exact types: a bool is no number here


class Difference(NamedTuple):
    """One quantity that differs: its key, each side's value (``ABSENT`` when that side lacks it) and the
    reference's tolerance ("rtol 1e-09, atol 1e-12, closed-form"; empty for a quantity the reference lacks)."""

    key: str
    ref: Any
    new: Any
    tolerance: str


@dataclass(frozen=True)
class SummaryDiff:
    """Two summaries compared: their experiment ids, how many quantities either has, and those that differ (the
    reference's in key order, then those only the other has, in its order)."""

    ref_experiment: str
    new_experiment: str
    compared: int
    differences: tuple[Difference, ...]

    @property
    def same_experiment(self) -> bool:
        return self.ref_experiment == self.new_experiment

    @property
    def differ(self) -> bool:
        """Some quantity differs, or the summaries are of different experiments."""
        return bool(self.differences) or not self.same_experiment


def compare(ref_experiment: str, ref: Mapping[str, Quantity], new_experiment: str, new: Mapping[str, Quantity],
            rtol: float | None = None) -> SummaryDiff:
    """Compare the quantities ``new`` with the reference ``ref`` (each as ``golden.flatten`` makes them), each
    within the reference's tolerance, or with the relative tolerance ``rtol`` for every quantity when given."""
    out = []
    isclose = math.isclose
    make = partial(tuple.__new__, Difference)  # Difference(…) without its Python __new__: a million a second
    labels: dict[tuple[float, float, str], str] = {}  # a tolerance's label, made once
    for key in sorted(ref):
        value, r, atol, why = ref[key]
        r = r if rtol is None else rtol
        other = new.get(key, ABSENT)
        if other is not ABSENT:
            other = other[0]
            if type(value) in _NUMBERS and type(other) in _NUMBERS and why != "direction":
                try:  # two numbers, nearly every quantity: agrees' test at once
                    if isclose(value, other, rel_tol=r, abs_tol=atol):
                        continue
                except OverflowError:  # an integer beyond float range
                    if agrees(value, other, r, atol, why):
                        continue
            elif agrees(value, other, r, atol, why):
                continue
        label = labels.get((r, atol, why))
        if label is None:
            label = labels[r, atol, why] = f"rtol {r:g}, atol {atol:g}, {why}"
        out.append(make((key, value, other, label)))
    only_new = [Difference(key, ABSENT, v[0], "") for key, v in new.items() if key not in ref]
    return SummaryDiff(ref_experiment, new_experiment, len(ref) + len(only_new), (*out, *only_new))


def agrees(a: Any, b: Any, rtol: float, atol: float, why: str | None) -> bool:
    """Whether two values of one quantity agree within its tolerance: as lines for a ``direction``, else number by
    number (``math.isclose``), and anything that is no number exactly."""
    return _same_lines(a, b, atol) if why == "direction" else _close(a, b, rtol, atol)


def _close(a: Any, b: Any, rtol: float, atol: float) -> bool:
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_close(x, y, rtol, atol) for x, y in zip(a, b, strict=True))
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, int | float) or not isinstance(b, int | float):
        return a == b
    try:
        return math.isclose(a, b, rel_tol=rtol, abs_tol=atol)
    except OverflowError:  # an integer beyond float range (JSON allows 4300 digits): the same test, exactly
        if not all(math.isfinite(x) for x in (a, b) if isinstance(x, float)):
            return a == b
        fa, fb = Fraction(a), Fraction(b)
        return abs(fa - fb) <= max(Fraction(rtol) * max(abs(fa), abs(fb)), Fraction(atol))


def _same_lines(a: Any, b: Any, atol: float) -> bool:
    """Lists of directions equal as lines: 1 − |cos θ| ≤ atol for each pair (a pair that is no pair of vectors of
    numbers within float range: exactly equal)."""
    if not isinstance(a, list) or not isinstance(b, list) or len(a) != len(b):
        return False
    for u, v in zip(a, b, strict=True):
        try:
            if len(u) != len(v):
                return False
            nu, nv = math.sqrt(sum(x * x for x in u)), math.sqrt(sum(y * y for y in v))
            if nu == 0 or nv == 0 or not 1 - abs(sum(x * y for x, y in zip(u, v, strict=True))) / (nu * nv) <= atol:
                return False  # (written so that a NaN, of components beyond √(float max), is no agreement)
        except (TypeError, OverflowError):
            if u != v:
                return False
    return True
