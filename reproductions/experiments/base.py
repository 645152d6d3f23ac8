"""What the experiment kinds share: the verdict of a printed value, the rows of a config, the ball section,
today's values. The result types themselves live in ``reproductions.results`` (re-exported here for the kinds)."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

from ..config import BEYOND_SUFFIX, MEASUREMENT_VERDICTS, Experiment, Node, Printed
from ..results import (
    Comparison,
    Computed,
    FigureSpec,
    FitRow,
    Layer,
    MeasurementRow,
    Reproduction,
    Row,
    TableSpec,
    family_report,
    fit_rows,
    identifiability_report,
    layer,
    modern_table,
)
from ..series import read_series

__all__ = [
    "Comparison", "Computed", "FigureSpec", "FitRow", "Layer", "MeasurementRow", "Reproduction", "Row", "TableSpec",
    "compare", "family_report", "fit_rows", "identifiability_report", "layer", "measurement_rows", "modern_rows",
    "read_ball", "read_series", "rows_for",
]


def compare(p: Printed, c: Computed) -> Row:
    """The verdict for one printed value: reproduced within the printed digits, differs (with why), or not
    checkable; with where it is printed and the config's reason code for a row that differs."""
    row = _compare(p, c)
    return dataclasses.replace(row, english=p.english, line=p.line, reason=p.reason, today=p.today,
                               config_line=int(p.where.rsplit(":", 1)[1]) if ":" in p.where else None,
                               computes=p.computed, margin=c.margin,
                               domain="beyond" if p.id.endswith(BEYOND_SUFFIX) else "paper")


def _compare(p: Printed, c: Computed) -> Row:
    if p.formula and c.value is not None:
        assert p.tolerance is not None
        ok = abs(c.value) <= p.tolerance
        return Row(p.id, p.quantity, p.source, None, p.text, c.value, None, p.tolerance, p.tolerance_rule,
                   "reproduced" if ok else "differs",
                   c.how if ok else (c.diagnose(0.0) if c.diagnose else "the printed formula disagrees: " + c.how))
    if p.value is None or c.value is None:
        note = c.how or "resal computes no value for this claim"
        return Row(p.id, p.quantity, p.source, p.value, p.text, c.value, None, p.tolerance, p.tolerance_rule,
                   "not-checkable", note)
    rel = (c.value - p.value) / abs(p.value) if p.value != 0 else c.value - p.value
    assert p.tolerance is not None
    if abs(rel) <= p.tolerance * (1 + 1e-9):
        verdict, note = "reproduced", c.how
    else:
        verdict = "differs"
        note = c.diagnose(p.value) if c.diagnose else "no explanation found: " + c.how
    return Row(p.id, p.quantity, p.source, p.value, p.text, c.value, rel, p.tolerance, p.tolerance_rule, verdict,
               note)


def rows_for(exp: Experiment, computed: dict[str, Computed]) -> tuple[Row, ...]:
    """One row per printed value of the config, in the config's (the paper's) order."""
    return tuple(compare(p, computed[p.computed]) for p in exp.printed)


def measurement_rows(exp: Experiment, comparisons: dict[str, Comparison]) -> tuple[MeasurementRow, ...]:
    """One row per measured entry of the config, in the config's order, each with the kind's comparison."""
    out = []
    for m in exp.measured:
        c = comparisons[m.computed]
        if c.verdict not in MEASUREMENT_VERDICTS:
            raise ValueError(f"{m.id}: verdict {c.verdict!r} is not one of {MEASUREMENT_VERDICTS}")
        note = f"{c.how} {m.note}".strip()
        out.append(MeasurementRow(m.id, m.quantity, m.source, m.unit, c.measured, c.measured_text, c.uncertainty,
                                  c.predicted, c.interval, c.verdict, note,
                                  int(m.where.rsplit(":", 1)[1]) if ":" in m.where else None, m.computed))
    return tuple(out)


def read_ball(node: Node, with_mass: bool = False) -> tuple[float, ...]:
    """The ``ball`` section shared by the kinds: (R, k), or (R, k, M) with ``with_mass``."""
    ball = node.child("ball", "a mapping with R, k" + (", M" if with_mass else ""))
    out = [ball.number("R", "a radius in m", lo=0.0, lo_open=True),
           ball.number("k", "k of the moment of inertia M R²/k", lo=0.0, lo_open=True)]
    if with_mass:
        out.append(ball.number("M", "a mass in kg", lo=0.0, lo_open=True))
    ball.done()
    return tuple(out)


def modern_rows(symbols: Sequence[str], values: dict[str, tuple[float, str]]) -> tuple[dict, ...]:
    """Rows of ``modern-values.csv`` for the requested symbols, beside the value resal derives."""
    table = modern_table()
    out = []
    for sym in symbols:
        resal_value, what = values[sym]
        for r in table:
            if r["symbol"] == sym:
                out.append({"symbol": sym, "quantity": r["quantity"], "resal": resal_value, "resal_what": what,
                            "low": r["low"], "typ": r["typ"], "high": r["high"],
                            "source": r["source"], "note": r["note"]})
    return tuple(out)


