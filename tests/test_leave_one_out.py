"""checks.leave_one_out against what it stands for, computed another way: each trial's data removed and the weighted
linear least-squares problem solved again (numpy's lstsq, no hat matrix), for trials of one residual (the vectorised
path) and of several (the per-trial path) in the same fit."""

import numpy as np
import pytest
from scipy import stats

from reproductions.fit.checks import leave_one_out


def _problem(seed: int, sizes: list[int], p: int = 3):
    rng = np.random.default_rng(seed)
    groups = np.repeat(np.arange(len(sizes)) * 7 + 3, sizes)  # labels neither 0-based nor contiguous
    perm = rng.permutation(groups.size)  # a trial's residuals need not be adjacent
    groups = groups[perm]
    J = rng.normal(size=(groups.size, p))
    y = J @ rng.normal(size=p) + rng.normal(size=groups.size)
    beta = np.linalg.lstsq(J, y, rcond=None)[0]
    return y - J @ beta, J, y, groups


def _refit(J, y, groups, g):
    keep = groups != g
    beta = np.linalg.lstsq(J[keep], y[keep], rcond=None)[0]
    resid = y[keep] - J[keep] @ beta
    return y[~keep] - J[~keep] @ beta, float(resid @ resid), int(keep.sum())


@pytest.mark.parametrize("sigma_known", [True, False])
def test_deleted_residuals_and_p_are_those_of_a_refit_without_the_trial(sigma_known):
    sizes = [1] * 14 + [2, 3, 1, 2]
    r, J, y, groups = _problem(4, sizes)
    out = leave_one_out(r, J, groups, sigma_known=sigma_known)
    labels = np.unique(groups)
    assert out["labels"].tolist() == labels.tolist()
    p = J.shape[1]
    for k, g in enumerate(labels):
        idx = np.flatnonzero(groups == g)
        e, rss_without, n_without = _refit(J, y, groups, g)
        np.testing.assert_allclose(out["deleted"][idx], e, rtol=1e-10, atol=1e-12)
        # the prediction error's covariance: s²(I + J_G (J_−Gᵀ J_−G)⁻¹ J_Gᵀ), s² known (1) or from the refit
        keep = groups != g
        C = np.eye(idx.size) + J[idx] @ np.linalg.inv(J[keep].T @ J[keep]) @ J[idx].T
        s2 = 1.0 if sigma_known else rss_without / (n_without - p)
        np.testing.assert_allclose(out["sd"][idx], np.sqrt(np.diag(C) * s2), rtol=1e-10)
        Q = float(e @ np.linalg.solve(C, e))
        want = stats.chi2.sf(Q, idx.size) if sigma_known else stats.f.sf(Q / idx.size / s2, idx.size, n_without - p)
        assert out["p"][k] == pytest.approx(want, rel=1e-9, abs=1e-15)


def test_a_trial_that_alone_sets_a_parameter_is_not_judged():
    """A parameter seen by one single-residual trial only: its leverage is 1, nothing else predicts it (NaN), while
    the other trials are still judged."""
    _, J, y, groups = _problem(5, [1] * 12, p=2)
    J = np.column_stack([J, np.zeros(12)])
    J[3, 2] = 1.0  # only trial 3 sees the third parameter
    beta = np.linalg.lstsq(J, y, rcond=None)[0]
    out = leave_one_out(y - J @ beta, J, groups, sigma_known=False)
    k = int(np.flatnonzero(out["labels"] == groups[3])[0])
    assert np.isnan(out["p"][k]) and np.isnan(out["deleted"][3])
    assert np.isfinite(np.delete(out["p"], k)).all()
