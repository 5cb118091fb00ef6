"""Elastic impacts against Hertz: convergence with a / h, domain extent and the target's inertia, and
the mesh layout (prints its figures; not a test; docs/validation.md section 2).

Usage (from the repository root)::

    python benchmarks/hertz.py table      # the convergence table, quarter model, frictionless
    python benchmarks/hertz.py layout     # 55 m/s: fine zone width and grading ratio
"""

from __future__ import annotations

import argparse
import time

from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots, hertz
from peenflow.validation.kernel_cases import R, loadavg


HERTZ_CASES = (
    # (speed m/s, a/h, domain extent in contact radii, target density kg/m^3)
    *((55.0, n, 25.0, 7800.0) for n in (4, 6, 8)),
    *((1.0, n, 25.0, 7800.0) for n in (4, 6, 8)),
    (1.0, 4, 100.0, 7800.0), (1.0, 4, 300.0, 7800.0),
    (20.0, 4, 25.0, 7800.0), (20.0, 4, 100.0, 7800.0), (20.0, 6, 100.0, 7800.0),
    (55.0, 4, 100.0, 7800.0), (55.0, 4, 300.0, 7800.0),
    # the target's inertia taken out: same stiffness and strains, waves 10x faster
    *((55.0, n, 100.0, 78.0) for n in (4, 6, 8)),
)


# mesh layout at 55 m/s, a/h = 4, 25 a: (fine-zone half width in a, grading ratio); the default is (2, 1.2)
HERTZ_LAYOUTS = ((2.0, 1.2), (2.0, 1.1), (4.0, 1.2), (6.0, 1.1))


def hertz_layouts(layouts=HERTZ_LAYOUTS, v=55.0, n=4, extent=25.0):
    """The 55 m/s deviation against the mesh layout (fine zone fine x a wide, 0.75 fine x a deep; grading ratio)."""
    mat = Material(E=205e9, nu=0.29, density=7800.0, A=1e13)
    print(f"# Hertz at {v:g} m/s, a/h = {n}, extent {extent:g} a: mesh layout; loadavg {loadavg()}")
    print("| fine zone / a | grading | elements | approach err | force err | restitution | wall s |")
    print("|---|---|---|---|---|---|---|")
    for fine, ratio in layouts:
        shots = Shots(centres=[[0, 0, -R - 1e-9]], velocities=[[0, 0, v]], radius=R, density=7800.0)
        ref = hertz(R, shots.mass, v, mat.E, mat.nu)
        a = ref["a"]
        ax = graded_axis(fine * a, a / n, extent * a, ratio)
        mesh = BoxMesh(ax, ax.copy(), graded_axis(0.75 * fine * a, a / n, extent * a, ratio))
        t0 = time.perf_counter()
        s = run_impacts(Target(mesh), mat, shots, Options(window=False, friction=0.0)).shots
        print(f"| {fine:g} | {ratio:g} | {mesh.n_elements} | {100*(s['max_approach'][0]/ref['delta']-1):+.2f} % | "
              f"{100*(s['peak_force'][0]/ref['F']-1):+.2f} % | {s['restitution'][0]:.4f} | "
              f"{time.perf_counter()-t0:.1f} |", flush=True)


def hertz_table(cases=HERTZ_CASES):
    print(f"# Hertz, quarter model, frictionless; loadavg {loadavg()}")
    print("| v m/s | a/h | extent / a | target density | elements | approach err | force err | radius err "
          "| duration err | restitution | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for v, n, extent, rho in cases:
        mat = Material(E=205e9, nu=0.29, density=rho, A=1e13)
        shots = Shots(centres=[[0, 0, -R - 1e-9]], velocities=[[0, 0, v]], radius=R, density=7800.0)
        ref = hertz(R, shots.mass, v, mat.E, mat.nu)
        a = ref["a"]
        ax = graded_axis(2 * a, a / n, extent * a, 1.2)
        mesh = BoxMesh(ax, ax.copy(), graded_axis(1.5 * a, a / n, extent * a, 1.2))
        t0 = time.perf_counter()
        res = run_impacts(Target(mesh), mat, shots, Options(window=False, friction=0.0))
        s = res.shots
        err = lambda got, k: 100 * (got / ref[k] - 1)
        print(f"| {v:g} | {n} | {extent:g} | {rho:g} | {mesh.n_elements} | "
              f"{err(s['max_approach'][0], 'delta'):+.2f} % | "
              f"{err(s['peak_force'][0], 'F'):+.2f} % | {err(s['contact_radius'][0], 'a'):+.2f} % | "
              f"{err(s['contact_duration'][0], 't'):+.2f} % | {s['restitution'][0]:.4f} | "
              f"{time.perf_counter()-t0:.1f} |", flush=True)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    sub.add_parser("table", help="approach, force, radius, duration against Hertz")
    sub.add_parser("layout", help="the 55 m/s deviation against the fine zone and the grading")
    {"table": hertz_table, "layout": hertz_layouts}[ap.parse_args(argv).mode]()


if __name__ == "__main__":
    main()
