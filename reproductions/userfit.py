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
from .fitting import fit_direct_impact, fit_physical, fit_positions, fit_rebound, fit_times
from .results import fit_rows, identifiability_report
from .series import check_pendulum_trials, read_imprints, read_rebounds, read_series

__all__ = ["KINDS", "fit_csv"]

KINDS = ("rebound", "pendulum", "ricochet")
G = 9.80665


def _rows(fits: list) -> list[dict[str, Any]]:
    return [{k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(f).items()} for f in fits]


def _header(path: Path) -> str:
    """The header line as ``read_series`` finds it: the first line that is neither empty nor a # comment."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError):
        return ""  # read_series says what is wrong with the file
    return next((ln for ln in text.splitlines() if ln.strip() and not ln.startswith("#")), "")


SIGMA_RANGE = (1e-12, 1e6)  # relative to the largest measured value


def _check_sigma(sigma: float | None, data: tuple[np.ndarray, ...]) -> None:
    """A given σ between 1e-12 and 1e6 times the largest measured value: smaller is below the rounding of the
    numbers themselves (and overflows the weighted residuals), larger says the data carry no information."""
    if sigma is None:
        return
    scale = max(float(np.max(np.abs(d))) for d in data)
    lo, hi = (r * scale for r in SIGMA_RANGE)
    if not lo <= sigma <= hi:
        raise InputError(f"--sigma {sigma:g}", f"expected a standard deviation in [{lo:.3g}, {hi:.3g}], i.e. 1e-12 "
                                               f"to 1e6 times the largest measured value ({scale:g}), in its unit")


def fit_csv(kind: str, path: Path, M: float = 0.6, Mp: float = 0.2, R: float = 0.0305, k: float = 2.5,
            sigma: float | None = None) -> dict[str, Any]:
    """Fit the file at ``path`` with the estimator of ``kind``; see the module docstring for the columns."""
    if kind not in KINDS:
        raise InputError(f"kind '{kind}'", f"expected one of {', '.join(KINDS)}")
    if not path.is_file():
        raise InputError(str(path), "no such file")
    note = "" if sigma is None else f"σ = {sigma:g} given"
    if kind == "ricochet" and sigma is not None:
        raise InputError(f"--sigma {sigma:g}", "not used by the ricochet fit, which estimates the noise of "
                                               "positions and instants from their residuals: leave it out")
    if kind == "rebound":
        heights = "h0" in _header(path)
        cols = ("h0", "h1") if heights else ("V0", "V1")
        s = read_rebounds(path, heights)  # refuses h1 < 0, h1 > h0, V1 > 0, |V1| > V0: no abs(), no guess
        a, b = s[cols[0]], s[cols[1]]
        _check_sigma(sigma, (a, b))
        V0, V1 = (np.sqrt(2 * G * a), -np.sqrt(2 * G * b)) if heights else (a, b)
        fit = fit_rebound(V0, V1, sigma)
        fits = fit_rows(fit, "rebound", {"eps": "ε"}, "least squares on §I eq. (9)", note)
        ident = [identifiability_report(fit, "rebound", {"eps": "ε"}, path.name)]
        n = a.size
    elif kind == "pendulum":
        s = read_series(path, ("V0", "V1", "V1p"), optional=("M", "Mp"), min_rows=1, positive=("V0", "M", "Mp"))
        n = s["V0"].size
        masses = s.get("M", np.full(n, M)), s.get("Mp", np.full(n, Mp))
        _check_sigma(sigma, (s["V0"], s["V1"], s["V1p"]))
        check_pendulum_trials(s, *masses, sigma)  # momentum kept and bodies apart, within the noise
        fit = fit_direct_impact(*masses, s["V0"], s["V1"], s["V1p"], sigma)
        labels = {"eps": "ε (striking body)", "epsp": "ε′ (struck body)"}
        fits = fit_rows(fit, "pendulum", labels, "least squares on §I eqs (8), bounds [0, 1]", note)
        ident = [identifiability_report(fit, "pendulum", labels, path.name)]
    else:
        x, t = read_imprints(path)
        fx = fit_positions(x, k=k)
        labels = {"nu": "ν", "A": "A = 2a0² sin α0 cos α0/g (m)", "u": "f tan α0"}
        fits = fit_rows(fx, "positions", labels, "least squares on imprint positions (§III, spinless)", note)
        ident = [identifiability_report(fx, "positions", labels, f"{path.name}: positions")]
        if t is not None:
            ft = fit_times(t, g=G)
            fits += fit_rows(ft, "times", {"nu": "ν (acoustic)", "zeta1": "ζ1 (m/s)"},
                             "least squares on impact instants")
            fj = fit_physical(x, t, fx, R=R, k=k, g=G)
            fits += fit_rows(fj, "joint-physical", {"f": "f (positions + instants)"},
                             "least squares, physical parameters", only=("f",))
            ident.append(identifiability_report(fj, "joint-physical",
                                                {"nu": "ν", "f": "f", "a0": "a0", "alpha0": "α0"},
                                                f"{path.name}: positions and instants"))
        n = x.size
    return {"kind": kind, "file": str(path), "n": int(n), "fits": _rows(fits), "identifiability": ident}
