"""Issue 34's targets as `resal bench` reports them: each figure read from the place of the report that measures
it, judged against its bound in the right direction, and "not measured" (never "met") where the report has no
such figure (`make all` is timed only by the full benchmark)."""

import math

from reproductions import targets


def _report(n1: dict[str, float], rate: float, err: float, make_all: tuple[float, float] | None) -> dict:
    rep = {"n1": {m: {"total": t} for m, t in n1.items()},
           "models": [{"model": "spheres-cloth", "paths": [
               {"path": "exact", "scenes_timed": 100_000, "scenes_per_second": 9e9, "where_exact": {
                   "max_error": 1.0, "scenes": 40}},
               {"path": "auto", "scenes_timed": 100_000, "scenes_per_second": rate, "where_exact": {
                   "max_error": err, "scenes": 40}}]}]}
    if make_all:
        rep["make_all"] = {"cold": {"median_wall": make_all[0]}, "cached": {"median_wall": make_all[1]}}
    return rep


def test_each_target_is_judged_in_its_own_direction() -> None:
    rep = _report({"direct-impact": 29.9, "cushion-impact": 30.1, "spheres-free": 59.0, "spheres-cloth": 61.0},
                  rate=1.2e6, err=2e-10, make_all=(4.9, 0.6))
    got = {t.what: t for t in targets.rows(rep)}
    assert got["one scene: direct impact"].met is True
    assert got["one scene: cushion-impact"].met is False
    assert got["one scene: two free balls"].met is True
    assert got["one scene: two balls on the cloth"].met is False
    batch = next(t for w, t in got.items() if w.startswith("§VI cloth: batch of 100,000"))
    assert (batch.now, batch.met) == (1.2e6, True)  # auto's rate, not the exact path's
    error = next(t for w, t in got.items() if "auto's error, 40 scenes" in w)
    assert (error.now, error.met) == (2e-10, False)
    assert got["make all, cold (median)"].met is True
    assert got["make all, nothing changed (median)"].met is False


def test_a_figure_the_report_does_not_hold_is_not_measured_never_met() -> None:
    rep = _report({}, rate=1.0, err=0.0, make_all=None)
    got = {t.what: t for t in targets.rows(rep)}
    for what in ("one scene: plane", "make all, cold (median)", "make all, nothing changed (median)"):
        assert (got[what].now, got[what].met) == (None, None)
    lines = targets.to_markdown([t.as_dict() for t in got.values()], None, None)
    table = [ln for ln in lines if ln.startswith("| ") and not ln.startswith("| what")]
    assert len(table) == len(got)
    assert sum("not measured" in ln for ln in table) == 11  # 7 single scenes, pooltool twice, make all twice
    assert not any("yes" in ln for ln in table if "not measured" in ln)


def test_the_calibration_measures_positive_finite_times() -> None:
    cal = targets.calibration(repeat=1)
    assert set(cal) == {"python_ns_per_iteration", "numpy_ns_per_element"}
    assert all(math.isfinite(v) and v > 0 for v in cal.values())
    # a Python iteration costs more than an element of a numpy operation on any machine this runs on
    assert cal["python_ns_per_iteration"] > cal["numpy_ns_per_element"]


def test_the_terminal_table_fits_80_columns_with_every_figure() -> None:
    rep = _report({"direct-impact": 12.3456, "spheres-cloth": 1234.5}, rate=987654.3, err=4.2e-13,
                  make_all=(13.25, 0.61))
    ts = [t.as_dict() for t in targets.rows(rep)]
    lines = targets.terminal_lines(ts, {"python_ns_per_iteration": 41.25, "numpy_ns_per_element": 0.51})
    assert max(len(ln) for ln in lines) <= 80, max(lines, key=len)
    body = "\n".join(lines)
    for shown in ("12.3 µs", "1.23e+03 µs", "9.88e+05 scenes/s", "4.2e-13", "13.2 s", "0.61 s", "41.2 ns"):
        assert shown in body, shown
    assert len(lines) == 2 + len(ts) + 1  # header, rule, one line per figure, the calibration


def _with_pooltool(rep: dict, bb_us: float | None, cushion_us: float, cushion_rate: float) -> dict:
    """A report with pooltool's figures (as ``pooltool_side.measure`` gives them) and cushion-impact's batch."""
    rep["models"].append({"model": "cushion-impact", "paths": [
        {"path": "auto", "scenes_timed": 100_000, "scenes_per_second": cushion_rate, "where_exact": {}}]})
    rep["pooltool"] = {"version": "0.6.0", "repeat": 10, "interactions": {
        "ball_ball": {"ours": "spheres-cloth", "what": "ball–ball", "models": [
            {"model": "Other", "default": False, "us_per_collision": 1.0, "first_call_s": 0.1},
            {"model": "FrictionalInelastic", "default": True, "us_per_collision": bb_us, "first_call_s": 9.5}]},
        "ball_linear_cushion": {"ours": "cushion-impact", "what": "cushion", "models": [
            {"model": "Stronge", "default": True, "us_per_collision": cushion_us, "first_call_s": 0.05},
            {"model": "NeedsArgs", "default": False, "us_per_collision": None, "first_call_s": None,
             "why": "needs arguments pooltool has no default for"}]}}}
    return rep


def test_pooltool_rows_divide_its_default_model_by_our_batch_per_scene() -> None:
    """pooltool's default model (not its fastest) per collision over our µs per scene through auto: 40 µs against
    5e5 scenes/s (2 µs) is 20×, short of 100×; 500 µs against 1e7 scenes/s (0.1 µs) is 5000×."""
    rep = _with_pooltool(_report({}, rate=5e5, err=0.0, make_all=None), 40.0, 500.0, 1e7)
    got = {t.what: t for t in targets.rows(rep)}
    bb, cu = got["pooltool ÷ ours: ball–ball"], got["pooltool ÷ ours: cushion"]
    assert math.isclose(bb.now, 20.0) and bb.met is False and "FrictionalInelastic" in bb.source
    assert math.isclose(cu.now, 5000.0) and cu.met is True
    lines = targets.to_markdown([t.as_dict() for t in got.values()], None, rep["pooltool"])
    assert "| ball–ball | spheres-cloth | FrictionalInelastic (its default) | 40 | 9.5 |" in lines
    assert "| cushion | cushion-impact | NeedsArgs | — | — |" in lines
    assert max(len(ln) for ln in targets.terminal_lines([t.as_dict() for t in got.values()], None)) <= 80


def test_a_pooltool_figure_missing_is_not_measured_and_pooltool_absent_is_said() -> None:
    rep = _with_pooltool(_report({}, rate=5e5, err=0.0, make_all=None), None, 500.0, 1e7)
    got = {t.what: t for t in targets.rows(rep)}
    assert (got["pooltool ÷ ours: ball–ball"].now, got["pooltool ÷ ours: ball–ball"].met) == (None, None)
    assert any("pooltool is not installed here" in ln for ln in targets.to_markdown([], None, None))


def test_pooltool_is_measured_only_where_it_is_installed(monkeypatch) -> None:
    import importlib.util

    from reproductions import pooltool_side

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "pooltool" else real(name, *a))
    assert pooltool_side.measure(repeat=1) is None and pooltool_side.version() is None


def test_a_figure_next_to_its_target_is_shown_apart_from_it() -> None:
    """60.04 µs against ≤ 60 µs is a miss: shown with the digits that tell it from 60, never as "60 … no"."""
    rep = _report({"spheres-cloth": 60.04, "spheres-free": 60.0}, rate=1.0, err=0.0, make_all=None)
    got = {t.what: t.as_dict() for t in targets.rows(rep)}
    miss = targets.terminal_lines([got["one scene: two balls on the cloth"]], None)[-1]
    tie = targets.terminal_lines([got["one scene: two free balls"]], None)[-1]
    assert "60.04 µs" in miss and miss.endswith("no"), miss
    assert " 60 µs" in tie and tie.endswith("yes"), tie
