"""Instabilities stop the run with a clear KernelInstabilityError."""

import numpy as np
import pytest

from peenflow.fe import solver as S
from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import graded_box
from peenflow.fe.model import Target
from peenflow.fe.safety import KernelInstabilityError, Stop, check_status
from peenflow.fe.shots import Shots

R = 0.29e-3


def test_crushing_impact_raises_with_advice():
    # 3 km/s on 50 um elements with a weak material: elements under the shot
    # are crushed; the run must stop with a named cause, not return garbage
    t = Target(graded_box(0.4e-3, 0.3e-3, 50e-6))
    mat = Material(E=205e9, nu=0.29, density=7800.0, A=50e6)
    shots = Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, 3000.0]], radius=R, density=7800.0)
    with pytest.raises(KernelInstabilityError) as err:
        run_impacts(t, mat, shots, Options())
    msg = str(err.value)
    assert "shot 0" in msg and "What to change" in msg
    assert err.value.status in (S.ST_NEGATIVE_VOLUME, S.ST_DISTORTION, S.ST_DT_COLLAPSE, S.ST_RUNAWAY, S.ST_NAN)


@pytest.mark.parametrize("code", [S.ST_NEGATIVE_VOLUME, S.ST_DISTORTION, S.ST_NAN, S.ST_DT_COLLAPSE,
                                  S.ST_RUNAWAY, S.ST_MAX_STEPS])
def test_every_status_has_a_message(code):
    with pytest.raises(KernelInstabilityError) as err:
        check_status(code, where="impact", shot_index=3, time=1e-6)
    assert "unknown" not in str(err.value) and "shot 3" in str(err.value)


def test_a_stop_carries_its_reason_and_pickles_whole():
    """A stop raised on a dask worker reaches the scheduler with its reason and message."""
    import pickle

    with pytest.raises(KernelInstabilityError) as err:
        check_status(S.ST_MAX_STEPS, where="final relaxation", time=1e-6, relaxing=True)
    assert err.value.reason is Stop.MAX_STEPS and err.value.status == S.ST_MAX_STEPS
    # a relaxation's stop names the relaxation's own damping and tolerance
    assert "options.relax_damping" in str(err.value) and "options.relax_ke_fraction" in str(err.value)
    back = pickle.loads(pickle.dumps(err.value))
    assert str(back) == str(err.value) and back.reason is Stop.MAX_STEPS and back.where == "final relaxation"


def test_ok_status_passes():
    check_status(S.ST_OK, where="impact")


def test_step_budget_exhaustion_raises():
    t = Target(graded_box(0.3e-3, 0.2e-3, 25e-6))
    mat = Material(E=205e9, nu=0.29, density=7800.0, A=1408e6)
    shots = Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, 30.0]], radius=R, density=7800.0)
    with pytest.raises(KernelInstabilityError, match="max_steps"):
        run_impacts(t, mat, shots, Options(max_steps=50))


def test_free_flight_costs_no_steps():
    # event-driven time: a shot launched 10 mm away takes the same number of
    # target steps as one launched 1 um away (and gives the same dent)
    t = Target(graded_box(0.3e-3, 0.2e-3, 25e-6))
    mat = Material(E=205e9, nu=0.29, density=7800.0, A=1408e6)
    near = Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, 30.0]], radius=R, density=7800.0)
    far = Shots(centres=[[0, 0, -R - 1e-2]], velocities=[[0, 0, 30.0]], radius=R, density=7800.0)
    a = run_impacts(t, mat, near, Options())
    b = run_impacts(t, mat, far, Options())
    assert a.shots["steps"][0] == b.shots["steps"][0]
    np.testing.assert_allclose(a.displacement, b.displacement, rtol=0, atol=1e-12)
    # the clock includes the free flight
    assert b.shots["t_contact"][0] == pytest.approx(1e-2 / 30.0, rel=1e-3)


@pytest.mark.parametrize("key,value", [("dt_safety", 1.2), ("dt_safety", float("nan")), ("friction", -0.1),
                                       ("hourglass_plastic_floor", 0.0), ("window_lateral", 0.0),
                                       ("rest_ke_fraction", 0.0), ("max_steps", 0), ("threads", 0),
                                       ("relax_cg_rtol", 1.5), ("runaway_fraction", -1.0),
                                       ("window_faces", "viscous-spring"), ("relax_method", "newton")])
def test_bad_option_is_refused_before_any_compute(key, value):
    with pytest.raises(ValueError, match=rf"Options\.{key} = "):
        Options(**{key: value})
