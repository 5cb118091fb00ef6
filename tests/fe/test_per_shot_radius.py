"""Shots of their own size (a stream with a size spread): the kernel takes each shot's radius and mass.

One radius given as an array of equal radii is the single-radius kernel bit for bit; a mixed stream is,
shot by shot, the kernel run with each shot's own uniform-radius stream (the radius, mass and inertia
of shot i are shot i's, and nothing else of the run depends on the others')."""

import numpy as np
import pytest

from peenflow.fe.impact import ImpactRun, Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots, sphere_mass
from peenflow.testing import SAE1070

R = 0.29e-3
H = 50e-6
MAT = Material(**SAE1070)
# a 24-element periodic block: smaller than the window was validated for, and the same for both runs compared
pytestmark = pytest.mark.filterwarnings("ignore::peenflow.fe.window.WindowValidityWarning")
CENTRES = [[0.5 * H, 0.5 * H, -R - 1e-6], [-2.5 * H, 1.5 * H, -1.3 * R - 1e-6]]
VELOCITIES = [[0.0, 0.0, 40.0], [0.0, 0.0, 46.0]]


def _target():
    ax = np.linspace(-12 * H, 12 * H, 25)
    return Target(BoxMesh(ax, ax.copy(), graded_axis(0.2e-3, H, 0.6e-3, 1.2)), lateral="periodic")


def _same(a, b):
    assert np.array_equal(a.stress, b.stress) and np.array_equal(a.eps_p, b.eps_p)
    assert np.array_equal(a.displacement, b.displacement)
    for k in a.shots:
        assert np.array_equal(a.shots[k], b.shots[k]), k


def test_equal_radii_as_an_array_are_the_single_radius_kernel_bit_for_bit():
    one = Shots(CENTRES, VELOCITIES, radius=R, density=7800.0)
    each = Shots(CENTRES, VELOCITIES, radius=np.full(2, R), density=7800.0)
    assert isinstance(one.radius, float) and each.radius.shape == (2,)
    _same(run_impacts(_target(), MAT, one, Options()), run_impacts(_target(), MAT, each, Options()))


def test_each_shot_hits_with_its_own_radius_and_mass():
    radii = np.array([R, 1.3 * R])
    mixed = Shots(CENTRES, VELOCITIES, radius=radii, density=7800.0)
    a = ImpactRun(_target(), MAT, Options())
    rec_a = [a.impact(mixed, i) for i in range(2)]
    # the same two impacts, each from a stream whose every shot has that shot's radius
    b = ImpactRun(_target(), MAT, Options())
    rec_b = [b.impact(Shots(CENTRES, VELOCITIES, radius=float(r), density=7800.0), i) for i, r in enumerate(radii)]
    assert rec_a == rec_b
    assert np.array_equal(a.state.stress, b.state.stress) and np.array_equal(a.state.x, b.state.x)
    # the impact energy the records state is each shot's own 1/2 m_i v_i^2
    for rec, r, v in zip(rec_a, radii, VELOCITIES):
        assert rec.impact_energy == pytest.approx(0.5 * sphere_mass(r, 7800.0) * v[2] ** 2, rel=1e-12)
    # a larger, faster shot leaves a deeper dent than the first: not the nominal shot twice
    assert rec_a[1].max_approach > 1.3 * rec_a[0].max_approach


@pytest.mark.parametrize("radius, message", [(np.full(3, R), "one per shot"), (np.array([R, -R]), "positive")])
def test_radii_that_do_not_fit_the_shots_are_refused(radius, message):
    with pytest.raises(ValueError, match=message):
        Shots(CENTRES, VELOCITIES, radius=radius, density=7800.0)
