"""The fits' memory is linear in the number of rows (issue 30: a 10 000-shot ball-ball file was killed by the
kernel at 23.6 GB; 10 000 markers took 4.4 GB). The two places that grew faster, each checked against what it
replaced and under a memory bound that the old code breaks by orders of magnitude."""

import tracemalloc

import numpy as np
import pytest

from reproductions.fit.estimators import lsq
from reproductions.fit.estimators import markers as mk


def _peak(f) -> int:
    """Peak bytes traced (numpy reports its buffers to tracemalloc) while ``f()`` runs."""
    tracemalloc.start()
    try:
        f()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


@pytest.mark.parametrize("shape,rank", [((50, 3), 3), ((50, 3), 2), ((2, 4), 2), ((4, 4), 3), ((1, 2), 1)])
def test_null_space_agrees_with_the_full_svd(shape, rank):
    """Singular values, rank, the fitted directions' projector and the null space's projector: those of the full
    SVD (which the thin one replaced), for tall, short and rank-deficient Jacobians."""
    rng = np.random.default_rng(sum(shape) + rank)
    J = rng.standard_normal((shape[0], rank)) @ rng.standard_normal((rank, shape[1]))
    s, V, r = lsq._null_space(J)
    _, s_full, Vt = np.linalg.svd(J, full_matrices=True)
    assert r == rank and V.shape == (shape[1], shape[1])
    np.testing.assert_allclose(s[: s_full.size], s_full, rtol=1e-12, atol=1e-12 * s_full[0])
    assert np.all(s[s_full.size:] == 0)
    for a, b in ((V[:, :r], Vt.T[:, :r]), (V[:, r:], Vt.T[:, r:])):
        np.testing.assert_allclose(a @ a.T, b @ b.T, atol=1e-10)


def test_null_space_of_a_long_jacobian_takes_memory_linear_in_its_rows():
    """200 000 residuals × 2 parameters: the thin SVD holds a few copies of J (3.2 MB each); the full one asked for
    U of 200 000² doubles (320 GB)."""
    J = np.random.default_rng(0).standard_normal((200_000, 2))
    assert _peak(lambda: lsq._null_space(J)) < 40 * J.nbytes


def _parts(n: int) -> list[mk.Part]:
    rng = np.random.default_rng(1)
    psi = rng.uniform(5.0, 80.0, n)
    obs = mk.angles(psi, 0.06, 0.93)["alpha1"] + rng.normal(0.0, 1.5, n)
    return [mk.Part(psi, obs, "alpha1")]


def test_markers_likelihood_is_the_same_to_the_bit_in_chunks(monkeypatch):
    parts = _parts(300)
    F, E = np.meshgrid(np.linspace(0.01, 0.3, 9), np.linspace(0.5, 1.0, 7), indexing="ij")
    whole = mk._total(parts, F, E, mk.Model(), mk.FLOOR)
    monkeypatch.setattr(mk, "CHUNK", 301)  # one pair at a time
    assert np.array_equal(mk._total(parts, F, E, mk.Model(), mk.FLOOR), whole)


def test_markers_likelihood_over_a_grid_takes_memory_linear_in_the_markers():
    """The local grid (25 × 25 pairs) over 10 000 markers: once a batch of 625 × 10 000 per intermediate (50 MB
    each, 4.5 GB at the peak), now chunks of ``CHUNK`` values: 47 MB measured."""
    parts = _parts(10_000)
    F, E = np.meshgrid(np.linspace(0.01, 0.3, 25), np.linspace(0.5, 1.0, 25), indexing="ij")
    assert _peak(lambda: mk._total(parts, F, E, mk.Model(), mk.FLOOR)) < 100 * 2**20
