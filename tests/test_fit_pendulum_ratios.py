"""Pendulum trials grouped by mass ratio for Newton's e: masses weighed trial by trial (differing in their last
digits) make one group per ratio, not one per trial (a file of 10⁵ such trials once printed 10⁵ rows of e)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from fit_tables import EXAMPLES

from reproductions.fit.kinds.common import FitOptions
from reproductions.fit.run import fit_csv


def _rows(path: Path) -> dict[str, dict]:
    out = fit_csv("pendulum", path, FitOptions(resamples=0)).summary
    return {f["id"]: f for f in out["fits"] if f["id"].startswith("e.ratio")}


def test_masses_weighed_trial_by_trial_make_one_group_per_ratio(tmp_path: Path) -> None:
    text = (EXAMPLES / "pendulum.csv").read_text(encoding="utf-8").splitlines()
    rows = [ln for ln in text if ln.strip() and not ln.startswith("#")]
    head, body = rows[0].split(","), [r.split(",") for r in rows[1:]]
    rng = np.random.default_rng(20261206)
    jm, jp = head.index("M_g"), head.index("Mp_g")
    weighed = []
    for r in body:
        r = list(r)
        for j in (jm, jp):  # a scale reading to 0.05 %: the last digit differs trial by trial
            r[j] = f"{float(r[j]) * (1 + 5e-4 * rng.uniform(-1, 1)):.6g}"
        weighed.append(r)
    path = tmp_path / "weighed.csv"
    path.write_text("\n".join([",".join(head), *(",".join(r) for r in weighed)]) + "\n", encoding="utf-8")
    exact, got = _rows(EXAMPLES / "pendulum.csv"), _rows(path)
    ratios = sorted({round(float(r[jp]) / float(r[jm]), 3) for r in body})
    assert len(got) == len(exact) == len(ratios) == 2, (list(got), list(exact))
    for (ka, a), (kb, b) in zip(sorted(exact.items()), sorted(got.items()), strict=True):
        assert a["note"].split(" trial")[0] == b["note"].split(" trial")[0]  # the same trials in each group
        assert "M′/M from" in b["note"] and "M′/M from" not in a["note"]
        # e per trial is (V1′ − V1)/V0: the masses do not enter, so each group's mean is the exact file's
        assert b["value"] == a["value"], (ka, kb)
