"""The edition as data: ``build`` turns a results folder's summaries into an ``Edition`` (``model``); ``readable``
turns a formula or a note into the spans a reader recognises; ``function_of`` names the function that computes a
row. No HTML and no Typst here."""

from __future__ import annotations

import ast
import functools
import math
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from .. import __version__
from ..config import FINDINGS, REASON_GROUP_LABELS, REASON_GROUPS, REASONS
from ..report import (
    _fmt,
    beyond_counts,
    computed_text,
    difference_text,
    interval_text,
    measurement_counts,
    parse_source,
    printed_text,
    today_value,
    tolerance_text,
    verdict_counts,
    whose_error,
)
from .formula import plain_number, segments
from .model import Edition, ErrorKind, FigureEntry, FindingEntry, MeasurementEntry, Rich, RowEntry, SectionEntry

__all__ = ["build", "function_of", "plain", "readable"]

_EXPERIMENTS = Path(__file__).resolve().parent.parent / "experiments"
@functools.cache
def _kind_modules() -> dict[str, str]:
    """Kind → the name of its module, read off ``experiments/__init__.py``'s ``KINDS`` table (without importing the
    physics): ``"spheres": ballball``."""
    tree = ast.parse((_EXPERIMENTS / "__init__.py").read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, (ast.Assign, ast.AnnAssign)) and isinstance(node.value, ast.Dict):
            target = node.targets[0] if isinstance(node, ast.Assign) else node.target
            if isinstance(target, ast.Name) and target.id == "KINDS":
                return {k.value: v.id for k, v in zip(node.value.keys, node.value.values, strict=True)
                        if isinstance(k, ast.Constant) and isinstance(v, ast.Name)}
    return {}
def readable(text: str | None) -> Rich:
    """A text of a config or a summary as the edition shows it: prose, and its formulas as LaTeX (``formula``)."""
    return segments(text)


def plain(rich: Rich) -> str:
    """The text of spans, a formula as its LaTeX (for a title attribute or a search)."""
    return "".join(s.text for s in rich)


# -- where a row is defined and computed -------------------------------------------------------------------------
@functools.cache
def _functions(kind: str) -> dict[str, str]:
    """Quantity key → the innermost function of the kind's module that sets it: a dict key, ``x["key"] = …``,
    ``put("key", …)``; an f-string key (``f"nu.{s.id}"``) counts for its constant prefix, written ``nu.*``."""
    module = _kind_modules().get(kind, kind)
    path = _EXPERIMENTS / f"{module}.py"
    if not path.is_file():
        return {}
    found: dict[str, tuple[int, str]] = {}

    def key_of(k: ast.AST) -> str | None:
        if isinstance(k, ast.Constant) and isinstance(k.value, str):
            return k.value
        if isinstance(k, ast.JoinedStr) and k.values and isinstance(k.values[0], ast.Constant):
            return f"{k.values[0].value}*"
        return None

    def visit(node: ast.AST, stack: tuple[str, ...]) -> None:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            stack = (*stack, node.name)
        keys: list[ast.AST] = []
        if isinstance(node, ast.Dict):
            keys = [k for k in node.keys if k is not None]
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            keys = [t.slice for t in targets if isinstance(t, ast.Subscript)]
        elif isinstance(node, ast.Call) and node.args:
            keys = [node.args[0]]
        for k in keys:
            key = key_of(k)
            if stack and key:
                depth = len(stack)
                if key not in found or depth > found[key][0]:
                    found[key] = (depth, stack[-1])
        for child in ast.iter_child_nodes(node):
            visit(child, stack)

    visit(ast.parse(path.read_text(encoding="utf-8")), ())
    return {k: f"reproductions.experiments.{module}.{name}" for k, (_, name) in found.items()}


def function_of(kind: str, quantity: str) -> str:
    """The function that computes a quantity of a kind, read off its module's source (``run`` when none names it)."""
    module = _kind_modules().get(kind, kind)
    table = _functions(kind)
    if quantity in table:
        return table[quantity]
    prefixes = [k for k in table if k.endswith("*") and quantity.startswith(k[:-1])]
    if prefixes:
        return table[max(prefixes, key=len)]
    return f"reproductions.experiments.{module}.run"


# -- the edition as data ----------------------------------------------------------------------------------------
def _config_name(s: dict[str, Any]) -> str:
    cfg = (s.get("provenance") or {}).get("config") or f"{s['experiment']}.yaml"
    return f"configs/{Path(cfg).name}"


def _row(name: str, s: dict[str, Any], r: dict[str, Any], computed_key: str) -> RowEntry:
    section, n, eq = parse_source(r.get("source"))
    reason = r.get("reason") or ""
    cfg = _config_name(s)
    return RowEntry(
        experiment=s["experiment"], id=r["id"], anchor=f"{s['experiment']}--{r['id']}",
        section=f"{section} n°{n}" if n else section, equation=eq, paper_line=r.get("line"),
        quantity=readable(r["quantity"]), printed=readable(printed_text(r)), printed_value=_fmt(r["printed"]),
        computed=computed_text(r), difference=difference_text(r), tolerance=tolerance_text(r),
        tolerance_rule=r.get("tolerance_rule") or "", verdict=r["verdict"], reason=reason,
        reason_label=REASONS.get(reason, ""), note=readable(r["note"]),
        today=today_value(r.get("today"), s.get("modern", ())),
        config=f"{cfg}:{r['config_line']}" if r.get("config_line") else cfg,
        function=function_of(s["kind"], computed_key), evidence=evidence(r),
        english=readable(r.get("english")) if r.get("english") else (), page=s["source"].get("page"))


def _number(x: float, digits: int = 3) -> str:
    """A number as a reader writes it: 0.155, 2.2 × 10⁻¹⁶ (never e-notation)."""
    return plain_number(_fmt(x, digits) if abs(x) < 1e-3 or abs(x) >= 1e5 else f"{x:.{digits}g}")


def evidence(r: dict[str, Any]) -> str:
    """What a row found, in words: "agrees to 4 digits (printed 0.155, computed 0.1550)", "holds: discrepancy
    2.2 × 10⁻¹⁶, judged within 10⁻⁹", "differs: printed 0.155, computed 0.101"."""
    printed, computed, verdict, tol = r.get("printed"), r.get("computed"), r["verdict"], r.get("tolerance")
    if verdict == "not-checkable" or computed is None:
        return "nothing to compute: " + ("a measurement the paper reports" if printed is not None else
                                         "a claim without a number")
    if printed is None:  # a formula or a claim: its discrepancy from the exact mechanics
        off = _number(computed, 2)
        bound = f", judged within {_number(tol, 2)}" if tol is not None else ""
        if verdict == "reproduced":
            return f"holds: discrepancy {off}{bound}"
        return f"differs: discrepancy {off}{bound}"
    pv, cv = _number(printed, 4), _number(computed, 4)
    if verdict == "differs":
        return f"differs: printed {pv}, computed {cv}"
    rel = r.get("rel_diff")
    if printed == 0 or rel is None:
        return f"agrees: printed {pv}, computed {cv}"
    if rel == 0:
        return f"agrees exactly: printed {pv}, computed {cv}"
    digits = max(0, math.floor(-math.log10(abs(rel))))
    return (f"agrees to {digits} digit{'s' if digits != 1 else ''}: printed {pv}, computed {cv}" if digits else
            f"agrees within its tolerance: printed {pv}, computed {cv}")


def _measurement(s: dict[str, Any], m: dict[str, Any]) -> MeasurementEntry:
    cfg = _config_name(s)
    return MeasurementEntry(
        experiment=s["experiment"], id=m["id"], anchor=f"{s['experiment']}--{m['id']}",
        quantity=readable(m["quantity"]), source=m["source"], measured=m["measured_text"] or _fmt(m["measured"]),
        uncertainty=m["uncertainty"],
        predicted=_fmt(m["predicted"]), interval=interval_text(m), verdict=m["verdict"], note=readable(m["note"]),
        config=f"{cfg}:{m['config_line']}" if m.get("config_line") else cfg,
        function=function_of(s["kind"], m.get("computes") or m["id"]))


def _figures(name: str, s: dict[str, Any]) -> tuple[FigureEntry, ...]:
    captions = {c["png"]: c for c in s.get("figure_captions", [])}
    out = []
    for f in s["figures"]:
        if not f.endswith(".png"):
            continue
        c = captions.get(f, {})
        title = c.get("title") or f
        caption = c.get("caption") or ""
        pdf = f[:-4] + ".pdf"
        out.append(FigureEntry(png=f"{name}/{f}", pdf=f"{name}/{pdf}" if pdf in s["figures"] else "", title=title,
                               caption=caption, alt=f"Figure: {title}." + (f" {caption}" if caption else "")))
    return tuple(out)


def build(summaries: Iterable[tuple[str, dict[str, Any]]]) -> Edition:
    """The edition of a results folder's summaries ((folder name, summary) in the paper's order)."""
    summaries = list(summaries)
    sections: list[SectionEntry] = []
    measured_sections: list[SectionEntry] = []  # the 1883 theory against today's measurements, after the paper
    lines: dict[str, int] = {}
    for name, s in summaries:
        rows = tuple(_row(name, s, r, r.get("computes") or r["id"]) for r in s["rows"])
        for r in s["rows"]:
            lines[f"{s['experiment']}--{r['id']}"] = r.get("line") or 10 ** 6
        page = s["source"].get("page")
        measured = tuple(_measurement(s, m) for m in s.get("measurements", ()))
        (measured_sections if measured else sections).append(SectionEntry(
            experiment=s["experiment"], title=s["title"],
            source=s["source"]["section"] + (f", p. {page}" if page else ""),
            question=readable(s.get("question") or ""), figures=_figures(name, s), rows=rows,
            counts=verdict_counts(s["rows"])[0], folder=name, notes=tuple(readable(n) for n in s.get("notes", [])),
            measurements=measured, measurement_counts=measurement_counts([s]), page=page))
    findings = []
    for name, s in summaries:
        for f in s.get("findings", []):
            fig = f"{name}/{f['figure']}.png" if f.get("figure") else None
            findings.append(FindingEntry(
                experiment=s["experiment"], id=f["id"], category=f["category"],
                category_label=FINDINGS.get(f["category"], f["category"]), consequence=int(f["consequence"]),
                text=readable(f["text"]), rows=tuple(f"{s['experiment']}--{r}" for r in f["rows"]), figure=fig))
    findings.sort(key=lambda f: (-f.consequence, min(lines.get(a, 10 ** 6) for a in f.rows), f.experiment, f.id))
    all_rows = [r for _, s in summaries for r in s["rows"]]
    counts, reasons = verdict_counts(all_rows)
    prov = next((s.get("provenance") or {} for _, s in summaries), {})
    commit = prov.get("git_commit")
    beyond = beyond_counts(all_rows)
    mcounts = measurement_counts(s for _, s in summaries)
    return Edition(
        answer=answer(counts, reasons, mcounts), error_kinds=error_kinds(reasons, beyond), history=HISTORY,
        title="Résal (1883) checked claim by claim",
        subtitle=("H. Résal, “Commentaire à la théorie mathématique du jeu de billard”, J. Math. Pures Appl. "
                  "(3) 9 (1883), 65–98: every printed value and claim, recomputed from the paper's own premises"),
        counts=counts, reasons=reasons, findings=tuple(findings), sections=tuple(sections),
        beyond_counts=beyond, whose_error=tuple(whose_error(reasons)),
        measured_sections=tuple(measured_sections), measurement_counts=mcounts,
        provenance=f"resal {prov.get('version', __version__)}" + (f", commit {commit[:12]}" if commit else "")
        + (" (uncommitted changes)" if prov.get("dirty") else ""))




# the summary's table: what each kind of error means, for a reader who has not met the reason codes
MEANINGS = {
    "paper": "Résal's own slips of 1883 and formulas that cannot be right as printed (a second row grades the repair)",
    "premise": "an assumption of the paper that its own premises or the exact mechanics do not support where it is "
               "applied",
    "rounding": "printed digits that round or truncate what the premises give: no error of substance",
    "digitised": "slips of the digitised text we read, not of the 1883 original (the note gives the likely original)",
    "beyond": "claims that fail beyond the domain where the paper applies them, counted apart from the paper's own",
}


def error_kinds(reasons: dict[str, int], beyond: dict[str, int]) -> tuple[ErrorKind, ...]:
    """The summary's table: each group of ``config.REASON_GROUPS`` with its rows (the paper's claims that differ,
    by whose error; the rows beyond the paper's domain that differ, apart)."""
    out = []
    for group, codes in REASON_GROUPS.items():
        n = beyond.get("differs", 0) if group == "beyond" else sum(reasons.get(c, 0) for c in codes)
        out.append(ErrorKind(group, REASON_GROUP_LABELS[group], n, MEANINGS[group]))
    if reasons.get("none given"):
        out.append(ErrorKind("none", "no reason given yet", reasons["none given"], "differs, and no reason is given"))
    return tuple(out)


def _plural(n: int, one: str, many: str | None = None) -> str:
    return f"{n} {one if n == 1 else many or one + 's'}"


def answer(counts: dict[str, int], reasons: dict[str, int], measured: dict[str, int]) -> tuple[Rich, ...]:
    """Three sentences: what holds, what 1883 got wrong, what today's measurements say (from the counts alone)."""
    total = sum(counts.values())
    group = {g: sum(reasons.get(c, 0) for c in codes) for g, codes in REASON_GROUPS.items()}
    first = (f"Of the paper's {total} printed values and claims, {counts.get('reproduced', 0)} are reproduced from "
             f"its own premises by an independent computation, and {counts.get('not-checkable', 0)} cannot be "
             "checked (a measurement it reports, a claim without a number).")
    second = (f"Of the {counts.get('differs', 0)} that differ, {_plural(group['paper'], 'is', 'are')} Résal's own "
              f"errata or formulas that cannot be right as printed and {group['premise']} premises that fail where "
              f"he applies them; the other {group['rounding'] + group['digitised'] + reasons.get('none given', 0)} "
              f"are rounded digits ({group['rounding']}) or slips of the digitised text, not of 1883 "
              f"({group['digitised']}).")
    n = sum(measured.values())
    third = (f"Against {n} published measurements of today's balls, his mechanics are consistent with "
             f"{measured.get('consistent', 0)} and inconsistent with {measured.get('inconsistent', 0)}"
             + (f" ({measured.get('fitted', 0)} fixed a parameter and test nothing)" if measured.get("fitted") else "")
             + ".") if n else "No measurement of today's balls is in this results folder."
    return tuple(readable(x) for x in (first, second, third))


HISTORY = tuple(readable(x) for x in (
    "Gaspard-Gustave Coriolis published his Théorie mathématique des effets du jeu de billard in 1835: the first "
    "mechanics of a ball that slides, rolls and spins on the cloth, of its impacts on a cushion and on another ball, "
    "and of the cue's stroke, with coefficients he measured himself.",
    "In 1883 Henri Résal, of the Académie des sciences and editor of the Journal de mathématiques pures et appliquées, "
    "published this commentary on it (J. Math. Pures Appl. (3) 9, 65–98). He keeps Coriolis's programme but measures "
    "the loss in an impact by his own energy-loss coefficient ε in place of Coriolis's fraction of the vis viva, "
    "simplifies the demonstrations, and compares the results with numbers Coriolis measured and with the ricochet "
    "experiments of M. Rozé, who threw an ivory ball on planes of marble, glass and other bodies and measured the "
    "spacing of its imprints.",
    "This edition recomputes every value and claim it prints from its own premises, integrates the equations of "
    "motion directly to check each closed form, and sets today's published measurements beside the 1883 mechanics.",
))
