"""A reference for the sliding-velocity formulas (eq. (1) of §II, §III, §VII): the velocity of a ball's material point
differentiated from its rigid motion, sharing no vector product with the mechanics it checks."""

from __future__ import annotations

import numpy as np

__all__ = ["material_point_velocity"]


def material_point_velocity(v: np.ndarray, w: np.ndarray, r: np.ndarray, step: float = 1e-3) -> np.ndarray:
    """Velocity of the ball's material point at ``r`` from C, differentiated from its position v t + rot(t ω) r (the
    rigid motion, rotated by scipy's ``Rotation``: no vector product of ours), by a fourth-order central difference
    over ±2h with |ω| h = ``step``: truncation about (|ω| h)⁴/30, rounding about 1e-16/(|ω| h), relative."""
    from scipy.spatial.transform import Rotation  # only the rows that check eq. (1) need it

    wn = float(np.linalg.norm(w))
    if wn == 0.0:
        return np.array(v, dtype=float)
    h = step / wn
    x = {j: v * (j * h) + Rotation.from_rotvec(w * (j * h)).apply(r) for j in (-2, -1, 1, 2)}
    return (x[-2] - 8.0 * x[-1] + 8.0 * x[1] - x[2]) / (12.0 * h)
