"""``resal list``: every experiment, a row each."""

from __future__ import annotations

import os

from rich.table import Table

from cli.app import app
from cli.common import _fail, out_console
from reproductions.errors import InputError


@app.command("list")
def list_cmd() -> None:
    """List every experiment: id, section, title, kind.

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
    t = Table(title=f"experiments in {api.config_dir()}")
    for c in ("id", "section", "title", "kind"):
        t.add_column(c)
    for e in exps:
        t.add_row(e.id, e.source.section, e.title, e.kind)
    out_console.print(t)
