"""Read-only array copies for the frozen result dataclasses of this package."""

from __future__ import annotations

import numpy as np


def read_only(a, dtype=float) -> np.ndarray:
    """A copy of ``a`` as a ``dtype`` array that cannot be written to (results stay immutable)."""
    arr = np.array(a, dtype=dtype, copy=True)
    arr.setflags(write=False)
    return arr
