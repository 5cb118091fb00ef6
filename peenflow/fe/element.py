"""One-point (uniform-strain) hexahedron with hourglass control: Flanagan-Belytschko
stiffness form or physical (assumed-strain) stabilisation.

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
   This is the ``"stiffness"`` form (``mat[M_HG_TYPE] = HG_STIFFNESS``).
5b. Physical form (``"physical"``, assumed-strain stabilisation after
   Belytschko & Bindeman 1993 (ASQBI) and Puso 2000 (for an isotropic box
   the bending and shear terms are those of Puso's enhanced-strain element,
   the xi eta zeta term is his for a cube), no coefficient): the hourglass
   rates are taken to the element frame (Gram-Schmidt of ``g_1, g_2``; the
   stored forces ``F_a`` live in that frame, so a rigid rotation carries
   them along instead of leaving them behind in global axes), and each
   hourglass pattern is given the strain field it represents in a box of
   half lengths ``a_k = |g_k|`` (``b_k = 1 / a_k``). With ``u_ak = q_ak / 8``
   the amplitude of mode ``a`` (xi eta, eta zeta, zeta xi, xi eta zeta) in
   frame component ``k``:

   * bending (normal strains linear across the element): ``e_xx`` from
     (1, x) and ``e_zz`` from (2, z) vary with eta, ``e_xx`` (3, x) and
     ``e_yy`` (2, y) with zeta, ``e_yy`` (1, y) and ``e_zz`` (3, z) with
     xi. The normal strain along the varying direction cannot be
     represented by the trilinear field, so its stress is condensed out
     (it is free, as in a bent beam): plane-stress moduli
     ``C11 = 4 mu (lambda + mu) / (lambda + 2 mu)``, ``C12 = 2 mu lambda /
     (lambda + 2 mu)``, energy ``V/6 e^T C e``. Pure bending of a box is
     then exact for any aspect ratio and Poisson's ratio, and there is no
     volumetric locking (``C`` stays finite as nu -> 1/2);
   * the shear strains that are real (torsion/warping patterns: ``2 e_xz``
     from (1, z) and (2, x), ``2 e_yz`` from (1, z) and (3, y), ``2 e_xy``
     from (2, x) and (3, y)), energy ``V/6 mu gamma^2``; the parasitic
     in-plane shears of the bending patterns (the cause of shear locking)
     are left out, as in the assumed-strain elements;
   * the xi eta zeta mode's normal strain made deviatoric: modulus
     ``4 mu / 3``, energy ``V/18 (4 mu / 3) e^2``.

   Increments ``dF = K q dt`` follow from these energies (``s = dt V /
   192``, :func:`_physical_increments`) with the element's tangent: the
   shear modulus of this step's return ``mu_t = mu g`` (``g`` = actual /
   elastic deviatoric stress increment, 1 when elastic) and the elastic
   bulk modulus (``lambda_t = K - 2 mu_t / 3``). A yielding element thus
   has the hourglass stiffness of the plastic flow it is in, without a
   floor or a coefficient.
6. Stable step of the element: highest frequency bounded by
   ``omega^2 = (2 (Q + sqrt(Q^2 + c^2)) / l)^2 + 32 Q_hg c^2 / l^2`` with
   ``l = V / A_max`` (largest face), ``c`` the dilatational speed at the
   current density and ``Q`` the bulk-viscosity term; ``dt_e = 2 / omega``.
   The physical form replaces ``32 Q_hg`` by its own bound, not below the
   stiffness form's default (:func:`hourglass_omega2_factor`).

Two implementations of the same element (they agree to round-off, see
tests/fe/test_element.py):

* :func:`element_rows` (used by the solver): rows of elements along ``i``,
  processed in blocks of ``BLOCK`` = 8 elements, one element per SIMD lane.
  The block's nodes and element state are copied into one flat scratch
  array (structure of arrays, every quantity at a compile-time offset, so
  LLVM proves the lane loops alias-free), two call- and branch-free lane
  loops compute everything but the plastic return (they compile to packed
  AVX-512 instructions), the Johnson-Cook return runs as a scalar loop over
  the yielding lanes only, and the nodal scatter adds each node's two
  contributions of the block in a fixed order. The 8-corner sums and the
  nodal forces use the tensor-product (Walsh-Hadamard) structure of the
  signs ``xi, eta, zeta, xi eta, ...``: 23 additions per component instead
  of 56 multiply-adds. Rows are coloured by the parity of ``(j, k)`` (4
  colours): rows of one colour share no node, so the scatter is race-free
  under ``prange`` and, each row being done in ``i`` order by one thread,
  the summation order is the same for any thread count (bit-identical
  results on 1 and 2 threads). ~4x faster than the per-element version on
  one thread when elastic (docs/performance.md section 1).
* :func:`peenflow.fe.element_reference.element_pass`: one element at a time
  in 8 colours (parity of ``i, j, k``); the reference implementation, in its
  own module (tests and benchmarks only).

The element's algebra -- face vectors and dual basis, rates, hourglass shape
vectors and per-mode rates, tractions, frame rotations, corner offsets -- is
written once, as ``inline="always"`` helpers below, and both passes call it:
numba inlines them at IR level, so the rows compile to the arithmetic they
had written out (bit-identical: tests/fe/test_driver_golden.py). A helper
takes at most 30 arguments: CPython compiles a longer call as ``f(*args)``,
which numba cannot inline.

Each pass is compiled twice from one source, serial and ``parallel=True``
(``element_rows_parallel``; :func:`peenflow._jit.jit_twins`).

Length: one element and its vectorised pass. About 110 lines are this
docstring (the element's equations); the algebra helpers, which the
per-element reference shares, are ``inline="always"`` pieces of the passes'
loop bodies; and ``_row`` (~360 lines) computes both hourglass forms in one
branch-free lane loop, blended by 0/1 weights, over one scratch layout whose
offsets are defined here.
"""

from __future__ import annotations

import math

from numba import prange

from peenflow._jit import jit, jit_twins
import numpy as np

from peenflow.fe.johnson_cook import (HG_PHYSICAL, M_ADIABATIC, M_BULK_LIN, M_BULK_QUAD, M_HEAT, M_HG, M_HG_FLOOR,
                                      M_HG_TYPE, M_LAM, M_MU, M_RHO, jaumann_trial, plastic_correction,
                                      static_flow_stress, thermal_factor, von_mises)
from peenflow.fe.safety import ST_DISTORTION, ST_NEGATIVE_VOLUME, ST_OK

# local node signs (xi, eta, zeta) and the 4 hourglass base vectors
SX = (-1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0, -1.0)
SY = (-1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0)
SZ = (-1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0)
H1 = (1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0)  # xi eta
H2 = (1.0, 1.0, -1.0, -1.0, -1.0, -1.0, 1.0, 1.0)  # eta zeta
H3 = (1.0, -1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0)  # zeta xi
H4 = (-1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0, -1.0)  # xi eta zeta


@jit(inline="always")
def corner_offsets(nnx, nnxy):
    """Node-index offsets of an element's 8 corners from its first node, in the local
    corner order of :data:`SX` ... :data:`H4` (counter-clockwise bottom face, then top);
    ``nnx`` nodes per row, ``nnxy`` per layer."""
    return (0, 1, 1 + nnx, nnx, nnxy, nnxy + 1, nnxy + 1 + nnx, nnxy + nnx)




@jit(inline="always")
def _element_frame(g1x, g1y, g1z, g2x, g2y, g2z, g3x, g3y, g3z):
    """Co-rotational frame of the element and its inverse half-edge lengths.

    Rows ``e1, e2, e3`` (orthonormal, right-handed): Gram-Schmidt of the
    covariant vectors ``g1, g2`` (half-edge vectors of the mid-step
    configuration); ``b_k = 1 / |g_k|`` (1/m). For a rectangular box the frame
    is the box's axes and ``b_k`` its inverse half lengths.
    """
    a1 = math.sqrt(g1x * g1x + g1y * g1y + g1z * g1z)
    i1 = 1.0 / a1
    e11 = g1x * i1
    e12 = g1y * i1
    e13 = g1z * i1
    t = g2x * e11 + g2y * e12 + g2z * e13
    ux = g2x - t * e11
    uy = g2y - t * e12
    uz = g2z - t * e13
    iu = 1.0 / math.sqrt(ux * ux + uy * uy + uz * uz)
    e21 = ux * iu
    e22 = uy * iu
    e23 = uz * iu
    e31 = e12 * e23 - e13 * e22
    e32 = e13 * e21 - e11 * e23
    e33 = e11 * e22 - e12 * e21
    b1 = i1
    b2 = 1.0 / math.sqrt(g2x * g2x + g2y * g2y + g2z * g2z)
    b3 = 1.0 / math.sqrt(g3x * g3x + g3y * g3y + g3z * g3z)
    return e11, e12, e13, e21, e22, e23, e31, e32, e33, b1, b2, b3


@jit(inline="always")
def _physical_increments(p1x, p1y, p1z, p2x, p2y, p2z, p3x, p3y, p3z, p4x, p4y, p4z, b1, b2, b3, mu_t, bulk, s):
    """Increments of the 12 hourglass forces (element frame) of the assumed-strain stabilisation.

    ``p_a``: hourglass rates ``sum_I gamma_a,I v_I`` (m/s) in the element
    frame, modes a = 1..4 = (xi eta, eta zeta, zeta xi, xi eta zeta);
    ``b_k`` inverse half lengths (1/m); ``mu_t`` tangent shear modulus and
    ``bulk`` bulk modulus (Pa); ``s = dt V / 192`` (s m^3). Returns the force
    increments (N), same order. Derivation in the module docstring.
    """
    lt = bulk - 2.0 * mu_t / 3.0
    den = 1.0 / (lt + 2.0 * mu_t)
    c11 = 4.0 * mu_t * (lt + mu_t) * den  # plane-stress moduli, the bending strain's own direction free
    c12 = 2.0 * mu_t * lt * den
    # bending: normal strains linear in eta (xx from mode 1 x, zz from mode 2 z), zeta (xx: 3x, yy: 2y), xi (yy: 1y, zz: 3z)
    a = p1x * b1
    c = p2z * b3
    d1x = s * b1 * (c11 * a + c12 * c)
    d2z = s * b3 * (c12 * a + c11 * c)
    a = p3x * b1
    c = p2y * b2
    d3x = s * b1 * (c11 * a + c12 * c)
    d2y = s * b2 * (c12 * a + c11 * c)
    a = p1y * b2
    c = p3z * b3
    d1y = s * b2 * (c11 * a + c12 * c)
    d3z = s * b3 * (c12 * a + c11 * c)
    # shear strains the modes represent (torsion, warping): 2 e_xz ~ eta, 2 e_yz ~ xi, 2 e_xy ~ zeta
    ga = p1z * b1 + p2x * b3
    gb = p1z * b2 + p3y * b3
    gc = p2x * b2 + p3y * b1
    sm = s * mu_t
    d1z = sm * (b1 * ga + b2 * gb)
    d2x = sm * (b3 * ga + b2 * gc)
    d3y = sm * (b3 * gb + b1 * gc)
    # xi eta zeta mode: its normal strain made deviatoric (modulus 4 mu / 3)
    s4 = sm * (4.0 / 9.0)
    d4x = s4 * b1 * b1 * p4x
    d4y = s4 * b2 * b2 * p4y
    d4z = s4 * b3 * b3 * p4z
    return d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z, d4x, d4y, d4z


# ---- the element's algebra, shared by the vectorised rows and the reference element
# (inlined at numba IR level, so both compile to the same arithmetic they had written out)


@jit(inline="always")
def _rotate(r11, r12, r13, r21, r22, r23, r31, r32, r33, x, y, z):
    """``R (x, y, z)`` for the 3 x 3 matrix of rows ``r1, r2, r3``."""
    return r11 * x + r12 * y + r13 * z, r21 * x + r22 * y + r23 * z, r31 * x + r32 * y + r33 * z


@jit(inline="always")
def _face_vectors(g1x, g1y, g1z, g2x, g2y, g2z, g3x, g3y, g3z):
    """``c_k = g_l x g_m`` (cyclic; a quarter of the face-area vectors, m^2) and
    ``det = g_1 . c_1`` (V / 8, m^3) of the covariant half-edge vectors ``g_k``."""
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
    return c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, det


@jit(inline="always")
def _scaled9(s, a1, a2, a3, a4, a5, a6, a7, a8, a9):
    """Nine values times ``s`` (the dual vectors ``g^k = c_k / det``; the 1/8 of the corner sums)."""
    return a1 * s, a2 * s, a3 * s, a4 * s, a5 * s, a6 * s, a7 * s, a8 * s, a9 * s


@jit(inline="always")
def _rates(v1x, v1y, v1z, v2x, v2y, v2z, v3x, v3y, v3z, d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z):
    """Velocity gradient ``L_ab = sum_k v^k_a g^k_b`` (1/s) of the mean corner-velocity
    differences ``v_k`` and the dual vectors ``g^k``: returns its diagonal
    ``lxx, lyy, lzz``, the strain rates ``dyz, dxz, dxy`` and spins ``wyz, wxz, wxy``."""
    lxx = v1x * d1x + v2x * d2x + v3x * d3x
    lxy = v1x * d1y + v2x * d2y + v3x * d3y
    lxz = v1x * d1z + v2x * d2z + v3x * d3z
    lyx = v1y * d1x + v2y * d2x + v3y * d3x
    lyy = v1y * d1y + v2y * d2y + v3y * d3y
    lyz = v1y * d1z + v2y * d2z + v3y * d3z
    lzx = v1z * d1x + v2z * d2x + v3z * d3x
    lzy = v1z * d1y + v2z * d2y + v3z * d3y
    lzz = v1z * d1z + v2z * d2z + v3z * d3z
    return (lxx, lyy, lzz, 0.5 * (lyz + lzy), 0.5 * (lxz + lzx), 0.5 * (lxy + lyx),
            0.5 * (lyz - lzy), 0.5 * (lxz - lzx), 0.5 * (lxy - lyx))


@jit(inline="always")
def _dot3(ax, ay, az, bx, by, bz, s):
    return (ax * bx + ay * by + az * bz) * s


@jit(inline="always")
def _hourglass_shape(s1x, s1y, s1z, s2x, s2y, s2z, s3x, s3y, s3z, s4x, s4y, s4z,
                     d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z):
    """``w_ak = (s_a . g^k) / 8`` of the Flanagan-Belytschko hourglass shape vectors
    ``gamma_a = H_a - sum_k w_ak xi_k`` (``s_a = sum_I H_a,I x_I``), a = 1..4, k = 1..3."""
    r8 = 0.125
    return (_dot3(s1x, s1y, s1z, d1x, d1y, d1z, r8), _dot3(s1x, s1y, s1z, d2x, d2y, d2z, r8),
            _dot3(s1x, s1y, s1z, d3x, d3y, d3z, r8), _dot3(s2x, s2y, s2z, d1x, d1y, d1z, r8),
            _dot3(s2x, s2y, s2z, d2x, d2y, d2z, r8), _dot3(s2x, s2y, s2z, d3x, d3y, d3z, r8),
            _dot3(s3x, s3y, s3z, d1x, d1y, d1z, r8), _dot3(s3x, s3y, s3z, d2x, d2y, d2z, r8),
            _dot3(s3x, s3y, s3z, d3x, d3y, d3z, r8), _dot3(s4x, s4y, s4z, d1x, d1y, d1z, r8),
            _dot3(s4x, s4y, s4z, d2x, d2y, d2z, r8), _dot3(s4x, s4y, s4z, d3x, d3y, d3z, r8))


@jit(inline="always")
def _mode_rate(hx, hy, hz, wa1, wa2, wa3, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z):
    """Hourglass rate ``q_a = sum_I gamma_a,I v_I = h_a - sum_k w_ak V_k`` (m/s) of one mode a
    from its velocity sum ``h_a = sum_I H_a,I v_I``, its ``w_ak`` and ``V_k = sum_I sign_k,I v_I``
    (= 8 v_k). (Per mode: a call of more than 30 arguments is compiled as ``f(*args)``,
    which numba cannot inline.)"""
    return (hx - (wa1 * V1x + wa2 * V2x + wa3 * V3x), hy - (wa1 * V1y + wa2 * V2y + wa3 * V3y),
            hz - (wa1 * V1z + wa2 * V2z + wa3 * V3z))


@jit(inline="always")
def _tractions(s0, s1, s2, s3, s4, s5, qb, vol, d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z):
    """``t_k = V (sigma - q I) g^k / 8`` (N) of the stress ``s0..s5`` (Voigt, Pa), the bulk
    viscosity pressure ``qb`` (Pa) and the volume ``vol`` (m^3)."""
    r8 = 0.125
    sxx = (s0 - qb) * vol
    syy = (s1 - qb) * vol
    szz = (s2 - qb) * vol
    syz = s3 * vol
    sxz = s4 * vol
    sxy = s5 * vol
    return (_dot3(sxx, sxy, sxz, d1x, d1y, d1z, r8), _dot3(sxy, syy, syz, d1x, d1y, d1z, r8),
            _dot3(sxz, syz, szz, d1x, d1y, d1z, r8), _dot3(sxx, sxy, sxz, d2x, d2y, d2z, r8),
            _dot3(sxy, syy, syz, d2x, d2y, d2z, r8), _dot3(sxz, syz, szz, d2x, d2y, d2z, r8),
            _dot3(sxx, sxy, sxz, d3x, d3y, d3z, r8), _dot3(sxy, syy, syz, d3x, d3y, d3z, r8),
            _dot3(sxz, syz, szz, d3x, d3y, d3z, r8))


#: hourglass term of the stable step (x c^2 / l^2) the kernel's stability was measured with: 32 x 0.05
HG_STEP_TERM = 1.6


@jit(inline="always")
def hourglass_omega2_factor(mat):
    """Highest hourglass frequency as ``omega^2 = factor c^2 / l^2`` (c dilatational speed, l = V / A_max).

    Stiffness form: ``32 Q_hg``. Physical form: the bound of its elastic mode
    stiffnesses over the lumped mass (``l / 2`` = smallest half length),
    ``4 max(2 mu (3 lambda + 2 mu) / (3 (lambda + 2 mu)), 4 mu / 3) / (lambda + 2 mu)``,
    but not below :data:`HG_STEP_TERM`. The physical modes lie below the
    element's volumetric mode (tests/fe/test_hourglass.py), so the step is set
    by the uniform-strain estimate ``2 c / l``, which a free element's volumetric
    mode exceeds (omega dt = 2.7 for a cube); the kernel's safety margin was
    measured with the stiffness form's default term (docs/validation.md
    section 8, "The sweep": 135 cases at 25-400 m/s), so the physical form
    keeps at least that term and the same step.
    """
    lam = mat[M_LAM]
    mu = mat[M_MU]
    mod = lam + 2.0 * mu
    phys = max(4.0 * max(2.0 * mu * (3.0 * lam + 2.0 * mu) / (3.0 * mod), 4.0 * mu / 3.0) / mod, HG_STEP_TERM)
    return phys if mat[M_HG_TYPE] == HG_PHYSICAL else 32.0 * mat[M_HG]


# ---------------------------------------------------------------------------
# Blocked variant: the same element, BLOCK consecutive elements of a row at a
# time, one per SIMD lane (see the module docstring). Rows are coloured by
# (j, k) parity (4 colours): rows of one colour share no node, each row is
# done by one thread in i order, so the summation order is fixed for any
# thread count.
# ---------------------------------------------------------------------------

BLOCK = 8

# Lane scratch of _row: one flat float64 array per row, every quantity a slot
# of BLOCK consecutive values (one per lane), slot offsets compile-time
# constants. One base pointer and constant offsets let LLVM prove the lane
# loops free of aliasing (no runtime checks) and vectorise them.
_NDS = BLOCK + 8  # slot length of node data (B + 1 nodes per row, padded)
# node data: 4 node rows (j,k) (j+1,k) (j,k+1) (j+1,k+1) x (px py pz vx vy vz) x B+1 nodes
_ND = 0
_RS = 6 * _NDS  # row stride of node data
# nodal forces, low (i) and high (i+1) corner of each lane: 4 rows x 3 components;
# node m of a row gets FLO[m] + FHI[m] (FLO[B] = FHI[0] = 0)
_FLO = _ND + 4 * _RS
_FHI = _FLO + 12 * _NDS
_L0 = _FHI + 12 * _NDS
# per-lane slots (index * BLOCK after _L0)
_OLD = 0  # 6: stress at the start of the step
_HG = 6  # 12: hourglass forces (old, then new)
_VOL0 = 18
_SN = 19  # 6: trial, then new stress
_LM = 25  # 6: lxx lyy lzz dyz dxz dxy
_VOL = 31
_QB = 32  # bulk-viscosity pressure
_STC = 33  # status code
_QTR = 34  # von Mises of the trial stress
_GR = 35  # hourglass stiffness ratio
_KHG = 36  # elastic hourglass stiffness x dt
_DTE = 37
_EWV = 38  # viscous work
_DUAL = 39  # 9: g^1 g^2 g^3
_WAK = 48  # 12: w_ak
_QA = 60  # 12: hourglass rates q_a
_EWI = 72  # internal work
_EWH = 73  # hourglass work
_FRM = 74  # 9: element frame rows e1 e2 e3 (physical hourglass; identity for the stiffness form)
_BK = 83  # 3: inverse half lengths 1/|g_k|
_NLANE = 86
_NSCR = _L0 + _NLANE * BLOCK


@jit(inline="always")
def _corner_sums(w, o, l):
    """Sums of one nodal component over the element's 8 corners weighted by
    xi, eta, zeta and the hourglass vectors H1..H4 (a Walsh-Hadamard transform
    in tensor form: 23 additions instead of 56 multiply-adds). ``o``: offset
    of the component's slot in row 0 of the node data; lane ``l`` has its low
    corners at node ``l`` and high corners at ``l + 1`` of each row."""
    s0 = w[o + l + 1] + w[o + l]
    d0 = w[o + l + 1] - w[o + l]
    s1 = w[o + _RS + l + 1] + w[o + _RS + l]
    d1 = w[o + _RS + l + 1] - w[o + _RS + l]
    s2 = w[o + 2 * _RS + l + 1] + w[o + 2 * _RS + l]
    d2 = w[o + 2 * _RS + l + 1] - w[o + 2 * _RS + l]
    s3 = w[o + 3 * _RS + l + 1] + w[o + 3 * _RS + l]
    d3 = w[o + 3 * _RS + l + 1] - w[o + 3 * _RS + l]
    sa = s1 + s0
    sd = s1 - s0
    sb = s3 + s2
    se = s3 - s2
    da = d1 + d0
    dd = d1 - d0
    db = d3 + d2
    de = d3 - d2
    # xi, eta, zeta, xi eta (H1), eta zeta (H2), zeta xi (H3), xi eta zeta (H4)
    return da + db, sd + se, sb - sa, dd + de, se - sd, db - da, de - dd


@jit(inline="always")
def _corner_forces(w, o, l, ok, X, Y, Z, P, Q, R, S):
    """Inverse of :func:`_corner_sums`: store ``-(X xi + Y eta + Z zeta + P xi eta
    + Q eta zeta + R zeta xi + S xi eta zeta)`` at the 8 corners of lane ``l``
    (component slot ``o`` of the force scratch; zero where ``ok`` is false)."""
    xp = X + P
    xm = X - P
    rp = R + S
    rm = R - S
    u0 = xm - rm  # row (eta-, zeta-)
    u1 = xp - rp  # (eta+, zeta-)
    u2 = xm + rm  # (eta-, zeta+)
    u3 = xp + rp  # (eta+, zeta+)
    yp = Y + Q
    ym = Y - Q
    c0 = ym + Z  # minus the xi-free part of each row
    c1 = Z - ym
    c2 = yp - Z
    c3 = -(yp + Z)
    w[_FLO + o + l] = u0 + c0 if ok else 0.0
    w[_FHI + o + l + 1] = c0 - u0 if ok else 0.0
    w[_FLO + o + 3 * _NDS + l] = u1 + c1 if ok else 0.0
    w[_FHI + o + 3 * _NDS + l + 1] = c1 - u1 if ok else 0.0
    w[_FLO + o + 6 * _NDS + l] = u2 + c2 if ok else 0.0
    w[_FHI + o + 6 * _NDS + l + 1] = c2 - u2 if ok else 0.0
    w[_FLO + o + 9 * _NDS + l] = u3 + c3 if ok else 0.0
    w[_FHI + o + 9 * _NDS + l + 1] = c3 - u3 if ok else 0.0


@jit
def _row(j, k, i0, i1, nnx, nny, nx, ny, x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt, out):
    """Elements ``i0 <= i < i1`` of row ``(j, k)``; ``out`` (6,) accumulates
    ``dt_min, status, dW_int, dW_plastic, dW_hourglass, dW_viscous``.

    Per block of ``BLOCK`` elements: gather nodes and element state into the
    lane scratch (scalar copies), two vectorised lane loops (kinematics and
    trial stress; forces) around a scalar plastic return of the yielding
    lanes only, then write back and scatter in a fixed order. Lanes past the
    end of the row compute a copy of the last element and are discarded.
    """
    B = BLOCK
    nnxy = nnx * nny
    hdt = 0.5 * dt
    r8 = 0.125
    # every slot is written before it is read (checked by filling it with NaN),
    # except the force slots FLO[B] and FHI[0] zeroed here: no memset per row
    w = np.empty(_NSCR)
    for c in range(12):  # node m = B has no low corner, node 0 of the block no high corner in it
        w[_FLO + c * _NDS + B] = 0.0
        w[_FHI + c * _NDS] = 0.0
    mod = mat[M_LAM] + 2.0 * mat[M_MU]
    lam = mat[M_LAM]
    mu = mat[M_MU]
    rho0 = mat[M_RHO]
    qlin = mat[M_BULK_LIN]
    qquad = mat[M_BULK_QUAD]
    qhg = mat[M_HG]
    hgfloor = mat[M_HG_FLOOR]
    khgc = qhg * mod
    hgom = hourglass_omega2_factor(mat)
    # hourglass form as 0/1 weights (loop invariant; the lane loops blend
    # instead of branching, and with weight 0 the other form's terms add
    # exact zeros, so the stiffness form is bit-identical to its old code)
    wph = 1.0 if mat[M_HG_TYPE] == HG_PHYSICAL else 0.0
    wfb = 1.0 - wph
    bulk = lam + 2.0 * mu / 3.0
    ebase = nx * (j + ny * k)
    nbase = nnx * (j + nny * k)
    for ib in range(i0, i1, B):
        nb = min(B, i1 - ib)
        e0 = ebase + ib
        n00 = nbase + ib
        # ---- gather nodes (mid-step positions, velocities) of the 4 node rows
        for r in range(4):
            nr = n00 + (r & 1) * nnx + (r >> 1) * nnxy
            o = _ND + r * _RS
            for m in range(nb + 1):
                n = nr + m
                vx = v[n, 0]
                vy = v[n, 1]
                vz = v[n, 2]
                w[o + m] = x[n, 0] - hdt * vx
                w[o + _NDS + m] = x[n, 1] - hdt * vy
                w[o + 2 * _NDS + m] = x[n, 2] - hdt * vz
                w[o + 3 * _NDS + m] = vx
                w[o + 4 * _NDS + m] = vy
                w[o + 5 * _NDS + m] = vz
            if nb < B:  # pad: translated copies of the last element
                for c in range(6):
                    oc = o + c * _NDS
                    step = w[oc + nb] - w[oc + nb - 1]
                    for m in range(nb + 1, B + 1):
                        w[oc + m] = w[oc + m - 1] + step
        # ---- gather element state
        for l in range(B):
            e = e0 + min(l, nb - 1)
            for c in range(6):
                w[_L0 + (_OLD + c) * B + l] = stress[e, c]
            for c in range(12):
                w[_L0 + (_HG + c) * B + l] = hg[e, c]
            w[_L0 + _VOL0 * B + l] = vol0[e]
        # ---- pass 1 (vectorised): geometry, rates, trial stress, step, viscosity, hourglass kinematics
        for l in range(B):
            gx1, gx2, gx3, s1x, s2x, s3x, s4x = _corner_sums(w, _ND, l)
            gy1, gy2, gy3, s1y, s2y, s3y, s4y = _corner_sums(w, _ND + _NDS, l)
            gz1, gz2, gz3, s1z, s2z, s3z, s4z = _corner_sums(w, _ND + 2 * _NDS, l)
            # V_k = 8 v_k (unscaled sums) and the hourglass velocity sums h_a
            V1x, V2x, V3x, h1x, h2x, h3x, h4x = _corner_sums(w, _ND + 3 * _NDS, l)
            V1y, V2y, V3y, h1y, h2y, h3y, h4y = _corner_sums(w, _ND + 4 * _NDS, l)
            V1z, V2z, V3z, h1z, h2z, h3z, h4z = _corner_sums(w, _ND + 5 * _NDS, l)
            g1x, g1y, g1z, g2x, g2y, g2z, g3x, g3y, g3z = _scaled9(r8, gx1, gy1, gz1, gx2, gy2, gz2, gx3, gy3, gz3)
            v1x, v1y, v1z, v2x, v2y, v2z, v3x, v3y, v3z = _scaled9(r8, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
            c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z, det = _face_vectors(g1x, g1y, g1z, g2x, g2y, g2z, g3x, g3y, g3z)
            vol = 8.0 * det
            v0 = w[_L0 + _VOL0 * B + l]
            ratio = vol / v0
            stc = float(ST_OK)
            stc = float(ST_DISTORTION) if (ratio < 0.1) | (ratio > 10.0) else stc
            stc = stc if det > 0.0 else float(ST_NEGATIVE_VOLUME)
            d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z = _scaled9(1.0 / det, c1x, c1y, c1z, c2x, c2y, c2z, c3x, c3y, c3z)
            lxx, lyy, lzz, dyz, dxz, dxy, wyz, wxz, wxy = _rates(v1x, v1y, v1z, v2x, v2y, v2z, v3x, v3y, v3z,
                                                                 d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z)
            t0, t1, t2, t3, t4, t5 = jaumann_trial(
                w[_L0 + _OLD * B + l], w[_L0 + (_OLD + 1) * B + l], w[_L0 + (_OLD + 2) * B + l],
                w[_L0 + (_OLD + 3) * B + l], w[_L0 + (_OLD + 4) * B + l], w[_L0 + (_OLD + 5) * B + l],
                lxx, lyy, lzz, dyz, dxz, dxy, wyz, wxz, wxy, dt, lam, mu)
            w[_L0 + _SN * B + l] = t0
            w[_L0 + (_SN + 1) * B + l] = t1
            w[_L0 + (_SN + 2) * B + l] = t2
            w[_L0 + (_SN + 3) * B + l] = t3
            w[_L0 + (_SN + 4) * B + l] = t4
            w[_L0 + (_SN + 5) * B + l] = t5
            w[_L0 + _QTR * B + l] = von_mises(t0, t1, t2, t3, t4, t5)
            w[_L0 + _LM * B + l] = lxx
            w[_L0 + (_LM + 1) * B + l] = lyy
            w[_L0 + (_LM + 2) * B + l] = lzz
            w[_L0 + (_LM + 3) * B + l] = dyz
            w[_L0 + (_LM + 4) * B + l] = dxz
            w[_L0 + (_LM + 5) * B + l] = dxy
            w[_L0 + _STC * B + l] = stc
            w[_L0 + _GR * B + l] = 1.0
            w[_L0 + _VOL * B + l] = vol
            w[_L0 + _DUAL * B + l] = d1x
            w[_L0 + (_DUAL + 1) * B + l] = d1y
            w[_L0 + (_DUAL + 2) * B + l] = d1z
            w[_L0 + (_DUAL + 3) * B + l] = d2x
            w[_L0 + (_DUAL + 4) * B + l] = d2y
            w[_L0 + (_DUAL + 5) * B + l] = d2z
            w[_L0 + (_DUAL + 6) * B + l] = d3x
            w[_L0 + (_DUAL + 7) * B + l] = d3y
            w[_L0 + (_DUAL + 8) * B + l] = d3z
            # wave speed, characteristic length (V / largest face), bulk viscosity, stable step
            amax = max(c1x * c1x + c1y * c1y + c1z * c1z, c2x * c2x + c2y * c2y + c2z * c2z)
            amax = max(amax, c3x * c3x + c3y * c3y + c3z * c3z)
            lch = 2.0 * det / math.sqrt(amax)
            rho = rho0 * v0 / vol
            c2 = mod / rho
            cw = math.sqrt(c2)
            ev = lxx + lyy + lzz
            comp = ev < 0.0
            qv = qlin * cw - qquad * lch * ev if comp else 0.0
            qb = -rho * lch * qv * ev if comp else 0.0
            w[_L0 + _QB * B + l] = qb
            w[_L0 + _EWV * B + l] = -qb * ev * vol * dt
            om = 2.0 * (qv + math.sqrt(qv * qv + c2)) / lch
            w[_L0 + _DTE * B + l] = 2.0 / math.sqrt(om * om + hgom * c2 / (lch * lch))
            # element frame (physical hourglass) blended with the identity (stiffness form)
            e11, e12, e13, e21, e22, e23, e31, e32, e33, b1, b2, b3 = _element_frame(
                g1x, g1y, g1z, g2x, g2y, g2z, g3x, g3y, g3z)
            w[_L0 + _FRM * B + l] = wph * e11 + wfb
            w[_L0 + (_FRM + 1) * B + l] = wph * e12
            w[_L0 + (_FRM + 2) * B + l] = wph * e13
            w[_L0 + (_FRM + 3) * B + l] = wph * e21
            w[_L0 + (_FRM + 4) * B + l] = wph * e22 + wfb
            w[_L0 + (_FRM + 5) * B + l] = wph * e23
            w[_L0 + (_FRM + 6) * B + l] = wph * e31
            w[_L0 + (_FRM + 7) * B + l] = wph * e32
            w[_L0 + (_FRM + 8) * B + l] = wph * e33 + wfb
            w[_L0 + _BK * B + l] = b1
            w[_L0 + (_BK + 1) * B + l] = b2
            w[_L0 + (_BK + 2) * B + l] = b3
            # hourglass: w_ak = (s_a . g^k)/8, q_a = h_a - sum_k w_ak V_k
            w11, w12, w13, w21, w22, w23, w31, w32, w33, w41, w42, w43 = _hourglass_shape(
                s1x, s1y, s1z, s2x, s2y, s2z, s3x, s3y, s3z, s4x, s4y, s4z, d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z)
            w[_L0 + _WAK * B + l] = w11
            w[_L0 + (_WAK + 1) * B + l] = w12
            w[_L0 + (_WAK + 2) * B + l] = w13
            w[_L0 + (_WAK + 3) * B + l] = w21
            w[_L0 + (_WAK + 4) * B + l] = w22
            w[_L0 + (_WAK + 5) * B + l] = w23
            w[_L0 + (_WAK + 6) * B + l] = w31
            w[_L0 + (_WAK + 7) * B + l] = w32
            w[_L0 + (_WAK + 8) * B + l] = w33
            w[_L0 + (_WAK + 9) * B + l] = w41
            w[_L0 + (_WAK + 10) * B + l] = w42
            w[_L0 + (_WAK + 11) * B + l] = w43
            qa = (_mode_rate(h1x, h1y, h1z, w11, w12, w13, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
                  + _mode_rate(h2x, h2y, h2z, w21, w22, w23, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
                  + _mode_rate(h3x, h3y, h3z, w31, w32, w33, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z)
                  + _mode_rate(h4x, h4y, h4z, w41, w42, w43, V1x, V1y, V1z, V2x, V2y, V2z, V3x, V3y, V3z))
            for c in range(12):
                w[_L0 + (_QA + c) * B + l] = qa[c]
            gsum = (d1x * d1x + d1y * d1y + d1z * d1z + d2x * d2x + d2y * d2y + d2z * d2z
                    + d3x * d3x + d3y * d3y + d3z * d3z)
            w[_L0 + _KHG * B + l] = khgc * vol * gsum / 24.0 * dt
        # ---- plastic return (scalar, yielding lanes only)
        if dt > 0.0:
            for l in range(nb):
                e = e0 + l
                q = w[_L0 + _QTR * B + l]
                if q > sy_static[e] and w[_L0 + _STC * B + l] == 0.0:
                    o = _L0 + _SN * B + l
                    ol = _L0 + _LM * B + l
                    n0_, n1_, n2_, n3_, n4_, n5_, deps, sy, gr, sy_new = plastic_correction(
                        w[o], w[o + B], w[o + 2 * B], w[o + 3 * B], w[o + 4 * B], w[o + 5 * B], q,
                        w[ol], w[ol + B], w[ol + 2 * B], w[ol + 3 * B], w[ol + 4 * B], w[ol + 5 * B],
                        dt, eps_p[e], temp[e], mat)
                    w[o] = n0_
                    w[o + B] = n1_
                    w[o + 2 * B] = n2_
                    w[o + 3 * B] = n3_
                    w[o + 4 * B] = n4_
                    w[o + 5 * B] = n5_
                    w[_L0 + _GR * B + l] = gr
                    if deps > 0.0:
                        ep = eps_p[e] + deps
                        eps_p[e] = ep
                        out[3] += sy * deps * w[_L0 + _VOL * B + l]
                        if mat[M_ADIABATIC] != 0.0:
                            temp[e] += mat[M_HEAT] * sy * deps
                            sy_new = static_flow_stress(ep, thermal_factor(temp[e], mat), mat)
                        sy_static[e] = sy_new
        # ---- pass 2 (vectorised): stress power, nodal forces, hourglass forces
        for l in range(B):
            ok = (l < nb) & (w[_L0 + _STC * B + l] == 0.0)
            vol = w[_L0 + _VOL * B + l]
            qb = w[_L0 + _QB * B + l]
            n0_ = w[_L0 + _SN * B + l]
            n1_ = w[_L0 + (_SN + 1) * B + l]
            n2_ = w[_L0 + (_SN + 2) * B + l]
            n3_ = w[_L0 + (_SN + 3) * B + l]
            n4_ = w[_L0 + (_SN + 4) * B + l]
            n5_ = w[_L0 + (_SN + 5) * B + l]
            w[_L0 + _EWI * B + l] = 0.5 * dt * vol * (
                (w[_L0 + _OLD * B + l] + n0_) * w[_L0 + _LM * B + l]
                + (w[_L0 + (_OLD + 1) * B + l] + n1_) * w[_L0 + (_LM + 1) * B + l]
                + (w[_L0 + (_OLD + 2) * B + l] + n2_) * w[_L0 + (_LM + 2) * B + l]
                + 2.0 * ((w[_L0 + (_OLD + 3) * B + l] + n3_) * w[_L0 + (_LM + 3) * B + l]
                         + (w[_L0 + (_OLD + 4) * B + l] + n4_) * w[_L0 + (_LM + 4) * B + l]
                         + (w[_L0 + (_OLD + 5) * B + l] + n5_) * w[_L0 + (_LM + 5) * B + l]))
            d1x = w[_L0 + _DUAL * B + l]
            d1y = w[_L0 + (_DUAL + 1) * B + l]
            d1z = w[_L0 + (_DUAL + 2) * B + l]
            d2x = w[_L0 + (_DUAL + 3) * B + l]
            d2y = w[_L0 + (_DUAL + 4) * B + l]
            d2z = w[_L0 + (_DUAL + 5) * B + l]
            d3x = w[_L0 + (_DUAL + 6) * B + l]
            d3y = w[_L0 + (_DUAL + 7) * B + l]
            d3z = w[_L0 + (_DUAL + 8) * B + l]
            # t_k = V (sigma - q I) g^k / 8
            t1x, t1y, t1z, t2x, t2y, t2z, t3x, t3y, t3z = _tractions(
                n0_, n1_, n2_, n3_, n4_, n5_, qb, vol, d1x, d1y, d1z, d2x, d2y, d2z, d3x, d3y, d3z)
            # hourglass forces. Stiffness form: F_a += k_hg q_a dt, k_hg following the
            # element's deviatoric tangent (not below the floor). Physical form:
            # rates to the element frame, increments from the assumed-strain
            # stiffness at the tangent shear modulus, forces kept in the frame.
            gr = w[_L0 + _GR * B + l]
            khg = w[_L0 + _KHG * B + l] * max(gr, hgfloor) * wfb
            r11 = w[_L0 + _FRM * B + l]
            r12 = w[_L0 + (_FRM + 1) * B + l]
            r13 = w[_L0 + (_FRM + 2) * B + l]
            r21 = w[_L0 + (_FRM + 3) * B + l]
            r22 = w[_L0 + (_FRM + 4) * B + l]
            r23 = w[_L0 + (_FRM + 5) * B + l]
            r31 = w[_L0 + (_FRM + 6) * B + l]
            r32 = w[_L0 + (_FRM + 7) * B + l]
            r33 = w[_L0 + (_FRM + 8) * B + l]
            o0 = w[_L0 + _HG * B + l]
            o1 = w[_L0 + (_HG + 1) * B + l]
            o2 = w[_L0 + (_HG + 2) * B + l]
            o3 = w[_L0 + (_HG + 3) * B + l]
            o4 = w[_L0 + (_HG + 4) * B + l]
            o5 = w[_L0 + (_HG + 5) * B + l]
            o6 = w[_L0 + (_HG + 6) * B + l]
            o7 = w[_L0 + (_HG + 7) * B + l]
            o8 = w[_L0 + (_HG + 8) * B + l]
            o9 = w[_L0 + (_HG + 9) * B + l]
            o10 = w[_L0 + (_HG + 10) * B + l]
            o11 = w[_L0 + (_HG + 11) * B + l]
            g1x_ = w[_L0 + _QA * B + l]
            g1y_ = w[_L0 + (_QA + 1) * B + l]
            g1z_ = w[_L0 + (_QA + 2) * B + l]
            g2x_ = w[_L0 + (_QA + 3) * B + l]
            g2y_ = w[_L0 + (_QA + 4) * B + l]
            g2z_ = w[_L0 + (_QA + 5) * B + l]
            g3x_ = w[_L0 + (_QA + 6) * B + l]
            g3y_ = w[_L0 + (_QA + 7) * B + l]
            g3z_ = w[_L0 + (_QA + 8) * B + l]
            g4x_ = w[_L0 + (_QA + 9) * B + l]
            g4y_ = w[_L0 + (_QA + 10) * B + l]
            g4z_ = w[_L0 + (_QA + 11) * B + l]
            q1x, q1y, q1z = _rotate(r11, r12, r13, r21, r22, r23, r31, r32, r33, g1x_, g1y_, g1z_)
            q2x, q2y, q2z = _rotate(r11, r12, r13, r21, r22, r23, r31, r32, r33, g2x_, g2y_, g2z_)
            q3x, q3y, q3z = _rotate(r11, r12, r13, r21, r22, r23, r31, r32, r33, g3x_, g3y_, g3z_)
            q4x, q4y, q4z = _rotate(r11, r12, r13, r21, r22, r23, r31, r32, r33, g4x_, g4y_, g4z_)
            k1x, k1y, k1z, k2x, k2y, k2z, k3x, k3y, k3z, k4x, k4y, k4z = _physical_increments(
                q1x, q1y, q1z, q2x, q2y, q2z, q3x, q3y, q3z, q4x, q4y, q4z,
                w[_L0 + _BK * B + l], w[_L0 + (_BK + 1) * B + l], w[_L0 + (_BK + 2) * B + l],
                mu * gr, bulk, dt * vol / 192.0 * wph)
            f1x = o0 + (khg * q1x + k1x)
            f1y = o1 + (khg * q1y + k1y)
            f1z = o2 + (khg * q1z + k1z)
            f2x = o3 + (khg * q2x + k2x)
            f2y = o4 + (khg * q2y + k2y)
            f2z = o5 + (khg * q2z + k2z)
            f3x = o6 + (khg * q3x + k3x)
            f3y = o7 + (khg * q3y + k3y)
            f3z = o8 + (khg * q3z + k3z)
            f4x = o9 + (khg * q4x + k4x)
            f4y = o10 + (khg * q4y + k4y)
            f4z = o11 + (khg * q4z + k4z)
            w[_L0 + _EWH * B + l] = 0.5 * dt * ((o0 + f1x) * q1x + (o1 + f1y) * q1y + (o2 + f1z) * q1z
                                                + (o3 + f2x) * q2x + (o4 + f2y) * q2y + (o5 + f2z) * q2z
                                                + (o6 + f3x) * q3x + (o7 + f3y) * q3y + (o8 + f3z) * q3z
                                                + (o9 + f4x) * q4x + (o10 + f4y) * q4y + (o11 + f4z) * q4z)
            w[_L0 + _HG * B + l] = f1x
            w[_L0 + (_HG + 1) * B + l] = f1y
            w[_L0 + (_HG + 2) * B + l] = f1z
            w[_L0 + (_HG + 3) * B + l] = f2x
            w[_L0 + (_HG + 4) * B + l] = f2y
            w[_L0 + (_HG + 5) * B + l] = f2z
            w[_L0 + (_HG + 6) * B + l] = f3x
            w[_L0 + (_HG + 7) * B + l] = f3y
            w[_L0 + (_HG + 8) * B + l] = f3z
            w[_L0 + (_HG + 9) * B + l] = f4x
            w[_L0 + (_HG + 10) * B + l] = f4y
            w[_L0 + (_HG + 11) * B + l] = f4z
            # stored forces are in the element frame; the nodal forces need them global
            f1x, f1y, f1z = _rotate(r11, r21, r31, r12, r22, r32, r13, r23, r33, f1x, f1y, f1z)
            f2x, f2y, f2z = _rotate(r11, r21, r31, r12, r22, r32, r13, r23, r33, f2x, f2y, f2z)
            f3x, f3y, f3z = _rotate(r11, r21, r31, r12, r22, r32, r13, r23, r33, f3x, f3y, f3z)
            f4x, f4y, f4z = _rotate(r11, r21, r31, r12, r22, r32, r13, r23, r33, f4x, f4y, f4z)
            # nodal forces -(sum_k t_k grad-sign_k + sum_a F_a gamma_a) with
            # gamma_a = H_a - sum_k w_ak xi_k: collect the xi_k parts first
            w11 = w[_L0 + _WAK * B + l]
            w12 = w[_L0 + (_WAK + 1) * B + l]
            w13 = w[_L0 + (_WAK + 2) * B + l]
            w21 = w[_L0 + (_WAK + 3) * B + l]
            w22 = w[_L0 + (_WAK + 4) * B + l]
            w23 = w[_L0 + (_WAK + 5) * B + l]
            w31 = w[_L0 + (_WAK + 6) * B + l]
            w32 = w[_L0 + (_WAK + 7) * B + l]
            w33 = w[_L0 + (_WAK + 8) * B + l]
            w41 = w[_L0 + (_WAK + 9) * B + l]
            w42 = w[_L0 + (_WAK + 10) * B + l]
            w43 = w[_L0 + (_WAK + 11) * B + l]
            _corner_forces(w, 0, l, ok,
                           t1x - (w11 * f1x + w21 * f2x + w31 * f3x + w41 * f4x),
                           t2x - (w12 * f1x + w22 * f2x + w32 * f3x + w42 * f4x),
                           t3x - (w13 * f1x + w23 * f2x + w33 * f3x + w43 * f4x), f1x, f2x, f3x, f4x)
            _corner_forces(w, _NDS, l, ok,
                           t1y - (w11 * f1y + w21 * f2y + w31 * f3y + w41 * f4y),
                           t2y - (w12 * f1y + w22 * f2y + w32 * f3y + w42 * f4y),
                           t3y - (w13 * f1y + w23 * f2y + w33 * f3y + w43 * f4y), f1y, f2y, f3y, f4y)
            _corner_forces(w, 2 * _NDS, l, ok,
                           t1z - (w11 * f1z + w21 * f2z + w31 * f3z + w41 * f4z),
                           t2z - (w12 * f1z + w22 * f2z + w32 * f3z + w42 * f4z),
                           t3z - (w13 * f1z + w23 * f2z + w33 * f3z + w43 * f4z), f1z, f2z, f3z, f4z)
        # ---- write back, reductions (lane order), scatter (node order)
        for l in range(nb):
            e = e0 + l
            st = w[_L0 + _STC * B + l]
            if st != 0.0:
                out[1] = max(out[1], st)
                continue
            for c in range(6):
                stress[e, c] = w[_L0 + (_SN + c) * B + l]
            for c in range(12):
                hg[e, c] = w[_L0 + (_HG + c) * B + l]
            out[0] = min(out[0], w[_L0 + _DTE * B + l])
            out[2] += w[_L0 + _EWI * B + l]
            out[4] += w[_L0 + _EWH * B + l]
            out[5] += w[_L0 + _EWV * B + l]
        for r in range(4):
            nr = n00 + (r & 1) * nnx + (r >> 1) * nnxy
            o = r * 3 * _NDS
            for m in range(nb + 1):
                n = nr + m
                f[n, 0] += w[_FLO + o + m] + w[_FHI + o + m]
                f[n, 1] += w[_FLO + o + _NDS + m] + w[_FHI + o + _NDS + m]
                f[n, 2] += w[_FLO + o + 2 * _NDS + m] + w[_FHI + o + 2 * _NDS + m]


def _rows_pass(x, v, f, stress, eps_p, sy_static, hg, temp, vol0, mat, dt, nnx, nny, nx, ny, i0, i1, j0, j1, k0, k1):
    """Blocked element pass over the index box (same contract as :func:`element_pass`)."""
    nj = j1 - j0
    nk = k1 - k0
    res = np.zeros((4, 6))
    res[:, 0] = 1e30  # a colour with no rows (a box one element thick) limits no step
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
    tot = np.zeros(6)  # over the colours in order: min step, max status, energy sums
    tot[0] = 1e30
    for colour in range(4):
        if res[colour, 0] < tot[0]:
            tot[0] = res[colour, 0]
        if res[colour, 1] > tot[1]:
            tot[1] = res[colour, 1]
        for c in range(2, 6):
            tot[c] += res[colour, c]
    status = int(tot[1])
    return (0.0 if status != 0 else tot[0]), status, tot[2], tot[3], tot[4], tot[5]


element_rows, element_rows_parallel = jit_twins(_rows_pass)
