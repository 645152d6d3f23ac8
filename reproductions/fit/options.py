"""The options of a fit, checked once for every way of giving them: ``resal fit --k 0.4`` and ``api.fit(k=0.4)`` call
the same ``check``, and only the spelling of the option in the message differs (``spell``). Masses and radii may
carry a unit (``--M 170g``, ``--R 28.575mm``, ``M="6oz"``); without one they are SI."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Any

from ..errors import InputError
from ..mechanics.inertia import K_MIN, K_SOLID, K_WHY

__all__ = ["CHOICES", "K_MIN", "MAX_RADIUS", "NUMBERS", "UNITS", "check"]

MAX_RADIUS = 1.0  # m: a ball radius; one in millimetres (30.5) is refused, not read as 30.5 m
NUMBERS = {"sigma": "a standard deviation", "sigma_in": "a standard deviation", "g": "gravity in m/s²",
           "M": "a mass in kg", "Mp": "a mass in kg", "h0": "a height in m", "max_seconds": "a time in seconds",
           "sigma_speed": "a relative standard deviation", "sigma_dir": "a standard deviation of an angle",
           "R": "a ball radius in metres", "Rp": "a ball radius in metres", "k": f"MR²/I, {K_SOLID:g} for a solid ball",
           "kp": f"MR²/I, {K_SOLID:g} for a solid ball"}
# the options that may carry a unit (--M 170g, --R 28.575mm; without one: SI), each unit's factor to SI
_MASS = {"kg": 1.0, "g": 1e-3, "oz": 0.028349523125, "lb": 0.45359237}
_LENGTH = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "in": 0.0254}
UNITS = {"M": _MASS, "Mp": _MASS, "R": _LENGTH, "Rp": _LENGTH}
_WITH_UNIT = re.compile(r"\s*([^a-zA-Z\s]+?)\s*([a-zA-Z]+)\s*")
CHOICES = {"noise": ("auto", "constant", "proportional"), "speeds": ("signed", "unsigned")}


def check(name: str, value: Any, spell: Callable[[str], str]) -> Any:
    """``value`` of the option ``name`` (its Python name) as the fit takes it, or ``InputError``. ``spell(text)``
    writes the option as the user gave it, for the message: ``--k 0.4`` on the command line, ``k=0.4`` in Python;
    ``value`` may be the command line's text."""
    if name in CHOICES:
        if value not in CHOICES[name]:
            raise InputError(spell(str(value)), f"expected one of {', '.join(CHOICES[name])}")
        return value
    if name not in NUMBERS:
        raise AssertionError(f"no check for the option {name}")  # every option of a kind has one
    text = value if isinstance(value, str) else repr(value)
    factor = 1.0
    units = UNITS.get(name)
    written = _WITH_UNIT.fullmatch(value) if isinstance(value, str) and units else None
    if written is not None:
        if written[2] not in units:
            example = "170g" if units is _MASS else "28.575mm"
            raise InputError(spell(text), f"unknown unit '{written[2]}': expected {NUMBERS[name]} or a number with "
                                          f"one of the units {', '.join(units)} (as {example})")
        value, factor = written[1], units[written[2]]
    try:
        v = math.nan if isinstance(value, bool) else float(value) * factor
    except (TypeError, ValueError):
        v = math.nan
    with_unit = " (or with a unit: 28.575mm)" if units else ""
    if name in ("R", "Rp") and not (math.isfinite(v) and 0 < v <= MAX_RADIUS):
        raise InputError(spell(text), f"expected a ball radius in metres, in (0, {MAX_RADIUS:g}]{with_unit}")
    if not (math.isfinite(v) and v > 0):
        unit = " (or with a unit: 170g)" if units is _MASS else with_unit
        raise InputError(spell(text), f"expected a positive number ({NUMBERS[name]}, finite){unit}")
    if name in ("k", "kp") and v < K_MIN:
        inverse = (f": {text} reads as I/MR², the inverse convention ({spell(f'{1 / v:.3g}')}?)"
                   if 1 / v >= K_MIN else "")
        raise InputError(spell(text), f"expected MR²/I ≥ {K_MIN:g} ({K_WHY}){inverse}")
    return v
