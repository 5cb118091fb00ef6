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

from .canonical import canonical_json, digest
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
    changed = diff_keys(old.get("params", {}), params)
    if changed:
        shown = ", ".join(
            f"{n}: {canonical_json(old.get('params', {}).get(n))} -> {canonical_json(params.get(n))}"
            for n in changed[:4]
        )
        more = f" (+{len(changed) - 4} more)" if len(changed) > 4 else ""
        return Reason.PARAMS_CHANGED, shown + more
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
