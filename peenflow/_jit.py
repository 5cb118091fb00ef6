"""The one place that owns numba settings.

Every kernel function is compiled through :func:`jit` so that caching, GIL
release and fast-math policy are decided here, not scattered over modules.

* ``cache=True``: compiled code is reused across processes (dask workers).
  Numba's disk cache checks only the source file of the function it
  caches, not the modules it calls: after an edit of ``element.py`` the
  cached ``solver.run_phase`` silently kept running the old element loop.
  So the cache lives in a folder named by a hash of every kernel source file
  (:func:`kernel_cache_dir`); any edit of the kernel starts a fresh cache.
  Result keys likewise fingerprint the whole kernel package
  (``peenflow.engine.fingerprint``).
* ``nogil=True``: kernels release the GIL so threads can overlap them.
* ``fastmath``: off by default; a caller may enable it only for a function
  where a test shows it harmless.
* ``PEENFLOW_DISABLE_JIT=1`` runs everything as plain Python (debugging).
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import numba

DISABLE_JIT = os.environ.get("PEENFLOW_DISABLE_JIT", "0") == "1"

_PACKAGE = Path(__file__).resolve().parent


def kernel_source_hash() -> str:
    """SHA-256 (16 hex) of this file, every ``peenflow/fe/*.py`` and the numba version."""
    h = hashlib.sha256(numba.__version__.encode())
    for path in [Path(__file__).resolve(), *sorted((_PACKAGE / "fe").glob("*.py"))]:
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def kernel_cache_dir() -> Path:
    """Numba cache folder for this exact kernel source.

    ``$NUMBA_CACHE_DIR`` (or ``$XDG_CACHE_HOME``, else ``~/.cache``) +
    ``peenflow-numba/<kernel_source_hash>``.  Old folders are never read again;
    delete them freely.
    """
    base = os.environ.get("NUMBA_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "peenflow-numba")
    return Path(base) / kernel_source_hash()


if not DISABLE_JIT:
    # Must be set before the first @jit below runs: numba picks a function's
    # cache locator when it is decorated.
    numba.config.CACHE_DIR = str(kernel_cache_dir())

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


def jit_twins(fn, **options):
    """``(serial, parallel)``: ``fn`` compiled by :func:`jit`, and with ``parallel=True``.

    One source for both (its ``prange`` loops run as plain ranges in the
    serial one). Numba's disk cache names a function's entries by its
    qualified name and first line, not by its compile flags, so the same
    function jitted twice would let one variant load the other's cached
    code: the parallel one is compiled from a copy of ``fn`` named
    ``<name>_parallel`` (same code object, so the same source and line).
    """
    import types

    twin = types.FunctionType(fn.__code__, fn.__globals__, f"{fn.__name__}_parallel", fn.__defaults__,
                              fn.__closure__)
    twin.__qualname__ = f"{fn.__qualname__}_parallel"
    twin.__module__ = fn.__module__
    twin.__doc__ = f"{fn.__qualname__} compiled with parallel=True (:func:`peenflow._jit.jit_twins`)."
    return jit(fn, **options), jit(twin, parallel=True, **options)
