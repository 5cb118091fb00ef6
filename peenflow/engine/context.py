"""What a running task may ask of the engine: progress and checkpoints.

A task function that declares a ``ctx`` keyword receives a
:class:`TaskContext`.  Both services write through the store, so they work
the same on the local scheduler and on a dask.distributed cluster sharing
the store directory.
"""

from __future__ import annotations

import time

import xarray as xr

from .checkpoint import position_of
from .interrupt import Interrupted, stop_requested


class TaskContext:
    """Handed to a task as ``ctx``.

    Attributes: ``key`` (result key), ``point`` (e.g. ``strip_runs[angle_deg=45]``),
    ``threads`` (compute threads this task may use without oversubscribing the
    machine; the first read draws them from the run's core budget, see
    cores.py), ``resumed`` (True when a checkpoint was found at start),
    ``notes`` (what the task wants the run's report to say, e.g. that it
    ignored an unusable checkpoint), ``resumed_from`` (the loaded
    checkpoint's position, ``{"done", "total", "unit"}``, or None).

    A checkpoint records the task's last progress report as its position, so
    a task reports its progress up to the state it saves before saving it.
    """

    PROGRESS_INTERVAL_S = 1.0

    def __init__(self, store, key: str, point: str, study: str, threads: int, budget=None):
        self.key = key
        self.point = point
        self.study = study
        self._wanted = threads
        self._budget = budget
        self.granted: int | None = None  # threads handed out, once asked for
        self._store = store
        self._checkpoints = store.checkpoints(key)
        self._last_progress = 0.0
        self._started = time.time()
        self._progress_base: tuple[float, float] | None = None
        self.resumed = self._checkpoints.exists()
        self.resumed_from: dict | None = None
        self._position: dict | None = None  # the last progress reported (the next checkpoint's position)
        self.notes: list[str] = []

    @property
    def threads(self) -> int:
        if self.granted is None:
            self.granted = self._budget.acquire(self._wanted) if self._budget is not None else self._wanted
        return self.granted

    def release_threads(self) -> None:
        """Give granted threads back to the budget (the runner calls it when the task ends)."""
        if self.granted is not None and self._budget is not None:
            self._budget.release(self.granted)
            self._budget = None

    def progress(self, done: float, total: float | None = None, unit: str = "", note: str = "") -> None:
        """Report progress (throttled to about once a second; the last call always lands)."""
        now = time.time()
        self._position = {"done": done, "total": total, "unit": unit}
        final = total is not None and done >= total
        if not final and now - self._last_progress < self.PROGRESS_INTERVAL_S:
            return
        self._last_progress = now
        if self._progress_base is None:
            # ETA base: this process's start, or for a resumed point its first
            # record (the work before it came from the checkpoint)
            self._progress_base = (now, done) if self.resumed else (self._started, 0.0)
        try:
            self._store.write_progress(self.key, {
                "study": self.study, "point": self.point, "done": done, "total": total,
                "unit": unit, "note": note, "time": now,
                "started": self._progress_base[0], "base": self._progress_base[1],
            })
        except OSError:  # progress is only shown: a full disk fails the result's write, with its cause
            pass

    def load_checkpoint(self) -> xr.Dataset | None:
        """The last saved checkpoint of this key, or None (an unreadable one is removed, and the run's
        report says so in one line: the task starts over)."""
        state = self._checkpoints.load()
        if state is None and self._checkpoints.unreadable:
            self._checkpoints.clear()
            self.resumed = False
            self.notes.append("checkpoint unreadable, starting over")
        if state is not None:
            self.resumed_from = self._position = position_of(state.attrs)
        return state

    def save_checkpoint(self, state: xr.Dataset) -> None:
        """Save intermediate state atomically; a later run with the same key resumes from it."""
        self._checkpoints.save(state, self._position)

    def clear_checkpoint(self) -> None:
        self._checkpoints.clear()

    def discard_checkpoint(self, why: str) -> None:
        """Drop a checkpoint the task cannot use (another task's, or damaged) and say so; start afresh."""
        self._checkpoints.clear()
        self.resumed = False
        self.resumed_from = self._position = None
        self.notes.append(f"ignored an unusable checkpoint ({why}); started from the beginning")

    @property
    def stop_requested(self) -> bool:
        """True once the user asked the run to stop (Ctrl-C, SIGTERM, SIGHUP): save a checkpoint, then
        call :meth:`stop`."""
        return stop_requested()

    def stop(self, where: str) -> None:
        """Raise :class:`Interrupted` (after the task saved its checkpoint); ``where``: e.g. "after shot 12 of 40"."""
        raise Interrupted(where)
