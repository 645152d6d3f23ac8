"""Where the time of one scene goes: ``paths.solve(model, model.scene(values), "auto")`` for N = 1, split.

A micro-benchmark of the overhead around the physics (issue 22): building the scene (``Model.scene``), the
dispatch of ``solve`` (admissibility, the cheapest path's predicates, flattening, relabelling the result), the
path's own run (the physics and the assembly of its result), and of that run the assembly of the result
dataclass alone. Timed with ``time.perf_counter``, the minimum over repeats after a warm-up; no I/O.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

from . import paths, registry

__all__ = ["COEFFICIENTS", "n1_scene", "n1_times"]

# the coefficients no model has a default for (no printed value of the paper is one): typical measured values
COEFFICIENTS: dict[str, Any] = {"eps": 0.3, "epsp": 0.4, "f": 0.2, "j": 0.2, "nu": 0.5, "v": [1.0, 0.2, 0.0]}


def n1_scene(m: paths.Model) -> dict[str, Any]:
    """The values of one scene of ``m``: its defaults, and ``COEFFICIENTS`` for the parameters without one."""
    return {p.name: COEFFICIENTS[p.name] for p in m.params if p.default is None}


def _best(fn: Callable[[], Any], repeat: int) -> float:
    fn()  # warm-up
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best * 1e6


def n1_times(models: Iterable[str] | None = None, repeat: int = 2000,
             values: Mapping[str, Mapping[str, Any]] | None = None) -> dict[str, dict[str, Any]]:
    """Per model (all by default), in microseconds, the minimum over ``repeat`` runs of one scene (``values``
    per model, else ``n1_scene``): ``total`` = ``scene`` (``Model.scene``) + ``solve`` (``paths.solve`` on the
    built scene); ``run`` the path ``auto`` chose run as ``solve`` runs it (on the scene's numpy floats
    where the path declares ``scalar``, else on the flattened scene), ``dispatch`` = ``solve`` − ``run``;
    ``assembly`` the construction of the result dataclass from its fields (part of ``run``), ``physics`` =
    ``run`` − ``assembly``; and ``path``, the name of the path ``auto`` chose. The parts are timed apart, so they
    add up to the totals only to within the timer's noise."""
    out: dict[str, dict[str, Any]] = {}
    for name in (models if models is not None else registry.MODELS):
        m = registry.model(name)
        v = dict(values[name]) if values is not None and name in values else n1_scene(m)
        scene = m.scene(v)
        res = paths.solve(m, scene, "auto")
        p = next(q for q in m.paths if q.code == int(res.path.reshape(-1)[0]))
        # one scene: the path that took it runs on its numpy floats where it declares ``scalar``, whether it is
        # the cheapest path (``solve``) or a later one taking the whole (``_auto_general``)
        single = p.scalar and np.shape(scene[paths.ONES]) in ((), (1,))
        one = paths._one(m, scene) if single else None
        flat = one if one is not None else paths._flatten(m, scene)[2]  # what ``solve`` runs the path on
        raw = p.run(flat)
        fields = {f.name: getattr(raw, f.name) for f in dataclasses.fields(raw)}
        kind = type(raw)
        row = {"path": p.name,
               "total": _best(lambda m=m, v=v: paths.solve(m, m.scene(v), "auto"), repeat),
               "scene": _best(lambda m=m, v=v: m.scene(v), repeat),
               "solve": _best(lambda m=m, s=scene: paths.solve(m, s, "auto"), repeat),
               "run": _best(lambda p=p, s=flat: p.run(s), repeat),
               "assembly": _best(lambda t=kind, f=fields: paths.result(t, **f), repeat)}
        row["dispatch"] = max(row["solve"] - row["run"], 0.0)
        row["physics"] = max(row["run"] - row["assembly"], 0.0)
        out[name] = row
    return out
