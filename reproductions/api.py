"""The Python entry point, and the functions the CLI calls. No argument parsing, no rendering, nothing printed.

For people who script (README, "From Python"): ``simulate(model, method, **scene)`` runs scenes of a mechanics
model (a ``Simulation`` of numpy arrays), ``reproduce(experiment)`` runs one experiment of the paper (a
``Reproduction``, nothing written), ``fit(kind, data, **options)`` fits your measurements, from a CSV file or from
arrays (a ``Fit``). Each takes what the matching ``resal`` command takes, in the same units, and raises
``InputError`` where it would exit 2. For the CLI: find experiments, run them, write them.
"""

from __future__ import annotations

import dataclasses
import math
import operator
import os
import re
import tempfile
import typing
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from .config import Experiment, load_experiment
from .errors import ComputationError, InputError
from .experiments import KINDS
from .fit import options as fit_options
from .fit.kinds import KINDS as FIT_KINDS
from .fit.kinds import MAX_RESAMPLES
from .locate import config_dir, experiment_ids, names_a_file
from .mechanics import paths, registry
from .mechanics.paths import PathCode, Regime
from .models import NOT_COMPUTED, OUTPUTS, solve_scene
from .models import degrees as to_degrees
from .processes import checkpoint, interruptible, parallel_map, process_pool
from .results import Reproduction

__all__ = ["Fit", "FitEstimate", "FitWarning", "PathCode", "Regime", "Simulation", "checkpoint",
           "config_dir", "experiment_ids", "fit", "interruptible", "list_experiments", "load", "parallel_map",
           "reproduce", "run", "run_and_draw", "simulate"]

T = TypeVar("T")
R = TypeVar("R")


def load(name_or_path: str) -> Experiment:
    """An experiment by id (``configs/<id>.yaml``) or by the path of a YAML file."""
    p = Path(name_or_path)
    # a path (the reader says what a FIFO, a device or a folder named *.yaml is), else an id
    if names_a_file(name_or_path):
        if not (p.exists() or p.is_symlink()):
            raise InputError(name_or_path, "no such experiment file")
        return load_experiment(p, KINDS)
    ids = experiment_ids()
    if name_or_path not in ids:
        raise InputError(f"experiment '{name_or_path}'",
                         f"unknown experiment id (expected one of: {', '.join(ids) or 'none found'}, "
                         "or the path of a YAML file)")
    return load_experiment(config_dir() / f"{name_or_path}.yaml", KINDS)


def list_experiments() -> list[Experiment]:
    return [load(i) for i in experiment_ids()]


def run(exp: Experiment) -> Reproduction:
    """Run one experiment: physics, fits and comparisons, no I/O but reading its data files."""
    return KINDS[exp.kind].run(exp)


def run_and_draw(exps: Sequence[Experiment], jobs: int, scratch: Path,
                 progress: Callable[[str], None] | None = None) -> list[Reproduction]:
    """Run the experiments and render their figures into ``scratch/<id>/`` on up to ``jobs`` processes, the
    figures of an experiment starting as soon as it has run (so one long experiment does not idle a core).
    Results in the input order; exceptions (an ``InputError`` from a data file) propagate."""
    from .report import draw_figure, prepare_drawing

    prepare_drawing()
    if jobs <= 1:
        reps = []
        for i, e in enumerate(exps, 1):
            checkpoint()
            reps.append(run(e))
            if progress:
                progress(f"running: {i}/{len(exps)} done")
        for r in reps:
            for spec in r.figures:
                checkpoint()
                draw_figure((spec, scratch / r.experiment.id))
        return reps
    from concurrent.futures import FIRST_COMPLETED, wait

    reps: list[Reproduction | None] = [None] * len(exps)
    with process_pool(jobs) as pool:
        # the longest first (each kind's declared COST): the last to start should be short, not roze-ricochets
        order = sorted(range(len(exps)), key=lambda i: -float(getattr(KINDS[exps[i].kind], "COST", 1.0)))
        running = {pool.submit(run, exps[i]): i for i in order}
        drawing = set()
        n_fig = done_fig = 0
        while running or drawing:
            checkpoint()
            finished, _ = wait([*running, *drawing], return_when=FIRST_COMPLETED, timeout=0.5)
            for fut in finished:
                if fut in running:
                    i = running.pop(fut)
                    reps[i] = r = fut.result()
                    n_fig += len(r.figures)
                    drawing |= {pool.submit(draw_figure, (spec, scratch / r.experiment.id)) for spec in r.figures}
                else:
                    drawing.discard(fut)
                    fut.result()
                    done_fig += 1
            if progress:
                progress(f"experiments run: {len(exps) - len(running)}/{len(exps)}; figures drawn: {done_fig}/"
                         f"{n_fig}")
    return reps  # type: ignore[return-value]


# ---- the Python entry point: simulate, reproduce, fit ---------------------------------------------------------
if typing.TYPE_CHECKING:  # `fit` imports the fitting code (scipy.stats …) when called: the CLI starts faster
    from .fit.run import FitOutcome

_NOT_OUTPUTS = ("method", "path", "regime", "label")


@dataclass(frozen=True)
class Simulation:
    """The outcome of ``simulate``: numbers and codes, no prose.

    ``path`` and ``regime`` hold one code per scene (int8 arrays of the batch's shape, 0-d for one scene):
    ``PathCode`` (1 exact, 2 elementary, 3 resal, 4 resal-corrected, 5 ode) and ``Regime`` (0 frictionless,
    1 slide, 2 grip, 3 no-slip), e.g. ``Regime(int(s.regime)).name``. ``inputs`` is the whole scene, defaults
    included, and ``outputs`` the results, both in the units of ``resal simulate --json`` (SI, angles in degrees),
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
    """A float array of ``value``: a number or an array of numbers (no booleans, strings or None)."""
    a = np.asarray(value) if not isinstance(value, (str, bytes)) else np.asarray(None)
    if a.dtype.kind not in "iuf":
        raise InputError(where, f"expected {what}, got {type(value).__name__}"
                                + (f" of dtype {a.dtype}" if isinstance(value, np.ndarray) else ""))
    if a.size == 0:
        raise InputError(where, f"expected {what}, got an empty array")
    return a.astype(float)


def _value_text(name: str, a: np.ndarray, index: tuple[int, ...] | None = None) -> str:
    if index is None:
        return f"{name}={float(a):g}" if a.ndim == 0 else f"{name}=<array of shape {a.shape}>"
    return f"{name}[{', '.join(map(str, index))}]={float(a[index]):g}"


def simulate(model: str, method: str = "auto", **scene: Any) -> Simulation:
    """One scene of a mechanics model, or a batch: ``resal simulate MODEL --set name=value … --method METHOD``.

    ``scene``: the model's parameters by name (``resal simulate --list`` lists them, their units, ranges and
    defaults), each a number or a numpy array; arrays broadcast against one another into a batch of scenes (a
    3-vector such as ``v`` of the spheres models has 3 on its last axis; ``n`` of ``ricochet`` is one number for
    the batch). Units are SI, **angles in degrees** (``alpha0`` of ``ricochet``, ``i`` of ``cue-stroke``; the
    output ``gamma`` too), as on the command line; the physics works in radians. The paper's coefficients (eps,
    epsp, nu, f, j) have no default. ``method``: ``"auto"`` (per scene, the cheapest path that declares itself
    exact there) or a path of the model (``exact``, ``elementary``, ``resal``, ``resal-corrected``, ``ode``).

    Returns a ``Simulation``. Raises ``InputError`` for an unknown model, method or parameter, a missing value, a
    value outside its range (naming the parameter, the scene and the range), arrays that do not broadcast, or a
    scene the model or the path does not admit; ``ComputationError`` (an ``InputError``) if a solver fails on an
    admissible scene."""
    if model not in registry.MODELS:
        raise InputError(f"model '{model}'", f"unknown model (expected one of: {', '.join(registry.MODELS)})")
    m = registry.MODELS[model]
    names = [p.name for p in m.paths]
    if method != "auto" and method not in names:
        raise InputError(f"method '{method}'", f"{model} has no path '{method}' (expected one of: auto, "
                                               f"{', '.join(names)})")
    params = {p.name: p for p in m.params}
    values: dict[str, np.ndarray] = {}
    degrees: dict[str, np.ndarray] = {}  # angles as given
    for name, raw in scene.items():
        p = params.get(name)
        if p is None:
            raise InputError(f"{name}=…", f"unknown parameter '{name}' for {model} (expected one of: "
                                          f"{', '.join(params)})")
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
        if p.cli_degrees:
            degrees[name] = a
        values[name] = np.radians(a) if p.cli_degrees else a
    missing = [p.name for p in m.params if p.default is None and p.name not in values]
    if missing:
        raise InputError(", ".join(missing), f"missing: {model} needs {', '.join(missing)} (no default: give your "
                                             f"measured value, e.g. {missing[0]}=…)")
    given = f"simulate('{model}', " + ", ".join(_value_text(k, np.asarray(v)) for k, v in scene.items()) + ")"
    try:
        with np.errstate(all="ignore"):  # an overflow is reported by solve_scene, as one message
            full = m.scene(values)
    except paths.PathError as err:
        raise InputError(given, str(err)) from None
    except ValueError:
        shapes = ", ".join(f"{k} {np.shape(v)}" for k, v in values.items())
        raise InputError(given, f"the arrays do not broadcast to one batch of scenes ({shapes})") from None
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
    return Simulation(model, res.method, path, np.asarray(res.regime), inputs, outputs,
                      {k: units[k] for k in [*inputs, *outputs]})


def reproduce(experiment: str | os.PathLike[str]) -> Reproduction:
    """One experiment of the paper, run: ``resal reproduce ID`` without writing anything.

    ``experiment``: an id (``configs/<id>.yaml``, ``resal list``) or the path of a YAML file. Returns the
    ``Reproduction`` (``reproductions.results``): ``rows`` (each printed value: ``printed``, ``computed``,
    ``rel_diff``, ``verdict``, ``reason``, …), ``fits``, and ``figures`` as descriptions (nothing drawn). Nothing is
    written; to write the experiment's folder (summary.json, tables, figures) call
    ``reproductions.report.write_reproduction(rep, Path("results"))``, or run ``resal reproduce ID``. Raises
    ``InputError`` for an unknown id, a missing file, or a config or data file with a mistake (naming file:line)."""
    return run(load(os.fspath(experiment)))


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
    message ``resal fit`` prints as ``WARNING [code]: message``."""

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
    try:
        n = None if isinstance(value, bool) else operator.index(value)
    except TypeError:
        n = None
    if n is None or not lo <= n <= hi:
        raise InputError(f"{name}={value!r}", f"expected {what}, a whole number in [{lo:,}, {hi:,}]")
    return n


def _fit_option(name: str, value: Any) -> Any:
    """One option of ``fit``, checked by ``fit.options.check`` as ``resal fit`` checks it (its Python name; None
    where the CLI's default is none)."""
    if value is None and name in ("sigma", "sigma_in", "speeds", "M", "Mp", "h0", "sigma_speed", "sigma_dir"):
        return None
    if name == "bootstrap":
        return _whole(name, value, 0, MAX_RESAMPLES, "a number of resamples")
    if isinstance(value, str) and name not in fit_options.CHOICES:  # a number given as text is not a number here
        raise InputError(f"{name}={value!r}", f"expected a positive number ({fit_options.NUMBERS[name]}, finite)")
    # a text is quoted as Python writes it (noise='gaussian'); a number as it is (k=0.4, and the hint k=2.5)
    return fit_options.check(name, value, lambda t: f"{name}={t!r}" if isinstance(value, str) and t == value
                             else f"{name}={t}")


def _columns_csv(columns: Mapping[str, Any], path: Path) -> None:
    """The arrays as a CSV file (header: the column names, units included; a NaN is an empty cell, "not
    measured" where the kind allows it). Numbers are written exactly (``repr``)."""
    if not columns:
        raise InputError("data", "no columns: expected a mapping of column name → array, or a CSV path")
    arrays = {}
    for name, values in columns.items():
        if not isinstance(name, str) or not name.strip() or any(c in name for c in ',"\n\r'):
            raise InputError(f"column {name!r}", "expected a column name as a CSV header writes it (V0, u1_mps …)")
        a = _numbers(f"column '{name}'", values, "a 1-D array of numbers, one per trial")
        if a.ndim != 1:
            raise InputError(f"column '{name}'", f"expected a 1-D array, one number per trial, got shape {a.shape}")
        arrays[name] = a
    lengths = {len(a) for a in arrays.values()}
    if len(lengths) > 1:
        raise InputError("data", "expected columns of one length, got "
                                 + ", ".join(f"{k}: {len(a)}" for k, a in arrays.items()))
    rows = zip(*arrays.values(), strict=True)
    text = [",".join(arrays), *(",".join("" if math.isnan(v) else repr(float(v)) for v in r) for r in rows)]
    path.write_text("\n".join(text) + "\n", encoding="utf-8")


def _relabel(obj: Any, path: Path) -> Any:
    """Strings (nested) with the temporary file's name as the caller knows the data: ``data``, ``data row i`` (the
    arrays' index i), ``data header``; an empty cell is a NaN."""
    if isinstance(obj, dict):
        return {k: _relabel(v, path) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_relabel(v, path) for v in obj]
    if not isinstance(obj, str):
        return obj

    def name(mt: re.Match[str]) -> str:
        line = mt.group(1)
        return "data" if line is None else "data header" if int(line) == 1 else f"data row {int(line) - 2}"

    return re.sub(re.escape(str(path)) + r"(?::(\d+))?", name, obj).replace("got ''", "got NaN")


def fit(kind: str, data: str | os.PathLike[str] | Mapping[str, Any], *, seed: int = 0, **options: Any) -> Fit:
    """Fit the paper's coefficients to your measurements: ``resal fit KIND data.csv [options]``, nothing written.

    ``kind``: rebound, cushion, drop, pendulum, ricochet, bounces or ball-ball (``resal fit --help``). ``data``:
    the path of a CSV file, or a mapping of column name → 1-D array, the names as a header writes them (``V0``,
    ``V1``, or with a unit: ``u0_cmps``, ``h0_mm``, ``phi_deg``; no unit: SI; a NaN is a blank cell, "not
    measured" where the kind allows it). ``options``: those the kind takes (``resal fit KIND --help``) by their
    Python names: ``sigma``, ``sigma_in``, ``noise``, ``speeds``, ``g``, ``M``, ``Mp``, ``R``, ``k``, ``h0``,
    ``sigma_speed``, ``sigma_dir``, ``max_seconds``, ``bootstrap`` (resamples, default 1000 where the kind takes
    it), in the CLI's units; ``seed``: the bootstrap's.

    Returns a ``Fit``; the checks' findings are in ``fit.warnings`` (nothing is printed). Raises ``InputError``
    for an unknown kind or option, an option out of range, or bad data (naming the column and row: for arrays,
    ``data row i`` is index i); ``ComputationError`` (an ``InputError``) when the fit itself fails."""
    if kind not in FIT_KINDS:
        raise InputError(f"kind '{kind}'", f"expected one of {', '.join(FIT_KINDS)}")
    takes = FIT_KINDS[kind].options
    for name in options:
        if name not in takes:
            why = ("not used by the ricochet fit, which estimates the noise of positions and instants from their "
                   "residuals: leave it out" if kind == "ricochet" and name == "sigma" else
                   f"not an option of the {kind} fit")
            raise InputError(f"{name}=…", f"{why} (it takes {', '.join([*takes, 'seed'])})")
    checked = {k: _fit_option(k, v) for k, v in options.items()}
    from .fit.estimators.trials import Noise
    from .fit.run import FitOptions, fit_csv

    noise = Noise(checked.pop("noise", "auto"))
    resamples = checked.pop("bootstrap", FitOptions.resamples if "bootstrap" in takes else 0)
    opts = FitOptions(noise=noise, resamples=resamples, seed=_whole("seed", seed, 0, 2**32 - 1, "a seed"),
                      **checked)
    with tempfile.TemporaryDirectory(prefix="resal-fit-") as tmp:
        if isinstance(data, Mapping):
            path = Path(tmp) / "data.csv"
            _columns_csv(data, path)
        elif isinstance(data, (str, os.PathLike)):
            path = Path(os.fspath(data))
        else:
            raise InputError("data", f"expected the path of a CSV file or a mapping of column name → array, got "
                                     f"{type(data).__name__}")
        try:
            outcome = fit_csv(kind, path, opts)
        except InputError as err:
            if not isinstance(data, Mapping):
                raise
            raise type(err)(_relabel(err.where, path), _relabel(err.message, path)) from None
        except (ArithmeticError, ValueError) as err:
            raise ComputationError("data" if isinstance(data, Mapping) else str(path),
                                   f"the fit failed: {err}") from None
        if isinstance(data, Mapping):
            outcome = dataclasses.replace(outcome, summary=_relabel(outcome.summary, path))
    s = outcome.summary
    estimates = tuple(FitEstimate(f["id"], f["parameter"], f["value"], f["stderr"], tuple(f["ci95"]),
                                  None if f.get("ci95_bootstrap") is None else tuple(f["ci95_bootstrap"]),
                                  f.get("unit", "1"), bool(f["identifiable"]), f["note"]) for f in s["fits"])
    return Fit(kind, int(s["n"]), estimates, tuple(FitWarning(w["code"], w["message"]) for w in s["warnings"]),
               s, outcome)
