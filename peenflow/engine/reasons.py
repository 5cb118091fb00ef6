"""Why a result is computed, reused, or left alone: typed decisions.

"Why did this rerun?" (or why did it *not*?) is the commonest question about a
workflow tool; every decision the planner makes carries one of these reasons
and a human-readable detail, and ``peenflow status --why`` prints them.
"""

from __future__ import annotations

import enum


class Reason(str, enum.Enum):
    """Why a point must be (re)computed -- or why it need not be."""

    MISSING = "missing"  # never computed for this slot
    PARAMS_CHANGED = "parameters changed"
    CODE_CHANGED = "code changed"
    UPSTREAM_CHANGED = "upstream changed"
    FORCED = "forced"  # `peenflow rerun`
    INCOMPLETE = "incomplete"  # killed mid-run, checkpoint left, or result file unreadable
    UP_TO_DATE = "up to date"
    STALE = "stale"  # explicit version unchanged but code changed: kept, flagged


class State(str, enum.Enum):
    """What ``status`` shows for one point."""

    DONE = "done"
    PENDING = "pending"
    RUNNING = "running"
    FAILED = "failed"
    STALE = "stale"
    BLOCKED = "blocked"  # an upstream failed, or a lease held by another run
