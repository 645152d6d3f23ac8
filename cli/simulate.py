"""``resal simulate``: one scene of a mechanics model, its inputs and outputs with their units; ``--list``, the
models."""

from __future__ import annotations

from typing import Annotated, Any

import typer
from rich.padding import Padding
from rich.text import Text

from cli.app import app
from cli.common import _fail, _json, _plain_table, _print_items, out_console
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
             _value_text(v, regimes=result["units"][side][k] == "code"), _unit_text(result["units"][side][k]),
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


def _value_text(v: Any, digits: int = 10, regimes: bool = False) -> str:
    """A simulate value as printed: lists flattened (components, or one value per impact), regime codes named."""
    from reproductions.mechanics.paths import Regime

    if v is None:
        return "—"
    if isinstance(v, list):
        return ", ".join(_value_text(x, 6, regimes) for x in _flat(v))
    if isinstance(v, bool):
        return "true" if v else "false"
    if regimes:
        return Regime(v).name.lower().replace("_", "-")
    return f"{v:.{digits}g}" if isinstance(v, float) else str(v)


def _range_cell(p: dict[str, Any]) -> str:
    """A parameter's admissible range, short: "(0, 1]", "> 0", "any"; "whole" for a count."""
    text = p["range"].removeprefix("a number").strip()
    text = text.removeprefix("in ").strip() or "any"
    return f"whole, {text}" if p["integer"] else text


def _default_cell(p: dict[str, Any]) -> str:
    if p["required"]:
        return "required"
    d = p["default"]
    return ",".join([f"{d:g}"] * 3) if p["vector"] else f"{d:g}"


def _print_models(info: dict[str, Any]) -> None:
    """``simulate --list``: per model a heading, its paths, a table of its parameters (name, unit, range,
    default, meaning) and its outputs with their units. Narrow columns never wrap; the meanings wrap at words."""
    out_console.print(Text("models of resal simulate", style="bold"))
    out_console.print(Text(f"units: {info['units']}; a parameter without a default must be given (--set "
                           f"name=value); --list --json gives the same with path and regime codes"))
    for m in info["models"]:
        out_console.print()
        out_console.print(Text(m["model"], style="bold") + Text(f": {m['doc']} ({m['section']})"))
        _print_items("paths (cost):", [f"{p['name']} ({p['cost']})" for p in m["paths"]], indent="  ")
        out_console.print(Padding(Text(f"admits: {m['admits']}"), (0, 0, 0, 2), expand=False))
        t = _plain_table()
        for c in ("parameter", "unit", "range", "default", "meaning"):
            t.add_column(c, no_wrap=c != "meaning", overflow="fold")
        for p in m["parameters"]:
            t.add_row(p["name"], p["unit"], _range_cell(p), _default_cell(p), p["doc"])
        out_console.print(Padding(t, (0, 0, 0, 2), expand=False))
        _print_items("outputs:", [f"{o['name']} ({o['unit']})" for o in m["outputs"]], indent="  ")


def _flat(v: list[Any]) -> list[Any]:
    return [y for x in v for y in (_flat(x) if isinstance(x, list) else [x])]
