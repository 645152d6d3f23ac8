"""Every command's default output at 80 columns, as a pipe (``resal … | cat``) or a small terminal shows it.

Each command runs through typer's runner with its console 80 columns wide and again 200 wide, and its stdout
must have:

- no line longer than 80 characters, except a line that is one path alone (a path cannot be broken: it is left
  whole rather than folded, see ``_fits``);
- no word broken across lines: every word of the 200-column output appears whole in the 80-column one (the words
  of the wide tables' column headers excepted: at 80 columns a row is a record whose lead cells carry no label);
- its key content: the units of ``simulate``, the full model and path names of ``bench`` and ``stress``, the
  experiments and verdicts of ``reproduce``, both paths of each side of ``diff``.

The computations of ``fit`` and ``bench`` run once and are rendered at both widths (the report is cached).
``bench`` runs in its smallest form, ``--quick`` on the models with the longest names (all models take ~9 s);
``stress`` in its smallest form that runs (``--scenes 10 --ode-scenes 1``; ``--scenes 2`` ends with an
IndexError in ``paths.solve``). ``reproduce --all`` runs on three experiments (``$RESAL_CONFIGS``), the longest
id among them.
"""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from cli import main
from cli.main import app
from reproductions import api, report
from reproductions.fit.kinds import KINDS
from reproductions.mechanics import paths, registry

ROOT = Path(__file__).resolve().parent.parent
NARROW, WIDE = 80, 200

# the scenes of the README, one per model
SCENES = {
    "direct-impact": ["--set", "M=3", "--set", "Mp=1", "--set", "V0=1", "--set", "eps=0", "--set", "epsp=0.2667"],
    "wall-impact": ["--set", "eps=0.3"],
    "plane-impact": ["--set", "chi0=1", "--set", "zeta0=-2", "--set", "f=0.2", "--set", "nu=0.8"],
    "ricochet": ["--set", "a0=2", "--set", "alpha0=20", "--set", "f=0.2", "--set", "nu=0.8"],
    "cloth-slide": ["--set", "vx=2", "--set", "wx=60", "--set", "f=0.25"],
    "cushion-impact": ["--set", "chi0=1", "--set", "p0=20", "--set", "j=0.2", "--set", "eps=0.3"],
    "spheres-free": ["--set", "v=2,0.5,0", "--set", "f=0.03", "--set", "eps=0.03", "--set", "epsp=0.03"],
    "spheres-cloth": ["--set", "v=2,0.5,0", "--set", "f=0.03", "--set", "eps=0.03", "--set", "epsp=0.03"],
    "cue-stroke": ["--set", "i=60", "--set", "b=0.01", "--set", "c=0.02", "--set", "f=0.25", "--set", "eps=0",
                   "--set", "epsp=0.8"],
}
# the column headers of the wide (≥ 140 columns) tables of reproduce and fit: at 80 columns the lead cell of a
# record (the quantity, the parameter) and the verdict in brackets have no label
HEADER_WORDS = {"quantity", "verdict", "parameter", "identifiable", "std", "error", "line", "reason", "rel",
                "diff", "bootstrap", "interval", "printed", "computed", "note", "value"}
# and the identifiable column's values: a fit's record says "(not identifiable)" or nothing
FIT_FLAGS = {"yes", "no"}


def run(*args: object, width: int) -> Result:
    """One command with the output console ``width`` columns wide (as a pipe is 80)."""
    before = main.out_console._width
    main.out_console.width = width
    try:
        return CliRunner(env={"COLUMNS": str(width)}).invoke(app, [str(a) for a in args])
    finally:
        main.out_console._width = before


def words(text: str) -> set[str]:
    """The words of a text: letters, with inner hyphens, apostrophes, primes or underscores (codes such as
    cushion-impact, resal-corrected, vis_viva_lost); numbers and symbols are not words."""
    out = set()
    for tok in re.findall(r"[^\s│┃┏┓┗┛━─┡┩╇┳┻╋┼┃]+", text):
        tok = tok.strip(".,;:()[]{}\"'«»*")
        if re.fullmatch(r"[A-Za-zÀ-ÿ]+(?:[-'’′_][A-Za-zÀ-ÿ]+)*", tok):
            out.add(tok)
    return out


def _fits(text: str) -> list[str]:
    """The lines longer than 80 columns, a line that is one path alone (no space, a slash) allowed."""
    return [ln for ln in text.splitlines() if len(ln.rstrip()) > NARROW
            and not (len(ln.split()) == 1 and "/" in ln)]


def check(narrow: Result, wide: Result, ignore: set[str] = frozenset()) -> str:
    """Both ran; the narrow stdout fits 80 columns and holds every word of the wide one whole."""
    assert narrow.exit_code == wide.exit_code, (narrow.output, wide.output)
    assert "Traceback" not in narrow.output
    assert not _fits(narrow.stdout), _fits(narrow.stdout)
    missing = words(wide.stdout) - words(narrow.stdout) - ignore
    assert not missing, (sorted(missing), narrow.stdout)
    return narrow.stdout


def both(*args: object) -> tuple[Result, Result]:
    return run(*args, width=NARROW), run(*args, width=WIDE)


@pytest.fixture()
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Run in a scratch folder (relative paths: short, as a user types them), with the shipped experiments."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("RESAL_CONFIGS", raising=False)
    return tmp_path


@pytest.fixture(scope="module")
def pendulum(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Result, Result]:
    """``reproduce coriolis-pendulum`` at both widths, in a scratch folder; the written results folder."""
    folder = tmp_path_factory.mktemp("pendulum")
    narrow = run("reproduce", "coriolis-pendulum", "--out", folder / "res", width=NARROW)
    wide = run("reproduce", "coriolis-pendulum", "--out", folder / "wide", width=WIDE)
    return folder, narrow, wide


# -- list and reproduce -----------------------------------------------------------------------------------------
def test_list(here: Path) -> None:
    titles = words(" ".join(e.title for e in api.list_experiments()))  # a title is cut at a word to fit a line
    out = check(*both("list"), ignore=titles)
    assert all(e in words(out) for e in api.experiment_ids())


def test_reproduce_one_experiment_as_records(pendulum: tuple[Path, Result, Result]) -> None:
    folder, narrow, wide = pendulum
    out = check(narrow, wide, ignore=HEADER_WORDS | FIT_FLAGS)
    s = json.loads((folder / "res" / "coriolis-pendulum" / "summary.json").read_text(encoding="utf-8"))
    for r in s["rows"]:  # every row, its verdict, and its note's words whole
        assert f"[{r['verdict']}]" in out
        assert words(r["note"]) <= words(out), r["id"]
    assert words(" ".join(f["note"] for f in s["fits"])) <= words(out)
    # the record puts section and line on one line, the relative difference and reason beside the computed value
    assert "where    §I n°5, line 164" in out and "(difference -50.00%; reason: assumption)" in out
    assert len(out.splitlines()) < 160  # 199 lines when each cell had its own line


def test_reproduce_all_prints_a_line_per_experiment(here: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    configs = here / "configs"
    configs.mkdir()
    ids = ["coriolis-cushion", "coriolis-pendulum", "marble-drop"]  # coriolis-pendulum: the longest id
    for i in ids:
        shutil.copy(api.config_dir() / f"{i}.yaml", configs)
    monkeypatch.setenv("RESAL_CONFIGS", str(configs))
    res = run("reproduce", "--all", "--out", "res", width=NARROW)
    assert res.exit_code == 0, res.output
    assert not _fits(res.stdout), res.stdout
    lines = res.stdout.splitlines()
    assert [ln.split()[0] for ln in lines[:3]] == ids
    assert lines[3].startswith("total") and lines[-1] == "folders: res/<experiment>/"
    reasons = report.verdict_counts([r for i in ids for r in json.loads(
        (here / "res" / i / "summary.json").read_text(encoding="utf-8"))["rows"]])[1]
    assert all(f"{k} {n}" in res.stdout for k, n in reasons.items())  # a reason never parted from its count


def test_reproduce_json_without_out_prints_and_writes_nothing(here: Path) -> None:
    """A pipe user (``resal reproduce my.yaml --json | jq``) gets the summary and no results/ folder."""
    res = run("reproduce", "marble-drop", "--json", width=NARROW)
    assert res.exit_code == 0, res.output
    s = json.loads(res.stdout)
    assert s["experiment"] == "marble-drop" and s["provenance"]["config_sha256"]
    assert list(here.iterdir()) == []
    # with --out, the same summary, and the files
    written = run("reproduce", "marble-drop", "--json", "--out", "res", width=NARROW)
    assert written.exit_code == 0 and json.loads(written.stdout) == s
    assert (here / "res" / "marble-drop" / "summary.json").is_file()
    assert "writes no file unless --out" in " ".join(run("reproduce", "--help", width=NARROW).stdout.split())


# -- simulate -----------------------------------------------------------------------------------------------------
def test_every_model_has_a_scene_here() -> None:
    assert set(SCENES) == set(registry.MODELS)


@pytest.mark.parametrize("model", list(SCENES))
def test_simulate_prints_every_output_with_its_unit(here: Path, model: str) -> None:
    out = check(*both("simulate", model, *SCENES[model]))
    res = run("simulate", model, *SCENES[model], "--json", width=NARROW)
    units = json.loads(res.stdout)["units"]
    assert set(units) == {"inputs", "outputs"}
    for side in ("inputs", "outputs"):
        for name, unit in units[side].items():
            assert unit, (model, name)
            shown = "" if unit in ("code", "flag") else unit
            row = re.compile(rf"^(?:in|out)?\s+{re.escape(name)}\s.*\s{re.escape(shown)}(\s|$)" if shown else
                             rf"^(?:in|out)?\s+{re.escape(name)}\s", re.M)
            assert row.search(out), (model, name, unit, out)


def test_simulate_gives_angles_in_degrees_like_its_inputs() -> None:
    res = run("simulate", "cue-stroke", *SCENES["cue-stroke"], "--json", width=NARROW)
    got = json.loads(res.stdout)
    assert got["inputs"]["i"] == 60.0 and got["units"]["inputs"]["i"] == "degrees"  # not 59.99999999999999
    assert got["units"]["outputs"]["gamma"] == "degrees"
    m = registry.MODELS["cue-stroke"]
    import math

    scene = m.scene({"i": math.radians(60), "b": 0.01, "c": 0.02, "f": 0.25, "eps": 0.0, "epsp": 0.8})
    radians = float(paths.solve(m, scene, "auto").gamma)
    assert radians != 0 and got["outputs"]["gamma"] == pytest.approx(math.degrees(radians), rel=1e-13)
    ode = run("simulate", "cue-stroke", *SCENES["cue-stroke"], "--method", "ode", "--json", width=NARROW)
    assert ode.exit_code == 0, ode.output  # the ode path computes no slip direction: null, not an overflow error
    assert json.loads(ode.stdout)["outputs"]["gamma"] is None


def test_simulate_list_shows_units_ranges_and_defaults(here: Path) -> None:
    out = check(*both("simulate", "--list"))
    info = json.loads(run("simulate", "--list", "--json", width=NARROW).stdout)
    for m in info["models"]:
        assert m["model"] in words(out)
        for o in m["outputs"]:
            assert f"{o['name']} ({o['unit']})" in out
    assert re.search(r"^\s+alpha0\s+degrees\s+0 < alpha0 < 90\s+20\s", out, re.M)  # typed in degrees
    assert re.search(r"^\s+eps\s+1\s+0 ≤ eps ≤ 1\s+required\s", out, re.M)
    assert re.search(r"^\s+n\s+1\s+1 ≤ n ≤ 1000, whole\s+12\s", out, re.M)


# -- fit ----------------------------------------------------------------------------------------------------------
@pytest.fixture()
def fit_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each fit computed once, rendered at both widths."""
    from reproductions.fit import run as fit_run

    real, cache = fit_run.fit_csv, {}

    def cached(name: str, csv: Path, opts: object) -> object:
        if (name, str(csv)) not in cache:
            cache[(name, str(csv))] = real(name, csv, opts)
        return cache[(name, str(csv))]

    monkeypatch.setattr(fit_run, "fit_csv", cached)


@pytest.mark.parametrize("kind", list(KINDS))
def test_fit(here: Path, fit_once: None, kind: str) -> None:
    data = ROOT / "examples" / KINDS[kind].example
    narrow = run("fit", kind, data, "--no-plot", "--out", "narrow", width=NARROW)
    wide = run("fit", kind, data, "--no-plot", "--out", "wide", width=WIDE)
    check(narrow, wide, ignore=HEADER_WORDS)


# -- diff ---------------------------------------------------------------------------------------------------------
def test_diff_labels_each_side_by_its_path(here: Path, pendulum: tuple[Path, Result, Result]) -> None:
    shutil.copytree(pendulum[0] / "res", "a")
    shutil.copytree(pendulum[0] / "res", "b")
    s = json.loads(Path("b/coriolis-pendulum/summary.json").read_text(encoding="utf-8"))
    next(r for r in s["rows"] if r["id"] == "eq7")["computed"] = 0.3
    Path("b/coriolis-pendulum/summary.json").write_text(json.dumps(s), encoding="utf-8")
    shutil.copytree("b/coriolis-pendulum", "b/mine")

    one = check(*both("diff", "a/coriolis-pendulum", "b/coriolis-pendulum"))
    assert both("diff", "a/coriolis-pendulum", "b/coriolis-pendulum")[0].exit_code == 1
    assert "golden" not in one and " now" not in one
    assert re.search(r"^rows\.eq7\.computed \(rtol", one, re.M)
    assert re.search(r"^  a/coriolis-pendulum/summary\.json: +[0-9.e-]+$", one, re.M)
    assert re.search(r"^  b/coriolis-pendulum/summary\.json: +0\.3$", one, re.M)

    folders = check(*both("diff", "a", "b"))  # results folders: every experiment in both, and those in one only
    assert "1 experiment(s) in both a and b" in folders and "coriolis-pendulum: 1 of" in folders
    assert "only in b: mine" in folders

    same = run("diff", "a", "a", width=NARROW)
    assert same.exit_code == 0 and "coriolis-pendulum: same numbers" in same.stdout

    mixed = run("diff", "a", "b/coriolis-pendulum", width=NARROW)
    assert mixed.exit_code == 2 and mixed.stdout == "" and mixed.stderr.count("\n") == 1
    assert "a: is a results folder and b/coriolis-pendulum one experiment" in mixed.stderr
    help_text = " ".join(run("diff", "--help", width=NARROW).stdout.split())
    assert "Exit status: 0 the same numbers, 1 some differ" in help_text and "2 bad input" in help_text


# -- bench and stress ---------------------------------------------------------------------------------------------
def _names_whole(out: str, models: list[str]) -> None:
    """Every model and path name whole, in its own column (a name is a code a user types)."""
    for name in models:
        assert re.search(rf"^{re.escape(name)}$", out, re.M), name
        for p in [*(p.name for p in registry.MODELS[name].paths), "auto"]:
            assert re.search(rf"^  {re.escape(p)}\s", out, re.M), (name, p)


@pytest.fixture()
def bench_once(monkeypatch: pytest.MonkeyPatch) -> None:
    from reproductions import bench

    real, cache = bench.run, {}

    def cached(models: list[str] = (), quick: bool = False, progress: object = None, **where: object) -> dict:
        key = (tuple(models), quick)  # where it runs (jobs, scheduler) changes only the timings
        if key not in cache:
            cache[key] = real(models, quick=quick, progress=progress, **where)
        return cache[key]

    monkeypatch.setattr(bench, "run", cached)


def test_bench_keeps_full_names(here: Path, bench_once: None) -> None:
    models = ["cushion-impact", "spheres-cloth"]  # the longest model name, resal-corrected, the longest kinds
    out = check(run("bench", *models, "--quick", "--out", "n", width=NARROW),
                run("bench", *models, "--quick", "--out", "w", width=WIDE))
    _names_whole(out, models)
    assert "approximation-as-printed" in out and "corrected-approximation" in out


def test_stress_keeps_full_names(here: Path) -> None:
    args = ("stress", "--scenes", "10", "--ode-scenes", "1")
    out = check(run(*args, "--out", "n", width=NARROW), run(*args, "--out", "w", width=WIDE))
    _names_whole(out, list(registry.MODELS))
