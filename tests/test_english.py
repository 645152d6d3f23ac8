"""Issue 32, item 3: every printed row quoting the paper (``text``) carries the project's English rendering of it
(``english``): the French words translated, the formulas and ellipses as printed, decimal commas written as decimal
points. The loader requires it where the row quotes the paper and refuses it where the row quotes nothing, and
summary.json carries it beside ``printed_text``."""

from __future__ import annotations

import re
import shutil
import unicodedata
from functools import lru_cache

import pytest

from reproductions import api, paper
from reproductions.report import summary

IDS = api.experiment_ids()
# common French words: a rendering holding one was not translated
FRENCH = frozenset("le la les des du de une un est et que qui dans sur pour par avec ne pas sont ces cette au aux "
                   "nous il elle se ou leur mais plus peut sera seront".split())
DECIMAL_COMMA = re.compile(r"(?<=\d),(?=\d)")  # 0,29 (not the list "ω1, 2ω′")
DROPPED = set(",.;:'’-")  # punctuation that English may place differently


@lru_cache(maxsize=1)
def _prose_words() -> frozenset[str]:
    """Words of three letters or more that the paper prints outside its formulas ($…$): its prose."""
    prose = re.sub(r"\$\$.*?\$\$|\$.*?\$", " ", paper.text(), flags=re.S)
    return frozenset(w.lower() for w in paper.WORD.findall(prose) if len(w) >= 3)


def _symbols(text: str) -> str:
    """What a rendering keeps as printed: the formulas' symbols, digits, Greek letters, brackets and ellipses, in
    order (the Latin letters, spaces and punctuation dropped: the words are translated, decimal commas become
    points)."""
    return "".join(c for c in text if not c.isspace() and c not in DROPPED
                   and not unicodedata.name(c, "").startswith("LATIN"))


def _quoted_rows():
    for eid in IDS:
        for p in api.load(eid).printed:
            yield eid, p


def test_every_row_quoting_the_paper_has_an_english_rendering():
    quoting = [(eid, p) for eid, p in _quoted_rows() if p.text.strip()]
    assert len(quoting) > 200  # every shipped row that quotes the paper
    bad = []
    for eid, p in quoting:
        en, fr = p.english, p.text
        where = f"{eid}/{p.id}"
        if not en or en != en.strip():
            bad.append(f"{where}: no English rendering ({en!r})")
            continue
        if not 0.5 <= len(en) / len(fr) <= 2:
            bad.append(f"{where}: {len(en)} characters for a French text of {len(fr)}")
        if _symbols(en) != _symbols(fr):
            bad.append(f"{where}: its formulas or ellipses are not the printed ones: {en!r} for {fr!r}")
        if FRENCH & {w.lower() for w in paper.WORD.findall(en)}:
            bad.append(f"{where}: French words left untranslated: {en!r}")
        words = [w for w in paper.WORD.findall(fr)
                 if w.lower() in FRENCH or (len(w) >= 3 and w.lower() in _prose_words())]
        if (words or DECIMAL_COMMA.search(fr)) and en == fr:
            bad.append(f"{where}: the English is the French ({', '.join(words) or 'a decimal comma'})")
        if not words and DECIMAL_COMMA.sub(".", fr) != en:
            bad.append(f"{where}: a formula is rendered as printed (decimal points only): {en!r} for {fr!r}")
    assert not bad, "\n".join(bad)


def test_a_row_quoting_nothing_has_no_english():
    assert all(p.english is None for _, p in _quoted_rows() if not p.text.strip())


def _copy(tmp_path, old: str, new: str):
    text = (api.config_dir() / "marble-drop.yaml").read_text(encoding="utf-8")
    assert text.count(old) == 1
    text = text.replace(old, new)
    shutil.copytree(api.config_dir() / "data", tmp_path / "data")
    path = tmp_path / "marble-drop.yaml"
    path.write_text(text, encoding="utf-8")
    return path, text[: text.index(new)].count("\n") + 1 if new else None


def _index(text_line: str) -> int:
    rows = api.load("marble-drop").printed
    return next(i for i, p in enumerate(rows) if p.text == text_line)


def test_a_row_quoting_the_paper_without_english_is_refused_at_its_line(tmp_path):
    i = _index("ne rejaillit pas")
    path, _ = _copy(tmp_path, '    english: "does not rebound"\n', "")
    entry = path.read_text(encoding="utf-8").split("\n").index("  - id: eps_no_rebound") + 1
    with pytest.raises(api.InputError) as info:
        api.load(str(path))
    assert info.value.where == f"{path}:{entry}"
    assert f"missing required key 'printed[{i}].english'" in info.value.message
    assert "row 'eps_no_rebound'" in info.value.message and "an English rendering of its 'text'" in info.value.message


def test_an_empty_english_is_refused_at_its_line(tmp_path):
    i = _index("ne rejaillit pas")
    path, line = _copy(tmp_path, '    english: "does not rebound"\n', '    english: "  "\n')
    with pytest.raises(api.InputError) as info:
        api.load(str(path))
    assert info.value.where == f"{path}:{line}"
    assert f"'printed[{i}].english' is empty (row 'eps_no_rebound')" in info.value.message


def test_an_english_without_a_text_is_refused(tmp_path):
    i = _index("ne rejaillit pas")
    path, line = _copy(tmp_path, '    text: "ne rejaillit pas"\n', '    text: ""\n')
    with pytest.raises(api.InputError) as info:
        api.load(str(path))
    assert info.value.where == f"{path}:{line + 1}"  # the english line, after the emptied text
    assert f"'printed[{i}].english' without a 'text' (row 'eps_no_rebound')" in info.value.message
    assert "expected no 'english' key" in info.value.message


@pytest.mark.parametrize("eid", ["marble-drop", "cloth-slide"])  # cloth-slide: rows that quote nothing, too
def test_summary_rows_carry_the_english_next_to_the_printed_text(eid):
    exp = api.load(eid)
    rows = summary(api.run(exp), prov={})["rows"]
    assert [r["english"] for r in rows] == [p.english for p in exp.printed]
    assert any(r["english"] is None for r in rows) == any(not p.text for p in exp.printed)
    for r in rows:
        keys = list(r)
        assert keys[keys.index("printed_text") + 1] == "english"
        assert r["english"] is None or (isinstance(r["english"], str) and r["english"])
