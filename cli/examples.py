"""``resal examples``: copy the example files that ship with resal (one synthetic CSV per kind of ``resal fit``, and
their README) into a folder, and say how to fit each: a pip user's first fit needs a file, and the wheel has no
``examples/`` folder to point at."""

from __future__ import annotations

import os
import re
import shlex
from pathlib import Path
from typing import Annotated

import typer
from rich.text import Text

from cli.app import app
from cli.common import _fail, err_console, out_console
from reproductions import locate
from reproductions.errors import InputError

DEFAULT = "resal-examples"  # the folder `resal examples` writes when given none; the help pages name it
_USE = re.compile(r"\(use (--[^)]*)\)")  # the options a file's first line says its fit needs: "(use --R 0.02855)"


def _fit_command(folder: str, path: Path) -> str | None:
    """The command that fits the example file ``path`` once copied into ``folder``: its kind (the kind whose
    example it is, else the kind its name starts with: pendulum-heights.csv is a pendulum file) and the options its
    first line asks for; None for a file that is no CSV."""
    from reproductions.fit.kinds import KINDS

    if path.suffix != ".csv":
        return None
    kind = next((k for k, v in KINDS.items() if v.example == path.name), None)
    kind = kind or max((k for k in KINDS if path.stem.startswith(k + "-")), key=len, default=None)
    if kind is None:
        return None
    with path.open(encoding="utf-8") as f:
        first = f.readline()
    options = [o for m in _USE.findall(first) for o in m.split()]
    return shlex.join(["resal", "fit", kind, os.path.join(folder, path.name), *options])


@app.command("examples")
def examples_cmd(
    folder: Annotated[str, typer.Argument(metavar="DIR", show_default=False, help=(
        f"the folder to copy them into (default {DEFAULT}, in the current folder; made if missing)"))] = DEFAULT,
) -> None:
    """Copy the example files of `resal fit` into a folder.

    The files are synthetic data, one CSV per kind of fit, labelled so in their first lines, and a README; they go
    into DIR (default resal-examples), and the command that fits each is printed. A file already there is left
    alone when it is the same, and refused when it differs (nothing is copied then).

    \b
    Examples:
      resal examples
      resal fit cushion resal-examples/cushion.csv
      resal examples my-examples
    """
    if not folder.strip():
        _fail(InputError(f"DIR '{folder}'", f"expected a folder (leave it out for {DEFAULT}; say . for the current "
                                            "folder)"))
    files = locate.example_files()
    if not files:  # a broken install, not the user's input
        err_console.print(Text("error: ", style="bold red")
                          + Text(f"{locate.examples_dir()}: no example files there (an incomplete install? reinstall "
                                 "resal)"), soft_wrap=True)
        raise typer.Exit(1)
    dest = Path(folder)
    if dest.exists() and not dest.is_dir():
        _fail(InputError(folder, f"is a file, not a folder: expected the folder to copy the example files into "
                                 f"(leave it out for {DEFAULT})"))
    new, same = [], []
    for src in files:  # every refusal before any write: a refused run leaves the folder as it was
        target = dest / src.name
        if not target.exists():
            new.append(src)
        elif target.is_file() and target.read_bytes() == src.read_bytes():
            same.append(src)
        else:
            what = "a folder" if target.is_dir() else "a different file"
            _fail(InputError(str(target), f"is {what}, not the shipped example: left as it is and nothing copied "
                                          f"(move it away, or name another folder: resal examples DIR)"))
    dest.mkdir(parents=True, exist_ok=True)
    for src in new:
        tmp = dest / f".{src.name}.{os.getpid()}.tmp"
        try:
            tmp.write_bytes(src.read_bytes())
            os.replace(tmp, dest / src.name)  # whole or absent, even when interrupted
        finally:
            tmp.unlink(missing_ok=True)
    shown = folder.rstrip("/\\") + "/" if folder.rstrip("/\\") else folder
    kept = f"{len(same)} already there, the same" if same else ""
    if new:
        head = f"wrote {len(new)} file{'s' * (len(new) != 1)} into {shown}" + (f" ({kept})" if kept else "")
    else:
        head = f"{shown} already holds the {len(same)} example files, the same"
    out_console.print(f"{head} (synthetic data, labelled so; see README.md)",
                      highlight=False, markup=False)
    commands = [c for c in (_fit_command(folder, p) for p in files) if c]
    out_console.print("next, fit one of them:", highlight=False, markup=False)
    for c in sorted(commands, key=lambda c: " cushion " not in c):  # the one the help pages name, first
        out_console.print(f"  {c}", highlight=False, markup=False, soft_wrap=True)  # one line, to copy whole
