"""What a real shot stream's scatter changes: the Almen intensity, the velocity for a target intensity and the
part's profile, with and without a size and a speed spread, beside the sequence noise (prints its figures).

Usage (from the repository root)::

    python benchmarks/shot_spread.py [STUDY] [--size PERCENT] [--speed PERCENT] [--strip-sequences N]
                                     [--target-sequences N] [--store DIR] [--workers N]

STUDY (default ``studies/quickstart.toml``) is run as a ``[sweep]`` of ``shot.diameter_spread_percent``
over [0, SIZE] and ``shot.velocity_spread_percent`` over [0, SPEED] (four streams: nominal, each spread
alone, both), with STRIP / TARGET sequences per point so that each figure has its sequence standard error.
The spreads reach the REV runs and what follows them: the single impact, the dent, N_f, the coverage
curve and the REV sizes are the nominal shot's, at the velocity each stream's control curve gives for the
target intensity (so N_f differs between the streams only through that velocity).

Prints per stream: the intensity at each control-curve velocity (mean over sequences and the standard
error of that mean), the velocity read off the control curve for the study's target intensity, and the
part's profile features (surface stress, peak compressive stress and its depth, compressive depth; mean
over sequences and standard error), with each difference to the nominal stream in units of its
combined standard error (|diff| / sqrt(se1^2 + se2^2); above 2 the spread's effect stands out of the
noise).  The store (``--store``, default a folder under ``benchmarks/reference/store``) keeps the runs, so
a second call prints again without computing.
"""

from __future__ import annotations

import argparse
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

import peenflow
from peenflow.methods.profile_features import compressive_depth

ROOT = Path(__file__).resolve().parents[1]
FEATURES = (("surface sigma_xx", "MPa"), ("peak compressive sigma_xx", "MPa"), ("its depth", "mm"),
            ("compressive depth", "mm"))


def _features(runs) -> np.ndarray:
    """(sequences, 4): each sequence's sigma_xx profile features at the study's (first) coverage level, in
    MPa and mm (``runs``: the target_runs of one stream)."""
    z = np.asarray(runs.depth_m.values).reshape(-1, runs.sizes["layer"])[0]
    out = []
    for k in range(runs.sizes["sequence"]):
        prof = runs.stress_xx_Pa.isel(sequence=k)
        if "coverage_percent" in prof.dims:
            prof = prof.isel(coverage_percent=0)
        s = prof.transpose(..., "layer").values.reshape(-1, runs.sizes["layer"])[0]
        i = int(np.argmin(s))
        depth, _ = compressive_depth(z, s)
        out.append([s[0] * 1e-6, s[i] * 1e-6, z[i] * 1e3, np.nan if depth is None else depth * 1e3])
    return np.array(out)


def _study(base: Path, size: float, speed: float, strip_seq: int, target_seq: int, folder: Path) -> Path:
    text = f'''[study]
name = "shot_spread"
description = "{base.name} with and without a shot size and speed spread"
extends = "{base.resolve()}"

[almen]
sequences = {strip_seq}
shot_counts = "auto"                  # a stream with a scatter saturates later: let each ladder extend itself
first_shots = 10
max_shots = 2560

[target]
sequences = {target_seq}

[sweep]
"shot.diameter_spread_percent" = [0.0, {size:g}]
"shot.velocity_spread_percent" = [0.0, {speed:g}]
'''
    path = folder / "shot_spread.toml"
    path.write_text(text)
    return path


def _se(values) -> tuple[float, float]:
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    return float(v.mean()), float(v.std(ddof=1) / math.sqrt(v.size)) if v.size > 1 else float("nan")


def _z(a, b) -> str:
    (ma, sa), (mb, sb) = a, b
    return f"{abs(mb - ma) / math.hypot(sa, sb):.1f}" if sa > 0 or sb > 0 else "-"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("study", nargs="?", default=str(ROOT / "studies" / "quickstart.toml"))
    ap.add_argument("--size", type=float, default=10.0, help="diameter spread, %% (default 10)")
    ap.add_argument("--speed", type=float, default=7.5, help="velocity spread, %% (default 7.5)")
    ap.add_argument("--strip-sequences", type=int, default=4)
    ap.add_argument("--target-sequences", type=int, default=3)
    ap.add_argument("--store", default=str(ROOT / "benchmarks" / "reference" / "store" / "shot_spread"))
    ap.add_argument("--workers", type=int, default=2)
    a = ap.parse_args(argv)
    folder = Path(a.store)
    folder.mkdir(parents=True, exist_ok=True)
    study = _study(Path(a.study), a.size, a.speed, a.strip_sequences, a.target_sequences, folder)
    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", "run", str(study), "--workers", str(a.workers)],
                          capture_output=True, text=True)
    if proc.returncode != 0:  # a point that failed is named; the others are still reported
        failed = [line for line in proc.stdout.splitlines() if line.strip().startswith("failed:")]
        print("points that did not finish (their cells are missing below):\n" + "\n".join(failed or [proc.stderr]))
    print(f"study: {a.study} with [sweep] diameter spread [0, {a.size:g}] %, velocity spread [0, {a.speed:g}] %; "
          f"{a.strip_sequences} strip sequences, {a.target_sequences} target sequences\n")
    sat, vel, runs = (peenflow.open_result(study, stage, allow_partial=True).load()
                      for stage in ("saturation", "target_velocity", "target_runs"))
    size_dim, speed_dim = "shot_diameter_spread_percent", "shot_velocity_spread_percent"
    streams = [(d, v) for d in (0.0, a.size) for v in (0.0, a.speed)]
    name = {(0.0, 0.0): "nominal", (a.size, 0.0): f"size {a.size:g} %", (0.0, a.speed): f"speed {a.speed:g} %",
            (a.size, a.speed): f"size {a.size:g} % + speed {a.speed:g} %"}

    def pick(ds, d, v):
        """One stream's part of a result (None where that stream's points did not finish)."""
        try:
            return ds.sel({size_dim: d, speed_dim: v})
        except KeyError:
            return None

    print("| stream | " + " | ".join(f"intensity at {float(u):g} m/s (mm)" for u in sat.velocity_m_s.values)
          + " | velocity for the target (m/s) |")
    print("|---|" + "---|" * (sat.velocity_m_s.size + 1))
    base = {}
    for d, v in streams:
        s = pick(sat, d, v)
        if s is None:
            continue
        cells = []
        for u in sat.velocity_m_s.values:
            per = s.sel(velocity_m_s=u).squeeze()
            n = int(np.isfinite(per.sequence_intensity_m.values).sum())
            stat = (float(per.intensity_m) * 1e3, float(per.intensity_std_m) * 1e3 / math.sqrt(max(n, 1)))
            base.setdefault(("I", float(u)), stat)
            cells.append(f"{stat[0]:.4f} ± {stat[1]:.4f} ({_z(base[('I', float(u))], stat)} se)")
        tv = pick(vel, d, v)
        cells.append("-" if tv is None else f"{float(tv.velocity_m_s):.2f}")
        print(f"| {name[(d, v)]} | " + " | ".join(cells) + " |")
    print("\n(mean over the sequences ± its standard error; in brackets |difference to nominal| / combined standard error)\n")
    print("| stream | " + " | ".join(f"{label} ({unit})" for label, unit in FEATURES) + " |")
    print("|---|" + "---|" * len(FEATURES))
    for d, v in streams:
        point = pick(runs, d, v)
        if point is None:
            print(f"| {name[(d, v)]} | " + " | ".join("-" for _ in FEATURES) + " |")
            continue
        per_sequence = _features(point)
        cells = []
        for k, (label, _) in enumerate(FEATURES):
            stat = _se(per_sequence[:, k])
            base.setdefault(("F", label), stat)
            cells.append(f"{stat[0]:.4g} ± {stat[1]:.2g} ({_z(base[('F', label)], stat)} se)")
        print(f"| {name[(d, v)]} | " + " | ".join(cells) + " |")
    print(f"store: {folder}")


if __name__ == "__main__":
    main()
