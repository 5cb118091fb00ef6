"""Stopping a run cleanly: the first signal asks, the second one insists.

``peenflow run`` turns SIGINT (Ctrl-C), SIGTERM and SIGHUP into a *stop
request* (:func:`request_stop`).  Points not yet started are not started;
a running task that checks :meth:`TaskContext.stop_requested` (the REV runs
do so after every shot, the two-shot search after every run) saves a
checkpoint and raises :class:`Interrupted`; the runner records the point as
*interrupted* (not failed) and releases its lease, so the next run resumes
from that checkpoint.  A second signal exits at once (``os._exit``) after
releasing this process's leases: what was checkpointed before stays.

The flag is per process; a dask.distributed worker does not see it.
"""

from __future__ import annotations

import threading

_STOP = threading.Event()
_REASON = {"text": ""}


class Interrupted(Exception):
    """A task stopped early on request; its checkpoint holds the work done so far."""


def request_stop(reason: str = "stop requested") -> None:
    _REASON["text"] = reason
    _STOP.set()


def stop_requested() -> bool:
    return _STOP.is_set()


def stop_reason() -> str:
    return _REASON["text"]


def reset() -> None:
    """Forget a stop request (the next run in this process starts normally)."""
    _STOP.clear()
    _REASON["text"] = ""
