"""pooltool beside resal (issue 34, item 5): where pooltool is installed (an optional comparison, never a
dependency), the time it takes to resolve one collision of the kinds resal's models compute, timed in this process
on this machine, so that ``resal bench`` can put its figures beside ours.

Two of pooltool's interactions stand beside two of our models:

- ``ball_ball``, two balls (on the cloth: pooltool resolves the collision alone): our ``spheres-cloth`` (§VI);
- ``ball_linear_cushion``, a ball against a straight cushion: our ``cushion-impact`` (§IV).

Each is timed with the model pooltool's default resolver uses and with every other model pooltool ships for it,
on one typical scene:

- the two balls: a rolling ball with side spin, 1 m/s with a sideways 0.2 m/s, meets one at rest;
- the cushion: a ball with spin, 1 m/s into the cushion and 0.3 m/s along it.

A collision is timed alone, as a pooltool shot meets it: fresh copies of the balls made beforehand, the resolver
applied in place. The figure is the minimum over ``repeat`` collisions after a first call, whose time is reported
apart: pooltool compiles its models with numba on first use.

Nothing of pooltool is imported unless ``measure`` is called and pooltool is installed. Standard library only
otherwise (layer 0)."""

from __future__ import annotations

import importlib
import importlib.util
import time
from collections.abc import Callable
from typing import Any

__all__ = ["INTERACTIONS", "installed", "measure", "version"]

# pooltool's interaction → (our model, what the two are, where pooltool keeps its models of it)
INTERACTIONS: dict[str, tuple[str, str, str]] = {
    "ball_ball": ("spheres-cloth", "ball–ball", "pooltool.physics.resolve.ball_ball"),
    "ball_linear_cushion": ("cushion-impact", "cushion", "pooltool.physics.resolve.ball_cushion"),
}


def installed() -> bool:
    """Whether pooltool can be imported here."""
    return importlib.util.find_spec("pooltool") is not None


def version() -> str | None:
    """pooltool's version where it is installed, else None."""
    if not installed():
        return None
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as dist_version

    try:
        return dist_version("pooltool-billiards")
    except PackageNotFoundError:
        return "installed"


def _best(resolve: Callable[..., Any], make: Callable[[], tuple[Any, ...]], repeat: int) -> tuple[float, float]:
    """(seconds of the first call, µs of the fastest of ``repeat`` later calls), each on its own fresh copies."""
    args = [make() for _ in range(repeat + 1)]
    t0 = time.perf_counter()
    resolve(*args[0])
    first = time.perf_counter() - t0
    best = float("inf")
    for a in args[1:]:
        t0 = time.perf_counter()
        resolve(*a)
        best = min(best, time.perf_counter() - t0)
    return first, best * 1e6


def _scenes(pt: Any) -> dict[str, Callable[[], tuple[Any, ...]]]:
    """Fresh objects for one collision of each interaction (module docstring), as pooltool's own types."""
    R = pt.Ball.create("cue").params.R
    cushion = pt.Table.default().cushion_segments.linear["3"]  # the straight cushion along x = 0

    def balls() -> tuple[Any, Any]:
        a, b = pt.Ball.create("cue", xy=(0.5, 0.5)), pt.Ball.create("1", xy=(0.5 + 2 * R, 0.5))
        a.state.rvw[1] = [1.0, 0.2, 0.0]
        a.state.rvw[2] = [-6.0, 30.0, 1.0]
        a.state.s = 2  # sliding
        return a, b

    def ball_and_cushion() -> tuple[Any, Any]:
        a = pt.Ball.create("cue", xy=(R, 0.5))
        a.state.rvw[1] = [-1.0, 0.3, 0.0]
        a.state.rvw[2] = [-10.0, -30.0, 2.0]
        a.state.s = 2
        return a, cushion.copy()

    return {"ball_ball": balls, "ball_linear_cushion": ball_and_cushion}


def _models(pt_resolver: Any, interaction: str) -> list[tuple[str, Any, bool]]:
    """(name, instance, whether pooltool's default) for each model pooltool ships for ``interaction``."""

    default = getattr(pt_resolver.default_resolver(), interaction)
    out = [(type(default).__name__, default, True)]
    if interaction == "ball_ball":
        from pooltool.physics.resolve.ball_ball import _ball_ball_model_registry as registry
    else:
        from pooltool.physics.resolve.ball_cushion import _ball_lcushion_model_registry as registry
    for cls in registry:
        if cls is type(default):
            continue
        try:
            out.append((cls.__name__, cls(), False))
        except TypeError:  # a model that needs arguments pooltool gives it no default for: left out, said so
            out.append((cls.__name__, None, False))
    return out


def measure(repeat: int = 2000, progress: Callable[[str], None] | None = None) -> dict[str, Any] | None:
    """pooltool's time per collision (µs, the fastest of ``repeat``) for each of its models of each interaction of
    ``INTERACTIONS``, with the first call's seconds; None where pooltool is not installed."""
    if not installed():
        return None
    pt = importlib.import_module("pooltool")
    pt_resolver = importlib.import_module("pooltool.physics.resolve.resolver")
    scenes = _scenes(pt)
    out: dict[str, Any] = {"version": version(), "repeat": repeat, "interactions": {}}
    for interaction, (ours, what, _) in INTERACTIONS.items():
        rows = []
        for name, model, default in _models(pt_resolver, interaction):
            if model is None:
                rows.append({"model": name, "default": default, "us_per_collision": None, "first_call_s": None,
                             "why": "needs arguments pooltool has no default for"})
                continue
            if progress:
                progress(f"pooltool: {interaction}, {name}")
            first, us = _best(lambda *a, m=model: m.resolve(*a, inplace=True), scenes[interaction], repeat)
            rows.append({"model": name, "default": default, "us_per_collision": us, "first_call_s": first})
        out["interactions"][interaction] = {"ours": ours, "what": what, "models": rows}
    return out
