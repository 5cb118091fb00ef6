"""Every schema key takes effect or is refused (issue 9 item 1; the complement
of test_docs.py).

For each field of each study-file model, a change to another valid value must
change the parameters (and so the result key) of at least one stage of the
graph; keys that only describe (names, descriptions, sources) or only steer
execution ([execution]: results are bit-identical on any number of workers
and threads) are listed with that reason. A new field fails this test until
it is classified here."""

from __future__ import annotations

import copy
import json

import pytest

import peenflow.api
from peenflow.study import Almen, Coverage, Dmin, Execution, Fidelity, Seeds, ShotSection, Target
from peenflow.study import JohnsonCook, Material, Shot, Strip
from peenflow.study.fidelity import REMOVED_KEYS
from peenflow.study.loader import validate_study

from .conftest import DELETE, base_study, set_path, to_toml

MAT = "materials.Al7075-T73"
STRIP_MAT = "materials.SAE1070"
EXPLICIT_REVS = {"almen.rev_rule": "explicit", "almen.rev_size_mm": 3.5, "target.rev_size_mm": 4.5}

# field -> (changes that make the base study use it, the change under test)
CHANGES = {
    "ShotSection.type": ({}, {"shot.type": "S330"}),
    "ShotSection.friction_coefficient": ({}, {"shot.friction_coefficient": 0.3}),
    "ShotSection.diameter_spread_percent": ({}, {"shot.diameter_spread_percent": 10.0}),
    "ShotSection.velocity_spread_percent": ({}, {"shot.velocity_spread_percent": 5.0}),
    "Almen.strip": ({}, {"almen.strip": "N", "target.almen_intensity": "12N"}),
    "Almen.angles_deg": ({}, {"almen.angles_deg": [45.0, 90.0]}),
    "Almen.velocities_m_s": ({}, {"almen.velocities_m_s": [25.0, 35.0, 45.0]}),
    "Almen.shot_counts": ({}, {"almen.shot_counts": [10, 20, 40, 160]}),
    "Almen.first_shots": ({"almen.shot_counts": "auto", "almen.first_shots": 10}, {"almen.first_shots": 20}),
    "Almen.max_shots": ({"almen.shot_counts": "auto", "almen.max_shots": 640}, {"almen.max_shots": 1280}),
    "Almen.sequences": ({}, {"almen.sequences": 3}),
    # adaptive sequences: the saturation stage records the rule it was grown by (tasks/strip_sequences.py)
    "Almen.sequence_tolerance_mm": ({"almen.sequences": 2}, {"almen.sequence_tolerance_mm": 0.004}),
    "Almen.max_sequences": ({"almen.sequences": 2, "almen.sequence_tolerance_mm": 0.004},
                            {"almen.max_sequences": 8}),
    "Almen.rev_rule": ({}, {"almen.rev_rule": "paper"}),
    "Almen.rev_size_mm": (EXPLICIT_REVS, {"almen.rev_size_mm": 3.0}),
    "Almen.measure_size_mm": ({**EXPLICIT_REVS, "almen.measure_size_mm": 1.0}, {"almen.measure_size_mm": 1.1}),
    "Almen.saturation_fit": ({}, {"almen.saturation_fit": "exponential_2p"}),
    "Almen.interpolation": ({}, {"almen.interpolation": "linear"}),
    "Almen.allow_extrapolated_intensity": ({}, {"almen.allow_extrapolated_intensity": True}),
    "Dmin.strip_velocity_m_s": ({}, {"dmin.strip_velocity_m_s": 50.0}),
    "Dmin.strip_angles_deg": ({}, {"dmin.strip_angles_deg": [67.5, 90.0]}),
    "Dmin.threshold": ({}, {"dmin.threshold": 0.06}),
    "Dmin.resolution_D": ({}, {"dmin.resolution_D": 0.1}),
    "Dmin.resolution_mm": ({}, {"dmin.resolution_mm": 0.02}),
    "Dmin.min_distance_D": ({}, {"dmin.min_distance_D": 1.2}),
    "Dmin.max_distance_D": ({}, {"dmin.max_distance_D": 5.0}),
    "Dmin.method": ({}, {"dmin.method": "scan"}),
    "Coverage.grid_points": ({}, {"coverage.grid_points": 61}),
    "Coverage.shot_counts": ({}, {"coverage.shot_counts": [10, 100, 1000]}),
    "Coverage.max_shots": ({}, {"coverage.max_shots": 2000}),
    "Coverage.sequences": ({}, {"coverage.sequences": 3}),
    "Coverage.full_coverage_percent": ({}, {"coverage.full_coverage_percent": 95.0}),
    "Target.material": ({}, {"target.material": "SAE1070"}),
    "Target.thickness_mm": ({}, {"target.thickness_mm": 8.0}),
    "Target.angle_deg": ({}, {"target.angle_deg": 60.0}),
    "Target.almen_intensity": ({}, {"target.almen_intensity": "14A"}),
    "Target.almen_intensity_mm": ({"target.almen_intensity": DELETE, "target.almen_intensity_mm": 0.3,
                                   "target.almen_strip": "A"}, {"target.almen_intensity_mm": 0.35}),
    "Target.almen_strip": ({"target.almen_intensity": DELETE, "target.almen_intensity_mm": 0.3,
                            "target.almen_strip": "A"}, {"target.almen_strip": "N", "almen.strip": "N"}),
    "Target.velocity_m_s": ({"target.almen_intensity": DELETE, "target.velocity_m_s": 45.0},
                            {"target.velocity_m_s": 50.0}),
    "Target.coverage_percent": ({}, {"target.coverage_percent": 150.0}),
    "Target.sequences": ({}, {"target.sequences": 3}),
    "Target.control_angle_rule": ({}, {"target.control_angle_rule": "interpolate"}),
    "Target.rev_size_mm": ({"target.rev_size_mm": 4.5}, {"target.rev_size_mm": 5.0}),
    "Target.measure_size_mm": ({"target.rev_size_mm": 4.5, "target.measure_size_mm": 1.5},
                               {"target.measure_size_mm": 1.4}),
    "Target.rev_thickness_mm": ({}, {"target.rev_thickness_mm": 3.0}),
    "Target.measured_profile_csv": ({}, {"target.measured_profile_csv": "measured.csv"}),
    "Target.almen_strips_csv": ({"target.almen_intensity": DELETE, "target.almen_strips_csv": "strips_a.csv",
                                 "target.almen_strip": "A"}, {"target.almen_strips_csv": "strips_b.csv"}),
    "Fidelity.preset": ({}, {"fidelity.preset": "standard"}),
    "Fidelity.element_size_um": ({}, {"fidelity.element_size_um": 50.0}),
    "Fidelity.fine_depth_D": ({}, {"fidelity.fine_depth_D": 0.9}),
    "Fidelity.fine_depth_mm": ({}, {"fidelity.fine_depth_mm": 0.5}),
    "Fidelity.grading_ratio": ({}, {"fidelity.grading_ratio": 1.1}),
    "Fidelity.time_step_safety": ({}, {"fidelity.time_step_safety": 0.7}),
    "Fidelity.window_contact_radii": ({}, {"fidelity.window_contact_radii": 5.0}),
    "Fidelity.settle_tolerance": ({}, {"fidelity.settle_tolerance": 1e-5}),
    "Fidelity.relaxation_tolerance": ({}, {"fidelity.relaxation_tolerance": 1e-7}),
    "Fidelity.lateral_boundary": (EXPLICIT_REVS, {"fidelity.lateral_boundary": "periodic"}),
    # the base study is at 60 um: a coarser level, outside the validated range on purpose
    "Fidelity.extrapolate_intensity_from_um": ({"fidelity.element_size_um": 25.0},
                                               {"fidelity.extrapolate_intensity_from_um": 40.0}),
    "Fidelity.intensity_extrapolation_order": ({"fidelity.element_size_um": 25.0,
                                                "fidelity.extrapolate_intensity_from_um": 40.0},
                                               {"fidelity.intensity_extrapolation_order": 2.0}),
    "Fidelity.dent_element_size_um": ({"fidelity.element_size_um": 25.0}, {"fidelity.dent_element_size_um": 12.5}),
    "Fidelity.dent_refinement": ({"fidelity.element_size_um": 25.0, "fidelity.dent_element_size_um": 12.5},
                                 {"fidelity.dent_refinement": "core"}),
    "Seeds.base": ({}, {"seeds.base": 8}),
    "Material.youngs_modulus_GPa": ({}, {f"{MAT}.youngs_modulus_GPa": 72.0}),
    "Material.poisson_ratio": ({}, {f"{MAT}.poisson_ratio": 0.32}),
    "Material.density_kg_m3": ({}, {f"{MAT}.density_kg_m3": 2850.0}),
    "JohnsonCook.A_MPa": ({}, {f"{MAT}.johnson_cook.A_MPa": 440.0}),
    "JohnsonCook.B_MPa": ({}, {f"{MAT}.johnson_cook.B_MPa": 310.0}),
    "JohnsonCook.C": ({}, {f"{MAT}.johnson_cook.C": 0.01}),
    "JohnsonCook.n": ({}, {f"{MAT}.johnson_cook.n": 0.4}),
    "JohnsonCook.m": ({f"{MAT}.johnson_cook.room_temperature_K": 293.0,
                       f"{MAT}.johnson_cook.melt_temperature_K": 893.0}, {f"{MAT}.johnson_cook.m": 1.0}),
    "JohnsonCook.reference_strain_rate_1_s": ({f"{MAT}.johnson_cook.C": 0.01},
                                              {f"{MAT}.johnson_cook.reference_strain_rate_1_s": 10.0}),
    "JohnsonCook.room_temperature_K": ({f"{MAT}.johnson_cook.m": 1.0, f"{MAT}.johnson_cook.room_temperature_K": 293.0,
                                        f"{MAT}.johnson_cook.melt_temperature_K": 893.0},
                                       {f"{MAT}.johnson_cook.room_temperature_K": 300.0}),
    "JohnsonCook.melt_temperature_K": ({f"{MAT}.johnson_cook.m": 1.0, f"{MAT}.johnson_cook.room_temperature_K": 293.0,
                                        f"{MAT}.johnson_cook.melt_temperature_K": 893.0},
                                       {f"{MAT}.johnson_cook.melt_temperature_K": 900.0}),
    "Shot.diameter_mm": ({}, {"shots.S230.diameter_mm": 0.6}),
    "Shot.density_kg_m3": ({}, {"shots.S230.density_kg_m3": 7600.0}),
    "Strip.material": ({}, {"strips.A.material": "Al7075-T73"}),
    "Strip.width_mm": ({}, {"strips.A.width_mm": 18.0}),
    "Strip.thickness_mm": ({}, {"strips.A.thickness_mm": 1.2}),
    "Strip.gauge_span_mm": ({}, {"strips.A.gauge_span_mm": 30.0}),
}

# fields that change no result by design, and why
NO_RESULT = {
    "Execution.workers": "execution only: results are bit-identical on any number of workers",
    "Execution.threads_per_worker": "execution only: results are bit-identical on 1 and 2 threads",
    "Fidelity.overrides": "bookkeeping of the resolved preset, not a key",
    "Material.johnson_cook": "a table: its fields are tested one by one as JohnsonCook.*",
    "Strip.length_mm": "a check only (the gauge span must fit on the strip): eq. (9)'s arc height is over "
                       "the gauge span, and the REV models a patch of the strip, not its length",
    **{f"{m}.{k}": "a library item's registry name and descriptive text" for m in ("Material", "Shot", "Strip")
       for k in ("name", "description", "source")},
}

MODELS = [ShotSection, Almen, Dmin, Coverage, Target, Fidelity, Seeds, Execution, JohnsonCook, Material, Shot, Strip]


def _signature(path) -> list[str]:
    graph = peenflow.api.load_study_graph(path)
    return sorted(f"{n.node_id} {json.dumps(n.params, sort_keys=True, default=repr)}" for n in graph.nodes)


def _write(tmp_path, name, changes):
    data = copy.deepcopy(base_study())
    for path, value in changes.items():
        set_path(data, path, value)
    p = tmp_path / f"{name}.toml"
    p.write_text(to_toml(data))
    return p


def test_every_field_is_classified():
    fields = {f"{m.__name__}.{k}" for m in MODELS for k in m.model_fields}
    assert fields - set(CHANGES) - set(NO_RESULT) == set()
    assert set(CHANGES) | set(NO_RESULT) <= fields  # no stale entries


@pytest.mark.parametrize("field", sorted(CHANGES))
def test_changing_a_key_changes_some_stage(field, tmp_path):
    (tmp_path / "measured.csv").write_text("depth_mm,stress_MPa,component\n0.05,-300,xx\n")
    for name, saturated_mm in (("strips_a.csv", 0.30), ("strips_b.csv", 0.34)):  # two exact exp2 strip sets
        rows = [f"{t:g},{saturated_mm / 0.9 * (1 - 0.1 ** (t / 4)):.6f}" for t in (1, 2, 4, 8, 16)]
        (tmp_path / name).write_text("time_min,arc_height_mm\n" + "\n".join(rows) + "\n")
    base_changes, change = CHANGES[field]
    base = _write(tmp_path, "base", base_changes)
    changed = _write(tmp_path, "changed", {**base_changes, **change})
    for p in (base, changed):
        assert validate_study(p) == [], (field, p.name, validate_study(p))
    assert _signature(base) != _signature(changed), f"{field}: {change} reaches no stage"


@pytest.mark.parametrize("key", sorted(REMOVED_KEYS))
def test_removed_keys_are_refused_with_the_reason(key, tmp_path):
    problems = validate_study(_write(tmp_path, "s", {f"fidelity.{key}": 1.0}))
    assert len(problems) == 1 and f"fidelity.{key}" in problems[0] and "removed" in problems[0]
