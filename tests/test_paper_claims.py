"""Every numbered equation, printed number and footnote of the digitised paper has a row (issue 13).

The digitised text is ``../shared/paper/resal-1883.md`` beside the checkout (the project does not copy it; CI has
it there). Its claims are found mechanically: display equations that carry a number or letter ``(7)``, ``(b′)``
(``$$(7) …``, or a label at the start of a line inside an aligned display);
decimals ``0,55`` (also ``2ᵐ,80`` and ``0, 25``) and numeric fractions ``\\frac{2}{3}``; footnotes ``(1) …``. A claim
at line L is covered by a printed entry of some config with ``line: L`` (for an equation, one whose ``source`` names
its label). ``OMITTED`` lists the deliberate exceptions with their reason.

Run ``python tests/test_paper_claims.py [FIRST LAST]`` to list what is not covered between two lines.
"""

from __future__ import annotations

import os
import re
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parent.parent
PAPER = Path(os.environ.get("RESAL_PAPER", ROOT.parent / "shared" / "paper" / "resal-1883.md"))
CONFIGS = ROOT / "configs"

# line → why it has no row (page furniture, dates, biography)
OMITTED: dict[int, str] = {
    53: "footnote on Euler's son: biography and dates (1734-1800), no claim of mechanics",
}

_EQ_DISPLAY = re.compile(r"^\$\$\s*\((?P<label>[0-9]+|[a-z])(?P<prime>['′]*)\)")  # $$(7) …
_EQ_ALIGNED = re.compile(r"^\s+\((?P<label>[0-9]+|[a-z])(?P<prime>['′]*)\)\s*\\quad")  # inside \begin{aligned}
_DECIMAL = re.compile(r"(?<![\w.])(?P<num>\d+(?:<sup>[a-z]+</sup>)?,\s?\d+)")
_FRACTION = re.compile(r"\\frac\{(?P<a>\d+)\}\{(?P<b>\d+)\}")
_FOOTNOTE = re.compile(r"^\((?:<sup>)?\d(?:</sup>)?\)\s")


@dataclass(frozen=True)
class Claim:
    line: int
    kind: str  # equation | number | footnote
    label: str  # "(7)", "(b′)", "0,55", "\\frac{2}{3}", "footnote"


def claims(text: str) -> list[Claim]:
    out = []
    for i, line in enumerate(text.splitlines(), 1):
        m = _EQ_DISPLAY.match(line) or _EQ_ALIGNED.match(line)
        if m:
            out.append(Claim(i, "equation", f"({m['label']}{'′' * len(m['prime'])})"))
            continue  # the numbers of a numbered equation are the equation's
        if _FOOTNOTE.match(line):
            out.append(Claim(i, "footnote", "footnote"))
        for d in _DECIMAL.finditer(line):
            out.append(Claim(i, "number", d["num"]))
        for f in _FRACTION.finditer(line):
            out.append(Claim(i, "number", f"{f['a']}/{f['b']}"))
    return out


def printed_entries() -> list[dict]:
    rows = []
    for path in sorted(CONFIGS.glob("*.yaml")):
        doc = yaml.safe_load(path.read_text(encoding="utf-8"))
        for p in doc.get("printed", []):
            rows.append({**p, "_config": path.stem})
    return rows


def _label_in(label: str, source: str) -> bool:
    norm = source.replace("'", "′")
    return label in norm


def missing(first: int = 1, last: int = 10**9) -> list[Claim]:
    text = PAPER.read_text(encoding="utf-8")
    rows = printed_entries()
    by_line: dict[int, list[dict]] = {}
    for r in rows:
        if isinstance(r.get("line"), int):
            by_line.setdefault(r["line"], []).append(r)
    out = []
    for c in claims(text):
        if not first <= c.line <= last or c.line in OMITTED:
            continue
        here = by_line.get(c.line, [])
        if c.kind == "equation":
            ok = any(_label_in(c.label, str(r.get("source", ""))) for r in here)
        else:
            ok = bool(here)
        if not ok:
            out.append(c)
    return out


def _paper() -> Path:
    if not PAPER.is_file():
        if os.environ.get("CI"):
            pytest.fail(f"the digitised paper is not at {PAPER} (CI has it beside the checkout)")
        pytest.skip(f"the digitised paper is not at {PAPER}")
    return PAPER


def test_the_parser_finds_the_claims_it_should():
    found = claims(_paper().read_text(encoding="utf-8"))
    eqs = [c for c in found if c.kind == "equation"]
    assert len(eqs) >= 80
    assert Claim(216, "equation", "(9)") in found  # §I eq. (9), the impact on an immovable mass
    assert any(c.line == 220 and c.label == "0,55" for c in found)  # Coriolis's ratio
    assert any(c.kind == "footnote" for c in found)


def test_every_numbered_equation_printed_number_and_footnote_has_a_row():
    _paper()
    gaps = missing()
    assert not gaps, f"{len(gaps)} claim(s) of the paper without a row:\n" + "\n".join(
        f"  line {c.line}: {c.kind} {c.label}" for c in gaps)


def test_every_row_says_where_it_is_printed():
    text = _paper().read_text(encoding="utf-8").splitlines()
    src = re.compile(r"^§[IVX]+( n°\d+(-\d+)?)?(, .+)?$")
    for r in printed_entries():
        where = f"{r['_config']}/{r['id']}"
        assert isinstance(r.get("line"), int) and 1 <= r["line"] <= len(text), f"{where}: no line"
        assert src.match(str(r.get("source", ""))), f"{where}: source {r.get('source')!r} is not '§II n°7, eq. (3)'"
    for line in OMITTED:
        assert 1 <= line <= len(text)


if __name__ == "__main__":
    lo, hi = (int(sys.argv[1]), int(sys.argv[2])) if len(sys.argv) == 3 else (1, 10**9)
    for c in missing(lo, hi):
        print(f"line {c.line}: {c.kind} {c.label}")
