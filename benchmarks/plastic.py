"""Plastic single impacts on the box of docs/validation.md section 3: dents under refinement, the
rate term on and off, and both hourglass forms (prints its figures; not a test).

Usage (from the repository root)::

    python benchmarks/plastic.py table    # S230 on SAE 1070 at 25 / 55 m/s, 25 / 12.5 / 6.25 um, rate on / off
    python benchmarks/plastic.py forms    # both hourglass forms at 25 / 12.5 / 6.25 um, window and rate term on

The box: 1.2 x 1.2 x 0.6 mm, fine zone 0.3 x 0.3 x 0.1 mm, graded outside
(``peenflow.fe.mesh.graded_box``). The single-impact accuracy against converged references (the
6D block, no window): ``benchmarks/single_impact.py``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots, johnson_plastic
from peenflow.validation.kernel_cases import R, SAE1070, loadavg
from peenflow.validation.single_impact import ELEMENTS


def plastic_table():
    print(f"# S230 on SAE 1070, single normal impact, box 1.2 x 1.2 x 0.6 mm; loadavg {loadavg()}")
    m = 7800.0 * 4 / 3 * np.pi * R**3
    for v in (25.0, 55.0):
        j = johnson_plastic(R, m, v, 3 * SAE1070["A"])
        print(f"# Johnson fully plastic at {v} m/s: depth {j['delta']*1e6:.1f} um, diameter {2*j['a']*1e3:.3f} mm")
    print("| v m/s | rate term | h um | dent depth um | crest diameter mm | contact diameter mm | max approach um | "
          "restitution | peak force N | hourglass | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    conv = {}
    for v in (25.0, 55.0):
        for rate in (True, False):
            for h in (25e-6, 12.5e-6, 6.25e-6):
                if h < 20e-6 and not rate:
                    continue
                from peenflow.fe.mesh import graded_box
                mesh = graded_box(0.6e-3, 0.6e-3, h, fine_half_width=0.15e-3, fine_depth=0.1e-3)
                mat = Material(**{**SAE1070, "C": SAE1070["C"] if rate else 0.0})
                shots = Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, v]], radius=R, density=7800.0)
                t0 = time.perf_counter()
                res = run_impacts(Target(mesh), mat, shots, Options())
                nnx, nny, _ = mesh.shape_nodes
                uz = res.displacement[: nnx * nny, 2]
                X = res.nodes[: nnx * nny]
                # dent diameter through the pile-up crest (highest point, min u_z) along the x axis
                row = np.abs(X[:, 1]) < 1e-12
                xs, us = X[row, 0], uz[row]
                right = xs > 0
                diam = 2.0 * xs[right][np.argmin(us[right])]
                s = res.shots
                if rate:
                    conv.setdefault(v, []).append((uz.max(), s["max_approach"][0], s["restitution"][0]))
                print(f"| {v:g} | {'on' if rate else 'off'} | {h*1e6:g} | {uz.max()*1e6:.2f} | {diam*1e3:.3f} | "
                      f"{2*s['max_contact_radius'][0]*1e3:.3f} | "
                      f"{s['max_approach'][0]*1e6:.2f} | {s['restitution'][0]:.3f} | {s['peak_force'][0]:.0f} | "
                      f"{res.hourglass_ratio:.3f} | {time.perf_counter()-t0:.1f} |", flush=True)
    # Richardson extrapolation from h, h/2, h/4 (rate term on): observed order p and the h -> 0 value
    print("| v m/s | quantity | 25 / 12.5 / 6.25 um | observed order | extrapolated h -> 0 | 6.25 um vs extrapolated |")
    print("|---|---|---|---|---|---|")
    for v, rows in conv.items():
        for k, (name, scale) in enumerate((("dent depth um", 1e6), ("max approach um", 1e6), ("restitution", 1.0))):
            f1, f2, f3 = (r[k] * scale for r in rows)
            ratio = (f1 - f2) / (f2 - f3) if f2 != f3 else float("nan")
            if ratio > 1.0:
                order = np.log2(ratio)
                f0 = f3 + (f3 - f2) / (2**order - 1)
                print(f"| {v:g} | {name} | {f1:.3f} / {f2:.3f} / {f3:.3f} | {order:.2f} | {f0:.3f} | "
                      f"{100*(f3/f0-1):+.2f} % |")
            else:  # not monotone / not converging at a fixed rate: no extrapolation
                print(f"| {v:g} | {name} | {f1:.3f} / {f2:.3f} / {f3:.3f} | - | - | - |")



def hourglass_forms() -> None:
    """The setup of docs/validation.md section 3 (box 1.2 x 1.2 x 0.6 mm, fine zone 0.3 x 0.3 x 0.1 mm,
    window on, rate term on), both forms at 25 / 12.5 / 6.25 um: the physical element against the
    stiffness form's 6.25 um dent reference there (6.05 / 13.46 um extrapolated)."""
    from peenflow.fe.mesh import graded_box

    mat = Material(**SAE1070)  # the rate term on
    print("| v m/s | form | 25 / 12.5 / 6.25 um dent um | order | extrapolated | restitution 25 / 12.5 / 6.25 |")
    print("|---|---|---|---|---|---|")
    for v in (25.0, 55.0):
        for form, opts in ELEMENTS.items():
            dents, rest = [], []
            for h in (25e-6, 12.5e-6, 6.25e-6):
                mesh = graded_box(0.6e-3, 0.6e-3, h, fine_half_width=0.15e-3, fine_depth=0.1e-3)
                shots = Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, v]], radius=R, density=7800.0)
                res = run_impacts(Target(mesh), mat, shots, Options(**opts))
                nnx, nny, _ = mesh.shape_nodes
                dents.append(res.displacement[: nnx * nny, 2].max() * 1e6)
                rest.append(res.shots["restitution"][0])
            f1, f2, f3 = dents
            ratio = (f1 - f2) / (f2 - f3) if f2 != f3 else float("nan")
            order, f0 = (np.log2(ratio), f3 + (f3 - f2) / (ratio - 1)) if ratio > 1 else (float("nan"),) * 2
            print(f"| {v:g} | {form} | {f1:.2f} / {f2:.2f} / {f3:.2f} | {order:.2f} | {f0:.2f} | "
                  + " / ".join(f"{r:.3f}" for r in rest) + " |", flush=True)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    sub.add_parser("table", help="plastic dents at 25 / 55 m/s: refinement, rate term on and off")
    sub.add_parser("forms", help="the stiffness and physical hourglass forms on the same box")
    {"table": plastic_table, "forms": hourglass_forms}[ap.parse_args(argv).mode]()


if __name__ == "__main__":
    main()
