"""Selective-reduced (B-bar, mean-dilatation) 8-node hexahedron, 2 x 2 x 2 Gauss points: a comparison
element for issue 13 §1 (not part of the kernel; nothing under ``peenflow/`` uses it).

Per element and step (central difference, forces at ``t_{n+1}``), at the mid-step configuration
``x_{n+1/2} = x_{n+1} - dt/2 v_{n+1/2}`` as the kernel's one-point element
(:mod:`peenflow.fe.element`, whose helpers are reused):

1. The trilinear map ``x(xi) = a_0 + a_1 xi + a_2 eta + a_3 zeta + a_4 xi eta + a_5 eta zeta
   + a_6 zeta xi + a_7 xi eta zeta`` with ``a_m = sum_I S_mI x_I / 8`` (the sign vectors
   ``SX SY SZ H1 H2 H3 H4`` of the one-point element), velocities likewise (``b_m``). At each
   Gauss point ``g`` (``xi, eta, zeta = +-1/sqrt 3``, weight 1): covariant vectors
   ``G_k = dx/dxi_k``, face vectors and ``det J_g`` (:func:`peenflow.fe.element._face_vectors`),
   duals ``g^k = c_k / det J_g``, volume share ``V_g = det J_g`` (``V = sum_g V_g`` exact for the
   trilinear hexahedron), velocity gradient ``L_g = sum_k dv/dxi_k (x) g^k``
   (:func:`peenflow.fe.element._rates`). Because the trilinear field reproduces linear fields
   exactly at every point, a rigid rotation gives ``D_g = 0`` at every Gauss point (Cayley
   transform, as in the one-point element) and a uniform strain rate gives the same ``D`` at all
   eight (patch test).
2. B-bar (Hughes 1980; mean dilatation, Nagtegaal-Parks-Rice 1974 / Simo-Taylor-Pister 1985):
   ``tr D_g`` replaced by the element's volume-weighted mean ``e_bar = sum_g V_g tr D_g / V``
   (``D_bar_g = D_g - (tr D_g - e_bar) I / 3``). With ``bbar = False`` the plain fully
   integrated element (volumetric locking; tests only).
3. Per Gauss point: Jaumann trial (:func:`peenflow.fe.johnson_cook.jaumann_trial`) with
   ``D_bar_g`` and the spin ``W_g``, its von Mises value, and where it exceeds the point's
   static flow stress (and ``dt > 0``) the Johnson-Cook return
   (:func:`peenflow.fe.johnson_cook.plastic_correction`), the static flow stress and the
   adiabatic temperature updated as in :mod:`peenflow.fe.element`. State per Gauss point:
   stress (6), eps_p, sy_static, temp (arrays of ``8 n_elements`` rows, row ``8 e + g``).
4. Bulk viscosity as the one-point element's, on ``e_bar``: ``q = rho l (c_quad l |e_bar| -
   c_lin c) e_bar`` (``e_bar < 0``), ``l = V / A_max`` from the centre's face vectors,
   ``rho = rho_0 V_0 / V``.
5. Forces of the B-bar operator: the power ``sum_g V_g (sigma_g - q I) : D_bar_g =
   sum_g V_g dev sigma_g : D_g + p_bar V e_bar`` with ``p_bar = sum_g V_g p_g / V - q``, so
   ``f_I = -sum_g V_g (dev sigma_g + p_bar I) grad N_I(x_g)``,
   ``grad N_I = sum_k dN_I/dxi_k g^k``. No hourglass control (full integration).
6. Energies: internal ``dt/2 sum_g V_g (sigma_old + sigma_new) : D_bar_g``, plastic
   ``sum_g sigma_y deps V_g``, viscous ``-q e_bar V dt`` (the one-point element's definitions).
7. Stable step: the one-point element's dilatational bound without its hourglass term,
   ``dt_e = 2 / omega``, ``omega = 2 (Q + sqrt(Q^2 + c^2)) / l``. Measured, not assumed: the
   highest frequency of assembled meshes of this element against this bound is in
   tests/fe/test_bbar_element.py (test_stable_step_bounds_assembled_mesh) and BENCHMARKS.md section 4d.

:func:`p8_pass` (kind 3, "physical8") is another comparison element in this file: the kernel's physical
one-point element with its assumed strain sampled at the Gauss points and a return at each (its docstring;
BENCHMARKS.md 4e).

:func:`bbar_pass` runs all elements of an index box one at a time (serial, element order; the
scatter needs no colouring); :func:`bbar_pass_v` is the same with each element's 8 Gauss points as SIMD
lanes (1.2x faster in bench_bbar.py cost, equal to round-off), the one the driver uses. :func:`run_phase_bbar` is a copy of
:func:`peenflow.fe.solver.run_phase` with the element pass chosen by ``kind`` (0: the kernel's
one-point element :func:`peenflow.fe.element.element_rows`, 1: B-bar, 2: plain full
integration) and the window's viscous-spring faces and periodic tying removed (the single-impact
driver integrates the whole mesh). Everything in this file is numba (``cache=True``,
``nogil=True``, no fastmath); the phase copy sits in the same file as the element so that
numba's per-file cache check sees an edit of either.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from benchmarks.bbar.contact_mortar import contact_mortar
from peenflow.fe.contact import contact_kinematic
from peenflow.fe.element import (H1, H2, H3, H4, ST_DISTORTION, ST_NEGATIVE_VOLUME, ST_OK, SX, SY, SZ,
                                 _element_frame, _face_vectors, _hourglass_shape, _mode_rate, _rates, _rotate,
                                 _scaled9, _tractions, corner_offsets, element_rows, hourglass_omega2_factor)
from peenflow.fe.johnson_cook import (M_ADIABATIC, M_BULK_LIN, M_BULK_QUAD, M_HEAT, M_LAM, M_MU, M_RHO,
                                      jaumann_trial, plastic_correction, static_flow_stress, thermal_factor,
                                      von_mises)
from peenflow.fe import solver as S
from peenflow.fe.solver import _node_update

NGP = 8
_G = 1.0 / math.sqrt(3.0)
#: Gauss point coordinates, in the corner order of the one-point element (SX, SY, SZ) / sqrt 3
GP = np.array([[SX[g] * _G, SY[g] * _G, SZ[g] * _G] for g in range(8)])
#: rows m = 0..7 of the trilinear basis: 1, xi, eta, zeta, xi eta, eta zeta, zeta xi, xi eta zeta
SIGNS8 = np.array(((1.0,) * 8, SX, SY, SZ, H1, H2, H3, H4))


def _dn_table() -> np.ndarray:
    """``dN_I/dxi_k`` at Gauss point g: (8 g, 8 I, 3 k)."""
    t = np.zeros((8, 8, 3))
    for g in range(8):
        xi, eta, zeta = GP[g]
        for i in range(8):
            a, b, c = SX[i], SY[i], SZ[i]
            t[g, i, 0] = a * (1 + b * eta) * (1 + c * zeta) / 8
            t[g, i, 1] = b * (1 + a * xi) * (1 + c * zeta) / 8
            t[g, i, 2] = c * (1 + a * xi) * (1 + b * eta) / 8
    return t


DN = _dn_table()

_jit = dict(cache=True, nogil=True)


@njit(**_jit, inline="always")
def _viscosity_and_step(c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, detc, vol, vol0_e, mat, lam, mu, ebar, dt,
                        hg_factor=0.0):
    """Bulk viscosity on the mean dilatation rate ``ebar`` (1/s) and the element's stable step, as the
    one-point element (element.py docstring 3 and 6; its hourglass term ``hg_factor c^2 / l^2`` only if
    ``hg_factor > 0``: physical8 has the one-point element's hourglass stiffness, B-bar none); ``c*`` the
    centre face vectors, ``detc`` their determinant. Returns (q Pa, its work J over ``dt``, dt_e s)."""
    amax = max(c1x * c1x + c1y * c1y + c1z * c1z, c2x * c2x + c2y * c2y + c2z * c2z)
    amax = max(amax, c3x * c3x + c3y * c3y + c3z * c3z)
    lch = 2.0 * detc / math.sqrt(amax)
    rho = mat[M_RHO] * vol0_e / vol
    c2 = (lam + 2.0 * mu) / rho
    cw = math.sqrt(c2)
    qv = 0.0
    qb = 0.0
    dw_visc = 0.0
    if ebar < 0.0:
        qv = mat[M_BULK_LIN] * cw - mat[M_BULK_QUAD] * lch * ebar
        qb = -rho * lch * qv * ebar
        dw_visc = -qb * ebar * vol * dt
    om = 2.0 * (qv + math.sqrt(qv * qv + c2)) / lch
    if hg_factor > 0.0:
        return qb, dw_visc, 2.0 / math.sqrt(om * om + hg_factor * c2 / (lch * lch))
    return qb, dw_visc, 2.0 / om


@njit(**_jit, inline="always")
def _point_update(q, dxx, dyy, dzz, dyz, dxz, dxy, wyz, wxz, wxy, dt, lam, mu, vg, stress, eps_p, sy_static, temp,
                  mat):
    """Gauss point ``q`` (state row): Jaumann trial with the rate ``d`` and spin ``w`` (1/s), its von Mises
    value, the Johnson-Cook return where it exceeds the point's static flow stress (and ``dt > 0``), the
    static flow stress and adiabatic temperature updated as in :mod:`peenflow.fe.element`; the new stress
    stored. ``vg`` the point's volume share (m^3). Returns the new stress (6, Pa), the point's internal
    work over the step at mid-step stress and its plastic work (J)."""
    o0 = stress[q, 0]
    o1 = stress[q, 1]
    o2 = stress[q, 2]
    o3 = stress[q, 3]
    o4 = stress[q, 4]
    o5 = stress[q, 5]
    t0, t1, t2, t3, t4, t5 = jaumann_trial(o0, o1, o2, o3, o4, o5, dxx, dyy, dzz, dyz, dxz, dxy, wyz, wxz, wxy,
                                           dt, lam, mu)
    qt = von_mises(t0, t1, t2, t3, t4, t5)
    dw_pl = 0.0
    if dt > 0.0 and qt > sy_static[q]:
        t0, t1, t2, t3, t4, t5, deps, sy, gr, sy_new = plastic_correction(
            t0, t1, t2, t3, t4, t5, qt, dxx, dyy, dzz, dyz, dxz, dxy, dt, eps_p[q], temp[q], mat)
        if deps > 0.0:
            ep = eps_p[q] + deps
            eps_p[q] = ep
            dw_pl = sy * deps * vg
            if mat[M_ADIABATIC] != 0.0:
                temp[q] += mat[M_HEAT] * sy * deps
                sy_new = static_flow_stress(ep, thermal_factor(temp[q], mat), mat)
            sy_static[q] = sy_new
    stress[q, 0] = t0
    stress[q, 1] = t1
    stress[q, 2] = t2
    stress[q, 3] = t3
    stress[q, 4] = t4
    stress[q, 5] = t5
    dw = 0.5 * dt * vg * ((o0 + t0) * dxx + (o1 + t1) * dyy + (o2 + t2) * dzz
                          + 2.0 * ((o3 + t3) * dyz + (o4 + t4) * dxz + (o5 + t5) * dxy))
    return t0, t1, t2, t3, t4, t5, dw, dw_pl


@njit(**_jit)
def _element(e, n0, nnx, nnxy, x, v, f, stress, eps_p, sy_static, temp, vol0, mat, dt, bbar, sc, a, b, fl):
    """Element ``e`` (first node ``n0``): update its 8 Gauss points, scatter its forces into ``f``.

    Scratch: ``sc`` (8, 25), ``a``, ``b``, ``fl`` (8, 3). Returns ``(dt_e, status, dW_int, dW_plastic,
    dW_viscous)``."""
    hdt = 0.5 * dt
    offs = corner_offsets(nnx, nnxy)
    lam = mat[M_LAM]
    mu = mat[M_MU]
    # coefficients of the trilinear maps of mid-step positions (a) and velocities (b)
    a[:] = 0.0
    b[:] = 0.0
    for I in range(8):
        n = n0 + offs[I]
        for c in range(3):
            vc = v[n, c]
            pc = x[n, c] - hdt * vc
            for m in range(8):
                s = SIGNS8[m, I] * 0.125
                a[m, c] += s * pc
                b[m, c] += s * vc
    # pass over the Gauss points: geometry, rates (sc[g]: 0-8 duals, 9 V_g, 10-18 rates)
    vol = 0.0
    evsum = 0.0
    for g in range(8):
        xi = GP[g, 0]
        eta = GP[g, 1]
        zeta = GP[g, 2]
        ez = eta * zeta
        zx = zeta * xi
        xe = xi * eta
        G1x = a[1, 0] + a[4, 0] * eta + a[6, 0] * zeta + a[7, 0] * ez
        G1y = a[1, 1] + a[4, 1] * eta + a[6, 1] * zeta + a[7, 1] * ez
        G1z = a[1, 2] + a[4, 2] * eta + a[6, 2] * zeta + a[7, 2] * ez
        G2x = a[2, 0] + a[4, 0] * xi + a[5, 0] * zeta + a[7, 0] * zx
        G2y = a[2, 1] + a[4, 1] * xi + a[5, 1] * zeta + a[7, 1] * zx
        G2z = a[2, 2] + a[4, 2] * xi + a[5, 2] * zeta + a[7, 2] * zx
        G3x = a[3, 0] + a[5, 0] * eta + a[6, 0] * xi + a[7, 0] * xe
        G3y = a[3, 1] + a[5, 1] * eta + a[6, 1] * xi + a[7, 1] * xe
        G3z = a[3, 2] + a[5, 2] * eta + a[6, 2] * xi + a[7, 2] * xe
        V1x = b[1, 0] + b[4, 0] * eta + b[6, 0] * zeta + b[7, 0] * ez
        V1y = b[1, 1] + b[4, 1] * eta + b[6, 1] * zeta + b[7, 1] * ez
        V1z = b[1, 2] + b[4, 2] * eta + b[6, 2] * zeta + b[7, 2] * ez
        V2x = b[2, 0] + b[4, 0] * xi + b[5, 0] * zeta + b[7, 0] * zx
        V2y = b[2, 1] + b[4, 1] * xi + b[5, 1] * zeta + b[7, 1] * zx
        V2z = b[2, 2] + b[4, 2] * xi + b[5, 2] * zeta + b[7, 2] * zx
        V3x = b[3, 0] + b[5, 0] * eta + b[6, 0] * xi + b[7, 0] * xe
        V3y = b[3, 1] + b[5, 1] * eta + b[6, 1] * xi + b[7, 1] * xe
        V3z = b[3, 2] + b[5, 2] * eta + b[6, 2] * xi + b[7, 2] * xe
        c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, det = _face_vectors(G1x, G1y, G1z, G2x, G2y, G2z,
                                                                         G3x, G3y, G3z)
        if not (det > 0.0):
            return 0.0, ST_NEGATIVE_VOLUME, 0.0, 0.0, 0.0
        d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z = _scaled9(1.0 / det, c1x, c1y, c1z, c2x, c2y, c2z,
                                                               c3x, c3y, c3z)
        lxx, lyy, lzz, dyz, dxz, dxy, wyz, wxz, wxy = _rates(V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z,
                                                             d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z)
        row = sc[g]
        row[0] = d1x
        row[1] = d1y
        row[2] = d1z
        row[3] = d2x
        row[4] = d2y
        row[5] = d2z
        row[6] = d3x
        row[7] = d3y
        row[8] = d3z
        row[9] = det
        row[10] = lxx
        row[11] = lyy
        row[12] = lzz
        row[13] = dyz
        row[14] = dxz
        row[15] = dxy
        row[16] = wyz
        row[17] = wxz
        row[18] = wxy
        vol += det
        evsum += det * (lxx + lyy + lzz)
    ratio = vol / vol0[e]
    if ratio < 0.1 or ratio > 10.0:
        return 0.0, ST_DISTORTION, 0.0, 0.0, 0.0
    ebar = evsum / vol
    # wave speed, characteristic length (centre face vectors, as the one-point element), bulk viscosity, step
    c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, detc = _face_vectors(a[1, 0], a[1, 1], a[1, 2], a[2, 0], a[2, 1],
                                                                      a[2, 2], a[3, 0], a[3, 1], a[3, 2])
    qb, dw_visc, dt_e = _viscosity_and_step(c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, detc, vol, vol0[e], mat,
                                             lam, mu, ebar, dt)
    # stress update per Gauss point (sc[g]: 19-24 the new stress)
    dw_int = 0.0
    dw_pl = 0.0
    psum = 0.0
    for g in range(8):
        row = sc[g]
        q = 8 * e + g
        tr = row[10] + row[11] + row[12]
        shift = (ebar - tr) / 3.0 if bbar else 0.0
        lxx = row[10] + shift
        lyy = row[11] + shift
        lzz = row[12] + shift
        t0, t1, t2, t3, t4, t5, dw, dwp = _point_update(q, lxx, lyy, lzz, row[13], row[14], row[15], row[16],
                                                        row[17], row[18], dt, lam, mu, row[9], stress, eps_p,
                                                        sy_static, temp, mat)
        dw_int += dw
        dw_pl += dwp
        row[19] = t0
        row[20] = t1
        row[21] = t2
        row[22] = t3
        row[23] = t4
        row[24] = t5
        psum += row[9] * (t0 + t1 + t2) / 3.0
    pbar = psum / vol - qb
    # nodal forces f_I = -sum_g V_g (s_g) grad N_I, s_g = dev sigma_g + p_bar I (B-bar) or sigma_g - q I
    fl[:] = 0.0
    for g in range(8):
        row = sc[g]
        s0 = row[19]
        s1 = row[20]
        s2 = row[21]
        p = (s0 + s1 + s2) / 3.0
        add = pbar - p if bbar else -qb
        vg = row[9]
        sxx = (s0 + add) * vg
        syy = (s1 + add) * vg
        szz = (s2 + add) * vg
        syz = row[22] * vg
        sxz = row[23] * vg
        sxy = row[24] * vg
        # t_k = V_g s g^k
        t1x = sxx * row[0] + sxy * row[1] + sxz * row[2]
        t1y = sxy * row[0] + syy * row[1] + syz * row[2]
        t1z = sxz * row[0] + syz * row[1] + szz * row[2]
        t2x = sxx * row[3] + sxy * row[4] + sxz * row[5]
        t2y = sxy * row[3] + syy * row[4] + syz * row[5]
        t2z = sxz * row[3] + syz * row[4] + szz * row[5]
        t3x = sxx * row[6] + sxy * row[7] + sxz * row[8]
        t3y = sxy * row[6] + syy * row[7] + syz * row[8]
        t3z = sxz * row[6] + syz * row[7] + szz * row[8]
        for I in range(8):
            n1 = DN[g, I, 0]
            n2 = DN[g, I, 1]
            n3 = DN[g, I, 2]
            fl[I, 0] += n1 * t1x + n2 * t2x + n3 * t3x
            fl[I, 1] += n1 * t1y + n2 * t2y + n3 * t3y
            fl[I, 2] += n1 * t1z + n2 * t2z + n3 * t3z
    for I in range(8):
        n = n0 + offs[I]
        f[n, 0] -= fl[I, 0]
        f[n, 1] -= fl[I, 1]
        f[n, 2] -= fl[I, 2]
    return dt_e, ST_OK, dw_int, dw_pl, dw_visc


@njit(**_jit)
def bbar_pass(x, v, f, stress, eps_p, sy_static, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1, k0, k1,
              bbar=True, p8=False):
    """All elements of the index box, one at a time (the contract of :func:`peenflow.fe.element.element_rows`
    with Gauss-point state: ``stress`` (8 ne, 6), ``eps_p``, ``sy_static``, ``temp`` (8 ne,); no hourglass
    array). ``f`` must be zero on the box's nodes. ``p8``: the element :func:`_element_p8` instead (``bbar``
    then unused). Returns ``(dt_min, status, dW_int, dW_plastic, 0, dW_viscous)``."""
    nnxy = nnx * nny
    sc = np.empty((8, 25))
    a = np.empty((8, 3))
    b = np.empty((8, 3))
    fl = np.empty((8, 3))
    sp = np.empty((7, 3))
    sv = np.empty((7, 3))
    dtmin = 1e30
    status = 0
    wi = 0.0
    wp = 0.0
    wv = 0.0
    for k in range(k0, k1):
        for j in range(j0, j1):
            for i in range(i0, i1):
                e = i + nx * (j + ny * k)
                n0 = i + nnx * (j + nny * k)
                if p8:
                    dte, st, a1, a2, a3 = _element_p8(e, n0, nnx, nnxy, x, v, f, stress, eps_p, sy_static, temp,
                                                      vol0, mat, dt, sp, sv)
                else:
                    dte, st, a1, a2, a3 = _element(e, n0, nnx, nnxy, x, v, f, stress, eps_p, sy_static, temp,
                                                   vol0, mat, dt, bbar, sc, a, b, fl)
                if st != ST_OK:
                    status = max(status, st)
                    continue
                dtmin = min(dtmin, dte)
                wi += a1
                wp += a2
                wv += a3
    return (0.0 if status != 0 else dtmin), status, wi, wp, 0.0, wv


# ---------------------------------------------------------------------------
# The same element with its 8 Gauss points as SIMD lanes: every per-point quantity a slot of 8
# consecutive values of one flat scratch array (the layout of the kernel's blocked rows), the
# kinematics, trial stresses, tractions and corner forces as branch- and call-free loops over the 8
# points or corners, the Johnson-Cook return a scalar loop over the yielding points only.
# Agrees with :func:`_element` to round-off (its sums run in another order; tests/fe/test_bbar_element.py).
# ---------------------------------------------------------------------------

_SIGN_T = np.ascontiguousarray(SIGNS8.T * 0.125)  # (8 I, 8 m): a_m = sum_I S_mI p_I / 8
_GPT = np.ascontiguousarray(GP.T)  # (3, 8 g)
_DNT = np.ascontiguousarray(DN.transpose(2, 0, 1))  # (3 k, 8 g, 8 I)
# slots (x 8) of the lane scratch
_P = 0  # 6 x 8 corners: mid-step x y z, velocity x y z
_A = 6  # 6 x 8 coefficients m: a (x y z), b (x y z)
_DU = 12  # 9: duals g^1 g^2 g^3
_VG = 21  # det J_g
_LR = 22  # 9: lxx lyy lzz dyz dxz dxy wyz wxz wxy
_SO = 31  # 6: old stress
_SN = 37  # 6: trial / new stress
_QT = 43  # von Mises of the trial
_EW = 44  # internal work of the point
_TR = 45  # 9: tractions t_k (x y z) per point
_FC = 54  # 3: corner forces x y z
_NW = 57


@njit(**_jit)
def _element_v(e, n0, nnx, nnxy, x, v, f, stress, eps_p, sy_static, temp, vol0, mat, dt, wb, w):
    """:func:`_element` with the Gauss points as lanes (``wb`` = 1.0 B-bar, 0.0 plain full integration;
    ``w``: scratch of ``_NW * 8``). Same returns."""
    hdt = 0.5 * dt
    offs = corner_offsets(nnx, nnxy)
    lam = mat[M_LAM]
    mu = mat[M_MU]
    for I in range(8):
        n = n0 + offs[I]
        for c in range(3):
            vc = v[n, c]
            w[(_P + c) * 8 + I] = x[n, c] - hdt * vc
            w[(_P + 3 + c) * 8 + I] = vc
    for c in range(6):
        o = (_A + c) * 8
        for m in range(8):
            w[o + m] = 0.0
        for I in range(8):
            p = w[(_P + c) * 8 + I]
            for m in range(8):
                w[o + m] += _SIGN_T[I, m] * p
    ax = _A * 8
    ay = (_A + 1) * 8
    az = (_A + 2) * 8
    bx = (_A + 3) * 8
    by = (_A + 4) * 8
    bz = (_A + 5) * 8
    a1x, a2x, a3x, a4x, a5x, a6x, a7x = w[ax + 1], w[ax + 2], w[ax + 3], w[ax + 4], w[ax + 5], w[ax + 6], w[ax + 7]
    a1y, a2y, a3y, a4y, a5y, a6y, a7y = w[ay + 1], w[ay + 2], w[ay + 3], w[ay + 4], w[ay + 5], w[ay + 6], w[ay + 7]
    a1z, a2z, a3z, a4z, a5z, a6z, a7z = w[az + 1], w[az + 2], w[az + 3], w[az + 4], w[az + 5], w[az + 6], w[az + 7]
    b1x, b2x, b3x, b4x, b5x, b6x, b7x = w[bx + 1], w[bx + 2], w[bx + 3], w[bx + 4], w[bx + 5], w[bx + 6], w[bx + 7]
    b1y, b2y, b3y, b4y, b5y, b6y, b7y = w[by + 1], w[by + 2], w[by + 3], w[by + 4], w[by + 5], w[by + 6], w[by + 7]
    b1z, b2z, b3z, b4z, b5z, b6z, b7z = w[bz + 1], w[bz + 2], w[bz + 3], w[bz + 4], w[bz + 5], w[bz + 6], w[bz + 7]
    q0 = 8 * e
    for g in range(8):
        for c in range(6):
            w[(_SO + c) * 8 + g] = stress[q0 + g, c]
    # lanes: geometry and rates at the 8 points
    for g in range(8):
        xi = _GPT[0, g]
        eta = _GPT[1, g]
        zeta = _GPT[2, g]
        ez = eta * zeta
        zx = zeta * xi
        xe = xi * eta
        G1x = a1x + a4x * eta + a6x * zeta + a7x * ez
        G1y = a1y + a4y * eta + a6y * zeta + a7y * ez
        G1z = a1z + a4z * eta + a6z * zeta + a7z * ez
        G2x = a2x + a4x * xi + a5x * zeta + a7x * zx
        G2y = a2y + a4y * xi + a5y * zeta + a7y * zx
        G2z = a2z + a4z * xi + a5z * zeta + a7z * zx
        G3x = a3x + a5x * eta + a6x * xi + a7x * xe
        G3y = a3y + a5y * eta + a6y * xi + a7y * xe
        G3z = a3z + a5z * eta + a6z * xi + a7z * xe
        V1x = b1x + b4x * eta + b6x * zeta + b7x * ez
        V1y = b1y + b4y * eta + b6y * zeta + b7y * ez
        V1z = b1z + b4z * eta + b6z * zeta + b7z * ez
        V2x = b2x + b4x * xi + b5x * zeta + b7x * zx
        V2y = b2y + b4y * xi + b5y * zeta + b7y * zx
        V2z = b2z + b4z * xi + b5z * zeta + b7z * zx
        V3x = b3x + b5x * eta + b6x * xi + b7x * xe
        V3y = b3y + b5y * eta + b6y * xi + b7y * xe
        V3z = b3z + b5z * eta + b6z * xi + b7z * xe
        c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, det = _face_vectors(G1x, G1y, G1z, G2x, G2y, G2z,
                                                                         G3x, G3y, G3z)
        d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z = _scaled9(1.0 / det, c1x, c1y, c1z, c2x, c2y, c2z,
                                                               c3x, c3y, c3z)
        lxx, lyy, lzz, dyz, dxz, dxy, wyz, wxz, wxy = _rates(V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z,
                                                             d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z)
        w[_DU * 8 + g] = d1x
        w[(_DU + 1) * 8 + g] = d1y
        w[(_DU + 2) * 8 + g] = d1z
        w[(_DU + 3) * 8 + g] = d2x
        w[(_DU + 4) * 8 + g] = d2y
        w[(_DU + 5) * 8 + g] = d2z
        w[(_DU + 6) * 8 + g] = d3x
        w[(_DU + 7) * 8 + g] = d3y
        w[(_DU + 8) * 8 + g] = d3z
        w[_VG * 8 + g] = det
        w[_LR * 8 + g] = lxx
        w[(_LR + 1) * 8 + g] = lyy
        w[(_LR + 2) * 8 + g] = lzz
        w[(_LR + 3) * 8 + g] = dyz
        w[(_LR + 4) * 8 + g] = dxz
        w[(_LR + 5) * 8 + g] = dxy
        w[(_LR + 6) * 8 + g] = wyz
        w[(_LR + 7) * 8 + g] = wxz
        w[(_LR + 8) * 8 + g] = wxy
    vol = 0.0
    evsum = 0.0
    dmin = 1.0
    for g in range(8):  # in point order, as _element
        det = w[_VG * 8 + g]
        dmin = min(dmin, det)
        vol += det
        evsum += det * (w[_LR * 8 + g] + w[(_LR + 1) * 8 + g] + w[(_LR + 2) * 8 + g])
    if not (dmin > 0.0):
        return 0.0, ST_NEGATIVE_VOLUME, 0.0, 0.0, 0.0
    ratio = vol / vol0[e]
    if ratio < 0.1 or ratio > 10.0:
        return 0.0, ST_DISTORTION, 0.0, 0.0, 0.0
    ebar = evsum / vol
    c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, detc = _face_vectors(a1x, a1y, a1z, a2x, a2y, a2z, a3x, a3y, a3z)
    qb, dw_visc, dt_e = _viscosity_and_step(c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, detc, vol, vol0[e], mat,
                                             lam, mu, ebar, dt)
    # lanes: B-bar rates (stored back), trial stresses and their von Mises values
    for g in range(8):
        lxx = w[_LR * 8 + g]
        lyy = w[(_LR + 1) * 8 + g]
        lzz = w[(_LR + 2) * 8 + g]
        shift = (ebar - (lxx + lyy + lzz)) / 3.0 * wb
        lxx += shift
        lyy += shift
        lzz += shift
        w[_LR * 8 + g] = lxx
        w[(_LR + 1) * 8 + g] = lyy
        w[(_LR + 2) * 8 + g] = lzz
        t0, t1, t2, t3, t4, t5 = jaumann_trial(
            w[_SO * 8 + g], w[(_SO + 1) * 8 + g], w[(_SO + 2) * 8 + g], w[(_SO + 3) * 8 + g],
            w[(_SO + 4) * 8 + g], w[(_SO + 5) * 8 + g], lxx, lyy, lzz, w[(_LR + 3) * 8 + g], w[(_LR + 4) * 8 + g],
            w[(_LR + 5) * 8 + g], w[(_LR + 6) * 8 + g], w[(_LR + 7) * 8 + g], w[(_LR + 8) * 8 + g], dt, lam, mu)
        w[_SN * 8 + g] = t0
        w[(_SN + 1) * 8 + g] = t1
        w[(_SN + 2) * 8 + g] = t2
        w[(_SN + 3) * 8 + g] = t3
        w[(_SN + 4) * 8 + g] = t4
        w[(_SN + 5) * 8 + g] = t5
        w[_QT * 8 + g] = von_mises(t0, t1, t2, t3, t4, t5)
    # scalar: the return of the yielding points
    dw_pl = 0.0
    if dt > 0.0:
        for g in range(8):
            q = q0 + g
            qt = w[_QT * 8 + g]
            if qt > sy_static[q]:
                t0, t1, t2, t3, t4, t5, deps, sy, gr, sy_new = plastic_correction(
                    w[_SN * 8 + g], w[(_SN + 1) * 8 + g], w[(_SN + 2) * 8 + g], w[(_SN + 3) * 8 + g],
                    w[(_SN + 4) * 8 + g], w[(_SN + 5) * 8 + g], qt, w[_LR * 8 + g], w[(_LR + 1) * 8 + g],
                    w[(_LR + 2) * 8 + g], w[(_LR + 3) * 8 + g], w[(_LR + 4) * 8 + g], w[(_LR + 5) * 8 + g],
                    dt, eps_p[q], temp[q], mat)
                w[_SN * 8 + g] = t0
                w[(_SN + 1) * 8 + g] = t1
                w[(_SN + 2) * 8 + g] = t2
                w[(_SN + 3) * 8 + g] = t3
                w[(_SN + 4) * 8 + g] = t4
                w[(_SN + 5) * 8 + g] = t5
                if deps > 0.0:
                    ep = eps_p[q] + deps
                    eps_p[q] = ep
                    dw_pl += sy * deps * w[_VG * 8 + g]
                    if mat[M_ADIABATIC] != 0.0:
                        temp[q] += mat[M_HEAT] * sy * deps
                        sy_new = static_flow_stress(ep, thermal_factor(temp[q], mat), mat)
                    sy_static[q] = sy_new
    # lanes: stress power of each point
    for g in range(8):
        w[_EW * 8 + g] = 0.5 * dt * w[_VG * 8 + g] * (
            (w[_SO * 8 + g] + w[_SN * 8 + g]) * w[_LR * 8 + g]
            + (w[(_SO + 1) * 8 + g] + w[(_SN + 1) * 8 + g]) * w[(_LR + 1) * 8 + g]
            + (w[(_SO + 2) * 8 + g] + w[(_SN + 2) * 8 + g]) * w[(_LR + 2) * 8 + g]
            + 2.0 * ((w[(_SO + 3) * 8 + g] + w[(_SN + 3) * 8 + g]) * w[(_LR + 3) * 8 + g]
                     + (w[(_SO + 4) * 8 + g] + w[(_SN + 4) * 8 + g]) * w[(_LR + 4) * 8 + g]
                     + (w[(_SO + 5) * 8 + g] + w[(_SN + 5) * 8 + g]) * w[(_LR + 5) * 8 + g]))
    dw_int = 0.0
    psum = 0.0
    for g in range(8):  # point order
        dw_int += w[_EW * 8 + g]
        psum += w[_VG * 8 + g] * (w[_SN * 8 + g] + w[(_SN + 1) * 8 + g] + w[(_SN + 2) * 8 + g]) / 3.0
        for c in range(6):
            stress[q0 + g, c] = w[(_SN + c) * 8 + g]
    pbar = psum / vol - qb
    # lanes: tractions t_k = V_g s_g g^k, s_g = dev sigma_g + p_bar I (B-bar) or sigma_g - q I
    for g in range(8):
        s0 = w[_SN * 8 + g]
        s1 = w[(_SN + 1) * 8 + g]
        s2 = w[(_SN + 2) * 8 + g]
        p = (s0 + s1 + s2) / 3.0
        add = wb * (pbar - p) - (1.0 - wb) * qb
        vg = w[_VG * 8 + g]
        sxx = (s0 + add) * vg
        syy = (s1 + add) * vg
        szz = (s2 + add) * vg
        syz = w[(_SN + 3) * 8 + g] * vg
        sxz = w[(_SN + 4) * 8 + g] * vg
        sxy = w[(_SN + 5) * 8 + g] * vg
        for k in range(3):
            dx = w[(_DU + 3 * k) * 8 + g]
            dy = w[(_DU + 3 * k + 1) * 8 + g]
            dz = w[(_DU + 3 * k + 2) * 8 + g]
            w[(_TR + 3 * k) * 8 + g] = sxx * dx + sxy * dy + sxz * dz
            w[(_TR + 3 * k + 1) * 8 + g] = sxy * dx + syy * dy + syz * dz
            w[(_TR + 3 * k + 2) * 8 + g] = sxz * dx + syz * dy + szz * dz
    # lanes (corners): f_I = -sum_g sum_k dN_I/dxi_k(g) t_gk
    for c in range(3):
        o = (_FC + c) * 8
        for I in range(8):
            w[o + I] = 0.0
        for k in range(3):
            for g in range(8):
                t = w[(_TR + 3 * k + c) * 8 + g]
                for I in range(8):
                    w[o + I] += _DNT[k, g, I] * t
    for I in range(8):
        n = n0 + offs[I]
        f[n, 0] -= w[_FC * 8 + I]
        f[n, 1] -= w[(_FC + 1) * 8 + I]
        f[n, 2] -= w[(_FC + 2) * 8 + I]
    return dt_e, ST_OK, dw_int, dw_pl, dw_visc


@njit(**_jit)
def bbar_pass_v(x, v, f, stress, eps_p, sy_static, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1, k0, k1,
                bbar=True):
    """:func:`bbar_pass` with :func:`_element_v` (the Gauss points as SIMD lanes)."""
    nnxy = nnx * nny
    w = np.empty(_NW * 8)
    wb = 1.0 if bbar else 0.0
    dtmin = 1e30
    status = 0
    wi = 0.0
    wp = 0.0
    wv = 0.0
    for k in range(k0, k1):
        for j in range(j0, j1):
            for i in range(i0, i1):
                e = i + nx * (j + ny * k)
                n0 = i + nnx * (j + nny * k)
                dte, st, a1, a2, a3 = _element_v(e, n0, nnx, nnxy, x, v, f, stress, eps_p, sy_static, temp, vol0,
                                                 mat, dt, wb, w)
                if st != ST_OK:
                    status = max(status, st)
                    continue
                dtmin = min(dtmin, dte)
                wi += a1
                wp += a2
                wv += a3
    return (0.0 if status != 0 else dtmin), status, wi, wp, 0.0, wv


@njit(**_jit)
def element_pass(kind, x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt, nnx, nny, nx, ny,
                 i0, i1, j0, j1, k0, k1):
    """The element pass of ``kind``: 0 the kernel's one-point element (element state per element, ``hg``
    its hourglass forces), 1 B-bar, 2 plain full integration (Gauss-point state, ``hg`` unused; the lane
    version :func:`bbar_pass_v`), 3 the physical element with plasticity at its Gauss points
    (:func:`p8_pass`, Gauss-point state, ``hg`` unused)."""
    if kind == 0:
        return element_rows(x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt, nnx, nny, nx, ny,
                            i0, i1, j0, j1, k0, k1)
    if kind == 3:
        return p8_pass(x, v, f, stress, eps_p, sy_static, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1,
                       k0, k1)
    return bbar_pass_v(x, v, f, stress, eps_p, sy_static, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1,
                       k0, k1, kind == 1)


@njit(**_jit)
def run_phase_bbar(kind, mode, max_steps, record_every, x, v, f, mass, bc, stress, eps_p, sy_static, hg, temp, vol0,
                   mat_dyn, mat_static, xs_ref, ys_ref, nnx, nny, nx, ny, win, hold, shot, ctl, energy, rec, info,
                   cand, dn, contact_form):
    """Copy of :func:`peenflow.fe.solver.run_phase` (same steps, same order, same stop rules) with the
    element pass of ``kind`` (:func:`element_pass`) and the sphere contact of ``contact_form`` (0 the
    kernel's node contact, 1 the mortar contact of :mod:`benchmarks.bbar.contact_mortar`), without
    viscous-spring window faces and periodic tying (serial). With ``kind = 0`` and ``contact_form = 0`` it is
    the kernel's loop (bit-identical: tests/fe/test_bbar_element.py)."""
    i0, i1, j0, j1, k0, k1 = win[0], win[1], win[2], win[3], win[4], win[5]
    ni0, ni1, nj0, nj1, nk0, nk1 = i0, i1, j0, j1, k0, k1
    dt_prev = ctl[S.C_DT_PREV]
    dt_next = ctl[S.C_DT_NEXT]
    time = ctl[S.C_TIME]
    safety = ctl[S.C_SAFETY]
    alpha = ctl[S.C_ALPHA]
    rest_ke = ctl[S.C_REST_KE]
    rest_v = ctl[S.C_REST_V]
    e_ref = ctl[S.C_E_REF]
    om_c2 = ctl[S.C_OMEGA_C2]
    fscale = ctl[S.C_FORCE_SCALE]
    sponge_w = int(ctl[S.C_SPONGE_W])
    bnodes = np.zeros(0, dtype=np.int64)
    b3 = np.zeros((0, 3))
    lx = xs_ref[nnx - 1] - xs_ref[0]
    ly = ys_ref[nny - 1] - ys_ref[0]
    shot_active = mode == S.MODE_IMPACT
    damping = mode == S.MODE_RELAX
    separated = False
    ke_shot = 0.0
    if shot_active:
        ke_shot = 0.5 * shot[9] * (shot[3] ** 2 + shot[4] ** 2 + shot[5] ** 2) + 0.5 * shot[10] * (
            shot[6] ** 2 + shot[7] ** 2 + shot[8] ** 2)
    ke0 = 0.0
    for k in range(nk0, nk1 + 1):
        for j in range(nj0, nj1 + 1):
            for i in range(ni0, ni1 + 1):
                n = i + nnx * (j + nny * k)
                ke0 += 0.5 * mass[n] * (v[n, 0] ** 2 + v[n, 1] ** 2 + v[n, 2] ** 2)
    e_start = ke0 + ke_shot + energy[S.E_INT] + energy[S.E_HG] + energy[S.E_VISC] + energy[S.E_CONTACT] + energy[
        S.E_DAMP]
    info[:] = 0.0
    info[S.I_T_CONTACT] = -1.0
    info[S.I_T_SEPARATE] = -1.0
    info[S.I_DT_MIN] = 1e30
    info[S.I_DT_START] = dt_next * safety
    nrec = 0
    hg_start = energy[S.E_HG]
    int_start = energy[S.E_INT]
    status = S.ST_OK
    max_err = 0.0
    ke = ke0
    vmax = 0.0
    dt = dt_next * safety
    jx = 0.0
    jy = 0.0
    jz = 0.0
    for step in range(max_steps):
        if dt_next <= 0.0:
            status = S.ST_NAN
            break
        om2 = 4.0 / (dt_next * dt_next) + om_c2
        dt = safety * 2.0 / math.sqrt(om2)
        if dt < ctl[S.C_DT_FLOOR]:
            status = S.ST_DT_COLLAPSE
            break
        if dt_prev <= 0.0:
            dt_prev = dt
        dt_avg = 0.5 * (dt_prev + dt)
        a_d = alpha if damping else 0.0
        ke, vmax, wd = _node_update(x, v, f, mass, bc, nnx, nny, ni0, ni1, nj0, nj1, nk0, nk1, hold, dt, dt_avg, a_d,
                                    sponge_w, ctl[S.C_SPONGE_A], bnodes, b3, b3, b3, b3, 1.0, False, lx, ly)
        energy[S.E_DAMP] += wd
        ncon = 0
        if shot_active:
            shot[0] += dt * shot[3]
            shot[1] += dt * shot[4]
            shot[2] += dt * shot[5]
            if contact_form == 1:
                ncon, jx, jy, jz, de, mov, mrad, dke, r2m = contact_mortar(
                    x, v, mass, bc, xs_ref, ys_ref, nnx, shot, dt, ni0, ni1, nj0, nj1, cand, dn)
            else:
                ncon, jx, jy, jz, de, mov, mrad, dke, r2m = contact_kinematic(
                    x, v, mass, bc, xs_ref, ys_ref, nnx, shot, dt, ni0, ni1, nj0, nj1, cand, dn)
            ke += dke
            energy[S.E_CONTACT] += de
            if ncon > 0:
                if info[S.I_T_CONTACT] < 0.0:
                    info[S.I_T_CONTACT] = time
                fmag = math.sqrt(jx * jx + jy * jy + jz * jz) / dt * fscale
                if fmag > info[S.I_PEAK_FORCE]:
                    info[S.I_PEAK_FORCE] = fmag
                    info[S.I_R2_AT_PEAK] = r2m
                if mov > info[S.I_MAX_OVERLAP]:
                    info[S.I_MAX_OVERLAP] = mov
                if mrad > info[S.I_MAX_RADIUS]:
                    info[S.I_MAX_RADIUS] = mrad
            app = shot[2] + shot[11]
            if app > info[S.I_MAX_APPROACH]:
                info[S.I_MAX_APPROACH] = app
            ke_shot = 0.5 * shot[9] * (shot[3] ** 2 + shot[4] ** 2 + shot[5] ** 2) + 0.5 * shot[10] * (
                shot[6] ** 2 + shot[7] ** 2 + shot[8] ** 2)
            if ncon == 0 and info[S.I_T_CONTACT] >= 0.0 and shot[5] < 0.0:
                separated = True
                shot_active = False
                damping = True
                info[S.I_T_SEPARATE] = time + dt
                info[S.I_VX] = shot[3]
                info[S.I_VY] = shot[4]
                info[S.I_VZ] = shot[5]
        mat = mat_static if damping else mat_dyn
        dtn, st, wi, wp, wh, wv = element_pass(kind, x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt,
                                               nnx, nny, nx, ny, i0, i1, j0, j1, k0, k1)
        time += dt
        dt_prev = dt
        dt_next = dtn
        if dt < info[S.I_DT_MIN]:
            info[S.I_DT_MIN] = dt
        if st != S.ST_OK:
            status = st
            break
        energy[S.E_INT] += wi
        energy[S.E_PL] += wp
        energy[S.E_HG] += wh
        if energy[S.E_HG] - hg_start > info[S.I_HG_PEAK]:
            info[S.I_HG_PEAK] = energy[S.E_HG] - hg_start
        if energy[S.E_INT] - int_start > info[S.I_INT_PEAK]:
            info[S.I_INT_PEAK] = energy[S.E_INT] - int_start
        energy[S.E_VISC] += wv
        etot = ke + ke_shot + energy[S.E_INT] + energy[S.E_HG] + energy[S.E_VISC] + energy[S.E_CONTACT] + energy[
            S.E_DAMP]
        if not math.isfinite(etot) or not math.isfinite(dtn):
            status = S.ST_NAN
            break
        err = etot - e_start
        if abs(err) > max_err:
            max_err = abs(err)
        if e_ref > 0.0 and err > ctl[S.C_RUNAWAY] * e_ref:
            status = S.ST_RUNAWAY
            break
        if record_every > 0 and (step % record_every == 0) and nrec < rec.shape[0]:
            r = rec[nrec]
            r[0] = time
            r[1] = jx / dt * fscale if ncon > 0 else 0.0
            r[2] = jy / dt * fscale if ncon > 0 else 0.0
            r[3] = jz / dt * fscale if ncon > 0 else 0.0
            for c in range(3):
                r[4 + c] = shot[c]
                r[7 + c] = shot[3 + c]
            r[10] = ke
            r[11] = ke_shot
            r[12] = energy[S.E_INT]
            r[13] = energy[S.E_PL]
            r[14] = energy[S.E_HG]
            r[15] = energy[S.E_VISC]
            r[16] = energy[S.E_CONTACT]
            r[17] = energy[S.E_DAMP]
            r[18] = dt
            nrec += 1
        if damping and step % 10 == 0 and ke <= rest_ke and vmax <= rest_v:
            info[S.I_STEPS] = step + 1
            break
        info[S.I_STEPS] = step + 1
    else:
        status = S.ST_MAX_STEPS
    ctl[S.C_DT_PREV] = dt_prev
    ctl[S.C_DT_NEXT] = dt_next
    ctl[S.C_TIME] = time
    info[S.I_STATUS] = status
    info[S.I_E_ERR] = max_err
    info[S.I_NREC] = nrec
    info[S.I_KE_END] = ke
    info[S.I_VMAX_END] = vmax
    info[S.I_SEPARATED] = 1.0 if separated else 0.0
    return status


# ---------------------------------------------------------------------------
# The kernel's physical one-point element with its assumed strain sampled at the 8 Gauss points
# ("physical8", kind 3): plasticity per point instead of the centroid's tangent in the hourglass
# stiffness. Elastic response the same as the one-point physical element (element.py 5b).
# ---------------------------------------------------------------------------


@njit(**_jit)
def _element_p8(e, n0, nnx, nnxy, x, v, f, stress, eps_p, sy_static, temp, vol0, mat, dt, sp, sv):
    """Element ``e``: the one-point element's kinematics and assumed-strain hourglass fields
    (:mod:`peenflow.fe.element` docstring 5b) evaluated at the 2 x 2 x 2 Gauss points, each point with
    its own Jaumann update and Johnson-Cook return (state rows ``8 e + g``).

    The strain rate at point ``(xi, eta, zeta)`` is ``D_0 + E^T D_hg E``: ``D_0`` the one-point element's
    (centroid, mid-step), ``E`` the element frame, ``D_hg`` in the frame from the hourglass rates
    ``p_ak`` (amplitudes ``p_ak / 8``, ``b_k`` inverse half lengths): bending normal strains linear in
    one coordinate with the transverse normal strain along it ``-nu_bar`` times their sum
    (``nu_bar = lambda / (lambda + 2 mu)``, elastic moduli, as Belytschko and Bindeman's ASQBI: the
    plane-stress condensation of the one-point element, so the elastic energies are its; the same
    condensation with each point's plastic tangent of its previous step made the element too soft,
    BENCHMARKS.md 4e), the torsion/warping shears, the
    xi eta zeta normal strains made deviatoric. Spin: the centroid's. Forces: ``-V (sigma_bar - q I)
    grad N_I`` with ``sigma_bar`` the points' mean, plus ``-sum_a gamma_a,I E^T F_a`` with
    ``F_ak = sum_g (V / 8) sigma_g : dD_hg,g / dp_ak`` (the power of the points' stresses is
    ``V sigma_bar : D_0 + F . p``). Scratch ``sp``, ``sv`` (7, 3).
    Returns ``(dt_e, status, dW_int, dW_plastic, dW_viscous)``."""
    hdt = 0.5 * dt
    offs = corner_offsets(nnx, nnxy)
    lam = mat[M_LAM]
    mu = mat[M_MU]
    sp[:] = 0.0
    sv[:] = 0.0
    for I in range(8):
        n = n0 + offs[I]
        sg = (SX[I], SY[I], SZ[I], H1[I], H2[I], H3[I], H4[I])
        for c in range(3):
            vc = v[n, c]
            pc = x[n, c] - hdt * vc
            for m in range(7):
                sp[m, c] += sg[m] * pc
                sv[m, c] += sg[m] * vc
    r8 = 0.125
    g1x, g1y, g1z = sp[0, 0] * r8, sp[0, 1] * r8, sp[0, 2] * r8
    g2x, g2y, g2z = sp[1, 0] * r8, sp[1, 1] * r8, sp[1, 2] * r8
    g3x, g3y, g3z = sp[2, 0] * r8, sp[2, 1] * r8, sp[2, 2] * r8
    c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, det = _face_vectors(g1x, g1y, g1z, g2x, g2y, g2z, g3x, g3y, g3z)
    if not (det > 0.0):
        return 0.0, ST_NEGATIVE_VOLUME, 0.0, 0.0, 0.0
    vol = 8.0 * det
    ratio = vol / vol0[e]
    if ratio < 0.1 or ratio > 10.0:
        return 0.0, ST_DISTORTION, 0.0, 0.0, 0.0
    d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z = _scaled9(1.0 / det, c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z)
    lxx, lyy, lzz, dyz, dxz, dxy, wyz, wxz, wxy = _rates(
        sv[0, 0] * r8, sv[0, 1] * r8, sv[0, 2] * r8, sv[1, 0] * r8, sv[1, 1] * r8, sv[1, 2] * r8,
        sv[2, 0] * r8, sv[2, 1] * r8, sv[2, 2] * r8, d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z)
    w11, w12, w13, w21, w22, w23, w31, w32, w33, w41, w42, w43 = _hourglass_shape(
        sp[3, 0], sp[3, 1], sp[3, 2], sp[4, 0], sp[4, 1], sp[4, 2], sp[5, 0], sp[5, 1], sp[5, 2],
        sp[6, 0], sp[6, 1], sp[6, 2], d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z)
    V1x, V1y, V1z = sv[0, 0], sv[0, 1], sv[0, 2]
    V2x, V2y, V2z = sv[1, 0], sv[1, 1], sv[1, 2]
    V3x, V3y, V3z = sv[2, 0], sv[2, 1], sv[2, 2]
    q1x, q1y, q1z = _mode_rate(sv[3, 0], sv[3, 1], sv[3, 2], w11, w12, w13, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
    q2x, q2y, q2z = _mode_rate(sv[4, 0], sv[4, 1], sv[4, 2], w21, w22, w23, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
    q3x, q3y, q3z = _mode_rate(sv[5, 0], sv[5, 1], sv[5, 2], w31, w32, w33, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
    q4x, q4y, q4z = _mode_rate(sv[6, 0], sv[6, 1], sv[6, 2], w41, w42, w43, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
    e11, e12, e13, e21, e22, e23, e31, e32, e33, b1, b2, b3 = _element_frame(g1x, g1y, g1z, g2x, g2y, g2z,
                                                                             g3x, g3y, g3z)
    p1x, p1y, p1z = _rotate(e11, e12, e13, e21, e22, e23, e31, e32, e33, q1x, q1y, q1z)
    p2x, p2y, p2z = _rotate(e11, e12, e13, e21, e22, e23, e31, e32, e33, q2x, q2y, q2z)
    p3x, p3y, p3z = _rotate(e11, e12, e13, e21, e22, e23, e31, e32, e33, q3x, q3y, q3z)
    p4x, p4y, p4z = _rotate(e11, e12, e13, e21, e22, e23, e31, e32, e33, q4x, q4y, q4z)
    nub = lam / (lam + 2.0 * mu)
    # strain-rate amplitudes in the frame (1/s), per coordinate the pattern varies with
    ex_eta = p1x * b1 * r8
    ez_eta = p2z * b3 * r8
    sxz_eta = ex_eta + ez_eta
    gxz_eta = (p1z * b1 + p2x * b3) * r8  # engineering shear
    ex_zeta = p3x * b1 * r8
    ey_zeta = p2y * b2 * r8
    sxy_zeta = ex_zeta + ey_zeta
    gxy_zeta = (p2x * b2 + p3y * b1) * r8
    ey_xi = p1y * b2 * r8
    ez_xi = p3z * b3 * r8
    syz_xi = ey_xi + ez_xi
    gyz_xi = (p1z * b2 + p3y * b3) * r8
    a4x = p4x * b1 * r8
    a4y = p4y * b2 * r8
    a4z = p4z * b3 * r8
    # bulk viscosity and step as the one-point element (element_reference.element_update)
    qb, dw_visc, dt_e = _viscosity_and_step(c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, det, vol, vol0[e], mat,
                                             lam, mu, lxx + lyy + lzz, dt, hourglass_omega2_factor(mat))
    wg = vol * r8
    dw_int = 0.0
    dw_pl = 0.0
    m0 = m1 = m2 = m3 = m4 = m5 = 0.0
    F1x = F1y = F1z = F2x = F2y = F2z = F3x = F3y = F3z = F4x = F4y = F4z = 0.0
    for g in range(8):
        xi = GP[g, 0]
        eta = GP[g, 1]
        zeta = GP[g, 2]
        # frame strain rate of the hourglass fields at the point
        txx = eta * ex_eta + zeta * ex_zeta - xi * nub * syz_xi
        tyy = -eta * nub * sxz_eta + zeta * ey_zeta + xi * ey_xi
        tzz = eta * ez_eta - zeta * nub * sxy_zeta + xi * ez_xi
        ux = eta * zeta * a4x
        uy = xi * zeta * a4y
        uz = xi * eta * a4z
        tu = (ux + uy + uz) / 3.0
        txx += ux - tu
        tyy += uy - tu
        tzz += uz - tu
        tyz = 0.5 * xi * gyz_xi
        txz = 0.5 * eta * gxz_eta
        txy = 0.5 * zeta * gxy_zeta
        # to global axes: D = E^T T E (rows of E are the frame axes)
        # columns k of E^T: e_k; D_ij = sum_kl e_ki T_kl e_lj
        ax0 = txx * e11 + txy * e21 + txz * e31
        ax1 = txx * e12 + txy * e22 + txz * e32
        ax2 = txx * e13 + txy * e23 + txz * e33
        ay0 = txy * e11 + tyy * e21 + tyz * e31
        ay1 = txy * e12 + tyy * e22 + tyz * e32
        ay2 = txy * e13 + tyy * e23 + tyz * e33
        az0 = txz * e11 + tyz * e21 + tzz * e31
        az1 = txz * e12 + tyz * e22 + tzz * e32
        az2 = txz * e13 + tyz * e23 + tzz * e33
        Dxx = lxx + e11 * ax0 + e21 * ay0 + e31 * az0
        Dyy = lyy + e12 * ax1 + e22 * ay1 + e32 * az1
        Dzz = lzz + e13 * ax2 + e23 * ay2 + e33 * az2
        Dyz = dyz + e12 * ax2 + e22 * ay2 + e32 * az2
        Dxz = dxz + e11 * ax2 + e21 * ay2 + e31 * az2
        Dxy = dxy + e11 * ax1 + e21 * ay1 + e31 * az1
        t0, t1, t2, t3, t4, t5, dw, dwp = _point_update(8 * e + g, Dxx, Dyy, Dzz, Dyz, Dxz, Dxy, wyz, wxz, wxy, dt,
                                                        lam, mu, wg, stress, eps_p, sy_static, temp, mat)
        dw_int += dw
        dw_pl += dwp
        m0 += t0
        m1 += t1
        m2 += t2
        m3 += t3
        m4 += t4
        m5 += t5
        # the point's stress in the frame: S = E sigma E^T
        r0x = e11 * t0 + e12 * t5 + e13 * t4
        r0y = e11 * t5 + e12 * t1 + e13 * t3
        r0z = e11 * t4 + e12 * t3 + e13 * t2
        r1x = e21 * t0 + e22 * t5 + e23 * t4
        r1y = e21 * t5 + e22 * t1 + e23 * t3
        r1z = e21 * t4 + e22 * t3 + e23 * t2
        r2x = e31 * t0 + e32 * t5 + e33 * t4
        r2y = e31 * t5 + e32 * t1 + e33 * t3
        r2z = e31 * t4 + e32 * t3 + e33 * t2
        Sxx = r0x * e11 + r0y * e12 + r0z * e13
        Syy = r1x * e21 + r1y * e22 + r1z * e23
        Szz = r2x * e31 + r2y * e32 + r2z * e33
        Syz = r1x * e31 + r1y * e32 + r1z * e33
        Sxz = r0x * e31 + r0y * e32 + r0z * e33
        Sxy = r0x * e21 + r0y * e22 + r0z * e23
        # F_ak += w sigma : dD/dp_ak (shear: 2 S_ij D_ij, D_ij = gamma / 2)
        s_eta = wg * eta * r8
        s_zeta = wg * zeta * r8
        s_xi = wg * xi * r8
        F1x += s_eta * b1 * (Sxx - nub * Syy)
        F2z += s_eta * b3 * (Szz - nub * Syy)
        F1z += s_eta * b1 * Sxz + s_xi * b2 * Syz
        F2x += s_eta * b3 * Sxz + s_zeta * b2 * Sxy
        F3x += s_zeta * b1 * (Sxx - nub * Szz)
        F2y += s_zeta * b2 * (Syy - nub * Szz)
        F3y += s_zeta * b1 * Sxy + s_xi * b3 * Syz
        F1y += s_xi * b2 * (Syy - nub * Sxx)
        F3z += s_xi * b3 * (Szz - nub * Sxx)
        pS = (Sxx + Syy + Szz) / 3.0
        F4x += wg * eta * zeta * r8 * b1 * (Sxx - pS)
        F4y += wg * xi * zeta * r8 * b2 * (Syy - pS)
        F4z += wg * xi * eta * r8 * b3 * (Szz - pS)
    m0 *= r8
    m1 *= r8
    m2 *= r8
    m3 *= r8
    m4 *= r8
    m5 *= r8
    t1x, t1y, t1z, t2x, t2y, t2z, t3x, t3y, t3z = _tractions(m0, m1, m2, m3, m4, m5, qb, vol,
                                                             d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z)
    f1x, f1y, f1z = _rotate(e11, e21, e31, e12, e22, e32, e13, e23, e33, F1x, F1y, F1z)
    f2x, f2y, f2z = _rotate(e11, e21, e31, e12, e22, e32, e13, e23, e33, F2x, F2y, F2z)
    f3x, f3y, f3z = _rotate(e11, e21, e31, e12, e22, e32, e13, e23, e33, F3x, F3y, F3z)
    f4x, f4y, f4z = _rotate(e11, e21, e31, e12, e22, e32, e13, e23, e33, F4x, F4y, F4z)
    for I in range(8):
        n = n0 + offs[I]
        a = SX[I]
        b = SY[I]
        c = SZ[I]
        ga1 = H1[I] - (w11 * a + w12 * b + w13 * c)
        ga2 = H2[I] - (w21 * a + w22 * b + w23 * c)
        ga3 = H3[I] - (w31 * a + w32 * b + w33 * c)
        ga4 = H4[I] - (w41 * a + w42 * b + w43 * c)
        f[n, 0] -= a * t1x + b * t2x + c * t3x + ga1 * f1x + ga2 * f2x + ga3 * f3x + ga4 * f4x
        f[n, 1] -= a * t1y + b * t2y + c * t3y + ga1 * f1y + ga2 * f2y + ga3 * f3y + ga4 * f4y
        f[n, 2] -= a * t1z + b * t2z + c * t3z + ga1 * f1z + ga2 * f2z + ga3 * f3z + ga4 * f4z
    return dt_e, ST_OK, dw_int, dw_pl, dw_visc


@njit(**_jit)
def p8_pass(x, v, f, stress, eps_p, sy_static, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1, k0, k1):
    """All elements of the index box with :func:`_element_p8`, one at a time (:func:`bbar_pass` with
    ``p8=True``; Gauss-point state as there). Returns ``(dt_min, status, dW_int, dW_plastic, 0, dW_viscous)``."""
    return bbar_pass(x, v, f, stress, eps_p, sy_static, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1, k0,
                     k1, True, True)
