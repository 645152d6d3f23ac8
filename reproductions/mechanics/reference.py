"""Direct numerical integration of impacts: the truth the closed forms are checked and benchmarked against.

§I n°2 describes an impact as a compression, up to the instant at which the normal velocities are
equal, followed by a restitution. ``integrate_direct_impact`` integrates exactly that: two translating
masses pressed by a contact force that rises linearly with the overlap δ while they approach (stiffness
K) and falls along a stiffer line K/e² while they separate, leaving a permanent set (a Walton-type
hysteretic contact). The restitution phase gives back the fraction e² of the energy stored in
compression, so the relative velocity is reversed with the factor e (Newton's coefficient). Nothing of
eqs (6)–(9) is used here: comparing with ``impact.direct_impact`` at e = ``impact.newton_restitution``
checks the closed form against the equations of motion.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import solve_ivp

__all__ = ["ReferenceImpact", "integrate_direct_impact"]


@dataclass(frozen=True)
class ReferenceImpact:
    """Velocities after the impact and the number of right-hand-side evaluations used."""

    V1: np.ndarray
    V1p: np.ndarray
    nfev: np.ndarray
    method: str


def _one(M: float, Mp: float, V0: float, V0p: float, e: float, rtol: float, atol: float) -> tuple[float, float, int]:
    if V0 <= V0p:  # no approach, no impact
        return V0, V0p, 0
    mu = M * Mp / (M + Mp)
    K = mu  # time unit: the compression lasts π/2
    scale = V0 - V0p

    def compress(_t: float, y: np.ndarray) -> list[float]:
        F = K * (y[0] - y[1])
        return [y[2], y[3], -F / M, F / Mp]

    def max_compression(_t: float, y: np.ndarray) -> float:
        return (y[2] - y[3]) / scale

    max_compression.terminal = True
    max_compression.direction = -1
    sol = solve_ivp(compress, (0.0, 10.0), [0.0, 0.0, V0, V0p], rtol=rtol, atol=atol * scale,
                    events=max_compression, method="DOP853")
    y = sol.y_events[0][0]
    nfev = sol.nfev
    if e == 0.0:  # nothing is given back: both move on with the common velocity u of §I n°3
        return y[2], y[3], nfev
    delta_max = y[0] - y[1]
    K2 = K / e**2
    delta_p = delta_max * (1.0 - e**2)

    def restitute(_t: float, z: np.ndarray) -> list[float]:
        F = K2 * (z[0] - z[1] - delta_p)
        return [z[2], z[3], -F / M, F / Mp]

    def separation(_t: float, z: np.ndarray) -> float:
        return (z[0] - z[1] - delta_p) / max(delta_max, 1e-300)

    separation.terminal = True
    separation.direction = -1
    sol2 = solve_ivp(restitute, (0.0, 10.0 * e + 1.0), y, rtol=rtol, atol=atol * scale, events=separation,
                     method="DOP853")
    z = sol2.y_events[0][0]
    return z[2], z[3], nfev + sol2.nfev


def integrate_direct_impact(
    M: ArrayLike, Mp: ArrayLike, V0: ArrayLike, V0p: ArrayLike, e: ArrayLike, *, rtol: float = 1e-10,
    atol: float = 1e-12,
) -> ReferenceImpact:
    """Integrate the two-phase contact (§I n°2) for each scene of the broadcast inputs; e in [0, 1]."""
    arrays = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (M, Mp, V0, V0p, e)))
    shape = arrays[0].shape
    flat = [a.ravel() for a in arrays]
    out = np.array([_one(*(float(a[i]) for a in flat), rtol, atol) for i in range(flat[0].size)]).reshape(
        (*shape, 3))
    return ReferenceImpact(V1=out[..., 0], V1p=out[..., 1], nfev=out[..., 2].astype(int),
                           method="ODE, two-phase hysteretic contact (DOP853)")
