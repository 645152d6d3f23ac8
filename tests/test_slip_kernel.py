"""The slip-decay function F(c, z) = ₂F₁(−½, c; c + 1; z) of ``slip._F`` (§IV n°11 eq. (10), §VI n°13) against
mpmath at 40 digits, over the range of c and z that the cushion and the two balls on the cloth can reach
(``tests/data/make_hyp2f1_reference.py`` wrote the table and documents the grid): every value to 1e-13
relative, c next to ½ + m, tiny and huge, z → 0 and −z up to 1e308. mpmath is not needed here."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from reproductions.mechanics import slip

TABLE = np.load(Path(__file__).parent / "data" / "hyp2f1_reference.npz")
RTOL = 1e-13


def _rel(got: np.ndarray, ref: np.ndarray) -> np.ndarray:
    return np.abs(got - ref) / np.abs(ref)


def test_grid_elementwise():
    """Each grid value on its own (one column of coefficients per call, the classes of ``_class_series``)."""
    c, w, ref = TABLE["c"], TABLE["w"], TABLE["table"]
    worst = max(float(np.max(_rel(slip._F(np.full(w.size, ci), -w), ref[i]))) for i, ci in enumerate(c))
    assert worst <= RTOL


def test_grid_mixed_c():
    """The whole grid at once: c differs from element to element (one column of coefficients per element)."""
    c, w, ref = TABLE["c"], TABLE["w"], TABLE["table"]
    C, W = np.meshgrid(c, w, indexing="ij")
    err = _rel(slip._F(C.ravel(), -W.ravel()), ref.ravel())
    assert np.all(np.isfinite(err)) and err.max() <= RTOL, (C.ravel()[np.argmax(err)], W.ravel()[np.argmax(err)])


def test_random_points():
    rc, rw, ref = TABLE["random_c"], TABLE["random_w"], TABLE["random"]
    assert _rel(slip._F(rc, -rw), ref).max() <= RTOL
    assert max(float(_rel(slip._F(rc[i:i + 1], -rw[i:i + 1]), ref[i:i + 1])[0]) for i in range(0, rc.size, 97)) <= RTOL


@pytest.mark.parametrize("c", [1e-12, 0.5 - 1e-12, 0.5, 0.5 + 1e-15, 1.25, 3.5, 15.999999, 16.0, 1e6])
def test_edges_of_the_grid(c):
    """z → 0 gives 1; −z → ∞ the leading term c/(c + ½) √(−z) (the rest of the large-|z| expansion is O(1))."""
    i = int(np.argmin(np.abs(TABLE["c"] - c)))
    ci, w, ref = TABLE["c"][i], TABLE["w"], TABLE["table"][i]
    got = slip._F(np.full(w.size, ci), -w)
    assert _rel(got, ref).max() <= RTOL
    assert got[0] == 1.0 and got[-1] == pytest.approx(ci / (ci + 0.5) * np.sqrt(w[-1]), rel=1e-13)


def test_classes_of_c_within_their_rounding():
    """c's within ``CLASS_ULPS`` (1 + 2c) ulps share one column of coefficients: still within RTOL of each own
    reference (F moves by less than c's rounding)."""
    i = int(np.argmin(np.abs(TABLE["c"] - 1.25)))
    c, w, ref = TABLE["c"][i], TABLE["w"], TABLE["table"][i]
    cs = c + np.spacing(c) * np.resize(np.arange(-12, 13), w.size)
    assert _rel(slip._F(cs, -w), ref).max() <= RTOL


def test_slip_decay_total_matches_the_integral():
    """H(1) = ∫_0^1 u^(β−1) √(ψ0² + φ0² u^(2d)) du, by the kernel and by Gauss–Legendre in u^β (smooth there)."""
    phi0, psi0, alpha, beta = 0.7, 0.3, 4.5, 2.0
    dec = slip.SlipDecay(np.array([phi0]), np.array([psi0]), np.array([alpha]), np.array([beta]))
    t, wt = np.polynomial.legendre.leggauss(200)
    s = 0.5 * (t + 1)  # s = u^β: ∫_0^1 √(ψ0² + φ0² s^(2d/β)) ds / β
    quad = 0.5 * np.sum(wt * np.sqrt(psi0**2 + phi0**2 * s ** (2 * (alpha - beta) / beta))) / beta
    assert dec.total[0] == pytest.approx(quad, rel=1e-13)
