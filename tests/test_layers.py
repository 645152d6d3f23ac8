"""The layering of docs/ARCHITECTURE.md, read off the code: imports point one way and form no cycle."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# lower numbers are lower layers; a module may import only from its own layer or below
LAYERS = {
    "reproductions.errors": 0, "reproductions.mechanics": 1, "reproductions.fitting": 2, "reproductions.config": 2,
    "reproductions.series": 2,
    "reproductions.estimation": 2, "reproductions.fitting_ballball": 2, "reproductions.fitkinds": 0,
    "reproductions.fitreport": 6, "reproductions.results": 3, "reproductions.experiments": 4, "reproductions.api": 5,
    "reproductions.report": 5, "reproductions.userfit": 5, "reproductions.models": 5, "reproductions.bench": 5,
    "reproductions.stress": 5, "reproductions.golden": 6, "reproductions": 0, "cli": 7,  # the package: __version__
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
    for mod in ("reproductions.report", "reproductions.userfit", "reproductions.config", "reproductions.results"):
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
