"""The methodology as a graph of stages: a study file -> a :class:`peenflow.engine.Graph`.

::

    strip_impact[angle] -> strip_dmin[angle] -> strip_rev            (almen.rev_rule = "dmin")
    strip_impact[angle] -> strip_indentation[angle] + strip_rev -> strip_coverage[angle]   (Fig. 11)
    strip_rev -> strip_runs[angle, velocity, sequence] -> arc_height[angle, velocity]
              (sequence grows per point with almen.sequence_tolerance_mm: tasks/strip_sequences.py)
              -> saturation[angle, velocity] -> control_curve
    with fidelity.extrapolate_intensity_from_um, the same chain at the coarse element size
    (coarse_strip_runs -> coarse_arc_height -> coarse_saturation), and
              saturation + coarse_saturation -> intensity_extrapolation[angle, velocity] -> control_curve
    control_curve -> target_velocity -> target_impact -> target_indentation
              (target_impact at fidelity.dent_element_size_um when given: N_f from a finer dent)
    target_impact -> target_dmin -> target_rev                       (no target.rev_size_mm)
    target_indentation + target_rev -> coverage_curve
    target_rev + target_velocity + coverage_curve -> target_runs[sequence] -> residual_profile
    after a run: plots of whatever is done (PNG) and report.html, in the store (report_dir)

Each task receives only the parameters it uses -- typed, in SI, read once by
:func:`tasks.params.study_params` -- so editing one section of a study
recomputes only the stages that depend on it, and two studies that share a
section (the paper's §5 study extends its §4 study) share results.
"""

from __future__ import annotations

from pathlib import Path

from peenflow.engine import Graph
from peenflow.engine.growth import Grow
from peenflow.study import load_study
from peenflow.study.accuracy import statement as fidelity_statement

from ._common import SWEEP_COORDS
from .arc_height import arc_height
from .control_curve import control_curve
from .cost_guard import refuse as refuse_unresolvable_or_unaffordable
from .coverage_curve import coverage_curve
from .dmin import dmin
from .headline import headline_numbers
from .indentation import indentation
from .intensity_extrapolation import intensity_extrapolation
from .params import study_params
from .plots import write_plots
from .report import write_report
from .residual_profile import residual_profile
from .rev_size import rev_size
from .rev_thickness import rev_thickness
from .saturation import saturation
from .single_impact import single_impact
from .strip_runs import strip_runs
from .strip_sequences import sequences_rule
from .target_runs import target_runs
from .target_velocity import target_velocity

#: single-impact / two-shot block: half width and depth in shot diameters
IMPACT_BLOCK_D = 2.0


#: Every stage a study can have, in dependency order, with when it runs: the
#: one list of stage names (the graph's, so `check`, `status`, `show`,
#: `rerun` and docs/study-files.md use the same names; tests keep them equal).
STAGES: dict[str, str] = {
    "strip_impact": '[almen] with rev_rule = "dmin": one shot on a strip block per d_min angle',
    "strip_dmin": '[almen] with rev_rule = "dmin": two-shot search for d_min (eq. 4) per angle',
    "strip_rev": "[almen]: the strip REV (3 d_min, the paper's 6D, or almen.rev_size_mm)",
    "strip_indentation": '[almen] with rev_rule = "dmin": the dent ellipse of each strip impact',
    "strip_coverage": '[almen] with rev_rule = "dmin": coverage curve on the strip REV (Fig. 11)',
    "strip_runs": "[almen]: strip REV runs per angle, velocity and sequence, a snapshot at every shot count",
    "arc_height": "[almen]: arc heights (eqs. 6-9) along the shot ladder",
    "saturation": "[almen]: saturation fit (eq. 10) and intensity at eq. (11)'s saturation point",
    "coarse_strip_runs": "[fidelity] extrapolate_intensity_from_um: the strip runs again at that coarser element "
                         "size, with the same shot streams",
    "coarse_arc_height": "[fidelity] extrapolate_intensity_from_um: arc heights of the coarse strip runs",
    "coarse_saturation": "[fidelity] extrapolate_intensity_from_um: saturation fits of the coarse strip runs",
    "intensity_extrapolation": "[fidelity] extrapolate_intensity_from_um: each intensity extrapolated to zero "
                               "element size from the two levels (paired sequences)",
    "control_curve": "[almen]: intensity against velocity, per angle (Fig. 17)",
    "target_velocity": "[target]: the velocity for the target intensity (or target.velocity_m_s as given)",
    "target_impact": "[target]: one shot on a block of the target material (at fidelity.dent_element_size_um "
                     "when given)",
    "target_indentation": "[target]: the dent ellipse through the pile-up crest",
    "target_rev_thickness": '[target] with rev_thickness_mm = "auto": the REV depth by a convergence check',
    "target_dmin": "[target] without rev_size_mm: two-shot search for d_min",
    "target_rev": "[target]: the target REV (3 d_min, or target.rev_size_mm)",
    "coverage_curve": "[target]: Monte-Carlo coverage, eq. (5) fit, N_f and N_c",
    "target_runs": "[target]: the final REV runs (N_c shots per sequence)",
    "residual_profile": "[target]: mean residual-stress profile with spread; the free part; the measured "
                        "profile's comparison when target.measured_profile_csv is given",
}


def build_graph(path) -> Graph:
    study = load_study(path)
    p = study_params(study)  # every stage parameter, in SI, read once
    # before any compute, opted-out bounds or not: an impact the mesh cannot resolve, a point no worker can afford
    refuse_unresolvable_or_unaffordable(path, study, p, IMPACT_BLOCK_D)
    g = Graph(study.name)
    g.coord_attrs = dict(SWEEP_COORDS)
    g.result_attrs = fidelity_statement(study.fidelity)  # what made each result, and its measured error
    D = p.shot.diameter_m
    kernel = {"shot": p.shot, "fidelity": p.fidelity}
    control = None

    if study.almen is not None:
        almen = study.almen
        smat = {"material": p.strip_material, **kernel}
        h = p.strip.thickness_m
        if almen.rev_rule == "dmin":
            angles = list(study.dmin.strip_angles_deg)
            imp = g.sweep(single_impact, dims={"angle_deg": angles}, stage="strip_impact", params={
                **smat, "velocity_m_s": study.dmin.strip_velocity_m_s,
                "half_width_m": IMPACT_BLOCK_D * D, "thickness_m": min(h, IMPACT_BLOCK_D * D)})
            dm = g.sweep(dmin, dims={"angle_deg": angles}, upstream={"impact": imp}, stage="strip_dmin",
                         params={**smat, "thickness_m": h, "search": p.dmin})
            rev = g.add(rev_size, upstream={"dmin": dm}, stage="strip_rev", params={"rev": p.strip_rev})
            # the paper's Fig. 11: coverage on the strip REV from each angle's dent
            dent_s = g.sweep(indentation, dims={"angle_deg": angles}, upstream={"impact": imp},
                             stage="strip_indentation")
            g.sweep(coverage_curve, dims={"angle_deg": angles}, upstream={"dent": dent_s, "rev": rev},
                    stage="strip_coverage", params={"settings": p.coverage, "coverage_percent": 100.0})
        else:
            rev = g.add(rev_size, stage="strip_rev", params={"rev": p.strip_rev})
        sat = _strip_level(g, study, p, rev, p.fidelity)
        if p.extrapolation is not None:
            # the same strip runs at the coarse level (same seeds: paired), then each intensity to h -> 0
            coarse = _strip_level(g, study, p, rev, p.coarse_fidelity, prefix="coarse_")
            sat = g.sweep(intensity_extrapolation, dims=_strip_sweep(study), upstream={"fine": sat, "coarse": coarse},
                          params={"extrapolation": p.extrapolation})
            # a one-level result says which level made it (tasks/intensity_extrapolation.py)
            fine_only = fidelity_statement(study.fidelity, extrapolated=False)
            coarse_only = fidelity_statement(study.fidelity, element_size_um=study.fidelity.extrapolate_intensity_from_um)
            for stage in LEVEL_STAGES:
                g.stage_result_attrs[stage] = fine_only
                g.stage_result_attrs["coarse_" + stage] = coarse_only
        control = g.add(control_curve, upstream={"sat": sat}, params={"interpolation": almen.interpolation})

    if study.target is not None:
        t = study.target
        tmat = {"material": p.target_material, **kernel}
        given = t.velocity_m_s is not None
        vel = g.add(target_velocity, upstream={} if given else {"control": control}, params={"target": p.target})
        # the dent's impact at its own element size (fidelity.dent_element_size_um; the study's by default)
        core = {} if p.dent_core_element_size_m is None else {"core_element_size_m": p.dent_core_element_size_m}
        imp_t = g.add(single_impact, upstream={"velocity": vel}, stage="target_impact", params={
            **tmat, "fidelity": p.dent_fidelity, "angle_deg": t.angle_deg,
            "half_width_m": IMPACT_BLOCK_D * D, "thickness_m": min(t.rev_thickness_m, IMPACT_BLOCK_D * D), **core})
        dent = g.add(indentation, upstream={"impact": imp_t}, stage="target_indentation")
        if study.fidelity.dent_element_size_um is not None:
            dent_level = fidelity_statement(study.fidelity, element_size_um=study.fidelity.dent_element_size_um,
                                            level="dent")
            for stage in DENT_STAGES:
                g.stage_result_attrs[stage] = dent_level
        thick_up = {}
        if t.rev_thickness_auto:
            thick_up["thickness"] = g.add(rev_thickness, upstream={"velocity": vel, "dent": dent},
                                          stage="target_rev_thickness", params={
                **tmat, "angle_deg": t.angle_deg,
                "half_width_m": IMPACT_BLOCK_D * D, "part_thickness_m": t.thickness_m})
        if p.target_rev.rule == "dmin":
            dm_t = g.add(dmin, upstream={"impact": imp_t}, stage="target_dmin", params={
                **tmat, "angle_deg": t.angle_deg,
                "thickness_m": min(t.rev_thickness_m, 2 * IMPACT_BLOCK_D * D), "search": p.dmin})
            rev_t = g.add(rev_size, upstream={"dmin": dm_t, **thick_up}, stage="target_rev",
                          params={"rev": p.target_rev})
        else:
            rev_t = g.add(rev_size, upstream=thick_up, stage="target_rev", params={"rev": p.target_rev})
        cov = g.add(coverage_curve, upstream={"dent": dent, "rev": rev_t}, params={
            "settings": p.coverage, "angle_deg": t.angle_deg, "coverage_percent": t.coverage_percent})
        runs_t = g.sweep(target_runs, dims={"sequence": list(range(t.sequences))},
                         upstream={"rev": rev_t, "velocity": vel, "coverage": cov},
                         params={**tmat, "angle_deg": t.angle_deg},
                         point_params=lambda c: {"seed": study.seeds.seed("target", c["sequence"])})
        # The release is that of a plate peened on one whole face; the stage
        # applies it only when the REV spans the part's thickness.
        g.add(residual_profile, upstream={"runs": runs_t}, params={"measured": p.measured, "free_part": p.plate})

    ex = study.execution
    g.execution = {k: v for k, v in (("workers", ex.workers), ("threads", ex.threads_per_worker))
                   if isinstance(v, int)}
    unknown = set(g.stages) - set(STAGES)
    if unknown:  # a programming error: a stage added without its name in STAGES
        raise RuntimeError(f"stages missing from tasks.pipeline.STAGES: {sorted(unknown)}")
    about = {"shot": study.shot.name,
             "strip": study.almen.strip.name if study.almen is not None else None,
             "target_material": study.target.material.name if study.target is not None else None,
             "coverage_percent": study.target.coverage_percent if study.target is not None else None}
    path = Path(study.path)
    g.headline = headline_numbers

    def plots_and_report(graph, store):
        out = report_dir(store, path)
        written = write_plots(graph, store, out, about)
        return written + [write_report(graph, store, out, path, written)]

    g.reports.append(plots_and_report)
    return g


#: the target stages that run at ``fidelity.dent_element_size_um`` when it is given (the dent's single
#: impact and its ellipse; target_dmin only takes its search bracket from that impact and runs its own
#: two-shot impacts at ``element_size_um``)
DENT_STAGES = ("target_impact", "target_indentation")

#: the strip stages one element size makes; a study that extrapolates its intensities runs them at a
#: coarse level too, as ``coarse_<stage>``
LEVEL_STAGES = ("strip_runs", "arc_height", "saturation")


def _strip_sweep(study) -> dict:
    return {"angle_deg": list(study.almen.angles_deg), "velocity_m_s": list(study.almen.velocities_m_s)}


def _strip_level(g: Graph, study, p, rev, fidelity, prefix: str = ""):
    """strip_runs -> arc_height -> saturation at one element size (``fidelity``); the saturation sweep.

    The same seeds at every level, so two levels see the same shot streams; the parameters are those
    of a study at that element size, so a study run at it shares these results."""
    almen = study.almen
    smat = {"material": p.strip_material, "shot": p.shot, "fidelity": fidelity}
    sweep = _strip_sweep(study)
    # the ladder extends itself (tasks/strip_runs.py), or a given one keeps its keys
    ladder = {"extend": p.ladder} if p.ladder is not None else {"shot_counts": list(almen.shot_counts)}
    # adaptive sequences: each point grows its sequences until the intensity's error is small enough
    grow = None if p.sequences is None else Grow("sequence", p.sequences.start, sequences_rule(p.sequences))
    runs = g.sweep(strip_runs, dims={**sweep, "sequence": list(range(almen.sequences_cap))}, upstream={"rev": rev},
                   params={**smat, **ladder}, stage=prefix + "strip_runs",
                   point_params=lambda c: {"seed": study.seeds.seed("almen", c["sequence"])}, grow=grow)
    arc = g.sweep(arc_height, dims=sweep, upstream={"runs": runs}, params={"strip": p.strip},
                  stage=prefix + "arc_height")
    return g.sweep(saturation, dims=sweep, upstream={"arc": arc}, stage=prefix + "saturation", params={
        "fit": almen.saturation_fit, **({} if p.sequences is None else {"sequences": p.sequences})})


def report_dir(store, study_path: Path) -> Path:
    """Where a study's plots (and report) go: in its store, one folder per study file.

    ``<store>/reports/<file stem>-<8 hex of the file's absolute path>``: never a
    tracked folder, and neither a copy of the study elsewhere nor another study
    run into the same ``--store`` overwrites them.
    """
    from peenflow.engine.canonical import digest

    resolved = Path(study_path).resolve()
    return Path(store.root) / "reports" / f"{resolved.stem}-{digest(str(resolved), 8)}"
