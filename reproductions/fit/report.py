"""The files of ``resal fit``: fit.json (the summary with provenance), fit.md, residuals.csv and the figures."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

from ..report import code_provenance, write_folder
from .run import FitOptions, FitOutcome

__all__ = ["fit_lines", "fit_markdown", "provenance", "write_fit"]


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


def fit_lines(s: dict[str, Any], warnings: bool = True) -> list[str]:
    """What a fit says besides its estimates, a sentence per line: method, the balls taken (ball-ball), bootstrap,
    noise model, speed dependence, goodness of fit, the paper's and today's values beside it, identifiability,
    warnings (unless the terminal prints them on stderr), columns read in SI."""
    lines = [f"method: {m}" for m in dict.fromkeys(f["method"] for f in s["fits"])]
    if s.get("balls"):
        lines.append(f"balls: {s['balls']['text']}")
    if s.get("bootstrap"):
        b = s["bootstrap"]
        ran = (f"{b['resamples']} of {b['requested']} resamples" if b.get("requested") is not None
               else f"{b['resamples']} resamples")
        lines.append(f"bootstrap: {ran} ({b['kind']}), seed {b['seed']}, {b['failed']} failed: {b['note']}")
    if s.get("noise") and "chosen_by" in s["noise"]:
        lines.append(f"noise model: {s['noise']['model']} (chosen by {s['noise']['chosen_by']})")
    lines += _verdict_lines(s)
    if s.get("speed_dependence"):
        lines.append(f"speed dependence: {s['speed_dependence']['verdict']}")
        if s["speed_dependence"].get("law"):
            lines.append(f"law: {s['speed_dependence']['law']['text']}")
    good = s.get("goodness") or {}
    if good.get("reduced_chi2") is not None:
        lines.append(f"goodness of fit: reduced χ² = {good['reduced_chi2']:.3g} (p = {good['chi2_p']:.2g})")
    if good.get("lack_of_fit"):
        lof = good["lack_of_fit"]
        lines.append(f"lack of fit (pure error, repeated speeds): F = {lof['F']:.3g}, p = {lof['p']:.2g}")
    for p in (s.get("comparison") or {}).get("paper", []):
        lines.append(f"paper (line {p['line']}): {p['claim']}: {p['value']:.4g}, {p['verdict']}")
    for m in (s.get("comparison") or {}).get("today", []):
        val = f"{m['typ']:.4g}" if m["typ"] is not None else (
            f"{m['low']:.4g}–{m['high']:.4g}" if m["low"] is not None else "law")
        lines.append(f"today: {m['quantity']} {val} ({m['source']}): {m['verdict']}")
    for i in s.get("identifiability", []):
        sv = ", ".join(f"{v:.3g}" for v in i["singular_values"])
        lines.append(f"{i['data']}: rank {i['rank']} of {len(i['parameters'])} (singular values {sv})")
    if warnings:
        lines += [f"WARNING [{w['code']}]: {w['message']}" for w in s.get("warnings", [])]
    lines += [f"column {c['column']}: {c['note']}" for c in s["columns"] if c["note"]]
    return lines


def _verdict_lines(s: dict[str, Any]) -> list[str]:
    """The tests a fit ran on its own data, as verdicts: whether its series agree (``agreement``: a likelihood
    ratio of the joint fit against each series alone, with the f intervals of each series alone, which a reader
    compares first) and whether the residuals trend with the impact angle (``residual_trend``, per series)."""
    lines = []
    agreement = s.get("agreement")
    if agreement:
        ok = agreement["p"] >= 0.05
        why = (f"p = {agreement['p']:.2g}, likelihood ratio {agreement['lr']:.3g} on {agreement['dof']} degrees of "
               "freedom")
        alone = [f["ci95"] for f in s["fits"] if f["id"].endswith(".f") and not f["id"].startswith("joint.")
                 and f["ci95"] and f["ci95"][0] is not None]
        if len(alone) == 2:
            (a0, a1), (b0, b1) = alone
            why += (f"; f intervals {_ci(alone[0])} and {_ci(alone[1])} "
                    f"{'overlap' if a0 <= b1 and b0 <= a1 else 'do not overlap'}")
        lines.append(f"series agree: {'yes' if ok else 'no'} ({why})")
    for series, t in (s.get("residual_trend") or {}).items():
        slope = f"{t['slope_per_10deg']:+.2g} ± {t['stderr_per_10deg']:.2g}° per 10°, p = {t['p']:.2g}"
        lines.append(f"residual trend against ψ ({series}): "
                     + (f"none (slope {slope})" if t["p"] >= 0.05 else f"slope {slope}: a constant friction through "
                        "the impact does not describe it"))
    return lines


def has_bootstrap(s: dict[str, Any]) -> bool:
    """Whether some estimate of the fit has a bootstrap interval (else no column for them is shown)."""
    return any(f.get("ci95_bootstrap") and f["ci95_bootstrap"][0] is not None for f in s["fits"])


def fit_markdown(s: dict[str, Any]) -> str:
    """fit.md: the estimates as a table, then ``fit_lines`` as a list."""
    out = [f"# resal fit {s['kind']}: {Path(s['file']).name} ({s['n']} rows)", ""]
    boot = has_bootstrap(s)
    out += ["| parameter | value | std. error | 95 % interval |" + (" bootstrap 95 % |" if boot else "") + " note |",
            "|---|---|---|---|" + ("---|" if boot else "") + "---|"]
    for f in s["fits"]:
        out.append(f"| {f['parameter']} | {_num(f['value'])} | {_num(f['stderr'], 3)} | {_ci(f['ci95'])} | "
                   + (f"{_ci(f.get('ci95_bootstrap'))} | " if boot else "") + f"{f['note']} |")
    out += [""] + [f"- {ln}" for ln in fit_lines(s)]
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
