"""Every shipped experiment against its golden numbers (``make golden`` regenerates them on purpose)."""

import copy
import json

import pytest

from reproductions import api, golden
from reproductions.report import summary

IDS = api.experiment_ids()


@pytest.fixture(scope="module")
def summaries(runs):
    return {i: summary(runs[i], prov={}) for i in IDS}


def test_every_config_has_a_golden_file():
    assert IDS, "no experiments found"
    missing = [i for i in IDS if not (golden.GOLDEN_DIR / f"{i}.json").is_file()]
    assert not missing, f"no golden file for {missing}: run `make golden` and review the numbers"


@pytest.mark.parametrize("eid", IDS)
def test_summary_matches_golden(eid, summaries):
    path = golden.GOLDEN_DIR / f"{eid}.json"
    if not path.is_file():
        pytest.fail(f"missing golden file {path}")
    diffs = golden.compare(json.loads(path.read_text(encoding="utf-8")), summaries[eid])
    assert not diffs, "\n".join(diffs)


def test_compare_catches_a_moved_number_and_a_flipped_verdict(summaries):
    s = summaries["coriolis-pendulum"]
    g = golden.golden_object(s)
    moved = copy.deepcopy(s)
    rows = {r["id"]: r for r in moved["rows"]}
    rows["combination"]["computed"] *= 1 + 1e-6
    rows["n_equations"]["verdict"] = "differs"
    rows["eq7"]["computed"] += 5e-8  # formula discrepancies are compared to their own tolerance (1e-7)
    diffs = golden.compare(g, moved)
    assert [d.split(":")[0] for d in diffs] == ["rows.combination.computed", "rows.n_equations.verdict"]
    rows["eq7"]["computed"] += 1e-6
    diffs = golden.compare(g, moved)
    assert len(diffs) == 3 and diffs[1].startswith("rows.eq7.computed")
    assert golden.compare(g, s) == []


def test_every_row_that_differs_names_its_reason_and_no_other_row_does(summaries):
    """Issue 13: a `differs` row says why (a code of config.REASONS); a reproduced or not-checkable row carrying a
    reason is a stale expectation of the config."""
    from reproductions.config import REASONS

    bad = []
    for eid, s in summaries.items():
        for r in s["rows"]:
            if r["verdict"] == "differs" and r.get("reason") not in REASONS:
                bad.append(f"{eid}/{r['id']}: differs without a reason")
            if r["verdict"] != "differs" and r.get("reason") is not None:
                bad.append(f"{eid}/{r['id']}: {r['verdict']} but carries reason {r['reason']!r}")
    assert not bad, "\n".join(bad)
