"""The measured coverage of ``resal fit``'s intervals (``coverage.json``, made by ``python -m reproductions.coverage``),
read and rendered for ``resal fit KIND --help``, the fits' bootstrap notes and docs/fit.md. JSON only: no numpy,
so a help page does not pay for the fitting code."""

from __future__ import annotations

import functools
import json
from pathlib import Path
from typing import Any

__all__ = ["TABLE", "boot_range", "help_lines", "kind_rows", "load", "markdown"]

TABLE = Path(__file__).resolve().parent / "coverage.json"


def load(path: Path = TABLE) -> dict[str, Any]:
    """The stored table (cached for the shipped one)."""
    return _stored() if path == TABLE else json.loads(path.read_text(encoding="utf-8"))


@functools.lru_cache(maxsize=1)
def _stored() -> dict[str, Any]:
    """The shipped table; an install without it (a broken one: the wheel ships it) prints no coverage rather than
    failing every help page, and tests/test_fit_coverage_table.py fails on it."""
    try:
        return json.loads(TABLE.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return {"cells": []}


def _pct(hits: int, given: int, series: int) -> str:
    if not given:
        return "no interval"
    return f"{100 * hits / given:.1f} %" + ("" if given == series else f" of {given}")


SYMBOL = {"e": "e", "eps": "ε", "epsp": "ε′", "nu": "ν", "f": "f"}


def _truth(t: dict[str, float]) -> str:
    return ", ".join(f"{SYMBOL.get(k, k)} {v:g}" for k, v in t.items())


PARAM = {"e": "e", "eps": "ε", "pendulum.eps": "ε", "pendulum.epsp": "ε′", "e.ratio0.333333": "e (M′/M = 1/3)",
         "e.ratio1": "e (M′/M = 1)", "positions.nu": "ν", "positions.A": "A", "positions.u": "f tan α0",
         "positions.x0": "x0", "times.nu": "ν (acoustic)", "times.zeta1": "ζ1", "times.t0": "t0",
         "joint-physical.f": "f", "bounces.nu": "ν", "bounces.T1": "T1", "bounces.t0": "t0",
         "ball-ball.f_bb": "f", "ball-ball.e": "e", "joint.f": "f (both)", "joint.e": "e (both)",
         "alpha1.f": "f (α1)", "alpha1.e": "e (α1)", "throw.f": "f (throw)", "throw.e": "e (throw)"}


def cells(kind: str, table: dict[str, Any] | None = None) -> list[dict[str, Any]]:
    return [c for c in (load() if table is None else table)["cells"] if c["kind"] == kind]


def kind_rows(kind: str, table: dict[str, Any] | None = None) -> list[tuple[str, str, list[str]]]:
    """Per (estimate id, interval: "95" or "boot") of ``kind``: its coverage at each true value, in the cells' order
    ("—" where not measured, "no interval" where no series gave one, "… of n" where only n of them did)."""
    cs = cells(kind, table)
    order: dict[tuple[str, str], list[str]] = {}
    for i, c in enumerate(cs):
        for r in c["rows"]:
            if r["series"]:
                order.setdefault((r["id"], r["interval"]), ["—"] * len(cs))[i] = _pct(r["hits"], r["given"],
                                                                                       r["series"])
    # a bootstrap row no series ever gave an interval for is not printed (that estimate has no bootstrap)
    return [(i, n, v) for (i, n), v in sorted(order.items(), key=lambda kv: kv[0][1] == "boot")
            if n != "boot" or any(x not in ("no interval", "—") for x in v)]


def _sizes(cs: list[dict[str, Any]]) -> str:
    n = max(r["series"] for c in cs for r in c["rows"] if r["interval"] == "95")
    b = max((r["series"] for c in cs for r in c["rows"] if r["interval"] == "boot"), default=0)
    refused = sum(c["refused"] for c in cs)
    return (f"{n} series per true value" + (f", the bootstrap ({BOOT_B} resamples) on the first {b}" if b else "")
            + (f"; {refused} series refused by the checks, not counted" if refused else ""))


BOOT_B = 200  # resamples per bootstrap interval in the coverage harness (its coverage does not depend on B beyond
# the Monte Carlo noise of its ends; 1000 would make those cells five times dearer); stored in the table too
WIDTH = 17  # a column of the help's table; the first is WIDTH + 1, and 2 + 18 + 3 × 17 = 71 columns in all


def help_lines(kind: str, table: dict[str, Any] | None = None) -> list[str]:
    """The coverage table of ``resal fit KIND --help``: a sentence, a blank line, then the table (within 80
    columns): a column per true value, a line per parameter, the bootstrap's below its own heading."""
    cs = cells(kind, table)
    if not cs:
        return []
    rows = kind_rows(kind, table)

    def line(label: str, vals: list[str]) -> str:
        return (f"  {label:<{WIDTH + 1}}" + "".join(f"{v:<{WIDTH}}" for v in vals)).rstrip()

    out = [f"Coverage, measured: the share of seeded synthetic series ({cs[0]['label']}) whose interval holds the "
           f"value that made them; {_sizes(cs)} (python -m reproductions.coverage):", "",
           line("95 % interval", [_truth(c["truth"]) for c in cs])]
    out += [line(PARAM.get(i, i), v) for i, n, v in rows if n == "95"]
    boot = [line(PARAM.get(i, i), v) for i, n, v in rows if n == "boot"]
    return out + (["  bootstrap", *boot] if boot else [])


def boot_range(kind: str, table: dict[str, Any] | None = None) -> str | None:
    """The bootstrap intervals' measured coverage of ``kind`` as a range ("83–91 %"), None if not measured."""
    vals = [100 * r["hits"] / r["given"] for c in cells(kind, table) for r in c["rows"]
            if r["interval"] == "boot" and r["given"]]
    if not vals:
        return None
    lo, hi = min(vals), max(vals)
    return f"{lo:.0f} %" if round(lo) == round(hi) else f"{lo:.0f}–{hi:.0f} %"


def markdown(table: dict[str, Any] | None = None) -> str:
    """The docs' table: a block per kind, a line per parameter × interval, a column per true value."""
    table = load() if table is None else table
    lines = []
    for kind in dict.fromkeys(c["kind"] for c in table["cells"]):
        cs = cells(kind, table)
        lines += [f"**{kind}**: {cs[0]['label']}; {_sizes(cs)}.", "",
                  "| interval | " + " | ".join(_truth(c["truth"]) for c in cs) + " |",
                  "|---|" + "---|" * len(cs)]
        lines += [f"| {PARAM.get(i, i)}, {'bootstrap' if n == 'boot' else '95 %'} | " + " | ".join(v) + " |"
                  for i, n, v in kind_rows(kind, table)]
        lines.append("")
    return "\n".join(lines)
