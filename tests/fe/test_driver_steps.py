"""The driver's small steps (peenflow.fe.impact.ImpactRun): a ladder of relaxed snapshots taken along one
sequence is the same, bit for bit, as separate runs of each prefix; records are named; shots go in order."""

import numpy as np
import pytest

from peenflow.fe.impact import ImpactRun, Options, ShotRecord, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots

R = 0.29e-3
MAT = Material(E=205e9, nu=0.29, density=7800.0, A=1408e6, B=600.8e6, n=0.234, C=0.0134, m=0.0)
OPT = Options(window_warning=False)


def rev():
    ax = np.linspace(-0.6e-3, 0.6e-3, 25)
    return Target(BoxMesh(ax, ax.copy(), graded_axis(0.15e-3, 50e-6, 0.5e-3, 1.3)))


def stream():
    xy = [(0.0, 0.0), (90e-6, -60e-6), (-0.2e-3, 0.15e-3), (30e-6, 40e-6)]
    v = [[0, 0, 45.0], [6.0, 0, 40.0], [0, 0, 55.0], [0, -4.0, 50.0]]
    return Shots([[x, y, -R - 2e-6] for x, y in xy], v, R, 7800.0)


def prefix(shots, n):
    return Shots(shots.centres[:n], shots.velocities[:n], shots.radius, shots.density)


def test_a_ladder_along_one_sequence_equals_separate_runs_of_each_prefix():
    target, shots = rev(), stream()
    run = ImpactRun(target, MAT, OPT)
    for n in (2, 4):
        for i in range(run.shots_done, n):
            rec = run.impact(shots, i)
            assert isinstance(rec, ShotRecord) and rec.shot_index == i and rec.hit
        snap = run.snapshot(prefix(shots, n))  # rest criteria scaled by the rung's own shots
        alone = run_impacts(target, MAT, prefix(shots, n), OPT)
        assert snap.n_shots == n
        np.testing.assert_array_equal(snap.stress, alone.stress)
        np.testing.assert_array_equal(snap.eps_p, alone.eps_p)
        np.testing.assert_array_equal(snap.displacement, alone.displacement)
        for name, col in alone.shots.items():
            np.testing.assert_array_equal(run.records[name], col)
    # the named record says what the result's columns say
    last = ShotRecord.from_row(run.records[-1])
    assert last.restitution == pytest.approx(-last.vout_z / last.vin_z) and last.peak_force > 0
    assert last.contact_duration == pytest.approx(last.t_separate - last.t_contact)


def test_shots_run_in_order_each_once():
    run = ImpactRun(rev(), MAT, OPT)
    with pytest.raises(ValueError, match="not the next one"):
        run.impact(stream(), 1)
    run.impact(stream(), 0)
    with pytest.raises(ValueError, match="shots_done = 1"):
        run.impact(stream(), 0)


def test_a_state_of_another_mesh_is_refused():
    ck = ImpactRun(rev(), MAT, OPT).checkpoint()
    ax = np.linspace(0.0, 0.2e-3, 5)
    with pytest.raises(ValueError, match="does not match the target mesh"):
        ImpactRun(Target(BoxMesh(ax, ax, ax)), MAT, OPT, state=ck)
