"""Engine overhead per point: keying, leasing, writing and verifying results.

Runs a generic sweep of N trivial points (no physics: each returns a
1000-value Dataset) through the real executor twice -- once computing
everything, once reusing everything -- and prints the wall time per point.
This is the floor under every stage of a study: a strip-REV point costs
seconds to minutes of kernel time, so the engine should stay near milliseconds.

    python benchmarks/engine_overhead.py [N]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
import xarray as xr

from peenflow.engine import DirectoryStore, Graph, Reporter, execute, task


@task(version="1")
def point(*, k: int) -> xr.Dataset:
    return xr.Dataset({"v": ("i", np.full(1000, float(k)))})


@task(version="1")
def gather(pts: xr.Dataset) -> xr.Dataset:
    return xr.Dataset({"total": pts.v.sum()})


def main(n: int = 200) -> None:
    g = Graph("bench")
    sweep = g.sweep(point, dims={"k": list(range(n))})
    g.add(gather, upstream={"pts": sweep})
    with tempfile.TemporaryDirectory() as d:
        store = DirectoryStore(Path(d))
        for label in ("compute", "reuse"):
            t0 = time.perf_counter()
            out = execute(g, store, g.nodes, workers=2, reporter=Reporter(quiet=True))
            dt = time.perf_counter() - t0
            assert all(o.ok for o in out)
            print(f"{label:8s} {n + 1:5d} points  {dt:7.2f} s  {1e3 * dt / (n + 1):7.2f} ms/point")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("points", type=int, nargs="?", default=200)
    points = ap.parse_args().points
    # the engine fingerprints a task by the source of its module, and a script run as __main__ has no
    # module spec to find it by: run the tasks of this file imported as a module (its folder is on sys.path)
    import engine_overhead

    engine_overhead.main(points)
