"""Solution paths as declared objects, and the result convention every model shares.

Each model of the paper offers several ways to compute a scene: a closed form, Résal's approximation as printed
(or corrected), an exact numerical solution, and a direct integration of the equations of motion (the ODE
reference, which shares no closed form with the others). A ``Path`` declares in code what it is (``Kind``),
where it is exact (a predicate over the scene), where it is defined at all, its stated accuracy and a cost rank;
``solve(model, scene, method="auto")`` picks, scene by scene, the cheapest path that declares itself exact there
(in the spirit of scipy's ``integrate._ivp`` ``METHODS``, plus the declarations pooltool leaves to docstrings).

Every result carries ``method`` (the code requested), ``path`` (per scene, a ``PathCode``), ``regime`` (per
scene, a ``Regime``, the same meaning in every model) and ``label`` (a sentence for people, never read by a
program). This module imports no model; ``registry`` assembles them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from enum import Enum, IntEnum
from typing import Any

import numpy as np

__all__ = ["ONES", "Kind", "Model", "Param", "Path", "PathCode", "PathError", "Regime", "always", "codes", "solve"]

Scene = Mapping[str, np.ndarray]


class Kind(str, Enum):
    """What a path is."""

    CLOSED_FORM = "closed-form"
    AS_PRINTED = "approximation-as-printed"
    CORRECTED = "corrected-approximation"
    EXACT_NUMERICAL = "exact-numerical"
    ODE = "ode-reference"


class PathCode(IntEnum):
    """Which path ran, one numbering for every model (``Result.path``)."""

    EXACT = 1  # the exact solution: a closed form, or an exact numerical solution
    ELEMENTARY = 2  # an elementary closed form, defined on a sub-domain only
    RESAL = 3  # Résal's approximation as printed
    RESAL_CORRECTED = 4  # Résal's approximation with a slip of the paper corrected
    ODE = 5  # direct integration of the equations of motion


class Regime(IntEnum):
    """The friction regime of a scene (``Result.regime``), the same meaning in every model."""

    FRICTIONLESS = 0  # a normal impact: the model has no tangential slip
    SLIDE = 1  # the contact slips throughout the phase computed (impact, stroke)
    GRIP = 2  # the slip stops during it; then the contact rolls or holds without slipping
    NO_SLIP = 3  # no slip to begin with


def codes(shape: tuple[int, ...], code: int) -> np.ndarray:
    """A per-scene array of one path or regime code."""
    return np.full(shape, int(code), dtype=np.int8)


class PathError(ValueError):
    """A path asked for where it is not defined, or an unknown path: the message says what the path handles."""


ONES = "ones"  # every scene dict carries ONES: True per scene, so that predicates know the batch shape


def always(scene: Scene) -> np.ndarray:
    return np.array(scene[ONES], dtype=bool)


@dataclass(frozen=True)
class Param:
    """A parameter of a model: SI unit, admissible range, default (None: it must be given; no printed value of
    the paper is ever a default). ``vector``: a 3-vector on the last axis. ``cli_degrees``: an angle stored
    in radians that the command line takes in degrees."""

    name: str
    unit: str
    doc: str
    default: float | None = None
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    cli_degrees: bool = False
    integer: bool = False

    def problem(self, value: float) -> str | None:
        """None if ``value`` is admissible, else what was expected."""
        if not np.isfinite(value):
            return "a finite number"
        if self.integer and value != int(value):
            return "a whole number"
        if self.lo is not None and (value < self.lo or (self.lo_open and value == self.lo)):
            return self.range_text()
        if self.hi is not None and (value > self.hi or (self.hi_open and value == self.hi)):
            return self.range_text()
        return None

    def range_text(self) -> str:
        lo, hi = self.lo, self.hi
        if lo is not None and hi is not None:
            return f"a number in {'(' if self.lo_open else '['}{lo:g}, {hi:g}{')' if self.hi_open else ']'}"
        if lo is not None:
            return f"a number {'>' if self.lo_open else '≥'} {lo:g}"
        if hi is not None:
            return f"a number {'<' if self.hi_open else '≤'} {hi:g}"
        return "a number"


@dataclass(frozen=True)
class Path:
    """One way to compute a model's scenes, and what it declares about itself."""

    code: PathCode
    kind: Kind
    run: Callable[[Scene], Any]
    exact_when: Callable[[Scene], np.ndarray]
    accuracy: float  # relative accuracy where exact (rounding for closed forms), in the model's error measure
    cost: int  # rank: 1 elementary arithmetic, 3 special functions or bisection, 1000 an ODE per scene
    doc: str
    handles: Callable[[Scene], np.ndarray] = always
    handles_text: str = "every scene"
    # ODE paths: the same integration at another tolerance and scipy solver (work-precision runs), and the
    # tolerance and solver that ``run`` uses
    tuned: Callable[[Scene, float, str], Any] | None = None
    rtol: float | None = None
    solver: str | None = None

    @property
    def name(self) -> str:
        return self.code.name.lower().replace("_", "-")


@dataclass(frozen=True)
class Model:
    """A situation of the paper: its parameters, its paths (cheapest first on a tie), the scenes it admits."""

    name: str
    section: str
    doc: str
    params: tuple[Param, ...]
    vectors: tuple[str, ...]  # parameters that are 3-vectors on the last axis
    paths: tuple[Path, ...]
    outputs: tuple[str, ...]  # result fields compared between paths ("p1*R": p1 times the scene's R)
    admissible: Callable[[Scene], np.ndarray]
    admissible_text: str
    static: tuple[str, ...] = ()  # parameters that must be one number for the whole batch (e.g. a count)
    sample: Callable[[np.random.Generator, int], dict[str, np.ndarray]] | None = None  # random admissible scenes
    scale: Callable[[Scene], np.ndarray] | None = None  # per-scene speed scale of the error measure
    vis_viva: Callable[[Scene, Any], tuple[np.ndarray, np.ndarray]] | None = None  # (before, after)
    mirror: Callable[[Scene], dict[str, np.ndarray]] | None = None  # the mirrored scene
    # the momenta the impulses conserve (linear, and angular about a contact where that holds): (before, after,
    # scale), components on the last axis, scale per scene (the sum of the magnitudes of the terms)
    momentum: Callable[[Scene, Any], tuple[np.ndarray, np.ndarray, np.ndarray]] | None = None
    # per compared output, its own natural scale (overrides ``scale`` and the output's factor), for outputs that
    # are not speeds (times, lengths)
    output_scale: Callable[[Scene], dict[str, np.ndarray]] | None = None
    mirrored: Callable[[Any], dict[str, np.ndarray]] | None = None  # a result's outputs, mirrored back

    def error(self, scene: Scene, a: Any, b: Any) -> np.ndarray:
        """Per scene, the largest difference of the compared outputs over the speed scale (angular velocities
        times the radius named with them in ``outputs``)."""
        assert self.scale is not None
        s = np.asarray(self.scale(scene), dtype=float)
        own = self.output_scale(scene) if self.output_scale is not None else {}
        worst = np.zeros(s.shape)
        for spec in self.outputs:
            name, _, factor = spec.partition("*")
            fa, fb = np.asarray(getattr(a, name), dtype=float), np.asarray(getattr(b, name), dtype=float)
            d = np.abs(fa - fb)
            if name in own:
                sc = np.asarray(own[name], dtype=float)
                d = d / np.where(sc > 0, sc, 1.0).reshape(s.shape + (1,) * (d.ndim - s.ndim))
            elif factor:
                d = d * np.asarray(scene[factor], dtype=float).reshape(s.shape + (1,) * (d.ndim - s.ndim))
            d = d.reshape(*s.shape, -1).max(axis=-1) if d.ndim > s.ndim else d
            worst = np.maximum(worst, d if name in own else d / s)
        return worst

    def path(self, name: str) -> Path:
        for p in self.paths:
            if p.name == name:
                return p
        raise PathError(f"{self.name} has no path '{name}' (expected auto or one of: "
                        f"{', '.join(p.name for p in self.paths)})")

    def scene(self, values: Mapping[str, Any]) -> dict[str, np.ndarray]:
        """Broadcast the given values (defaults for the others) into arrays with one batch shape."""
        missing = [p.name for p in self.params if p.name not in values and p.default is None]
        if missing:
            raise PathError(f"{self.name} needs {', '.join(missing)} (no default)")
        unknown = [k for k in values if k not in {p.name for p in self.params}]
        if unknown:
            raise PathError(f"{self.name} has no parameter {', '.join(unknown)}")
        raw = {p.name: np.asarray(values.get(p.name, p.default), dtype=float) for p in self.params}
        batch = np.broadcast_shapes(*(a.shape[:-1] if k in self.vectors else a.shape for k, a in raw.items()
                                      if k not in self.static))
        out = {ONES: np.ones(batch, dtype=bool)}
        for k, a in raw.items():
            if k in self.static:
                if a.size != 1:
                    raise PathError(f"{self.name}: '{k}' must be one number for the whole batch")
                out[k] = a.reshape(())
            else:
                out[k] = np.broadcast_to(a, (*batch, 3) if k in self.vectors else batch)
        return out


def _take(model: Model, scene: Scene, mask: np.ndarray) -> dict[str, np.ndarray]:
    return {k: (a if k in model.static else a[mask]) for k, a in scene.items()}


def solve(model: Model, scene: Scene, method: str = "auto") -> Any:
    """Compute a batch of scenes by the path ``method``, or for ``"auto"`` by the cheapest path that declares
    itself exact for each scene. Raises ``PathError`` for an unknown path, a path asked for outside the region it
    handles, or a scene the model does not admit."""
    ok = np.asarray(model.admissible(scene), dtype=bool)
    if not ok.all():
        raise PathError(f"{model.name}: {int((~ok).sum())} scene(s) outside the model: {model.admissible_text}")
    if method != "auto":
        p = model.path(method)
        handled = np.asarray(p.handles(scene), dtype=bool)
        if not handled.all():
            raise PathError(f"{model.name}: path '{p.name}' handles only {p.handles_text}; "
                            f"{int((~handled).sum())} scene(s) are outside it")
        return p.run(scene)
    batch = np.shape(scene[ONES])
    flat = {k: (a if k in model.static else a.reshape(-1, 3) if k in model.vectors else a.reshape(-1))
            for k, a in scene.items()}
    n = int(np.prod(batch, dtype=int))
    todo = np.ones(n, dtype=bool)
    parts: list[tuple[np.ndarray, Any]] = []
    for p in sorted(model.paths, key=lambda q: q.cost):  # stable: declared order breaks ties
        if not todo.any():
            break
        sel = todo & np.asarray(p.handles(flat), dtype=bool) & np.asarray(p.exact_when(flat), dtype=bool)
        if sel.any():
            parts.append((sel, p.run(_take(model, flat, sel))))
            todo &= ~sel
    if todo.any():  # cannot happen when some path is exact everywhere (every model has its ODE path)
        raise PathError(f"{model.name}: no path declares itself exact for {int(todo.sum())} scene(s)")
    if not parts:  # an empty batch: the cheapest path's result of no scene (its arrays of length 0)
        cheapest = min(model.paths, key=lambda q: q.cost)
        return _merge([(todo, cheapest.run(_take(model, flat, todo)))], n, batch)
    return _merge(parts, n, batch)


def _merge(parts: list[tuple[np.ndarray, Any]], n: int, batch: tuple[int, ...]) -> Any:
    """One result from the per-path results of disjoint subsets of the scenes (array fields scattered back)."""
    first = parts[0][1]
    values: dict[str, Any] = {}
    for f in dataclasses.fields(first):
        v0 = getattr(first, f.name)
        if isinstance(v0, np.ndarray) and v0.ndim >= 1:
            out = np.empty((n, *v0.shape[1:]), dtype=v0.dtype)
            for sel, res in parts:
                out[sel] = getattr(res, f.name)
            values[f.name] = out.reshape((*batch, *v0.shape[1:]))
        else:
            values[f.name] = v0
    values["method"] = "auto"
    values["label"] = "auto: " + "; ".join(f"{int(sel.sum())} by {res.label}" for sel, res in parts)
    return type(first)(**values)
