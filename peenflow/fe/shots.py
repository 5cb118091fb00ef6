"""Rigid spherical shots: data, free flight, and impact-size estimates.

Shots are rigid spheres (radius, density, centre, velocity, spin) with no
shot-shot contact (the paper's "effective stream", §2.2). The initial
centres come from the stream generator of eqs. (2)/(3) (``peenflow.methods``);
the kernel only needs the arrays. Shots are processed in the given order, one
at a time, each hitting a target at rest (event-driven time, see
:mod:`peenflow.fe.impact`).

Free flight is a straight line (no gravity, no drag); :func:`time_to_contact`
finds exactly when the sphere first touches a top-surface node.

Symmetry: a shot whose centre lies on a symmetric lateral face of the mesh
(e.g. the corner of a quarter model) is represented by the matching fraction
of its mass and inertia (1/2 per plane), and keeps only the motion its
mirror half allows (no velocity normal to the plane, no spin about axes in
it: :mod:`peenflow.fe.contact`); a shot whose motion breaks the symmetry is
refused.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from peenflow._jit import jit


def sphere_mass(radius: float, density: float) -> float:
    """Mass (kg) of a solid sphere of ``radius`` (m) and ``density`` (kg m-3)."""
    return density * 4.0 / 3.0 * math.pi * radius**3


@dataclass(frozen=True)
class Shots:
    """A sequence of rigid spherical shots of one density.

    centres : (n, 3) m, initial centres (z < 0 above the surface z = 0);
    velocities : (n, 3) m/s (v_z > 0 towards the target);
    radius : m, one radius for every shot (a float) or each shot's own (an (n,) array: a stream with a
    size spread, :func:`peenflow.methods.shot_stream`);  density : kg/m^3;
    spins : (n, 3) rad/s initial angular velocities (default zero).
    """

    centres: np.ndarray
    velocities: np.ndarray
    radius: float | np.ndarray
    density: float
    spins: np.ndarray | None = None

    def __post_init__(self):
        c = np.ascontiguousarray(np.atleast_2d(np.asarray(self.centres, float)))
        v = np.ascontiguousarray(np.atleast_2d(np.asarray(self.velocities, float)))
        if c.shape != v.shape or c.shape[1] != 3:
            raise ValueError("centres and velocities must both be (n, 3)")
        r = np.asarray(self.radius, float)
        if r.ndim not in (0, 1) or (r.ndim == 1 and r.shape != (c.shape[0],)):
            raise ValueError(f"radius must be one float or one per shot ({c.shape[0]},), got shape {r.shape}")
        if not (np.all(r > 0) and self.density > 0):
            raise ValueError("radius and density must be positive")
        s = np.zeros_like(c) if self.spins is None else np.ascontiguousarray(np.asarray(self.spins, float))
        if s.shape != c.shape:
            raise ValueError("spins must be (n, 3)")
        object.__setattr__(self, "centres", c)
        object.__setattr__(self, "velocities", v)
        object.__setattr__(self, "spins", s)
        # one radius stays a float, so a stream without a spread is computed exactly as before
        object.__setattr__(self, "radius", float(r) if r.ndim == 0 else np.ascontiguousarray(r))

    def __len__(self) -> int:
        return len(self.centres)

    @property
    def mass(self) -> float | np.ndarray:
        """kg (a float, or (n,) with per-shot radii)"""
        return sphere_mass(self.radius, self.density)

    @property
    def inertia(self) -> float | np.ndarray:
        """Moment of inertia of a solid sphere, kg m^2 (a float, or (n,) with per-shot radii)."""
        return 0.4 * self.mass * self.radius**2

    def radius_of(self, i: int) -> float:
        """Radius of shot ``i``, m."""
        return self.radius if isinstance(self.radius, float) else float(self.radius[i])

    def mass_of(self, i: int) -> float:
        """Mass of shot ``i``, kg."""
        return sphere_mass(self.radius_of(i), self.density)

    def inertia_of(self, i: int) -> float:
        """Moment of inertia of shot ``i``, kg m^2."""
        return 0.4 * self.mass_of(i) * self.radius_of(i) ** 2


@jit
def time_to_contact(xs, centre, vel, radius):
    """When the sphere ``centre + vel t``, coming from far upstream, first touches a point of ``xs``.

    ``xs`` (n, 3) m: top-surface node positions; ``centre`` (3,) m; ``vel``
    (3,) m/s, nonzero. Returns the earliest entry time t (s) over the points,
    ``min_p (-b - sqrt(b^2 - 4ac)) / 2a`` of ``|centre + vel t - x_p|^2 = R^2``;
    ``inf`` if the line misses every point.

    t may be NEGATIVE: a start centre that already overlaps the surface (a
    pile-up higher than the gap the caller left, or a crest the line passed
    through before the given centre) is not a physical state, since the
    shot has come from far away along its line; it is put back to where it
    first touched. Treating such a start as contact at t = 0 instead let the
    kinematic contact snap the overlapped nodes out in one step, an
    unphysical impulse that showed up as energy-balance errors of up to
    0.3 impact energies in dense sequences
    (docs/validation.md section 8, "Dense sequences").
    """
    a = vel[0] ** 2 + vel[1] ** 2 + vel[2] ** 2
    best = math.inf
    r2 = radius * radius
    if a == 0.0:
        return best
    for p in range(xs.shape[0]):
        dx = centre[0] - xs[p, 0]
        dy = centre[1] - xs[p, 1]
        dz = centre[2] - xs[p, 2]
        c = dx * dx + dy * dy + dz * dz - r2
        b = 2.0 * (dx * vel[0] + dy * vel[1] + dz * vel[2])
        disc = b * b - 4.0 * a * c
        if disc < 0.0:
            continue
        t = (-b - math.sqrt(disc)) / (2.0 * a)
        if t < best:
            best = t
    return best


def hertz(radius: float, mass: float, speed: float, E: float, nu: float) -> dict:
    """Hertz impact of a rigid sphere on an elastic half-space (SI units).

    Returns max approach ``delta`` (m), contact radius ``a`` (m), peak force
    ``F`` (N) and contact duration ``t`` (s) (Johnson, Contact Mechanics §11.4)::

        E* = E / (1 - nu^2);  delta = (15 m v^2 / (16 E* sqrt(R)))^(2/5)
        a = sqrt(R delta);  F = 4/3 E* sqrt(R) delta^(3/2);  t = 2.943 delta / v
    """
    Es = E / (1.0 - nu**2)
    delta = (15.0 * mass * speed**2 / (16.0 * Es * math.sqrt(radius))) ** 0.4
    return {
        "delta": delta,
        "a": math.sqrt(radius * delta),
        "F": 4.0 / 3.0 * Es * math.sqrt(radius) * delta**1.5,
        "t": 2.943 * delta / speed,
    }


def johnson_plastic(radius: float, mass: float, speed: float, mean_pressure: float) -> dict:
    """Fully plastic indentation estimate (constant mean pressure, no hardening).

    Energy balance ``m v^2 / 2 = integral p pi a^2 d delta`` with
    ``a^2 = 2 R delta``: ``delta = v sqrt(m / (2 pi R p))``, ``a = sqrt(2 R delta)``.
    Returns ``delta`` (m) and ``a`` (m).
    """
    delta = speed * math.sqrt(mass / (2.0 * math.pi * radius * mean_pressure))
    return {"delta": delta, "a": math.sqrt(2.0 * radius * delta)}
