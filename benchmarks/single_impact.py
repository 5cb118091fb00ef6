"""Single-impact accuracy of the kernel's element against converged references (prints its tables; not
a test): the runs, and the tables of docs/validation.md section 4 made from them.

The cases, the block, the figures and the references: :mod:`peenflow.validation.single_impact` and
:mod:`peenflow.validation.readings`. Every run is stored: summarised in the package's
``peenflow/validation/data/single_impact.json`` (every figure and the sigma_xx(z) column; the tables
and the tests read only that), in full (with its sigma_xx(x, z) map and surface line) in the
git-ignored ``benchmarks/reference/store/single_impact.json``, which ``remetric`` needs. The full
records of the runs measured so far: ``git show research-kernels-2026-12:benchmarks/reference/hourglass.json
> benchmarks/reference/store/single_impact.json``.

Usage (from the repository root, one thread: ``NUMBA_NUM_THREADS=1``)::

    python benchmarks/single_impact.py run CASE ELEMENT H_UM [OFFSET]   # one run (physical | stiffness), stored
    python benchmarks/single_impact.py table                 # per case, each element and size against the reference
    python benchmarks/single_impact.py offsets [H_UM ...]    # the shot aimed between nodes (runs what is missing)
    python benchmarks/single_impact.py cores                 # finer cores under the shot (runs what is missing)
    python benchmarks/single_impact.py study-cores [H_UM FINE_MM [CORE_UM ...]]  # the cores a study makes (idem)
    python benchmarks/single_impact.py goals                 # issue 13 section 1 goal by goal
    python benchmarks/single_impact.py remetric              # the figures again from the full records' fields

Readings before the present ones (the stored runs were remeasured, ``remetric``, or run again): the
crest was the vertex of the parabola through the highest node and its neighbours, the dent edge a
straight line between nodes, the sigma_xx column fixed in space at |x - round(xc / 50 um) 50 um| <=
50 um; the sigma_xx peak the vertex of the parabola through the most compressive layer mid-depth and
its neighbours, the zero crossing linear between mid-depths, the profile RMS the layer values joined
by straight lines (``profile_rms(..., "lines")``, still printed beside the present one); the dent
depth the deepest node, which reads a dent whose bottom falls between nodes too shallow (25 m/s at
25 um, half an element off: -7.1 % against -4.3 % read between nodes).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from peenflow.validation import runs as validation_runs
from peenflow.validation.goals import GOALS, goals
from peenflow.validation.readings import column_profile, profile_metrics, profile_rms, surface_metrics
from peenflow.validation.single_impact import (CASES, CORES, ELEMENTS, FINE_ZONE_MM, OFFSET_SIZES, OFFSETS,
                                               QUANTITIES, STUDY_CORES, core_key, error, fine_zone_key,
                                               offset_key, reference, run, study_core_key)

ROOT = Path(__file__).resolve().parents[1]
NAME = "single_impact"


def _load() -> dict:
    return validation_runs.load(NAME)


def _store(key: str, value: dict) -> None:
    validation_runs.record(ROOT, NAME, key, value)


def error_cells(v: dict, ref: dict) -> list[str]:
    """The tables' cells of run ``v`` against ``ref``, one per :data:`QUANTITIES`: signed, relative in %
    (restitution: the difference)."""
    cells = []
    for k, _, kind in QUANTITIES:
        e = error(v, ref, k, kind)
        cells.append(f"{e:+.3f}" if kind == "abs" else f"{100 * e:+.1f} %")
    return cells


def worst_cells(runs: list[tuple[dict, dict]]) -> tuple[list[str], float]:
    """Largest |error| over ``runs`` ((run, its reference) pairs) per :data:`QUANTITIES`, as the tables'
    cells, and the largest profile RMS (:func:`profile_rms`)."""
    cells = []
    for k, _, kind in QUANTITIES:
        w = max(abs(error(v, r, k, kind)) for v, r in runs)
        cells.append(f"{w:.3f}" if kind == "abs" else f"{100 * w:.1f} %")
    return cells, max(profile_rms(v, r) for v, r in runs)



def table() -> None:
    data = _load()
    for case in CASES:
        ref, note = reference(data, case)
        if not ref:
            continue
        print(f"\n#### {case} (reference: {note})")
        print("| element | h um | " + " | ".join(q[1] for q in QUANTITIES) +
              " | profile RMS | (lines) | W_hg/W_int peak | CPU s |")
        print("|---|---|" + "---|" * (len(QUANTITIES) + 4))
        print("| reference | | " + " | ".join(
            f"{ref[k]:.4g}" for k, _, _ in QUANTITIES) + f" | | | {ref['hg_over_int']:.3f} | |")
        for element in ELEMENTS:
            for h in (60, 50, 40, 25, 12.5, 6.25):
                v = data.get(f"{case}/{element}/{h:g}")
                if v is None:
                    continue
                print(f"| {element} | {h:g} | " + " | ".join(error_cells(v, ref)) + f" | {100 * profile_rms(v, ref):.1f} % | "
                      f"{100 * profile_rms(v, ref, 'lines'):.1f} % | {v['hg_over_int']:.3f} | {v['cpu_s']:.0f} |")



def summary() -> None:
    """Largest |error| over the cases per element size and form."""
    data = _load()
    refs = {case: reference(data, case)[0] for case in CASES}
    print("\n| form | h um | cases | " + " | ".join(q[1] for q in QUANTITIES) + " | profile RMS | W_hg/W_int peak |")
    print("|---|---|---|" + "---|" * (len(QUANTITIES) + 2))
    for element in ELEMENTS:
        for h in (60, 50, 40, 25, 12.5):
            runs = [(v, ref) for case, ref in refs.items()
                    if (v := data.get(f"{case}/{element}/{h:g}")) is not None and ref]
            if runs:
                cells, rms_w = worst_cells(runs)
                hg_w = max(v["hg_over_int"] for v, _ in runs)
                print(f"| {element} | {h:g} | {len(runs)} | " + " | ".join(cells) +
                      f" | {100 * rms_w:.1f} % | {hg_w:.3f} |")




def offset_table(sizes=OFFSET_SIZES) -> None:
    """Errors of the physical element against the references when the shot lands anywhere on the
    element grid, as it does in a REV: per case and size, the mean and the range over the aims of
    :data:`OFFSETS` (all on the half model; the reference is the node-aimed 6.25 um run)."""
    data = _load()
    print("\n| case | h um | aims | " + " | ".join(q[1] for q in QUANTITIES) + " | profile RMS |")
    print("|---|---|---|" + "---|" * (len(QUANTITIES) + 1))
    worst: dict = {}
    for case in CASES:
        ref, _ = reference(data, case)
        for h in sizes:
            runs = [data[k] for k in (offset_key(case, h, o) for o in OFFSETS) if k in data]
            if not runs:
                continue
            cells = []
            for k, _, kind in QUANTITIES + (("profile_rms", "profile RMS", "rms"),):
                if kind == "rms":
                    e = np.array([profile_rms(v, ref) for v in runs])
                else:
                    e = np.array([error(v, ref, k, kind) for v in runs])
                worst.setdefault((h, k), []).extend(np.abs(e).tolist())
                if kind == "abs":
                    cells.append(f"{e.mean():+.3f} ({e.min():+.3f} … {e.max():+.3f})")
                elif kind == "rms":
                    cells.append(f"{100 * e.mean():.1f} % ({100 * e.min():.1f} … {100 * e.max():.1f})")
                else:
                    cells.append(f"{100 * e.mean():+.1f} % ({100 * e.min():+.1f} … {100 * e.max():+.1f})")
            print(f"| {case} | {h:g} | {len(runs)} | " + " | ".join(cells) + " |")
    print(f"\nWorst |error| over the {len(CASES)} cases and the four aims per element size:\n")
    print("| h um | runs | " + " | ".join(q[1] for q in QUANTITIES) + " | profile RMS |")
    print("|---|---|" + "---|" * (len(QUANTITIES) + 1))
    for h in sizes:
        if (h, "dent_um") not in worst:
            continue
        cells = []
        for k, _, kind in QUANTITIES + (("profile_rms", "profile RMS", "rms"),):
            w = max(worst[(h, k)])
            cells.append(f"{w:.3f}" if kind == "abs" else f"{100 * w:.1f} %")
        print(f"| {h:g} | {len(worst[(h, 'dent_um')])} | " + " | ".join(cells) + " |")



def cores(h_um: float = 25.0, variants=CORES) -> None:
    """A finer core under the shot on the ``h_um`` block (:func:`block`): each case with each core of
    ``variants``, stored, against the references, beside the uniform runs at ``h_um`` and at the core's
    size (docs/validation.md section 4, "A finer core under the shot")."""
    stored = set(_load())
    for case in CASES:
        for c in variants:
            if core_key(case, h_um, c) not in stored:
                _store(core_key(case, h_um, c), run(case, "physical", h_um, core=tuple(x * 1e-6 for x in c)))
    data = _load()

    def rows(case):
        out = [(f"{h_um:g} um", data.get(f"{case}/physical/{h_um:g}"))]
        out += [(f"{h_um:g} um, core {c[0]:g} um to {c[1]:g} um wide, {c[2]:g} um deep",
                 data.get(core_key(case, h_um, c))) for c in variants]
        return out + [(f"{hc:g} um", data.get(f"{case}/physical/{hc:g}"))
                      for hc in sorted({c[0] for c in variants}, reverse=True)]

    core_table(data, rows)


def core_table(data: dict, rows) -> None:
    """Per case the runs ``rows(case)`` gives ((label, stored run or None), ...) against the case's
    reference, then each label's largest |error| over the cases."""
    print("| case | mesh | elements | steps | CPU s | " + " | ".join(q[1] for q in QUANTITIES) + " | profile RMS |")
    print("|---|---|---|---|---|" + "---|" * (len(QUANTITIES) + 1))
    worst: dict = {}
    for case in CASES:
        ref, _ = reference(data, case)
        for label, v in rows(case):
            if v is None:
                continue
            worst.setdefault(label, []).append((v, ref))
            print(f"| {case} | {label} | {v.get('elements', '')} | {v.get('steps', '')} | {v['cpu_s']:.1f} | "
                  + " | ".join(error_cells(v, ref)) + f" | {100 * profile_rms(v, ref):.1f} % |")
    print(f"\nLargest |error| over the {len(CASES)} cases (node-aimed):\n")
    print("| mesh | CPU s (sum of 4) | " + " | ".join(q[1] for q in QUANTITIES) + " | profile RMS |")
    print("|---|---|" + "---|" * (len(QUANTITIES) + 1))
    for label, runs in worst.items():
        if len(runs) == len(CASES):
            cells, rms = worst_cells(runs)
            print(f"| {label} | {sum(v['cpu_s'] for v, _ in runs):.0f} | " + " | ".join(cells) + f" | {100 * rms:.1f} % |")



def study_cores(h_um: float = 25.0, sizes=STUDY_CORES, fine_mm: float = FINE_ZONE_MM) -> None:
    """The cores a study makes (``fidelity.dent_refinement = "core"``, :mod:`tasks._impact_core`:
    1.5 estimated contact radii either side of the aim, one deep, graded back to ``h_um`` within the
    block's ratio 1.2) on the ``h_um`` block with a fine zone of ``fine_mm`` (:func:`block`), each case,
    stored, against the references beside the uniform runs at ``h_um`` and at the core's size
    (docs/validation.md section 4, "The cores a study makes"). With a fine zone other than the tables' 0.3 mm
    the uncored ``h_um`` block of that fine zone is run and shown too: what the wider zone alone does."""
    stored = set(_load())
    wider = fine_mm != FINE_ZONE_MM
    command = "python benchmarks/single_impact.py study-cores" + (
        "" if (h_um, fine_mm, tuple(sizes)) == (25.0, FINE_ZONE_MM, STUDY_CORES)
        else f" {h_um:g} {fine_mm:g} " + " ".join(f"{c:g}" for c in sizes))
    for case in CASES:
        if wider and fine_zone_key(case, h_um, fine_mm) not in stored:
            out = run(case, "physical", h_um, fine_zone=fine_mm * 1e-3)
            out["command"] = command
            _store(fine_zone_key(case, h_um, fine_mm), out)
        for hc in sizes:
            if study_core_key(case, h_um, hc, fine_mm) not in stored:
                out = run(case, "physical", h_um, study_core_um=hc, fine_zone=fine_mm * 1e-3)
                out["command"] = command
                _store(study_core_key(case, h_um, hc, fine_mm), out)
    data = _load()

    def rows(case):
        out = [(f"{h_um:g} um", data.get(f"{case}/physical/{h_um:g}"))]
        if wider:
            out.append((f"{h_um:g} um, fine zone {fine_mm:g} mm", data.get(fine_zone_key(case, h_um, fine_mm))))
        for hc in sizes:
            out += [(f"{h_um:g} um, study core {hc:g} um", data.get(study_core_key(case, h_um, hc, fine_mm))),
                    (f"{hc:g} um", data.get(f"{case}/physical/{hc:g}"))]
        return out

    core_table(data, rows)



def goals_table() -> None:
    """:func:`goals` as the tables of docs/validation.md section 4, "Goal by goal"."""
    rows = goals()
    label = {"dent_um": "dent", "dent_radius_mm": "dent radius", "sxx_peak_mpa": "σxx peak",
             "zero_depth_mm": "zero crossing", "crest_radius_mm": "crest radius", "crest_height_um": "crest height",
             "restitution": "restitution", "profile_rms": "profile RMS", "hg_over_int": "W_hg / W_int peak"}

    def cell(key, e, signed=True):
        if key == "restitution":
            return f"{e:+.3f}" if signed else f"{e:.3f}"
        if key == "hg_over_int":
            return f"{e:.3f}"
        return f"{100 * e:+.1f} %" if signed and key != "profile_rms" else f"{100 * abs(e):.1f} %"

    for h in GOALS:
        sub = [r for r in rows if r["h_um"] == h]
        cores = sorted({hc for r in sub for hc in r["cores"]}, reverse=True)
        print(f"\n#### {h:g} um: the uniform block, its resolution limit and the dent cores\n")
        print("| case | figure | goal | uniform, node-aimed | worst of node + aims | resolution limit, mean / worst |"
              + "".join(f" {h:g} um + {hc:g} um core |" for hc in cores) + " verdict |")
        print("|---|---|---|---|---|---|" + "---|" * len(cores) + "---|")
        for r in sub:
            k = r["figure"]
            lim = "" if k in ("restitution", "hg_over_int") else \
                f"{100 * r['limit_mean']:.1f} / {100 * r['limit_worst']:.1f} %"
            print(f"| {r['case']} | {label[k]} | {cell(k, r['goal'], False)} | {cell(k, r['node'])} | "
                  f"{cell(k, r['worst_aim'], False)} ({r['n_aims']} aims) | {lim} |"
                  + "".join(f" {cell(k, r['cores'][hc]) if hc in r['cores'] else ''} |" for hc in cores)
                  + f" {r['verdict']} |")
        n = {v: sum(r["verdict"] == v for r in sub) for v in ("met", "resolution", "element")}
        print(f"\n{h:g} um: {len(sub)} (case, figure) goals: {n['met']} met, {n['resolution']} missed below the "
              f"reading's resolution, {n['element']} missed by the element")
        for hc in cores:
            ok = sum(abs(r["cores"][hc]) <= r["goal"] for r in sub if hc in r["cores"])
            have = sum(hc in r["cores"] for r in sub)
            print(f"  with a {hc:g} um core: {ok} of {have} within the goal")



def remetric() -> None:
    """Recompute the figures of every run in the full records from its stored surface line and sigma_xx
    map (after a change of a reading; the runs themselves are not repeated), and store them. Runs
    stored without their surface line are listed: they must be run again."""
    path = validation_runs.records_path(ROOT, NAME)
    if not path.exists():
        sys.exit(f"remetric: no full records at {path.relative_to(ROOT)}; those of the runs measured so far: "
                 "git show research-kernels-2026-12:benchmarks/reference/hourglass.json > "
                 f"{path.relative_to(ROOT)}")
    with validation_runs.locked(path):
        data = validation_runs.load_records(ROOT, NAME)
        for key, v in sorted(data.items()):
            if "surface_x_mm" not in v:
                print(f"{key}: no surface line stored, run it again")
                continue
            m = surface_metrics(np.array(v["surface_x_mm"]) * 1e-3, np.array(v["surface_uz_um"]) * 1e-6)
            v.update(m)
            if "map_mpa" in v:
                v.update(profile_metrics(*column_profile(v, v["dent_centre_mm"])))
            elif abs(v["dent_centre_mm"]) <= 1e-9:  # on the axis the stored column is the one to read
                v.update(profile_metrics(v["profile_z_mm"], v["profile_mpa"]))
            else:
                print(f"{key}: no sigma_xx map stored and the dent is off the axis: run it again")
        validation_runs.write_records(ROOT, NAME, data)
    summary_runs = _load()
    missing = sorted(set(summary_runs) - set(data))
    if missing:
        print(f"{len(missing)} summarised runs have no full record and were not remeasured (e.g. {missing[0]})")
    validation_runs.write(NAME, {**summary_runs, **data})


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="mode")
    p = sub.add_parser("run", help="one run, stored")
    p.add_argument("case", choices=list(CASES))
    p.add_argument("element", choices=list(ELEMENTS))
    p.add_argument("h_um", type=float)
    p.add_argument("offset", type=float, nargs="?", default=0.0, help="the aim, in elements off a node")
    sub.add_parser("table", help="per case, each element and size against the reference (default)")
    p = sub.add_parser("offsets", help="the shot aimed between nodes: every case at each aim (runs what is missing)")
    p.add_argument("sizes", type=float, nargs="*", help=f"element sizes um (default {OFFSET_SIZES})")
    sub.add_parser("cores", help="finer cores under the shot on the 25 um block (runs what is missing)")
    p = sub.add_parser("study-cores", help="the cores a study makes (runs what is missing)")
    p.add_argument("block", type=float, nargs="*",
                   help=f"H_UM FINE_MM [CORE_UM ...] (default 25 {FINE_ZONE_MM:g} and {STUDY_CORES})")
    sub.add_parser("goals", help="issue 13 section 1 goal by goal: uniform, resolution limit, cores")
    sub.add_parser("remetric", help="the figures again from the full records' fields")
    a = ap.parse_args(argv)
    if a.mode == "run":
        out = run(a.case, a.element, a.h_um, a.offset)
        _store(offset_key(a.case, a.h_um, a.offset) if a.offset else f"{a.case}/{a.element}/{a.h_um:g}", out)
        print(json.dumps({k: v for k, v in out.items() if not k.startswith(("profile", "map", "surface"))}, indent=1))
    elif a.mode == "offsets":
        sizes = tuple(a.sizes) or OFFSET_SIZES
        done = set(_load())  # read once; _store re-reads under its lock before each write
        for case in CASES:
            for h in sizes:
                for o in OFFSETS:
                    if offset_key(case, h, o) not in done:
                        _store(offset_key(case, h, o), run(case, "physical", h, o))
        offset_table()
    elif a.mode == "cores":
        cores()
    elif a.mode == "study-cores":
        if len(a.block) == 1:
            ap.error("study-cores: give the block's fine zone (mm) after its element size (um), e.g. "
                     "study-cores 50 0.5 12.5 6.25; or no arguments for 25 um, 0.3 mm and the default cores")
        if a.block:
            study_cores(a.block[0], tuple(a.block[2:]) or STUDY_CORES, a.block[1])
        else:
            study_cores()
    elif a.mode == "goals":
        goals_table()
    elif a.mode == "remetric":
        remetric()
    else:
        table()
        summary()


if __name__ == "__main__":
    main()
