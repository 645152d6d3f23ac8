"""The digitised text of the paper (``data/resal-1883.md``: H. Résal, J. Math. Pures Appl. (3) 9, 1883, p. 65-98, OCR
with LaTeX math), shipped so that every row's `line` and `text` can be checked against what the paper prints."""

from __future__ import annotations

import re
from functools import lru_cache
from importlib import resources

__all__ = ["WORD", "text", "words"]

WORD = re.compile(r"[A-Za-zÀ-ÖØ-öø-ÿŒœ]{2,}")  # a word of two letters or more (accents included)


@lru_cache(maxsize=1)
def text() -> str:
    """The digitised text, apostrophes normalised to ``'``."""
    raw = resources.files("reproductions").joinpath("data/resal-1883.md").read_text(encoding="utf-8")
    return raw.replace("’", "'")


@lru_cache(maxsize=1)
def words() -> frozenset[str]:
    """Every word the paper prints (lower case): a row's `text` quotes the paper only, so its words are among them."""
    return frozenset(w.lower() for w in WORD.findall(text()))
