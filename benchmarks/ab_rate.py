"""One element-pass rate of a given source tree, for interleaved A/B timing (prints wall and CPU-time M/s).

Usage (run from outside the trees so that PYTHONPATH picks the tree)::

    PYTHONPATH=<tree> python <tree>/benchmarks/ab_rate.py <tree> 60x60x60 p 1 15 20
    #                                                     shape  e|p threads timed-passes warm-up-passes

Alternate two trees (e.g. ``git worktree add --detach /tmp/wt-base main``) in a shell loop and
compare medians; the benchmark state of ``bench_kernel.py`` (plastic: yields from the ~20th pass).
"""
import sys, os, time
tree = sys.argv[1]
sys.path.insert(0, os.path.join(tree, "benchmarks"))
import numpy as np, numba
import bench_kernel as bk
import peenflow
assert peenflow.__file__.startswith(tree), peenflow.__file__
shape = tuple(int(s) for s in sys.argv[2].split("x"))
plastic = sys.argv[3] == "p"
th = int(sys.argv[4])
reps = int(sys.argv[5])
warm = int(sys.argv[6]) if len(sys.argv) > 6 else 0
from peenflow.fe.element import element_rows, element_rows_parallel
from peenflow.fe.mesh import BoxMesh
nx, ny, nz = shape
h = 25e-6
mesh = BoxMesh(np.arange(nx + 1) * h, np.arange(ny + 1) * h, np.arange(nz + 1) * h)
a = bk._pass_arrays(mesh, plastic)
nnx, nny, _ = mesh.shape_nodes
fn = element_rows_parallel if th > 1 else element_rows
numba.set_num_threads(th)
args = lambda: (a["x"], a["v"], a["f"], a["stress"], a["eps_p"], a["sy"], a["hg"], a["temp"], a["vol0"],
                a["mat"], 4e-9, nnx, nny, nx, ny, 0, nx, 0, ny, 0, nz)
for _ in range(max(1, warm)):
    fn(*args())
t = time.perf_counter(); c = time.process_time()
for _ in range(reps):
    fn(*args())
dt = time.perf_counter() - t; dc = time.process_time() - c
n = reps * mesh.n_elements / 1e6
print(f"{n/dt:.3f} {n/dc*th:.3f} load={bk.loadavg()} ep_mean={a['eps_p'].mean():.4f}")
