"""Reference implementation of the element of :mod:`peenflow.fe.element`: one element at a time.

The production kernel is the blocked, vectorised :func:`peenflow.fe.element.element_rows`
(one element per SIMD lane). This module keeps the same element written
plainly, one element per call (:func:`element_update`), and a pass over an
index box in 8 colours (parity of ``i, j, k``; :func:`element_pass` and its
``parallel=True`` twin), built from the same inlined algebra as the rows
(face vectors, dual basis, rates, hourglass shape vectors and rates,
tractions, frame rotations: the ``_``-helpers of :mod:`peenflow.fe.element`),
so the two differ only in loop order and data layout. It is the readable statement of the formulation
(module docstring of :mod:`peenflow.fe.element`) that the tests and
benchmarks compare the vectorised rows against (to 1e-12, with plastic flow
and stored hourglass forces: tests/fe/test_element.py,
tests/fe/test_hourglass.py); the solver never calls it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from peenflow._jit import jit, jit_twins
from peenflow.fe.element import (H1, H2, H3, H4, SX, SY, SZ,
                                 _element_frame, _face_vectors, _mode_rate, _hourglass_shape,
                                 _physical_increments, _rates,
                                 _rotate, _scaled9, _tractions, corner_offsets, hourglass_omega2_factor)
from peenflow.fe.safety import ST_DISTORTION, ST_NEGATIVE_VOLUME, ST_OK
from peenflow.fe.johnson_cook import (HG_PHYSICAL, M_ADIABATIC, M_BULK_LIN, M_BULK_QUAD, M_HEAT, M_HG, M_HG_FLOOR,
                                      M_HG_TYPE, M_LAM, M_MU, M_RHO, static_flow_stress, stress_update,
                                      thermal_factor)


#: the corner sign vectors: SX, SY, SZ (covariant sums), then the hourglass vectors H1 ... H4
SIGNS = np.array((SX, SY, SZ, H1, H2, H3, H4))


@jit(inline="always")
def _rows9(a, scale):
    """The first three rows of ``a`` (7, 3) times ``scale``, row by row."""
    return (a[0, 0] * scale, a[0, 1] * scale, a[0, 2] * scale, a[1, 0] * scale, a[1, 1] * scale,
            a[1, 2] * scale, a[2, 0] * scale, a[2, 1] * scale, a[2, 2] * scale)


@jit(inline="always")
def _modes12(a, first=3):
    """Rows ``first ... first + 3`` of ``a`` (., 3), row by row: the four hourglass modes' vectors."""
    m = first
    return (a[m, 0], a[m, 1], a[m, 2], a[m + 1, 0], a[m + 1, 1], a[m + 1, 2],
            a[m + 2, 0], a[m + 2, 1], a[m + 2, 2], a[m + 3, 0], a[m + 3, 1], a[m + 3, 2])


@jit
def element_update(e, n0, nnx, nnxy, x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt):
    """Update element ``e`` whose first node is ``n0``; scatter its forces into ``f``.

    Returns ``(dt_e, status, dW_int, dW_plastic, dW_hourglass, dW_viscous)``
    (s, -, J, J, J, J).
    """
    hdt = 0.5 * dt
    offs = corner_offsets(nnx, nnxy)
    # corner sums per sign vector (rows of SIGNS) and component: mid-step positions, velocities
    sp = np.zeros((7, 3))
    sv = np.zeros((7, 3))
    for I in range(8):
        n = n0 + offs[I]
        for a in range(3):
            va = v[n, a]
            pa = x[n, a] - hdt * va
            for m in range(7):
                sp[m, a] += SIGNS[m, I] * pa
                sv[m, a] += SIGNS[m, I] * va
    # g_k = (1/8) sum_I sign_k,I x_I, v_k likewise (V_k = 8 v_k), hourglass sums s_a, h_a
    g1x, g1y, g1z, g2x, g2y, g2z, g3x, g3y, g3z = _rows9(sp, 0.125)
    v1x, v1y, v1z, v2x, v2y, v2z, v3x, v3y, v3z = _rows9(sv, 0.125)
    V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z = _rows9(sv, 1.0)
    s1x, s1y, s1z, s2x, s2y, s2z, s3x, s3y, s3z, s4x, s4y, s4z = _modes12(sp)
    h1x, h1y, h1z, h2x, h2y, h2z, h3x, h3y, h3z, h4x, h4y, h4z = _modes12(sv)
    c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, det = _face_vectors(g1x, g1y, g1z, g2x, g2y, g2z, g3x, g3y, g3z)
    if not (det > 0.0):
        return 0.0, ST_NEGATIVE_VOLUME, 0.0, 0.0, 0.0, 0.0
    vol = 8.0 * det
    ratio = vol / vol0[e]
    if ratio < 0.1 or ratio > 10.0:
        return 0.0, ST_DISTORTION, 0.0, 0.0, 0.0, 0.0
    # dual vectors g^k, velocity gradient and its parts
    d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z = _scaled9(1.0 / det, c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z)
    lxx, lyy, lzz, dyz, dxz, dxy, wyz, wxz, wxy = _rates(v1x, v1y, v1z, v2x, v2y, v2z, v3x, v3y, v3z,
                                                         d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z)
    o0 = stress[e, 0]
    o1 = stress[e, 1]
    o2 = stress[e, 2]
    o3 = stress[e, 3]
    o4 = stress[e, 4]
    o5 = stress[e, 5]
    ep = eps_p[e]
    n0_, n1_, n2_, n3_, n4_, n5_, deps, sy, gr, sy_new = stress_update(
        o0, o1, o2, o3, o4, o5, lxx, lyy, lzz, dyz, dxz, dxy, wyz, wxz, wxy, dt, ep, sy_static[e], temp[e], mat
    )
    stress[e, 0] = n0_
    stress[e, 1] = n1_
    stress[e, 2] = n2_
    stress[e, 3] = n3_
    stress[e, 4] = n4_
    stress[e, 5] = n5_
    dw_pl = 0.0
    if deps > 0.0:
        eps_p[e] = ep + deps
        dw_pl = sy * deps * vol
        if mat[M_ADIABATIC] != 0.0:
            temp[e] += mat[M_HEAT] * sy * deps
            sy_new = static_flow_stress(ep + deps, thermal_factor(temp[e], mat), mat)
        sy_static[e] = sy_new
    # stress power (mid-step stress)
    dw_int = (
        0.5
        * dt
        * vol
        * (
            (o0 + n0_) * lxx
            + (o1 + n1_) * lyy
            + (o2 + n2_) * lzz
            + 2.0 * ((o3 + n3_) * dyz + (o4 + n4_) * dxz + (o5 + n5_) * dxy)
        )
    )
    # wave speed, characteristic length, bulk viscosity
    mod = mat[M_LAM] + 2.0 * mat[M_MU]
    rho = mat[M_RHO] * vol0[e] / vol
    c2 = mod / rho
    cw = math.sqrt(c2)
    amax = c1x * c1x + c1y * c1y + c1z * c1z
    t = c2x * c2x + c2y * c2y + c2z * c2z
    if t > amax:
        amax = t
    t = c3x * c3x + c3y * c3y + c3z * c3z
    if t > amax:
        amax = t
    lch = 2.0 * det / math.sqrt(amax)
    ev = lxx + lyy + lzz
    qb = 0.0
    qv = 0.0
    dw_visc = 0.0
    if ev < 0.0:
        qv = mat[M_BULK_LIN] * cw - mat[M_BULK_QUAD] * lch * ev
        qb = -rho * lch * qv * ev
        dw_visc = -qb * ev * vol * dt
    qhg = mat[M_HG]
    om = 2.0 * (qv + math.sqrt(qv * qv + c2)) / lch
    om2 = om * om + hourglass_omega2_factor(mat) * c2 / (lch * lch)
    dt_e = 2.0 / math.sqrt(om2)
    # t_k = V (sigma - q I) g^k
    t1x, t1y, t1z, t2x, t2y, t2z, t3x, t3y, t3z = _tractions(
        n0_, n1_, n2_, n3_, n4_, n5_, qb, vol, d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z)
    # hourglass: w_ak = (s_a . g^k)/8, q_a = h_a - sum_k w_ak * 8 vk
    w11, w12, w13, w21, w22, w23, w31, w32, w33, w41, w42, w43 = _hourglass_shape(
        s1x, s1y, s1z, s2x, s2y, s2z, s3x, s3y, s3z, s4x, s4y, s4z, d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z)
    q1x, q1y, q1z = _mode_rate(h1x, h1y, h1z, w11, w12, w13, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
    q2x, q2y, q2z = _mode_rate(h2x, h2y, h2z, w21, w22, w23, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
    q3x, q3y, q3z = _mode_rate(h3x, h3y, h3z, w31, w32, w33, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
    q4x, q4y, q4z = _mode_rate(h4x, h4y, h4z, w41, w42, w43, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
    o = hg[e]
    physical = mat[M_HG_TYPE] == HG_PHYSICAL
    if physical:
        # assumed-strain stabilisation in the element frame: rates to the
        # frame, force increments from the element's tangent (shear modulus
        # of this step's return, bulk modulus elastic); the stored forces stay
        # in the frame, so a rigid rotation carries them along
        e11, e12, e13, e21, e22, e23, e31, e32, e33, b1, b2, b3 = _element_frame(
            g1x, g1y, g1z, g2x, g2y, g2z, g3x, g3y, g3z)
        p1x, p1y, p1z = _rotate(e11, e12, e13, e21, e22, e23, e31, e32, e33, q1x, q1y, q1z)
        p2x, p2y, p2z = _rotate(e11, e12, e13, e21, e22, e23, e31, e32, e33, q2x, q2y, q2z)
        p3x, p3y, p3z = _rotate(e11, e12, e13, e21, e22, e23, e31, e32, e33, q3x, q3y, q3z)
        p4x, p4y, p4z = _rotate(e11, e12, e13, e21, e22, e23, e31, e32, e33, q4x, q4y, q4z)
        mu = mat[M_MU]
        k1x, k1y, k1z, k2x, k2y, k2z, k3x, k3y, k3z, k4x, k4y, k4z = _physical_increments(
            p1x, p1y, p1z, p2x, p2y, p2z, p3x, p3y, p3z, p4x, p4y, p4z, b1, b2, b3, mu * gr,
            mat[M_LAM] + 2.0 * mu / 3.0, dt * vol / 192.0)
    else:
        # stiffness form in global axes: the rates are the global ones
        e11 = e12 = e13 = e21 = e22 = e23 = e31 = e32 = e33 = 0.0
        p1x, p1y, p1z, p2x, p2y, p2z, p3x, p3y, p3z, p4x, p4y, p4z = (
            q1x, q1y, q1z, q2x, q2y, q2z, q3x, q3y, q3z, q4x, q4y, q4z)
        gsum = d1x * d1x + d1y * d1y + d1z * d1z + d2x * d2x + d2y * d2y + d2z * d2z + d3x * d3x + d3y * d3y + d3z * d3z
        # hourglass stiffness follows the element's deviatoric tangent: full when
        # elastic, reduced (not below M_HG_FLOOR) in a yielding element, whose
        # elastic hourglass stiffness would otherwise stiffen the dent
        if gr < mat[M_HG_FLOOR]:
            gr = mat[M_HG_FLOOR]
        khg = qhg * mod * vol * gsum / 24.0 * dt * gr
        k1x, k1y, k1z, k2x, k2y, k2z, k3x, k3y, k3z, k4x, k4y, k4z = (
            khg * q1x, khg * q1y, khg * q1z, khg * q2x, khg * q2y, khg * q2z,
            khg * q3x, khg * q3y, khg * q3z, khg * q4x, khg * q4y, khg * q4z)
    # stored forces (element frame for the physical form, global axes for the
    # stiffness form) grow by the increments; work at mid-step force
    inc = (k1x, k1y, k1z, k2x, k2y, k2z, k3x, k3y, k3z, k4x, k4y, k4z)
    rates = (p1x, p1y, p1z, p2x, p2y, p2z, p3x, p3y, p3z, p4x, p4y, p4z)
    work = 0.0
    for c in range(12):
        grown = o[c] + inc[c]
        work += (o[c] + grown) * rates[c]
        o[c] = grown
    dw_hg = 0.5 * dt * work
    l1x, l1y, l1z, l2x, l2y, l2z, l3x, l3y, l3z, l4x, l4y, l4z = _modes12(o.reshape((4, 3)), 0)
    if physical:
        # back to global axes (the frame's transpose)
        f1x, f1y, f1z = _rotate(e11, e21, e31, e12, e22, e32, e13, e23, e33, l1x, l1y, l1z)
        f2x, f2y, f2z = _rotate(e11, e21, e31, e12, e22, e32, e13, e23, e33, l2x, l2y, l2z)
        f3x, f3y, f3z = _rotate(e11, e21, e31, e12, e22, e32, e13, e23, e33, l3x, l3y, l3z)
        f4x, f4y, f4z = _rotate(e11, e21, e31, e12, e22, e32, e13, e23, e33, l4x, l4y, l4z)
    else:
        f1x, f1y, f1z, f2x, f2y, f2z, f3x, f3y, f3z, f4x, f4y, f4z = (
            l1x, l1y, l1z, l2x, l2y, l2z, l3x, l3y, l3z, l4x, l4y, l4z)
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
    return dt_e, ST_OK, dw_int, dw_pl, dw_hg, dw_visc


def _element_pass(x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1, k0, k1):
    """All elements of the index box ``[i0,i1) x [j0,j1) x [k0,k1)``, in 8 colours.

    ``f`` (n_nodes, 3) N must be zero on the box's nodes on entry; it returns
    the nodal forces ``-f_int``. Returns ``(dt_min, status, dW_int, dW_plastic,
    dW_hourglass, dW_viscous)``.
    """
    nnxy = nnx * nny
    dtmin = 1e30
    status = 0
    wi = 0.0
    wp = 0.0
    wh = 0.0
    wv = 0.0
    for colour in range(8):
        ci = colour & 1
        cj = (colour >> 1) & 1
        ck = (colour >> 2) & 1
        ni = (i1 - i0 - ci + 1) // 2
        nj = (j1 - j0 - cj + 1) // 2
        nk = (k1 - k0 - ck + 1) // 2
        if ni <= 0 or nj <= 0 or nk <= 0:
            continue
        for jk in prange(nj * nk):
            kk = jk // nj
            jj = jk - kk * nj
            k = k0 + ck + 2 * kk
            j = j0 + cj + 2 * jj
            for ii in range(ni):
                i = i0 + ci + 2 * ii
                e = i + nx * (j + ny * k)
                n0 = i + nnx * (j + nny * k)
                dte, st, a1, a2, a3, a4 = element_update(e, n0, nnx, nnxy, x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt)
                dtmin = min(dtmin, dte)
                status = max(status, st)
                wi += a1
                wp += a2
                wh += a3
                wv += a4
    return dtmin, status, wi, wp, wh, wv


element_pass, element_pass_parallel = jit_twins(_element_pass)
