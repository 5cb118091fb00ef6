"""One-point (uniform-strain) hexahedron with Flanagan-Belytschko hourglass control.

Per element and step (central difference, forces at ``t_{n+1}``):

1. Geometry at mid-step ``x_{n+1/2} = x_{n+1} - dt/2 v_{n+1/2}``: covariant
   vectors ``g_k = sum_I xi_k,I x_I / 8`` (the Jacobian at the centre), their
   duals ``g^k``, volume ``V = 8 det J``. Shape-function gradients
   ``grad N_I = sum_k xi_k,I g^k / 8``: exact for linear fields, so a uniform
   strain (patch test) is reproduced to round-off. Evaluating the rate at the
   mid-step configuration makes ``D`` exactly zero for a rigid rotation
   (Cayley transform), so rigid motion creates no stress.
2. ``L = sum_I v_I (x) grad N_I``, ``D = sym L``, ``W = skew L``; Jaumann
   stress update + Johnson-Cook return (:mod:`peenflow.fe.johnson_cook`).
3. Bulk viscosity (linear + quadratic, in compression only)::

       q = rho l (c_quad l |tr D| - c_lin c) tr D      (tr D < 0)

4. Nodal forces ``f_I = -V (sigma - q I) grad N_I``.
5. Hourglass (Flanagan & Belytschko 1981, stiffness type): hourglass shape
   vectors ``gamma_a = Gamma_a - (Gamma_a . x) grad N`` for the 4 modes,
   hourglass rates ``q_a = sum_I gamma_a,I v_I``; the element keeps an
   hourglass force ``F_a`` (12 values) that grows by ``k_hg q_a dt`` with
   ``k_hg = Q_hg (lambda + 2 mu) V sum_k |g^k|^2 / 24`` (``= Q_hg (lambda+2mu) h / 2``
   for a cube of side ``h``); nodal forces ``-sum_a F_a gamma_a,I``. A
   stiffness (not viscous) form is used because residual stresses are read
   at rest, where a viscous form would leave the hourglass modes free.
6. Stable step of the element: highest frequency bounded by
   ``omega^2 = (2 (Q + sqrt(Q^2 + c^2)) / l)^2 + 32 Q_hg c^2 / l^2`` with
   ``l = V / A_max`` (largest face), ``c`` the dilatational speed at the
   current density and ``Q`` the bulk-viscosity term; ``dt_e = 2 / omega``.

Two implementations of the same element (they agree to round-off, see
tests/fe/test_element.py):

* :func:`element_rows` (used by the solver): rows of elements along ``i``,
  processed in blocks of ``BLOCK`` elements with structure-of-arrays scratch;
  the plastic return and the nodal scatter in separate scalar loops. Rows are
  coloured by the parity of ``(j, k)`` (4 colours): rows of one colour share
  no node, so the scatter is race-free under ``prange`` and, each row being
  done in ``i`` order by one thread, the summation order is the same for any
  thread count (bit-identical results on 1 and 2 threads). ~1.5x faster than
  the per-element version on one thread (BENCHMARKS.md).
* :func:`element_pass`: one element at a time in 8 colours (parity of
  ``i, j, k``); the reference implementation.
"""

from __future__ import annotations

import math

from numba import prange

from peenflow._jit import jit
import numpy as np

from peenflow.fe.johnson_cook import radial_return, M_HG_FLOOR, M_BULK_LIN, M_BULK_QUAD, M_HG, M_LAM, M_MU, M_RHO, static_flow_stress, stress_update, thermal_factor, M_ADIABATIC, M_HEAT

# local node signs (xi, eta, zeta) and the 4 hourglass base vectors
SX = (-1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0, -1.0)
SY = (-1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0)
SZ = (-1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0)
H1 = (1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0)  # xi eta
H2 = (1.0, 1.0, -1.0, -1.0, -1.0, -1.0, 1.0, 1.0)  # eta zeta
H3 = (1.0, -1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0)  # zeta xi
H4 = (-1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0, -1.0)  # xi eta zeta

# status codes shared with the solver (see safety.py)
ST_OK = 0
ST_NEGATIVE_VOLUME = 2
ST_DISTORTION = 3


@jit
def element_update(e, n0, nnx, nnxy, x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt):
    """Update element ``e`` whose first node is ``n0``; scatter its forces into ``f``.

    Returns ``(dt_e, status, dW_int, dW_plastic, dW_hourglass, dW_viscous)``
    (s, -, J, J, J, J).
    """
    hdt = 0.5 * dt
    nd0 = n0
    nd1 = n0 + 1
    nd2 = n0 + 1 + nnx
    nd3 = n0 + nnx
    nodes = (nd0, nd1, nd2, nd3, nd0 + nnxy, nd1 + nnxy, nd2 + nnxy, nd3 + nnxy)
    g1x = g1y = g1z = g2x = g2y = g2z = g3x = g3y = g3z = 0.0
    v1x = v1y = v1z = v2x = v2y = v2z = v3x = v3y = v3z = 0.0
    s1x = s1y = s1z = s2x = s2y = s2z = s3x = s3y = s3z = s4x = s4y = s4z = 0.0
    h1x = h1y = h1z = h2x = h2y = h2z = h3x = h3y = h3z = h4x = h4y = h4z = 0.0
    for I in range(8):
        n = nodes[I]
        vx = v[n, 0]
        vy = v[n, 1]
        vz = v[n, 2]
        px = x[n, 0] - hdt * vx
        py = x[n, 1] - hdt * vy
        pz = x[n, 2] - hdt * vz
        a = SX[I]
        b = SY[I]
        c = SZ[I]
        g1x += a * px
        g1y += a * py
        g1z += a * pz
        g2x += b * px
        g2y += b * py
        g2z += b * pz
        g3x += c * px
        g3y += c * py
        g3z += c * pz
        v1x += a * vx
        v1y += a * vy
        v1z += a * vz
        v2x += b * vx
        v2y += b * vy
        v2z += b * vz
        v3x += c * vx
        v3y += c * vy
        v3z += c * vz
        a = H1[I]
        s1x += a * px
        s1y += a * py
        s1z += a * pz
        h1x += a * vx
        h1y += a * vy
        h1z += a * vz
        a = H2[I]
        s2x += a * px
        s2y += a * py
        s2z += a * pz
        h2x += a * vx
        h2y += a * vy
        h2z += a * vz
        a = H3[I]
        s3x += a * px
        s3y += a * py
        s3z += a * pz
        h3x += a * vx
        h3y += a * vy
        h3z += a * vz
        a = H4[I]
        s4x += a * px
        s4y += a * py
        s4z += a * pz
        h4x += a * vx
        h4y += a * vy
        h4z += a * vz
    r8 = 0.125
    g1x *= r8
    g1y *= r8
    g1z *= r8
    g2x *= r8
    g2y *= r8
    g2z *= r8
    g3x *= r8
    g3y *= r8
    g3z *= r8
    v1x *= r8
    v1y *= r8
    v1z *= r8
    v2x *= r8
    v2y *= r8
    v2z *= r8
    v3x *= r8
    v3y *= r8
    v3z *= r8
    # cross products c_k (face area vectors / 4) and determinant
    c1x = g2y * g3z - g2z * g3y
    c1y = g2z * g3x - g2x * g3z
    c1z = g2x * g3y - g2y * g3x
    c2x = g3y * g1z - g3z * g1y
    c2y = g3z * g1x - g3x * g1z
    c2z = g3x * g1y - g3y * g1x
    c3x = g1y * g2z - g1z * g2y
    c3y = g1z * g2x - g1x * g2z
    c3z = g1x * g2y - g1y * g2x
    det = g1x * c1x + g1y * c1y + g1z * c1z
    if not (det > 0.0):
        return 0.0, ST_NEGATIVE_VOLUME, 0.0, 0.0, 0.0, 0.0
    vol = 8.0 * det
    ratio = vol / vol0[e]
    if ratio < 0.1 or ratio > 10.0:
        return 0.0, ST_DISTORTION, 0.0, 0.0, 0.0, 0.0
    idet = 1.0 / det
    # dual vectors g^k
    d1x = c1x * idet
    d1y = c1y * idet
    d1z = c1z * idet
    d2x = c2x * idet
    d2y = c2y * idet
    d2z = c2z * idet
    d3x = c3x * idet
    d3y = c3y * idet
    d3z = c3z * idet
    # velocity gradient L_ab = sum_k vk_a g^k_b
    lxx = v1x * d1x + v2x * d2x + v3x * d3x
    lxy = v1x * d1y + v2x * d2y + v3x * d3y
    lxz = v1x * d1z + v2x * d2z + v3x * d3z
    lyx = v1y * d1x + v2y * d2x + v3y * d3x
    lyy = v1y * d1y + v2y * d2y + v3y * d3y
    lyz = v1y * d1z + v2y * d2z + v3y * d3z
    lzx = v1z * d1x + v2z * d2x + v3z * d3x
    lzy = v1z * d1y + v2z * d2y + v3z * d3y
    lzz = v1z * d1z + v2z * d2z + v3z * d3z
    dyz = 0.5 * (lyz + lzy)
    dxz = 0.5 * (lxz + lzx)
    dxy = 0.5 * (lxy + lyx)
    wyz = 0.5 * (lyz - lzy)
    wxz = 0.5 * (lxz - lzx)
    wxy = 0.5 * (lxy - lyx)
    o0 = stress[e, 0]
    o1 = stress[e, 1]
    o2 = stress[e, 2]
    o3 = stress[e, 3]
    o4 = stress[e, 4]
    o5 = stress[e, 5]
    ep = eps_p[e]
    n0_, n1_, n2_, n3_, n4_, n5_, deps, sy, gr = stress_update(
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
        sy_static[e] = static_flow_stress(ep + deps, thermal_factor(temp[e], mat), mat)
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
    om2 = om * om + 32.0 * qhg * c2 / (lch * lch)
    dt_e = 2.0 / math.sqrt(om2)
    # t_k = V (sigma - q I) g^k
    sxx = (n0_ - qb) * vol
    syy = (n1_ - qb) * vol
    szz = (n2_ - qb) * vol
    syz = n3_ * vol
    sxz = n4_ * vol
    sxy = n5_ * vol
    t1x = (sxx * d1x + sxy * d1y + sxz * d1z) * r8
    t1y = (sxy * d1x + syy * d1y + syz * d1z) * r8
    t1z = (sxz * d1x + syz * d1y + szz * d1z) * r8
    t2x = (sxx * d2x + sxy * d2y + sxz * d2z) * r8
    t2y = (sxy * d2x + syy * d2y + syz * d2z) * r8
    t2z = (sxz * d2x + syz * d2y + szz * d2z) * r8
    t3x = (sxx * d3x + sxy * d3y + sxz * d3z) * r8
    t3y = (sxy * d3x + syy * d3y + syz * d3z) * r8
    t3z = (sxz * d3x + syz * d3y + szz * d3z) * r8
    # hourglass: w_ak = (s_a . g^k)/8, q_a = h_a - sum_k w_ak * 8 vk
    w11 = (s1x * d1x + s1y * d1y + s1z * d1z) * r8
    w12 = (s1x * d2x + s1y * d2y + s1z * d2z) * r8
    w13 = (s1x * d3x + s1y * d3y + s1z * d3z) * r8
    w21 = (s2x * d1x + s2y * d1y + s2z * d1z) * r8
    w22 = (s2x * d2x + s2y * d2y + s2z * d2z) * r8
    w23 = (s2x * d3x + s2y * d3y + s2z * d3z) * r8
    w31 = (s3x * d1x + s3y * d1y + s3z * d1z) * r8
    w32 = (s3x * d2x + s3y * d2y + s3z * d2z) * r8
    w33 = (s3x * d3x + s3y * d3y + s3z * d3z) * r8
    w41 = (s4x * d1x + s4y * d1y + s4z * d1z) * r8
    w42 = (s4x * d2x + s4y * d2y + s4z * d2z) * r8
    w43 = (s4x * d3x + s4y * d3y + s4z * d3z) * r8
    q1x = h1x - 8.0 * (w11 * v1x + w12 * v2x + w13 * v3x)
    q1y = h1y - 8.0 * (w11 * v1y + w12 * v2y + w13 * v3y)
    q1z = h1z - 8.0 * (w11 * v1z + w12 * v2z + w13 * v3z)
    q2x = h2x - 8.0 * (w21 * v1x + w22 * v2x + w23 * v3x)
    q2y = h2y - 8.0 * (w21 * v1y + w22 * v2y + w23 * v3y)
    q2z = h2z - 8.0 * (w21 * v1z + w22 * v2z + w23 * v3z)
    q3x = h3x - 8.0 * (w31 * v1x + w32 * v2x + w33 * v3x)
    q3y = h3y - 8.0 * (w31 * v1y + w32 * v2y + w33 * v3y)
    q3z = h3z - 8.0 * (w31 * v1z + w32 * v2z + w33 * v3z)
    q4x = h4x - 8.0 * (w41 * v1x + w42 * v2x + w43 * v3x)
    q4y = h4y - 8.0 * (w41 * v1y + w42 * v2y + w43 * v3y)
    q4z = h4z - 8.0 * (w41 * v1z + w42 * v2z + w43 * v3z)
    gsum = d1x * d1x + d1y * d1y + d1z * d1z + d2x * d2x + d2y * d2y + d2z * d2z + d3x * d3x + d3y * d3y + d3z * d3z
    # hourglass stiffness follows the element's deviatoric tangent: full when
    # elastic, reduced (not below M_HG_FLOOR) in a yielding element, whose
    # elastic hourglass stiffness would otherwise stiffen the dent
    if gr < mat[M_HG_FLOOR]:
        gr = mat[M_HG_FLOOR]
    khg = qhg * mod * vol * gsum / 24.0 * dt * gr
    o = hg[e]
    f1x = o[0] + khg * q1x
    f1y = o[1] + khg * q1y
    f1z = o[2] + khg * q1z
    f2x = o[3] + khg * q2x
    f2y = o[4] + khg * q2y
    f2z = o[5] + khg * q2z
    f3x = o[6] + khg * q3x
    f3y = o[7] + khg * q3y
    f3z = o[8] + khg * q3z
    f4x = o[9] + khg * q4x
    f4y = o[10] + khg * q4y
    f4z = o[11] + khg * q4z
    dw_hg = (
        0.5
        * dt
        * (
            (o[0] + f1x) * q1x + (o[1] + f1y) * q1y + (o[2] + f1z) * q1z
            + (o[3] + f2x) * q2x + (o[4] + f2y) * q2y + (o[5] + f2z) * q2z
            + (o[6] + f3x) * q3x + (o[7] + f3y) * q3y + (o[8] + f3z) * q3z
            + (o[9] + f4x) * q4x + (o[10] + f4y) * q4y + (o[11] + f4z) * q4z
        )
    )
    o[0] = f1x
    o[1] = f1y
    o[2] = f1z
    o[3] = f2x
    o[4] = f2y
    o[5] = f2z
    o[6] = f3x
    o[7] = f3y
    o[8] = f3z
    o[9] = f4x
    o[10] = f4y
    o[11] = f4z
    for I in range(8):
        n = nodes[I]
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


element_pass = jit(_element_pass)


def _element_pass_parallel(x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1, k0, k1):
    """Same as :func:`element_pass`, compiled with ``parallel=True``.

    (A separate function, not a second ``jit`` of the same one, because
    numba's disk cache keys entries by function and signature only.)
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


element_pass_parallel = jit(_element_pass_parallel, parallel=True)


# ---------------------------------------------------------------------------
# Blocked variant: the same element, B consecutive elements of a row at a time
# with the per-element arithmetic in loops over the block that LLVM can
# vectorise (structure-of-arrays scratch), the plastic return and the nodal
# scatter in scalar loops. Rows are coloured by (j, k) parity (4 colours):
# rows of one colour share no node, each row is done by one thread in i
# order, so the summation order is fixed for any thread count.
# ---------------------------------------------------------------------------

BLOCK = 8


@jit
def _row(j, k, i0, i1, nnx, nny, nx, ny, x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt, out):
    """Elements ``i0 <= i < i1`` of row ``(j, k)``; ``out`` (6,) accumulates
    ``dt_min, status, dW_int, dW_plastic, dW_hourglass, dW_viscous``."""
    B = BLOCK
    nnxy = nnx * nny
    hdt = 0.5 * dt
    r8 = 0.125
    offs = (0, 1, 1 + nnx, nnx, nnxy, nnxy + 1, nnxy + 1 + nnx, nnxy + nnx)
    acc = np.empty((42, B))
    dual = np.empty((9, B))
    lm = np.empty((9, B))
    old = np.empty((6, B))
    sn = np.empty((6, B))
    aux = np.empty((8, B))  # vol, det, lch, q_trial, g_ratio, dt_e, status
    ew = np.empty((3, B))  # dW_int, dW_hg, dW_visc per lane
    fe = np.empty((24, B))
    mod = mat[M_LAM] + 2.0 * mat[M_MU]
    lam = mat[M_LAM]
    mu2 = 2.0 * mat[M_MU] * dt
    rho0 = mat[M_RHO]
    qlin = mat[M_BULK_LIN]
    qquad = mat[M_BULK_QUAD]
    qhg = mat[M_HG]
    hgfloor = mat[M_HG_FLOOR]
    ebase = nx * (j + ny * k)
    nbase = nnx * (j + nny * k)
    for ib in range(i0, i1, B):
        nb = min(B, i1 - ib)
        e0 = ebase + ib
        n00 = nbase + ib
        # ---- gather: sums over the 8 nodes (vectorised over the block)
        for r in range(42):
            for l in range(nb):
                acc[r, l] = 0.0
        for I in range(8):
            a = SX[I]
            b = SY[I]
            c = SZ[I]
            h1 = H1[I]
            h2 = H2[I]
            h3 = H3[I]
            h4 = H4[I]
            nI = n00 + offs[I]
            for l in range(nb):
                n = nI + l
                vx = v[n, 0]
                vy = v[n, 1]
                vz = v[n, 2]
                px = x[n, 0] - hdt * vx
                py = x[n, 1] - hdt * vy
                pz = x[n, 2] - hdt * vz
                acc[0, l] += a * px
                acc[1, l] += a * py
                acc[2, l] += a * pz
                acc[3, l] += b * px
                acc[4, l] += b * py
                acc[5, l] += b * pz
                acc[6, l] += c * px
                acc[7, l] += c * py
                acc[8, l] += c * pz
                acc[9, l] += a * vx
                acc[10, l] += a * vy
                acc[11, l] += a * vz
                acc[12, l] += b * vx
                acc[13, l] += b * vy
                acc[14, l] += b * vz
                acc[15, l] += c * vx
                acc[16, l] += c * vy
                acc[17, l] += c * vz
                acc[18, l] += h1 * px
                acc[19, l] += h1 * py
                acc[20, l] += h1 * pz
                acc[21, l] += h2 * px
                acc[22, l] += h2 * py
                acc[23, l] += h2 * pz
                acc[24, l] += h3 * px
                acc[25, l] += h3 * py
                acc[26, l] += h3 * pz
                acc[27, l] += h4 * px
                acc[28, l] += h4 * py
                acc[29, l] += h4 * pz
                acc[30, l] += h1 * vx
                acc[31, l] += h1 * vy
                acc[32, l] += h1 * vz
                acc[33, l] += h2 * vx
                acc[34, l] += h2 * vy
                acc[35, l] += h2 * vz
                acc[36, l] += h3 * vx
                acc[37, l] += h3 * vy
                acc[38, l] += h3 * vz
                acc[39, l] += h4 * vx
                acc[40, l] += h4 * vy
                acc[41, l] += h4 * vz
        # ---- geometry, rates, Jaumann trial stress (vectorised)
        for l in range(nb):
            e = e0 + l
            g1x = acc[0, l] * r8
            g1y = acc[1, l] * r8
            g1z = acc[2, l] * r8
            g2x = acc[3, l] * r8
            g2y = acc[4, l] * r8
            g2z = acc[5, l] * r8
            g3x = acc[6, l] * r8
            g3y = acc[7, l] * r8
            g3z = acc[8, l] * r8
            v1x = acc[9, l] * r8
            v1y = acc[10, l] * r8
            v1z = acc[11, l] * r8
            v2x = acc[12, l] * r8
            v2y = acc[13, l] * r8
            v2z = acc[14, l] * r8
            v3x = acc[15, l] * r8
            v3y = acc[16, l] * r8
            v3z = acc[17, l] * r8
            c1x = g2y * g3z - g2z * g3y
            c1y = g2z * g3x - g2x * g3z
            c1z = g2x * g3y - g2y * g3x
            c2x = g3y * g1z - g3z * g1y
            c2y = g3z * g1x - g3x * g1z
            c2z = g3x * g1y - g3y * g1x
            c3x = g1y * g2z - g1z * g2y
            c3y = g1z * g2x - g1x * g2z
            c3z = g1x * g2y - g1y * g2x
            det = g1x * c1x + g1y * c1y + g1z * c1z
            vol = 8.0 * det
            ratio = vol / vol0[e]
            stc = 0.0
            if not (det > 0.0):
                stc = ST_NEGATIVE_VOLUME
            elif ratio < 0.1 or ratio > 10.0:
                stc = ST_DISTORTION
            aux[6, l] = stc
            idet = 1.0 / det
            d1x = c1x * idet
            d1y = c1y * idet
            d1z = c1z * idet
            d2x = c2x * idet
            d2y = c2y * idet
            d2z = c2z * idet
            d3x = c3x * idet
            d3y = c3y * idet
            d3z = c3z * idet
            dual[0, l] = d1x
            dual[1, l] = d1y
            dual[2, l] = d1z
            dual[3, l] = d2x
            dual[4, l] = d2y
            dual[5, l] = d2z
            dual[6, l] = d3x
            dual[7, l] = d3y
            dual[8, l] = d3z
            lxx = v1x * d1x + v2x * d2x + v3x * d3x
            lxy = v1x * d1y + v2x * d2y + v3x * d3y
            lxz = v1x * d1z + v2x * d2z + v3x * d3z
            lyx = v1y * d1x + v2y * d2x + v3y * d3x
            lyy = v1y * d1y + v2y * d2y + v3y * d3y
            lyz = v1y * d1z + v2y * d2z + v3y * d3z
            lzx = v1z * d1x + v2z * d2x + v3z * d3x
            lzy = v1z * d1y + v2z * d2y + v3z * d3y
            lzz = v1z * d1z + v2z * d2z + v3z * d3z
            dyz = 0.5 * (lyz + lzy)
            dxz = 0.5 * (lxz + lzx)
            dxy = 0.5 * (lxy + lyx)
            wyz = 0.5 * (lyz - lzy)
            wxz = 0.5 * (lxz - lzx)
            wxy = 0.5 * (lxy - lyx)
            lm[0, l] = lxx
            lm[1, l] = lyy
            lm[2, l] = lzz
            lm[3, l] = dyz
            lm[4, l] = dxz
            lm[5, l] = dxy
            amax = max(c1x * c1x + c1y * c1y + c1z * c1z, c2x * c2x + c2y * c2y + c2z * c2z,
                       c3x * c3x + c3y * c3y + c3z * c3z)
            aux[0, l] = vol
            aux[1, l] = det
            aux[2, l] = 2.0 * det / math.sqrt(amax)
            sxx = stress[e, 0]
            syy = stress[e, 1]
            szz = stress[e, 2]
            syz = stress[e, 3]
            sxz = stress[e, 4]
            sxy = stress[e, 5]
            old[0, l] = sxx
            old[1, l] = syy
            old[2, l] = szz
            old[3, l] = syz
            old[4, l] = sxz
            old[5, l] = sxy
            m00 = wxy * sxy + wxz * sxz
            m11 = -wxy * sxy + wyz * syz
            m22 = -wxz * sxz - wyz * syz
            m01 = wxy * syy + wxz * syz
            m10 = -wxy * sxx + wyz * sxz
            m02 = wxy * syz + wxz * szz
            m20 = -wxz * sxx - wyz * sxy
            m12 = -wxy * sxz + wyz * szz
            m21 = -wxz * sxy - wyz * syy
            lt = lam * (lxx + lyy + lzz) * dt
            t0 = sxx + dt * 2.0 * m00 + lt + mu2 * lxx
            t1 = syy + dt * 2.0 * m11 + lt + mu2 * lyy
            t2 = szz + dt * 2.0 * m22 + lt + mu2 * lzz
            t3 = syz + dt * (m12 + m21) + mu2 * dyz
            t4 = sxz + dt * (m02 + m20) + mu2 * dxz
            t5 = sxy + dt * (m01 + m10) + mu2 * dxy
            sn[0, l] = t0
            sn[1, l] = t1
            sn[2, l] = t2
            sn[3, l] = t3
            sn[4, l] = t4
            sn[5, l] = t5
            p = (t0 + t1 + t2) / 3.0
            a0 = t0 - p
            a1 = t1 - p
            a2 = t2 - p
            aux[3, l] = math.sqrt(1.5 * (a0 * a0 + a1 * a1 + a2 * a2 + 2.0 * (t3 * t3 + t4 * t4 + t5 * t5)))
            aux[4, l] = 1.0
        # ---- plastic return (scalar, only yielding elements)
        for l in range(nb):
            e = e0 + l
            if aux[6, l] != 0.0:
                out[1] = max(out[1], aux[6, l])
                continue
            if aux[3, l] > sy_static[e] and dt > 0.0:
                deps, sy, gr = _return_on_trial(sn, l, aux[3, l], lm, dt, eps_p[e], temp[e], mat)
                if deps > 0.0:
                    ep = eps_p[e] + deps
                    eps_p[e] = ep
                    out[3] += sy * deps * aux[0, l]
                    if mat[M_ADIABATIC] != 0.0:
                        temp[e] += mat[M_HEAT] * sy * deps
                    sy_static[e] = static_flow_stress(ep, thermal_factor(temp[e], mat), mat)
                aux[4, l] = gr
            for c in range(6):
                stress[e, c] = sn[c, l]
        # ---- forces, hourglass, step, energies (vectorised)
        for l in range(nb):
            e = e0 + l
            vol = aux[0, l]
            det = aux[1, l]
            lch = aux[2, l]
            lxx = lm[0, l]
            lyy = lm[1, l]
            lzz = lm[2, l]
            n0_ = sn[0, l]
            n1_ = sn[1, l]
            n2_ = sn[2, l]
            n3_ = sn[3, l]
            n4_ = sn[4, l]
            n5_ = sn[5, l]
            ew[0, l] = 0.5 * dt * vol * ((old[0, l] + n0_) * lxx + (old[1, l] + n1_) * lyy + (old[2, l] + n2_) * lzz
                                         + 2.0 * ((old[3, l] + n3_) * lm[3, l] + (old[4, l] + n4_) * lm[4, l]
                                                  + (old[5, l] + n5_) * lm[5, l]))
            rho = rho0 * vol0[e] / vol
            c2 = mod / rho
            cw = math.sqrt(c2)
            ev = lxx + lyy + lzz
            qv = 0.0
            qb = 0.0
            if ev < 0.0:
                qv = qlin * cw - qquad * lch * ev
                qb = -rho * lch * qv * ev
            ew[2, l] = -qb * ev * vol * dt
            om = 2.0 * (qv + math.sqrt(qv * qv + c2)) / lch
            aux[5, l] = 2.0 / math.sqrt(om * om + 32.0 * qhg * c2 / (lch * lch))
            d1x = dual[0, l]
            d1y = dual[1, l]
            d1z = dual[2, l]
            d2x = dual[3, l]
            d2y = dual[4, l]
            d2z = dual[5, l]
            d3x = dual[6, l]
            d3y = dual[7, l]
            d3z = dual[8, l]
            sxx = (n0_ - qb) * vol
            syy = (n1_ - qb) * vol
            szz = (n2_ - qb) * vol
            syz = n3_ * vol
            sxz = n4_ * vol
            sxy = n5_ * vol
            t1x = (sxx * d1x + sxy * d1y + sxz * d1z) * r8
            t1y = (sxy * d1x + syy * d1y + syz * d1z) * r8
            t1z = (sxz * d1x + syz * d1y + szz * d1z) * r8
            t2x = (sxx * d2x + sxy * d2y + sxz * d2z) * r8
            t2y = (sxy * d2x + syy * d2y + syz * d2z) * r8
            t2z = (sxz * d2x + syz * d2y + szz * d2z) * r8
            t3x = (sxx * d3x + sxy * d3y + sxz * d3z) * r8
            t3y = (sxy * d3x + syy * d3y + syz * d3z) * r8
            t3z = (sxz * d3x + syz * d3y + szz * d3z) * r8
            s1x = acc[18, l]
            s1y = acc[19, l]
            s1z = acc[20, l]
            s2x = acc[21, l]
            s2y = acc[22, l]
            s2z = acc[23, l]
            s3x = acc[24, l]
            s3y = acc[25, l]
            s3z = acc[26, l]
            s4x = acc[27, l]
            s4y = acc[28, l]
            s4z = acc[29, l]
            w11 = (s1x * d1x + s1y * d1y + s1z * d1z) * r8
            w12 = (s1x * d2x + s1y * d2y + s1z * d2z) * r8
            w13 = (s1x * d3x + s1y * d3y + s1z * d3z) * r8
            w21 = (s2x * d1x + s2y * d1y + s2z * d1z) * r8
            w22 = (s2x * d2x + s2y * d2y + s2z * d2z) * r8
            w23 = (s2x * d3x + s2y * d3y + s2z * d3z) * r8
            w31 = (s3x * d1x + s3y * d1y + s3z * d1z) * r8
            w32 = (s3x * d2x + s3y * d2y + s3z * d2z) * r8
            w33 = (s3x * d3x + s3y * d3y + s3z * d3z) * r8
            w41 = (s4x * d1x + s4y * d1y + s4z * d1z) * r8
            w42 = (s4x * d2x + s4y * d2y + s4z * d2z) * r8
            w43 = (s4x * d3x + s4y * d3y + s4z * d3z) * r8
            v1x = acc[9, l]
            v1y = acc[10, l]
            v1z = acc[11, l]
            v2x = acc[12, l]
            v2y = acc[13, l]
            v2z = acc[14, l]
            v3x = acc[15, l]
            v3y = acc[16, l]
            v3z = acc[17, l]
            # acc[9:18] are 8 vk (unscaled sums), as needed by q_a = h_a - sum_k w_ak 8 vk
            q1x = acc[30, l] - (w11 * v1x + w12 * v2x + w13 * v3x)
            q1y = acc[31, l] - (w11 * v1y + w12 * v2y + w13 * v3y)
            q1z = acc[32, l] - (w11 * v1z + w12 * v2z + w13 * v3z)
            q2x = acc[33, l] - (w21 * v1x + w22 * v2x + w23 * v3x)
            q2y = acc[34, l] - (w21 * v1y + w22 * v2y + w23 * v3y)
            q2z = acc[35, l] - (w21 * v1z + w22 * v2z + w23 * v3z)
            q3x = acc[36, l] - (w31 * v1x + w32 * v2x + w33 * v3x)
            q3y = acc[37, l] - (w31 * v1y + w32 * v2y + w33 * v3y)
            q3z = acc[38, l] - (w31 * v1z + w32 * v2z + w33 * v3z)
            q4x = acc[39, l] - (w41 * v1x + w42 * v2x + w43 * v3x)
            q4y = acc[40, l] - (w41 * v1y + w42 * v2y + w43 * v3y)
            q4z = acc[41, l] - (w41 * v1z + w42 * v2z + w43 * v3z)
            gsum = (d1x * d1x + d1y * d1y + d1z * d1z + d2x * d2x + d2y * d2y + d2z * d2z
                    + d3x * d3x + d3y * d3y + d3z * d3z)
            gr = max(aux[4, l], hgfloor)
            khg = qhg * mod * vol * gsum / 24.0 * dt * gr
            o0 = hg[e, 0]
            o1 = hg[e, 1]
            o2 = hg[e, 2]
            o3 = hg[e, 3]
            o4 = hg[e, 4]
            o5 = hg[e, 5]
            o6 = hg[e, 6]
            o7 = hg[e, 7]
            o8 = hg[e, 8]
            o9 = hg[e, 9]
            o10 = hg[e, 10]
            o11 = hg[e, 11]
            f1x = o0 + khg * q1x
            f1y = o1 + khg * q1y
            f1z = o2 + khg * q1z
            f2x = o3 + khg * q2x
            f2y = o4 + khg * q2y
            f2z = o5 + khg * q2z
            f3x = o6 + khg * q3x
            f3y = o7 + khg * q3y
            f3z = o8 + khg * q3z
            f4x = o9 + khg * q4x
            f4y = o10 + khg * q4y
            f4z = o11 + khg * q4z
            ew[1, l] = 0.5 * dt * ((o0 + f1x) * q1x + (o1 + f1y) * q1y + (o2 + f1z) * q1z
                                   + (o3 + f2x) * q2x + (o4 + f2y) * q2y + (o5 + f2z) * q2z
                                   + (o6 + f3x) * q3x + (o7 + f3y) * q3y + (o8 + f3z) * q3z
                                   + (o9 + f4x) * q4x + (o10 + f4y) * q4y + (o11 + f4z) * q4z)
            hg[e, 0] = f1x
            hg[e, 1] = f1y
            hg[e, 2] = f1z
            hg[e, 3] = f2x
            hg[e, 4] = f2y
            hg[e, 5] = f2z
            hg[e, 6] = f3x
            hg[e, 7] = f3y
            hg[e, 8] = f3z
            hg[e, 9] = f4x
            hg[e, 10] = f4y
            hg[e, 11] = f4z
            for I in range(8):
                a = SX[I]
                b = SY[I]
                c = SZ[I]
                ga1 = H1[I] - (w11 * a + w12 * b + w13 * c)
                ga2 = H2[I] - (w21 * a + w22 * b + w23 * c)
                ga3 = H3[I] - (w31 * a + w32 * b + w33 * c)
                ga4 = H4[I] - (w41 * a + w42 * b + w43 * c)
                fe[3 * I, l] = -(a * t1x + b * t2x + c * t3x + ga1 * f1x + ga2 * f2x + ga3 * f3x + ga4 * f4x)
                fe[3 * I + 1, l] = -(a * t1y + b * t2y + c * t3y + ga1 * f1y + ga2 * f2y + ga3 * f3y + ga4 * f4y)
                fe[3 * I + 2, l] = -(a * t1z + b * t2z + c * t3z + ga1 * f1z + ga2 * f2z + ga3 * f3z + ga4 * f4z)
        # ---- scatter and reductions (scalar, fixed order)
        for l in range(nb):
            if aux[6, l] != 0.0:
                continue
            nl = n00 + l
            for I in range(8):
                n = nl + offs[I]
                f[n, 0] += fe[3 * I, l]
                f[n, 1] += fe[3 * I + 1, l]
                f[n, 2] += fe[3 * I + 2, l]
            out[0] = min(out[0], aux[5, l])
            out[2] += ew[0, l]
            out[4] += ew[1, l]
            out[5] += ew[2, l]


@jit
def _return_on_trial(sn, l, q, lm, dt, eps_p, temp, mat):
    """Radial return of the trial stress ``sn[:, l]`` (in place); returns
    ``(d_eps_p, sigma_y, g_ratio)`` as :func:`stress_update` does."""
    mu = mat[M_MU]
    theta = thermal_factor(temp, mat)
    deps, sy = radial_return(q, eps_p, dt, theta, mat)
    fr = (q - 3.0 * mu * deps) / q
    p = (sn[0, l] + sn[1, l] + sn[2, l]) / 3.0
    a0 = sn[0, l] - p
    a1 = sn[1, l] - p
    a2 = sn[2, l] - p
    t3 = sn[3, l]
    t4 = sn[4, l]
    t5 = sn[5, l]
    sn[0, l] = p + fr * a0
    sn[1, l] = p + fr * a1
    sn[2, l] = p + fr * a2
    sn[3, l] = fr * t3
    sn[4, l] = fr * t4
    sn[5, l] = fr * t5
    mu2 = 2.0 * mu * dt
    trd = (lm[0, l] + lm[1, l] + lm[2, l]) / 3.0
    e0 = mu2 * (lm[0, l] - trd)
    e1 = mu2 * (lm[1, l] - trd)
    e2 = mu2 * (lm[2, l] - trd)
    e3 = mu2 * lm[3, l]
    e4 = mu2 * lm[4, l]
    e5 = mu2 * lm[5, l]
    den = e0 * e0 + e1 * e1 + e2 * e2 + 2.0 * (e3 * e3 + e4 * e4 + e5 * e5)
    g = 1.0
    if den > 0.0:
        u0 = (fr - 1.0) * a0 + e0
        u1 = (fr - 1.0) * a1 + e1
        u2 = (fr - 1.0) * a2 + e2
        u3 = (fr - 1.0) * t3 + e3
        u4 = (fr - 1.0) * t4 + e4
        u5 = (fr - 1.0) * t5 + e5
        g = min(1.0, math.sqrt((u0 * u0 + u1 * u1 + u2 * u2 + 2.0 * (u3 * u3 + u4 * u4 + u5 * u5)) / den))
    return deps, sy, g


def _rows_pass(x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1, k0, k1):
    """Blocked element pass over the index box (same contract as :func:`element_pass`)."""
    nj = j1 - j0
    nk = k1 - k0
    res = np.zeros((4, 6))
    for colour in range(4):
        cj = colour & 1
        ck = (colour >> 1) & 1
        mj = (nj - cj + 1) // 2
        mk = (nk - ck + 1) // 2
        if mj <= 0 or mk <= 0:
            continue
        nrows = mj * mk
        outs = np.zeros((nrows, 6))
        for r in prange(nrows):
            kk = r // mj
            jj = r - kk * mj
            outs[r, 0] = 1e30
            _row(j0 + cj + 2 * jj, k0 + ck + 2 * kk, i0, i1, nnx, nny, nx, ny, x, v, f, stress, eps_p, sy_static,
                 hg, temp, vol0, mat, dt, outs[r])
        res[colour, 0] = 1e30
        for r in range(nrows):
            res[colour, 0] = min(res[colour, 0], outs[r, 0])
            res[colour, 1] = max(res[colour, 1], outs[r, 1])
            for c in range(2, 6):
                res[colour, c] += outs[r, c]
    dtmin = 1e30
    status = 0
    wi = 0.0
    wp = 0.0
    wh = 0.0
    wv = 0.0
    for colour in range(4):
        if res[colour, 0] < dtmin:
            dtmin = res[colour, 0]
        if res[colour, 1] > status:
            status = int(res[colour, 1])
        wi += res[colour, 2]
        wp += res[colour, 3]
        wh += res[colour, 4]
        wv += res[colour, 5]
    if status != 0:
        dtmin = 0.0
    return dtmin, status, wi, wp, wh, wv


element_rows = jit(_rows_pass)


def _rows_pass_parallel(x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1, k0, k1):
    """:func:`element_rows` compiled with ``parallel=True`` (separate source for numba's cache)."""
    nj = j1 - j0
    nk = k1 - k0
    res = np.zeros((4, 6))
    for colour in range(4):
        cj = colour & 1
        ck = (colour >> 1) & 1
        mj = (nj - cj + 1) // 2
        mk = (nk - ck + 1) // 2
        if mj <= 0 or mk <= 0:
            continue
        nrows = mj * mk
        outs = np.zeros((nrows, 6))
        for r in prange(nrows):
            kk = r // mj
            jj = r - kk * mj
            outs[r, 0] = 1e30
            _row(j0 + cj + 2 * jj, k0 + ck + 2 * kk, i0, i1, nnx, nny, nx, ny, x, v, f, stress, eps_p, sy_static,
                 hg, temp, vol0, mat, dt, outs[r])
        res[colour, 0] = 1e30
        for r in range(nrows):
            res[colour, 0] = min(res[colour, 0], outs[r, 0])
            res[colour, 1] = max(res[colour, 1], outs[r, 1])
            for c in range(2, 6):
                res[colour, c] += outs[r, c]
    dtmin = 1e30
    status = 0
    wi = 0.0
    wp = 0.0
    wh = 0.0
    wv = 0.0
    for colour in range(4):
        if res[colour, 0] < dtmin:
            dtmin = res[colour, 0]
        if res[colour, 1] > status:
            status = int(res[colour, 1])
        wi += res[colour, 2]
        wp += res[colour, 3]
        wh += res[colour, 4]
        wv += res[colour, 5]
    if status != 0:
        dtmin = 0.0
    return dtmin, status, wi, wp, wh, wv


element_rows_parallel = jit(_rows_pass_parallel, parallel=True)
