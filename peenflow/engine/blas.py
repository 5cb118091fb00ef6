"""One BLAS thread in every process that computes points, local or on a dask worker.

A BLAS reduction (a dot product, a least-squares fit) sums in an order that
depends on its thread count, so the same inputs give results that differ in
the last bits on 1 and on 2 threads.  dask workers run BLAS on one thread
while a plain local process uses every core: a cluster run then differed from
a local one by ~1e-6 relative, and so did every downstream content hash and
key.  Pinning BLAS to one thread everywhere makes them bit-identical.  It
costs little: the heavy compute is the numba kernel, whose threads are the
engine's to choose (cores.py) and whose results do not depend on them; BLAS
only serves small fits and solves.

threadpoolctl changes the thread count of the BLAS libraries already loaded,
so the project's numeric libraries are imported first.
"""

from __future__ import annotations

BLAS_THREADS = 1


def pin_blas_threads() -> int:
    """Limit every loaded BLAS library to :data:`BLAS_THREADS`; returns that count.

    Process-wide (BLAS libraries have one setting per process) and idempotent:
    called before every task, so a library a previous task loaded is pinned too.
    """
    import numpy  # noqa: F401  (loads its BLAS)
    import scipy.linalg  # noqa: F401  (scipy ships a BLAS of its own)
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=BLAS_THREADS, user_api="blas")
    return BLAS_THREADS
