"""The figures as a reader sees them: every figure says what it shows (``reading``), its text is English with
decimal points, signed maps are diverging around zero, nothing is cut by the figure's edge, and the fixes of the
reader's edition hold (category ticks, smooth zero curves, one colour per stroke height and per benchmark method,
the cue ball's deflection once rolling, markers on the frame drawn whole)."""

import dataclasses
import math
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.colors import TwoSlopeNorm

from reproductions import api, bench, report
from reproductions.experiments import ballball
from reproductions.mechanics import registry
from reproductions.results import FigureSpec, Layer, layer

DECIMAL_COMMA = re.compile(r"\d,\d")


@pytest.fixture(scope="module")
def figures(runs) -> dict[str, tuple[FigureSpec, ...]]:
    """Every experiment's figures, by experiment id."""
    return {eid: rep.figures for eid, rep in runs.items()}


def _all(figures):
    return [(eid, f) for eid, figs in figures.items() for f in figs]


def _by_name(figures, eid: str, name: str) -> FigureSpec:
    return next(f for f in figures[eid] if f.name == name)


def _panels(spec: FigureSpec) -> tuple[FigureSpec, ...]:
    return spec.panels or (spec,)


def _layers(spec: FigureSpec) -> list[Layer]:
    return [ly for p in _panels(spec) for ly in p.layers]


def _texts(spec: FigureSpec) -> list[str]:
    """Every piece of text a figure shows or carries: title, caption, labels, ticks, keys, panels, its reading."""
    out = [spec.title, spec.caption, spec.xlabel, spec.ylabel, spec.reading, *spec.xticklabels, *spec.yticklabels]
    for p in spec.panels:
        out += _texts(p)
    return out + [ly.label for ly in spec.layers]


def test_every_figure_has_a_reading_that_is_not_its_title(figures):
    assert sum(len(f) for f in figures.values()) >= 19
    for eid, f in _all(figures):
        text = f.reading.strip()
        assert text, (eid, f.name)
        assert text.rstrip(".").lower() != f.title.strip().rstrip(".").lower(), (eid, f.name)
        assert f.title not in text, (eid, f.name, "the reading repeats the title")
        assert len(text) >= 80 and text.endswith("."), (eid, f.name, text)


def test_no_decimal_comma_in_any_figure_text(figures):
    for eid, f in _all(figures):
        bad = [t for t in _texts(f) if DECIMAL_COMMA.search(t)]
        assert not bad, (eid, f.name, bad)


def test_no_french_left_in_the_figures(figures):
    for eid, f in _all(figures):
        bad = [t for t in _texts(f) if re.search(r"fausse queue|rétrograde|bille|tapis", t, re.I)]
        assert not bad, (eid, f.name, bad)


def test_every_signed_heatmap_is_diverging_and_centred_on_zero(figures):
    """A map whose values take both signs, the sign being the message, uses a diverging map centred on 0 (a map of
    log10 of an error takes both signs too, but its sign means nothing: it stays sequential)."""
    seen = 0
    for eid, f in _all(figures):
        for ly in _layers(f):
            if ly.kind != "heatmap":
                continue
            z = np.asarray(ly.z, dtype=float)
            if np.nanmin(z) < 0 < np.nanmax(z) and not ly.label.startswith("log10"):
                assert ly.centre == 0.0, (eid, f.name, ly.label)
                seen += 1
    assert seen >= 1  # the retrograde region of the cue


def test_a_centred_heatmap_is_drawn_with_a_two_slope_norm_at_its_centre():
    z = np.array([[-1.0, 0.5], [2.0, 3.0]])
    spec = FigureSpec("t", "t", "x", "y", (layer("heatmap", [0, 1], [0, 1], z=z, label="signed", centre=0.0),
                                            layer("contour", [0, 1], [0, 1], z=z, label="zero", color="k")))
    fig = report._render(spec)
    try:
        norm = fig.axes[0].images[0].norm
        assert isinstance(norm, TwoSlopeNorm) and norm.vcenter == 0.0
        assert (norm.vmin, norm.vmax) == (-1.0, 3.0)
        assert fig.axes[0].collections, "the zero contour is drawn"
        assert "zero" in fig.axes[0].get_legend_handles_labels()[1]
    finally:
        plt.close(fig)


def test_grid_layers_match_their_grid_and_panels_hold_the_layers(figures):
    for eid, f in _all(figures):
        assert not (f.panels and f.layers), (eid, f.name)
        assert all(p.layers for p in _panels(f)), (eid, f.name)
        if f.heights:
            assert len(f.heights) == -(-len(_panels(f)) // f.columns), (eid, f.name)
        for ly in _layers(f):
            if ly.kind in ("heatmap", "contour"):
                assert np.shape(ly.z) == (len(ly.y), len(ly.x)), (eid, f.name, ly.label)
            if ly.kind == "line" and ly.x:
                assert len(ly.x) == len(ly.y), (eid, f.name, ly.label)
        for p in _panels(f):
            if p.yscale == "log":
                assert all(min(ly.y) > 0 for ly in p.layers if ly.y), (eid, f.name)


def test_estimators_name_the_surfaces_on_the_ticks(figures):
    f = _by_name(figures, "roze-ricochets", "estimators")
    surfaces = api.load("roze-ricochets").params.surfaces
    assert [t.replace("\n", " ") for t in f.xticklabels] == [s.name for s in surfaces]
    assert not any(s.id in f.xlabel for s in surfaces)
    assert f.xlim == (-0.5, len(surfaces) - 0.5)


def test_the_error_map_of_eq9_speaks_of_eq9(figures):
    f = _by_name(figures, "roze-ricochets", "error-eq9")
    assert "(9)" in f.caption and "(8) is exact" not in f.caption
    assert "(9)" in f.reading


def test_retrograde_region_zero_curves_are_contours_of_the_map(figures):
    f = _by_name(figures, "cue-stroke", "retrograde-region")
    (heat,) = [ly for ly in f.layers if ly.kind == "heatmap"]
    contours = [ly for ly in f.layers if ly.kind == "contour"]
    assert heat.centre == 0.0
    assert any(ly.z == heat.z for ly in contours), "the zero of the map itself is drawn"
    assert any("χ1 = 0" in ly.label for ly in contours), "χ1 = 0 is a contour, not a staircase of cells"
    assert not [ly for ly in f.layers if ly.kind == "line"]


def test_strokes_tell_inclination_and_height_apart(figures):
    f = _by_name(figures, "cue-stroke", "strokes")
    p = api.load("cue-stroke").params
    assert len(f.panels) == len(p.fan_inclinations)
    for panel, i in zip(f.panels, p.fan_inclinations, strict=True):
        assert f"{math.degrees(i):.0f}°" in panel.title
        paths = [ly for ly in panel.layers if ly.kind == "line" and ly.x]
        assert len(paths) == len(p.fan_heights)
        assert len({ly.color for ly in paths}) == len(p.fan_heights), "one colour per height"
        assert {ly.style for ly in paths} <= {"-", "--"}
    keys = [ly.label for ly in _layers(f) if ly.label]
    assert len([k for k in keys if k.startswith("c/R")]) == len(p.fan_heights)
    assert {"direct", "retrograde"} <= set(keys)


def test_the_cue_ball_deflection_once_rolling_is_the_closed_form_of_the_30_degree_rule():
    """Elastic, frictionless balls: the cue ball leaves along the tangent line with its rolling spin, and the cloth
    turns it to (V cos c/(1 + k), V sin c); at a half-ball hit (30°) that is 33.7° from its path."""
    p = dataclasses.replace(api.load("ball-ball").params, f=0.0, eps=0.0)
    cut = np.radians(np.array([10.0, 30.0, 60.0]))
    out = ballball._cut_outcomes(p, cut, "exact")
    want = np.degrees(np.arctan2(np.sin(cut), np.cos(cut) / (1 + p.k)) - cut)
    np.testing.assert_allclose(out["rolling"], want, atol=1e-9)
    assert out["rolling"][1] == pytest.approx(33.67, abs=0.01)


def test_cut_figures_show_the_rolling_ball_and_the_difference_of_the_two_methods(figures):
    angles = _by_name(figures, "ball-ball", "cut-angles")
    speeds = _by_name(figures, "ball-ball", "cut-speeds")
    for f in (angles, speeds):
        assert len(f.panels) == 2 and "exact" in f.panels[1].ylabel
        assert any("once rolling" in ly.label for ly in f.panels[0].layers)
        assert any("just after the impact" in ly.label for ly in f.panels[0].layers)
    assert any("30° rule" in ly.label for ly in angles.panels[0].layers)
    assert "turn" in angles.caption


def test_markers_on_the_frame_are_drawn_whole(figures):
    fig = report._render(_by_name(figures, "coriolis-pendulum", "pendulum"))
    try:
        ax = fig.axes[0]
        edge = [ln for ln in ax.lines if ln.get_linestyle() == "None" and 0.0 in ln.get_ydata()]
        assert edge and all(not ln.get_clip_on() for ln in edge)
    finally:
        plt.close(fig)


def test_no_text_is_cut_by_the_figures_edge(figures):
    for eid, f in _all(figures):
        fig = report._render(f)
        try:
            r = fig.canvas.get_renderer()
            W, H = fig.bbox.width, fig.bbox.height
            boxes = [b for a in fig.axes for b in (a.xaxis.get_tightbbox(r), a.yaxis.get_tightbbox(r)) if b is not None]
            boxes += [leg.get_window_extent(r) for leg in fig.legends]
            boxes += [a.get_legend().get_window_extent(r) for a in fig.axes if a.get_legend() is not None]
            titles = [a.title for a in fig.axes] + list(fig.texts) + [fig._suptitle]
            boxes += [t.get_window_extent(r) for t in titles if t is not None and t.get_text()]
            for b in boxes:
                assert b.x0 >= -0.5 and b.y0 >= -0.5 and b.x1 <= W + 0.5 and b.y1 <= H + 0.5, (eid, f.name, b)
        finally:
            plt.close(fig)


def test_new_figure_kinds_are_drawn_byte_for_byte_the_same_twice(figures, tmp_path):
    chosen = [_by_name(figures, "cue-stroke", "strokes"), _by_name(figures, "cue-stroke", "retrograde-region"),
              _by_name(figures, "ball-ball", "cut-angles"), _by_name(figures, "roze-ricochets", "estimators")]
    for run in ("a", "b"):
        (tmp_path / run).mkdir()
        for f in chosen:
            report.draw_figure((f, tmp_path / run))
    for f in chosen:
        for ext in ("png", "pdf"):
            name = f"{f.name}.{ext}"
            assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes(), name


def _fake_model_report(name: str) -> dict:
    """A model's entry of the bench report with made-up numbers (the figure only draws them)."""
    m = registry.MODELS[name]
    paths = [{"path": p.name, "kind": p.kind.value, "seconds_per_scene": 1e-6 * (i + 1),
              "all_scenes": {"max_error": 10.0 ** -(i + 3)}} for i, p in enumerate(m.paths)]
    paths.append({"path": "auto", "kind": "auto", "seconds_per_scene": 2e-6, "all_scenes": {"max_error": 1e-12}})
    grid = [{"solver": s, "rtol": r, "max_error": r, "seconds_per_scene": 1e-3 / r ** 0.1}
            for s in bench.FULL["solvers"] for r in bench.FULL["rtols"]]
    return {"model": name, "paths": paths, "ode_grid": grid}


@pytest.mark.parametrize("name", list(registry.MODELS))
def test_bench_figures_give_each_method_its_own_colour_and_say_what_the_error_measures(name):
    fig = bench._work_precision_figure(plt, _fake_model_report(name), bench.FULL["rtols"])
    try:
        ax = fig.axes[0]
        drawn = [ln for ln in ax.lines if not ln.get_label().startswith("_")]
        assert len(drawn) == len(registry.MODELS[name].paths) + 1 + len(bench.FULL["solvers"])
        looks = [(matplotlib.colors.to_hex(ln.get_markerfacecolor(), keep_alpha=True), ln.get_marker())
                 for ln in drawn]
        assert len(set(looks)) == len(looks), looks
        colours = [matplotlib.colors.to_hex(ln.get_color()) for ln in drawn if ln.get_label() != "auto (auto)"]
        assert len(set(colours)) == len(colours), colours
        xlabel = ax.get_xlabel()
        assert "model's measure" not in xlabel and " over " in xlabel
        assert name in bench._MEASURES
    finally:
        plt.close(fig)
