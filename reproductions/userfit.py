"""``resal fit``: ε or ν, with uncertainties and an identifiability report, from a user's own CSV file.

The same estimators as the experiments: eq. (9) of §I for rebounds, eqs (8) of §I for two pendulums, the
ricochet model of §III for imprint positions (and impact instants, when the file has them).
"""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputError
from .experiments import ricochet
from .experiments.base import fit_rows, identifiability_report, read_series
from .fitting import fit_direct_impact, fit_rebound

__all__ = ["KINDS", "fit_csv"]

KINDS = ("rebound", "pendulum", "ricochet")
G = 9.80665


def _rows(fits: list) -> list[dict[str, Any]]:
    return [{k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(f).items()} for f in fits]


def fit_csv(kind: str, path: Path, M: float = 0.6, Mp: float = 0.2, R: float = 0.0305, k: float = 2.5,
            sigma: float | None = None) -> dict[str, Any]:
    """Fit the file at ``path`` with the estimator of ``kind``; see the module docstring for the columns."""
    if kind not in KINDS:
        raise InputError(f"kind '{kind}'", f"expected one of {', '.join(KINDS)}")
    if not path.is_file():
        raise InputError(str(path), "no such file")
    note = "" if sigma is None else f"σ = {sigma:g} given"
    if kind == "rebound":
        header = path.read_text(encoding="utf-8", errors="replace").lstrip().splitlines()[0:1]
        heights = bool(header) and "h0" in header[0]
        cols = ("h0", "h1") if heights else ("V0", "V1")
        s = read_series(path, cols, min_rows=2, positive=(cols[0],))
        a, b = s[cols[0]], s[cols[1]]
        V0, V1 = (np.sqrt(2 * G * a), -np.sqrt(2 * G * np.abs(b))) if heights else (a, b)
        fit = fit_rebound(V0, V1, sigma)
        fits = fit_rows(fit, {"eps": "ε"}, "least squares on §I eq. (9)", note)
        ident = [identifiability_report(fit, {"eps": "ε"}, path.name)]
        n = a.size
    elif kind == "pendulum":
        s = read_series(path, ("V0", "V1", "V1p"), optional=("M", "Mp"), min_rows=1, positive=("V0", "M", "Mp"))
        n = s["V0"].size
        fit = fit_direct_impact(s.get("M", np.full(n, M)), s.get("Mp", np.full(n, Mp)), s["V0"], s["V1"], s["V1p"],
                                sigma)
        labels = {"eps": "ε (striking body)", "epsp": "ε′ (struck body)"}
        fits = fit_rows(fit, labels, "least squares on §I eqs (8), bounds [0, 1]", note)
        ident = [identifiability_report(fit, labels, path.name)]
    else:
        surface = ricochet.Surface("user", path.stem, None, path)
        x, t = ricochet.load_series(surface)
        p = ricochet.Params(R=R, k=k, g=G, p0_fit=0.0, surfaces=(surface,), seeds=1, drop_height_ratio=1.0,
                            map_alpha_max=1.0, map_f_max=0.5, map_nu=0.8)  # the map fields are unused by the fits
        fx = ricochet.fit_positions(p, x)
        labels = {"nu": "ν", "A": "A = 2a0² sin α0 cos α0/g (m)", "u": "f tan α0"}
        fits = fit_rows(fx, labels, "least squares on imprint positions (§III, spinless)", note)
        ident = [identifiability_report(fx, labels, f"{path.name}: positions")]
        if t is not None:
            ft = ricochet.fit_times(p, t)
            fits += fit_rows(ft, {"nu": "ν (acoustic)", "zeta1": "ζ1 (m/s)"}, "least squares on impact instants")
            fj = ricochet.fit_physical(p, x, t, fx)
            fits += fit_rows(fj, {"f": "f (positions + instants)"}, "least squares, physical parameters",
                             only=("f",))
            ident.append(identifiability_report(fj, {"nu": "ν", "f": "f", "a0": "a0", "alpha0": "α0"},
                                                f"{path.name}: positions and instants"))
        n = x.size
    return {"kind": kind, "file": str(path), "n": int(n), "fits": _rows(fits), "identifiability": ident}
