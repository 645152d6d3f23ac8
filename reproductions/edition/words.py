"""The edition's shared words and templates: what the HTML page and the PDF both say (the glossary, the consequence
scale, the measured part's introduction), and the files of ``templates/``."""

from __future__ import annotations

from functools import cache
from importlib import resources

__all__ = ["CONSEQUENCE", "MEASURED_INTRO", "SYMBOLS", "VERDICT_WORDS", "template"]


@cache
def template(name: str) -> str:
    """A file of ``templates/``, as text."""
    return resources.files(__package__).joinpath("templates", name).read_text(encoding="utf-8")


MEASURED_INTRO = ("Published measurements of billiard balls, each against what the paper's mechanics predict "
                   "(§I's law of impact, §V–§VI's friction during the impact, §II's sliding on the cloth), with "
                   "the measurement's uncertainty and the prediction's 95 % interval. These rows judge the 1883 "
                   "theory, not a printed claim: their verdicts, consistent or inconsistent at 95 % (fitted where "
                   "the measurement fixed a parameter), are counted apart from the printed claims.")


# the words and symbols a reader meets in the rows (the paper's notation, §I)
SYMBOLS = (
    ("vis viva", "m v², the “living force” of the period: twice the kinetic energy"),
    ("ε, ε′", "Résal's energy-loss coefficients of the two bodies (§I): the vis viva lost in an impact is "
              "governed by them; ε = 0 loses nothing in the restitution, ε = 1 is a plastic impact"),
    ("e", "Newton's coefficient of restitution; for a ball on a fixed body e = (1 − ε)/(1 + ε) (eq. (9))"),
    ("ν", "the normal-velocity yield: the normal velocity after an impact over the one before (§III–IV)"),
    ("f", "the coefficient of friction between the bodies in contact (ball–cloth, ball–cushion, ball–ball)"),
    ("k", "a ball's moment of inertia is M R²/k: k = 5/2 for a homogeneous sphere"),
    ("discrepancy", "for a printed formula: its largest difference from the exact mechanics (a direct numerical "
                    "integration), in the units the row's note gives; within its tolerance the formula holds"),
)
VERDICT_WORDS = (
    ("reproduced", "what resal computes from the paper's premises agrees with the printed value within its "
                   "printed digits (or the formula within its tolerance)"),
    ("differs", "it does not; the reason says why"),
    ("not-checkable", "nothing can be computed or compared (a measurement the paper reports, a claim without a "
                      "number)"),
    ("consistent", "a published measurement and the paper's prediction agree at 95 % (the measurement's "
                   "uncertainty and the prediction's interval both counted)"),
    ("inconsistent", "they do not: the paper's mechanics do not describe the measurement"),
    ("fitted", "the measurement fixed a parameter of the prediction, so it tests nothing"))
CONSEQUENCE = ("Each finding is ranked by its consequence, from 5 (it changes what the paper teaches) through 3 "
               "(a result a reader would use is wrong as printed) to 1 (a detail).")
