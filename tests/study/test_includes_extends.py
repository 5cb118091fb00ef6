"""Library resolution, includes, inline items and extends (deep merge)."""

from __future__ import annotations

import copy

import pytest

from peenflow.study import Material, load_study, validate_study
from tasks.params import study_params

DELETE = "__delete__"  # see conftest.set_path

SOFT = (
    "[materials.Soft]\ndescription = 'soft test alloy'\nyoungs_modulus_GPa = 70\npoisson_ratio = 0.3\n"
    "density_kg_m3 = 2700\n[materials.Soft.johnson_cook]\nA_MPa = 100\nB_MPa = 200\nC = 0.01\nn = 0.3\n"
    "[shots.Tiny]\ndiameter_mm = 0.2\ndensity_kg_m3 = 7800\n"
)


def test_library_items_are_resolved_by_name(write_study):
    s = load_study(write_study())
    assert isinstance(s.target.material, Material)
    assert s.target.material.name == "Al7075-T73" and s.target.material.poisson_ratio == 0.33
    assert s.almen.strip.material.name == "SAE1070"
    assert s.shot.type.name == "S230" and s.shot.diameter_mm == 0.58 and s.shot.density_kg_m3 == 7800.0
    assert s.info.include == ("peenflow:library",)


def test_default_include_is_the_packaged_library(write_study):
    s = load_study(write_study({"study.include": DELETE}))
    assert s.info.include == ("peenflow:library",)
    assert s.target.material.name == "Al7075-T73"


def test_single_packaged_file_and_empty_include(write_study):
    problems = validate_study(write_study({"study.include": ["peenflow:shots"]}))
    assert any(p.startswith('target.material = "Al7075-T73": unknown material (known: none') for p in problems)
    assert any(p.startswith('almen.strip = "A": unknown Almen strip') for p in problems)
    assert not any(p.startswith("shot.type") for p in problems)
    assert any("include peenflow:library?" in p for p in validate_study(write_study({"study.include": []})))


def test_included_file_relative_to_the_study_defines_new_items(write_study, tmp_path):
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "mine.toml").write_text(SOFT)
    s = load_study(write_study({"study.include": ["peenflow:library", "lib/mine.toml"],
                                "target.material": "Soft", "shot.type": "Tiny",
                                "fidelity.element_size_um": 40.0}))  # D / 5 of the 0.2 mm shot (bounds.py)
    assert s.target.material.johnson_cook.C == 0.01 and s.target.material.youngs_modulus_GPa == 70.0
    assert s.shot.diameter_mm == 0.2
    assert s.info.include == ("peenflow:library", str(tmp_path / "lib" / "mine.toml"))


def test_later_sources_override_library_keys(write_study, tmp_path):
    (tmp_path / "override.toml").write_text("[materials.Al7075-T73.johnson_cook]\nC = 0.02\n")
    s = load_study(write_study({
        "study.include": ["peenflow:library", "override.toml"],
        "materials": {"Al7075-T73": {"density_kg_m3": 2800.0}},  # the study's own table wins last
    }))
    m = s.target.material
    assert m.johnson_cook.C == 0.02 and m.johnson_cook.A_MPa == 434.0  # deep merge: other keys kept
    assert m.density_kg_m3 == 2800.0 and m.youngs_modulus_GPa == 71.0


def test_inline_material_shot_and_strip(write_study):
    s = load_study(write_study({
        "target.material": {"youngs_modulus_GPa": 110.0, "poisson_ratio": 0.34, "density_kg_m3": 4430.0,
                            "johnson_cook": {"A_MPa": 1098.0, "B_MPa": 1092.0, "C": 0.014, "n": 0.93}},
        "shot.type": {"name": "S230-worn", "diameter_mm": 0.55, "density_kg_m3": 7800.0},
        "almen.strip": {"name": "A", "material": "SAE1070", "thickness_mm": 1.3},
    }))
    assert s.target.material.name == "inline-material" and s.target.material.johnson_cook.n == 0.93
    assert s.target.material.johnson_cook.reference_strain_rate_1_s == 1.0  # default
    assert s.shot.name == "S230-worn" and s.shot.diameter_mm == 0.55
    assert s.almen.strip.material.name == "SAE1070" and s.almen.strip.gauge_span_mm == 31.75


def test_extends_child_overrides_parent(write_study, tmp_path):
    write_study(name="parent.toml")
    child = write_study(name="child.toml", data={
        "study": {"name": "child", "extends": "parent.toml"},
        "almen": {"sequences": 3, "angles_deg": [90.0]},  # lists are replaced whole
        "target": {"angle_deg": 80.0},
        "fidelity": {"element_size_um": 50.0},
    })
    s = load_study(child)
    parent = load_study(tmp_path / "parent.toml")
    assert s.name == "child" and s.description == ""  # name/description are not inherited
    assert s.almen.sequences == 3 and s.almen.angles_deg == (90.0,)
    assert s.almen.velocities_m_s == parent.almen.velocities_m_s  # inherited
    assert s.target.angle_deg == 80.0 and s.target.material == parent.target.material
    assert s.fidelity.preset == "coarse" and s.fidelity.element_size_um == 50.0
    assert s.fidelity.overrides == ("element_size_um",)
    assert s.extends_chain == (child, tmp_path / "parent.toml")


def test_extends_chain_of_three_and_paths_relative_to_their_file(write_study, tmp_path):
    (tmp_path / "base").mkdir()
    (tmp_path / "base" / "lib.toml").write_text(SOFT)
    (tmp_path / "base" / "profile.csv").write_text("depth_mm,stress_MPa,component\n0.05,-350,xx\n")
    write_study(name="base/grand.toml", data=None, changes={
        "study.include": ["peenflow:library", "lib.toml"],
        "target.measured_profile_csv": "profile.csv",
    })
    write_study(name="base/parent.toml", data={"study": {"extends": "grand.toml"}, "target": {"material": "Soft"}})
    child = write_study(name="child.toml", data={"study": {"name": "c", "extends": "base/parent.toml"},
                                                 "seeds": {"base": 99}})
    s = load_study(child)
    assert s.target.material.name == "Soft"
    assert s.target.measured_profile_csv == str(tmp_path / "base" / "profile.csv")
    assert s.target.measured_profile is not None  # parsed from the grandparent's path
    assert s.seeds.base == 99
    assert len(s.extends_chain) == 3


def test_parent_with_problem_is_reported_with_its_file(write_study, tmp_path):
    write_study(name="parent.toml", changes={"study.include": ["peenflow:library", "gone.toml"]})
    child = write_study(name="child.toml", data={"study": {"name": "child", "extends": "parent.toml"}})
    problems = validate_study(child)
    assert problems == ['[in parent.toml] study.include[1] = "gone.toml": included file not found '
                        f"(looked for {tmp_path / 'gone.toml'})"]


def test_stages_follow_sections(write_study, tmp_path):
    from peenflow.api import load_study_graph

    stages = lambda p: tuple(load_study_graph(p).stages)  # noqa: E731
    full = stages(write_study())
    assert {"strip_dmin", "control_curve", "target_dmin", "coverage_curve", "residual_profile"} <= set(full)
    assert "target_rev_thickness" not in full  # only with rev_thickness_mm = "auto"
    no_target = stages(write_study({"target": DELETE}))
    assert no_target[-1] == "control_curve" and not any(s.startswith("target") for s in no_target)
    paper_rev = stages(write_study({"target": DELETE, "almen.rev_rule": "paper"}))
    assert "strip_dmin" not in paper_rev and "strip_impact" not in paper_rev
    s = load_study(write_study({"target": DELETE, "almen.rev_rule": "paper"}))
    rev = study_params(s).strip_rev.geometry()
    assert rev.side == pytest.approx(6 * 0.58e-3) and rev.measuring_side == pytest.approx(2 * 0.58e-3)
    given = write_study({"almen": DELETE, "target.almen_intensity": DELETE, "target.velocity_m_s": 47.0,
                         "target.rev_size_mm": 4.5})
    target_only = stages(given)
    assert "coverage_curve" in target_only and "target_dmin" not in target_only
    assert not any(x.startswith("strip") for x in target_only) and "control_curve" not in target_only
    assert study_params(load_study(given)).target_rev.geometry().measuring_side == pytest.approx(1.5e-3)


def test_models_are_frozen(write_study):
    s = load_study(write_study())
    with pytest.raises(Exception):
        s.almen.sequences = 3  # type: ignore[misc]
    assert copy.deepcopy(s) == s


def test_study_pickles_with_its_shot_diameter(write_study):
    import pickle

    s = load_study(write_study())
    t = pickle.loads(pickle.dumps(s))
    assert t == s and study_params(t).fidelity == study_params(s).fidelity and study_params(t).dmin == study_params(s).dmin
