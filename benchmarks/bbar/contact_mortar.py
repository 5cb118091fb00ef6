"""Mortar (weighted-gap) sphere contact, for comparison with the kernel's node contact (issue 13 §1-§2).

The kernel's :func:`peenflow.fe.contact.contact_kinematic` holds every top-surface NODE out of the rigid
sphere: the bilinear faces between the nodes (chords of the sphere) cut into it, and the load ends at the
outermost node in contact. Here each node instead holds its WEIGHTED GAP

    g_n = int_S N_n gap dA / int_S N_n dA        (gap = |p - c| - R, p on the bilinear top faces),

at zero where it would be negative: the mortar method with lumped (dual) multipliers, the
variationally consistent discretisation of the contact constraint (Puso & Laursen 2004; Popp et al. 2010).
The face integrals use 3 x 3 Gauss points per face on the reference area. Enforcement is kinematic, as in
the kernel: every active node (g_n < 0) moves along its radius by -g_n, the opposite impulse goes to the
shot, Jacobi passes repeated until the largest remaining weighted penetration is below 1e-3 of the
largest one found (g contracts monotonically: the eigenvalues of L^-1 M, lumped and consistent face
mass, lie in (0, 1]). Friction, the shot's spin and the dissipation are the kernel's (the lines below the
normal correction are a copy of ``contact_kinematic``'s).

Measured (BENCHMARKS.md 4c, "Mortar contact"): not kept; the node contact stays.

Same signature and return as :func:`peenflow.fe.contact.contact_kinematic`; the driver
(:mod:`benchmarks.bbar.driver`) selects it with ``contact="mortar"``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from peenflow.fe.contact import MIRROR_X, MIRROR_Y, S_I, S_M, S_MIRROR, S_MU, S_R, _move_node

_jit = dict(cache=True, nogil=True, error_model="numpy")
MORTAR_ITERS = 16  # Jacobi passes at most (the runs converge in fewer: 64 passes and 1e-5 give the same figures)
MORTAR_TOL = 1e-3  # remaining weighted penetration / the largest found, to stop
_G3 = (-0.7745966692414834, 0.0, 0.7745966692414834)
_W3 = (0.5555555555555556, 0.8888888888888888, 0.5555555555555556)


@njit(**_jit, inline="always")
def _accumulate(g, w, s, nw, gq, first):
    """A Gauss point's share ``nw`` (= N_n w_q, m^2) of its gap ``gq`` (m) into the near node ``s`` (-1: not near)."""
    if s >= 0:
        g[s] += nw * gq
        if first:
            w[s] += nw


@njit(**_jit)
def _weighted_gaps(x, xs_ref, ys_ref, nnx, ia, ib, ja, jb, slot, nbx, cx, cy, cz, R, w, g, first):
    """Weighted gap ``g[a]`` (m) of each near node ``a`` (``slot``: the node box ``(i - ia) + nbx (j - ja)``
    -> its index ``a``, -1 if not near): ``g_n = int N_n (|p - c| - R) dA / int N_n dA`` over the top faces
    of the box ``[ia, ib] x [ja, jb]``, 3 x 3 Gauss points per bilinear face on its reference area. ``w[a]``
    (m^2, ``int N_n dA``) is filled when ``first`` (it does not change during the passes)."""
    for a in range(g.shape[0]):
        g[a] = 0.0
        if first:
            w[a] = 0.0
    for j in range(ja, jb):
        for i in range(ia, ib):
            s00 = slot[(i - ia) + nbx * (j - ja)]
            s10 = slot[(i + 1 - ia) + nbx * (j - ja)]
            s01 = slot[(i - ia) + nbx * (j + 1 - ja)]
            s11 = slot[(i + 1 - ia) + nbx * (j + 1 - ja)]
            if s00 < 0 and s10 < 0 and s01 < 0 and s11 < 0:
                continue
            n00 = i + nnx * j
            n10 = n00 + 1
            n01 = n00 + nnx
            n11 = n01 + 1
            area4 = 0.25 * (xs_ref[i + 1] - xs_ref[i]) * (ys_ref[j + 1] - ys_ref[j])
            for qa in range(3):
                xi = _G3[qa]
                for qb in range(3):
                    et = _G3[qb]
                    wq = _W3[qa] * _W3[qb] * area4
                    N00 = 0.25 * (1 - xi) * (1 - et)
                    N10 = 0.25 * (1 + xi) * (1 - et)
                    N01 = 0.25 * (1 - xi) * (1 + et)
                    N11 = 0.25 * (1 + xi) * (1 + et)
                    px = N00 * x[n00, 0] + N10 * x[n10, 0] + N01 * x[n01, 0] + N11 * x[n11, 0] - cx
                    py = N00 * x[n00, 1] + N10 * x[n10, 1] + N01 * x[n01, 1] + N11 * x[n11, 1] - cy
                    pz = N00 * x[n00, 2] + N10 * x[n10, 2] + N01 * x[n01, 2] + N11 * x[n11, 2] - cz
                    gq = math.sqrt(px * px + py * py + pz * pz) - R
                    _accumulate(g, w, s00, N00 * wq, gq, first)
                    _accumulate(g, w, s10, N10 * wq, gq, first)
                    _accumulate(g, w, s01, N01 * wq, gq, first)
                    _accumulate(g, w, s11, N11 * wq, gq, first)
    for a in range(g.shape[0]):
        g[a] /= w[a]


@njit(**_jit)
def contact_mortar(x, v, mass, bc, xs_ref, ys_ref, nnx, shot, dt, ni0, ni1, nj0, nj1, cand, dn):
    """Mortar contact of the sphere ``shot`` on top-surface nodes ``i in [ni0, ni1], j in [nj0, nj1]``
    (module docstring); arguments and return as :func:`peenflow.fe.contact.contact_kinematic`."""
    R = shot[S_R]
    M = shot[S_M]
    # translation and spin components the shot may take (symmetry planes)
    mirror = int(shot[S_MIRROR])
    kx = 0.0 if mirror & MIRROR_X else 1.0
    ky = 0.0 if mirror & MIRROR_Y else 1.0
    kwx = 0.0 if mirror & MIRROR_Y else 1.0
    kwy = 0.0 if mirror & MIRROR_X else 1.0
    kwz = kx * ky
    cx = shot[0]
    cy = shot[1]
    cz = shot[2]
    margin = 0.25 * R
    ia = np.searchsorted(xs_ref, cx - R - margin)
    ib = np.searchsorted(xs_ref, cx + R + margin)
    ja = np.searchsorted(ys_ref, cy - R - margin)
    jb = np.searchsorted(ys_ref, cy + R + margin)
    ia = max(ia - 1, ni0)
    ja = max(ja - 1, nj0)
    ib = min(ib, ni1)
    jb = min(jb, nj1)
    nc = 0
    ke_nodes0 = 0.0
    nbx = ib - ia + 1
    nby = jb - ja + 1
    slot = np.full(nbx * nby, -1, dtype=np.int64)
    hmax = 0.0
    for i in range(ia, ib):
        hmax = max(hmax, xs_ref[i + 1] - xs_ref[i])
    for j in range(ja, jb):
        hmax = max(hmax, ys_ref[j + 1] - ys_ref[j])
    # near: within 1.5 face widths of the sphere. A face's points lie within its diagonal (< 1.5 h) of a
    # corner, so a face whose corners are all farther cannot cut it; only near nodes can become active,
    # but every face next to one enters its weighted gap
    dlim = 1.5 * hmax
    for j in range(ja, jb + 1):
        for i in range(ia, ib + 1):
            n = i + nnx * j
            ddx = x[n, 0] - cx
            ddy = x[n, 1] - cy
            ddz = x[n, 2] - cz
            if math.sqrt(ddx * ddx + ddy * ddy + ddz * ddz) - R > dlim:
                continue
            slot[(i - ia) + nbx * (j - ja)] = nc
            cand[nc] = n
            dn[nc, 0] = 0.0
            dn[nc, 1] = 0.0
            dn[nc, 2] = 0.0
            dn[nc, 3] = 0.0
            ke_nodes0 += 0.5 * mass[n] * (v[n, 0] ** 2 + v[n, 1] ** 2 + v[n, 2] ** 2)
            nc += 1
    if nc == 0:
        return 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    jx = 0.0
    jy = 0.0
    jz = 0.0
    max_ov = 0.0
    idt = 1.0 / dt
    wgt = np.zeros(nc)
    gap = np.zeros(nc)
    for it in range(MORTAR_ITERS):  # Jacobi passes
        px = py = pz = 0.0
        cx, cy, cz = shot[0], shot[1], shot[2]
        _weighted_gaps(x, xs_ref, ys_ref, nnx, ia, ib, ja, jb, slot, nbx, cx, cy, cz, R, wgt, gap, it == 0)
        worst = 0.0
        for a in range(nc):
            if gap[a] >= 0.0:
                continue
            n = cand[a]
            dx = x[n, 0] - cx
            dy = x[n, 1] - cy
            dz = x[n, 2] - cz
            r = math.sqrt(dx * dx + dy * dy + dz * dz)
            ov = -gap[a]
            if ov > max_ov:
                max_ov = ov
            if ov > worst:
                worst = ov
            s = ov / r
            ux, uy, uz = _move_node(x, v, n, bc[n], dx * s, dy * s, dz * s, 1.0, idt)
            m = mass[n]
            px += m * ux * idt
            py += m * uy * idt
            pz += m * uz * idt
            dn[a, 0] += m * ux * idt
            dn[a, 1] += m * uy * idt
            dn[a, 2] += m * uz * idt
            dn[a, 3] = 1.0
        # equal and opposite impulse on the shot (less what the mirror half cancels)
        px *= kx
        py *= ky
        shot[3] -= px / M
        shot[4] -= py / M
        shot[5] -= pz / M
        shot[0] -= px / M * dt
        shot[1] -= py / M * dt
        shot[2] -= pz / M * dt
        jx -= px
        jy -= py
        jz -= pz
        if worst <= MORTAR_TOL * (max_ov + 1e-30):
            break
    # friction on the nodes in contact
    mu = shot[S_MU]
    ncontact = 0
    max_rad = 0.0
    sj = 0.0
    sjr2 = 0.0
    cx, cy, cz = shot[0], shot[1], shot[2]
    fpx = fpy = fpz = 0.0
    lx = ly = lz = 0.0
    for a in range(nc):
        if dn[a, 3] == 0.0:
            continue
        ncontact += 1
        n = cand[a]
        dx = x[n, 0] - cx
        dy = x[n, 1] - cy
        dz = x[n, 2] - cz
        r = math.sqrt(dx * dx + dy * dy + dz * dz)
        rad = math.sqrt(dx * dx + dy * dy)
        if rad > max_rad:
            max_rad = rad
        jmag = math.sqrt(dn[a, 0] ** 2 + dn[a, 1] ** 2 + dn[a, 2] ** 2)
        sj += jmag
        sjr2 += jmag * rad * rad
        if mu <= 0.0:
            continue
        nx_ = dx / r
        ny_ = dy / r
        nz_ = dz / r
        jn = dn[a, 0] * nx_ + dn[a, 1] * ny_ + dn[a, 2] * nz_
        if jn <= 0.0:
            continue
        # shot surface velocity at the contact point c + R n
        rx = R * nx_
        ry = R * ny_
        rz = R * nz_
        wx = shot[6]
        wy = shot[7]
        wz = shot[8]
        sx = shot[3] + wy * rz - wz * ry
        sy = shot[4] + wz * rx - wx * rz
        sz = shot[5] + wx * ry - wy * rx
        vrx = v[n, 0] - sx
        vry = v[n, 1] - sy
        vrz = v[n, 2] - sz
        vn = vrx * nx_ + vry * ny_ + vrz * nz_
        vtx = vrx - vn * nx_
        vty = vry - vn * ny_
        vtz = vrz - vn * nz_
        vt = math.sqrt(vtx * vtx + vty * vty + vtz * vtz)
        if vt <= 0.0:
            continue
        m = mass[n]
        # impulse that stops the sliding (node mass + shot translational/rotational compliance)
        meff = 1.0 / (1.0 / m + 1.0 / M + R * R / shot[S_I])
        jt = meff * vt
        if jt > mu * jn:
            jt = mu * jn
        tx = vtx / vt
        ty = vty / vt
        tz = vtz / vt
        # impulse -jt t on the node (masked by its fixities), +jt t on the shot
        # at R n; the shot's share is summed and applied after the loop
        # (Jacobi), so the result does not depend on the node order
        ux, uy, uz = _move_node(x, v, n, bc[n], -jt * tx / m, -jt * ty / m, -jt * tz / m, dt, 1.0)
        px = -m * ux
        py = -m * uy
        pz = -m * uz
        fpx += px
        fpy += py
        fpz += pz
        lx += ry * pz - rz * py
        ly += rz * px - rx * pz
        lz += rx * py - ry * px
        dn[a, 0] -= px
        dn[a, 1] -= py
        dn[a, 2] -= pz
    fpx *= kx
    fpy *= ky
    lx *= kwx
    ly *= kwy
    lz *= kwz
    shot[3] += fpx / M
    shot[4] += fpy / M
    shot[5] += fpz / M
    shot[0] += fpx / M * dt
    shot[1] += fpy / M * dt
    shot[2] += fpz / M * dt
    iI = 1.0 / shot[S_I]
    shot[6] += lx * iI
    shot[7] += ly * iI
    shot[8] += lz * iI
    jx += fpx
    jy += fpy
    jz += fpz
    # dissipation: minus the power of the contact impulses on the nodes'
    # velocity relative to the shot surface, after correction (normal part ~0
    # for nodes that follow the sphere; friction gives mu j_n |v_slip|)
    de = 0.0
    cx = shot[0]
    cy = shot[1]
    cz = shot[2]
    for a in range(nc):
        if dn[a, 3] == 0.0:
            continue
        n = cand[a]
        dx = x[n, 0] - cx
        dy = x[n, 1] - cy
        dz = x[n, 2] - cz
        r = math.sqrt(dx * dx + dy * dy + dz * dz)
        rx = R * dx / r
        ry = R * dy / r
        rz = R * dz / r
        sx = shot[3] + shot[7] * rz - shot[8] * ry
        sy = shot[4] + shot[8] * rx - shot[6] * rz
        sz = shot[5] + shot[6] * ry - shot[7] * rx
        de -= dn[a, 0] * (v[n, 0] - sx) + dn[a, 1] * (v[n, 1] - sy) + dn[a, 2] * (v[n, 2] - sz)
    ke_nodes1 = 0.0
    for a in range(nc):
        n = cand[a]
        ke_nodes1 += 0.5 * mass[n] * (v[n, 0] ** 2 + v[n, 1] ** 2 + v[n, 2] ** 2)
    return ncontact, jx, jy, jz, de, max_ov, max_rad, ke_nodes1 - ke_nodes0, sjr2 / sj if sj > 0.0 else 0.0
