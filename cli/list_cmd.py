"""``resal list``: every experiment, a row each."""

from __future__ import annotations

import os

from rich.cells import cell_len
from rich.text import Text

from cli.app import app
from cli.common import _fail, out_console
from reproductions.errors import InputError


@app.command("list")
def list_cmd() -> None:
    """List every experiment in the paper's order: id, section, title.

    \b
    Examples:
      resal list
      resal reproduce coriolis-pendulum
    """
    from reproductions import api

    try:
        exps = api.list_experiments()
    except InputError as err:
        _fail(err)
    if not exps:  # one line naming where it looked, exit 2 (not an empty table)
        d = api.config_dir()
        where = f"{d} ($RESAL_CONFIGS)" if os.environ.get("RESAL_CONFIGS") else str(d)
        _fail(InputError(where, f"no experiments found ({'no *.yaml file there' if d.is_dir() else 'no such folder'})"))
    from reproductions.report import paper_order

    # the reader's edition's order: the paper's experiments by page, then those of today's measurements
    exps = sorted(exps, key=lambda e: paper_order(e.source.page, e.id, bool(e.measured)))
    wid = max(cell_len(e.id) for e in exps)
    wsec = max(cell_len(e.source.section) for e in exps)
    room = max(out_console.width - wid - wsec - 4, 16)  # a title is cut to the rest of the line, at a word

    def line(eid: str, section: str, title: str, style: str = "") -> None:
        text = f"{eid.ljust(wid)}  {section.ljust(wsec)}  {_cut(title, room)}".rstrip()
        out_console.print(Text(text, style=style), highlight=False, soft_wrap=True)

    line("id", "§", "title", "bold")
    for j, e in enumerate(exps):
        if e.measured and (j == 0 or not exps[j - 1].measured):
            out_console.print(Text("today's measurements against the paper's mechanics:", style="bold"),
                              highlight=False, soft_wrap=True)
        line(e.id, e.source.section, e.title)
    env = " ($RESAL_CONFIGS)" if os.environ.get("RESAL_CONFIGS") else ""
    out_console.print(Text(f"{len(exps)} experiments in the paper's order; their configs{env}:"), highlight=False,
                      soft_wrap=True)
    out_console.print(Text(str(api.config_dir())), highlight=False, soft_wrap=True)  # a path is never folded


def _cut(text: str, width: int) -> str:
    """``text`` in ``width`` columns: whole, or cut at a word and ended with "…"."""
    if cell_len(text) <= width:
        return text
    words = text.split(" ")
    while len(words) > 1 and cell_len(" ".join(words) + "…") > width:
        words.pop()
    return " ".join(words).rstrip(",;:—-") + "…"
