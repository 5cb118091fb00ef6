"""Johnson-Cook elasto-viscoplasticity (paper eq. 1) and its stress update.

Flow stress (the STANDARD Johnson-Cook form)::

    sigma_y = (A + B eps_p^n) (1 + C ln eps_dot*) (1 - T*^m)

The paper prints eq. (1) with ``[1 - C ln(eps_dot*)]``; with C > 0 that would
make the steel softer at higher rate, contrary to the source of its constants
(Johnson & Cook 1983, Bhuvaraghan et al.) -- it is a typo and the standard
``1 + C ln`` form is implemented here.

* ``eps_dot* = eps_dot_p / eps_dot_0`` with a configurable reference rate
  ``eps_dot_0`` (default 1 /s); below the reference rate there is no rate
  effect (``eps_dot* < 1`` -> factor 1).
* ``T* = (T - T_room) / (T_melt - T_room)`` clipped to [0, 1]; ``m = 0`` means
  *no thermal softening* (the literal ``1 - T*^0 = 0`` would be nonsense).
* Temperature is a per-element field; with ``adiabatic=True`` it rises by
  ``beta sigma_y d eps_p / (rho c_p)`` (Taylor-Quinney ``beta = 0.9``).

Stress update per element and step (hypo-elastic, Jaumann rate, radial
return): rotate the old stress with the spin, add the elastic trial increment
``lambda tr(D) dt I + 2 mu D dt``, and if the von Mises trial stress ``q``
exceeds the current static flow stress solve
``q - 3 mu d_eps_p = sigma_y(eps_p + d_eps_p, d_eps_p / dt)`` for ``d_eps_p``
by Newton iterations safeguarded by bisection (the residual is convex and
decreasing, so the bracket ``[0, (q - sigma_y_static)/(3 mu)]`` always holds
the root).

Cost when ``C = 0`` and ``m = 0``: elastic elements compare ``q`` with the
stored static flow stress only (no ``pow``/``log``); yielding elements skip
the rate and thermal terms (``RATE``/``THERMAL`` flags are loop-invariant and
only read inside the return mapping, and the branch is perfectly predicted).
The plastic-impact table of docs/validation.md section 3 shows the same wall time with the
rate term on and off.

Material parameters travel to numba as one float64 vector, see
:meth:`Material.to_array` and the ``M_*`` indices below.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from peenflow._jit import jit

# indices into the material vector
M_LAM, M_MU, M_RHO, M_A, M_B, M_N, M_C, M_RATE0, M_M = 0, 1, 2, 3, 4, 5, 6, 7, 8
M_TROOM, M_TMELT, M_HEAT, M_RATE_ON, M_THERMAL_ON, M_ADIABATIC = 9, 10, 11, 12, 13, 14
M_BULK_LIN, M_BULK_QUAD, M_HG, M_HG_FLOOR, M_HG_TYPE = 15, 16, 17, 18, 19
N_MAT = 20

# hourglass control of the one-point hexahedron (value of mat[M_HG_TYPE], see element.py)
HG_STIFFNESS = 0  # Flanagan-Belytschko stiffness: coefficient Q_hg, plastic floor
HG_PHYSICAL = 1  # assumed-strain physical stabilisation (no coefficient), co-rotational
HOURGLASS_TYPES = {"stiffness": HG_STIFFNESS, "physical": HG_PHYSICAL}


#: bulk-viscosity coefficients of the element (linear, quadratic in the volumetric strain rate): the kernel's own
BULK_LINEAR = 0.06
BULK_QUADRATIC = 1.5


@dataclass(frozen=True)
class Material:
    """Elastic constants + Johnson-Cook parameters of the target (SI units).

    E : Pa, Young's modulus;  nu : -, Poisson's ratio;  density : kg/m^3.
    A, B : Pa; n, C, m : -  (eq. 1); ref_strain_rate : 1/s (eps_dot_0).
    T_room, T_melt : K; initial_temperature : K; specific_heat : J/(kg K);
    taylor_quinney : - (fraction of plastic work turned into heat);
    adiabatic : bool, heat the element with its plastic work.

    ``A = inf`` (:meth:`elastic`) is a plain linear-elastic material: the
    static flow stress is infinite, so every trial stress is accepted and
    the return map never runs (needs ``B = 0`` and ``m = 0``).
    """

    E: float
    nu: float
    density: float
    A: float
    B: float = 0.0
    n: float = 1.0
    C: float = 0.0
    m: float = 0.0
    ref_strain_rate: float = 1.0
    T_room: float = 293.0
    T_melt: float = 1793.0
    initial_temperature: float = 293.0
    specific_heat: float = 477.0
    taylor_quinney: float = 0.9
    adiabatic: bool = False

    def __post_init__(self):
        # each check is written so that NaN fails it
        checks = (
            ("E", self.E > 0, "> 0 (Pa)"), ("nu", -1 < self.nu < 0.5, "in (-1, 0.5)"),
            ("density", self.density > 0, "> 0 (kg/m^3)"), ("A", self.A > 0, "> 0 (Pa)"),
            ("B", self.B >= 0, ">= 0 (Pa)"), ("n", self.n > 0, "> 0"), ("C", self.C >= 0, ">= 0"),
            ("m", self.m >= 0, ">= 0"), ("ref_strain_rate", self.ref_strain_rate > 0, "> 0 (1/s)"),
            ("T_room", self.T_room > 0, "> 0 (K)"), ("T_melt", self.T_melt > self.T_room, "> T_room (K)"),
            ("initial_temperature", self.T_melt > self.initial_temperature > 0, "in (0, T_melt) (K)"),
            ("specific_heat", self.specific_heat > 0, "> 0 (J/(kg K))"),
            ("taylor_quinney", 0 <= self.taylor_quinney <= 1, "in [0, 1]"),
        )
        for name, ok, expected in checks:
            if not ok:
                raise ValueError(f"Material.{name} = {getattr(self, name)!r}: expected {expected}")
        if math.isinf(self.A) and (self.B != 0.0 or self.m != 0.0):
            raise ValueError(f"Material: A = inf (elastic) with B = {self.B!r}, m = {self.m!r}: expected B = 0 and "
                             "m = 0 (an elastic material has no hardening or thermal softening)")

    @classmethod
    def elastic(cls, E: float, nu: float, density: float, **kwargs) -> "Material":
        """A linear-elastic target (Pa, -, kg/m^3): ``A = inf``, never yields.

        Same results as a flow stress too high to reach (the old ``A = 1e13``
        workaround) -- both skip the return map -- without a made-up number.
        """
        return cls(E=E, nu=nu, density=density, A=math.inf, **kwargs)

    @property
    def is_elastic(self) -> bool:
        """True for a material that never yields (``A = inf``)."""
        return math.isinf(self.A)

    @property
    def lam(self) -> float:
        return self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))

    @property
    def mu(self) -> float:
        return self.E / (2 * (1 + self.nu))

    @property
    def wave_speed(self) -> float:
        """Dilatational wave speed sqrt((lambda + 2 mu)/rho), m/s."""
        return math.sqrt((self.lam + 2 * self.mu) / self.density)

    @property
    def thermal_on(self) -> bool:
        return self.m > 0 and (self.adiabatic or self.initial_temperature > self.T_room)

    def to_array(self, bulk_linear: float = BULK_LINEAR, bulk_quadratic: float = BULK_QUADRATIC,
                 hourglass: float = 0.05, hourglass_plastic_floor: float = 0.1,
                 hourglass_type: str = "stiffness") -> np.ndarray:
        """The float64 material vector the numba kernels read (see ``M_*``).

        ``hourglass_type``: "stiffness" (Flanagan-Belytschko, uses ``hourglass``
        and ``hourglass_plastic_floor``) or "physical" (assumed-strain
        stabilisation; ignores both).
        """
        if hourglass_type not in HOURGLASS_TYPES:
            raise ValueError(f"hourglass_type = {hourglass_type!r}: expected one of {tuple(HOURGLASS_TYPES)}")
        a = np.zeros(N_MAT)
        a[M_LAM], a[M_MU], a[M_RHO] = self.lam, self.mu, self.density
        a[M_A], a[M_B], a[M_N], a[M_C], a[M_RATE0], a[M_M] = self.A, self.B, self.n, self.C, self.ref_strain_rate, self.m
        a[M_TROOM], a[M_TMELT] = self.T_room, self.T_melt
        a[M_HEAT] = self.taylor_quinney / (self.density * self.specific_heat)
        a[M_RATE_ON] = 1.0 if self.C > 0 else 0.0
        a[M_THERMAL_ON] = 1.0 if self.thermal_on else 0.0
        a[M_ADIABATIC] = 1.0 if (self.adiabatic and self.m > 0) else 0.0
        a[M_BULK_LIN], a[M_BULK_QUAD], a[M_HG] = bulk_linear, bulk_quadratic, hourglass
        a[M_HG_FLOOR] = hourglass_plastic_floor
        a[M_HG_TYPE] = HOURGLASS_TYPES[hourglass_type]
        return a

    def flow_stress(self, eps_p, rate=0.0, T=None):
        """Eq. (1) in plain numpy (for tests and plots): Pa."""
        eps_p = np.asarray(eps_p, float)
        s = self.A + self.B * np.power(np.maximum(eps_p, 0.0), self.n)
        r = np.maximum(np.asarray(rate, float) / self.ref_strain_rate, 1.0)
        s = s * (1 + self.C * np.log(r))
        if self.m > 0 and T is not None:
            ts = np.clip((np.asarray(T, float) - self.T_room) / (self.T_melt - self.T_room), 0, 1)
            s = s * (1 - ts**self.m)
        return s


@jit
def thermal_factor(temp, mat):
    """``1 - T*^m`` of eq. (1) (1 when the thermal term is off)."""
    if mat[M_THERMAL_ON] == 0.0:
        return 1.0
    ts = (temp - mat[M_TROOM]) / (mat[M_TMELT] - mat[M_TROOM])
    if ts <= 0.0:
        return 1.0
    if ts >= 1.0:
        return 0.0
    return 1.0 - ts ** mat[M_M]


@jit
def static_flow_stress(eps_p, theta, mat):
    """``(A + B eps_p^n)(1 - T*^m)``, Pa."""
    h = mat[M_A]
    if eps_p > 0.0:
        h += mat[M_B] * eps_p ** mat[M_N]
    return h * theta


@jit
def radial_return(q_trial, q_old, eps_p, dt, theta, mat):
    """Solve ``q_trial - 3 mu d = sigma_y(eps_p + d, d/dt)`` for ``d >= 0``.

    ``q_old``: von Mises stress of the (rotated) stress at the step start --
    after a plastic step the flow stress of that step, which gives the start
    of the iteration (below). Returns ``(d_eps_p, sigma_y, sigma_y_static)``:
    the flow stress at the solution and the static flow stress
    ``(A + B (eps_p + d)^n)(1 - T*^m)`` there (Pa; the caller stores it, no
    extra ``pow``).

    Start: the root of a model residual, without ``pow``/``log``: the
    hardening ``B (eps_p + d)^n`` expanded to second order about ``eps_p``
    (slopes from the one ``pow`` at ``eps_p`` needed for the bracket anyway)
    and, when the element yielded in the previous step at a rate above the
    reference rate (``q_old`` above the static flow stress), one Newton step
    of that model from the previous step's rate, recovered from its rate
    factor ``q_old / sigma_y_static = 1 + C ln(rate / eps_dot_0)`` by one
    ``exp``; otherwise the rate-free model's root. In steady flow (a rate
    changing by less than ~1 % a step) the first evaluation then already
    satisfies ``|f| <= 1e-7 q``: one ``pow`` and one ``log`` per return plus
    the bracket's ``pow``. Measured evaluations per return, starting from the
    bracket end before: 4 -> 1 in the all-plastic throughput benchmark, 6.0 ->
    2.6 in a 55 m/s impact (rates there change by up to tens of % a step).
    The start only moves the first iterate; the iteration and its tolerance
    are unchanged, so a poor start (first yield, ``eps_p`` small against
    ``d``) costs iterations, never accuracy.

    Newton on ``d`` safeguarded by the bracket ``[lo, hi]``. A Newton step
    that would leave the bracket on the left (the rate term's ``ln d`` makes
    the residual steep near 0) is taken in ``ln d`` instead, which keeps it
    positive; bisection only if that fails too. Once ``|f| <= 1e-7 q`` (with
    the iterate and the step on the same side of the rate kink ``d = dt
    eps_dot_0``, where the residual is smooth) one last Newton step is taken
    without evaluating it: its error is O(f^2), below the ``1e-12 q``
    tolerance of the residual test, and the flow stress there follows from the
    yield condition itself, ``sigma_y = q - 3 mu d``.
    """
    mu3 = 3.0 * mat[M_MU]
    A, B, n, C = mat[M_A], mat[M_B], mat[M_N], mat[M_C]
    rate_on = mat[M_RATE_ON] != 0.0
    d_kink = dt * mat[M_RATE0]
    rate_scale = 1.0 / d_kink
    inv_c = 1.0 / C if C > 0.0 else 0.0
    p0 = eps_p ** n if eps_p > 0.0 else 0.0
    s_static = (A + B * p0) * theta
    hi = (q_trial - s_static) / mu3
    if hi <= 0.0:
        return 0.0, q_trial, s_static
    # start (see the docstring): model flow stress (s_static + h1 d + h2 d^2 / 2) R(d)
    h1 = 0.0
    h2 = 0.0
    inv_ep = 0.0
    if eps_p > 0.0:
        inv_ep = 1.0 / eps_p
        h1 = n * B * p0 * inv_ep * theta
        h2 = h1 * (n - 1.0) * inv_ep
    d = hi
    d0 = -1.0  # the previous step's rate as an increment of this step (-1: none)
    u0 = 0.0  # ln(d0 / d_kink)
    if rate_on and q_old > s_static * (1.0 + 1e-12):
        u = (q_old / s_static - 1.0) * inv_c
        if u < 700.0 and d_kink * math.exp(u) < hi:
            u0 = u
            d0 = d_kink * math.exp(u)
            r_old = 1.0 + C * u0
            st = s_static + d0 * (h1 + 0.5 * h2 * d0)
            fm = q_trial - mu3 * d0 - st * r_old
            dfm = -(mu3 + (h1 + h2 * d0) * r_old) * d0 - st * C  # d fm / d ln d
            d = d0 - fm * d0 / dfm
            if d <= 0.0:
                d = d0 * math.exp(-fm / dfm)
    else:
        d = (q_trial - s_static) / (mu3 + h1)
        d = (q_trial - s_static - 0.5 * h2 * d * d) / (mu3 + h1)
    if not (0.0 < d < hi):
        d = hi
    lo = 0.0
    sy = q_trial
    for _ in range(60):
        e = eps_p + d
        if e < 1e-12:
            e = 1e-12
        x = d * inv_ep
        if eps_p > 0.0 and x <= 0.01:
            # (1 + x)^n by 7 terms of the binomial series (truncation < 1e-15): no pow
            t = 1.0 + (n - 6.0) * 0.14285714285714285 * x
            t = 1.0 + (n - 5.0) * 0.16666666666666666 * x * t
            t = 1.0 + (n - 4.0) * 0.2 * x * t
            t = 1.0 + (n - 3.0) * 0.25 * x * t
            t = 1.0 + (n - 2.0) * 0.3333333333333333 * x * t
            t = 1.0 + (n - 1.0) * 0.5 * x * t
            t = 1.0 + n * x * t
            en = p0 * t
        else:
            en = e ** n
        stat = A + B * en
        dstat = n * B * en / e
        R = 1.0
        dR = 0.0
        if rate_on:
            r = d * rate_scale
            if r > 1.0:
                y = (d - d0) / d0
                if d0 > 0.0 and abs(y) <= 0.01:
                    # ln r = ln(d0 / d_kink) + ln(1 + y), 8 terms of the series (truncation < 1e-17): no log
                    R = 1.0 + C * (u0 + y * (1.0 - y * (0.5 - y * (0.3333333333333333 - y * (
                        0.25 - y * (0.2 - y * (0.16666666666666666 - y * (0.14285714285714285 - y * 0.125))))))))
                else:
                    R = 1.0 + C * math.log(r)
                dR = C / d
        sy = stat * R * theta
        s_static = stat * theta
        f = q_trial - mu3 * d - sy
        if f > 0.0:
            lo = d
        else:
            hi = d
        if abs(f) <= 1e-12 * q_trial or hi - lo <= 1e-15 * (1.0 + eps_p):
            break
        df = -mu3 - (dstat * R + stat * dR) * theta
        dn = d - f / df
        if abs(f) <= 1e-7 * q_trial and lo < dn < hi and (not rate_on or (d > d_kink) == (dn > d_kink)):
            return dn, q_trial - mu3 * dn, (stat + dstat * (dn - d)) * theta
        if dn <= lo:
            dn = d * math.exp(-f / (df * d))  # the Newton step in ln d
        if dn <= lo or dn >= hi:
            dn = 0.5 * (lo + hi)
        d = dn
    return d, sy, s_static


@jit(inline="always")
def jaumann_trial(s0, s1, s2, s3, s4, s5, d0, d1, d2, d3, d4, d5, w0, w1, w2, dt, lam, mu):
    """Hypo-elastic trial stress: old stress rotated with the Jaumann rate plus
    ``lambda tr(D) dt I + 2 mu D dt`` (arguments as :func:`stress_update`).

    The one implementation of the elastic update: :func:`stress_update` and the
    blocked element kernel (``peenflow.fe.element``) both call it; it is
    inlined (numba IR) so that the element kernel's lane loop stays free of
    calls and vectorises.
    """
    # Jaumann rotation: s += dt (W s - s W) = dt (M + M^T), M = W s
    # W = [[0, wxy, wxz], [-wxy, 0, wyz], [-wxz, -wyz, 0]]
    wyz, wxz, wxy = w0, w1, w2
    sxx, syy, szz, syz, sxz, sxy = s0, s1, s2, s3, s4, s5
    m00 = wxy * sxy + wxz * sxz
    m11 = -wxy * sxy + wyz * syz
    m22 = -wxz * sxz - wyz * syz
    m01 = wxy * syy + wxz * syz
    m10 = -wxy * sxx + wyz * sxz
    m02 = wxy * syz + wxz * szz
    m20 = -wxz * sxx - wyz * sxy
    m12 = -wxy * sxz + wyz * szz
    m21 = -wxz * sxy - wyz * syy
    tr = (d0 + d1 + d2) * dt
    lt = lam * tr
    mu2 = 2.0 * mu * dt
    t0 = sxx + dt * 2.0 * m00 + lt + mu2 * d0
    t1 = syy + dt * 2.0 * m11 + lt + mu2 * d1
    t2 = szz + dt * 2.0 * m22 + lt + mu2 * d2
    t3 = syz + dt * (m12 + m21) + mu2 * d3
    t4 = sxz + dt * (m02 + m20) + mu2 * d4
    t5 = sxy + dt * (m01 + m10) + mu2 * d5
    return t0, t1, t2, t3, t4, t5


@jit(inline="always")
def von_mises(t0, t1, t2, t3, t4, t5):
    """Von Mises equivalent of a stress (Voigt order xx yy zz yz xz xy), Pa."""
    p = (t0 + t1 + t2) / 3.0
    a0 = t0 - p
    a1 = t1 - p
    a2 = t2 - p
    return math.sqrt(1.5 * (a0 * a0 + a1 * a1 + a2 * a2 + 2.0 * (t3 * t3 + t4 * t4 + t5 * t5)))


@jit
def plastic_correction(t0, t1, t2, t3, t4, t5, q, d0, d1, d2, d3, d4, d5, dt, eps_p, temp, mat):
    """Radial return of the trial stress ``t`` whose von Mises value ``q``
    exceeds the static flow stress; ``d`` the rate of deformation of the step.

    Returns the corrected stress (6 values), ``d_eps_p``, the flow stress,
    ``g_ratio`` as :func:`stress_update` does, and the new static flow stress
    at ``eps_p + d_eps_p`` (at the temperature ``temp`` of the step start).
    """
    mu = mat[M_MU]
    theta = thermal_factor(temp, mat)
    p = (t0 + t1 + t2) / 3.0
    a0 = t0 - p
    a1 = t1 - p
    a2 = t2 - p
    # deviatoric increments: elastic trial (2 mu D' dt) vs actual (f a - s_old')
    mu2 = 2.0 * mu * dt
    trd = (d0 + d1 + d2) / 3.0
    e0 = mu2 * (d0 - trd)
    e1 = mu2 * (d1 - trd)
    e2 = mu2 * (d2 - trd)
    e3 = mu2 * d3
    e4 = mu2 * d4
    e5 = mu2 * d5
    # von Mises stress at the step start (rotated): trial deviator - elastic increment
    q_old = von_mises(a0 - e0, a1 - e1, a2 - e2, t3 - e3, t4 - e4, t5 - e5)
    deps, sy, sy_static = radial_return(q, q_old, eps_p, dt, theta, mat)
    f = (q - 3.0 * mu * deps) / q
    den = e0 * e0 + e1 * e1 + e2 * e2 + 2.0 * (e3 * e3 + e4 * e4 + e5 * e5)
    g_ratio = 1.0
    if den > 0.0:
        # old (rotated) deviator = trial deviator - elastic deviatoric increment
        u0 = (f - 1.0) * a0 + e0
        u1 = (f - 1.0) * a1 + e1
        u2 = (f - 1.0) * a2 + e2
        u3 = (f - 1.0) * t3 + e3
        u4 = (f - 1.0) * t4 + e4
        u5 = (f - 1.0) * t5 + e5
        g_ratio = math.sqrt((u0 * u0 + u1 * u1 + u2 * u2 + 2.0 * (u3 * u3 + u4 * u4 + u5 * u5)) / den)
        if g_ratio > 1.0:
            g_ratio = 1.0
    return p + f * a0, p + f * a1, p + f * a2, f * t3, f * t4, f * t5, deps, sy, g_ratio, sy_static


@jit
def stress_update(s0, s1, s2, s3, s4, s5, d0, d1, d2, d3, d4, d5, w0, w1, w2, dt, eps_p, sy_static, temp, mat):
    """Jaumann-rotated hypo-elastic trial + Johnson-Cook radial return.

    Stress ``s`` (Pa) and rate of deformation ``d`` (1/s, tensor components,
    NOT engineering shear) in Voigt order xx yy zz yz xz xy; spin
    ``w = (W_yz, W_xz, W_xy)`` (1/s, W = (L - L^T)/2). Returns the new stress
    (6 values), ``d_eps_p``, the flow stress (Pa; the static one if elastic)
    and ``g_ratio``: the ratio of the actual to the elastic-trial deviatoric
    stress increment of the step (1 when elastic, ~E_t/E in steady plastic
    flow), used to soften the hourglass stiffness of yielding elements; last
    the static flow stress at the new plastic strain (the input one if elastic).
    """
    t0, t1, t2, t3, t4, t5 = jaumann_trial(s0, s1, s2, s3, s4, s5, d0, d1, d2, d3, d4, d5, w0, w1, w2, dt,
                                           mat[M_LAM], mat[M_MU])
    q = von_mises(t0, t1, t2, t3, t4, t5)
    if q <= sy_static or dt <= 0.0:
        return t0, t1, t2, t3, t4, t5, 0.0, sy_static, 1.0, sy_static
    return plastic_correction(t0, t1, t2, t3, t4, t5, q, d0, d1, d2, d3, d4, d5, dt, eps_p, temp, mat)


def material_point(material: "Material", path: str, strain_rate: float, total_strain: float, n_steps: int = 2000):
    """Drive one material point with :func:`stress_update` (tests and plots).

    ``path``: ``"uniaxial"`` -- axial rate ``strain_rate`` (1/s) with the
    lateral stresses held at zero (lateral rate found by iteration each
    increment); ``"shear"`` -- pure shear ``D_xy = strain_rate / 2``
    (engineering shear rate ``strain_rate``), no spin.

    Returns a dict of arrays (one entry per increment): ``strain`` (axial
    strain or engineering shear), ``stress`` (sigma_xx or tau_xy, Pa),
    ``von_mises`` (Pa), ``eps_p``, ``eps_p_rate`` (1/s).
    """
    mat = material.to_array()
    dt = total_strain / strain_rate / n_steps
    s = np.zeros(6)
    ep = 0.0
    sy = static_flow_stress(0.0, 1.0, mat)
    lam, mu = mat[M_LAM], mat[M_MU]
    out = {k: np.zeros(n_steps) for k in ("strain", "stress", "von_mises", "eps_p", "eps_p_rate")}
    d_lat = -material.nu * strain_rate
    for k in range(n_steps):
        if path == "uniaxial":
            d = [strain_rate, d_lat, d_lat, 0.0, 0.0, 0.0]
            for _ in range(200):
                r = stress_update(*s, *d, 0.0, 0.0, 0.0, dt, ep, sy, material.initial_temperature, mat)
                syy = r[1]
                if abs(syy) <= 1e-9 * max(abs(r[0]), 1.0):
                    break
                # elastic tangent d sigma_yy / d D_lat = 2 (lambda + mu) dt (stiffer than the
                # elasto-plastic one, so the iteration converges monotonically)
                d_lat -= syy / (2.0 * (lam + mu) * dt)
                d[1] = d[2] = d_lat
        elif path == "shear":
            d = [0.0, 0.0, 0.0, 0.0, 0.0, 0.5 * strain_rate]
            r = stress_update(*s, *d, 0.0, 0.0, 0.0, dt, ep, sy, material.initial_temperature, mat)
        else:
            raise ValueError("path must be 'uniaxial' or 'shear'")
        s = np.array(r[:6])
        deps = r[6]
        if deps > 0:
            ep += deps
            sy = static_flow_stress(ep, 1.0, mat)
        p = s[:3].mean()
        dev = s[:3] - p
        out["strain"][k] = (k + 1) * dt * strain_rate
        out["stress"][k] = s[0] if path == "uniaxial" else s[5]
        out["von_mises"][k] = np.sqrt(1.5 * (dev @ dev + 2 * (s[3:] @ s[3:])))
        out["eps_p"][k] = ep
        out["eps_p_rate"][k] = deps / dt
    return out
