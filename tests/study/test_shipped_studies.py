"""The study files shipped in studies/ load, validate and mean what they say."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import peenflow.api
from peenflow.study import load_study, validate_study
from tasks.params import study_params

STUDIES = Path(__file__).resolve().parents[2] / "studies"
SHIPPED = sorted(p.name for p in STUDIES.glob("*.toml"))


@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_study_is_valid(name):
    path = STUDIES / name
    assert validate_study(path) == []
    study = load_study(path)
    assert study.name == name.removesuffix(".toml")
    assert study.path == path.absolute() and study.directory == STUDIES


def _stages(name):
    return set(peenflow.api.load_study_graph(STUDIES / name).stages)


def test_paper_almen_study_matches_section_4():
    s = load_study(STUDIES / "paper_almen_s230.toml")
    assert {"strip_dmin", "control_curve"} <= _stages("paper_almen_s230.toml")
    assert not any(x.startswith("target") for x in _stages("paper_almen_s230.toml"))
    assert s.shot.name == "S230" and s.shot.diameter_mm == 0.58 and study_params(s).shot.diameter_m == pytest.approx(0.58e-3)
    assert s.shot.density_kg_m3 == 7800.0 and s.shot.friction_coefficient == 0.2
    a = s.almen
    assert a.strip.name == "A" and a.strip.thickness_mm == 1.29 and a.strip.gauge_span_mm == 31.75
    m = a.strip.material
    assert (m.name, m.youngs_modulus_GPa, m.poisson_ratio, m.density_kg_m3) == ("SAE1070", 205.0, 0.29, 7800.0)
    jc = study_params(s).strip_material
    assert (jc.A_Pa, jc.B_Pa, jc.C, jc.n, jc.m) == (1408e6, pytest.approx(600.8e6), 0.0134, 0.234, 0.0)
    assert a.angles_deg == (45.0, 67.5, 90.0)
    assert a.velocities_m_s == (25.0, 35.0, 45.0, 55.0)
    assert a.shot_counts == (10, 20, 40, 80, 160, 320, 480)
    assert a.sequences == 6 and a.rev_rule == "dmin"
    rev = study_params(s).strip_rev.geometry(d_min=2 * 0.58e-3)
    assert rev.side == pytest.approx(6 * 0.58e-3) and rev.measuring_side == pytest.approx(2 * 0.58e-3)
    assert s.dmin.strip_velocity_m_s == 55.0 and s.dmin.strip_angles_deg == (45.0, 90.0)
    assert s.dmin.threshold == 0.05
    assert s.fidelity.preset == "paper" and s.fidelity.element_size_um == 25.0
    assert s.target is None


def test_paper_al7075_study_matches_section_5():
    s = load_study(STUDIES / "paper_al7075.toml")
    almen = load_study(STUDIES / "paper_almen_s230.toml")
    # extends: the control-curve inputs are those of the almen study
    assert s.to_canonical_dict()["almen"] == almen.to_canonical_dict()["almen"]
    assert {"strip_dmin", "control_curve", "target_dmin", "coverage_curve", "residual_profile"} <= _stages(
        "paper_al7075.toml")
    t = s.target
    assert t.material.name == "Al7075-T73" and study_params(s).target_material.youngs_modulus_Pa == 71e9
    assert t.material.johnson_cook.A_MPa == 434.0 and t.material.johnson_cook.B_MPa == 303.58
    assert not t.material.johnson_cook.rate_dependent and not t.material.johnson_cook.thermal
    plan = study_params(s).target_plan
    assert plan.thickness_m == pytest.approx(9.5e-3) and plan.rev_thickness_m == pytest.approx(9.5e-3)
    assert t.angle_deg == 65.0 and t.coverage_percent == 200.0 and t.sequences == 2
    assert t.intensity_mm == 0.30 and t.intensity_strip == "A"
    assert {"target_velocity", "control_curve"} <= _stages("paper_al7075.toml")
    assert study_params(s).target_rev.geometry(d_min=1.5e-3).side == pytest.approx(4.5e-3)
    assert t.measured_profile_csv == ""
    assert s.coverage.full_coverage_percent == 98.0


def test_quickstart_is_coarse_and_runs_the_whole_chain():
    s = load_study(STUDIES / "quickstart.toml")
    stages = _stages("quickstart.toml")
    assert {"control_curve", "target_dmin", "coverage_curve", "residual_profile"} <= stages
    assert "strip_dmin" not in stages
    assert s.fidelity.preset == "coarse" and 50 <= s.fidelity.element_size_um <= 60
    assert len(s.almen.velocities_m_s) >= 2  # a control curve needs two velocities to invert
    assert len(s.almen.shot_counts) >= 3  # eq. (10) has three parameters
    rev = study_params(s).strip_rev.geometry()
    assert 0 < rev.measuring_side < rev.side
    assert s.target.intensity_mm is not None and s.target.velocity_m_s is None  # velocity from the curve
    assert s.target.material.name == "Al7075-T73"
    assert math.isfinite(study_params(s).target_material.to_kernel().wave_speed)


def _point_params(name, stage):
    """{point label: canonical parameters} of a stage of a shipped study (what its result keys hash)."""
    return {n.node_id.split("[", 1)[1]: n.params for n in peenflow.api.load_study_graph(STUDIES / name).stage_nodes(stage)}


def test_the_extrapolated_whole_paper_is_the_40_and_25_um_studies_levels():
    """paper_fast_extrapolated.toml runs the strips of paper_fast_25um.toml (25 um) and of
    paper_fast.toml (40 um) -- the same parameters, so the same keys and shot streams -- and
    extrapolates from them with the measured order."""
    from peenflow.study.accuracy import INTENSITY_ORDER

    for stage, other in (("strip_runs", "paper_fast_25um.toml"), ("coarse_strip_runs", "paper_fast.toml")):
        mine = _point_params("paper_fast_extrapolated.toml", stage)
        assert len(mine) == 24 and mine == _point_params(other, "strip_runs"), stage
    (e,) = {p["extrapolation"]["order"] for p in _point_params("paper_fast_extrapolated.toml", "intensity_extrapolation").values()}
    assert e == INTENSITY_ORDER


def test_the_literal_studies_are_the_papers_section_4_procedure():
    """paper_literal_40um.toml is section 4 as the paper states it on the 67.5 deg curve: a 6D x 6D
    REV with symmetric lateral faces and a 2D x 2D measuring region, the ladder N = 10 ... 480, eq.
    (10) fitted to it and eq. (11) used wherever it lands; paper_literal.toml is the same at 25 um
    with the 40 um study's strips as its coarse level (same parameters, so the same keys)."""
    s = load_study(STUDIES / "paper_literal_40um.toml")
    a = s.almen
    assert a.angles_deg == (67.5,) and a.velocities_m_s == (25.0, 35.0, 45.0, 55.0)
    assert a.shot_counts == (10, 20, 40, 80, 160, 320, 480) and a.saturation_fit == "paper"
    assert a.rev_rule == "paper" and a.allow_extrapolated_intensity
    assert s.fidelity.lateral_boundary == "symmetric" and s.fidelity.element_size_um == 40.0
    rev = study_params(s).strip_rev.geometry(d_min=None)
    assert rev.side == pytest.approx(6 * 0.58e-3) and rev.measuring_side == pytest.approx(2 * 0.58e-3)
    assert "strip_dmin" not in _stages("paper_literal_40um.toml")  # the paper's REV needs no search

    fine = load_study(STUDIES / "paper_literal.toml")
    assert fine.fidelity.element_size_um == 25.0
    assert fine.fidelity.extrapolate_intensity_from_um == 40.0
    mine = _point_params("paper_literal.toml", "coarse_strip_runs")
    assert len(mine) == 8 and mine == _point_params("paper_literal_40um.toml", "strip_runs")


def test_the_process_map_study_reuses_the_fast_paper_strips_and_maps_two_materials():
    """studies/process_map_al7075.toml: its strip runs at the paper study's velocities are that study's
    (same parameters, same upstream: the same keys), only the 15 m/s strips are new; the map's
    dimensions are 3 intensities x 2 materials, with coverage levels 100 / 200 / 400 % from one run."""
    from peenflow.engine.canonical import canonical_json

    def strips(name):
        graph = peenflow.api.load_study_graph(STUDIES / name)
        return graph, {(canonical_json(n.coords), canonical_json(n.params)) for n in graph.stage_nodes("strip_runs")}

    paper, paper_strips = strips("paper_fast_extrapolated.toml")
    mapped, map_strips = strips("process_map_al7075.toml")
    assert paper_strips < map_strips
    new = map_strips - paper_strips
    assert new and all('"velocity_m_s":15}' in coords for coords, _ in new)
    assert mapped.labels["process_dims"] == ["almen_intensity_m", "target_material"]
    assert mapped.labels["coverage_levels_percent"] == [100.0, 200.0, 400.0]
    assert len(mapped.stage_nodes("target_runs")) == 3 * 2 * 2  # intensities x materials x sequences
    assert {"process_map", "suggested_settings", "verify_runs", "verified_settings"} <= set(mapped.stages)
