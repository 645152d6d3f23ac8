"""Markers beyond ``PSI_NODES``: the model interpolated in ψ (issue 30: 10⁵ markers in bounded time), checked
against the model evaluated at every marker (``nodes=None``, the path that interpolates nothing)."""

from __future__ import annotations

import numpy as np
import pytest

from reproductions.fit.estimators import markers as mk


def _parts(n: int, seed: int = 20261206) -> list[mk.Part]:
    rng = np.random.default_rng(seed)
    out = []
    for key, sd in (("alpha1", 1.5), ("throw", 0.5)):
        psi = np.sort(rng.uniform(5.0, 80.0, n))
        true = mk.angles(psi, 0.06, 0.93)[key]
        out.append(mk.Part(psi, true + sd * rng.standard_normal(n), key))
    return out


def test_few_nodes_give_the_exact_fit_within_a_small_part_of_its_interval():
    parts = _parts(150)
    exact = mk.fit_markers(parts, nodes=None)
    coarse = mk.fit_markers(parts, nodes=64)  # 64 nodes, h ≈ 1.2°, err by 0.1° where the slip stops: refined to 256
    assert exact.nodes == 0 and exact.interp_error == 0.0
    assert coarse.nodes == 256 and 0.0 < coarse.interp_error <= mk.INTERP_TOL
    for a, b, ci in ((coarse.f, exact.f, exact.ci_f), (coarse.e, exact.e, exact.ci_e)):
        assert abs(a - b) <= 0.02 * (ci[1] - ci[0]), (a, b, ci)
    for ca, cb in ((coarse.ci_f, exact.ci_f), (coarse.ci_e, exact.ci_e)):
        assert np.allclose(ca, cb, atol=0.02 * (cb[1] - cb[0]), rtol=0.0), (ca, cb)
    assert abs(coarse.m2lnl - exact.m2lnl) < 0.05  # −2 ln L: a shift far below the cut of 3.84


def test_the_reported_error_is_the_interpolation_against_the_model_at_every_marker():
    parts = _parts(150)
    fit = mk.fit_markers(parts, nodes=64)
    psi = np.concatenate([p.psi for p in parts])
    grid = np.linspace(psi.min(), psi.max(), fit.nodes)
    at_grid, at_markers = mk.angles(grid, fit.f, fit.e), mk.angles(psi, fit.f, fit.e)
    err, start = 0.0, 0
    for p in parts:  # np.interp: numpy's own linear interpolation, not the module's
        sl = slice(start, start + p.psi.size)
        err = max(err, float(np.max(np.abs(np.interp(p.psi, grid, at_grid[p.key]) - at_markers[p.key][sl]))))
        start += p.psi.size
    assert fit.interp_error == pytest.approx(err, rel=1e-9, abs=1e-12)


def test_an_interpolation_too_coarse_is_refined_until_the_model_itself(monkeypatch):
    """With a tolerance of 0 no interpolation passes: the loop quadruples the nodes (16, 64, 256 < 300 markers),
    then evaluates every marker, and ends with the exact fit, bit for bit."""
    parts = _parts(150)
    monkeypatch.setattr(mk, "INTERP_TOL", 0.0)
    calls = []
    real = mk._fit_markers
    monkeypatch.setattr(mk, "_fit_markers", lambda *a: calls.append(a[-1]) or real(*a))
    fit = mk.fit_markers(parts, nodes=16)
    assert calls == [16, 64, 256, None]
    exact = mk.fit_markers(parts, nodes=None)
    assert (fit.f, fit.e, fit.ci_f, fit.ci_e, fit.m2lnl, fit.nodes) == (exact.f, exact.e, exact.ci_f, exact.ci_e,
                                                                         exact.m2lnl, 0)
