"""Golden numbers: the expected values of every summary, compared with a relative tolerance per quantity.

``python -m reproductions.golden`` (``make golden``) regenerates ``tests/golden/<experiment>.json`` on
purpose; the golden test compares a fresh run with them and ignores provenance.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any

__all__ = ["GOLDEN_DIR", "compare", "flatten", "golden_object"]

GOLDEN_DIR = Path(__file__).resolve().parent.parent / "tests" / "golden"
RTOL_CLOSED_FORM = 1e-9  # rows: closed forms and inverse maps, exact to rounding
RTOL_ITERATIVE = 1e-6  # fits: iterative least squares
ATOL = 1e-12  # for quantities that are zero up to rounding


def flatten(s: dict[str, Any]) -> dict[str, tuple[Any, float, float]]:
    """Every compared quantity of a summary as key → (value, rtol, atol); provenance is left out.

    The discrepancy of a printed formula from a numerical reference (a row with no printed number but a
    tolerance) is compared in absolute terms, to the row's own tolerance: its digits are integration noise.
    """
    out: dict[str, tuple[Any, float, float]] = {}
    for r in s["rows"]:
        for k in ("printed", "computed", "rel_diff", "tolerance", "verdict"):
            out[f"rows.{r['id']}.{k}"] = (r[k], RTOL_CLOSED_FORM, ATOL)
        if r["printed"] is None and r["tolerance"] is not None:
            out[f"rows.{r['id']}.computed"] = (r["computed"], 0.0, float(r["tolerance"]))
    for i, f in enumerate(s["fits"]):
        key = f"fits.{i}.{f['parameter']}"
        out[f"{key}.value"] = (f["value"], RTOL_ITERATIVE, ATOL)
        out[f"{key}.stderr"] = (f["stderr"], RTOL_ITERATIVE, ATOL)
        out[f"{key}.ci95"] = (f["ci95"], RTOL_ITERATIVE, ATOL)
        out[f"{key}.identifiable"] = (f["identifiable"], 0.0, 0.0)
        out[f"{key}.family_range"] = (f["family_range"], RTOL_ITERATIVE, ATOL)
    for j, i in enumerate(s.get("identifiability", [])):
        out[f"identifiability.{j}.rank"] = (i["rank"], 0.0, 0.0)
        out[f"identifiability.{j}.null_directions"] = (i["null_directions"], RTOL_ITERATIVE, 1e-9)
        out[f"identifiability.{j}.family_of_solutions"] = (i["family_of_solutions"], RTOL_ITERATIVE, 1e-9)
    for t in s.get("tables", []):
        for j, row in enumerate(t["rows"]):
            out[f"tables.{t['name']}.{j}"] = (row, RTOL_ITERATIVE, 1e-9)
    for m in s["modern"]:
        out[f"modern.{m['symbol']}.resal"] = (m["resal"], RTOL_CLOSED_FORM, ATOL)
    out["figures"] = (s["figures"], 0.0, 0.0)
    return out


def golden_object(s: dict[str, Any]) -> dict[str, Any]:
    return {"experiment": s["experiment"],
            "values": {k: {"value": v, "rtol": r, "atol": a} for k, (v, r, a) in sorted(flatten(s).items())}}


def _close(a: Any, b: Any, rtol: float, atol: float) -> bool:
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_close(x, y, rtol, atol) for x, y in zip(a, b, strict=True))
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, int | float) or not isinstance(b, int | float):
        return a == b
    return math.isclose(a, b, rel_tol=rtol, abs_tol=atol)


def compare(golden: dict[str, Any], s: dict[str, Any]) -> list[str]:
    """Differences between a golden object and a summary, one line each; empty when they agree."""
    now = flatten(s)
    diffs = []
    for k, g in golden["values"].items():
        if k not in now:
            diffs.append(f"{k}: in the golden file, missing now")
        elif not _close(g["value"], now[k][0], g["rtol"], g["atol"]):
            diffs.append(f"{k}: golden {g['value']!r}, now {now[k][0]!r} (rtol {g['rtol']:g}, atol {g['atol']:g})")
    diffs += [f"{k}: new quantity, not in the golden file" for k in now if k not in golden["values"]]
    return diffs


def main() -> int:
    from . import api
    from .report import summary

    GOLDEN_DIR.mkdir(parents=True, exist_ok=True)
    for eid in api.experiment_ids():
        s = summary(api.run(api.load(eid)), prov={})
        path = GOLDEN_DIR / f"{eid}.json"
        path.write_text(json.dumps(golden_object(s), indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
