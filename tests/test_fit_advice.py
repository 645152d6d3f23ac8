"""Every advice is checked by following it (issue 30): a warning or refusal that tells the user to write a unit in
the header (or another unit for angles) is taken literally — the header renamed as it says, nothing else — and the
file fitted again, until no advice is left; the file must then fit (exit 0) without an implausible input or another
convention, and give back the coefficient the example was made with. Where a refusal names two units (positions
alone cannot tell centimetres from millimetres), each is followed: the right one fits, the wrong one is caught by
the instants."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from fit_tables import invoke, write
from test_fit_traps import REFUSED, WARNED

# the forms an advice to rename a header column takes
_FORMS = (
    re.compile(r"plausible \(write the unit in the header: (?P<names>'\w+'(?:, '\w+')*)\)"),
    re.compile(r"with (?P<written>\w+) in [^(]*\('(?P<new>\w+)' in the header\)"),
    re.compile(r"in the header \((?P<alts>\w+(?: or \w+)*)\)"),
    re.compile(r"write (?P<all>\w+(?: and \w+)*) in the header"),
)
TRUTH = {"rebound.csv": ("e", 0.8), "ricochet.csv": ("joint-physical.f", 0.2)}  # what the examples were made with


def _advice(message: str, head: list[str]) -> list[list[str]]:
    """The headers the message tells the user to write (one per alternative it offers)."""
    out = []
    for m in _FORMS[0].finditer(message):
        names = {n.strip("'").rsplit("_", 1)[0]: n.strip("'") for n in m["names"].split(", ")}
        out.append([names.get(h, h) for h in head])
    for m in _FORMS[1].finditer(message):
        out.append([m["new"] if h == m["written"] else h for h in head])
    for m in _FORMS[2].finditer(message):
        for alt in m["alts"].split(" or "):
            base = alt.rsplit("_", 1)[0]
            out.append([alt if h.rsplit("_", 1)[0] == base or h == base else h for h in head])
    for m in _FORMS[3].finditer(message):
        names = {n.rsplit("_", 1)[0]: n for n in m["all"].split(" and ")}
        out.append([names.get(h.rsplit("_", 1)[0], names.get(h, h)) for h in head])
    return [h for h in out if h != head]


def _messages(res) -> list[str]:
    if res.exit_code == 2:
        return [" ".join(res.stderr.split())]
    s = json.loads(res.stdout)
    return [" ".join(w["message"].split()) for w in s["warnings"] if w["code"] in ("implausible-input", "convention")]


def _cases() -> list[tuple[str, str, str, object, tuple[str, ...]]]:
    out = []
    for name, (kind, example, change, args, codes, _) in WARNED.items():
        if {"implausible-input", "convention"} & codes:
            out.append((name, kind, example, change, args))
    for name, (kind, example, change, args, _) in REFUSED.items():
        out.append((name, kind, example, change, args))
    return out


def _follow(tmp_path: Path, kind: str, example: str, change, args: tuple[str, ...]) -> list[tuple[list[str], dict]]:
    """Each chain of advice followed to its end: (the header written last, its fit.json)."""
    f = write(tmp_path, example, change)
    lines = f.read_text(encoding="utf-8").splitlines()
    at = next(i for i, ln in enumerate(lines) if not ln.startswith("#"))
    ends = []
    todo = [(lines[at].split(","), 0)]
    seen = set()
    while todo:
        head, depth = todo.pop()
        assert depth <= 3, f"advice keeps coming after three rounds: {head}"
        lines[at] = ",".join(head)
        f.write_text("\n".join(lines) + "\n", encoding="utf-8")
        out = tmp_path / f"out{len(seen)}"
        seen.add(tuple(head))
        res = invoke(out, kind, f, *args)
        nexts = [h for m in _messages(res) for h in _advice(m, head) if tuple(h) not in seen]
        if nexts:
            todo += [(h, depth + 1) for h in nexts]
        elif depth > 0:
            ends.append((head, res))
    return ends


@pytest.mark.parametrize("name, kind, example, change, args", _cases(), ids=[c[0] for c in _cases()])
def test_each_advice_followed_leads_to_a_plausible_file(tmp_path, name, kind, example, change, args):
    ends = _follow(tmp_path, kind, example, change, args)
    if not ends:
        pytest.skip("no header advice in this case's message")
    good = 0
    for head, res in ends:
        assert res.exit_code in (0, 2), res.output
        if res.exit_code == 2:  # an alternative the data themselves refuse, naming why: not silent
            continue
        s = json.loads(res.stdout)
        codes = [w["code"] for w in s["warnings"]]
        if "implausible-input" in codes or "convention" in codes:  # a wrong alternative (mm for cm), caught: not silent
            continue
        good += 1
        if example in TRUTH:
            pid, truth = TRUTH[example]
            row = next(f for f in s["fits"] if f["id"].endswith(pid))
            assert row["ci95"][0] <= truth <= row["ci95"][1], (head, row)
    assert good >= 1, ends


def test_a_fit_that_will_take_minutes_says_so_before_it_starts(tmp_path, monkeypatch):
    """Beyond the rows its kind fits in a minute (measured: ``Kind.per_minute``), one line on stderr before the fit
    (its progress bar shows only on a terminal); below it, nothing."""
    import dataclasses

    from fit_tables import EXAMPLES

    from reproductions.fit.kinds import KINDS

    quiet = invoke(tmp_path / "a", "rebound", EXAMPLES / "rebound.csv")
    assert quiet.exit_code == 0 and "a minute" not in quiet.stderr
    monkeypatch.setitem(KINDS, "rebound", dataclasses.replace(KINDS["rebound"], per_minute=4))
    res = invoke(tmp_path / "b", "rebound", EXAMPLES / "rebound.csv")
    assert res.exit_code == 0, res.output
    said = " ".join(res.stderr.split())
    assert "12 rows, more than the 4 a rebound fit handles in a minute on two cores: expect about 3 minutes" in said
