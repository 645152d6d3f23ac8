"""Formulas in the rows' text, found and written once as LaTeX: the one source from which the HTML's MathML
(``mathml``, by latex2mathml) and the PDF's Typst math (``typst_math.latex_to_typst``) are both made.

The configs write formulas as a reader types them in plain text: ``(1 − ε)/(1 + ε)``, ``V1``, ``φ0²``,
``v_z``, ``x^(b/a)``, ``∫_{η0}^{η1}``, ``√(1 + …)``, inside English prose. ``segments`` splits such a text into
prose spans and formula spans (style "math", text the LaTeX), by rules a test runs over every text of the
edition: a formula is a run of words that are symbols (one letter, Latin or Greek, with primes, an index or a
script; a product of such letters written with a capital, ``pR``, ``fZ``, ``MV1``), numbers and operators, which
holds at least one symbol and one operator or script. English words never qualify (``a ball`` stays prose; ``a(1 + k)``
does not). Numbers in e-notation become ``2.2 × 10⁻¹⁶`` as a formula, never ``2.2e-16``."""

from __future__ import annotations

import itertools
import re
from functools import lru_cache

from .model import Rich, Span

__all__ = ["mathml", "plain_number", "segments"]

GREEK = {"α": "alpha", "β": "beta", "γ": "gamma", "δ": "delta", "ε": "varepsilon", "ζ": "zeta", "η": "eta",
         "θ": "theta", "ι": "iota", "κ": "kappa", "λ": "lambda", "μ": "mu", "ν": "nu", "ξ": "xi", "π": "pi",
         "ρ": "rho", "σ": "sigma", "τ": "tau", "υ": "upsilon", "φ": "varphi", "χ": "chi", "ψ": "psi", "ω": "omega",
         "Γ": "Gamma", "Δ": "Delta", "Θ": "Theta", "Λ": "Lambda", "Ξ": "Xi", "Π": "Pi", "Σ": "Sigma", "Φ": "Phi",
         "Ψ": "Psi", "Ω": "Omega"}
# LaTeX a config may write (the digitised text's habit) → the plain character the rules below read
_COMMANDS = {r"\alpha": "α", r"\beta": "β", r"\gamma": "γ", r"\delta": "δ", r"\epsilon": "ε", r"\varepsilon": "ε",
             r"\zeta": "ζ", r"\eta": "η", r"\theta": "θ", r"\lambda": "λ", r"\mu": "μ", r"\nu": "ν", r"\xi": "ξ",
             r"\pi": "π", r"\rho": "ρ", r"\sigma": "σ", r"\tau": "τ", r"\phi": "φ", r"\varphi": "φ", r"\chi": "χ",
             r"\psi": "ψ", r"\omega": "ω", r"\Delta": "Δ", r"\Omega": "Ω", r"\cdot": "·", r"\times": "×",
             r"\sqrt": "√", r"\int": "∫", r"\pm": "±", r"\mp": "∓", r"\leq": "≤", r"\geq": "≥", r"\le": "≤",
             r"\ge": "≥", r"\infty": "∞", r"\prime": "′", r"\left": "", r"\right": "", r"\,": " ", r"\;": " "}
_OPS = {"=": "=", "+": "+", "−": "-", "×": r"\times", "·": r"\cdot", "±": r"\pm", "∓": r"\mp", "≤": r"\le",
        "≥": r"\ge", "<": "<", ">": ">", "≈": r"\approx", "≠": r"\ne", "→": r"\to", "/": "/", "∫": r"\int"}
_FUNCTIONS = ("arctan", "sin", "cos", "tan", "exp", "ln", "log")
_UNITS = {"m", "s", "cm", "mm", "kg", "g", "N", "J", "rad", "ms", "µs", "Hz", "m/s", "rad/s", "J/kg"}
_SUPERSCRIPT = str.maketrans("0123456789-+", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺")
_ENOTATION = re.compile(r"(?<![\w.])(\d+(?:\.\d+)?)e([+-]?)(\d+)(?![\w.])")
_LETTER = "A-Za-zα-ωΑ-Ω"


def plain_number(text: str) -> str:
    """A text with its e-notation numbers written as a reader writes them: ``2.2e-16`` → ``2.2 × 10⁻¹⁶`` (and
    ``1e-9`` → ``10⁻⁹``, ``0e+00`` → ``0``)."""

    def one(m: re.Match) -> str:
        mant, sign, exp = m.group(1), m.group(2), int(m.group(3))
        if float(mant) == 0:
            return "0"
        power = f"10{(('-' if sign == '-' else '') + str(exp)).translate(_SUPERSCRIPT)}"
        return power if mant == "1" else f"{mant} × {power}"

    return _ENOTATION.sub(one, text)


# -- tokens ---------------------------------------------------------------------------------------------------
def _balanced(text: str, i: int) -> int:
    """The index after the bracket group that opens at ``text[i]`` (``(``, ``{`` or ``[``), or -1."""
    pairs = {"(": ")", "{": "}", "[": "]"}
    depth = 0
    for j in range(i, len(text)):
        if text[j] in pairs:
            depth += 1
        elif text[j] in ")}]":
            depth -= 1
            if depth == 0:
                return j + 1
    return -1


_GROUP_START = re.compile(r"[\^_√][({\[]")
_SPACES = re.compile(r"(\s+)")


def _tokens(text: str) -> list[str]:
    """Words and the spaces between them; a script's bracket group (``^(k/(1 + k))``, ``_{a b}``) and a root's
    (``√(1 + x)``) never split."""
    if not _GROUP_START.search(text):  # most texts: words between spaces
        return [t for t in _SPACES.split(text) if t]
    out: list[str] = []
    buf: list[str] = []
    i = 0
    while i < len(text):
        ch = text[i]
        if ch.isspace():
            if buf:
                out.append("".join(buf))
                buf = []
            j = i
            while j < len(text) and text[j].isspace():
                j += 1
            out.append(text[i:j])
            i = j
            continue
        if ch in "^_√" and i + 1 < len(text) and text[i + 1] in "({[":
            end = _balanced(text, i + 1)
            if end > 0:
                buf.append(text[i:end])
                i = end
                continue
        buf.append(ch)
        i += 1
    if buf:
        out.append("".join(buf))
    return out


# a symbol: a letter, primes, an index of one or two digits, a script, a power
_SCRIPT = r"(?:[_^](?:\{[^{}]*\}|\((?:[^()]|\([^()]*\))*\)|[A-Za-z0-9α-ωΑ-Ω]{1,3}(?![A-Za-z0-9])))"
_SYMBOL = re.compile(rf"[{_LETTER}][′″']*(?:\d{{1,2}})?[′″']*(?:{_SCRIPT})*[²³]?")
_NUMBER = re.compile(r"\d+(?:[.,]\d+)?(?:e[+-]?\d+)?|½")


# short words of English and French that are never a product of two symbols, even beside a bracket
_WORDS = {"of", "to", "in", "at", "on", "by", "or", "is", "no", "as", "if", "an", "be", "it", "we", "de", "la", "le",
          "et", "du", "en", "un", "ms", "and", "the", "for", "not", "its", "one", "two", "all", "see", "are", "per",
          "les", "des", "une", "est", "que", "qui", "par", "sur", "aux", "eqs", "eq", "max", "min", "mm", "cm"}


@lru_cache(maxsize=16384)
def _piece_latex(piece: str, after_number: bool, in_fraction: bool, in_math: bool = False) -> tuple[str, bool] | None:
    """One piece of a word between operators and brackets, as LaTeX, and whether it is a symbol (a letter); None
    when it is English, not mathematics."""
    if not piece:
        return "", False
    m = _NUMBER.fullmatch(piece)
    if m:
        return _number_latex(piece), False
    if after_number and piece in _UNITS:
        return rf"\,\mathrm{{{piece}}}", False
    if piece in _FUNCTIONS:
        return rf"\{piece}", True
    if (in_fraction and re.fullmatch(rf"d[{_LETTER}][′']*\d?", piece)) or re.fullmatch(r"d[txyzα-ω]", piece):
        # dn/dt, dχ/dt; a differential standing alone: dt, dφ
        return "d" + _symbols_latex(piece[1:]), True
    coeff = re.match(r"\d+(?:\.\d+)?", piece)
    rest = piece[coeff.end():] if coeff else piece
    symbols = []
    at = 0
    while at < len(rest):
        s = _SYMBOL.match(rest, at)
        if not s:
            return None
        symbols.append(s.group(0))
        at = s.end()
    letters = [s[0] for s in symbols]
    if not letters:
        return None
    scripted = any(re.search(r"\d|[_^²³′″']", s[1:]) for s in symbols)
    greek = any(c in GREEK for c in letters)
    capital = any(c.isupper() for c in letters)
    if len(letters) > 1 and not (scripted or greek or capital or (in_math and rest not in _WORDS)):
        return None  # an English word: at, to, of, ms
    if len(letters) > 3:
        return None
    if len(letters) > 1 and all(c.isupper() for c in letters) and not scripted and not greek:
        return None  # an acronym: ODE, CSV
    if any(re.search(r"\d[a-z]", a + b[:1]) for a, b in itertools.pairwise(symbols)):
        return None  # an index followed by a small letter: a name (V1p), not a product
    return (_number_latex(coeff.group(0)) if coeff else "") + " ".join(_symbol_latex(s) for s in symbols), True


def _number_latex(n: str) -> str:
    if n == "½":
        return r"\frac{1}{2}"
    m = _ENOTATION.fullmatch(n)
    if m:
        mant, sign, exp = m.group(1), m.group(2), int(m.group(3))
        power = f"10^{{{'-' if sign == '-' else ''}{exp}}}"
        return "0" if float(mant) == 0 else power if mant == "1" else rf"{mant} \times {power}"
    return n.replace(",", "{,}")


def _letter(c: str) -> str:
    return rf"\{GREEK[c]} " if c in GREEK else c


def _symbols_latex(text: str) -> str:
    return " ".join(_symbol_latex(s.group(0)) for s in _SYMBOL.finditer(text))


def _symbol_latex(s: str) -> str:
    """One symbol (``V′1``, ``φ0²``, ``v_z``, ``x^(b/a)``) as LaTeX."""
    m = re.match(rf"([{_LETTER}])([′″']*)(\d{{1,2}})?([′″']*)(.*?)([²³]?)$", s)
    assert m is not None
    base, p1, index, p2, scripts, power = m.groups()
    primes = (p1 + p2).replace("″", "''").replace("′", "'")
    out = _letter(base).rstrip() + primes
    subs, sups = [], []
    if index:
        subs.append(index)
    for sm in re.finditer(_SCRIPT, scripts):
        tok = sm.group(0)
        body = tok[1:]
        if body[0] in "({":
            body = body[1:-1]
        (subs if tok[0] == "_" else sups).append(_expression(body))
    if power:
        sups.append("2" if power == "²" else "3")
    if subs:
        out += "_{" + " ".join(subs) + "}"
    if sups:
        out += "^{" + " ".join(sups) + "}"
    return out


def _expression(text: str) -> str:
    """A whole text read as mathematics (inside a script or a root, or a run ``segments`` found)."""
    out = []
    prev_number = False
    for tok in _tokens(text):
        if tok.isspace():
            out.append(" ")
            continue
        lx = _word_latex(tok, prev_number, whole=True)
        out.append(lx if lx is not None else rf"\text{{{tok}}}")
        prev_number = bool(re.fullmatch(r"[\d.,]+", tok))
    return "".join(out).strip()


_UNIT_POWER = re.compile(r"((?:m|cm|mm|rad)/s)(?:\^(\d)|([²]))")


@lru_cache(maxsize=16384)  # a word recurs across the texts (and a run's words are read twice)
def _word_latex(word: str, after_number: bool = False, whole: bool = False) -> str | None:
    """A word between spaces as LaTeX, or None when it is prose. ``whole``: inside a formula already (a script's
    or a root's content), where a lone letter or number is mathematics too."""
    if after_number and (word in _UNITS or _UNIT_POWER.fullmatch(word)):
        u = _UNIT_POWER.fullmatch(word)
        if u:
            return rf"\,\mathrm{{{u.group(1)}}}^{{{u.group(2) or '2'}}}"
        return rf"\,\mathrm{{{word}}}"
    out: list[str] = []
    in_fraction = "/" in word
    i = 0
    symbols = 0
    prev_number = after_number
    while i < len(word):
        ch = word[i]
        if ch in "^_√" and i + 1 < len(word) and word[i + 1] in "({":
            end = _balanced(word, i + 1)
            if end < 0:
                return None
            body = _expression(word[i + 2:end - 1])
            symbols += bool(re.search(rf"[{_LETTER}]", word[i + 2:end - 1]))
            out.append(rf"\sqrt{{{body}}}" if ch == "√" else f"{ch}{{{body}}}")
            i = end
            continue
        if ch in "^_":  # a script after a bracket or an integral sign: ]_φ^φ0, ∫_φ1^φ0
            sm = re.match(_SCRIPT, word[i:])
            if not sm:
                return None
            body = sm.group(0)[1:]
            if body[0] in "({":
                body = body[1:-1]
            out.append(f"{ch}{{{_expression(body)}}}")
            i += sm.end()
            continue
        if ch == "√":
            out.append(r"\sqrt")
            i += 1
            # a root of one symbol or number: √2, √v
            m = _NUMBER.match(word, i) or _SYMBOL.match(word, i)
            if m:
                out.append("{" + (_number_latex(m.group(0)) if m.group(0)[0].isdigit() else _symbol_latex(m.group(0)))
                           + "}")
                i = m.end()
            continue
        if ch in _OPS:
            out.append(f" {_OPS[ch]} " if ch not in "/" else "/")
            i += 1
            prev_number = False
            continue
        if ch == "-" and (i == 0 or not word[i - 1].isalpha()):
            out.append(" - ")
            i += 1
            continue
        if ch == "," and 0 < i < len(word) - 1 and word[i - 1].isdigit() and word[i + 1].isdigit():
            out.append("{,}")
            i += 1
            continue
        if ch in "()[]|,;:%…²³":
            out.append({"…": r"\ldots ", "%": r"\%", "²": "^{2}", "³": "^{3}", ",": ", "}.get(ch, ch))
            i += 1
            continue
        if ch in "{}":
            out.append("\\" + ch)
            i += 1
            continue
        # a piece: up to the next operator or bracket (a script stays with its symbol; a number in e-notation whole)
        e = _ENOTATION.match(word, i) if (i == 0 or not word[i - 1].isalnum()) else None
        if e:
            out.append(_number_latex(e.group(0)))
            prev_number = True
            i = e.end()
            continue
        j = i
        while j < len(word):
            if word[j] in "^_" and j + 1 < len(word):
                s = re.match(_SCRIPT, word[j:])
                if s:
                    j += s.end()
                    continue
            if word[j] == "," and 0 < j < len(word) - 1 and word[j - 1].isdigit() and word[j + 1].isdigit():
                j += 1  # a decimal comma: 0,155
                continue
            if word[j] in "()[]{}|=+−×·±∓≤≥<>≈≠→/∫,;:%…√" or (word[j] == "-" and not word[j - 1].isalpha()):
                break
            if word[j] in "²³" and j + 1 < len(word) and word[j + 1] not in "()[]/":
                j += 1
                break
            j += 1
        piece = word[i:j]
        res = _piece_latex(piece, prev_number, in_fraction, whole or any(c in word for c in "()[]{}=+−/^_"))
        if res is None:
            if whole and re.fullmatch(rf"[{_LETTER}]+", piece):
                res = (r"\mathrm{" + piece + "}", False)
            else:
                return None
        lx, is_symbol = res
        symbols += is_symbol
        prev_number = bool(_NUMBER.fullmatch(piece))
        out.append(lx)
        i = j
    if not whole and not symbols and not re.search(r"\d", word) and not all(c in _OPS or c in "-±∓" for c in word):
        return None
    return "".join(out)


_OPERATOR_WORD = re.compile(r"^-$|[=+−×·±∓≤≥<>≈≠→/∫√^_²³]|(?<![A-Za-z])d[A-Za-zα-ω]/d[a-z]")


@lru_cache(maxsize=8192)
def segments(text: str | None) -> Rich:
    """A text as prose and formula spans (style "math", the LaTeX). Never loses a character of the text but the
    ``$`` of LaTeX input and the spaces between a formula's words (its typesetting decides them)."""
    s = text or ""
    if "\\" in s:
        for cmd in sorted(_COMMANDS, key=len, reverse=True):
            s = re.sub(re.escape(cmd) + r"(?![A-Za-z])", _COMMANDS[cmd], s)
    s = s.replace("$", "")
    s = re.sub(r"(?:(?<=\s)|^)- (?=\d)", "− ", s)  # a hyphen typed for a minus before a number
    toks = _tokens(s)
    kinds: list[tuple[str, str | None]] = []  # (token, its LaTeX, or None for prose)
    prev_number = False
    for t in toks:
        if t.isspace():
            kinds.append((t, " "))
            continue
        core, tail = t, ""
        while core and core[-1] in ",.;:":  # a sentence's punctuation is prose
            tail = core[-1] + tail
            core = core[:-1]
        lx = _word_latex(core, prev_number) if core else None
        if lx is None and _ENOTATION.fullmatch(core or ""):
            lx = _number_latex(core)
        if lx is None:
            kinds.append((t, None))
        else:
            kinds.append((core, lx))
            if tail:
                kinds.append((tail, None))
        prev_number = bool(re.fullmatch(r"\d+(?:[.,]\d+)?", core or ""))
    spans: list[Span] = []
    i = 0
    n = len(kinds)
    while i < n:
        tok, lx = kinds[i]
        if lx is None or tok.isspace():
            spans.append(Span(tok))
            i += 1
            continue
        j = i
        while j < n and kinds[j][1] is not None:
            j += 1
        end = j
        while end > i and kinds[end - 1][0].isspace():  # a space after the run is prose
            end -= 1
        spans.extend(_run([k[0] for k in kinds[i:end]]))
        spans.extend(Span(k[0]) for k in kinds[end:j])
        i = j
    return _merge(spans)


def _run(words: list[str]) -> list[Span]:
    """A run of words that may be mathematics (spaces between them included): one formula span when it is one
    (a bracket the prose opened or closed around it left as prose), else prose."""
    text = "".join(words)
    cut = _unmatched(text)
    if cut is not None and 0 < cut < len(text) - 1:  # a bracket of the prose inside the run: the run is two
        left, right = text[:cut], text[cut + 1:]
        return [*_run(_tokens(left)), Span(text[cut]), *_run(_tokens(right))]
    head = tail = ""
    while text.count("(") > text.count(")") and text.startswith("("):
        head, text = head + "(", text[1:]
    while text.count(")") > text.count("(") and text.endswith(")"):
        text, tail = text[:-1], ")" + tail
    parts = [w for w in _tokens(text) if not w.isspace()]
    has_symbol = any(re.search(rf"[{_LETTER}]", w) and _word_latex(w) is not None for w in parts)
    has_operator = any(_OPERATOR_WORD.search(w) or re.search(rf"[{_LETTER}][′″']*\d", w) for w in parts)
    notation = len(parts) == 1 and _ENOTATION.fullmatch(parts[0]) is not None
    if not ((has_symbol and has_operator and _brackets_balance(text)) or notation):
        return [Span("".join(words))]
    lx = _number_latex(parts[0]) if notation else _expression(text)
    return [Span(head), Span(lx, "math"), Span(tail)]


def _unmatched(text: str) -> int | None:
    """The index of the first bracket without its partner, or None."""
    stack: list[int] = []
    for i, ch in enumerate(text):
        if ch in "([{":
            stack.append(i)
        elif ch in ")]}":
            if not stack:
                return i
            stack.pop()
    return stack[0] if stack else None


def _brackets_balance(text: str) -> bool:
    depth = 0
    for ch in text:
        depth += ch in "([{"
        depth -= ch in ")]}"
        if depth < 0:
            return False
    return depth == 0


def _merge(spans: list[Span]) -> Rich:
    out: list[Span] = []
    for sp in spans:
        if not sp.text:
            continue
        if out and out[-1].style == sp.style == "":
            out[-1] = Span(out[-1].text + sp.text)
        else:
            out.append(sp)
    return tuple(out)


@lru_cache(maxsize=8192)
def mathml(source: str) -> str:
    """One formula's LaTeX as an inline MathML element (latex2mathml), its source in ``alttext`` (what a screen
    reader without MathML reads, and what a test compares the rendering with)."""
    import html

    from latex2mathml.converter import convert

    out = convert(source)
    # a decimal comma ({,}, as the French prints 0,155) is part of its number, not a separator with space after it
    out = re.sub(r"<mn>(\d+)</mn><mrow><mo>&#x0002C;</mo></mrow><mn>(\d+)</mn>", r"<mn>\1,\2</mn>", out)
    return out.replace("<math ", f'<math alttext="{html.escape(source, quote=True)}" ', 1)
