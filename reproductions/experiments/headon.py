"""Kind ``head_on``: one head-on collision on the cloth, filmed (Derby & Fuller 1999), against §VI n°13 then §II n°7.

The cue ball, with topspin s V/R before the impact (s = 1: natural roll), strikes the object ball at rest head on.
The impact is §VI (``spheres.two_spheres(on_cloth=True)``, ε = ε′ = (1 − e)/(1 + e), §I eq. (9)): the vertical
slip R ω0 of the topspin makes the ball–ball friction f act even head on (it takes topspin from the cue ball and
gives the object ball backspin). Then each ball slides on the cloth until it rolls (§II, ``cloth.slide``): its centre
changes speed at μg, against the slip u = v − Rω, for t = |u|/((1 + k) μ g), and it ends at v − u/(1 + k).

What is fitted and what is tested. μ is the weighted mean of the two published sliding accelerations (§II gives
both balls the same |acceleration| μg). The cue ball's spin before the impact and the ball–ball f are not published,
and one collision cannot fix both, so every row the mechanics grade is computed under two readings: (A) the spin s
inferred from the cue ball's slip after the impact, |u1| = (1 + k) a_c t_c (§II: the slip changes (1 + k) times as
fast as the centre's speed), e from the object ball's final speed, f drawn from today's range; (B) natural roll
(s = 1), e and f fitted to both final speeds (``fit_natural_roll``). A row both readings grade alike keeps that
verdict; a row the reading decides is not-checkable (« a modelling choice »), both outcomes in its note; a row that
cannot fail (M V, momentum kept by any impact) is not-checkable (« a definition »). The uncertainties are a seeded
Monte Carlo: the published standard errors as normal errors, every other number uniform over ± half its last
printed digit (a rounding bound, not a measurement error, and the rows say so), f from its prior in reading A; a
prediction's interval is its 2.5–97.5 % quantiles, and a reading is consistent when the 95 % interval of
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
COST = 1.05  # CPU seconds of a run with its figures, about: the process pool starts the longest first
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
    def rounding_only(self) -> bool:
        """No error is published: the only uncertainty is the rounding of the last printed digit."""
        return self.se is None

    @property
    def how_uncertain(self) -> str:
        if self.se is not None:
            return f"± {self.se:g} (published standard error)"
        return (f"± {self.digit / 2:g}, a rounding bound (half its last printed digit), not a measurement error: none "
                f"is published (drawn uniform, σ = {self.sigma:.2g})")

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


def rolling_speeds(b: Ball, V: Any, s: Any, e: Any, f: Any) -> tuple[np.ndarray, np.ndarray]:
    """The cue ball's and the object ball's speeds once they roll, §VI then §II: v − (v − Rω)/(1 + k) (the rolling
    speed does not depend on μ)."""
    out = after_impact(b, V, s, e, f)
    return (out["v1"] - (out["v1"] - out["Rw1"]) / (1 + b.k), out["v1p"] - (out["v1p"] - out["Rw1p"]) / (1 + b.k))


def fit_natural_roll(b: Ball, V: Any, v_cf: Any, v_tf: Any) -> tuple[np.ndarray, np.ndarray]:
    """Per draw: e and f such that §VI then §II, the cue ball rolling naturally into the impact (s = 1), give both
    published final speeds; Newton's method on the two equations, its Jacobian by finite differences (the final
    speeds are smooth in e and f while the vertical slip lasts the whole impact). Raises ``ValueError`` when a draw
    does not converge or ends outside 0 ≤ e ≤ 1, f ≥ 0: the reading then has no solution, which the caller must
    not hide."""
    V, v_cf, v_tf = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (V, v_cf, v_tf)))
    one = np.ones_like(V)
    e, f = np.full_like(V, 0.9), np.full_like(V, 0.05)
    h = 1e-7

    def residual(e_: np.ndarray, f_: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        c, t = rolling_speeds(b, V, one, e_, f_)
        return c - v_cf, t - v_tf

    for _ in range(40):
        r1, r2 = residual(e, f)
        a1, a2 = residual(e + h, f)
        c1, c2 = residual(e, f + h)
        j11, j21, j12, j22 = (a1 - r1) / h, (a2 - r2) / h, (c1 - r1) / h, (c2 - r2) / h
        det = j11 * j22 - j12 * j21
        de, df = (j22 * r1 - j12 * r2) / det, (j11 * r2 - j21 * r1) / det
        e, f = e - de, f - df
        if float(np.max(np.abs(de))) < 1e-11 and float(np.max(np.abs(df))) < 1e-11:
            break
    r1, r2 = residual(e, f)
    if not (np.all(np.isfinite(e)) and np.all(np.isfinite(f)) and float(np.max(np.abs(r1))) < 1e-9
            and float(np.max(np.abs(r2))) < 1e-9 and np.all((e >= 0) & (e <= 1) & (f >= 0))):
        raise ValueError("natural roll: no e and f give both final speeds")
    return e, f


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
    # reading B: the cue ball rolling naturally into the impact (s = 1), e and f fitted to both final speeds
    # (None when no e, f give both)
    e_nat: np.ndarray | None = None
    f_nat: np.ndarray | None = None
    pred_nat: dict[str, np.ndarray] | None = None


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
    try:
        e_nat, f_nat = fit_natural_roll(ball, V, meas["cue_final_speed"], meas["target_final_speed"])
    except ValueError:
        return HeadOn(s, e, f, mug, pred, meas, mug0, float(w.sum() ** -0.5), chi2)
    pred_nat = predict(ball, V, 1.0, e_nat, f_nat, mug)
    return HeadOn(s, e, f, mug, pred, meas, mug0, float(w.sum() ** -0.5), chi2, e_nat, f_nat, pred_nat)


@dataclass(frozen=True)
class Outcome:
    """One reading's outcome for one row: its verdict ('consistent', 'inconsistent', 'fitted' or 'restated': no test
    of its own), the prediction's median and 95 % interval, the 95 % interval of (predicted − measured), and its
    words."""

    verdict: str
    mid: float
    interval: tuple[float, float]
    diff: tuple[float, float]
    text: str


def _outcome(pred: Any, meas: Any, unit: str, why: str = "", fitted: bool = False, restated: str = "") -> Outcome:
    lo, mid, hi = quantiles(pred)
    verdict, diff = judge(pred, meas)
    where = f"{mid:.3f} [{lo:.3f}, {hi:.3f}]{(' ' + unit) if unit and unit != '1' else ''}"
    if fitted:
        return Outcome("fitted", mid, (lo, hi), diff, f"{where}, fitted{(' (' + why + ')') if why else ''}: it "
                                                      "tests nothing")
    if restated:
        return Outcome("restated", mid, (lo, hi), diff, f"{where}, {restated}: no test of its own")
    return Outcome(verdict, mid, (lo, hi), diff, f"{where}{(' (' + why + ')') if why else ''}, predicted − measured "
                                                 f"{_fmt_interval(diff)} (95 %): {verdict}")


def _combine(a: Outcome, b: Outcome | None) -> str:
    """The row's verdict: the readings' common verdict when both test it the same way (or both fitted it), else
    not-checkable: a choice of ours (which reading) would decide it."""
    if b is not None and a.verdict == b.verdict and a.verdict in ("consistent", "inconsistent", "fitted"):
        return a.verdict
    return "not-checkable"


def readings_text(p: Params, h: HeadOn) -> tuple[str, str]:
    """The two readings of what the article leaves open (the cue ball's spin before the impact, f), in words with
    their fitted values."""
    ac, tc = p.get("cue_sliding_acceleration"), p.get("cue_sliding_time")
    s_q, e_q = quantiles(h.s), quantiles(h.e)
    a = (f"(A) the cue ball's spin s = {s_q[1]:.2f} [{s_q[0]:.2f}, {s_q[2]:.2f}] inferred from its published "
         f"{ac.text} {ac.unit} × {tc.text} s, f drawn from today's {p.f_prior[0]:g}–{p.f_prior[1]:g}, e = "
         f"{e_q[1]:.3f} fitted to the object ball's final speed")
    if h.e_nat is None or h.f_nat is None:
        return a, "(B) natural roll into the impact (s = 1): no e and f give both final speeds"
    en, fn = quantiles(h.e_nat), quantiles(h.f_nat)
    b = (f"(B) natural roll into the impact (s = 1), e = {en[1]:.3f} [{en[0]:.3f}, {en[2]:.3f}] and f = {fn[1]:.3f} "
         f"[{fn[0]:.3f}, {fn[2]:.3f}] fitted to both final speeds (their intervals from rounding bounds alone)")
    return a, b


def comparisons(p: Params, h: HeadOn, rng: np.random.Generator
                ) -> tuple[dict[str, Comparison], dict[str, dict[str, Outcome]]]:
    """The rows' comparisons, and for each row graded against §VI then §II the outcome of each reading (``A``,
    ``B``), which the verdicts' figure draws. The cue ball's spin before the impact and f are not published, and
    one collision cannot fix both: reading A infers the spin from the cue ball's sliding acceleration and time and
    draws f from today's range, reading B takes natural roll and fits e and f to both final speeds. A row whose
    verdict the reading decides is not-checkable (« a modelling choice »), with both outcomes in its note."""
    out: dict[str, Comparison] = {}
    outcomes: dict[str, dict[str, Outcome]] = {}
    tag_a, tag_b = readings_text(p, h)
    choice = "a modelling choice: the cue ball's spin before the impact and f are not published, and the reading "\
             "decides this row"

    def rounding(pub: Published, tests: bool) -> str:
        if not (pub.rounding_only and tests):
            return ""
        return (f"; the published {pub.text} {pub.unit} carries only a rounding bound, ± {pub.digit / 2:g} {pub.unit}, "
                "not a measurement error: the intervals that decide are the predictions'")

    def graded(q: str, a: Outcome, b: Outcome | None, extra: str = "") -> None:
        pub = p.get(q)
        outcomes[q] = {"A": a} | ({"B": b} if b is not None else {})
        verdict = _combine(a, b)
        b_text = f"{tag_b}: {b.text}" if b is not None else tag_b
        tests = any(o is not None and o.verdict in ("consistent", "inconsistent") for o in (a, b))
        both = f"{tag_a}: {a.text}; {b_text}{extra}{rounding(pub, tests)}"
        if verdict == "not-checkable":
            out[q] = Comparison(pub.value, f"{pub.text} {pub.unit}".strip(), pub.how_uncertain, None, None, verdict,
                                f"{choice}. {both}")
            return
        assert b is not None
        out[q] = Comparison(pub.value, f"{pub.text} {pub.unit}".strip(), pub.how_uncertain, a.mid, a.interval,
                            verdict, f"{verdict} under both readings (the prediction shown is A's). {both}")

    nat = h.pred_nat
    meas = h.meas

    # one cloth μ (§II): independent of the readings
    ac, at = p.get("cue_sliding_acceleration"), p.get("target_sliding_acceleration")
    verdict, diff = judge(np.abs(meas["target_sliding_acceleration"]), meas["cue_sliding_acceleration"])
    lo, mid, hi = quantiles(np.abs(meas["target_sliding_acceleration"]))
    from ..fit import distributions as dist  # only here: the χ² tail

    p_value = float(dist.chi2_sf(h.chi2, 1))
    outcomes["mu_common"] = {"": Outcome(verdict, mid, (lo, hi), diff, "")}
    out["mu_common"] = Comparison(
        ac.value, f"{ac.text} {ac.unit}", ac.how_uncertain, mid, (lo, hi), verdict,
        f"§II gives both balls the same |acceleration| μg, so the cue ball's is predicted by the object ball's "
        f"{abs(at.value):g} ± {at.sigma:.2g} (both with published standard errors); predicted − measured "
        f"{_fmt_interval(diff)} (95 %); one μ for both: χ² = {h.chi2:.1f} (1 dof), p = {p_value:.1g}; their weighted "
        f"mean μg = {h.mug0:.3f} ± {h.mug_se:.3f} m/s² (μ = {h.mug0 / p.g:.3f}) is the cloth's μ of every other row, "
        "under both readings of the cue ball's spin")

    def nat_outcome(q: str, **kw: Any) -> Outcome | None:
        return None if nat is None else _outcome(nat[q], meas[q], p.get(q).unit, **kw)

    a_t = _outcome(h.pred["cue_sliding_time"], meas["cue_sliding_time"], "s",
                   restated="the published t_c × a_c/μg (the spin was inferred from a_c t_c, and §II's slip changes "
                            "at (1 + k) μg): row mu_common restated")
    graded("cue_sliding_time", a_t, nat_outcome("cue_sliding_time"))
    graded("target_sliding_time",
           _outcome(h.pred["target_sliding_time"], meas["target_sliding_time"], "s"),
           nat_outcome("target_sliding_time"))
    graded("cue_final_speed", _outcome(h.pred["cue_final_speed"], meas["cue_final_speed"], "m/s"),
           nat_outcome("cue_final_speed", fitted=True, why="with the object ball's, by e and f"),
           "" if h.f_nat is None else
           f"; B's f lies {'above' if quantiles(h.f_nat)[0] > p.f_prior[1] else 'against'} today's "
           f"{p.f_prior[0]:g}–{p.f_prior[1]:g}")
    graded("target_final_speed",
           _outcome(h.pred["target_final_speed"], meas["target_final_speed"], "m/s", fitted=True, why="by e"),
           nat_outcome("target_final_speed", fitted=True, why="with the cue ball's, by e and f"))

    # e against today's: the e each reading needs
    e_mod = rng.uniform(p.e_modern[0], p.e_modern[1], h.e.size)
    lo_n, mid_n, hi_n = quantiles(h.pred["normal_e"])
    e_a = _outcome(h.e, e_mod, "1", why=f"the impact's ratio of normal velocities {mid_n:.3f} [{lo_n:.3f}, "
                                       f"{hi_n:.3f}]")
    e_b = None
    if nat is not None and h.e_nat is not None:
        lo_b, mid_b, hi_b = quantiles(nat["normal_e"])
        e_b = _outcome(h.e_nat, e_mod, "1", why=f"normal ratio {mid_b:.3f} [{lo_b:.3f}, {hi_b:.3f}]")
    outcomes["e_vs_modern"] = {"A": e_a} | ({"B": e_b} if e_b is not None else {})
    verdict = _combine(e_a, e_b)
    today = f"{p.e_modern[0]:g}–{p.e_modern[1]:g} (today's ball–ball e)"
    words = (f"the e the object ball's final speed needs (law (6) with ε = (1 − e)/(1 + e)) against today's range, "
             f"drawn uniformly: {tag_a}: "
             f"{e_a.text}; " + (f"{tag_b}: {e_b.text}" if e_b is not None else tag_b))
    out["e_vs_modern"] = Comparison(
        0.5 * (p.e_modern[0] + p.e_modern[1]), today, "the range, drawn uniformly",
        None if verdict == "not-checkable" else e_a.mid, None if verdict == "not-checkable" else e_a.interval,
        verdict, (f"{choice}. " if verdict == "not-checkable" else f"{verdict} under both readings (the prediction "
                                                                   "shown is A's): ") + words)

    # what the published numbers define, not what the mechanics predict
    M, V = p.get("ball_mass"), p.get("incident_speed")
    mb = p.get("momentum_before")
    out["momentum_before"] = Comparison(
        mb.value, f"{mb.text} {mb.unit}", mb.how_uncertain, None, None, "not-checkable",
        f"a definition: the momentum before is M V of the published mass and incident speed, {M.text} × {V.text} = "
        f"{M.value * V.value:.4f} {mb.unit}, the published {mb.text} to its last digit (a rounding bound); no "
        "mechanics of the paper's enters it")
    vcf, vtf = p.get("cue_final_speed"), p.get("target_final_speed")
    ma = p.get("momentum_after")
    after = M.value * (vcf.value + vtf.value)

    def readings_of(q: str, unit: str) -> str:
        a = quantiles(h.pred[q])
        s = f"(A) {a[1]:.3f} [{a[0]:.3f}, {a[2]:.3f}]{unit}"
        if nat is not None:
            b = quantiles(nat[q])
            s += f", (B) {b[1]:.3f} [{b[0]:.3f}, {b[2]:.3f}]{unit}"
        return s

    out["momentum_after"] = Comparison(
        ma.value, f"{ma.text} {ma.unit}", ma.how_uncertain, None, None, "not-checkable",
        f"a modelling choice: what the published momentum after measures is ours to guess, and its own final speeds "
        f"rule out the stated one: once both roll it is M (v_cf + v_tf) = {M.text} × ({vcf.text} + {vtf.text}) = "
        f"{after:.3f} {ma.unit}, not {ma.text}. Read as once both roll, §VI then §II give "
        f"{readings_of('momentum_after', ' ' + ma.unit)}; read as right after the impact, §I keeps M V = "
        f"{M.value * V.value:.3f} {ma.unit} whatever e and f")
    ke = p.get("kinetic_energy_loss")
    left = (vcf.value**2 + vtf.value**2) / V.value**2
    out["kinetic_energy_loss"] = Comparison(
        ke.value, f"{ke.text}", ke.how_uncertain, None, None, "not-checkable",
        f"a modelling choice: what the published loss measures is ours to guess, and its own speeds rule out the "
        f"stated one: counting translation only, or with the cue ball rolling into the impact (s ≥ 1, rolling after), "
        f"the published final speeds leave at most ({vcf.text}² + {vtf.text}²)/{V.text}² = {left:.2f} of the energy "
        f"before, a loss of {1 - left:.2f} or more, not {ke.text}. Read as once both roll, §VI then §II give a loss of "
        f"{readings_of('kinetic_energy_loss', '')}; read as at the instant after the impact, "
        f"{readings_of('kinetic_energy_loss_impact', '')}")
    # the data alone: the speeds right after the impact, from §II's kinematics, must keep momentum (§I)
    v1 = meas["cue_final_speed"] - meas["cue_sliding_acceleration"] * meas["cue_sliding_time"]
    v1p = meas["target_final_speed"] - meas["target_sliding_acceleration"] * meas["target_sliding_time"]
    ratio = (v1 + v1p) / meas["incident_speed"]
    r_mid = quantiles(ratio)[1]
    sd = float(np.std(ratio))
    _, diff = judge(np.ones_like(ratio), ratio)
    out["impact_momentum"] = Comparison(
        r_mid, f"(v1 + v1′)/V = {r_mid:.3f} from the data", f"± {sd:.3f} (propagated from the published values)",
        1.0, None, "not-checkable",
        f"a definition: an impact keeps momentum whatever e and f (§I: its impulses are internal), so the prediction "
        f"1 cannot fail and the row grades the data, not the mechanics: v1 = v_cf − a_c t_c = "
        f"{float(np.median(v1)):+.3f} m/s and v1′ = v_tf − a_t t_t = {float(np.median(v1p)):.3f} m/s by §II's uniform "
        f"acceleration give (v1 + v1′)/V = {r_mid:.3f}, 1 − it {_fmt_interval(diff, 3)} (95 %), {(1 - r_mid) / sd:.1f} "
        "σ: the published accelerations, times and final speeds do not keep momentum through the impact")
    return out, outcomes


def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    h = simulate(p, exp.seed)
    comps, outcomes = comparisons(p, h, np.random.default_rng(exp.seed + 1))
    s_q, e_q, f_q = quantiles(h.s), quantiles(h.e), quantiles(h.f)
    a, b_, c = p.friction_law
    slip = s_q[1] * p.get("incident_speed").value
    fits = [
        FitRow("design-a.mu", "μ (ball–cloth)", h.mug0 / p.g, h.mug_se / p.g,
               ((h.mug0 - 1.96 * h.mug_se) / p.g, (h.mug0 + 1.96 * h.mug_se) / p.g),
               "weighted mean of the two published sliding accelerations (§II: |a| = μg)", True,
               f"the two accelerations disagree (χ² = {h.chi2:.1f}, 1 dof): see row mu_common; both readings use it"),
        FitRow("design-a.s", "s = Rω0/V, the cue ball's topspin before the impact (reading A)", s_q[1],
               float(np.std(h.s)), (s_q[0], s_q[2]),
               "inferred per draw from the cue ball's slip after the impact, (1 + k) a_c t_c", True,
               "not published: reading A infers it from the cue ball's sliding acceleration and time; reading B "
               "takes natural roll, s = 1"),
        FitRow("design-a.e", "e (ball–ball, law (6) with ε = ε′ = (1 − e)/(1 + e)), reading A", e_q[1],
               float(np.std(h.e)), (e_q[0], e_q[2]),
               "solved per draw so that §VI then §II give the object ball's final speed", True,
               f"today's {p.e_modern[0]:g}–{p.e_modern[1]:g}: see row e_vs_modern"),
        FitRow("prior.f", "f (ball–ball), reading A", None, None, (None, None),
               "not fitted: drawn uniformly from today's range", False,
               f"one head-on collision cannot fix f with the spin; today's μ(v) at the cue ball's vertical slip Rω0 ≈ "
               f"{slip:.2f} m/s gives {a + b_ * math.exp(-c * slip):.3f}", family_range=p.f_prior),
    ]
    if h.e_nat is not None and h.f_nat is not None:
        en, fn = quantiles(h.e_nat), quantiles(h.f_nat)
        fits += [
            FitRow("natural-roll.e", "e (ball–ball), reading B: natural roll", en[1], float(np.std(h.e_nat)),
                   (en[0], en[2]), "solved per draw, with f, so that §VI then §II give both final speeds (s = 1)",
                   True, f"today's {p.e_modern[0]:g}–{p.e_modern[1]:g}: see row e_vs_modern"),
            FitRow("natural-roll.f", "f (ball–ball), reading B: natural roll", fn[1], float(np.std(h.f_nat)),
                   (fn[0], fn[2]), "solved per draw, with e, so that §VI then §II give both final speeds (s = 1)",
                   True, f"today's {p.f_prior[0]:g}–{p.f_prior[1]:g} (modern-values.csv mu_bb)"),
        ]
    e_b = "" if h.e_nat is None else f" (reading A; natural roll, B: {quantiles(h.e_nat)[1]:.3f})"
    f_b = "" if h.f_nat is None else f" (natural roll, B, fits {quantiles(h.f_nat)[1]:.3f})"
    modern = modern_rows(exp.modern, {"e_bb": (e_q[1], "e the object ball's final speed needs" + e_b),
                                      "mu_s": (h.mug0 / p.g, "μ from the two sliding accelerations"),
                                      "mu_bb": (f_q[1], "f: not fitted in reading A, today's range drawn" + f_b)})
    figures = (_figure_speeds(p, h), _figure_verdicts(outcomes, comps, exp))
    note = (f"Monte Carlo of {p.draws} draws, seed {exp.seed}: published standard errors normal, other numbers uniform "
            "over ± half their last digit (rounding bounds), f uniform over today's range in reading A")
    return Reproduction(exp, (), tuple(fits), figures, modern, data_note=note,
                        measurements=measurement_rows(exp, comps))


# ---------------------------------------------------------------------------------------------------------------
# figures


def _figure_speeds(p: Params, h: HeadOn) -> FigureSpec:
    ball = Ball(p.get("ball_mass").value, p.get("ball_diameter").value / 2, p.k, p.g)
    t_end = 0.25
    t = np.linspace(0.0, t_end, 126)
    layers = []
    z = np.zeros_like(h.s)
    gap, start = {}, {}
    for name, v, Rw, colour in (("cue", "v1", "Rw1", "C0"), ("target", "v1p", "Rw1p", "C3")):
        _, _, vx, _ = cloth.state_at(t, h.pred[v], z, z, h.pred[Rw] / ball.R, R=ball.R, k=ball.k, f=h.mug / ball.g,
                                     g=ball.g)
        lo, mid, hi = np.percentile(vx, [2.5, 50.0, 97.5], axis=0)
        layers.append(layer("band", t, lo, hi, color=colour))
        layers.append(layer("line", t, mid, color=colour))
        if h.pred_nat is not None:
            _, _, vb, _ = cloth.state_at(t, h.pred_nat[v], z, z, h.pred_nat[Rw] / ball.R, R=ball.R, k=ball.k,
                                         f=h.mug / ball.g, g=ball.g)
            layers.append(layer("line", t, np.percentile(vb, 50.0, axis=0), color=colour, style=":"))
        tp, vf, a = (p.get(f"{name}_sliding_time"), p.get(f"{name}_final_speed"),
                     p.get(f"{name}_sliding_acceleration"))
        gap[name] = quantiles(h.pred[f"{name}_final_speed"])[1] - vf.value
        # the published slope holds while the ball slides, up to the published time; extended back towards the
        # impact only as far as a speed can go: a speed below zero would not be a speed
        start[name] = max(0.0, tp.value - vf.value / a.value) if a.value > 0 else 0.0
        layers.append(layer("line", [start[name], tp.value, t_end],
                            [vf.value - a.value * (tp.value - start[name]), vf.value, vf.value], color=colour,
                            style="--"))
        layers.append(layer("points", [tp.value], [vf.value], color=colour, marker="s"))
    layers += [layer("line", label="cue ball", color="C0"), layer("line", label="object ball", color="C3"),
               layer("band", label="reading A: median, 95 % band", color="0.4"),
               layer("line", label="reading B: median", color="0.4", style=":"),
               layer("line", label="published slope, final speed", color="0.4", style="--"),
               layer("points", label="published sliding time", color="0.4", marker="s")]
    caption = f"Derby & Fuller 1999; A: s = {quantiles(h.s)[1]:.2f}, e = {quantiles(h.e)[1]:.3f}, f drawn"
    b_words = ""
    if h.e_nat is not None and h.f_nat is not None and h.pred_nat is not None:
        caption += f"\nB: s = 1, e = {quantiles(h.e_nat)[1]:.3f}, f = {quantiles(h.f_nat)[1]:.3f}"
        b_words = (f" Dotted, reading B: natural roll into the impact, e and f fitted to both final speeds; both balls "
                   f"end on their published speeds by construction, after sliding "
                   f"{quantiles(h.pred_nat['cue_sliding_time'])[1]:.3f} s and "
                   f"{quantiles(h.pred_nat['target_sliding_time'])[1]:.3f} s.")
    back = (f"the cue ball's from {start['cue']:.3f} s, where it reaches zero speed" if start["cue"] > 0 else
            "the cue ball's from the impact")
    return FigureSpec(
        "head-on-speeds", "Speeds after a head-on collision (§VI then §II), two readings",
        "time after the impact (s)", "speed of the centre (m/s)", tuple(layers), (0.0, t_end), None,
        caption=caption,
        reading=(
            "The speed of each ball's centre after the impact (blue the cue ball, red the object ball): dashed, the "
            "published final speed (square, at the published sliding time) and the published acceleration extended "
            f"back towards the impact ({back}). Solid, reading A: the cue ball's spin inferred from its published "
            "acceleration and time, f drawn from today's range, e fitted to the object ball; the cue ball ends "
            f"{gap['cue']:.2f} m/s above its published speed." + b_words + " Which ball fits is the reading's doing, "
            "not the paper's."),
        legend="below")


_SHORT = {"mu_common": "cue acceleration (one μ)", "cue_sliding_time": "cue sliding time",
          "target_sliding_time": "object sliding time", "cue_final_speed": "cue final speed",
          "target_final_speed": "object final speed", "e_vs_modern": "e against today's"}
_READING = {"": ("both readings", "0.3"), "A": ("A: spin from the cue ball's acceleration, f drawn", "C0"),
            "B": ("B: natural roll, e and f fitted to both final speeds", "C1")}


def _figure_verdicts(outcomes: dict[str, dict[str, Outcome]], comps: dict[str, Comparison],
                     exp: Experiment) -> FigureSpec:
    ids = [m.computed for m in exp.measured if m.computed in outcomes]
    layers = []
    labels = []
    seen: set[str] = set()
    offset = {"": 0.0, "A": 0.15, "B": -0.15}
    for i, q in enumerate(ids):
        y = len(ids) - 1 - i
        scale = abs(comps[q].measured or 1.0)
        for key, o in outcomes[q].items():
            name, colour = _READING[key]
            rel = [o.diff[0] / scale, 0.5 * (o.diff[0] + o.diff[1]) / scale, o.diff[1] / scale]
            yy = y + offset[key]
            fitted = o.verdict == "fitted"
            tested = o.verdict in ("consistent", "inconsistent")
            label = "" if key in seen or not tested else name  # the key shows the reading's round marker
            if tested:
                seen.add(key)
            if not fitted:
                layers.append(layer("line", [rel[0], rel[2]], [yy, yy], color=colour))
            layers.append(layer("points", [rel[1]], [yy], label=label, color=colour,
                                marker="x" if fitted else ("s" if o.verdict == "restated" else "o")))
        labels.append(_SHORT.get(q, q) + f"\n{comps[q].verdict}")
    layers.append(layer("line", [0.0, 0.0], [-0.6, len(ids) - 0.4], label="prediction = measurement", color="0.3",
                        style=":"))
    consistent = {k: [_SHORT.get(q, q) for q in ids if outcomes[q].get(k) and outcomes[q][k].verdict == "consistent"]
                  for k in ("A", "B")}
    return FigureSpec(
        "head-on-verdicts", "Each published scalar against §VI then §II, two readings",
        "(predicted − measured)/measured", "",
        tuple(layers), None, (-0.6, len(ids) - 0.4), yticklabels=tuple(reversed(labels)),
        caption="dot: median, bar: 95 % interval; cross: fitted; square: restates another row",
        reading=(
            "For each published number, how far the prediction of Résal's mechanics lies from it, as a fraction of "
            "it, with the 95 % interval of the difference (the prediction's and the measurement's uncertainties "
            "both counted; numbers without a published error carry only a rounding bound): a bar that crosses the "
            "dotted zero line is consistent; a cross sits on zero by construction (fitted); a square restates "
            "another row. Blue, reading A (the cue ball's spin inferred from its acceleration): consistent "
            f"{', '.join(consistent['A']) or 'nowhere'}; orange, reading B (natural roll, e and f fitted to both "
            f"final speeds): consistent {', '.join(consistent['B']) or 'nowhere'}. A row the reading decides is "
            "not-checkable."),
        legend="below")
