"""The moment of inertia of a ball, I = M R²/k, as every model and fit of resal takes it: the one bound on k.

Standard library only (no numpy): the command line's fit options read it while ``resal --help`` is built.
"""

from __future__ import annotations

__all__ = ["K_MIN", "K_SOLID", "K_WHY"]

K_MIN = 1.5  # a thin spherical shell, I = (2/3) M R²: the least k (the most inertia) a spherically symmetric ball has
K_SOLID = 2.5  # a homogeneous ball, I = (2/5) M R²
# why k has that bound, as a message says it: I = (2/3)∫r² dm ≤ (2/3) M R² for mass within the radius R
K_WHY = (f"a thin shell, all its mass at the radius, has the least k = MR²/I any ball can have, {K_MIN:g}; a solid "
         f"ball {K_SOLID:g}")
