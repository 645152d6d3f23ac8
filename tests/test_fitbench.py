"""`resal bench fit`: the large files it fits are the example files' rows, replicated and jittered (so a fit of them
finds the example's values), and each fit runs in a fresh process whose peak memory is reported."""

from __future__ import annotations

import numpy as np

from reproductions import fitbench, locate
from reproductions.fit.kinds import KINDS


def _rows(text: str) -> list[list[str]]:
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.startswith("#")]
    return [ln.split(",") for ln in lines]


def test_replicated_files_are_the_examples_rows_jittered_and_seeded() -> None:
    for kind in fitbench.KINDS:
        text = fitbench.replicate(kind, 250)
        assert text == fitbench.replicate(kind, 250)  # seeded: the same file on every run
        rows = _rows(text)
        example = _rows((locate.examples_dir() / KINDS[kind].example).read_text(encoding="utf-8"))
        assert rows[0] == example[0] and len(rows) == 251
        assert len({tuple(r) for r in rows[1:]}) == 250  # no two rows alike
        for i, r in enumerate(rows[1:]):
            src = example[1 + i % (len(example) - 1)]
            for a, b in zip(r, src, strict=True):
                try:
                    assert abs(float(a) - float(b)) <= 1.0001e-4 * abs(float(b)) + 1e-12
                except ValueError:
                    assert a == b  # a label


def test_one_fits_in_a_fresh_process_and_reports_its_memory() -> None:
    r = fitbench.one("rebound", 300)
    assert "error" not in r, r
    assert r["rows"] == 300 and r["seconds"] > 0
    assert r["peak_mb"] >= r["after_imports_mb"] > 10  # numpy and scipy are imported before the fit
    assert np.isclose(r["fit_mb"], r["peak_mb"] - r["after_imports_mb"])


def test_sizes_beyond_a_minute_are_not_run() -> None:
    assert fitbench.run(sizes=(10**9,), kinds=("rebound",)) == []
    assert fitbench.steps(True) == len(fitbench.KINDS)  # every kind fits 100 rows within a minute
    assert fitbench.steps(False) == sum(1 + (KINDS[k].per_minute >= 10_000) for k in fitbench.KINDS)


def test_a_failed_fit_is_a_row_that_says_so() -> None:
    text = "\n".join(fitbench.markdown([{"kind": "markers", "rows": 1000, "error": "MemoryError"}]))
    assert "| markers | 1,000 | failed: MemoryError |" in text
