"""A stop request that reaches the points running on a dask.distributed cluster.

The client's Ctrl-C, SIGTERM or SIGHUP sets only its own process's flag
(:mod:`.interrupt`); the points run in the workers' processes.  Each
cluster run therefore owns a dask ``Variable`` named in its points' specs:
the client sets it to "" when the run starts and :class:`StopRelay` sets it
to the stop's reason (``SIGINT received``) as soon as the client is asked
to stop.  On a worker, :func:`worker_check` reads it for the point's stop
checks, at most every :data:`POLL_S` seconds (one small scheduler call):
the point saves its checkpoint and stops as it would in a local run, and
points not yet started return at once.  A Variable, not an Event, so the
workers report the client's reason.
"""

from __future__ import annotations

import threading
import time
import uuid
from collections.abc import Callable

from . import interrupt

#: seconds between two reads of the run's stop variable by one running point
POLL_S = 0.5
#: seconds a read may wait for the scheduler before the point goes on as if no stop was asked
READ_TIMEOUT_S = 2.0


def variable_name() -> str:
    """A name no other run on the same scheduler uses."""
    return f"peenflow-stop-{uuid.uuid4().hex}"


class StopRelay:
    """On the client, for the duration of a run: passes this process's stop request to the workers."""

    def __init__(self, client, name: str):
        from distributed import Variable

        self._variable = Variable(name, client=client)
        self._done = threading.Event()
        self._thread = threading.Thread(target=self._relay, name="peenflow-stop-relay", daemon=True)

    def __enter__(self) -> StopRelay:
        self._variable.set("")
        self._thread.start()
        return self

    def _relay(self) -> None:
        # a thread, not the signal handler: a handler must not wait for the scheduler
        while not self._done.is_set():
            if interrupt.wait_for_stop(0.1):
                self._variable.set(interrupt.stop_reason())
                return

    def __exit__(self, kind, exc, tb) -> None:
        self._done.set()
        self._thread.join()
        try:
            if kind is None:  # every point has returned: nobody reads the variable any more
                self._variable.delete()
            elif not interrupt.stop_requested():
                # the client gives up (a KeyboardInterrupt without the command's handlers, an error):
                # the points it abandons stop at their next checkpoint instead of running unwatched
                self._variable.set(f"the run's client stopped ({kind.__name__})")
        except Exception:  # the scheduler went away meanwhile: nothing left to tell or tidy there
            pass


def worker_check(name: str) -> Callable[[], str]:
    """For a point on a worker: a check returning the run's stop reason, or "" while none is asked."""
    state = {"reason": "", "next": 0.0, "variable": None}

    def check() -> str:
        now = time.monotonic()
        if state["reason"] or now < state["next"]:
            return state["reason"]
        state["next"] = now + POLL_S
        try:
            if state["variable"] is None:
                from distributed import Variable

                state["variable"] = Variable(name)  # through this worker's client
            state["reason"] = state["variable"].get(timeout=READ_TIMEOUT_S) or ""
        except Exception:  # the scheduler is slow or gone: compute on rather than fail the point
            pass
        return state["reason"]

    return check
