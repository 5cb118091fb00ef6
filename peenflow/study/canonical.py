"""Canonical, JSON-able form of study values, for hashing.

The engine's canonical form (:mod:`peenflow.engine.canonical`: keys sorted,
tuples as lists, floats to 12 significant digits, integral floats as
integers, -0.0 as 0) applied to a study's models, less the cosmetic keys
(``description``, ``source``) that change no result.
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel

from peenflow.engine.canonical import canonical_json as _canonical_json
from peenflow.engine.canonical import canonical_value

__all__ = ["canonical", "canonical_json", "COSMETIC_KEYS"]

COSMETIC_KEYS = frozenset({"description", "source"})


def _plain(value: Any) -> Any:
    if isinstance(value, BaseModel):
        value = value.model_dump(mode="python")
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items() if k not in COSMETIC_KEYS}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def canonical(value: Any) -> Any:
    """Canonical JSON-able form of a model, dict, sequence or scalar."""
    return canonical_value(_plain(value), "study")


def canonical_json(value: Any) -> str:
    """Compact, sorted JSON of canonical(value): the string to hash."""
    return _canonical_json(_plain(value), "study")
