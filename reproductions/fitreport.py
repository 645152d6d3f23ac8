"""The files of ``resal fit``: fit.json (the summary with provenance), fit.md, residuals.csv and the figures."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

from .report import code_provenance, write_folder
from .userfit import FitOptions, FitOutcome

__all__ = ["fit_markdown", "provenance", "write_fit"]


def provenance(path: Path, opts: FitOptions) -> dict[str, Any]:
    """Code version and commit, the data file's SHA-256, and the options that shaped the answer."""
    c = code_provenance()
    c["data_sha256"] = hashlib.sha256(path.read_bytes()).hexdigest()
    c["options"] = {k: (v.value if hasattr(v, "value") else v) for k, v in vars(opts).items() if k != "progress"}
    return c


def _num(v: Any, digits: int = 6) -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def _ci(ci: list | None) -> str:
    if not ci or ci[0] is None:
        return "—"
    return f"[{ci[0]:.4g}, {ci[1]:.4g}]"


def fit_markdown(s: dict[str, Any]) -> str:
    """fit.md: the estimates, the noise model, the tests, the comparisons, the warnings, the columns read."""
    out = [f"# resal fit {s['kind']}: {Path(s['file']).name} ({s['n']} rows)", ""]
    out += ["| parameter | value | std. error | 95 % interval | bootstrap 95 % | note |", "|---|---|---|---|---|---|"]
    for f in s["fits"]:
        out.append(f"| {f['parameter']} | {_num(f['value'])} | {_num(f['stderr'], 3)} | {_ci(f['ci95'])} | "
                   f"{_ci(f.get('ci95_bootstrap'))} | {f['note'] or f['method']} |")
    noise = s.get("noise")
    if noise:
        out += ["", f"Noise model: **{noise['model']}**" + (f" (chosen by {noise['chosen_by']})"
                                                             if "chosen_by" in noise else "")]
    sd = s.get("speed_dependence")
    if sd:
        out += ["", f"Speed dependence: {sd['verdict']}."]
        if sd.get("law"):
            out.append(f"Law: {sd['law']['text']}.")
    good = s.get("goodness") or {}
    if good.get("reduced_chi2") is not None:
        out.append(f"Reduced χ² = {good['reduced_chi2']:.3g} (p = {good['chi2_p']:.2g}).")
    if good.get("lack_of_fit"):
        lof = good["lack_of_fit"]
        out.append(f"Lack of fit (pure error): F = {lof['F']:.3g}, p = {lof['p']:.2g}.")
    comp = s.get("comparison")
    if comp:
        out += ["", "| beside | value | verdict | source |", "|---|---|---|---|"]
        for p in comp["paper"]:
            out.append(f"| {p['claim']} | {_num(p['value'], 4)} | {p['verdict']} | paper, line {p['line']} |")
        for m in comp["today"]:
            val = _num(m["typ"], 4) if m["typ"] is not None else f"{_num(m['low'], 4)}–{_num(m['high'], 4)}"
            out.append(f"| today: {m['quantity']} | {val} | {m['verdict']} | {m['source']} |")
    if s.get("warnings"):
        out += [""] + [f"- WARNING: {w}" for w in s["warnings"]]
    out += ["", "Columns read: " + "; ".join(f"{c['column']} ({c['unit']}{', ' + c['note'] if c['note'] else ''})"
                                             for c in s["columns"])]
    return "\n".join(out) + "\n"


def _csv(headers: tuple[str, ...], rows: tuple[tuple[Any, ...], ...]) -> str:
    lines = [",".join(f'"{h}"' if "," in h else h for h in headers)]
    lines += [",".join(repr(v) if isinstance(v, float) else str(v) for v in r) for r in rows]
    return "\n".join(lines) + "\n"


def write_fit(outcome: FitOutcome, out: Path, plot: bool = True) -> Path:
    """Write ``out`` whole (staging folder, then swapped in): fit.json, fit.md, residuals.csv and, with ``plot``,
    each figure as PNG and PDF."""
    s = outcome.summary
    files = {"fit.json": json.dumps(s, indent=2, ensure_ascii=False, allow_nan=False) + "\n",
             "fit.md": fit_markdown(s), "residuals.csv": _csv(outcome.residual_headers, outcome.residual_rows)}
    out.parent.mkdir(parents=True, exist_ok=True)
    return write_folder(out, files, outcome.figures if plot else ())
