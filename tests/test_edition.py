"""The reader's edition built from a results folder: formulas as a reader writes them, each row's config entry
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
from reproductions.edition.model import Span

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize(("text", "spans"), [
    ("v_y = η", [Span("v"), Span("y", "sub"), Span(" = η")]),
    ("φ0 = U/(1 + n)", [Span("φ"), Span("0", "sub"), Span(" = U/(1 + n)")]),
    ("τ′0", [Span("τ′"), Span("0", "sub")]),
    ("−nφ0", [Span("−nφ"), Span("0", "sub")]),  # a product: n times φ₀
    ("n0²R²", [Span("n"), Span("0", "sub"), Span("²R²")]),
    ("n0R", [Span("n"), Span("0", "sub"), Span("R")]),
    ("2V′0", [Span("2V′"), Span("0", "sub")]),
    ("(φ0/φ)^((1+k)/2)", [Span("(φ"), Span("0", "sub"), Span("/φ)"), Span("(1+k)/2", "sup")]),
    ("∫_{η0}^{η1} dη", [Span("∫"), Span("η0", "sub"), Span("η1", "sup"), Span(" dη")]),
    (r"$\varepsilon \le 1$", [Span("ε ≤ 1")]),
    # identifiers, numbers and words stay whole
    ("eq9_beyond, f_today, 1e-12, 2e5, V1p, eq. (9), n°14",
     [Span("eq9_beyond, f_today, 1e-12, 2e5, V1p, eq. (9), n°14")]),
])
def test_formulas_read_as_a_reader_writes_them(text, spans):
    assert list(edition.readable(text)) == spans


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
    for s in _summaries(out):
        for r in s["rows"]:  # every note and printed text reaches the page whole, set as a reader writes it
            for key in ("note", "printed_text", "quantity"):
                assert edition.rich_html(edition.readable(r[key])) in page, (s["experiment"], r["id"], key)


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
