"""The layering of docs/ARCHITECTURE.md, read off the code: imports point one way and form no cycle."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# lower numbers are lower layers; a module may import only from its own layer or below
LAYERS = {
    "reproductions.errors": 0, "reproductions.mechanics": 1, "reproductions.config": 2, "reproductions.series": 2,
    "reproductions.fit": 0,  # the package's __init__ only: a docstring, no imports
    "reproductions.fit.estimators": 2, "reproductions.fit.options": 2, "reproductions.fit.kinds": 5,
    "reproductions.fit.checks": 5,
    "reproductions.fit.run": 5, "reproductions.fit.report": 6,
    "reproductions.results": 3, "reproductions.experiments": 4, "reproductions.api": 5,
    "reproductions.report": 5, "reproductions.digest": 5, "reproductions.locate": 0, "reproductions.processes": 0,
    "reproductions.sweep": 0,  # the executors of stress and bench: standard library and processes only
    "reproductions.pooltool_side": 0,  # pooltool timed beside us where installed: standard library (pooltool lazily)
    "reproductions.targets": 0,  # issue 34's table read from a bench report: standard library (numpy to calibrate)
    "reproductions.startup": 0, "reproductions.diffing": 0, "reproductions.lazy": 0,
    "reproductions.edition.model": 3, "reproductions.edition": 6,
    "reproductions.models": 5, "reproductions.bench": 5,
    "reproductions.stress": 5, "reproductions.golden": 6, "reproductions.fitbench": 5, "reproductions.coverage": 6,
    "reproductions.fit.coverage_table": 0,  # reads a JSON file: no numpy, no other module of ours
    "reproductions": 0, "cli": 7,  # the package: __version__
}


def _module(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports() -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {}
    for path in [*ROOT.glob("reproductions/**/*.py"), *ROOT.glob("cli/*.py")]:
        mod = _module(path)
        pkg = mod if path.name == "__init__.py" else mod.rpartition(".")[0]
        out = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    up = pkg.split(".")[: len(pkg.split(".")) - node.level + 1]
                    base = ".".join([*up, base] if base else up)
                names = [f"{base}.{a.name}" for a in node.names]
                out |= {n if n.rpartition(".")[0] == base and _is_module(n) else base for n in names}
            elif isinstance(node, ast.Import):
                out |= {a.name for a in node.names}
        graph[mod] = {m for m in out if m.split(".")[0] in ("reproductions", "cli") and m != mod}
    return graph


def _is_module(name: str) -> bool:
    p = ROOT / Path(*name.split("."))
    return p.with_suffix(".py").is_file() or (p / "__init__.py").is_file()


def _layer(mod: str) -> int:
    best = max((k for k in LAYERS if mod == k or mod.startswith(k + ".")), key=len)
    return LAYERS[best]


def test_imports_point_down_the_layers():
    bad = [(a, b) for a, deps in _imports().items() for b in deps if _layer(b) > _layer(a)]
    assert not bad, f"imports that point up the layers: {bad}"


def test_the_physics_imports_nothing_above_it_and_reporting_no_experiment():
    g = _imports()
    for mod, deps in g.items():
        if mod.startswith("reproductions.mechanics"):
            assert all(d.startswith("reproductions.mechanics") for d in deps), (mod, deps)
    for mod in ("reproductions.report", "reproductions.config", "reproductions.results",
                *(m for m in g if m.startswith("reproductions.fit"))):
        assert not any(d.startswith("reproductions.experiments") for d in g[mod]), (mod, g[mod])


def test_no_import_cycle():
    g = _imports()
    state: dict[str, int] = {}

    def visit(m: str, stack: list[str]) -> None:
        state[m] = 1
        for d in sorted(g.get(m, ())):
            if state.get(d) == 1:
                raise AssertionError("import cycle: " + " → ".join([*stack, m, d]))
            if d in g and not state.get(d):
                visit(d, [*stack, m])
        state[m] = 2

    for m in sorted(g):
        if not state.get(m):
            visit(m, [])


def test_the_fit_package_and_the_kinds_data_import_nothing_heavy():
    """``resal --help`` reads the kinds' data: ``fit/__init__`` and ``fit/kinds/__init__`` import no numpy."""
    for rel in ("reproductions/fit/__init__.py", "reproductions/fit/kinds/__init__.py"):
        tree = ast.parse((ROOT / rel).read_text(encoding="utf-8"))
        mods = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
        mods |= {n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
        assert mods <= {"__future__", "dataclasses"}, (rel, mods)


def test_the_referees_share_no_code_with_the_paths_they_check():
    """A referee (``mechanics.referee``) imports from the project only the ODE budget: no model module, no slip
    decay, no path machinery, no older reference; two paths that share a function are one witness, not two. And
    every impact model declares a referee path in the registry, which is where bench and stress find it."""
    g = _imports()
    referees = [m for m in g if m.startswith("reproductions.mechanics.referee.")]
    assert {m.rpartition(".")[2] for m in referees} >= {"spheres", "cushion", "plane", "cue"}
    for mod in referees:
        assert g[mod] <= {"reproductions.mechanics.budget"}, (mod, g[mod])
    from reproductions.mechanics import paths, registry

    for name in ("plane-impact", "cushion-impact", "spheres-free", "spheres-cloth", "cue-stroke"):
        kinds = {p.kind for p in registry.MODELS[name].paths}
        assert paths.Kind.REFEREE in kinds, name
