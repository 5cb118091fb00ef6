"""Canonical serialisation of task parameters.

The canonical string is what a result key hashes, so it must be identical for
the same study in any process, on any machine, under any PYTHONHASHSEED:

* dict keys sorted, no whitespace, ASCII only;
* floats rounded to 12 significant digits, so ``0.1 + 0.2`` and ``0.3`` (or a
  value that went through a unit conversion) give the same key, and an
  integral float is written as an integer (``55.0`` == ``55``);
* numpy scalars and arrays become Python numbers and lists;
* NaN and infinities become strings (JSON has no spelling for them);
* an object with a ``__canonical__()`` method (typed stage parameters) is
  its canonical form, which must name every field that can change a result
  (the task is called with the object rebuilt from that form: ``Task``);
* anything else (objects, sets, paths with machine-specific prefixes) is
  rejected with the parameter's path in the message, so a key can never
  silently depend on an object's ``repr``.
"""

from __future__ import annotations

import hashlib
import json
import math
from typing import Any

import numpy as np

SIGNIFICANT_DIGITS = 12


class ParameterError(TypeError):
    """A task parameter that cannot be serialised canonically."""


def canonical_value(value: Any, path: str = "params") -> Any:
    """Return a JSON-ready, machine-independent form of ``value``."""
    if value is None or isinstance(value, (bool, np.bool_)):
        return None if value is None else bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        x = float(value)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        x = float(f"{x:.{SIGNIFICANT_DIGITS}g}")
        if x.is_integer() and abs(x) < 1e15:
            return int(x)
        return x
    if isinstance(value, str):
        return value
    if isinstance(value, dict):
        out = {}
        for k in value:
            if not isinstance(k, str):
                raise ParameterError(f"{path}: dict key {k!r} is not a string")
        for k in sorted(value):
            out[k] = canonical_value(value[k], f"{path}.{k}")
        return out
    if isinstance(value, (list, tuple)):
        return [canonical_value(v, f"{path}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, np.ndarray):
        return [canonical_value(v, f"{path}[{i}]") for i, v in enumerate(value.tolist())]
    if callable(getattr(type(value), "__canonical__", None)):
        return canonical_value(value.__canonical__(), path)
    raise ParameterError(
        f"{path}: value {value!r} of type {type(value).__name__} cannot be a task "
        "parameter (use numbers, strings, booleans, lists or dicts of them)"
    )


def canonical_json(value: Any, path: str = "params") -> str:
    """Canonical JSON text of ``value`` (see module docstring)."""
    return json.dumps(
        canonical_value(value, path), sort_keys=True, separators=(",", ":"), ensure_ascii=True
    )


def digest(text: str, length: int = 32) -> str:
    """Hex SHA-256 of ``text``, truncated to ``length`` characters."""
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:length]
