"""Broken study files: one message per problem, naming key path, value and expectation."""

from __future__ import annotations

import pytest

from peenflow.study import StudyError, load_study, validate_study

DELETE = "__delete__"  # see conftest.set_path

# (id, changes to the valid base study, substrings that one message must contain)
CASES = [
    # unknown keys, with suggestions
    ("unknown-key", {"almen.velocity_m_s": [30.0]},
     ["almen.velocity_m_s = [30.0]: unknown key", 'did you mean "velocities_m_s"?']),
    ("unknown-key-shot", {"shot.friction": 0.3}, ["shot.friction = 0.3: unknown key", 'did you mean "friction_coefficient"?']),
    ("unknown-section", {"fidelty": {"preset": "coarse"}}, ["fidelty: unknown section", 'did you mean "fidelity"?']),
    ("unknown-study-key", {"study.includes": ["peenflow:library"]}, ["study.includes: unknown key", 'did you mean "include"?']),
    ("unknown-fidelity-key", {"fidelity.element_size_mm": 0.05},
     ["fidelity.element_size_mm = 0.05: unknown key", 'did you mean "element_size_um"?']),
    # missing keys
    ("missing-key", {"target.thickness_mm": DELETE}, ["target.thickness_mm: required key is missing", "part thickness in mm"]),
    ("missing-name", {"study.name": DELETE}, ["study.name: required key is missing"]),
    ("missing-shot", {"shot": DELETE}, ["shot: missing [shot] section"]),
    ("missing-strip-thickness", {"almen.strip": {"name": "X", "material": "SAE1070"}},
     ["almen.strip.thickness_mm: required key is missing"]),
    # wrong types
    ("int-as-string", {"almen.sequences": "6"}, ['almen.sequences = "6": expected an integer, got a string']),
    ("float-as-string", {"target.thickness_mm": "9.5"}, ['target.thickness_mm = "9.5": expected a number, got a string']),
    ("bool-as-number", {"shot.friction_coefficient": True}, ["shot.friction_coefficient = true: expected a number"]),
    ("rev-thickness-word", {"target.rev_thickness_mm": "automatic"},
     ['target.rev_thickness_mm = "automatic": expected "auto" or a number > 0']),
    ("string-as-bool", {"almen.allow_extrapolated_intensity": "yes"},
     ['almen.allow_extrapolated_intensity = "yes": expected true or false']),
    ("scalar-for-list", {"almen.velocities_m_s": 55.0}, ["almen.velocities_m_s = 55.0: expected a list"]),
    ("float-for-int", {"almen.shot_counts": [10, 20.5, 40]}, ["almen.shot_counts[1] = 20.5: expected an integer"]),
    ("table-for-scalar", {"target.angle_deg": {"value": 65.0}}, ["target.angle_deg: expected a number, got a table"]),
    # non-physical values
    ("zero-diameter-inline", {"shot.type": {"diameter_mm": 0.0, "density_kg_m3": 7800.0}},
     ["shot.type.diameter_mm = 0.0: expected a value > 0"]),
    ("negative-diameter-library", {"shots": {"Big": {"diameter_mm": -1.0, "density_kg_m3": 7800.0}}, "shot.type": "Big"},
     ["shots.Big.diameter_mm = -1.0: expected a value > 0"]),
    ("angle-above-90", {"almen.angles_deg": [45.0, 95.0]},
     ["almen.angles_deg[1] = 95.0: expected an impingement angle in (0, 90] deg"]),
    ("angle-zero", {"target.angle_deg": 0.0}, ["target.angle_deg = 0.0: expected an impingement angle in (0, 90]"]),
    ("angle-negative", {"dmin.strip_angles_deg": [-10.0]}, ["dmin.strip_angles_deg[0] = -10.0: expected an impingement angle"]),
    ("velocity-negative", {"almen.velocities_m_s": [25.0, 35.0, -5.0]},
     ["almen.velocities_m_s[2] = -5.0: expected a shot velocity > 0 m/s"]),
    ("velocity-nan", {"almen.velocities_m_s": [25.0, float("nan")]},
     ["almen.velocities_m_s[1] = nan: expected a finite number (not nan or inf)"]),
    ("unknown-key-suffix", {"almen.sequences": DELETE, "almen.sequences_x": 1},
     ["almen.sequences_x = 1: unknown key; did you mean \"sequences\"?"]),
    ("velocity-zero", {"dmin.strip_velocity_m_s": 0.0}, ["dmin.strip_velocity_m_s = 0.0: expected a shot velocity > 0 m/s"]),
    ("coverage-zero", {"target.coverage_percent": 0.0}, ["target.coverage_percent = 0.0: expected a coverage in percent > 0"]),
    ("coverage-negative", {"target.coverage_percent": -100.0}, ["target.coverage_percent = -100.0: expected a coverage in percent > 0"]),
    ("full-coverage-100", {"coverage.full_coverage_percent": 100.0},
     ["coverage.full_coverage_percent = 100.0: expected a percentage in (0, 100)"]),
    ("poisson-0.5", {"target.material": {"youngs_modulus_GPa": 71.0, "poisson_ratio": 0.5, "density_kg_m3": 2780.0,
                                         "johnson_cook": {"A_MPa": 434.0, "B_MPa": 303.58, "C": 0.0, "n": 0.39}}},
     ["target.material.poisson_ratio = 0.5: expected a Poisson ratio in (-1, 0.5)"]),
    ("poisson-below-minus-1", {"materials": {"Odd": {"youngs_modulus_GPa": 71.0, "poisson_ratio": -1.5,
                                                      "density_kg_m3": 2780.0,
                                                      "johnson_cook": {"A_MPa": 1.0, "B_MPa": 1.0, "C": 0.0, "n": 0.1}}}},
     ["materials.Odd.poisson_ratio = -1.5: expected a Poisson ratio in (-1, 0.5)"]),
    ("negative-modulus", {"materials": {"Neg": {"youngs_modulus_GPa": -71.0, "poisson_ratio": 0.3, "density_kg_m3": 2780.0,
                                                 "johnson_cook": {"A_MPa": 1.0, "B_MPa": 1.0, "C": 0.0, "n": 0.1}}}},
     ["materials.Neg.youngs_modulus_GPa = -71.0: expected a value > 0"]),
    ("jc-thermal-without-temperatures", {"materials": {"Hot": {
        "youngs_modulus_GPa": 71.0, "poisson_ratio": 0.3, "density_kg_m3": 2780.0,
        "johnson_cook": {"A_MPa": 1.0, "B_MPa": 1.0, "C": 0.0, "n": 0.1, "m": 1.0}}}},
     ["materials.Hot.johnson_cook: johnson_cook.m = 1.0 is not 0, so room_temperature_K and melt_temperature_K are required"]),
    ("grading-above-1.2", {"fidelity.grading_ratio": 1.3}, ["fidelity.grading_ratio = 1.3: expected a grading ratio in [1, 1.2]"]),
    ("grading-below-1", {"fidelity.grading_ratio": 0.9}, ["fidelity.grading_ratio = 0.9: expected a grading ratio in [1, 1.2]"]),
    ("time-step-safety", {"fidelity.time_step_safety": 1.5},
     ["fidelity.time_step_safety = 1.5: expected a time-step safety factor in (0, 1]"]),
    ("contact-stiffness", {"fidelity.contact_stiffness_factor": 1.0},
     ["fidelity.contact_stiffness_factor = 1.0: removed: the kernel's contact is kinematic"]),
    ("fidelity-overrides-key", {"fidelity.overrides": ["x"]}, ['fidelity.overrides = ["x"]: unknown key']),
    ("lateral-boundary", {"fidelity.lateral_boundary": "periodical"},
     ['fidelity.lateral_boundary = "periodical": expected one of', 'did you mean "periodic"?']),
    ("precision", {"fidelity.precision": "float64"}, ['fidelity.precision = "float64": removed: the kernel runs in float64 only']),
    ("preset-typo", {"fidelity.preset": "standrad"}, ['fidelity.preset = "standrad": expected one of', 'did you mean "standard"?']),
    ("element-too-large", {"fidelity.element_size_um": 400.0},
     ["fidelity.element_size_um = 400.0: an element as large as the shot radius"]),
    ("shot-counts-not-increasing", {"almen.shot_counts": [10, 20, 20, 40]},
     ["almen.shot_counts = [10, 20, 20, 40]: expected shot counts strictly increasing; item [2] = 20"]),
    ("shot-counts-not-positive", {"almen.shot_counts": [0, 10, 20]}, ["almen.shot_counts[0] = 0: expected an integer > 0"]),
    ("shot-counts-too-few", {"almen.shot_counts": [10, 20]}, ["almen.shot_counts = [10, 20]: expected at least 3 item(s)"]),
    ("shot-counts-other-word", {"almen.shot_counts": "automatic"},
     ['almen.shot_counts = "automatic": expected "auto" or a list of shot counts']),
    ("first-shots-without-auto", {"almen.first_shots": 20},
     ['almen.first_shots = 20 needs almen.shot_counts = "auto"']),
    ("auto-ladder-too-short", {"almen.shot_counts": "auto", "almen.first_shots": 100, "almen.max_shots": 200},
     ["almen.first_shots = 100: the ladder to almen.max_shots = 200 has fewer than the 3 rungs"]),
    ("sequences-zero", {"almen.sequences": 0}, ["almen.sequences = 0: expected an integer > 0"]),
    ("duplicate-angles", {"almen.angles_deg": [45.0, 90.0, 45.0]}, ["almen.angles_deg = [45.0, 90.0, 45.0]: expected distinct angles"]),
    ("seed-negative", {"seeds.base": -1}, ["seeds.base = -1: expected an integer in [0, 2**63)"]),
    ("workers-zero", {"execution": {"workers": 0}}, ['execution.workers = 0: expected "auto" or an integer >= 1']),
    ("dmin-range", {"dmin.max_distance_D": 0.5}, ["dmin.max_distance_D = 0.5 must be larger than min_distance_D = 1.0"]),
    # references
    ("material-not-in-library", {"target.material": "Al7075"},
     ['target.material = "Al7075": unknown material; did you mean "Al7075-T73"?']),
    ("shot-not-in-library", {"shot.type": "S23"}, ['shot.type = "S23": unknown shot; did you mean "S230"?']),
    ("strip-not-in-library", {"almen.strip": "B"}, ['almen.strip = "B": unknown Almen strip', "known: A, C, N"]),
    ("strip-material-not-in-library", {"strips": {"X": {"material": "Steel", "thickness_mm": 1.0}}},
     ['strips.X.material = "Steel": unknown material']),
    ("include-missing", {"study.include": ["peenflow:library", "nope.toml"]},
     ['study.include[1] = "nope.toml": included file not found']),
    ("include-bad-package-name", {"study.include": ["peenflow:libary"]},
     ['study.include[0] = "peenflow:libary": no such packaged library; did you mean "library"?']),
    ("include-not-a-list", {"study.include": "peenflow:library"}, ['study.include = "peenflow:library": expected a list']),
    ("extends-missing", {"study.extends": "parent.toml"}, ['study.extends = "parent.toml": parent study file not found']),
    # target consistency
    ("intensity-notation", {"target.almen_intensity": "twelve"},
     ['target.almen_intensity = "twelve": expected Almen intensity notation such as "12A"']),
    ("intensity-ambiguous", {"target.almen_intensity": "0.3A"},
     ['target.almen_intensity = "0.3A": ambiguous unit: write "0.3 mmA" for millimetres']),
    ("intensity-wrong-strip", {"target.almen_intensity": "12C"},
     ['target.almen_intensity: the target intensity is on strip C but the control curves are computed on almen.strip = "A"']),
    ("intensity-and-velocity", {"target.velocity_m_s": 47.0},
     ["target: give exactly one of target.almen_intensity", "got almen_intensity, velocity_m_s"]),
    ("intensity-none", {"target.almen_intensity": DELETE}, ["target: give exactly one of", "got none"]),
    ("intensity-mm-without-strip", {"target.almen_intensity": DELETE, "target.almen_intensity_mm": 0.3},
     ["target.almen_intensity_mm needs target.almen_strip"]),
    ("intensity-without-almen", {"almen": DELETE}, ["target.almen_intensity: a target intensity needs control curves"]),
    ("one-velocity-curve", {"almen.velocities_m_s": [55.0]},
     ["almen.velocities_m_s = [55.0]: a control curve needs at least 2 velocities"]),
    ("interpolate-outside", {"target.control_angle_rule": "interpolate", "target.angle_deg": 30.0},
     ["target.angle_deg = 30.0: outside the control-curve angles [45.0, 90.0]"]),
    ("rev-thicker-than-part", {"target.rev_thickness_mm": 12.0},
     ["target.rev_thickness_mm = 12.0 is thicker than the part"]),
    ("rev-rule-and-size", {"almen.rev_rule": "paper", "almen.rev_size_mm": 3.0},
     ['almen.rev_size_mm is given but rev_rule = "paper"']),
    ("profile-missing", {"target.measured_profile_csv": "nope.csv"},
     ["target.measured_profile_csv = ", "nope.csv", "measured profile not found"]),
    ("nothing-to-compute", {"almen": DELETE, "target": DELETE}, ["nothing to compute: add an [almen] section"]),
    ("extrapolation-level-not-coarser", {"fidelity.element_size_um": 25.0, "fidelity.extrapolate_intensity_from_um": 30.0},
     ["fidelity.extrapolate_intensity_from_um = 30.0: expected a coarser level than element_size_um = 25 um, "
      "at least 1.25 x that = 31.25 um"]),
    ("extrapolation-without-almen", {"almen": DELETE, "target.almen_intensity": DELETE, "target.velocity_m_s": 47.0,
                                     "fidelity.element_size_um": 25.0, "fidelity.extrapolate_intensity_from_um": 40.0},
     ["fidelity.extrapolate_intensity_from_um extrapolates the Almen intensities", "no [almen] section"]),
    ("dent-level-not-finer", {"fidelity.element_size_um": 25.0, "fidelity.dent_element_size_um": 30.0},
     ["fidelity.dent_element_size_um = 30.0: expected an element size no coarser than element_size_um = 25 um"]),
    ("dent-core-without-dent-size", {"fidelity.element_size_um": 25.0, "fidelity.dent_refinement": "core"},
     ["fidelity.dent_refinement", "dent_element_size_um, which is not given"]),
    ("dent-core-not-finer", {"fidelity.element_size_um": 25.0, "fidelity.dent_element_size_um": 25.0,
                             "fidelity.dent_refinement": "core"},
     ["fidelity.dent_refinement", '"core" needs dent_element_size_um = 25 um finer than element_size_um = 25 um']),
    ("dent-level-without-target", {"target": DELETE, "fidelity.element_size_um": 25.0,
                                   "fidelity.dent_element_size_um": 12.5},
     ["fidelity.dent_element_size_um refines the single impact of the [target] section", "no [target] section"]),
    ("extrapolation-order-alone", {"fidelity.intensity_extrapolation_order": 2.0},
     ["fidelity.intensity_extrapolation_order = 2.0: given without fidelity.extrapolate_intensity_from_um"]),
]


# limits of the kernel's own (tasks.preflight): refused by the stage layer, before any compute
KERNEL_CASES = [
    ("periodic-rev-too-small", {"fidelity.lateral_boundary": "periodic", "target.rev_size_mm": 0.5,
                                "study.allow_outside_bounds": ["target.rev_size_mm"]},
     ['target.rev_size_mm = 0.5: with fidelity.lateral_boundary = "periodic" the REV side must exceed']),
    ("periodic-oblique-travel", {"fidelity.lateral_boundary": "periodic", "fidelity.element_size_um": 40.0,
                                 "target.rev_size_mm": 0.9, "target.almen_intensity": DELETE,
                                 "target.velocity_m_s": 30.0, "target.angle_deg": 65.0},
     ['target.rev_size_mm = 0.9: with fidelity.lateral_boundary = "periodic" the REV side must exceed 1.25 D + 4 '
      "elements (40.91 um: 40 um fitted to the side) + twice the tangential travel during the contact (0.0455 mm at 30 m/s, 65 deg) = 0.934 mm"]),
    ("extrapolation-coarse-rev", {"fidelity.element_size_um": 25.0, "fidelity.extrapolate_intensity_from_um": 40.0,
                                  "fidelity.lateral_boundary": "periodic", "almen.rev_rule": "explicit",
                                  "almen.rev_size_mm": 0.85, "target.rev_size_mm": 1.2},
     ['almen.rev_size_mm = 0.85: with fidelity.lateral_boundary = "periodic" the REV side must exceed 1.25 D + 4 '
      "elements (40.48 um: 40 um fitted to the side)"]),
]


@pytest.mark.parametrize("changes, expected", [c[1:] for c in KERNEL_CASES], ids=[c[0] for c in KERNEL_CASES])
def test_a_study_the_kernel_would_stop_is_refused_before_compute(write_study, changes, expected):
    from tasks.pipeline import build_graph
    from tasks.preflight import study_problems

    path = write_study(changes)
    assert validate_study(path) == []  # the file itself is valid
    problems = study_problems(path)
    assert [p for p in problems if all(s in p for s in expected)], "\n".join(problems)
    with pytest.raises(StudyError) as info:
        build_graph(path)
    assert info.value.problems == problems and str(path) in str(info.value)


@pytest.mark.parametrize("changes, expected", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_broken_study_reports_its_problem(write_study, changes, expected):
    path = write_study(changes)
    problems = validate_study(path)
    matching = [p for p in problems if all(s in p for s in expected)]
    assert matching, f"no message contains {expected}; got:\n" + "\n".join(problems)
    with pytest.raises(StudyError) as info:
        load_study(path)
    assert isinstance(info.value, ValueError)
    assert str(path) in str(info.value)
    assert info.value.problems == problems
    for p in problems:  # never pydantic's own wording or links
        assert "pydantic" not in p and "Input should be" not in p and "Value error," not in p


def test_base_study_is_valid(write_study):
    assert validate_study(write_study()) == []


def test_a_broken_library_item_is_reported_once_where_it_is_defined(write_study):
    path = write_study({"shots": {"Big": {"diameter_mm": -1.0, "density_kg_m3": 7800.0}}, "shot.type": "Big"})
    problems = validate_study(path)
    assert problems == ["shots.Big.diameter_mm = -1.0: expected a value > 0"]


def test_all_problems_reported_together(write_study):
    path = write_study({
        "almen.velocities_m_s": [25.0, -1.0],
        "almen.angles_deg": [100.0],
        "target.material": "Unobtainium",
        "fidelity.grading_ratio": 2.0,
        "shot.frction_coefficient": 0.2,
        "target.coverage_percent": 0.0,
    })
    with pytest.raises(StudyError) as info:
        load_study(path)
    text = str(info.value)
    for fragment in [
        "almen.velocities_m_s[1] = -1.0",
        "almen.angles_deg[0] = 100.0",
        'target.material = "Unobtainium": unknown material',
        "fidelity.grading_ratio = 2.0",
        'shot.frction_coefficient = 0.2: unknown key; did you mean "friction_coefficient"?',
        "target.coverage_percent = 0.0",
    ]:
        assert fragment in text
    assert len(info.value.problems) == 6
    assert text.splitlines()[0] == f"{path}: 6 problems in study file"


def test_toml_syntax_error(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text('[study]\nname = "x"\n[almen\n')
    problems = validate_study(path)
    assert len(problems) == 1 and "TOML syntax error in broken.toml" in problems[0] and "line 3" in problems[0]


def test_missing_study_file(tmp_path):
    problems = validate_study(tmp_path / "none.toml")
    assert len(problems) == 1 and "file not found" in problems[0]


def test_circular_extends(write_study):
    write_study({"study.extends": "b.toml"}, name="a.toml")
    b = write_study({"study.extends": "a.toml"}, name="b.toml")
    problems = validate_study(b)
    assert any("study.extends" in p and "circular extends (b.toml -> a.toml -> b.toml)" in p for p in problems), problems


def test_self_extends(write_study):
    a = write_study({"study.extends": "a.toml"}, name="a.toml")
    assert any("circular extends (a.toml -> a.toml)" in p for p in validate_study(a))


def test_problem_in_included_file_names_that_file(write_study, tmp_path):
    (tmp_path / "mine.toml").write_text(
        "[materials.Soft]\nyoungs_modulus_GPa = 70.0\npoisson_ratio = 0.7\ndensity_kg_m3 = 2700.0\n"
        "[materials.Soft.johnson_cook]\nA_MPa = 100.0\nB_MPa = 100.0\nC = 0.0\nn = 0.3\n"
        "[shot]\ntype = 'S230'\n"
    )
    path = write_study({"study.include": ["peenflow:library", "mine.toml"], "target.material": "Soft"})
    problems = validate_study(path)
    assert "[in mine.toml] materials.Soft.poisson_ratio = 0.7: expected a Poisson ratio in (-1, 0.5)" in problems
    assert any(p.startswith("[in mine.toml] shot: unknown table in an included file") for p in problems)
    assert not any(p.startswith("target.material") for p in problems)  # reported once, at its source


def test_measured_profile_checked(write_study, tmp_path):
    (tmp_path / "bad.csv").write_text("depth_mm,stress\n0.1,-300\n")
    problems = validate_study(write_study({"target.measured_profile_csv": "bad.csv"}))
    assert any("lacks column(s) stress_MPa, component" in p for p in problems), problems
    (tmp_path / "rows.csv").write_text("# comment\ndepth_mm,stress_MPa,component\n0.1,-300,xx\n-1,oops,qq\n")
    problems = validate_study(write_study({"target.measured_profile_csv": "rows.csv"}))
    assert any("rows.csv: bad data on line(s) 4" in p for p in problems), problems  # file line numbers


def test_periodic_lateral_boundary_is_valid(write_study):
    assert validate_study(write_study({"fidelity.lateral_boundary": "periodic"})) == []


def test_a_long_missing_path_keeps_its_file_name_in_the_message(write_study, tmp_path):
    # a study deep in a folder tree: the message shortens the path in its middle, never its name
    deep = tmp_path / ("a_long_folder_name_" * 6) / "profiles" / "shot_peened_part_measured.csv"
    problems = validate_study(write_study({"target.measured_profile_csv": str(deep)}))
    (msg,) = [p for p in problems if p.startswith("target.measured_profile_csv = ")]
    value = msg.split(": measured profile not found")[0].removeprefix("target.measured_profile_csv = ")
    assert value.startswith('"/') and value.endswith('shot_peened_part_measured.csv"') and "..." in value
    assert len(value) <= 80
