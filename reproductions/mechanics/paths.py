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
import functools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from enum import Enum, IntEnum
from typing import Any

import numpy as np

__all__ = ["ONES", "ImpactCheck", "Kind", "Model", "Param", "Path", "PathCode", "PathError", "Regime", "always",
           "as_floats", "auto_by_masks", "batch_arrays", "by_route", "codes", "every", "maximum", "minimum", "pick",
           "result", "solve"]

Scene = Mapping[str, np.ndarray]


class Kind(str, Enum):
    """What a path is."""

    CLOSED_FORM = "closed-form"
    AS_PRINTED = "approximation-as-printed"
    CORRECTED = "corrected-approximation"
    EXACT_NUMERICAL = "exact-numerical"
    ODE = "ode-reference"
    REFEREE = "referee"  # Newton–Euler integrated in the impulse, sharing no code with the other paths


class PathCode(IntEnum):
    """Which path ran, one numbering for every model (``Result.path``)."""

    EXACT = 1  # the exact solution: a closed form, or an exact numerical solution
    ELEMENTARY = 2  # an elementary closed form, defined on a sub-domain only
    RESAL = 3  # Résal's approximation as printed
    RESAL_CORRECTED = 4  # Résal's approximation with a slip of the paper corrected
    ODE = 5  # direct integration of the equations of motion
    REFERENCE = 6  # the referee: every velocity component integrated, the model's law evaluated literally


class Regime(IntEnum):
    """The friction regime of a scene (``Result.regime``), the same meaning in every model."""

    FRICTIONLESS = 0  # a normal impact: the model has no tangential slip
    SLIDE = 1  # the contact slips throughout the phase computed (impact, stroke)
    GRIP = 2  # the slip stops during it; then the contact rolls or holds without slipping
    NO_SLIP = 3  # no slip to begin with


_INT8 = {c: np.int8(c) for c in range(8)}  # the codes as numpy's int8, for ``codes`` of one scene


def codes(shape: tuple[int, ...], code: int) -> np.ndarray:
    """A per-scene array of one path or regime code (one scene, shape (): the same array, a new one, without
    ``np.full``'s fixed cost)."""
    if shape == ():
        try:
            one = _INT8.get(code)
        except TypeError:  # (an unhashable code: an array of one number)
            one = None
        if one is not None:
            return np.asarray(one)
    return np.full(shape, int(code), dtype=np.int8)


def result(kind: type[Any], **fields: Any) -> Any:
    """``kind(**fields)`` for a frozen result dataclass given every field by name, in its order: the object its
    ``__init__`` makes (the same ``__dict__``), without the cost of setting each field through the frozen
    ``object.__setattr__`` (a tenth of the time of a closed form on one scene). Tests check the fields."""
    out = object.__new__(kind)
    out.__dict__.update(fields)
    return out


def every(mask: np.ndarray) -> bool:
    """``mask.all()`` for a boolean array, without the reduction's fixed cost for a single scene."""
    return bool(mask.item()) if mask.size == 1 else bool(mask.all())


def _some(mask: np.ndarray) -> bool:
    """``mask.any()``, as ``every``."""
    return bool(mask.item()) if mask.size == 1 else bool(mask.any())


_F64, _BOOL, _NDARRAY = np.float64, np.bool_, np.ndarray
_F64_DTYPE = np.dtype(np.float64)


def batch_arrays(*xs: Any) -> list[Any]:
    """The arguments as float arrays of one broadcast shape (``np.broadcast_arrays``). Float arrays that already
    share one shape, as ``Model.scene`` gives them, pass as they are, without its fixed cost; so do numpy floats
    (``np.float64``) when every argument is one: one scene, as the single-scene route of ``solve`` gives it
    (numpy's operations on them are the ones its arrays use, at a fifth of the cost)."""
    first = xs[0]
    cls = first.__class__
    if cls is _F64:
        for x in xs:  # (a loop: cheaper than ``all`` over a generator, on the single-scene route)
            if x.__class__ is not _F64:
                break
        else:
            return list(xs)
    elif cls is np.ndarray and first.dtype == np.float64:
        shape = first.shape
        if all(x.__class__ is np.ndarray and x.dtype == np.float64 and x.shape == shape for x in xs):
            return list(xs)
    return np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in xs))


def as_floats(*xs: Any) -> list[Any]:
    """``np.asarray(x, dtype=float)`` of each argument (no broadcasting), numpy floats passing as they are (see
    ``batch_arrays``)."""
    for x in xs:
        if x.__class__ is not _F64 and not (x.__class__ is _NDARRAY and x.dtype is _F64_DTYPE):
            return [x if x.__class__ is _F64 else np.asarray(x, dtype=float) for x in xs]
    return list(xs)  # (float arrays too: ``np.asarray`` would give each itself)


def pick(cond: Any, a: Any, b: Any) -> Any:
    """``np.where(cond, a, b)``; for one scene as numpy scalars, the chosen value itself (the same number)."""
    if cond.__class__ is _BOOL and a.__class__ is not _NDARRAY and b.__class__ is not _NDARRAY:
        return a if cond else b
    return np.where(cond, a, b)


def maximum(a: Any, b: Any) -> Any:
    """``np.maximum(a, b)``; for two numpy floats, numpy's own choice without the ufunc's fixed cost: ``a`` where
    a > b or ``a`` is nan, else ``b`` (so ``b`` on a tie of ±0, and nan from either side, as its loop gives it)."""
    if a.__class__ is _F64 and b.__class__ is _F64:
        return a if (a > b or a != a) else b
    return np.maximum(a, b)


def minimum(a: Any, b: Any) -> Any:
    """``np.minimum(a, b)``, as ``maximum``: ``a`` where a < b or ``a`` is nan, else ``b``."""
    if a.__class__ is _F64 and b.__class__ is _F64:
        return a if (a < b or a != a) else b
    return np.minimum(a, b)


class PathError(ValueError):
    """A path asked for where it is not defined, or an unknown path: the message says what the path handles."""


ONES = "ones"  # every scene dict carries ONES: True per scene, so that predicates know the batch shape


def always(scene: Scene) -> np.ndarray:
    return np.array(scene[ONES], dtype=bool)


@dataclass(frozen=True)
class Param:
    """A parameter of a model: SI unit, admissible range, default (None: it must be given; no printed value of
    the paper is ever a default). ``vector``: a 3-vector on the last axis. ``cli_degrees``: an angle stored
    in radians that the command line takes in degrees. ``why``: the physical reason for the range, which a value
    outside it is told (k ≥ 1.5: ``inertia.K_WHY``)."""

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
    why: str = ""

    def problem(self, value: float) -> str | None:
        """None if ``value`` is admissible, else what was expected (with ``why`` for a value out of range)."""
        if not np.isfinite(value):
            return "a finite number"
        if self.integer and value != int(value):
            return "a whole number"
        below = self.lo is not None and (value < self.lo or (self.lo_open and value == self.lo))
        if below or (self.hi is not None and (value > self.hi or (self.hi_open and value == self.hi))):
            return self.range_text() + (f" ({self.why})" if self.why else "")
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
    # ``run`` and the predicates also take one scene as numpy floats (``np.float64``, vectors as arrays) and give
    # numpy scalars: ``solve`` then runs a single scene so (``_run_one``), with the numbers of the array route.
    # Such code converts with ``batch_arrays``/``as_floats``, chooses with ``pick`` (``maximum``, ``minimum``),
    # assembles its result with ``result`` and writes x * x, never x**2: numpy's scalar power calls the C library's
    # pow, its arrays square or their own pow (tests/test_small_batch.py)
    scalar: bool = False
    # ODE paths: the same integration at another tolerance and scipy solver (work-precision runs), and the
    # tolerance and solver that ``run`` uses
    tuned: Callable[[Scene, float, str], Any] | None = None
    rtol: float | None = None
    solver: str | None = None

    @property
    def name(self) -> str:
        return self.code.name.lower().replace("_", "-")


@dataclass(frozen=True)
class ImpactCheck:
    """What an impact model's declared law says of a returned state, per scene (first principles, not the path's
    own algebra): the normal approach speed at the contact before (> 0) and after (> 0: still approaching); the
    normal ratio the law implies (nan where it implies none); where the impact must end at the greatest
    compression (ε = ε′ = 1, §I n°2); the declared law's residual on the state, relative to its own scale."""

    approach0: np.ndarray
    approach1: np.ndarray
    ratio: np.ndarray
    plastic: np.ndarray
    law: np.ndarray


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
    # impact models: what the declared law implies on a returned state (``ImpactCheck``), and the frictionless
    # elastic version of given scenes with its textbook outputs (``resal stress``'s invariants)
    impact: Callable[[Scene, Any], ImpactCheck] | None = None
    elastic: Callable[[Scene], tuple[dict[str, np.ndarray], dict[str, np.ndarray]]] | None = None

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

    @functools.cached_property
    def _plan(self) -> _Plan:
        """What ``scene`` and ``solve`` read on every call, computed once per model."""
        return _Plan(self)

    def scene(self, values: Mapping[str, Any]) -> dict[str, np.ndarray]:
        """Broadcast the given values (defaults for the others) into arrays with one batch shape."""
        plan = self._plan
        if not values.keys() >= plan.required:
            missing = [p.name for p in self.params if p.name not in values and p.default is None]
            raise PathError(f"{self.name} needs {', '.join(missing)} (no default)")
        if not values.keys() <= plan.names:
            unknown = [k for k in values if k not in plan.names]
            raise PathError(f"{self.name} has no parameter {', '.join(unknown)}")
        raw = {k: (np.asarray(values[k], dtype=float) if k in values else d) for k, d in plan.defaults.items()}
        if plan.plain:  # numbers only, every default of shape (): one scene if every value given is a number
            for k in values:
                if raw[k].shape != ():
                    break
            else:  # the loop below would keep every array as it is
                out = {ONES: plan.ones}
                out.update(raw)
                for k, v in values.items():
                    if raw[k] is v:  # the caller's own array: a read-only view of it, as below
                        a = v.view()
                        a.flags.writeable = False
                        out[k] = a
                return out
        elif not plan.static:  # vectors: one scene if every value is a number, or 3 numbers for a vector
            out = {ONES: plan.ones}
            vectors = plan.vectors
            for k, a in raw.items():  # as the loop below makes them for a batch of shape ()
                shape = a.shape
                if k in vectors and shape != (3,):
                    if shape != ():
                        break
                    a = plan.vector_defaults[k] if k not in values else np.broadcast_to(a, (3,))  # read-only
                elif k not in vectors and shape != ():
                    break
                elif a is values.get(k):  # the caller's own array: a read-only view of it
                    a = a.view()
                    a.flags.writeable = False
                out[k] = a
            else:
                return out
        shapes = {a.shape[:-1] if k in self.vectors else a.shape for k, a in raw.items() if k not in self.static}
        batch = shapes.pop() if len(shapes) == 1 else np.broadcast_shapes(*shapes)
        out = {ONES: plan.ones if batch == () else np.ones(batch, dtype=bool)}
        for k, a in raw.items():
            if k in self.static:
                if a.size != 1:
                    raise PathError(f"{self.name}: '{k}' must be one number for the whole batch")
                out[k] = a.reshape(())
            else:
                shape = (*batch, 3) if k in self.vectors else batch
                if a.shape != shape:
                    if batch == () and k not in values:  # a default vector of one scene: one shared view
                        a = plan.vector_defaults[k]
                    else:
                        a = np.broadcast_to(a, shape)  # a read-only view
                elif a is values.get(k):  # the caller's own array: a read-only view of it, as broadcast_to gives
                    a = a.view()
                    a.flags.writeable = False
                out[k] = a
        return out


class _Plan:
    """A model's parameter names, defaults as arrays and paths in the order ``solve`` tries them (read-only)."""

    def __init__(self, model: Model) -> None:
        self.names = frozenset(p.name for p in model.params)
        self.static, self.vectors = frozenset(model.static), frozenset(model.vectors)
        self.required = frozenset(p.name for p in model.params if p.default is None)
        self.defaults: dict[str, np.ndarray | None] = {}
        for p in model.params:
            d = None if p.default is None else np.asarray(p.default, dtype=float)
            if d is not None:
                d.flags.writeable = False  # shared by every scene that takes the default
            self.defaults[p.name] = d
        self.vector_defaults = {k: np.broadcast_to(d, (3,)) for k, d in self.defaults.items()
                                if k in self.vectors and d is not None}
        self.ones = np.ones((), dtype=bool)
        self.ones.flags.writeable = False
        self.order = tuple(sorted(model.paths, key=lambda q: q.cost))  # stable: declared order breaks ties
        # no static or vector parameter, and every default one number (shape ()): ``Model.scene``'s short route
        self.plain = not self.static and not self.vectors and all(d is None or d.shape == ()
                                                                  for d in self.defaults.values())


def _take(model: Model, scene: Scene, mask: np.ndarray) -> dict[str, np.ndarray]:
    idx = np.flatnonzero(mask)  # once: indexing by it is cheaper than by the mask, array after array
    return {k: (a if k in model.static else a.take(idx, axis=0)) for k, a in scene.items()}


def solve(model: Model, scene: Scene, method: str = "auto") -> Any:
    """Compute a batch of scenes by the path ``method``, or for ``"auto"`` by the cheapest path that declares
    itself exact for each scene. Raises ``PathError`` for an unknown path, a path asked for outside the region it
    handles, or a scene the model does not admit.

    ``auto`` has two routes to the same numbers (tests/test_small_batch.py requires them equal bit for bit). The
    small-batch route: where the cheapest path handles every scene and declares itself exact for each (every
    scene of a closed-form model, a single scene whatever its path), that path runs once, on the flattened batch
    (``_auto_single``), or for a single scene on its numpy floats where the path declares ``scalar``
    (``_run_one``: the same function, numpy's scalar arithmetic instead of its array loops); no masks, no merge.
    The general route (``auto_by_masks``): each path in turn, cheapest first, takes the scenes left to it (a single
    scene, by the first path that takes it, again without masks or merge, on its numpy floats where that path
    declares ``scalar``)."""
    one = None
    if method == "auto":
        first = model._plan.order[0]
        ones = scene[ONES]
        batch = ones.shape if ones.__class__ is np.ndarray else np.shape(ones)
        if first.scalar and batch in ((), (1,)):  # one scene, and a path that takes it as numpy floats
            one = _one(model, scene)
    ok = model.admissible(scene if one is None else one)
    if not (ok.__class__ is np.bool_ and ok):  # (one scene admitted: a numpy bool, True)
        ok = np.asarray(ok, dtype=bool)
        if not every(ok):
            raise PathError(f"{model.name}: {int((~ok).sum())} scene(s) outside the model: {model.admissible_text}")
    if method != "auto":
        p = model.path(method)
        if p.handles is not always:
            handled = np.asarray(p.handles(scene), dtype=bool)
            if not every(handled):
                raise PathError(f"{model.name}: path '{p.name}' handles only {p.handles_text}; "
                                f"{int((~handled).sum())} scene(s) are outside it")
        return p.run(scene)
    if one is not None:
        if first.handles is always and first.exact_when is always:  # (``_selection`` gives None)
            return _run_one(first, one, batch)
        sel = _selection_one(first, one)
        if sel is None or (sel if sel.__class__ is _BOOL else every(sel)):
            return _run_one(first, one, batch)
        later = _later_one(model, one, batch)
        if later is not None:
            return later
    batch, n, flat = _flatten(model, scene)
    if n >= ROOMY_FROM and not _heap[0]:
        _roomy_heap()
    sel = np.zeros(n, dtype=bool) if one is not None else _selection(first, flat) if n else None
    if n and (sel is None or every(sel)):
        return _auto_single(first, flat, n, batch)
    return _auto_general(model, flat, n, batch, sel, whole=n == 1)


ROOMY_FROM = 1 << 14  # scenes: from this batch size on, ``solve`` first makes the heap roomy (``_roomy_heap``)
ROOMY_BYTES = 30 << 20  # below glibc's cap on its dynamic mmap threshold (32 MiB on 64 bits), chunk header included
_heap = [False]  # whether ``_roomy_heap`` has run in this process


def _roomy_heap() -> None:
    """Once per process, before the first large batch: a block of ``ROOMY_BYTES`` allocated and freed (never
    written: no page of it is touched). glibc's malloc maps each block above its mmap threshold (128 KiB at
    start) afresh and unmaps it when freed, and trims the heap's top beyond twice that threshold, so a batch's
    arrays (0.8 MB each for 1e5 scenes) were page-faulted anew at each operation: about 3 µs per 4 KiB page, 40 %
    of a batch of 1e5 scenes of spheres-cloth. The free of a mapped block raises the threshold to its size
    (mallopt(3), M_MMAP_THRESHOLD), so after this one such arrays are recycled within the heap. The numbers
    computed are the same; the process keeps up to twice that size of freed memory instead of returning it. With
    another allocator: a block allocated and freed, nothing else."""
    _heap[0] = True
    try:
        block = np.empty(ROOMY_BYTES, dtype=np.uint8)
    except MemoryError:  # (an address-space limit tighter than that: the heap stays as it is)
        return
    del block


def _one(model: Model, scene: Scene) -> dict[str, Any]:
    """A scene of one, its numbers as numpy floats (vectors as arrays of 3, static parameters as given)."""
    plan = model._plan
    static, vectors = plan.static, plan.vectors
    if not static:  # (a vector of one scene of shape (): the array itself, as ``reshape`` would view it)
        if not vectors:
            return {k: (a[()] if a.ndim == 0 else a[0]) for k, a in scene.items()}
        return {k: (a[()] if a.ndim == 0 else (a if a.ndim == 1 else a.reshape(3)) if k in vectors else a[0])
                for k, a in scene.items()}
    return {k: (a if k in static else a.reshape(3) if k in vectors else a[()] if a.ndim == 0 else a[0])
            for k, a in scene.items()}


def _later_one(model: Model, one: dict[str, Any], batch: tuple[int, ...]) -> Any:
    """The general route's single scene that the cheapest path does not take, without batch arrays or masks: the
    later paths in ``_auto_general``'s order, each declaring ``scalar``, their predicates on the scene's numpy
    floats; the first that handles it and declares itself exact runs on them (``_run_one``), as ``_auto_general``
    runs a path that takes the whole batch of one. None where a path that does not declare ``scalar`` comes first
    (or none takes the scene): the batch route decides then."""
    for p in model._plan.order[1:]:
        if not p.scalar:
            return None
        sel = _selection_one(p, one)
        if sel is None or every(sel):
            return _run_one(p, one, batch)
    return None


def _run_one(p: Path, one: dict[str, Any], batch: tuple[int, ...]) -> Any:
    """The result of ``auto`` where ``p`` serves a scene of one (``batch`` () or (1,)), run on its numpy floats:
    its outputs as arrays of the batch shape, as the array route gives them."""
    res = p.run(one)
    values = res.__dict__.copy()
    if batch:
        for name, v in values.items():
            cls = v.__class__
            if cls is np.ndarray or (cls is not str and isinstance(v, (np.ndarray, np.generic))):
                v = v if cls is np.ndarray else np.asarray(v)
                values[name] = v.reshape((*batch, *v.shape))  # (a vector per scene: its own axis last)
    else:
        f64, ndarray, asarray, generic = _F64, np.ndarray, np.asarray, np.generic
        for name, v in values.items():
            cls = v.__class__
            if cls is ndarray or cls is str:
                continue
            if cls is f64 or isinstance(v, generic):
                values[name] = asarray(v)
    values["method"] = "auto"
    values["label"] = f"auto: 1 by {res.label}"
    out = object.__new__(type(res))  # a frozen dataclass: its fields set as its own __init__ sets them
    out.__dict__.update(values)
    return out


def by_route(model: Model, scene: Scene, method: str, route: str) -> Any:
    """The path ``method`` (not auto) on an admissible scene it handles, as one route of ``solve(…, "auto")``
    would run it: ``"general"`` on the selected scenes taken out of the flattened batch and merged back, or
    ``"small"`` as the single-path route does (a scene of one as numpy floats where the path declares
    ``scalar``, else the whole flattened batch). For the tests, which require the two to agree bit for bit."""
    p = model.path(method)
    batch, n, flat = _flatten(model, scene)
    if route == "general":
        every_scene = np.ones(n, dtype=bool)
        return _merge([(every_scene, p.run(_take(model, flat, every_scene)))], n, batch)
    if route != "small":
        raise ValueError(f"route must be 'small' or 'general', got {route!r}")
    if p.scalar and n == 1:
        return _run_one(p, _one(model, scene), batch)
    return _auto_single(p, flat, n, batch)


def _flatten(model: Model, scene: Scene) -> tuple[tuple[int, ...], int, dict[str, np.ndarray]]:
    """The batch shape, the number of scenes and the scene with one batch axis (static parameters as given)."""
    batch = np.shape(scene[ONES])
    n = math.prod(batch)
    static, vectors = model._plan.static, model._plan.vectors
    flat = {k: (a if k in static else a.reshape(n, 3) if k in vectors else a.reshape(n)) for k, a in scene.items()}
    return batch, n, flat


def _selection(p: Path, flat: Scene) -> np.ndarray | None:
    """Where ``p`` handles the scene and declares itself exact (``None``: everywhere, declared ``always``)."""
    sel = None if p.handles is always else np.asarray(p.handles(flat), dtype=bool)
    if p.exact_when is not always and p.exact_when is not p.handles:
        exact = np.asarray(p.exact_when(flat), dtype=bool)
        sel = exact if sel is None else sel & exact
    return sel


def _selection_one(p: Path, one: Scene) -> Any:
    """``_selection`` for a single scene as numpy floats (``_one``): a predicate's numpy bool as it is, not made
    a 0-d array (``every`` takes either)."""
    sel = None
    if p.handles is not always:
        sel = p.handles(one)
        if sel.__class__ is not _BOOL:
            sel = np.asarray(sel, dtype=bool)
    if p.exact_when is not always and p.exact_when is not p.handles:
        exact = p.exact_when(one)
        if exact.__class__ is not _BOOL:
            exact = np.asarray(exact, dtype=bool)
        sel = exact if sel is None else sel & exact
    return sel


def auto_by_masks(model: Model, scene: Scene) -> Any:
    """``solve(model, scene, "auto")`` by the general route alone, for the tests that compare the two routes (the
    scene is taken as admissible)."""
    batch, n, flat = _flatten(model, scene)
    return _auto_general(model, flat, n, batch)


def _auto_single(p: Path, flat: Scene, n: int, batch: tuple[int, ...]) -> Any:
    """The result of ``auto`` where one path serves every scene: that path's result, reshaped to the batch."""
    return _relabel(p.run(flat), n, batch, [(n, None)])


def _auto_general(model: Model, flat: Scene, n: int, batch: tuple[int, ...], first: np.ndarray | None = None,
                  whole: bool = False) -> Any:
    """Each path, cheapest first, on the scenes left where it handles them and declares itself exact; ``first``:
    that selection for the cheapest path, already computed. ``whole``: a path that takes every scene (none taken
    before it) runs on the batch itself, as ``_auto_single`` (a single scene past the cheapest path: on its numpy
    floats where the path declares ``scalar``, as ``_run_one``)."""
    todo = np.ones(n, dtype=bool)
    parts: list[tuple[np.ndarray, Any]] = []
    masks: dict[Callable[[Scene], np.ndarray], np.ndarray] = {}  # a predicate that several paths share, once

    def mask(predicate: Callable[[Scene], np.ndarray]) -> np.ndarray | bool:
        if predicate is always:
            return True
        if predicate not in masks:
            masks[predicate] = np.asarray(predicate(flat), dtype=bool)
        return masks[predicate]

    for i, p in enumerate(model._plan.order):  # cheapest first; stable: declared order breaks ties
        if not _some(todo):
            break
        if i == 0 and first is not None:
            sel = todo & first
        else:
            sel = todo & mask(p.handles) & mask(p.exact_when)
        if whole and not parts and every(sel):
            if p.scalar and n == 1:  # a single scene, by a path that takes it as numpy floats (``_run_one``)
                return _run_one(p, _one(model, flat), batch)
            return _auto_single(p, flat, n, batch)
        if _some(sel):
            parts.append((sel, p.run(_take(model, flat, sel))))
            todo &= ~sel
    if _some(todo):  # cannot happen when some path is exact everywhere (every model has its ODE path)
        raise PathError(f"{model.name}: no path declares itself exact for {int(todo.sum())} scene(s)")
    if not parts:  # an empty batch: the cheapest path's result of no scene (its arrays of length 0)
        cheapest = model._plan.order[0]
        return _merge([(todo, cheapest.run(_take(model, flat, todo)))], n, batch)
    return _merge(parts, n, batch)


def _merge(parts: list[tuple[np.ndarray, Any]], n: int, batch: tuple[int, ...]) -> Any:
    """One result from the per-path results of disjoint subsets of the scenes (array fields scattered back)."""
    first = parts[0][1]
    values: dict[str, Any] = {}
    where = [np.flatnonzero(sel) for sel, _ in parts]  # once: cheaper than the masks, array after array
    for f in dataclasses.fields(first):
        v0 = getattr(first, f.name)
        if isinstance(v0, np.ndarray) and v0.ndim >= 1:
            out = np.empty((n, *v0.shape[1:]), dtype=v0.dtype)
            for idx, (_, res) in zip(where, parts, strict=True):
                _scatter(out, idx, getattr(res, f.name))
            values[f.name] = out
        else:
            values[f.name] = v0
    merged = object.__new__(type(first))
    merged.__dict__.update(values)
    return _relabel(merged, n, batch, [(int(sel.sum()), res) for sel, res in parts])


def _scatter(out: np.ndarray, idx: np.ndarray, v: np.ndarray) -> None:
    """``out[idx] = v`` over the first axis; a vector per scene (rows of ``out`` and ``v`` contiguous, the same
    dtype) as one opaque item per row, which numpy moves several times faster than the rows' numbers one by one
    (the same bytes)."""
    if out.ndim > 1 and v.shape == (idx.size, *out.shape[1:]) and v.dtype == out.dtype and v.flags.c_contiguous:
        row = np.dtype((np.void, out.itemsize * int(np.prod(out.shape[1:]))))
        out.view(row).reshape(out.shape[0])[idx] = v.view(row).reshape(idx.size)
    else:
        out[idx] = v


def _relabel(res: Any, n: int, batch: tuple[int, ...], counts: list[tuple[int, Any]]) -> Any:
    """``res`` (arrays over the flattened batch) as the result of ``auto``: array fields reshaped to the batch,
    ``method`` "auto", ``label`` saying how many scenes each path computed (``None``: ``res`` itself)."""
    values = dict(res.__dict__)
    for name, v in values.items():
        if isinstance(v, np.ndarray) and v.ndim >= 1:  # as ``_merge`` scatters them: batch axis first
            values[name] = v.reshape((*batch, *v.shape[1:]))
    values["method"] = "auto"
    values["label"] = "auto: " + "; ".join(f"{k} by {(r if r is not None else res).label}" for k, r in counts)
    out = object.__new__(type(res))  # a frozen dataclass: its fields set as its own __init__ sets them
    out.__dict__.update(values)
    return out
