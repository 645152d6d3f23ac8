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
            "body *", "els => els.filter(e => e.getBoundingClientRect().right > "
                      "document.documentElement.clientWidth + 1).map(e => e.tagName + '#' + e.id).slice(0, 5)")
        assert over == []


def test_the_first_screen_is_the_findings(browser, edition):
    out, _ = edition
    with _open(browser, out) as (page, _):
        top = page.eval_on_selector("#findings", "e => e.getBoundingClientRect().top")
        assert top < 900, "the findings begin below the first screen"
        items = page.eval_on_selector_all("#findings li", "els => els.length")
        assert items >= 10
        headings = page.eval_on_selector_all("h1", "els => els.length")
        assert headings == 1
