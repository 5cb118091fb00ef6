"""Canonical, JSON-able form of study values, for hashing result keys.

Same study -> same dict in any process on any machine: keys sorted, tuples
as lists, floats rounded to 12 significant digits (so 0.1 and
0.10000000000000001, or a value recomputed through a unit conversion, agree),
-0.0 as 0.0. Cosmetic keys (``description``, ``source``) are dropped.
"""

from __future__ import annotations

import json
import math
from typing import Any

from pydantic import BaseModel

__all__ = ["canonical", "canonical_json", "COSMETIC_KEYS"]

COSMETIC_KEYS = frozenset({"description", "source"})


def _float(x: float) -> float | str:
    if not math.isfinite(x):
        return repr(x)
    y = float(f"{x:.12g}")
    return 0.0 if y == 0.0 else y


def canonical(value: Any) -> Any:
    """Canonical JSON-able form of a model, dict, sequence or scalar."""
    if isinstance(value, BaseModel):
        value = value.model_dump(mode="python")
    if isinstance(value, dict):
        return {str(k): canonical(v) for k, v in sorted(value.items(), key=lambda kv: str(kv[0])) if k not in COSMETIC_KEYS}
    if isinstance(value, (list, tuple)):
        return [canonical(v) for v in value]
    if isinstance(value, bool) or value is None or isinstance(value, (int, str)):
        return value
    if isinstance(value, float):
        return _float(value)
    raise TypeError(f"no canonical form for {type(value).__name__}")


def canonical_json(value: Any) -> str:
    """Compact, sorted JSON of canonical(value): the string to hash."""
    return json.dumps(canonical(value), sort_keys=True, separators=(",", ":"), ensure_ascii=True, allow_nan=False)
