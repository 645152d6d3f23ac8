"""The functions the CLI calls: find experiments, run them, write them. No argument parsing, no rendering."""

from __future__ import annotations

import os
import signal
import sys
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypeVar

from .config import Experiment, load_experiment
from .errors import InputError, Interrupted
from .experiments import KINDS
from .results import Reproduction

__all__ = ["checkpoint", "config_dir", "experiment_ids", "interruptible", "list_experiments", "load", "parallel_map",
           "run", "run_and_draw"]

T = TypeVar("T")
R = TypeVar("R")


def config_dir() -> Path:
    """``$RESAL_CONFIGS``, else the ``configs/`` folder of the source tree, else ``./configs``."""
    env = os.environ.get("RESAL_CONFIGS")
    if env:
        return Path(env)
    here = Path(__file__).resolve().parent.parent / "configs"
    return here if here.is_dir() else Path("configs")


def experiment_ids() -> list[str]:
    d = config_dir()
    return sorted(p.stem for p in d.glob("*.yaml")) if d.is_dir() else []


def load(name_or_path: str) -> Experiment:
    """An experiment by id (``configs/<id>.yaml``) or by the path of a YAML file."""
    p = Path(name_or_path)
    if p.suffix in (".yaml", ".yml") or p.is_file():
        if not p.is_file():
            raise InputError(name_or_path, "no such experiment file")
        return load_experiment(p, KINDS)
    ids = experiment_ids()
    if name_or_path not in ids:
        raise InputError(f"experiment '{name_or_path}'",
                         f"unknown experiment id (expected one of: {', '.join(ids) or 'none found'}, "
                         "or the path of a YAML file)")
    return load_experiment(config_dir() / f"{name_or_path}.yaml", KINDS)


def list_experiments() -> list[Experiment]:
    return [load(i) for i in experiment_ids()]


def run(exp: Experiment) -> Reproduction:
    """Run one experiment: physics, fits and comparisons, no I/O but reading its data files."""
    return KINDS[exp.kind].run(exp)


@contextmanager
def interruptible() -> Iterator[None]:
    """Within the block, SIGTERM (as SIGINT already does) raises an exception in the main thread:
    ``Interrupted(signum)`` for either signal, raised once (a repeat during the cleanup is ignored), so that the
    ``finally`` blocks stop the worker processes and remove the staging folders. Forked workers that inherit
    the handler before ``_worker_init`` runs die of SIGTERM and ignore SIGINT. Main thread only."""
    import threading

    if threading.current_thread() is not threading.main_thread():  # signal handlers belong to the main thread
        yield
        return
    owner = os.getpid()
    _RECEIVED["signum"] = None

    def handler(signum: int, frame: Any) -> None:
        if os.getpid() != owner:  # a forked worker, before _worker_init
            if signum == signal.SIGTERM:
                signal.signal(signum, signal.SIG_DFL)
                os.kill(os.getpid(), signum)
            return
        if _RECEIVED["signum"] is None:
            _RECEIVED["signum"] = signum
            if not _FORKING[0]:  # inside an at-fork hook the exception would be printed and dropped
                raise Interrupted(signum)  # (there the next ``checkpoint`` raises it)

    # a signal ignored from the start (SIGINT of a background job, `nohup`-like wrappers) stays ignored
    sigs = [s for s in (signal.SIGINT, signal.SIGTERM) if signal.getsignal(s) is not signal.SIG_IGN]
    previous = {s: signal.signal(s, handler) for s in sigs}
    try:
        yield
        checkpoint()  # a signal whose exception was swallowed still ends the block as an interruption
    finally:
        for s, h in previous.items():
            signal.signal(s, h)
        _RECEIVED["signum"] = None


_RECEIVED: dict[str, int | None] = {"signum": None}  # the signal ``interruptible`` received, if any
_FORKING = [False]  # True while this process forks (between the at-fork hooks, ours outermost)


def _fork_begins() -> None:
    _FORKING[0] = True


def _fork_ends() -> None:
    _FORKING[0] = False


if hasattr(os, "register_at_fork"):
    os.register_at_fork(before=_fork_begins, after_in_parent=_fork_ends, after_in_child=_fork_ends)


def checkpoint() -> None:
    """Raise ``Interrupted`` if a signal came within ``interruptible`` and its exception was not raised. Python
    prints and drops an exception raised where it cannot propagate: a signal that landed inside the ``logging``
    module's at-fork hook (the parent forking a worker) was lost that way, with a traceback on stderr, and the run
    went on to the end (found by the SIGTERM test under load). So the handler does not raise while the process
    forks, and this raises instead. Called between the steps of a run, never in cleanup code."""
    if _RECEIVED["signum"] is not None:
        raise Interrupted(_RECEIVED["signum"])


def _worker_init(parent: int) -> None:
    """In each worker: SIGTERM kills at once (even inside a long numpy call), SIGINT (a Ctrl-C reaches the
    whole process group) is left to the parent, which stops the workers itself. On Linux the worker also dies
    with its parent (``PR_SET_PDEATHSIG``): a signal that interrupts the parent while it forks a worker leaves
    that worker unknown to the pool, and it would wait on the pool's queue for ever, holding the parent's
    stderr open (a SIGTERM test hung in CI that way under load)."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        import ctypes

        ctypes.CDLL(None).prctl(1, int(signal.SIGKILL))  # 1 = PR_SET_PDEATHSIG
    if os.getppid() != parent:  # the parent died before the line above
        os._exit(1)


@contextmanager
def _process_pool(jobs: int) -> Iterator[Any]:
    """A ``ProcessPoolExecutor`` (fork where available) whose workers are terminated, not waited for, when the
    block ends by an exception (an interruption, an error of one experiment)."""
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor

    ctx = mp.get_context("fork") if "fork" in mp.get_all_start_methods() else None
    pool = ProcessPoolExecutor(max_workers=jobs, mp_context=ctx, initializer=_worker_init,
                               initargs=(os.getpid(),))
    try:
        yield pool
    except BaseException:
        procs = list((getattr(pool, "_processes", None) or {}).values())
        for p in procs:
            p.terminate()
        pool.shutdown(wait=False, cancel_futures=True)
        for p in procs:
            p.join(timeout=10)
            if p.is_alive():
                p.kill()
                p.join(timeout=10)
        raise
    pool.shutdown(wait=True)


def parallel_map(fn: Callable[[T], R], items: Sequence[T], jobs: int,
                 progress: Callable[[int, int], None] | None = None) -> list[R]:
    """``[fn(x) for x in items]`` on up to ``jobs`` processes, results in the input order; ``progress(done,
    total)`` is called as items finish. Exceptions (an ``InputError`` from a data file) propagate."""
    if jobs <= 1 or len(items) <= 1:
        out = []
        for i, x in enumerate(items, 1):
            out.append(fn(x))
            if progress:
                progress(i, len(items))
        return out
    from concurrent.futures import as_completed

    results: list[R | None] = [None] * len(items)
    with _process_pool(min(jobs, len(items))) as pool:
        futures = {pool.submit(fn, x): i for i, x in enumerate(items)}
        for done, fut in enumerate(as_completed(futures), 1):
            results[futures[fut]] = fut.result()
            if progress:
                progress(done, len(items))
    return results  # type: ignore[return-value]


def run_and_draw(exps: Sequence[Experiment], jobs: int, scratch: Path,
                 progress: Callable[[str], None] | None = None) -> list[Reproduction]:
    """Run the experiments and render their figures into ``scratch/<id>/`` on up to ``jobs`` processes, the
    figures of an experiment starting as soon as it has run (so one long experiment does not idle a core).
    Results in the input order; exceptions (an ``InputError`` from a data file) propagate."""
    from .report import draw_figure, prepare_drawing

    prepare_drawing()
    if jobs <= 1:
        reps = []
        for i, e in enumerate(exps, 1):
            checkpoint()
            reps.append(run(e))
            if progress:
                progress(f"running: {i}/{len(exps)} done")
        for r in reps:
            for spec in r.figures:
                checkpoint()
                draw_figure((spec, scratch / r.experiment.id))
        return reps
    from concurrent.futures import FIRST_COMPLETED, wait

    reps: list[Reproduction | None] = [None] * len(exps)
    with _process_pool(jobs) as pool:
        running = {pool.submit(run, e): i for i, e in enumerate(exps)}
        drawing = set()
        n_fig = done_fig = 0
        while running or drawing:
            checkpoint()
            finished, _ = wait([*running, *drawing], return_when=FIRST_COMPLETED, timeout=0.5)
            for fut in finished:
                if fut in running:
                    i = running.pop(fut)
                    reps[i] = r = fut.result()
                    n_fig += len(r.figures)
                    drawing |= {pool.submit(draw_figure, (spec, scratch / r.experiment.id)) for spec in r.figures}
                else:
                    drawing.discard(fut)
                    fut.result()
                    done_fig += 1
            if progress:
                progress(f"experiments run: {len(exps) - len(running)}/{len(exps)}; figures drawn: {done_fig}/"
                         f"{n_fig}")
    return reps  # type: ignore[return-value]
