"""Features of a residual-stress depth profile that process engineers specify: where it stops being compressive.

Arrays in, numbers out (depths in m, stresses in Pa).
"""

from __future__ import annotations

import numpy as np

__all__ = ["VANISHING_FRACTION", "compressive_depth"]

#: a profile that never turns tensile (a REV held at its bottom) is compressive down to
#: where it rises above this fraction of its peak
VANISHING_FRACTION = 0.05


def _crossing(z: np.ndarray, s: np.ndarray, level: float) -> float | None:
    """First depth where ``s`` rises above ``level`` (linear between layers); None if it never does."""
    k = np.nonzero(s > level)[0]
    if not k.size or k[0] == 0:
        return None
    i = int(k[0])
    return float(z[i - 1] + (z[i] - z[i - 1]) * (level - s[i - 1]) / (s[i] - s[i - 1]))


def compressive_depth(z: np.ndarray, s: np.ndarray) -> tuple[float | None, str]:
    """(depth, how) of the compressive layer of a profile compressive at the surface.

    The first zero crossing, where tension of more than ``VANISHING_FRACTION`` of the peak
    compression follows it; without one (a held REV has no balancing tension, and its
    profile reaches zero through round-off of either sign), where ``s`` rises above
    ``VANISHING_FRACTION`` of its peak compression.
    """
    if s[0] >= 0:
        return None, "not compressive at the surface"
    level = VANISHING_FRACTION * float(np.min(s))
    zero = _crossing(z, s, 0.0)
    # a crossing counts only where real tension follows (more than the same fraction of the peak):
    # a held REV's profile decays to zero through round-off of either sign
    if zero is not None and float(np.max(s[z > zero])) > -level:
        return zero, "first zero crossing of the mean"
    return _crossing(z, s, level), (f"no tension in the held REV: where the mean rises above "
                                    f"{VANISHING_FRACTION:.0%} of its peak")
