"""Study-level references: a strip point, or the section 5 target, refined until its intensity and
profile stop changing (prints its figures; not a test).

Usage (from the repository root)::

    python benchmarks/study_reference.py run POINT LEVEL [LEVEL ...]
    python benchmarks/study_reference.py dent POINT H [H ...]
    python benchmarks/study_reference.py table [POINT]

A LEVEL is an element size in um (``25``), or an element size and a REV side in mm
(``60@2.4``: the same point on a larger periodic REV, measured over its whole face:
the REV-size convergence of issue 10 §3), or for the target an element size and a
number of sequences (``16s1``: its first sequence only -- the same shot stream as
every level's first sequence, so the levels compare paired on it at half the cost).
Any LEVEL may name a window of W contact radii (``40w0``: 40 um with every impact integrated
on the whole mesh, ``fidelity.window_contact_radii = 0``: the window against the full mesh).

A target LEVEL may also name the element size of its dent (``25d6.25s1``: REV at 25 um, the
single impact whose dent gives N_f and N_c at 6.25 um, ``fidelity.dent_element_size_um``): levels
with the same dent run the same number of shots, so they compare the REV's mesh at a fixed N.
``dent POINT H ...`` runs the target only up to its coverage curve at each element size H and
records the dent ellipse, N_f and N_c (key ``POINT/dent/H``); ``HcC`` (``25c6.25``) runs the single
impact on the H um block with a core of C um elements under the impact (``fidelity.dent_element_size_um
= C``, ``dent_refinement = "core"``; key ``POINT/dent/HcC``).

POINT is a study file stem under ``benchmarks/reference/studies/``: a strip point
(``strip_90_55``, ``strip_67_25``/``30``/``35``) or the §5 target (``al7075_30``: a study
with ``[target]`` and no ``[almen]``, run up to ``residual_profile``; its figures are the
mean sigma_xx(z) profile's surface value, peak, peak depth and zero crossing, the dent,
N_c and the REV depth).  ``run`` writes a copy of the study with ``[fidelity]
element_size_um = H`` per level into ``benchmarks/reference/store/<POINT>/``
(git-ignored; the results store is there too, so a killed run resumes where it
stopped, across sessions), runs ``peenflow run --until saturation`` on it with
one worker and one thread, and stores the level's figures in the package's summary
``peenflow/validation/data/study_level.json`` (:mod:`peenflow.validation.runs`): the intensity
(eq. 11 on the sequence-mean curve) and per-sequence intensities, saturation points, the
sigma_xx(z) profile figures of the measuring region (mean over sequences) at every rung (surface
value, peak, peak depth, zero crossing), the process CPU time of the run (``RUSAGE_CHILDREN``:
the machine may be shared), and the kernel's code fingerprint.  Every level uses the same seeds,
so the meshes see the same shot streams: differences between levels are paired, with little of
the sequences' sampling noise in them.

``table`` prints, per point, each level's figures and their difference from
the finest level, and a Richardson extrapolation from the three finest
levels where they converge monotonically with an observed order in [0.5, 4]
(ratios of element sizes need not be equal: the order solves
(f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p)).  Profiles are compared
at the largest rung every level reached.  The errors each element size gives a study:
``benchmarks/presets.py``.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from peenflow.validation import runs
from peenflow.validation.study_level import (dent_level_name, level_name, level_window, parse_dent_level,
                                             parse_level, profile_figures, richardson, stage_results)

ROOT = Path(__file__).resolve().parents[1]
STUDIES = ROOT / "benchmarks" / "reference" / "studies"
STORE = ROOT / "benchmarks" / "reference" / "store"
PROFILE_DEPTH_M = 0.5e-3


def _level_study(point: str, h_um: float, side_mm: float | None = None, sequences: int | None = None,
                 dent_um: float | None = None, window: float | None = None) -> Path:
    text = (STUDIES / f"{point}.toml").read_text()
    lines, section = [], ""
    for ln in text.splitlines():
        key = ln.split("#")[0].strip()
        if key.startswith("["):
            section = key
        if key.startswith("element_size_um"):
            ln = f"element_size_um = {h_um!r}"
            if dent_um is not None:  # the target's dent (N_f, N_c) from a single impact at its own size
                ln += f"\ndent_element_size_um = {dent_um!r}"
            if window is not None:  # the window against the full mesh (0: every impact on the whole mesh)
                ln += f"\nwindow_contact_radii = {window!r}"
        elif side_mm is not None and key.startswith(("rev_size_mm", "measure_size_mm")):
            ln = f"{key.split('=')[0].strip()} = {side_mm!r}"
        elif sequences is not None and section == "[target]" and key.startswith("sequences"):
            ln = f"sequences = {sequences}"  # a level of the first N sequences only (paired with the others')
        lines.append(ln)
    d = STORE / point
    d.mkdir(parents=True, exist_ok=True)
    path = d / f"h{level_name(h_um, side_mm, sequences, dent_um, window)}.toml"
    new = "\n".join(lines) + "\n"
    if not path.exists() or path.read_text() != new:
        path.write_text(new)
    return path



def _collect(study: Path) -> dict:
    """A strip level's figures from its study's store: the intensity and its sequences', the
    saturation point, the profile figures at every rung all sequences reached, the code fingerprint."""
    sat, strip = stage_results(study, "saturation", "strip_runs")
    sq = lambda a: np.asarray(a).squeeze()  # noqa: E731 - the point's length-1 sweep dims
    z_edges = sq(strip.z_edge_m)
    z_edges = z_edges.reshape(-1, z_edges.shape[-1])[0]
    zc = 0.5 * (z_edges[:-1] + z_edges[1:])
    depth = zc if zc[0] >= 0 else -zc
    if depth[0] > depth[-1]:
        depth = depth.max() - depth  # depth below the top face
    sxx = strip.stress_xx_Pa.transpose(..., "sequence", "shots", "layer")
    sxx = np.asarray(sxx).reshape(-1, sxx.shape[-2], sxx.shape[-1]) if sxx.ndim > 3 else np.asarray(sxx)
    shots = [int(n) for n in np.asarray(strip.shots)]
    mean = np.nanmean(sxx, axis=0)  # (shots, layer)
    order = np.argsort(depth)
    profiles = {str(n): profile_figures(depth[order], mean[k][order])
                for k, n in enumerate(shots) if np.all(np.isfinite(sxx[:, k]))}  # every sequence reached it
    fp = strip.attrs.get("peenflow_source_hash") or strip.attrs.get("peenflow_code", "")  # covers the kernel
    mm = 1e3  # the store is SI; the summary's figures are in mm
    return {
        "intensity_mm": float(sq(sat.intensity_m)) * mm,
        "intensity_extrapolated": int(sq(sat.intensity_extrapolated)),
        "saturation_shots": float(sq(sat.saturation_shots)),
        "sequence_intensity_mm": (np.atleast_1d(sq(sat.sequence_intensity_m)) * mm).tolist(),
        "profiles": profiles,
        "code": str(fp),
    }


def _collect_target(study: Path) -> dict:
    prof, cov, thick = stage_results(study, "residual_profile", "coverage_curve", "target_rev_thickness")
    sq = lambda a: float(np.asarray(a).squeeze())  # noqa: E731
    depth = np.asarray(prof.depth_m)
    order = np.argsort(depth)
    mean = np.asarray(prof.stress_xx_mean_Pa)[order]
    per_seq = np.asarray(prof.stress_xx_Pa.transpose("sequence", "layer"))[:, order]
    entry = {**profile_figures(depth[order], mean),
             "z_mm": (depth[order] * 1e3).round(6).tolist(),
             "sequence_sxx_MPa": (per_seq / 1e6).round(4).tolist(),
             "sequence_peak_MPa": [float(r.min() / 1e6) for r in per_seq],
             "peak_yy_MPa": sq(prof.peak_compressive_yy_Pa) / 1e6,
             "coverage_shots": sq(cov.coverage_shots_rounded),
             "full_coverage_shots": sq(cov.full_coverage_shots),
             "rev_thickness_mm": sq(thick.thickness_m) * 1e3}
    fp = prof.attrs.get("peenflow_source_hash") or prof.attrs.get("peenflow_code", "")
    entry["code"] = str(fp)
    return entry


def _is_target(point: str) -> bool:
    """A reference study with ``[target]`` and no ``[almen]`` (run up to ``residual_profile``)."""
    sections = {ln.strip() for ln in (STUDIES / f"{point}.toml").read_text().splitlines()}
    return "[target]" in sections and "[almen]" not in sections



def _commit() -> str:
    return subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip()


def _store(key: str, entry: dict) -> None:
    """Store ``entry`` under ``key`` in the summary (:func:`peenflow.validation.runs.update`)."""
    runs.update("study_level", key, entry)


def _load() -> dict:
    return runs.load("study_level")


def run(point: str, levels: list[str]) -> None:
    for level in levels:
        h, side, seqs, dent = parse_level(level)
        win = level_window(level)
        study = _level_study(point, h, side, seqs, dent, win)
        t0, c0 = time.time(), resource.getrusage(resource.RUSAGE_CHILDREN)
        target = _is_target(point)
        cmd = [sys.executable, "-m", "peenflow.cli", "run", str(study),
               "--until", "residual_profile" if target else "saturation",
               "--workers", "1", "--threads", "1", "--quiet"]
        print("$", " ".join(cmd), flush=True)
        proc = subprocess.run(cmd, capture_output=True, text=True)
        c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        print(proc.stdout[-3000:], proc.stderr[-3000:], flush=True)
        if proc.returncode != 0:
            print(f"level {level} did not finish (rc {proc.returncode}); run again to resume")
            return
        entry = _collect_target(study) if target else _collect(study)
        key = f"{point}/{level_name(h, side, seqs, dent, win)}"
        prev = _load().get(key, {})
        # CPU of this call; a resumed level keeps the sum of its calls
        cpu = (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)
        entry["cpu_s"] = prev.get("cpu_s", 0.0) + cpu if prev.get("code") == entry["code"] else cpu
        entry["wall_s"] = time.time() - t0
        entry["command"] = f"python benchmarks/study_reference.py run {point} {level}"
        entry["rev_side_mm"] = side if side is not None else _template_side(point)
        entry["date"] = time.strftime("%Y-%m-%d")
        entry["commit"] = _commit()
        _store(key, entry)
        if target:
            print(f"{key}: peak {entry['peak_MPa']:.1f} MPa at {entry['peak_depth_mm']:.3f} mm, "
                  f"N_c {entry['coverage_shots']:.0f}, CPU {entry['cpu_s']:.0f} s")
        else:
            print(f"{key}: intensity {entry['intensity_mm']:.4f} mm, T {entry['saturation_shots']:.0f}, "
                  f"CPU {entry['cpu_s']:.0f} s")


def _template_side(point: str) -> float:
    for ln in (STUDIES / f"{point}.toml").read_text().splitlines():
        if ln.split("#")[0].strip().startswith("rev_size_mm"):
            return float(ln.split("=")[1].split("#")[0])
    return float("nan")



def table(only: str | None = None) -> None:
    data = _load()
    points = sorted({k.split("/")[0] for k in data if only in (None, k.split("/")[0])})
    for point in points:
        if "intensity_mm" not in next(v for k, v in data.items() if k.startswith(point + "/")):
            _target_table(point, data)
            continue
        # mesh levels on the study's own REV; larger-REV levels (h@side) in a table of their own
        levels = sorted(((float(k.split("/")[1]), v) for k, v in data.items()
                         if k.startswith(point + "/") and not set(k.split("/")[1]) & set("@w")), reverse=True)
        windows = sorted((k.split("/")[1], v) for k, v in data.items() if k.startswith(point + "/") and "w" in k)
        sides = sorted((k.split("/")[1], v) for k, v in data.items() if k.startswith(point + "/") and "@" in k)
        common = set.intersection(*(set(v["profiles"]) for _, v in levels))
        rung = str(max(int(n) for n in common)) if common else None
        print(f"\n#### {point} (profile at N = {rung})")
        print("| h um | intensity mm | per sequence | T shots | surface MPa | peak MPa | peak depth mm | "
              "zero crossing mm | CPU s | code |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for h, v in levels:
            pm = v["profiles"].get(rung, {}) if rung else {}
            print(f"| {h:g} | {v['intensity_mm']:.4f}{' (extrap.)' if v['intensity_extrapolated'] else ''} | "
                  + ", ".join(f"{x:.4f}" for x in v["sequence_intensity_mm"])
                  + f" | {v['saturation_shots']:.0f} | {pm.get('surface_MPa', float('nan')):.0f} | "
                  f"{pm.get('peak_MPa', float('nan')):.0f} | {pm.get('peak_depth_mm', float('nan')):.3f} | "
                  f"{pm.get('zero_depth_mm', float('nan')):.3f} | {v['cpu_s']:.0f} | {v['code'][:12]} |")
        if sides:
            print("\nREV side (periodic, whole face measured) at fixed element size; profile at N = T of each:")
            print("| level | side mm | intensity mm | per sequence | T shots | CPU s |")
            print("|---|---|---|---|---|---|")
            for name, v in [(f"{h:g}", v) for h, v in levels] + sides:
                print(f"| {name} | {v.get('rev_side_mm', float('nan')):g} | {v['intensity_mm']:.4f} | "
                      + ", ".join(f"{x:.4f}" for x in v["sequence_intensity_mm"])
                      + f" | {v['saturation_shots']:.0f} | {v['cpu_s']:.0f} |")
        if windows:
            print("\nThe window against the full mesh (wW: W contact radii, w0: every impact on the whole mesh):")
            print("| level | intensity mm | per sequence | T shots | against the point's own window | CPU s |")
            print("|---|---|---|---|---|---|")
            own = dict(levels)
            for name, v in windows:
                base = own.get(parse_level(name)[0])
                diff = f"{100 * (v['intensity_mm'] / base['intensity_mm'] - 1):+.2f} %" if base else ""
                print(f"| {name} | {v['intensity_mm']:.4f} | " + ", ".join(f"{x:.4f}" for x in v["sequence_intensity_mm"])
                      + f" | {v['saturation_shots']:.0f} | {diff} | {v['cpu_s']:.0f} |")
        if len(levels) >= 3:
            hs = [h for h, _ in levels[-3:]]
            quantities = [("intensity_mm", lambda v: v["intensity_mm"])]
            if rung:
                for q in ("surface_MPa", "peak_MPa", "peak_depth_mm", "zero_depth_mm"):
                    quantities.append((q, lambda v, q=q: v["profiles"][rung][q]))
            for name, get in quantities:
                fs = [get(v) for _, v in levels[-3:]]
                ext, p = richardson(hs, fs)
                finest = fs[-1]
                if ext is None:
                    print(f"- {name}: {', '.join(f'{f:.4g}' for f in fs)} at {', '.join(f'{h:g}' for h in hs)} um: "
                          "not monotone or order outside [0.5, 4]: the finest value is the reference")
                else:
                    print(f"- {name}: Richardson {ext:.4g} (order {p:.2f}); finest level {finest:.4g} "
                          f"({100 * (finest / ext - 1):+.1f} %)")


def _target_table(point: str, data: dict) -> None:
    named = sorted(((parse_level(k.split("/")[1]), k.split("/")[1], v) for k, v in data.items()
                    if k.startswith(point + "/") and k.count("/") == 1),
                   key=lambda t: (-(t[0][1] or 0.0), -t[0][0], -(t[0][3] or t[0][0])))
    def finest(name: str) -> float:  # "25c6.25": the 25 um block with a 6.25 um core
        block, core = parse_dent_level(name)
        return block if core is None else core

    dents = sorted(((k.split("/")[2], v) for k, v in data.items() if k.startswith(point + "/dent/")),
                   key=lambda t: (-finest(t[0]), "c" in t[0]))
    if dents:
        print(f"\n#### {point}: the dent, N_f and N_c against the single impact's element size "
              "(H cC: the H um block with a core of C um elements under the impact)")
        print("| h um | semi-axes um | dent depth um | pile-up um | N_f | N_c | CPU s |")
        print("|---|---|---|---|---|---|---|")
        for name, v in dents:
            print(f"| {name.replace('c', ' c')} | {v['semi_axis_along_um']:.1f} x {v['semi_axis_across_um']:.1f} | {v['dent_depth_um']:.2f} | "
                  f"{v['pileup_height_um']:.2f} | {v['full_coverage_shots']:.1f} | {v['coverage_shots']:.0f} | "
                  f"{v['cpu_s']:.0f} |")
    print(f"\n#### {point} (target profile, mean of the sequences; level H dD: REV at H um, dent at D um)")
    print("| level | surface MPa | peak MPa | per sequence | peak depth mm | zero crossing mm | "
          "sigma_yy peak MPa | N_c | REV depth mm | CPU s | code |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for _, name, v in named:
        print(f"| {name} | {v['surface_MPa']:.0f} | {v['peak_MPa']:.0f} | "
              + ", ".join(f"{x:.0f}" for x in v["sequence_peak_MPa"])
              + f" | {v['peak_depth_mm']:.3f} | {v['zero_depth_mm']:.3f} | {v['peak_yy_MPa']:.0f} | "
              f"{v['coverage_shots']:.0f} | {v['rev_thickness_mm']:.2f} | {v['cpu_s']:.0f} | {v['code'][:12]} |")
    # Richardson over the levels whose dent is at their own element size
    levels = [(lv[0], v) for lv, _, v in named if lv[1] is None and lv[3] is None]
    if len(levels) >= 3:
        hs = [h for h, _ in levels[-3:]]
        for q in ("surface_MPa", "peak_MPa", "peak_depth_mm", "zero_depth_mm", "peak_yy_MPa"):
            fs = [v[q] for _, v in levels[-3:]]
            ext, p = richardson(hs, fs)
            if ext is None:
                print(f"- {q}: {', '.join(f'{f:.4g}' for f in fs)} at {', '.join(f'{h:g}' for h in hs)} um: "
                      "not monotone or order outside [0.5, 4]: the finest value is the reference")
            else:
                print(f"- {q}: Richardson {ext:.4g} (order {p:.2f}); finest level {fs[-1]:.4g} "
                      f"({100 * (fs[-1] / ext - 1):+.1f} %)")

def dent(point: str, sizes: list[str]) -> None:
    """The target's dent ellipse, N_f and N_c at each element size (the study run ``--until
    coverage_curve``): what ``fidelity.dent_element_size_um`` takes from a finer single impact.

    The REV thickness of each level study is the part's (what ``"auto"`` gives the single impact's
    block), so no REV-depth check runs; the coverage curve uses the same seeds at every size."""
    for text in sizes:
        h, core = parse_dent_level(text)
        name = dent_level_name(h, core)
        study = _level_study(point, h, dent_um=core)
        body = study.read_text()
        if core is not None:
            body = body.replace(f"dent_element_size_um = {core!r}",
                                f'dent_element_size_um = {core!r}\ndent_refinement = "core"')
        part = next(ln.split("=")[1].split("#")[0].strip() for ln in body.splitlines()
                    if ln.strip().startswith("thickness_mm"))
        body = body.replace('rev_thickness_mm = "auto"', f"rev_thickness_mm = {part}")
        path = study.parent / "dent" / f"h{name}.toml"
        path.parent.mkdir(parents=True, exist_ok=True)
        if not path.exists() or path.read_text() != body:
            path.write_text(body)
        c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cmd = [sys.executable, "-m", "peenflow.cli", "run", str(path), "--until", "coverage_curve",
               "--workers", "1", "--threads", "1", "--quiet"]
        print("$", " ".join(cmd), flush=True)
        proc = subprocess.run(cmd, capture_output=True, text=True)
        c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        if proc.returncode != 0:
            print(proc.stdout[-3000:], proc.stderr[-3000:], f"dent level {text} did not finish", flush=True)
            return
        cov, ind, imp = stage_results(path, "coverage_curve", "target_indentation", "target_impact")
        sq = lambda a: float(np.asarray(a).squeeze())  # noqa: E731
        entry = {"full_coverage_shots": sq(cov.full_coverage_shots), "coverage_shots": sq(cov.coverage_shots_rounded),
                 "semi_axis_along_um": sq(ind.dent_semi_axis_along_m) * 1e6,
                 "semi_axis_across_um": sq(ind.dent_semi_axis_across_m) * 1e6,
                 "dent_depth_um": sq(ind.dent_depth_m) * 1e6, "pileup_height_um": sq(ind.pileup_height_m) * 1e6,
                 "cpu_s": (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime),
                 "code": str(imp.attrs.get("peenflow_source_hash") or imp.attrs.get("peenflow_code", "")),
                 "command": f"python benchmarks/study_reference.py dent {point} {text}",
                 "date": time.strftime("%Y-%m-%d"), "commit": _commit()}
        _store(f"{point}/dent/{name}", entry)
        print(f"{point} dent at {name} um: N_f {entry['full_coverage_shots']:.2f}, N_c {entry['coverage_shots']:.0f}, "
              f"semi-axes {entry['semi_axis_along_um']:.1f} x {entry['semi_axis_across_um']:.1f} um, "
              f"CPU {entry['cpu_s']:.0f} s", flush=True)


def main(argv=None) -> None:
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="mode", required=True)
    p = sub.add_parser("run", help="run levels of a point up to its saturation / residual profile, stored")
    p.add_argument("point", help="a study file stem under benchmarks/reference/studies/")
    p.add_argument("levels", nargs="+", help="H[@SIDE][dHD][sN]")
    p = sub.add_parser("dent", help="the target's single impact (dent, N_f, N_c) at element sizes, stored")
    p.add_argument("point")
    p.add_argument("sizes", nargs="+", help="H or HcC (a core of C um in the H um block)")
    p = sub.add_parser("table", help="each point's levels and their Richardson limits")
    p.add_argument("point", nargs="?")
    a = ap.parse_args(argv)
    os.chdir(ROOT)
    if a.mode == "run":
        run(a.point, a.levels)
    elif a.mode == "dent":
        dent(a.point, a.sizes)
    else:
        table(a.point)


if __name__ == "__main__":
    main()
