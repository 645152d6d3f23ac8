"""What a results folder was computed from, as one digest, so that a run whose inputs have not changed reuses it.

An experiment folder depends on its config file, the data files its config names, the code that runs and writes
it, and the libraries that code calls. Its digest is the SHA-256 of

- the config file's bytes and each data file's (by the path the config gives);
- the code: every module of the package that the experiment kinds, the result types and the report writer import,
  found by reading their ``import`` statements (an import inside a function counts), closed over, plus the
  package's data files (``modern-values.csv``). A module nothing of theirs imports (the reader's edition, the CLI,
  ``bench``) is not in it: editing it recomputes nothing;
- resal's version, Python's and the runtime dependencies' (numpy, scipy, matplotlib … as installed).

``summary.json`` records it (``provenance.digest``) with the data files' own digests. Every folder resal writes
also holds ``manifest.json``: each file resal wrote there, with its SHA-256. A later run recomputes the digest from
the files as they are now, without importing the physics or parsing the config; when it matches and every file of
the manifest still has the bytes resal wrote, the folder is reused. A file changed by hand (a summary edited, a
figure replaced) makes the run compute that experiment again and say which file it was. ``resal reproduce
--force`` recomputes regardless. The whole-paper files (index, paper table, HTML, PDF) have their own digest, of
every experiment folder's files that resal wrote and of the code that renders them, kept with each whole-paper
file's SHA-256 in ``<out>/edition-digest.json``.
"""

from __future__ import annotations

import functools
import hashlib
import json
import platform
import re
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path, PurePath
from typing import Any

from . import __version__

__all__ = [
    "DEPENDENCIES",
    "EDITION_ROOTS",
    "EXPERIMENT_ROOTS",
    "INDEX_FILE",
    "INDEX_OUTPUTS",
    "MANIFEST",
    "changed_by_hand",
    "code_digest",
    "data_files",
    "edition_digest",
    "experiment_digest",
    "file_sha256",
    "import_closure",
    "index_current",
    "mark_index",
    "read_manifest",
    "record",
    "reusable",
    "reuse",
]

PACKAGE = Path(__file__).resolve().parent
DEPENDENCIES = ("numpy", "scipy", "matplotlib", "rich", "typer", "PyYAML", "typst", "latex2mathml")
# what an experiment folder is made by: the kinds (and through them the physics and the fits), the config reader,
# the result types, the report writer (tables and figures)
EXPERIMENT_ROOTS = ("reproductions.experiments", "reproductions.config", "reproductions.results",
                    "reproductions.report")
# what the whole-paper files are made by
EDITION_ROOTS = ("reproductions.edition", "reproductions.report")
INDEX_FILE = "edition-digest.json"
INDEX_OUTPUTS = ("index.md", "paper-table.md", "paper-table.csv", "paper-table.tex", "index.html", "report.pdf")
_TABLES = ("summary.json", "table.md", "table.csv", "table.tex")


def file_sha256(path: str | Path) -> str | None:
    """The SHA-256 of a file's bytes, or None when it cannot be read."""
    h = hashlib.sha256()
    try:
        with open(path, "rb") as fh:
            for chunk in iter(lambda: fh.read(1 << 20), b""):
                h.update(chunk)
    except OSError:
        return None
    return h.hexdigest()


def _module_file(name: str) -> Path | None:
    """The source file of the package's module ``name`` (``reproductions.x.y``), or None."""
    parts = name.split(".")
    if parts[0] != "reproductions":
        return None
    p = PACKAGE.joinpath(*parts[1:])
    if (p / "__init__.py").is_file():
        return p / "__init__.py"
    return p.with_suffix(".py") if p.with_suffix(".py").is_file() else None


_FROM = re.compile(rb"^[ \t]*from[ \t]+(\.*[\w.]*)[ \t]+import[ \t]+(\([^)]*\)|[^\n#;]*)", re.M)
_IMPORT = re.compile(rb"^[ \t]*import[ \t]+([^\n#;]+)", re.M)


def _imports(name: str, path: Path) -> set[str]:
    """The package's modules that the module ``name`` (at ``path``) imports, at any indentation (an import inside a
    function counts). Read off the lines by pattern, not parsed: ten times faster than ``ast``, and a line of a
    docstring that reads like an import can only add a module, never lose one."""
    pkg = name if path.name == "__init__.py" else name.rpartition(".")[0]
    text = path.read_bytes()
    found: set[str] = set()
    for m in _FROM.finditer(text):
        dots = len(m[1]) - len(m[1].lstrip(b"."))
        base = m[1][dots:].decode()
        if dots:
            up = pkg.split(".")[: len(pkg.split(".")) - dots + 1]
            base = ".".join([*up, base] if base else up)
        found.add(base)
        for item in m[2].strip(b"()").split(b","):
            sub = item.split()[0].decode() if item.split() else ""
            if sub and _module_file(f"{base}.{sub}") is not None:
                found.add(f"{base}.{sub}")
    for m in _IMPORT.finditer(text):
        found |= {item.split()[0].decode() for item in m[1].split(b",") if item.split()}
    # importing a.b.c runs a/__init__ and a/b/__init__ first
    parents = {".".join(m.split(".")[:i]) for m in found for i in range(1, m.count(".") + 1)}
    return {m for m in found | parents if _module_file(m) is not None and m != name}


def import_closure(roots: Iterable[str]) -> dict[str, Path]:
    """Every module of the package that ``roots`` import, directly or not, with its file (roots included)."""
    todo, seen = list(roots), {}
    while todo:
        name = todo.pop()
        path = _module_file(name)
        if name in seen or path is None:
            continue
        seen[name] = path
        todo += sorted(_imports(name, path) - seen.keys())
    return dict(sorted(seen.items()))


@functools.lru_cache(maxsize=1)  # importlib.metadata scans site-packages: 0.1 s a call
def _versions() -> dict[str, str | None]:
    from importlib import metadata

    out: dict[str, str | None] = {"resal": __version__, "python": platform.python_version()}
    for d in DEPENDENCIES:
        try:
            out[d] = metadata.version(d)
        except metadata.PackageNotFoundError:
            out[d] = None
    return out


@functools.lru_cache(maxsize=4)
def code_digest(roots: tuple[str, ...] = EXPERIMENT_ROOTS) -> str:
    """The digest of the modules ``roots`` import (their paths inside the package and their bytes), the package's
    data files, and the versions of resal, Python and the runtime dependencies."""
    h = hashlib.sha256()
    modules = import_closure(roots).values()
    # a package's templates (the edition's CSS, script and Typst source) are its code too
    templates = sorted({t for m in modules for t in (m.parent / "templates").glob("*") if t.is_file()})
    files = [*modules, *templates, *sorted(p for p in (PACKAGE / "data").rglob("*") if p.is_file())]
    for f in files:
        h.update(f.relative_to(PACKAGE).as_posix().encode() + b"\0" + (file_sha256(f) or "unreadable").encode()
                 + b"\n")
    h.update(json.dumps(_versions(), sort_keys=True).encode())
    return h.hexdigest()


def _paths(value: Any) -> Iterator[PurePath]:
    if isinstance(value, PurePath):
        yield value
    elif isinstance(value, Mapping):
        for v in value.values():
            yield from _paths(v)
    elif isinstance(value, (list, tuple)):
        for v in value:
            yield from _paths(v)
    elif hasattr(value, "__dataclass_fields__"):
        for f in value.__dataclass_fields__:
            yield from _paths(getattr(value, f))


def data_files(params: Any) -> list[str]:
    """The data files an experiment's parameters name (every path among them), sorted, each once."""
    return sorted({str(p) for p in _paths(params)})


def experiment_digest(config_sha256: str, data: Mapping[str, str | None], code: str) -> str:
    """The digest of one experiment folder's inputs: its config's, its data files' and the code's digests."""
    h = hashlib.sha256(f"config {config_sha256}\ncode {code}\n".encode())
    for path, sha in sorted(data.items()):
        h.update(f"data {path} {sha}\n".encode())
    return h.hexdigest()


def record(config_sha256: str, params: Any) -> dict[str, Any]:
    """``provenance.digest`` of a summary being written: the digest and what it is made of."""
    data = {p: file_sha256(p) for p in data_files(params)}
    code = code_digest()
    return {"inputs": experiment_digest(config_sha256, data, code), "code": code, "data": data}


def reuse(folder: Path, config: Path) -> tuple[dict[str, Any] | None, str | None]:
    """(summary, None) when ``folder`` was computed from the file ``config`` as it is now, its data files as they
    are now, with today's code, and every file resal wrote there (its manifest) has the bytes it wrote; else
    (None, why) — ``why`` is None for the ordinary reasons to recompute (no folder yet, an input changed) and a
    sentence for a folder that resal's outputs were changed in by hand, which the run says. Nothing is ever
    guessed: a summary that cannot be read, or was written without a digest or a manifest, is recomputed."""
    changed = changed_by_hand(folder)
    if changed is None:
        return None, None
    if changed:
        shown = ", ".join(changed[:4]) + (f" and {len(changed) - 4} more" if len(changed) > 4 else "")
        return None, f"{folder}: {shown} changed since resal wrote {'it' if len(changed) == 1 else 'them'}"
    try:
        summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
        prov = summary["provenance"]
        recorded = prov["digest"]
        if prov.get("config") != str(config) or not isinstance(recorded, dict):
            return None, None
        sha = file_sha256(config)
        data = {str(p): file_sha256(p) for p in recorded.get("data", {})}
        if sha is None or None in data.values():
            return None, None
        if recorded.get("inputs") != experiment_digest(sha, data, code_digest()):
            return None, None
        files = [*_TABLES, *summary.get("figures", [])]
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return None, None
    listed = read_manifest(folder) or {}
    return (summary, None) if all(f in listed for f in files) else (None, None)


def reusable(folder: Path, config: Path) -> dict[str, Any] | None:
    """The summary of ``folder`` when it can be reused as it is (``reuse``), else None."""
    return reuse(folder, config)[0]


MANIFEST = "manifest.json"  # in every folder resal writes: the files it wrote there, each with its SHA-256


def read_manifest(folder: Path) -> dict[str, str] | None:
    """The files resal wrote in ``folder`` (name → SHA-256), from its manifest; None when there is none or it is
    not resal's (then no file of the folder is known to be ours)."""
    try:
        m = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
        files = m["files"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if not isinstance(files, dict) or not all(isinstance(k, str) and isinstance(v, str) and "/" not in k
                                              and k not in ("", ".", "..", MANIFEST) for k, v in files.items()):
        return None
    return files


def changed_by_hand(folder: Path) -> list[str] | None:
    """The files of ``folder``'s manifest that are missing or whose bytes are not those resal wrote, sorted;
    None when the folder has no manifest (nothing can be verified)."""
    files = read_manifest(folder)
    if files is None:
        return None
    return sorted(n for n, sha in files.items() if file_sha256(folder / n) != sha)


def edition_digest(folders: Iterable[Path]) -> str:
    """The digest of the whole-paper files' inputs: each experiment folder's files that resal wrote (its manifest;
    every file when it has none), by bytes, and the code that renders them. A user's notes in a folder change
    nothing."""
    h = hashlib.sha256(f"code {code_digest(EDITION_ROOTS)}\n".encode())
    for d in sorted(folders):
        h.update(f"folder {d.name}\n".encode())
        listed = read_manifest(d)
        names = sorted(listed) if listed is not None else sorted(p.name for p in d.iterdir() if p.is_file())
        for n in names:
            h.update(f"{n} {file_sha256(d / n)}\n".encode())
    return h.hexdigest()


def index_current(out: Path, digest: str) -> tuple[bool, list[str]]:
    """(whether ``out``'s whole-paper files were rendered from inputs of this digest and each still has the bytes
    resal wrote, the files among them changed by hand since)."""
    try:
        rec = json.loads((out / INDEX_FILE).read_text(encoding="utf-8"))
        recorded, files = rec.get("digest"), rec.get("files")
    except (OSError, ValueError, AttributeError):
        return False, []
    if not isinstance(files, dict):
        return False, []
    changed = sorted(f for f in INDEX_OUTPUTS if file_sha256(out / f) != files.get(f))
    return recorded == digest and not changed, changed


def mark_index(out: Path, digest: str) -> None:
    """Record that ``out``'s whole-paper files were rendered from inputs of this digest, with each one's SHA-256
    (written whole)."""
    tmp = out / f"{INDEX_FILE}.tmp"
    files = {f: file_sha256(out / f) for f in INDEX_OUTPUTS}
    tmp.write_text(json.dumps({"digest": digest, "files": files}, indent=1) + "\n", encoding="utf-8")
    tmp.replace(out / INDEX_FILE)
