"""Issue 10 §4: the whole paper's control curves extrapolated to zero element size, against the
converged references (prints its figures; not a test).

Usage (from the repository root)::

    peenflow run studies/paper_fast_extrapolated.toml --workers 2 --threads 1
    python benchmarks/whole_paper.py

The study runs every strip point at 40 and 25 um with the same seeds and extrapolates each
intensity (stage ``intensity_extrapolation``, fidelity.extrapolate_intensity_from_um); this
script reads that stage and prints, per (angle, velocity), the two levels and the extrapolated
intensity with the number of sequences each level ran; the velocity for 12A per angle from
each level's curve and from the extrapolated one (the ``target_velocity`` stage's PCHIP inverse);
and, where the study's points coincide with the study-level reference points (67.5 deg at 25 and
35 m/s, 90 deg at 55 m/s; docs/validation.md section 9), each intensity's error, and the 67.5 deg 12A
velocity's error against the converged one (PCHIP through the references' 25 / 30 / 35 m/s).
The study's seeds differ from the references', so these errors include the sequences' sampling.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from peenflow.validation.study_level import stage_results, study_level_errors, velocity_12a

ROOT = Path(__file__).resolve().parents[1]

STUDY = ROOT / "studies" / "paper_fast_extrapolated.toml"
#: (angle deg, velocity m/s) of the reference points the study's grid contains
REFERENCE_POINTS = {(67.5, 25.0): "strip_67_25", (67.5, 35.0): "strip_67_35", (90.0, 55.0): "strip_90_55"}


def main() -> None:
    ext, fine, coarse = stage_results(STUDY, "intensity_extrapolation", "saturation", "coarse_saturation")
    dims = ("angle_deg", "velocity_m_s")
    angles = np.asarray(ext.angle_deg, float)
    vel = np.asarray(ext.velocity_m_s, float)
    levels = {"40 um": np.asarray(ext.coarse_intensity_m.transpose(*dims)) * 1e3,
              "25 um": np.asarray(ext.fine_intensity_m.transpose(*dims)) * 1e3,
              "extrapolated": np.asarray(ext.intensity_m.transpose(*dims)) * 1e3}
    seqs = {k: np.asarray(ds.sequence_intensity_m.count("sequence").transpose(*dims)) for k, ds in
            (("40 um", coarse), ("25 um", fine))}
    refs = study_level_errors()["reference"]
    ref_v = refs["velocity_12a_m_s"]
    print(f"{ext.attrs['extrapolation']}; factor {ext.attrs['extrapolation_factor']:.3f}")
    print("\n| angle | velocity m/s | 40 um mm (seq.) | 25 um mm (seq.) | extrapolated mm | reference mm | error % |")
    print("|---|---|---|---|---|---|---|")
    for a, ang in enumerate(angles):
        for v, vv in enumerate(vel):
            point = REFERENCE_POINTS.get((float(ang), float(vv)))
            ref = f"{refs['intensity_mm'][point]:.4f}" if point else "-"
            err = f"{100 * (levels['extrapolated'][a, v] / refs['intensity_mm'][point] - 1):+.1f}" if point else "-"
            print(f"| {ang:g} | {vv:g} | {levels['40 um'][a, v]:.4f} ({seqs['40 um'][a, v]}) | "
                  f"{levels['25 um'][a, v]:.4f} ({seqs['25 um'][a, v]}) | {levels['extrapolated'][a, v]:.4f} | "
                  f"{ref} | {err} |")
    print("\nvelocity for 12A (0.30 mm) per angle:")
    for a, ang in enumerate(angles):
        vs = {}
        for name, table in levels.items():
            try:  # the target_velocity stage's PCHIP inverse (the angle does not enter it)
                vs[name] = velocity_12a(dict(zip(vel.tolist(), table[a].tolist())))
            except ValueError:
                vs[name] = float("nan")
        line = f"  {ang:g} deg: " + ", ".join(f"{k} {x:.2f}" for k, x in vs.items()) + " m/s"
        if abs(ang - 67.5) < 1e-9:
            line += (f"; converged reference {ref_v:.2f} m/s: "
                     + ", ".join(f"{k} {100 * (x / ref_v - 1):+.1f} %" for k, x in vs.items()))
        print(line)


if __name__ == "__main__":
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args()
    main()
