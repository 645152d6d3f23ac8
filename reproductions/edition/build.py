"""The edition as data: ``build`` turns a results folder's summaries into an ``Edition`` (``model``); ``readable``
turns a formula or a note into the spans a reader recognises; ``function_of`` names the function that computes a
row. No HTML and no Typst here."""

from __future__ import annotations

import ast
import functools
import re
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from .. import __version__
from ..config import FINDINGS, REASONS
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
from .model import Edition, FigureEntry, FindingEntry, MeasurementEntry, Rich, RowEntry, SectionEntry, Span

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
_LATEX = {r"\alpha": "α", r"\beta": "β", r"\gamma": "γ", r"\delta": "δ", r"\epsilon": "ε", r"\varepsilon": "ε",
          r"\zeta": "ζ", r"\eta": "η", r"\theta": "θ", r"\lambda": "λ", r"\mu": "μ", r"\nu": "ν", r"\xi": "ξ",
          r"\pi": "π", r"\rho": "ρ", r"\sigma": "σ", r"\tau": "τ", r"\phi": "φ", r"\varphi": "φ", r"\chi": "χ",
          r"\psi": "ψ", r"\omega": "ω", r"\Delta": "Δ", r"\Omega": "Ω", r"\cdot": "·", r"\times": "×",
          r"\sqrt": "√", r"\int": "∫", r"\pm": "±", r"\mp": "∓", r"\leq": "≤", r"\geq": "≥", r"\le": "≤",
          r"\ge": "≥", r"\infty": "∞", r"\prime": "′", r"\left": "", r"\right": "", r"\,": " ", r"\;": " "}
_LETTER = re.compile(r"[A-Za-zα-ωΑ-Ω]")


# -- formulas as a reader writes them ---------------------------------------------------------------------------
def _group(text: str, i: int) -> tuple[str, int]:
    """The script that starts at ``text[i]``: a balanced {…} or (…) (without its brackets), else a run of up to
    three letters, digits and primes. Returns (content, index after it); ("", i) when there is none."""
    if i >= len(text):
        return "", i
    if text[i] in "{(":
        close = "}" if text[i] == "{" else ")"
        depth = 0
        for j in range(i, len(text)):
            depth += text[j] == text[i]
            depth -= text[j] == close
            if depth == 0:
                return text[i + 1:j], j + 1
        return "", i
    m = re.match(r"[A-Za-z0-9α-ωΑ-Ω½′]{1,3}", text[i:])
    return (m.group(0), i + m.end()) if m else ("", i)


def _script_allowed(text: str, i: int) -> bool:
    """Whether the ``_`` at ``i`` starts a subscript: after ∫, or after a symbol of one or two letters (v_y, dx_i),
    never inside an identifier such as eq9_beyond or f_today."""
    if i > 0 and text[i - 1] == "∫":
        return True
    j = i
    while j > 0 and text[j - 1] in "′″":
        j -= 1
    k = j
    while k > 0 and _LETTER.match(text[k - 1]):
        k -= 1
    if not 1 <= j - k <= 2 or (k > 0 and (text[k - 1].isalnum() or text[k - 1] == "_")):
        return False
    content, end = _group(text, i + 1)
    return bool(content) and (end >= len(text) or not (text[end].isalnum() or text[end] == "_"))


def readable(text: str | None) -> Rich:
    """A formula or a note as spans a reader recognises: LaTeX commands as Unicode, ``x_i``, ``x_{…}``, ``x^(…)``
    and ``x^{…}`` as sub- and superscripts, ``$`` dropped. Text without them comes back as one span."""
    s = text or ""
    if "\\" in s:
        for cmd in sorted(_LATEX, key=len, reverse=True):
            s = re.sub(re.escape(cmd) + r"(?![A-Za-z])", _LATEX[cmd], s)
    s = s.replace("$", "")
    spans: list[Span] = []
    buf: list[str] = []
    i = 0
    while i < len(s):
        ch = s[i]
        if ch in "_^" and (ch == "^" or _script_allowed(s, i)):
            content, end = _group(s, i + 1)
            if content:
                if buf:
                    spans.append(Span("".join(buf)))
                    buf = []
                spans.append(Span(content, "sub" if ch == "_" else "sup"))
                i = end
                continue
        buf.append(ch)
        i += 1
    if buf:
        spans.append(Span("".join(buf)))
    return tuple(x for sp in spans for x in (_indices(sp.text) if not sp.style else (sp,)))


# a one-letter symbol (primes allowed) with a one- or two-digit index, as the digitised text writes φ₀ or V₁: φ0,
# τ′0, V1, nφ0, n0R, φ0², 2V′0; never inside a word or a number (eq9, 1e-12, 2e5, V1p, f_today)
_INDEX = re.compile(r"([A-Za-zα-ωΑ-Ω])([′″]*)(\d{1,2})")
_GREEK = re.compile(r"[α-ωΑ-Ω]")


def _is_index(text: str, m: re.Match) -> bool:
    sym, primes = m.group(1), m.group(2)
    before = text[m.start() - 1] if m.start() else " "
    after = text[m.end()] if m.end() < len(text) else " "
    if _GREEK.match(sym):
        ok_before = not (_GREEK.match(before) or before in "_.")
    else:
        ok_before = not (before.isalpha() or before in "_." or (before.isdigit() and not primes))
    ok_after = (not (after.isalnum() or after == "_") or after in "²³"
                or (after.isupper() and after.isascii() and (sym.islower() or _GREEK.match(sym) is not None)))
    return ok_before and ok_after


def _indices(text: str) -> tuple[Span, ...]:
    out: list[Span] = []
    at = 0
    for m in _INDEX.finditer(text):
        if not _is_index(text, m):
            continue
        out.append(Span(text[at:m.end(2)]))
        out.append(Span(m.group(3), "sub"))
        at = m.end()
    out.append(Span(text[at:]))
    merged: list[Span] = []
    for sp in out:
        if sp.text:
            merged.append(sp)
    return tuple(merged)


def plain(rich: Rich) -> str:
    """The text of spans, scripts written back with _ and ^ (for a title attribute or a search)."""
    out = []
    for s in rich:
        if s.style in ("sub", "sup"):
            out.append(("_" if s.style == "sub" else "^") + (s.text if len(s.text) == 1 else f"({s.text})"))
        else:
            out.append(s.text)
    return "".join(out)


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
        function=function_of(s["kind"], computed_key))


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
            measurements=measured, measurement_counts=measurement_counts([s])))
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
    return Edition(
        title="Résal (1883) checked claim by claim",
        subtitle=("H. Résal, “Commentaire à la théorie mathématique du jeu de billard”, J. Math. Pures Appl. "
                  "(3) 9 (1883), 65–98: every printed value and claim, recomputed from the paper's own premises"),
        counts=counts, reasons=reasons, findings=tuple(findings), sections=tuple(sections),
        beyond_counts=beyond_counts(all_rows), whose_error=tuple(whose_error(reasons)),
        measured_sections=tuple(measured_sections), measurement_counts=measurement_counts(s for _, s in summaries),
        provenance=f"resal {prov.get('version', __version__)}" + (f", commit {commit[:12]}" if commit else "")
        + (" (uncommitted changes)" if prov.get("dirty") else ""))


