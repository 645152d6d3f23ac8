"""Log axes are labelled in plain text with Unicode superscripts (``report.unicode_power``), not in mathtext, whose
parser took half of a log-scaled figure's drawing time. The label must still say the tick's value: each is read
back here into a number, by a reading that shares nothing with the conversion, and compared with the tick."""

import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pytest
from matplotlib.ticker import LogFormatterSciNotation

from reproductions import report
from reproductions.results import FigureSpec, layer

_DIGITS = {c: str(i) for i, c in enumerate("⁰¹²³⁴⁵⁶⁷⁸⁹")}


def _value(label: str) -> float:
    """A label read as a number: "2×10⁻³", "10⁻¹⁴", "10⁰", "0.01"."""
    m = re.fullmatch(r"(?:([0-9.]+)×)?10([⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)", label)
    if not m:
        return float(label.replace("−", "-"))
    power = int("".join("-" if c == "⁻" else _DIGITS[c] for c in m[2]))
    return float(m[1] or 1.0) * 10.0**power


@pytest.mark.parametrize("power", range(-17, 8))
@pytest.mark.parametrize("coeff", [1, 2, 5])
def test_each_label_matplotlib_writes_reads_back_as_its_value(power: int, coeff: int) -> None:
    fig, ax = plt.subplots()
    ax.set_xscale("log")
    ax.set_xlim(10.0**power / 3, 10.0**power * 30)  # few decades: matplotlib labels the 2× and 5× ticks too
    fmt = LogFormatterSciNotation(labelOnlyBase=False)
    ax.xaxis.set_major_formatter(fmt)
    x = coeff * 10.0**power
    fmt.set_locs([x])
    printed = fmt(x)
    plt.close(fig)
    if not printed:  # matplotlib leaves this tick unlabelled: so do we
        assert report.unicode_power(printed) == ""
        return
    plain = report.unicode_power(printed)
    assert "$" not in plain and "\\" not in plain, (printed, plain)
    assert _value(plain) == pytest.approx(x, rel=1e-12), (printed, plain)


def test_text_that_is_not_matplotlibs_power_is_left_as_it_is() -> None:
    for s in ("", "0.01", "$V_0$", "10^3", "$\\mathdefault{e^{2}}$"):
        assert report.unicode_power(s) == s


def test_a_drawn_figure_over_many_decades_has_no_mathtext_tick_and_every_label_says_its_tick() -> None:
    xs = [10.0**p for p in range(-15, 1)]
    spec = FigureSpec(name="t", title="t", xlabel="error", ylabel="seconds", reading="r", xscale="log", yscale="log",
                      layers=(layer("points", x=xs, y=[1e-7 * (1 + i) for i in range(len(xs))], label="a"),))
    fig = report._render(spec)
    fig.canvas.draw()
    seen = 0
    for axis in (fig.axes[0].xaxis, fig.axes[0].yaxis):
        lo, hi = sorted(axis.get_view_interval())
        for tick in [*axis.get_major_ticks(), *axis.get_minor_ticks()]:
            text = tick.label1.get_text()
            if not text or not lo <= tick.get_loc() <= hi:
                continue
            assert "$" not in text, text
            assert _value(text) == pytest.approx(tick.get_loc(), rel=1e-9), (text, tick.get_loc())
            seen += 1
    plt.close(fig)
    assert seen >= 6
