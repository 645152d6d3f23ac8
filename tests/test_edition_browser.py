"""The reader's edition (results/index.html) as a reader meets it: opened from the file system in a real headless
Chromium (Debian's package, driven by Playwright; never a downloaded browser). What is checked comes from
paper-table.csv, written by other code: every row once, each filter showing exactly what it names."""

from __future__ import annotations

import csv
import os
import re
import shutil
from collections import Counter
from contextlib import contextmanager
from pathlib import Path
from urllib.parse import unquote, urlparse

import pytest
from conftest import SCREENSHOTS

ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
        "--disable-component-update", "--disable-sync", "--disable-default-apps"]


def _chromium() -> str:
    path = os.environ.get("RESAL_CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")
    if not path:
        pytest.fail("no chromium on PATH: install Debian's package (apt-get install chromium); .ci/run does so")
    return path


@pytest.fixture(scope="module")
def browser():
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is a test dependency: make setup")
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=_chromium(), args=ARGS)
        yield b
        b.close()


@pytest.fixture(scope="module")
def edition(reproduced_all):
    out, _ = reproduced_all
    with (out / "paper-table.csv").open(encoding="utf-8", newline="") as fh:
        rows = list(csv.DictReader(fh))
    return out, rows


@contextmanager
def _open(browser, out: Path, width: int = 1280, scripts: bool = True):
    """(page, console errors) of index.html in a fresh browser context, closed on leaving."""
    ctx = browser.new_context(viewport={"width": width, "height": 900}, java_script_enabled=scripts)
    page = ctx.new_page()
    errors: list[str] = []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto((out / "index.html").as_uri(), wait_until="load")
    try:
        yield page, errors
    finally:
        ctx.close()


def test_every_row_once_figures_loaded_no_console_error(browser, edition, tmp_path):
    out, rows = edition
    with _open(browser, out) as (page, errors):
        ids = page.eval_on_selector_all("article.row", "els => els.map(e => e.id)")
        expected = [f"{r['experiment']}--{r['id']}" for r in rows]
        assert Counter(ids) == Counter(expected), "rows of paper-table.csv missing or repeated in index.html"
        imgs = page.eval_on_selector_all("img", "els => els.map(e => [e.getAttribute('src'), e.naturalWidth, "
                                                "e.getAttribute('alt') || ''])")
        assert imgs, "the edition shows no figure"
        assert [src for src, w, _ in imgs if w <= 0] == [], "figures that did not load"
        assert [src for src, _, alt in imgs if len(alt) < 20] == [], "figures without a real alt text"
        assert errors == []
        shot = tmp_path / "first-screen.png"
        page.screenshot(path=str(shot))
        assert shot.stat().st_size > 10_000
        SCREENSHOTS.append(str(shot))


def test_every_local_link_resolves(browser, edition):
    out, _ = edition
    with _open(browser, out) as (page, _):
        links = page.eval_on_selector_all("a[href], img[src]", "els => els.map(e => e.getAttribute('href') || "
                                                               "e.getAttribute('src'))")
        ids = set(page.eval_on_selector_all("[id]", "els => els.map(e => e.id)"))
    broken = []
    for link in links:
        u = urlparse(link)
        if u.scheme in ("http", "https"):  # the way back to 1883 and to the sources: the facsimile and DOIs only
            assert u.netloc in ("www.numdam.org", "doi.org"), f"a link to an unexpected site: {link}"
            continue
        assert u.scheme in ("", "file"), f"a link leaves the machine: {link}"
        if link.startswith("#"):
            if link[1:] not in ids:
                broken.append(link)
        elif not (out / unquote(u.path)).is_file():
            broken.append(link)
    assert broken == []


def test_each_filter_shows_exactly_what_it_names(browser, edition):
    out, rows = edition
    with _open(browser, out) as (page, errors):
        assert page.is_visible("#filters")
        key = {"verdict": lambda r: r["verdict"], "reason": lambda r: r["reason"] or "none",
               "section": lambda r: re.match(r"§[IVXLC]+", r["section"]).group(0)}  # a section of the paper
        for name, of in key.items():
            values = page.eval_on_selector_all(f"#f-{name} option", "els => els.map(e => e.value)")
            assert set(values) - {""} >= {of(r) for r in rows}, f"the {name} filter lacks values the rows have"
            for value in values:
                page.select_option(f"#f-{name}", value)
                shown = page.eval_on_selector_all("article.row:not([hidden])", "els => els.map(e => e.id)")
                want = [f"{r['experiment']}--{r['id']}" for r in rows if value == "" or of(r) == value]
                assert Counter(shown) == Counter(want), f"filter {name} = {value!r}"
            page.select_option(f"#f-{name}", "")
        # two filters at once: their intersection
        page.select_option("#f-verdict", "differs")
        page.select_option("#f-reason", "erratum")
        shown = page.eval_on_selector_all("article.row:not([hidden])", "els => els.length")
        assert shown == sum(r["verdict"] == "differs" and r["reason"] == "erratum" for r in rows) > 0
        # a section with no row shown hides its figures too; a link to a hidden row clears the filters
        page.select_option("#f-reason", "")
        page.select_option("#f-verdict", "reproduced")
        empty = page.eval_on_selector_all(
            "section.experiment", "ss => ss.filter(s => !s.querySelector('article.row:not([hidden])'))"
                                  ".map(s => [s.id, s.querySelectorAll('figure:not([hidden])').length])")
        assert all(n == 0 for _, n in empty)
        target = next(f"{r['experiment']}--{r['id']}" for r in rows if r["verdict"] == "differs")
        assert page.is_hidden(f"[id='{target}']")
        page.evaluate("id => { const a = document.createElement('a'); a.href = '#' + id; a.textContent = 'x'; "
                      "document.getElementById('findings').appendChild(a); a.click(); }", target)
        assert page.is_visible(f"[id='{target}']")
        assert page.eval_on_selector("#f-verdict", "e => e.value") == ""
        assert errors == []


def test_filters_reach_measurements_and_findings_and_live_in_the_address(browser, edition):
    """The part filter separates the paper's claims from today's measurements, the findings filter shows one kind of
    finding, and the filters' state is in the address: a reloaded or shared link shows the same rows."""
    import json

    out, rows = edition
    summaries = [json.loads(p.read_text(encoding="utf-8")) for p in sorted(out.glob("*/summary.json"))]
    measured = [f"{s['experiment']}--{m['id']}" for s in summaries for m in s.get("measurements", [])]
    findings = Counter(f["category"] for s in summaries for f in s.get("findings", []))
    assert measured and len(findings) > 2
    with _open(browser, out) as (page, errors):
        page.select_option("#f-part", "measured")
        assert page.eval_on_selector_all("article.row:not([hidden])", "els => els.length") == 0
        shown = page.eval_on_selector_all("article.measure:not([hidden])", "els => els.map(e => e.id)")
        assert Counter(shown) == Counter(measured)
        page.select_option("#f-verdict", "inconsistent")
        shown = page.eval_on_selector_all("article.measure:not([hidden])", "els => els.map(e => e.dataset.verdict)")
        assert shown and set(shown) == {"inconsistent"}
        page.select_option("#f-part", "")
        page.select_option("#f-verdict", "")
        for category, n in findings.items():
            page.select_option("#f-category", category)
            cats = page.eval_on_selector_all("#findings li[data-category]:not([hidden])",
                                             "els => els.map(e => e.dataset.category)")
            assert Counter(cats) == Counter({category: n}), category
        page.select_option("#f-category", "")
        page.select_option("#f-verdict", "differs")
        page.select_option("#f-reason", "erratum")
        assert "verdict=differs" in page.url and "reason=erratum" in page.url
        url = page.url
        assert errors == []
    with _open(browser, out) as (page, errors):
        page.goto(url, wait_until="load")
        assert page.eval_on_selector("#f-verdict", "e => e.value") == "differs"
        shown = page.eval_on_selector_all("article.row:not([hidden])", "els => els.length")
        assert shown == sum(r["verdict"] == "differs" and r["reason"] == "erratum" for r in rows) > 0
        assert errors == []


def test_each_card_shows_its_verdict_once(browser, edition):
    out, _ = edition
    with _open(browser, out) as (page, _):
        counts = page.eval_on_selector_all(
            "article.row, article.measure", "els => els.map(e => [e.id, e.querySelectorAll('.badge').length, "
                                            "e.querySelector('details.dev') !== null])")
    assert counts and all(n == 1 for _, n, _ in counts), [c for c in counts if c[1] != 1][:5]
    assert all(dev for _, _, dev in counts), "every card keeps its ids and files in a developers' block"


def test_without_scripts_everything_is_shown(browser, edition):
    out, rows = edition
    with _open(browser, out, scripts=False) as (page, _):
        assert page.eval_on_selector_all("article.row", "els => els.filter(e => e.offsetParent !== null).length") \
            == len(rows)
        assert not page.is_visible("#filters"), "filters that cannot work without scripts are hidden"


def test_a_phone_wide_screen_needs_no_sideways_scrolling(browser, edition):
    out, _ = edition
    with _open(browser, out, width=375) as (page, _):
        wide = page.evaluate("() => [document.documentElement.scrollWidth, document.documentElement.clientWidth]")
        assert wide[0] <= wide[1], f"page {wide[0]} px wide in a {wide[1]} px window"
        over = page.eval_on_selector_all(
            "body *", "els => els.filter(e => !e.closest('math') && e.getBoundingClientRect().right > "
                      "document.documentElement.clientWidth + 1).map(e => e.tagName + '#' + e.id).slice(0, 5)")
        assert over == []
        # a figure spans the phone's width: tests/test_figures.py holds every figure's text at 9 CSS px or more
        # when the figure is 375 px wide
        widths = page.eval_on_selector_all("figure img", "els => els.map(e => e.getBoundingClientRect().width)")
        assert widths and min(widths) >= 374, min(widths)


def test_the_first_screen_is_the_answer(browser, edition):
    """A reader's first screen (1280 × 900) holds the three sentences of the answer, with the counts the tables
    give; the findings follow, ten of them with the rest one click away, after the key to their labels."""
    out, rows = edition
    with _open(browser, out) as (page, _):
        sentences = page.eval_on_selector_all(
            "#answer > p", "ps => ps.map(p => [p.innerText, p.getBoundingClientRect().bottom])")
        assert len(sentences) == 3
        assert all(bottom < 900 for _, bottom in sentences), "the answer runs below the first screen"
        paper = [r for r in rows if not r["id"].endswith("_beyond")]  # rows beyond the paper count apart
        reproduced = sum(r["verdict"] == "reproduced" for r in paper)
        assert f"{reproduced} are reproduced" in sentences[0][0], sentences[0][0]
        kinds = page.eval_on_selector_all("#answer table.kinds tbody tr", "trs => trs.length")
        assert kinds >= 4
        assert page.eval_on_selector_all("#findings > ol.findings > li", "els => els.length") == 10
        key = page.eval_on_selector("#key", "e => e.getBoundingClientRect().top")
        first = page.eval_on_selector("#findings li", "e => e.getBoundingClientRect().top")
        assert key < first and page.is_visible("#key"), "the labels are explained before the first finding"
        assert "consequence" in page.inner_text("#key") and page.is_hidden("#more-findings li")
        page.click("#more-findings > summary")
        assert page.is_visible("#more-findings li")
        assert page.eval_on_selector_all("h1", "els => els.length") == 1


def _reader_text(page) -> str:
    """What a reader reads: the page's text without the developers' details and the formulas' sources."""
    return page.evaluate("() => { const c = document.body.cloneNode(true);"
                         "c.querySelectorAll('details.dev, script, style').forEach(e => e.remove());"
                         "return c.innerText; }")


def test_formulas_are_mathml_and_numbers_are_written_out(browser, edition):
    """Formulas are MathML that Chromium lays out (not text with underscores and carets); no e-notation and no
    internal id reaches the reader's text; a hyphen never stands for a minus before a number."""
    out, rows = edition
    with _open(browser, out) as (page, _):
        maths = page.eval_on_selector_all(
            "math", "ms => ms.map(m => [m.textContent, m.getAttribute('alttext'), m.getBoundingClientRect().width])")
        assert len(maths) > 500
        for shown, source, width in maths:
            assert not re.search(r"[\\_^$]", shown), (shown, source)
            assert shown.count("{") == source.count("\\{"), (shown, source)
            assert width > 0, f"a formula not laid out: {source}"
        text = _reader_text(page)
    assert not re.search(r"\d(?:\.\d+)?e[-+]?\d", text), re.search(r".{40}\d(?:\.\d+)?e[-+]?\d.{20}", text)
    assert not re.search(r"(?:^|\s)- \d", text, flags=re.M)
    ids = {r["id"] for r in rows if "_" in r["id"]}
    leaked = sorted(i for i in ids if re.search(rf"(?<![\w-]){re.escape(i)}(?![\w-])", text))
    assert leaked == [], f"internal ids in the reader's text: {leaked[:10]}"


def test_lines_are_a_readable_measure(browser, edition):
    """The body text's lines hold at most 80 characters (measured: each paragraph's width over the mean advance of
    its own characters in its own font)."""
    out, _ = edition
    with _open(browser, out) as (page, _):
        widths = page.evaluate("""() => {
          const ctx = document.createElement('canvas').getContext('2d'); const out = [];
          document.querySelectorAll('#answer p, #history p, #findings li, article dd, .question').forEach(e => {
            const t = e.innerText.trim(); if (t.length < 200) return;
            const cs = getComputedStyle(e); ctx.font = cs.fontStyle + ' ' + cs.fontWeight + ' ' + cs.fontSize + ' '
              + cs.fontFamily;
            const mean = ctx.measureText(t).width / t.length;
            out.push(e.getBoundingClientRect().width / mean); });
          return out; }""")
    assert len(widths) > 50, "paragraphs of 200 characters or more measured"
    assert max(widths) <= 80, f"lines of up to {max(widths):.0f} characters"
    assert min(widths) >= 45, f"lines of only {min(widths):.0f} characters at 1280 px"
