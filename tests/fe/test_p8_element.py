"""The physical one-point element with plasticity at its 2 x 2 x 2 Gauss points ("physical8" of
benchmarks/bbar/element_bbar.py; a comparison element for issue 13 §1, not part of the kernel).

Its elastic response is by construction the kernel's physical element: the same centroid rates and the same
assumed-strain hourglass fields, with the bending modes' transverse strain ``-nu_bar`` times theirs (the
plane-stress condensation of element.py 5b). What is checked: its 24 x 24 stiffness is the one-point
physical element's on boxes of several aspect ratios; a uniform strain, elastic and through the Johnson-Cook
return, gives every point the one-point element's stress (the hourglass fields vanish); a rigid rotation
creates no stress; an elastic impact has the one-point element's rebound; a plastic impact closes its energy
balance.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from benchmarks.bbar.element_bbar import p8_pass  # noqa: E402
from peenflow.fe.johnson_cook import Material  # noqa: E402
from tests.fe.test_bbar_element import (PLASTIC, STEEL, _mat, element_matrix, rigid_rotation_stress,  # noqa: E402
                                        uniform_strain_against_one_point)


def _p8(mesh, x, v, f, st, mat, dt):
    nnx, nny, _ = mesh.shape_nodes
    nx, ny, nz = mesh.shape_elements
    f[:] = 0.0
    return p8_pass(x, v, f, *st, mesh.element_volumes(), mat, dt, nnx, nny, nx, ny, 0, nx, 0, ny, 0, nz)


@pytest.mark.parametrize("box", [(1.0, 1.0, 1.0), (2.5, 1.0, 1.0), (1.0, 0.4, 2.0)])
def test_elastic_stiffness_is_the_one_point_physical_element(box):
    """Same 24 x 24 stiffness as the kernel's physical element (all 18 non-rigid modes, bending and
    torsion included), to the probe's round-off: the 8-point sampling changes only the plastic response."""
    h = 1e-4
    mat = _mat()
    k0 = element_matrix(0, *(h * b for b in box), mat)
    k3 = element_matrix(3, *(h * b for b in box), mat)
    assert np.abs(k3 - k0).max() <= 1e-7 * np.abs(k0).max()
    assert np.linalg.matrix_rank(k3, tol=1e-8 * np.abs(k3).max()) == 18


@pytest.mark.parametrize("material", [STEEL, PLASTIC], ids=["elastic", "johnson-cook"])
def test_uniform_strain_equals_one_point_element(material):
    """A uniform velocity gradient with spin on an affinely distorted mesh, 40 steps: the hourglass rates
    vanish, so every Gauss point follows the one-point element's stress, plastic strain and flow stress."""
    uniform_strain_against_one_point(material, _p8, 1e-9)


def test_rigid_rotation_creates_no_stress():
    """A finite rigid rotation (0.3 rad) and translation over one step of a distorted mesh: no stress, no force."""
    stress, force = rigid_rotation_stress(_p8)
    assert stress <= 1e-9 and force <= 1e-9


def test_impacts_against_the_one_point_element():
    """Through the driver's explicit loop (tests/fe/test_bbar_element.py checks it is the kernel's): an elastic
    45-degree impact rebounds as with the kernel's element (restitution to 1e-4, lateral rebound speed to
    1e-4: their elastic stiffness is the same, they differ only in how the hourglass stress is rotated), and a
    plastic normal impact closes its energy balance as the kernel's element does (0.4-0.9 % measured)."""
    import bench_hourglass as bh

    from benchmarks.bbar import driver as d
    from peenflow.fe.model import Target
    from peenflow.fe.shots import Shots

    elastic = dict(bh.SAE1070, A=1e13)
    mesh = bh.block(100e-6, True)
    th = math.radians(45.0)
    shots = Shots(centres=[[0, 0, -bh.R - 1e-6]], velocities=[[10 * math.cos(th), 0, 10 * math.sin(th)]],
                  radius=bh.R, density=7800.0)
    opt = d._options()
    one, p8 = (d.simulate(Target(mesh), Material(**elastic), shots, opt, el) for el in ("physical", "physical8"))
    assert abs(p8.shots["restitution"][0] - one.shots["restitution"][0]) <= 1e-4 * one.shots["restitution"][0]
    assert abs(p8.shots["vout_x"][0] - one.shots["vout_x"][0]) <= 1e-4 * abs(one.shots["vout_x"][0])
    mesh = bh.block(100e-6, False)
    shots = Shots(centres=[[0, 0, -bh.R - 1e-6]], velocities=[[0, 0, 40.0]], radius=bh.R, density=7800.0)
    plastic = d.simulate(Target(mesh), Material(**bh.SAE1070), shots, opt, "physical8")
    assert plastic.eps_p.max() > 0.01
    assert plastic.shots["energy_error"][0] < 0.02
