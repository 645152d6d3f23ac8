"""Coverage of the 95 % intervals that ``resal fit`` reports, over many seeds, for each noise model it handles.

A reported 95 % interval must cover the value that generated the data in 92–98 % of seeded synthetic series (the
band is ±3 binomial standard errors at 1000 seeds, ±2.4 at 600). The series are small, as an experimenter's are
(8–12 trials), because that is where a normal quantile in place of Student's t, or a noise model that ignores how
the scatter grows with speed, loses coverage. Seeds are fixed, so the counts are the same on every machine (an
interval end within rounding of the true value would be needed to move one).
"""

from __future__ import annotations

import numpy as np
import pytest

from reproductions.fit.estimators.lsq import fit_direct_impact
from reproductions.fit.estimators.trials import Noise, bounded_interval, fit_ratio, fit_ratio_both, select_law
from reproductions.fit.kinds.pendulum import fit_pendulum
from reproductions.fit.kinds.rebound import fit_rebounds
from reproductions.fit.run import FitOptions
from reproductions.mechanics import impact

BAND = (0.92, 0.98)
E_TRUE = 0.8


def _speeds(rng: np.random.Generator, n: int) -> np.ndarray:
    return rng.uniform(0.5, 4.0, n)


def _cover(ci: tuple[float, float], value: float) -> bool:
    return ci[0] <= value <= ci[1]


# noise: how the synthetic outcome scatters; model: what the fit is told
SPEED_CASES = {
    "constant, auto": (lambda rng, x: 0.03 * rng.standard_normal(x.size), 0.0, Noise.AUTO, None),
    "proportional, auto": (lambda rng, x: 0.03 * x * rng.standard_normal(x.size), 0.0, Noise.AUTO, None),
    "proportional, told": (lambda rng, x: 0.03 * x * rng.standard_normal(x.size), 0.0, Noise.PROPORTIONAL, None),
    "V0 noisy too": (lambda rng, x: 0.03 * rng.standard_normal(x.size), 0.03, Noise.AUTO, None),
    "sigma given": (lambda rng, x: 0.03 * rng.standard_normal(x.size), 0.0, Noise.GIVEN, 0.03),
}


@pytest.mark.parametrize("case", sorted(SPEED_CASES))
def test_rebound_speed_intervals_cover(case: str) -> None:
    noise, v0_noise, model, sigma = SPEED_CASES[case]
    hits = 0
    seeds = 1000
    for seed in range(seeds):
        rng = np.random.default_rng(seed)
        x = _speeds(rng, 8)
        y = E_TRUE * x + noise(rng, x)
        xm = x + v0_noise * rng.standard_normal(x.size)
        hits += _cover(fit_ratio(xm, y, model, sigma).ci95, E_TRUE)
    assert BAND[0] <= hits / seeds <= BAND[1], f"{case}: {hits / seeds:.3f}"


def test_a_constant_model_told_of_proportional_noise_would_not_cover() -> None:
    """The reason for the noise models: with scatter ∝ speed over a wide speed range, the constant model's interval
    is too narrow, so auto must not pick it (the coverage tests above), and the check can fail."""
    hits = 0
    for seed in range(600):
        rng = np.random.default_rng(seed)
        x = rng.uniform(0.2, 6.0, 8)
        y = E_TRUE * x * (1 + 0.05 * rng.standard_normal(8))
        hits += _cover(fit_ratio(x, y, Noise.CONSTANT).ci95, E_TRUE)
    assert hits / 600 < BAND[0] - 0.005


@pytest.mark.parametrize("sigma_mm, unit", [(2.0, "mm"), (None, "mm"), (0.002, "m")])
def test_drop_height_intervals_cover_through_the_command(tmp_path, sigma_mm, unit) -> None:
    """Drop heights in the header's unit, σ in that same unit (it was once applied in metres to speeds)."""
    hits = 0
    seeds = 600
    scale = 1000.0 if unit == "mm" else 1.0
    e = 0.9
    for seed in range(seeds):
        rng = np.random.default_rng(10_000 + seed)
        h0 = rng.uniform(0.2, 1.0, 8)
        h1 = e**2 * h0 + 0.002 * rng.standard_normal(8)
        f = tmp_path / "drops.csv"
        f.write_text(f"h0_{unit},h1_{unit}\n" + "".join(f"{a * scale!r},{b * scale!r}\n"
                                                        for a, b in zip(h0.tolist(), h1.tolist(), strict=True)))
        out = fit_rebounds("drop", f, FitOptions(sigma=sigma_mm, resamples=0))
        est = {r["id"]: r for r in out.summary["fits"]}
        hits += _cover(tuple(est["e"]["ci95"]), e)
        assert (est["eps"]["ci95"][0] <= impact.eps_from_newton(e) <= est["eps"]["ci95"][1]) == \
            _cover(tuple(est["e"]["ci95"]), e)  # ε's interval is e's, mapped
    assert BAND[0] <= hits / seeds <= BAND[1], f"σ = {sigma_mm} {unit}: {hits / seeds:.3f}"


def test_the_speed_law_test_keeps_its_level_and_finds_hans_law() -> None:
    """With a constant e the constant is rejected about as often as the level says (5 %); with Han's (2005)
    e(v) = 0.39 + 0.257 v − 0.044 v² and 2 % scatter over 0.5–3.5 m/s it is rejected nearly always."""
    false, found = 0, 0
    seeds = 600
    for seed in range(seeds):
        rng = np.random.default_rng(seed)
        v = np.linspace(0.5, 3.5, 10)
        y0 = E_TRUE * v + 0.03 * rng.standard_normal(10)
        fr = fit_ratio(v, y0)
        false += select_law(v, y0 / v, np.asarray(fr.weights))[0].order > 0
        e = 0.39 + 0.257 * v - 0.044 * v**2
        y1 = e * v * (1 + 0.02 * rng.standard_normal(10))
        fr = fit_ratio(v, y1)
        found += select_law(v, y1 / v, np.asarray(fr.weights))[0].order > 0
    assert 0.02 <= false / seeds <= 0.08, false / seeds
    assert found / seeds >= 0.95, found / seeds


@pytest.mark.parametrize("sigma", [None, 0.005])
def test_pendulum_intervals_cover(sigma) -> None:
    """ε and ε′ from two mass ratios (so both are identified), 10 trials, noise 0.005 m/s on V1 and V1′."""
    hits = np.zeros(2)
    seeds = 400
    M = np.repeat([0.6, 0.2], 5)
    Mp = np.full(10, 0.2)
    for seed in range(seeds):
        rng = np.random.default_rng(seed)
        V0 = rng.uniform(0.5, 2.0, 10)
        r = impact.direct_impact(M, Mp, V0, 0.0, eps=0.1, epsp=0.3)
        fit = fit_direct_impact(M, Mp, V0, r.V1 + 0.005 * rng.standard_normal(10),
                                r.V1p + 0.005 * rng.standard_normal(10), sigma)
        hits += [_cover(fit.estimate(n).ci95, v) for n, v in (("eps", 0.1), ("epsp", 0.3))]
    cov = hits / seeds
    assert np.all((BAND[0] <= cov) & (cov <= BAND[1])), cov


@pytest.mark.parametrize("sigma_mm", [None, 0.5])
def test_pendulum_heights_intervals_cover(tmp_path, sigma_mm) -> None:
    """Release and rise heights (mm), σ on each height given in mm or estimated; one mass ratio sends the striker
    back (its direction is then taken from momentum). The heights' noise is carried to the speeds by dV/dh = g/V."""
    g = 9.80665
    M = np.repeat([0.6, 0.2], 5)
    Mp = np.repeat([0.2, 0.6], 5)
    hits = np.zeros(2)
    seeds = 400
    for seed in range(seeds):
        rng = np.random.default_rng(50_000 + seed)
        h0 = rng.uniform(0.1, 0.3, 10)
        r = impact.direct_impact(M, Mp, np.sqrt(2 * g * h0), 0.0, eps=0.1, epsp=0.3)
        noisy = [h + 0.0005 * rng.standard_normal(10) for h in (h0, r.V1**2 / (2 * g), r.V1p**2 / (2 * g))]
        f = tmp_path / "heights.csv"
        f.write_text("h0_mm,h1_mm,h1p_mm,M,Mp\n" + "".join(
            ",".join(repr(float(v)) for v in row) + "\n"
            for row in zip(*(1e3 * np.abs(h) for h in noisy), M, Mp, strict=True)))
        out = fit_pendulum("pendulum", f, FitOptions(sigma=sigma_mm, resamples=0))
        est = {x["id"]: x for x in out.summary["fits"]}
        hits += [_cover(tuple(est[k]["ci95"]), v) for k, v in (("pendulum.eps", 0.1), ("pendulum.epsp", 0.3))]
        assert sum(t["striker_back"] for t in out.summary["per_trial"]) == 5
    cov = hits / seeds
    assert np.all((BAND[0] <= cov) & (cov <= BAND[1])), cov


# ---- errors in both variables: the impact speed V0 measured with a known σ_in ------------------------------------
SIGMA_IN = 0.175  # m/s: 5 % of the impact speeds' spread (0.5–4 m/s)
SIGMA_OUT = 0.03  # m/s on |V1|


def _both(rng: np.random.Generator, n: int, sigma_in: float = SIGMA_IN) -> tuple[np.ndarray, np.ndarray]:
    V0 = _speeds(rng, n)
    return V0 + sigma_in * rng.standard_normal(n), E_TRUE * V0 + SIGMA_OUT * rng.standard_normal(n)


@pytest.mark.parametrize("sigma_out", [SIGMA_OUT, None], ids=["sigma-given", "sigma-estimated"])
def test_errors_in_both_intervals_cover(sigma_out) -> None:
    """8 trials, V0 noisy with σ_in known: the effective-variance fit's bounded profile interval covers e (measured:
    94.6 % with σ given, 94.5 % with σ estimated by moments, 1000 seeds)."""
    hits = 0
    seeds = 1000
    for seed in range(seeds):
        x, y = _both(np.random.default_rng(seed), 8)
        hits += _cover(bounded_interval(fit_ratio_both(x, y, SIGMA_IN, sigma_out)).ci95, E_TRUE)
    assert BAND[0] <= hits / seeds <= BAND[1], f"{sigma_out}: {hits / seeds:.3f}"


def test_ignoring_the_impact_noise_covers_worse() -> None:
    """The old fit, told σ on |V1| only, takes V0 as exact: its interval is too narrow (measured: 32 % against 95 %,
    σ_in at 5 % of the speeds' spread). Estimating the scale absorbs V0's scatter into it, but not the attenuation
    bias c·σ_in²/E[V0²], which grows against a shrinking interval: with 40 trials and σ_in at 10 % of the spread the
    old fit covers 84 %, the errors-in-both fit 94 % (600 seeds)."""
    told, both = 0, 0
    for seed in range(600):
        x, y = _both(np.random.default_rng(seed), 8)
        told += _cover(bounded_interval(fit_ratio(x, y, Noise.GIVEN, SIGMA_OUT)).ci95, E_TRUE)
        both += _cover(bounded_interval(fit_ratio_both(x, y, SIGMA_IN, SIGMA_OUT)).ci95, E_TRUE)
    assert told / 600 < 0.5 and BAND[0] <= both / 600 <= BAND[1], (told / 600, both / 600)
    old, new = 0, 0
    for seed in range(600):
        x, y = _both(np.random.default_rng(seed), 40, 2 * SIGMA_IN)
        old += _cover(bounded_interval(fit_ratio(x, y, Noise.CONSTANT)).ci95, E_TRUE)
        new += _cover(bounded_interval(fit_ratio_both(x, y, 2 * SIGMA_IN)).ci95, E_TRUE)
    assert old / 600 < BAND[0] - 0.03 and BAND[0] <= new / 600 <= BAND[1], (old / 600, new / 600)
