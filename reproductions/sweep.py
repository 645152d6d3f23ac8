"""Sweeps past one machine: the chunks of ``resal stress`` and the ODE part of ``resal bench`` run in this process
(``jobs`` 1), on the project's process pool (``processes.process_pool``, the default: one worker per core), or on a
Dask cluster (``scheduler``: the address of a ``dask.distributed`` scheduler, ``tcp://host:port``; the optional
extra ``pip install 'resal[cluster]'``, imported only then).

What makes the report the same whoever runs it: a sweep is cut into chunks whose boundaries depend on the scene
counts only (never on the number of workers), each chunk draws from its own random stream (``chunk_seed``: a child
of the run's seed, the chunk's index in its spawn key, as ``numpy.random.SeedSequence.spawn`` makes them), and the
results are gathered in chunk order. Only the timings differ. Standard library only at import (numpy is imported by
``chunk_seed`` alone, which the callers already hold)."""

from __future__ import annotations

import os
from collections.abc import Callable, Generator, Iterable, Iterator
from contextlib import closing, contextmanager
from typing import Any, TypeVar

from .errors import InputError
from .processes import checkpoint, process_pool, timed

__all__ = ["EXTRA", "Executor", "chunk_seed", "chunks", "default_jobs", "executor", "map_chunks"]

T = TypeVar("T")
R = TypeVar("R")

EXTRA = "pip install 'resal[cluster]'"


def default_jobs() -> int:
    """One worker per core this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def chunks(total: int, size: int) -> list[tuple[int, int]]:
    """``[start, stop)`` of each chunk of ``total`` items, ``size`` a chunk (the last one shorter): fixed by the
    counts alone, whatever runs them."""
    if size < 1:
        raise ValueError("a chunk holds at least one item")
    return [(a, min(a + size, total)) for a in range(0, max(total, 0), size)]


def chunk_seed(seed: int | Iterable[int], *key: int) -> Any:
    """The ``numpy.random.SeedSequence`` of the chunk named by ``key`` (e.g. (part, index)) under the run's ``seed``:
    the child that ``SeedSequence(seed).spawn`` would give at that place, made directly, so that no chunk's stream
    depends on how many chunks or workers there are."""
    import numpy as np

    entropy = [int(x) for x in seed] if not isinstance(seed, int) else int(seed)
    return np.random.SeedSequence(entropy, spawn_key=tuple(int(k) for k in key))


class Executor:
    """Where a sweep's chunks run: ``describe`` says so in the report's timing fields; ``workers`` is how many run
    at once (the divisor of the throughput per core)."""

    def __init__(self, kind: str, workers: int, submit: Callable[..., Generator[Any, None, None]],
                 address: str | None = None) -> None:
        self.kind, self.workers, self.address, self._run = kind, workers, address, submit

    def describe(self) -> dict[str, Any]:
        out: dict[str, Any] = {"executor": self.kind, "workers": self.workers}
        if self.address:
            out["scheduler"] = self.address
        return out

    def map(self, fn: Callable[[T], R], items: Iterable[T],
            done: Callable[[int, R, float], None] | None = None) -> list[R]:
        """``[fn(x) for x in items]`` in the order of ``items`` (consumed lazily: a planner may draw the next chunk
        while the workers compute); ``done(index, result, seconds)`` as each finishes, in any order, with the
        seconds ``fn`` took in the process that ran it."""
        results: dict[int, R] = {}
        with closing(self._run(fn, items)) as running:  # an exception here stops the pool's workers at once
            for i, r, seconds in running:
                results[i] = r
                if done:
                    done(i, r, seconds)
                checkpoint()
        return [results[i] for i in range(len(results))]


def _in_process(fn: Callable[[T], R], items: Iterable[T]) -> Iterator[tuple[int, R, float]]:
    for i, x in enumerate(items):
        r, seconds = timed(fn, x)
        yield i, r, seconds


def _pool(jobs: int) -> Callable[[Callable[[T], R], Iterable[T]], Iterator[tuple[int, R, float]]]:
    def run(fn: Callable[[T], R], items: Iterable[T]) -> Iterator[tuple[int, R, float]]:
        from concurrent.futures import FIRST_COMPLETED, wait

        with process_pool(jobs) as pool:
            pending: dict[Any, int] = {}
            for i, x in enumerate(items):  # submitted as the planner makes them; the queue holds the rest
                pending[pool.submit(timed, fn, x)] = i
                finished, _ = wait(list(pending), timeout=0)
                for fut in finished:
                    r, seconds = fut.result()
                    yield pending.pop(fut), r, seconds
            while pending:
                finished, _ = wait(list(pending), return_when=FIRST_COMPLETED)
                for fut in finished:
                    r, seconds = fut.result()
                    yield pending.pop(fut), r, seconds
    return run


def _dask(client: Any) -> Callable[[Callable[[T], R], Iterable[T]], Iterator[tuple[int, R, float]]]:
    def run(fn: Callable[[T], R], items: Iterable[T]) -> Iterator[tuple[int, R, float]]:
        from distributed import as_completed

        futures = {}
        for i, x in enumerate(items):
            # pure=False: two equal chunks are still two pieces of work; the key keeps the order readable
            futures[client.submit(timed, fn, x, pure=False)] = i
        for fut in as_completed(list(futures)):
            r, seconds = fut.result()
            yield futures[fut], r, seconds
    return run


def _workers(client: Any) -> int:
    info = client.scheduler_info()
    return max(1, sum(int(w.get("nthreads", 1)) for w in info.get("workers", {}).values()))


@contextmanager
def executor(jobs: int | None = None, scheduler: str | None = None) -> Iterator[Executor]:
    """The executor of a sweep: a Dask cluster's client when ``scheduler`` is given (``InputError`` if the optional
    extra is missing or the scheduler cannot be reached), else ``jobs`` processes (None: one per core; 1: this
    process)."""
    if scheduler:
        try:
            from distributed import Client
        except ImportError:
            raise InputError(f"--scheduler {scheduler}", f"needs the optional extra: {EXTRA}") from None
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError, ValueError) as err:
            raise InputError(f"--scheduler {scheduler}", f"cannot reach the Dask scheduler ({err})") from None
        try:
            yield Executor("dask", _workers(client), _dask(client), address=scheduler)
        finally:
            client.close()
        return
    n = default_jobs() if jobs is None else max(1, int(jobs))
    if n == 1:
        yield Executor("in-process", 1, _in_process)
    else:
        yield Executor("process-pool", n, _pool(n))


def map_chunks(fn: Callable[[T], R], items: Iterable[T], jobs: int | None = None, scheduler: str | None = None,
               done: Callable[[int, R, float], None] | None = None) -> list[R]:
    """``[fn(x) for x in items]`` on the executor of ``jobs`` and ``scheduler`` (``executor``), in input order."""
    with executor(jobs, scheduler) as ex:
        return ex.map(fn, items, done)
