"""``resal simulate``: one scene of a mechanics model, its inputs and outputs with their units; ``--list``, the
models."""

from __future__ import annotations

from typing import Annotated, Any

import typer
from rich.text import Text

from cli.app import app
from cli.common import _count, _fail, _json, _plain_table, _print_items, err_console, out_console
from reproductions.errors import InputError


@app.command()
def simulate(
    model: Annotated[str | None, typer.Argument(help="model name; see --list")] = None,
    set_: Annotated[list[str] | None, typer.Option("--set", help="name=value: SI units, angles in degrees, "
                                                                  "vectors as x,y,z")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object (its 'units' give each input's "
                                                         "and output's unit)")] = False,
    list_: Annotated[bool, typer.Option("--list", help="list the models: their parameters (units, ranges, "
                                                       "defaults), paths and outputs")] = False,
    method: Annotated[str, typer.Option(help="solution path: auto (the cheapest exact one for the scene) or a "
                                             "path of the model (see --list)")] = "auto",
    digits: Annotated[int, typer.Option("--digits", parser=_count("--digits", 1, 17, "a number of significant digits"),
                                        help="significant digits of the numbers printed, 1 to 17 (--json gives "
                                             "every digit)")] = 6,
) -> None:
    """Run one scene of a mechanics model: its inputs and outputs.

    \b
    Examples:
      resal simulate --list
      resal simulate wall-impact --set eps=0.3
      resal simulate direct-impact --set eps=0.5 --set epsp=0.5
      resal simulate cloth-slide --set vx=2 --set wx=60 --set f=0.25
      resal simulate wall-impact --set eps=0.3 --json

    Each input and output is printed with its unit (SI; angles in degrees, as the inputs are).
    """
    from reproductions.models import list_models
    from reproductions.models import simulate as run_scene

    if list_:
        info = list_models()
        if as_json:
            typer.echo(_json(info))
        else:
            _print_models(info)
        return
    try:
        if model is None:
            raise InputError("arguments", "name a model (see resal simulate --list)")
        result = run_scene(model, list(set_ or []), method)
    except InputError as err:
        _fail(err)
    for w in result["warnings"]:  # on stderr, one line each, the scene computed all the same (exit 0)
        err_console.print(Text("warning: ", style="bold yellow") + Text(w["message"]), soft_wrap=True)
    if as_json:
        typer.echo(_json(result))
        return
    described = next(m for m in list_models()["models"] if m["model"] == model)
    meaning = {p["name"]: p["doc"] for p in described["parameters"]} | {o["name"]: o["doc"]
                                                                       for o in described["outputs"]}
    out_console.print(Text(result["model"], style="bold") + Text(f": path {result['path_name']}, regime "
                                                                 f"{result['regime_name']}"))
    out_console.print(Text(result["label"]))
    rows = [("in" if side == "inputs" and j == 0 else "out" if j == 0 else "", k,
             _value_text(v, digits, regimes=result["units"][side][k] == "code"), _unit_text(result["units"][side][k]),
             meaning[k], side == "inputs" and j == len(result[side]) - 1)
            for side in ("inputs", "outputs") for j, (k, v) in enumerate(result[side].items())]
    # Names, units and numbers are never cut: on a console too narrow for the table (COLUMNS=20), a line per value
    # that the terminal wraps (a list of values folds between its numbers, so 24 columns suffice for it).
    need = sum(min(max(len(r[i]) for r in rows), 24) for i in range(4)) + 12 + 10
    if out_console.width < need:
        for tag, name, value, unit, what, _ in rows:
            if tag:
                out_console.print(Text("inputs:" if tag == "in" else "outputs:", style="bold"))
            unit = "" if unit == "1" else unit
            out_console.print(Text(f"  {name} = {value} {unit}".rstrip() + f" ({what})"), soft_wrap=True)
        return
    t = _plain_table()
    for c in ("", "name", "value", "unit", "meaning"):
        t.add_column(c, no_wrap=c in ("", "name", "unit"), overflow="fold")
    for *cells, end in rows:
        t.add_row(*cells, end_section=end)
    out_console.print(t)


def _unit_text(unit: str) -> str:
    """A unit as printed: codes and flags need none (their values are names and true/false)."""
    return "" if unit in ("code", "flag") else unit


def _value_text(v: Any, digits: int = 6, regimes: bool = False) -> str:
    """A simulate value as printed: lists flattened (components, or one value per impact), regime codes named."""
    from reproductions.mechanics.paths import Regime

    if v is None:
        return "—"
    if isinstance(v, list):
        return ", ".join(_value_text(x, digits, regimes) for x in _flat(v))
    if isinstance(v, bool):
        return "true" if v else "false"
    if regimes:
        return Regime(v).name.lower().replace("_", "-")
    return f"{v:.{digits}g}" if isinstance(v, float) else str(v)


def _range_cell(p: dict[str, Any]) -> str:
    """A parameter's admissible range in the unit it is typed in (degrees for an angle): "0 < alpha0 < 90",
    "M > 0", "any"; ", whole" for a count."""
    n, lo, hi = p["name"], p["lo"], p["hi"]
    below, above = "<" if p["lo_open"] else "≤", "<" if p["hi_open"] else "≤"
    if lo is not None and hi is not None:
        text = f"{lo:g} {below} {n} {above} {hi:g}"
    elif lo is not None:
        text = f"{n} {'>' if p['lo_open'] else '≥'} {lo:g}"
    elif hi is not None:
        text = f"{n} {above} {hi:g}"
    else:
        text = "any"
    return f"{text}, whole" if p["integer"] else text


def _default_cell(p: dict[str, Any]) -> str:
    if p["required"]:
        return "required"
    d = p["default"]
    return ",".join([f"{d:g}"] * 3) if p["vector"] else f"{d:g}"


def _print_wrapped(text: str, indent: str = "", hanging: str | None = None, bold: int = 0) -> None:
    """``text`` wrapped at words to the console (a word longer than a line left whole), its first ``bold``
    characters bold; no trailing space."""
    import textwrap

    lines = textwrap.wrap(text, max(out_console.width, 20), initial_indent=indent,
                          subsequent_indent=indent if hanging is None else hanging, break_long_words=False,
                          break_on_hyphens=False) or [""]
    for j, ln in enumerate(lines):
        t = Text(ln)
        if j == 0 and bold:
            t.stylize("bold", len(indent), len(indent) + bold)
        out_console.print(t, highlight=False, soft_wrap=True)


def _print_models(info: dict[str, Any]) -> None:
    """``simulate --list``: per model a heading (model, section, paths), its meaning and the scenes it admits,
    a line per parameter (name, unit, range, default, meaning; the meaning wrapped at words in the room left)
    and its outputs with their units on one wrapped line."""
    out_console.print(Text("models of resal simulate", style="bold"), highlight=False, soft_wrap=True)
    _print_wrapped(f"units: {info['units']}. A line per parameter: name, unit (1: a pure number), range, "
                   "default (required: give yours, --set name=value), meaning. --list --json: the same, with the "
                   "codes and the cost of each path.")
    for m in info["models"]:
        out_console.print()
        _print_wrapped(f"{m['model']}  {m['section']}  paths: {', '.join(p['name'] for p in m['paths'])}",
                       hanging="    ", bold=len(m["model"]))
        _print_wrapped(f"{m['doc']}; admits {m['admits']}", indent="  ", hanging="    ")
        rows = [(p["name"], p["unit"], _range_cell(p), _default_cell(p), p["doc"]) for p in m["parameters"]]
        widths = [max(len(r[i]) for r in rows) for i in range(4)]
        lead = 2 + sum(widths) + 2 * 4  # the columns before the meaning
        room = out_console.width - lead
        for *cells, doc in rows:
            head = "  " + "  ".join(c.ljust(w) for c, w in zip(cells, widths, strict=True))
            if room >= 24:  # the meaning beside, wrapped under itself
                _print_wrapped(f"{head}  {doc}", hanging=" " * lead)
            else:  # a console too narrow: the meaning on the lines below
                out_console.print(Text(head.rstrip()), highlight=False, soft_wrap=True)
                _print_wrapped(doc, indent="      ")
        _print_items("outputs:", [f"{o['name']} ({o['unit']})" for o in m["outputs"]], indent="  ")


def _flat(v: list[Any]) -> list[Any]:
    return [y for x in v for y in (_flat(x) if isinstance(x, list) else [x])]
