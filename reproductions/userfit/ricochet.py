"""``resal fit ricochet``: ν (and f where identifiable) from imprint positions and instants, §III n°8-10."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from ..fitting import fit_physical, fit_positions, fit_times
from ..results import FigureSpec, layer
from ..series import check_imprints, read_series
from .common import FitOptions, FitOutcome, base_summary, columns_read, identifiability, rows_from_fit

DIMS = {"x": "length", "t": "time"}


def fit_ricochet(kind: str, path: Path, opts: FitOptions) -> FitOutcome:
    if opts.sigma is not None:
        raise InputError(f"--sigma {opts.sigma:g}", "not used by the ricochet fit, which estimates the noise of "
                                                    "positions and instants from their residuals: leave it out")
    s = read_series(path, ("x",), optional=("t",), min_rows=1, dims=DIMS)
    x, t = s["x"], s.get("t")
    check_imprints(x, str(path), t, s.lines)
    x = x - x[0]
    t = None if t is None else t - t[0]
    fx = fit_positions(x, k=opts.k)
    labels = {"nu": "ν", "A": "A = 2a0² sin α0 cos α0/g (m)", "u": "f tan α0"}
    fits = rows_from_fit(fx, "positions", labels, "least squares on imprint positions (§III, spinless)",
                         units={"A": "m"})
    ident = [identifiability(fx, labels, f"{path.name}: positions")]
    if t is not None:
        ft = fit_times(t, g=opts.g)
        fits += rows_from_fit(ft, "times", {"nu": "ν (acoustic)", "zeta1": "ζ1 (m/s)"},
                              "least squares on impact instants", units={"zeta1": "m/s"})
        fj = fit_physical(x, t, fx, R=opts.R, k=opts.k, g=opts.g)
        fits += rows_from_fit(fj, "joint-physical", {"f": "f (positions + instants)"},
                              "least squares, physical parameters", only=("f",))
        ident.append(identifiability(fj, {"nu": "ν", "f": "f", "a0": "a0", "alpha0": "α0"},
                                     f"{path.name}: positions and instants"))
    summary = base_summary(kind, path, x.size, columns_read(s, DIMS), opts)
    summary["fits"] = fits
    summary["identifiability"] = ident
    summary["bootstrap"] = None
    nrange = np.arange(x.size)
    fig = FigureSpec("fit", "resal fit ricochet: imprint positions", "imprint number", "x (m)",
                     (layer("points", nrange, x, label="measured"),))
    return FitOutcome(summary, (fig,), ("line", "x (m)") + (("t (s)",) if t is not None else ()),
                      tuple((s.lines[i], float(x[i]), *(() if t is None else (float(t[i]),))) for i in range(x.size)))
