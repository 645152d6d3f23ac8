"""The options of a fit, checked once for every way of giving them: ``resal fit --k 0.4`` and ``api.fit(k=0.4)`` call
the same ``check``, and only the spelling of the option in the message differs (``spell``)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from ..errors import InputError
from ..mechanics.inertia import K_MIN, K_SOLID, K_WHY

__all__ = ["CHOICES", "K_MIN", "MAX_RADIUS", "NUMBERS", "check"]

MAX_RADIUS = 1.0  # m: a ball radius; one in millimetres (30.5) is refused, not read as 30.5 m
NUMBERS = {"sigma": "a standard deviation", "sigma_in": "a standard deviation", "g": "gravity in m/s²",
           "M": "a mass in kg", "Mp": "a mass in kg", "h0": "a height in m", "max_seconds": "a time in seconds",
           "sigma_speed": "a relative standard deviation", "sigma_dir": "a standard deviation of an angle",
           "R": "a ball radius in metres", "k": f"MR²/I, {K_SOLID:g} for a solid ball"}
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
    try:
        v = math.nan if isinstance(value, bool) else float(value)
    except (TypeError, ValueError):
        v = math.nan
    if name == "R" and not (math.isfinite(v) and 0 < v <= MAX_RADIUS):
        raise InputError(spell(text), f"expected a ball radius in metres, in (0, {MAX_RADIUS:g}]")
    if not (math.isfinite(v) and v > 0):
        raise InputError(spell(text), f"expected a positive number ({NUMBERS[name]}, finite)")
    if name == "k" and v < K_MIN:
        inverse = (f": {text} reads as I/MR², the inverse convention ({spell(f'{1 / v:.3g}')}?)"
                   if 1 / v >= K_MIN else "")
        raise InputError(spell(text), f"expected MR²/I ≥ {K_MIN:g} ({K_WHY}){inverse}")
    return v
