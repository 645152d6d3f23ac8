"""Single scenes for ``resal simulate``: each model declares its parameters (names in the paper's notation,
SI units, defaults, admissible ranges) and maps validated inputs to the physics."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from .config import parse_number
from .errors import InputError
from .mechanics import impact

__all__ = ["MODELS", "Model", "Param", "simulate"]


@dataclass(frozen=True)
class Param:
    name: str
    default: float
    doc: str
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False

    def check(self, value: float) -> str | None:
        if not math.isfinite(value):
            return "a finite number"
        if self.lo is not None and (value < self.lo or (self.lo_open and value == self.lo)):
            return self.range_text()
        if self.hi is not None and value > self.hi:
            return self.range_text()
        return None

    def range_text(self) -> str:
        if self.lo is not None and self.hi is not None:
            return f"a number in {'(' if self.lo_open else '['}{self.lo:g}, {self.hi:g}]"
        if self.lo is not None:
            return f"a number {'>' if self.lo_open else '≥'} {self.lo:g}"
        return "a number"


@dataclass(frozen=True)
class Model:
    name: str
    doc: str
    params: tuple[Param, ...]
    run: Callable[[dict[str, float]], tuple[str, dict[str, float]]]


def _direct(v: dict[str, float]) -> tuple[str, dict[str, float]]:
    r = impact.direct_impact(v["M"], v["Mp"], v["V0"], v["V0p"], v["eps"], v["epsp"])
    return r.method, {"V1": float(r.V1), "V1p": float(r.V1p), "newton_e": float(r.newton_e),
                      "kinetic_energy_lost": 0.5 * float(r.vis_viva_lost)}


def _wall(v: dict[str, float]) -> tuple[str, dict[str, float]]:
    V1 = float(impact.infinite_mass_impact(v["V0"], v["eps"]))
    return "closed form, §I eq. (9)", {"V1": V1, "ratio": float(impact.velocity_ratio_from_eps(v["eps"]))}


_EPS = dict(lo=0.0, hi=1.0)
MODELS: dict[str, Model] = {
    "direct-impact": Model("direct-impact", "direct impact of M on M′ (§I n°5, eq. 7)", (
        Param("M", 1.0, "mass of the striking body (kg)", lo=0.0, lo_open=True),
        Param("Mp", 1.0, "mass of the struck body (kg)", lo=0.0, lo_open=True),
        Param("V0", 1.0, "velocity of M before the impact (m/s)"),
        Param("V0p", 0.0, "velocity of M′ before the impact (m/s)"),
        Param("eps", 0.0, "Résal's ε of M", **_EPS),
        Param("epsp", 0.0, "Résal's ε′ of M′", **_EPS),
    ), _direct),
    "wall-impact": Model("wall-impact", "impact on an immovable mass: cushion, slab (§I n°5, eq. 9)", (
        Param("V0", 1.0, "normal velocity before the impact (m/s)"),
        Param("eps", 0.29, "Résal's ε of the ball", **_EPS),
    ), _wall),
}


def simulate(model: str, assignments: list[str]) -> dict[str, Any]:
    """Run one scene; ``assignments`` are ``name=value`` strings. Raises ``InputError`` on bad input."""
    if model not in MODELS:
        raise InputError(f"model '{model}'", f"unknown model (expected one of: {', '.join(MODELS)})")
    m = MODELS[model]
    values = {p.name: p.default for p in m.params}
    for a in assignments:
        name, sep, text = a.partition("=")
        name = name.strip()
        where = f"--set {a}"
        if not sep:
            raise InputError(where, "expected name=value")
        param = next((p for p in m.params if p.name == name), None)
        if param is None:
            raise InputError(where, f"unknown parameter '{name}' for {model} "
                                    f"(expected one of: {', '.join(p.name for p in m.params)})")
        parsed = parse_number(text)
        if parsed is None:
            raise InputError(where, f"'{name}' must be a number, got '{text}'")
        problem = param.check(parsed[0])
        if problem:
            raise InputError(where, f"'{name}' must be {problem}, got {text}")
        values[name] = parsed[0]
    method, outputs = m.run(values)
    return {"model": model, "method": method, "inputs": values, "outputs": outputs}
