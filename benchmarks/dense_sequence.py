"""Energy balance of a dense shot sequence: which shots exceed a per-shot energy error.

80 shots of S230 at 55 m/s, normal, landing uniformly in a 0.6 x 0.6 mm square
(the density of ~2700 shots on the paper's 3.48 mm strip REV) on a
1.8 x 1.8 x 1.29 mm SAE 1070 block; runaway detection off, no final
relaxation.  Prints the shots whose energy-balance error exceeds 5 % of the
impact energy, with their peak hourglass energy, for the default options and
for variations given as ``key=value`` Options overrides:

    python benchmarks/dense_sequence.py 50e-6 80
    python benchmarks/dense_sequence.py 50e-6 80 hourglass_plastic_floor=1.0 dt_safety=0.4

Findings in docs/validation.md section 8 ("Dense sequences").
"""

from __future__ import annotations

import argparse
import time

import numpy as np


from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots
from peenflow.validation.kernel_cases import R, SAE1070, loadavg


def dense_sequence(h: float, n: int, **options) -> None:
    half = 0.9e-3
    lat = np.linspace(-half, half, int(round(2 * half / h)) + 1)
    target = Target(BoxMesh(lat, lat.copy(), graded_axis(0.3e-3, h, 1.29e-3, 1.2)))
    rng = np.random.default_rng(0)
    centres = np.column_stack([rng.uniform(-0.3e-3, 0.3e-3, n), rng.uniform(-0.3e-3, 0.3e-3, n),
                               np.full(n, -R - 1e-6)])
    shots = Shots(centres=centres, velocities=[[0.0, 0.0, 55.0]] * n, radius=R, density=7800.0)
    t0 = time.time()
    res = run_impacts(target, Material(**SAE1070), shots,
                      Options(final_relaxation=False, runaway_fraction=1e9, **options))
    err, hg = res.shots["energy_error"], res.shots["hourglass_peak"]
    bad = np.nonzero(err > 0.05)[0]
    print(f"| {h * 1e6:.0f} | {n} | {options or 'defaults'} | "
          + (", ".join(f"{i}: {err[i]:.3f} (hg {hg[i]:.2f})" for i in bad) or "none")
          + f" | {err.max():.3f} | {res.eps_p.max():.2f} | {res.displacement[:, 2].max() * 1e6:.1f} | "
          f"{time.time() - t0:.1f} | {loadavg()} |", flush=True)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("h", type=float, help="element size m, e.g. 50e-6")
    ap.add_argument("n", type=int, help="shots")
    ap.add_argument("overrides", nargs="*", help="Options overrides KEY=VALUE, one row each")
    a = ap.parse_args()
    h, n = a.h, a.n
    overrides = [(k, float(v)) for k, v in (arg.split("=") for arg in a.overrides)]
    print("| h um | shots | options | shots with energy error > 0.05: error (peak hourglass / impact energy) "
          "| max error | max eps_p | max dent um | wall s | load |")
    print("|---|---|---|---|---|---|---|---|---|")
    dense_sequence(h, n)  # warm-up and the default row
    for key, value in overrides:
        dense_sequence(h, n, **{key: value})
