"""The Python entry point, and the functions the CLI calls. No argument parsing, no rendering, nothing printed.

For people who script (README, "From Python"): ``simulate(model, method, **scene)`` runs scenes of a mechanics
model (a ``Simulation`` of numpy arrays), ``reproduce(experiment)`` runs one experiment of the paper (a
``Reproduction``, nothing written), ``fit(kind, data, **options)`` fits your measurements, from a CSV file or from
arrays (a ``Fit``). Each takes what the matching ``resal`` command takes, in the same units, and raises
``InputError`` where it would exit 2. For the CLI: find experiments, run them, write them.

One error contract for every function of ``__all__`` (tests/test_api_contract.py): whatever the arguments hold, a
call returns, or raises ``InputError`` (bad input, named in the message) or ``ComputationError`` (an ``InputError``
too: valid input on which a computation failed, or the environment did: out of memory, a worker process killed,
no temporary folder). Arguments are checked up front, by type before by value. Besides, as documented where they
arise: what the caller's own code raises (``fn`` of ``parallel_map``, a ``progress`` callback), ``OSError`` of
``run_and_draw`` writing into its scratch folder (a full disk: the CLI names its --out), and ``Interrupted`` (a
signal within ``interruptible``). Nothing is printed: the Python warnings raised within a call (numpy's floating-
point ones among them) are caught. ``fit`` returns them among ``Fit.warnings`` (code ``numerical``); the others
drop them, what they signal being checked anyway (a non-finite output of ``simulate`` is an ``InputError``).
Sizes are bounded before anything is allocated: ``MAX_SCENES`` per ``simulate`` call, ``MAX_JOBS`` processes.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import operator
import os
import pickle
import sys
import typing
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from . import locate, processes
from .config import Experiment, load_experiment
from .errors import ComputationError, InputError, did_you_mean
from .experiments import KINDS
from .fit import options as fit_options
from .fit.kinds import KINDS as FIT_KINDS
from .fit.kinds import MAX_RESAMPLES
from .lazy import HEAVY, preload
from .locate import names_a_file
from .mechanics import paths, registry
from .mechanics.paths import PathCode, Regime
from .models import NOT_COMPUTED, OUTPUTS, code_name, solve_scene
from .models import degrees as to_degrees
from .processes import checkpoint, interruptible, process_pool
from .results import Reproduction
from .series import MAX_CSV_BYTES, Table, table_from_columns

__all__ = ["MAX_JOBS", "MAX_ODE_SCENES", "MAX_SCENES", "Fit", "FitEstimate", "FitWarning", "PathCode", "Regime",
           "RunProgress", "Simulation", "checkpoint", "config_dir", "experiment_ids", "fit", "interruptible",
           "list_experiments", "load", "parallel_map", "reproduce", "run", "run_and_draw", "simulate"]

T = TypeVar("T")
R = TypeVar("R")
F = TypeVar("F", bound=Callable[..., Any])

# Scenes one `simulate` call computes, at most: checked on the broadcast shape before any array of the batch is
# allocated. The heaviest closed-form model (spheres-cloth) peaks at about 0.7 kB per scene, so a million scenes
# stay under 1 GB, and the cheap models compute them in well under a second. A ricochet scene counts as its n
# impacts (about 0.1 kB each: n = 1000 weighs what a thousand scenes of another model do).
MAX_SCENES = 1_000_000
# Scenes of a path that integrates an ODE per scene (``ode``, ``reference``: cost 1000 and more), a loop in Python of
# 1 to 20 ms a scene: ten thousand take two minutes at most. Asked for by name only: ``auto`` never runs one (every
# model has a path exact on every scene, cheaper).
MAX_ODE_SCENES = 10_000
MAX_JOBS = 256  # processes, as `resal reproduce --jobs`: a pool forks all its workers at once, a typo must not fork 10⁹


def _short(text: str, limit: int = 80) -> str:
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _shown(value: Any, limit: int = 80) -> str:
    """``repr(value)`` for a message: shortened, and never raising (an int of 5000 digits, a hostile ``__repr__``)."""
    try:
        text = repr(value)
    except Exception:
        return f"<{type(value).__name__}>"
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _a(value: Any) -> str:
    """What ``value`` is, for "got …": its type (and dtype and shape for an array)."""
    if value is None:
        return "None"
    if isinstance(value, np.ndarray):
        return f"an array of dtype {value.dtype} and shape {value.shape}"
    name = type(value).__name__
    return f"{'an' if name[:1].lower() in 'aeiou' else 'a'} {name}"


def _text(where: str, value: Any, what: str) -> str:
    """``value`` if it is a string (a name: a model, a method, a kind), else ``InputError``."""
    if not isinstance(value, str):
        raise InputError(f"{where}={_shown(value)}", f"expected {what}, a string; got {_a(value)}")
    return value


def _path_text(where: str, value: Any, what: str) -> str:
    """The text of a path or a name given as ``str`` or ``os.PathLike`` (no bytes, no NUL character)."""
    if not isinstance(value, (str, os.PathLike)):
        raise InputError(f"{where}={_shown(value)}", f"expected {what}, a string or a path; got {_a(value)}")
    try:
        text = os.fspath(value)
    except Exception as err:  # a PathLike whose __fspath__ fails: the caller's object, said plainly
        raise InputError(f"{where}={_shown(value)}", f"expected {what}; its __fspath__ failed ({err})") from None
    if not isinstance(text, str):
        raise InputError(f"{where}={_shown(value)}", f"expected {what} as text, got a path of {_a(text)}")
    if "\x00" in text:
        raise InputError(f"{where}={_shown(text)}", f"expected {what}: a path holds no NUL character")
    return text


def _callback(where: str, value: Any) -> Callable[..., Any] | None:
    if value is not None and not callable(value):
        raise InputError(f"{where}={_shown(value)}", f"expected a function or None, got {_a(value)}")
    return value


def _sequence(where: str, value: Any, what: str) -> list[Any]:
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes, bytearray)):
        raise InputError(f"{where}={_shown(value)}", f"expected {what} (a list or a tuple), got {_a(value)}")
    return list(value)


def _quiet(fn: F) -> F:
    """``fn`` under the contract's common part: the warnings raised within caught and dropped (numpy's floating-
    point errors silenced where they arise), an exhausted memory a ``ComputationError`` naming the call."""
    @functools.wraps(fn)
    def call(*args: Any, **kwargs: Any) -> Any:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            try:
                return fn(*args, **kwargs)
            except MemoryError:
                raise ComputationError(f"{fn.__name__}(…)", "out of memory: this machine could not hold the "
                                                            "computation's arrays (a smaller one needs less)") from None

    return typing.cast(F, call)


@contextmanager
def _pool_dies_as_computation_error(jobs: int) -> Iterator[None]:
    """A worker process killed (the kernel's OOM killer, a signal from outside): the environment failed."""
    from concurrent.futures.process import BrokenProcessPool

    try:
        yield
    except BrokenProcessPool as err:
        raise ComputationError(f"jobs={jobs}", f"a worker process died ({err}); out of memory? fewer jobs need "
                                               "less") from None


def _configs_unreadable(err: OSError) -> InputError:
    env = os.environ.get("RESAL_CONFIGS")
    return InputError(f"$RESAL_CONFIGS={_short(env)}" if env else "the experiment files",
                      f"cannot be read ({err.strerror or err})")


def config_dir() -> Path:
    """Where the experiment files are: the folder ``$RESAL_CONFIGS`` names (``InputError`` if it names none),
    else the shipped ``configs/``."""
    try:
        return locate.config_dir()
    except OSError as err:  # a $RESAL_CONFIGS too long for the file system, a loop of symlinks
        raise _configs_unreadable(err) from None


def experiment_ids() -> list[str]:
    """The ids of the experiments in ``config_dir()``, sorted."""
    try:
        return locate.experiment_ids()
    except OSError as err:
        raise _configs_unreadable(err) from None


@_quiet
def load(name_or_path: str | os.PathLike[str]) -> Experiment:
    """An experiment by id (``configs/<id>.yaml``) or by the path of a YAML file."""
    name = _path_text("experiment", name_or_path, "an experiment id or the path of a YAML file")
    p = Path(name)
    # a path (the reader says what a FIFO, a device or a folder named *.yaml is), else an id
    try:
        is_file = names_a_file(name)
        present = is_file and (p.exists() or p.is_symlink())
    except OSError as err:  # a name too long for the file system, a loop of symlinks
        raise InputError(f"experiment '{_short(name)}'", "neither an experiment id nor a file that can be read "
                                                        f"({err.strerror or err})") from None
    if is_file:
        if not present:
            raise InputError(name, "no such experiment file")
        return load_experiment(p, KINDS)
    ids = experiment_ids()
    if name not in ids:
        raise InputError(f"experiment '{_short(name)}'",
                         f"unknown experiment id (expected one of: {', '.join(ids) or 'none found'}, "
                         f"or the path of a YAML file){did_you_mean(name, ids)}")
    return load_experiment(config_dir() / f"{name}.yaml", KINDS)


@_quiet
def list_experiments() -> list[Experiment]:
    """Every experiment of ``config_dir()``, loaded."""
    return [load(i) for i in experiment_ids()]


def _experiment(where: str, exp: Any) -> Experiment:
    if not isinstance(exp, Experiment):
        raise InputError(f"{where}={_shown(exp)}", f"expected an Experiment (api.load(id)), got {_a(exp)}")
    if not isinstance(exp.kind, str) or exp.kind not in KINDS:
        raise InputError(f"{where} {_shown(exp.id)}", f"unknown kind {_shown(exp.kind)} (expected one of: "
                                                      f"{', '.join(KINDS)})")
    return exp


@_quiet
def run(exp: Experiment) -> Reproduction:
    """Run one experiment: physics, fits and comparisons, no I/O but reading its data files."""
    return KINDS[_experiment("exp", exp).kind].run(exp)


def _jobs(jobs: Any) -> int:
    return _whole("jobs", jobs, 1, MAX_JOBS, "a number of processes")


@_quiet
def _draw(job: tuple[Any, Path]) -> Path:
    """``report.draw_figure`` with its warnings dropped (matplotlib's), in whichever process draws."""
    from .report import draw_figure

    return draw_figure(job)


@dataclass(frozen=True)
class RunProgress:
    """Where ``run_and_draw`` stands, given to its ``progress`` callback as each experiment finishes running (then
    ``finished`` is that experiment and ``seconds`` its running time, in its process) and as each figure is drawn.
    ``figures`` is the number of figures to draw in all, None until every experiment has run (an experiment says
    what it draws once it has run); its ``str`` is a line that says all this."""

    experiments: int
    ran: int
    figures: int | None
    drawn: int
    finished: Reproduction | None = None
    seconds: float | None = None

    def __str__(self) -> str:
        return (f"experiments run: {self.ran}/{self.experiments}; figures drawn: {self.drawn}/"
                f"{'?' if self.figures is None else self.figures}")


@_quiet
def run_and_draw(exps: Sequence[Experiment], jobs: int, scratch: Path | str,
                 progress: Callable[[RunProgress], None] | None = None) -> list[Reproduction]:
    """Run the experiments and render their figures into ``scratch/<id>/`` on up to ``jobs`` processes (1 to
    ``MAX_JOBS``), the figures of an experiment starting as soon as it has run (so one long experiment does not
    idle a core). Results in the input order. ``progress`` gets a ``RunProgress`` as each experiment finishes
    (in the order they finish) and as each figure is drawn. Exceptions propagate: an ``InputError`` from a data
    file, what ``progress`` raises, and ``OSError`` when ``scratch`` cannot be written (a full disk: the caller
    names it)."""
    from .report import prepare_drawing

    exps = [_experiment(f"exps[{i}]", e) for i, e in enumerate(_sequence("exps", exps, "experiments"))]
    jobs = _jobs(jobs)
    scratch = Path(_path_text("scratch", scratch, "a folder"))
    try:
        if scratch.exists() and not scratch.is_dir():
            raise InputError(f"scratch={scratch}", "expected a folder, got a file")
    except OSError as err:
        raise InputError(f"scratch={_shown(str(scratch))}", f"cannot be used ({err.strerror or err})") from None
    progress = _callback("progress", progress)
    prepare_drawing()
    n = len(exps)
    if jobs <= 1:
        reps = []
        for i, e in enumerate(exps, 1):
            checkpoint()
            r, seconds = processes.timed(run, e)
            reps.append(r)
            if progress is not None:
                progress(RunProgress(n, i, sum(len(x.figures) for x in reps) if i == n else None, 0, r, seconds))
        n_fig = sum(len(r.figures) for r in reps)
        drawn = 0
        for r in reps:
            for spec in r.figures:
                checkpoint()
                _draw((spec, scratch / r.experiment.id))
                drawn += 1
                if progress is not None:
                    progress(RunProgress(n, n, n_fig, drawn))
        return reps
    from concurrent.futures import FIRST_COMPLETED, wait

    preload(*HEAVY)  # once here, inherited by the forks: not once per worker, nor inside an experiment's time
    reps: list[Reproduction | None] = [None] * n
    with _pool_dies_as_computation_error(jobs), process_pool(jobs) as pool:
        # the longest first (each kind's declared COST): the last to start should be short, not roze-ricochets
        order = sorted(range(n), key=lambda i: -float(getattr(KINDS[exps[i].kind], "COST", 1.0)))
        running = {pool.submit(processes.timed, run, exps[i]): i for i in order}
        drawing = set()
        n_fig = done_fig = 0
        while running or drawing:
            checkpoint()
            finished, _ = wait([*running, *drawing], return_when=FIRST_COMPLETED, timeout=0.5)
            for fut in finished:  # each said as it happens: an experiment by name, a figure by the count
                if fut in running:
                    i = running.pop(fut)
                    r, seconds = fut.result()
                    reps[i] = r
                    n_fig += len(r.figures)
                    drawing |= {pool.submit(_draw, (spec, scratch / r.experiment.id)) for spec in r.figures}
                    event = RunProgress(n, n - len(running), None if running else n_fig, done_fig, r, seconds)
                else:
                    drawing.discard(fut)
                    fut.result()
                    done_fig += 1
                    event = RunProgress(n, n - len(running), None if running else n_fig, done_fig)
                if progress is not None:
                    progress(event)
    return reps  # type: ignore[return-value]


def parallel_map(fn: Callable[[T], R], items: Sequence[T], jobs: int,
                 progress: Callable[[int, int], None] | None = None,
                 finished: Callable[[int, R, float], None] | None = None) -> list[R]:
    """``[fn(x) for x in items]`` on up to ``jobs`` processes (1 to ``MAX_JOBS``), results in the input order;
    ``progress(done, total)`` is called as items finish, and before it ``finished(index, result, seconds)``: which
    item finished (its index in ``items``: out of order on several processes), its result and the seconds its call
    took. On more than one process, ``fn`` and the items must pickle. What ``fn``, ``progress`` and ``finished``
    raise propagates (an ``InputError`` from a data file); ``fn``'s warnings and output are its own."""
    if not callable(fn):
        raise InputError(f"fn={_shown(fn)}", f"expected a function, got {_a(fn)}")
    items = _sequence("items", items, "the items to map")
    jobs = _jobs(jobs)
    progress = _callback("progress", progress)
    finished = _callback("finished", finished)
    if jobs > 1 and len(items) > 1:  # sent to worker processes: refused here, not by a pickling error there
        for where, x in (("fn", fn), *((f"items[{i}]", x) for i, x in enumerate(items))):
            try:
                pickle.dumps(x)
            except Exception as err:
                raise InputError(f"{where}={_shown(x)}", f"cannot be sent to a worker process (it does not pickle: "
                                                         f"{_shown(err, 120)}); jobs=1 runs in this process") from None
    with _pool_dies_as_computation_error(jobs):
        return processes.parallel_map(fn, items, jobs, progress, finished)


# ---- the Python entry point: simulate, reproduce, fit ---------------------------------------------------------
if typing.TYPE_CHECKING:  # `fit` imports the fitting code (scipy.stats …) when called: the CLI starts faster
    from .fit.run import FitOutcome

_NOT_OUTPUTS = ("method", "path", "regime", "label")


@dataclass(frozen=True)
class Simulation:
    """The outcome of ``simulate``: numbers and codes, no prose.

    ``path`` and ``regime`` hold one code per scene (int8 arrays of the batch's shape, 0-d for one scene):
    ``PathCode`` (1 exact, 2 elementary, 3 resal, 4 resal-corrected, 5 ode, 6 reference) and ``Regime``
    (0 frictionless, 1 slide, 2 grip, 3 no-slip); ``path_name`` and ``regime_name`` hold their names beside them,
    arrays of str of the same shape (``str(s.path_name)`` for one scene), the names ``resal simulate --json``
    gives as path_name and regime_name (``PathCode.RESAL_CORRECTED``: "resal-corrected"). ``inputs`` is the whole
    scene, defaults included, and ``outputs`` the results, both in the units of ``resal simulate --json`` (SI,
    angles in degrees),
    the batch's shape first (then 3 for a vector, n for a ricochet's impacts); an output that a path does not
    compute is NaN for its scenes (``gamma`` of ``cue-stroke`` by ``ode``). ``units`` names the unit of every
    input and output (``resal simulate --list``: "1" a pure number, "code" a ``Regime`` per impact, "flag")."""

    model: str
    method: str
    path: np.ndarray
    regime: np.ndarray
    inputs: dict[str, np.ndarray]
    outputs: dict[str, np.ndarray]
    units: dict[str, str]
    path_name: np.ndarray
    regime_name: np.ndarray


def _names(kind: type[PathCode] | type[Regime], codes: np.ndarray) -> np.ndarray:
    """The names of an array of path or regime codes, an array of str of the same shape."""
    return np.array([code_name(kind(int(c))) for c in codes.ravel()], dtype=str).reshape(codes.shape)


def _scene_param(p: paths.Param) -> paths.Param:
    """``p`` with its range in the unit ``simulate`` takes (degrees for an angle), as ``resal simulate`` reads it."""
    if not p.cli_degrees:
        return p

    def deg(v: float | None) -> float | None:
        return None if v is None else to_degrees(v)

    return paths.Param(p.name, "degrees", p.doc, deg(p.default), deg(p.lo), deg(p.hi), p.lo_open, p.hi_open,
                       integer=p.integer)


def _admissible(p: paths.Param, a: np.ndarray) -> np.ndarray:
    """Per value, ``p.problem(value) is None`` (vectorised)."""
    ok = np.isfinite(a)
    if p.integer:
        ok &= np.where(ok, a, 0.0) == np.trunc(np.where(ok, a, 0.0))
    if p.lo is not None:
        ok &= (a > p.lo) if p.lo_open else (a >= p.lo)
    if p.hi is not None:
        ok &= (a < p.hi) if p.hi_open else (a <= p.hi)
    return ok


def _numbers(where: str, value: Any, what: str) -> np.ndarray:
    """A float array of ``value``: a number or a (nested) list or array of numbers; no booleans, strings, None,
    complex numbers or objects, nothing ragged, empty or masked."""
    if value is None or isinstance(value, (str, bytes, bytearray, bool, np.bool_)):
        raise InputError(where, f"expected {what}, got {_a(value)}")
    if isinstance(value, int) and not math.isfinite(_float_or_inf(value)):
        raise InputError(where, f"expected {what}, got an int too large for a float (|x| > 1.8e308)")
    if isinstance(value, np.ma.MaskedArray) and np.ma.is_masked(value):
        raise InputError(where, f"expected {what}, got a masked array (np.ma.filled gives the numbers)")
    try:
        a = np.asarray(value)
    except Exception:  # ragged nesting (rows of different lengths), an object that refuses conversion
        raise InputError(where, f"expected {what}, got {_a(value)} that is not one array of numbers (ragged rows, "
                                "or elements that are not numbers)") from None
    if a.dtype.kind not in "iuf":
        raise InputError(where, f"expected {what}, got {_a(value)}"
                                + (f" of dtype {a.dtype}" if not isinstance(value, np.ndarray) and a.ndim else ""))
    if a.size == 0:
        raise InputError(where, f"expected {what}, got an empty array")
    return a.astype(float)


def _float_or_inf(n: int) -> float:
    try:
        return float(n)
    except OverflowError:
        return math.inf


def _value_text(name: str, a: np.ndarray, index: tuple[int, ...] | None = None) -> str:
    if index is None:
        return f"{name}={float(a):g}" if a.ndim == 0 else f"{name}=<array of shape {a.shape}>"
    return f"{name}[{', '.join(map(str, index))}]={float(a[index]):g}"


def _bounded(m: paths.Model, method: str, values: dict[str, np.ndarray], given: str) -> None:
    """``InputError`` unless the arrays broadcast into one batch within ``MAX_SCENES`` (``MAX_ODE_SCENES`` for a
    path that integrates each scene): from their shapes alone, before anything of the batch is allocated."""
    shapes = [a.shape[:-1] if k in m.vectors else a.shape for k, a in values.items() if k not in m.static]
    try:
        batch = np.broadcast_shapes(*shapes)
    except ValueError:
        shown = ", ".join(f"{k} {np.shape(v)}" for k, v in values.items())
        raise InputError(given, f"the arrays do not broadcast to one batch of scenes ({shown})") from None
    scenes = math.prod(batch)
    weight = {p.name: int(np.ravel(values[p.name])[0]) if p.name in values else int(p.default or 1)
              for p in m.params if p.name in m.static and p.integer}  # ricochet's n: its impacts
    total = scenes * math.prod(weight.values())
    ode = method != "auto" and m.path(method).cost >= 1000
    bound = MAX_ODE_SCENES if ode else MAX_SCENES
    if total > bound:
        size = " × ".join(map(str, batch)) or "1"
        each = "".join(f" of {n} {'impacts' if k == 'n' else k} each" for k, n in weight.items())
        why = (f"the path '{method}' integrates each scene (1 to 20 ms each)" if ode else "under 1 GB of memory")
        raise InputError(given, f"a batch of {size} = {scenes:,} scenes{each} is more than one call computes: at "
                                f"most {bound:,} {'scene-impacts' if weight else 'scenes'} ({why}); split it into "
                                "smaller batches")


@_quiet
def simulate(model: str, method: str = "auto", **scene: Any) -> Simulation:
    """One scene of a mechanics model, or a batch: ``resal simulate MODEL --set name=value … --method METHOD``.

    ``scene``: the model's parameters by name (``resal simulate --list`` lists them, their units, ranges and
    defaults), each a number or a numpy array; arrays broadcast against one another into a batch of scenes (a
    3-vector such as ``v`` of the spheres models has 3 on its last axis; ``n`` of ``ricochet`` is one number for
    the batch). Units are SI, **angles in degrees** (``alpha0`` of ``ricochet``, ``i`` of ``cue-stroke``; the
    output ``gamma`` too), as on the command line; the physics works in radians. The paper's coefficients (eps,
    epsp, nu, f, j) have no default. ``method``: ``"auto"`` (per scene, the cheapest path that declares itself
    exact there) or a path of the model (``exact``, ``elementary``, ``resal``, ``resal-corrected``, ``ode``).

    Returns a ``Simulation``. Raises ``InputError`` for a model, method or parameter unknown or not a string, a
    value not numbers (None, text, ragged lists, …), missing, or outside its range (naming the parameter, the
    scene and the range), arrays that do not broadcast or make more than ``MAX_SCENES`` scenes (``MAX_ODE_SCENES``
    by ``ode`` or ``reference``; a ricochet scene counts as its n impacts), or a scene the model or the path does
    not admit; ``ComputationError`` (an ``InputError``) if a solver fails on an admissible scene. Warnings are
    dropped: an output that overflows is an ``InputError``."""
    model = _text("model", model, f"a model's name (one of: {', '.join(registry.MODELS)})")
    if model not in registry.MODELS:
        raise InputError(f"model '{_short(model)}'", f"unknown model (expected one of: "
                                                     f"{', '.join(registry.MODELS)})"
                                                     f"{did_you_mean(model, registry.MODELS)}")
    m = registry.MODELS[model]
    names = [p.name for p in m.paths]
    method = _text("method", method, f"auto or a path of {model} ({', '.join(names)})")
    if method != "auto" and method not in names:
        raise InputError(f"method '{_short(method)}'", f"{model} has no path '{_short(method)}' (expected one of: "
                                                       f"auto, {', '.join(names)})"
                                                       f"{did_you_mean(method, ['auto', *names])}")
    params = {p.name: p for p in m.params}
    values: dict[str, np.ndarray] = {}
    given_values: dict[str, np.ndarray] = {}  # as given, checked
    degrees: dict[str, np.ndarray] = {}  # angles as given
    for name, raw in scene.items():
        p = params.get(name)
        if p is None:
            raise InputError(f"{_short(name)}=…", f"unknown parameter '{_short(name)}' for {model} (expected one "
                                                  f"of: {', '.join(params)}){did_you_mean(name, params)}")
        q = _scene_param(p)
        vector = name in m.vectors
        a = _numbers(name, raw, "a 3-vector (x, y, z)" if vector else "a number or an array of numbers"
                     + (f" in {q.unit}" if q.unit != "1" else ""))
        if vector and (a.ndim == 0 or a.shape[-1] != 3):
            raise InputError(_value_text(name, a), f"'{name}' is a 3-vector: expected 3 numbers x, y, z on the "
                                                   f"last axis, got shape {a.shape}")
        if name in m.static and a.size != 1:
            raise InputError(_value_text(name, a), f"'{name}' must be one number for the whole batch")
        bad = ~_admissible(q, a)
        if bad.any():
            idx = tuple(int(i) for i in np.argwhere(bad)[0])
            problem = q.problem(float(a[idx])) or "admissible"
            raise InputError(_value_text(name, a, idx if a.ndim else None),
                             f"'{name}' must be {problem}" + (" (degrees)" if p.cli_degrees else "")
                             + f", got {float(a[idx]):g}")
        tiny = (a != 0) & (np.abs(a) < sys.float_info.min)  # as the command line: a subnormal is no measurement
        if tiny.any():
            idx = tuple(int(i) for i in np.argwhere(tiny)[0])
            raise InputError(_value_text(name, a, idx if a.ndim else None),
                             f"'{name}': {float(a[idx]):g} is nonzero but below the smallest normal double "
                             f"({sys.float_info.min:.1e}): expected a value of a physical size")
        given_values[name] = a
        if p.cli_degrees:
            degrees[name] = a
        values[name] = np.radians(a) if p.cli_degrees else a
    missing = [p.name for p in m.params if p.default is None and p.name not in values]
    if missing:
        raise InputError(", ".join(missing), f"missing: {model} needs {', '.join(missing)} (no default: give your "
                                             f"measured value, e.g. {missing[0]}=…)")
    given = f"simulate('{model}', " + ", ".join(_value_text(k, v) for k, v in given_values.items()) + ")"
    _bounded(m, method, values, given)
    try:
        full = m.scene(values)
    except paths.PathError as err:
        raise InputError(given, str(err)) from None
    res = solve_scene(m, full, method, given, f"method '{method}'", "call")
    path = np.asarray(res.path)
    units = {p.name: _scene_param(p).unit for p in m.params}
    outputs = {}
    for f in dataclasses.fields(res):
        if f.name in _NOT_OUTPUTS:
            continue
        a = np.asarray(getattr(res, f.name))
        units[f.name] = OUTPUTS[model][f.name][0]
        if units[f.name] == "degrees":
            a = np.degrees(a)
        if a.dtype.kind == "f":
            bad = ~np.isfinite(a)
            skipped = [int(PathCode[q.upper().replace("-", "_")]) for mo, q, o in NOT_COMPUTED
                       if (mo, o) == (model, f.name)]
            if skipped:  # NaN where the scene's path does not compute this output
                bad &= ~(np.isnan(a) & np.isin(path, skipped).reshape(path.shape + (1,) * (a.ndim - path.ndim)))
            if bad.any():
                raise InputError(given, f"the scene's outputs overflow ({f.name} not finite): expected inputs "
                                        "whose products and squares stay within floating point (|x| ≲ 1e150 in SI "
                                        "units)")
        outputs[f.name] = a
    inputs = {}
    for p in m.params:  # angles as given (no round trip through radians), the defaults as the CLI prints them
        shape = np.shape(full[p.name])
        v = degrees.get(p.name, _scene_param(p).default) if p.cli_degrees else full[p.name]
        inputs[p.name] = np.array(np.broadcast_to(v, shape) if np.ndim(v) <= len(shape) else np.reshape(v, shape),
                                  dtype=float)
    regime = np.asarray(res.regime)
    return Simulation(model, res.method, path, regime, inputs, outputs, {k: units[k] for k in [*inputs, *outputs]},
                      _names(PathCode, path), _names(Regime, regime))


@_quiet
def reproduce(experiment: str | os.PathLike[str]) -> Reproduction:
    """One experiment of the paper, run: ``resal reproduce ID`` without writing anything.

    ``experiment``: an id (``configs/<id>.yaml``, ``resal list``) or the path of a YAML file. Returns the
    ``Reproduction`` (``reproductions.results``): ``rows`` (each printed value: ``printed``, ``computed``,
    ``rel_diff``, ``verdict``, ``reason``, …), ``fits``, and ``figures`` as descriptions (nothing drawn). Nothing is
    written; to write the experiment's folder (summary.json, tables, figures) call
    ``reproductions.report.write_reproduction(rep, Path("results"))``, or run ``resal reproduce ID``. Raises
    ``InputError`` for an unknown id, a missing file, or a config or data file with a mistake (naming file:line).
    Warnings are dropped (a ``Reproduction`` has no place for them; its rows grade every value)."""
    return run(load(experiment))


@dataclass(frozen=True)
class FitEstimate:
    """One fitted quantity: ``value``, ``stderr`` and the 95 % interval ``ci95`` (None where the data do not
    determine it), the bootstrap's percentile interval beside it (None without one), its ``unit`` ("1": a pure
    number)."""

    id: str
    parameter: str
    value: float | None
    stderr: float | None
    ci95: tuple[float | None, float | None]
    ci95_bootstrap: tuple[float, float] | None
    unit: str
    identifiable: bool
    note: str


@dataclass(frozen=True)
class FitWarning:
    """A finding of the fit's checks: ``code`` (``outlier``, ``speed-dependence``, …, listed in the README) and the
    message ``resal fit`` prints as ``WARNING [code]: message``; or, code ``numerical``, a Python warning raised
    during the fit (a ``RuntimeWarning`` of numpy: an overflow, a division by zero), its category and text."""

    code: str
    message: str


@dataclass(frozen=True)
class Fit:
    """The outcome of ``fit``: ``estimates`` (``fit["eps"]`` picks one by id), ``warnings``, ``n`` the rows read,
    ``summary`` the whole of what ``resal fit --json`` prints (noise model, per-trial checks, leave-one-out
    predictions, identifiability …; its provenance aside), and ``outcome``, which
    ``reproductions.fit.report.write_fit(fit.outcome, Path("my-fit"))`` writes as fit.json, fit.md, residuals.csv
    and the figures."""

    kind: str
    n: int
    estimates: tuple[FitEstimate, ...]
    warnings: tuple[FitWarning, ...]
    summary: dict[str, Any]
    outcome: FitOutcome

    def __getitem__(self, id_: str) -> FitEstimate:
        for e in self.estimates:
            if e.id == id_:
                return e
        raise KeyError(f"{self.kind} fit has no estimate '{id_}' (it has: {', '.join(e.id for e in self.estimates)})")


def _whole(name: str, value: Any, lo: int, hi: int, what: str) -> int:
    """``value`` as an int in [lo, hi]: an int or a numpy integer, not a bool, not a float."""
    n = operator.index(value) if isinstance(value, (int, np.integer)) and not isinstance(value, bool) else None
    if n is None or not lo <= n <= hi:
        raise InputError(f"{name}={_shown(value)}", f"expected {what}, a whole number in [{lo:,}, {hi:,}]"
                                                    + ("" if n is not None else f", got {_a(value)}"))
    return n


def _fit_option(name: str, value: Any) -> Any:
    """One option of ``fit``, checked by ``fit.options.check`` as ``resal fit`` checks it (its Python name; None
    where the CLI's default is none): a choice is a string, a number an int or a float (numpy's too)."""
    if value is None and name in ("sigma", "sigma_in", "speeds", "M", "Mp", "Rp", "kp", "h0", "sigma_speed",
                                  "sigma_dir"):
        return None
    if name in fit_options.UNITS and isinstance(value, str):  # a mass or a radius with its unit: "170g"
        return fit_options.check(name, value, lambda t: f"{name}={t!r}")
    if name == "bootstrap":
        return _whole(name, value, 0, MAX_RESAMPLES, "a number of resamples")
    if name in fit_options.CHOICES:
        if not isinstance(value, str):
            raise InputError(f"{name}={_shown(value)}", f"expected one of {', '.join(fit_options.CHOICES[name])}, "
                                                        f"got {_a(value)}")
    elif (not isinstance(value, (int, float, np.integer, np.floating)) or isinstance(value, bool)
          or not math.isfinite(_float_or_inf(value) if isinstance(value, int) else float(value))):
        # a number given as text is not a number here; an int beyond floats is not finite
        raise InputError(f"{name}={_shown(value)}", f"expected a positive number ({fit_options.NUMBERS[name]}, "
                                                    f"finite)" + ("" if isinstance(value, (int, float, np.number))
                                                                  and not isinstance(value, bool)
                                                                  else f", got {_a(value)}"))
    # a text is quoted as Python writes it (noise='gaussian'); a number as it is (k=0.4, and the hint k=2.5)
    return fit_options.check(name, value, lambda t: f"{name}={t!r}" if isinstance(value, str) and t == value
                             else f"{name}={t}")


def _columns_table(columns: Mapping[str, Any]) -> Table:
    """The arrays as the table a CSV file of them would give (``series.table_from_columns``): the header the
    column names (units included), a NaN an empty cell ("not measured" where the kind allows it), each number as
    ``repr`` writes it (exactly); no larger than a CSV file ``resal fit`` reads (``series.MAX_CSV_BYTES``)."""
    if not columns:
        raise InputError("data", "no columns: expected a mapping of column name → array, or a CSV path")
    arrays = {}
    for name, values in columns.items():
        if not isinstance(name, str) or not name.strip() or any(c in name for c in ',"\n\r\x00'):
            raise InputError(f"column {_shown(name)}", "expected a column name as a CSV header writes it (V0, u1_mps "
                                                       "…)")
        a = _numbers(f"column '{_short(name)}'", values, "a 1-D array of numbers, one per trial")
        if a.ndim != 1:
            raise InputError(f"column '{_short(name)}'", f"expected a 1-D array, one number per trial, got shape "
                                                         f"{a.shape}")
        arrays[name] = a
    lengths = {len(a) for a in arrays.values()}
    if len(lengths) > 1:
        raise InputError("data", "expected columns of one length, got "
                                 + ", ".join(f"{_short(k, 40)}: {len(a)}" for k, a in arrays.items()))
    cells, size = [], len(",".join(arrays)) + 1
    for a in arrays.values():
        cells.append(["" if math.isnan(v) else repr(v) for v in a.astype(float).tolist()])
        size += sum(map(len, cells[-1])) + len(a)
        if size > MAX_CSV_BYTES:  # refused as the reader would refuse their CSV file
            raise InputError("data", f"{len(a):,} rows make more than {MAX_CSV_BYTES:,} bytes of CSV, more than "
                                     "resal fit reads: expected fewer trials")
    return table_from_columns(list(arrays), cells, "data")


def fit(kind: str, data: str | os.PathLike[str] | Mapping[str, Any], *, seed: int = 0, **options: Any) -> Fit:
    """Fit the paper's coefficients to your measurements: ``resal fit KIND data.csv [options]``, nothing written.

    ``kind``: rebound, cushion, drop, pendulum, ricochet, bounces or ball-ball (``resal fit --help``). ``data``:
    the path of a CSV file, or a mapping of column name → 1-D array, the names as a header writes them (``V0``,
    ``V1``, or with a unit: ``u0_cmps``, ``h0_mm``, ``phi_deg``; no unit: SI; a NaN is a blank cell, "not
    measured" where the kind allows it). ``options``: those the kind takes (``resal fit KIND --help``) by their
    Python names: ``sigma``, ``sigma_in``, ``noise``, ``speeds``, ``g``, ``M``, ``Mp``, ``R``, ``k``, ``h0``,
    ``sigma_speed``, ``sigma_dir``, ``max_seconds``, ``bootstrap`` (resamples, default 1000 where the kind takes
    it), in the CLI's units; ``seed``: the bootstrap's.

    Returns a ``Fit``; the checks' findings are in ``fit.warnings`` (nothing is printed), with the Python
    warnings raised during the fit (code ``numerical``). Raises ``InputError`` for a kind, option or seed unknown,
    out of range or of the wrong type, or bad data (naming the column and row: for arrays, ``data row i`` is index
    i); ``ComputationError`` (an ``InputError``) when the fit itself fails. Arrays reach the fit as the same table a
    CSV file gives (``series.Table``): no file is written."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for category in (DeprecationWarning, PendingDeprecationWarning, FutureWarning, ImportWarning):
            warnings.simplefilter("ignore", category)  # about code (an import's first call), not about the data
        try:
            result = _fit(kind, data, seed, options)
        except MemoryError:
            raise ComputationError(f"fit({_shown(kind)}, …)", "out of memory: this machine could not hold the fit's "
                                                        "arrays") from None
    found = dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught)
    if not found:
        return result
    return dataclasses.replace(result, warnings=result.warnings + tuple(FitWarning("numerical", m) for m in found))


def _fit(kind: Any, data: Any, seed: Any, options: dict[str, Any]) -> Fit:
    kind = _text("kind", kind, f"one of {', '.join(FIT_KINDS)}")
    if kind not in FIT_KINDS:
        raise InputError(f"kind '{_short(kind)}'", f"expected one of {', '.join(FIT_KINDS)}"
                                                   f"{did_you_mean(kind, FIT_KINDS)}")
    takes = FIT_KINDS[kind].options
    for name in options:
        if name not in takes:
            why = ("not used by the ricochet fit, which estimates the noise of positions and instants from their "
                   "residuals: leave it out" if kind == "ricochet" and name == "sigma" else
                   f"not an option of the {kind} fit")
            raise InputError(f"{_short(name)}=…", f"{why} (it takes {', '.join([*takes, 'seed'])})")
    checked = {k: _fit_option(k, v) for k, v in options.items()}
    seed = _whole("seed", seed, 0, 2**32 - 1, "a seed")
    if not isinstance(data, Mapping):
        if not isinstance(data, (str, os.PathLike)):
            raise InputError("data", f"expected the path of a CSV file or a mapping of column name → array, got "
                                     f"{_a(data)}")
        path = Path(_path_text("data", data, "the path of a CSV file"))
        try:
            path.exists()
        except OSError as err:  # a name too long for the file system, a loop of symlinks
            raise InputError(_short(str(path)), f"cannot be read ({err.strerror or err})") from None
    from .fit.estimators.trials import Noise
    from .fit.run import FitOptions, fit_csv

    noise = Noise(checked.pop("noise", "auto"))
    resamples = checked.pop("bootstrap", FitOptions.resamples if "bootstrap" in takes else 0)
    opts = FitOptions(noise=noise, resamples=resamples, seed=seed, **checked)
    source: Path | Table = _columns_table(data) if isinstance(data, Mapping) else path
    try:
        outcome = fit_csv(kind, source, opts)
    except InputError:  # an InputError is a ValueError: passed on as it is
        raise
    except (ArithmeticError, ValueError) as err:
        raise ComputationError("data" if isinstance(source, Table) else str(path), f"the fit failed: {err}") from None
    s = outcome.summary
    estimates = tuple(FitEstimate(f["id"], f["parameter"], f["value"], f["stderr"], tuple(f["ci95"]),
                                  None if f.get("ci95_bootstrap") is None else tuple(f["ci95_bootstrap"]),
                                  f.get("unit", "1"), bool(f["identifiable"]), f["note"]) for f in s["fits"])
    return Fit(kind, int(s["n"]), estimates, tuple(FitWarning(w["code"], w["message"]) for w in s["warnings"]),
               s, outcome)
