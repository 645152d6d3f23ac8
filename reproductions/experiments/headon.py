"""Kind ``head_on``: one head-on collision on the cloth, filmed (Derby & Fuller 1999), against §VI n°13 then §II n°7.

The cue ball, with topspin s V/R before the impact (s = 1: natural roll), strikes the object ball at rest head on.
The impact is §VI (``spheres.two_spheres(on_cloth=True)``, ε = ε′ = (1 − e)/(1 + e), §I eq. (9)): the vertical
slip R ω0 of the topspin makes the ball–ball friction f act even head on (it takes topspin from the cue ball and
gives the object ball backspin). Then each ball slides on the cloth until it rolls (§II, ``cloth.slide``): its centre
changes speed at μg, against the slip u = v − Rω, for t = |u|/((1 + k) μ g), and it ends at v − u/(1 + k).

What is fitted and what is tested (design A): μ is the weighted mean of the two published sliding accelerations
(§II gives both balls the same |acceleration| μg); the cue ball's spin s is not published: it is inferred from the
cue ball's slip after the impact, |u1| = (1 + k) a_c t_c (§II: the slip changes (1 + k) times as fast as the centre's
speed), and e from the object ball's final speed; f cannot be fixed by one collision and is drawn from today's range.
Every other published scalar is then predicted. The uncertainties are a seeded Monte Carlo: the published standard
errors as normal errors, every other number uniform over ± half its last printed digit, f from its prior; a
prediction's interval is its 2.5–97.5 % quantiles, and a row is consistent when the 95 % interval of
(predicted − measured) contains 0.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..config import Experiment, Node, decode_text, read_input
from ..errors import InputError
from ..mechanics import cloth, impact, spheres
from .base import Comparison, FigureSpec, FitRow, Reproduction, layer, measurement_rows, modern_rows

QUANTITIES = ("mu_common", "cue_sliding_time", "target_sliding_time", "cue_final_speed", "target_final_speed",
              "e_vs_modern", "momentum_before", "momentum_after", "kinetic_energy_loss", "impact_momentum")
COST = 0.4  # CPU seconds of a run with its figures, about: the process pool starts the longest first
MODERN = ("e_bb", "mu_s", "mu_bb")
MAX_DRAWS = 20_000
MAX_DATA_BYTES = 1 << 16  # a table of published scalars: a few hundred bytes
REQUIRED = ("ball_mass", "ball_diameter", "incident_speed", "cue_sliding_time", "target_sliding_time",
            "cue_final_speed", "target_final_speed", "cue_sliding_acceleration", "target_sliding_acceleration",
            "momentum_before", "momentum_after", "kinetic_energy_loss")
_TOL = 1e-7  # bisection: width of the final bracket of s and e
_MAX_BISECT = 60
_MAX_OUTER = 12


@dataclass(frozen=True)
class Published:
    """One published scalar as the data file gives it: its value, its text (for the last printed digit), its unit,
    its standard error when the source states one, and its line."""

    name: str
    value: float
    text: str
    unit: str
    se: float | None
    where: str

    @property
    def digit(self) -> float:
        """A unit of the last printed digit."""
        t = self.text.strip().lstrip("+-")
        mantissa = t.split("e")[0].split("E")[0]
        return 10.0 ** -(len(mantissa.split(".")[1]) if "." in mantissa else 0)

    @property
    def sigma(self) -> float:
        """The standard error as published, else that of a uniform error over ± half the last digit."""
        return self.se if self.se is not None else self.digit / math.sqrt(12.0)

    @property
    def how_uncertain(self) -> str:
        if self.se is not None:
            return f"± {self.se:g} (published standard error)"
        return f"± {self.digit / 2:g} (half its last printed digit, uniform; σ = {self.sigma:.2g})"

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        if self.se is not None:
            return rng.normal(self.value, self.se, n)
        return self.value + self.digit * rng.uniform(-0.5, 0.5, n)


def read_published(path: Path, required: tuple[str, ...]) -> dict[str, Published]:
    """The published scalars of a data file (``#`` comment lines; columns quantity, value, unit[, standard_error],
    note). A missing quantity, a repeated one, a value or standard error that is not a finite number is refused,
    naming the file and the line."""
    where = str(path)
    text = decode_text(read_input(path, "a CSV file of published values", MAX_DATA_BYTES,
                                  "cannot read the data file"), where, "a CSV file of published values")
    numbered = [(i + 1, ln) for i, ln in enumerate(text.splitlines()) if ln.strip() and not ln.lstrip().startswith("#")]
    if not numbered:
        raise InputError(f"{where}:1", "no header: expected the columns quantity,value,unit,note")
    header_line = numbered[0][0]
    rows = list(csv.reader([ln for _, ln in numbered]))
    header = [h.strip() for h in rows[0]]
    for col in ("quantity", "value", "unit"):
        if col not in header:
            raise InputError(f"{where}:{header_line}", f"no column '{col}': expected the columns quantity,value,unit"
                                                       f"[,standard_error],note, got {','.join(header)}")
    iq, iv, iu = header.index("quantity"), header.index("value"), header.index("unit")
    ise = header.index("standard_error") if "standard_error" in header else None
    out: dict[str, Published] = {}
    for (line, _), row in zip(numbered[1:], rows[1:], strict=True):
        at = f"{where}:{line}"
        if len(row) < len(header) - 1:
            raise InputError(at, f"{len(row)} fields: expected {len(header)} ({','.join(header)})")
        name = row[iq].strip()
        if name in out:
            raise InputError(at, f"quantity '{name}' given twice (first at {out[name].where})")
        raw = row[iv].strip()
        try:
            value = float(raw)
        except ValueError:
            value = math.nan
        if not math.isfinite(value):
            raise InputError(at, f"the value of '{name}' must be a finite number, got '{raw}'")
        se = None
        if ise is not None and ise < len(row) and row[ise].strip():
            try:
                se = float(row[ise])
            except ValueError:
                se = math.nan
            if not (math.isfinite(se) and se > 0):
                raise InputError(at, f"the standard error of '{name}' must be a number > 0, got '{row[ise].strip()}'")
        out[name] = Published(name, value, raw, row[iu].strip() if iu < len(row) else "", se, at)
    missing = [q for q in required if q not in out]
    if missing:
        raise InputError(f"{where}:{header_line}", f"missing quantit{'y' if len(missing) == 1 else 'ies'} "
                                                   f"{', '.join(missing)}: expected rows for {', '.join(required)}")
    return out


@dataclass(frozen=True)
class Params:
    data: Path
    published: tuple[Published, ...]
    k: float
    g: float
    f_prior: tuple[float, float]  # today's ball-ball friction range, drawn uniformly (f is not fitted)
    e_modern: tuple[float, float]  # today's ball-ball restitution range, for e_vs_modern
    draws: int
    friction_law: tuple[float, float, float]  # today's μ(v) = a + b exp(−c v), for a note

    def get(self, name: str) -> Published:
        return next(p for p in self.published if p.name == name)


def _pair(node: Node, key: str, what: str, lo: float, hi: float) -> tuple[float, float]:
    v = node.number_list(key, what)
    if len(v) != 2 or not lo <= v[0] <= v[1] <= hi:
        raise node.fail(f"'{node.path}.{key}' must be two numbers [low, high] with {lo:g} ≤ low ≤ high ≤ {hi:g}, "
                        f"got {list(v)}", node._mapping()[key])
    return v[0], v[1]


def parse(node: Node, base: Path) -> Params:
    data = base / node.string("data")
    published = read_published(data, REQUIRED)  # a bad file stops the run before any work
    k = node.number("k", "k of the moment of inertia M R²/k", lo=0.0, lo_open=True)
    g = node.number("g", "the acceleration of gravity (m/s²)", lo=0.0, lo_open=True)
    f_prior = _pair(node, "f_prior", "a range of ball-ball friction", 0.0, 1.0)
    e_modern = _pair(node, "e_modern", "a range of ball-ball restitution", 0.0, 1.0)
    draws = node.integer("draws", "Monte Carlo draws", lo=100, hi=MAX_DRAWS)
    law = node.number_list("friction_law", "coefficients a, b, c of μ(v) = a + b exp(−c v)")
    if len(law) != 3:
        raise node.fail(f"'{node.path}.friction_law' must have exactly three coefficients a, b, c")
    node.done()
    return Params(data, tuple(published.values()), k, g, f_prior, e_modern, draws, (law[0], law[1], law[2]))


# ---------------------------------------------------------------------------------------------------------------
# the mechanics: §VI then §II


@dataclass(frozen=True)
class Ball:
    M: float
    R: float
    k: float
    g: float


def after_impact(b: Ball, V: Any, s: Any, e: Any, f: Any) -> dict[str, np.ndarray]:
    """Right after the §VI impact (head on, on the cloth): centre speeds and R ω of both balls (along the motion);
    ``normal_e`` = (v1′ − v1)/V, the ratio of the normal velocities: e exactly while the slip (vertical only, head
    on) does not stop during the impact (law (6), ``spheres`` docstring); above e where it stops."""
    V, s, e, f = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (V, s, e, f)))
    z = np.zeros_like(V)
    v0 = np.stack([V, z, z], -1)
    w0 = np.stack([z, s * V / b.R, z], -1)  # topspin about +y for a motion along +x (natural roll: R w_y = v_x)
    eps = impact.eps_from_newton(e)
    imp = spheres.two_spheres(b.M, b.M, b.R, b.R, b.k, b.k, v0, w0, np.zeros_like(v0), np.zeros_like(v0), f=f,
                              eps=eps, epsp=eps, on_cloth=True)
    return {"v1": imp.v1[..., 0], "v1p": imp.v1p[..., 0], "Rw1": b.R * imp.w1[..., 1], "Rw1p": b.R * imp.w1p[..., 1],
            "normal_e": (imp.v1p[..., 0] - imp.v1[..., 0]) / V, "regime": imp.regime}


def predict(b: Ball, V: Any, s: Any, e: Any, f: Any, mug: Any) -> dict[str, np.ndarray]:
    """Every published scalar by §VI then §II (arrays broadcast)."""
    V, s, e, f, mug = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (V, s, e, f, mug)))
    out = after_impact(b, V, s, e, f)
    z = np.zeros_like(V)
    for name, v, Rw in (("cue", out["v1"], out["Rw1"]), ("target", out["v1p"], out["Rw1p"])):
        roll = cloth.slide(v, z, z, Rw / b.R, R=b.R, k=b.k, f=mug / b.g, g=b.g)
        out[f"{name}_sliding_time"] = roll.t_roll
        out[f"{name}_final_speed"] = roll.vx_roll
        out[f"{name}_slip"] = v - Rw  # §II eq. (1): slip of the contact point on the cloth
    out["momentum_before"] = b.M * V
    out["momentum_after"] = b.M * (out["cue_final_speed"] + out["target_final_speed"])
    ke0 = V**2 + (s * V) ** 2 / b.k  # 2/M × (translation + rotation, I = M R²/k)
    ke1 = (1 + 1 / b.k) * (out["cue_final_speed"] ** 2 + out["target_final_speed"] ** 2)  # both rolling
    out["kinetic_energy_loss"] = 1 - ke1 / ke0
    out["kinetic_energy_loss_impact"] = 1 - (out["v1"] ** 2 + out["v1p"] ** 2
                                             + (out["Rw1"] ** 2 + out["Rw1p"] ** 2) / b.k) / ke0
    return out


def bisect(fun: Any, target: np.ndarray, lo: float, hi: float, tol: float = _TOL,
           max_iter: int = _MAX_BISECT) -> np.ndarray:
    """Vectorised bisection of an increasing ``fun`` on [lo, hi] for fun(x) = target, stopped when every bracket is
    narrower than ``tol`` (at most ``max_iter`` halvings); a target beyond the range ends at its bound."""
    target = np.asarray(target, dtype=float)
    a, c = np.full(target.shape, lo), np.full(target.shape, hi)
    for _ in range(max_iter):
        if float(np.max(c - a)) <= tol:
            break
        mid = 0.5 * (a + c)
        up = fun(mid) < target
        a, c = np.where(up, mid, a), np.where(up, c, mid)
    return 0.5 * (a + c)


def infer(b: Ball, V: Any, f: Any, mug: Any, a_c: Any, t_c: Any, v_tf: Any) -> tuple[np.ndarray, np.ndarray]:
    """Per draw: the cue ball's spin s = Rω0/V before the impact, from its slip after the impact,
    u1 = −(1 + k) a_c t_c (the cloth speeds it up: u1 < 0), and e from the object ball's final speed v_tf.
    The two are solved alternately (each enters the other's equation weakly) until neither moves by ``_TOL``."""
    V, f, mug, a_c, t_c, v_tf = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (V, f, mug, a_c, t_c, v_tf)))
    u_target = -(1 + b.k) * a_c * t_c
    s, e = np.ones_like(V), np.full_like(V, 0.9)

    def target_speed(x: np.ndarray, s_: np.ndarray) -> np.ndarray:
        out = after_impact(b, V, s_, x, f)
        return out["v1p"] - (out["v1p"] - out["Rw1p"]) / (1 + b.k)  # §II: the rolling speed v − u/(1 + k)

    def minus_cue_slip(x: np.ndarray, e_: np.ndarray) -> np.ndarray:
        out = after_impact(b, V, x, e_, f)
        return out["Rw1"] - out["v1"]

    for _ in range(_MAX_OUTER):
        e_new = bisect(lambda x, s_=s: target_speed(x, s_), v_tf, 0.05, 1.0)
        s_new = bisect(lambda x, e_=e_new: minus_cue_slip(x, e_), -u_target, 0.0, 4.0)
        moved = max(float(np.max(np.abs(e_new - e))), float(np.max(np.abs(s_new - s))))
        s, e = s_new, e_new
        if moved <= 2 * _TOL:
            break
    return s, e


# ---------------------------------------------------------------------------------------------------------------
# verdicts


def quantiles(x: Any) -> tuple[float, float, float]:
    """(2.5 %, median, 97.5 %) of Monte Carlo draws."""
    lo, mid, hi = np.percentile(np.asarray(x, dtype=float), [2.5, 50.0, 97.5])
    return float(lo), float(mid), float(hi)


def judge(pred: Any, meas: Any) -> tuple[str, tuple[float, float]]:
    """consistent when the 95 % interval of (predicted − measured), over the joint draws of both, contains 0."""
    d = np.broadcast_arrays(np.asarray(pred, dtype=float), np.asarray(meas, dtype=float))
    lo, _, hi = quantiles(d[0] - d[1])
    return ("consistent" if lo <= 0.0 <= hi else "inconsistent"), (lo, hi)


def _fmt_interval(iv: tuple[float, float], digits: int = 4) -> str:
    return f"[{iv[0]:+.{digits}g}, {iv[1]:+.{digits}g}]"


@dataclass(frozen=True)
class HeadOn:
    """Everything ``run`` reports: the draws' parameters, predictions and measured values."""

    s: np.ndarray
    e: np.ndarray
    f: np.ndarray
    mug: np.ndarray
    pred: dict[str, np.ndarray]
    meas: dict[str, np.ndarray]
    mug0: float
    mug_se: float
    chi2: float


def simulate(p: Params, seed: int) -> HeadOn:
    ball = Ball(p.get("ball_mass").value, p.get("ball_diameter").value / 2, p.k, p.g)
    rng = np.random.default_rng(seed)
    n = p.draws
    names = ("incident_speed", "cue_sliding_time", "target_sliding_time", "cue_final_speed", "target_final_speed",
             "cue_sliding_acceleration", "target_sliding_acceleration", "momentum_before", "momentum_after",
             "kinetic_energy_loss")
    meas = {q: p.get(q).draw(rng, n) for q in names}
    ac, at = p.get("cue_sliding_acceleration"), p.get("target_sliding_acceleration")
    w = np.array([1 / ac.sigma**2, 1 / at.sigma**2])
    mug0 = float((w[0] * ac.value + w[1] * abs(at.value)) / w.sum())
    chi2 = float(w[0] * (ac.value - mug0) ** 2 + w[1] * (abs(at.value) - mug0) ** 2)
    mug = (w[0] * meas["cue_sliding_acceleration"] + w[1] * np.abs(meas["target_sliding_acceleration"])) / w.sum()
    f = rng.uniform(p.f_prior[0], p.f_prior[1], n)
    V = meas["incident_speed"]
    s, e = infer(ball, V, f, mug, meas["cue_sliding_acceleration"], meas["cue_sliding_time"],
                 meas["target_final_speed"])
    pred = predict(ball, V, s, e, f, mug)
    return HeadOn(s, e, f, mug, pred, meas, mug0, float(w.sum() ** -0.5), chi2)


def comparisons(p: Params, h: HeadOn, rng: np.random.Generator
                ) -> tuple[dict[str, Comparison], dict[str, tuple[float, float]]]:
    """The rows' comparisons, and for each the 95 % interval of (predicted − measured) that decides its verdict."""
    out: dict[str, Comparison] = {}
    diffs: dict[str, tuple[float, float]] = {}

    def row(q: str, how: str, fitted: bool = False) -> None:
        pub = p.get(q)
        lo, mid, hi = quantiles(h.pred[q])
        verdict, diff = judge(h.pred[q], h.meas[q])
        if fitted:
            verdict = "fitted"
        diffs[q] = diff
        out[q] = Comparison(pub.value, f"{pub.text} {pub.unit}".strip(), pub.how_uncertain, mid, (lo, hi), verdict,
                            f"{how}; predicted − measured {_fmt_interval(diff)} (95 %)")

    ac, at = p.get("cue_sliding_acceleration"), p.get("target_sliding_acceleration")
    verdict, diff = judge(np.abs(h.meas["target_sliding_acceleration"]), h.meas["cue_sliding_acceleration"])
    diffs["mu_common"] = diff
    lo, mid, hi = quantiles(np.abs(h.meas["target_sliding_acceleration"]))
    from scipy import stats  # only here: the χ² tail

    p_value = float(stats.chi2.sf(h.chi2, 1))
    out["mu_common"] = Comparison(
        ac.value, f"{ac.text} {ac.unit}", ac.how_uncertain, mid, (lo, hi), verdict,
        f"§II gives both balls the same |acceleration| μg, so the cue ball's is predicted by the object ball's "
        f"{abs(at.value):g} ± {at.sigma:.2g}; predicted − measured {_fmt_interval(diff)} (95 %); one μ for both: χ² = "
        f"{h.chi2:.1f} (1 dof), p = {p_value:.1g}; their weighted mean μg = {h.mug0:.3f} ± {h.mug_se:.3f} m/s² "
        f"(μ = {h.mug0 / p.g:.3f}) is the cloth's μ of every other row")
    row("cue_sliding_time", "§VI then §II; the spin s was inferred from a_c × t_c, so with one μ this time is the "
                            "published t_c × a_c/μg: it fails with mu_common")
    row("target_sliding_time", "§VI then §II with the common μ")
    row("cue_final_speed", "§VI then §II: v1 − u1/(1 + k)")
    row("target_final_speed", "e was solved per draw so that §VI then §II give this speed", fitted=True)
    e_mod = rng.uniform(p.e_modern[0], p.e_modern[1], h.e.size)
    verdict, diff = judge(h.e, e_mod)
    diffs["e_vs_modern"] = diff
    lo, mid, hi = quantiles(h.e)
    lo_n, mid_n, hi_n = quantiles(h.pred["normal_e"])
    out["e_vs_modern"] = Comparison(
        0.5 * (p.e_modern[0] + p.e_modern[1]), f"{p.e_modern[0]:g}–{p.e_modern[1]:g} (today's ball–ball e)",
        "the range, drawn uniformly", mid, (lo, hi), verdict,
        f"the e the object ball's final speed needs (law (6) with ε = (1 − e)/(1 + e)); the impact's ratio of normal "
        f"velocities is {mid_n:.3f} [{lo_n:.3f}, {hi_n:.3f}]; e − today's {_fmt_interval(diff, 3)} (95 %)")
    row("momentum_before", "M V, with the published mass and incident speed")
    row("momentum_after", "M (v_cf + v_tf), both balls rolling, §VI then §II (momentum is kept in the impact, the "
                          "cloth's friction changes it while they slide)")
    row("kinetic_energy_loss", "1 − (kinetic energy once both roll)/(before the impact, with the cue ball's inferred "
                               "topspin); at the instant after the impact the loss is "
                               f"{quantiles(h.pred['kinetic_energy_loss_impact'])[1]:.3f}")
    # the data alone: the speeds right after the impact, from §II's kinematics, must keep momentum (§I)
    V = h.meas["incident_speed"]
    v1 = h.meas["cue_final_speed"] - h.meas["cue_sliding_acceleration"] * h.meas["cue_sliding_time"]
    v1p = h.meas["target_final_speed"] - h.meas["target_sliding_acceleration"] * h.meas["target_sliding_time"]
    ratio = (v1 + v1p) / V
    r_mid = quantiles(ratio)[1]
    sd = float(np.std(ratio))
    verdict, diff = judge(np.ones_like(ratio), ratio)
    diffs["impact_momentum"] = diff
    out["impact_momentum"] = Comparison(
        r_mid, f"(v1 + v1′)/V = {r_mid:.3f} from the data", f"± {sd:.3f} (propagated from the published values)",
        1.0, (1.0, 1.0), verdict,
        f"data only: v1 = v_cf − a_c t_c = {float(np.median(v1)):+.3f} m/s and v1′ = v_tf − a_t t_t = "
        f"{float(np.median(v1p)):.3f} m/s by §II's uniform acceleration; an impact keeps momentum (§I), so "
        f"(v1 + v1′)/V = 1 whatever e and f; 1 − measured {_fmt_interval(diff, 3)} (95 %), "
        f"{(1 - r_mid) / sd:.1f} σ")
    return out, diffs


def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    h = simulate(p, exp.seed)
    comps, diffs = comparisons(p, h, np.random.default_rng(exp.seed + 1))
    s_q, e_q, f_q = quantiles(h.s), quantiles(h.e), quantiles(h.f)
    a, b_, c = p.friction_law
    slip = s_q[1] * p.get("incident_speed").value
    fits = (
        FitRow("design-a.mu", "μ (ball–cloth)", h.mug0 / p.g, h.mug_se / p.g,
               ((h.mug0 - 1.96 * h.mug_se) / p.g, (h.mug0 + 1.96 * h.mug_se) / p.g),
               "weighted mean of the two published sliding accelerations (§II: |a| = μg)", True,
               f"the two accelerations disagree (χ² = {h.chi2:.1f}, 1 dof): see row mu_common"),
        FitRow("design-a.s", "s = Rω0/V, the cue ball's topspin before the impact", s_q[1], float(np.std(h.s)),
               (s_q[0], s_q[2]), "inferred per draw from the cue ball's slip after the impact, (1 + k) a_c t_c", True,
               "not published: inferred from the cue ball's sliding acceleration and time (s = 1: natural roll)"),
        FitRow("design-a.e", "e (ball–ball, law (6) with ε = ε′ = (1 − e)/(1 + e))", e_q[1], float(np.std(h.e)),
               (e_q[0], e_q[2]), "solved per draw so that §VI then §II give the object ball's final speed", True,
               f"today's {p.e_modern[0]:g}–{p.e_modern[1]:g}: see row e_vs_modern"),
        FitRow("prior.f", "f (ball–ball)", None, None, (None, None), "not fitted: drawn uniformly from today's range",
               False, f"one head-on collision cannot fix f; today's μ(v) at the cue ball's vertical slip Rω0 ≈ "
                      f"{slip:.2f} m/s gives {a + b_ * math.exp(-c * slip):.3f}", family_range=p.f_prior),
    )
    modern = modern_rows(exp.modern, {"e_bb": (e_q[1], "e the object ball's final speed needs"),
                                      "mu_s": (h.mug0 / p.g, "μ from the two sliding accelerations"),
                                      "mu_bb": (f_q[1], "f: not fitted, today's range drawn")})
    figures = (_figure_speeds(p, h), _figure_verdicts(comps, diffs, exp))
    note = (f"Monte Carlo of {p.draws} draws, seed {exp.seed}: published standard errors normal, other numbers uniform "
            "over ± half their last digit, f uniform over today's range")
    return Reproduction(exp, (), fits, figures, modern, data_note=note,
                        measurements=measurement_rows(exp, comps))


# ---------------------------------------------------------------------------------------------------------------
# figures


def _figure_speeds(p: Params, h: HeadOn) -> FigureSpec:
    ball = Ball(p.get("ball_mass").value, p.get("ball_diameter").value / 2, p.k, p.g)
    t_end = 0.25
    t = np.linspace(0.0, t_end, 126)
    layers = []
    z = np.zeros_like(h.s)
    for name, v, Rw, colour, who in (("cue", "v1", "Rw1", "C0", "cue ball"),
                                     ("target", "v1p", "Rw1p", "C3", "object ball")):
        _, _, vx, _ = cloth.state_at(t, h.pred[v], z, z, h.pred[Rw] / ball.R, R=ball.R, k=ball.k, f=h.mug / ball.g,
                                     g=ball.g)
        lo, mid, hi = np.percentile(vx, [2.5, 50.0, 97.5], axis=0)
        layers.append(layer("band", t, lo, hi, label="", color=colour))
        layers.append(layer("line", t, mid, label=f"{who}: §VI then §II (median, 95 % band)", color=colour))
        tp, vf, a = (p.get(f"{name}_sliding_time"), p.get(f"{name}_final_speed"),
                     p.get(f"{name}_sliding_acceleration"))
        layers.append(layer("line", [0.0, tp.value, t_end], [vf.value - a.value * tp.value, vf.value, vf.value],
                            label=f"{who}: published slope {a.value:g} ± {a.sigma:.2g} m/s², time, final speed",
                            color=colour, style="--"))
        layers.append(layer("points", [tp.value], [vf.value], label="", color=colour, marker="s"))
    return FigureSpec(
        "head-on-speeds", "Speeds of the two balls after a head-on collision (§VI then §II)",
        "time after the impact (s)", "speed of the centre (m/s)", tuple(layers), (0.0, t_end), None,
        caption=f"Derby & Fuller 1999; μ, s and e fitted (s = {quantiles(h.s)[1]:.2f}, "
                f"e = {quantiles(h.e)[1]:.3f})",
        reading=(
            "The speed of each ball's centre after the impact: solid, §VI's impact then §II's sliding until the ball "
            "rolls, with its 95 % band; dashed, the published final speed (square, at the published sliding time) "
            "and the published acceleration extended back to the impact. The object ball's dashed line falls in its "
            "band; the cue ball's starts below zero (the data put it moving backwards just after a head-on hit) and "
            "ends 0.15 m/s under the prediction."),
        legend="below")


_SHORT = {"mu_common": "cue acceleration (one μ)", "cue_sliding_time": "cue sliding time",
          "target_sliding_time": "object sliding time", "cue_final_speed": "cue final speed",
          "target_final_speed": "object final speed (fitted)", "e_vs_modern": "e against today's",
          "momentum_before": "momentum before", "momentum_after": "momentum after",
          "kinetic_energy_loss": "energy lost", "impact_momentum": "momentum in the impact (data)"}


def _figure_verdicts(comps: dict[str, Comparison], diffs: dict[str, tuple[float, float]],
                     exp: Experiment) -> FigureSpec:
    ids = [m.computed for m in exp.measured if comps[m.computed].measured]
    layers = []
    labels = []
    seen: set[str] = set()
    for i, q in enumerate(ids):
        c = comps[q]
        assert c.measured is not None and c.predicted is not None and c.interval is not None
        y = len(ids) - 1 - i
        d = diffs[q]
        rel = [x / abs(c.measured) for x in (d[0], c.predicted - c.measured, d[1])]
        colour = {"consistent": "C2", "inconsistent": "C3"}.get(c.verdict, "0.5")
        label = "" if c.verdict in seen else c.verdict
        seen.add(c.verdict)
        layers.append(layer("line", [rel[0], rel[2]], [y, y], color=colour))
        layers.append(layer("points", [rel[1]], [y], label=label, color=colour))
        labels.append(_SHORT.get(q, q))
    layers.append(layer("line", [0.0, 0.0], [-0.6, len(ids) - 0.4], label="prediction = measurement", color="0.3",
                        style=":"))
    return FigureSpec(
        "head-on-verdicts", "Each published scalar against §VI then §II",
        "(predicted − measured)/measured, with its 95 % interval", "",
        tuple(layers), None, (-0.6, len(ids) - 0.4), yticklabels=tuple(reversed(labels)),
        reading=(
            "For each published number, how far the prediction of Résal's mechanics lies from it, as a fraction of "
            "it, with the 95 % interval of the difference (the prediction's and the measurement's uncertainties "
            "both counted): a bar that crosses the dotted zero line is consistent. Only the object ball's sliding "
            "time and the momentum before do; the object ball's final speed sits on it by construction (e was "
            "fitted to it)."),
        legend="below")
