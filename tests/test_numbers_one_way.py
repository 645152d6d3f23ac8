"""A number a user types reads one way or is refused (hypothesis): ``resal simulate --set`` and the CSV cells of
``resal fit``.

A comma in a number has two readings (``1,000``: a thousands separator, 1000, or a decimal comma, 1.0) and resal
picks neither: given where one number is expected, any text with a comma between digits ends with exit status 2
and one ``error:`` line. A nonzero literal that floating point cannot hold (``1e-400`` reads as 0, ``5e-324`` as a
subnormal) is refused the same way, never taken as 0. Ordinary numbers still read as Python reads them.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest
from cli_helpers import invoke
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from typer.testing import Result

from reproductions.errors import InputError
from reproductions.mechanics import registry
from reproductions.models import _parse
from reproductions.series import read_series

# (model, the --set it needs besides, a scalar parameter whose range admits 0 and any sign or size)
SCALARS = [("direct-impact", ["--set", "eps=0.1", "--set", "epsp=0.1"], "V0"),
           ("direct-impact", ["--set", "eps=0.1", "--set", "epsp=0.1"], "V0p"),
           ("plane-impact", ["--set", "f=0.2", "--set", "nu=0.5"], "chi0"),
           ("cushion-impact", ["--set", "j=0.2", "--set", "eps=0.3"], "p0")]
DIGITS = st.sampled_from("0123456789")


def _one_error_line(result: Result, starts: str) -> str:
    """Exit 2, nothing on stdout, exactly one line on stderr, starting with ``starts``; that line."""
    assert result.exit_code == 2, (result.exit_code, result.output, repr(result.exception))
    assert result.stdout == ""
    err = result.stderr
    assert err.endswith("\n") and err.count("\n") == 1, repr(err)
    assert err.startswith(starts), repr(err)
    return err


@st.composite
def _with_a_comma(draw: st.DrawFn) -> str:
    """Any text holding a comma between two digits: 1,000 · 0,5 · x1,2y · 1,000,000.5."""
    return (draw(st.text(max_size=6)) + draw(DIGITS) + "," + draw(DIGITS) + draw(st.text(max_size=6)))


@st.composite
def _underflowing(draw: st.DrawFn) -> str:
    """A finite literal with a nonzero digit whose value is below the smallest normal double: it reads as 0 or as
    a subnormal (``1e-400``, ``-3.5e-310``, ``0.000…01`` with 330 zeros)."""
    sign = draw(st.sampled_from(["", "-", "+"]))
    digits = str(draw(st.integers(1, 99_999)))
    if draw(st.booleans()):  # m·10^e with m < 1e5 and e ≤ −313: below 1e-308
        point = draw(st.integers(0, len(digits)))
        mantissa = digits[:point] + ("." + digits[point:] if point < len(digits) else "")
        exponent = draw(st.integers(-5000, -313)) + (len(digits) - point if point < len(digits) else 0)
        text = f"{sign}{mantissa or '0'}e{exponent}"
    else:  # no exponent: a long run of zeros after the point
        text = f"{sign}0.{'0' * draw(st.integers(308, 400))}{digits}"
    value = float(text)
    assume(abs(value) < sys.float_info.min)
    return text


@settings(max_examples=150, deadline=None)
@given(scene=st.sampled_from(SCALARS), text=_with_a_comma())
def test_a_comma_in_a_scalar_is_refused_in_one_line(scene: tuple[str, list[str], str], text: str) -> None:
    model, fixed, name = scene
    err = _one_error_line(invoke("simulate", model, *fixed, "--set", f"{name}={text}"), f"error: --set {name}=")
    assert f"'{name}' is one number" in err


@pytest.mark.parametrize(("text", "readings"), [
    ("1,000", ["a thousands separator (1000) or a decimal comma (1.0)? write 1000 or 1.0"]),
    ("0,5", ["a decimal comma? write 0.5"]),
    ("12,345,678.5", ["a thousands separator? write 12345678.5"]),
    ("-2,5e-3", ["a decimal comma? write -0.0025"]),
])
def test_each_reading_is_written_out(text: str, readings: list[str]) -> None:
    err = _one_error_line(invoke("simulate", "direct-impact", "--set", "eps=0.1", "--set", "epsp=0.1", "--set",
                                 f"V0={text}"), f"error: --set V0={text}: ")
    assert all(r in err for r in readings), err


@settings(max_examples=150, deadline=None)
@given(scene=st.sampled_from(SCALARS), text=_underflowing())
def test_an_underflow_given_to_set_is_refused(scene: tuple[str, list[str], str], text: str) -> None:
    model, fixed, name = scene
    err = _one_error_line(invoke("simulate", model, *fixed, "--set", f"{name}={text}"), f"error: --set {name}=")
    assert f"'{name}': {text} is nonzero but below the smallest normal double" in err


@settings(max_examples=100, deadline=None)
@given(text=_underflowing(), a=st.integers(0, 3))
def test_an_underflow_in_a_vector_component_is_refused(text: str, a: int) -> None:
    parts = ["1", "0", "0"]
    parts[a % 3] = text
    with pytest.raises(InputError, match="is nonzero but below the smallest normal double"):
        _parse(registry.MODELS["spheres-free"], "v=" + ",".join(parts))


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=_underflowing())
def test_an_underflow_in_a_csv_cell_is_refused(text: str, tmp_path: Path) -> None:
    f = tmp_path / "trials.csv"
    f.write_text(f"V0,V1\n1.0,-0.55\n2.0,{text}\n", encoding="utf-8")
    with pytest.raises(InputError, match="no measurement in any unit") as exc:
        read_series(f, ("V0", "V1"))
    assert exc.value.where == f"{f}:3"


LINE_BREAKS = set("\0\r\n\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029")  # and NUL: what no CSV cell holds on one line


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=_with_a_comma().filter(lambda t: '"' not in t and not set(t) & LINE_BREAKS))
def test_a_comma_in_a_quoted_csv_cell_is_refused(text: str, tmp_path: Path) -> None:
    f = tmp_path / "trials.csv"
    f.write_text(f'V0,V1\n1.0,-0.55\n2.0,"{text}"\n', encoding="utf-8")
    with pytest.raises(InputError) as exc:
        read_series(f, ("V0", "V1"))
    assert exc.value.where == f"{f}:3" and "expected one number" in exc.value.message


@settings(max_examples=300, deadline=None)
@given(x=st.floats(allow_nan=False, allow_infinity=False).filter(lambda v: v == 0 or abs(v) >= sys.float_info.min))
def test_every_other_finite_number_reads_as_python_reads_it(x: float) -> None:
    name, v = _parse(registry.MODELS["direct-impact"], f"V0p={x!r}")
    assert name == "V0p" and v == x and math.copysign(1.0, v) == math.copysign(1.0, x)
