"""Issue 10 §4: the whole paper's control curves at 40 and 25 um and their paired two-level extrapolation
(prints its figures; not a test).

Usage (from the repository root, after both studies have run into ``studies/.peenflow``)::

    peenflow run studies/paper_fast.toml --workers 2 --threads 1
    peenflow run studies/paper_fast_25um.toml --workers 2 --threads 1
    PYTHONPATH=. python benchmarks/bench_whole_paper.py

The two studies use the same seeds, so every (angle, velocity) point sees the same
shot streams at both element sizes (as far as the adaptive sequences rule gave
both the same number of sequences; the rule may give one more to one of them).
Per point, ``I = I25 + (I25 - I40) 25^p / (40^p - 25^p)`` with ``p`` the mean
Richardson order of the study-level reference points (``bench_presets``: 1.72-2.0,
BENCHMARKS.md §9); the velocity for 12A on each angle's curve by the
``target_velocity`` stage's PCHIP inverse; the 67.5 deg result beside the converged
reference's 12A velocity (PCHIP through its 25 / 30 / 35 m/s points).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
from bench_presets import INTENSITY_12A_MM, OUT, STRIP_POINTS, _levels, reference_orders, study_level_errors  # noqa: E402
from bench_reference import _results, extrapolate  # noqa: E402

STUDIES = {40.0: ROOT / "studies" / "paper_fast.toml", 25.0: ROOT / "studies" / "paper_fast_25um.toml"}


def _intensities(study: Path):
    (sat,) = _results(study, "saturation")
    mm = sat.intensity_m.transpose("angle_deg", "velocity_m_s") * 1e3
    return (np.asarray(sat.angle_deg, float), np.asarray(sat.velocity_m_s, float), np.asarray(mm),
            np.asarray(sat.sequence_intensity_m.count("sequence").transpose("angle_deg", "velocity_m_s")))


def mean_order() -> float:
    """Mean Richardson order of the study-level reference points' intensities."""
    data = json.loads(OUT.read_text())
    return float(np.mean(list(reference_orders({p: _levels(data, p) for p in STRIP_POINTS}).values())))


def main() -> None:
    from peenflow.methods.control_curve import ControlCurve

    (angles, vel, i40, n40), (_, vel25, i25, n25) = (_intensities(STUDIES[h]) for h in (40.0, 25.0))
    assert np.array_equal(vel, vel25)
    p = mean_order()
    k = 25.0**p / (40.0**p - 25.0**p)
    ext = extrapolate(i40, i25, 40.0, 25.0, p)
    ref_v = study_level_errors()["reference"]["velocity_12a_m_s"]
    print(f"order p = {p:.3f} (mean of the reference points' Richardson orders); factor {k:.3f}")
    print("\n| angle | velocity m/s | 40 um mm (seq.) | 25 um mm (seq.) | extrapolated mm |")
    print("|---|---|---|---|---|")
    for a, ang in enumerate(angles):
        for v, vv in enumerate(vel):
            print(f"| {ang:g} | {vv:g} | {i40[a, v]:.4f} ({n40[a, v]}) | {i25[a, v]:.4f} ({n25[a, v]}) | "
                  f"{ext[a, v]:.4f} |")
    print("\nvelocity for 12A (0.30 mm) per angle:")
    for a, ang in enumerate(angles):
        vs = []
        for curve in (i40[a], i25[a], ext[a]):
            try:
                vs.append(float(ControlCurve(ang, vel, curve * 1e-3).velocity(INTENSITY_12A_MM * 1e-3)))
            except ValueError:
                vs.append(float("nan"))
        line = f"  {ang:g} deg: 40 um {vs[0]:.2f}, 25 um {vs[1]:.2f}, extrapolated {vs[2]:.2f} m/s"
        if abs(ang - 67.5) < 1e-9:
            line += (f"; converged reference {ref_v:.2f} m/s: " +
                     ", ".join(f"{100 * (x / ref_v - 1):+.1f} %" for x in vs))
        print(line)


if __name__ == "__main__":
    main()
