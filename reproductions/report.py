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
import hashlib
import io
import json
import math
import os
import platform
import re
import secrets
import shutil
import signal
import socket
import subprocess
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import asdict
from pathlib import Path
from typing import Any

from . import __version__
from .errors import InputError
from .results import FigureSpec, Reproduction

__all__ = ["clean_stale", "make_staging", "provenance", "staging_name", "summary", "write_index",
           "write_reproduction"]

HEADERS = ("quantity", "§ / eq.", "printed", "computed", "rel. diff", "verdict", "note")


def provenance(rep: Reproduction) -> dict[str, Any]:
    """Version, git commit, config hash and library versions; golden comparisons ignore this block."""
    import numpy
    import scipy

    root = Path(__file__).resolve().parent.parent
    commit, dirty = None, None
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True,
                                timeout=5).stdout.strip() or None
        if commit:
            status = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=root,
                                    capture_output=True, text=True, timeout=5).stdout
            dirty = bool(status.strip())
    except (OSError, subprocess.SubprocessError):
        pass
    return {"version": __version__, "git_commit": commit, "dirty": dirty, "config": rep.experiment.path,
            "config_sha256": rep.experiment.sha256, "python": platform.python_version(),
            "numpy": numpy.__version__, "scipy": scipy.__version__, "seed": rep.experiment.seed}


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
        "notes": list(e.notes),
        "provenance": prov if prov is not None else {},
    }


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


def _row_cells(r: dict[str, Any]) -> list[str]:
    return [r["quantity"], r["source"], f"{r['printed_text']}", _fmt(r["computed"]), _rel(r["rel_diff"]),
            r["verdict"], r["note"]]


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
    out.append("## Printed values\n")
    out.append(_md_table(HEADERS, (_row_cells(r) for r in s["rows"])))
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


def table_csv(s: dict[str, Any]) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    cols = ["id", "quantity", "source", "printed", "printed_text", "computed", "rel_diff", "tolerance", "verdict",
            "note"]
    w.writerow(cols)
    for r in s["rows"]:
        w.writerow(["" if r[c] is None else (repr(r[c]) if isinstance(r[c], float) else r[c]) for c in cols])
    return buf.getvalue()


_TEX = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_", "{": r"\{",
        "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}


def _tex(s: str) -> str:
    return "".join(_TEX.get(ch, ch) for ch in s)


def table_tex(s: dict[str, Any]) -> str:
    lines = [f"% {s['title']} (resal {s['experiment']}); needs \\usepackage{{booktabs}} and UTF-8 input",
             r"\begin{tabular}{llllll}", r"\toprule",
             " & ".join(_tex(h) for h in HEADERS[:6]) + r" \\", r"\midrule"]
    lines += [" & ".join(_tex(c) for c in _row_cells(r)[:6]) + r" \\" for r in s["rows"]]
    lines += [r"\bottomrule", r"\end{tabular}", ""]
    return "\n".join(lines)


def _draw(spec: FigureSpec, folder: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # fixed margins, not a layout solve: the solve took a third of each figure's time (make all: 19 figures)
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    fig.subplots_adjust(left=0.12, right=0.96, bottom=0.11, top=0.84 if spec.caption else 0.88)
    for ly in spec.layers:
        if ly.kind == "line":
            ax.plot(ly.x, ly.y, ly.style, color=ly.color, label=ly.label)
        elif ly.kind == "points":
            ax.plot(ly.x, ly.y, linestyle="none", marker=ly.marker, color=ly.color, label=ly.label, ms=7)
        elif ly.kind == "band":
            ax.fill_between(ly.x, ly.y, ly.y2, color=ly.color, alpha=0.2, label=ly.label, lw=0)
        elif ly.kind == "vband":
            ax.axvspan(ly.x[0], ly.x[1], color=ly.color, alpha=0.15, label=ly.label, lw=0)
        elif ly.kind == "hband":
            ax.axhspan(ly.y[0], ly.y[1], color=ly.color, alpha=0.15, label=ly.label, lw=0)
        elif ly.kind == "errorbar":
            ax.errorbar(ly.x, ly.y, yerr=ly.y2, fmt=ly.marker, color=ly.color, label=ly.label, capsize=3)
        elif ly.kind == "heatmap":
            dx, dy = (ly.x[1] - ly.x[0]) / 2, (ly.y[1] - ly.y[0]) / 2  # a regular grid: drawn as one image
            img = ax.imshow(ly.z, origin="lower", aspect="auto", cmap="viridis", interpolation="nearest",
                            extent=(ly.x[0] - dx, ly.x[-1] + dx, ly.y[0] - dy, ly.y[-1] + dy))
            fig.colorbar(img, ax=ax, label=ly.label)
        else:
            raise ValueError(f"unknown layer kind {ly.kind!r}")
    fig.suptitle(spec.title)
    if spec.caption:
        ax.set_title(spec.caption, fontsize=7, color="0.3", wrap=True)
    ax.set(xlabel=spec.xlabel, ylabel=spec.ylabel)
    if spec.xlim:
        ax.set_xlim(*spec.xlim)
    if spec.ylim:
        ax.set_ylim(*spec.ylim)
    ax.grid(alpha=0.3)
    if any(ly.label and ly.kind != "heatmap" for ly in spec.layers):
        ax.legend(fontsize=8, loc="best")
    fig.savefig(folder / f"{spec.name}.png", dpi=120, metadata={"Software": None})
    fig.savefig(folder / f"{spec.name}.pdf", metadata={"Creator": None, "Producer": None, "CreationDate": None})
    plt.close(fig)


STAGING_PREFIX = ".resal-"
_HOST = hashlib.sha256(socket.gethostname().encode()).hexdigest()[:8]  # a pid means nothing on another host
_STAGING_RE = re.compile(r"\.resal-(?P<host>[0-9a-f]{8})-(?P<pid>[0-9]+)-[0-9a-f]{8}\.(?P<what>.+)")


def staging_name(what: str, pid: int | None = None) -> str:
    """A hidden name for something being written by this process: ``.resal-<host>-<pid>-<random>.<what>``."""
    return f"{STAGING_PREFIX}{_HOST}-{os.getpid() if pid is None else pid}-{secrets.token_hex(4)}.{what}"


def make_staging(parent: Path, what: str) -> Path:
    """A new staging folder in ``parent``, made by a plain ``mkdir``: it gets the umask's mode (not 0700)."""
    while True:
        p = parent / staging_name(what)
        try:
            p.mkdir()
            return p
        except FileExistsError:
            continue


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


@contextmanager
def _signals_deferred() -> Iterator[None]:
    """SIGINT and SIGTERM wait until the block ends (a swap of two renames is never left half done)."""
    sigs = {signal.SIGINT, signal.SIGTERM}
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _atomic_text(path: Path, text: str) -> None:
    """Write ``path`` through a temporary file beside it (a plain ``open``: the umask's mode), then rename."""
    while True:
        tmp = path.parent / staging_name(f"{path.name}.tmp")
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            break
        except FileExistsError:
            continue
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def ensure_writable(out: Path, where: str = "--out") -> None:
    """Fail early, before any work, when the output folder cannot be created or written."""
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
    eid = rep.experiment.id
    final = out / eid
    try:
        stage = make_staging(out, f"{eid}.staging")
    except OSError as exc:
        raise InputError(f"--out {out}", f"cannot write the output folder ({exc.strerror})") from None
    old = None
    try:
        (stage / "summary.json").write_text(json.dumps(s, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
        (stage / "table.md").write_text(table_md(s), encoding="utf-8")
        (stage / "table.csv").write_text(table_csv(s), encoding="utf-8")
        (stage / "table.tex").write_text(table_tex(s), encoding="utf-8")
        for spec in rep.figures:
            if drawn is None:
                _draw(spec, stage)
            else:
                for ext in ("png", "pdf"):
                    os.replace(drawn / f"{spec.name}.{ext}", stage / f"{spec.name}.{ext}")
        with _signals_deferred():  # both renames or neither: never a missing experiment folder
            if final.exists():
                old = out / staging_name(f"{eid}.old")
                os.replace(final, old)
            try:
                os.replace(stage, final)
            except BaseException:
                if old is not None:
                    os.replace(old, final)
                    old = None
                raise
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        if old is not None and final.exists():
            shutil.rmtree(old, ignore_errors=True)
        raise
    return final


def _summaries(out: Path) -> list[tuple[str, dict[str, Any]]]:
    """(folder name, summary) of every experiment written under ``out``, in the paper's order (page, id)."""
    found = []
    for d in sorted(p for p in out.iterdir() if p.is_dir() and not p.name.startswith(".")):
        f = d / "summary.json"
        if f.is_file():
            found.append((d.name, json.loads(f.read_text(encoding="utf-8"))))
    return sorted(found, key=lambda x: (x[1]["source"].get("page") or 0, x[1]["experiment"]))


def write_index(out: Path) -> Path:
    """``out/index.md`` (one line per experiment found under ``out``, with its verdict counts) and
    ``out/paper-table.{md,tex}`` (every printed value of the paper, in the paper's order)."""
    lines = ["# resal: results\n", "Reproduction of H. Résal (1883), *Commentaire à la théorie mathématique du jeu "
             "de billard*. One folder per experiment; `summary.json` holds every number; "
             "[paper-table.md](paper-table.md) lists every printed value.\n",
             "| experiment | section | title | reproduced | differs | not checkable | tables |",
             "|---|---|---|---|---|---|---|"]
    summaries = _summaries(out)
    for name, s in summaries:
        v = [r["verdict"] for r in s["rows"]]
        lines.append(f"| [{s['experiment']}]({name}/table.md) | {s['source']['section']} | {_md_escape(s['title'])} "
                     f"| {v.count('reproduced')} | {v.count('differs')} | {v.count('not-checkable')} "
                     f"| [md]({name}/table.md) · [csv]({name}/table.csv) · [tex]({name}/table.tex) · "
                     f"[json]({name}/summary.json) |")
    path = out / "index.md"
    _atomic_text(path, "\n".join(lines) + "\n")
    md = ["# Every printed value of Résal (1883), in the paper's order\n"]
    md.append(_md_table(("experiment", *HEADERS), ([s["experiment"], *_row_cells(r)] for _, s in summaries
                                                    for r in s["rows"])))
    _atomic_text(out / "paper-table.md", "\n".join(md))
    tex = [r"% Every printed value of Résal (1883) (resal); needs \usepackage{booktabs, longtable} and UTF-8 input",
           r"\begin{longtable}{lllllll}", r"\toprule",
           " & ".join(_tex(h) for h in ("experiment", *HEADERS[:6])) + r" \\", r"\midrule"]
    tex += [" & ".join(_tex(c) for c in [s["experiment"], *_row_cells(r)[:6]]) + r" \\"
            for _, s in summaries for r in s["rows"]]
    tex += [r"\bottomrule", r"\end{longtable}", ""]
    _atomic_text(out / "paper-table.tex", "\n".join(tex))
    return path
