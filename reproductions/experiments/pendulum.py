"""Kind ``pendulum``: two bodies hung as pendulums, one striking the other at rest (§I n°5, eqs (8)).

Coriolis's cue-and-ball experiment. The measured ratios V1/V0 and V1′/V0 are the data; ε, ε′ are fitted
to them. The paper's derived values (the combination 24/5, ε′ = 4/15 = 0,27) are only compared.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import Experiment, Node
from ..fit.estimators.lsq import FitResult, fit_direct_impact
from ..mechanics import impact, reference
from ..series import check_pendulum_trials
from .base import (
    Computed,
    FigureSpec,
    Reproduction,
    fit_rows,
    identifiability_report,
    layer,
    modern_rows,
    read_series,
    rows_for,
)

QUANTITIES = ("eq_b_vs_integration", "eq7_vs_integration", "eq8_vs_integration", "n_equations", "combination",
              "momentum_balance", "epsp_given_eps", "eps_given_epsp", "swapped_struck_ratio", "translation_kept",
              "momentum_vs_integration", "law6_vs_integration", "max_rank", "speed_range",
              "mass_ratio")
COST = 0.3  # CPU seconds of a run with its figures, about: the process pool starts the longest first
MODERN = ("e_tip", "m_ball/m_cue")


@dataclass(frozen=True)
class Body:
    name: str
    mass: float


@dataclass(frozen=True)
class Params:
    striker: Body
    struck: Body
    ratio: float  # measured V1/V0 of the striking body
    ratio_p: float  # measured V1′/V0 of the struck body
    V0_max: float
    sigma: float | None  # assumed standard deviation of each measured ratio
    sigma_note: str
    eps_paper: float  # the paper's assumption on ε (striking body) in n°5
    epsp_premise: float  # the premise as worded (the ball keeps its shape) applied to the ball M′
    series: Path | None  # a user's CSV of trials: V0, V1, V1p [, M, Mp]


def _body(n: Node) -> Body:
    b = Body(n.string("name"), n.number("mass", "a mass in kg", lo=0.0, lo_open=True))
    n.done()
    return b


def parse(node: Node, base: Path) -> Params:
    striker = _body(node.child("striker", "a mapping with name and mass"))
    struck = _body(node.child("struck", "a mapping with name and mass"))
    m = node.child("measured", "a mapping with V1_over_V0, V1p_over_V0, V0_max")
    ratio = m.number("V1_over_V0", "a velocity ratio", lo=-1.0, hi=1.0)
    ratio_p = m.number("V1p_over_V0", "a velocity ratio", lo=0.0, lo_open=True)
    v0max = m.number("V0_max", "a speed in m/s", lo=0.0, lo_open=True)
    sigma = m.number("sigma", "a standard deviation of the ratios", lo=0.0, lo_open=True) if m.has("sigma") else None
    sigma_note = m.string("sigma_note") if sigma is not None else ""
    series = None
    if m.has("series_csv"):
        series = base / m.string("series_csv")
    m.done()
    a = node.child("assumptions", "a mapping with eps_paper and epsp_premise")
    eps_paper = a.number("eps_paper", "a coefficient", lo=0.0, hi=1.0)
    epsp_premise = a.number("epsp_premise", "a coefficient", lo=0.0, hi=1.0)
    a.done()
    node.done()
    params = Params(striker, struck, ratio, ratio_p, v0max, sigma, sigma_note, eps_paper, epsp_premise, series)
    if series is not None:
        _trials(params)  # a bad file stops the run before any work
    return params


def _trials(p: Params) -> tuple[np.ndarray, ...]:
    """(M, M′, V0, V1, V1′) of every trial: the user's series, or the paper's ratios as one trial at V0 = 1."""
    if p.series is None:
        one = np.ones(1)
        return (p.striker.mass * one, p.struck.mass * one, one, p.ratio * one, p.ratio_p * one)
    s = read_series(p.series, ("V0", "V1", "V1p"), optional=("M", "Mp"), min_rows=1, positive=("V0", "M", "Mp"))
    n = s["V0"].size
    M = s.get("M", np.full(n, p.striker.mass))
    Mp = s.get("Mp", np.full(n, p.struck.mass))
    check_pendulum_trials(s, M, Mp, p.sigma)  # momentum kept, bodies apart, within the noise
    return M, Mp, s["V0"], s["V1"], s["V1p"]


Arrays = tuple[np.ndarray, np.ndarray]


def _printed_eq7(M: np.ndarray, Mp: np.ndarray, V0: np.ndarray, V0p: np.ndarray, eps: np.ndarray,
                 epsp: np.ndarray) -> Arrays:
    """Eqs (7) of §I n°5 as printed, transcribed only to be compared with the integration."""
    den = Mp * (1 + eps) + M * (1 + epsp)
    return V0 - 2 * Mp * (V0 - V0p) / den, V0p + 2 * M * (V0 - V0p) / den


def _printed_eq8(M: np.ndarray, Mp: np.ndarray, V0: np.ndarray, eps: np.ndarray, epsp: np.ndarray) -> Arrays:
    """Eqs (8) of §I n°5 as printed (struck body at rest), transcribed only to be compared."""
    den = Mp * (1 + eps) + M * (1 + epsp)
    return V0 * (1 - 2 * Mp / den), 2 * M * V0 / den


def formula_checks(seed: int, n: int = 16) -> dict[str, float]:
    """Largest discrepancy, relative to the approach speed, between each printed formula of n°5 and a direct
    integration of the two-phase contact (``reference``) at the Newton e that law (6) implies, over n
    random scenes (struck body at rest for eq. (8))."""
    rng = np.random.default_rng(seed)
    M, Mp = rng.uniform(0.1, 5.0, (2, n))
    V0 = rng.uniform(0.5, 3.0, n)
    V0p = V0 - rng.uniform(0.2, 3.0, n)
    eps, epsp = rng.uniform(0.0, 0.9, (2, n))
    e = impact.newton_restitution(M, Mp, eps, epsp)
    ode = reference.integrate_direct_impact(M, Mp, V0, V0p, e)
    scale = np.abs(V0 - V0p)
    p1, p1p = _printed_eq7(M, Mp, V0, V0p, eps, epsp)
    # (b): V0 + V1 − (V0′ + V1′) = ε(V0 − V1) − ε′(V0′ − V1′), evaluated on the integrated outcome
    b = (V0 + ode.V1 - V0p - ode.V1p) - (eps * (V0 - ode.V1) - epsp * (V0p - ode.V1p))
    ode0 = reference.integrate_direct_impact(M, Mp, V0, 0.0, impact.newton_restitution(M, Mp, eps, epsp))
    q1, q1p = _printed_eq8(M, Mp, V0, eps, epsp)
    # momentum, M V1 + M′V1′ = M V0 + M′V0′, i.e. (a): M′(V0′ − V1′) = M(V1 − V0), on the integrated outcome
    a = (Mp * (V0p - ode.V1p) - M * (ode.V1 - V0)) / ((M + Mp) * scale)
    # law (6) reduced to the direct impact (J = 0), on the integrated outcome, relative to the vis viva
    law6 = (M * (V0**2 - ode.V1**2) + Mp * (V0p**2 - ode.V1p**2)
            - eps * M * (V0 - ode.V1) ** 2 - epsp * Mp * (V0p - ode.V1p) ** 2) / (M * V0**2 + Mp * V0p**2)
    return {
        "momentum_vs_integration": float(np.max(np.abs(a))),
        "law6_vs_integration": float(np.max(np.abs(law6))),
        "eq_b_vs_integration": float(np.max(np.abs(b) / scale)),
        "eq7_vs_integration": float(max(np.max(np.abs(p1 - ode.V1) / scale), np.max(np.abs(p1p - ode.V1p) / scale))),
        "eq8_vs_integration": float(max(np.max(np.abs(q1 - ode0.V1) / V0), np.max(np.abs(q1p - ode0.V1p) / V0))),
    }


def translation_check(seed: int, n: int = 64) -> float:
    """Largest |ΔΩ| R / |ΔV| of rigid bodies of random shape (random inertia tensors) struck along the line
    through their centre of gravity (§I n°5: no moment, the bodies keep translating); an impulse a tenth of the
    size off that line is the contrast (order 0.1 and more)."""
    rng = np.random.default_rng(seed + 1)
    worst = 0.0
    for _ in range(n):
        A = rng.normal(size=(3, 3))
        inertia = A @ A.T + 0.1 * np.eye(3)
        d = rng.normal(size=3)  # centre of gravity → contact, the normal along it
        P = rng.uniform(0.1, 2.0) * d / np.linalg.norm(d)
        dV, dW = impact.rigid_impulse_response(1.0, inertia, d, P)
        worst = max(worst, float(np.linalg.norm(dW) * np.linalg.norm(d) / np.linalg.norm(dV)))
    return worst


def max_rank(seed: int, n: int = 64) -> float:
    """The largest number of independent equations in (ε, ε′) that eqs (8) give, over random masses and
    outcomes that keep momentum (generated by eqs (8) themselves at random ε, ε′): the rank of their Jacobian."""
    rng = np.random.default_rng(seed + 2)
    worst = 0
    for _ in range(n):
        M, Mp = rng.uniform(0.1, 5.0, 2)
        eps, epsp = rng.uniform(0.0, 1.0, 2)
        h = 1e-6

        def ratios(e: float, ep: float, M: float = M, Mp: float = Mp) -> np.ndarray:
            out = impact.direct_impact(M, Mp, 1.0, 0.0, eps=e, epsp=ep)
            return np.array([float(out.V1), float(out.V1p)])

        jac = np.column_stack([(ratios(eps + h, epsp) - ratios(eps - h, epsp)) / (2 * h),
                               (ratios(eps, epsp + h) - ratios(eps, epsp - h)) / (2 * h)])
        sv = np.linalg.svd(jac, compute_uv=False)
        worst = max(worst, int(np.sum(sv > 1e-6 * sv[0])))
    return float(worst)


def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    M, Mp = p.striker.mass, p.struck.mass
    mu = M / Mp
    sb, st = p.striker.name, p.struck.name
    # inverse maps of eqs (8): each measured ratio gives D = M′(1+ε) + M(1+ε′); the data give nothing else
    D_p = float(impact.denominator_from_struck_ratio(M, p.ratio_p))
    D = float(impact.denominator_from_striker_ratio(Mp, p.ratio))
    comb = D_p / Mp  # (1 + ε) + (M/M′)(1 + ε′), the paper's "1 + ε + 3(1 + ε′)"
    epsp_given_eps = (D_p - Mp * (1 + p.eps_paper)) / M - 1.0
    eps_given_epsp = (D_p - M * (1 + p.epsp_premise)) / Mp - 1.0
    swapped = impact.direct_impact(M, Mp, 1.0, 0.0, eps=epsp_given_eps, epsp=p.eps_paper)
    momentum = (M * p.ratio + Mp * p.ratio_p - M) / M

    trials = _trials(p)
    fit: FitResult = fit_direct_impact(*trials, sigma=p.sigma)

    def why_swapped(printed: float) -> str:
        return (f"§VII (footnote of n°14) gives the ball ε = 0 and the cue ε′ = 0,27, the reverse of n°5's reading "
                f"({sb} {p.eps_paper:g}, {st} {epsp_given_eps:.4f}); with that assignment eq. (8) predicts "
                f"V1′ = {float(swapped.V1p):.4f} V0 where Coriolis measured {printed:g} V0, so the swapped pair "
                f"is not a solution of the data")

    checks = formula_checks(exp.seed)
    how = "largest |printed − integrated| / approach speed over 16 random scenes (two-phase contact ODE)"
    computed = {k: Computed(v, how) for k, v in checks.items()}
    computed["momentum_vs_integration"] = Computed(
        checks["momentum_vs_integration"], "largest |M′(V0′ − V1′) − M(V1 − V0)| / ((M + M′)(V0 − V0′)) over 16 "
                                           "random scenes integrated (two-phase contact ODE)")
    computed["law6_vs_integration"] = Computed(
        checks["law6_vs_integration"], "largest |M(V0² − V1²) + M′(V0′² − V1′²) − εM(V0 − V1)² − ε′M′(V0′ − V1′)²| / "
                                       "initial vis viva over 16 random scenes integrated at Newton's e of (7)")
    computed |= {
        "n_equations": Computed(
            abs(D - D_p) / D_p,
            f"relative difference of D = M′(1 + ε) + M(1 + ε′) by the first and by the second of eqs (8): one "
            f"result, D/M′ = {comb:.6g}, as the ratios keep momentum (row momentum_balance)",
            lambda printed: f"the two eqs (8) give D/M′ = {D / Mp:.6g} and {comb:.6g}: not one result but two, "
                            "and no (ε, ε′) satisfies both; the measured ratios do not keep momentum "
                            f"(imbalance {momentum:.3g} of M V0)"),
        "combination": Computed(comb, f"2(M/M′)/(V1′/V0) from the second of eqs (8); the first gives "
                                      f"{D / Mp:.12g}, the same because the data conserve momentum"),
        "momentum_balance": Computed(momentum, "(M V1 + M′ V1′ − M V0)/(M V0) of the measured ratios"),
        "epsp_given_eps": Computed(epsp_given_eps, f"eq. (8) with ε = {p.eps_paper:g} for the {sb}"),
        "translation_kept": Computed(translation_check(exp.seed),
                                     "largest |ΔΩ|·|lever| / |ΔV| of 64 rigid bodies of random inertia struck along "
                                     "the line through their centre of gravity"),
        "max_rank": Computed(max_rank(exp.seed), "largest rank of the Jacobian of eqs (8) in (ε, ε′) over 64 random "
                                                 "masses and coefficients (singular values above 1e-6 of the first)",
                             lambda printed: "eqs (8) depend on (ε, ε′) only through D = M′(1 + ε) + M(1 + ε′), and "
                                             "data that keep momentum make the two equations one: a single "
                                             "experiment never gives two distinct equations (two mass ratios would)"),
        "speed_range": Computed(None, "a measurement: the range of Coriolis's impact speeds"),
        "mass_ratio": Computed(None, "a measurement: M′/M, an input (params.struck, params.striker)"),
        "eps_given_epsp": Computed(
            eps_given_epsp,
            f"n°5 justifies ε = 0 by a ball keeping its shape, but in n°5's notation ε belongs to the striking "
            f"body M, the {sb}; applied to the {st} (ε′ = {p.epsp_premise:g}) the premise gives ε = "
            f"{eps_given_epsp:.4f} for the {sb}. The data allow every pair on ε + {mu:g}ε′ = {comb - 1 - mu:.4f}",
            lambda printed: f"a slip of the original: ε is the striking {sb}'s coefficient (n°3), but the premise "
                            f"(a ball keeps its shape) concerns the {st}'s ε′; with ε′ = {p.epsp_premise:g} the data "
                            f"give the {sb} ε = {eps_given_epsp:.4f} (corrected value), not {printed:g}"),
        "swapped_struck_ratio": Computed(float(swapped.V1p), "eq. (8) with the coefficients swapped as in §VII",
                                         why_swapped),
    }
    labels = {"eps": f"ε ({sb})", "epsp": f"ε′ ({st})"}
    note = p.sigma_note if p.sigma is not None else ""
    fits = fit_rows(fit, "trials", labels, "least squares on eqs (8), bounds [0, 1]", note)
    e_data = p.ratio_p - p.ratio
    modern = modern_rows(exp.modern, {
        "e_tip": (e_data, "Newton's e = (V1′ − V1)/V0 of Coriolis's cue–ball data"),
        "m_ball/m_cue": (Mp / M, "mass ratio of Coriolis's experiment"),
    })
    data = "measured ratios" if p.series is None else f"series: {p.series.name}"
    figure = _figure(p, fit, comb, mu, epsp_given_eps, eps_given_epsp)
    return Reproduction(exp, rows_for(exp, computed), tuple(fits), (figure,), modern,
                        data_note="" if p.series is None else data,
                        identifiability=(identifiability_report(fit, "trials", labels, data),))


def _figure(p: Params, fit: FitResult, comb: float, mu: float, paper_epsp: float, premise_eps: float) -> FigureSpec:
    """The solution set of Coriolis's data in the (ε, ε′) plane (§I n°5), with the readings of the paper."""
    c = comb - 1.0 - mu  # ε + μ ε′ = c
    eps = np.linspace(0.0, 1.0, 201)
    line = (c - eps) / mu
    inside = (line >= 0) & (line <= 1)
    layers = [layer("line", eps[inside], line[inside], label=f"data: ε + {mu:g}ε′ = {c:.4f}", color="C0")]
    comb_rows = fit.combinations
    banded = bool(comb_rows) and comb_rows[0].stderr is not None
    if banded:
        lo, hi = comb_rows[0].ci95
        layers.append(layer("band", eps, np.clip((lo - eps) / mu, 0, 1), np.clip((hi - eps) / mu, 0, 1),
                            label="95 % band (assumed σ)", color="C0"))
    layers += [
        layer("points", [p.eps_paper], [paper_epsp], label=f"n°5 reading: ε = {p.eps_paper:g} ⇒ ε′ = {paper_epsp:.4f}",
              color="C3", marker="o"),
        layer("points", [premise_eps], [p.epsp_premise],
              label=f"premise on the ball: ε′ = {p.epsp_premise:g} ⇒ ε = {premise_eps:.4f}", color="C2", marker="s"),
        layer("points", [paper_epsp], [p.eps_paper], label="§VII's assignment (swapped): off the line",
              color="C1", marker="x"),
    ]
    return FigureSpec("pendulum", "Coriolis's pendulum: the pairs (ε, ε′) the data allow",
                      f"ε of the striking body ({p.striker.name})", f"ε′ of the struck body ({p.struck.name})",
                      tuple(layers), (0.0, 1.0), (0.0, 0.5),
                      f"One equation for two unknowns: every point of the segment reproduces $V_1$ = {p.ratio:.4g} "
                      f"$V_0$ and $V′_1$ = {p.ratio_p:.4g} $V_0$.",
                      reading=(
                          f"The pairs of Résal's coefficients, ε of the {p.striker.name} and ε′ of the "
                          f"{p.struck.name}, that reproduce Coriolis's two measured speeds: they all lie on the line "
                          f"ε + {mu:g}ε′ = {c:.4f}, so the data fix only this combination"
                          + (" (the band allows for an assumed reading error)" if banded else "")
                          + f". On it lie n°5's reading (ε = {p.eps_paper:g}, red) and the premise that the "
                          f"{p.struck.name} keeps its shape (ε′ = {p.epsp_premise:g}, green); §VII swaps the two "
                          "coefficients and falls off the line (cross)."))
