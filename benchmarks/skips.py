"""Issue 10 §3: what each study-level skip saves, and what it costs in error (prints its figures; not a test).

Usage (from the repository root)::

    python benchmarks/skips.py ladder STUDY [FIRST MAX]   # default FIRST 10, MAX 5120
    python benchmarks/skips.py sequences STUDY TOL_MM [N_MIN]

``ladder``: for every strip point (angle, velocity) and sequence of the study
file, the strip REV run twice with the study's REV, fidelity and seeds: with
the study's own ``almen.shot_counts`` (the skip off) and with the ladder that
extends itself (``"auto"``, FIRST ... MAX, the skip on).  Prints per point the
CPU time of each (``time.process_time``: the machine is shared), the shots
and rungs run, the intensity (eq. 11, the saturation stage's fit over the
point's sequences), whether it is extrapolated, and the intensity difference
against the sequence spread.  The two runs draw different shot streams (the
"auto" stream is drawn for MAX shots), so their difference includes sequence
noise: compare it with the spread.  Cost: the whole strip sweep twice; run it
on the final kernel, not on a shared machine during other work.

``sequences``: no compute.  From a finished study's ``saturation`` results
(all of its ``almen.sequences``), replays the adaptive-sequences rule
(:func:`peenflow.methods.sequences_verdict`, tolerance TOL_MM on the standard
error of the intensity) on each point's per-sequence intensities in sequence
order, and prints the sequences it would have run (the speed-up is N / n:
every strip sequence costs about the same) and the error of the mean of those
n against the mean of all N, beside the tolerance.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import peenflow
from peenflow.methods import fit_sequences, sequences_verdict
from peenflow.study import load_study
from tasks._rev_run import run_rev
from tasks.arc_height import rung_releases
from tasks.params import LadderParams, study_params
from tasks.saturation import MODELS


def _intensity(runs, strip, model):
    """(intensity mm, extrapolated, per-sequence std mm) of a point's runs (list of run Datasets)."""
    counts = sorted({int(n) for r in runs for n in r.shots.values})
    ah = np.full((len(runs), len(counts)), np.nan)
    for s, r in enumerate(runs):
        ah[s, [counts.index(int(n)) for n in r.shots.values]] = rung_releases(
            r.z_edge_m.values, r.stress_xx_Pa.transpose("shots", "layer").values, strip)[0]
    try:
        res = fit_sequences(np.array(counts, float), ah, model)
    except ValueError as exc:  # the ladder did not saturate at all: the fixed ladder's usual failure
        print(f"    no saturation fit: {exc}")
        return float("nan"), True, float("nan")
    return res.mean_fit.intensity / 1e-3, res.mean_fit.extrapolated, res.intensity_std / 1e-3


def ladder(path, first=10, cap=5120):
    s = load_study(path)
    a = s.almen
    if a.ladder_auto:
        raise SystemExit(f"{path}: almen.shot_counts is already \"auto\"; give a study with a fixed ladder to compare")
    rev = peenflow.open_result(path, "strip_rev")  # the REV the study uses (run the study to strip_rev first)
    side, measure = float(rev.rev_side_m), float(rev.measure_side_m)
    p = study_params(s)
    strip, model = p.strip, MODELS[a.saturation_fit]
    extend = LadderParams(first, cap, a.saturation_fit, strip)
    common = dict(material=p.strip_material, shot=p.shot, fidelity=p.fidelity,
                  side_m=side, measure_side_m=measure, thickness_m=a.strip.thickness_m)
    print(f"{path}: REV {side * 1e3:.3g} mm, ladder {list(a.shot_counts)} vs auto {first}..{cap}, "
          f"{a.sequences} sequences, fit {a.saturation_fit}")
    print("angle  v m/s | fixed: cpu s  shots  I mm  extrap | auto: cpu s  shots (rungs)  I mm  extrap | "
          "dI %  spread %  speed-up")
    for angle in a.angles_deg:
        for v in a.velocities_m_s:
            out = {}
            for mode in ("fixed", "auto"):
                runs, cpu = [], time.process_time()
                for q in range(a.sequences):
                    runs.append(run_rev(None, **common, angle_deg=angle, velocity_m_s=v, seed=s.seeds.seed("almen", q),
                                        ladder=list(a.shot_counts), extend=extend if mode == "auto" else None))
                cpu = time.process_time() - cpu
                out[mode] = (cpu, sum(int(r.shots.values[-1]) for r in runs),
                             [len(r.shots) for r in runs], *_intensity(runs, strip, model))
            (cf, nf, _, i_f, xf, sd), (ca, na, ra, i_a, xa, _) = out["fixed"], out["auto"]
            print(f"{angle:5g} {v:6g} | {cf:10.1f} {nf:6d} {i_f:6.4f} {int(xf):3d}    | {ca:9.1f} {na:6d} {ra} "
                  f"{i_a:6.4f} {int(xa):3d}    | {100 * (i_a - i_f) / i_f:+6.2f} {100 * sd / i_f:7.2f} "
                  f"{cf / ca:8.2f}")


def sequences(path, tol_mm, n_min=2):
    sat = peenflow.open_result(path, "saturation")
    print(f"{path}: tolerance {tol_mm} mm on the standard error of the intensity, n_min {n_min}")
    print("angle  v m/s |  N  n used  speed-up | I(all N) mm  I(n) mm  error mm  met")
    for angle in sat.angle_deg.values:
        for v in sat.velocity_m_s.values:
            per = sat.sequence_intensity_m.sel(angle_deg=angle, velocity_m_s=v).values / 1e-3  # mm, as tol_mm
            N = per.size
            for n in range(1, N + 1):
                verdict = sequences_verdict(per[:n], tol_mm, n_min, N)
                if verdict.stop:
                    break
            full, part = np.nanmean(per), np.nanmean(per[:n])
            print(f"{angle:5g} {v:6g} | {N:2d} {n:6d} {N / n:9.2f} | {full:11.4f} {part:8.4f} {part - full:+9.4f} "
                  f"{'yes' if verdict.met else 'no'}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    p = sub.add_parser("ladder", help="each strip point with its own rungs and with the self-extending ladder")
    p.add_argument("study")
    p.add_argument("first_max", type=int, nargs="*", help="FIRST MAX rungs of the ladder (default 10 5120)")
    p = sub.add_parser("sequences", help="replay the adaptive-sequences rule on a finished study (no compute)")
    p.add_argument("study")
    p.add_argument("tol_mm", type=float)
    p.add_argument("n_min", type=int, nargs="?")
    a = ap.parse_args()
    if a.mode == "ladder":
        ladder(a.study, *a.first_max[:2])
    else:
        sequences(a.study, a.tol_mm, *([] if a.n_min is None else [a.n_min]))
