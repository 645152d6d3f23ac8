"""Sweeps past one machine (``reproductions.sweep``): ``resal stress`` gives the same report on one process, on the
process pool and on a Dask cluster (a ``LocalCluster`` of two processes here, the optional extra
``resal[cluster]``).

"The same report" is the report without its timing fields (``stress.TIMINGS``: the run's ``execution``, what ran it
and the slow sweeps' throughput per core, and each model's ``seconds`` and ``throughput``): those are measured, so
they differ from run to run; every count, margin, worst scene and finding must be equal, to the bit."""

from __future__ import annotations

import json

import numpy as np
import pytest

from reproductions import stress, sweep
from reproductions.errors import InputError

# two models: one with a referee and a path that handles only part of the scenes (more chunks drawn for it), one
# with two bodies; small counts, several chunks of each kind (the slow sweep in slices of SLOW_CHUNK scenes)
SMALL = {"models": ["cushion-impact", "direct-impact"], "scenes": 2500, "ode_scenes": 3, "pairs": 100, "seed": 7,
         "referee_scenes": 2 * stress.SLOW_CHUNK + 3}


def _same(rep: dict) -> str:
    return json.dumps(stress.without_timings(rep), sort_keys=True, allow_nan=False)


@pytest.fixture(scope="module")
def one_process(monkeypatch_module) -> dict:
    return stress.run(jobs=1, **SMALL)


@pytest.fixture(scope="module")
def monkeypatch_module():
    mp = pytest.MonkeyPatch()
    mp.setattr(stress, "CHUNK", 1000)  # 2500 scenes: chunks of 1000, 1000 and 500, and more for the partial path
    yield mp
    mp.undo()


def test_chunks_and_their_seeds_do_not_depend_on_the_workers():
    assert sweep.chunks(2500, 1000) == [(0, 1000), (1000, 2000), (2000, 2500)]
    assert sweep.chunks(0, 10) == [] and sweep.chunks(3, 10) == [(0, 3)]
    # chunk c's stream is the child c of the run's seed, whether made alone or among all the others
    whole = np.random.SeedSequence([7, 3]).spawn(5)
    for c in range(5):
        alone = sweep.chunk_seed([7, 3], c)
        assert np.array_equal(alone.generate_state(4), whole[c].generate_state(4))
    assert not np.array_equal(sweep.chunk_seed([7, 3], 0, 1).generate_state(4),
                              sweep.chunk_seed([7, 3], 1, 1).generate_state(4))


def test_the_plan_of_a_model_is_the_same_whoever_runs_it(monkeypatch_module):
    from reproductions.mechanics import registry

    def plan() -> list:
        p = stress._Plan(registry.MODELS["cushion-impact"], 2500, 3, 100, 7, 53)
        return [(t[0], t[3]) + ((t[4], t[5]) if t[0] == "fast" else ()) for t in p.tasks()]

    first = plan()
    assert first == plan()
    fast = [t for t in first if t[0] == "fast"]
    assert [t[2] for t in fast[:3]] == [1000, 1000, 500]  # fixed by the counts, never by the workers
    assert all(sum(t[3][name][0] for t in fast if name in t[3]) == 2500 for name in fast[0][3])
    assert [t[1] for t in first if t[0] == "slow"] == [0, 25, 50]


def test_the_pool_gives_the_report_of_one_process(one_process):
    pooled = stress.run(jobs=2, **SMALL)
    assert pooled["execution"]["executor"] == "process-pool" and one_process["execution"]["executor"] == "in-process"
    assert _same(pooled) == _same(one_process)
    assert pooled["failures"] == 0
    ex = pooled["execution"]["throughput"]
    assert ex["referee"]["scenes"] == one_process["execution"]["throughput"]["referee"]["scenes"] > 0
    assert ex["referee"]["scenes_per_second_per_worker"] > 0 and ex["workers"] == 2


def test_a_dask_cluster_of_two_processes_gives_the_report_of_the_pool(one_process):
    pytest.importorskip("distributed")
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None) as cluster:
        on_dask = stress.run(scheduler=cluster.scheduler_address, **SMALL)
    assert on_dask["execution"]["executor"] == "dask" and on_dask["execution"]["workers"] == 2
    assert _same(on_dask) == _same(one_process)


def test_a_scheduler_without_the_extra_is_one_clear_error(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "distributed", None)  # as if `resal[cluster]` were not installed
    with pytest.raises(InputError, match=r"needs the optional extra: pip install 'resal\[cluster\]'"):
        stress.run(models=["wall-impact"], scenes=10, ode_scenes=1, referee_scenes=1, scheduler="tcp://127.0.0.1:1")
