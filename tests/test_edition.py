"""The reader's edition built from a results folder: formulas found in the text as LaTeX, each row's config entry
and function, printed zeros with absolute differences, the same bytes twice. (The browser's view is in
test_edition_browser.py.)"""

from __future__ import annotations

import csv
import html
import importlib
import inspect
import json
import re
import shutil
from pathlib import Path

import pytest

from reproductions import edition

ROOT = Path(__file__).resolve().parent.parent


def _formulas(text: str) -> list[str]:
    return [s.text for s in edition.readable(text) if s.style == "math"]


@pytest.mark.parametrize(("text", "latex"), [
    ("v_y = η", [r"v_{y} = \eta"]),
    ("φ0 = U/(1 + n)", [r"\varphi_{0} = U/(1 + n)"]),
    ("τ′0 = 2V′0", [r"\tau'_{0} = 2V'_{0}"]),
    ("n0²R² = 1", [r"n_{0}^{2}R^{2} = 1"]),
    ("(φ0/φ)^((1+k)/2) = 1", [r"(\varphi_{0}/\varphi)^{(1 + k)/2} = 1"]),
    ("f(χ1 − χ0) = ∫_{η0}^{η1} (v/v_y) dη", [r"f(\chi_{1} - \chi_{0}) = \int_{\eta_{0}}^{\eta_{1}} (v/v_{y}) d\eta"]),
    (r"$\varepsilon \le 1$", [r"\varepsilon \le 1"]),
    ("ε = 0,155", [r"\varepsilon = 0{,}155"]),  # the French decimal comma, as printed
    ("g = 9.81 m/s²", [r"g = 9.81 \,\mathrm{m/s}^{2}"]),
    ("v = ±φ √(1 + x)", [r"v = \pm\varphi \sqrt{1 + x}"]),
    ("off by 2.2e-16 here", [r"2.2 \times 10^{-16}"]),  # never e-notation
    ("at V = 2 m/s the ball", [r"V = 2 \,\mathrm{m/s}"]),
])
def test_formulas_are_found_and_written_as_latex(text, latex):
    """A formula inside prose becomes one LaTeX source: symbols with their indices, scripts, roots, units upright."""
    assert [re.sub(r"\s+", "", x) for x in _formulas(text)] == [re.sub(r"\s+", "", x) for x in latex]


@pytest.mark.parametrize("text", [
    "a ball of radius R", "eq9_beyond, f_today, V1p, eq. (9), n°14", "the cue ball's spin (no closed form)",
    "Coriolis measured it in 1835", "(A) the cue ball", "ODE and CSV", "ne paraît pas devoir atteindre 0,03",
])
def test_prose_is_never_a_formula(text):
    assert _formulas(text) == [] and edition.plain(edition.readable(text)) == text


def _texts(out: Path) -> list[str]:
    texts = []
    for s in _summaries(out):
        for r in s["rows"]:
            texts += [r["quantity"], r["printed_text"] or "", r["note"], r.get("english") or ""]
        texts += [f["text"] for f in s.get("findings", [])] + list(s.get("notes", [])) + [s.get("question") or ""]
        for m in s.get("measurements", []):
            texts += [m["quantity"], m["note"]]
    return [t for t in texts if t]


def _census(text: str) -> tuple[list[str], list[str]]:
    """The digits and the Greek letters of a text, in order (² and ³ count as digits)."""
    text = text.replace("²", "2").replace("³", "3").replace("½", "12")
    return re.findall(r"\d", text), re.findall(r"[α-ωΑ-Ω]", text)


def test_no_character_of_a_formula_is_lost(reproduced_all):
    """Over every text of the edition: the digits and Greek letters of the text are those of its prose and its
    formulas' LaTeX, in order (a formula that swallowed or dropped a symbol fails). Texts with e-notation, which
    becomes × 10ⁿ, are left out."""
    from reproductions.edition.formula import GREEK

    back = {v: k for k, v in GREEK.items()}
    out, _ = reproduced_all
    checked = 0
    for text in _texts(out):
        if re.search(r"\de[-+]?\d", text) or "\\" in text:
            continue
        rebuilt = []
        for sp in edition.readable(text):
            if sp.style != "math":
                rebuilt.append(sp.text)
                continue
            lx = re.sub(r"\\([A-Za-z]+)", lambda m: back.get(m.group(1), " "), sp.text.replace("{,}", ","))
            rebuilt.append(lx)
        assert _census("".join(rebuilt)) == _census(text.replace("$", "")), text
        checked += 1
    assert checked > 500


def test_every_formula_becomes_mathml_with_no_source_left(reproduced_all):
    """Every formula of the edition converts (latex2mathml), and the rendered symbols hold no LaTeX: no backslash,
    no _ or ^, and a brace only where the formula has one."""
    from reproductions.edition.formula import mathml

    out, _ = reproduced_all
    n = 0
    for text in _texts(out):
        for f in _formulas(text):
            shown = html.unescape(re.sub(r"<[^>]+>", "", re.sub(r'alttext="[^"]*"', "", mathml(f))))
            assert not re.search(r"[\\_^]", shown), (f, shown)
            assert shown.count("{") == f.count(r"\{"), (f, shown)
            n += 1
    assert n > 300


@pytest.mark.parametrize(("row", "words"), [
    ({"printed": 0.155, "computed": 0.101, "rel_diff": -0.348, "verdict": "differs", "tolerance": 0.005},
     "differs: printed 0.155, computed 0.101"),
    ({"printed": 0.5, "computed": 0.5000000000000001, "rel_diff": 2.2e-16, "verdict": "reproduced",
      "tolerance": 1e-9}, "agrees to 15 digits: printed 0.5, computed 0.5"),
    ({"printed": None, "computed": 2.2e-16, "rel_diff": None, "verdict": "reproduced", "tolerance": 1e-9},
     "holds: discrepancy 2.2 × 10⁻¹⁶, judged within 10⁻⁹"),
    ({"printed": 3.0, "computed": None, "rel_diff": None, "verdict": "not-checkable", "tolerance": None},
     "nothing to compute: a measurement the paper reports"),
])
def test_evidence_is_said_in_words(row, words):
    from reproductions.edition.build import evidence

    assert evidence(row) == words


def _summaries(out: Path) -> list[dict]:
    return [json.loads(p.read_text(encoding="utf-8")) for p in sorted(out.glob("*/summary.json"))]


def test_each_row_names_its_config_entry_and_a_function_that_computes_it(reproduced_all):
    out, _ = reproduced_all
    fallback = 0
    total = 0
    for s in _summaries(out):
        cfg = ROOT / "configs" / f"{s['experiment']}.yaml"
        lines = cfg.read_text(encoding="utf-8").splitlines()
        for r in s["rows"]:
            total += 1
            entry = lines[r["config_line"] - 1]
            assert re.search(rf"\bid:\s*{re.escape(r['id'])}\s*(#.*)?$", entry), (s["experiment"], r["id"], entry)
            where = edition.function_of(s["kind"], r.get("computes") or r["id"])
            module, _, name = where.rpartition(".")
            fn = getattr(importlib.import_module(module), name)
            assert callable(fn), where
            key = r.get("computes") or r["id"]
            src = inspect.getsource(fn)
            named = f'"{key}"' in src or any(f'f"{key[:i]}{{' in src for i in range(2, len(key)))
            if name == "run" and not named:
                fallback += 1
            else:
                assert named, (where, key)
    assert fallback <= total // 10, f"{fallback} of {total} rows name only their kind's run()"


def test_a_printed_zero_gets_an_absolute_difference(reproduced_all):
    out, _ = reproduced_all
    with (out / "paper-table.csv").open(encoding="utf-8", newline="") as fh:
        rows = list(csv.DictReader(fh))
    zeros = [r for r in rows if r["printed_value"] not in ("", None) and float(r["printed_value"]) == 0
             and r["computed"] not in ("", None)]
    assert zeros, "the paper prints zeros that resal compares (ε = 0, …)"
    for r in zeros:
        assert r["rel_diff"] == "" and float(r["abs_diff"]) == pytest.approx(float(r["computed"]))
    md = (out / "paper-table.md").read_text(encoding="utf-8")
    for r in zeros:
        line = next(x for x in md.splitlines() if f"| {r['id']} |" in x and f"| {r['experiment']} |" in x)
        assert "Δ =" in line and "%" not in line.split("|")[10], line
    header = md.splitlines()[md.splitlines().index(next(x for x in md.splitlines() if x.startswith("| experiment")))]
    assert "| note |" in header and "| tolerance |" in header


def _visible_text(page: str) -> str:
    body = re.sub(r"<(script|style)>.*?</\1>", " ", page, flags=re.S)
    return html.unescape(re.sub(r"<[^>]+>", " ", body))


def test_the_page_shows_no_latex_source_and_every_note_whole(reproduced_all):
    out, _ = reproduced_all
    page = (out / "index.html").read_text(encoding="utf-8")
    text = _visible_text(page)
    for pattern in (r"\\[A-Za-z]+", r"_\{", r"\^\{", r"\^\(", r"\$"):
        assert not re.search(pattern, text), pattern
    from reproductions.edition.formula import mathml

    for s in _summaries(out):
        for r in s["rows"]:  # every note and printed text reaches the page whole: its formulas as MathML, its prose
            for key in ("note", "printed_text", "quantity"):  # escaped (a row's id in it may have become a link)
                for sp in edition.readable(r[key]):
                    if sp.style == "math":
                        assert mathml(sp.text) in page, (s["experiment"], r["id"], key, sp.text)
                        continue
                    for piece in re.split(r"[a-z][a-z0-9_]* of [a-z]+(?:-[a-z]+)+|[a-z][a-z0-9]*(?:_[a-z0-9]+)+|"
                                          r"[a-z]+\d+[a-z0-9]*|doi:\S+|\d+e-\d+", sp.text):
                        assert html.escape(piece, quote=True) in page, (s["experiment"], r["id"], key, piece)


def test_the_edition_is_the_same_bytes_twice(reproduced_all, tmp_path):
    out, _ = reproduced_all
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    first = (copy / "index.html").read_bytes()
    edition.write_index(copy)
    assert (copy / "index.html").read_bytes() == first
    assert (copy / "report.pdf").read_bytes() == (out / "report.pdf").read_bytes()


def _luminance(hex_colour: str) -> float:
    rgb = [int(hex_colour[i:i + 2], 16) / 255 for i in (1, 3, 5)]
    lin = [c / 12.92 if c <= 0.03928 else ((c + 0.055) / 1.055) ** 2.4 for c in rgb]
    return 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]


def test_text_colours_have_enough_contrast():
    """WCAG AA for normal text (4.5:1): every foreground of the page's palette on the background it is set on."""
    var = dict(re.findall(r"--([a-z]+):(#[0-9a-f]{6})", edition.html._CSS))
    pairs = [("fg", "bg"), ("muted", "bg"), ("link", "bg"), ("ok", "okbg"), ("bad", "badbg"), ("na", "nabg"),
             ("muted", "filters"), ("beyondfg", "beyondbg")]
    var["beyondfg"], var["beyondbg"] = re.search(r"\.beyond\{color:(#[0-9a-f]{6});background:(#[0-9a-f]{6})",
                                                 edition.html._CSS).groups()
    var["filters"] = re.search(r"\.filters\{[^}]*background:(#[0-9a-f]{6})", edition.html._CSS).group(1)
    for fg, bg in pairs:
        a, b = sorted((_luminance(var[fg]), _luminance(var[bg])), reverse=True)
        assert (a + 0.05) / (b + 0.05) >= 4.5, (fg, bg, (a + 0.05) / (b + 0.05))
