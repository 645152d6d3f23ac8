"""Experiment kinds: each module reads its ``params`` (``parse``), lists the quantities it computes
(``QUANTITIES``) and the modern values it can stand beside (``MODERN``), and runs (``run``)."""

from __future__ import annotations

from types import ModuleType

from . import ballball, cloth, cue, cushion, headon, impact_law, oblique, pendulum, rebound, restitution, ricochet

KINDS: dict[str, ModuleType] = {
    "cloth": cloth, "cue": cue, "cushion": cushion, "impact_law": impact_law, "pendulum": pendulum, "rebound": rebound,
    "oblique_markers": oblique, "ricochet": ricochet, "spheres": ballball, "head_on": headon,
    "restitution": restitution,
}
