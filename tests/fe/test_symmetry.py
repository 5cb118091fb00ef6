"""Quarter and half models against the full block: the shot on a symmetry plane
keeps the motion its mirror half allows (issue 13 §2).

By mirror symmetry the full block's lateral impulses cancel, so a quarter
(normal impact) or half model (oblique, plane of incidence y = 0) must give
the same dent, rebound and stress field as the full block to round-off of the
explicit dynamics; the 1 % / 0.5 % tolerances are the issue's and are far
above what is measured (1e-5 on dent and restitution, 3e-4 of the peak on
the profile). Before the fix the quarter model was 9 % low on restitution
and 19 % off on the profile.
"""

import numpy as np
import pytest

from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_box
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots
from peenflow.testing import SAE1070 as SAE1070_LIBRARY

R = 0.29e-3
SAE1070 = {**SAE1070_LIBRARY, "C": 0.0}  # rate-independent: the symmetry checks need no rate term


def _meshes(h=25e-6):
    kw = dict(fine_half_width=0.15e-3, fine_depth=0.1e-3)
    full = graded_box(0.6e-3, 0.6e-3, h, **kw)
    quarter = graded_box(0.6e-3, 0.6e-3, h, quarter=True, **kw)
    return full, quarter, BoxMesh(full.x, quarter.y, full.z)


def _run(mesh, angle_deg, speed=55.0):
    th = np.radians(angle_deg)
    shots = Shots(centres=[[0.0, 0.0, -R - 1e-6]], velocities=[speed * np.array([np.cos(th), 0.0, np.sin(th)])],
                  radius=R, density=7800.0)
    res = run_impacts(Target(mesh), Material(**SAE1070), shots, Options(window=False))
    nnx, nny, _ = mesh.shape_nodes
    c = mesh.element_centroids()
    zs = np.unique(c[:, 2])
    meas = (np.abs(c[:, 0]) <= 0.1e-3) & (np.abs(c[:, 1]) <= 0.1e-3)
    profile = np.array([res.stress[meas & (c[:, 2] == z), 0].mean() for z in zs])
    s = res.shots
    return dict(dent=res.displacement[: nnx * nny, 2].max(), restitution=s["restitution"][0],
                vout=np.array([s["vout_x"][0], s["vout_y"][0], s["vout_z"][0]]), profile=profile)


def _assert_same(part, full):
    assert part["dent"] == pytest.approx(full["dent"], rel=0.01)
    assert part["restitution"] == pytest.approx(full["restitution"], rel=0.01)
    assert np.abs(part["profile"] - full["profile"]).max() <= 0.01 * np.abs(full["profile"]).max()
    # the rebound's lateral velocity is the full block's to 0.5 % of the speed
    assert np.abs(part["vout"] - full["vout"]).max() <= 0.005 * 55.0


def test_quarter_and_half_models_equal_full_block_normal_impact():
    full_mesh, quarter_mesh, half_mesh = _meshes()
    full = _run(full_mesh, 90.0)
    quarter = _run(quarter_mesh, 90.0)
    _assert_same(quarter, full)
    assert quarter["vout"][0] == 0.0 and quarter["vout"][1] == 0.0
    _assert_same(_run(half_mesh, 90.0), full)


def test_half_model_equals_full_block_oblique_impact():
    full_mesh, _, half_mesh = _meshes()
    full = _run(full_mesh, 45.0)
    half = _run(half_mesh, 45.0)
    _assert_same(half, full)
    assert half["vout"][1] == 0.0 and half["vout"][0] > 0.0  # slides along the stream, not across it


def test_shot_with_motion_a_symmetry_plane_cannot_hold_is_refused():
    _, quarter_mesh, _ = _meshes(50e-6)
    shots = Shots(centres=[[0.0, 0.0, -R - 1e-6]], velocities=[[5.0, 0.0, 50.0]], radius=R, density=7800.0)
    with pytest.raises(ValueError, match="symmetry plane"):
        run_impacts(Target(quarter_mesh), Material(**SAE1070), shots, Options(window=False))
