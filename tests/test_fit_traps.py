"""The corpus of convention traps: each kind's example file, recorded the way a user might get it wrong (a mirrored
angle, degrees read as radians, a unit left out, columns swapped, a mistyped trial, a σ too small, a file given to
the wrong kind). Each must give its named warning (a code in fit.json, a WARNING line on stderr) or its refusal
(one message, exit 2): never a silent exit 0. The examples as written give no warning but the ones true of them."""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest
from typer.testing import CliRunner

from cli.main import app

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
Table = tuple[list[str], list[list[str]]]


def _read(example: str) -> tuple[list[str], Table]:
    lines = (EXAMPLES / example).read_text(encoding="utf-8").splitlines()
    comments = [ln for ln in lines if ln.startswith("#")]
    data = [ln.split(",") for ln in lines if ln and not ln.startswith("#")]
    return comments, (data[0], data[1:])


def _col(header: list[str], name: str) -> int:
    return next(i for i, h in enumerate(header) if h == name or h.rsplit("_", 1)[0] == name or h.startswith(name + "_"))


def scale(name: str, factor: float) -> Callable[[Table], Table]:
    def t(tab: Table) -> Table:
        h, rows = tab
        j = _col(h, name)
        return h, [[*r[:j], repr(float(r[j]) * factor), *r[j + 1:]] for r in rows]
    return t


def rename(old: str, new: str) -> Callable[[Table], Table]:
    def t(tab: Table) -> Table:
        h, rows = tab
        return [new if c == old else c for c in h], rows
    return t


def shift(name: str, row: int, by: float) -> Callable[[Table], Table]:
    def t(tab: Table) -> Table:
        h, rows = tab
        j = _col(h, name)
        rows = [list(r) for r in rows]
        rows[row][j] = repr(float(rows[row][j]) + by)
        return h, rows
    return t


def chain(*fs: Callable[[Table], Table]) -> Callable[[Table], Table]:
    def t(tab: Table) -> Table:
        for f in fs:
            tab = f(tab)
        return tab
    return t


@dataclass(frozen=True)
class Trap:
    id: str
    kind: str
    example: str
    transform: Callable[[Table], Table]
    args: tuple[str, ...] = ()
    warning: str | None = None  # the code expected in fit.json's warnings
    refusal: str | None = None  # a fragment of the one-line error


TRAPS = [
    Trap("bounces: milliseconds under a header without unit", "bounces", "bounces.csv", rename("t_ms", "t"),
         ("--bootstrap", "0"), warning="implausible-input"),
    Trap("bounces: one click mistyped by 30 ms", "bounces", "bounces.csv", shift("t", 5, 30.0),
         ("--bootstrap", "0"), warning="outlier"),
    Trap("ricochet: one imprint mistyped by 5 cm", "ricochet", "ricochet.csv", shift("x", 4, 0.05),
         warning="outlier"),
    Trap("ricochet: instants in ms without unit", "ricochet", "ricochet.csv", scale("t", 1000.0),
         refusal="expected t in seconds"),
    Trap("rebound: a pendulum's file", "rebound", "pendulum.csv", lambda t: t,
         refusal="this header is that of `resal fit pendulum`"),
    Trap("bounces: a ricochet's file", "bounces", "ricochet.csv", lambda t: t,
         refusal="this header is that of `resal fit ricochet`"),
    Trap("ball-ball: a rebound's file", "ball-ball", "rebound.csv", lambda t: t,
         refusal="this header is that of `resal fit rebound` or `resal fit cushion` or `resal fit drop`"),
    Trap("pendulum: a drop's file", "pendulum", "drop.csv", lambda t: t,
         refusal="this header is that of `resal fit rebound` or `resal fit drop`"),
]


def _run(tmp_path: Path, trap: Trap, *extra: str):
    comments, tab = _read(trap.example)
    header, rows = trap.transform(tab)
    f = tmp_path / "data.csv"
    f.write_text("\n".join([*comments, ",".join(header), *(",".join(r) for r in rows)]) + "\n", encoding="utf-8")
    out = tmp_path / "out"
    res = CliRunner().invoke(app, ["fit", trap.kind, str(f), "--no-plot", "--out", str(out), *trap.args, *extra])
    return res, out


@pytest.mark.parametrize("trap", TRAPS, ids=[t.id for t in TRAPS])
def test_no_trap_passes_silently(tmp_path: Path, trap: Trap) -> None:
    res, out = _run(tmp_path, trap)
    if trap.refusal is not None:
        assert res.exit_code == 2, res.output
        assert res.stderr.startswith("error: ") and trap.refusal in res.stderr, res.stderr
        assert not out.exists(), "a refused input wrote its output folder"
        return
    assert res.exit_code == 0, res.output
    codes = [w["code"] for w in json.loads((out / "fit.json").read_text(encoding="utf-8"))["warnings"]]
    assert trap.warning in codes, codes
    assert f"WARNING [{trap.warning}]" in res.stderr and "WARNING" not in res.stdout


@pytest.mark.parametrize("trap", [t for t in TRAPS if t.warning][:2], ids=lambda t: t.id)
def test_strict_turns_a_warning_into_exit_1_and_still_writes(tmp_path: Path, trap: Trap) -> None:
    res, out = _run(tmp_path, trap, "--strict")
    assert res.exit_code == 1, res.output
    assert (out / "fit.json").is_file() and (out / "residuals.csv").is_file()
    assert "--strict" in res.stderr


CLEAN = [("bounces", "bounces.csv", ("--h0", "0.5", "--bootstrap", "0")), ("ricochet", "ricochet.csv", ()),
         ("bounces", "bounces.csv", ("--bootstrap", "0"))]


@pytest.mark.parametrize("kind, example, args", CLEAN, ids=[f"{k}-{' '.join(a)}" for k, _, a in CLEAN])
def test_the_examples_as_written_give_no_warning(tmp_path: Path, kind: str, example: str, args: tuple) -> None:
    out = tmp_path / "out"
    res = CliRunner().invoke(app, ["fit", kind, str(EXAMPLES / example), "--no-plot", "--out", str(out),
                                   "--strict", *args])
    assert res.exit_code == 0, res.output
    s = json.loads((out / "fit.json").read_text(encoding="utf-8"))
    assert s["warnings"] == [] and res.stderr == ""
    loo = s["leave_one_out"]
    assert loo and all(e["low"] is None or e["low"] <= e["predicted"] <= e["high"] for e in loo)
    inside = sum(e["low"] is not None and e["low"] <= e["measured"] <= e["high"] for e in loo)
    assert inside >= 0.8 * len(loo), loo  # 95 % intervals: most measured values lie inside the others' prediction
