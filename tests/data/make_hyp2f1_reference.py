"""Writes ``hyp2f1_reference.npz``: ₂F₁(−½, c; c + 1; z) by mpmath at 40 digits, over the range of the models
that decay a slip (``reproductions.mechanics.slip``), for ``tests/test_slip_kernel.py``.

Run it with mpmath, which the project does not need (e.g. ``python3 -m venv /tmp/mp && /tmp/mp/bin/pip install
mpmath numpy && /tmp/mp/bin/python tests/data/make_hyp2f1_reference.py``); it takes seconds.

The range: c = β/(2(α − β)) is k/2 on the cushion (§IV, α = 1 + k, β = k) and (k + k′μ)/(2(1 + μ)) on the
cloth (§VI, μ = M/M′), between k/2 and k′/2; k, k′ > 0 and μ > 0 are unbounded in the registry, so c covers
(0, ∞). z = −(φ0/ψ0)² U^(2d) covers (−∞, 0]. The grid: c from 1e-12 to 1e8 (log-spaced), next to ½ + m
(where the connection formulas for z → −∞ degenerate) and to the switches of ``slip._F`` (C_SERIES, C_BIG);
−z from 0 and 1e-300 to 1e300, dense next to 1 (the switch between its series); and 4000 random points,
log-uniform in c ∈ [1e-6, 1e3] and −z ∈ [1e-6, 1e12]. Inputs are stored as binary floats (exact), the reference
as the float nearest the 40-digit value.
"""

from __future__ import annotations

from pathlib import Path

import mpmath as mp
import numpy as np

mp.mp.dps = 40
OUT = Path(__file__).with_name("hyp2f1_reference.npz")


def grid_c() -> np.ndarray:
    c = list(np.logspace(-12, 8, 61))
    for m in range(0, 8):  # ½ + m from both sides, down to an ulp
        h = 0.5 + m
        c += [h, *(h + s * d for s in (-1, 1) for d in (1e-15 * h, 1e-12, 1e-9, 1e-6, 1e-4, 1e-2))]
    c += [float(np.nextafter(0.5, 0)), float(np.nextafter(0.5, 1))]
    c += [1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 7.5, 10.0, 12.5, 15.0, 16.0, 20.0, 50.0, 100.0]  # k/2, k = 2.5
    for edge in (3.0, 16.0):  # slip._F's switches
        c += [float(np.nextafter(edge, 0)), float(np.nextafter(edge, 20)), edge - 1e-9, edge + 1e-9]
    c += [1e-300, 1e-100, 1e-30, 1e10, 1e15]
    return np.unique(np.array(c, dtype=float))


def grid_w() -> np.ndarray:
    w = [0.0, 1e-300, 1e-200, 1e-100, *np.logspace(-20, 300, 65)]
    for d in (1e-15, 1e-12, 1e-9, 1e-6, 1e-3, 0.01, 0.1, 0.25):
        w += [1 - d, 1 + d]
    w += [1.0, float(np.nextafter(1.0, 0)), float(np.nextafter(1.0, 2)), 0.5, 2.0, 3.0, 5.0, 10.0, 1e308]
    return np.unique(np.array(w, dtype=float))


def ref(c: float, w: float) -> float:
    return float(mp.hyp2f1(-0.5, mp.mpf(c), mp.mpf(c) + 1, -mp.mpf(w)))


def main() -> None:
    c, w = grid_c(), grid_w()
    table = np.array([[ref(ci, wi) for wi in w] for ci in c])
    rng = np.random.default_rng(20260202)
    rc = 10.0 ** rng.uniform(-6, 3, 4000)
    rw = 10.0 ** rng.uniform(-6, 12, 4000)
    rv = np.array([ref(ci, wi) for ci, wi in zip(rc, rw, strict=True)])
    np.savez_compressed(OUT, c=c, w=w, table=table, random_c=rc, random_w=rw, random=rv)
    print(f"{OUT}: {c.size} c × {w.size} w + {rc.size} random points")


if __name__ == "__main__":
    main()
