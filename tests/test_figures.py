"""The figures as a reader sees them: every figure says what it shows (``reading``), its text is English with
decimal points, signed maps are diverging around zero, nothing is cut by the figure's edge, and the fixes of the
reader's edition hold (category ticks, smooth zero curves, one colour per stroke height and per benchmark method,
the cue ball's deflection once rolling, markers on the frame drawn whole). Issue 32: every text is legible on a
phone (at least 9 CSS px tall with the figure 375 px wide), minus signs are real ones, paths in a plane are drawn
at equal scales, the ricochets are one figure of panels, impact-law has its figure, the error map of (9) shows
where (9) holds, a published slope never runs below zero speed, and the benchmark's figure counts what its table
counts."""

import dataclasses
import math
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.colors import LogNorm, TwoSlopeNorm

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
    assert sum(len(f) for f in figures.values()) >= 23
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


def test_the_error_map_of_eq9_shows_where_eq9_holds(figures):
    """Issue 32: the map was one colour over most of the panel. On logarithmic axes and a logarithmic colour scale,
    with the line of Rozé's two digits (the tolerance of row eq9_beyond) drawn, the corner where (9) holds shows:
    the map spans several decades and the line crosses it."""
    f = _by_name(figures, "roze-ricochets", "error-eq9")
    (heat,) = [ly for ly in f.layers if ly.kind == "heatmap"]
    assert heat.norm == "log" and f.xscale == f.yscale == "log"
    z = np.asarray(heat.z)
    assert np.log10(z.max() / z.min()) > 3
    tolerance = next(p.tolerance for p in api.load("roze-ricochets").printed if p.computed == "eq9_beyond")
    holds = float(np.mean(z <= tolerance))
    assert 0.2 < holds < 0.8, holds  # a region of its own, not a sliver at the edge
    lines = [ly for ly in f.layers if ly.kind == "contour" and f"{tolerance * 100:g} %" in ly.label]
    assert lines and np.asarray(lines[0].z).min() < 0 < np.asarray(lines[0].z).max()
    fig = report._render(f)
    try:
        ax = fig.axes[0]
        assert ax.get_xscale() == ax.get_yscale() == "log"
        assert isinstance(ax.collections[0].norm, LogNorm)
        assert "error" in fig.axes[1].get_ylabel()  # the colour bar says what the colours are
    finally:
        plt.close(fig)


def test_retrograde_region_zero_curves_are_contours_of_the_map(figures):
    f = _by_name(figures, "cue-stroke", "retrograde-region")
    (heat,) = [ly for ly in f.layers if ly.kind == "heatmap"]
    contours = [ly for ly in f.layers if ly.kind == "contour"]
    assert heat.centre == 0.0
    assert any(ly.z == heat.z for ly in contours), "the zero of the map itself is drawn"
    assert any("$\\chi_1$ = 0" in ly.label for ly in contours), "χ1 = 0 is a contour, not a staircase of cells"
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
              "where_exact": {"max_error": 10.0 ** -(i + 3)}, "all_scenes": {"max_error": 10.0 ** -(i + 3)}}
             for i, p in enumerate(m.paths)]
    paths.append({"path": "auto", "kind": "auto", "seconds_per_scene": 2e-6, "where_exact": {"max_error": 1e-12},
                  "all_scenes": {"max_error": 1e-12}})
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


# ---- issue 32: every figure fixed, and legible at phone width -----------------------------------------------------

INDEX = re.compile(r"(?<![\w$\\′])[A-Za-zα-ωΑ-Ω]′?\d(?![\d.,]?\d)")  # α1, V0, h1: a symbol and its index, unscripted
ASCII_GREEK = re.compile(r"\b(alpha|beta|gamma|delta|psi|phi|chi|eps|epsilon|nu|mu|deg)\d*\b")


def _drawn_texts(fig) -> list:
    """Every text artist the figure draws (titles, labels, tick labels, keys, annotations, colour bars), drawn once
    so that the axes have made their ticks."""
    fig.canvas.draw()
    return [t for t in fig.findobj(matplotlib.text.Text) if t.get_visible() and t.get_text().strip()]


def _too_small(fig) -> list[tuple[str, float]]:
    """The texts smaller than MIN_TEXT_PX CSS px when the figure is shown PHONE_WIDTH_PX px wide: (text, px)."""
    scale = report.PHONE_WIDTH_PX / (72.0 * fig.get_figwidth())  # CSS px per point
    return [(t.get_text()[:40], round(t.get_fontsize() * scale, 2)) for t in _drawn_texts(fig)
            if t.get_fontsize() * scale < report.MIN_TEXT_PX - 1e-9]


def _outside_math(text: str) -> str:
    """The text without its mathtext spans, and without names of readings such as (c1)."""
    return re.sub(r"\$[^$]*\$|\([a-z]\d\)", " ", text)


def test_the_legibility_rule_is_the_one_of_the_issue():
    """A font of s pt on a figure W in wide shown 375 px wide is s·375/(72·W) px: 9 px needs s ≥ 1.728·W."""
    assert (report.PHONE_WIDTH_PX, report.MIN_TEXT_PX) == (375, 9.0)
    assert report.min_font_pt(6.4) == pytest.approx(11.06, abs=0.01)
    assert report.min_font_pt(report._FIG_W) <= min(report.FONT.values())


def test_every_text_of_every_figure_is_legible_at_phone_width_with_real_minus_signs(figures, monkeypatch, tmp_path):
    """The hook is the figures' writer: ``report.draw_figure`` (what ``resal reproduce`` runs for every figure)
    with ``Figure.savefig`` replaced by a check of every text artist of the figure it would save, as it would save
    it: each at least MIN_TEXT_PX tall at phone width, and no hyphen for a minus (tick labels get U+2212 from
    axes.unicode_minus, our texts from ``report.minus_signs``)."""
    from matplotlib.figure import Figure

    checked, small, hyphens, negative = [], [], [], []

    def check(fig, fname, *args, **kwargs):
        if str(fname).endswith(".pdf"):  # the same figure as the PNG just checked
            return
        checked.append(str(fname))
        small.extend((str(fname), *t) for t in _too_small(fig))
        texts = [t.get_text() for t in _drawn_texts(fig)]
        hyphens.extend((str(fname), t) for t in texts if re.search(r"(^|[\s(=/,;:\[])-\.?\d", _outside_math(t)))
        negative.extend(t for t in texts if t.startswith("−"))

    monkeypatch.setattr(Figure, "savefig", check)
    for eid, f in _all(figures):
        report.draw_figure((f, tmp_path / eid))
    assert len(checked) == sum(len(f) for f in figures.values())
    assert not small, small
    assert not hyphens, hyphens
    assert negative  # some axis does go below zero, and says so with a minus sign


def test_minus_signs_are_made_real_ones():
    assert report.STYLE["axes.unicode_minus"] is True
    assert report.minus_signs("trend -0.12, 1e-6, ball-ball, -x, $x-1$") == "trend −0.12, 1e−6, ball-ball, -x, $x-1$"


@pytest.mark.parametrize("name", list(registry.MODELS))
def test_the_bench_figures_are_legible_at_phone_width(name):
    with report.figure_style():
        fig = bench._work_precision_figure(plt, _fake_model_report(name), bench.FULL["rtols"])
        try:
            assert not _too_small(fig)
            r = fig.canvas.get_renderer()
            for box in [a.get_tightbbox(r) for a in fig.axes] + [leg.get_window_extent(r) for leg in fig.legends]:
                assert box.x0 >= -0.5 and box.x1 <= fig.bbox.width + 0.5, (name, box)
        finally:
            plt.close(fig)


def test_symbols_with_an_index_are_subscripts_in_what_the_figures_draw(figures):
    """Axis labels, keys, captions, panel titles and tick labels write α1 as $\\alpha_1$ (mathtext: a subscript
    1), never α1 or ASCII alpha1 (deg); the titles and readings stay plain text (the edition shows them as HTML)."""
    for eid, f in _all(figures):
        drawn = [f.caption, f.xlabel, f.ylabel, *f.xticklabels, *f.yticklabels]
        for p in _panels(f):
            drawn += [p.xlabel, p.ylabel, p.title if f.panels else "", *(ly.label for ly in p.layers)]
        for text in drawn:
            plain = _outside_math(text)
            assert not INDEX.search(plain), (eid, f.name, text)
            assert not ASCII_GREEK.search(plain), (eid, f.name, text)
        assert "$" not in f.title + f.reading, (eid, f.name)


def test_cloth_slide_paths_are_drawn_at_equal_scales(figures):
    """Euler's parabolas undistorted: a metre along x is as long on the page as a metre along y."""
    f = _by_name(figures, "cloth-slide", "trajectories")
    assert f.aspect == "equal"
    fig = report._render(f)
    try:
        fig.canvas.draw()
        ax = fig.axes[0]
        (x0, y0), (x1, _), (_, y2) = ax.transData.transform([(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)])
        assert x1 - x0 == pytest.approx(y2 - y0, rel=1e-6)
        # and the axes are not a strip: the figure is made as tall as the paths need
        assert 0.6 < ax.bbox.height / ax.bbox.width < 1.4
        paths = [ly for ly in f.layers if ly.kind == "line"]
        lo, hi = ax.get_ylim()
        assert lo <= min(min(ly.y) for ly in paths) and max(max(ly.y) for ly in paths) <= hi
    finally:
        plt.close(fig)


def test_the_published_slope_of_the_head_on_speeds_never_runs_below_zero(figures):
    """Issue 32: the cue ball's published acceleration, extended back to the impact, ran to −0.03 m/s at t = 0.
    It is drawn from where its speed is zero (or the impact) to the published sliding time, then level."""
    f = _by_name(figures, "modern-head-on", "head-on-speeds")
    published = [ly for ly in f.layers if ly.kind == "line" and ly.style == "--" and ly.x]
    assert len(published) == 2
    for ly in published:
        assert min(ly.y) >= 0.0 and min(ly.x) >= 0.0
        assert ly.y[1] == ly.y[2]  # level after the sliding time
    cue = min(published, key=lambda ly: ly.y[-1])  # the cue ball ends slower
    assert cue.x[0] > 0.0 and cue.y[0] == pytest.approx(0.0, abs=1e-12)
    fig = report._render(f)
    try:
        drawn = [ln for ln in fig.axes[0].lines if ln.get_linestyle() == "--" and len(ln.get_xdata())]
        assert drawn and min(min(ln.get_ydata()) for ln in drawn) >= 0.0
    finally:
        plt.close(fig)


def test_the_ricochets_are_one_figure_with_a_panel_per_surface_two_a_row(figures):
    names = [f.name for f in figures["roze-ricochets"]]
    assert "ricochets" in names and not [n for n in names if n.startswith("ricochet-")]
    f = _by_name(figures, "roze-ricochets", "ricochets")
    surfaces = api.load("roze-ricochets").params.surfaces
    assert [p.name for p in f.panels] == [f"ricochet-{s.id}" for s in surfaces]
    assert f.columns == 2 and f.sharey and f.legend == "below"
    assert all(s.name in p.title for s, p in zip(surfaces, f.panels, strict=True))
    fig = report._render(f)
    try:
        boxes = [a.get_position() for a in fig.axes]
        assert len(boxes) == 4
        assert len({round(b.x0, 3) for b in boxes}) == 2 and len({round(b.y0, 3) for b in boxes}) == 2  # 2 × 2
    finally:
        plt.close(fig)
    # every finding's figure names a figure the experiment draws (a config names a figure by its file's stem)
    for eid, figs in figures.items():
        drawn = {g.name for g in figs}
        for finding in api.load(eid).findings:
            assert finding.figure is None or finding.figure in drawn, (eid, finding.id, finding.figure)


def test_impact_law_has_a_figure_of_what_its_rows_check(figures):
    """The vis viva lost in sphere–plane impacts by eq. (6) against the exact impact (rows n4_sliding,
    n4_slip_stops, vis_viva_decreases), with n°5's measured rebounds; finding slip-stops points to it."""
    (f,) = figures["impact-law"]
    assert f.name == "vis-viva-lost" and f.title and len(f.reading) >= 80
    points = [ly for ly in f.layers if ly.kind == "points"]
    sliding, stops = (next(ly for ly in points if key in ly.label) for key in ("lasts", "stops"))
    np.testing.assert_allclose(sliding.y, sliding.x, atol=1e-12)  # the law is exact while the slip lasts
    assert max(abs(np.asarray(stops.y) - np.asarray(stops.x))) > 0.5  # and not where it stops
    assert min(sliding.x + stops.x) >= 0.0  # no impact gains vis viva
    measured = next(ly for ly in points if "n°5" in ly.label)
    assert measured.x == pytest.approx((1 - 0.55**2, 1 / 3))
    finding = next(x for x in api.load("impact-law").findings if x.id == "slip-stops")
    assert finding.figure == "vis-viva-lost"


def test_the_interval_of_the_coriolis_series_can_be_seen(figures):
    """The 95 % interval of ε, invisible on the speeds, is drawn on each point's ratio too, where it is wide, and
    named in the key."""
    f = _by_name(figures, "coriolis-cushion", "series")
    assert any(ly.kind == "band" and ly.label for ly in f.panels[0].layers)
    fig = report._render(f)
    try:
        fig.canvas.draw()
        ratio = fig.axes[1]
        (band,) = [c for c in ratio.collections if c.get_paths()]
        height = band.get_window_extent().height / fig.dpi
        assert height > 0.15, height  # inches
        assert band.get_edgecolor().size and band.get_facecolor()[0][3] > 0.2  # edged, not faint
        assert "95 % interval of ε" in [t.get_text() for t in fig.legends[0].get_texts()]
    finally:
        plt.close(fig)


def test_the_bench_figure_counts_what_its_table_counts():
    """A path's dot is its error where it declares itself exact (bench.md's "max error where exact"); its error
    over all the scenes it handles, where larger, is an open ring of its colour; the axis says which is which."""
    mod = _fake_model_report("ricochet")
    resal = next(p for p in mod["paths"] if p["path"] == "resal")
    resal["where_exact"]["max_error"], resal["all_scenes"]["max_error"] = 6e-16, 0.3
    with report.figure_style():
        fig = bench._work_precision_figure(plt, mod, bench.FULL["rtols"])
    try:
        ax = fig.axes[0]
        (dot,) = [ln for ln in ax.lines if ln.get_label().startswith("resal")]
        assert dot.get_xdata()[0] == pytest.approx(6e-16)
        rings = [ln for ln in ax.lines if ln.get_marker() == "o" and ln.get_markerfacecolor() == "none"
                 and list(ln.get_xdata()) == [0.3]]
        assert rings and rings[0].get_color() == dot.get_color()
        assert "where the path declares itself exact" in ax.get_xlabel().replace("\n", " ")
        assert "over all scenes, where larger" in [t.get_text() for t in fig.legends[0].get_texts()]
    finally:
        plt.close(fig)


def test_pngs_are_written_for_screens_of_several_pixels_per_css_pixel(figures, tmp_path):
    """Twice the former 120 dpi: crisp on a phone that shows the figure 375 CSS px wide at 3 device px each."""
    from PIL import Image

    f = _by_name(figures, "marble-drop", "height-vs-eps")
    report.draw_figure((f, tmp_path))
    with Image.open(tmp_path / f"{f.name}.png") as im:
        assert im.width >= 3 * report.PHONE_WIDTH_PX and report._DPI >= 2 * 120
        assert im.width == round(report._FIG_W * report._DPI)
