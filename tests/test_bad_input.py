"""Bad input of any kind ends ``resal`` with one clear message on stderr and exit status 2.

The message names the place (``file:line`` for YAML and CSV files, the argument otherwise) and what was
expected; there is no Python traceback, and nothing under the results folder changes. Every bad config is
a mutated copy of a real one from ``configs/``, and the line numbers asserted are computed from its text.

Rich wraps long messages at the console width, so messages are compared with all whitespace removed.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
import yaml
from cli_helpers import assert_bad, invoke, snapshot

from reproductions import config
from reproductions.errors import InputError
from reproductions.experiments import KINDS, pendulum

CONFIGS = Path(__file__).resolve().parent.parent / "configs"
KNOWN_IDS = sorted(p.stem for p in CONFIGS.glob("*.yaml"))


# -- helpers ------------------------------------------------------------------------------------------------
@pytest.fixture(autouse=True)
def _default_configs(monkeypatch: pytest.MonkeyPatch) -> None:
    """Experiment ids resolve against the source tree's configs/, whatever the caller's environment says."""
    monkeypatch.delenv("RESAL_CONFIGS", raising=False)


def config_text(name: str) -> str:
    return (CONFIGS / f"{name}.yaml").read_text(encoding="utf-8")


def mutate(text: str, old: str, new: str) -> str:
    assert text.count(old) == 1, f"{old!r} must occur exactly once in the config"
    return text.replace(old, new)


def line_of(text: str, needle: str) -> int:
    """1-based line number of the unique occurrence of ``needle`` in ``text``."""
    assert text.count(needle) == 1, f"{needle!r} must occur exactly once"
    return text[: text.index(needle)].count("\n") + 1


def write_csv_config(tmp_path: Path, rows: str, eid: str = "csv-cushion") -> tuple[Path, Path]:
    """A rebound config in ``tmp_path`` whose series is ``csv: data.csv``, and that CSV file."""
    text = mutate(config_text("coriolis-cushion"), "    synthetic: {n: 24, low: 0.5, high: 7.0, noise: 0.03}",
                  "    csv: data.csv")
    text = mutate(text, "id: coriolis-cushion", f"id: {eid}")
    cfg = tmp_path / f"{eid}.yaml"
    cfg.write_text(text, encoding="utf-8")
    csv = tmp_path / "data.csv"
    csv.write_text(rows, encoding="utf-8")
    return cfg, csv


@pytest.fixture(scope="module")
def baseline(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A results folder written by a successful ``resal reproduce coriolis-cushion``."""
    out = tmp_path_factory.mktemp("baseline") / "res"
    result = invoke("reproduce", "coriolis-cushion", "--out", out)
    assert result.exit_code == 0, (result.output, repr(result.exception))
    assert (out / "coriolis-cushion" / "summary.json").is_file()
    assert (out / "index.md").is_file()
    return out


@pytest.fixture
def results(baseline: Path, tmp_path: Path) -> Path:
    """A private copy of the baseline results folder."""
    out = tmp_path / "res"
    shutil.copytree(baseline, out)
    return out


def load_experiment(path):
    return config.load_experiment(path, KINDS)


# -- bad YAML configs: load_experiment and the CLI ----------------------------------------------------------
CUSHION, PENDULUM = "coriolis-cushion", "coriolis-pendulum"

# (config, old text, new text, text marking the expected line in the mutated file, message fragments)
YAML_CASES = [
    pytest.param(CUSHION, 'equations: ["(9)"]}', 'equations: ["(9)"}', 'equations: ["(9)"}',
                 ("malformed YAML", "expected ',' or ']'"), id="malformed-unclosed-bracket"),
    pytest.param(CUSHION, "kind: rebound", "kind: rebound: yes", "kind: rebound: yes", ("malformed YAML",),
                 id="malformed-mapping-in-value"),
    pytest.param(CUSHION, "title: \"Coriolis's cushion: normal-velocity ratio 0.55 up to 7 m/s\"\n", "",
                 "id: coriolis-cushion", ("missing required key 'title'", "a text"), id="missing-title"),
    pytest.param(CUSHION, "    speed_max: 7.0", "    colour: red\n    speed_max: 7.0", "colour: red",
                 ("unknown key 'params.measured.colour'",), id="unknown-key-rebound"),
    pytest.param(PENDULUM, "    V0_max: 2.80", "    colour: red\n    V0_max: 2.80", "colour: red",
                 ("unknown key 'params.measured.colour'",), id="unknown-key-pendulum"),
    pytest.param(PENDULUM, "mass: 0.2}", "mass: heavy}", "mass: heavy",
                 ("'params.struck.mass'", "a mass in kg", "'heavy'"), id="wrong-type-mass"),
    pytest.param(PENDULUM, "mass: 0.2}", "mass: -0.2}", "mass: -0.2",
                 ("'params.struck.mass'", "a mass in kg > 0", "-0.2"), id="negative-mass"),
    pytest.param(PENDULUM, "mass: 0.6}", "mass: .nan}", "mass: .nan",
                 ("'params.striker.mass'", "a mass in kg"), id="nan-mass"),
    pytest.param(PENDULUM, "eps_paper: 0 ", "eps_paper: 1.5 ", "eps_paper: 1.5",
                 ("'params.assumptions.eps_paper'", "in [0, 1]", "1.5"), id="eps-above-one"),
    pytest.param(PENDULUM, "eps_paper: 0 ", "eps_paper: -0.1 ", "eps_paper: -0.1",
                 ("'params.assumptions.eps_paper'", "in [0, 1]", "-0.1"), id="eps-below-zero"),
    pytest.param(CUSHION, "value: 0.55 ", "value: 1.55 ", "value: 1.55",
                 ("'params.measured.value'", "a ratio in [0, 1]", "1.55"), id="ratio-above-one"),
    pytest.param(CUSHION, "kind: rebound", "kind: cannon", "kind: cannon",
                 ("'kind'", "must be one of", "'cannon'"), id="unknown-kind"),
    pytest.param(CUSHION, "seed: 1835", "seed: 1835\nseed: 7", "seed: 7", ("key 'seed' appears twice",),
                 id="duplicate-key"),
    pytest.param(CUSHION, "seed: 1835", "seed: -3", "seed: -3", ("'seed'", "a non-negative integer seed", "-3"),
                 id="negative-seed"),
    pytest.param(CUSHION, "synthetic: {n: 24,", "csv: x.csv\n    synthetic: {n: 24,", "csv: x.csv",
                 ("'params.series' must have exactly one of 'csv'", "'synthetic'"), id="series-csv-and-synthetic"),
]


def _bad_config(tmp_path: Path, name: str, old: str, new: str, at: str) -> tuple[Path, int]:
    text = mutate(config_text(name), old, new)
    path = tmp_path / f"broken-{name}.yaml"
    path.write_text(text, encoding="utf-8")
    return path, line_of(text, at)


@pytest.mark.parametrize(("name", "old", "new", "at", "fragments"), YAML_CASES)
def test_load_experiment_names_file_and_line(tmp_path: Path, name: str, old: str, new: str, at: str,
                                             fragments: tuple[str, ...]) -> None:
    path, line = _bad_config(tmp_path, name, old, new, at)
    with pytest.raises(InputError) as info:
        load_experiment(path)
    assert info.value.where == f"{path}:{line}"
    for f in fragments:
        assert f in info.value.message


@pytest.mark.parametrize(("name", "old", "new", "at", "fragments"), YAML_CASES)
def test_cli_reproduce_bad_config(tmp_path: Path, name: str, old: str, new: str, at: str,
                                  fragments: tuple[str, ...]) -> None:
    path, line = _bad_config(tmp_path, name, old, new, at)
    out = tmp_path / "results"
    assert_bad(invoke("reproduce", path, "--out", out), f"{path}:{line}:", *fragments)
    assert not out.exists()


@pytest.mark.parametrize(("text", "where_line", "fragment"), [
    pytest.param("", 1, "empty file", id="empty"),
    pytest.param("# only a comment\n\n", 1, "empty file", id="only-comment"),
    pytest.param("- coriolis-cushion\n- marble-drop\n", 1, "'document' must be a mapping", id="list"),
    pytest.param("# a scalar\nhello\n", 2, "'document' must be a mapping", id="scalar"),
])
def test_document_that_is_not_an_experiment(tmp_path: Path, text: str, where_line: int, fragment: str) -> None:
    path = tmp_path / "odd.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as info:
        load_experiment(path)
    assert info.value.where == f"{path}:{where_line}"
    assert fragment in info.value.message
    out = tmp_path / "results"
    assert_bad(invoke("reproduce", path, "--out", out), f"{path}:{where_line}:", fragment)
    assert not out.exists()


def test_not_utf8_config(tmp_path: Path) -> None:
    path = tmp_path / "latin1.yaml"
    path.write_bytes(config_text(CUSHION).encode("utf-8").replace("§".encode(), "§".encode("latin-1")))
    with pytest.raises(InputError, match="not a UTF-8 text file"):
        load_experiment(path)
    assert_bad(invoke("reproduce", path, "--out", tmp_path / "results"), str(path), "UTF-8")


def test_unclosed_bracket_at_end_of_line_names_the_bracket_line(tmp_path: Path) -> None:
    path, line = _bad_config(tmp_path, CUSHION, "modern: [e_c, e_c(v)]", "modern: [e_c, e_c(v)",
                             "modern: [e_c, e_c(v)")
    with pytest.raises(InputError) as info:
        load_experiment(path)
    assert "malformed YAML" in info.value.message
    assert info.value.where == f"{path}:{line}" or f"line {line}" in info.value.message


# -- numbers PyYAML reads as strings are accepted ------------------------------------------------------------
@pytest.mark.parametrize(("written", "value"), [("1e-3", 0.001), ("1E-2", 0.01), ("1/100", 0.01), ("0,02", 0.02)])
def test_sigma_written_as_string_is_accepted(tmp_path: Path, written: str, value: float) -> None:
    text = mutate(config_text(PENDULUM), "sigma: 0.01\n", f"sigma: {written}\n")
    assert isinstance(yaml.safe_load(text)["params"]["measured"]["sigma"], str)
    path = tmp_path / "sigma.yaml"
    path.write_text(text, encoding="utf-8")
    exp = load_experiment(path)
    assert exp.params.sigma == pytest.approx(value, rel=1e-15)


def test_fractions_are_accepted(tmp_path: Path) -> None:
    text = mutate(config_text(PENDULUM), "mass: 0.2}", "mass: 1/5}")
    path = tmp_path / "fractions.yaml"
    path.write_text(text, encoding="utf-8")
    exp = load_experiment(path)
    assert exp.params.ratio == 7 / 12
    assert exp.params.ratio_p == 5 / 4
    assert exp.params.struck.mass == 1 / 5
    printed = {p.id: p for p in exp.printed}
    assert printed["epsp_fraction"].value == 4 / 15
    assert printed["epsp_fraction"].tolerance == 1e-9  # an exact fraction is compared exactly


# -- printed entries ----------------------------------------------------------------------------------------
def test_printed_computed_names_unknown_quantity(tmp_path: Path) -> None:
    text = mutate(config_text(PENDULUM), "computed: eps_given_epsp", "computed: eps_of_the_moon")
    path = tmp_path / "computed.yaml"
    path.write_text(text, encoding="utf-8")
    entry, key = line_of(text, "- id: eps_premise"), line_of(text, "computed: eps_of_the_moon")
    with pytest.raises(InputError) as info:
        load_experiment(path)
    assert info.value.where in (f"{path}:{entry}", f"{path}:{key}")
    assert "'eps_of_the_moon'" in info.value.message
    assert "names no quantity" in info.value.message
    for q in pendulum.QUANTITIES:
        assert q in info.value.message
    assert_bad(invoke("reproduce", path, "--out", tmp_path / "results"), info.value.where + ":", "eps_of_the_moon")
    assert not (tmp_path / "results").exists()


def test_printed_computed_error_names_the_computed_line(tmp_path: Path) -> None:
    text = mutate(config_text(PENDULUM), "computed: eps_given_epsp", "computed: eps_of_the_moon")
    path = tmp_path / "computed.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as info:
        load_experiment(path)
    assert info.value.where == f"{path}:{line_of(text, 'computed: eps_of_the_moon')}"


def _duplicate_ids(tmp_path: Path) -> tuple[Path, int]:
    text = mutate(config_text(PENDULUM), "- id: epsp_decimal", "- id: epsp_fraction")
    path = tmp_path / "dup.yaml"
    path.write_text(text, encoding="utf-8")
    second = text.index("- id: epsp_fraction", text.index("- id: epsp_fraction") + 1)
    return path, text[:second].count("\n") + 1


def test_duplicate_printed_ids(tmp_path: Path) -> None:
    path, _ = _duplicate_ids(tmp_path)
    with pytest.raises(InputError) as info:
        load_experiment(path)
    assert info.value.where.startswith(f"{path}:")
    assert info.value.where.rsplit(":", 1)[1].isdigit()
    assert "unique" in info.value.message
    assert "repeated: epsp_fraction" in info.value.message
    assert_bad(invoke("reproduce", path, "--out", tmp_path / "results"), f"{path}:", "repeated: epsp_fraction")
    assert not (tmp_path / "results").exists()


def test_duplicate_printed_ids_names_the_repeated_entry(tmp_path: Path) -> None:
    path, line = _duplicate_ids(tmp_path)
    with pytest.raises(InputError) as info:
        load_experiment(path)
    assert info.value.where == f"{path}:{line}"


@pytest.mark.parametrize("bad", ["2001-13-45", "!!int abc", "!foo 1"])
def test_value_that_pyyaml_cannot_construct(tmp_path: Path, bad: str) -> None:
    path, line = _bad_config(tmp_path, PENDULUM, "mass: 0.2}", f"mass: {bad}}}", f"mass: {bad}")
    out = tmp_path / "results"
    assert_bad(invoke("reproduce", path, "--out", out), f"{path}:{line}:", "'params.struck.mass'")
    assert not out.exists()


# -- unknown experiments and unusable output folders ---------------------------------------------------------
def test_unknown_experiment_id(tmp_path: Path) -> None:
    out = tmp_path / "results"
    assert_bad(invoke("reproduce", "nope", "--out", out), "experiment 'nope'", "unknown experiment id", *KNOWN_IDS)
    assert len(KNOWN_IDS) >= 3
    assert not out.exists()


def test_missing_yaml_path(tmp_path: Path) -> None:
    missing = tmp_path / "missing.yaml"
    out = tmp_path / "results"
    assert_bad(invoke("reproduce", missing, "--out", out), str(missing), "no such experiment file")
    assert not out.exists()


def test_no_experiment_named(tmp_path: Path) -> None:
    out = tmp_path / "results"
    assert_bad(invoke("reproduce", "--out", out), "arguments", "--all")
    assert not out.exists()


@pytest.mark.parametrize("sub", [("afile", "sub"), ("afile",)], ids=["under-a-file", "is-a-file"])
def test_out_folder_not_writable(tmp_path: Path, sub: tuple[str, ...]) -> None:
    afile = tmp_path / "afile"
    afile.write_text("not a folder\n", encoding="utf-8")
    out = tmp_path.joinpath(*sub)
    assert_bad(invoke("reproduce", "coriolis-cushion", "--out", out), f"--out {out}", "output folder")
    assert afile.read_text(encoding="utf-8") == "not a folder\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]


# -- CSV series -----------------------------------------------------------------------------------------------
GOOD_ROWS = ["1.0,-0.55", "2.0,-1.1", "3.0,-1.65"]


@pytest.mark.parametrize(("bad_row", "fragments"), [
    pytest.param("2.5,abc", ("column 'V1'", "expected a number", "'abc'"), id="not-a-number"),
    pytest.param("2.5,-1.3,7", ("expected 2 values, got 3",), id="too-many-cells"),
    pytest.param("2.5", ("expected 2 values, got 1",), id="too-few-cells"),
    pytest.param("2.5,nan", ("column 'V1'", "expected a finite number", "'nan'"), id="nan"),
    pytest.param("inf,-1.3", ("column 'V0'", "expected a finite number", "'inf'"), id="inf"),
    pytest.param("0,-1.3", ("column 'V0'", "expected a positive number", "'0'"), id="non-positive-speed"),
])
def test_csv_series_bad_row(tmp_path: Path, results: Path, bad_row: str, fragments: tuple[str, ...]) -> None:
    rows = "# my rebounds, m/s\nV0,V1\n" + "\n".join([*GOOD_ROWS[:2], bad_row, GOOD_ROWS[2]]) + "\n"
    cfg, csv = write_csv_config(tmp_path, rows)
    line = line_of(rows, bad_row + "\n")
    before = snapshot(results)
    assert_bad(invoke("reproduce", cfg, "--out", results), f"{csv}:{line}:", *fragments)
    assert snapshot(results) == before


def test_csv_series_bad_header(tmp_path: Path, results: Path) -> None:
    rows = "\n# header follows\nV0,W1\n" + "\n".join(GOOD_ROWS) + "\n"
    cfg, csv = write_csv_config(tmp_path, rows)
    before = snapshot(results)
    assert_bad(invoke("reproduce", cfg, "--out", results), f"{csv}:{line_of(rows, 'V0,W1')}:",
               "missing column(s) V1", "expected V0, V1")
    assert snapshot(results) == before


def test_csv_series_good_file_is_accepted(tmp_path: Path) -> None:
    """The same config with a clean CSV runs: the failures above are the bad rows, not the config."""
    cfg, csv = write_csv_config(tmp_path, "V0,V1\n" + "\n".join(GOOD_ROWS) + "\n")
    out = tmp_path / "results"
    result = invoke("reproduce", cfg, "--json", "--out", out)
    assert result.exit_code == 0, (result.output, repr(result.exception))
    s = json.loads(result.stdout)
    assert s["experiment"] == "csv-cushion"
    assert csv.name in s["data_note"]


# -- simulate --set -----------------------------------------------------------------------------------------
@pytest.mark.parametrize(("assignment", "fragments"), [
    ("eps=2", ("'eps' must be a number in [0, 1]", "got 2")),
    ("eps=-0.5", ("'eps' must be a number in [0, 1]", "got -0.5")),
    ("M=-1", ("'M' must be a number > 0", "got -1")),
    ("M=0", ("'M' must be a number > 0", "got 0")),
    ("foo=1", ("unknown parameter 'foo'", "M, Mp, V0, V0p, eps, epsp")),
    ("eps=abc", ("'eps' must be a number", "'abc'")),
    ("eps=nan", ("'eps' must be a finite number",)),
    ("eps", ("expected name=value",)),
])
def test_simulate_bad_set(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, assignment: str,
                          fragments: tuple[str, ...]) -> None:
    monkeypatch.chdir(tmp_path)
    assert_bad(invoke("simulate", "direct-impact", "--set", "eps=0.1", "--set", "epsp=0.1", "--set", assignment),
               f"--set {assignment}:", *fragments)
    assert list(tmp_path.iterdir()) == []


def test_simulate_unknown_model() -> None:
    assert_bad(invoke("simulate", "nope"), "model 'nope'", "direct-impact, wall-impact")


@pytest.mark.parametrize(("args", "fragments"), [
    (("direct-impact", "--set", "eps=0.1", "--set", "epsp=0.1", "--method", "resal"),
     ("--method resal:", "direct-impact has no path 'resal'", "auto, exact, ode")),
    (("cushion-impact", "--set", "n0=-30", "--set", "j=0.2", "--set", "eps=0.3", "--method", "elementary"),
     ("--method elementary:", "path 'elementary' handles only n0 = 0")),
    (("direct-impact", "--set", "eps=0.1", "--set", "epsp=0.1", "--set", "V0=1", "--set", "V0p=2"),
     ("separating bodies do not collide",)),
    (("wall-impact",), ("wall-impact needs eps (no default",)),
    (("spheres-free", "--set", "v=1,2", "--set", "f=0", "--set", "eps=0", "--set", "epsp=0"),
     ("'v' is a 3-vector",)),
])
def test_simulate_refuses_a_path_outside_its_region_and_missing_coefficients(args: tuple[str, ...],
                                                                           fragments: tuple[str, ...]) -> None:
    assert_bad(invoke("simulate", *args), *fragments)


@pytest.mark.parametrize(("assignment", "value"), [("eps=1e-3", 0.001), ("eps=7/12", 7 / 12), ("M=2", 2.0)])
def test_simulate_accepts_numbers_yaml_would_not(assignment: str, value: float) -> None:
    result = invoke("simulate", "direct-impact", "--set", "eps=0.2", "--set", "epsp=0.1", "--set", assignment,
                    "--json")
    assert result.exit_code == 0, (result.output, repr(result.exception))
    name = assignment.split("=")[0]
    assert json.loads(result.stdout)["inputs"][name] == pytest.approx(value, rel=1e-15)


# -- nothing under the results folder changes ----------------------------------------------------------------
def _broken_copy(tmp_path: Path) -> tuple[Path, int]:
    return _bad_config(tmp_path, CUSHION, "modern: [e_c, e_c(v)]", "modern: [e_c, e_c(v)}", "e_c(v)}")


def test_results_unchanged_after_failing_runs(tmp_path: Path, results: Path) -> None:
    before = snapshot(results)
    assert "coriolis-cushion/summary.json" in before
    assert "index.md" in before
    broken, line = _broken_copy(tmp_path)
    runs = [
        ("reproduce", broken, "--out", results),
        ("reproduce", "--all", broken, "--out", results),
        ("reproduce", "coriolis-cushion", broken, "--out", results),
        ("reproduce", "coriolis-cushion", "nope", "--out", results),
    ]
    for args in runs:
        assert_bad(invoke(*args), "nope" if "nope" in args else f"{broken}:{line}:")
        after = snapshot(results)
        assert sorted(after) == sorted(before), f"{args}: files or folders appeared or vanished"
        assert not [k for k in after if Path(k).name.startswith(".")], "a hidden staging folder was left"
        assert after == before, f"{args}: a file under the results folder changed"


def test_results_unchanged_after_csv_error(tmp_path: Path, results: Path) -> None:
    cfg, csv = write_csv_config(tmp_path, "V0,V1\n1.0,-0.55\n2.0,oops\n3.0,-1.6\n")
    before = snapshot(results)
    assert_bad(invoke("reproduce", cfg, "--out", results), f"{csv}:3:", "'oops'")
    assert snapshot(results) == before


def test_results_unchanged_when_a_later_experiment_has_a_bad_csv(tmp_path: Path, results: Path) -> None:
    changed = tmp_path / "cushion-seed-7.yaml"
    changed.write_text(mutate(config_text(CUSHION), "seed: 1835", "seed: 7"), encoding="utf-8")
    cfg, csv = write_csv_config(tmp_path, "V0,V1\n1.0,-0.55\n2.0,oops\n3.0,-1.6\n")
    before = snapshot(results)
    assert_bad(invoke("reproduce", changed, cfg, "--out", results), f"{csv}:3:", "'oops'")
    assert snapshot(results) == before
