"""Periodic lateral faces: the mesh they need, their tying, and the roll that keeps impacts off the seam.

``Target(lateral="periodic")`` ties the node ``i = nnx - 1`` to ``i = 0``
(same ``j, k``) shifted by the period ``Lx = x[-1] - x[0]``, likewise ``j``
(:mod:`peenflow.fe.boundary` marks such slaves with ``TIE_X`` / ``TIE_Y``;
:func:`tie_masters` gives each its master; the solver folds slave forces into
masters and copies their motion back). It needs a uniform lateral spacing
(:func:`check_periodic_mesh`): the target is then translation-invariant
laterally, so before a shot whose window (or, without a window, whose
contact zone) would reach the seam the driver ROLLS the whole state by whole
elements (:func:`roll`, by :func:`seam_shift`) to bring the landing point to
the middle of the mesh, runs the shot with an ordinary window and rolls back
once it has settled. The shot's contact zone must fit in half a period
(ValueError otherwise). Effect against symmetric faces on a REV:
docs/validation.md section 7; its cost: docs/performance.md section 4.
"""

from __future__ import annotations

import math

import numpy as np

from peenflow.fe.boundary import TIE_X, TIE_Y
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh
from peenflow.fe.shots import Shots
from peenflow.fe.window import contact_estimates, window_size


def check_periodic_mesh(mesh: BoxMesh) -> None:
    """Periodic lateral faces need a uniform lateral spacing (the driver moves the
    state by whole elements to keep each impact away from the seam)."""
    for name in ("x", "y"):
        a = getattr(mesh, name)
        h = np.diff(a)
        if len(h) < 2:
            raise ValueError(f"periodic lateral faces: the {name} axis needs at least 2 elements")
        if np.max(np.abs(h - h.mean())) > 1e-9 * h.mean():
            raise ValueError(
                f"periodic lateral faces need a uniform lateral spacing; the {name} axis is not uniform "
                f"(element sizes {h.min():.6g} to {h.max():.6g} m)")


def tie_masters(bc: np.ndarray, nnx: int, nny: int) -> np.ndarray:
    """Per node: its master (itself for an untied node), (n_nodes,) int64."""
    n = np.arange(len(bc), dtype=np.int64)
    tx = (bc & TIE_X) != 0
    ty = (bc & TIE_Y) != 0
    return n - tx * (nnx - 1) - ty * nnx * (nny - 1)


def contact_reach(radius: float, contact_time: float, tangential_speed: float, element: float) -> float:
    """How far (m) a shot's contact zone reaches from its landing point along one axis: the contact
    search box 1.25 R, the tangential travel during 1.5 estimated contact times (``contact_time`` s,
    ``tangential_speed`` m s-1 along the axis), and a margin of two elements (``element`` m).  A
    periodic target's period must exceed twice this (:func:`seam_shift` refuses it otherwise; the
    stage layer checks a study's REVs with it before any compute)."""
    return 1.25 * radius + abs(1.5 * contact_time * tangential_speed) + 2.0 * element


def seam_shift(model, shot: np.ndarray, vel: np.ndarray, shots: Shots, material: Material,
               options, i: int = 0) -> tuple[int, int]:
    """Whole-element roll (:func:`roll`) that keeps a shot's window and
    contact clear of a periodic target's seam (0, 0 when they already are), for shot ``i`` of
    ``shots`` (its radius and mass size the contact).

    The landing point is where the sphere's lowest point reaches ``z = 0`` on
    its line; the reach around it is the window's (``options.window``) or the
    contact's search box plus the tangential travel (full-mesh runs). The
    contact must fit in half a period (ValueError otherwise)."""
    R = shots.radius_of(i)
    t_l = (-R - shot[2]) / vel[2]
    xl, yl = shot[0] + vel[0] * t_l, shot[1] + vel[1] * t_l
    a_est, t_est = contact_estimates(shots, material, abs(vel[2]), i)
    travel = 1.5 * t_est * vel[0:2]
    h = (model.mesh.x_step, model.mesh.y_step)
    contact = [contact_reach(R, t_est, vel[a], h[a]) for a in (0, 1)]
    for a, L in enumerate(model.period):
        if 2.0 * contact[a] >= L:
            raise ValueError(
                f"periodic target: the period along {'xy'[a]} ({L:.4g} m) is too short for the shot's contact "
                f"zone (2 x {contact[a]:.4g} m: 1.25 R + tangential travel + 2 elements each side)")
    if options.window:
        lat_x, lat_y, _ = window_size(model, material, options, a_est, t_est, xl, yl)
        reach = [(lat + max(-travel[a], 0.0), lat + max(travel[a], 0.0)) for a, lat in ((0, lat_x), (1, lat_y))]
        reach = [(max(lo, c), max(hi, c)) for (lo, hi), c in zip(reach, contact)]
    else:
        reach = [(c, c) for c in contact]
    return _shift_to_middle(model, xl, yl, reach[0], reach[1])


def _shift_to_middle(model, xl: float, yl: float, reach_x: tuple, reach_y: tuple) -> tuple[int, int]:
    """Whole-element shift ``(sx, sy)`` for :func:`roll` that keeps
    ``[xl - reach_x[0], xl + reach_x[1]] x [...]`` clear of the seam: 0
    along an axis where that box already is (at least one element from
    it), else the one that brings ``xl`` (``yl``) to the middle column (row)."""
    out = []
    for c, (lo, hi), ax, n in ((xl, reach_x, model.mesh.x, model.nx), (yl, reach_y, model.mesh.y, model.ny)):
        if c - lo >= ax[1] and c + hi <= ax[-2]:
            out.append(0)
        else:
            h = (ax[-1] - ax[0]) / n
            out.append(int(math.floor((c - ax[0]) / h)) - n // 2)
    return out[0], out[1]


def roll(model, state, sx: int, sy: int) -> None:
    """Periodic target: move the material by ``(-sx, -sy)`` whole elements, in place.

    What was at element column ``i`` is afterwards at ``(i - sx) mod nx``
    (rows likewise): the displacements ``x - X0``, velocities, forces and
    every element field are permuted; slaves are unfolded again. The
    target is translation-invariant laterally (uniform spacing), so a
    rolled state is the same physical state seen from another origin;
    ``roll(model, s, -sx, -sy)`` undoes it up to the round-off of ``x - X0``.
    """
    if not model.periodic:
        raise ValueError("roll: only a periodic target can be rolled")
    sx %= model.nx
    sy %= model.ny
    if sx == 0 and sy == 0:
        return
    nnz, nny, nnx, nz, ny, nx = model.nnz, model.nny, model.nnx, model.nz, model.ny, model.nx

    def nodal(a, unfold):
        # on a new array, assigned back (a reshape of a non-contiguous array would be a copy)
        a3 = np.array(a).reshape(nnz, nny, nnx, 3)
        u = np.roll(a3[:, :ny, :nx], (-sy, -sx), axis=(1, 2))
        a3[:, :ny, :nx] = u
        a3[:, :ny, nx] = u[:, :, 0] if unfold else 0.0
        a3[:, ny, :] = a3[:, 0, :] if unfold else 0.0
        a[:] = a3.reshape(a.shape)

    u = state.x - model.nodes0
    nodal(u, True)
    state.x[:] = model.nodes0 + u
    lx, ly = model.period
    slaves = model._slaves
    state.x[slaves] = state.x[model.masters[slaves]]
    state.x[slaves, 0] += np.where(model.bc[slaves] & TIE_X, lx, 0.0)
    state.x[slaves, 1] += np.where(model.bc[slaves] & TIE_Y, ly, 0.0)
    nodal(state.v, True)
    nodal(state.f, False)
    for a in (state.stress, state.eps_p, state.sy_static, state.hg, state.temp):
        a[:] = np.roll(a.reshape((nz, ny, nx) + a.shape[1:]), (-sy, -sx), axis=(1, 2)).reshape(a.shape)
