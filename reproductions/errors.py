"""The errors that user-facing code turns into one clear message: bad input (exit status 2), a computation that
failed on valid input (exit status 1) and an interruption by a signal (exit status 128 + the signal's number)."""

from __future__ import annotations

import signal
from collections.abc import Iterable


class InputError(Exception):
    """Bad user input: a config, a CSV, a command-line argument or an output folder.

    ``where`` names the place (``file:line``, or ``--set eps``); ``expected`` says what was wanted.
    """

    def __init__(self, where: str, message: str) -> None:
        super().__init__(f"{where}: {message}")
        self.where = where
        self.message = message

    def __reduce__(self) -> tuple[type, tuple[str, str]]:  # so that it crosses process boundaries intact
        return (InputError, (self.where, self.message))


def did_you_mean(given: str, known: Iterable[str]) -> str:
    """``"; did you mean X?"`` for the name of ``known`` closest to ``given`` (a typo: difflib's ratio at least
    0.6, as click's suggestions of options), else ``""``: the end of an "unknown …" message."""
    import difflib

    if not isinstance(given, str) or len(given) > 200:  # not a typo of a name
        return ""
    close = difflib.get_close_matches(given, [k for k in known if k != given], n=1, cutoff=0.6)
    return f"; did you mean {close[0]}?" if close else ""


class ComputationError(InputError):
    """Valid input on which a numerical method of resal failed (no convergence, an ODE over its budget): a defect
    of ours for that scene, said in one message (exit status 1) with the command that shows it."""

    def __reduce__(self) -> tuple[type, tuple[str, str]]:
        return (ComputationError, (self.where, self.message))


class Interrupted(BaseException):
    """SIGTERM (``timeout``, a CI cancellation) or SIGINT received while ``api.interruptible`` was active.

    A ``BaseException`` like ``KeyboardInterrupt``, so ``except Exception`` does not swallow it; the cleanup
    in ``finally`` and ``except BaseException`` blocks runs on the way out.
    """

    def __init__(self, signum: int) -> None:
        self.signum = signum
        self.name = signal.Signals(signum).name
        super().__init__(self.name)

    def __reduce__(self) -> tuple[type, tuple[int]]:
        return (Interrupted, (self.signum,))
