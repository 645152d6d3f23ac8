"""How a ``resal`` process ends, and what its terminal can print: the exit of an interrupted run (``_exit_now``),
the last line of a process that cannot go on (``_last_words``), and ASCII renderings on a standard output or error
whose encoding cannot hold Unicode (``_streams_for_this_terminal``)."""

from __future__ import annotations

import os
import sys
from typing import Any, NoReturn

import typer

_PROCESS = {"own": False}  # True when cli.main.main() runs the process (not a test's CliRunner)


def _exit_now(code: int) -> NoReturn:
    """End an interrupted run. The cleanup (workers terminated, staging removed) has run; the process pool's
    queue threads may still be blocked on a pipe that no terminated worker will read, and the interpreter's exit
    would join them forever (a SIGTERM run once hung in CI): the process itself exits at once. Under a test's
    CliRunner, an ordinary exit."""
    if _PROCESS["own"]:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    raise typer.Exit(code)


# where the terminal cannot print Unicode (LANG=C, a latin-1 locale): what a person would write instead
_ASCII = {"ε": "eps", "ν": "nu", "α": "alpha", "β": "beta", "γ": "gamma", "δ": "delta", "θ": "theta", "λ": "lambda",
          "μ": "mu", "π": "pi", "ρ": "rho", "σ": "sigma", "τ": "tau", "φ": "phi", "χ": "chi", "ψ": "psi",
          "ω": "omega", "Δ": "Delta", "Ω": "Omega", "≤": "<=", "≥": ">=", "≈": "~", "≠": "!=", "±": "+/-",
          "×": "x", "·": ".", "−": "-", "–": "-", "—": "--", "…": "...", "′": "'", "″": "''", "«": '"', "»": '"',
          "‘": "'", "’": "'", "“": '"', "”": '"', "→": "->", "←": "<-", "√": "sqrt", "∞": "inf", "°": " deg",
          "²": "^2", "³": "^3", "½": "1/2", "₀": "0", "₁": "1", "₂": "2", "§": "sec.", "µ": "u",
          "\u00a0": " ", "\u202f": " ", "\u2009": " ", "✓": "ok", "✗": "x", "•": "*", "█": "#", "━": "-"}


def _ascii_text(text: str, encoding: str) -> str:
    """``text`` with each character the stream cannot encode written as a person would in ASCII (``_ASCII``, an
    accent dropped), or ``?``."""
    import unicodedata

    out = []
    if "n°" in text and not _encodes("°", encoding):
        text = text.replace("n°", "no.")
    for c in text:
        try:
            c.encode(encoding)
            out.append(c)
        except UnicodeEncodeError:
            alt = _ASCII.get(c) or unicodedata.normalize("NFKD", c).encode("ascii", "ignore").decode() or "?"
            out.append(alt)
    return "".join(out)


def _encodes(text: str, encoding: str) -> bool:
    try:
        text.encode(encoding)
    except (UnicodeEncodeError, LookupError):
        return False
    return True


class _Transliterating:
    """A text stream that writes through ``stream`` what its encoding can hold (``_ascii_text``)."""

    def __init__(self, stream: Any) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        self._stream.write(_ascii_text(text, self._stream.encoding or "ascii"))
        return len(text)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def _cannot_print_unicode(stream: Any) -> bool:
    return not _encodes("ε≤–é", getattr(stream, "encoding", None) or "ascii")


def _streams_for_this_terminal() -> None:
    """Standard output and error in an encoding that cannot print Unicode get ASCII renderings instead of a
    UnicodeEncodeError; JSON on such a stdout is written with \\u escapes (exact, unlike a rendering)."""
    for name in ("stdout", "stderr"):
        stream = getattr(sys, name)
        if stream is not None and _cannot_print_unicode(stream):
            if hasattr(stream, "reconfigure"):
                stream.reconfigure(errors="replace")
            setattr(sys, name, _Transliterating(stream))
            if name == "stdout":
                _JSON_ASCII[0] = True


_JSON_ASCII = [False]


def _last_words(text: str, code: int) -> NoReturn:
    """End the process with one line on stderr (if stderr can still take it) and ``code``, whatever the state of
    stdout: a stdout that cannot be written (a full disk, a closed pipe) is sent to /dev/null first, so that the
    interpreter's own flush at exit prints no traceback."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.__stdout__.fileno() if sys.__stdout__ else 1)
    except (OSError, ValueError, AttributeError):
        pass
    if text:
        try:
            sys.stderr.write(f"error: {text}\n")
            sys.stderr.flush()
        except (OSError, ValueError):
            pass
    os._exit(code)
