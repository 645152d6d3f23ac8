"""The reader's edition of a results folder: ``index.html`` (self-contained, figures beside it) and ``report.pdf``
(set by Typst), both rendered from one ``Edition`` (``model``) built from the summaries (``build``), beside the
index and the paper table of ``report``. Templates are files of ``templates/`` beside the code."""

from __future__ import annotations

from pathlib import Path

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
    ``skipped`` receives the summaries left out (not resal's, or changed by hand: ``report.summary_problem``)."""
    from .typst import write_pdf  # the typst package: imported only when a report is written

    summaries = _summaries(out, skipped)
    rows = paper_rows(summaries)
    path = out / "index.md"
    _atomic_text(path, index_md(summaries))
    _atomic_text(out / "paper-table.md", paper_table_md(rows))
    _atomic_text(out / "paper-table.csv", paper_table_csv(rows))
    _atomic_text(out / "paper-table.tex", paper_table_tex(rows))
    ed = build(summaries)
    _atomic_text(out / "index.html", index_html(ed))
    with signals_deferred():  # a signal waits for the PDF writer (matplotlib) to finish, then ends the run
        _atomic_write(out / "report.pdf", lambda fh: write_pdf(ed, out, fh))
    return path
