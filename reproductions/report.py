"""Reproductions → ``summary.json`` (the machine-readable truth) and its renderings: tables, figures, index.

Every experiment is written into a staging folder beside its final place and swapped in only when
complete, so an error or an interruption leaves earlier results untouched. Staging names start with
``.resal-<host>-<pid>-`` so that a later run can remove what a killed one left (``clean_stale``). Folders and
files are made with a plain ``mkdir``/``open`` (never ``mkdtemp``/``mkstemp``, which make them private), so
they get the user's umask. Output is deterministic: stable key order, ``repr`` floats, figures without time
stamps or software versions.
"""

from __future__ import annotations

import csv
import errno
import hashlib
import io
import json
import math
import os
import platform
import re
import secrets
import shutil
import socket
import subprocess
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import AbstractContextManager, contextmanager
from dataclasses import asdict
from pathlib import Path
from typing import Any, BinaryIO

from . import __version__, digest, processes
from .config import MEASUREMENT_VERDICTS, REASON_GROUP_LABELS, REASON_GROUPS, REASONS
from .errors import ComputationError, InputError
from .results import FigureSpec, Reproduction

__all__ = [
    "MANIFEST",
    "beyond_counts",
    "beyond_text",
    "changed_by_hand",
    "clean_stale",
    "code_provenance",
    "dangling_link",
    "foreign_files",
    "index_md",
    "is_beyond",
    "make_staging",
    "paper_order",
    "paper_rows",
    "parse_source",
    "provenance",
    "read_manifest",
    "remove_staging",
    "row_cells",
    "signals_deferred",
    "staging_folder",
    "staging_name",
    "summary",
    "summary_problem",
    "today_value",
    "verdict_counts",
    "whose_error",
    "whose_error_text",
    "write_folder",
    "write_reproduction",
]

HEADERS = ("quantity", "§ / eq.", "line", "printed", "computed", "difference", "verdict", "reason", "note")
_TEX_COLS = 8  # the LaTeX table leaves out the note


def code_provenance() -> dict[str, Any]:
    """Version, git commit (and whether the tree was dirty), Python, and the versions of the runtime dependencies
    (pyproject.toml's, as installed: requirements.lock pins them), numpy's and scipy's also at the top level."""
    from importlib import metadata

    deps: dict[str, str | None] = {}
    for name in ("numpy", "scipy", "matplotlib", "rich", "typer", "PyYAML", "typst", "latex2mathml"):
        try:
            deps[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            deps[name] = None
    root = Path(__file__).resolve().parent.parent
    commit, dirty = None, None
    if (root / ".git").exists():  # a checkout's own commit only: a wheel's site-packages may lie in another repo
        try:
            commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True,
                                    timeout=5).stdout.strip() or None
            if commit:
                status = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=root,
                                        capture_output=True, text=True, timeout=5).stdout
                dirty = bool(status.strip())
        except (OSError, subprocess.SubprocessError):
            pass
    return {"version": __version__, "git_commit": commit, "dirty": dirty, "python": platform.python_version(),
            "numpy": deps["numpy"], "scipy": deps["scipy"], "dependencies": deps}


def provenance(rep: Reproduction) -> dict[str, Any]:
    """Version, git commit, config hash, library versions and the digest of what the folder is computed from
    (``digest.record``: a later run with the same digest reuses the folder); golden comparisons ignore this block."""
    c = code_provenance()
    return {"version": c["version"], "git_commit": c["git_commit"], "dirty": c["dirty"], "config": rep.experiment.path,
            "config_sha256": rep.experiment.sha256, "python": c["python"], "numpy": c["numpy"], "scipy": c["scipy"],
            "dependencies": c["dependencies"], "seed": rep.experiment.seed,
            "digest": digest.record(rep.experiment.sha256, rep.experiment.params)}


def _figure_files(rep: Reproduction) -> list[str]:
    return [f"{f.name}.{ext}" for f in rep.figures for ext in ("png", "pdf")]


def summary(rep: Reproduction, prov: dict[str, Any] | None = None) -> dict[str, Any]:
    """The ``summary.json`` object (schema in ARCHITECTURE.md)."""
    e = rep.experiment
    return {
        "experiment": e.id,
        "title": e.title,
        "kind": e.kind,
        "source": {"section": e.source.section, "page": e.source.page, "equations": list(e.source.equations)},
        "data_note": rep.data_note,
        "rows": [{k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(r).items()} for r in rep.rows],
        "fits": [{k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(f).items()} for f in rep.fits],
        "identifiability": [dict(i) for i in rep.identifiability],
        "tables": [{"name": t.name, "title": t.title, "headers": list(t.headers), "rows": [list(r) for r in t.rows],
                    "note": t.note} for t in rep.tables],
        "modern": [dict(m) for m in rep.modern],
        "figures": _figure_files(rep),
        "figure_captions": [{"png": f"{f.name}.png", "title": f.title, "caption": f.reading} for f in rep.figures],
        "notes": list(e.notes),
        "question": e.question,
        "findings": [{"id": f.id, "category": f.category, "consequence": f.consequence, "text": f.text,
                      "rows": list(f.rows), "figure": f.figure,
                      "config_line": int(f.where.rsplit(":", 1)[1]) if ":" in f.where else None}
                     for f in e.findings],
        "provenance": prov if prov is not None else {},
    } | ({"measurements": [{k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(m).items()}
                           for m in rep.measurements]} if rep.measurements else {})


def _fmt(v: Any, digits: int = 6) -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        return f"{v:.{digits}g}"
    return str(v)


def _rel(v: float | None) -> str:
    return "—" if v is None else f"{v:+.2%}"


# what a row without a printed text shows people (its `text` is "": the paper prints nothing for it)
NOT_PRINTED = "— (not printed: an implicit premise, or a form derived here)"


def printed_text(r: dict[str, Any]) -> str:
    """A row's printed text for people: the paper's own writing, or ``NOT_PRINTED``."""
    return r["printed_text"] or NOT_PRINTED


def row_cells(r: dict[str, Any]) -> list[str]:
    """A row's cells for people (HEADERS): a formula's computed number named a discrepancy, the difference relative,
    or absolute where the paper prints zero (``computed_text``, ``difference_text``)."""
    return [r["quantity"], r["source"], _fmt(r.get("line")), printed_text(r), computed_text(r),
            difference_text(r), r["verdict"], r.get("reason") or "", r["note"]]


MEASUREMENT_HEADERS = ("quantity", "source", "measured", "uncertainty", "predicted", "95 % interval", "verdict",
                       "note")


def interval_text(m: dict[str, Any]) -> str:
    """A prediction's 95 % interval for people, "—" when there is none."""
    iv = m.get("interval")
    return "—" if not iv else f"[{_fmt(iv[0], 4)}, {_fmt(iv[1], 4)}]"


def measurement_cells(m: dict[str, Any]) -> list[str]:
    """A measured row's cells for people (MEASUREMENT_HEADERS): the measurement as published with its uncertainty,
    the prediction of the paper's mechanics with its interval, the verdict at 95 %."""
    return [m["quantity"], m["source"], m["measured_text"] or _fmt(m["measured"]), m["uncertainty"],
            _fmt(m["predicted"], 4), interval_text(m), m["verdict"], m["note"]]


def _fit_cells(f: dict[str, Any]) -> list[str]:
    ci = f["ci95"]
    ci_s = "—" if ci[0] is None else f"[{_fmt(ci[0], 4)}, {_fmt(ci[1], 4)}]"
    return [f["parameter"], _fmt(f["value"]), _fmt(f["stderr"], 3), ci_s, "yes" if f["identifiable"] else "no",
            f["note"]]


def _md_escape(s: str) -> str:
    return s.replace("|", "\\|").replace("\n", " ")


def _md_table(headers: Iterable[str], rows: Iterable[list[str]]) -> str:
    h = list(headers)
    lines = ["| " + " | ".join(h) + " |", "|" + "---|" * len(h)]
    lines += ["| " + " | ".join(_md_escape(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def table_md(s: dict[str, Any]) -> str:
    src = s["source"]
    out = [f"# {s['title']}\n", f"Résal (1883), {src['section']}, p. {src['page']}, eqs {', '.join(src['equations'])}."
           f" Experiment `{s['experiment']}`.\n"]
    if s["data_note"]:
        out.append(f"Data: {s['data_note']}\n")
    if s["rows"] or not s.get("measurements"):
        out.append("## Printed values\n")
        out.append(_md_table(HEADERS, (row_cells(r) for r in s["rows"])))
    if s.get("measurements"):
        out.append("\n## Today's measurements against the paper's mechanics\n")
        out.append("Verdicts at 95 %, the measurement's uncertainty and the prediction's interval both counted "
                   "(fitted: the measurement fixed a parameter and tests nothing).\n")
        out.append(_md_table(MEASUREMENT_HEADERS, (measurement_cells(m) for m in s["measurements"])))
    if s["fits"]:
        out.append("\n## Fits\n")
        out.append(_md_table(("parameter", "value", "std. error", "95 % interval", "identifiable", "note"),
                             (_fit_cells(f) for f in s["fits"])))
    for i in s.get("identifiability", []):
        sv = ", ".join(f"{v:.3g}" for v in i["singular_values"])
        text = (f"Parameters {', '.join(i['parameters'])}; {i['n_data']} residuals; singular values of the "
                f"Jacobian {sv}; rank {i['rank']} of {len(i['parameters'])}.")
        if i["null_directions"]:
            nd = "; ".join("(" + ", ".join(f"{v:.4g}" for v in d) + ")" for d in i["null_directions"])
            text += f" Null direction(s) {nd}: moving along them leaves every prediction unchanged."
        fam = i["family_of_solutions"]
        if fam:
            a, b = (", ".join(f"{v:.4g}" for v in end) for end in fam["ends"])
            kind = "the exact family" if fam["kind"] == "exact" else "the linearised family (tangent segment)"
            check = "holds" if fam["holds"] else "does NOT hold"
            text += (f" Solutions within the bounds: {kind} from ({a}) to ({b}), along {fam['along']}; "
                     f"Δχ² at its ends {max(fam['end_chi2']):.2g}: it {check}. {fam['label']}.")
        out.append(f"\n## Identifiability ({_md_escape(i['data'])})\n\n{text}\n")
    for t in s.get("tables", []):
        out.append(f"\n## {t['title']}\n")
        out.append(_md_table(t["headers"], ([_fmt(c) for c in r] for r in t["rows"])))
        if t["note"]:
            out.append(f"\n{t['note']}\n")
    if s["modern"]:
        out.append("\n## Today's values\n")
        out.append(_md_table(("quantity", "resal", "modern low", "typ", "high", "source", "note"), (
            [m["quantity"], f"{_fmt(m['resal'], 4)} ({m['resal_what']})", _fmt(m["low"]), _fmt(m["typ"]),
             _fmt(m["high"]), m["source"], m["note"]] for m in s["modern"])))
    if s["figures"]:
        out.append("\n## Figures\n")
        out += [f"![{f}]({f})\n" for f in s["figures"] if f.endswith(".png")]
    return "\n".join(out)


def _csv_cell(v: Any) -> str:
    return "" if v is None else (repr(v) if isinstance(v, float) else str(v))


def table_csv(s: dict[str, Any]) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    cols = ["id", "quantity", "source", "printed", "printed_text", "computed", "rel_diff", "tolerance", "verdict",
            "note", "line", "reason", "today"]
    w.writerow(cols)
    for r in s["rows"]:
        w.writerow([_csv_cell(r.get(c)) for c in cols])
    if s.get("measurements"):  # a second table, after an empty line: the measured rows, their own columns
        mcols = ["id", "quantity", "source", "unit", "measured", "measured_text", "uncertainty", "predicted",
                 "interval_low", "interval_high", "verdict", "note"]
        w.writerow([])
        w.writerow(mcols)
        for m in s["measurements"]:
            iv = m.get("interval") or (None, None)
            w.writerow([_csv_cell(v) for v in (m["id"], m["quantity"], m["source"], m["unit"], m["measured"],
                                               m["measured_text"], m["uncertainty"], m["predicted"], iv[0], iv[1],
                                               m["verdict"], m["note"])])
    return buf.getvalue()


_TEX = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_", "{": r"\{",
        "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}


def _tex(s: str) -> str:
    return "".join(_TEX.get(ch, ch) for ch in s)


def table_tex(s: dict[str, Any]) -> str:
    lines = [f"% {s['title']} (resal {s['experiment']}); needs \\usepackage{{booktabs}} and UTF-8 input",
             r"\begin{tabular}{" + "l" * _TEX_COLS + "}", r"\toprule",
             " & ".join(_tex(h) for h in HEADERS[:_TEX_COLS]) + r" \\", r"\midrule"]
    lines += [" & ".join(_tex(c) for c in row_cells(r)[:_TEX_COLS]) + r" \\" for r in s["rows"]]
    lines += [r"\bottomrule", r"\end{tabular}", ""]
    if s.get("measurements"):
        n = len(MEASUREMENT_HEADERS) - 1  # the note left out, as above
        lines += [r"\begin{tabular}{" + "l" * n + "}", r"\toprule",
                  " & ".join(_tex(h) for h in MEASUREMENT_HEADERS[:n]) + r" \\", r"\midrule"]
        lines += [" & ".join(_tex(c) for c in measurement_cells(m)[:n]) + r" \\" for m in s["measurements"]]
        lines += [r"\bottomrule", r"\end{tabular}", ""]
    return "\n".join(lines)


# Figures are read on phones too: the reader's edition shows each 375 CSS px wide there, and every text in it must
# then be at least 9 CSS px tall. A font of s pt on a figure W inches wide, shown 375 px wide, is s·375/(72·W) px:
# every figure is _FIG_W inches wide and none of its texts is smaller than min_font_pt(_FIG_W), 8.6 pt at 5 in.
PHONE_WIDTH_PX = 375
MIN_TEXT_PX = 9.0


def min_font_pt(width_in: float) -> float:
    """The smallest font (pt) that is MIN_TEXT_PX tall on a figure ``width_in`` inches wide shown on a phone."""
    return MIN_TEXT_PX * 72.0 * width_in / PHONE_WIDTH_PX


_FIG_W = 5.0  # inches: every figure
_AX_H = 2.9  # inches: the axes of one row of panels; each further row adds _ROW_H (the rows share them by heights)
_ROW_H = 1.5
_PAD, _GAP = 0.06, 0.08  # inches: between the texts and the figure's edge; between stacked texts
# the PNG's resolution, also the figure's own: the text measured while laying the figure out (legend, margins)
# is then measured by the renderer that draws the PNG, whose cache serves it again. 240 dpi, twice the former 120:
# 1200 px across, 3.2 device pixels per CSS px on a phone showing it 375 px wide (crisp on HiDPI screens)
_DPI = 240
_PDF_RASTER_DPI = 150  # the few raster parts of a PDF (a map of many cells): its vectors are not affected
_PNG_COMPRESSION = 3  # zlib level of the PNGs: 5 % larger than the default 6, encoded in 70 % of its time
_LINESTYLES = {"-": "solid", "--": "dashed", ":": "dotted", "-.": "dashdot"}
FONT = {"tick": 9.5, "label": 10.0, "legend": 9.0, "caption": 9.0, "panel": 10.0, "title": 11.5}  # points
# matplotlib's settings for every figure (ours and the benchmark's): the sizes above, a real minus sign (U+2212) in
# the tick labels, and mathtext ($\alpha_1$) in the upright font of the text around it
STYLE = {"font.size": FONT["label"], "axes.labelsize": FONT["label"], "axes.titlesize": FONT["panel"],
         "xtick.labelsize": FONT["tick"], "ytick.labelsize": FONT["tick"], "legend.fontsize": FONT["legend"],
         "legend.title_fontsize": FONT["legend"], "figure.titlesize": FONT["title"], "axes.unicode_minus": True,
         "mathtext.default": "regular"}
_MINUS = re.compile(r"(?<![\w\-−])-(?=\.?\d)|(?<=\de)-(?=\d)")  # a hyphen before a number, or in 1e-6: a minus
_MATH = re.compile(r"(\$[^$]*\$)")


def figure_style() -> Any:
    """The rc context of every figure (``STYLE``): enter it around drawing and saving."""
    import matplotlib

    return matplotlib.rc_context(STYLE)


def minus_signs(text: str) -> str:
    """``text`` with each hyphen that stands for a minus (before a number, or in an exponent) made a real minus
    sign, outside mathtext (where matplotlib draws a minus already)."""
    return "".join(part if part.startswith("$") else _MINUS.sub("−", part) for part in _MATH.split(text))


def subscripts(text: str) -> str:
    """A symbol's index drawn as a subscript (mathtext): χ1 → $χ_1$, V′0 → $V′_0$. For the texts that are plain
    elsewhere (a figure's title is the edition's caption too) and drawn in the figure as its labels are."""
    return re.sub(r"(?<![A-Za-z0-9$])([A-Za-zα-ω]′?)(\d)(?![\d.])", r"$\1_\2$", text)


_SUPERSCRIPT = str.maketrans("0123456789-−+", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁻⁺")


def unicode_power(label: str) -> str:
    """A log axis' tick label written by matplotlib in mathtext (``$\\mathdefault{2\\times10^{-3}}$``) as plain
    text with Unicode superscripts (``2×10⁻³``): the same label, without mathtext's parser, which took half of a
    log-scaled figure's drawing time (each label parsed again at each resolution, PNG and PDF). Any other text is
    returned as it is."""
    m = re.fullmatch(r"\$\\mathdefault\{(?:([0-9.]+)\\times\s*)?([0-9.]+)(?:\^\{([−\-0-9]+)\})?\}\$", label)
    if not m:
        return label
    coeff, base, power = m.groups()
    return (f"{coeff}×" if coeff else "") + base + (power.translate(_SUPERSCRIPT) if power else "")


def plain_log_labels(fig: Any) -> None:
    """Every log-scaled axis of ``fig`` whose ticks matplotlib labels by default labelled the same, in plain text
    (``unicode_power``); an axis given a formatter of its own keeps it."""
    from matplotlib.ticker import LogFormatterSciNotation

    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            if axis.get_scale() != "log":
                continue
            if type(axis.get_major_formatter()) is LogFormatterSciNotation:
                axis.set_major_formatter(_log_ticks(numbers=False))
            if type(axis.get_minor_formatter()) is LogFormatterSciNotation:
                axis.set_minor_formatter(_log_ticks(numbers=False, label_only_base=False))


def _colour(c: str) -> Any:
    """A layer's colour: a matplotlib colour, or ``<colour map>:<t>`` (the map's colour at t in [0, 1])."""
    if ":" not in c:
        return c
    import matplotlib

    name, t = c.rsplit(":", 1)
    return matplotlib.colormaps[name](float(t))


def _regular(v: Sequence[float]) -> bool:
    import numpy as np

    d = np.diff(np.asarray(v, dtype=float))
    return len(v) < 2 or bool(np.allclose(d, d[0], rtol=1e-6, atol=0.0))


def _log_ticks(numbers: bool = True, label_only_base: bool = False) -> Any:
    """Labels of a logarithmic axis, matplotlib's ticks in plain text (``unicode_power``: no mathtext). With
    ``numbers``, plain numbers (0.01, 0.1, 1, 10) where the axis spans 0.001 to 1000 at most, else powers of ten
    (not a mixture of both on one axis)."""
    from matplotlib.ticker import LogFormatterSciNotation

    class Plain(LogFormatterSciNotation):
        def __call__(self, x: float, pos: int | None = None) -> str:
            s = super().__call__(x, pos)
            if numbers and s:
                lo, hi = sorted(self.axis.get_view_interval()) if self.axis is not None else (x, x)
                if lo >= 0.999e-3 and hi <= 1.001e3:
                    return minus_signs(f"{x:g}")
            return unicode_power(s)

    return Plain(labelOnlyBase=label_only_base)


def _draw_layers(fig: Any, ax: Any, spec: FigureSpec, legend: str) -> list[tuple[Any, list[float], list[float]]]:
    """Draw one panel's layers on ``ax``, its key at ``legend`` (none: "below"); returns the markers (artist, x, y)
    that may overlap the frame."""
    import numpy as np
    from matplotlib.colors import to_rgba

    markers = []
    for ly in spec.layers:
        color, label = _colour(ly.color), minus_signs(ly.label)
        if ly.kind == "line":
            ax.plot(ly.x, ly.y, ly.style, color=color, label=label)
        elif ly.kind == "points":
            (art,) = ax.plot(ly.x, ly.y, linestyle="none", marker=ly.marker, color=color, label=label, ms=7)
            markers.append((art, list(ly.x), list(ly.y)))
        elif ly.kind == "band":  # shaded, and edged: a narrow band still shows as two lines
            ax.fill_between(ly.x, ly.y, ly.y2, facecolor=to_rgba(color, 0.25), edgecolor=to_rgba(color, 0.7),
                            lw=0.8, label=label)
        elif ly.kind == "vband":
            ax.axvspan(ly.x[0], ly.x[1], color=color, alpha=0.15, label=label, lw=0)
        elif ly.kind == "hband":
            ax.axhspan(ly.y[0], ly.y[1], color=color, alpha=0.15, label=label, lw=0)
        elif ly.kind == "errorbar":
            ax.errorbar(ly.x, ly.y, yerr=ly.y2, fmt=ly.marker, color=color, label=label, capsize=3)
        elif ly.kind == "heatmap":
            z = np.asarray(ly.z, dtype=float)
            norm, cmap = None, "viridis"
            if ly.centre is not None:  # a signed quantity: a diverging map whose middle colour is the centre
                from matplotlib.colors import CenteredNorm, TwoSlopeNorm

                lo, hi = float(np.nanmin(z)), float(np.nanmax(z))
                norm = TwoSlopeNorm(ly.centre, lo, hi) if lo < ly.centre < hi else CenteredNorm(ly.centre)
                cmap = "RdBu"
            elif ly.norm == "log":
                from matplotlib.colors import LogNorm

                norm = LogNorm(float(np.nanmin(z)), float(np.nanmax(z)))
            if spec.xscale == spec.yscale == "linear" and _regular(ly.x) and _regular(ly.y):  # one image
                dx, dy = (ly.x[1] - ly.x[0]) / 2, (ly.y[1] - ly.y[0]) / 2
                img = ax.imshow(z, origin="lower", aspect="auto", cmap=cmap, norm=norm, interpolation="nearest",
                                extent=(ly.x[0] - dx, ly.x[-1] + dx, ly.y[0] - dy, ly.y[-1] + dy))
            else:  # cells on a logarithmic axis: a mesh, drawn as an image in the PDF too
                img = ax.pcolormesh(ly.x, ly.y, z, shading="nearest", cmap=cmap, norm=norm, rasterized=True)
            bar = fig.colorbar(img, ax=ax, label=label)
            if ly.centre is not None:
                bar.ax.axhline(ly.centre, color="k", lw=0.8)
        elif ly.kind == "contour":  # the curve z = 0, interpolated on the grid
            z = np.asarray(ly.z, dtype=float)
            if np.nanmin(z) < 0.0 < np.nanmax(z):
                ax.contour(ly.x, ly.y, z, levels=[0.0], colors=[color], linestyles=[_LINESTYLES.get(ly.style, "solid")],
                           linewidths=1.5)
            if ly.label:  # a contour set has no legend entry of its own
                ax.plot([], [], ly.style, color=color, label=label)
        else:
            raise ValueError(f"unknown layer kind {ly.kind!r}")
    ax.set_xscale(spec.xscale)
    ax.set_yscale(spec.yscale)
    for axis, scale in ((ax.xaxis, spec.xscale), (ax.yaxis, spec.yscale)):
        if scale == "log":
            axis.set_major_formatter(_log_ticks())
    if spec.xlim:
        ax.set_xlim(*spec.xlim)
    if spec.ylim:
        ax.set_ylim(*spec.ylim)
    if spec.xticklabels:
        ax.set_xticks(range(len(spec.xticklabels)), [minus_signs(t) for t in spec.xticklabels])
    if spec.yticklabels:
        ax.set_yticks(range(len(spec.yticklabels)), [minus_signs(t) for t in spec.yticklabels])
    if spec.aspect == "equal":  # the limits give way, not the box (the figure's height is made to fit them)
        if spec.xlim and spec.ylim:
            raise ValueError(f"figure {spec.name!r}: equal scales and both limits fixed (leave one free)")
        ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    for a in fig.axes:  # ticks made later (at the save) get this size too, whatever the rc then
        a.tick_params(which="both", labelsize=FONT["tick"])
    if legend != "below" and any(ly.label and ly.kind != "heatmap" for ly in spec.layers):
        ax.legend(loc=legend)
    return markers


def _legend_below(fig: Any, axes: list[Any]) -> Any:
    """One key for the whole figure, under the axes, in as many columns as its widest entry allows (None: no
    entry). The layout makes room for it."""
    from matplotlib import cbook
    from matplotlib.font_manager import FontProperties

    found: dict[str, Any] = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            found.setdefault(label, handle)
    if not found:
        return None
    renderer, prop = fig.canvas.get_renderer(), FontProperties(size=FONT["legend"])
    em = FONT["legend"] * fig.dpi / 72.0
    widest = max(renderer.get_text_width_height_descent(s, prop, ismath=cbook.is_math_text(s))[0] for s in found)
    column = widest + (2.0 + 0.8 + 2.0) * em  # matplotlib's handle, its pad and the spacing of columns, in ems
    room = (_FIG_W - 2 * _PAD) * fig.dpi + 2.0 * em  # the last column needs no spacing after it
    ncols = max(1, min(len(found), int(room // column)))
    return fig.legend(list(found.values()), list(found), loc="lower center", bbox_to_anchor=(0.5, 0.0), ncols=ncols,
                      frameon=False)


def _words(paragraph: str) -> list[str]:
    """The words of a line of text, a mathtext span ($…$) kept whole."""
    return re.findall(r"(?:\$[^$]*\$|[^\s$])+", paragraph)


def _wrap(fig: Any, text: Any, limit: float) -> None:
    """Break ``text`` into lines no wider than ``limit`` (pixels), measured by the renderer of the PNG, and draw it
    unwrapped: matplotlib would wrap again at every draw (PNG, PDF), measuring word by word. Each line is the
    longest run of words (at least one) that fits, found by bisection since the width grows with the words."""
    from matplotlib import cbook

    renderer, prop = fig.canvas.get_renderer(), text.get_fontproperties()

    def fits(words: list[str]) -> bool:
        s = " ".join(words)
        return math.ceil(renderer.get_text_width_height_descent(s, prop, ismath=cbook.is_math_text(s))[0]) <= limit

    lines = []
    for paragraph in text.get_text().split("\n"):
        words = _words(paragraph)
        while len(words) > 1 and not fits(words):
            lo, hi = 1, len(words)  # words[:lo] fits (or is one word), words[:hi] does not
            while hi - lo > 1:
                mid = (lo + hi) // 2
                lo, hi = (mid, hi) if fits(words[:mid]) else (lo, mid)
            lines.append(" ".join(words[:lo]))
            words = words[lo:]
        lines.append(" ".join(words))
    text.set_text("\n".join(lines))
    text.set_wrap(False)


def _slots(fig: Any) -> list[tuple[Any, int, int, Any]]:
    """Each axes of the figure (colour bars included) with the row and the column of the grid it stands in, and
    that cell of the grid (in pixels): a colour bar shares its cell with the axes it belongs to."""
    from matplotlib.transforms import Bbox

    out = []
    for a in fig.axes:
        spec = a.get_subplotspec()
        if spec is None:
            continue
        top = spec.get_topmost_subplotspec()
        cell = Bbox(top.get_position(fig).get_points() * [fig.bbox.width, fig.bbox.height])
        out.append((a, top.rowspan.start, top.colspan.start, cell))
    return out


def _fit_width(fig: Any, ncols: int) -> None:
    """Set the left and right margins and the space between columns from the text around the axes (tick labels,
    axis labels, colour bars), measured: the texts end _PAD inside the figure's edges, _GAP apart."""
    renderer, W, pad = fig.canvas.get_renderer(), fig.bbox.width, _PAD * fig.dpi
    left, right = [0.0] * ncols, [0.0] * ncols
    for a, _, c, cell in _slots(fig):
        b = a.get_tightbbox(renderer)
        left[c], right[c] = max(left[c], cell.x0 - b.x0), max(right[c], b.x1 - cell.x1)
    x0, x1 = pad + left[0], W - pad - right[-1]
    gap = max((right[c] + left[c + 1] for c in range(ncols - 1)), default=0.0) + _GAP * fig.dpi
    width = (x1 - x0 - (ncols - 1) * gap) / ncols
    fig.subplots_adjust(left=x0 / W, right=x1 / W, wspace=gap / width)


def _fit_height(fig: Any, nrows: int, title: Any, caption: Any, legend: Any, rows_h: float) -> None:
    """Make the figure as tall as its texts and its rows of axes (``rows_h`` inches) need: the title, the caption
    and the texts above the first row at the top, the x axis' labels and the key at the bottom, the panels' titles
    between rows; each measured, _GAP apart."""
    renderer, dpi = fig.canvas.get_renderer(), fig.dpi
    above, below = [0.0] * nrows, [0.0] * nrows
    for a, r, _, cell in _slots(fig):
        b = a.get_tightbbox(renderer)
        above[r], below[r] = max(above[r], (b.y1 - cell.y1) / dpi), max(below[r], (cell.y0 - b.y0) / dpi)
    title_h = title.get_window_extent(renderer).height / dpi if title.get_text() else 0.0
    caption_h = caption.get_window_extent(renderer).height / dpi if caption is not None else 0.0
    legend_h = legend.get_window_extent(renderer).height / dpi if legend is not None else 0.0
    top = _PAD + title_h + (_GAP + caption_h if caption is not None else 0.0) + _GAP + above[0]
    bottom = _PAD + (legend_h + _GAP if legend is not None else 0.0) + below[-1]
    gap = max((below[r] + above[r + 1] for r in range(nrows - 1)), default=0.0) + _GAP
    H = top + rows_h + (nrows - 1) * gap + bottom
    fig.set_size_inches(_FIG_W, H)
    fig.subplots_adjust(top=1 - top / H, bottom=bottom / H, hspace=gap / (rows_h / nrows))
    title.set_y(1 - _PAD / H)
    if caption is not None:
        caption.set_y(1 - (_PAD + title_h + _GAP) / H)
    if legend is not None:
        legend.set_bbox_to_anchor((0.5, _PAD / H), transform=fig.transFigure)


def _draw(spec: FigureSpec, folder: Path) -> None:
    import matplotlib.pyplot as plt

    with figure_style():
        fig = _render(spec)
        # the title goes into the PNG too: report.pdf heads the figure's page with it
        fig.savefig(folder / f"{spec.name}.png", dpi=_DPI, metadata={"Software": None, "Title": spec.title},
                    pil_kwargs={"compress_level": _PNG_COMPRESSION})
        fig.savefig(folder / f"{spec.name}.pdf", dpi=_PDF_RASTER_DPI,
                    metadata={"Creator": None, "Producer": None, "CreationDate": None})
    plt.close(fig)


def _render(spec: FigureSpec) -> Any:
    """The matplotlib figure of a spec, laid out (the caller saves and closes it, in ``figure_style()``)."""
    import matplotlib

    matplotlib.use("Agg")
    with figure_style():
        return _render_styled(spec)


def _render_styled(spec: FigureSpec) -> Any:
    import matplotlib.pyplot as plt

    if spec.panels and spec.layers:
        raise ValueError(f"figure {spec.name!r}: layers of its own and panels (put them in a panel)")
    panels = spec.panels or (spec,)
    cols = max(1, min(spec.columns, len(panels)))
    nrows = -(-len(panels) // cols)
    rows_h = _AX_H + _ROW_H * (nrows - 1)
    # fixed margins set from the measured texts, not a layout solve: the solve took a third of each figure's time
    height = rows_h + 1.6  # about the final height: the axes' ticks are then those of the final figure
    fig, grid = plt.subplots(nrows, cols, figsize=(_FIG_W, height), dpi=_DPI, squeeze=False, sharex=len(panels) > 1,
                             sharey=spec.sharey, gridspec_kw={"height_ratios": list(spec.heights) or None})
    fig.subplots_adjust(left=0.8 / _FIG_W, right=1 - 0.2 / _FIG_W, top=1 - 1.0 / height, bottom=0.6 / height,
                        hspace=0.4 / (rows_h / nrows))
    axes = list(grid.flat)
    markers = []
    for j, (ax, p) in enumerate(zip(axes, panels, strict=False)):
        markers += _draw_layers(fig, ax, p, spec.legend)
        below = j + cols < len(panels)  # another panel under this one: it carries the x axis' labels
        ax.set(xlabel="" if below else minus_signs(p.xlabel or spec.xlabel),
               ylabel="" if spec.sharey and j % cols else minus_signs(p.ylabel or spec.ylabel))
        if not below:
            ax.tick_params(labelbottom=True)
        if spec.panels and p.title:
            ax.set_title(minus_signs(p.title), fontsize=FONT["panel"])
        if spec.aspect == "equal" and spec.panels:
            ax.set_aspect("equal", adjustable="datalim")
    for ax in axes[len(panels):]:
        ax.remove()
    axes = axes[:len(panels)]
    plain_log_labels(fig)
    title = fig.suptitle(subscripts(minus_signs(spec.title)), fontsize=FONT["title"], va="top")
    limit = (_FIG_W - 2 * _PAD) * fig.dpi
    _wrap(fig, title, limit)
    caption = None
    if spec.caption:
        caption = fig.text(0.5, 0.9, minus_signs(spec.caption), fontsize=FONT["caption"], color="0.3", ha="center",
                           va="top")
        _wrap(fig, caption, limit)
    legend = _legend_below(fig, axes) if spec.legend == "below" else None
    equal = spec.aspect == "equal" and len(axes) == 1
    if equal:  # the limits of the data, before a draw widens one of them to the axes' shape
        (x0, x1), (y0, y1) = axes[0].get_xlim(), axes[0].get_ylim()
    if equal:  # rows as tall as those limits need at the axes' width (within bounds), the limits then kept
        _fit_width(fig, cols)  # that width first (elsewhere the height does not depend on the side margins)
        rows_h = min(max(axes[0].bbox.width / fig.dpi * abs(y1 - y0) / abs(x1 - x0), 1.6), 4.6)
        axes[0].set_xlim(x0, x1, auto=None)
        axes[0].set_ylim(y0, y1, auto=None)
    _fit_height(fig, nrows, title, caption, legend, rows_h)
    _fit_width(fig, cols)  # again: the y axes' ticks are those of the final height
    renderer = fig.canvas.get_renderer()
    for a in fig.axes:  # colour bars placed where the final margins put them (else only at the next draw)
        if a.get_axes_locator() is not None:
            a.apply_aspect(a.get_axes_locator()(a, renderer))
    for art, xs, ys in markers:  # a marker on the frame is drawn whole, not cut in half by the axes' clip
        (xa, xb), (ya, yb) = sorted(art.axes.get_xlim()), sorted(art.axes.get_ylim())
        if all(xa <= x <= xb for x in xs) and all(ya <= y <= yb for y in ys):
            art.set_clip_on(False)
            art.set_zorder(2.6)  # above the frame's spines
    return fig


STAGING_PREFIX = ".resal-"
_HOST = hashlib.sha256(socket.gethostname().encode()).hexdigest()[:8]  # a pid means nothing on another host
_STAGING_RE = re.compile(r"\.resal-(?P<host>[0-9a-f]{8})-(?P<pid>[0-9]+)-[0-9a-f]{8}\.(?P<what>.+)")


def staging_name(what: str, pid: int | None = None) -> str:
    """A hidden name for something being written by this process: ``.resal-<host>-<pid>-<random>.<what>``."""
    return f"{STAGING_PREFIX}{_HOST}-{os.getpid() if pid is None else pid}-{secrets.token_hex(4)}.{what}"


def make_staging(parent: Path, what: str) -> Path:
    """A new staging folder in ``parent``, made by a plain ``mkdir``: it gets the umask's mode (not 0700). A caller
    that must remove it whatever happens assigns the result inside ``signals_deferred()``: an interruption between
    the ``mkdir`` and the assignment would leave a folder nobody knows of."""
    while True:
        p = parent / staging_name(what)
        try:
            p.mkdir()
            return p
        except FileExistsError:
            continue


def remove_staging(p: Path) -> None:
    """Remove a staging folder whole, the stop signals held until it is gone: an interruption raised inside
    ``shutil.rmtree`` would stop it half way and leave the folder behind (seen once under load in CI: a SIGINT
    at the end of a run left ``.resal-….figures``)."""
    with signals_deferred():
        shutil.rmtree(p, ignore_errors=True)


@contextmanager
def staging_folder(parent: Path, what: str) -> Iterator[Path]:
    """A staging folder in ``parent`` for the block, removed whole after it, whatever ends it."""
    p = None
    try:
        with signals_deferred():  # made and known together
            p = make_staging(parent, what)
        yield p
    finally:
        if p is not None:
            remove_staging(p)


def _owner_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True


def clean_stale(out: Path) -> list[Path]:
    """Remove what killed runs staged in ``out``: only names with our prefix, made on this host by a process
    that is gone (a running resal's staging is left alone). A previous experiment folder set aside during a
    swap (``<id>.old``) is put back if its replacement never arrived. Returns the paths removed or restored."""
    done = []
    try:
        entries = sorted(out.iterdir())
    except OSError:
        return done
    for p in entries:
        m = _STAGING_RE.fullmatch(p.name)
        if not m or m["host"] != _HOST or int(m["pid"]) == os.getpid() or _owner_alive(int(m["pid"])):
            continue
        what = m["what"]
        try:
            if what.endswith(".old") and p.is_dir() and not p.is_symlink() and not (out / what[:-4]).exists():
                os.replace(p, out / what[:-4])
            elif p.is_dir() and not p.is_symlink():
                shutil.rmtree(p)
            else:
                p.unlink()
        except OSError:
            continue
        done.append(p)
    return done


def signals_deferred() -> AbstractContextManager[None]:
    """SIGINT, SIGTERM and SIGHUP wait until the block ends (``processes.deferred``)."""
    return processes.deferred()


def _atomic_write(path: Path, write: Callable[[BinaryIO], None]) -> None:
    """Write ``path`` through a temporary file beside it (a plain ``open``: the umask's mode), then rename;
    ``write`` fills the file. An error or an interruption removes the temporary file and leaves ``path``."""
    while True:
        tmp = path.parent / staging_name(f"{path.name}.tmp")
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            break
        except FileExistsError:
            continue
    try:
        with os.fdopen(fd, "wb") as fh:
            write(fh)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _atomic_text(path: Path, text: str) -> None:
    """``path`` holds ``text`` (UTF-8), written whole through a temporary file and a rename."""
    _atomic_write(path, lambda fh: fh.write(text.encode("utf-8")))


def dangling_link(path: Path) -> str | None:
    """What is wrong with ``path`` (or a folder above it) as a symbolic link that leads nowhere: to a missing
    target, or round in a loop; None when it is not such a link."""
    for p in (path, *path.parents):
        if p.is_symlink():
            try:
                p.resolve(strict=True)
            except RuntimeError:
                return f"{p} is a symbolic link that loops back on itself: expected a folder"
            except OSError as exc:
                if exc.errno == errno.ELOOP:
                    return f"{p} is a symbolic link that loops back on itself: expected a folder"
                return f"{p} is a symbolic link to {os.readlink(p)}, which does not exist: expected a folder"
    return None


def ensure_writable(out: Path, where: str = "--out") -> None:
    """Fail early, before any work, when the output folder cannot be created or written."""
    dangling = dangling_link(out)
    if dangling:
        raise InputError(f"{where} {out}", dangling)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{where} {out}", f"cannot create the output folder ({exc.strerror})") from None
    if not out.is_dir() or not os.access(out, os.W_OK | os.X_OK):
        raise InputError(f"{where} {out}", "the output folder is not a writable directory")


def prepare_drawing() -> None:
    """Import matplotlib (Agg) once, in the parent, so that forked drawing processes inherit it."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot


def draw_figure(job: tuple[FigureSpec, Path]) -> Path:
    """Render one figure (PNG and PDF) into a folder: a unit of work that processes can share."""
    spec, folder = job
    folder.mkdir(parents=True, exist_ok=True)
    _draw(spec, folder)
    return folder


def write_reproduction(rep: Reproduction, out: Path, prov: dict[str, Any] | None = None,
                       drawn: Path | None = None) -> Path:
    """Write ``out/<experiment>/`` completely in a staging folder, then swap it in. ``drawn``: a folder where
    the figures were already rendered (``draw_figure``); they are moved in instead of drawn again."""
    s = summary(rep, prov if prov is not None else provenance(rep))
    files = {"summary.json": json.dumps(s, indent=2, ensure_ascii=False) + "\n", "table.md": table_md(s),
             "table.csv": table_csv(s), "table.tex": table_tex(s)}
    return write_folder(out / rep.experiment.id, files, rep.figures, drawn)


_SWAP_ATTEMPTS = 20  # renames tried when another run swaps the same folder at the same moment


def lock_holders(folder: Path) -> list[int]:
    """The pids holding a ``flock`` on ``folder`` (Linux's /proc/locks; empty elsewhere or when unknown)."""
    try:
        st = folder.stat()
        lines = Path("/proc/locks").read_text().splitlines()
    except OSError:
        return []
    ident = f"{os.major(st.st_dev):02x}:{os.minor(st.st_dev):02x}:{st.st_ino}"
    pids = []
    for ln in lines:
        f = ln.split()
        if len(f) >= 6 and f[1] == "FLOCK" and f[5] == ident and f[4].isdigit():
            pids.append(int(f[4]))
    return sorted(set(pids) - {os.getpid()})


@contextmanager
def locked(out: Path, wait: float = 60.0, waiting: Callable[[list[int]], None] | None = None,
           poll: float = 0.05) -> Iterator[None]:
    """An exclusive lock on the folder ``out`` itself (``flock``: no lock file is left, and a killed holder's lock
    goes with its process) while a run writes into it: two runs into one folder write one after the other, and
    the folder ends as one whole result, the later run's. A run that finds the lock held calls ``waiting(pids of
    the holders)`` once after a second, and gives up after ``wait`` seconds with a ``ComputationError`` naming
    the holder (a stopped run, Ctrl-Z, holds it for ever)."""
    try:
        import fcntl
    except ImportError:  # not POSIX: the renames alone keep each folder whole
        yield
        return
    import time

    fd = os.open(out, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    try:
        start, told = time.monotonic(), False
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except BlockingIOError:
                pass
            waited = time.monotonic() - start
            if waited >= wait:
                pids = lock_holders(out)
                who = f"another resal run (pid {', '.join(map(str, pids))})" if pids else "another resal run"
                raise ComputationError(f"--out {out}", f"{who} has held this folder for {waited:.0f} s (stopped? "
                                                       f"`kill -CONT <pid>` resumes it); nothing was written "
                                                       f"here; --wait SECONDS waits longer")
            if not told and waited >= 1.0 and waiting is not None:
                waiting(lock_holders(out))
                told = True
            time.sleep(min(poll, max(wait - waited, 0.0)))
        yield
    finally:
        os.close(fd)


MANIFEST = digest.MANIFEST
read_manifest = digest.read_manifest
changed_by_hand = digest.changed_by_hand


def foreign_files(folder: Path) -> list[str]:
    """The entries of ``folder`` that resal did not write there (not in its manifest): the user's, kept by every
    rewrite. Without a manifest, every entry is foreign."""
    ours = set(read_manifest(folder) or ()) | {MANIFEST}
    try:
        return sorted(p.name for p in folder.iterdir() if p.name not in ours and not _STAGING_RE.fullmatch(p.name))
    except OSError:
        return []


def _carry(src: Path, dst: Path) -> None:
    """``src`` (a user's file, folder or link) appears at ``dst`` too, without being moved: a hard link (a copy
    where links cannot be made), so that an interruption at any point leaves it in the old folder or both."""
    if src.is_symlink():
        os.symlink(os.readlink(src), dst)
    elif src.is_dir():
        shutil.copytree(src, dst, symlinks=True, copy_function=_link_or_copy)
    else:
        _link_or_copy(src, dst)


def _link_or_copy(src: str | Path, dst: str | Path) -> None:
    try:
        os.link(src, dst)
    except OSError:
        shutil.copy2(src, dst)


def write_folder(final: Path, files: dict[str, str], figures: Sequence[FigureSpec] = (),
                 drawn: Path | None = None, moved: Path | None = None) -> Path:
    """Write the folder ``final`` whole: ``files`` (name → text), ``figures`` (drawn here, or moved from
    ``drawn``) and every file of ``moved`` go into a staging folder beside it, with a manifest of what resal
    wrote (``manifest.json``), which is then swapped in; an error or an interruption leaves what was there
    before. resal replaces only what it wrote: every entry of the old folder that its manifest does not list
    (the user's notes, a folder of theirs) is carried into the new one (``foreign_files`` names them
    afterwards); a user's file that bears the name of one resal now writes is kept beside it as
    ``<name>.yours`` (in a folder without a manifest, written before resal kept one, such a file is taken as
    resal's own earlier output)."""
    out, name = final.parent, final.name
    stage = old = None
    try:
        try:
            with signals_deferred():  # made and known together: the ``except`` below removes it
                stage = make_staging(out, f"{name}.staging")
        except OSError as exc:
            if exc.errno == errno.ENAMETOOLONG:
                why = (f"too long for a folder name of this file system ({len(name.encode())} bytes): "
                       "choose a shorter id")
                raise InputError(f"experiment id '{name}'", why) from None
            raise InputError(f"--out {out}", f"cannot write the output folder ({exc.strerror})") from None
        for fname, text in files.items():
            (stage / fname).write_text(text, encoding="utf-8")
        for spec in figures:
            if drawn is None:
                with signals_deferred():  # matplotlib's writers do not survive an exception raised inside them
                    _draw(spec, stage)
            else:
                for ext in ("png", "pdf"):
                    os.replace(drawn / f"{spec.name}.{ext}", stage / f"{spec.name}.{ext}")
        for f in sorted(moved.iterdir()) if moved is not None else ():  # files made elsewhere (bench's figures)
            os.replace(f, stage / f.name)
        written = sorted(p.name for p in stage.iterdir())
        manifest = {"written_by": "resal", "files": {n: digest.file_sha256(stage / n) for n in written}}
        (stage / MANIFEST).write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n", encoding="utf-8")
        if final.is_dir() and not final.is_symlink():
            legacy = read_manifest(final) is None  # written before manifests: a name resal writes now was its own
            for n in foreign_files(final):
                if not (stage / n).exists():
                    _carry(final / n, stage / n)
                elif not legacy:
                    aside = next(a for k in range(1, 10**6) if not (stage / (a := f"{n}.yours{k if k > 1 else ''}"))
                                 .exists() and not (final / a).exists())
                    _carry(final / n, stage / aside)
        with signals_deferred():  # both renames or neither: never a missing folder
            for attempt in range(_SWAP_ATTEMPTS):
                if final.exists():
                    old = out / staging_name(f"{name}.old")
                    try:
                        os.replace(final, old)
                    except FileNotFoundError:  # another run (not holding ``locked``) moved it away: again
                        old = None
                        continue
                try:
                    os.replace(stage, final)
                    break
                except BaseException as exc:
                    if old is not None:
                        try:
                            os.replace(old, final)
                        except OSError:  # another run's whole folder is there now: ours was the older one
                            shutil.rmtree(old, ignore_errors=True)
                        old = None
                    busy = isinstance(exc, OSError) and exc.errno in (errno.ENOTEMPTY, errno.EEXIST)
                    if not busy or attempt == _SWAP_ATTEMPTS - 1:
                        raise
        if old is not None:
            remove_staging(old)
    except BaseException:
        if stage is not None:
            remove_staging(stage)
        if old is not None and final.exists():
            remove_staging(old)
        raise
    return final


def summary_problem(folder: Path) -> str | None:
    """Why ``folder/summary.json`` cannot be taken as an experiment's results written by resal, or None: a file of
    resal's manifest changed by hand, a file that is not JSON, or JSON without what resal's summaries hold."""
    f = folder / "summary.json"
    changed = changed_by_hand(folder)
    if changed:
        return (f"{', '.join(changed)} changed since resal wrote {'it' if len(changed) == 1 else 'them'} "
                f"(`resal reproduce {folder.name} --force` writes it again, or remove the folder)")
    try:
        s = json.loads(f.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        return f"cannot be read as JSON ({exc})"
    if not isinstance(s, dict):
        return "is not a summary written by resal: expected a JSON object"
    need = {"experiment": str, "source": dict, "rows": list, "figures": list}
    missing = [k for k, t in need.items() if not isinstance(s.get(k), t)]
    if not missing and not all(isinstance(r, dict) and {"id", "verdict"} <= r.keys() for r in s["rows"]):
        missing = ["rows[].id, rows[].verdict"]
    if missing:
        return f"is not a summary written by resal: no {', '.join(missing)}"
    return None


def _summaries(out: Path, skipped: list[tuple[Path, str]] | None = None) -> list[tuple[str, dict[str, Any]]]:
    """(folder name, summary) of every experiment written under ``out``, in the paper's order (page, id). A folder
    whose summary.json is not resal's, or whose files resal wrote were changed by hand (``summary_problem``), is
    left out, never a cause to fail: ``skipped`` receives (its summary.json, why)."""
    found = []
    for d in sorted(p for p in out.iterdir() if p.is_dir() and not p.name.startswith(".")):
        f = d / "summary.json"
        if f.is_file():
            why = summary_problem(d)
            if why is not None:
                if skipped is not None:
                    skipped.append((f, why))
                continue
            found.append((d.name, json.loads(f.read_text(encoding="utf-8"))))
    return sorted(found, key=lambda x: paper_order(x[1]["source"].get("page"), x[1]["experiment"]))


def paper_order(page: Any, experiment: str, measured: bool = False) -> tuple[bool, int, str]:
    """Where an experiment stands in the reader's edition: by its page in the paper, then its id (no page: first);
    ``measured``, an experiment of today's measurements (``Experiment.measured``, a summary's ``measurements``):
    after the paper's, in the edition's part of its own (``edition.build``), in the same order."""
    return (bool(measured), page if isinstance(page, int) else 0, experiment)


# -- the paper as a whole: index.md, paper-table.{md,csv,tex}, report.pdf ---------------------------------------
VERDICTS = ("reproduced", "differs", "not-checkable")
PAPER_HEADERS = ("experiment", "section", "n°", "equation", "line", "id", "claim", "printed", "computed",
                 "difference", "tolerance", "verdict", "reason", "note", "today's value")
PAPER_CSV = ("experiment", "section", "n", "equation", "line", "id", "claim", "printed", "printed_value", "computed",
             "rel_diff", "abs_diff", "tolerance", "tolerance_text", "tolerance_rule", "verdict", "reason", "note",
             "today_symbol", "today")
# a row's source: "§II n°7, eq. (3)", "§III n°8-10", "§V n°12, eqs (5), (8)", "§III n°10, footnote"
_SOURCE_RE = re.compile(r"§\s*(?P<section>[IVXLC]+)\s*n°\s*(?P<n>\d+(?:\s*[-–]\s*\d+)?)(?:\s*,\s*(?P<eq>[^§]*?))?\s*")
# "Mathavan, Jackson & Parkin 2009, Am. J. Phys. …" → "Mathavan 2009": a name, then other names up to a year
_AUTHOR_YEAR_RE = re.compile(r"(?P<who>[^\W\d_][\w'’-]*)[^\d:;()]*?\b(?P<year>1[6-9]\d\d|20\d\d)\b")


def parse_source(source: str | None) -> tuple[str, str, str]:
    """(section, n°, equation) of a row's ``source``, written ``§<roman> n°<n>[, eq. (…)]``. What does not
    parse that way (a second section, free text) is kept whole as the section, with n° and equation empty."""
    m = _SOURCE_RE.fullmatch((source or "").strip())
    if m is None:
        return (source or "").strip(), "", ""
    return f"§{m['section']}", re.sub(r"\s+", "", m["n"]), (m["eq"] or "").strip()


def _short_source(text: str) -> str:
    """A modern value's source, short: "Mathavan 2009", "Alciatore FAQ (leather tips)"; several joined by ';'."""
    parts = []
    for part in text.split(";"):
        part = re.sub(r"\s*\([^)]*\d[^)]*\)", "", part.split(": ", 1)[0]).strip()  # no "(0.14)", no formula
        m = _AUTHOR_YEAR_RE.match(part)
        parts.append(f"{m['who']} {m['year']}" if m else re.split(r",", part, maxsplit=1)[0].strip())
    return "; ".join(p for p in parts if p)


def _modern_value(m: dict[str, Any]) -> str:
    """One modern value as the paper table shows it: "0.818 (Mathavan 2009)", "0.6–0.9 (Alciatore FAQ)"."""
    lo, typ, hi = m.get("low"), m.get("typ"), m.get("high")
    rng = (f"{_fmt(lo, 4)}–{_fmt(hi, 4)}" if lo is not None and hi is not None else
           f"≥ {_fmt(lo, 4)}" if lo is not None else f"≤ {_fmt(hi, 4)}" if hi is not None else "")
    if typ is not None:
        value = _fmt(typ, 4) + (f", range {rng}" if rng else "")
    elif rng:
        value = rng
    else:  # a law: the formula its source gives
        source = m.get("source") or ""
        value = source.split(": ", 1)[1].strip() if ": " in source else "a law"
    who = _short_source(m.get("source") or "")
    return f"{value} ({who})" if who else value


def today_value(symbol: str | None, modern: Iterable[dict[str, Any]]) -> str:
    """Today's value(s) of ``symbol`` among an experiment's ``modern`` entries; "" when the row names none."""
    if not symbol:
        return ""
    found = [_modern_value(m) for m in modern if m.get("symbol") == symbol]
    return "; ".join(found) if found else f"{symbol}: not among the experiment's modern values"


def paper_rows(summaries: Iterable[tuple[str, dict[str, Any]]]) -> list[dict[str, Any]]:
    """Every row of every experiment, in the paper's order: by ``line`` of the digitised text; rows without a line
    after them, in experiment order. Each: experiment, folder, the row, section / n° / equation, today's value."""
    found = []
    for name, s in summaries:
        for r in s["rows"]:
            section, n, eq = parse_source(r.get("source"))
            found.append({"experiment": s["experiment"], "folder": name, "row": r, "section": section, "n": n,
                          "equation": eq, "today": today_value(r.get("today"), s.get("modern", ()))})
    return sorted(found, key=lambda x: (x["row"].get("line") is None, x["row"].get("line") or 0))


def computed_text(r: dict[str, Any]) -> str:
    """The computed cell for people: a formula row's number is its discrepancy from the reference, so say so."""
    if r["printed"] is None and r.get("tolerance") is not None and r["computed"] is not None:
        return f"discrepancy {_fmt(r['computed'], 2)}"
    return _fmt(r["computed"])


def difference_text(r: dict[str, Any]) -> str:
    """Printed against computed: relative in %, absolute (Δ) where the printed value is zero, "—" where none."""
    if r["printed"] is None or r["computed"] is None or r["rel_diff"] is None:
        return "—"
    if r["printed"] == 0:
        return f"Δ = {r['computed'] - r['printed']:+.3g} (printed 0)"
    return _rel(r["rel_diff"])


def tolerance_text(r: dict[str, Any]) -> str:
    """The tolerance a row is judged with: a bound on a formula's discrepancy, absolute for a printed zero, else
    relative."""
    tol = r.get("tolerance")
    if tol is None:
        return "—"
    if r["printed"] is None:
        return f"discrepancy ≤ {tol:.2g}"
    if r["printed"] == 0:
        return f"|Δ| ≤ {tol:.2g}"
    return f"±{tol:.3g} (relative)" if tol < 1e-4 else f"±{tol * 100:.3g} %"


def _paper_cells(x: dict[str, Any]) -> list[str]:
    r = x["row"]
    return [x["experiment"], x["section"], x["n"], x["equation"], _fmt(r.get("line"), 9), r["id"], r["quantity"],
            printed_text(r), computed_text(r), difference_text(r), tolerance_text(r), r["verdict"],
            r.get("reason") or "", r["note"], x["today"]]


def paper_table_md(rows: list[dict[str, Any]]) -> str:
    return "\n".join(["# Every printed value of Résal (1883), in the paper's order\n",
                      "By line of the digitised text (`line`); rows not yet given a line follow, in experiment order. "
                      "`difference` is relative (computed − printed)/|printed|, or absolute (Δ) where the paper prints "
                      "zero; a printed formula's row gives its largest discrepancy from a numerical reference. "
                      "`tolerance` is what the row is judged with (the tolerance rule is in the CSV and in "
                      "index.html). `reason` says why a row that differs differs (see `configs/README.md`); `note` "
                      "says what the computed number is and what was found.\n",
                      _md_table(PAPER_HEADERS, (_paper_cells(x) for x in rows))])


def paper_table_csv(rows: list[dict[str, Any]]) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(PAPER_CSV)
    for x in rows:
        r = x["row"]
        zero = r["printed"] == 0 and r["rel_diff"] is not None
        w.writerow([_csv_cell(v) for v in (
            x["experiment"], x["section"], x["n"], x["equation"], r.get("line"), r["id"], r["quantity"],
            r["printed_text"], r["printed"], r["computed"], None if zero else r["rel_diff"],
            r["rel_diff"] if zero else None, r["tolerance"], tolerance_text(r), r.get("tolerance_rule"),
            r["verdict"], r.get("reason"), r["note"], r.get("today"), x["today"])])
    return buf.getvalue()


def paper_table_tex(rows: list[dict[str, Any]]) -> str:
    cols = "lllllp{3.5cm}p{2.5cm}lllllp{4cm}p{2cm}"
    tex = [r"% Every printed value of Résal (1883) (resal), in the paper's order; needs \usepackage{booktabs, "
           r"longtable} and UTF-8 input",
           r"\begin{longtable}{" + cols + "}", r"\toprule",
           " & ".join(_tex(h) for h in PAPER_HEADERS if h != "id") + r" \\", r"\midrule", r"\endhead"]
    tex += [" & ".join(_tex(c) for i, c in enumerate(_paper_cells(x)) if PAPER_HEADERS[i] != "id") + r" \\"
            for x in rows]
    tex += [r"\bottomrule", r"\end{longtable}", ""]
    return "\n".join(tex)


def is_beyond(r: dict[str, Any]) -> bool:
    """A row grading a claim beyond the paper's domain (``Row.domain``): counted apart from the paper's claims."""
    return r.get("domain") == "beyond"


def verdict_counts(rows: Iterable[dict[str, Any]]) -> tuple[dict[str, int], dict[str, int]]:
    """The paper's claims (rows beyond its domain left out: ``beyond_counts``) per verdict, and those that differ per
    reason code (``none given`` for a differing row without one)."""
    verdicts = dict.fromkeys(VERDICTS, 0)
    reasons = dict.fromkeys(REASONS, 0)
    for r in rows:
        if is_beyond(r):
            continue
        verdicts[r["verdict"]] = verdicts.get(r["verdict"], 0) + 1
        if r["verdict"] == "differs":
            code = r.get("reason") or "none given"
            reasons[code] = reasons.get(code, 0) + 1
    return verdicts, {k: v for k, v in reasons.items() if v}


def beyond_counts(rows: Iterable[dict[str, Any]]) -> dict[str, int]:
    """The rows beyond the paper's domain per verdict (they grade no claim where the paper applies it)."""
    verdicts = dict.fromkeys(VERDICTS, 0)
    for r in rows:
        if is_beyond(r):
            verdicts[r["verdict"]] += 1
    return verdicts


def whose_error(reasons: dict[str, int]) -> list[tuple[str, int, str]]:
    """The differing claims by whose error they show (``config.REASON_GROUPS``, in order; the group ``beyond`` is
    not among the paper's claims): (label, rows, the reason codes with their counts)."""
    out = []
    for group, codes in REASON_GROUPS.items():
        n = sum(reasons.get(c, 0) for c in codes)
        if n and group != "beyond":
            out.append((REASON_GROUP_LABELS[group], n, ", ".join(f"{c} {reasons[c]}" for c in codes if reasons.get(c))))
    if reasons.get("none given"):
        out.append(("no reason given yet", reasons["none given"], f"none given {reasons['none given']}"))
    return out


def whose_error_text(reasons: dict[str, int]) -> str:
    """One sentence: the differing claims by whose error they show, e.g. "20 Résal's errata … (erratum 12, repair 8);
    20 slips of the digitised text, not of 1883 (ocr 20)"."""
    return "; ".join(f"{n} {label} ({codes})" for label, n, codes in whose_error(reasons))


def beyond_text(rows: Iterable[dict[str, Any]]) -> str:
    """The rows beyond the paper's domain, in a phrase ("" when there are none)."""
    b = beyond_counts(rows)
    n = sum(b.values())
    if not n:
        return ""
    return (f"{n} more row{'s' if n != 1 else ''} beyond the paper's domain, counted apart: "
            + ", ".join(f"{b[v]} {v}" for v in VERDICTS if b[v]))


def measurement_counts(summaries: Iterable[dict[str, Any]]) -> dict[str, int]:
    """Measured rows per verdict (``config.MEASUREMENT_VERDICTS``): counted apart from the printed claims."""
    counts = dict.fromkeys(MEASUREMENT_VERDICTS, 0)
    for s in summaries:
        for m in s.get("measurements", ()):
            counts[m["verdict"]] = counts.get(m["verdict"], 0) + 1
    return counts


def _counts_text(verdicts: dict[str, int], reasons: dict[str, int]) -> str:
    text = ", ".join(f"{verdicts[v]} {v}" for v in VERDICTS)
    if reasons:
        text += " (" + ", ".join(f"{k} {v}" for k, v in reasons.items()) + ")"
    return text


def index_md(summaries: list[tuple[str, dict[str, Any]]]) -> str:
    all_rows = [r for _, s in summaries for r in s["rows"]]
    verdicts, reasons = verdict_counts(all_rows)
    out = ["# resal: results\n",
           "Reproduction of H. Résal (1883), *Commentaire à la théorie mathématique du jeu de billard*. "
           "[index.html](index.html) is the reader's edition (the findings first, then every row with its note, "
           "filterable). One folder per experiment; `summary.json` holds every number; "
           "[paper-table.md](paper-table.md) "
           "([csv](paper-table.csv), [tex](paper-table.tex)) lists every printed value in the paper's order, and "
           "[report.pdf](report.pdf) gathers this index, that table and every figure.\n",
           "## Verdicts\n",
           f"{sum(verdicts.values())} printed values and claims of the paper, graded where the paper applies them, in "
           f"{sum(1 for _, s in summaries if s['rows'])} experiments: "
           f"**{verdicts['reproduced']} reproduced**, **{verdicts['differs']} differ**, "
           f"**{verdicts['not-checkable']} not checkable**."
           + (f" And {beyond_text(all_rows)}.\n" if beyond_text(all_rows) else "\n"),
           _md_table(("verdict", "rows"), ([v, str(verdicts[v])] for v in VERDICTS))]
    if reasons:
        out += ["\nWhose error the differing claims show (a slip of the digitised text is not Résal's; rounded digits "
                "are no error):\n",
                _md_table(("whose error", "rows", "reasons"), ([label, str(n), codes]
                                                              for label, n, codes in whose_error(reasons))),
                "\n" + _md_table(("reason", "rows", "meaning"),
                                 ([k, str(n), REASONS.get(k, "the row names no reason yet")]
                                  for k, n in reasons.items()))]
    out += ["\n## Experiments\n",
            _md_table(("experiment", "section", "title", "reproduced", "differs", "not checkable",
                       "beyond the domain"), (
                [f"[{s['experiment']}]({name}/table.md)", s["source"]["section"], s["title"],
                 *(str(verdict_counts(s["rows"])[0][v]) for v in VERDICTS),
                 str(sum(beyond_counts(s["rows"]).values()))] for name, s in summaries if s["rows"]))]
    measured = [(name, s) for name, s in summaries if s.get("measurements")]
    if measured:
        mc = measurement_counts(s for _, s in measured)
        out += ["\n## The 1883 theory against today's measurements\n",
                f"{sum(mc.values())} published measurements in {len(measured)} experiments, each against what the "
                "paper's mechanics predict, at 95 % (counted apart from the printed claims above): "
                + ", ".join(f"**{mc[v]} {v}**" for v in MEASUREMENT_VERDICTS) + ".\n",
                _md_table(("experiment", "source", "title", *MEASUREMENT_VERDICTS), (
                    [f"[{s['experiment']}]({name}/table.md)", s["source"]["section"], s["title"],
                     *(str(measurement_counts([s])[v]) for v in MEASUREMENT_VERDICTS)] for name, s in measured))]
    for name, s in summaries:
        v, why = verdict_counts(s["rows"])
        counts = _counts_text(v, why) + (f"; {beyond_text(s['rows'])}" if beyond_text(s["rows"]) else "")
        if s.get("measurements"):
            mc = measurement_counts([s])
            counts = (f"{counts}; measurements: " if s["rows"] else "measurements: ") + ", ".join(
                f"{mc[x]} {x}" for x in MEASUREMENT_VERDICTS)
        out.append(f"\n### [{s['experiment']}]({name}/table.md): {_md_escape(s['title'])}\n")
        out.append(f"{s['source']['section']}. {counts}. Tables: [md]({name}/table.md) · "
                   f"[csv]({name}/table.csv) · [tex]({name}/table.tex) · [json]({name}/summary.json).\n")
        out += [f"![{name}/{f}]({name}/{f})\n" for f in s["figures"] if f.endswith(".png")]
    return "\n".join(out)
