"""Hertz: elastic impact of a rigid S230 shot on elastic SAE 1070 (quarter model).

Reference values are recomputed from Hertz's formulas (peenflow.fe.shots.hertz):
at 55 m/s delta = 12.86 um, a = 61.1 um, F = 234 N, t = 0.688 us; at 1 m/s
0.521 um, 12.3 um, 1.91 N, 1.53 us.

Quarter model: symmetric planes x = 0 and y = 0 through the impact point,
fine zone 2a x 2a x 1.5a with a / h elements across the contact radius,
graded (1.2) to ``extent`` x a, fixed bottom, frictionless (Hertz).

What is measured (docs/validation.md section 2) and what the tolerances stand on:
* the errors do not change from a/h = 4 to 8: no discretisation error left;
* domain truncation: a fixed bottom at 25 a stiffens the target (1 m/s:
  approach -1.3 %, force +2.8 %); at 100 a, -0.5 % / +1.1 %;
* target inertia, which quasi-static Hertz leaves out: at 55 m/s the
  approach and force are ~4 % low whatever the domain, but with the
  target's density divided by 100 (same shot, same strains, waves 10x
  faster) the same impact is within 2.2 % of Hertz. The large strains
  (~14 % under the shot) are not the cause.
"""

import numpy as np
import pytest

from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots, hertz

R = 0.29e-3
ELASTIC = Material(E=205e9, nu=0.29, density=7800.0, A=1e13)


def hertz_run(speed, a_over_h, extent=25.0, target_density=7800.0):
    target_material = Material(E=ELASTIC.E, nu=ELASTIC.nu, density=target_density, A=ELASTIC.A)
    shots = Shots(centres=[[0.0, 0.0, -R - 1e-9]], velocities=[[0.0, 0.0, speed]], radius=R, density=7800.0)
    ref = hertz(R, shots.mass, speed, ELASTIC.E, ELASTIC.nu)
    a = ref["a"]
    h = a / a_over_h
    ax = graded_axis(2 * a, h, extent * a, 1.2)
    mesh = BoxMesh(ax, ax.copy(), graded_axis(1.5 * a, h, extent * a, 1.2))
    res = run_impacts(Target(mesh), target_material, shots, Options(window=False, friction=0.0))
    s = res.shots
    got = {"delta": s["max_approach"][0], "a": s["contact_radius"][0], "F": s["peak_force"][0],
           "t": s["contact_duration"][0]}
    return got, ref, res


def test_hertz_checks_formulas():
    m = 7800.0 * 4.0 / 3.0 * np.pi * R**3
    ref = hertz(R, m, 55.0, 205e9, 0.29)
    # the brief's values, to the digits it quotes
    assert ref["delta"] == pytest.approx(12.86e-6, rel=1e-3)
    assert ref["a"] == pytest.approx(61.1e-6, rel=1e-3)
    assert ref["F"] == pytest.approx(234.0, rel=2e-3)
    assert ref["t"] == pytest.approx(0.688e-6, rel=1e-3)


@pytest.mark.parametrize("speed,extent,tol", [(1.0, 100.0, 0.02), (20.0, 25.0, 0.03)])
def test_hertz_low_speed(speed, extent, tol):
    # 1 m/s on a deep domain (measured <= 1.2 %); 20 m/s on the short one (<= 2.6 %)
    got, ref, res = hertz_run(speed, 4, extent)
    for k in ("delta", "a", "F", "t"):
        assert got[k] == pytest.approx(ref[k], rel=tol), k
    # elastic: the shot leaves with nearly all its energy (Hunter: wave loss ~1.04 (v/c0)^0.6)
    c0 = np.sqrt(ELASTIC.E / ELASTIC.density)
    assert res.shots["restitution"][0] ** 2 > 1 - 2.0 * 1.04 * (speed / c0) ** 0.6
    assert res.energy_error < 0.01
    assert res.eps_p.max() == 0.0


@pytest.fixture(scope="module")
def hertz55():
    return hertz_run(55.0, 4, extent=100.0)


def test_hertz_55(hertz55):
    # measured -3.8 % approach, -4.1 % force (target inertia, see the module docstring)
    got, ref, res = hertz55
    for k in ("delta", "F"):
        assert got[k] == pytest.approx(ref[k], rel=0.05), k
    for k in ("a", "t"):
        assert got[k] == pytest.approx(ref[k], rel=0.03), k
    assert res.energy_error < 0.01


@pytest.mark.slow  # 40 s: ten times the steps of test_hertz_55; it explains that test's 4 %, which stays
def test_hertz_55_without_target_inertia(hertz55):
    """The 55 m/s impact on a target 100x lighter (waves 10x faster, same
    stiffness, so the same strains): quasi-static Hertz within 3 % on
    approach, radius and duration (measured -1.0 %, -0.7 %, -0.9 %) and
    within 4 % on the peak force (+3.4 %; +2.95 % at a/h = 6, so it is the
    contact's discretisation: test_light_target_force_error_is_discretisation,
    slow). The earlier +2.1 % force came from the
    quarter model's shot drifting sideways off its symmetry planes (issue 13
    section 2; the shot is held on them now). So the ~4 % of test_hertz_55
    is the real target's inertia, and the approach is lower with it."""
    got, ref, res = hertz_run(55.0, 4, extent=100.0, target_density=78.0)
    for k in ("delta", "a", "t"):
        assert got[k] == pytest.approx(ref[k], rel=0.03), k
    assert got["F"] == pytest.approx(ref["F"], rel=0.04)
    heavy = hertz55[0]
    assert heavy["delta"] < got["delta"] * (1 - 0.02)
    assert res.energy_error < 0.01


@pytest.mark.slow
def test_light_target_force_error_is_discretisation():
    """The +3.4 % peak force of the light target at a/h = 4 (test above) is the
    contact's discretisation: it falls with refinement (+2.95 % at a/h = 6)
    and is inside the 3 % the other quantities keep."""
    coarse, ref, _ = hertz_run(55.0, 4, extent=100.0, target_density=78.0)
    fine, _, _ = hertz_run(55.0, 6, extent=100.0, target_density=78.0)
    assert abs(fine["F"] / ref["F"] - 1) < abs(coarse["F"] / ref["F"] - 1)
    for k in ("delta", "a", "F", "t"):
        assert fine[k] == pytest.approx(ref[k], rel=0.03), k


@pytest.mark.slow
def test_hertz_converged_with_refinement():
    """a/h = 4 -> 8 moves every quantity by < 1.5 % (measured < 1 %, docs/validation.md section 2),
    and the refined values keep the tolerances of test_hertz_55."""
    coarse, ref, _ = hertz_run(55.0, 4)
    fine, ref, res = hertz_run(55.0, 8)
    for k in ("delta", "a", "F", "t"):
        assert fine[k] == pytest.approx(coarse[k], rel=0.015), k
    for k in ("delta", "F"):
        assert fine[k] == pytest.approx(ref[k], rel=0.05), k
    for k in ("a", "t"):
        assert fine[k] == pytest.approx(ref[k], rel=0.03), k
