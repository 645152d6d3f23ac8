"""One formula's LaTeX source (a span of style "math", from ``formula``) as Typst math, for the PDF (``typst``).

The subset is the formula detector's: single letters (Latin, or Greek commands), digits and decimals (a decimal comma
written ``{,}``), primes, ``_`` and ``^`` scripts, ``\\frac``, ``\\sqrt``, ``\\left``/``\\right``, brackets and bars,
the usual operators and relations, ``\\mathrm{…}`` and ``\\text{…}``, and the named functions (``\\sin``, ``\\ln``…).
Typst reads a run of letters as one name (``pR`` is an unknown variable), so every atom is written apart (``p R``);
upright words are Typst strings (``"cm"``); a comma or a semicolon is escaped (``\\,``) so that it never splits a
function's arguments; a slash stays a slash (``\\/``), never Typst's fraction. A command outside the subset raises
``ValueError`` naming it: LaTeX never passes through."""

from __future__ import annotations

import re
from dataclasses import dataclass

__all__ = ["latex_to_typst"]

GREEK = {
    "alpha": "alpha", "beta": "beta", "gamma": "gamma", "delta": "delta", "epsilon": "epsilon.alt",
    "varepsilon": "epsilon", "zeta": "zeta", "eta": "eta", "theta": "theta", "vartheta": "theta.alt", "iota": "iota",
    "kappa": "kappa", "varkappa": "kappa.alt", "lambda": "lambda", "mu": "mu", "nu": "nu", "xi": "xi", "pi": "pi",
    "varpi": "pi.alt", "rho": "rho", "varrho": "rho.alt", "sigma": "sigma", "varsigma": "sigma.alt", "tau": "tau",
    "upsilon": "upsilon", "phi": "phi.alt", "varphi": "phi", "chi": "chi", "psi": "psi", "omega": "omega",
    "Gamma": "Gamma", "Delta": "Delta", "Theta": "Theta", "Lambda": "Lambda", "Xi": "Xi", "Pi": "Pi",
    "Sigma": "Sigma", "Upsilon": "Upsilon", "Phi": "Phi", "Psi": "Psi", "Omega": "Omega",
}
SYMBOLS = {
    "cdot": "dot.op", "times": "times", "pm": "plus.minus", "mp": "minus.plus", "le": "lt.eq", "leq": "lt.eq",
    "ge": "gt.eq", "geq": "gt.eq", "approx": "approx", "ne": "eq.not", "neq": "eq.not", "to": "arrow.r",
    "rightarrow": "arrow.r", "leftarrow": "arrow.l", "Rightarrow": "arrow.r.double", "infty": "infinity",
    "int": "integral", "iint": "integral.double", "sum": "sum", "prod": "product", "partial": "partial",
    "prime": "prime", "circ": "compose", "nabla": "nabla", "propto": "prop", "sim": "tilde.op", "equiv": "equiv",
    "in": "in", "perp": "perp", "parallel": "parallel", "div": "div", "ll": "lt.double", "gg": "gt.double",
    "cdots": "dots.c", "ldots": "dots.h", "dots": "dots.h", "ell": "ell",
    # spaces
    ",": "thin", ";": "med", ":": "med", ">": "med", "!": "", " ": "space", "quad": "quad", "qquad": "wide",
    # escaped characters
    "{": "\\{", "}": "\\}", "%": "%", "_": "\\_", "#": "\\#", "&": "\\&", "$": "\\$", "|": "bar.v.double",
}
# the named functions of LaTeX that Typst has under the same name (set upright, spaced as operators)
FUNCTIONS = frozenset("sin cos tan cot sec csc arcsin arccos arctan sinh cosh tanh coth ln log lg exp lim max min "
                      "det arg deg dim gcd inf sup ker Pr".split())
ACCENTS = {"dot": "dot", "ddot": "dot.double", "bar": "overline", "overline": "overline", "hat": "hat",
           "vec": "arrow", "tilde": "tilde", "underline": "underline"}
STYLES = {"mathrm": "upright", "mathit": "italic", "mathbf": "bold"}
DELIMITERS = {"(": "(", ")": ")", "[": "[", "]": "]", "|": "|", ".": "", "\\{": "\\{", "\\}": "\\}",
              "\\|": "bar.v.double"}
# characters written as they are; the others of ASCII have a meaning of their own in Typst or in LaTeX
PLAIN = frozenset("+-=<>!?:*()[]|.")
ESCAPED = {"/": "\\/", ",": "\\,", ";": "\\;", "~": "space"}
TEXT_ESCAPES = {"%": "%", "&": "&", "_": "_", "#": "#", "$": "$", "{": "{", "}": "}", ",": "\u2009", " ": " ",
                ";": "\u2005", "!": ""}

_TOKEN = re.compile(r"\\([A-Za-z]+)|\\(.)|(\{,\})|(\s+)|(.)", re.DOTALL)


@dataclass
class _Atom:
    base: str
    primes: int = 0
    sub: str | None = None
    sup: str | None = None

    def typst(self) -> str:
        out = self.base + "'" * self.primes  # primes first: Typst sets x'_(0) as x′₀, x_(0)' as x₍₀₎′
        if self.sub is not None:
            out += f"_({self.sub})"
        if self.sup is not None:
            out += f"^({self.sup})"
        return out


def _string(text: str) -> str:
    """A Typst string literal (upright text in math)."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


class _Parser:
    def __init__(self, latex: str) -> None:
        self.latex = latex
        self.tokens: list[tuple[str, str]] = []
        for m in _TOKEN.finditer(latex):
            if m.group(1) is not None:
                self.tokens.append(("cmd", m.group(1)))
            elif m.group(2) is not None:
                self.tokens.append(("cmd", m.group(2)))
            elif m.group(3) is not None:
                self.tokens.append(("deccomma", ","))
            elif m.group(4) is not None:
                self.tokens.append(("space", m.group(4)))
            else:
                self.tokens.append(("char", m.group(5)))
        self.i = 0

    def fail(self, what: str) -> ValueError:
        return ValueError(f"{what} in the formula {self.latex!r}")

    def peek(self, raw: bool = False) -> tuple[str, str] | None:
        """The next token (spaces skipped, as LaTeX's math mode does, unless ``raw``)."""
        while not raw and self.i < len(self.tokens) and self.tokens[self.i][0] == "space":
            self.i += 1
        return self.tokens[self.i] if self.i < len(self.tokens) else None

    def take(self, raw: bool = False) -> tuple[str, str]:
        tok = self.peek(raw)
        if tok is None:
            raise self.fail("an argument missing at its end")
        self.i += 1
        return tok

    # -- sequences and arguments
    def seq(self, until: str | None = None) -> str:
        """Atoms up to ``until`` ("}" or "right", consumed but for "right"), or the end."""
        atoms: list[_Atom] = []
        while True:
            tok = self.peek()
            if tok is None:
                if until is not None:
                    raise self.fail("an unclosed { or \\left")
                break
            kind, val = tok
            if until == "}" and tok == ("char", "}"):
                self.i += 1
                break
            if until == "right" and tok == ("cmd", "right"):
                break
            if tok == ("char", "}"):
                raise self.fail("an unmatched }")
            if tok == ("cmd", "right"):
                raise self.fail("a \\right without its \\left")
            if kind == "char" and val in "_^":
                self.i += 1
                if not atoms:
                    atoms.append(_Atom("zws"))
                atom = atoms[-1]
                if (atom.sub if val == "_" else atom.sup) is not None:
                    raise self.fail(f"a double {'subscript' if val == '_' else 'superscript'}")
                arg = self.arg()
                if val == "_":
                    atom.sub = arg
                else:
                    atom.sup = arg
                continue
            if tok == ("char", "'"):
                self.i += 1
                if atoms and atoms[-1].sub is None and atoms[-1].sup is None:
                    atoms[-1].primes += 1
                elif atoms and atoms[-1].sup is None:  # x_0' : the prime before the script, as Typst wants it
                    atoms[-1].primes += 1
                else:
                    atoms.append(_Atom("prime"))
                continue
            if tok == ("char", "{"):
                self.i += 1
                inner = self.seq("}")
                atoms.append(_Atom(inner if inner else "zws"))
                continue
            if kind == "char" and val.isdigit():
                atoms.append(_Atom(self.number()))
                continue
            atoms.append(_Atom(self.item()))
        return " ".join(a.typst() for a in atoms if a.typst())

    def number(self) -> str:
        """Digits, with a decimal point or comma between digits: 0.155 as a number, 0{,}155 as upright text."""
        digits = [self.take()[1]]
        comma = False
        while (tok := self.peek(raw=True)) is not None:
            if tok[0] == "char" and tok[1].isdigit():
                digits.append(tok[1])
                self.i += 1
                continue
            nxt = self.tokens[self.i + 1] if self.i + 1 < len(self.tokens) else None
            if tok in (("char", "."), ("deccomma", ",")) and nxt is not None and nxt[0] == "char" and nxt[1].isdigit():
                digits.append(tok[1])
                comma |= tok[0] == "deccomma"
                self.i += 1
                continue
            break
        text = "".join(digits)
        return _string(text) if comma else text

    def arg(self) -> str:
        """A command's or a script's argument: a {group}, or one token (one digit, one letter, one command)."""
        tok = self.peek()
        if tok is None:
            raise self.fail("an argument missing at its end")
        if tok == ("char", "{"):
            self.i += 1
            return self.seq("}") or "zws"
        if tok[0] == "char" and tok[1].isdigit():
            self.i += 1
            return tok[1]
        if tok[0] == "char" and tok[1] in "}^_'":
            raise self.fail(f"an argument missing before {tok[1]!r}")
        return self.item()

    def raw_group(self) -> str:
        """The source of a {group}, braces balanced, for \\text and \\mathrm."""
        if self.peek() != ("char", "{"):
            raise self.fail("a { missing after \\text or \\mathrm")
        self.i += 1
        depth, out = 1, []
        while True:
            kind, val = self.take(raw=True)
            if kind == "char" and val == "{":
                depth += 1
            elif kind == "char" and val == "}":
                depth -= 1
                if depth == 0:
                    return "".join(out)
            out.append(("\\" + val + (" " if val.isalpha() else "")) if kind == "cmd" else
                       "{,}" if kind == "deccomma" else val)  # a space token: its own text

    def text(self, raw: str) -> str:
        """The text of \\text{…}: its escapes resolved, anything else of LaTeX refused."""
        out, i = [], 0
        while i < len(raw):
            ch = raw[i]
            if ch == "\\":
                m = re.match(r"\\([A-Za-z]+) ?|\\(.)", raw[i:])
                if m is None or m.group(1) is not None or m.group(2) not in TEXT_ESCAPES:
                    name = (m.group(1) or m.group(2)) if m else ""
                    raise self.fail(f"the command \\{name} inside \\text")
                out.append(TEXT_ESCAPES[m.group(2)])
                i += m.end()
                continue
            if ch in "$^_&#%":
                raise self.fail(f"the character {ch!r} inside \\text")
            out.append("\u00a0" if ch == "~" else ch.replace("{", "").replace("}", ""))
            i += 1
        return _string("".join(out))

    def delimiter(self) -> str:
        kind, val = self.take()
        key = ("\\" + val) if kind == "cmd" else val
        if key not in DELIMITERS:
            raise self.fail(f"the delimiter {key!r} after \\left or \\right")
        return DELIMITERS[key]

    # -- one item
    def item(self) -> str:
        kind, val = self.take()
        if kind == "char":
            if val.isascii() and val.isalpha():
                return val
            if val in PLAIN:
                return val
            if val in ESCAPED:
                return ESCAPED[val]
            if not val.isascii() and val.isprintable():  # a Unicode letter or symbol: itself, one atom
                return val
            raise self.fail(f"the character {val!r}")
        if kind == "deccomma":
            return "\\,"
        if val in GREEK:
            return GREEK[val]
        if val in SYMBOLS:
            return SYMBOLS[val]
        if val in FUNCTIONS:
            return val
        if val in ("frac", "dfrac", "tfrac"):
            num, den = self.arg(), self.arg()
            return f"frac({num}, {den})"
        if val == "sqrt":
            if self.peek() == ("char", "["):
                self.i += 1
                index = self.until_bracket()
                return f"root({index}, {self.arg()})"
            return f"sqrt({self.arg()})"
        if val == "left":
            left = self.delimiter()
            body = self.seq("right")
            self.take()  # \right
            right = self.delimiter()
            return f"lr({left} {body} {right})" if left or right else body
        if val in ("text", "textrm", "textit", "mbox"):
            return self.text(self.raw_group())
        if val in ("mathrm", "operatorname"):
            raw = self.raw_group()
            if raw in FUNCTIONS:
                return raw
            if re.fullmatch(r"[A-Za-z0-9 .()/+\-]*", raw) and raw.strip():
                word = _string(raw)
                return f"op({word})" if val == "operatorname" else word
            inner = _Parser(raw)
            inner.latex = self.latex
            return f"upright({inner.seq() or 'zws'})"
        if val in STYLES:
            return f"{STYLES[val]}({self.arg()})"
        if val in ACCENTS:
            return f"{ACCENTS[val]}({self.arg()})"
        raise self.fail(f"the unknown command \\{val}")

    def until_bracket(self) -> str:
        """The optional argument of \\sqrt[n]{…}, up to its ]."""
        start = self.i
        depth = 0
        while True:
            tok = self.take()
            if tok == ("char", "{"):
                depth += 1
            elif tok == ("char", "}"):
                depth -= 1
            elif tok == ("char", "]") and depth == 0:
                inner = _Parser("")
                inner.latex, inner.tokens = self.latex, self.tokens[start:self.i - 1]
                return inner.seq() or "zws"


def latex_to_typst(latex: str) -> str:
    """One formula's LaTeX source as Typst math, without the ``$``: ``\\frac{v_0}{2}`` → ``frac(v_(0), 2)``.
    Raises ``ValueError`` naming a command or character outside the subset."""
    return _Parser(latex).seq()
