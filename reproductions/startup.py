"""What the ``resal`` process runs first (``cli.launch``, and the top of ``cli.main``): until the command
installs its own handlers (``processes.interruptible``), SIGINT, SIGTERM and SIGHUP end the process with one line
and 128 + the signal's number — nothing has been written yet — instead of a KeyboardInterrupt traceback or a
silent death while Python is still importing the command line (a signal 0.4 s into a run on a loaded machine
lands there)."""

from __future__ import annotations

import os
import signal
import sys
from typing import Any

__all__ = ["install"]


def _starting(signum: int, frame: Any) -> None:
    try:
        os.write(2, f"error: interrupted ({signal.Signals(signum).name}) while starting; nothing written\n"
                 .encode())
    finally:
        os._exit(128 + signum)


def install() -> None:
    """The start-up handlers; a signal ignored from the start (``nohup``, a background job's SIGINT) stays so."""
    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        s = getattr(signal, name, None)
        if s is not None and signal.getsignal(s) is not signal.SIG_IGN:
            signal.signal(s, _starting)


_main = sys.modules.get("__main__")
if getattr(getattr(_main, "__spec__", None), "name", None) == "cli.main":  # `python -m cli.main`
    install()
