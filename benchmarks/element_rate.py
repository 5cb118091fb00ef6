"""Element-pass throughput of the kernel (prints its figures; not a test;
docs/performance.md section 1).

Usage (from the repository root)::

    python benchmarks/element_rate.py throughput   # element updates/s, blocked and per-element pass, 1 and 2 threads
    python benchmarks/element_rate.py forms        # CPU s per 10^6 updates, stiffness vs physical hourglass form
    PYTHONPATH=<tree> python <tree>/benchmarks/element_rate.py ab <tree> 60x60x60 p 1 15 20   # one tree's rate

``ab`` times one element pass of the source tree ``<tree>`` (shape, ``e`` elastic or ``p`` plastic,
threads, timed passes, warm-up passes) and prints ``wall-rate cpu-rate load=... ep_mean=...`` (M
element updates/s): alternate two trees (e.g. ``git worktree add --detach /tmp/wt-base main``) in a
shell loop and compare the medians. The state
(:func:`peenflow.validation.kernel_cases.element_pass_state`) is a uniform velocity gradient;
plastic: every element yields in every pass from the ~20th on.

JIT compilation is excluded (each kernel is warmed up first). The machine's load is printed beside
every figure: the rates are only as good as the machine was idle.
"""

from __future__ import annotations

import argparse
import os
import time

import numba
import numpy as np

from peenflow.fe.element import element_rows, element_rows_parallel
from peenflow.fe.element_reference import element_pass, element_pass_parallel
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh
from peenflow.validation.kernel_cases import SAE1070, element_pass_state, loadavg

#: the arguments of an element pass after the arrays of :func:`element_pass_state`
_ARRAYS = ("x", "v", "f", "stress", "eps_p", "sy", "hg", "temp", "vol0", "mat")


def _box(shape) -> BoxMesh:
    nx, ny, nz = shape
    h = 25e-6
    return BoxMesh(np.arange(nx + 1) * h, np.arange(ny + 1) * h, np.arange(nz + 1) * h)


def _args(a: dict, mesh: BoxMesh) -> tuple:
    nnx, nny, _ = mesh.shape_nodes
    nx, ny, nz = mesh.shape_elements
    return (*(a[k] for k in _ARRAYS), 4e-9, nnx, nny, nx, ny, 0, nx, 0, ny, 0, nz)


def element_rate(shape, threads, plastic, reps=None, blocked=True):
    """Element-updates/s (M/s) of one element pass over a ``shape`` box: ``(wall, cpu)``.

    ``cpu`` divides by the process CPU time (per thread): the rate of the cores we actually got,
    less sensitive to other jobs on the machine than ``wall``. ``blocked``: the solver's pass
    (``element_rows``), else the per-element reference pass (``element_reference``).
    """
    mesh = _box(shape)
    a = element_pass_state(mesh, plastic)
    if blocked:
        fn = element_rows_parallel if threads > 1 else element_rows
    else:
        fn = element_pass_parallel if threads > 1 else element_pass
    numba.set_num_threads(threads)
    fn(*_args(a, mesh))  # warm-up (compiled already by the tiny call in throughput)
    if plastic and reps is None:
        # the stress starts at zero and reaches the yield surface in the ~20th pass; before, the
        # (deliberately low) stored flow stress sends every element into the return, which exits
        # at once. Time only passes in plastic flow.
        for _ in range(25):
            fn(*_args(a, mesh))
    reps = reps or max(3, int(2e7 / mesh.n_elements))
    t = time.perf_counter()
    c = time.process_time()
    for _ in range(reps):
        fn(*_args(a, mesh))
    dt = time.perf_counter() - t
    dc = time.process_time() - c
    n = reps * mesh.n_elements / 1e6
    return n / dt, n / dc * threads


def throughput():
    print(f"# element-updates/s (M/s), element pass only; loadavg at start {loadavg()}, {os.cpu_count()} cores")
    print("# each cell: wall-clock rate / rate per CPU-second actually received (process CPU time / threads)")
    for b in (True, False):
        for th in (1, 2):
            element_rate((4, 4, 4), th, False, 2, b)
    print("| mesh | elements | threads | blocked elastic | blocked plastic | per-element elastic | per-element plastic "
          "| load |")
    print("|---|---|---|---|---|---|---|---|")
    for shape in ((20, 20, 20), (60, 60, 60), (120, 120, 40)):
        for th in (1, 2):
            l0 = loadavg()
            r = [element_rate(shape, th, p) for p in (False, True)]
            r += [element_rate(shape, th, p, blocked=False) for p in (False, True)]
            print(f"| {shape[0]}x{shape[1]}x{shape[2]} | {np.prod(shape)} | {th} | "
                  + " | ".join(f"{w:.2f} / {c:.2f}" for w, c in r) + f" | {l0}-{loadavg()} |", flush=True)
    numba.set_num_threads(1)
    print(f"# loadavg at end {loadavg()}")


def forms(shape=(60, 60, 60), rounds=5, reps=20) -> None:
    """CPU s per million element updates of one element pass (1 thread), stiffness vs physical hourglass
    form, elastic and plastic (every element yielding), rounds interleaved; the best round of each is
    kept (CPU time of this process: what other jobs on the machine take is not counted)."""
    numba.set_num_threads(1)
    mesh = _box(shape)
    mat = Material(**{**SAE1070, "C": 0.0})
    best = {}
    for _ in range(rounds):
        for plastic in (False, True):
            for form in ("stiffness", "physical"):
                a = element_pass_state(mesh, plastic)
                # with hourglass rates: the velocity field off the uniform gradient by noise
                a["v"] = a["v"] + np.random.default_rng(0).normal(0, 1e-2, a["x"].shape)
                a["mat"] = mat.to_array(hourglass_type=form) if form == "physical" else mat.to_array()
                for _ in range(25):  # compiled, and (plastic) the stress on the yield surface
                    element_rows(*_args(a, mesh))
                c = time.process_time()
                for _ in range(reps):
                    element_rows(*_args(a, mesh))
                per = (time.process_time() - c) / (reps * mesh.n_elements / 1e6)
                best[(form, plastic)] = min(best.get((form, plastic), 1e30), per)
    print("| form | elastic CPU s / 10^6 updates | plastic CPU s / 10^6 updates |")
    print("|---|---|---|")
    for form in ("stiffness", "physical"):
        print(f"| {form} | {best[(form, False)]:.3f} | {best[(form, True)]:.3f} |")


def ab(tree: str, shape: str, kind: str, threads: int, reps: int, warm: int = 0) -> None:
    """One element-pass rate of the source tree ``tree`` (the peenflow imported must be that tree's)."""
    import peenflow

    if not peenflow.__file__.startswith(os.path.abspath(tree)):
        raise SystemExit(f"ab: peenflow is imported from {peenflow.__file__}, not from {tree}: "
                         f"run with PYTHONPATH={tree}")
    mesh = _box(tuple(int(s) for s in shape.split("x")))
    a = element_pass_state(mesh, kind == "p")
    fn = element_rows_parallel if threads > 1 else element_rows
    numba.set_num_threads(threads)
    for _ in range(max(1, warm)):
        fn(*_args(a, mesh))
    t = time.perf_counter()
    c = time.process_time()
    for _ in range(reps):
        fn(*_args(a, mesh))
    dt, dc = time.perf_counter() - t, time.process_time() - c
    n = reps * mesh.n_elements / 1e6
    print(f"{n/dt:.3f} {n/dc*threads:.3f} load={loadavg()} ep_mean={a['eps_p'].mean():.4f}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode")
    sub.add_parser("throughput", help="element updates/s of the blocked and per-element pass (default)")
    sub.add_parser("forms", help="CPU s per 10^6 updates of the stiffness and physical hourglass forms")
    p = sub.add_parser("ab", help="one source tree's element-pass rate, for interleaved A/B timing")
    p.add_argument("tree")
    p.add_argument("shape", help="NXxNYxNZ elements, e.g. 60x60x60")
    p.add_argument("kind", choices=("e", "p"), help="elastic or plastic")
    p.add_argument("threads", type=int)
    p.add_argument("reps", type=int, help="timed passes")
    p.add_argument("warm", type=int, nargs="?", default=0, help="warm-up passes")
    a = ap.parse_args(argv)
    if a.mode == "forms":
        forms()
    elif a.mode == "ab":
        ab(a.tree, a.shape, a.kind, a.threads, a.reps, a.warm)
    else:
        throughput()


if __name__ == "__main__":
    main()
