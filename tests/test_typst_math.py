"""One formula's LaTeX as Typst math (reproductions.edition.typst_math): a table of the subset's forms, commands
outside it refused by name, and every converted formula compiled by Typst (all of a test's formulas in one
document, so one compile)."""

from __future__ import annotations

import pytest

from reproductions.edition.typst_math import GREEK, SYMBOLS, latex_to_typst

typst = pytest.importorskip("typst")

PAIRS = [
    # letters: a run of them is one name to Typst, so each stands apart
    ("pR", "p R"),
    ("MV_1", "M V_(1)"),
    (r"\alpha\beta", "alpha beta"),
    (r"\varepsilon", "epsilon"),
    (r"\epsilon", "epsilon.alt"),
    (r"\varphi", "phi"),
    (r"\phi", "phi.alt"),
    (r"\Delta \Omega", "Delta Omega"),
    # numbers: a decimal point stays in the number, a decimal comma is upright text (no space after it)
    ("0.155", "0.155"),
    ("0{,}155", '"0,155"'),
    ("2x", "2 x"),
    ("12x^23", "12 x^(2) 3"),  # LaTeX's script takes one digit
    # scripts and primes: primes before the scripts, as Typst sets them
    ("v_0", "v_(0)"),
    ("v_{0}'", "v'_(0)"),
    ("x''", "x''"),
    (r"\chi'_{0}^{2}", "chi'_(0)^(2)"),
    ("x^{b/a}", "x^(b \\/ a)"),
    ("{}^2", "zws^(2)"),
    (r"e^{-2ft}", "e^(- 2 f t)"),
    # fractions, roots, brackets
    (r"\frac{1-\varepsilon}{1+\varepsilon}", "frac(1 - epsilon, 1 + epsilon)"),
    (r"\frac12", "frac(1, 2)"),
    (r"\sqrt{2/3}", "sqrt(2 \\/ 3)"),
    (r"\sqrt[3]{x}", "root(3, x)"),
    (r"\left( \frac{a}{b} \right)^2", "lr(( frac(a, b) ))^(2)"),
    (r"\left| x \right|", "lr(| x |)"),
    (r"\left. x \right|_0", "lr( x |)_(0)"),
    (r"\{x\}", "\\{ x \\}"),
    ("[a, b)", "[ a \\, b )"),
    # a slash is a slash (Typst's / would make a fraction); commas and semicolons never split an argument
    ("a/b", "a \\/ b"),
    ("a, b; c", "a \\, b \\; c"),
    # operators and relations
    (r"a \cdot b \times c", "a dot.op b times c"),
    (r"\pm 3 \mp 2", "plus.minus 3 minus.plus 2"),
    (r"a \le b \leq c \ge d \geq e", "a lt.eq b lt.eq c gt.eq d gt.eq e"),
    (r"a \approx b \ne c \neq d", "a approx b eq.not c eq.not d"),
    (r"x \to \infty", "x arrow.r infinity"),
    (r"\int_0^1 f(x)\,dx", "integral_(0)^(1) f ( x ) thin d x"),
    (r"\sum_{i=1}^{n} x_i", "sum_(i = 1)^(n) x_(i)"),
    (r"\partial_t u", "partial_(t) u"),
    ("a < b > c", "a < b > c"),
    ("a = -b + c", "a = - b + c"),
    # upright text: functions by their Typst names, units and words as strings
    (r"\sin\varphi", "sin phi"),
    (r"\arctan \frac{b}{a}", "arctan frac(b, a)"),
    (r"\ln 2 + \exp x", "ln 2 + exp x"),
    (r"\mathrm{cm}", '"cm"'),
    (r"\mathrm{m/s}", '"m/s"'),
    (r"\mathrm{sin}\,x", "sin thin x"),
    (r"\mathrm{m\,s^{-1}}", "upright(m thin s^(- 1))"),
    (r"\text{ if } x > 0", '" if " x > 0'),
    (r"v_\text{max}", 'v_("max")'),
    (r"\text{a \% of it}", '"a % of it"'),
    # Unicode a config may carry: each character an atom of its own
    ("αβ′", "α β ′"),
]


@pytest.mark.parametrize(("latex", "typst_math"), PAIRS)
def test_the_subset_becomes_typst(latex, typst_math):
    assert latex_to_typst(latex) == typst_math


@pytest.mark.parametrize(("latex", "named"), [
    (r"\foo x", r"\foo"),
    (r"\mathcal{F}", r"\mathcal"),
    (r"\bigl( x \bigr)", r"\bigl"),
    (r"\text{\bf x}", r"\bf"),
    (r"\left< x \right>", "'<'"),
    (r"\frac{a}", "argument missing"),
    ("x^{2", "unclosed"),
    ("a}", "unmatched }"),
    (r"\right)", r"\right without its \left"),
    ("x^2^3", "double superscript"),
    (r"\text{$x$}", "'$'"),
    ("a & b", "'&'"),
    ('"x"', "'\"'"),
    ("a # b", "'#'"),
    ("a @b", "'@'"),
    (r"a \\ b", "\\\\"),
])
def test_outside_the_subset_is_refused_by_name(latex, named):
    with pytest.raises(ValueError, match=None) as err:
        latex_to_typst(latex)
    assert named in str(err.value)
    assert repr(latex) in str(err.value)  # the formula is named too


def _compiles(formulas: list[str]) -> None:
    """Every formula, inline and displayed, in one Typst document: it compiles without an error or a warning."""
    body = "\n".join(f"#box[${f}$] $ {f} $" for f in formulas if f)
    src = '#set page(width: 16cm, height: auto)\n#set text(font: "Libertinus Serif")\n' + body
    _, warnings = typst.compile_with_warnings(src.encode(), format="pdf", ignore_system_fonts=True)
    assert not warnings, [w.message for w in warnings]


def test_every_converted_formula_of_the_table_compiles():
    _compiles([latex_to_typst(latex) for latex, _ in PAIRS])


def test_every_command_of_the_subset_compiles():
    names = [*GREEK, *(k for k in SYMBOLS if k.isalpha())]
    _compiles([latex_to_typst(f"a \\{n} b") for n in names] + [latex_to_typst(f"x_\\{n}") for n in GREEK])


FORMULAS = [  # as the formula detector writes them: long formulas of the paper's sections
    r"V_{1} = -\frac{1 - \varepsilon}{1 + \varepsilon} V_{0}",
    r"\varepsilon = \frac{1 - e}{1 + e}",
    r"A = 1 + \mu\{(\cos i - f \cos \gamma \sin i)^{2} + f^{2} \sin^{2}\gamma \sin^{2}i\}",
    r"M[\chi_{0}^{2} - \chi_{1}^{2} + (R^{2}/k)(q_{0}^{2} - q_{1}^{2})] + M'[\chi'_{0}^{2} - \chi'_{1}^{2}] =",
    r"d\eta/\{\tau_{0} - \tau'_{0} + R q_{0} + [1 + k + (M/M')(1 + k')](\tau_{1} - \tau_{0})\}",
    r"\tan \alpha_{1} = \nu \tan \alpha_{0}/(1 - f(1 + \nu) \tan \alpha_{0})",
    r"x_{1} = \frac{2 V_{0}^{2}}{7 f g}\left(1 - \frac{R \omega_{0}}{V_{0}}\right)^{2}",
    r"\sqrt{1 + \frac{k}{R^{2}}} \approx 1{,}183",
    r"2{,}2 \times 10^{-16} \le \Delta \le 0.5",
    r"\int_{\eta_{0}}^{\eta_{1}} \frac{d\eta}{\sqrt{\eta^{2} + a^{2}}} \to \infty",
    r"\theta \in [0, \pi/2)",
    r"|v_{y}| = f g t \pm \mathrm{cm}",
    r"e^{-(x - \mu)^{2}/2\sigma^{2}}",
    r"\frac{1}{2} M (V_{0}^{2} - V_{1}^{2}) = \varepsilon \cdot \frac{1}{2} M V_{0}^{2}",
]


def test_long_formulas_of_the_paper_compile():
    _compiles([latex_to_typst(f) for f in FORMULAS])


def test_no_latex_passes_through():
    for latex in [latex for latex, _ in PAIRS] + FORMULAS:
        out = latex_to_typst(latex)
        assert "\\" not in out.replace("\\/", "").replace("\\,", "").replace("\\;", "").replace("\\{", "").replace(
            "\\}", ""), (latex, out)
        assert "{" not in out.replace("\\{", "") and "}" not in out.replace("\\}", ""), (latex, out)
