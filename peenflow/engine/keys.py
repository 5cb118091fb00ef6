"""Result keys, and the typed reason a point must be computed.

key = SHA-256 of the canonical JSON of::

    {"task": name, "code": "version:<v>" | "source:<fingerprint>",
     "params": <canonical params>, "upstream": {name: <content hash(es)>}}

Upstream entries are *content* hashes of the upstream results (for a
combined group: the sorted (point label, content hash) pairs), so the same
inputs give the same key in any process or machine, and an upstream that is
recomputed to identical data leaves downstream keys unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

import json
from typing import Any

from .canonical import canonical_json, canonical_value, digest
from .reasons import Reason


@dataclass(frozen=True)
class KeyParts:
    task: str
    code: str
    params: dict
    upstream: dict

    def to_dict(self) -> dict:
        return {"task": self.task, "code": self.code, "params": self.params, "upstream": self.upstream}

    @property
    def key(self) -> str:
        return digest(canonical_json(self.to_dict()))


def diff_keys(old: dict, new: dict) -> list[str]:
    """Names of the entries that differ between two flat-ish dicts."""
    names = sorted(set(old) | set(new))
    return [n for n in names if canonical_json(old.get(n)) != canonical_json(new.get(n))]


#: list items compared one by one when at most this many differ; otherwise the lists are shown whole
_ITEMS_SHOWN = 2
#: the changes named in one reason (one line), and the characters of one value
_CHANGES_SHOWN, _VALUE_CHARS = 4, 48


def changed_fields(old: Any, new: Any) -> list[tuple[str, Any, Any]]:
    """(dotted path, old, new) of every field that differs between two parameter sets, in canonical form:
    tables by key (``material.A_Pa``), lists of one length item by item (``velocities_m_s[2]``) when only
    a few items differ, otherwise whole; a missing field is None."""
    out: list[tuple[str, Any, Any]] = []

    def walk(path: str, a: Any, b: Any) -> None:
        if a == b:
            return
        if isinstance(a, dict) and isinstance(b, dict):
            for k in sorted(set(a) | set(b)):
                walk(f"{path}.{k}" if path else k, a.get(k), b.get(k))
        elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b) \
                and sum(x != y for x, y in zip(a, b)) <= _ITEMS_SHOWN:
            for i, (x, y) in enumerate(zip(a, b)):
                walk(f"{path}[{i}]", x, y)
        else:
            out.append((path, a, b))

    walk("", canonical_value(old), canonical_value(new))
    return out


def describe_changes(changes: list[tuple[str, Any, Any]]) -> str:
    """One line: ``intensity_m: 0.0003 -> 0.00035, material.A_Pa: 4.34e8 -> 5e8 (+2 more)``."""
    shown = ", ".join(f"{path}: {' -> '.join(_pair(a, b))}" for path, a, b in changes[:_CHANGES_SHOWN])
    more = len(changes) - _CHANGES_SHOWN
    return shown + (f" (+{more} more)" if more > 0 else "")


def _pair(a: Any, b: Any) -> tuple[str, str]:
    """Two values as text, numbers with the fewest digits (at least 6) that tell them apart."""
    for digits in range(6, 13):
        pair = _value(a, digits), _value(b, digits)
        if pair[0] != pair[1]:
            return pair
    return pair


def _value(v: Any, digits: int) -> str:
    if v is None:
        return "none"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        text = f"{v:.{digits}g}"
        mantissa, e, exponent = text.partition("e")
        return f"{mantissa}e{int(exponent)}" if e else text
    if isinstance(v, list):
        items = [_value(x, digits) for x in v[:3]]
        return "[" + ", ".join(items) + (f", ... ({len(v)} items)]" if len(v) > 3 else "]")
    if isinstance(v, dict):
        text = "{" + ", ".join(f"{k}: {_value(x, digits)}" for k, x in v.items()) + "}"
    else:
        text = json.dumps(v)  # a string quoted, a newline escaped: one line
    return text if len(text) <= _VALUE_CHARS else text[:_VALUE_CHARS - 3] + "..."


def reason_against_slot(slot: dict | None, task: str, code: str, params: dict,
                        upstream: dict | None) -> tuple[Reason, str]:
    """Why this point is not reusable, judged against its last recorded attempt.

    ``upstream`` is None when some upstream result does not exist yet.
    Checked in the order a user would ask: parameters, code, upstream;
    when all agree the stored result itself must be missing or damaged.
    """
    if slot is None or "parts" not in slot:
        return Reason.MISSING, "never computed"
    old = slot["parts"]
    if old.get("task") != task:
        return Reason.MISSING, f"slot held task {old.get('task')!r}"
    changes = changed_fields(old.get("params", {}), params)
    if changes:
        return Reason.PARAMS_CHANGED, describe_changes(changes)
    if old.get("code") != code:
        return Reason.CODE_CHANGED, f"{_short(old.get('code'))} -> {_short(code)}"
    if upstream is None:
        return Reason.UPSTREAM_CHANGED, "an upstream result is still to be computed"
    changed = diff_keys(old.get("upstream", {}), upstream)
    if changed:
        return Reason.UPSTREAM_CHANGED, "new content in " + ", ".join(changed)
    return Reason.INCOMPLETE, "same inputs as the last attempt, but no valid result"


def _short(code: str | None) -> str:
    """``source:0123abcd...`` -> ``source 0123abcd``; versions shown whole."""
    if not code:
        return "?"
    kind, _, value = code.partition(":")
    return f"{kind} {value[:8]}" if kind == "source" else f"{kind} {value}"
