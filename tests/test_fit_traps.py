"""The corpus of traps: each kind's example file recorded the way a user might get it wrong — a unit left out,
degrees read as radians, directions mirrored, columns swapped, speeds without their sign, a mistyped trial, a σ ten
times too small, options that contradict one another, a file given to the wrong kind. Each gives its coded warning
(fit.json's ``warnings``, a WARNING line on stderr) or a refusal (one message naming the fix, exit 2, nothing
written): never a silent exit 0. The examples as written warn only of what is true of them (the cushion example is
made with Han's speed law, examples/generate.py; the pendulum heights' striker direction is taken from momentum)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from fit_tables import (
    EXAMPLES,
    cell,
    chain,
    first_row_only,
    header,
    invoke,
    line,
    ok,
    rows_scaled,
    same,
    scale,
    shift,
    write,
)

BB = ("--R", "0.02855")  # the ball-ball example's radius (its comment says so)
BB_HEAD = ["v", "phi_deg", "cue_speed", "cue_dir_deg", "obj_speed", "obj_dir_deg"]

# ---- warned: (kind, example, change, options, the warning codes expected (exactly), fragments of their messages)
WARNED = {
    "rebound as written": ("rebound", "rebound.csv", same, (), set(), ()),
    "cushion as written (made with Han's law)": ("cushion", "cushion.csv", same, (), {"speed-dependence"}, ()),
    "drop as written": ("drop", "drop.csv", same, (), set(), ()),
    "pendulum as written": ("pendulum", "pendulum.csv", same, (), set(), ()),
    "pendulum heights as written": ("pendulum", "pendulum-heights.csv", same, (), {"assumed"}, ()),
    "rebound in cm/s, no unit": ("rebound", "rebound.csv", chain(header(["u0", "u1"]), scale(0, 100),
                                                                   scale(1, 100)),
                                 (), {"implausible-input"}, ("column 'u0'", "in cm/s they would be plausible")),
    "cushion in cm/s, no unit": ("cushion", "cushion.csv", header(["V0", "V1"]), (),
                                 {"implausible-input", "speed-dependence"}, ("column 'V0'", "in cm/s")),
    "drop in mm, no unit": ("drop", "drop.csv", header(["h0", "h1"]), (), {"implausible-input"},
                            ("column 'h0'", "in mm they would be plausible")),
    "pendulum masses in g, no unit": ("pendulum", "pendulum.csv", header(["V0", "V1", "V1p", "M", "Mp"]), (),
                                      {"implausible-input"}, ("column 'M'", "column 'Mp'", "in g")),
    # the first six trials (600 g on 200 g), masses on the command line in grams: one mass ratio, so rank 1 too
    "pendulum --M in g": ("pendulum", "pendulum.csv", lambda t: (t[0][:3], [r[:3] for r in t[1][:6]]),
                          ("--M", "600", "--Mp", "200"), {"implausible-input", "not-identifiable"},
                          ("--M 600 kg", "in g it would be plausible")),
    "rebound σ ten times too small": ("rebound", "rebound.csv", same, ("--sigma", "0.002"),
                                      {"chi2-exceeds-sigma"}, ("reduced χ²",)),
    "drop σ ten times too small": ("drop", "drop.csv", same, ("--sigma", "0.2"), {"chi2-exceeds-sigma"}, ()),
    "rebound one mistyped trial": ("rebound", "rebound.csv", shift(0, 1, 0.3), (), {"outlier"},
                                   (f"line(s) {line(0)} ",)),
    "cushion one mistyped trial": ("cushion", "cushion.csv", shift(6, 1, -30.0), (),
                                   {"outlier", "speed-dependence"}, (f"line(s) {line(6)} ",)),
    "drop one mistyped trial": ("drop", "drop.csv", shift(3, 1, 30.0), (), {"outlier"}, (f"line(s) {line(3)} ",)),
    "pendulum one mistyped trial": ("pendulum", "pendulum.csv", shift(3, 2, 0.1), (), {"outlier"},
                                    (f"line(s) {line(3)} ",)),
    "ball-ball as written": ("ball-ball", "ball-ball.csv", same, BB, set(), ()),
    "bounces as written": ("bounces", "bounces.csv", same, ("--h0", "0.5"), set(), ()),
    "ricochet as written": ("ricochet", "ricochet.csv", same, (), set(), ()),
    # read as written, the mirrored directions leave f and e undetermined (rank 1): also true, also said
    "ball-ball directions mirrored (clockwise)": ("ball-ball", "ball-ball.csv", chain(scale(3, -1), scale(5, -1)), BB,
                                                  {"convention", "noise-implausible", "not-identifiable"},
                                                  ("clockwise", "negate both direction columns")),
    "ball-ball cue and object columns swapped": ("ball-ball", "ball-ball.csv",
                                                 header([*BB_HEAD[:2], *BB_HEAD[4:], *BB_HEAD[2:4]]), BB,
                                                 {"convention", "noise-implausible"},
                                                 ("swap the cue_ and obj_ columns",)),
    "ball-ball speeds in cm/s, no unit": ("ball-ball", "ball-ball.csv", chain(scale(0, 100), scale(2, 100),
                                                                              scale(4, 100)), BB,
                                          {"implausible-input"}, ("column 'v'", "in cm/s they would be plausible")),
    "ball-ball σ ten times too small": ("ball-ball", "ball-ball.csv", same,
                                        (*BB, "--sigma-speed", "0.002", "--sigma-dir", "0.05"),
                                        {"chi2-exceeds-sigma"}, ("reduced χ²",)),
    "bounces in ms, no unit": ("bounces", "bounces.csv", header(["t"]), (), {"implausible-input", "noise-implausible"},
                               ("in ms they would be plausible",)),
    "bounces one click mistyped by 30 ms": ("bounces", "bounces.csv", shift(5, 0, 30.0), (), {"outlier"},
                                            (f"line(s) {line(5)} ",)),
    "ricochet one imprint mistyped by 5 cm": ("ricochet", "ricochet.csv", shift(4, 0, 0.05), (), {"outlier"},
                                              (f"line(s) {line(4)} ",)),
    "ricochet --g in cm/s²": ("ricochet", "ricochet.csv", same, ("--g", "981"), {"implausible-input"},
                              ("in cm/s² it would be plausible",)),
    "ricochet equal spacings (no ricochet)": ("ricochet", "ricochet.csv",
                                              lambda t: (t[0], [[f"{0.1 * i:g}", f"{0.1 * i:g}"]
                                                                for i in range(len(t[1]))]), (), {"at-bound"}, ()),
    "bounces --h0 in mm": ("bounces", "bounces.csv", same, ("--h0", "500"), {"implausible-input", "implausible-result"},
                           ("--h0 500: 500 m", "in mm", "is not gravity")),
    "bounces --h0 wrong": ("bounces", "bounces.csv", same, ("--h0", "0.3"), {"implausible-result"},
                           ("is not gravity",)),
    "bounces σ given in s for a column in ms": ("bounces", "bounces.csv", same, ("--sigma", "0.001"),
                                                {"chi2-exceeds-sigma"}, ("in the clicks' unit, ms",)),
    "bounces σ far too large": ("bounces", "bounces.csv", same, ("--sigma", "100"), {"sigma-exceeds-scatter"}, ()),
    "ball-ball identical shots": ("ball-ball", "ball-ball.csv", first_row_only, BB, {"no-scatter"}, ()),
    "rebound identical trials": ("rebound", "rebound.csv", first_row_only, (), {"no-scatter", "duplicate-rows"},
                                 ("has no width", "copied twice?")),
    "rebound σ far too large": ("rebound", "rebound.csv", same, ("--sigma", "2"), {"sigma-exceeds-scatter"},
                                ("is σ in the data's unit?",)),
    # radians under degree headers, and an object ball's direction from the line of centres: the convention named
    "ball-ball radians under degree headers": ("ball-ball", "ball-ball.csv",
                                               chain(scale(1, math.pi / 180), scale(3, math.pi / 180),
                                                     scale(5, math.pi / 180)), BB,
                                               {"convention", "noise-implausible", "at-bound"},
                                               ("hold radians, not degrees", "phi_rad")),
    "ball-ball object direction from the line of centres": ("ball-ball", "ball-ball.csv",
                                                            lambda t: (t[0], [[*r[:5], repr(float(r[5]) - float(r[1]))]
                                                                              for r in t[1]]), BB,
                                                            {"convention", "noise-implausible", "not-identifiable"},
                                                            ("measured from the line of centres",)),
    # a declared unit can be wrong too: checked against the other column (issue 30)
    "rebound u1 declared in cm/s, written in m/s": ("rebound", "rebound.csv", header(["u0_mps", "u1_cmps"]), (),
                                                    {"implausible-input"}, ("is 0.00801 in the median", "'u1_mps'")),
    "rebound three impacts in km/h": ("rebound", "rebound.csv", rows_scaled((6, 7, 8), 0, 3.6), (),
                                      {"implausible-input", "speed-dependence", "noise-implausible"},
                                      (f"lines {line(6)}–{line(8)}", "km/h")),
    # positions in cm written as mm: the instants tell (the refusal of cm without a unit names both)
    "ricochet positions in cm under x_mm": ("ricochet", "ricochet.csv", chain(header(["x_mm", "t"]), scale(0, 100)), (),
                                            {"implausible-input"}, ("leaves the plane at 77°", "cm (x_cm)")),
}


@pytest.mark.parametrize("case", list(WARNED))
def test_each_trap_gives_its_warning_and_the_examples_only_theirs(tmp_path: Path, case: str) -> None:
    kind, example, change, args, codes, fragments = WARNED[case]
    res = invoke(tmp_path, kind, write(tmp_path, example, change), *args)
    assert res.exit_code == 0, res.output
    s = json.loads(res.stdout)
    assert {w["code"] for w in s["warnings"]} == codes, s["warnings"]
    text = " ".join(w["message"] for w in s["warnings"])
    assert all(f in " ".join(text.split()) for f in fragments), text
    # on stderr, one line each, and the files still written
    assert sorted(ln.split("]")[0] for ln in res.stderr.splitlines()) == sorted(
        f"WARNING [{w['code']}" for w in s["warnings"])
    assert (tmp_path / "out" / "fit.json").is_file()


REFUSED = {
    "rebound separated by semicolons": ("rebound", "rebound.csv",
                                        lambda t: ([";".join(t[0])], [[";".join(r)] for r in t[1]]), (),
                                        ("separated by semicolons", "(as u0_mps,u1_mps)")),
    "bounces with decimal commas": ("bounces", "bounces.csv", lambda t: (t[0], [[r[0].replace(".", ",")]
                                                                                for r in t[1]]), (),
                                    ("'321,105'", "or a decimal comma (321.105)?")),
    "ricochet positions in cm, no unit": ("ricochet", "ricochet.csv", scale(0, 100), (),
                                          ("in cm they would span 0.662 m", "in mm they would span 0.0662 m",
                                           "(x_cm or x_mm)")),
    "rebound columns swapped": ("rebound", "rebound.csv", header(["u1_mps", "u0_mps"]), (),
                                ("faster than it arrived", "12 of 12 rows", "the columns may be swapped",
                                 "swap the two names in the header")),
    "drop columns swapped": ("drop", "drop.csv", header(["h1_mm", "h0_mm"]), (),
                             ("higher than the drop", "the columns may be swapped", "swap the two names")),
    "cushion columns swapped": ("cushion", "cushion.csv", header(["V1_cmps", "V0_cmps"]), (),
                                ("column 'V0_cmps' (#2)", "the columns may be swapped")),
    "rebound positive rebounds": ("rebound", "rebound.csv", header(["V0_mps", "V1_mps"]), (),
                                  ("expected the signed velocity after the impact", "u0,u1", "--speeds unsigned")),
    "cushion mirrored axis": ("cushion", "cushion.csv", chain(scale(0, -1), scale(1, -1)), (),
                              ("the axis points away from the obstacle", "negate both columns", "--speeds unsigned")),
    "negative speeds under u0,u1": ("rebound", "rebound.csv", scale(1, -1), (),
                                    ("expected a speed ≥ 0", "name the columns V0,V1")),
    "--noise proportional with --sigma": ("rebound", "rebound.csv", same, ("--noise", "proportional", "--sigma",
                                                                             "0.01"),
                                          ("--noise proportional: --sigma 0.01 gives the outcome's noise already",)),
    "--noise constant with --sigma": ("drop", "drop.csv", same, ("--noise", "constant", "--sigma", "2"),
                                      ("--noise constant:", "leave --noise out")),
    "--sigma-in with --noise proportional": ("cushion", "cushion.csv", same,
                                             ("--sigma-in", "1", "--noise", "proportional"),
                                             ("--noise proportional:", "not supported")),
    "--speeds with heights": ("drop", "drop.csv", same, ("--speeds", "unsigned"),
                              ("--speeds unsigned: the file gives heights",)),
    "--g with speeds": ("rebound", "rebound.csv", same, ("--g", "9.81"), ("--g 9.81: the file gives speeds",)),
    "--g with pendulum speeds": ("pendulum", "pendulum.csv", same, ("--g", "9.81"), ("--g 9.81",)),
    "pendulum σ ten times too small": ("pendulum", "pendulum.csv", same, ("--sigma", "0.0005"),
                                       ("breaks momentum", "5 σ of the noise")),
    "ball-ball degrees under a radian header": ("ball-ball", "ball-ball.csv",
                                                header(["v", "phi_rad", "cue_speed", "cue_dir_rad", "obj_speed",
                                                        "obj_dir_rad"]), BB,
                                                (f":{line(0)}:", "beyond 2π", "write phi_deg in the header")),
    "ball-ball degrees without a unit": ("ball-ball", "ball-ball.csv",
                                         header(["v", "phi", "cue_speed", "cue_dir", "obj_speed", "obj_dir"]), BB,
                                         ("beyond 2π", "write phi_deg in the header")),
    "ricochet --k as I/MR²": ("ricochet", "ricochet.csv", same, ("--k", "0.4"), ("reads as I/MR²", "--k 2.5?")),
    "ball-ball a dash for a value not measured": ("ball-ball", "ball-ball.csv", cell(2, 3, "-"), BB,
                                                  (f":{line(2)}:", "or an empty cell (not measured)")),
    "pendulum V1 and V1p swapped": ("pendulum", "pendulum.csv", header(["V0", "V1p", "V1", "M_g", "Mp_g"]), (),
                                    ("V1 and V1p swapped",)),
    "rebound a value of 1e300 (an export slip)": ("rebound", "rebound.csv", scale(0, 1e300), (),
                                                  (f":{line(0)}:", "is no measurement in any unit")),
    "rebound an unknown unit on both columns": ("rebound", "rebound.csv", header(["u0_furlong", "u1_furlong"]), (),
                                                ("unknown unit 'furlong' for a speed",)),
    "ricochet instants in ms, no unit": ("ricochet", "ricochet.csv", scale(1, 1000.0), (),
                                         ("expected t in seconds",)),
    "rebound given a pendulum's file": ("rebound", "pendulum.csv", same, (),
                                        ("this header is that of `resal fit pendulum`",)),
    "bounces given a ricochet's file": ("bounces", "ricochet.csv", same, (),
                                        ("this header is that of `resal fit ricochet`",)),
    "ball-ball given a rebound's file": ("ball-ball", "rebound.csv", same, (),
                                         ("this header is that of `resal fit rebound` or `resal fit cushion` or "
                                          "`resal fit drop`",)),
    "pendulum given a drop's file": ("pendulum", "drop.csv", same, (),
                                     ("this header is that of `resal fit rebound` or `resal fit drop`",)),
}


@pytest.mark.parametrize("case", list(REFUSED))
def test_each_trap_is_refused_naming_the_other_reading(tmp_path: Path, case: str) -> None:
    """One message (file and line, or the option), exit 2, nothing written."""
    kind, example, change, args, fragments = REFUSED[case]
    res = invoke(tmp_path, kind, write(tmp_path, example, change), *args)
    err = " ".join(res.stderr.split())
    assert res.exit_code == 2 and all(f in err for f in fragments), err
    assert res.stderr.count("\n") == 1 and "Traceback" not in res.output
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("case", ["bounces one click mistyped by 30 ms", "rebound σ ten times too small"])
def test_strict_turns_a_warning_into_exit_1_and_still_writes(tmp_path: Path, case: str) -> None:
    kind, example, change, args, _, _ = WARNED[case]
    res = invoke(tmp_path, kind, write(tmp_path, example, change), *args, "--strict")
    assert res.exit_code == 1, res.output
    assert (tmp_path / "out" / "fit.json").is_file() and (tmp_path / "out" / "residuals.csv").is_file()
    assert "--strict" in res.stderr
    clean = invoke(tmp_path / "clean", kind, EXAMPLES / example, "--strict")  # the example as written: exit 0
    assert clean.exit_code == 0, clean.output


@pytest.mark.parametrize("kind, example, args", [("bounces", "bounces.csv", ("--h0", "0.5")),
                                                 ("bounces", "bounces.csv", ()), ("ricochet", "ricochet.csv", ())])
def test_each_click_and_imprint_is_predicted_from_the_others(tmp_path: Path, kind: str, example: str,
                                                             args: tuple[str, ...]) -> None:
    """fit.json's leave_one_out: every measured value with the prediction of the fit without its trial and the 95 %
    interval; on the clean example most values lie inside (95 % intervals), none is named an outlier."""
    s = ok(tmp_path, kind, EXAMPLES / example, *args)
    loo = s["leave_one_out"]
    assert len(loo) == s["n"] * (2 if kind == "ricochet" else 1)
    assert all(e["low"] is None or e["low"] < e["predicted"] < e["high"] for e in loo)  # intervals with a width
    inside = sum(e["low"] is not None and e["low"] <= e["measured"] <= e["high"] for e in loo)
    assert inside >= 0.8 * len(loo), loo
    assert not any(w["code"] == "outlier" for w in s["warnings"])
