"""``resal stress`` / ``make stress``: every model × path of the registry over seeded random scenes drawn over and
beyond the physical range, and eq. (7) of §I over extreme mass ratios (``sweep``).

Scenes start from each model's typical sample and are widened parameter by parameter: speeds and spins scaled
together over 1e-6 … 1e3 m/s, masses over ratios 1e-9 … 1e9, lengths over 1e-3 … 10 m, coefficients at the ends
of their ranges (ε, ν at 0 and 1; f, j at 0 and up to 10), k over 1.5 (a thin shell) … 10, angles grazing and
normal, spins zero and huge. Checks per scene and path (``Check``):

- every output finite;
- the momenta the model's impulses conserve (``Model.momentum``) conserved to ``MOMENTUM_RTOL``;
- no gain of vis viva (``GAIN_RTOL``) by a path of an exact kind;
- outputs continuous across regime boundaries, approached from both sides: pairs of scenes in different regimes
  (or, for ``auto``, solved by different paths) are bisected along the segment between them until the two
  sides are 2⁻⁵² apart, and their outputs compared (``CONTINUITY_TOL`` in the model's error measure);
- the ODE path agrees with ``auto`` to the ODE path's declared accuracy, and every integration ends within the
  evaluation budget of ``mechanics.budget``;
- for impact models (``Model.impact``), what the declared law implies on the returned state, from first principles
  and not from the path's own algebra (``INVARIANT_RTOL``): no pair still approaching after the impact; ε = ε′ = 1
  ends at equal normal velocities (§I n°2); the normal ratio equals the one the law implies where it implies one
  (also on a copy of the scenes with ε′ = ε, where the ratio is e); the declared law balances on the state (law (6)
  evaluated literally for two balls); the frictionless elastic version of the scenes gives the textbook result;
- the referee (``reference`` path, shares no code with the others: ``mechanics.referee``) over ``referee_scenes``
  scenes: its own invariants, and every exact path and ``auto`` against it to its declared accuracy.

A path of an approximate kind (Résal's formulas as printed or corrected) is held to these checks only where it
declares itself exact; elsewhere a gain of vis viva or a broken conservation law is counted as a *finding*, with
the region where it happens, not as a failure. Each row names its worst scene as a ``resal simulate`` command.
"""

from __future__ import annotations

import json
import math
import time
import types
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import Any

import numpy as np

from .mechanics import budget, impact, paths, registry

__all__ = ["TIMINGS", "Check", "run", "sweep", "to_markdown", "wide_scenes", "without_timings", "write"]

TOL = 1e-9  # §I sweep: momentum, energy law and gain of vis viva, relative
MOMENTUM_RTOL = 1e-12  # relative to the sum of the magnitudes of the momentum terms
GAIN_RTOL = 1e-12  # relative to the vis viva before
CONTINUITY_TOL = 1e-9  # outputs on both sides of a boundary 2⁻⁵² apart, in the model's error measure
WIDEN = 2.0**12  # the wide bracket around a boundary: 2¹² + 1 times the final one on each side
SHRINK = 64.0  # a continuous change shrinks by about 2¹³ from the wide bracket to the final one; a jump by ~1
BISECTIONS = 60  # along a segment of length 1: ends 2⁻⁵² apart after 52 halvings; the loop tests that
CHUNK = 100_000
DEFAULT_SCENES = 1_000_000
DEFAULT_ODE_SCENES = 150
DEFAULT_PAIRS = 2_000
MAX_ROUNDS = 20  # chunks drawn per chunk asked for, at most (a path that handles few scenes)
INVARIANT_RTOL = 1e-9  # approach, plastic end, normal ratio and energy law, relative to the approach speed / terms
ELASTIC_RTOL = 1e-12  # the frictionless elastic limit against the textbook, in the model's error measure
DEFAULT_REFEREE_SCENES = 1_000
EXACT_KINDS = (paths.Kind.CLOSED_FORM, paths.Kind.EXACT_NUMERICAL, paths.Kind.ODE, paths.Kind.REFEREE)
SLOW_KINDS = (paths.Kind.ODE, paths.Kind.REFEREE)  # run scene by scene over their own smaller pool
APPROX_KINDS = (paths.Kind.AS_PRINTED, paths.Kind.CORRECTED)


class Check(str, Enum):
    """What a failure or a finding is."""

    NON_FINITE = "non-finite"
    NOT_CONVERGED = "not-converged"  # an iteration inside a path (the §VI fixed point) reports no convergence
    MOMENTUM = "momentum"
    VIS_VIVA_GAIN = "vis-viva-gain"
    DISCONTINUITY = "discontinuity"
    ODE_DISAGREES = "ode-disagrees"
    ODE_BUDGET = "ode-budget"
    SOLVER_ERROR = "solver-error"
    STILL_APPROACHING = "still-approaching"  # the pair still approaches after the impact
    PLASTIC_END = "plastic-end"  # ε = ε′ = 1 does not end at equal normal velocities
    NORMAL_RATIO = "normal-ratio"  # not the normal ratio the law implies
    ENERGY_LAW = "energy-law"  # the declared law does not balance on the returned state
    ELASTIC_LIMIT = "elastic-limit"  # frictionless and elastic, not the textbook result
    REFEREE_DISAGREES = "referee-disagrees"  # a path against the referee, beyond the referee's accuracy


@dataclass(frozen=True)
class Explanation:
    """A failure understood and left as it is: the scenes it covers (``applies``, per failing scene, from the scene
    and the failure's measure) are counted as explained, with the reason, and do not fail the run."""

    model: str
    check: Check
    applies: Callable[[dict, np.ndarray], np.ndarray]
    reason: str


EXPLAINED: tuple[Explanation, ...] = ()  # none: law (6) written right on the cloth has one root (spheres docstring)


# ---- scenes ----------------------------------------------------------------------------------------------------
def _admissible_values(m: paths.Model, s: dict[str, np.ndarray]) -> np.ndarray:
    """Per scene: every parameter inside its declared range (``Param.problem``, vectorised) and the model's
    admissibility."""
    n = np.shape(s[paths.ONES])[0]
    ok = np.ones(n, dtype=bool)
    for p in m.params:
        if p.name in m.static:
            continue
        a = np.asarray(s[p.name], dtype=float)
        a2 = a.reshape(n, -1)
        good = np.all(np.isfinite(a2), axis=1)
        if p.lo is not None:
            good &= np.all(a2 > p.lo, axis=1) if p.lo_open else np.all(a2 >= p.lo, axis=1)
        if p.hi is not None:
            good &= np.all(a2 < p.hi, axis=1) if p.hi_open else np.all(a2 <= p.hi, axis=1)
        ok &= good
    with np.errstate(all="ignore"):
        ok &= np.asarray(m.admissible(s), dtype=bool)
    return ok


def _widen(m: paths.Model, raw: dict[str, np.ndarray], rng: np.random.Generator, n: int) -> None:
    """Widen a typical sample in place (module docstring); each extreme hits an eighth of the scenes."""
    def some(q: float = 1 / 8) -> np.ndarray:
        return rng.random(n) < q

    def times(name: str, factor: np.ndarray) -> None:
        a = np.asarray(raw[name], dtype=float)
        raw[name] = a * (factor[:, None] if a.ndim == 2 else factor)

    c = 10 ** rng.uniform(-6, 3, n)  # one speed scale per scene: the regime is kept, only the size moves
    lengths = 10 ** rng.uniform(-1.5, 2.5, n) * np.where(some(1 / 2), 1.0, np.nan)
    lengths = np.where(np.isnan(lengths), 1.0, lengths)
    for p in m.params:
        if p.name in m.static or p.name not in raw:
            continue
        name = p.name
        raw[name] = np.array(np.broadcast_to(np.asarray(raw[name], dtype=float),
                                             (n, 3) if name in m.vectors else (n,)))
        if p.unit in ("m/s", "rad/s"):
            times(name, c)
        if p.unit == "m":
            times(name, lengths)  # every length of the scene together: the geometry keeps its shape
        if p.unit == "rad/s":
            times(name, np.where(some(), 0.0, np.where(some(), 1e3, 1.0)))  # no spin, huge spin
        elif p.unit == "kg":
            # mass ratios 1e-6 … 1e6, and a sixteenth out to 1e-9 … 1e9 (a direct impact at 1.3e8 failed, issue 29)
            times(name, np.where(some(1 / 4), 10 ** np.where(some(1 / 4), rng.uniform(-9, 9, n),
                                                              rng.uniform(-6, 6, n)), 1.0))
        elif p.unit == "rad" and p.lo is not None and p.hi is not None:
            span = p.hi - p.lo
            edge = 10 ** rng.uniform(-9, -2, n) * span
            a = raw[name]
            raw[name] = np.where(some(), p.lo + edge, np.where(some(), p.hi - edge, a))  # grazing, normal
        elif p.unit == "1" and name in ("k", "kp"):
            # k = MR²/I from its least, a thin shell (p.lo: no ball has less), to a heavy core; next to the shell
            # (within 0.01 … 0.5 of it), and the shell exactly
            raw[name] = np.where(some(1 / 2), rng.uniform(p.lo, 10.0, n), raw[name])
            raw[name] = np.where(some(1 / 16), p.lo + 10 ** rng.uniform(-2, -0.3, n), raw[name])
            raw[name] = np.where(some(), p.lo, raw[name])
        elif p.unit == "1" and p.lo == 0.0 and p.hi == 1.0:  # ε, ν: the ends of the range
            lo = 1e-9 if p.lo_open else 0.0
            raw[name] = np.where(some(), lo, np.where(some(), 1.0, raw[name]))
        elif p.unit == "1" and p.lo == 0.0 and p.hi is None and not p.integer:  # f, j: none, large
            zero = 1e-9 if p.lo_open else 0.0
            raw[name] = np.where(some(), zero, np.where(some(), 10 ** rng.uniform(0, 1, n), raw[name]))


def wide_scenes(m: paths.Model, rng: np.random.Generator, n: int) -> tuple[dict[str, np.ndarray], int]:
    """``n`` admissible widened scenes of model ``m`` (a scene dict for ``paths.solve``) and how many were drawn."""
    assert m.sample is not None
    parts: list[dict[str, np.ndarray]] = []
    have = drawn = 0
    for _ in range(50):  # each round keeps well over half its scenes; the bound is a guard
        k = max(2 * (n - have), 64)
        raw = m.sample(rng, k)
        _widen(m, raw, rng, k)
        s = m.scene(raw)
        keep = _admissible_values(m, s)
        drawn += k
        parts.append(_take(m, s, keep))
        have += int(keep.sum())
        if have >= n:
            break
    else:
        raise RuntimeError(f"{m.name}: could not draw {n} admissible scenes")
    out = {key: (parts[0][key] if key in m.static else np.concatenate([q[key] for q in parts])[:n])
           for key in parts[0]}
    return out, drawn


def _take(m: paths.Model, s: dict[str, np.ndarray], sel: Any) -> dict[str, np.ndarray]:
    return {k: (a if k in m.static else np.asarray(a)[sel]) for k, a in s.items()}


def _interp(m: paths.Model, a: dict[str, np.ndarray], b: dict[str, np.ndarray], t: np.ndarray) -> dict:
    out = {}
    for k, x in a.items():
        if k in m.static or k == paths.ONES:
            out[k] = x
        else:
            tt = t[:, None] if np.ndim(x) == 2 else t
            out[k] = x + tt * (b[k] - x)
            out[k] = np.where(tt == 1.0, b[k], out[k])  # the end is the scene itself, to the bit
    return out


def replay(m: paths.Model, s: dict[str, np.ndarray], i: int, path: str) -> str:
    """The ``resal simulate`` command that reruns scene ``i`` of ``s`` by ``path`` (angles in degrees)."""
    parts = []
    for p in m.params:
        v = np.asarray(s[p.name], dtype=float)
        if p.name in m.static:
            text = repr(float(v))
        elif p.name in m.vectors:
            text = ",".join(repr(float(x)) for x in v[i])
        else:
            x = float(v[i])
            text = repr(math.degrees(x) if p.cli_degrees else x)
        parts.append(f"--set {p.name}={text}")
    return f"resal simulate {m.name} {' '.join(parts)} --method {path}"


# ---- checks ------------------------------------------------------------------------------------------------------
def _outputs(m: paths.Model, r: Any, n: int) -> list[np.ndarray]:
    return [np.asarray(getattr(r, o.partition("*")[0]), dtype=float).reshape(n, -1) for o in m.outputs]


def _regime_key(r: Any, n: int, with_path: bool) -> np.ndarray:
    reg = np.asarray(getattr(r, "regimes", r.regime)).reshape(n, -1).astype(np.int16)
    if with_path:
        reg = np.concatenate([reg, np.asarray(r.path).reshape(n, -1).astype(np.int16) * 16], axis=1)
    return reg


class _Row:
    """Counts, worst scenes and findings of one model × path."""

    def __init__(self, m: paths.Model, name: str, kind: str) -> None:
        self.m, self.name, self.kind = m, name, kind
        self.scenes = 0
        self.failures: dict[str, int] = {}
        self.explained: dict[str, dict[str, Any]] = {}  # per check: scenes, reason, worst
        self.worst: dict[str, dict[str, Any]] = {}  # per check: ratio to tolerance, value, replay
        self.findings: dict[str, dict[str, Any]] = {}
        self.boundary_pairs = 0
        self.margin: dict[str, float] = {}  # largest value / tolerance over every scene, per check
        self.closest: dict[str, Any] = {}  # the scene nearest to failing (largest value / tolerance), any check

    def note(self, check: Check, values: np.ndarray, tol: float, s: dict, fail: np.ndarray,
             finding: np.ndarray | None = None, path: str | None = None) -> None:
        """Record one check over a batch: ``fail`` per scene, ``values`` its measure (tolerance ``tol``)."""
        path = path or self.name
        values = np.where(np.isfinite(values), values, np.inf)
        for e in EXPLAINED:
            if e.model == self.m.name and e.check is check and fail.any():
                known = fail & np.asarray(e.applies(s, values), dtype=bool)
                if known.any():
                    x = self.explained.setdefault(check.value, {"scenes": 0, "max": 0.0, "reason": e.reason,
                                                                "replay": ""})
                    x["scenes"] += int(known.sum())
                    i = int(np.argmax(np.where(known, values, -np.inf)))
                    if values[i] > x["max"]:
                        x["max"], x["replay"] = float(values[i]), replay(self.m, s, i, path)
                    fail = fail & ~known
        if values.size:
            i = int(np.argmax(values))
            ratio = float(values[i]) / tol
            self.margin[check.value] = max(self.margin.get(check.value, 0.0), ratio)
            judged = fail if finding is None else fail | ~finding  # an approximation's finding is not a near miss
            if judged[i] and ratio > self.closest.get("ratio", 0.0):
                self.closest = {"check": check.value, "ratio": ratio, "replay": replay(self.m, s, i, path)}
        nf = int(fail.sum())
        if nf:
            self.failures[check.value] = self.failures.get(check.value, 0) + nf
            i = int(np.argmax(np.where(fail, values, -np.inf)))
            if check.value not in self.worst or values[i] > self.worst[check.value]["value"]:
                self.worst[check.value] = {"value": float(values[i]), "tolerance": tol,
                                           "replay": replay(self.m, s, i, path)}
        if finding is not None and finding.any():
            f = self.findings.setdefault(check.value, {"scenes": 0, "max": 0.0, "region": {}, "replay": ""})
            f["scenes"] += int(finding.sum())
            i = int(np.argmax(np.where(finding, values, -np.inf)))
            if values[i] > f["max"]:
                f["max"], f["replay"] = float(values[i]), replay(self.m, s, i, path)
            for p in self.m.params:
                if p.name in self.m.static or p.name in self.m.vectors:
                    continue
                v = np.asarray(s[p.name], dtype=float)[finding]
                lo, hi = f["region"].get(p.name, (math.inf, -math.inf))
                f["region"][p.name] = (min(lo, float(v.min())), max(hi, float(v.max())))

    def __getstate__(self) -> dict[str, Any]:
        """A chunk's row crosses to the parent without its model (whose paths hold lambdas); ``merge`` reads only
        the counts."""
        return {k: v for k, v in self.__dict__.items() if k != "m"} | {"m": None}

    def merge(self, other: _Row) -> None:
        """Add a later chunk's row: the same counts, worst scenes and findings as one row that had seen both
        chunks in order (a later scene replaces an earlier one only if strictly worse, as in ``note``)."""
        self.scenes += other.scenes
        self.boundary_pairs += other.boundary_pairs
        for k, v in other.failures.items():
            self.failures[k] = self.failures.get(k, 0) + v
        for k, x in other.explained.items():
            mine = self.explained.setdefault(k, {"scenes": 0, "max": 0.0, "reason": x["reason"], "replay": ""})
            mine["scenes"] += x["scenes"]
            if x["max"] > mine["max"]:
                mine["max"], mine["replay"] = x["max"], x["replay"]
        for k, w in other.worst.items():
            if k not in self.worst or w["value"] > self.worst[k]["value"]:
                self.worst[k] = w
        for k, v in other.margin.items():
            self.margin[k] = max(self.margin.get(k, 0.0), v)
        if other.closest and other.closest["ratio"] > self.closest.get("ratio", 0.0):
            self.closest = other.closest
        for k, f in other.findings.items():
            mine = self.findings.setdefault(k, {"scenes": 0, "max": 0.0, "region": {}, "replay": ""})
            mine["scenes"] += f["scenes"]
            if f["max"] > mine["max"]:
                mine["max"], mine["replay"] = f["max"], f["replay"]
            for name, (a, b) in f["region"].items():
                lo, hi = mine["region"].get(name, (math.inf, -math.inf))
                mine["region"][name] = (min(lo, a), max(hi, b))

    def as_dict(self) -> dict[str, Any]:
        return {"model": self.m.name, "path": self.name, "kind": self.kind, "scenes": self.scenes,
                "boundary_pairs": self.boundary_pairs, "failures": dict(sorted(self.failures.items())),
                "explained": dict(sorted(self.explained.items())),
                "worst": dict(sorted(self.worst.items())),
                "margin": {k: float(f"{v:.3g}") for k, v in sorted(self.margin.items())},
                "closest": self.closest,
                "findings": {k: {**v, "region": {p: list(r) for p, r in v["region"].items()}}
                             for k, v in sorted(self.findings.items())}}


def _invariants(row: _Row, m: paths.Model, s: dict, r: Any, exact_here: np.ndarray, exact_kind: bool,
                tol: float | None = None) -> None:
    """Finite outputs, momenta, vis viva; ``tol``: rounding (None), or an ODE path's declared accuracy (its end
    state meets the end condition, e.g. a slip that has stopped, only to that accuracy)."""
    mom_tol, gain_tol = (MOMENTUM_RTOL, GAIN_RTOL) if tol is None else (tol, tol)
    n = exact_here.size
    finite = np.ones(n, dtype=bool)
    for o in _outputs(m, r, n):
        finite &= np.all(np.isfinite(o), axis=1)
    row.note(Check.NON_FINITE, (~finite).astype(float), 0.5, s, ~finite)
    if hasattr(r, "converged"):
        stuck = ~np.asarray(r.converged, dtype=bool).reshape(n)
        row.note(Check.NOT_CONVERGED, stuck.astype(float), 0.5, s, stuck)
    judged = exact_here if not exact_kind else np.ones(n, dtype=bool)
    with np.errstate(all="ignore"):
        if m.momentum is not None:
            before, after, scale = m.momentum(s, r)
            err = np.max(np.abs(np.asarray(after) - np.asarray(before)), axis=-1) / np.where(scale > 0, scale, 1.0)
            err = np.where(finite, err, 0.0)
            bad = err > mom_tol
            row.note(Check.MOMENTUM, err, mom_tol, s, bad & judged, finding=bad & ~judged)
        if m.vis_viva is not None:
            before, after = m.vis_viva(s, r)
            gain = np.where(finite, np.maximum(after - before, 0.0) / np.where(before > 0, before, 1.0), 0.0)
            bad = gain > gain_tol
            row.note(Check.VIS_VIVA_GAIN, gain, gain_tol, s, bad & judged, finding=bad & ~judged)
    if m.impact is not None:
        _impact_invariants(row, m, s, r, judged, finite, INVARIANT_RTOL if tol is None else max(tol, INVARIANT_RTOL))


def _impact_invariants(row: _Row, m: paths.Model, s: dict, r: Any, judged: np.ndarray, finite: np.ndarray,
                       tol: float) -> None:
    """What the model's declared law implies on the returned state (``paths.ImpactCheck``), each a named check."""
    assert m.impact is not None
    n = judged.size
    with np.errstate(all="ignore"):
        c = m.impact(s, r)
        a0 = np.asarray(c.approach0, dtype=float).reshape(n)
        rel1 = np.asarray(c.approach1, dtype=float).reshape(n) / a0
        ratio = np.asarray(c.ratio, dtype=float).reshape(n)
        plastic = np.asarray(c.plastic, dtype=bool).reshape(n)
        law = np.asarray(c.law, dtype=float).reshape(n)
        checks = (
            (Check.STILL_APPROACHING, np.maximum(rel1, 0.0), finite),
            (Check.PLASTIC_END, np.abs(rel1), finite & plastic),
            (Check.NORMAL_RATIO, np.abs(-rel1 - ratio), finite & np.isfinite(ratio)),
            (Check.ENERGY_LAW, law, finite & np.isfinite(law)),
        )
    for check, value, where in checks:
        value = np.where(where, value, 0.0)
        bad = value > tol
        row.note(check, value, tol, s, bad & judged, finding=bad & ~judged)


def _elastic(row: _Row, m: paths.Model, s: dict, name: str, exact_kind: bool) -> None:
    """The frictionless elastic version of the scenes against the textbook (``Model.elastic``)."""
    assert m.elastic is not None
    es, textbook = m.elastic(s)
    es = m.scene({k: v for k, v in es.items() if k != paths.ONES})
    if name != "auto":
        p = m.path(name)
        keep = np.asarray(p.handles(es), dtype=bool)
        if not exact_kind:
            keep &= np.asarray(p.exact_when(es), dtype=bool)
        if not keep.all():
            es = _take(m, es, keep)
            textbook = {k: np.asarray(v)[keep] for k, v in textbook.items()}
    if not np.size(es[paths.ONES]):
        return
    r, _, _ = _solve(m, es, name)
    if r is None:
        return
    with np.errstate(all="ignore"):
        err = np.asarray(m.error(es, r, types.SimpleNamespace(**textbook)), dtype=float)
    err = np.where(np.isfinite(err), err, np.inf)
    row.note(Check.ELASTIC_LIMIT, err, ELASTIC_RTOL, es, err > ELASTIC_RTOL)


def _solve(m: paths.Model, s: dict, path: str) -> tuple[Any | None, str | None, int | None]:
    """The result, or the error and (found by halving) the first scene that raises it."""
    try:
        with np.errstate(all="ignore"):
            return paths.solve(m, s, path), None, None
    except (ArithmeticError, ValueError, FloatingPointError) as exc:
        idx = np.arange(np.shape(s[paths.ONES])[0])
        while idx.size > 1:
            half = idx[: idx.size // 2]
            try:
                with np.errstate(all="ignore"):
                    paths.solve(m, _take(m, s, half), path)
                idx = idx[idx.size // 2:]
            except (ArithmeticError, ValueError, FloatingPointError):
                idx = half
        return None, f"{type(exc).__name__}: {exc}", int(idx[0])


def _boundaries(row: _Row, m: paths.Model, s: dict, r: Any, path: str, rng: np.random.Generator,
                pairs: int) -> None:
    """Continuity across regime (and, for auto, path) boundaries: bisect pairs of scenes in different regimes."""
    n = np.shape(s[paths.ONES])[0]
    key = _regime_key(r, n, path == "auto")
    # each scene's partner differs in one parameter (one component of a vector), scaled by a factor in [−2, 3]:
    # the segment crosses boundaries along one parameter at a time, in its own scale
    names = [p.name for p in m.params if p.name not in m.static]
    which = rng.integers(len(names), size=n)
    comp = rng.integers(3, size=n)
    factor = rng.uniform(-2.0, 3.0, n)
    sb_all = {k: np.array(v) if k not in m.static else v for k, v in s.items()}
    for j, name in enumerate(names):
        sel = which == j
        if name in m.vectors:
            sb_all[name][sel, comp[sel]] *= factor[sel]
        else:
            sb_all[name][sel] *= factor[sel]
    ok = _admissible_values(m, sb_all)
    if path != "auto":
        ok &= np.asarray(m.path(path).handles(sb_all), dtype=bool)
    idx = np.nonzero(ok)[0]
    if idx.size == 0:  # no partner scene the model admits (a batch of one or two): no boundary to look for
        return
    rb, _, _ = _solve(m, _take(m, sb_all, idx), path)
    if rb is None:
        return
    differ = np.any(key[idx] != _regime_key(rb, idx.size, path == "auto"), axis=1)
    a = idx[differ][:pairs]
    if a.size == 0:
        return
    sa, sb = _take(m, s, a), _take(m, sb_all, a)
    ka = key[a]
    lo, hi = np.zeros(a.size), np.ones(a.size)
    alive = np.ones(a.size, dtype=bool)
    p = None if path == "auto" else m.path(path)
    for _ in range(BISECTIONS):
        if np.all(hi - lo <= 2.0**-52):
            break
        mid = 0.5 * (lo + hi)
        sm = _interp(m, sa, sb, mid)
        ok = _admissible_values(m, sm)
        if p is not None:
            ok &= np.asarray(p.handles(sm), dtype=bool)
        alive &= ok
        if not alive.any():
            return
        rm, _, _ = _solve(m, _take(m, sm, alive), path)
        if rm is None:
            return  # the invariant checks report the solver error
        same = np.zeros(a.size, dtype=bool)
        same[alive] = np.all(_regime_key(rm, int(alive.sum()), path == "auto") == ka[alive], axis=1)
        lo = np.where(alive & same, mid, lo)
        hi = np.where(alive & ~same, mid, hi)
    else:
        raise RuntimeError("bisection did not converge")  # 60 halvings always reach 2⁻⁵²
    # a jump does not shrink with the bracket; a steep but continuous change does (by the widening factor)
    width = np.maximum(hi - lo, 2.0**-52)
    wide_lo, wide_hi = np.maximum(lo - WIDEN * width, 0.0), np.minimum(hi + WIDEN * width, 1.0)
    got = []
    for x in (lo, hi, wide_lo, wide_hi):
        sx = _take(m, _interp(m, sa, sb, x), alive)
        rx, _, _ = _solve(m, sx, path)
        if rx is None:
            return
        got.append((sx, rx))
    n_alive = int(alive.sum())
    # a side whose iteration did not converge is that failure, named with its own scene: the outputs of an
    # unconverged iteration say nothing of the continuity of what it solves for (a jump between them is its doing)
    stuck = np.zeros(n_alive, dtype=bool)
    for sx, rx in got[:2]:
        if hasattr(rx, "converged"):
            here = ~np.asarray(rx.converged, dtype=bool).reshape(n_alive)
            row.note(Check.NOT_CONVERGED, here.astype(float), 0.5, sx, here)
            stuck |= here
    same_side = (np.all(_regime_key(got[2][1], n_alive, path == "auto") == ka[alive], axis=1)
                 & np.any(_regime_key(got[3][1], n_alive, path == "auto") != ka[alive], axis=1))
    with np.errstate(all="ignore"):
        jump = np.asarray(m.error(got[0][0], got[0][1], got[1][1]), dtype=float)
        wide = np.asarray(m.error(got[0][0], got[2][1], got[3][1]), dtype=float)
    steep = same_side & (jump * SHRINK < wide)  # shrank with the bracket: continuous
    row.boundary_pairs += n_alive
    row.note(Check.DISCONTINUITY, np.where(steep | stuck, 0.0, jump), CONTINUITY_TOL, got[0][0],
             (jump > CONTINUITY_TOL) & ~steep & ~stuck)


def _slow(row: _Row, m: paths.Model, s: dict, name: str) -> list[Any]:
    """A path of a slow kind (ODE, referee) scene by scene: its budget, its invariants (to its declared accuracy),
    its agreement with ``auto``. Returns its result per scene (None where it failed), for the referee's checks."""
    n = np.shape(s[paths.ONES])[0]
    p = m.path(name)
    budget_hit, errors = np.zeros(n, dtype=bool), np.zeros(n, dtype=bool)
    agree = np.zeros(n)
    results: list[Any] = []
    for i in range(n):
        one = _take(m, s, slice(i, i + 1))
        try:
            with np.errstate(all="ignore"):
                r = paths.solve(m, one, name)
        except budget.ODEBudgetExceeded:
            budget_hit[i] = True
            results.append(None)
            continue
        except (ArithmeticError, ValueError) as exc:
            errors[i] = True
            results.append(None)
            row.worst.setdefault(Check.SOLVER_ERROR.value, {"value": 1.0, "tolerance": 0.5, "message": str(exc),
                                                            "replay": replay(m, s, i, name)})
            continue
        results.append(r)
        _invariants(row, m, one, r, np.ones(1, dtype=bool), True, tol=p.accuracy)
        try:  # auto's own failures are its row's (solver-error there): here the scene is not compared
            with np.errstate(all="ignore"):
                ref = paths.solve(m, one, "auto")
        except (ArithmeticError, ValueError):
            agree[i] = 0.0
            continue
        with np.errstate(all="ignore"):
            agree[i] = float(m.error(one, r, ref)[0])
    row.scenes += n
    row.note(Check.ODE_BUDGET, budget_hit.astype(float), 0.5, s, budget_hit)
    if errors.any():
        row.failures[Check.SOLVER_ERROR.value] = row.failures.get(Check.SOLVER_ERROR.value, 0) + int(errors.sum())
    agree = np.where(np.isfinite(agree), agree, np.inf)
    check = Check.REFEREE_DISAGREES if p.kind is paths.Kind.REFEREE else Check.ODE_DISAGREES
    row.note(check, agree, p.accuracy, s, agree > p.accuracy)
    return results


def _against_referee(rows: dict[str, _Row], m: paths.Model, s: dict, refs: list[Any], accuracy: float,
                     slow: dict[str, list[Any]]) -> None:
    """Every exact path (and ``auto``) against the referee's results on its pool, to the referee's accuracy (or
    the path's own, if coarser); the slow paths (``slow``: their results, scene by scene, on the start of the same
    pool) on the scenes they ran."""
    for name, results in slow.items():
        p = m.path(name)
        for i, (a, b) in enumerate(zip(results, refs, strict=False)):
            if a is None or b is None:
                continue
            one = _take(m, s, slice(i, i + 1))
            with np.errstate(all="ignore"):
                err = np.asarray(m.error(one, a, b), dtype=float)
            err = np.where(np.isfinite(err), err, np.inf)
            tol = max(accuracy, p.accuracy)
            rows[name].note(Check.REFEREE_DISAGREES, err, tol, one, err > tol)
    ok = np.array([r is not None for r in refs])
    if not ok.any():
        return
    sub = _take(m, s, ok)
    ref = paths._merge([(np.arange(int(ok.sum())) == i, r) for i, r in enumerate(x for x in refs if x is not None)],
                       int(ok.sum()), (int(ok.sum()),))
    for name, row in rows.items():
        p = None if name == "auto" else m.path(name)
        if p is not None and (p.kind not in EXACT_KINDS or p.kind in SLOW_KINDS):
            continue
        keep = np.ones(int(ok.sum()), dtype=bool) if p is None else np.asarray(p.handles(sub), dtype=bool)
        if not keep.any():
            continue
        sk = _take(m, sub, keep)
        r, _, _ = _solve(m, sk, name)
        if r is None:
            continue
        with np.errstate(all="ignore"):
            err = np.asarray(m.error(sk, r, _take_result(ref, keep)), dtype=float)
        err = np.where(np.isfinite(err), err, np.inf)
        tol = accuracy if p is None else max(accuracy, p.accuracy)  # an ODE path answers for its own accuracy
        row.note(Check.REFEREE_DISAGREES, err, tol, sk, err > tol)


def _take_result(res: Any, sel: np.ndarray) -> Any:
    values = dict(res.__dict__)
    for k, v in values.items():
        if isinstance(v, np.ndarray) and v.ndim >= 1:
            values[k] = v[sel]
    out = object.__new__(type(res))
    out.__dict__.update(values)
    return out


# ---- the sweep in chunks -----------------------------------------------------------------------------------------
# A model's sweep is cut into tasks that any process may run (``sweep``): the chunks of the closed-form sweep (CHUNK
# scenes each, the last one shorter; chunk c draws from its own stream, ``sweep.chunk_seed(seed, FAST, c)``), then
# the slow paths (ODE, referee) over slices of SLOW_CHUNK scenes of their own pool (drawn from the stream
# ``chunk_seed(seed, SLOW)``). The parent plans the chunks (it draws each one to count the scenes that every path
# handles, so that a path runs on exactly ``scenes`` of them) and merges the rows in chunk order: the report is the
# same on one process, on a pool of any size and on a Dask cluster. Only its timing fields differ (``TIMINGS``).
FAST, SLOW = 0, 1  # the spawn keys of the two kinds of chunk
SLOW_CHUNK = 25  # scenes of the ODE and referee sweeps per task: 40 tasks for the default referee sweep
# the report's fields that are timings (or say what ran the sweep): everything else is the same whoever runs it
TIMINGS = {"report": ("execution",), "model": ("seconds", "throughput")}


def _model_key(m: paths.Model) -> int:
    return sum(m.name.encode())


def _chunk_rng(m: paths.Model, seed: int, *key: int) -> np.random.Generator:
    from .sweep import chunk_seed

    return np.random.default_rng(chunk_seed([seed, _model_key(m)], *key))


def _model_of(ref: str | paths.Model) -> paths.Model:
    return registry.MODELS[ref] if isinstance(ref, str) else ref


def _fast_rows(m: paths.Model) -> dict[str, _Row]:
    rows = {p.name: _Row(m, p.name, p.kind.value) for p in m.paths if p.kind not in SLOW_KINDS}
    rows["auto"] = _Row(m, "auto", "auto")
    return rows


def _fast_chunk(m: paths.Model, seed: int, index: int, k: int, plan: dict[str, tuple[int, bool]],
                pairs: int) -> dict[str, _Row]:
    """Chunk ``index`` of the closed-form sweep: ``k`` scenes drawn from its own stream; each path of ``plan`` on
    the first ``take`` of the scenes it handles (its ε′ = ε copy, elastic limit and boundary pairs where ``first``:
    the path's first chunk)."""
    rng = _chunk_rng(m, seed, FAST, index)
    s, _ = wide_scenes(m, rng, k)
    rows = {name: row for name, row in _fast_rows(m).items() if name in plan}
    for name, row in rows.items():
        take, first = plan[name]
        p = None if name == "auto" else m.path(name)
        sel = np.ones(k, dtype=bool) if p is None else np.asarray(p.handles(s), dtype=bool)
        sel &= np.cumsum(sel) <= take  # no more than the count asked for
        sub = _take(m, s, sel)
        nsub = int(sel.sum())
        r, err, bad = _solve(m, sub, name)
        row.scenes += nsub
        if r is None:
            row.failures[Check.SOLVER_ERROR.value] = row.failures.get(Check.SOLVER_ERROR.value, 0) + 1
            row.worst.setdefault(Check.SOLVER_ERROR.value, {"value": 1.0, "tolerance": 0.5, "message": err,
                                                            "replay": replay(m, sub, int(bad or 0), name)})
            continue
        exact_kind = p is None or p.kind in EXACT_KINDS
        here = np.ones(nsub, dtype=bool) if exact_kind else np.asarray(p.exact_when(sub), dtype=bool)
        _invariants(row, m, sub, r, here, exact_kind)
        if m.impact is not None and first and "epsp" in sub:  # where the ratio is e: ε′ = ε
            eq = m.scene({**{key: v for key, v in sub.items() if key != paths.ONES}, "epsp": sub["eps"]})
            if p is not None and not exact_kind:
                eq = _take(m, eq, np.asarray(p.handles(eq), dtype=bool))
            if np.size(eq[paths.ONES]):
                req, _, _ = _solve(m, eq, name)
                if req is not None:
                    n_eq = int(np.size(eq[paths.ONES]))
                    ok_here = (np.ones(n_eq, dtype=bool) if exact_kind
                               else np.asarray(p.exact_when(eq), dtype=bool))
                    fin = np.ones(n_eq, dtype=bool)
                    for o in _outputs(m, req, n_eq):
                        fin &= np.all(np.isfinite(o), axis=1)
                    _impact_invariants(row, m, eq, req, ok_here, fin, INVARIANT_RTOL)
        if m.elastic is not None and first:
            _elastic(row, m, sub, name, exact_kind)
        if exact_kind and first:  # one chunk of boundary pairs per path
            _boundaries(row, m, sub, r, name, rng, pairs)
    return rows


def _slow_paths(m: paths.Model) -> list[paths.Path]:
    return sorted((q for q in m.paths if q.kind in SLOW_KINDS), key=lambda q: q.kind is paths.Kind.REFEREE)


def _slow_chunk(m: paths.Model, s: dict, start: int, ode_scenes: int,
                referee_scenes: int) -> tuple[dict[str, _Row], dict[str, tuple[int, float, float]]]:
    """Scenes ``start`` … of the slow paths' pool (``s``: this slice of it): each ODE path on those below
    ``ode_scenes``, each referee on those below ``referee_scenes`` and every exact path against it there. Returns
    the rows (the slow paths' own, and the fast paths' referee checks) and, per slow path, its scenes and the
    seconds they took here: on the clock, and of this process's CPU (a busy machine slows the first, not the
    second)."""
    n = int(np.shape(s[paths.ONES])[0])
    rows = _fast_rows(m)
    slow_rows: dict[str, _Row] = {}
    slow_results: dict[str, list[Any]] = {}
    seconds: dict[str, tuple[int, float, float]] = {}
    for p in _slow_paths(m):
        k = min(max((referee_scenes if p.kind is paths.Kind.REFEREE else ode_scenes) - start, 0), n)
        if k == 0:
            continue
        t0, c0 = time.perf_counter(), time.process_time()
        srow = _Row(m, p.name, p.kind.value)
        sub = _take(m, s, slice(0, k))
        results = _slow(srow, m, sub, p.name)
        if p.kind is paths.Kind.REFEREE:
            _against_referee({**rows, **slow_rows}, m, sub, results, p.accuracy, slow_results)
        else:
            slow_results[p.name] = results
        slow_rows[p.name] = srow
        seconds[p.name] = (k, time.perf_counter() - t0, time.process_time() - c0)
    return {**rows, **slow_rows}, seconds


def _task(task: tuple) -> tuple:
    """One chunk, in whichever process runs it: ``("fast", model, seed, index, k, plan, pairs)`` or ``("slow",
    model, scenes, start, ode_scenes, referee_scenes)``; the model by its registry name (or the model itself, run in
    this process)."""
    kind, ref, *args = task
    m = _model_of(ref)
    if kind == "fast":
        return kind, _fast_chunk(m, *args), {}
    rows, seconds = _slow_chunk(m, *args)
    return kind, rows, seconds


class _Plan:
    """The tasks of one model, made as the executor asks for them (the parent draws chunk c+1 while the workers
    run chunk c), and what the parent learns on the way: the scenes drawn, the steps of the progress bar."""

    def __init__(self, m: paths.Model, scenes: int, ode_scenes: int, pairs: int, seed: int,
                 referee_scenes: int) -> None:
        self.m, self.scenes, self.ode_scenes, self.pairs, self.seed = m, scenes, ode_scenes, pairs, seed
        self.referee_scenes = referee_scenes
        self.ref: str | paths.Model = m.name if registry.MODELS.get(m.name) is m else m
        self.drawn = 0
        self.steps: list[int] = []  # per fast chunk: scenes it advances the progress bar by

    def tasks(self) -> Iterator[tuple]:
        m, scenes = self.m, self.scenes
        counts = {name: 0 for name in _fast_rows(m)}
        done = rounds = 0
        # a path that handles only part of the scenes (cushion's elementary one) gets more chunks until it too has
        # run ``scenes`` of them; MAX_ROUNDS bounds the draws for one that would handle almost none
        while min(counts.values()) < scenes and rounds < MAX_ROUNDS * max(1, scenes // CHUNK):
            k = min(CHUNK, max(scenes - done, CHUNK if done >= scenes else 1))
            s, drawn = wide_scenes(m, _chunk_rng(m, self.seed, FAST, rounds), k)
            self.drawn += drawn
            plan: dict[str, tuple[int, bool]] = {}
            for name, have in counts.items():
                if have >= scenes:
                    continue
                handled = k if name == "auto" else int(np.count_nonzero(m.path(name).handles(s)))
                take = min(handled, scenes - have)
                if take:
                    plan[name] = (take, have == 0)
                    counts[name] += take
            self.steps.append(min(k, max(scenes - done, 0)))
            yield ("fast", self.ref, self.seed, rounds, k, plan, self.pairs)
            rounds += 1
            done += k
        n_slow = max(self.ode_scenes, self.referee_scenes)
        pool, _ = wide_scenes(m, _chunk_rng(m, self.seed, SLOW), n_slow)
        for a, b in _chunks(n_slow, SLOW_CHUNK):
            yield ("slow", self.ref, _take(m, pool, slice(a, b)), a, self.ode_scenes, self.referee_scenes)


def _chunks(total: int, size: int) -> list[tuple[int, int]]:
    from .sweep import chunks

    return chunks(total, size)


def _assemble(plan: _Plan, results: list[tuple[tuple, float]]) -> dict[str, Any]:
    """One model's report from its chunks' results (each with the seconds it took), merged in chunk order."""
    m = plan.m
    rows = _fast_rows(m)
    slow_rows = {p.name: _Row(m, p.name, p.kind.value) for p in _slow_paths(m)}
    spent: dict[str, list[float]] = {p.name: [0, 0.0, 0.0] for p in _slow_paths(m)}
    total = 0.0
    for (_, part, seconds), took in results:
        total += took
        for name, r in part.items():
            (rows if name in rows else slow_rows)[name].merge(r)
        for name, (k, sec, cpu) in seconds.items():
            spent[name][0] += k
            spent[name][1] += sec
            spent[name][2] += cpu
    throughput = {}
    for p in _slow_paths(m):
        k, sec, cpu = spent[p.name]
        throughput[p.name] = {"kind": p.kind.value, "scenes": int(k), "seconds": round(sec, 3),
                              "cpu_seconds": round(cpu, 3),
                              "scenes_per_second_per_worker": round(k / sec, 3) if sec > 0 else None,
                              "scenes_per_cpu_second": round(k / cpu, 3) if cpu > 0 else None}
    out = [r.as_dict() for r in rows.values()] + [r.as_dict() for r in slow_rows.values()]
    return {"model": m.name, "section": m.section, "drawn": plan.drawn, "admissible": plan.scenes,
            "seconds": round(total, 1), "throughput": throughput, "rows": out}


def _sweep(plans: Sequence[_Plan], ex: Any, progress: Callable[[str, int], None] | None) -> list[dict[str, Any]]:
    """Every plan's tasks on the executor ``ex``, one stream (a model's slow tasks overlap the next model's fast
    ones); the reports in the plans' order."""
    owner: list[tuple[int, int]] = []  # per task: its plan, and its fast chunk's index (or -1)

    def items() -> Iterator[tuple]:
        for i, plan in enumerate(plans):
            for t in plan.tasks():
                owner.append((i, t[3] if t[0] == "fast" else -1))
                yield t

    def done(index: int, result: tuple, seconds: float) -> None:
        if progress:
            i, chunk = owner[index]
            progress(plans[i].m.name, plans[i].steps[chunk] if chunk >= 0 else 0)

    took: dict[int, float] = {}

    def keep(index: int, result: tuple, seconds: float) -> None:
        took[index] = seconds
        done(index, result, seconds)

    results = ex.map(_task, items(), keep)
    per: list[list[tuple[tuple, float]]] = [[] for _ in plans]
    for index, r in enumerate(results):
        per[owner[index][0]].append((r, took[index]))
    return [_assemble(plan, per[i]) for i, plan in enumerate(plans)]


def stress_model(m: paths.Model, scenes: int, ode_scenes: int, pairs: int, seed: int,
                 progress: Callable[[int], None] | None = None,
                 referee_scenes: int = DEFAULT_REFEREE_SCENES, jobs: int = 1) -> dict[str, Any]:
    """Every path of ``m`` (and ``auto``) over ``scenes`` widened scenes, the ODE over ``ode_scenes``, the referee
    over ``referee_scenes``; on ``jobs`` processes (1: this one; more needs a model of the registry)."""
    from .sweep import executor

    plan = _Plan(m, scenes, ode_scenes, pairs, seed, referee_scenes)
    with executor(jobs if isinstance(plan.ref, str) else 1) as ex:
        return _sweep([plan], ex, None if progress is None else (lambda _, k: progress(k)))[0]


# ---- §I sweep --------------------------------------------------------------------------------------------------
def sweep() -> dict[str, float]:
    """Eq. (7) of §I over mass ratios 1e-12 … 1e12, ε and ε′ at and near 0 and 1, speeds 1e-9 … 1e6."""
    ratio = np.logspace(-12, 12, 49)
    eps = np.array([0.0, 1e-12, 0.25, 0.5, 1 - 1e-12, 1.0])
    speed = np.array([1e-9, 1.0, 1e6])
    Mp, e1, e2, V0, V0p = np.meshgrid(ratio, eps, eps, speed, [0.0, -0.5], indexing="ij")
    V0p = V0p * V0
    M = np.ones_like(Mp)
    r = impact.direct_impact(M, Mp, V0, V0p, eps=e1, epsp=e2)
    p0 = M * V0 + Mp * V0p
    scale_p = M * np.abs(V0) + Mp * np.abs(V0p) + Mp * np.abs(r.V1p) + M * np.abs(r.V1)
    mom = np.abs(M * r.V1 + Mp * r.V1p - p0) / scale_p
    T0 = M * V0**2 + Mp * V0p**2 + M * r.V1**2 + Mp * r.V1p**2
    law = impact.vis_viva_loss(M, V0 - r.V1, e1, Mp, r.V1p - V0p, e2)
    energy = np.abs(r.vis_viva_lost - law) / T0
    gained = np.maximum(-r.vis_viva_lost / T0, 0.0)
    return {"scenes": float(M.size), "non_finite": float(np.sum(~np.isfinite(r.V1) | ~np.isfinite(r.V1p))),
            "max_momentum_rel_error": float(mom.max()), "max_energy_law_rel_error": float(energy.max()),
            "max_energy_gained_rel": float(gained.max())}


def sweep_ok(res: dict[str, float]) -> bool:
    return (res["non_finite"] == 0 and res["max_momentum_rel_error"] < TOL and res["max_energy_law_rel_error"] < TOL
            and res["max_energy_gained_rel"] < TOL)


# ---- the whole run ---------------------------------------------------------------------------------------------
def run(models: Sequence[str] = (), scenes: int = DEFAULT_SCENES, ode_scenes: int = DEFAULT_ODE_SCENES,
        pairs: int = DEFAULT_PAIRS, seed: int = 12, progress: Callable[[str, int], None] | None = None,
        referee_scenes: int | None = None, jobs: int | None = None, scheduler: str | None = None) -> dict:
    """The stress report of the named models (default: all); ``progress(model, scenes_done)``; ``referee_scenes``
    by default ``DEFAULT_REFEREE_SCENES``, at most ``scenes`` (a small run stays small). The chunks run on
    ``jobs`` processes (None: one per core; 1: this process) or, given ``scheduler`` (``tcp://host:port``), on that
    Dask cluster (``sweep.executor``); the report is the same whichever runs them, but for its timing fields
    (``TIMINGS``, ``without_timings``)."""
    from .sweep import executor

    names = list(models) or list(registry.MODELS)
    if referee_scenes is None:
        referee_scenes = min(DEFAULT_REFEREE_SCENES, scenes)
    plans = [_Plan(registry.MODELS[name], scenes, ode_scenes, pairs, seed, referee_scenes) for name in names]
    t0 = time.perf_counter()
    with executor(jobs, scheduler) as ex:
        out = _sweep(plans, ex, progress)
        execution = ex.describe()
    execution["wall_seconds"] = round(time.perf_counter() - t0, 1)
    execution["throughput"] = _throughput(out, execution["workers"], execution["wall_seconds"])
    failures = sum(sum(r["failures"].values()) for mod in out for r in mod["rows"])
    eq7 = sweep()
    return {"seed": seed, "scenes_per_path": scenes, "ode_scenes": ode_scenes, "referee_scenes": referee_scenes,
            "boundary_pairs": pairs,
            "tolerances": {"momentum": MOMENTUM_RTOL, "vis_viva_gain": GAIN_RTOL, "continuity": CONTINUITY_TOL,
                           "ode": "the ODE path's declared accuracy (also its vis viva gain)", "eq7_sweep": TOL,
                           "still-approaching": INVARIANT_RTOL, "plastic-end": INVARIANT_RTOL,
                           "normal-ratio": INVARIANT_RTOL, "energy-law": INVARIANT_RTOL,
                           "elastic-limit": ELASTIC_RTOL,
                           "referee-disagrees": "the referee's declared accuracy"},
            "models": out, "eq7_sweep": eq7, "failures": failures + (0 if sweep_ok(eq7) else 1),
            "verdict": "stable" if failures == 0 and sweep_ok(eq7) else "UNSTABLE", "execution": execution}


def _throughput(models: list[dict], workers: int, wall: float) -> dict[str, Any]:
    """The slow sweeps' throughput per core: scenes over the seconds they took in the workers that ran them (each
    worker one core), per kind (ODE, referee) over every model; and per second of the workers' CPU (what a core
    gives when nothing else competes for it)."""
    out: dict[str, Any] = {}
    for kind in (paths.Kind.ODE.value, paths.Kind.REFEREE.value):
        k = sum(t["scenes"] for mod in models for t in mod["throughput"].values() if t["kind"] == kind)
        sec = sum(t["seconds"] for mod in models for t in mod["throughput"].values() if t["kind"] == kind)
        cpu = sum(t["cpu_seconds"] for mod in models for t in mod["throughput"].values() if t["kind"] == kind)
        out[kind] = {"scenes": k, "seconds": round(sec, 3), "cpu_seconds": round(cpu, 3),
                     "scenes_per_second_per_worker": round(k / sec, 3) if sec > 0 else None,
                     "scenes_per_cpu_second": round(k / cpu, 3) if cpu > 0 else None}
    out["workers"] = workers
    out["wall_seconds"] = wall
    return out


def without_timings(rep: dict) -> dict:
    """The report without its timing fields (``TIMINGS``: the run's ``execution``, each model's ``seconds`` and
    ``throughput``): what is the same whichever runs the sweep, on one process, a pool or a Dask cluster."""
    out = {k: v for k, v in rep.items() if k not in TIMINGS["report"]}
    out["models"] = [{k: v for k, v in mod.items() if k not in TIMINGS["model"]} for mod in rep["models"]]
    return out


def _g(x: float) -> str:
    return f"{x:.2g}"


def _execution_lines(ex: dict | None) -> list[str]:
    """What ran the sweep and the slow sweeps' throughput per core (timings: they differ from run to run)."""
    if not ex:
        return []
    where = {"in-process": "in one process", "process-pool": f"on a pool of {ex['workers']} processes",
             "dask": f"on the Dask cluster {ex.get('scheduler', '')} ({ex['workers']} workers)"}[ex["executor"]]
    per = [f"{kind} {t['scenes_per_second_per_worker']:.3g} scenes/s per worker, {t['scenes_per_cpu_second']:.3g} per "
           f"CPU second ({t['scenes']:,} scenes, {t['seconds']:.3g} s in the workers)"
           for kind, t in ex["throughput"].items() if isinstance(t, dict) and t["scenes_per_second_per_worker"]
           and t["scenes_per_cpu_second"]]
    return [f"Run {where} in {ex['wall_seconds']:g} s (a timing: it differs from run to run, the rest of the report "
            f"does not). Throughput per core of the slow sweeps, each scene integrated: {'; '.join(per) or 'none'}.",
            ""]


def to_markdown(rep: dict) -> str:
    lines = [f"# Stress: every model × path (seed {rep['seed']}, {rep['scenes_per_path']:,} scenes per exact "
             f"path, {rep['ode_scenes']} per ODE path, {rep.get('referee_scenes', 0):,} per referee)", "",
             f"Verdict: **{rep['verdict']}** — {rep['failures']} failure(s). Tolerances: momentum "
             f"{MOMENTUM_RTOL:g} relative, vis viva gain {GAIN_RTOL:g}, continuity across regime boundaries "
             f"{CONTINUITY_TOL:g}, ODE against auto: its declared accuracy; impact models: still-approaching, "
             f"plastic-end, normal-ratio and energy-law {INVARIANT_RTOL:g} (of the approach speed, or of the law's "
             f"terms), elastic-limit {ELASTIC_RTOL:g}, every exact path against the referee: the referee's declared "
             "accuracy (or the path's own, if coarser).", "",
             *_execution_lines(rep.get("execution")),
             "| model | path | kind | scenes | boundary pairs | failures | margin (largest / tolerance) |",
             "|---|---|---|---|---|---|---|"]
    worst, findings, explained = [], [], []
    for mod in rep["models"]:
        for r in mod["rows"]:
            fails = ", ".join(f"{k}: {v}" for k, v in r["failures"].items()) or "none"
            margin = ", ".join(f"{k} {_g(v)}" for k, v in r["margin"].items()
                               if k not in ("non-finite", "ode-budget", "not-converged"))
            lines.append(f"| {r['model']} | {r['path']} | {r['kind']} | {r['scenes']:,} | {r['boundary_pairs']} | "
                         f"{fails} | {margin} |")
            for k, w in r["worst"].items():
                worst.append(f"- {r['model']} / {r['path']}, {k}: {_g(w['value'])} (tolerance {_g(w['tolerance'])})"
                             f"{'; ' + w['message'] if 'message' in w else ''}\n  `{w['replay']}`")
            for k, x in r["explained"].items():
                explained.append(f"- {r['model']} / {r['path']}, {k}: {x['scenes']} scene(s), largest {_g(x['max'])}: "
                                 f"{x['reason']}\n  `{x['replay']}`")
            for k, f in r["findings"].items():
                region = ", ".join(f"{p} ∈ [{_g(a)}, {_g(b)}]" for p, (a, b) in f["region"].items())
                findings.append(f"- {r['model']} / {r['path']}: {k} in {f['scenes']:,} of {r['scenes']:,} scenes "
                                f"(largest {_g(f['max'])}), outside the region where the path declares itself "
                                f"exact; region of the scenes: {region}\n  worst: `{f['replay']}`")
    closest = [f"- {r['model']} / {r['path']}: {r['closest']['check']} at {_g(r['closest']['ratio'])} of its "
               f"tolerance\n  `{r['closest']['replay']}`" for mod in rep["models"] for r in mod["rows"] if r["closest"]]
    lines += ["", "## Failures: the worst scene of each", "", *(worst or ["none"]), "",
              "## The scene nearest to failing, per model and path", "", *(closest or ["none"]), "",
              "## Explained failures (understood, not counted)", "", *(explained or ["none"]), "",
              "## Findings: Résal's approximations outside their premises", "", *(findings or ["none"]), "",
              "## §I eq. (7) over extreme mass ratios, coefficients and speeds", "",
              "| check | value |", "|---|---|", *(f"| {k} | {v:.3g} |" for k, v in rep["eq7_sweep"].items())]
    return "\n".join(lines) + "\n"


def write(rep: dict, out: Path) -> list[Path]:
    """``stress.json`` and ``stress.md`` in ``out``, the folder written whole (``report.write_folder``: a staging
    folder swapped in; a full disk or a signal leaves the previous report whole, the user's files are kept)."""
    from .report import write_folder

    out.parent.mkdir(parents=True, exist_ok=True)
    files = {"stress.json": json.dumps(rep, indent=2, ensure_ascii=False, allow_nan=False) + "\n",
             "stress.md": to_markdown(rep)}
    write_folder(out, files)
    return [out / n for n in files]
