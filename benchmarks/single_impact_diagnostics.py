"""Where the single impact's remaining errors come from (prints its tables; not a test; every run is
made here and not stored): friction and the 45 deg profile, the normal dents' elastic recovery,
thinner surface layers (docs/validation.md section 4, "Why the 45° profile misses",
"What the normal dents miss", "Thinner surface layers").

The cases and the figures: :mod:`peenflow.validation.single_impact`, :mod:`peenflow.validation.readings`;
the references: the stored runs (``peenflow/validation/data/single_impact.json``).

Usage (from the repository root, one thread: ``NUMBA_NUM_THREADS=1``)::

    python benchmarks/single_impact_diagnostics.py friction [CASE]  # the 45 deg (or CASE's) hump with and without friction
    python benchmarks/single_impact_diagnostics.py recovery   # normal dents: approach against recovery
    python benchmarks/single_impact_diagnostics.py variants   # thinner top layers, 20 um

``friction`` also lists the hump of every stored 45 deg run, from the full records
(``benchmarks/reference/store/single_impact.json``, benchmarks/single_impact.py); without them that
part is left out.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from peenflow.validation import runs
from peenflow.validation.readings import column_profile, profile_rms
from peenflow.validation.single_impact import CASES, QUANTITIES, error, friction, reference, run

ROOT = Path(__file__).resolve().parents[1]


HUMP_X_MM = np.arange(-0.100, 0.1501, 0.025)  # column centres along the stream for :func:`hump`


def hump(v: dict) -> tuple[float, float]:
    """Where along the stream (x mm) the most compressive sigma_xx column of a run's map is, and its
    peak (MPa): the column mean of :func:`column_profile` centred every 25 um."""
    peaks = [column_profile(v, x)[1].min() for x in HUMP_X_MM]
    i = int(np.argmin(peaks))
    return float(HUMP_X_MM[i]), float(peaks[i])


def friction_hump(case: str = "sae-55-45") -> None:
    """An oblique case with and without friction at 25 and 12.5 um (runs not stored), and the hump of
    every stored run of it: where friction puts the compressive zone, against the element size
    (docs/validation.md section 4, "Why the 45° profile misses"); and the friction's share of each impact
    (:func:`peenflow.validation.single_impact.friction`: friction / normal impulse from the shot's spin,
    the contact point's slip at separation, and the rigid sphere's)."""
    ref, _ = reference(runs.load("single_impact"), case)
    print(f"# {case}")
    print("| friction | h um | hump x mm (MPa) | dent centre um | dent | σxx peak | profile RMS against the "
          "reference (friction 0.2) | vout_x m/s | friction / normal impulse | slip at separation m/s (rigid) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for mu in (0.0, 0.2):
        for h in (25.0, 12.5):
            v = run(case, "physical", h, friction=mu)
            x, p = hump(v)
            f = friction(v, case, mu)
            print(f"| {mu:g} | {h:g} | {x:.3f} ({p:.0f}) | {v['dent_centre_mm'] * 1e3:.1f} | {v['dent_um']:.2f} um | "
                  f"{v['sxx_peak_mpa']:.0f} MPa | {100 * profile_rms(v, ref):.1f} % | {v['vout_x']:.2f} | "
                  f"{f['ratio']:.4f} | {f['slip_out']:.2f} ({f['slip_rigid']:.2f}) |", flush=True)
    full = runs.load_records(ROOT, "single_impact")
    if not full:
        print(f"\n(no full records at {runs.records_path(ROOT, 'single_impact').relative_to(ROOT)}: the stored "
              "runs' humps need their sigma_xx maps; see benchmarks/single_impact.py)")
        return
    print("\n| stored run | hump x mm (MPa) |\n|---|---|")
    for key in sorted(k for k in full if k.startswith(f"{case}/") and "offset" not in k):
        x, p = hump(full[key])
        print(f"| {key} | {x:.3f} ({p:.0f}) |")


def recovery(cases=("sae-25-90", "sae-55-90"), sizes=(50.0, 25.0, 12.5, 6.25)) -> None:
    """Where a normal dent's error comes from (runs not stored; quarter model, node-aimed): the shot's
    largest approach (its lowest point's travel into the target, um), the residual dent read between
    nodes, the elastic recovery between them, the peak force and the contact radius (Hertz-equivalent
    sqrt(5/2 <r^2>) of the nodal normal impulses at peak force; and the outermost contact node's radius)
    (docs/validation.md section 4, "What the normal dents miss")."""
    print("| case | h um | max approach um | residual dent um | recovery um | peak force N | "
          "contact radius um (Hertz-equivalent / outermost node) | CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    for case in cases:
        for h in sizes:
            v = run(case, "physical", h)
            print(f"| {case} | {h:g} | {v['max_approach_um']:.3f} | {v['dent_um']:.3f} | "
                  f"{v['max_approach_um'] - v['dent_um']:.3f} | {v['peak_force_n']:.1f} | "
                  f"{v['contact_radius_um']:.1f} / {v['max_contact_radius_um']:.1f} | {v['cpu_s']:.1f} |", flush=True)


def variants() -> None:
    """Mesh variants at about the 25 um cost, not stored: the 25 um block with thinner top layers
    (depth / thickness um) and a uniform 20 um mesh, all on the half model, node-aimed, against the references
    (docs/validation.md section 4, "Thinner surface layers")."""
    data = runs.load("single_impact")
    rows = [("sae-55-45", None), ("sae-55-45", (25, 12.5)), ("sae-55-45", (50, 12.5)), ("sae-55-45", (100, 12.5)),
            ("sae-55-45", (150, 12.5)), ("sae-55-45", (50, 6.25))]
    rows += [(c, layers) for c in ("sae-25-90", "sae-55-90", "al-47-65") for layers in (None, (50, 12.5))]
    print("| case | mesh | steps | CPU s | dent | σxx peak | zero crossing | profile RMS | crest radius | restitution |")
    print("|---|---|---|---|---|---|---|---|---|---|")

    def line(case, label, v):
        ref, _ = reference(data, case)
        e = {k: error(v, ref, k, kind) for k, _, kind in QUANTITIES}
        print(f"| {case} | {label} | {v['steps']} | {v['cpu_s']:.1f} | {100 * e['dent_um']:+.1f} % | "
              f"{100 * e['sxx_peak_mpa']:+.1f} % | {100 * e['zero_depth_mm']:+.1f} % | {100 * profile_rms(v, ref):.1f} % | "
              f"{100 * e['crest_radius_mm']:+.1f} % | {e['restitution']:+.3f} |", flush=True)

    for case, layers in rows:  # all on the half model, so that steps and CPU compare
        sl = (0.0, 25e-6) if layers is None else (layers[0] * 1e-6, layers[1] * 1e-6)
        v = run(case, "physical", 25.0, surface_layers=sl)
        line(case, "25 um" if layers is None else f"25 um, top {layers[0]:g} um in {layers[1]:g} um layers", v)
    for case in CASES:
        line(case, "20 um", run(case, "physical", 20.0, surface_layers=(0.0, 20e-6)))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    p = sub.add_parser("friction", help="an oblique case with and without friction at 25 and 12.5 um")
    p.add_argument("case", nargs="?", default="sae-55-45", choices=[c for c, (_, _, a) in CASES.items() if a != 90.0])
    sub.add_parser("recovery", help="normal dents: largest approach, residual dent, recovery, contact")
    sub.add_parser("variants", help="thinner top layers and a uniform 20 um mesh at about the 25 um cost")
    a = ap.parse_args(argv)
    if a.mode == "friction":
        friction_hump(a.case)
    else:
        {"recovery": recovery, "variants": variants}[a.mode]()


if __name__ == "__main__":
    main()
