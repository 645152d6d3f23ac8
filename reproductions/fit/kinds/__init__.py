"""The kinds of ``resal fit``, as data (no numpy): their columns, options and example, for the command line's
help. ``fit.run`` maps each kind to the function that fits it."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["KINDS", "MAX_RESAMPLES", "Kind"]

MAX_RESAMPLES = 100_000  # a bound on --bootstrap: a typo cannot make a fit run for hours


@dataclass(frozen=True)
class Kind:
    name: str
    title: str  # one line, for `resal fit --help`
    columns: str  # the columns, for `resal fit <kind> --help`
    example: str  # file name in examples/
    options: tuple[str, ...]  # the options this kind takes, besides --out, --json, --plot, --seed
    per_minute: int = 0  # rows a fit of this kind (its checks included, no bootstrap) handles in a minute on two
    # cores, measured (the closing note of issue 30): beyond it the command says so before it starts; 0: any size


_SPEEDS = ("V0,V1: signed velocities (m/s), V0 > 0 towards the obstacle and V1 ≤ 0 after it (the paper's "
           "convention); or u0,u1: speeds, both ≥ 0 (or V0,V1 with --speeds unsigned)")
_HEIGHTS = "h0,h1: drop and rebound heights (m), 0 ≤ h1 ≤ h0"
UNITS_HELP = ("A header may carry a unit: V0_mps, V0_cmps, V0_kmph, h0_mm, h0_cm, t_ms, M_g, phi_deg …; a column "
              "without one is read in SI and the output says so. Lines starting with # are comments.")

KINDS: dict[str, Kind] = {k.name: k for k in (
    Kind("rebound", "e and ε from rebounds on an immovable mass, §I eq. (9): speeds or heights",
         f"{_SPEEDS}. Or {_HEIGHTS}.", "rebound.csv",
         ("sigma", "sigma_in", "noise", "speeds", "g", "bootstrap"), per_minute=300000),
    Kind("cushion", "e and ε from perpendicular cushion rebounds, beside Coriolis's 0.55 and today's e",
         f"{_SPEEDS}.", "cushion.csv", ("sigma", "sigma_in", "noise", "speeds", "bootstrap"), per_minute=300000),
    Kind("drop", "e and ε from a ball dropped on a slab: drop and rebound heights (or speeds)",
         f"{_HEIGHTS}; or speeds just before and after the impact ({_SPEEDS}).", "drop.csv",
         ("sigma", "sigma_in", "noise", "speeds", "g", "bootstrap"), per_minute=300000),
    Kind("pendulum", "ε, ε′ and e from two-pendulum impacts, §I eqs (8); momentum checked per trial",
         "V0,V1,V1p: signed velocities (m/s) of the striker before the impact and of striker and struck body "
         "after it (the struck body at rest before); or h0,h1,h1p: the striker's release height and the rise heights "
         "of both bodies after the impact (m; the speeds at the bottom are √(2gh), and the striker's direction after "
         "the impact is taken from momentum, said per trial); M,Mp: the masses (kg) per trial, or --M and --Mp.",
         "pendulum.csv", ("sigma", "M", "Mp", "g", "bootstrap"), per_minute=1000000),
    Kind("ricochet", "ν (and f where identifiable) from ricochet imprints, §III n°8-10",
         "x: imprint positions along the plane (m), increasing; t (optional): their impact instants (s).",
         "ricochet.csv", ("R", "k", "g")),
    Kind("bounces", "ν (and g, given the drop height) from the instants of a ball bouncing in place (clicks)",
         "t: the impact instants (s; t_ms for milliseconds), increasing, at least 5; the origin need not be the "
         "first click, it is fitted.", "bounces.csv", ("sigma", "h0", "g", "bootstrap")),
    Kind("ball-ball", "ball–ball friction f and e from oblique shots, §VI n°13 then §II n°7; each shot predicted",
         "v: the cue ball's speed before the impact (m/s, rolling); phi: the cut angle, between its velocity and "
         "the line of centres (rad; phi_deg for degrees); cue_speed, cue_dir, obj_speed, obj_dir: each ball's speed "
         "(m/s) and direction (rad, counter-clockwise from the cue ball's incoming direction, seen from above) once "
         "it rolls. v and phi are required; of the four outcome columns any subset will do (the two speeds alone "
         "fix f and e, as a published table of speeds and cut angles gives them), and an empty cell means not "
         "measured. The balls are taken equal unless --M and --Mp (and --Rp, --kp) say otherwise. An optional "
         "column shot labels each shot (text).", "ball-ball.csv",
         ("M", "Mp", "R", "Rp", "k", "kp", "sigma_speed", "sigma_dir", "bootstrap", "max_seconds"), per_minute=50000),
    Kind("markers", "ball–ball friction f and e from angle markers of oblique collisions against ψ, §VI n°13",
         "series: alpha1 (the cue ball's turn at the impact, between its directions before and after) or throw "
         "(the object ball's departure from the line of centres, positive forward); psi_deg: the impact angle "
         "(0 = head-on); angle_deg: the angle; degrees, right after the impact. One series or both, at least 5 "
         "markers of each present; an optional last column figure is ignored. The cue ball rolls onto a ball at "
         "rest; the angles depend neither on the speed nor on the size of the balls.", "markers.csv", ("k",),
         per_minute=60000),  # beyond 2048 markers the model is interpolated in ψ: 10⁴ in 33 s, 10⁵ in 78 s
)}
