"""Stopping a run cleanly: the first signal asks, the second one insists.

``peenflow run`` turns SIGINT (Ctrl-C), SIGTERM and SIGHUP into a *stop
request* (:func:`request_stop`).  Points not yet started are not started;
a running task that checks :meth:`TaskContext.stop_requested` (the REV runs
do so after every shot, the two-shot search after every run) saves a
checkpoint and raises :class:`Interrupted`; the runner records the point as
*interrupted* (not failed) and releases its lease, so the next run resumes
from that checkpoint.  A second signal exits at once (``os._exit``) after
releasing this process's leases: what was checkpointed before stays.

The flag is per process.  A point that runs in another process (a
dask.distributed worker) heeds the run's request through :func:`heeding`:
within it, this thread's :func:`stop_requested` also asks a check that
reads a request made elsewhere (:mod:`.cluster_stop` relays the client's).
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Callable

_STOP = threading.Event()
_REASON = {"text": ""}
_HEEDED = threading.local()


class Interrupted(Exception):
    """A task stopped early on request; its checkpoint holds the work done so far."""


def request_stop(reason: str = "stop requested") -> None:
    _REASON["text"] = reason
    _STOP.set()


def stop_requested() -> bool:
    return _STOP.is_set() or bool(_elsewhere())


def stop_reason() -> str:
    return _REASON["text"] if _STOP.is_set() else _elsewhere()


def wait_for_stop(timeout_s: float) -> bool:
    """Block until this process is asked to stop or ``timeout_s`` passed; True if asked."""
    return _STOP.wait(timeout_s)


@contextlib.contextmanager
def heeding(check: Callable[[], str] | None):
    """Within: this thread also stops when ``check()`` returns a reason ("" while none); None: no change."""
    before = getattr(_HEEDED, "check", None)
    _HEEDED.check = check or before
    try:
        yield
    finally:
        _HEEDED.check = before


def _elsewhere() -> str:
    check = getattr(_HEEDED, "check", None)
    return check() if check is not None else ""


def reset() -> None:
    """Forget a stop request (the next run in this process starts normally)."""
    _STOP.clear()
    _REASON["text"] = ""
