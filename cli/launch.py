"""The console script ``resal``: the start-up signal handlers (``reproductions.startup``), then the command line."""

from __future__ import annotations

from reproductions import startup

__all__ = ["main"]


def main() -> None:
    """Install the start-up handlers, then run ``cli.main``."""
    startup.install()
    from cli.main import main as run

    run()
