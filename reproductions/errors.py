"""The one error type that user-facing code turns into a clear message and exit status 2."""

from __future__ import annotations


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
