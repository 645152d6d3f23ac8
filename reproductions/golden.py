"""Golden numbers: the expected values of every summary, each compared with a tolerance that has a reason.

``python -m reproductions.golden`` (``make golden``) regenerates ``tests/golden/<experiment>.json`` on
purpose; ``python -m reproductions.golden --check`` compares fresh runs with them and prints the differences
as JSON (the test suite runs it in a fresh process under other BLAS kernels). Provenance is ignored.

Only what the data determine is compared numerically: a rank-deficient fit contributes its canonical point,
its determined estimates and its family (when the family holds), never where an optimiser happened to stop;
null directions are compared as lines (up to sign), codes and verdicts exactly.
"""

from __future__ import annotations

import json
import math
import sys
from itertools import repeat
from pathlib import Path
from typing import Any

from .diffing import agrees

__all__ = ["GOLDEN_DIR", "MAX_SUMMARY_BYTES", "MAX_SUMMARY_QUANTITIES", "SUMMARY_FIELDS", "TOLERANCES", "agrees",
           "check_all", "compare", "flatten", "golden_object", "quantity_count", "read_summary", "summary_problem"]

GOLDEN_DIR = Path(__file__).resolve().parent.parent / "tests" / "golden"

# class → (rtol, atol, reason). The movements quoted were measured by tests/test_golden_stability.py (data
# perturbed by one ulp, optimiser started elsewhere) and under other OpenBLAS kernels.
TOLERANCES: dict[str, tuple[float, float, str]] = {
    "code": (0.0, 0.0, "verdicts, ranks, kinds, flags and names are codes: they match exactly or not at all"),
    "closed-form": (1e-9, 1e-12, "rows come from closed forms, inverse maps and well-conditioned fits (xtol 1e-14): "
                                 "they move by < 1e-12 relative under a one-ulp perturbation; 1e-9 leaves three "
                                 "decades for other libm/BLAS rounding and still catches any change of formula; "
                                 "atol 1e-12 for quantities that are zero up to rounding"),
    "fit": (1e-6, 1e-12, "least-squares estimates, their uncertainties, canonical points and families: "
                         "determined by the data to < 1e-8 relative (measured by the one-ulp test); 1e-6 is "
                         "far below any statistical uncertainty and far above that movement"),
    "direction": (0.0, 1e-9, "null directions are lines: compared up to sign and scale, 1 − |cos θ| ≤ 1e-9 "
                             "(their orientation can flip only at an exact tie of two components)"),
    "table": (1e-6, 1e-9, "estimator comparisons: means over seeded synthetic fits of full rank, as 'fit'"),
    "measured": (1e-6, 1e-12, "a measurement against the paper's mechanics: the published value (read from its "
                              "file: exact) and the prediction with its 95 % interval, from seeded Monte Carlo "
                              "draws and profile-likelihood fits solved to ≤ 1e-9 relative; 1e-6 is far below "
                              "their statistical uncertainty and far above rounding"),
}
FORMULA_REASON = ("a printed formula's discrepancy from a numerical reference: below the row's tolerance it is "
                  "integration noise, compared in absolute terms to that tolerance; above it (a formula that "
                  "differs) it is a computed amount, compared relatively as a closed form (rtol 1e-9)")


def _entry(value: Any, why: str) -> tuple[Any, float, float, str]:
    rtol, atol, _ = TOLERANCES[why]
    return value, rtol, atol, why


def flatten(s: dict[str, Any]) -> dict[str, tuple[Any, float, float, str]]:
    """Every compared quantity of a summary as key → (value, rtol, atol, tolerance class)."""
    out: dict[str, tuple[Any, float, float, str]] = {}
    (cf_rtol, cf_atol, _), (code_rtol, code_atol, _) = TOLERANCES["closed-form"], TOLERANCES["code"]
    for r in s["rows"]:  # (the entries of _entry, spelt out: a summary may hold a million quantities)
        key = f"rows.{r['id']}."
        for k in ("printed", "computed", "rel_diff", "tolerance"):
            out[key + k] = (r[k], cf_rtol, cf_atol, "closed-form")
        out[key + "verdict"] = (r["verdict"], code_rtol, code_atol, "code")
        if r["printed"] is None and r["tolerance"] is not None:
            out[key + "computed"] = (r["computed"], cf_rtol, float(r["tolerance"]), "formula")
    for f in s["fits"]:
        key = f"fits.{f['id']}"
        for k in ("value", "stderr", "ci95", "family_range"):
            out[f"{key}.{k}"] = _entry(f[k], "fit")
        out[f"{key}.identifiable"] = _entry(f["identifiable"], "code")
    for i in s.get("identifiability", []):
        j = i["id"]
        out[f"identifiability.{j}.rank"] = _entry(i["rank"], "code")
        out[f"identifiability.{j}.null_directions"] = _entry(i["null_directions"], "direction")
        if i["rank"] < len(i["parameters"]):
            out[f"identifiability.{j}.point"] = _entry(i["point"], "fit")
        fam = i["family_of_solutions"]
        out[f"identifiability.{j}.family.kind"] = _entry(None if fam is None else [fam["kind"], fam["along"],
                                                                                   fam["holds"]], "code")
        if fam is not None and fam["holds"]:  # the ends of a family that fails its check are not determined
            out[f"identifiability.{j}.family.ends"] = _entry(fam["ends"], "fit")
            out[f"identifiability.{j}.family.ranges"] = _entry(fam["ranges"], "fit")
    table_rtol, table_atol, _ = TOLERANCES["table"]
    for t in s.get("tables", []):  # tables.<name>.<j> → (row j, …), made in C: a table may have a million rows
        keys = map(f"tables.{t['name']}.".__add__, map(str, range(len(t["rows"]))))
        out.update(zip(keys, zip(t["rows"], repeat(table_rtol), repeat(table_atol), repeat("table")), strict=True))
    for m in s["modern"]:
        out[f"modern.{m['symbol']}.resal"] = _entry(m["resal"], "closed-form")
    for m in s.get("measurements", []):
        for k in ("measured", "predicted", "interval"):
            out[f"measurements.{m['id']}.{k}"] = _entry(m[k], "measured")
        out[f"measurements.{m['id']}.verdict"] = _entry(m["verdict"], "code")
    out["figures"] = _entry(s["figures"], "code")
    return out


# what ``flatten`` reads of each entry of a summary's lists (``resal diff`` checks a file against it first)
SUMMARY_FIELDS: dict[str, tuple[str, ...]] = {
    "rows": ("id", "printed", "computed", "rel_diff", "tolerance", "verdict"),
    "fits": ("id", "value", "stderr", "ci95", "family_range", "identifiable"),
    "identifiability": ("id", "rank", "null_directions", "parameters", "point", "family_of_solutions"),
    "tables": ("name", "rows"),
    "modern": ("symbol", "resal"),
    "measurements": ("id", "measured", "predicted", "interval", "verdict"),
}


MAX_SUMMARY_BYTES = 16 << 20  # 16 MiB: the largest summary.json resal writes is 60 kB
# the quantities ``flatten`` makes of one summary: resal's largest has 352. 16 MiB alone does not bound them
# sanely: a table row may be two bytes ("0,"), so 16 MiB of table holds 8 million quantities, each a key and a
# tuple on each side and (in ``resal diff``) three lines of output. A million, all differing, take ~600 MB and
# ~6 s of ``resal diff``; two million took 1 GB and 14 s.
MAX_SUMMARY_QUANTITIES = 1 << 20


def read_summary(path: Path) -> dict[str, Any]:
    """A summary.json read for ``resal diff``: a regular UTF-8 file of at most ``MAX_SUMMARY_BYTES``, JSON nested at
    most ``config.MAX_DEPTH`` levels, no key twice in one object, with everything ``flatten`` reads (ids unique,
    at most ``MAX_SUMMARY_QUANTITIES`` quantities); anything else is an ``InputError`` naming the file (a folder, a
    FIFO, ``/dev/zero``, UTF-16, a NUL byte, an integer of thousands of digits, a duplicated key or row id …)."""
    from .config import MAX_DEPTH, decode_text, read_input
    from .errors import InputError

    where = str(path)
    text = decode_text(read_input(path, "a summary.json file", MAX_SUMMARY_BYTES), where, "a summary.json file",
                       max_line=None)
    def no_constant(name: str) -> Any:  # resal writes strict JSON: NaN and ±Infinity are no number it wrote
        raise InputError(where, f"not a summary.json file: {name} is not a JSON number (resal writes strict JSON)")

    def unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:  # json.loads would keep the last silently
        obj = dict(pairs)
        if len(obj) < len(pairs):
            seen: set[str] = set()
            for key, _ in pairs:
                if key in seen:
                    break
                seen.add(key)
            owner = next((f" (in the object with {f} {obj[f][:60]!r})" for f in ("id", "name", "symbol")
                          if isinstance(obj.get(f), str) and f != key), "")
            raise InputError(where, f"not a summary.json file: the key {key[:60]!r} appears twice in one object{owner} "
                                    "(a JSON reader would keep one of them silently)")
        return obj

    try:
        obj = json.loads(text, parse_constant=no_constant, object_pairs_hook=unique_keys)
    except json.JSONDecodeError as exc:
        raise InputError(f"{where}:{exc.lineno}", f"not a summary.json file ({exc.msg}, column {exc.colno})") from None
    except RecursionError:
        raise InputError(where, f"not a summary.json file: nested too deeply (expected at most {MAX_DEPTH} "
                                "levels)") from None
    except ValueError:  # an integer beyond Python's limit on digits (4300)
        raise InputError(where, "not a summary.json file: an integer of more than 4300 digits (expected the "
                                "numbers resal writes)") from None
    problem = _depth_problem(obj, MAX_DEPTH) or summary_problem(obj)
    if problem:
        raise InputError(where, f"not a summary.json file: {problem}")
    return obj


def _depth_problem(obj: Any, limit: int) -> str | None:
    """Arrays and objects nested deeper than ``limit`` (walked without recursion, so any depth is safe)."""
    level, depth = [obj], 0  # walked level by level: the containers at one depth at a time
    while level := [o for o in level if isinstance(o, dict | list)]:
        depth += 1
        if depth > limit:
            return f"nested more than {limit} levels deep (a summary nests 6)"
        level = [v for o in level for v in (o.values() if isinstance(o, dict) else o)]
    return None


def summary_problem(s: Any) -> str | None:
    """None if ``s`` has everything ``flatten`` reads, of the types it needs, each entry's id once (a ``modern``
    symbol may repeat, one entry per source, with the same ``resal`` value) and at most ``MAX_SUMMARY_QUANTITIES``
    quantities; else what is wrong, naming the entry."""
    if not isinstance(s, dict):
        return "expected a JSON object"
    missing = [k for k in ("experiment", "rows", "fits", "modern", "figures") if k not in s]
    if missing:
        return f"expected the keys {', '.join(missing)} of a summary"
    if not isinstance(s["experiment"], str):
        return "'experiment' must be a string (an experiment id)"
    for key, fields in SUMMARY_FIELDS.items():
        entries = s.get(key, [])
        if not isinstance(entries, list):
            return f"'{key}' must be a list"
        for i, e in enumerate(entries):
            if not isinstance(e, dict):
                return f"{key}[{i}] must be an object with {', '.join(fields)}"
            lacks = [f for f in fields if f not in e]
            if lacks:
                name = f" (id '{e['id']}')" if isinstance(e.get("id"), str) else ""
                return f"{key}[{i}]{name} lacks {', '.join(lacks)} (expected {', '.join(fields)})"
    problem = _type_problem(s) or _duplicate_problem(s)
    if problem:
        return problem
    n = quantity_count(s)
    if n > MAX_SUMMARY_QUANTITIES:
        return (f"{n:,} quantities to compare: expected at most {MAX_SUMMARY_QUANTITIES:,} (the largest summary "
                "resal writes has a few hundred)")
    fam = [i for i, e in enumerate(s.get("identifiability", [])) if e["family_of_solutions"] is not None and not (
        isinstance(e["family_of_solutions"], dict) and {"kind", "along", "holds", "ends", "ranges"}
        <= e["family_of_solutions"].keys())]
    if fam:
        return f"identifiability[{fam[0]}].family_of_solutions must be null or have kind, along, holds, ends, ranges"
    return None


def _type_problem(s: dict[str, Any]) -> str | None:
    """The values ``flatten`` computes with (not only copies) of a type it cannot use, naming the first."""
    for i, t in enumerate(s.get("tables", [])):
        if not isinstance(t["rows"], list):
            return f"tables[{i}].rows must be a list"
    for i, e in enumerate(s.get("identifiability", [])):
        if not isinstance(e["parameters"], list):
            return f"identifiability[{i}].parameters must be a list"
        if isinstance(e["rank"], bool) or not isinstance(e["rank"], int | float):
            return f"identifiability[{i}].rank must be a number"
    for i, r in enumerate(s["rows"]):
        tol = r["tolerance"]
        if tol is not None and (isinstance(tol, bool) or not isinstance(tol, int | float) or not _in_float_range(tol)
                                or tol < 0):  # a formula's tolerance is its absolute tolerance (math.isclose's)
            return f"rows[{i}].tolerance must be null or a number ≥ 0 within float range (got {json.dumps(tol)[:40]})"
    return None


def _in_float_range(x: int | float) -> bool:
    try:
        float(x)
    except OverflowError:
        return False
    return True


def _duplicate_problem(s: dict[str, Any]) -> str | None:
    """An id (a table's name, a symbol) that two entries of one list share: ``flatten`` keys quantities by it, so
    one would hide the other. A ``modern`` symbol repeats, one entry per modern source: only its ``resal`` is
    compared, and that must then be the same."""
    for key, fields in SUMMARY_FIELDS.items():
        first: dict[str, int] = {}
        entries = s.get(key, [])
        for i, e in enumerate(entries):
            name = str(e[fields[0]])  # as flatten spells it in the key
            j = first.setdefault(name, i)
            if j == i:
                continue
            if key == "modern":
                if entries[j]["resal"] == e["resal"]:
                    continue
                return (f"modern[{i}]: symbol {name[:60]!r} again (as modern[{j}]) with another resal value "
                        f"({json.dumps(entries[j]['resal'])[:40]}, then {json.dumps(e['resal'])[:40]})")
            return f"{key}[{i}]: {fields[0]} {name[:60]!r} again (as {key}[{j}]): each {fields[0]} must be unique"
    return None


def quantity_count(s: dict[str, Any]) -> int:
    """An upper bound on the quantities ``flatten`` makes of ``s`` (one that ``summary_problem`` accepts), counted
    without making them."""
    return (5 * len(s["rows"]) + 5 * len(s["fits"]) + 6 * len(s.get("identifiability", []))
            + sum(len(t["rows"]) for t in s.get("tables", [])) + len(s["modern"])
            + 4 * len(s.get("measurements", [])) + 1)


def golden_object(s: dict[str, Any]) -> dict[str, Any]:
    reasons = {k: v[2] for k, v in TOLERANCES.items()} | {"formula": FORMULA_REASON}
    return {"experiment": s["experiment"], "tolerances": reasons,
            "values": {k: {"value": v, "rtol": r, "atol": a, "why": w}
                       for k, (v, r, a, w) in sorted(flatten(s).items())}}


def movement(g: dict[str, Any], value: Any) -> float:
    """How far ``value`` is from a golden entry, in units of its tolerance (≤ 1 passes)."""
    if g["why"] == "direction":
        if not isinstance(value, list) or len(value) != len(g["value"]):
            return math.inf
        worst = 0.0
        for u, v in zip(g["value"], value, strict=True):
            nu, nv = math.sqrt(sum(x * x for x in u)), math.sqrt(sum(y * y for y in v))
            c = abs(sum(x * y for x, y in zip(u, v, strict=True))) / (nu * nv)
            worst = max(worst, (1 - c) / g["atol"])
        return worst
    return _movement(g["value"], value, g["rtol"], g["atol"])


def _movement(a: Any, b: Any, rtol: float, atol: float) -> float:
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return math.inf
        return max((_movement(x, y, rtol, atol) for x, y in zip(a, b, strict=True)), default=0.0)
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, int | float) or not isinstance(b, int | float):
        return 0.0 if a == b else math.inf
    allowed = max(rtol * max(abs(a), abs(b)), atol)
    return 0.0 if a == b else (abs(a - b) / allowed if allowed > 0 else math.inf)


def compare(golden: dict[str, Any], s: dict[str, Any]) -> list[str]:
    """Differences between a golden object and a summary, one line each; empty when they agree. Linear in the
    quantities: each is looked up in the other side's dict."""
    now = flatten(s)
    diffs = []
    for k, g in golden["values"].items():
        if k not in now:
            diffs.append(f"{k}: in the golden file, missing now")
            continue
        if not agrees(g["value"], now[k][0], g["rtol"], g["atol"], g.get("why")):
            diffs.append(f"{k}: golden {g['value']!r}, now {now[k][0]!r} "
                         f"(rtol {g['rtol']:g}, atol {g['atol']:g}, {g.get('why', '?')})")
    diffs += [f"{k}: new quantity, not in the golden file" for k in now if k not in golden["values"]]
    return diffs


def _summaries(only: set[str] | None = None) -> dict[str, dict[str, Any]]:
    from . import api
    from .report import summary

    return {eid: summary(api.run(api.load(eid)), prov={}) for eid in api.experiment_ids()
            if not only or eid in only}


def check_all() -> dict[str, list[str]]:
    """Every shipped experiment against its golden file: experiment id → differences (empty when it agrees)."""
    out = {}
    for eid, s in _summaries().items():
        path = GOLDEN_DIR / f"{eid}.json"
        out[eid] = (compare(json.loads(path.read_text(encoding="utf-8")), s) if path.is_file()
                    else [f"no golden file {path.name}"])
    return out


def main(argv: list[str]) -> int:
    if argv == ["--check"]:
        diffs = check_all()
        print(json.dumps(diffs, ensure_ascii=False))
        return 1 if any(diffs.values()) else 0
    GOLDEN_DIR.mkdir(parents=True, exist_ok=True)
    only = set(argv)  # `python -m reproductions.golden ball-ball`: regenerate only these experiments' goldens
    for eid, s in _summaries(only).items():
        path = GOLDEN_DIR / f"{eid}.json"
        path.write_text(json.dumps(golden_object(s), indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
