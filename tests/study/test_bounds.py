"""Issue 12 item 8: values outside the validated ranges are refused before any compute, naming the
key, the value and the range; a study overrides a bound only by naming the key."""

from __future__ import annotations

import math

import numpy as np
import pytest

from peenflow.study import load_study, validate_study
from peenflow.study.bounds import BOUNDS, RELATIVE_BOUNDS, bound_keys
from tasks.params import MaterialParams, ShotParams
from tasks.preflight import contact_radius, periodic_contact_half, study_problems


def _problems_for(write_study, changes, key):
    """The problems on ``key``: the study's own and the kernel limits the stage layer checks before compute."""
    return [p for p in study_problems(write_study(changes)) if p.startswith(key)]


@pytest.mark.parametrize("changes, key, shown", [
    ({"target.almen_intensity": "__delete__", "target.velocity_m_s": 1e6}, "target.velocity_m_s", "1000000.0"),
    ({"target.coverage_percent": 10000.0}, "target.coverage_percent", "10000.0"),
    ({"almen.velocities_m_s": [25.0, 500.0]}, "almen.velocities_m_s[1]", "500.0"),
    ({"target.angle_deg": 20.0}, "target.angle_deg", "20.0"),
    ({"almen.shot_counts": [10, 20, 40, 20000]}, "almen.shot_counts[3]", "20000"),
    ({"fidelity.element_size_um": 3.0}, "fidelity.element_size_um", "3.0"),
    ({"fidelity.time_step_safety": 0.01}, "fidelity.time_step_safety", "0.01"),
])
def test_the_issue_s_bad_values_are_refused_with_key_value_and_range(write_study, changes, key, shown):
    found = _problems_for(write_study, changes, key)
    assert len(found) == 1, found
    assert found[0].startswith(f"{key} = {shown}: outside the validated range [")
    assert "allow_outside_bounds" in found[0]


def test_a_rev_smaller_than_one_element_is_refused(write_study):
    # 60 um coarse elements; a 0.05 mm REV used to fail with "math domain error" in coverage_curve
    found = _problems_for(write_study, {"target.rev_size_mm": 0.05}, "target.rev_size_mm")
    assert found and "smaller than max(1 D = 0.58 mm, 10 elements of 60 um = 0.6 mm)" in found[0]


def test_an_element_too_large_for_the_dent_is_refused(write_study):
    # 100 um is inside the absolute range and below D / 5 = 116 um of the 0.58 mm shot; at 1 m/s on the
    # strip (contact radius 13.7 um on SAE 1070) it is 7.3 radii per element, the sweep's largest: allowed
    assert not _problems_for(write_study, {"fidelity.element_size_um": 100.0, "almen.velocities_m_s": [1.0, 55.0]},
                             "fidelity.element_size_um")
    # at 0.5 m/s (allowed on purpose) it is 10.4 radii: beyond what was run
    found = _problems_for(write_study, {"fidelity.element_size_um": 100.0, "almen.velocities_m_s": [0.5, 55.0],
                                        "study.allow_outside_bounds": ["almen.velocities_m_s"]},
                          "fidelity.element_size_um")
    assert found and "10.4 estimated contact radii" in found[0] and "at 0.5 m/s, A strip" in found[0]


def test_an_explicit_override_lets_a_value_through_and_only_that_one(write_study):
    path = write_study({"target.coverage_percent": 10000.0, "target.angle_deg": 20.0,
                        "study.allow_outside_bounds": ["target.coverage_percent"]})
    problems = validate_study(path)
    assert [p.split(" =")[0] for p in problems] == ["target.angle_deg"]
    s = load_study(write_study({"target.coverage_percent": 10000.0,
                                "study.allow_outside_bounds": ["target.coverage_percent"]}))
    assert s.target.coverage_percent == 10000.0
    # the override changes no result: it is not in the canonical form
    assert s.digest() == load_study(write_study({"target.coverage_percent": 10000.0,
                                                 "study.allow_outside_bounds": ["target.coverage_percent",
                                                                                "target.angle_deg"]})).digest()


def test_an_override_of_an_unknown_key_is_refused_with_a_suggestion(write_study):
    problems = validate_study(write_study({"study.allow_outside_bounds": ["target.coverage_percnt"]}))
    assert any(p.startswith('study.allow_outside_bounds[0] = "target.coverage_percnt": no bound on this key; '
                            'did you mean "target.coverage_percent"?') for p in problems)


@pytest.mark.parametrize("bound", [b for b in BOUNDS if not b.key.startswith(("materials.", "shots."))
                                   and b.key not in ("fidelity.fine_depth_mm", "coverage.max_shots")],
                         ids=lambda b: b.key)
def test_each_bound_refuses_just_outside_and_accepts_its_edges(write_study, bound):
    section, name = bound.key.split(".")
    listed = name in ("velocities_m_s", "angles_deg", "strip_angles_deg", "shot_counts")
    extra = {"target.almen_intensity": "__delete__"} if bound.key == "target.velocity_m_s" else {}

    def changes(v):
        if bound.key == "almen.shot_counts":
            v = int(v)
            return {**extra, bound.key: [max(v - 2, 1), max(v - 1, 2), v] if v >= 3 else [v, v + 1, v + 2]}
        if bound.key in ("almen.first_shots", "almen.max_shots"):  # the "auto" ladder, >= 3 rungs possible
            v = int(v)
            other = {"almen.max_shots": 4 * v} if name == "first_shots" else {"almen.first_shots": 1}
            return {"almen.shot_counts": "auto", **other, bound.key: v}
        if bound.key in ("almen.max_sequences", "almen.sequence_tolerance_mm"):  # adaptive sequences
            other = {"almen.sequence_tolerance_mm": 0.005} if name == "max_sequences" else {}
            return {"almen.sequences": 2, **other, bound.key: int(v) if name == "max_sequences" else v}
        if bound.key == "fidelity.extrapolate_intensity_from_um":  # a coarser level than the study's 25 um
            return {"fidelity.element_size_um": 25.0, bound.key: v}
        if bound.key == "fidelity.dent_element_size_um":  # finer than the study's elements
            return {"fidelity.element_size_um": 60.0, bound.key: v}
        if bound.key == "fidelity.intensity_extrapolation_order":
            return {"fidelity.element_size_um": 25.0, "fidelity.extrapolate_intensity_from_um": 40.0, bound.key: v}
        if isinstance(bound.low, float) and name in ("sequences", "grid_points"):
            v = int(v)
        return {**extra, bound.key: [v] if listed else v}

    for edge in (bound.low, bound.high):
        if edge is None or (edge == 0.0 and name == "window_contact_radii"):
            continue
        inside = _problems_for(write_study, changes(edge), bound.key)
        assert not [p for p in inside if "validated range" in p], inside
    # just outside each side: refused, by the bound or (where the bound is the hard limit, e.g. 90 deg)
    # by the model; at least one side by the bound itself
    by_bound = 0
    for outside in ([bound.high * 1.5] if bound.high else []) + ([bound.low * 0.5] if bound.low else []):
        found = _problems_for(write_study, changes(outside), bound.key)
        assert found, (bound.key, outside)
        by_bound += any("outside the validated range" in p for p in found)
    assert by_bound >= 1


def test_a_hardening_exponent_the_kernel_refuses_is_refused_by_the_loader(write_study):
    inline = {"name": "X", "youngs_modulus_GPa": 70.0, "poisson_ratio": 0.33, "density_kg_m3": 2800.0,
              "johnson_cook": {"A_MPa": 400.0, "B_MPa": 300.0, "C": 0.01, "n": 0.0}}
    problems = validate_study(write_study({"materials": {"X": inline}, "target.material": "X"}))
    assert any(p.startswith("materials.X.johnson_cook.n = 0.0: expected a value > 0") for p in problems), problems
    inline["johnson_cook"] = {"A_MPa": 400.0, "B_MPa": 300.0, "C": 0.01, "n": 0.3, "melt_temperature_K": 250.0}
    problems = validate_study(write_study({"materials": {"X": inline}, "target.material": "X"}))
    assert any("melt_temperature_K = 250.0 must be above room_temperature_K = 293.0" in p for p in problems)
    inline["johnson_cook"] = {"A_MPa": 400.0, "B_MPa": 300.0, "C": 0.01, "n": 0.3, "room_temperature_K": 200.0,
                              "melt_temperature_K": 250.0}  # above room, below the 293 K every run starts at
    problems = validate_study(write_study({"materials": {"X": inline}, "target.material": "X"}))
    assert any("melt_temperature_K = 250.0 must be above" in p and "293 K" in p for p in problems), problems
    inline["johnson_cook"] = {"A_MPa": 400.0, "B_MPa": 300.0, "C": 0.01, "n": 5.0}
    problems = validate_study(write_study({"materials": {"X": inline}, "target.material": "X"}))
    assert any(p.startswith("materials.X.johnson_cook.n = 5.0: outside the validated range") for p in problems)


@pytest.mark.parametrize("bad", ["nan", "inf", "-inf"])
def test_nan_or_inf_in_the_measured_profile_is_refused(write_study, tmp_path, bad):
    csv = tmp_path / "profile.csv"
    csv.write_text(f"depth_mm,stress_MPa,component\n0.0,-400,xx\n0.1,{bad},xx\n")
    problems = validate_study(write_study({"target.measured_profile_csv": str(csv)}))
    assert any("target.measured_profile_csv" in p and "bad data on line(s) 3" in p for p in problems), problems


def test_the_contact_radius_estimate_is_the_kernel_s():
    """The stage layer's check reads the estimate the kernel sizes its windows by, on the same inputs."""
    from peenflow.fe.shots import Shots
    from peenflow.fe.window import contact_estimates

    material = MaterialParams(71e9, 0.33, 2800.0, 434e6, 303e6, 0.3, 0.01, 0.0, 1.0, None, None)
    shot = ShotParams(0.29e-3, 7800.0, 0.2)
    for v in (1.0, 5.0, 55.0, 400.0):
        a_kernel, _ = contact_estimates(Shots([[0, 0, -1.0]], [[0, 0, v]], 0.29e-3, 7800.0), material.to_kernel(), v)
        assert contact_radius(shot, material, v) == a_kernel


def test_every_bound_is_documented():
    from pathlib import Path

    doc = (Path(__file__).resolve().parents[2] / "docs" / "study-files.md").read_text()
    section = doc.split("## Bounds", 1)[1] if "## Bounds" in doc else ""
    missing = [k for k in bound_keys() if f"`{k}`" not in section]
    assert not missing, f"docs/study-files.md '## Bounds' lacks {missing}"
    for b in BOUNDS:  # the documented range is the enforced one
        assert b.describe().replace(" " + b.unit, "") in section or b.describe() in section, b.key
    assert len(RELATIVE_BOUNDS) >= 4


def test_the_documented_example_message_is_the_real_one(write_study):
    from pathlib import Path

    doc = (Path(__file__).resolve().parents[2] / "docs" / "study-files.md").read_text()
    found = _problems_for(write_study, {"target.coverage_percent": 10000.0}, "target.coverage_percent")
    assert found and f"  - {found[0]}\n" in doc


@pytest.mark.parametrize("speed, angle_deg, h", [(30.0, 65.0, 40e-6), (55.0, 45.0, 25e-6), (47.0, 90.0, 60e-6)])
def test_the_periodic_contact_zone_is_the_kernel_s(speed, angle_deg, h):
    """The stage layer's periodic-REV check (tasks.preflight.periodic_contact_half) is the kernel's own
    test in seam_shift: a period just under twice it is refused by the kernel, one just over is not."""
    from types import SimpleNamespace

    from peenflow.fe.johnson_cook import Material
    from peenflow.fe.periodic import seam_shift
    from peenflow.fe.shots import Shots
    from peenflow.fe import Options

    E, nu, rho, A = 71e9, 0.33, 2800.0, 434e6
    mat = Material(E=E, nu=nu, density=rho, A=A, B=303e6, n=0.3, C=0.0, m=0.0, ref_strain_rate=1.0)
    R, rho_s = 0.29e-3, 7800.0
    a = math.radians(angle_deg)
    vel = np.array([speed * math.cos(a), 0.0, speed * math.sin(a)])
    shot = np.array([0.0, 0.0, -R - 1e-6])
    shots = Shots([shot], [vel], R, rho_s)
    half = periodic_contact_half(ShotParams(R, rho_s, 0.2),
                                 MaterialParams(E, nu, rho, A, 303e6, 0.3, 0.0, 0.0, 1.0, None, None), speed, angle_deg, h)

    def model(period):
        n = 16
        axis = np.linspace(-0.5 * period, 0.5 * period, n + 1)
        mesh = SimpleNamespace(x_step=h, y_step=h, x=axis, y=axis)
        return SimpleNamespace(mesh=mesh, period=(period, period), nx=n, ny=n)

    with pytest.raises(ValueError, match="too short for the shot's contact"):
        seam_shift(model(2.0 * half * (1.0 - 1e-9)), shot, vel, shots, mat, Options(window=False))
    seam_shift(model(2.0 * half * (1.0 + 1e-9)), shot, vel, shots, mat, Options(window=False))


_ANGLE = "target.angle_deg = 20.0: outside the validated range [30, 90] deg"


@pytest.mark.parametrize("unknown, shown", [
    ({"target.angel": 3.0}, "target.angel = 3.0: unknown key"),  # in the same section as the bad value
    ({"seeds.bogus": 1}, "seeds.bogus = 1: unknown key"),  # in another section
    ({"dmn": {"x": 1}}, 'dmn: unknown section; did you mean "dmin"?'),
    ({"study.nme": "x"}, 'study.nme: unknown key; did you mean "name"?'),
])
def test_check_lists_an_unknown_key_and_an_out_of_range_value_at_once(write_study, unknown, shown):
    """One `peenflow check` lists both kinds of problem: the bound is checked on the value the file gives
    even when the section's model refused a key beside it."""
    import subprocess
    import sys

    study = write_study({"target.angle_deg": 20.0, **unknown})
    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", "check", str(study)], capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    lines = [ln.strip() for ln in proc.stderr.splitlines()]
    assert "2 problems in study file" in lines[0], proc.stderr
    assert any(ln.startswith(f"- {shown}") for ln in lines), proc.stderr
    assert any(ln.startswith(f"- {_ANGLE}") for ln in lines), proc.stderr


def test_a_value_the_model_refuses_is_not_reported_twice(write_study):
    # 100 deg is impossible (the model's (0, 90]); the bound [30, 90] would say it again
    problems = validate_study(write_study({"target.angle_deg": 100.0, "target.angel": 3.0}))
    assert [p.split(":")[0] for p in problems] == ["target.angle_deg = 100.0", "target.angel = 3.0"], problems


@pytest.mark.parametrize("key", ["almen.angles_deg", "target.angle_deg", "dmin.strip_angles_deg"])
def test_shallow_angles_are_admitted_down_to_30_deg_and_refused_below_naming_the_key(write_study, key):
    """Shops peen bores and fillets at 30-45 deg: the single-impact and strip checks at 30 deg
    (docs/validation.md, shallow angles) admit it; below it the shot's slide is unmeasured."""
    listed = key != "target.angle_deg"
    for angle in (30.0, 35.0, 40.0):
        inside = _problems_for(write_study, {key: [angle, 90.0] if listed else angle}, key)
        assert not inside, inside
    found = _problems_for(write_study, {key: [29.0, 90.0] if listed else 29.0}, key)
    shown = f"{key}[0]" if listed else key
    assert len(found) == 1 and found[0].startswith(f"{shown} = 29.0: outside the validated range [30, 90] deg"), found
    assert "allow_outside_bounds" in found[0]
