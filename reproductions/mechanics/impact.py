"""§I n°3–5 of Résal (1883): the energy-loss law and the direct impact of two bodies.

Notation of the paper: M strikes M′ along the line of centres; V0, V1 (V0′, V1′) are the velocities of
M (M′) before and after the impact; ε, ε′ are Résal's coefficients of the vis viva of the velocities lost
(ε = 0: perfectly elastic, ε = 1: Carnot's inelastic impact). SI units; every function broadcasts over
its arguments, so a leading batch axis evaluates many scenes at once.

Derivation of eqs (7)–(9) from the premises (momentum, eq. (a), and the energy law (6) with J = 0):
write Δ = V0 − V1. Momentum gives V1′ − V0′ = (M/M′) Δ. Substituting in (6) and dividing by MΔ gives
(b): (V0 + V1) − (V0′ + V1′) = εΔ + ε′ (M/M′) Δ, i.e. 2(V0 − V0′) = Δ [1 + ε + (M/M′)(1 + ε′)], whence
Δ = 2M′(V0 − V0′) / D with D = M′(1 + ε) + M(1 + ε′): eq. (7). The code below implements that
derivation, not the printed formula; tests check it against momentum, the law (6) itself, and a direct
integration of a two-phase contact (``reference.integrate_direct_impact``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .paths import PathCode, Regime, as_floats, batch_arrays, codes, result

__all__ = [
    "DirectImpact",
    "WallImpact",
    "denominator",
    "denominator_from_striker_ratio",
    "denominator_from_struck_ratio",
    "direct_impact",
    "eps_from_height_ratio",
    "eps_from_newton",
    "eps_from_nu",
    "eps_from_velocity_ratio",
    "infinite_mass_impact",
    "newton_restitution",
    "nu_from_eps",
    "velocity_ratio_from_eps",
    "vis_viva_loss",
    "wall_impact",
]


@dataclass(frozen=True)
class DirectImpact:
    """Outcome of a direct impact (§I n°5, eq. 7). Arrays broadcast from the inputs; ``method``, ``path``,
    ``regime`` and ``label`` follow the convention of ``paths``."""

    V1: np.ndarray
    V1p: np.ndarray
    newton_e: np.ndarray
    vis_viva_lost: np.ndarray
    method: str
    path: np.ndarray
    regime: np.ndarray
    label: str


@dataclass(frozen=True)
class WallImpact:
    """Outcome of an impact on an immovable mass (§I n°5, eq. 9)."""

    V1: np.ndarray
    ratio: np.ndarray  # −V1/V0
    method: str
    path: np.ndarray
    regime: np.ndarray
    label: str


def vis_viva_loss(
    M: ArrayLike, U: ArrayLike, eps: ArrayLike, Mp: ArrayLike, Up: ArrayLike, epsp: ArrayLike,
    J_omega: ArrayLike = 0.0,
) -> np.ndarray:
    """Right side of eq. (6), §I n°3: ε M U² + ε′ M′ U′² − 2Jω, the vis viva Σmv² lost (2 × kinetic energy).

    U, U′ are the velocities lost by the translating bodies M, M′; Jω the work term of the tangential
    impulse (zero in a direct impact).
    """
    M, U, eps, Mp, Up, epsp, J_omega = (np.asarray(a, dtype=float) for a in (M, U, eps, Mp, Up, epsp, J_omega))
    return eps * M * U**2 + epsp * Mp * Up**2 - 2.0 * J_omega


def denominator(M: ArrayLike, Mp: ArrayLike, eps: ArrayLike, epsp: ArrayLike) -> np.ndarray:
    """D = M′(1 + ε) + M(1 + ε′), the denominator of eqs (7)–(8), §I n°5."""
    M, Mp, eps, epsp = as_floats(M, Mp, eps, epsp)
    return Mp * (1.0 + eps) + M * (1.0 + epsp)


def direct_impact(
    M: ArrayLike, Mp: ArrayLike, V0: ArrayLike, V0p: ArrayLike = 0.0, *, eps: ArrayLike, epsp: ArrayLike,
) -> DirectImpact:
    """Direct impact of M on M′, eq. (7) §I n°5 (eq. (8) when V0′ = 0), derived as in the module docstring."""
    M, Mp, V0, V0p, eps, epsp = as_floats(M, Mp, V0, V0p, eps, epsp)
    D = denominator(M, Mp, eps, epsp)
    delta = 2.0 * Mp * (V0 - V0p) / D
    V1 = V0 - delta
    V1p = V0p + (M / Mp) * delta
    lost = M * (V0 * V0 - V1 * V1) + Mp * (V0p * V0p - V1p * V1p)  # x * x: what numpy computes for x**2
    shape = V1.shape
    return result(DirectImpact, V1=V1, V1p=V1p, newton_e=_newton(M, Mp, eps, epsp, D), vis_viva_lost=lost,
                  method="exact", path=codes(shape, PathCode.EXACT), regime=codes(shape, Regime.FRICTIONLESS),
                  label="closed form, §I eq. (7)")


def wall_impact(V0: ArrayLike, *, eps: ArrayLike) -> WallImpact:
    """Impact on an immovable mass, eq. (9) §I n°5, as a result of the shared convention."""
    V0, eps = batch_arrays(V0, eps)
    r = velocity_ratio_from_eps(eps)
    shape = V0.shape
    return result(WallImpact, V1=-r * V0, ratio=r, method="exact", path=codes(shape, PathCode.EXACT),
                  regime=codes(shape, Regime.FRICTIONLESS), label="closed form, §I eq. (9)")


def infinite_mass_impact(V0: ArrayLike, *, eps: ArrayLike) -> np.ndarray:
    """Velocity after striking an immovable mass, eq. (9) §I n°5: V1 = −(1 − ε)/(1 + ε) V0 (limit M′ → ∞ of (8))."""
    return -velocity_ratio_from_eps(eps) * np.asarray(V0, dtype=float)


def velocity_ratio_from_eps(eps: ArrayLike) -> np.ndarray:
    """The ratio −V1/V0 = (1 − ε)/(1 + ε) of an impact on an immovable mass, eq. (9) §I n°5: the yield ν of
    the normal velocity (§III, §IV) and Newton's e of a ball on a wall are this same number."""
    eps = eps if eps.__class__ is np.float64 else np.asarray(eps, dtype=float)
    return (1.0 - eps) / (1.0 + eps)


nu_from_eps = velocity_ratio_from_eps  # ν = (1 − ε)/(1 + ε): the one ε ↔ ν ↔ e map, eq. (9)


def eps_from_velocity_ratio(ratio: ArrayLike) -> np.ndarray:
    """Inverse of eq. (9), §I n°5: ε = (1 − r)/(1 + r) for a measured r = −V1/V0 in [0, 1]."""
    r = np.asarray(ratio, dtype=float)
    return (1.0 - r) / (1.0 + r)


eps_from_nu = eps_from_velocity_ratio  # ε = (1 − ν)/(1 + ν), the inverse map


def eps_from_height_ratio(height_ratio: ArrayLike) -> np.ndarray:
    """ε from a drop test (§I n°5, marble): free fall gives V = √(2gh), so r = √(h1/h0), then eq. (9)."""
    return eps_from_velocity_ratio(np.sqrt(np.asarray(height_ratio, dtype=float)))


def newton_restitution(M: ArrayLike, Mp: ArrayLike, eps: ArrayLike, epsp: ArrayLike) -> np.ndarray:
    """Newton's e = (V1′ − V1)/(V0 − V0′) implied by eq. (7): e = [M′(1 − ε) + M(1 − ε′)] / D.

    Not in the paper; follows from (7): V1′ − V1 = −(V0 − V0′) + Δ(1 + M/M′). For ε = ε′, or for M′ → ∞,
    e = (1 − ε)/(1 + ε) whatever the masses.
    """
    M, Mp, eps, epsp = as_floats(M, Mp, eps, epsp)
    return _newton(M, Mp, eps, epsp, denominator(M, Mp, eps, epsp))


def _newton(M: ArrayLike, Mp: ArrayLike, eps: ArrayLike, epsp: ArrayLike, D: ArrayLike) -> ArrayLike:
    """``newton_restitution`` with its denominator D of eqs (7)-(8) given."""
    return (Mp * (1.0 - eps) + M * (1.0 - epsp)) / D


def eps_from_newton(e: ArrayLike) -> np.ndarray:
    """ε = (1 − e)/(1 + e): the common coefficient (ε = ε′) equivalent to Newton's e; same as eq. (9)'s inverse."""
    return eps_from_velocity_ratio(e)


def denominator_from_struck_ratio(M: ArrayLike, ratio_p: ArrayLike) -> np.ndarray:
    """D from a measured V1′/V0 (struck body at rest), second of eqs (8): D = 2M / (V1′/V0)."""
    return 2.0 * np.asarray(M, dtype=float) / np.asarray(ratio_p, dtype=float)


def denominator_from_striker_ratio(Mp: ArrayLike, ratio: ArrayLike) -> np.ndarray:
    """D from a measured V1/V0 (struck body at rest), first of eqs (8): D = 2M′ / (1 − V1/V0)."""
    return 2.0 * np.asarray(Mp, dtype=float) / (1.0 - np.asarray(ratio, dtype=float))


# ---------------------------------------------------------------------------------------------------------------
# §I n°2–3: the derivation of the energy-loss law on explicit molecular configurations (issue 13).
#
# A body is a set of molecules (masses m_i at r_i). At the instant of greatest compression every body moves
# rigidly, u_i = V_b + Ω_b × (r_i − G_b), and the normal velocities at each contact are equal (the two
# principles of n°2). The velocities before and after follow from the impulses each molecule receives in the
# compression (P1_i) and the restitution (P2_i): v0_i = u_i − P1_i/m_i, v1_i = u_i + P2_i/m_i. The impulses are
# the contact impulses (at a molecule placed on the contact point) and central pairwise impulses between
# molecules of one body (equal, opposite, along the line joining them): nothing of eqs (1)–(6) is used to
# build them, so the equations can be checked on them.
# ---------------------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class MolecularImpact:
    """One impact of ``bodies`` bodies in a row, molecule by molecule (§I n°3, fig. 1).

    ``m`` (N,), ``body`` (N,) body index, ``u``, ``v0``, ``v1`` (N, 3) velocities at the greatest compression,
    before and after. ``J_omega`` is Σ over the contacts of J·ω: the tangential impulse received by the body
    ahead times the slip of that body on the one behind at the greatest compression (Résal's −Jω sign)."""

    m: np.ndarray
    body: np.ndarray
    u: np.ndarray
    v0: np.ndarray
    v1: np.ndarray
    J_omega: float


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.cross(a, b)


def _internal_pairs(rng: np.random.Generator, bodies: int, molecules: int) -> tuple[np.ndarray, np.ndarray]:
    """``molecular_impact``'s central internal impulses, drawn: per body (its molecules b·molecules …), 2·molecules
    pairs of two distinct molecules, each followed by its normal random size q. Returns the pairs' ends (k, i)
    flattened in the order drawn, and the sizes. A pair is drawn as ``rng.choice(idx, 2, replace=False)`` draws it,
    the same bits at a third of its cost: Floyd's algorithm, which ``choice`` uses up to 10 000 items (a first index
    in 0 … n − 2, a second in 0 … n − 1, n − 1 where it repeats the first), then its shuffle (which of the two comes
    first); tests/test_impact_law.py checks it against ``choice`` on the generator's stream."""
    if molecules > 10_000:
        raise ValueError(f"at most 10000 molecules per body (got {molecules}): Floyd's draw is choice's up to there")
    integers, normal, last = rng.integers, rng.normal, molecules - 1
    ends: list[int] = []
    sizes = []
    for b in range(bodies):
        base = b * molecules
        for _ in range(2 * molecules):
            i, k = int(integers(0, last)), int(integers(0, molecules))
            if k == i:
                k = last
            if integers(0, 2) == 0:
                i, k = k, i
            ends += (base + k, base + i)
            sizes.append(normal())
    return np.array(ends, dtype=np.intp), np.array(sizes)


def molecular_impact(rng: np.random.Generator, *, bodies: int = 2, molecules: int = 12, n: float | None = None,
                     f: float = 0.3, oppose_slip: bool = True) -> MolecularImpact:
    """A random impact of ``bodies`` bodies of ``molecules`` molecules each, contacts along Ox between
    consecutive bodies (normal e_x). The motion at the greatest compression is rigid per body with equal
    normal contact velocities; the compression impulses are a normal part, a tangential part of at most f
    times it (opposing the slip when ``oppose_slip``) and central internal impulses. The restitution impulses
    are ``n`` times the compression ones (Résal's premise φ1 = −nφ0 for every molecule, with n the same for all)
    or, with ``n=None``, independent random ones of the same kind."""
    N = bodies * molecules
    body = np.repeat(np.arange(bodies), molecules)
    m = rng.uniform(0.2, 2.0, N)
    r = np.empty((N, 3))
    contacts = [np.array([2.0 * j + 1.0, 0.0, 0.0]) for j in range(bodies - 1)]
    for b in range(bodies):
        centre = np.array([2.0 * b, 0.0, 0.0])
        pts = rng.normal(size=(molecules, 3))
        pts *= (rng.uniform(0.0, 1.0, molecules) ** (1 / 3) / np.linalg.norm(pts, axis=1))[:, None]
        r[body == b] = centre + pts
    # a molecule of each body on each of its contact points
    contact_mol: list[tuple[int, int]] = []
    for j, c in enumerate(contacts):
        ia, ib = j * molecules, (j + 1) * molecules + 1
        r[ia] = c
        r[ib] = c
        contact_mol.append((ia, ib))
    G = np.array([np.average(r[body == b], axis=0, weights=m[body == b]) for b in range(bodies)])
    V = rng.normal(size=(bodies, 3))
    W = rng.normal(size=(bodies, 3))
    for j, c in enumerate(contacts):  # equal normal velocities at each contact: fix V_x of the body ahead
        ua = V[j] + _cross(W[j], c - G[j])
        ub = V[j + 1] + _cross(W[j + 1], c - G[j + 1])
        V[j + 1, 0] += ua[0] - ub[0]
    u = V[body] + _cross(W[body], r - G[body])

    def impulses() -> tuple[np.ndarray, list[np.ndarray]]:
        P = np.zeros((N, 3))
        tangential = []
        for (ia, ib) in contact_mol:
            slip = u[ib] - u[ia]  # the body ahead on the one behind
            slip[0] = 0.0
            Nn = rng.uniform(0.5, 2.0)
            if oppose_slip:
                T = -f * Nn * rng.uniform(0.0, 1.0) * slip / max(np.linalg.norm(slip), 1e-300)
            else:
                T = f * Nn * np.array([0.0, *rng.normal(size=2)])
            Pb = np.array([Nn, 0.0, 0.0]) + T  # impulse on the body ahead; the one behind receives −Pb
            P[ib] += Pb
            P[ia] -= Pb
            tangential.append(T)
        ends, sizes = _internal_pairs(rng, bodies, molecules)
        d = r[ends[0::2]] - r[ends[1::2]]
        qd = sizes[:, None] * (d / np.sqrt(np.sum(d * d, axis=1))[:, None])
        # each impulse on its two molecules, in the order drawn: P[k] += q d, then P[i] −= q d (the same sums)
        np.add.at(P, ends, np.stack((qd, -qd), axis=1).reshape(-1, 3))
        return P, tangential

    P1, T1 = impulses()
    if n is None:
        P2, T2 = impulses()
    else:
        P2, T2 = n * P1, [n * t for t in T1]
    J_omega = 0.0
    for (ia, ib), t1, t2 in zip(contact_mol, T1, T2, strict=True):
        J_omega += float(np.dot(t1 + t2, u[ib] - u[ia]))
    return MolecularImpact(m=m, body=body, u=u, v0=u - P1 / m[:, None], v1=u + P2 / m[:, None], J_omega=J_omega)


def vis_viva(m: ArrayLike, v: ArrayLike) -> float:
    """Σ m v², the vis viva (twice the kinetic energy) of a set of molecules."""
    v = np.asarray(v, dtype=float)
    return float(np.sum(np.asarray(m, dtype=float) * np.sum(v * v, axis=-1)))


def eq1_per_molecule(v0: ArrayLike, v1: ArrayLike, u: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The geometric steps of §I n°3 for each molecule (fig. 1): returns (v0² − (u² + φ0² + 2u·uI0),
    v1² − (u² + φ1² + 2u·uI1), I0I1 − U cos(U, u)), where I0, I1 are the projections of the points v0, v1 on
    the line Ou and uI0 the segment from u to I0 counted along Ou. Each is zero for any vectors."""
    v0, v1, u = (np.asarray(a, dtype=float) for a in (v0, v1, u))
    un = np.linalg.norm(u, axis=-1)
    e = u / un[..., None]
    phi0, phi1, U = v0 - u, v1 - u, v0 - v1
    uI0 = np.sum(v0 * e, axis=-1) - un  # signed segment u → I0 along Ou
    uI1 = np.sum(v1 * e, axis=-1) - un
    sq = lambda a: np.sum(a * a, axis=-1)  # noqa: E731
    U_cos = np.sum(U * e, axis=-1)  # U cos(U, u), also where U = 0
    return (sq(v0) - (un**2 + sq(phi0) + 2 * un * uI0), sq(v1) - (un**2 + sq(phi1) + 2 * un * uI1),
            (uI0 - uI1) - U_cos)


def sphere_plane_law(chi0: ArrayLike, zeta0: ArrayLike, p0: ArrayLike, *, R: ArrayLike, k: ArrayLike,
                     f: ArrayLike, nu: ArrayLike) -> dict[str, np.ndarray]:
    """A sphere striking a fixed plane with friction (§III n°8, exact outcome of ``plane.plane_impact``) read
    with §I n°3's law: per unit mass, the vis viva lost exactly, the loss that eq. (3) gives with
    ε = (1 − ν)/(1 + ν) (ε Σ m U² − 2Jω, ω the slip at the greatest compression, which is the impact run
    with ν = 0), and the largest angle (rad) between φ1 and −φ0 over the molecules of the ball (the premise of
    eq. (3)). ν is the ratio of the restitution's normal impulse to the compression's, as in §III."""
    from . import plane  # a sibling module of the same layer

    chi0, zeta0, p0, R, k, f, nu = (np.asarray(a, dtype=float) for a in (chi0, zeta0, p0, R, k, f, nu))
    end = plane.plane_impact(chi0, zeta0, p0, R=R, k=k, f=f, nu=nu)
    mid = plane.plane_impact(chi0, zeta0, p0, R=R, k=k, f=f, nu=np.zeros_like(nu))
    inertia = R**2 / k  # per unit mass

    def vv(chi: np.ndarray, zeta: np.ndarray, p: np.ndarray) -> np.ndarray:
        return chi**2 + zeta**2 + inertia * p**2

    exact = vv(chi0, zeta0, p0) - vv(end.chi1, end.zeta1, end.p1)
    dchi, dzeta, dp = chi0 - end.chi1, zeta0 - end.zeta1, p0 - end.p1
    sum_mU2 = dchi**2 + dzeta**2 + inertia * dp**2
    J = end.chi1 - chi0  # tangential impulse per unit mass received by the ball
    omega = mid.chi1 - mid.p1 * R  # slip of the ball on the plane at the greatest compression
    eps = eps_from_nu(nu)
    law = eps * sum_mU2 - 2.0 * J * omega
    # φ0 = v0 − u and φ1 = v1 − u at a molecule (x, z) of the ball: (Δχ + Δp z, Δζ − Δp x)
    ang = np.linspace(0.0, 2 * np.pi, 73)[:-1]
    rad = np.array([0.0, 0.5, 1.0])
    x = (R[..., None, None] if np.ndim(R) else R) * np.cos(ang)[None, :] * rad[:, None]
    z = (R[..., None, None] if np.ndim(R) else R) * np.sin(ang)[None, :] * rad[:, None]

    def field(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        a, b, c = (np.asarray(t)[..., None, None] for t in (a, b, c))
        return a + c * z, b - c * x

    f0x, f0z = field(chi0 - mid.chi1, zeta0 - mid.zeta1, p0 - mid.p1)
    f1x, f1z = field(end.chi1 - mid.chi1, end.zeta1 - mid.zeta1, end.p1 - mid.p1)
    n0, n1 = np.hypot(f0x, f0z), np.hypot(f1x, f1z)
    dot = -(f0x * f1x + f0z * f1z)
    crs = np.abs(f0x * f1z - f0z * f1x)
    ok = (n0 > 1e-12 * np.max(n0)) & (n1 > 1e-12 * np.max(n0))
    angle = np.where(ok, np.arctan2(crs, dot), 0.0).max(axis=(-2, -1))
    return {"initial": vv(chi0, zeta0, p0), "exact_loss": exact, "law_loss": law, "premise_angle": angle,
            "sliding": plane.slides_throughout(chi0, zeta0, p0, R=R, k=k, f=f, nu=nu)}


def chain_at_greatest_compression(tau: float, *, molecules: int = 12, mass_ratio: float = 1.0) -> dict[str, float]:
    """Two elastic bodies as chains of ``molecules`` equal masses joined by springs (a 1-D model of molecular
    bodies), body M moving at 1 onto M′ at rest through a contact spring, solved in closed form (normal modes:
    the motion is linear while the contact is compressed). ``tau`` is the contact's half period for rigid
    bodies, π√(μ/k_c), over the time a wave takes to cross a body, n√(m/k). Returns, at the first instant of
    greatest compression (the first zero of the contact's rate of compression): the difference of the normal
    velocities of the two contact molecules, and the largest departure of a molecule's velocity from its body's
    mean velocity, both over the approach speed (0 for bodies that move as rigid solids, §I n°2)."""
    from scipy.optimize import brentq

    nm = molecules
    m = np.concatenate([np.full(nm, 1.0 / nm), np.full(nm, mass_ratio / nm)])
    mu = mass_ratio / (1.0 + mass_ratio)
    kc = 1.0  # time unit: rigid bodies would stay in contact π√μ
    t_contact = np.pi * np.sqrt(mu / kc)
    t_transit = t_contact / tau
    ka = (nm * np.sqrt(1.0 / nm) / t_transit) ** 2  # n √(m/k) = t_transit for body M
    kb = (nm * np.sqrt(mass_ratio / nm) / t_transit) ** 2
    K = np.zeros((2 * nm, 2 * nm))

    def spring(i: int, j: int, s: float) -> None:
        K[i, i] += s
        K[j, j] += s
        K[i, j] -= s
        K[j, i] -= s

    for i in range(nm - 1):
        spring(i, i + 1, ka)
        spring(nm + i, nm + i + 1, kb)
    spring(nm - 1, nm, kc)
    s = 1.0 / np.sqrt(m)
    lam, Q = np.linalg.eigh(K * s[:, None] * s[None, :])
    w = np.sqrt(np.clip(lam, 0.0, None))
    v0 = np.concatenate([np.ones(nm), np.zeros(nm)])
    a = Q.T @ (v0 / s)  # modal velocities at t = 0 (y = √m x)

    def velocity(t: float) -> np.ndarray:
        return s * (Q @ (np.cos(w * t) * a))

    def rate(t: float) -> float:
        v = velocity(t)
        return float(v[nm - 1] - v[nm])

    dt = 0.05 * np.pi / max(float(w.max()), 1e-300)
    t, t_end = 0.0, 50.0 * t_contact + 50.0 * t_transit
    while rate(t + dt) > 0.0:
        t += dt
        if t > t_end:
            raise RuntimeError("no greatest compression found: the contact never stops closing")
    t_star = brentq(rate, t, t + dt, xtol=1e-15 * max(t_contact, 1.0), rtol=1e-15, maxiter=200)
    v = velocity(t_star)
    spread = 0.0
    for b in (slice(0, nm), slice(nm, 2 * nm)):
        mean = np.average(v[b], weights=m[b])
        spread = max(spread, float(np.max(np.abs(v[b] - mean))))
    return {"normal_difference": abs(rate(t_star)), "rigid_departure": spread, "t_star": t_star / t_contact}


def rigid_impulse_response(M: float, inertia: ArrayLike, lever: ArrayLike, P: ArrayLike) -> tuple[np.ndarray,
                                                                                                   np.ndarray]:
    """Changes (ΔV, ΔΩ) of a rigid body of mass M and inertia tensor ``inertia`` (about its centre of gravity)
    struck by the impulse P at the point ``lever`` from its centre: ΔV = P/M, ΔΩ = I⁻¹ (lever × P) (§I n°5:
    a direct impact, the normal through the centres, leaves the bodies translating)."""
    P = np.asarray(P, dtype=float)
    return P / M, np.linalg.solve(np.asarray(inertia, dtype=float), np.cross(np.asarray(lever, dtype=float), P))


def drop_rebound_height_ratio(h0: ArrayLike, r: ArrayLike, g: float, *, rtol: float = 1e-12) -> np.ndarray:
    """h1/h0 of a ball dropped from h0 that leaves the slab at r times its impact speed (eq. (9)'s −V1/V0),
    by integrating the fall and the rise in time (§I n°5, the marble drop): the reference for h1/h0 = r²."""
    from scipy.integrate import solve_ivp

    from .budget import bounded, check

    out = []
    for hh, rr in zip(*(np.ravel(a) for a in np.broadcast_arrays(np.asarray(h0, float), np.asarray(r, float))),
                      strict=True):
        def rhs(_t: float, y: np.ndarray) -> list[float]:
            return [y[1], -g]

        def ground(_t: float, y: np.ndarray) -> float:
            return y[0]

        def apex(_t: float, y: np.ndarray) -> float:
            return y[1]

        ground.terminal, ground.direction = True, -1
        apex.terminal, apex.direction = True, -1
        t_fall = np.sqrt(2 * hh / g)
        fall = check(solve_ivp(bounded(rhs), (0.0, 4 * t_fall), [hh, 0.0], events=ground, rtol=rtol,
                               atol=1e-14 * hh, method="DOP853"))
        v_impact = fall.y_events[0][0][1]
        rise = check(solve_ivp(bounded(rhs), (0.0, 4 * t_fall), [0.0, -rr * v_impact], events=apex, rtol=rtol,
                               atol=1e-14 * hh, method="DOP853"))
        out.append(rise.y_events[0][0][0] / hh)
    return np.array(out).reshape(np.broadcast_shapes(np.shape(h0), np.shape(r)))
