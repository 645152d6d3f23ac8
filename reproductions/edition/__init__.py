"""The reader's edition of a results folder: ``index.html`` (self-contained, figures beside it) and ``report.pdf``
(set by Typst), both rendered from one ``Edition`` (``model``) built from the summaries (``build``), beside the
index and the paper table of ``report``. Templates are files of ``templates/`` beside the code."""

from __future__ import annotations

import io
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ..report import (
    _atomic_text,
    _atomic_write,
    _summaries,
    index_md,
    paper_rows,
    paper_table_csv,
    paper_table_md,
    paper_table_tex,
    signals_deferred,
)
from .build import build, function_of, plain, readable
from .html import index_html, rich_html

__all__ = ["build", "function_of", "index_html", "plain", "readable", "rich_html", "write_index"]


# -- writing a results folder's whole-paper files ----------------------------------------------------------------
def write_index(out: Path, skipped: list[tuple[Path, str]] | None = None) -> Path:
    """``out/index.md`` and ``out/paper-table.{md,csv,tex}`` (``report``), the reader's edition ``out/index.html``
    and ``out/report.pdf`` from the summaries found under ``out``, each written whole and renamed into place.
    ``skipped`` receives the summaries left out (not resal's, or changed by hand: ``report.summary_problem``).
    Typst compiles the PDF in a thread while the other files are rendered: its compiler releases the GIL, and it
    was the longest part (1.6 s of 2.5 s), after every experiment, on one core."""
    from . import typst  # the typst package: imported only when a report is written

    summaries = _summaries(out, skipped)
    ed = build(summaries)
    pdf = _Background(lambda: _pdf_bytes(typst, ed, out))
    rows = paper_rows(summaries)
    path = out / "index.md"
    _atomic_text(path, index_md(summaries))
    _atomic_text(out / "paper-table.md", paper_table_md(rows))
    _atomic_text(out / "paper-table.csv", paper_table_csv(rows))
    _atomic_text(out / "paper-table.tex", paper_table_tex(rows))
    _atomic_text(out / "index.html", index_html(ed))
    data = pdf.result()  # what the compile raised is raised here, before report.pdf is touched
    with signals_deferred():  # a signal waits for the renaming, then ends the run
        _atomic_write(out / "report.pdf", lambda fh: fh.write(data))
    return path


def _pdf_bytes(typst: Any, ed: Any, out: Path) -> bytes:
    buf = io.BytesIO()
    typst.write_pdf(ed, out, buf)
    return buf.getvalue()


class _Background:
    """``fn()`` run in a daemon thread from now on; ``result()`` waits for it and returns what it returned, or
    raises what it raised. A daemon: a run interrupted meanwhile ends without waiting for it."""

    def __init__(self, fn: Callable[[], Any]) -> None:
        self._fn, self._value, self._error = fn, None, None
        self._thread = threading.Thread(target=self._run, name="resal-edition-pdf", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        try:
            self._value = self._fn()
        except BaseException as exc:  # handed to the caller's thread by result()
            self._error = exc

    def result(self) -> Any:
        self._thread.join()
        if self._error is not None:
            raise self._error
        return self._value
