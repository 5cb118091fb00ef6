"""Central-difference explicit loop over an active window (numba).

One call of :func:`run_phase` integrates the target inside an element index
box (the *active window*; the whole mesh for a full run or a global
relaxation) with at most one shot in contact, until a stop condition:

* ``MODE_IMPACT``: the shot hits, leaves (no node in contact and the shot
  moving away from the surface), then the window is damped to rest;
* ``MODE_RELAX``: damped from the start until at rest.

Step ``n -> n+1`` (lumped mass, variable step)::

    dt   = safety * min_e dt_e       (recomputed EVERY step from the deformed
                                      elements, + contact/hourglass terms)
    v   += (dt_prev + dt)/2 * (f/m - alpha v_mid)    (alpha: damping, 0 in impact)
    x   += dt v ;  c_shot += dt V_shot
    kinematic contact correction (contact.py)
    element pass at x_{n+1}: stresses, forces f, next dt_e

Window: nodes on a window face that is not a mesh face are held fixed (their
elements outside the window are not integrated), or, given a viscous-spring
boundary (``bnodes``, see :func:`_node_update`), move against springs and
dashpots that stand for the exterior; nodes on mesh faces keep the mesh's
boundary conditions (``bc`` masks).

Rate term at rest: while damping (settling, relaxation) the elements use
``mat_static`` (the Johnson-Cook rate term switched off). The rest state is
reached on a time scale far longer than 1/eps_dot_0; with the rate term on,
the over-stress left by the impact (a few % for C = 0.0134) would relax by
viscoplastic creep that the damping cannot speed up (measured: 15 000 steps
instead of a few hundred, velocities ~ creep rate x element size).

"At rest": every 10 steps after separation (impact) or always (relax),
``KE_window <= rest_ke`` (J) AND ``max |v| <= rest_v`` (m/s); both are set by
the driver (relative to the shot's impact energy and speed).

Safety (status codes, the Python driver raises, see safety.py): NaN/Inf,
negative volume, excessive distortion (V/V0 outside [0.1, 10]), step collapse
(``dt < dt_floor``), runaway energy (energy balance error > ``runaway`` x the
reference energy), step budget exhausted.
"""

from __future__ import annotations

import math

import numpy as np

from peenflow._jit import jit
from peenflow.fe.boundary import TIE_X, TIE_Y, TIED, tied_master
from peenflow.fe.contact import contact_kinematic
from peenflow.fe.element import element_rows, element_rows_parallel
# the status codes and their messages live in safety.py
from peenflow.fe.safety import (ST_DISTORTION, ST_DT_COLLAPSE, ST_MAX_STEPS, ST_NAN,  # noqa: F401
                                ST_NEGATIVE_VOLUME, ST_OK, ST_RUNAWAY)

MODE_IMPACT = 0
MODE_RELAX = 1


# control vector indices (float64)
C_DT_PREV, C_DT_NEXT, C_TIME, C_SAFETY, C_ALPHA, C_REST_KE, C_REST_V, C_E_REF = 0, 1, 2, 3, 4, 5, 6, 7
C_DT_FLOOR, C_RUNAWAY, C_OMEGA_C2, C_FORCE_SCALE, C_SPONGE_W, C_SPONGE_A = 8, 9, 10, 11, 12, 13
N_CTL = 14

# energy accumulator indices (J, cumulative over the run)
E_INT, E_PL, E_HG, E_VISC, E_CONTACT, E_DAMP = 0, 1, 2, 3, 4, 5
N_EN = 6

# phase info indices
I_STATUS, I_STEPS, I_T_CONTACT, I_T_SEPARATE, I_MAX_APPROACH, I_MAX_OVERLAP = 0, 1, 2, 3, 4, 5
I_PEAK_FORCE, I_MAX_RADIUS, I_VX, I_VY, I_VZ, I_E_ERR, I_DT_MIN, I_NREC = 6, 7, 8, 9, 10, 11, 12, 13
I_KE_END, I_VMAX_END, I_SEPARATED, I_DT_START, I_R2_AT_PEAK, I_HG_PEAK = 14, 15, 16, 17, 18, 19
I_INT_PEAK = 20  # peak internal energy gained in the phase (J), the pair of I_HG_PEAK
N_INFO = 21

# record columns: time, force on shot (3, full-shot equivalent), shot centre (3),
# shot velocity (3), KE target, KE shot, W_int, W_plastic, W_hg, W_visc, E_contact, E_damp, dt
N_REC = 19


@jit(inline="always")
def _advance_dof(v, x, f, n, a, c1, c2, im, force, dt, fixed):
    """Velocity and position of dof ``(n, a)`` by the damped central difference
    ``v+ = (c1 v- + im force) c2`` (``c1 = 1 - alpha dt/2``, ``c2 = 1 / (1 + alpha dt/2)``,
    ``im = dt / m``; 0 where ``fixed``), then ``x += dt v+``; clears the force.
    Returns ``(v-, v+)`` (m/s)."""
    vo = v[n, a]
    vn = (c1 * vo + im * force) * c2
    if fixed:
        vn = 0.0
    v[n, a] = vn
    x[n, a] += dt * vn
    f[n, a] = 0.0
    return vo, vn


@jit
def _node_update(x, v, f, mass, bc, nnx, nny, ni0, ni1, nj0, nj1, nk0, nk1, hold, dt, dt_avg, alpha,
                 sponge_w, sponge_a, bnodes, bk, bcd, bf0, bx0, bdash, periodic, lx, ly):
    """Velocity/position update of the window's nodes; zeroes ``f`` there.

    Nodes within ``sponge_w`` node layers of a held window face get extra
    mass-proportional damping ``sponge_a * (1 - d / sponge_w)^2`` (1/s; d the
    distance in layers): an absorbing layer that keeps the held faces from
    reflecting the impact's waves back to the contact.

    Window-face nodes listed in ``bnodes`` (viscous-spring boundary, see
    :func:`peenflow.fe.window.viscous_spring_boundary`) are not held: they move
    under the window's element forces plus the exterior's
    ``bf0 - bk (x - bx0) - bdash bcd v`` (N; per component, faces are axis-aligned
    so the spring and dashpot matrices are diagonal). The dashpot is
    integrated semi-implicitly like the mass damping. The work done on the
    exterior joins the damping work.

    Periodic lateral faces (``periodic``; slave nodes carry the ``bc`` bits
    8 / 16, :mod:`peenflow.fe.boundary`): first every slave's force is
    folded into its master (fixed order: deterministic); ``mass`` holds the
    master's combined mass and 0 for a slave; the master is updated like any
    node, then the slave takes its velocity and its position plus the period
    (``lx``, ``ly`` m). A window that holds a slave must hold its master: it
    spans the period along that axis (:meth:`peenflow.fe.model.Model.phase`).

    Returns ``(KE, max speed, damping + boundary work)``.
    """
    ke = 0.0
    vmax2 = 0.0
    wd = 0.0
    # slaves lie on the last column / row: only a window reaching them ties
    tie = periodic and (ni1 == nnx - 1 or nj1 == nny - 1)
    if tie:
        for k in range(nk0, nk1 + 1):
            for j in range(nj0, nj1 + 1):
                base = nnx * (j + nny * k)
                for i in range(ni0, ni1 + 1):
                    n = base + i
                    b = bc[n]
                    if b & TIED:
                        m = tied_master(n, b, nnx, nny)
                        f[m, 0] += f[n, 0]
                        f[m, 1] += f[n, 1]
                        f[m, 2] += f[n, 2]
                        f[n, 0] = 0.0
                        f[n, 1] = 0.0
                        f[n, 2] = 0.0
    for q in range(bnodes.shape[0]):
        n = bnodes[q]
        im = dt_avg / mass[n]
        b = bc[n]
        s2 = 0.0
        for a in range(3):
            fb = bf0[q, a] - bk[q, a] * (x[n, a] - bx0[q, a])
            al = alpha + bdash * bcd[q, a] / mass[n]
            c1 = 1.0 - 0.5 * al * dt_avg
            c2 = 1.0 / (1.0 + 0.5 * al * dt_avg)
            vo, vn = _advance_dof(v, x, f, n, a, c1, c2, im, f[n, a] + fb, dt, b & (1 << a))
            s2 += vn * vn
            vm = 0.5 * (vo + vn)
            # work on the exterior (spring + frozen reaction + dashpot) and by the mass damping
            wd += (al * mass[n] * vm - fb) * vm * dt_avg
        ke += 0.5 * mass[n] * s2
        if s2 > vmax2:
            vmax2 = s2
    for k in range(nk0, nk1 + 1):
        hk = (k == nk0 and hold[4]) or (k == nk1 and hold[5])
        for j in range(nj0, nj1 + 1):
            hj = (j == nj0 and hold[2]) or (j == nj1 and hold[3])
            base = nnx * (j + nny * k)
            for i in range(ni0, ni1 + 1):
                n = base + i
                if tie and bc[n] & TIED:
                    # slave: its master (lower index) is already updated
                    b = bc[n]
                    m = tied_master(n, b, nnx, nny)
                    ox = lx if b & TIE_X else 0.0
                    oy = ly if b & TIE_Y else 0.0
                    v[n, 0] = v[m, 0]
                    v[n, 1] = v[m, 1]
                    v[n, 2] = v[m, 2]
                    x[n, 0] = x[m, 0] + ox
                    x[n, 1] = x[m, 1] + oy
                    x[n, 2] = x[m, 2]
                    f[n, 0] = 0.0
                    f[n, 1] = 0.0
                    f[n, 2] = 0.0
                    continue
                if hk or hj or (i == ni0 and hold[0]) or (i == ni1 and hold[1]):
                    f[n, 0] = 0.0
                    f[n, 1] = 0.0
                    f[n, 2] = 0.0
                    continue
                al = alpha
                if sponge_w > 0:
                    dmin = sponge_w
                    if hold[0] and i - ni0 < dmin:
                        dmin = i - ni0
                    if hold[1] and ni1 - i < dmin:
                        dmin = ni1 - i
                    if hold[2] and j - nj0 < dmin:
                        dmin = j - nj0
                    if hold[3] and nj1 - j < dmin:
                        dmin = nj1 - j
                    if hold[5] and nk1 - k < dmin:
                        dmin = nk1 - k
                    if dmin < sponge_w:
                        r = 1.0 - dmin / sponge_w
                        al += sponge_a * r * r
                c1 = 1.0 - 0.5 * al * dt_avg
                c2 = 1.0 / (1.0 + 0.5 * al * dt_avg)
                im = dt_avg / mass[n]
                b = bc[n]
                s2 = 0.0
                sm = 0.0
                for a in range(3):
                    vo, vn = _advance_dof(v, x, f, n, a, c1, c2, im, f[n, a], dt, b & (1 << a))
                    s2 += vn * vn
                    vm = 0.5 * (vo + vn)
                    sm += vm * vm
                ke += 0.5 * mass[n] * s2
                wd += al * mass[n] * sm * dt_avg
                if s2 > vmax2:
                    vmax2 = s2
    return ke, math.sqrt(vmax2), wd


@jit
def run_phase(
    mode, parallel, max_steps, record_every,
    x, v, f, mass, bc, stress, eps_p, sy_static, hg, temp, vol0, mat_dyn, mat_static,
    xs_ref, ys_ref, nnx, nny, nx, ny, win, hold,
    shot, ctl, energy, rec, info, cand, dn, bnodes, bk, bcd, bf0, bx0, bnd_settle, periodic,
):
    """Integrate until the phase ends (see module docstring). All arrays are
    updated in place; ``info`` receives the phase summary, ``rec`` the records.
    Viscous-spring window faces (``bnodes``...; see :func:`_node_update`)
    while the window settles after the shot's separation: ``bnd_settle`` =
    0 springs and dashpots, 1 held where they are (their kinetic energy then
    joins the damping work), 2 springs only (the dashpots over-damp the
    faces' slow static return: 400 instead of 240 settle steps on the strip
    REV; only the rest state matters then). ``periodic``: tied lateral
    faces (``mass``: the masters' combined masses, 0 on slaves; see
    :func:`_node_update`). Returns the status code."""
    i0, i1, j0, j1, k0, k1 = win[0], win[1], win[2], win[3], win[4], win[5]
    ni0, ni1, nj0, nj1, nk0, nk1 = i0, i1, j0, j1, k0, k1  # node index box (inclusive)
    dt_prev = ctl[C_DT_PREV]
    dt_next = ctl[C_DT_NEXT]
    time = ctl[C_TIME]
    safety = ctl[C_SAFETY]
    alpha = ctl[C_ALPHA]
    rest_ke = ctl[C_REST_KE]
    rest_v = ctl[C_REST_V]
    e_ref = ctl[C_E_REF]
    om_c2 = ctl[C_OMEGA_C2]
    fscale = ctl[C_FORCE_SCALE]
    sponge_w = int(ctl[C_SPONGE_W])
    nb = bnodes.shape[0]
    bdash = 1.0
    lx = xs_ref[nnx - 1] - xs_ref[0]
    ly = ys_ref[nny - 1] - ys_ref[0]
    shot_active = mode == MODE_IMPACT
    damping = mode == MODE_RELAX
    separated = False
    ke_shot = 0.0
    if shot_active:
        ke_shot = 0.5 * shot[9] * (shot[3] ** 2 + shot[4] ** 2 + shot[5] ** 2) + 0.5 * shot[10] * (
            shot[6] ** 2 + shot[7] ** 2 + shot[8] ** 2)
    # starting energy of the phase (target KE from the current velocities)
    ke0 = 0.0
    for k in range(nk0, nk1 + 1):
        for j in range(nj0, nj1 + 1):
            for i in range(ni0, ni1 + 1):
                n = i + nnx * (j + nny * k)
                ke0 += 0.5 * mass[n] * (v[n, 0] ** 2 + v[n, 1] ** 2 + v[n, 2] ** 2)
    e_start = ke0 + ke_shot + energy[E_INT] + energy[E_HG] + energy[E_VISC] + energy[E_CONTACT] + energy[E_DAMP]
    info[:] = 0.0
    info[I_T_CONTACT] = -1.0
    info[I_T_SEPARATE] = -1.0
    info[I_DT_MIN] = 1e30
    info[I_DT_START] = dt_next * safety
    nrec = 0
    hg_start = energy[E_HG]
    int_start = energy[E_INT]
    status = ST_OK
    max_err = 0.0
    ke = ke0
    vmax = 0.0
    dt = dt_next * safety
    jx = 0.0
    jy = 0.0
    jz = 0.0
    for step in range(max_steps):
        if dt_next <= 0.0:
            status = ST_NAN
            break
        om2 = 4.0 / (dt_next * dt_next) + om_c2
        dt = safety * 2.0 / math.sqrt(om2)
        if dt < ctl[C_DT_FLOOR]:
            status = ST_DT_COLLAPSE
            break
        if dt_prev <= 0.0:
            dt_prev = dt
        dt_avg = 0.5 * (dt_prev + dt)
        a_d = alpha if damping else 0.0
        ke, vmax, wd = _node_update(x, v, f, mass, bc, nnx, nny, ni0, ni1, nj0, nj1, nk0, nk1, hold, dt, dt_avg, a_d,
                                     sponge_w, ctl[C_SPONGE_A], bnodes[:nb], bk, bcd, bf0, bx0, bdash,
                                     periodic, lx, ly)
        energy[E_DAMP] += wd
        ncon = 0
        if shot_active:
            shot[0] += dt * shot[3]
            shot[1] += dt * shot[4]
            shot[2] += dt * shot[5]
            ncon, jx, jy, jz, de, mov, mrad, dke, r2m = contact_kinematic(
                x, v, mass, bc, xs_ref, ys_ref, nnx, shot, dt, ni0, ni1, nj0, nj1, cand, dn)
            ke += dke
            energy[E_CONTACT] += de
            if ncon > 0:
                if info[I_T_CONTACT] < 0.0:
                    info[I_T_CONTACT] = time
                fmag = math.sqrt(jx * jx + jy * jy + jz * jz) / dt * fscale
                if fmag > info[I_PEAK_FORCE]:
                    info[I_PEAK_FORCE] = fmag
                    info[I_R2_AT_PEAK] = r2m
                if mov > info[I_MAX_OVERLAP]:
                    info[I_MAX_OVERLAP] = mov
                if mrad > info[I_MAX_RADIUS]:
                    info[I_MAX_RADIUS] = mrad
            app = shot[2] + shot[11]
            if app > info[I_MAX_APPROACH]:
                info[I_MAX_APPROACH] = app
            ke_shot = 0.5 * shot[9] * (shot[3] ** 2 + shot[4] ** 2 + shot[5] ** 2) + 0.5 * shot[10] * (
                shot[6] ** 2 + shot[7] ** 2 + shot[8] ** 2)
            if ncon == 0 and info[I_T_CONTACT] >= 0.0 and shot[5] < 0.0:
                # left the surface: record the rebound, start settling
                separated = True
                if bnd_settle == 2:
                    bdash = 0.0
                if bnd_settle == 1 and nb > 0:
                    for q in range(nb):
                        n = bnodes[q]
                        e_b = 0.5 * mass[n] * (v[n, 0] ** 2 + v[n, 1] ** 2 + v[n, 2] ** 2)
                        energy[E_DAMP] += e_b
                        ke -= e_b
                        v[n, 0] = 0.0
                        v[n, 1] = 0.0
                        v[n, 2] = 0.0
                    nb = 0
                shot_active = False
                damping = True
                info[I_T_SEPARATE] = time + dt
                info[I_VX] = shot[3]
                info[I_VY] = shot[4]
                info[I_VZ] = shot[5]
        mat = mat_static if damping else mat_dyn
        if parallel:
            dtn, st, wi, wp, wh, wv = element_rows_parallel(
                x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1, k0, k1)
        else:
            dtn, st, wi, wp, wh, wv = element_rows(
                x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1, k0, k1)
        time += dt
        dt_prev = dt
        dt_next = dtn
        if dt < info[I_DT_MIN]:
            info[I_DT_MIN] = dt
        if st != ST_OK:
            status = st
            break
        energy[E_INT] += wi
        energy[E_PL] += wp
        energy[E_HG] += wh
        if energy[E_HG] - hg_start > info[I_HG_PEAK]:
            info[I_HG_PEAK] = energy[E_HG] - hg_start
        if energy[E_INT] - int_start > info[I_INT_PEAK]:
            info[I_INT_PEAK] = energy[E_INT] - int_start
        energy[E_VISC] += wv
        # after separation the shot's rebound energy (ke_shot frozen at its
        # value when it left) stays in the balance
        etot = ke + ke_shot + energy[E_INT] + energy[E_HG] + energy[E_VISC] + energy[E_CONTACT] + energy[E_DAMP]
        if not math.isfinite(etot) or not math.isfinite(dtn):
            status = ST_NAN
            break
        err = etot - e_start
        if abs(err) > max_err:
            max_err = abs(err)
        if e_ref > 0.0 and err > ctl[C_RUNAWAY] * e_ref:
            status = ST_RUNAWAY
            break
        if record_every > 0 and (step % record_every == 0) and nrec < rec.shape[0]:
            r = rec[nrec]
            r[0] = time
            r[1] = jx / dt * fscale if ncon > 0 else 0.0
            r[2] = jy / dt * fscale if ncon > 0 else 0.0
            r[3] = jz / dt * fscale if ncon > 0 else 0.0
            for a in range(3):
                r[4 + a] = shot[a]
                r[7 + a] = shot[3 + a]
            r[10] = ke
            r[11] = ke_shot
            r[12] = energy[E_INT]
            r[13] = energy[E_PL]
            r[14] = energy[E_HG]
            r[15] = energy[E_VISC]
            r[16] = energy[E_CONTACT]
            r[17] = energy[E_DAMP]
            r[18] = dt
            nrec += 1
        if damping and step % 10 == 0 and ke <= rest_ke and vmax <= rest_v:
            info[I_STEPS] = step + 1
            break
        info[I_STEPS] = step + 1
    else:
        status = ST_MAX_STEPS
    ctl[C_DT_PREV] = dt_prev
    ctl[C_DT_NEXT] = dt_next
    ctl[C_TIME] = time
    info[I_STATUS] = status
    info[I_E_ERR] = max_err
    info[I_NREC] = nrec
    info[I_KE_END] = ke
    info[I_VMAX_END] = vmax
    info[I_SEPARATED] = 1.0 if separated else 0.0
    return status


@jit
def initial_dt(x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, nnx, nny, nx, ny, win):
    """Smallest element step of the window at the current state, without
    changing anything (a zero-step element pass on copies would be wasteful:
    with ``dt = 0`` and ``f`` scratch the pass leaves the state unchanged)."""
    dtn, st, wi, wp, wh, wv = element_rows(
        x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, 0.0, nnx, nny, nx, ny,
        win[0], win[1], win[2], win[3], win[4], win[5])
    return dtn, st
