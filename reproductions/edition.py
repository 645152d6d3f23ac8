"""The reader's edition of a results folder: ``index.html`` (self-contained, figures beside it) and ``report.pdf``
(``edition_pdf``), both rendered from one ``Edition`` built here from the summaries, beside the index and the
paper table of ``report``. The findings come from the configs' ``findings:`` lists (carried by summary.json)."""

from __future__ import annotations

import ast
import functools
import html
import re
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from . import __version__
from .config import FINDINGS, MEASUREMENT_VERDICTS, REASONS
from .edition_model import Edition, FigureEntry, FindingEntry, MeasurementEntry, Rich, RowEntry, SectionEntry, Span
from .report import (
    VERDICTS,
    _atomic_text,
    _atomic_write,
    _fmt,
    _summaries,
    beyond_counts,
    computed_text,
    difference_text,
    index_md,
    interval_text,
    measurement_counts,
    paper_rows,
    paper_table_csv,
    paper_table_md,
    paper_table_tex,
    parse_source,
    printed_text,
    signals_deferred,
    today_value,
    tolerance_text,
    verdict_counts,
    whose_error,
)

__all__ = ["build", "function_of", "index_html", "plain", "readable", "rich_html", "write_index"]

_EXPERIMENTS = Path(__file__).resolve().parent / "experiments"
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
# a finding's category, short (its badge; the long words of config.FINDINGS are its title) and its badge's colours
CATEGORY = {"erratum": ("slip of 1883", "differs"), "formula": ("formula wrong", "formula"),
            "premise": ("premise fails", "premise"), "beyond": ("not in the paper", "beyond"),
            "holds": ("Résal right", "reproduced"), "measured": ("measured today", "beyond")}
VERDICT_LABEL = {"reproduced": "reproduced", "differs": "differs", "not-checkable": "not checkable",
                 "consistent": "consistent", "inconsistent": "inconsistent", "fitted": "fitted"}
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


# -- HTML -------------------------------------------------------------------------------------------------------
def _h(text: str) -> str:
    return html.escape(text, quote=True)


def rich_html(rich: Rich) -> str:
    """Spans as HTML: sub, sup, em and code elements, the text escaped."""
    tags = {"sub": "sub", "sup": "sup", "em": "em", "code": "code"}
    return "".join(f"<{tags[s.style]}>{_h(s.text)}</{tags[s.style]}>" if s.style in tags else _h(s.text)
                   for s in rich)


_CSS = """
:root{--fg:#1a1a1a;--muted:#4a4a4a;--line:#d0d0d0;--bg:#ffffff;--ok:#0b5d1e;--okbg:#e3f1e6;--bad:#9b1c1c;
--badbg:#fbe7e7;--na:#6b4e00;--nabg:#fbf1d6;--link:#0b4f9c}
*{box-sizing:border-box}
html{-webkit-text-size-adjust:100%}
body{margin:0 auto;max-width:62rem;padding:0 1rem 4rem;font:16px/1.5 Georgia,"DejaVu Serif",serif;color:var(--fg);
background:var(--bg);overflow-wrap:anywhere}
h1,h2,h3,h4{font-family:system-ui,"DejaVu Sans",sans-serif;line-height:1.25}
h1{font-size:1.7rem;margin:1.5rem 0 .3rem}
h2{font-size:1.35rem;margin:2.5rem 0 .5rem;border-top:2px solid var(--fg);padding-top:.6rem}
h3{font-size:1.05rem;margin:1.2rem 0 .4rem}
a{color:var(--link)}
.sub{color:var(--muted);margin:.2rem 0 1rem}
.counts{font-family:system-ui,"DejaVu Sans",sans-serif}
.badge{display:inline-block;padding:0 .45em;border-radius:.3em;font:600 .85rem/1.6 system-ui,"DejaVu Sans",sans-serif;
white-space:nowrap}
.reproduced{color:var(--ok);background:var(--okbg)}
.differs{color:var(--bad);background:var(--badbg)}
.not-checkable{color:var(--na);background:var(--nabg)}
.cat{color:#fff;background:#3b3b3b}
.beyond{color:#0b3d6b;background:#e2ecf7}
ol.findings{padding-left:1.4rem}
ol.findings li{margin:.2rem 0 .9rem}
.evidence{font-size:.9rem;color:var(--muted)}
nav ul{columns:2 16rem;padding-left:1.2rem}
figure{margin:1rem 0;border:1px solid var(--line);padding:.5rem}
figure img{display:block;max-width:100%;height:auto}
figcaption{font-size:.92rem;color:var(--muted);margin-top:.4rem}
.question{font-style:italic}
.filters{display:flex;flex-wrap:wrap;gap:.5rem 1rem;align-items:end;background:#f4f4f4;padding:.6rem;margin:1rem 0;
font-family:system-ui,"DejaVu Sans",sans-serif;position:sticky;top:0;z-index:1}
.filters[hidden],.none[hidden]{display:none}
.filters label{display:flex;flex-direction:column;font-size:.85rem}
.filters select{font-size:1rem;max-width:100%}
article.row{border:1px solid var(--line);border-left:5px solid var(--line);padding:.4rem .7rem;margin:.6rem 0}
article.row.v-reproduced{border-left-color:var(--ok)}
article.row.v-differs{border-left-color:var(--bad)}
article.row.v-not-checkable{border-left-color:var(--na)}
article.row[hidden],figure[hidden],.rows-heading[hidden]{display:none}
.consistent{color:var(--ok);background:var(--okbg)}
.inconsistent{color:var(--bad);background:var(--badbg)}
.fitted{color:#0b3d6b;background:#e2ecf7}
article.measure{border:1px solid var(--line);border-left:5px solid var(--line);padding:.4rem .7rem;margin:.6rem 0}
article.measure.v-consistent{border-left-color:var(--ok)}
article.measure.v-inconsistent{border-left-color:var(--bad)}
article.measure.v-fitted{border-left-color:#0b3d6b}
article.measure.v-not-checkable{border-left-color:var(--na)}
article.row,article.measure,section.experiment,section.measured-experiment,#measured,#findings li{
scroll-margin-top:8rem}
.rank{font:600 .8rem/1 system-ui,"DejaVu Sans",sans-serif;color:var(--muted);white-space:nowrap}
.premise{color:#4b2173;background:#efe6f7}
.formula{color:#7a3300;background:#fbe9dc}
dl.glossary{font-size:.92rem}
article.row h4{margin:.1rem 0 .3rem;font-size:1rem}
dl{display:grid;grid-template-columns:minmax(6rem,9rem) 1fr;gap:.1rem .8rem;margin:0}
dt{font:600 .85rem/1.7 system-ui,"DejaVu Sans",sans-serif;color:var(--muted)}
dd{margin:0}
code{font-size:.85em;overflow-wrap:anywhere}
.printed{font-style:italic}
@media (max-width:30rem){dl{grid-template-columns:1fr}dt{margin-top:.3rem}body{padding:0 .6rem 3rem}
.filters{position:static}article.row,article.measure,section.experiment,section.measured-experiment,#measured,
#findings li{scroll-margin-top:1rem}}
@media print{.filters{display:none}article.row{break-inside:avoid}}
"""

_JS = """
(function(){
  var box=document.getElementById('filters');box.hidden=false;
  var sel={verdict:document.getElementById('f-verdict'),reason:document.getElementById('f-reason'),
           section:document.getElementById('f-section')};
  var rows=document.querySelectorAll('article.row');var shown=document.getElementById('f-shown');
  function apply(){var n=0;
    rows.forEach(function(r){var ok=true;
      for(var k in sel){var v=sel[k].value;if(v&&r.dataset[k]!==v){ok=false;}}
      r.hidden=!ok;if(ok){n++;}});
    document.querySelectorAll('section.experiment').forEach(function(s){
      var any=!!s.querySelector('article.row:not([hidden])');s.querySelector('.none').hidden=any;
      s.querySelectorAll('figure, .rows-heading').forEach(function(e){e.hidden=!any;});});
    shown.textContent=n+' of '+rows.length+' rows shown';}
  for(var k in sel){sel[k].addEventListener('change',apply);}
  document.addEventListener('click',function(e){
    var a=e.target.closest('a[href^="#"]');if(!a){return;}
    var t=document.getElementById(decodeURIComponent(a.getAttribute('href').slice(1)));
    if(t&&t.closest('[hidden]')){for(var k in sel){sel[k].value='';}apply();}});
  apply();
})();
"""


def _roman(section: str) -> tuple[int, str]:
    """§IV → 4: the order of the paper's sections (anything else after them)."""
    values = {"I": 1, "V": 5, "X": 10, "L": 50, "C": 100}
    digits = [values.get(c, 0) for c in section.lstrip("§")]
    if not digits or 0 in digits:
        return (10 ** 6, section)
    return (sum(-d if i + 1 < len(digits) and d < digits[i + 1] else d for i, d in enumerate(digits)), section)


def _options(name: str, label: str, values: list[tuple[str, str]]) -> str:
    opts = "".join(f'<option value="{_h(v)}">{_h(t)}</option>' for v, t in values)
    return (f'<label for="f-{name}">{_h(label)}<select id="f-{name}"><option value="">all</option>{opts}</select>'
            "</label>")


def _row_html(r: RowEntry) -> str:
    verdict = f'<span class="badge {r.verdict}">{VERDICT_LABEL[r.verdict]}</span>'
    reason = f' <span class="badge cat" title="{_h(r.reason_label)}">{_h(r.reason)}</span>' if r.reason else ""
    where = r.section + (f", {r.equation}" if r.equation else "") + (
        f", line {r.paper_line}" if r.paper_line else "")
    items = [("claim", rich_html(r.quantity)), ("printed", f'<span class="printed">{rich_html(r.printed)}</span>'),
             ("computed", _h(r.computed)), ("difference", _h(r.difference)),
             ("tolerance", _h(r.tolerance) + (f" — {_h(r.tolerance_rule)}" if r.tolerance_rule else "")),
             ("verdict", verdict + reason + (f" — {_h(r.reason_label)}" if r.reason_label else "")),
             ("note", rich_html(r.note))]
    if r.today:
        items.append(("today", _h(r.today)))
    items.append(("defined in", f"<code>{_h(r.config)}</code>; computed by <code>{_h(r.function)}</code>"))
    dl = "".join(f"<dt>{k}</dt><dd>{v}</dd>" for k, v in items)
    return (f'<article class="row v-{r.verdict}" id="{_h(r.anchor)}" data-verdict="{r.verdict}" '
            f'data-reason="{_h(r.reason or "none")}" data-section="{_h(r.section.split(" ")[0])}">'
            f"<h4>{_h(r.id)} <span class=\"sub\">({_h(where)})</span> {verdict}{reason}</h4><dl>{dl}</dl></article>")


def _measure_html(m: MeasurementEntry) -> str:
    verdict = f'<span class="badge {m.verdict}">{VERDICT_LABEL[m.verdict]}</span>'
    items = [("measured", rich_html(m.quantity)), ("published", _h(m.measured) + f" — {_h(m.source)}"),
             ("uncertainty", _h(m.uncertainty)), ("predicted", _h(m.predicted) + (
                 f", 95 % interval {_h(m.interval)}" if m.interval != "—" else "")),
             ("verdict", verdict), ("how", rich_html(m.note)),
             ("defined in", f"<code>{_h(m.config)}</code>; computed by <code>{_h(m.function)}</code>")]
    dl = "".join(f"<dt>{k}</dt><dd>{v}</dd>" for k, v in items)
    return (f'<article class="measure v-{m.verdict}" id="{_h(m.anchor)}" data-verdict="{m.verdict}">'
            f"<h4>{_h(m.id)} {verdict}</h4><dl>{dl}</dl></article>")


def _evidence(anchor: str, r: RowEntry | MeasurementEntry | None) -> str:
    """A finding's row: its link, and what it found (printed → computed, or measured → predicted; verdict)."""
    if r is None:
        return f'<a href="#{_h(anchor)}">{_h(anchor)}</a>'
    if isinstance(r, MeasurementEntry):
        return (f'<a href="#{_h(anchor)}">{_h(r.id)}</a> (measured {_h(r.measured)}, predicted {_h(r.predicted)}'
                f'{" " + _h(r.interval) if r.interval != "—" else ""}, {VERDICT_LABEL[r.verdict]})')
    found = (f"printed {_h(r.printed_value)}, computed {_h(r.computed)}" if r.printed_value != "—" else
             _h(r.computed) if r.computed != "—" else "")
    return (f'<a href="#{_h(anchor)}">{_h(r.id)}</a> ({found + ", " if found else ""}'
            f'{VERDICT_LABEL[r.verdict]}{" · " + _h(r.reason) if r.reason else ""})')


def _figure_html(f: FigureEntry) -> str:
    vector = f' (<a href="{_h(f.pdf)}">PDF</a>)' if f.pdf else ""
    return (f'<figure><a href="{_h(f.png)}"><img src="{_h(f.png)}" alt="{_h(f.alt)}"></a>'
            f"<figcaption><strong>{_h(f.title)}.</strong> {_h(f.caption)}{vector}</figcaption></figure>")


def _counts_html(counts: dict[str, int], verdicts: tuple[str, ...] = VERDICTS) -> str:
    return ", ".join(f'<span class="badge {v}">{counts.get(v, 0)} {VERDICT_LABEL[v]}</span>' for v in verdicts)


_MEASURED_INTRO = ("Published measurements of billiard balls, each against what the paper's mechanics predict "
                   "(§I's law of impact, §V–§VI's friction during the impact, §II's sliding on the cloth), with "
                   "the measurement's uncertainty and the prediction's 95 % interval. These rows judge the 1883 "
                   "theory, not a printed claim: their verdicts, consistent or inconsistent at 95 % (fitted where "
                   "the measurement fixed a parameter), are counted apart from the printed claims above.")


def _section_head(s: SectionEntry, cls: str, counts: str) -> list[str]:
    """An experiment's section up to its rows: title, source and counts, question, notes, figures."""
    out = [f'<section class="{cls}" id="exp-{_h(s.experiment)}"><h2>{_h(s.title)}</h2>',
           f'<p class="sub">{_h(s.source)} · <code>{_h(s.experiment)}</code> · {counts} · '
           f'files: <a href="{_h(s.folder)}/table.md">table.md</a>, '
           f'<a href="{_h(s.folder)}/summary.json">summary.json</a></p>']
    if s.question:
        out.append(f'<p class="question">{rich_html(s.question)}</p>')
    out += [f"<p>{rich_html(n)}</p>" for n in s.notes]
    return out + [_figure_html(f) for f in s.figures]


def _measured_part(ed: Edition) -> list[str]:
    """The 1883 theory against today's measurements: after the paper's experiments, its own counts."""
    if not ed.measured_sections:
        return []
    n = sum(ed.measurement_counts.values())
    out = [f'<section id="measured" class="measured-part"><h2>The 1883 theory against today\'s measurements</h2>'
           f"<p>{_h(_MEASURED_INTRO)}</p><p class=\"counts\">{n} measurements: "
           f"{_counts_html(ed.measurement_counts, MEASUREMENT_VERDICTS)}.</p></section>\n"]
    for s in ed.measured_sections:
        out += _section_head(s, "measured-experiment", _counts_html(s.measurement_counts, MEASUREMENT_VERDICTS))
        out.append(f"<h3>Its {len(s.measurements)} measurements</h3>")
        out += [_measure_html(m) for m in s.measurements]
        if s.rows:
            out.append(f"<h3>Its {len(s.rows)} printed claims</h3>")
            out += [_row_html(r) for r in s.rows]
        out.append("</section>\n")
    return out


# the words and symbols a reader meets in the rows (the paper's notation, §I)
SYMBOLS = (
    ("vis viva", "m v², the “living force” of the period: twice the kinetic energy"),
    ("ε, ε′", "Résal's energy-loss coefficients of the two bodies (§I): the vis viva lost in an impact is "
              "governed by them; ε = 0 loses nothing in the restitution, ε = 1 is a plastic impact"),
    ("e", "Newton's coefficient of restitution; for a ball on a fixed body e = (1 − ε)/(1 + ε) (eq. (9))"),
    ("ν", "the normal-velocity yield: the normal velocity after an impact over the one before (§III–IV)"),
    ("f", "the coefficient of friction between the bodies in contact (ball–cloth, ball–cushion, ball–ball)"),
    ("k", "a ball's moment of inertia is M R²/k: k = 5/2 for a homogeneous sphere"),
    ("discrepancy", "for a printed formula: its largest difference from the exact mechanics (a direct numerical "
                    "integration), in the units the row's note gives; within its tolerance the formula holds"),
)


def _glossary(ed: Edition) -> str:
    verdicts = (("reproduced", "what resal computes from the paper's premises agrees with the printed value within "
                               "its printed digits (or the formula within its tolerance)"),
                ("differs", "it does not; the reason says why"),
                ("not-checkable", "nothing can be computed or compared (a measurement the paper reports, a claim "
                                  "without a number)"))
    items = [f'<dt><span class="badge {v}">{VERDICT_LABEL[v]}</span></dt><dd>{_h(t)}</dd>' for v, t in verdicts]
    items += [f'<dt><span class="badge cat">{_h(k)}</span></dt><dd>{_h(v)}</dd>' for k, v in REASONS.items()
              if k in ed.reasons]
    if ed.measured_sections:  # the verdicts of a measurement against the mechanics, their own words
        items += [f'<dt><span class="badge {v}">{VERDICT_LABEL[v]}</span></dt><dd>{_h(t)}</dd>' for v, t in (
            ("consistent", "a published measurement and the paper's prediction agree at 95 % (the measurement's "
                           "uncertainty and the prediction's interval both counted)"),
            ("inconsistent", "they do not: the paper's mechanics do not describe the measurement"),
            ("fitted", "the measurement fixed a parameter of the prediction, so it tests nothing"))]
    items += [f"<dt>{_h(k)}</dt><dd>{_h(v)}</dd>" for k, v in SYMBOLS]
    return ('<section id="reading"><h2>How to read the rows</h2><p>Each row is one printed value or claim of the '
            "paper: the claim in words, the text as printed, what resal computes, their difference and the tolerance "
            "it is judged with, the verdict and, for a row that differs, its reason. The words:</p>"
            f'<dl class="glossary">{"".join(items)}</dl></section>\n')


def index_html(ed: Edition) -> str:
    """The reader's edition as one HTML page: styles and script inline, figures linked beside it."""
    total = sum(ed.counts.values())
    anchors: dict[str, RowEntry | MeasurementEntry] = {
        r.anchor: r for s in (*ed.sections, *ed.measured_sections) for r in s.rows}
    anchors |= {m.anchor: m for s in ed.measured_sections for m in s.measurements}
    out = ['<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n',
           '<meta name="viewport" content="width=device-width, initial-scale=1">\n',
           f"<title>{_h(ed.title)}</title>\n<style>{_CSS}</style>\n</head>\n<body>\n",
           f"<header><h1>{_h(ed.title)}</h1><p class=\"sub\">{_h(ed.subtitle)}.</p>",
           f'<p class="counts">{total} printed values and claims, graded where the paper applies them: '
           f"{_counts_html(ed.counts)}"
           + (" (of the claims that differ: " + "; ".join(f"{n} {_h(label)}" for label, n, _ in ed.whose_error)
              + ")" if ed.whose_error else "")
           + (f"; {sum(ed.beyond_counts.values())} more rows beyond the paper's domain, counted apart: "
              f"{_counts_html(ed.beyond_counts)}" if sum(ed.beyond_counts.values()) else "")
           + (f'; and, <a href="#measured">apart</a>, {sum(ed.measurement_counts.values())} of today\'s '
              f"measurements against the paper's mechanics: "
              f"{_counts_html(ed.measurement_counts, MEASUREMENT_VERDICTS)}" if ed.measured_sections else "")
           + '. Tables: '
           '<a href="paper-table.csv">paper-table.csv</a> · <a href="paper-table.md">paper-table.md</a> · '
           '<a href="report.pdf">report.pdf</a> (this edition on paper).</p></header>\n<main>\n',
           '<section id="findings"><h2>What Résal got right and wrong</h2>',
           "<p>The findings that matter, most consequential first. Each names the rows (and the figure) that carry "
           "it; the rows below give the printed text, the computed value and the reason.</p>",
           '<ol class="findings">']
    for f in ed.findings:
        ev = "; ".join(_evidence(a, anchors.get(a)) for a in f.rows)
        fig = f' · figure <a href="{_h(f.figure)}">{_h(Path(f.figure).name)}</a>' if f.figure else ""
        short, style = CATEGORY.get(f.category, (f.category, "cat"))
        out.append(f'<li><span class="badge {style}" title="{_h(f.category_label)}">{_h(short)}</span> '
                   f'<span class="rank">consequence {f.consequence}/5</span> {rich_html(f.text)} '
                   f'<span class="evidence">({_h(f.experiment)}: {ev}{fig})</span></li>')
    out.append("</ol></section>\n")
    out.append('<nav aria-label="Experiments"><h2>The experiments, in the paper\'s order</h2><ul>')
    out += [f'<li><a href="#exp-{_h(s.experiment)}">{_h(s.title)}</a> ({_h(s.source)})</li>' for s in ed.sections]
    out.append("</ul>")
    if ed.measured_sections:
        out.append('<h3><a href="#measured">The 1883 theory against today\'s measurements</a></h3><ul>')
        out += [f'<li><a href="#exp-{_h(s.experiment)}">{_h(s.title)}</a> ({_h(s.source)})</li>'
                for s in ed.measured_sections]
        out.append("</ul>")
    out.append("</nav>\n")
    out.append(_glossary(ed))
    reasons = sorted({r.reason for s in ed.sections for r in s.rows if r.reason})
    sections = sorted({r.section.split(" ")[0] for s in ed.sections for r in s.rows}, key=_roman)
    out.append('<div class="filters" id="filters" hidden role="search">'
               + _options("verdict", "verdict", [(v, VERDICT_LABEL[v]) for v in VERDICTS])
               + _options("reason", "reason", [("none", "none (no reason given)"), *((r, r) for r in reasons)])
               + _options("section", "section of the paper", [(x, x) for x in sections])
               + '<span id="f-shown" aria-live="polite"></span></div>\n')
    for s in ed.sections:
        out += _section_head(s, "experiment", _counts_html(s.counts))
        out.append(f'<h3 class="rows-heading">Its {len(s.rows)} rows</h3>')
        out += [_row_html(r) for r in s.rows]
        out.append('<p class="none" hidden>No row of this experiment matches the filters.</p></section>\n')
    out += _measured_part(ed)
    out.append(f'</main>\n<footer><p class="sub">{_h(ed.provenance)}.</p></footer>\n')
    out.append(f"<script>{_JS}</script>\n</body>\n</html>\n")
    return "".join(out)


# -- writing a results folder's whole-paper files ----------------------------------------------------------------
def write_index(out: Path, skipped: list[tuple[Path, str]] | None = None) -> Path:
    """``out/index.md`` and ``out/paper-table.{md,csv,tex}`` (``report``), the reader's edition ``out/index.html``
    and ``out/report.pdf`` from the summaries found under ``out``, each written whole and renamed into place.
    ``skipped`` receives the summaries left out (not resal's, or changed by hand: ``report.summary_problem``)."""
    from .edition_pdf import write_pdf  # matplotlib: imported only when a report is written

    summaries = _summaries(out, skipped)
    rows = paper_rows(summaries)
    path = out / "index.md"
    _atomic_text(path, index_md(summaries))
    _atomic_text(out / "paper-table.md", paper_table_md(rows))
    _atomic_text(out / "paper-table.csv", paper_table_csv(rows))
    _atomic_text(out / "paper-table.tex", paper_table_tex(rows))
    ed = build(summaries)
    _atomic_text(out / "index.html", index_html(ed))
    with signals_deferred():  # a signal waits for the PDF writer (matplotlib) to finish, then ends the run
        _atomic_write(out / "report.pdf", lambda fh: write_pdf(ed, out, fh))
    return path
