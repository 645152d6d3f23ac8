"""``resal``: list, reproduce and simulate. Parses arguments, calls one library function, renders.

Heavy imports (numpy, scipy, matplotlib) happen inside the commands, so ``resal --help`` stays fast.
Bad input of any kind ends with one message on stderr and exit status 2; every command interrupted by SIGINT,
SIGTERM or SIGHUP stops its workers, removes its staging folders and exits with one line and 128 + the signal
(130, 143, 129); the earlier results are left whole.

The entry point. Each command is a module of this package (``cli/list_cmd.py``, ``cli/reproduce.py``,
``cli/simulate.py``, ``cli/fit.py``, ``cli/bench.py``, ``cli/stress.py``, ``cli/diff.py``, ``cli/examples.py``)
that registers it on ``app`` (``cli/app.py``) as it is imported here; what several share is in ``cli/common.py``,
and how a process ends and what its terminal can print in ``cli/terminal.py``.
"""

from __future__ import annotations

import reproductions.startup  # noqa: F401  (first: a signal during the imports below ends the run in one line)

# isort: split
import sys
from typing import NoReturn

# each module registers its command on app as it is imported: in this order, the order of `resal --help`
# isort: off
from cli import list_cmd, reproduce, simulate, fit, bench, stress, diff, examples  # noqa: F401
# isort: on
from cli.app import app
from cli.common import WIDE_TABLE, out_console
from cli.terminal import _PROCESS, _last_words, _streams_for_this_terminal
from reproductions.errors import Interrupted

__all__ = ["WIDE_TABLE", "app", "main", "out_console"]  # what cli.launch and the tests use


def main() -> None:
    """The ``resal`` command: every command ends in its result, or one line and an exit status — 2 bad input, 1
    a failure of the environment or of a computation, 128 + n for a signal (SIGINT, SIGTERM, SIGHUP) — never a
    traceback."""
    _PROCESS["own"] = True
    _streams_for_this_terminal()
    try:
        from reproductions import processes

        with processes.interruptible(hold_after=True):  # the work done, a late signal cannot undo it
            try:
                app(prog_name="resal")  # `python -m cli.main --help` shows the command as a user types it
            finally:
                sys.stdout.flush()
    except SystemExit:
        raise
    except (Interrupted, KeyboardInterrupt) as exc:
        _stopped(exc)
    except BrokenPipeError:  # `resal … | head`: the reader has gone; nothing to say
        _last_words("", 141)
    except (OSError, MemoryError, ImportError) as exc:
        _failed(exc)


def _signal_within(exc: BaseException) -> BaseException | None:
    """The stop signal behind ``exc``, if one is: a signal whose handler raised inside a library's initialisation
    comes out wrapped (pybind11's modules, matplotlib's among them, turn any error of their init into
    ``ImportError('initialization failed')`` raised from it)."""
    seen: set[int] = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, (Interrupted, KeyboardInterrupt)):
            return exc
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return None


def _stopped(exc: BaseException) -> NoReturn:
    """One line and 128 + n for the stop signal ``exc`` (``Interrupted``, or Python's own ``KeyboardInterrupt``)."""
    name, signum = (exc.name, exc.signum) if isinstance(exc, Interrupted) else ("SIGINT", 2)
    _last_words(f"interrupted ({name}); earlier results left as they were", 128 + signum)


def _failed(exc: BaseException) -> NoReturn:
    """One line and the status for a failure of the environment (1), or for the signal that caused it (128 + n)."""
    import errno

    stop = _signal_within(exc)
    if stop is None:  # a library that printed the interruption and raised its own error (numpy's import_array)
        from reproductions import processes

        signum = processes.signal_received()
        stop = Interrupted(signum) if signum is not None else None
    if stop is not None:
        _stopped(stop)
    if isinstance(exc, OSError):
        if exc.errno in (errno.ENOSPC, errno.EIO, errno.EDQUOT, errno.EFBIG):
            _last_words(f"cannot write ({exc.strerror}): standard output or a file could not take the output", 1)
        if exc.errno == errno.ENOMEM:  # a thread or a mapping refused under a memory limit (where numpy loads)
            _last_words(f"out of memory ({exc.strerror}; a limit on this process's memory? `ulimit -v`)", 1)
        _last_words(f"a failure of the environment: {exc.strerror or exc}", 1)
    if isinstance(exc, MemoryError):
        _last_words("out of memory (a limit on this process's memory? `ulimit -v`)", 1)
    name = getattr(exc, "name", None)
    _last_words(f"cannot load {name or 'a library'} ({exc}); out of memory, or an incomplete install "
                "(`make setup`)?", 1)


if __name__ == "__main__":
    main()
