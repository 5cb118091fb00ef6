"""Typed stage parameters (tasks/params.py): built once from the study in SI, one canonical form
that names every field, rebuilt exactly from it, and one conversion to each kernel object."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest

from peenflow.engine.canonical import canonical_json, canonical_value
from peenflow.study import load_study
from tasks.params import FidelityParams, MaterialParams, StageParams, study_params
from tasks.pipeline import build_graph

HERE = Path(__file__).parent
STUDIES = [HERE / "micro.toml", HERE.parents[1] / "studies" / "quickstart.toml"]


def _all_params(path):
    p = study_params(load_study(path))
    return [v for v in vars(p).values() if isinstance(v, StageParams)]


@pytest.mark.parametrize("path", STUDIES, ids=lambda p: p.stem)
def test_every_parameter_comes_back_from_its_canonical_form(path):
    for params in _all_params(path):
        back = type(params).from_canonical(canonical_value(params))
        assert canonical_json(back) == canonical_json(params)
        assert set(canonical_value(params)) == {f.name for f in dataclasses.fields(params)}


@pytest.mark.parametrize("path", STUDIES, ids=lambda p: p.stem)
def test_changing_any_field_changes_the_canonical_form(path):
    for params in _all_params(path):
        for f in dataclasses.fields(params):
            value = getattr(params, f.name)
            if isinstance(value, bool):
                other = not value
            elif isinstance(value, (int, float)):
                other = value * 1.5 + 1
            elif isinstance(value, str):
                other = value + "x"
            else:
                continue
            changed = dataclasses.replace(params, **{f.name: other})
            assert canonical_json(changed) != canonical_json(params), (type(params).__name__, f.name)


def test_the_study_is_read_in_si():
    s = load_study(HERE / "micro.toml")
    p = study_params(s)
    assert p.shot.radius_m == pytest.approx(0.29e-3) and p.fidelity.element_size_m == pytest.approx(100e-6)
    assert p.target_material.youngs_modulus_Pa == pytest.approx(71e9) and p.target_material.A_Pa == pytest.approx(434e6)
    assert p.strip_rev.side_m == pytest.approx(1.2e-3) and p.strip_rev.measure_side_m == pytest.approx(0.4e-3)
    assert p.strip.gauge_span_m == pytest.approx(31.75e-3) and p.strip.thickness_m == pytest.approx(1.29e-3)


def test_the_kernel_material_takes_every_field_and_the_kernel_s_own_temperatures():
    p = study_params(load_study(HERE / "micro.toml")).target_material
    k = p.to_kernel()
    assert (k.E, k.nu, k.density, k.A, k.B, k.n, k.C, k.m, k.ref_strain_rate) == (
        p.youngs_modulus_Pa, p.poisson_ratio, p.density_kg_m3, p.A_Pa, p.B_Pa, p.n, p.C, p.m,
        p.reference_strain_rate_1_s)
    assert p.room_temperature_K is None  # m = 0: the study gives none, so the kernel's defaults apply
    default = type(k)(E=1.0, nu=0.3, density=1.0, A=1.0)
    assert (k.T_room, k.T_melt) == (default.T_room, default.T_melt)
    hot = dataclasses.replace(p, m=1.0, room_temperature_K=300.0, melt_temperature_K=900.0).to_kernel()
    assert (hot.T_room, hot.T_melt, hot.m) == (300.0, 900.0, 1.0)


def test_kernel_options_follow_the_fidelity():
    p = study_params(load_study(HERE / "micro.toml"))
    f = p.fidelity
    o = f.options(p.shot, threads=2)
    assert o.dt_safety == f.time_step_safety and o.friction == p.shot.friction_coefficient and o.threads == 2
    assert o.window and o.window_lateral == o.window_depth == f.window_contact_radii
    assert o.rest_ke_fraction == f.settle_tolerance and o.relax_ke_fraction == f.relaxation_tolerance
    assert o.rest_v_fraction == pytest.approx(0.1 * math.sqrt(f.settle_tolerance))
    assert not dataclasses.replace(f, window_contact_radii=0.0).options(p.shot).window


def test_stages_are_called_with_the_typed_parameters_their_key_holds():
    graph = build_graph(HERE / "micro.toml")
    node = graph.stage_nodes("target_runs")[0]
    bound = node.task.bind(node.params)
    assert isinstance(bound["material"], MaterialParams) and isinstance(bound["fidelity"], FidelityParams)
    # what the stage receives is what its key holds, field for field
    assert canonical_json(bound) == canonical_json(node.params)


def test_a_parameter_dict_with_a_missing_or_unknown_field_is_refused():
    f = canonical_value(study_params(load_study(HERE / "micro.toml")).fidelity)
    with pytest.raises(TypeError, match="expected"):
        FidelityParams.from_canonical({k: v for k, v in f.items() if k != "grading_ratio"})
    with pytest.raises(TypeError, match="expected"):
        FidelityParams.from_canonical({**f, "precision": "float32"})
