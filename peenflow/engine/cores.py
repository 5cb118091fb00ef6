"""Sharing a process's cores between the points it computes at the same time.

A sweep of many points runs best with one compute thread per point; a lone
big point (a single REV run) runs best with all the cores.  The executor
asks for the natural share of each point up front (:func:`wanted_threads`)
and a :class:`CoreBudget` hands threads out when a computing point first asks
for its thread count (``ctx.threads``; a reused point, or a light task that
never asks, takes none), never more than the budget holds in total: whatever
order dask starts points in, kernel threads never exceed the cores.  A point
that finds the budget empty waits for a thread, which costs nothing since
every core is busy meanwhile.  Counts are fixed for a point's life (numba
cannot change a running parallel loop's threads), so a point that starts
beside others keeps its smaller share after they finish.
"""

from __future__ import annotations

import threading
from collections import Counter

__all__ = ["CoreBudget", "wanted_threads", "active_budget", "set_active_budget"]


def wanted_threads(stages: list[str], cores: int, workers: int) -> dict[str, int]:
    """Threads each stage's points ask for: ``cores // min(workers, points in the stage)``.

    ``stages``: the stage of every point to run (one entry per point).  A
    stage with one point asks for every core; a sweep of at least ``workers``
    points asks for ``cores // workers`` each.
    """
    counts = Counter(stages)
    return {s: max(1, cores // max(1, min(workers, n))) for s, n in counts.items()}


class CoreBudget:
    """``total`` compute threads shared by the points running in this process."""

    def __init__(self, total: int):
        if total < 1:
            raise ValueError(f"a core budget needs at least one thread, got {total}")
        self.total = total
        self._free = total
        self._cond = threading.Condition()

    @property
    def in_use(self) -> int:
        with self._cond:
            return self.total - self._free

    def acquire(self, wanted: int) -> int:
        """Take between 1 and ``wanted`` threads, as many as are free (waits for one)."""
        with self._cond:
            while self._free < 1:
                self._cond.wait()
            n = max(1, min(wanted, self._free))
            self._free -= n
            return n

    def release(self, n: int) -> None:
        """Give back ``n`` threads taken by :meth:`acquire`."""
        with self._cond:
            self._free += n
            self._cond.notify_all()


_active: CoreBudget | None = None


def set_active_budget(budget: CoreBudget | None) -> None:
    """The budget points computed in this process draw from (None: use each point's own count)."""
    global _active
    _active = budget


def active_budget() -> CoreBudget | None:
    return _active
