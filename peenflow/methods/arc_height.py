"""Almen-strip arc height from an induced residual-stress profile (paper eqs. 6-9).

The REV of the clamped strip gives ``σx_ind(z)``, the longitudinal stress
averaged over the measuring region (z = depth below the peened surface). The
clamping fixture holds the strip straight with a force ``F_x`` (eq. 6) and a
moment ``M_y`` (eq. 7); releasing the bolts applies ``-F_x`` and ``-M_y``, which
gives the released stress (eq. 8) and the curvature, hence the arc height over
the gauge span ``l`` (eq. 9).

Moment reference (a documented correction of the paper's notation): eq. (8)
subtracts ``M_y z / I_y`` with ``I_y = b h^3 / 12``, the second moment about the
*centroid* of the section. Beam theory is only consistent (released stress
with zero net force *and* zero net moment) if ``z`` in eqs. (7)-(8) is measured
from the neutral axis, i.e. the strip mid-plane: ``z' = z - h/2``. Measured
from the peened surface instead, a uniform stress would produce a spurious
moment ``σ b h^2 / 2`` and an arc height although it only stretches the strip.
Here ``M_y = b ∫ σx_ind(z) (z - h/2) dz``. With z pointing into the strip, a
compressive surface layer (σ < 0 at z < h/2) gives ``M_y > 0`` and a positive
arc height, convex towards the peened side, the Almen convention.

The strip is a beam with modulus ``E`` (as in the paper); the transverse
curvature and the plate (biaxial) stiffening are neglected, as the paper does.
"""

from __future__ import annotations

from dataclasses import dataclass

from .residual_profile import DepthProfile, _check_within

@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class StripRelease:
    """Result of releasing a peened, clamped Almen strip.

    force : N, ``F_x`` held by the fixture (eq. 6).
    moment : N·m, ``M_y`` about the strip mid-plane (eq. 7).
    released : DepthProfile (kind ``linear``), Pa, the released stress (eq. 8),
        exact for the input representation.
    curvature : 1/m, ``M_y / (E I_y)``, positive when convex towards the peened side.
    arc_height : m, eq. (9) over the gauge span.
    """

    force: float
    moment: float
    released: DepthProfile
    curvature: float
    arc_height: float


def clamping_force_moment(profile: DepthProfile, width: float, thickness: float) -> tuple[float, float]:
    """``(F_x, M_y)`` of eqs. (6)-(7): N and N·m, moment about the mid-plane.

    Parameters
    ----------
    profile : σx_ind(z), Pa, depths in [0, thickness] m; zero stress is assumed
        outside the profile's depth range (normally the profile spans the whole
        strip thickness, since the REV has the strip's thickness).
    width : strip width ``b``, m. thickness : strip thickness ``h``, m.
    """
    _check_within(profile, thickness)
    if not width > 0:
        raise ValueError(f"width must be positive, got {width}")
    f, m = profile.moments(origin=0.5 * thickness)
    return width * f, width * m


def release_strip(
    profile: DepthProfile,
    width: float,
    thickness: float,
    young_modulus: float,
    span: float,
) -> StripRelease:
    """Release the clamped strip: eqs. (6)-(9).

    ``σ_res(z) = σ_ind(z) - F_x / (b h) - M_y (z - h/2) / I_y`` with
    ``I_y = b h^3 / 12`` and ``Ah = M_y l^2 / (8 E I_y) = 3 M_y l^2 / (2 E b h^3)``.
    Units: Pa, m (width, thickness, span), Pa (young_modulus); returns StripRelease.
    """
    if not young_modulus > 0:
        raise ValueError("young_modulus must be positive")
    if not span > 0:
        raise ValueError("span must be positive")
    force, moment = clamping_force_moment(profile, width, thickness)
    area = width * thickness
    inertia = width * thickness**3 / 12.0
    released = profile.minus_linear(force / area, moment / inertia, origin=0.5 * thickness)
    curvature = moment / (young_modulus * inertia)
    arc = moment / (2.0 * young_modulus * inertia) * (0.5 * span) ** 2
    return StripRelease(force, moment, released, curvature, arc)
