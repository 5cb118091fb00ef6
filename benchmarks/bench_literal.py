"""Issue 10 §5: the paper's §4 procedure run literally, beside ours (prints its figures; not a test).

Usage (from the repository root)::

    peenflow run studies/paper_literal_40um.toml --workers 2 --threads 1 --until target_velocity
    peenflow run studies/paper_fast_extrapolated.toml --workers 2 --threads 1
    PYTHONPATH=. python benchmarks/bench_literal.py

The literal study peens the paper's strip REV (6D x 6D, symmetric lateral faces, 2D x 2D
measuring region) through the paper's ladder N = 10 ... 480, fits eq. (10) to those rungs and
solves eq. (11) wherever it lands. Ours (studies/paper_fast_extrapolated.toml) peens a periodic
1.2 mm REV measured over its whole face through a ladder that extends itself until eq. (11)'s
saturation point T has a rung at >= 2 T, at 40 um and at 25 um with the same seeds, and
extrapolates each intensity to zero element size. Printed, on the 67.5 deg curve (the paper's
12A curve): per velocity each procedure's intensity, the literal one's saturation point T against
its last rung (480) and its mean arc height at 480 shots; then the velocity for 12A (0.30 mm) of
each, the converged reference's (BENCHMARKS.md §9) and the paper's 47 m/s, and the differences
read as the steps from the paper's procedure to the converged one: the literal procedure at
40 um -> ours at 40 um (ladder and REV together, the same mesh), ours at 40 um -> ours
extrapolated (the mesh), ours extrapolated -> the converged reference (sampling and the
extrapolation's error).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
from bench_presets import INTENSITY_12A_MM, study_level_errors, velocity_12a  # noqa: E402
from bench_reference import _results  # noqa: E402

LITERAL = ROOT / "studies" / "paper_literal_40um.toml"
OURS = ROOT / "studies" / "paper_fast_extrapolated.toml"
ANGLE_DEG = 67.5
PAPER_12A_M_S = 47.0
LITERAL_LAST_RUNG = 480


def _curve(ds, var="intensity_m") -> dict[float, float]:
    """{velocity m/s: intensity mm} of the 67.5 deg points of a saturation-like Dataset."""
    da = ds[var].sel(angle_deg=ANGLE_DEG) if "angle_deg" in ds[var].dims else ds[var]
    return {float(v): float(x) * 1e3 for v, x in zip(np.asarray(da.velocity_m_s), np.asarray(da))}


def _v12a(curve: dict[float, float]) -> str:
    try:
        return f"{velocity_12a(curve):.2f}"
    except ValueError:  # 0.30 mm outside the curve: say on which side
        side = "below" if min(curve.values()) > INTENSITY_12A_MM else "above"
        return f"{side} {min(curve) if side == 'below' else max(curve):g} (out of the curve)"


def main() -> None:
    (lit,) = _results(LITERAL, "saturation")
    ext, fine, coarse = _results(OURS, "intensity_extrapolation", "saturation", "coarse_saturation")
    lit_i = _curve(lit)
    sel = lambda var: lit[var].sel(angle_deg=ANGLE_DEG) if "angle_deg" in lit[var].dims else lit[var]  # noqa: E731
    t = dict(zip(lit_i, np.asarray(sel("saturation_shots"), float)))
    at_last = dict(zip(lit_i, np.asarray(sel("mean_arc_height_m").sel(shots=LITERAL_LAST_RUNG), float) * 1e3))
    spread = dict(zip(lit_i, np.asarray(sel("intensity_std_m"), float) * 1e3))
    nseq = dict(zip(lit_i, np.asarray(sel("sequence_intensity_m").count("sequence"))))
    curves = {"literal 40 um": lit_i, "ours 40 um": _curve(coarse), "ours 25 um": _curve(fine),
              "ours extrapolated": _curve(ext)}
    refs = study_level_errors()["reference"]
    ref_v = refs["velocity_12a_m_s"]

    print(f"67.5 deg control curve, intensity mm (literal: 6D x 6D REV, N <= {LITERAL_LAST_RUNG}, eq. (11) "
          "extrapolated; ours: periodic 1.2 mm, saturated inside its ladder)\n")
    print("| velocity m/s | literal: intensity (seq., spread) | literal: T shots | literal: Ah(480) | "
          "ours 40 um | ours 25 um | ours extrapolated |")
    print("|---|---|---|---|---|---|---|")
    for v in sorted(lit_i):
        print(f"| {v:g} | {lit_i[v]:.4f} ({nseq[v]}, ± {spread[v]:.4f}) | {t[v]:.0f} | {at_last[v]:.4f} | "
              + " | ".join(f"{curves[k].get(v, float('nan')):.4f}" for k in list(curves)[1:]) + " |")
    print("\nvelocity for 12A (0.30 mm), m/s:")
    v12 = {k: _v12a(c) for k, c in curves.items()}
    for k, x in v12.items():
        print(f"  {k}: {x}")
    print(f"  converged reference: {ref_v:.2f}\n  paper: {PAPER_12A_M_S:g}")
    num = {k: float(x) for k, x in v12.items() if x.replace(".", "", 1).isdigit()}
    if {"literal 40 um", "ours 40 um", "ours extrapolated"} <= set(num):
        print("\nsteps, m/s:")
        print(f"  paper -> literal 40 um (what our kernel and material data do with the paper's "
              f"procedure): {num['literal 40 um'] - PAPER_12A_M_S:+.2f}")
        print(f"  literal 40 um -> ours 40 um (ladder and REV): {num['ours 40 um'] - num['literal 40 um']:+.2f}")
        print(f"  ours 40 um -> ours extrapolated (mesh): {num['ours extrapolated'] - num['ours 40 um']:+.2f}")
        print(f"  ours extrapolated -> converged reference: {ref_v - num['ours extrapolated']:+.2f}")


if __name__ == "__main__":
    main()
