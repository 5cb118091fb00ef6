"""Signals during ``run`` / ``rerun``: the first stops at a checkpoint, the second exits now.

SIGINT (Ctrl-C), SIGTERM and SIGHUP are handled alike.  The first asks the
engine to stop (:mod:`peenflow.engine.interrupt`): no new point starts, a
REV run saves a checkpoint after its current shot and stops, and the command
exits with 128 + the signal number once the running points have returned
(seconds).  A second signal releases this process's leases and exits at
once, without a traceback; checkpoints saved before it are kept.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys

from ..engine import interrupt
from ..engine.lease import release_all_held

SIGNALS = tuple(s for s in (getattr(signal, n, None) for n in ("SIGINT", "SIGTERM", "SIGHUP")) if s is not None)


@contextlib.contextmanager
def stop_on_signals():
    """Install the handlers for the duration of a run; yields a dict whose "signal" is set once stopped."""
    got: dict = {"signal": None}

    def handler(signum, frame):
        name = signal.Signals(signum).name
        if got["signal"] is None:
            got["signal"] = signum
            interrupt.request_stop(f"{name} received")
            print(f"\n{name}: stopping -- running points save a checkpoint at their next shot and stop; "
                  "finished results are kept. Press Ctrl-C again to exit at once.", file=sys.stderr, flush=True)
            return
        n = release_all_held()
        print(f"\n{name} again: exiting now ({n} lease(s) released; the last saved checkpoints are kept; "
              "run again to resume)", file=sys.stderr, flush=True)
        os._exit(128 + got["signal"])

    previous = {s: signal.getsignal(s) for s in SIGNALS}
    for s in SIGNALS:
        signal.signal(s, handler)
    interrupt.reset()
    try:
        yield got
    finally:
        for s, h in previous.items():
            signal.signal(s, h)
        interrupt.reset()
