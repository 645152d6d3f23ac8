"""§IV n°11 of Résal (1883): a ball striking a cushion with friction j, with side spin.

Frame of the paper: Ox along the cushion, Oy vertical, Oz normal to the cushion; the ball keeps to the
cloth (η = 0) and touches the cushion at the height of its centre. χ, ζ the velocity of the centre
(ζ0 = −a < 0 approaching), p the rotation about Oy (side spin), n the rotation about Ox; the contact point
slips at φ = χ − pR along Ox and ψ = nR along Oy (eq. 1). Friction j Z opposes the slip; the normal
velocity is returned in the ratio ν, ζ1 = νa, with ν = (1 − ε)/(1 + ε) from §I eq. (9).

Derivation in the normal impulse π = (1/M)∫Z dt, from 0 to (1 + ν)a: dχ = −jφ/v dπ, d(pR) = kjφ/v dπ,
d(nR) = −kjψ/v dπ, so dφ = −j(1 + k)φ/v dπ and dψ = −jkψ/v dπ: ψ = ψ0 (φ/φ0)^(k/(1+k)) (eq. 6), and the slip
turns while it slows. With φ = φ0 U^(1+k), ψ = ψ0 U^k (0 ≤ U ≤ 1),

    j π(U) = ∫_U^1 u^(k−1) √(φ0² u² + ψ0²) du = H(1) − H(U),
    H(U) = ψ0 U^k / k · ₂F₁(−1/2, k/2; k/2 + 1; −(φ0 U/ψ0)²)

(an exact closed form of Résal's integral (10), which he judged impractical). The slip stops during the
impact iff j(1 + ν)a ≥ H(1) (both φ and ψ reach 0 together; the contact then needs no friction); otherwise
U1 solves H(U1) = H(1) − j(1 + ν)a, found by Newton's method on ln H (``slip.slip_decay``; H is monotone).
Then φ1, ψ1 as above and eq. (9):
χ1 = (kχ0 + p0R + φ1)/(1 + k), p1R = χ1 − φ1, n1R = ψ1.

Special cases with elementary closed forms: no rotation about Ox (ψ0 = 0, the paper's n0 = 0): the slip
keeps its direction, Δφ = −min(|φ0|, j(1 + k)(1 + ν)a) sign φ0; no slip along the cushion (φ0 = 0):
Δψ = −min(|ψ0|, jk(1 + ν)a) sign ψ0.

Résal's approximation (eq. 11): (φ0/φ)^e ≈ 1 + e (φ0 − φ)/φ0 under the square root of (10), after which
(10) integrates in closed form. The paper prints the exponent e = (1 + k)/2; the derivation gives
2/(1 + k). ``method="resal"`` uses the printed exponent, ``"resal-corrected"`` the derived one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .budget import bounded, check
from .impact import nu_from_eps
from .paths import PathCode, Regime, as_floats, batch_arrays, codes, every, maximum, pick, result
from .slip import slip_decay

__all__ = ["METHODS", "CushionImpact", "cushion_impact", "elementary_applies"]

METHODS = ("exact", "elementary", "resal", "resal-corrected", "ode")
_CODES = {"exact": PathCode.EXACT, "elementary": PathCode.ELEMENTARY, "resal": PathCode.RESAL,
          "resal-corrected": PathCode.RESAL_CORRECTED, "ode": PathCode.ODE}
_REGIMES = np.array([Regime.NO_SLIP, Regime.SLIDE, Regime.GRIP], dtype=np.int8)  # no slip, slips, slip stops
_NO_SLIP, _SLIDE, _GRIP = _REGIMES  # (numpy's int8: one scene's regime, chosen with ``pick``)
_ZERO = np.float64(0.0)


@dataclass(frozen=True)
class CushionImpact:
    """After the impact; ``regime``: SLIDE (slips throughout), GRIP (the slip stops), NO_SLIP (none at first)."""

    chi1: np.ndarray
    zeta1: np.ndarray
    p1: np.ndarray
    n1: np.ndarray
    method: str
    path: np.ndarray
    regime: np.ndarray
    label: str


def elementary_applies(chi0: ArrayLike, p0: ArrayLike, n0: ArrayLike, R: ArrayLike, j: ArrayLike) -> np.ndarray:
    """Where the slip keeps its direction and the elementary closed form is exact: n0 = 0 (no rotation about the
    cushion's direction), φ0 = χ0 − p0R = 0 (no slip along the cushion) or j = 0 (no friction)."""
    chi0, p0, n0, R, j = as_floats(chi0, p0, n0, R, j)
    return (n0 == 0) | (chi0 - p0 * R == 0) | (j == 0)


def _elementary(phi0: np.ndarray, psi0: np.ndarray, k: np.ndarray, budget: np.ndarray) -> tuple[np.ndarray, ...]:
    """One slip component only (the module docstring's special cases): it falls linearly in π until it stops,
    at the rate j(1 + k) along the cushion (ψ0 = 0) or jk across it (φ0 = 0)."""
    f1 = pick(psi0 == 0, maximum(phi0 - (1 + k) * budget, _ZERO), phi0)
    s1 = pick(phi0 == 0, maximum(psi0 - k * budget, _ZERO), psi0)
    return f1, s1


def _exact(phi0: np.ndarray, psi0: np.ndarray, k: np.ndarray, budget: np.ndarray) -> tuple[np.ndarray, ...]:
    """Slips (|φ1|, |ψ1|) after the impact, budget = j(1 + ν)a: ``slip.slip_decay`` with α = 1 + k, β = k."""
    return slip_decay(phi0, psi0, 1 + k, k, budget)


def _resal(phi0: np.ndarray, psi0: np.ndarray, k: np.ndarray, budget: np.ndarray,
           e: np.ndarray) -> tuple[np.ndarray, ...]:
    """Eq. (11): (φ0/φ)^e ≈ 1 + e(φ0 − φ)/φ0, then (10) in closed form; slips stop at 0 (φ0 > 0)."""
    r2 = (psi0 / np.where(phi0 > 0, phi0, 1.0)) ** 2
    A = 1 + r2 + e * r2  # integrand √(A + Bφ)
    B = -e * r2 / np.where(phi0 > 0, phi0, 1.0)
    lhs = (1 + k) * budget  # j(1 + k)(1 + ν)a = ∫_{φ1}^{φ0} √(A + Bφ) dφ = (2/3B)[(A + Bφ0)^(3/2) − (A + Bφ1)^(3/2)]
    # φ1 − φ0 = [(A + Bφ1) − (A + Bφ0)]/B = top^(2/3)·[(1 − x)^(2/3) − 1]/B with x = 3B·lhs/(2 top), written with
    # expm1 and log1p: (cbrt(inner)² − A)/B cancels when B is tiny (ψ0 ≪ φ0) and missed j = 0 by 3e-5 of the speeds
    # (``resal stress``'s elastic limit); B → 0 gives φ0 − lhs/√A
    with np.errstate(invalid="ignore", divide="ignore"):
        top = (A + B * phi0) ** 1.5
        x = 1.5 * B * lhs / top
        safeB = np.where(B == 0, 1.0, B)
        step = np.where(B == 0, -lhs / np.sqrt(A),
                        np.cbrt(top) ** 2 * np.expm1(np.log1p(-np.minimum(x, 1.0)) * (2.0 / 3.0)) / safeB)
        phi1 = np.where(x >= 1, 0.0, phi0 + step)
    phi1 = np.clip(np.nan_to_num(phi1, nan=0.0), 0.0, phi0)
    psi1 = psi0 * np.where(phi0 > 0, phi1 / np.where(phi0 > 0, phi0, 1.0), 0.0) ** (k / (1 + k))
    return phi1, psi1


def _ode(chi0: np.ndarray, pR0: np.ndarray, nR0: np.ndarray, k: np.ndarray, j: np.ndarray,
         pi_end: np.ndarray, rtol: float = 1e-11, solver: str = "DOP853") -> tuple[np.ndarray, ...]:
    """Integrate eqs (2) of n°11 in the normal impulse π over [0, (1 + ν)a]: dχ = −jφ/v, d(pR) = kjφ/v,
    d(nR) = −kjψ/v, until the slip v vanishes (an event), after which the contact holds without friction.
    Returns χ1, p1R, n1R; nothing of eqs (5)–(10) is used.

    The stop event is the slip projected on (sign φ0, sign ψ0), |φ| + |ψ| while both keep their signs: both reach
    zero together, so it crosses zero once, cleanly. Not on the unit vector of the initial slip: the slip turns
    towards ψ as it slows (φ/ψ ∝ (ψ/ψ0)^(1/k)), and with ψ0 ≪ |φ0| that projection weights the last of the slip by
    ψ0/|φ0| while φ = χ − pR, a difference of two states, carries an error of order rtol·|χ| (it oscillates about
    0 once φ has died, the decay rate j(1 + k)/v being stiff there): the event fired when the remaining ψ was
    |χ|·rtol·|φ0|/ψ0, and n1R kept it (1.7e-7 of the speed scale at k = 0.023, ψ0/φ0 ≈ 1e-5). At the event the
    slip is closed, ψ = 0 and χ = pR = (kχ + pR)/(1 + k): eqs (2) keep kχ + pR (the angular momentum about the
    contact), and the residual slip is the integration's error."""
    from scipy.integrate import solve_ivp

    out = np.empty((3, *chi0.shape))
    for idx in np.ndindex(chi0.shape):
        y0 = [chi0[idx], pR0[idx], nR0[idx]]
        kk, jj = k[idx], j[idx]
        scale = max(abs(y0[0] - y0[1]), abs(y0[2]))
        if jj == 0 or pi_end[idx] == 0 or scale == 0:
            out[(slice(None), *idx)] = y0
            continue
        sides = (float(np.sign(y0[0] - y0[1])), float(np.sign(y0[2])))

        def rhs(_pi: float, y: np.ndarray, kk: float = kk, jj: float = jj) -> list[float]:
            c0, c1, psi = y.tolist()  # floats: numpy's scalars cost 3× more per right-hand side
            phi = c0 - c1
            v = max(np.hypot(phi, psi), 1e-300)
            return [-jj * phi / v, kk * jj * phi / v, -kk * jj * psi / v]

        def stops(_pi: float, y: np.ndarray, sides: tuple[float, float] = sides) -> float:
            # never |slip| − tiny, which would chatter (ARCHITECTURE.md); see the docstring for the weights
            return float((y[0] - y[1]) * sides[0] + y[2] * sides[1])

        stops.terminal = True
        stops.direction = -1
        sol = solve_ivp(bounded(rhs), (0.0, pi_end[idx]), y0, method=solver, rtol=rtol, atol=1e-14 * scale,
                        events=stops)
        check(sol)
        if sol.status == 0:
            out[(slice(None), *idx)] = sol.y[:, -1]
        else:
            c0, c1, _ = sol.y_events[0][0]
            closed = (kk * c0 + c1) / (1 + kk)
            out[(slice(None), *idx)] = (closed, closed, 0.0)
    return out[0], out[1], out[2]


def cushion_impact(chi0: ArrayLike, zeta0: ArrayLike, p0: ArrayLike, n0: ArrayLike, *, R: ArrayLike,
                   k: ArrayLike, j: ArrayLike, eps: ArrayLike, method: str = "exact", rtol: float = 1e-11,
                   solver: str = "DOP853") -> CushionImpact:
    """The cushion impact of §IV by the chosen path (module docstring): ``exact`` (₂F₁ and Newton's method, every
    scene), ``elementary`` (only where ``elementary_applies``), ``resal``, ``resal-corrected``, ``ode``.
    ``registry`` chooses per scene for ``auto``."""
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    chi0, zeta0, p0, n0, R, k, j, eps = batch_arrays(chi0, zeta0, p0, n0, R, k, j, eps)
    nu = nu_from_eps(eps)
    a = -zeta0
    phi0, psi0 = chi0 - p0 * R, n0 * R
    sphi, spsi = np.sign(phi0), np.sign(psi0)
    f0, s0 = np.abs(phi0), np.abs(psi0)
    budget = j * (1 + nu) * a
    if method == "exact":
        f1, s1 = _exact(f0, s0, k, budget)
        label = "closed form (₂F₁ and Newton's method)"
    elif method == "elementary":
        if not every((n0 == 0) | (phi0 == 0) | (j == 0)):  # ``elementary_applies``, φ0 = χ0 − p0R computed
            raise ValueError("the elementary cushion form handles only n0 = 0, φ0 = χ0 − p0R = 0 or j = 0")
        f1, s1 = _elementary(f0, s0, k, budget)
        label = "elementary closed form (the slip keeps its direction)"
    elif method == "ode":
        chi1, pR1, nR1 = _ode(chi0, p0 * R, n0 * R, k, j, (1 + nu) * a, rtol, solver)
        f1, s1 = np.abs(chi1 - pR1) * (np.sign(chi1 - pR1) == sphi), np.abs(nR1) * (np.sign(nR1) == spsi)
        stopped = np.hypot(f1, s1) <= 1e-10 * np.maximum(f0, s0)  # the integration's slip-stop event fired
        f1, s1 = np.where(stopped, 0.0, f1), np.where(stopped, 0.0, s1)
        label = f"ODE in the normal impulse ({solver}, rtol {rtol:g}, slip-stop event), eqs (2) of n°11"
    else:
        e = (1 + k) / 2 if method == "resal" else 2 / (1 + k)
        f1, s1 = _resal(f0, s0, k, budget, e)
        label = ("Résal's first-order eq. (11), exponent (1 + k)/2 as printed" if method == "resal"
                 else "Résal's first-order eq. (11), exponent 2/(1 + k) as derived")
    phi1, psi1 = sphi * f1, spsi * s1
    chi1 = (k * chi0 + p0 * R + phi1) / (1 + k)  # eq. (9)
    moving = (f0 > 0) | (s0 > 0)
    regime = np.asarray(pick(moving, pick((f1 == 0) & (s1 == 0), _GRIP, _SLIDE), _NO_SLIP))  # slides, stops; none
    return result(CushionImpact, chi1=chi1, zeta1=nu * a, p1=(chi1 - phi1) / R, n1=psi1 / R, method=method,
                  path=codes(chi1.shape, _CODES[method]), regime=regime, label=label)


# ---- §IV n°11, the paper's steps checked one by one (issue 13) ---------------------------------------------
# These functions rebuild the impact from vectors (no equation of n°11 is used), so that each printed step can
# be compared with an independent computation. Frame of the paper: Ox along the cushion, Oy vertical, Oz normal
# to the cushion; the cushion is on the −z side (ζ0 < 0 approaching) and touches the ball at r = −R e_z, at the
# height of its centre; ω = (n, q, p): n about Ox, q about Oz (the normal), p about Oy (side spin).

def contact_velocity(v: ArrayLike, omega: ArrayLike, R: ArrayLike) -> np.ndarray:
    """Velocity of the ball's point touching the cushion, v + ω × r with r = −R e_z; ``v`` = (χ, η, ζ) and
    ``omega`` = (ω_x, ω_y, ω_z) = (n, p, q) along the last axis. Its x, y components are the slip (eq. 1)."""
    v, omega = np.asarray(v, dtype=float), np.asarray(omega, dtype=float)
    r = np.zeros(np.broadcast_shapes(v.shape, omega.shape))
    r[..., 2] = -np.asarray(R, dtype=float)
    return v + np.cross(omega, r)


def rigid_body_rates(v: ArrayLike, omega: ArrayLike, R: ArrayLike, k: ArrayLike,
                     j: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Rates per unit normal impulse π = (1/M)∫Z dt of the velocity and the rotation under the cushion's
    reaction alone: the normal push e_z and the Coulomb friction j opposite the slip (the x, y components of
    ``contact_velocity``), with the moment r × F about the centre and the moment of inertia MR²/k. Newton and
    Euler in vectors, the independent reference for eqs (1)-(3), (8) and the vertical push the cloth must
    hold (the premise η = 0). Returns (dv/dπ, dω/dπ), components as in ``contact_velocity``."""
    v, omega = np.broadcast_arrays(np.asarray(v, dtype=float), np.asarray(omega, dtype=float))
    R, k, j = (np.broadcast_to(np.asarray(x, dtype=float), v.shape[:-1])[..., None] for x in (R, k, j))
    slip = contact_velocity(v, omega, R[..., 0])
    slip[..., 2] = 0.0
    speed = np.linalg.norm(slip, axis=-1, keepdims=True)
    F = -j * slip / np.where(speed > 0, speed, 1.0)
    F[..., 2] = 1.0
    r = np.zeros(F.shape)
    r[..., 2] = -R[..., 0]
    return F, k / R**2 * np.cross(r, F)


def state_after_impulse(chi0: ArrayLike, p0: ArrayLike, n0: ArrayLike, impulse: ArrayLike, *, R: ArrayLike,
                        k: ArrayLike, j: ArrayLike, rtol: float = 1e-11) -> tuple[np.ndarray, ...]:
    """(χ, p, n) once the normal impulse per unit mass has reached ``impulse`` (m/s), by the integration of
    eqs (2) (``_ode``): a point inside the impact, where the paper's running φ, ζ of (8) and the integral of
    its n°11 stand (ζ − ζ0 = impulse)."""
    chi0, p0, n0, impulse, R, k, j = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (chi0, p0, n0, impulse, R, k, j)))
    chi, pR, nR = _ode(chi0, p0 * R, n0 * R, k, j, impulse, rtol)
    return chi, pR / R, nR / R


def eq11_as_printed(phi0: ArrayLike, psi0: ArrayLike, k: ArrayLike, budget: ArrayLike,
                    e: ArrayLike) -> np.ndarray:
    """φ1 from eq. (11) exactly as printed, j(1 + k)(1 + ν)a = ∫_{φ1}^{φ0} √(1 + r² − e r² (φ − φ0)) dφ with
    r = n0R/φ0 (φ0 > 0): the last term lacks the 1/φ0 of the expansion above it, so it adds a velocity to a
    pure number and the root depends on the unit of velocity (nan where there is none). No clip at zero."""
    phi0, psi0, k, budget, e = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (phi0, psi0, k, budget, e)))
    r2 = (psi0 / phi0) ** 2
    A = 1 + r2 + e * r2 * phi0  # √(A + Bφ), as printed
    B = -e * r2
    lhs = (1 + k) * budget
    with np.errstate(invalid="ignore", divide="ignore"):
        inner = (A + B * phi0) ** 1.5 - 1.5 * B * lhs
        curved = (np.where(inner >= 0, np.cbrt(inner), np.nan) ** 2 - A) / B
    return np.where(B == 0, phi0 - lhs / np.sqrt(A), curved)


def binomial_integral_is_elementary(m: float, n: float, p: float, max_den: int = 1000) -> bool:
    """Chebyshev's theorem (1853) on ∫ x^m (a + b x^n)^p dx with rational m, n, p and ab ≠ 0: it is elementary
    iff p, (m + 1)/n or (m + 1)/n + p is an integer. The integral (10) of n°11 is of this form with x = φ,
    m = 0, n = −2/(1 + k) (−(1 + k)/2 as printed), p = ½."""
    from fractions import Fraction

    m_, n_, p_ = (Fraction(x).limit_denominator(max_den) for x in (m, n, p))
    return any(x.denominator == 1 for x in (p_, (m_ + 1) / n_, (m_ + 1) / n_ + p_))
