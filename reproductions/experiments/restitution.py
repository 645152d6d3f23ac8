"""Kind ``restitution``: published regressions and means of billiard-ball impacts (Sudo & Shibata 2002) against §I
n°5 (the law of ε, eq. (9)) and §VI n°13 (two balls on the cloth).

§I eq. (9): a ball striking an immovable mass leaves at −V1/V0 = (1 − ε)/(1 + ε), so a measured restitution e gives
ε = (1 − e)/(1 + e); for two equal balls with ε = ε′ (§VI n°13: « on peut admettre que les coefficients ε, ε′ sont
égaux »), eq. (7) gives Newton's e = (1 − ε)/(1 + ε) exactly (``impact.newton_restitution``).

Separation angle. For smooth equal balls (f = 0) with ε = ε′, the object ball leaves along the line of centres with
v cos ψ (1 + e)/2 and the cue ball keeps v sin ψ across it and v cos ψ (1 − e)/2 along it, so the angle between the
two directions is θ = 90° − atan[(1 − e)/(2 tan ψ)] (``theta_smooth``; checked against ``two_spheres(f = 0)``).
With friction, θ comes from §VI's ``two_spheres(on_cloth=True)``, the cue ball rolling naturally into the impact.
The published mean over shots depends on how the shots were spread, which the article does not give: the mean is
computed over each spread of the config's ``shots`` (the impact parameter b = 2R sin ψ uniform, i.e. u = sin ψ
uniform, or the cut angle ψ uniform, over a range of ψ), by Gauss–Legendre, and the row is not-checkable: a choice
of ours, the spread, would decide it. The rounding of a published number with no published error (half its last
printed digit) is a rounding bound, not a measurement error, and every row that rests on one says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..config import Experiment, Node
from ..mechanics import impact, spheres
from .base import Comparison, FigureSpec, Reproduction, TableSpec, layer, measurement_rows, modern_rows
from .headon import Published, judge, quantiles, read_published

QUANTITIES = ("eps_cushion_low", "eps_cushion_all", "eps_constant", "eps_ball_ball", "contact_time",
              "separation_mean", "transverse_momentum")
COST = 0.55  # CPU seconds of a run with its figures, about: the process pool starts the longest first
MODERN = ("e_c", "e_c(v)", "e_bb", "mu_bb")
REQUIRED = ("ball_mass", "ball_diameter", "cushion_restitution_below_1.8_mps", "cushion_restitution_all_speeds",
            "cushion_contact_time", "ball_ball_restitution_head_on", "separation_angle_mean",
            "transverse_momentum_deficit")
MAX_NODES = 2000
MAX_DRAWS = 20_000


SPREADS = ("impact_parameter", "cut_angle")
MAX_SPREADS = 10


@dataclass(frozen=True)
class Spread:
    """A spread of shots: the impact parameter b = 2R sin ψ uniform (every cut equally likely across the ball's
    width) or the cut angle ψ uniform, over ψ from ``lo_deg`` to ``hi_deg``."""

    kind: str
    lo_deg: float
    hi_deg: float

    @property
    def label(self) -> str:
        what = "impact parameter" if self.kind == "impact_parameter" else "cut angle"
        return f"{what} uniform over ψ {self.lo_deg:g}–{self.hi_deg:g}°"


@dataclass(frozen=True)
class Params:
    data: Path
    published: tuple[Published, ...]
    k: float
    g: float
    split_speed: float  # the low-speed regression's upper speed (m/s)
    paper_cushion_ratio: float  # Coriolis's −V1/V0 = 0,55 of the cushion (§I n°5), a measurement the paper quotes
    paper_marble_height_ratio: float  # the ball on marble rises to 2/3 of its height (§I n°5)
    f_range: tuple[float, float]  # ball-ball friction for the separation angle: from smooth to today's highest
    f_typical: float
    nodes: int  # Gauss–Legendre nodes of the average over shots
    draws: int
    cushion_law: tuple[float, float, float]  # today's e(v) = a + b v + c v² of the cushion (Han 2005), for the figure
    cushion_law_vmax: float
    spreads: tuple[Spread, ...] = ()  # the spreads of shots the mean separation angle is computed over

    def get(self, name: str) -> Published:
        return next(p for p in self.published if p.name == name)


def parse(node: Node, base: Path) -> Params:
    data = base / node.string("data")
    published = read_published(data, REQUIRED)
    k = node.number("k", "k of the moment of inertia M R²/k", lo=0.0, lo_open=True)
    g = node.number("g", "the acceleration of gravity (m/s²)", lo=0.0, lo_open=True)
    split = node.number("split_speed", "a speed in m/s", lo=0.0, lo_open=True)
    ratio = node.number("paper_cushion_ratio", "a velocity ratio in (0, 1)", lo=0.0, hi=1.0, lo_open=True,
                        hi_open=True)
    marble = node.number("paper_marble_height_ratio", "a height ratio in (0, 1)", lo=0.0, hi=1.0, lo_open=True,
                         hi_open=True)
    fr = node.number_list("f_range", "two friction coefficients [low, high]")
    if len(fr) != 2 or not 0.0 <= fr[0] <= fr[1] <= 1.0:
        raise node.fail(f"'{node.path}.f_range' must be [low, high] with 0 ≤ low ≤ high ≤ 1, got {list(fr)}",
                        node._mapping()["f_range"])
    f_typ = node.number("f_typical", "a friction coefficient within f_range", lo=fr[0], hi=fr[1])
    nodes = node.integer("nodes", "Gauss–Legendre nodes", lo=20, hi=MAX_NODES)
    draws = node.integer("draws", "Monte Carlo draws", lo=100, hi=MAX_DRAWS)
    law = node.number_list("cushion_law", "coefficients a, b, c of e(v) = a + b v + c v²")
    if len(law) != 3:
        raise node.fail(f"'{node.path}.cushion_law' must have exactly three coefficients a, b, c")
    vmax = node.number("cushion_law_vmax", "a speed in m/s", lo=0.0, lo_open=True)
    spreads = []
    for sp in node.children("shots"):
        kind = sp.string("spread", choices=SPREADS)
        psi = sp.number_list("psi_deg", "two cut angles [low, high] in degrees")
        if len(psi) != 2 or not 0.0 <= psi[0] < psi[1] <= 90.0:
            raise sp.fail(f"'{sp.path}.psi_deg' must be [low, high] with 0 ≤ low < high ≤ 90, got {list(psi)}",
                          sp._mapping()["psi_deg"])
        sp.done()
        spreads.append(Spread(kind, psi[0], psi[1]))
    if not 1 <= len(spreads) <= MAX_SPREADS:
        raise node.fail(f"'{node.path}.shots' must list 1 to {MAX_SPREADS} spreads of shots, got {len(spreads)}")
    node.done()
    return Params(data, tuple(published.values()), k, g, split, ratio, marble, (fr[0], fr[1]), f_typ, nodes, draws,
                  (law[0], law[1], law[2]), vmax, tuple(spreads))


def eps_of(e: object) -> np.ndarray:
    """ε = (1 − e)/(1 + e): the inverse of §I eq. (9)."""
    return impact.eps_from_newton(np.asarray(e, dtype=float))


def theta_smooth(psi: object, e: object) -> np.ndarray:
    """Separation angle (degrees) of smooth equal balls with ε = ε′ (module docstring), ψ in radians."""
    psi = np.asarray(psi, dtype=float)
    return 90.0 - np.degrees(np.arctan((1 - np.asarray(e, dtype=float)) / (2 * np.tan(psi))))


def theta_spheres(psi: object, e: object, f: object, R: float, M: float, k: float) -> np.ndarray:
    """Separation angle (degrees) right after the §VI impact on the cloth (``two_spheres``), the cue ball rolling
    naturally at unit speed into a ball at rest; ψ (radians) is the angle of the line of centres to the motion."""
    psi, e, f = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (psi, e, f)))
    vx, vy = np.cos(psi), -np.sin(psi)  # in the paper's frame: Ox along the line of centres
    z = np.zeros_like(vx)
    v0 = np.stack([vx, vy, z], -1)
    w0 = np.stack([-vy / R, vx / R, z], -1)  # natural roll: no slip on the cloth
    eps = eps_of(e)
    imp = spheres.two_spheres(M, M, R, R, k, k, v0, w0, np.zeros_like(v0), np.zeros_like(v0), f=f, eps=eps, epsp=eps,
                              on_cloth=True)
    a = np.arctan2(imp.v1[..., 1], imp.v1[..., 0])
    b = np.arctan2(imp.v1p[..., 1], imp.v1p[..., 0])
    return np.degrees(b - a)


@lru_cache(maxsize=4)
def _gauss(nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on [−1, 1]: Newton's method on the Legendre polynomial from the classical
    guess cos(π(i − 1/4)/(n + 1/2)), by its three-term recurrence (no eigenvalue problem, which a threaded BLAS
    makes costly); every node converges quadratically, to 1e-15 in a few steps."""
    n = nodes
    x = np.cos(np.pi * (np.arange(1, n + 1) - 0.25) / (n + 0.5))
    for _ in range(100):
        p0, p1 = np.ones_like(x), x
        for j in range(2, n + 1):
            p0, p1 = p1, ((2 * j - 1) * x * p1 - (j - 1) * p0) / j
        dp = n * (x * p1 - p0) / (x * x - 1)
        step = p1 / dp
        x = x - step
        if float(np.max(np.abs(step))) < 1e-15:
            break
    p0, p1 = np.ones_like(x), x
    for j in range(2, n + 1):
        p0, p1 = p1, ((2 * j - 1) * x * p1 - (j - 1) * p0) / j
    dp = n * (x * p1 - p0) / (x * x - 1)
    w = 2 / ((1 - x * x) * dp * dp)
    return x[::-1].copy(), w[::-1].copy()


def mean_over_b(values_of_psi: object, nodes: int) -> float:
    """⟨θ⟩ with the impact parameter uniform (u = sin ψ uniform on [0, 1)): Gauss–Legendre in u; ``values_of_psi``
    maps ψ (radians) to θ."""
    x, w = _gauss(nodes)
    u = 0.5 * (x + 1)
    return float(0.5 * np.sum(w * values_of_psi(np.arcsin(u))))  # type: ignore[operator]


def spread_nodes(spread: Spread, nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """The cut angles ψ (radians) and weights (summing to 1) of the mean over a spread of shots: Gauss–Legendre in
    u = sin ψ (impact parameter uniform) or in ψ (cut angle uniform) over the spread's range."""
    x, w = _gauss(nodes)
    a, b = math.radians(spread.lo_deg), math.radians(spread.hi_deg)
    t = 0.5 * (x + 1)
    if spread.kind == "impact_parameter":
        psi = np.arcsin(math.sin(a) + (math.sin(b) - math.sin(a)) * t)
    else:
        psi = a + (b - a) * t
    return psi, 0.5 * w


def spread_means(p: Params, e: float, fs: np.ndarray) -> np.ndarray:
    """⟨θ⟩ of §VI over each spread of shots (rows) at each f of ``fs`` (columns), the cue ball rolling."""
    R, M = p.get("ball_diameter").value / 2, p.get("ball_mass").value
    out = np.empty((len(p.spreads), fs.size))
    for i, sp in enumerate(p.spreads):
        psi, w = spread_nodes(sp, p.nodes)
        out[i] = theta_spheres(psi[None, :], e, fs[:, None], R, M, p.k) @ w
    return out


def _b_means(p: Params, e: float, fs: np.ndarray) -> np.ndarray:
    """⟨θ⟩_b for each f, one batched §VI call over the nodes × frictions."""
    R, M = p.get("ball_diameter").value / 2, p.get("ball_mass").value
    x, w = _gauss(p.nodes)
    psi = np.arcsin(0.5 * (x + 1))
    th = theta_spheres(psi[None, :], e, fs[:, None], R, M, p.k)
    return 0.5 * th @ w


def _bisect_e(p: Params, target: float) -> float:
    """The e whose smooth-ball ⟨θ⟩_b is ``target`` (θ rises with e), by bisection to 1e-6."""
    lo, hi = 0.0, 1.0
    while hi - lo > 1e-7:
        mid = 0.5 * (lo + hi)
        if mean_over_b(lambda s, e=mid: theta_smooth(s, e), p.nodes) < target:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _psi_from(p: Params, e: float, fs: np.ndarray, target: float) -> np.ndarray:
    """For each f, the smallest ψ (degrees) from which θ(ψ) of §VI reaches ``target`` (θ rises with ψ), by one
    vectorised bisection to 1e-6 rad."""
    R, M = p.get("ball_diameter").value / 2, p.get("ball_mass").value
    lo, hi = np.full(fs.shape, math.radians(0.5)), np.full(fs.shape, math.radians(89.5))
    for _ in range(60):
        if float(np.max(hi - lo)) < 1e-6:
            break
        mid = 0.5 * (lo + hi)
        up = theta_spheres(mid, e, fs, R, M, p.k) < target
        lo, hi = np.where(up, mid, lo), np.where(up, hi, mid)
    return np.degrees(0.5 * (lo + hi))


@dataclass(frozen=True)
class Separation:
    e: float
    fs: np.ndarray
    means: np.ndarray  # ⟨θ⟩_b of §VI at each f of fs
    smooth: float  # ⟨θ⟩_b of smooth balls (closed form)
    e_needed: float
    psi_smooth: float
    psi_typical: float
    table_fs: np.ndarray  # the frictions of ``table``'s columns: 0 (smooth), then f_range and f_typical
    table: np.ndarray  # ⟨θ⟩ over each spread of shots (rows) at each f of table_fs


def separation(p: Params) -> Separation:
    e = p.get("ball_ball_restitution_head_on").value
    target = p.get("separation_angle_mean").value
    fs = np.array([p.f_range[0], p.f_typical, p.f_range[1]])
    means = _b_means(p, e, fs)
    smooth = mean_over_b(lambda s: theta_smooth(s, e), p.nodes)
    psi = _psi_from(p, e, np.array([0.0, p.f_typical]), target)
    table_fs = np.array(sorted({0.0, *fs.tolist()}))
    return Separation(e, fs, means, smooth, _bisect_e(p, target), float(psi[0]), float(psi[1]), table_fs,
                      spread_means(p, e, table_fs))


def _rounding_words(half: float, what: str = "e to ± half its last printed digit") -> str:
    return f"± {half:.1g}, a rounding bound ({what}), not a measurement error: none is published"


def separation_words(p: Params, sep: Separation) -> str:
    """The mean separation angle of §VI over each spread of shots, in words: the prediction as a function of the
    spread, which the article does not give."""
    cols = ", ".join("smooth" if f == 0 else f"f = {f:g}" for f in sep.table_fs)
    per = "; ".join(f"{sp.label}: " + ", ".join(f"{v:.2f}°" for v in row) for sp, row in zip(p.spreads, sep.table,
                                                                                         strict=True))
    return f"⟨θ⟩ ({cols}): {per}"


def comparisons(p: Params, sep: Separation, seed: int) -> dict[str, Comparison]:
    rng = np.random.default_rng(seed)
    n = p.draws
    low, allsp = p.get("cushion_restitution_below_1.8_mps"), p.get("cushion_restitution_all_speeds")
    bb = p.get("ball_ball_restitution_head_on")
    e_low, e_all = low.draw(rng, n), allsp.draw(rng, n)
    # Coriolis's « différait peu de 0,55 »: its last digit, ± 0.005, uniform
    ratio = p.paper_cushion_ratio + 0.01 * rng.uniform(-0.5, 0.5, n)
    eps_paper = eps_of(ratio)
    pq = quantiles(eps_paper)
    half_paper = float(eps_of(p.paper_cushion_ratio - 0.005) - eps_of(p.paper_cushion_ratio))
    out: dict[str, Comparison] = {}
    for key, pub, what in (("eps_cushion_low", low, f"below {p.split_speed:g} m/s"),
                           ("eps_cushion_all", allsp, "over all speeds")):
        draws = eps_of(e_low if pub is low else e_all)
        verdict, diff = judge(eps_paper, draws)
        eps_m = float(eps_of(pub.value))
        half = float(eps_of(pub.value - pub.digit / 2) - eps_m)
        gap = abs(pq[1] - eps_m)
        out[key] = Comparison(
            eps_m, f"e = {pub.text} → ε = {eps_m:.4f} (eq. (9))", _rounding_words(half),
            pq[1], (pq[0], pq[2]), verdict,
            f"the paper's ε of the cushion, from Coriolis's −V1/V0 = {p.paper_cushion_ratio:g} (§I n°5, printed "
            f"ε = 0,29); today's regression {what}; paper − today's {_iv(diff)} (95 % of the draws). Both sides carry "
            f"only rounding bounds (today's e to ± {pub.digit / 2:g}, Coriolis's ratio to ± 0.005, ε ± "
            f"{half_paper:.4f}: « différait peu de 0,55 »), not measurement errors: the gap, {gap:.3f}, is "
            f"{gap / (half + half_paper):.0f} times their sum")
    d = e_low - e_all
    verdict, diff = judge(np.zeros(n), d)
    W = 0.5
    e_above = (allsp.value - (1 - W) * low.value) / W
    gap = low.value - allsp.value
    out["eps_constant"] = Comparison(
        gap, f"e {low.text} (below {p.split_speed:g} m/s) − {allsp.text} (all) = {gap:.3f}",
        _rounding_words(float(np.std(d)), "both e to ± half their last printed digit; σ shown"), 0.0, (0.0, 0.0),
        verdict,
        f"a constant ε (§I n°5: Coriolis's ratio « différait peu de 0,55 » up to 7 m/s) gives one ratio −V1/V0 at "
        f"every speed, so both regressions would be equal; 0 − measured {_iv(diff)} (95 % of the draws). No standard "
        f"error of either regression is published, so this rests on rounding bounds: agreement at 95 % would need "
        f"each regression's standard error to reach {gap / (1.96 * math.sqrt(2)):.3f} (equal, independent). A "
        f"regression through the origin is the v²-weighted mean of e, so above {p.split_speed:g} m/s e ≤ {allsp.text} "
        f"and ε ≥ {float(eps_of(allsp.value)):.3f}, {float(eps_of(allsp.value) / eps_of(low.value)):.2f} × the "
        f"low-speed ε; with half of Σv² above, e = {e_above:.3f} there (ε = {float(eps_of(e_above)):.3f})")
    eps_bb = float(eps_of(bb.value))
    eps_marble = float(impact.eps_from_height_ratio(p.paper_marble_height_ratio))
    bb_draws = eps_of(bb.draw(rng, n))
    inside = bool(np.all(bb_draws <= eps_marble))
    half_bb = float(eps_of(bb.value - bb.digit / 2) - eps_bb)
    out["eps_ball_ball"] = Comparison(
        eps_bb, f"e = {bb.text} → ε = ε′ = {eps_bb:.4f}", _rounding_words(half_bb),
        None, (0.0, eps_marble), "consistent" if inside else "inconsistent",
        f"§VI n°13 calls the balls' ε « très petite » and undetermined; very small taken as below the smallest ε the "
        f"paper puts a number on, the ball on marble (√(2/3) → ε = {eps_marble:.3f}); eq. (7) with ε = ε′ gives back "
        f"e = {float(impact.newton_restitution(1.0, 1.0, eps_bb, eps_bb)):.4f}. The measured ε carries only a "
        f"rounding bound, ± {half_bb:.1g}, not a measurement error: the verdict rests on that threshold, ε lying "
        f"{eps_marble - eps_bb:.3f} below it, {(eps_marble - eps_bb) / half_bb:.0f} times the bound")
    tau = p.get("cushion_contact_time")
    v = p.split_speed
    out["contact_time"] = Comparison(
        tau.value, f"{tau.text} {tau.unit}", tau.how_uncertain, None, None, "not-checkable",
        f"a definition: §I's impact is instantaneous (a jump of the velocities), so it predicts no duration. Its "
        f"premise holds for the forces: the weight's impulse over the contact, g τ, is "
        f"{p.g * tau.value / (v * (1 + low.value)):.3f} of the cushion's normal impulse at {v:g} m/s; the centre "
        f"travels v τ = {1000 * v * tau.value:.1f} mm = {v * tau.value / (p.get('ball_diameter').value / 2):.2f} R "
        "meanwhile")
    th = p.get("separation_angle_mean")
    lo_th, hi_th = float(sep.table.min()), float(sep.table.max())
    where = "inside" if lo_th <= th.value <= hi_th else "outside"
    out["separation_mean"] = Comparison(
        th.value, f"{th.text}°", _rounding_words(th.digit / 2, "half its last printed digit; no spread published"),
        None, None, "not-checkable",
        f"a modelling choice: the article gives neither its shots' cut angles nor how they were spread, and the mean "
        f"of §VI (e = {sep.e:g}, the cue ball rolling; friction only closes the angle) turns on that spread: "
        f"{separation_words(p, sep)}. The published mean lies {where} their range, {lo_th:.2f}–{hi_th:.2f}°: with "
        f"every cut equally likely across the ball's width it needs e = {sep.e_needed:.3f} (smooth balls), and "
        f"θ(ψ) reaches it only for cuts ψ ≥ {sep.psi_smooth:.1f}° (smooth) or ≥ {sep.psi_typical:.1f}° "
        f"(f = {sep.fs[1]:g})")
    tm = p.get("transverse_momentum_deficit")
    out["transverse_momentum"] = Comparison(
        tm.value, f"{tm.text} (trend only)", "none published", 0.0, None, "not-checkable",
        "a definition: the pair's momentum across the line of centres is kept exactly by §V and §VI whatever ε and f "
        "(their impulses are internal), so nothing of the paper's can fail here; the published fraction is a trend "
        "whose instant and body are not defined")
    return out


def _iv(iv: tuple[float, float]) -> str:
    return f"[{iv[0]:+.4f}, {iv[1]:+.4f}]"


def run(exp: Experiment) -> Reproduction:
    p: Params = exp.params
    sep = separation(p)
    comps = comparisons(p, sep, exp.seed)
    low, allsp = p.get("cushion_restitution_below_1.8_mps"), p.get("cushion_restitution_all_speeds")
    modern = modern_rows(exp.modern, {
        "e_c": (float(eps_of(low.value)), "ε of today's cushion below 1.8 m/s"),
        "e_c(v)": (float(eps_of(allsp.value)), "ε of today's cushion over all speeds"),
        "e_bb": (float(eps_of(p.get("ball_ball_restitution_head_on").value)), "ε = ε′ of the balls"),
        "mu_bb": (p.f_typical, "f of the separation angle's prediction"),
    })
    figures = (_figure_separation(p, sep), _figure_cushion(p))
    table = TableSpec(
        "separation-by-spread", "Mean separation angle of §VI against the spread of shots (degrees)",
        ("spread of shots", *("smooth" if f == 0 else f"f = {f:g}" for f in sep.table_fs)),
        tuple((sp.label, *(round(float(v), 2) for v in row)) for sp, row in zip(p.spreads, sep.table, strict=True)),
        f"§VI on the cloth, e = {sep.e:g} (Sudo & Shibata's head-on restitution), the cue ball rolling into the "
        f"impact; published mean {p.get('separation_angle_mean').text}°. The article does not give its spread of "
        "shots.")
    return Reproduction(exp, (), (), figures, modern, tables=(table,), measurements=measurement_rows(exp, comps))


def _figure_separation(p: Params, sep: Separation) -> FigureSpec:
    R, M = p.get("ball_diameter").value / 2, p.get("ball_mass").value
    deg = np.linspace(1.0, 89.0, 177)
    psi = np.radians(deg)
    th = p.get("separation_angle_mean").value
    fric = theta_spheres(psi, sep.e, sep.fs[1], R, M, p.k)
    i_typ = int(np.argmin(np.abs(sep.table_fs - sep.fs[1])))
    layers = [
        layer("line", [0.0, 90.0], [90.0, 90.0], label="e = 1, smooth: 90°", color="0.5", style="--"),
        layer("line", deg, theta_smooth(psi, sep.e), label=f"smooth balls, e = {sep.e:g}", color="C0"),
        layer("line", deg, fric, label=f"§VI, cue ball rolling, e = {sep.e:g}, f = {sep.fs[1]:g}", color="C1"),
        layer("line", [0.0, 90.0], [th, th], label=f"published mean {th:g}°", color="C3"),
    ]
    styles = (":", "-.", "--", "-")
    for k, (sp, row) in enumerate(zip(p.spreads, sep.table, strict=True)):
        style = styles[k % len(styles)]
        xs = [sp.lo_deg, sp.hi_deg]
        layers.append(layer("line", xs, [float(row[0])] * 2, color="C0", style=style,
                            label=f"means, {sp.label}"))
        layers.append(layer("line", xs, [float(row[i_typ])] * 2, color="C1", style=style))
    lo_th, hi_th = float(sep.table.min()), float(sep.table.max())
    return FigureSpec(
        "separation-angle", "Separation angle of the two balls after an oblique impact", "cut angle ψ (degrees)",
        "separation angle θ (degrees)", tuple(layers), (0.0, 90.0), (40.0, 92.0),
        caption=f"Sudo & Shibata 2002: e = {sep.e:g}, mean {th:g}°, spread of shots not published; segments: "
                "means over a spread (blue smooth, orange with f)",
        reading=(
            "The angle between the cue ball's and the object ball's directions right after the impact, against the "
            "cut angle: 90° for smooth elastic balls, less with e < 1 (blue) and less again with friction (orange); "
            "both fall to 0 for a full hit (ψ → 0). Each pair of horizontal segments is the two curves' mean over one "
            "spread of shots, drawn over the cut angles it covers; the article gives no spread, and the means run "
            f"from {lo_th:.1f}° to {hi_th:.1f}° around the published mean {th:g}° (red), which the curves reach only "
            f"for ψ ≥ {sep.psi_smooth:.0f}° and ψ ≥ {sep.psi_typical:.0f}°."),
        legend="below")


def _figure_cushion(p: Params) -> FigureSpec:
    low, allsp = p.get("cushion_restitution_below_1.8_mps"), p.get("cushion_restitution_all_speeds")
    e_low, e_all = float(eps_of(low.value)), float(eps_of(allsp.value))
    eps_paper = float(eps_of(p.paper_cushion_ratio))
    a, b, c = p.cushion_law
    v = np.linspace(0.2, p.cushion_law_vmax, 60)
    han = eps_of(np.clip(a + b * v + c * v * v, 0.0, 1.0))
    top = 0.45
    layers = (
        layer("line", [0.0, p.split_speed], [e_low, e_low], label=f"Sudo & Shibata, below {p.split_speed:g} m/s: "
                                                                  f"ε = {e_low:.3f}", color="C0"),
        layer("band", [p.split_speed, 7.0], [e_all, e_all], [top, top],
              label=f"what their all-speed value needs above {p.split_speed:g} m/s: ε ≥ {e_all:.3f}", color="C0"),
        layer("line", [0.0, 7.0], [eps_paper, eps_paper], label=f"Résal/Coriolis: ε = {eps_paper:.2f} up to 7 m/s",
              color="C3", style="--"),
        layer("line", v, han, label="Han 2005 law e(v), as ε (today's, for context)", color="0.4", style=":"),
    )
    return FigureSpec(
        "cushion-eps", "Résal's ε of the cushion against the impact speed", "impact speed (m/s)", "ε = (1 − e)/(1 + e)",
        layers, (0.0, 7.0), (0.0, top),
        reading=(
            "Résal's ε of a ball on the cushion, from measured rebound ratios through eq. (9), against the impact "
            f"speed. The paper takes one value, {eps_paper:.2f}, at every speed (dashed); today's cushion gives "
            f"{e_low:.3f} at low speed and, for the all-speed regression to come out at {allsp.text}, at least "
            f"{e_all:.3f} above {p.split_speed:g} m/s (shaded): ε is not a constant, and today's is lower."),
        legend="below")
