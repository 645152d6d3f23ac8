"""The speed targets of issue 34, read from a benchmark report (``bench.run``): each figure as measured, its target,
and whether it is met, beside the machine's calibration loop (so that a figure from another machine can be scaled
before it is compared). Standard library only; pooltool's figures (``pooltool_side``) where pooltool is installed."""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass
from typing import Any

__all__ = ["CALIBRATION_LOOP", "POOLTOOL_TARGET", "Target", "calibration", "rows", "terminal_lines", "to_markdown"]

CALIBRATION_LOOP = 1_000_000  # iterations of the pure-Python loop timed by ``calibration``


@dataclass(frozen=True)
class Target:
    """One figure of issue 34's table: ``now`` as measured (None: not in this report, e.g. `make all` under
    --quick), ``target`` its bound, ``met`` whether ``now`` is within it (None when not measured)."""

    what: str
    unit: str
    now: float | None
    target: float
    larger_is_better: bool
    source: str
    met: bool | None

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def calibration(repeat: int = 5) -> dict[str, float]:
    """The machine's speed on two fixed loops, the minimum over ``repeat`` runs: a pure-Python loop of float
    multiply-adds (ns per iteration: the cost of interpreted code, what one scene's Python pays) and numpy's
    ``a * b + c`` over 10⁶ doubles (ns per element: the floor of a batch)."""
    import numpy as np

    def py() -> float:
        x, t0 = 0.0, time.perf_counter()
        for i in range(CALIBRATION_LOOP):
            x = x * 0.999 + i
        return (time.perf_counter() - t0) / CALIBRATION_LOOP

    a, b, c = (np.random.default_rng(k).random(1_000_000) for k in range(3))
    out = np.empty_like(a)

    def vec() -> float:
        t0 = time.perf_counter()
        np.multiply(a, b, out=out)
        np.add(out, c, out=out)
        return (time.perf_counter() - t0) / a.size

    return {"python_ns_per_iteration": min(py() for _ in range(repeat)) * 1e9,
            "numpy_ns_per_element": min(vec() for _ in range(repeat)) * 1e9}


# model id → what the issue calls it; one scene through `auto`, µs (issue 34, item 1)
_ONE_SCENE = (("direct-impact", "one scene: direct impact", 30.0), ("plane-impact", "one scene: plane", 30.0),
              ("cloth-slide", "one scene: cloth-slide", 30.0), ("cue-stroke", "one scene: cue-stroke", 30.0),
              ("cushion-impact", "one scene: cushion-impact", 30.0),
              ("spheres-free", "one scene: two free balls", 60.0),
              ("spheres-cloth", "one scene: two balls on the cloth", 60.0))
BATCH_TARGET = 1e6  # §VI on the cloth, scenes/s through auto (item 2)
BATCH_ERROR = 1e-10  # … at this error against the referee
MAKE_ALL_COLD, MAKE_ALL_CACHED = 5.0, 0.5  # seconds (item 3)
POOLTOOL_TARGET = 100.0  # pooltool's default model's µs per collision over ours per scene in a batch (item 5)


def _met(now: float | None, target: float, larger: bool) -> bool | None:
    if now is None:
        return None
    return now >= target if larger else now <= target


def rows(report: dict[str, Any]) -> list[Target]:
    """Issue 34's table from a benchmark report: what the report measured, each against its target."""
    out = []
    n1 = report.get("n1", {})
    for model, what, target in _ONE_SCENE:
        t = n1.get(model, {}).get("total")  # µs, minimum over repeats, through auto
        out.append(Target(what, "µs", t, target, False, f"n1[{model}].total", _met(t, target, False)))
    cloth = next((m for m in report.get("models", []) if m["model"] == "spheres-cloth"), None)
    auto = next((r for r in cloth["paths"] if r["path"] == "auto"), None) if cloth else None
    if auto is not None:
        n = auto["scenes_timed"]
        rate, err = auto["scenes_per_second"], auto["where_exact"]["max_error"]
        out.append(Target(f"§VI cloth: batch of {n:,}, auto", "scenes/s", rate, BATCH_TARGET, True,
                          "models[spheres-cloth].auto.scenes_per_second", _met(rate, BATCH_TARGET, True)))
        out.append(Target(f"§VI cloth: auto's error, {auto['where_exact']['scenes']} scenes", "relative", err,
                          BATCH_ERROR, False, "models[spheres-cloth].auto.where_exact.max_error (against the referee)",
                          _met(err, BATCH_ERROR, False)))
    kinds = report.get("cloth_kinds")
    if kinds is not None:  # item 2: heterogeneous k, k′ not slower than homogeneous (their rates' ratio ≥ 1)
        rate = kinds["scenes_per_second"]
        for key, what in (("kinds", f"balls of {len(kinds['kinds'])} kinds"), ("per_scene", "k, k′ per scene")):
            ratio = rate[key] / rate["homogeneous"]
            out.append(Target(f"§VI cloth: {what} ÷ k = k′", "×", ratio, 1.0, True,
                              f"cloth_kinds.scenes_per_second.{key} / .homogeneous", _met(ratio, 1.0, True)))
    out += _pooltool_rows(report)
    ma = report.get("make_all")
    for key, what, target in (("cold", "make all, cold (median)", MAKE_ALL_COLD),
                              ("cached", "make all, nothing changed (median)", MAKE_ALL_CACHED)):
        t = ma[key]["median_wall"] if ma else None
        out.append(Target(what, "s", t, target, False, f"make_all.{key}.median_wall", _met(t, target, False)))
    return out


def _auto_us(report: dict[str, Any], model: str) -> float | None:
    """Our µs per scene in a batch through ``auto``: the inverse of the throughput the report measured."""
    m = next((m for m in report.get("models", []) if m["model"] == model), None)
    auto = next((r for r in m["paths"] if r["path"] == "auto"), None) if m else None
    return 1e6 / auto["scenes_per_second"] if auto and auto["scenes_per_second"] > 0 else None


def _pooltool_rows(report: dict[str, Any]) -> list[Target]:
    """pooltool's default model's time per collision over ours per scene (a batch through ``auto``), for each
    interaction ``pooltool_side`` timed; "not measured" where pooltool is not installed or a figure is missing."""
    from .pooltool_side import INTERACTIONS

    pt = report.get("pooltool") or {}
    out = []
    for interaction, (ours, what, _) in INTERACTIONS.items():
        models = (pt.get("interactions") or {}).get(interaction, {}).get("models", [])
        default = next((m for m in models if m["default"]), None)
        theirs, mine = (default or {}).get("us_per_collision"), _auto_us(report, ours)
        ratio = theirs / mine if theirs is not None and mine is not None else None
        model = default["model"] if default else "its default model"
        out.append(Target(f"pooltool ÷ ours: {what}", "×", ratio, POOLTOOL_TARGET, True,
                          f"pooltool.interactions[{interaction}] ({model}, µs per collision) over "
                          f"1/models[{ours}].auto.scenes_per_second (µs per scene)",
                          _met(ratio, POOLTOOL_TARGET, True)))
    return out


def _fmt(x: float, unit: str) -> str:
    return f"{x:.1e}" if unit == "relative" else f"{x:.3g}"


def _fmt_apart(x: float, target: float, unit: str) -> str:
    """``x`` as ``_fmt`` shows it, with more digits where that would read as the target itself (60.04 µs against
    ≤ 60 µs shown "60": a miss that reads as a tie)."""
    shown, digits = _fmt(x, unit), 3
    while x != target and shown == _fmt(target, unit) and digits < 17:
        digits += 1
        shown = f"{x:.{digits - 1}e}" if unit == "relative" else f"{x:.{digits}g}"
    return shown


def _cells(t: dict[str, Any]) -> tuple[str, str, str, str]:
    unit = "" if t["unit"] == "relative" else f" {t['unit']}"
    now = "not measured" if t["now"] is None else f"{_fmt_apart(t['now'], t['target'], t['unit'])}{unit}"
    bound = ("≥ " if t["larger_is_better"] else "≤ ") + _fmt(t["target"], t["unit"]) + unit
    return t["what"], now, bound, {True: "yes", False: "no", None: "—"}[t["met"]]


def terminal_lines(targets: list[dict[str, Any]], cal: dict[str, float] | None) -> list[str]:
    """The targets as plain lines of at most 80 characters (the terminal's table; its words as bench.md's)."""
    rows = [("issue 34's figure", "now", "target", "met"), *(_cells(t) for t in targets)]
    w = [max(len(r[i]) for r in rows) for i in range(4)]
    out = ["  ".join((r[0].ljust(w[0]), r[1].rjust(w[1]), r[2].rjust(w[2]), r[3])).rstrip() for r in rows]
    out.insert(1, "─" * len(out[0]))
    if cal:
        out.append(f"calibration: Python loop {cal['python_ns_per_iteration']:.1f} ns/iteration, numpy a·b + c "
                   f"{cal['numpy_ns_per_element']:.2f} ns/element")
    return out


def pooltool_markdown(pooltool: dict[str, Any] | None) -> list[str]:
    """bench.md's lines on pooltool: each of its models timed per collision, or why there is no column."""
    if not pooltool:
        return ["pooltool is not installed here (optional, never a dependency): no side-by-side column. With "
                "pooltool in the same environment, `resal bench` times its collisions beside ours."]
    lines = [f"pooltool {pooltool['version']}, in this process, per collision (the fastest of {pooltool['repeat']}, "
             "each on fresh copies; its first call apart: numba compiles on first use):", "",
             "| interaction | our model | pooltool's model | µs per collision | first call (s) |",
             "|---|---|---|---|---|"]
    for inter in pooltool["interactions"].values():
        for m in inter["models"]:
            name = f"{m['model']} (its default)" if m["default"] else m["model"]
            us = "—" if m["us_per_collision"] is None else f"{m['us_per_collision']:.3g}"
            first = "—" if m["first_call_s"] is None else f"{m['first_call_s']:.3g}"
            lines.append(f"| {inter['what']} | {inter['ours']} | {name} | {us} | {first} |")
    return lines


def to_markdown(targets: list[dict[str, Any]], cal: dict[str, float] | None,
                pooltool: dict[str, Any] | None) -> list[str]:
    """bench.md's section of the targets, the calibration and pooltool's column (``pooltool_markdown``)."""
    lines = ["## Issue 34's targets, as measured here", "",
             "| what | now | target | met |", "|---|---|---|---|"]
    for t in targets:
        what, now, bound, met = _cells(t)
        lines.append(f"| {what} | {now} | {bound} | {'**no**' if met == 'no' else met} |")
    lines.append("")
    if cal:
        lines.append(f"Calibration of this machine: a pure-Python loop of float multiply-adds takes "
                     f"{cal['python_ns_per_iteration']:.1f} ns per iteration; numpy's a·b + c "
                     f"{cal['numpy_ns_per_element']:.2f} ns per element (scale a figure from another machine by "
                     "the ratio of these before comparing it).")
    lines += pooltool_markdown(pooltool)
    lines.append("")
    return lines
