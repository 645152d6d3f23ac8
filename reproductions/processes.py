"""Running a long job in processes that a signal stops cleanly: ``interruptible`` turns SIGTERM and SIGINT into
``Interrupted``, ``checkpoint`` raises one that landed where it could not be raised, and the process pool's workers
die with their parent. Standard library only (a run that recomputes nothing imports no physics)."""

from __future__ import annotations

import os
import signal
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any, TypeVar

from .errors import Interrupted

__all__ = ["STOP_SIGNALS", "checkpoint", "deferred", "interruptible", "parallel_map", "process_pool"]

T = TypeVar("T")
R = TypeVar("R")


@contextmanager
def interruptible(hold_after: bool = False) -> Iterator[None]:
    """Within the block, SIGTERM and SIGHUP (as SIGINT already does) raise an exception in the main thread:
    ``Interrupted(signum)`` for any of them (``STOP_SIGNALS``), raised once (a repeat during the cleanup is
    ignored), so that the ``finally`` blocks stop the worker processes and remove the staging folders. Forked
    workers that inherit the handler before ``_worker_init`` runs die of SIGTERM or SIGHUP and ignore SIGINT.
    Main thread only. ``hold_after`` (the process's outermost block, its work done when it ends): the stop
    signals are ignored after the block, so that one arriving while the interpreter shuts down cannot end a
    finished run by Python's own SIGINT death (status -2 and a traceback, seen under load)."""
    import threading

    if threading.current_thread() is not threading.main_thread():  # signal handlers belong to the main thread
        yield
        return
    owner = os.getpid()
    _RECEIVED["signum"] = None

    def handler(signum: int, frame: Any) -> None:
        if os.getpid() != owner:  # a forked worker, before _worker_init
            if signum != signal.SIGINT:  # SIGTERM, SIGHUP
                signal.signal(signum, signal.SIG_DFL)
                os.kill(os.getpid(), signum)
            return
        if _RECEIVED["signum"] is None:
            _RECEIVED["signum"] = _LAST[0] = signum
            # inside an at-fork hook, a weakref callback, a finaliser or the garbage collector the exception would
            # be printed ("Exception ignored in …", a traceback) and dropped: there the next ``checkpoint`` raises;
            # inside ``deferred()`` its end raises
            if _DEFERRED[0]:
                _PENDING[0] = signum
            elif not _FORKING[0] and not _in_callback(frame):
                raise Interrupted(signum)

    # a signal ignored from the start (SIGINT of a background job, `nohup`-like wrappers) stays ignored
    sigs = [s for s in STOP_SIGNALS if signal.getsignal(s) is not signal.SIG_IGN]
    previous = {s: signal.signal(s, handler) for s in sigs}
    try:
        try:
            yield
        except SystemExit:  # click ends every command with one, exit 0 included: a signal held back is not dropped
            checkpoint()
            raise
        checkpoint()  # a signal whose exception was swallowed still ends the block as an interruption
    finally:
        for s, h in previous.items():
            signal.signal(s, signal.SIG_IGN if hold_after else h)
        _RECEIVED["signum"] = _PENDING[0] = None


@contextmanager
def deferred() -> Iterator[None]:
    """SIGINT, SIGTERM and SIGHUP wait until the block ends, then interrupt: a swap of two renames is never left
    half done, a folder is never half removed, and an interruption is never raised inside matplotlib's PDF or PNG
    writer (whose own cleanup then failed with another exception and a traceback, exit 1 instead of 143: seen once
    under load in CI). Two means, as neither is enough alone: ``interruptible``'s handler only records a signal that
    lands inside the block (a signal goes to any thread that does not block it, and numpy's BLAS threads do not:
    masking the main thread alone did not hold it back), and the main thread blocks them (where no handler of ours
    is installed, Python's own SIGINT handler would raise ``KeyboardInterrupt`` inside)."""
    sigs = set(STOP_SIGNALS)
    masked = hasattr(signal, "pthread_sigmask") and _on_main_thread()
    old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs) if masked else None
    _DEFERRED[0] += 1
    try:
        yield
    finally:
        _DEFERRED[0] -= 1
        if masked:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)  # a signal held by the mask is handled here
        if not _DEFERRED[0] and _PENDING[0] is not None:
            signum, _PENDING[0] = _PENDING[0], None
            raise Interrupted(signum)


def _on_main_thread() -> bool:
    """Whether this is the main thread (the only one that may change signal handling), without importing
    ``threading`` where it is not yet loaded."""
    threading = sys.modules.get("threading")
    return threading is None or threading.current_thread() is threading.main_thread()


def _in_callback(frame: Any) -> bool:
    """Whether ``frame`` runs inside code whose exceptions Python prints and drops instead of propagating: a
    weakref callback (``weakref.py``'s ``remove``, seen under SIGTERM in tests/test_hostile_environment.py), a
    ``__del__`` finaliser, a ``weakref.finalize``."""
    while frame is not None:
        code = frame.f_code
        if code.co_name == "__del__" or code.co_filename.endswith(("weakref.py", "_weakrefset.py")):
            return True
        frame = frame.f_back
    return False


# the signals that end a command the same way: one line, earlier results intact, staging removed, 128 + n
STOP_SIGNALS = tuple(getattr(signal, n) for n in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, n))
_RECEIVED: dict[str, int | None] = {"signum": None}  # the signal ``interruptible`` received, if any
_LAST: list[int | None] = [None]  # the last signal any ``interruptible`` block received: kept after the block
_DEFERRED = [0]  # how many ``deferred()`` blocks this thread is inside
_PENDING: list[int | None] = [None]  # a signal received inside ``deferred()``, raised at its end
_FORKING = [False]  # True while this process forks (between the at-fork hooks, ours outermost)


def _fork_begins() -> None:
    _FORKING[0] = True


def _fork_ends() -> None:
    _FORKING[0] = False


if hasattr(os, "register_at_fork"):
    os.register_at_fork(before=_fork_begins, after_in_parent=_fork_ends, after_in_child=_fork_ends)


def signal_received() -> int | None:
    """The stop signal an ``interruptible`` block of this process received, if one did, even after the block has
    ended: a failure that followed it (a library's initialisation that turned the interruption into an
    ``ImportError`` of its own, with no trace of it) is the signal's doing, and the run ends as that signal."""
    return _LAST[0]


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
    if hasattr(signal, "SIGHUP"):  # a hang-up reaches the whole process group too: the parent stops the workers
        signal.signal(signal.SIGHUP, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        import ctypes

        ctypes.CDLL(None).prctl(1, int(signal.SIGKILL))  # 1 = PR_SET_PDEATHSIG
    if os.getppid() != parent:  # the parent died before the line above
        os._exit(1)


@contextmanager
def process_pool(jobs: int) -> Iterator[Any]:
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


def timed(fn: Callable[[T], R], x: T) -> tuple[R, float]:
    """``fn(x)`` and the seconds it took, timed in whichever process runs it (a worker's queue is not counted)."""
    t0 = time.perf_counter()
    return fn(x), time.perf_counter() - t0


def parallel_map(fn: Callable[[T], R], items: Sequence[T], jobs: int,
                 progress: Callable[[int, int], None] | None = None,
                 finished: Callable[[int, R, float], None] | None = None) -> list[R]:
    """``[fn(x) for x in items]`` on up to ``jobs`` processes, results in the input order; ``progress(done,
    total)`` is called as items finish, and before it ``finished(index, result, seconds)`` (the item's index in
    ``items``, out of order on several processes; the seconds its call took). Exceptions (an ``InputError`` from a
    data file) propagate."""
    if jobs <= 1 or len(items) <= 1:
        out = []
        for i, x in enumerate(items, 1):
            r, seconds = timed(fn, x)
            out.append(r)
            if finished:
                finished(i - 1, r, seconds)
            if progress:
                progress(i, len(items))
        return out
    from concurrent.futures import as_completed

    results: list[R | None] = [None] * len(items)
    with process_pool(min(jobs, len(items))) as pool:
        futures = {pool.submit(timed, fn, x): i for i, x in enumerate(items)}
        for done, fut in enumerate(as_completed(futures), 1):
            r, seconds = fut.result()
            results[futures[fut]] = r
            if finished:
                finished(futures[fut], r, seconds)
            if progress:
                progress(done, len(items))
    return results  # type: ignore[return-value]
