"""The one place that owns numba settings.

Every kernel function is compiled through :func:`jit` so that caching, GIL
release and fast-math policy are decided here, not scattered over modules.

* ``cache=True``: compiled code is reused across processes (dask workers).
  Numba's disk cache does not notice edits in *other* modules a function
  calls, which is why result keys fingerprint the whole kernel package
  (``peenflow.engine.fingerprint``) instead of trusting this cache.
* ``nogil=True``: kernels release the GIL so threads can overlap them.
* ``fastmath``: off by default; a caller may enable it only for a function
  where a test shows it harmless.
* ``PEENFLOW_DISABLE_JIT=1`` runs everything as plain Python (debugging).
"""

from __future__ import annotations

import os

import numba

DISABLE_JIT = os.environ.get("PEENFLOW_DISABLE_JIT", "0") == "1"

if not DISABLE_JIT:
    # Start numba's thread pool now, while the import lock serialises us: two
    # dask threads making the first call of a kernel that contains a parallel
    # section at the same moment crashed the interpreter (segfault) while both
    # launched the pool.  get_num_threads() launches it.
    numba.get_num_threads()


def jit(fn=None, *, fastmath: bool = False, parallel: bool = False, inline: str = "never"):
    """Compile ``fn`` with peenflow's numba policy (usable bare or with options)."""

    def wrap(f):
        if DISABLE_JIT:
            return f
        return numba.njit(
            cache=True,
            nogil=True,
            fastmath=fastmath,
            parallel=parallel,
            error_model="numpy",
            inline=inline,
        )(f)

    if fn is not None:
        return wrap(fn)
    return wrap
