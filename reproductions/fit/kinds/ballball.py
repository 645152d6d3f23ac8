"""``resal fit ball-ball``: oblique shots → the ball–ball friction f and e, and each shot's predicted outcome.

Per shot: the cue ball's speed v (rolling, natural roll) and the cut angle φ at the impact, and, once each ball has
stopped sliding on the cloth, any of the speeds and directions of both (a column may be absent, a cell blank: not
measured). The prediction is the §VI n°13 impact of two equal balls with friction f (ε = ε′ = (1 − e)/(1 + e))
followed by the §II n°7 slide to rolling (``estimators.shots``); the fit adjusts (f, e) to all measured values,
with one noise level per kind of measurement (speeds, directions) estimated from the residuals, or given.

Before it reports, the fit checks itself (``fit.checks``): the goodness of fit (χ² against a given σ; an estimated
noise against what such a measurement plausibly has), each shot against the others (leave-one-out), other readings
of the columns (directions clockwise, degrees read as radians, cue and object columns swapped), the plausibility
of the speeds; e's interval is the profile likelihood's with the bound e ≤ 1. A wall-clock bound
(``FitOptions.max_seconds``) covers the fit and every refit.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import ComputationError, InputError
from ...results import FigureSpec, layer
from ...series import Series, Table, as_table, read_series
from .. import distributions as dist
from ..checks import (
    CHI2_P,
    Code,
    Reading,
    better_reading,
    chi2_given,
    leave_one_out,
    name_outliers,
    noise_plausible,
    plausible_columns,
    plausible_ratio,
    warn,
)
from ..estimators.shots import (
    QUANTITIES,
    BallBallFit,
    OverBudget,
    ball_tilt,
    fit_many,
    predict_shots,
    weighted_rows,
    wrap_angle,
)
from ..estimators.trials import bootstrap_many
from .common import (
    MIN_BOOT_TRIALS,
    FitOptions,
    FitOutcome,
    base_summary,
    boot_note,
    columns_read,
    estimate_row,
    identifiability,
    rows_from_fit,
    today,
)

DIMS = {"v": "speed", "phi": "angle", "cue_speed": "speed", "cue_dir": "angle", "obj_speed": "speed",
        "obj_dir": "angle"}
REQUIRED = ("v", "phi")
ID = "shot"  # an optional column of shot labels (text), kept in the per-shot output
OUTCOMES = QUANTITIES  # cue_speed, cue_dir, obj_speed, obj_dir: any of them, a blank cell is "not measured"
SPEEDS, DIRS = ("cue_speed", "obj_speed"), ("cue_dir", "obj_dir")
BOOT_BATCH = 200  # at most this many resamples refitted together (one batched prediction per iteration for all),
# and at most a tenth of them, so that the progress bar moves at least ten times (the draws do not depend on it)
LABELS = {"f_bb": "f (ball–ball friction)", "e_bb": "e (Newton's, ε = ε′ = (1 − e)/(1 + e))"}
CORIOLIS_F = ("Coriolis: the friction of one ball on the other 'does not seem to reach 0.03' (§V n°12)", 0.03, 610)
WHAT = {"cue_speed": "cue speed", "cue_dir": "cue direction", "obj_speed": "object speed",
        "obj_dir": "object direction"}

# The noise a post-slip measurement plausibly has. Speeds: from a video (frame-to-frame distance over the frame
# interval) or from timing gates a rolling ball's speed is good to 1–5 %; 15 %, three times the worse of these,
# is already a poor measurement. Directions: read from a video track or the chalk line a ball leaves on the cloth,
# over the ≥ 0.3 m of a roll, to about 1°; 5° is more than the whole throw of a cut shot (2–4°).
SPEED_NOISE_LIMIT = 0.15  # relative standard deviation
DIR_NOISE_LIMIT = math.radians(5.0)
# e's profile-likelihood interval (``shots.fit_many(profile=True)``), its coverage measured over 2000 synthetic
# series (seeds default_rng([5150, 1000 e, s]), s < 2000) of 14 shots: v 0.5–3 m/s, φ 10°–60°, f 0.06, 2 % speed
# and 0.5° direction noise; tests/test_fit_ballball_checks.py measures it again over 300. Measured again after issue
# 29 (law (6) written for the cloth): estimated 95.5, 94.1, 96.7 %, given 95.9, 94.7, 96.7 %
E_NOTE = ("95 % interval from the profile likelihood over f, with the bound e ≤ 1 (not a Wald interval cut at "
          "1): it covered {cov} of 2000 synthetic series of 14 shots each at e = 0.95, 0.98 and 0.995")
E_COVERAGE = {"estimated": "95.5 %, 94.1 % and 96.7 %", "given": "95.9 %, 94.7 % and 96.7 %"}
# Balls taken equal: the mass ratios M/M′ at which (f, e) are refitted to look for the signature of unequal balls
# (bar-box cue balls are 6 oz against 5.5 oz, 9 % heavier; some are lighter); the best of them and its neighbours
# place a parabola whose lowest point is fitted once more. The check is one more reading of the data, compared with
# the conventions' by likelihood (``checks.better_reading``).
MASS_RATIOS = (0.80, 0.86, 0.93, 1.075, 1.16, 1.25)
CHECK_SHOTS = 2000  # the checks of other readings (conventions, mass ratio) refit at most this many shots
TILT_WARN = math.radians(0.5)  # radii this unequal tilt the line of centres by more than this: said in a warning

class _Stages:
    """The stage being worked on, announced through ``opts.progress.stage(name, total)`` where it has one."""

    def __init__(self, opts: FitOptions) -> None:
        self.name = "reading"
        self.announce: Callable[[str, int], None] | None = getattr(opts.progress, "stage", None)

    def __call__(self, name: str, total: int = 1) -> None:
        self.name = name
        if self.announce is not None:
            self.announce(name, total)


def fit_ballball(kind: str, source: Path | Table, opts: FitOptions) -> FitOutcome:
    src = as_table(source)  # a CSV file read once, or a program's arrays
    if not (math.isfinite(opts.max_seconds) and opts.max_seconds > 0):
        raise InputError(f"max_seconds {opts.max_seconds:g}", "expected a positive number of seconds")
    deadline = time.monotonic() + opts.max_seconds
    stage = _Stages(opts)
    s, cols = _read(src)
    try:
        return _fit(kind, src, opts, s, cols, deadline, stage)
    except OverBudget:
        raise ComputationError(src.where, f"the fit of (f, e) to these shots ran past its time bound of "
                                          f"{opts.max_seconds:g} s ({stage.name}) and was stopped; nothing was "
                                          f"written ({_slow_hint(stage.name)})") from None


def _slow_hint(stage: str) -> str:
    """What to do when the time bound stops a fit, by the stage it stopped in."""
    if stage == "bootstrap":
        return "give fewer resamples, --bootstrap, or more time, --max-seconds"
    return ("give more time, --max-seconds; data the model cannot describe make the fit slow: check the columns' "
            "units, signs and conventions")


def _read(src: Table) -> tuple[Series, dict[str, np.ndarray]]:
    """The file's columns (SI); an outcome column absent from the header is all NaN (not measured)."""
    s = read_series(src, REQUIRED, optional=OUTCOMES, min_rows=3, positive=("v", "cue_speed", "obj_speed"),
                    dims=DIMS, blank=OUTCOMES, labels=(ID,))
    if not any(c in s for c in OUTCOMES):
        raise InputError(src.at(src.head_line), f"no measured outcome: expected at least one of the "
                                                            f"columns {', '.join(OUTCOMES)} besides v and phi")
    n = s["v"].size
    for c in ("phi", *DIRS):
        if c not in s or s.units[c] not in (None, "rad"):
            continue
        for i in range(n):
            if abs(s[c][i]) > 2 * math.pi:
                unit = "the header says rad" if s.units[c] == "rad" else "the header gives no unit"
                raise InputError(s.at(i), f"column '{s.written[c]}': {s[c][i]:g} is beyond 2π, read as radians "
                                          f"({unit}): if the angles are in degrees, write {c}_deg in the header")
    phi = s["phi"]
    for i in range(n):
        if not abs(phi[i]) < math.pi / 2:
            raise InputError(s.at(i), f"column '{s.written['phi']}': expected a cut angle strictly between −90° and "
                                      f"90° (the cue ball must reach the object ball), got {math.degrees(phi[i]):g}°")
    cols = {c: (np.asarray(s[c], dtype=float) if c in s else np.full(n, math.nan)) for c in (*REQUIRED, *OUTCOMES)}
    for i in range(n):
        if not any(math.isfinite(cols[c][i]) for c in OUTCOMES):
            raise InputError(s.at(i), f"no measured outcome in this shot: the cells of "
                                      f"{', '.join(s.written[c] for c in OUTCOMES if c in s)} are all blank "
                                      "(a shot needs at least one)")
    return s, cols


def _sigmas(s: Series, cols: dict[str, np.ndarray], opts: FitOptions) -> tuple[float | None, float | None]:
    """The given σ in SI (speed relative, direction in rad), each only for a kind the file measures."""
    has = {"speed": any(np.isfinite(cols[c]).any() for c in SPEEDS),
           "dir": any(np.isfinite(cols[c]).any() for c in DIRS)}
    for opt, key, names in (("--sigma-speed", "speed", SPEEDS), ("--sigma-dir", "dir", DIRS)):
        given = opts.sigma_speed if key == "speed" else opts.sigma_dir
        if given is not None and not has[key]:
            raise InputError(f"{opt} {given:g}", f"the file measures no {'speed' if key == 'speed' else 'direction'}"
                                                 f" ({' or '.join(names)}): there is no noise of it to give")
    if opts.sigma_speed is None and opts.sigma_dir is None:
        return None, None
    if (has["speed"] and opts.sigma_speed is None) or (has["dir"] and opts.sigma_dir is None):
        raise InputError("--sigma-speed/--sigma-dir", "give the noise of each kind of value the file measures "
                                                      "(--sigma-speed, relative, for speeds; --sigma-dir, in the "
                                                      "direction columns' unit, for directions), or neither")
    sig_dir = None
    if opts.sigma_dir is not None:
        factors = {s.factors[c] for c in DIRS if c in s}
        if len(factors) > 1:
            raise InputError(f"--sigma-dir {opts.sigma_dir:g}", "the direction columns are in different units: "
                                                                "write both in one unit")
        sig_dir = opts.sigma_dir * factors.pop()
    return opts.sigma_speed, sig_dir


def _readings(s: Series, cols: dict[str, np.ndarray]) -> list[tuple[str, str, dict[str, np.ndarray], float]]:
    """Other readings of the columns: (name, how to select it, the columns so read, the term that makes its
    −2 log-likelihood one of the values as written: −2 Σ ln |d reading / d written| over the outcomes)."""
    out = []
    dirs = [c for c in DIRS if c in s and np.isfinite(cols[c]).any()]
    if dirs:
        out.append(("directions measured clockwise (both direction columns negated)",
                    "measure directions counter-clockwise (seen from above, from the cue ball's incoming direction), "
                    "or negate both direction columns", {**cols, **{c: -cols[c] for c in dirs}}, 0.0))
    rad = [c for c in ("phi", *DIRS) if c in s and s.units[c] in (None, "rad")]
    if rad:  # only where the values allow: beyond 2π the file is refused before
        a = math.pi / 180
        n_conv = sum(int(np.isfinite(cols[c]).sum()) for c in rad if c in DIRS)
        out.append((f"degrees (the columns {', '.join(s.written[c] for c in rad)} read as radians)",
                    f"write {' and '.join(c + '_deg' for c in rad)} in the header",
                    {**cols, **{c: cols[c] * a for c in rad}}, -2.0 * n_conv * math.log(a)))
    deg = [c for c in ("phi", *DIRS) if c in s and s.units[c] == "deg"]
    if deg and np.nanmax(np.abs(cols["phi"])) * 180 / math.pi < math.pi / 2 and all(
            np.nanmax(np.abs(cols[c])) * 180 / math.pi <= math.pi for c in deg if c in DIRS):
        # radians under a degree header: only where the values allow (a cut below 90° read so)
        b = 180 / math.pi
        n_conv = sum(int(np.isfinite(cols[c]).sum()) for c in deg if c in DIRS)
        out.append((f"radians (the columns {', '.join(s.written[c] for c in deg)} hold radians, not degrees)",
                    f"write {' and '.join(c + '_rad' for c in deg)} in the header",
                    {**cols, **{c: cols[c] * b for c in deg}}, -2.0 * n_conv * math.log(b)))
    if "obj_dir" in s and np.isfinite(cols["obj_dir"]).any():
        phi = cols["phi"]
        out.append(("the object ball's direction measured from the line of centres (not from the cue ball's "
                    "incoming direction)", "measure both directions from the cue ball's incoming direction (or add "
                    "the cut angle to obj_dir)", {**cols, "obj_dir": wrap_angle(cols["obj_dir"] + phi)}, 0.0))
        if "cue_dir" in s and np.isfinite(cols["cue_dir"]).any():
            out.append(("both directions measured from the line of centres (not from the cue ball's incoming "
                        "direction)", "measure both directions from the cue ball's incoming direction (or add the "
                        "cut angle to both)", {**cols, "obj_dir": wrap_angle(cols["obj_dir"] + phi),
                                               "cue_dir": wrap_angle(cols["cue_dir"] + phi)}, 0.0))
    out.append(("the cue ball's and the object ball's columns swapped",
                "swap the cue_ and obj_ columns (cue_: the ball struck by the cue, which strikes the other)",
                {**cols, "cue_speed": cols["obj_speed"], "cue_dir": cols["obj_dir"], "obj_speed": cols["cue_speed"],
                 "obj_dir": cols["cue_dir"]}, 0.0))
    return out


def _fit(kind: str, src: Table, opts: FitOptions, s: Series, cols: dict[str, np.ndarray], deadline: float,
         stage: _Stages) -> FitOutcome:
    n = s["v"].size
    v, phi = cols["v"], cols["phi"]
    sig_speed, sig_dir = _sigmas(s, cols, opts)
    given = sig_speed is not None or sig_dir is not None
    balls, assumed = _balls(opts)
    kw: dict[str, Any] = {**balls, "deadline": deadline}
    stage("fit")
    fit = fit_many([cols], sigma_speed=sig_speed, sigma_dir=sig_dir, profile=True, **kw)[0]
    names = dict(zip(fit.names, ("f_bb", "e_bb"), strict=True))
    labels = {k: LABELS[v_] for k, v_ in names.items()}
    kinds = [w for w, m in (("speeds", fit.n_speed), ("directions", fit.n_dir)) if m]
    measured = " and ".join(kinds)
    method = f"least squares on post-slip {measured}: §VI n°13 impact, then §II n°7 slide" + (
        "; σ given" if given else "; a noise level per kind of measurement, estimated (Student's t)")
    summary = base_summary(kind, src, n, columns_read(s, DIMS), opts)
    summary["balls"] = _balls_summary(balls, assumed)
    tilt = summary["balls"]["tilt_deg"]
    if abs(math.radians(tilt)) > TILT_WARN:
        share = abs(math.sin(math.radians(tilt)))
        warn(summary, Code.ASSUMED, f"the radii differ (R′/R = {balls['Rp'] / balls['R']:.4g}): the line of centres "
                                    f"of the balls on the cloth tilts by {abs(tilt):.2g}°, which the model (§VI: a "
                                    "horizontal line of centres, both balls held on the cloth) neglects; the normal "
                                    f"impulse's vertical share, {share:.2g}, is taken by neither ball's motion")
    for msg in plausible_columns(s, {"v": "ball-speed", "cue_speed": "ball-speed", "obj_speed": "ball-speed"}, DIMS):
        warn(summary, Code.UNIT, msg)
    for c in SPEEDS:  # a ball leaving ten times faster, or a hundredth as fast, as the cue ball came: units
        for msg in plausible_ratio(s, c, "v", DIMS, (0.01, 10.0), f"the {WHAT[c]} over the cue ball's speed",
                                   (0.1, 1.0)):
            warn(summary, Code.UNIT, msg)

    # Past the time bound from here on, the estimate stands: what the bound stopped (the check of other conventions,
    # the bootstrap) is said, in a warning and in fit.json, and the files are written (issue: the bound once threw
    # away an estimate that had taken seconds because its bootstrap ran long)
    stage("conventions")
    summary["conventions"] = None
    try:
        # on at most CHECK_SHOTS shots, evenly spread through the file: a wrong convention or mass ratio shows in
        # any two thousand shots, and the check then costs the same for 10⁵ shots as for 2000
        sub = np.unique(np.linspace(0, n - 1, min(n, CHECK_SHOTS)).round().astype(int))
        ccols = {c: a[sub] for c, a in cols.items()}
        others = _readings(s, ccols)
        refits = fit_many([ccols, *(r[2] for r in others)], canonical=False, **kw)
        masses = _mass_ratio(ccols, kw, refits[0]) if "masses" in assumed else None
    except OverBudget:
        warn(summary, Code.TIME_BOUND, f"the time bound ({opts.max_seconds:g} s) stopped the check of other "
                                       "conventions of the columns (units, signs, angle references): not made; give "
                                       "more time, --max-seconds")
    else:
        readings = [Reading(name, how, f.misfit() + jac, f"f = {f.point[0]:.3g}, e = {f.point[1]:.3g}")
                    for (name, how, _, jac), f in zip(others, refits[1:], strict=True)]
        rows = [{"reading": r.name, "misfit": r.misfit, "f": f.point[0], "e": f.point[1]}
                for r, f in zip(readings, refits[1:], strict=True)]
        if masses is not None:
            q, mfit = masses
            readings.append(Reading(f"a cue ball {_heavier(q)} than the object ball (mass ratio M/M′ = {q:.3g}, "
                                    "fitted; the fit takes equal balls)",
                                    "give both balls' masses, --M and --Mp (as --M 6oz --Mp 5.5oz)", mfit.misfit(),
                                    f"f = {mfit.point[0]:.3g}, e = {mfit.point[1]:.3g}", Code.BALLS))
            rows.append({"reading": readings[-1].name, "misfit": mfit.misfit(), "f": mfit.point[0],
                         "e": mfit.point[1], "mass_ratio": q})
        better_reading(summary, refits[0].misfit(), readings)
        summary["conventions"] = {"as_read": refits[0].misfit(), "readings": rows, "shots": int(sub.size),
            "misfit": "−2 log-likelihood of the values as written, each kind's noise estimated: Σ n_k ln(RSS_k/n_k)"}

    boot, boot_failed, boot_stopped = None, 0, None
    if opts.resamples and n >= MIN_BOOT_TRIALS:
        stage("bootstrap", opts.resamples)
        failed = [0]
        ran = [0]

        def progress(done: int) -> None:
            ran[0] = done
            if opts.progress is not None:
                opts.progress(done)

        def refit_many(batch: list[np.ndarray]) -> list[list[float] | None]:
            sets = [{c: a[idx] for c, a in cols.items()} for idx in batch]
            out = [list(f.point) if f.identifiability.rank == 2 else None
                   for f in fit_many(sets, sigma_speed=sig_speed, sigma_dir=sig_dir, canonical=False, **kw)]
            failed[0] += out.count(None)
            return out

        try:
            boot = bootstrap_many(refit_many, lambda rng: rng.integers(0, n, n), fit.names, opts.resamples,
                                  opts.seed, progress, batch=max(1, min(BOOT_BATCH, opts.resamples // 10)))
        except OverBudget:
            boot_stopped = ran[0]
            warn(summary, Code.TIME_BOUND, f"the time bound ({opts.max_seconds:g} s) stopped the bootstrap after "
                                           f"{ran[0]} of {opts.resamples} resamples: no bootstrap interval; the "
                                           "estimate and its profile intervals stand (give more time, --max-seconds, "
                                           "or fewer resamples, --bootstrap)")
        except ArithmeticError:  # most resamples do not determine both f and e: no bootstrap interval
            boot_failed = failed[0]
    fits = rows_from_fit(fit, "ball-ball", labels, method, boot)
    point = fit.point
    pred = predict_shots(v, phi, f_bb=point[0], e=point[1], **balls)
    p = {"cue_speed": pred.cue_speed, "cue_dir": pred.cue_dir, "obj_speed": pred.obj_speed, "obj_dir": pred.obj_dir}
    err = {c: p[c] - cols[c] for c in OUTCOMES}
    for c in DIRS:
        err[c] = wrap_angle(err[c])
    summary["fits"] = fits
    summary["identifiability"] = [identifiability(fit, labels, f"{src.name} ({measured})")]
    if fit.identifiability.rank < 2:
        warn(summary, Code.IDENTIFIABILITY, f"the {measured} measured do not determine both f and e (rank "
                                            f"{fit.identifiability.rank} of 2): see the combination reported")
    summary["noise"] = {"model": "given" if given else "estimated per kind",
                        "sigma_speed_relative": _num(fit.sigma_speed), "sigma_dir_rad": _num(fit.sigma_dir),
                        "values": {"speeds": fit.n_speed, "directions": fit.n_dir}}
    _goodness(summary, fit, given)
    stage("leave-one-out")
    # a given σ that the scatter contradicts would put every shot outside its interval: the scale is estimated
    _loo(summary, s, cols, fit, given and summary["goodness"]["chi2_p"] >= CHI2_P, balls)
    label = (lambda i: {"shot": str(s[ID][i])}) if ID in s else (lambda i: {})
    summary["per_shot"] = [{"line": s.lines[i], **label(i), "predicted": {c: float(p[c][i]) for c in OUTCOMES},
                            "error": {c: _num(err[c][i]) for c in OUTCOMES}} for i in range(n)]
    f_row = next(r for r in fits if r["id"].endswith(fit.names[0]))
    e_row = next(r for r in fits if r["id"].endswith(fit.names[1]))
    if e_row["value"] is not None and fit.e_profile is not None:
        cov = E_NOTE.format(cov=E_COVERAGE["given" if given else "estimated"])
        new = estimate_row(e_row["id"], e_row["parameter"], e_row["value"], e_row["stderr"], fit.e_profile,
                           method=method, boot=e_row["ci95_bootstrap"] and tuple(e_row["ci95_bootstrap"]),
                           at_bound=fit.estimate(fit.names[1]).at_bound, bound_aware=True,
                           note=f"{cov}; the paper's coefficient through ε = (1 − e)/(1 + e), §VI: the impact's "
                                "normal ratio where the friction keeps one direction (law (6)); over these shots it "
                                f"averages {float(np.mean(pred.normal_e)):.4g}")
        fits[fits.index(e_row)] = e_row = new
    comp: dict = {"paper": [], "today": []}
    if f_row["value"] is not None:
        ci = tuple(f_row["ci95"])
        inside = ci[1] is not None and ci[1] < CORIOLIS_F[1]
        comp["paper"].append({"claim": CORIOLIS_F[0], "value": CORIOLIS_F[1], "line": CORIOLIS_F[2],
                              "verdict": "your 95 % interval of f lies below it" if inside else
                              "your 95 % interval of f does not lie below it"})
        comp["today"] += today(("mu_bb",), ci, "f")
    if e_row["value"] is not None:
        comp["today"] += today(("e_bb",), tuple(e_row["ci95"]), "e")
    summary["comparison"] = comp
    summary["bootstrap"] = None if boot is None else {"resamples": boot.resamples, "seed": boot.seed,
                                                      "failed": boot.failed, "kind": "pairs (shots resampled)",
                                                      "note": boot_note(kind)}
    if boot_stopped is not None:
        summary["bootstrap"] = {"resamples": boot_stopped, "requested": opts.resamples, "seed": opts.seed,
                                "failed": failed[0], "kind": "pairs (shots resampled)",
                                "note": f"stopped by the time bound after {boot_stopped} of {opts.resamples} "
                                        "resamples: no bootstrap interval"}
    if boot_failed:
        summary["bootstrap"] = {"resamples": opts.resamples, "seed": opts.seed, "failed": boot_failed,
                                "kind": "pairs (shots resampled)", "note": "no bootstrap interval: most resamples "
                                "do not determine both f and e"}
    return FitOutcome(summary, _figures(cols, p, err, phi), *_table(s, cols, p, err))


def _balls(opts: FitOptions) -> tuple[dict[str, float], list[str]]:
    """The balls (``predict_shots``' M, Mp, R, Rp, k, kp) and what was assumed of them: equal masses unless both
    --M and --Mp are given (only their ratio matters), the object ball's radius and inertia the cue ball's unless
    given."""
    if (opts.M is None) != (opts.Mp is None):
        given = "--M" if opts.M is not None else "--Mp"
        mass = opts.M if opts.M is not None else opts.Mp
        raise InputError(f"{given} ({mass:.4g} kg) alone", "give both balls' masses, "
                         "--M (the cue ball) and --Mp (the object ball), or neither (equal balls): only their ratio "
                         "enters the impact")
    assumed = []
    if opts.M is None:
        assumed.append("masses")
    if opts.Rp is None:
        assumed.append("radii")
    if opts.kp is None:
        assumed.append("inertia")
    M = 0.17 if opts.M is None else opts.M  # equal balls: any mass, only M/M′ = 1 enters
    balls = {"M": M, "Mp": M if opts.Mp is None else opts.Mp, "R": opts.R, "Rp": opts.R if opts.Rp is None else opts.Rp,
             "k": opts.k, "kp": opts.k if opts.kp is None else opts.kp}
    return balls, assumed


def _balls_summary(balls: dict[str, float], assumed: list[str]) -> dict[str, Any]:
    """fit.json's ``balls``: what the prediction took, what of it was assumed, and a line for people."""
    tilt = math.degrees(ball_tilt(balls["R"], balls["Rp"]))
    said = {"masses": "equal masses (only M/M′ enters: give --M and --Mp if the balls differ)",
            "radii": "the object ball's radius the cue ball's (--Rp)", "inertia": "the object ball's MR²/I the cue "
            "ball's (--kp)"}
    masses = ("M/M′ = 1 (equal, assumed)" if "masses" in assumed else
              f"M = {balls['M'] * 1e3:.4g} g, M′ = {balls['Mp'] * 1e3:.4g} g (M/M′ = {balls['M'] / balls['Mp']:.4g})")
    radii = (f"R = R′ = {balls['R'] * 1e3:.4g} mm" if balls["Rp"] == balls["R"] else
             f"R = {balls['R'] * 1e3:.4g} mm, R′ = {balls['Rp'] * 1e3:.4g} mm (line of centres tilted {tilt:.2g}°, "
             "neglected)")
    inertia = (f"k = k′ = {balls['k']:g}" if balls["kp"] == balls["k"] else f"k = {balls['k']:g}, k′ = {balls['kp']:g}")
    text = f"{masses}; {radii}; {inertia} (MR²/I)"
    if assumed:
        text += "; assumed: " + "; ".join(said[a] for a in assumed)
    return {"M_kg": balls["M"] if "masses" not in assumed else None,
            "Mp_kg": balls["Mp"] if "masses" not in assumed else None, "mass_ratio": balls["M"] / balls["Mp"],
            "R_m": balls["R"], "Rp_m": balls["Rp"], "k": balls["k"], "kp": balls["kp"], "tilt_deg": tilt,
            "assumed": assumed, "text": text}


def _heavier(q: float) -> str:
    """"9 % heavier" for a mass ratio q = 1.09, "8 % lighter" for 0.92."""
    return f"{abs(q - 1) * 100:.2g} % {'heavier' if q > 1 else 'lighter'}"


def _mass_ratio(cols: dict[str, np.ndarray], kw: dict[str, Any], equal: BallBallFit
                ) -> tuple[float, BallBallFit] | None:
    """The mass ratio M/M′ at which the shots fit best, and the fit there: (f, e) refitted at each of
    ``MASS_RATIOS`` and 1, then at the lowest point of the parabola through the best and its neighbours (kept
    inside the grid); the best of all evaluated. One batched fit per stage (``fit_many``), started from the equal
    balls' estimate, with its noise levels held (``equal``): a σ re-estimated at a ratio far from the data's
    oscillates for ten rounds; held, the misfit found is at least the one with σ profiled, so the improvement is,
    if anything, understated."""
    qs = np.array(sorted((1.0, *MASS_RATIOS)))
    x0 = (float(equal.point[0]), float(equal.point[1]))
    held = {"sigma_speed": _num(equal.sigma_speed), "sigma_dir": _num(equal.sigma_dir), "x0": x0}
    if not all(v is None or v > 0 for v in (held["sigma_speed"], held["sigma_dir"])):
        return None  # no scatter to weigh by (said by its own warning): no ratio to look for
    fits = fit_many([cols] * qs.size, canonical=False, **held, **{**kw, "M": kw["Mp"] * qs})
    m = np.array([f.misfit() for f in fits])
    i = int(np.clip(np.argmin(m), 1, qs.size - 2))
    x, y = qs[i - 1:i + 2], m[i - 1:i + 2]
    a, b, _ = np.polyfit(x, y, 2)
    q = float(np.clip(-b / (2 * a), qs[0], qs[-1])) if a > 0 else float(qs[np.argmin(m)])
    extra = fit_many([cols], canonical=False, **held, **{**kw, "M": kw["Mp"] * q})[0]
    cands = [*zip(qs.tolist(), fits, strict=True), (q, extra)]
    best = min(cands, key=lambda c: c[1].misfit())
    return float(best[0]), best[1]


def _num(x: float) -> float | None:
    """A number for fit.json: None where not measured (JSON has no NaN)."""
    return float(x) if math.isfinite(x) else None


def _goodness(summary: dict[str, Any], fit: BallBallFit, given: bool) -> None:
    """σ given: χ² and its p (warned below ``CHI2_P``). σ estimated: each kind's noise against the plausible."""
    if given:
        red, p = chi2_given(fit.chi2, fit.dof)
        summary["goodness"] = {"chi2": fit.chi2, "dof": fit.dof, "reduced_chi2": red, "chi2_p": p}
        if p < CHI2_P:
            warn(summary, Code.CHI2, f"the scatter exceeds the given σ: reduced χ² = {red:.3g} on {fit.dof} degrees "
                                     f"of freedom (p = {p:.2g}); the intervals from that σ are too narrow (omit "
                                     "--sigma-speed/--sigma-dir to estimate the noise)")
        return
    summary["goodness"] = {"reduced_chi2": None, "chi2_p": None,
                           "plausible_noise": {"speed_relative": SPEED_NOISE_LIMIT, "dir_rad": DIR_NOISE_LIMIT}}
    if fit.n_speed:
        noise_plausible(summary, 100 * fit.sigma_speed, 100 * SPEED_NOISE_LIMIT, "the post-slip speeds", "%")
    if fit.n_dir:
        noise_plausible(summary, math.degrees(fit.sigma_dir), math.degrees(DIR_NOISE_LIMIT),
                        "the post-slip directions", "°")


def _loo(summary: dict[str, Any], s: Series, cols: dict[str, np.ndarray], fit: BallBallFit, given: bool,
         balls: dict[str, float]) -> None:
    """Each shot predicted from the others: the linearised deleted residuals of the weighted fit at its optimum
    (``checks.leave_one_out``, the first-order approximation of a refit without the shot, not a refit), each
    measured value's 95 % prediction interval (normal with σ known, ``given``, else Student's t on the degrees of
    freedom left), and the shots outside theirs named at the family-wise 5 % (``checks.name_outliers``). Speeds
    in m/s, directions in rad."""
    if fit.identifiability.rank < 2:
        summary["leave_one_out"] = []
        return
    sig = [x if math.isfinite(x) else 1.0 for x in (fit.sigma_speed, fit.sigma_dir)]
    rows = weighted_rows(cols, fit.point, sigma_speed=sig[0], sigma_dir=sig[1], **balls)
    # estimated per kind: each scale beyond the common one costs a degree of freedom; a given σ's ratio costs none
    n_kinds = int(fit.n_speed > 0) + int(fit.n_dir > 0)
    extra = 0 if given or summary["noise"]["model"] == "given" else n_kinds - 1
    res = leave_one_out(rows.r, rows.J, rows.shot, sigma_known=given, dof_extra=extra)
    labels = [int(g) for g in res["labels"]]
    q = np.full(rows.r.size, float(dist.norm_ppf(0.975)))  # per row: the 95 % quantile of its shot's interval
    if not given:
        for g in labels:
            idx = rows.shot == g
            df = rows.r.size - int(res["rank"]) - int(idx.sum()) - extra
            q[idx] = float(dist.t_ppf(0.975, df)) if df >= 1 else math.nan
    e, sd = res["deleted"], res["sd"]
    pred, lo, hi = (rows.value(z) for z in (e, e - q * sd, e + q * sd))
    out, lines = [], []
    for k, g in enumerate(labels):
        qty = {}
        for i in np.flatnonzero(rows.shot == g):
            name = QUANTITIES[int(rows.quantity[i])]
            qty[name] = {"measured": float(rows.measured[i]), "predicted": _num(pred[i]), "low": _num(lo[i]),
                         "high": _num(hi[i]), "unit": "rad" if name in DIRS else "m/s"}
        out.append({"line": s.lines[g], "p": _num(res["p"][k]), "quantities": qty})
        lines.append(s.lines[g])
    summary["leave_one_out"] = out
    bad = name_outliers(summary, lines, res["p"], "shot", s.table)
    if bad and any(w["code"] == Code.OUTLIER.value for w in summary["warnings"]):
        # the speeds' noise is taken as relative: a constant noise (video tracking, ± a few cm/s) makes slow balls
        # look like outliers; say so beside the warning
        summary["warnings"][-1]["message"] += ("; the fit takes the speeds' noise as proportional to the speed: "
                                               "a constant noise (± a few cm/s) makes slow balls look like outliers")


def _table(s: Series, cols: dict[str, np.ndarray], p: dict[str, np.ndarray], err: dict[str, np.ndarray]
           ) -> tuple[tuple[str, ...], tuple[tuple[Any, ...], ...]]:
    """residuals.csv: per shot and quantity, measured, predicted and predicted − measured (blank: not measured)."""
    headers = ["line", "v (m/s)", "φ (rad)"]
    for c in OUTCOMES:
        unit = "rad" if c in DIRS else "m/s"
        headers += [f"{WHAT[c]} ({unit}): measured", "predicted", "predicted − measured"]
    rows = []
    for i in range(s["v"].size):
        row: list[Any] = [s.lines[i], float(cols["v"][i]), float(cols["phi"][i])]
        for c in OUTCOMES:
            m = float(cols[c][i])
            row += [m if math.isfinite(m) else "", float(p[c][i]), float(err[c][i]) if math.isfinite(m) else ""]
        rows.append(tuple(row))
    return tuple(headers), tuple(rows)


def _figures(cols: dict[str, np.ndarray], p: dict[str, np.ndarray], err: dict[str, np.ndarray], phi: np.ndarray
             ) -> tuple[FigureSpec, ...]:
    """Predicted against measured speeds, and direction errors against the cut angle (measured values only)."""
    def pts(x: np.ndarray, y: np.ndarray, ok: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return x[ok], y[ok]

    out = []
    ok = {c: np.isfinite(cols[c]) for c in OUTCOMES}
    if ok["cue_speed"].any() or ok["obj_speed"].any():
        top = max(float(np.max(cols[c][ok[c]], initial=0.0)) for c in SPEEDS) * 1.05
        lim = [0.0, top]
        out.append(FigureSpec("fit", "resal fit ball-ball: post-slip speeds, predicted against measured",
                              "measured speed (m/s)", "predicted speed (m/s)",
                              (layer("points", *pts(cols["obj_speed"], p["obj_speed"], ok["obj_speed"]),
                                     label="object ball"),
                               layer("points", *pts(cols["cue_speed"], p["cue_speed"], ok["cue_speed"]), color="C1",
                                     marker="s", label="cue ball"),
                               layer("line", lim, lim, color="0.4", style=":", label="predicted = measured"))))
    if ok["cue_dir"].any() or ok["obj_dir"].any():
        deg = 180 / math.pi
        out.append(FigureSpec("residuals", "resal fit ball-ball: direction errors against the cut angle",
                              "cut angle φ (°)", "predicted − measured direction (°)",
                              (layer("points", *pts(phi * deg, err["obj_dir"] * deg, ok["obj_dir"]),
                                     label="object ball"),
                               layer("points", *pts(phi * deg, err["cue_dir"] * deg, ok["cue_dir"]), color="C1",
                                     marker="s", label="cue ball"),
                               layer("line", [float(phi.min() * deg), float(phi.max() * deg)], [0.0, 0.0],
                                     color="0.4", style=":"))))
    return tuple(out)
