"""The command line's one error contract, as a property (issue 31): whatever a person types or feeds it, every
command ends in its result (exit 0), or in one ``error:`` message and exit 2 (bad input) or 1 (a failure of the
environment or of a computation) — never another exception, never a traceback.

Hypothesis draws hostile values (any Unicode text, control characters, numbers at and past the limits of a double,
thousands separators, paths that lead nowhere) into each command's arguments, and hostile cells into the example
files of every ``fit`` kind. Derandomized: the same examples on every machine, so a failure is reproducible.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner, Result

from cli.main import app
from reproductions import locate
from reproductions.mechanics import paths, registry

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
FIT_KINDS = sorted(p.stem for p in EXAMPLES.glob("*.csv"))

NASTY = ["", " ", "-", "--", "=", ",", "nan", "NaN", "inf", "-inf", "1e309", "-1e309", "1e-400", "5e-324",
         "-5e-324", "1,000", "1,5", "1.000,5", "0x10", "1_000", "１２", "٣", "1e", "e5", "+-1", "1/2", "½", "None",
         "true", "[1, 2]", "{}", "\x00", "\t", "a" * 3000, "9" * 400, "-0", "0", "1e308", "-1e308",
         "2.2250738585072014e-308", "../../etc/passwd", "/dev/null", "/nonexistent/x", "~", "$HOME", "%s",
         "'; DROP TABLE", "é", "\u202e", "\ufeff1", "1\u00a0000"]
TEXT = st.one_of(st.sampled_from(NASTY),
                 st.text(st.characters(blacklist_categories=("Cs",)), max_size=30),
                 st.floats().map(repr),
                 st.integers(-(10 ** 400), 10 ** 400).map(str))
SETTINGS = settings(max_examples=int(os.environ.get("RESAL_CONTRACT_EXAMPLES", "60")), deadline=None,
                    derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def _run(*args: object) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


def _holds(result: Result) -> None:
    """The contract: exit 0, or exit 1/2 with exactly one ``error:`` message on stderr; no other exception."""
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    assert result.exit_code in (0, 1, 2), (result.exit_code, result.output)
    assert "Traceback" not in result.output
    if result.exit_code:
        err = result.stderr
        assert err.startswith("error: ") and err.count("error:") == 1, err
        assert err.endswith("\n") and err.strip(), err


MODELS = list(registry.MODELS)
PARAMS = sorted({p.name for m in registry.MODELS.values() for p in m.params})
METHODS = sorted({p.name for m in registry.MODELS.values() for p in m.paths} | {"auto"})


# values a person might give, near and at the edges of the ranges, and the limits of a double
EDGY = st.one_of(st.floats(-2.0, 5.0).map(lambda x: f"{x:.3g}"),
                 st.sampled_from(["0", "1", "-1", "0.5", "1e-300", "1e300", "1e308", "-1e308",
                                  "2.2250738585072014e-308", "89.999999", "90", "1e-12", "1e12", "0.999999999999",
                                  "1.5", "2.5", "10"]))


def _mostly(normal: st.SearchStrategy, hostile: st.SearchStrategy) -> st.SearchStrategy:
    """``normal`` about 9 times in 10, else ``hostile`` (a uniform pick of branches would make nearly every
    command fail on its first hostile argument, and the solvers behind it would never be reached)."""
    return st.integers(0, 99).flatmap(lambda i: hostile if 40 <= i < 50 else normal)


def _in_range(p: paths.Param) -> st.SearchStrategy[str]:
    """A number inside (or on the edge of) ``p``'s range, as typed on the command line (degrees for angles)."""
    lo = -10.0 if p.lo is None else p.lo
    hi = max(lo, 10.0) if p.hi is None else p.hi
    if p.cli_degrees:
        lo, hi = math.degrees(lo), math.degrees(hi)
    if p.integer:
        return st.integers(math.ceil(lo), int(min(hi, lo + 50))).map(str)
    return st.floats(lo, hi).map(lambda x: f"{x:.6g}")


def _value(p: paths.Param, vector: bool) -> st.SearchStrategy[str]:
    one = _mostly(_in_range(p), st.one_of(EDGY, TEXT))
    if vector:
        return st.lists(one, min_size=3, max_size=3).map(",".join) | one
    return one


VECTORS = {p.name for m in registry.MODELS.values() for p in m.params if p.name in m.vectors}


@SETTINGS
@given(data=st.data(), as_json=st.booleans())
def test_simulate_keeps_the_contract(data: st.DataObject, as_json: bool) -> None:
    model = data.draw(_mostly(st.sampled_from(MODELS), TEXT))
    m = registry.MODELS.get(model)
    own = [p.name for p in m.paths] if m else []
    method = data.draw(_mostly(st.one_of(st.none(), st.sampled_from(own or ["auto"])),
                               st.one_of(st.sampled_from(METHODS), TEXT)))
    args: list[str] = ["simulate", model]
    for p in (m.params if m else []):  # each parameter, given or left to its default
        if p.default is None or data.draw(st.booleans()):
            args += ["--set", f"{p.name}={data.draw(_value(p, p.name in m.vectors))}"]
    if data.draw(_mostly(st.just(False), st.just(True))):  # and one more assignment, hostile
        args += ["--set", f"{data.draw(st.one_of(st.sampled_from(PARAMS), TEXT))}={data.draw(TEXT)}"]
    if method is not None:
        args += ["--method", method]
    result = _run(*args, *(["--json"] if as_json else []))
    _holds(result)
    if result.exit_code == 0 and as_json:
        json.loads(result.stdout)  # strict JSON, or this raises


@SETTINGS
@given(name=TEXT)
def test_reproduce_of_a_hostile_id_keeps_the_contract(name: str, tmp_path_factory) -> None:
    known = set(locate.experiment_ids())
    if name in known or not name.strip() or name.startswith("-"):
        return  # a real experiment would run (tested elsewhere); an option is the usage tests' business
    out = tmp_path_factory.mktemp("out")
    result = _run("reproduce", name, "--out", out)
    _holds(result)
    assert result.exit_code != 0  # no experiment by that name: said, not run


def _mutated(kind: str, data: st.DataObject) -> str:
    """The example file of ``kind`` with a few cells, the header or whole lines replaced by hostile text."""
    rows = list(csv.reader(io.StringIO((EXAMPLES / f"{kind}.csv").read_text(encoding="utf-8"))))
    for _ in range(data.draw(st.integers(1, 3))):
        i = data.draw(st.integers(0, len(rows) - 1))
        action = data.draw(st.sampled_from(["cell", "cell", "row", "drop", "extra"]))
        if action == "cell" and rows[i]:
            rows[i][data.draw(st.integers(0, len(rows[i]) - 1))] = data.draw(TEXT)
        elif action == "row":
            rows[i] = [data.draw(TEXT)]
        elif action == "drop" and len(rows) > 1:
            del rows[i]
        else:
            rows[i] = [*rows[i], data.draw(TEXT)]
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerows(rows)
    return buf.getvalue()


@settings(SETTINGS, max_examples=40)
@given(kind=st.sampled_from(FIT_KINDS), data=st.data())
def test_fit_of_a_damaged_file_keeps_the_contract(kind: str, data: st.DataObject, tmp_path_factory) -> None:
    folder = tmp_path_factory.mktemp("fit")
    path = folder / "data.csv"
    path.write_text(_mutated(kind, data), encoding="utf-8", errors="surrogatepass")
    fit_kind = kind.split("-")[0]  # pendulum-heights.csv is a pendulum file
    result = _run("fit", fit_kind, path, "--no-plot", "--bootstrap", "0", "--out", folder / "out")
    _holds(result)


NUMBERS = st.one_of(st.floats(), st.integers(-(10 ** 30), 10 ** 30), st.sampled_from(NASTY), st.none(),
                    st.booleans())


@SETTINGS
@given(a=st.dictionaries(st.sampled_from(["experiment", "rows", "quantities", "id", "computed", "printed"]),
                         st.one_of(NUMBERS, st.lists(st.dictionaries(st.sampled_from(
                             ["id", "computed", "printed", "tolerance", "path"]), NUMBERS, max_size=4),
                             max_size=3)), max_size=4),
       same=st.booleans())
def test_diff_of_hostile_summaries_keeps_the_contract(a: dict, same: bool, tmp_path_factory) -> None:
    folder = tmp_path_factory.mktemp("diff")
    left, right = folder / "a.json", folder / "b.json"
    left.write_text(json.dumps(a), encoding="utf-8")
    right.write_text(json.dumps(a if same else {**a, "experiment": "other"}), encoding="utf-8")
    _holds(_run("diff", left, right))


@SETTINGS
@given(option=st.sampled_from(["--scenes", "--ode-scenes", "--referee-scenes"]), value=TEXT)
def test_stress_options_keep_the_contract(option: str, value: str, tmp_path_factory) -> None:
    try:
        if int(value) > 0:
            return  # a real sweep would run (tested in test_stress.py)
    except ValueError:
        pass
    result = _run("stress", option, value, "--out", tmp_path_factory.mktemp("stress"))
    _holds(result)
    assert result.exit_code == 2  # no count ≤ 0 and no non-integer is a number of scenes
