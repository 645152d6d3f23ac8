"""The README's first screen and the pages under docs/ (issue 33).

The README's first 40 lines are all a newcomer should need: the two commands (`make all`, `make test`), a picture
of the reader's edition and a link to every page of docs/. Every relative link of README.md and docs/*.md (images
included) points to a file or folder that exists, and a link to a heading (`page.md#heading`) to a heading that
exists. The example of `resal fit` in docs/fit.md shows the numbers the fit computes on that file today.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from reproductions import api

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
DOCS = ROOT / "docs"
PAGES = sorted(DOCS.glob("*.md"))
FIRST_SCREEN = 40  # lines
WIDTH = 100  # columns of the first screen

_FENCE = re.compile(r"^(```|~~~).*?^\1[ \t]*$", re.S | re.M)
_CODE_SPAN = re.compile(r"(`+)(?!`).+?(?<!`)\1(?!`)", re.S)
_INLINE = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
_REFDEF = re.compile(r"^ {0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s|$)", re.M)
_HTML = re.compile(r"<(?:a|img)\b[^>]*?\b(?:href|src)=\"([^\"]+)\"", re.I)
_SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")


def _prose(text: str) -> str:
    """The text without its fenced code blocks and code spans, where brackets are not links."""
    return _CODE_SPAN.sub("code", _FENCE.sub("", text))


def links(text: str) -> list[str]:
    """Every link target of a Markdown text: inline links and images, reference definitions, HTML href/src."""
    prose = _prose(text)
    return [m.group(1) for pattern in (_INLINE, _REFDEF, _HTML) for m in pattern.finditer(prose)]


def slug(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces as hyphens."""
    text = re.sub(r"[`*_]|\[([^\]]*)\]\([^)]*\)", r"\1", heading.strip()).lower()
    return re.sub(r"[^\w\- ]", "", text).replace(" ", "-")


def anchors(path: Path) -> set[str]:
    heads = re.findall(r"^#{1,6}[ \t]+(.+?)[ \t#]*$", _FENCE.sub("", path.read_text(encoding="utf-8")), re.M)
    return {slug(h) for h in heads}


def broken_links(page: Path) -> list[str]:
    """The relative links of ``page`` whose target does not exist (or whose #heading its page lacks)."""
    out = []
    for target in links(page.read_text(encoding="utf-8")):
        if not target or _SCHEME.match(target):
            continue  # http:, https:, mailto: … are not checked here (no network)
        path, _, fragment = target.partition("#")
        dest = (page.parent / path).resolve() if path else page
        if not dest.exists():
            out.append(f"{target}: no {dest}")
        elif fragment and dest.suffix == ".md" and fragment not in anchors(dest):
            out.append(f"{target}: no heading #{fragment} in {dest.name}")
    return out


# ---- the checker itself ------------------------------------------------------------------------------------------
def test_link_checker_finds_broken_links_and_ignores_code(tmp_path):
    (tmp_path / "there.md").write_text("# A title: with `code`\n\n## Second one\n", encoding="utf-8")
    (tmp_path / "sub").mkdir()
    page = tmp_path / "page.md"
    page.write_text(
        "[ok](there.md) [ok folder](sub/) [ok anchor](there.md#second-one) [ok title](there.md#a-title-with-code)\n"
        "![missing image](pic.png) [missing](docs/none.md) [bad anchor](there.md#nowhere)\n"
        "[multi\nline](gone.md) <img src=\"img/x.png\">\n[ref]: refs/missing.md\n"
        "[web](https://example.org/x.md) `[in code](not-checked.md)`\n"
        "```\n[in a block](not-checked-either.md)\n```\n", encoding="utf-8")
    found = broken_links(page)
    assert [b.split(":")[0] for b in found] == ["pic.png", "docs/none.md", "there.md#nowhere", "gone.md",
                                                "refs/missing.md", "img/x.png"], found


# ---- the first screen --------------------------------------------------------------------------------------------
def _first_screen() -> list[str]:
    return README.read_text(encoding="utf-8").splitlines()[:FIRST_SCREEN]


def test_first_screen_gives_the_two_commands():
    head = _first_screen()
    for target in ("all", "test"):
        assert any(re.match(rf"make {target}\s+# \S", line) for line in head), f"`make {target}` with what it does"
        assert re.search(rf"^{target}:", (ROOT / "Makefile").read_text(encoding="utf-8"), re.M), target


def test_first_screen_shows_the_edition_and_links_every_docs_page():
    head = "\n".join(_first_screen())
    assert re.search(r"!\[[^\]]+\]\(docs/edition-first-screen\.png\)", head), "the picture, with alt text"
    targets = set(links(head))
    assert len(PAGES) >= 6  # ARCHITECTURE, api, cli, development, experiments, fit
    missing = [f"docs/{p.name}" for p in PAGES if f"docs/{p.name}" not in targets]
    assert not missing, f"the README's first {FIRST_SCREEN} lines do not link {missing}"
    assert "configs/README.md" in targets  # the schema of the experiment files stays there


def test_first_screen_fits_the_width():
    wide = [(n, len(line)) for n, line in enumerate(_first_screen(), 1) if len(line) > WIDTH]
    assert not wide, f"lines wider than {WIDTH} columns (line, width): {wide}"


# ---- every relative link -----------------------------------------------------------------------------------------
@pytest.mark.parametrize("page", [README, *PAGES], ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_resolve(page):
    assert links(page.read_text(encoding="utf-8")) or page.name == "ARCHITECTURE.md", "a page with no link"
    assert broken_links(page) == []


def test_every_docs_page_links_back_to_the_readme():
    for page in PAGES:
        if page.name != "ARCHITECTURE.md":
            assert "../README.md" in links(page.read_text(encoding="utf-8")), page.name


# ---- the example of docs/fit.md ----------------------------------------------------------------------------------
def _near(printed: str, value: float) -> bool:
    """``value`` rounds to ``printed`` (half a unit of its last digit, which is how it was printed)."""
    decimals = len(printed.split(".")[1]) if "." in printed else 0
    return abs(float(printed) - value) <= 0.5 * 10 ** -decimals * (1 + 1e-9)


def test_fit_example_shows_what_the_fit_computes():
    text = (DOCS / "fit.md").read_text(encoding="utf-8")
    command = re.search(r"^resal fit (\S+) (\S+\.csv)", text, re.M)
    assert command, "docs/fit.md runs `resal fit <kind> <file>`"
    kind, data = command.groups()
    assert (ROOT / data).is_file(), data
    output = text[command.end():].split("\n```\n")[2]  # the block after the command's block
    assert output.startswith(f"resal fit {kind}: {data} ")
    fit = api.fit(kind, str(ROOT / data))
    number = r"(-?\d+\.?\d*(?:e-?\d+)?)"
    for key, title in (("e", "e (Newton"), ("eps", "ε (Résal")):
        record = output.split(f"\n{title}", 1)[1].split("\n\n", 1)[0]
        est = fit[key]
        value = re.search(rf"value\s+{number}", record).group(1)
        stderr = re.search(rf"std\. error\s+{number}", record).group(1)
        lo, hi = re.search(rf"95 % interval\s+\[{number}, {number}\]", record).groups()
        blo, bhi = re.search(rf"bootstrap 95 %\s+\[{number}, {number}\]", record).groups()
        assert _near(value, est.value), (key, value, est.value)
        assert _near(stderr, est.stderr), (key, stderr, est.stderr)
        assert _near(lo, est.ci95[0]) and _near(hi, est.ci95[1]), (key, lo, hi, est.ci95)
        assert _near(blo, est.ci95_bootstrap[0]) and _near(bhi, est.ci95_bootstrap[1]), (key, est.ci95_bootstrap)
    codes = re.findall(r"^WARNING \[([\w-]+)\]", output, re.M)
    assert codes == [w.code for w in fit.warnings]
