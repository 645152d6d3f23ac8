"""``resal fit ball-ball``: oblique shots → the ball–ball friction f and e, and each shot's predicted outcome.

Per shot: the cue ball's speed v (rolling, natural roll) and the cut angle φ at the impact, and, once each ball has
stopped sliding on the cloth, the speeds and directions of both. The prediction is the §VI n°13 impact of two
equal balls with friction f (ε = ε′ = (1 − e)/(1 + e)) followed by the §II n°7 slide to rolling
(``fitting_ballball``); the fit adjusts (f, e) to all shots, with one noise level per kind of measurement (speeds,
directions) estimated from the residuals, or given.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...errors import InputError
from ...results import FigureSpec, layer
from ...series import read_series
from ..estimators.shots import fit_many, fit_shots, predict_shots, shot_residuals
from ..estimators.trials import bootstrap_many
from .common import (
    BOOT_NOTE,
    MIN_BOOT_TRIALS,
    FitOptions,
    FitOutcome,
    base_summary,
    columns_read,
    identifiability,
    rows_from_fit,
    today,
)

DIMS = {"v": "speed", "phi": "angle", "cue_speed": "speed", "cue_dir": "angle", "obj_speed": "speed",
        "obj_dir": "angle"}
COLS = tuple(DIMS)
LABELS = {"f_bb": "f (ball–ball friction)", "e_bb": "e (Newton's, ε = ε′ = (1 − e)/(1 + e))"}
CORIOLIS_F = ("Coriolis: the friction of one ball on the other 'does not seem to reach 0.03' (§V n°12)", 0.03, 610)


def fit_ballball(kind: str, path: Path, opts: FitOptions) -> FitOutcome:
    s = read_series(path, COLS, min_rows=3, positive=("v", "cue_speed", "obj_speed"), dims=DIMS)
    n = s["v"].size
    v, phi = s["v"], s["phi"]
    for i in range(n):
        if not abs(phi[i]) < math.pi / 2:
            raise InputError(s.at(i), f"column '{s.written['phi']}': expected a cut angle strictly between −90° and "
                                      f"90° (the cue ball must reach the object ball), got {math.degrees(phi[i]):g}°")
    if (opts.sigma_speed is None) != (opts.sigma_dir is None):
        raise InputError("--sigma-speed/--sigma-dir", "give both noise levels (speed, relative; direction, in the "
                                                      "direction columns' unit) or neither")
    sig_dir = None if opts.sigma_dir is None else opts.sigma_dir * s.factors["cue_dir"]
    cols = [s[c] for c in COLS]
    fit = fit_shots(*cols, R=opts.R, k=opts.k, sigma_speed=opts.sigma_speed, sigma_dir=sig_dir)
    names = dict(zip(fit.names, ("f_bb", "e_bb"), strict=True))
    labels = {k: LABELS[v_] for k, v_ in names.items()}
    method = "least squares on post-slip speeds and directions: §VI n°13 impact, then §II n°7 slide" + (
        "; σ given" if sig_dir is not None else "; a noise level per kind of measurement, estimated (Student's t)")
    def refit_many(batch: list[np.ndarray]) -> list[list[float] | None]:
        sets = [dict(zip(("v", "phi", "cue_speed", "cue_dir", "obj_speed", "obj_dir"), (c[idx] for c in cols),
                         strict=True)) for idx in batch]
        return [list(f.point) if f.identifiability.rank == 2 else None
                for f in fit_many(sets, R=opts.R, k=opts.k, sigma_speed=opts.sigma_speed, sigma_dir=sig_dir)]

    boot = bootstrap_many(refit_many, lambda rng: rng.integers(0, n, n), fit.names, opts.resamples, opts.seed,
                          opts.progress) if opts.resamples and n >= MIN_BOOT_TRIALS else None
    fits = rows_from_fit(fit, "ball-ball", labels, method, boot)
    point = fit.point
    pred = predict_shots(v, phi, f_bb=point[0], e=point[1], R=opts.R, k=opts.k)
    res = shot_residuals((point[0], point[1]), *cols, R=opts.R, k=opts.k)
    summary = base_summary(kind, path, n, columns_read(s, DIMS), opts)
    summary["fits"] = fits
    summary["identifiability"] = [identifiability(fit, labels, path.name)]
    summary["noise"] = {"model": "given" if sig_dir is not None else "estimated per kind",
                        "sigma_speed_relative": fit.sigma_speed, "sigma_dir_rad": fit.sigma_dir}
    summary["per_shot"] = [{"line": s.lines[i], "predicted": {"cue_speed": float(pred.cue_speed[i]),
                                                              "cue_dir": float(pred.cue_dir[i]),
                                                              "obj_speed": float(pred.obj_speed[i]),
                                                              "obj_dir": float(pred.obj_dir[i])},
                            "error": {"cue_speed": float(res.cue_speed[i]), "cue_dir": float(res.cue_dir[i]),
                                      "obj_speed": float(res.obj_speed[i]), "obj_dir": float(res.obj_dir[i])}}
                           for i in range(n)]
    f_row = next(r for r in fits if r["id"].endswith(fit.names[0]))
    e_row = next(r for r in fits if r["id"].endswith(fit.names[1]))
    if e_row["value"] is not None:
        e_row["note"] = "; ".join(t for t in (e_row["note"], (
            "the paper's coefficient through ε = (1 − e)/(1 + e), §VI: with friction the impact's normal "
            f"restitution is lower, {float(np.mean(pred.normal_e)):.4g} on average over these shots")) if t)
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
                                                      "note": BOOT_NOTE}
    headers = ("line", "v (m/s)", "φ (rad)", "cue speed: measured", "predicted", "cue direction (rad): measured",
               "predicted", "object speed: measured", "predicted", "object direction (rad): measured", "predicted")
    rows = tuple((s.lines[i], float(v[i]), float(phi[i]), float(s["cue_speed"][i]), float(pred.cue_speed[i]),
                  float(s["cue_dir"][i]), float(pred.cue_dir[i]), float(s["obj_speed"][i]),
                  float(pred.obj_speed[i]), float(s["obj_dir"][i]), float(pred.obj_dir[i])) for i in range(n))
    lim = [0.0, float(max(s["cue_speed"].max(), s["obj_speed"].max()) * 1.05)]
    fig = FigureSpec("fit", "resal fit ball-ball: post-slip speeds, predicted against measured",
                     "measured speed (m/s)", "predicted speed (m/s)",
                     (layer("points", s["obj_speed"], pred.obj_speed, label="object ball"),
                      layer("points", s["cue_speed"], pred.cue_speed, color="C1", marker="s", label="cue ball"),
                      layer("line", lim, lim, color="0.4", style=":", label="predicted = measured")))
    deg = 180 / math.pi
    resid = FigureSpec("residuals", "resal fit ball-ball: direction errors against the cut angle", "cut angle φ (°)",
                       "predicted − measured direction (°)",
                       (layer("points", phi * deg, res.obj_dir * deg, label="object ball"),
                        layer("points", phi * deg, res.cue_dir * deg, color="C1", marker="s", label="cue ball"),
                        layer("line", [float(phi.min() * deg), float(phi.max() * deg)], [0.0, 0.0], color="0.4",
                              style=":")))
    return FitOutcome(summary, (fig, resid), headers, rows)
