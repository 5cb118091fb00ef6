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
    (the headline, plots and report.html are peenflow.report's, attached by the verbs)

Each task receives only the parameters it uses -- typed, in SI, read once by
:func:`tasks.params.study_params` -- so editing one section of a study
recomputes only the stages that depend on it, and two studies that share a
section (the paper's §5 study extends its §4 study) share results.
"""

from __future__ import annotations

from pathlib import Path

from peenflow.engine import Graph, Group
from peenflow.engine.growth import Grow
from peenflow.study import StudyError, load_study
from peenflow.study.accuracy import statement as fidelity_statement
from peenflow.study.accuracy import target_error_basis, target_point_error
from peenflow.study.variants import SENSITIVITY_DIM

from ._common import SWEEP_COORDS
from .arc_height import arc_height
from .control_curve import control_curve
from .coverage_curve import coverage_curve
from .dmin import dmin
from .indentation import indentation
from .intensity_extrapolation import intensity_extrapolation
from .params import StripSweep, StudyFamily, StudyParams, requirements_params, study_family
from .process_map import process_map
from .sensitivity import sensitivity
from .suggested_settings import suggested_settings
from .verification import verified_settings, verify_runs
from .preflight import check_before_compute
from .residual_profile import residual_profile
from .rev_size import rev_size
from .rev_thickness import rev_thickness
from .saturation import saturation
from .single_impact import IMPACT_BLOCK_D, single_impact
from .strip_runs import strip_runs
from .strip_sequences import sequences_rule
from .target_runs import target_runs
from .target_velocity import target_velocity



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
    "residual_profile": "[target]: mean residual-stress profile with spread, per coverage level; the free part; "
                        "the measured profile's comparison when target.measured_profile_csv is given",
    "process_map": "[target] with lists, [targets.NAME], [sweep], coverage levels or [requirements]: the profiles "
                   "and their features over every process dimension, in one Dataset",
    "suggested_settings": "[requirements]: the settings that meet every requirement with the least of minimise",
    "verify_runs": "[requirements] verify = true: the chosen map point's REV runs to the suggested coverage "
                   "(the other points return at once)",
    "verified_settings": "[requirements] verify = true: each requirement predicted by the map and computed at "
                         "the suggestion",
    "sensitivity": "[sensitivity]: each input's change of the part's velocity and profile features against the "
                   "study as written",
}


def build_graph(path) -> Graph:
    """The graph of the study file at ``path``: read once into typed parameters (one set per combination of
    its process dimensions), checked against the kernel's limits (:mod:`tasks.preflight`), then built."""
    study = load_study(path)
    family = study_family(study)
    for (_, variant), (_, p) in zip(study.variants, family.points):
        check_before_compute(variant, p)
    return graph_for_family(family)


def graph_for(p: StudyParams) -> Graph:
    """The stage graph of a single-point study's typed parameters."""
    return graph_for_family(StudyFamily((), (({}, p),)))


def graph_for_family(f: StudyFamily) -> Graph:
    """The stage graph of a study family's typed parameters (it reads nothing else: the one door in).

    Each combination of the process dimensions is built in turn; a point that a dimension does not reach
    is one point, shared by every combination (engine.Graph.variant), and carries the values of the
    dimensions that do reach it. With process dimensions or coverage levels, ``process_map`` lays the
    profiles and their features on one grid; with ``[requirements]``, ``suggested_settings`` reads it, and with
    ``[sensitivity]``, ``sensitivity``."""
    first = f.first
    g = Graph(first.name)
    g.coord_attrs = {**SWEEP_COORDS, **{d.name: dim_attrs(d) for d in f.dims}}
    g.result_attrs = fidelity_statement(first.levels)  # what made each result, and its measured error
    finals, handles = [], []
    for coords, p in f.points:
        with g.variant(coords):
            finals.append(_add_point(g, p, handles))
            own = fidelity_statement(p.levels)
            if own != g.result_attrs:  # a swept fidelity: each point states its own
                for node in g.variant_nodes:
                    node.result_attrs.update({**own, **g.stage_result_attrs.get(node.stage, {})})
    g.settle_variants([d.name for d in f.dims])
    _check_dims_reach(f, finals)
    if first.target_plan is not None and (f.dims or len(first.target_plan.coverage_levels_percent) > 1
                                          or f.requirements is not None):
        dims = [d.name for d in f.dims]
        pmap = g.add(process_map, upstream={"profiles": Group(finals, tuple(dims))}, params={
            "dims": dims, "errors": [_point_error(p) for _, p in f.points], "error_basis": target_error_basis()})
        if f.requirements is not None:
            req = requirements_params(f.requirements, f.dims)
            sug = g.add(suggested_settings, upstream={"process_map": pmap}, params={"requirements": req})
            if f.requirements.verify:
                _add_verification(g, f, handles, sug, req)
        if any(d.name == SENSITIVITY_DIM for d in f.dims):
            g.add(sensitivity, upstream={"process_map": pmap})
    g.execution = {k: v for k, v in (("workers", first.workers), ("threads", first.threads)) if v is not None}
    unknown = set(g.stages) - set(STAGES)
    if unknown:  # a programming error: a stage added without its name in STAGES
        raise RuntimeError(f"stages missing from tasks.pipeline.STAGES: {sorted(unknown)}")
    t = first.target_plan
    g.labels = {**first.names, "coverage_percent": t.coverage_levels_percent[-1] if t is not None else None,
                "process_dims": [d.name for d in f.dims],
                "coverage_levels_percent": list(t.coverage_levels_percent) if t is not None else []}
    return g


def dim_attrs(d) -> dict:
    """CF attributes of a process dimension's coordinate (a named one: integer values, names in flag_meanings)."""
    attrs = {"units": d.units, "long_name": d.long_name, "peenflow_study_key": d.key}
    if d.labels:
        attrs["flag_values"] = list(range(len(d.values)))
        attrs["flag_meanings"] = " ".join(str(v).replace(" ", "_") for v in d.values)
    elif d.key.endswith("almen_intensity"):
        attrs["shop_notation"] = " ".join(str(v) for v in d.given)
    return attrs


def _check_dims_reach(f: StudyFamily, finals: list) -> None:
    """Every process dimension must change the study's answer: refused before compute otherwise."""
    if not f.dims:
        return
    if len({id(n) for n in finals}) == len(finals):
        return
    idle = [d for d in f.dims if not all(d.name in n.coords for n in finals)]
    keys = ", ".join(d.key for d in idle) or ", ".join(d.key for d in f.dims)
    raise StudyError(f.first.path, [f"{keys}: reaches no stage of the study's answer (every value gives the same "
                                    "points): it cannot be a dimension here; expected a key that changes a result "
                                    "of this study"])


def _point_error(p: StudyParams):
    """The point's own stated error of its profile and N_f, or None where it was not measured."""
    lv = p.levels
    core = lv.element_size_um if lv.dent_refinement == "core" and lv.dent_element_size_um is not None else None
    return target_point_error(p.names.get("target_material"), p.names.get("shot"), lv.element_size_um,
                              lv.dent_element_size_um, core)


def _add_verification(g: Graph, f: StudyFamily, handles: list, sug, req) -> None:
    """``verify_runs`` per map point and sequence (the chosen point's run to the suggested coverage) and
    ``verified_settings`` over them (:mod:`tasks.verification`)."""
    dims = [d.name for d in f.dims]
    nodes = []
    for (coords, _), h in zip(f.points, handles):
        point = {d.name: (coords[d.name] if d.labels else d.values.index(coords[d.name])) for d in f.dims}
        with g.variant(coords):
            runs = g.sweep(verify_runs, dims={"sequence": list(range(h["plan"].sequences))}, upstream={
                "suggestion": sug, "rev": h["rev"], "velocity": h["velocity"], "coverage": h["coverage"]},
                params={**h["params"], "point": point},
                point_params=lambda c, seeds=h["plan"].seeds: {"seed": seeds[c["sequence"]]})
            nodes += runs.nodes
    g.settle_variants(dims)
    g.add(verified_settings, upstream={"suggestion": sug, "runs": Group(nodes, (*dims, "sequence"))},
          params={"requirements": req})


def _add_point(g: Graph, p: StudyParams, handles: list | None = None):
    """One combination's stages; the node of its answer (``residual_profile``, or ``control_curve``);
    ``handles`` gets the target's REV, velocity, coverage and run parameters (for a verification)."""
    D = p.shot.diameter_m
    kernel = {"shot": p.shot, "fidelity": p.fidelity}
    control = final = None
    if (strips := p.strips) is not None:
        smat = {"material": p.strip_material, **kernel}
        h = p.strip.thickness_m
        if strips.rev_rule == "dmin":
            angles = list(strips.dmin_angles_deg)
            imp = g.sweep(single_impact, dims={"angle_deg": angles}, stage="strip_impact", params={
                **smat, "velocity_m_s": strips.dmin_velocity_m_s,
                "half_width_m": IMPACT_BLOCK_D * D, "thickness_m": min(h, IMPACT_BLOCK_D * D)})
            dm = g.sweep(dmin, dims={"angle_deg": angles}, upstream={"impact": imp}, stage="strip_dmin",
                         params={**smat, "thickness_m": h, "search": p.dmin})
            rev = g.add(rev_size, upstream={"dmin": dm}, stage="strip_rev", params={"rev": p.strip_rev})
            # the paper's Fig. 11: coverage on the strip REV from each angle's dent
            dent_s = g.sweep(indentation, dims={"angle_deg": angles}, upstream={"impact": imp},
                             stage="strip_indentation")
            g.sweep(coverage_curve, dims={"angle_deg": angles}, upstream={"dent": dent_s, "rev": rev},
                    stage="strip_coverage", params={"settings": p.coverage, "coverage_levels_percent": [100.0]})
        else:
            rev = g.add(rev_size, stage="strip_rev", params={"rev": p.strip_rev})
        sat = _strip_level(g, p, rev, p.fidelity)
        if p.extrapolation is not None:
            # the same strip runs at the coarse level (same seeds: paired), then each intensity to h -> 0
            coarse = _strip_level(g, p, rev, p.coarse_fidelity, prefix="coarse_")
            sat = g.sweep(intensity_extrapolation, dims=_strip_sweep(strips), upstream={"fine": sat, "coarse": coarse},
                          params={"extrapolation": p.extrapolation})
            # a one-level result says which level made it (tasks/intensity_extrapolation.py)
            fine_only = fidelity_statement(p.levels, extrapolated=False)
            coarse_only = fidelity_statement(p.levels, element_size_um=p.levels.extrapolate_intensity_from_um)
            for stage in LEVEL_STAGES:
                g.stage_result_attrs[stage] = fine_only
                g.stage_result_attrs["coarse_" + stage] = coarse_only
        control = final = g.add(control_curve, upstream={"sat": sat}, params={"interpolation": strips.interpolation})

    if (t := p.target_plan) is not None:
        angle_deg = p.target.angle_deg
        tmat = {"material": p.target_material, **kernel}
        given = p.target.velocity_m_s is not None
        vel = g.add(target_velocity, upstream={} if given else {"control": control}, params={"target": p.target})
        if t.intensity_source:  # measured strips: which fit made the intensity
            vel.result_attrs["peenflow_target_intensity_source"] = t.intensity_source
        # the dent's impact at its own element size (fidelity.dent_element_size_um; the study's by default)
        core = {} if p.dent_core_element_size_m is None else {"core_element_size_m": p.dent_core_element_size_m}
        imp_t = g.add(single_impact, upstream={"velocity": vel}, stage="target_impact", params={
            **tmat, "fidelity": p.dent_fidelity, "angle_deg": angle_deg,
            "half_width_m": IMPACT_BLOCK_D * D, "thickness_m": min(t.rev_thickness_m, IMPACT_BLOCK_D * D), **core})
        dent = g.add(indentation, upstream={"impact": imp_t}, stage="target_indentation")
        if p.levels.dent_element_size_um is not None:
            dent_level = fidelity_statement(p.levels, element_size_um=p.levels.dent_element_size_um, level="dent")
            for stage in DENT_STAGES:
                g.stage_result_attrs[stage] = dent_level
        thick_up = {}
        if t.rev_thickness_auto:
            thick_up["thickness"] = g.add(rev_thickness, upstream={"velocity": vel, "dent": dent},
                                          stage="target_rev_thickness", params={
                **tmat, "angle_deg": angle_deg,
                "half_width_m": IMPACT_BLOCK_D * D, "part_thickness_m": t.thickness_m})
        if p.target_rev.rule == "dmin":
            dm_t = g.add(dmin, upstream={"impact": imp_t}, stage="target_dmin", params={
                **tmat, "angle_deg": angle_deg,
                "thickness_m": min(t.rev_thickness_m, 2 * IMPACT_BLOCK_D * D), "search": p.dmin})
            rev_t = g.add(rev_size, upstream={"dmin": dm_t, **thick_up}, stage="target_rev",
                          params={"rev": p.target_rev})
        else:
            rev_t = g.add(rev_size, upstream=thick_up, stage="target_rev", params={"rev": p.target_rev})
        cov = g.add(coverage_curve, upstream={"dent": dent, "rev": rev_t}, params={
            "settings": p.coverage, "angle_deg": angle_deg, "coverage_levels_percent": list(t.coverage_levels_percent)})
        run_params = {**tmat, "angle_deg": angle_deg, **({"stream": p.stream} if p.stream.any else {})}
        runs_t = g.sweep(target_runs, dims={"sequence": list(range(t.sequences))},
                         upstream={"rev": rev_t, "velocity": vel, "coverage": cov}, params=run_params,
                         point_params=lambda c: {"seed": t.seeds[c["sequence"]]})
        if handles is not None:
            handles.append({"rev": rev_t, "velocity": vel, "coverage": cov, "params": run_params, "plan": t})
        # The release is that of a plate peened on one whole face; the stage
        # applies it only when the REV spans the part's thickness.
        final = g.add(residual_profile, upstream={"runs": runs_t, "velocity": vel, "coverage": cov},
                      params={"measured": p.measured, "free_part": p.plate})

    return final


#: the target stages that run at ``fidelity.dent_element_size_um`` when it is given (the dent's single
#: impact and its ellipse; target_dmin only takes its search bracket from that impact and runs its own
#: two-shot impacts at ``element_size_um``)
DENT_STAGES = ("target_impact", "target_indentation")

#: the strip stages one element size makes; a study that extrapolates its intensities runs them at a
#: coarse level too, as ``coarse_<stage>``
LEVEL_STAGES = ("strip_runs", "arc_height", "saturation")


def _strip_sweep(strips: StripSweep) -> dict:
    return {"angle_deg": list(strips.angles_deg), "velocity_m_s": list(strips.velocities_m_s)}


def _strip_level(g: Graph, p: StudyParams, rev, fidelity, prefix: str = ""):
    """strip_runs -> arc_height -> saturation at one element size (``fidelity``); the saturation sweep.

    The same seeds at every level, so two levels see the same shot streams; the parameters are those
    of a study at that element size, so a study run at it shares these results."""
    strips = p.strips
    smat = {"material": p.strip_material, "shot": p.shot, "fidelity": fidelity}
    sweep = _strip_sweep(strips)
    # the ladder extends itself (tasks/strip_runs.py), or a given one keeps its keys
    ladder = {"extend": p.ladder} if p.ladder is not None else {"shot_counts": list(strips.shot_counts)}
    # the REV runs alone see the stream's spreads (a study without them keeps the keys it had)
    spreads = {"stream": p.stream} if p.stream.any else {}
    # adaptive sequences: each point grows its sequences until the intensity's error is small enough
    grow = None if p.sequences is None else Grow("sequence", p.sequences.start, sequences_rule(p.sequences))
    runs = g.sweep(strip_runs, dims={**sweep, "sequence": list(range(strips.sequences_cap))}, upstream={"rev": rev},
                   params={**smat, **ladder, **spreads}, stage=prefix + "strip_runs",
                   point_params=lambda c: {"seed": strips.seeds[c["sequence"]]}, grow=grow)
    arc = g.sweep(arc_height, dims=sweep, upstream={"runs": runs}, params={"strip": p.strip},
                  stage=prefix + "arc_height")
    return g.sweep(saturation, dims=sweep, upstream={"arc": arc}, stage=prefix + "saturation", params={
        "fit": strips.saturation_fit, **({} if p.sequences is None else {"sequences": p.sequences})})
