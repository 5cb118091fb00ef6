"""How far the single-impact readings themselves are from the truth (prints its tables; not a test):
the converged 6.25 um runs' own fields taken at a coarser spacing against themselves in full, what no
element at that spacing can read closer (docs/validation.md section 4,
"The metrics on known data").

Reads only the stored runs (``peenflow/validation/data/single_impact.json``); the readings:
:mod:`peenflow.validation.readings`.

Usage (from the repository root)::

    python benchmarks/single_impact_readings.py surface    # the surface figures on every 4th node (25 um)
    python benchmarks/single_impact_readings.py profile    # the sigma_xx(z) reading on 25 um layers
"""

from __future__ import annotations

import argparse

from peenflow.validation import runs
from peenflow.validation.readings import profile_sampling_bias, sampling_bias


def surface() -> None:
    print("| 6.25 um run | dent radius um | its bias at 25 um spacing (mean / worst) um | crest radius um | "
          "its bias (mean / worst) um | dent um | its bias (mean / worst) | crest height um | "
          "its bias (mean / worst) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in sampling_bias(runs.load("single_impact")):
        print(f"| {r['run']} | {1e3 * r['dent_radius_mm']:.1f} | {r['dent_radius_bias_um']:+.1f} / "
              f"{r['dent_radius_worst_um']:.1f} | {1e3 * r['crest_radius_mm']:.1f} | "
              f"{r['crest_radius_bias_um']:+.1f} / {r['crest_radius_worst_um']:.1f} | {r['dent_um']:.2f} | "
              f"{100 * r['dent_bias']:+.1f} / {100 * r['dent_worst']:+.1f} % | {r['crest_height_um']:.2f} | "
              f"{100 * r['crest_height_bias']:+.1f} / {100 * r['crest_height_worst']:+.1f} % |")


def profile() -> None:
    print("| 6.25 um run | its sigma_xx(z) in 25 um layers: RMS, recovered curve | lines between mid-depths |")
    print("|---|---|---|")
    for r in profile_sampling_bias(runs.load("single_impact")):
        print(f"| {r['run']} | {100 * r['recovered']:.1f} % | {100 * r['lines']:.1f} % |")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    sub.add_parser("surface", help="dent and crest radius, dent depth, crest height on every 4th node")
    sub.add_parser("profile", help="the sigma_xx(z) reading on 25 um layers: recovered curve and straight lines")
    {"surface": surface, "profile": profile}[ap.parse_args(argv).mode]()


if __name__ == "__main__":
    main()
