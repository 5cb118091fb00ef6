"""Fixity masks (peenflow.fe.boundary) and the periodic faces' mesh check and masters (peenflow.fe.periodic)."""

import numpy as np
import pytest

from peenflow.fe.boundary import FIX_X, FIX_Y, FIX_Z, TIE_X, TIE_Y, TIED, node_fixity, tied_master
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.periodic import check_periodic_mesh, tie_masters

AX = np.linspace(0.0, 0.3e-3, 4)
MESH = BoxMesh(AX, np.linspace(0.0, 0.4e-3, 5), np.linspace(0.0, 0.2e-3, 3))  # 4 x 5 x 3 nodes


def fields(bc):
    nnx, nny, nnz = MESH.shape_nodes
    return bc.reshape(nnz, nny, nnx)


def test_symmetric_sides_hold_their_normal_and_a_fixed_bottom_holds_all():
    bc = fields(node_fixity(MESH, "symmetric", "fixed"))
    assert np.all(bc[-1] == FIX_X | FIX_Y | FIX_Z)  # the bottom: embedded
    inner = bc[:-1]
    assert np.all(inner[:, 1:-1, 0] == FIX_X) and np.all(inner[:, 1:-1, -1] == FIX_X)  # x faces: u_x only
    assert np.all(inner[:, 0, 1:-1] == FIX_Y) and np.all(inner[:, -1, 1:-1] == FIX_Y)  # y faces: u_y only
    assert np.all(inner[:, 0, 0] == FIX_X | FIX_Y)  # an edge on two planes holds both normals
    assert np.all(inner[:, 1:-1, 1:-1] == 0)  # the interior and the top are free


def test_free_faces_and_free_bottom_hold_nothing():
    assert not node_fixity(MESH, "free", "free").any()
    assert not fields(node_fixity(MESH, "free", "fixed"))[:-1].any()


def test_unknown_conditions_are_refused():
    with pytest.raises(ValueError, match="lateral must be one of"):
        node_fixity(MESH, "clamped")
    with pytest.raises(ValueError, match="bottom one of"):
        node_fixity(MESH, "free", "pinned")


def test_periodic_slaves_map_to_masters_one_period_away():
    bc = node_fixity(MESH, "periodic", "free")
    nnx, nny, _ = MESH.shape_nodes
    b3 = fields(bc)
    assert np.all(b3[:, :, -1] & TIE_X) and np.all(b3[:, -1, :] & TIE_Y)
    assert not (b3[:, :-1, :-1] & TIED).any()  # every other node is its own master
    masters = tie_masters(bc, nnx, nny)
    X = MESH.node_coordinates()
    slaves = np.nonzero(bc & TIED)[0]
    period = np.array([AX[-1] - AX[0], 0.4e-3, 0.0])
    shift = np.column_stack([(bc[slaves] & TIE_X) != 0, (bc[slaves] & TIE_Y) != 0, np.zeros(len(slaves))])
    np.testing.assert_allclose(X[slaves] - X[masters[slaves]], shift * period, atol=1e-15)
    assert not (bc[masters] & TIED).any()  # a master is never itself a slave (the corner chains to (0, 0))
    assert all(tied_master(n, bc[n], nnx, nny) == masters[n] for n in slaves)  # the solver's own rule


def test_periodic_faces_need_a_uniform_lateral_spacing():
    check_periodic_mesh(MESH)  # uniform: accepted
    graded = BoxMesh(graded_axis(0.1e-3, 25e-6, 0.4e-3, 1.2), AX, AX)
    with pytest.raises(ValueError, match="x axis is not uniform"):
        check_periodic_mesh(graded)
    with pytest.raises(ValueError, match="at least 2 elements"):
        check_periodic_mesh(BoxMesh(np.array([0.0, 1e-4]), AX, AX))
