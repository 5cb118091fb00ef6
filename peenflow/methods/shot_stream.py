"""Random shot streams: initial centres (paper eqs. 2-3), velocities, landing points, arrival order.

Frame (the paper's): origin at the centre of the ``2a × 2b`` peening surface,
z normal to it and pointing *into* the target, so shots start at z < 0 and
travel towards +z. An oblique shot with impingement angle θ (θ = 90° is
normal) travels along ``u = (cos θ, 0, sin θ)``, i.e. in the +x, +z direction.

Eq. (3) analysed. A shot whose centre starts at (x, y, z) first touches the
plane z = 0 when its centre reaches z = -R, after a path ``s = (-R - z)/sin θ``;
the *landing point* is then ``(x + s cos θ, y)``. With the x of eq. (3) as
printed, ``x = a(2r - 1) + (z - R)/tan θ``, the landing abscissa is

    x_land = a(2r - 1) + (z - R)/tan θ - (z + R)/tan θ = a(2r - 1) - 2R/tan θ,

uniform over [-a, a] but shifted upstream by the constant 2R/tan θ (0.58 mm for
S230 at 45°, 10 % of a 6D REV), so part of the peening surface downstream gets
no landings. The intent of eq. (3) is clearly uniform landing over the peening
surface; that needs ``x = a(2r - 1) + (z + R)/tan θ``, which is what is
implemented (``literal_eq3=True`` reproduces the printed version, for comparison).

Minimum distance. As in §2.2, a new centre closer than 2R to any accepted one
is discarded and redrawn (all three coordinates), so initial shots never
interpenetrate.

Reproducibility. A stream is a pure function of its arguments and ``seed``:
``numpy.random.Generator(PCG64(seed))``, one triple of uniforms (x, y, z) per
candidate centre, in that order. PCG64 and ``Generator.random`` produce the same
doubles on every platform.

Sequences and the saturation ladder. A *sequence* is a seed. Shots are sorted
by arrival (all shots share speed and direction, so arrival order is the order
of decreasing z); ``stream.first(n)`` is the first n shots *to arrive*. Why this
is a valid n-shot stream in distribution:

* the landing points of the first n arrivals are independent of their z, hence
  still independent and uniform over the peening surface, and their arrival
  order is a uniformly random permutation of them, exactly as in an n-shot
  stream of eq. (2);
* eq. (2) fixes the mean column density at one shot per 2R of height for any
  N (column 2R(N-1) for N shots); the first n arrivals of an N_max stream fill
  the top ``≈ 2R(N_max - 1) n/(N_max + 1) ≈ 2R n`` of its column at the same
  density, so their arrival rate is that of an n-shot stream;
* any subset of a 2R-separated set is 2R-separated;
* first-n sets are nested, so one run to N_max with a snapshot after the n-th
  impact gives every rung of the ladder (N = 10 … 480).

Spreads (beyond the paper, which takes every shot at the nominal size and speed "for simplicity").
A real stream scatters in size (a sieve distribution, SAE J444) and in speed (air blast, several
per cent). With ``diameter_spread`` / ``velocity_spread`` (relative standard deviations, 1) each shot
draws a size factor and a speed factor from a normal distribution truncated at 3 of its standard
deviations, the truncated distribution's mean being exactly 1 and its standard deviation exactly the
spread (the untruncated sigma is the spread / :data:`TRUNCATED_STD_FACTOR`). The factors come from
their own generator (``PCG64([seed, 1])``, sizes then speeds, by generation index), so a stream without
spreads is the stream above bit for bit, and a spread does not move the centres' draws. A shot of
radius R_i starts at ``z - (R_i - R)`` and at ``x + (R_i - R)/tan θ``, so it still touches z = 0 over
its nominal landing point, the 2R rule becomes R_i + R_j, and the arrival order is that of the arrival
times at each shot's own speed: the first n arrivals remain a valid n-shot stream (their landing points
and factors are independent of their arrival times only approximately, since a faster shot arrives
earlier; with spreads of a few per cent the bias is a few per cent of the column).

"First n generated" would not do: those are spread over the whole N_max
column, so a snapshot after the n-th *impact* would not contain them.
Shot-shot collisions are ignored (the paper's "effective stream"), so the
impacts, their order and their timing are all a run depends on.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._arrays import read_only as _ro

#: standard deviation of a standard normal truncated at +-3: sqrt(1 - 6 phi(3) / (1 - 2 Phi(-3)))
TRUNCATED_STD_FACTOR = 0.9865783926
#: the truncation, in standard deviations of the untruncated normal
TRUNCATION_SIGMAS = 3.0


def spread_factors(n: int, spread: float, rng: np.random.Generator) -> np.ndarray:
    """(n,) factors of mean 1 and standard deviation ``spread`` (1): a normal truncated at +-3 sigma
    (module docstring), drawn from ``rng`` by rejection; all exactly 1.0 when ``spread`` is 0 (the
    draws are still made, so a later array from the same generator does not depend on it)."""
    if not 0.0 <= spread < TRUNCATED_STD_FACTOR / TRUNCATION_SIGMAS:
        raise ValueError(f"a spread must be in [0, {TRUNCATED_STD_FACTOR / TRUNCATION_SIGMAS:.3f}) so every factor "
                         f"is positive, got {spread}")
    z = rng.standard_normal(n)
    out = np.abs(z) > TRUNCATION_SIGMAS
    while np.any(out):
        z[out] = rng.standard_normal(int(out.sum()))
        out = np.abs(z) > TRUNCATION_SIGMAS
    return 1.0 + (spread / TRUNCATED_STD_FACTOR) * z


def largest_factor(spread: float) -> float:
    """The largest factor :func:`spread_factors` can draw (1 + 3 sigma of the untruncated normal)."""
    return 1.0 + TRUNCATION_SIGMAS * spread / TRUNCATED_STD_FACTOR



def impingement_direction(angle_deg: float) -> np.ndarray:
    """Unit travel direction (3,) for impingement angle θ in degrees (90° = normal).

    θ = 90° gives exactly (0, 0, 1) (no 6e-17 x component).
    """
    if not 0.0 < angle_deg <= 90.0:
        raise ValueError(f"impingement angle must be in (0, 90] degrees, got {angle_deg}")
    if angle_deg == 90.0:
        return np.array([0.0, 0.0, 1.0])
    t = np.deg2rad(angle_deg)
    return np.array([np.cos(t), 0.0, np.sin(t)])


def _cot(angle_deg: float) -> float:
    u = impingement_direction(angle_deg)
    return float(u[0] / u[2])


@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class ShotStream:
    """Shots of one random sequence, sorted by arrival.

    centres : (n, 3) m, initial centres (x, y, z), z < 0 (above the target).
    velocities : (n, 3) m/s, ``speeds * u``.
    landing : (n, 2) m, (x, y) where each shot first touches z = 0.
    arrival_time : (n,) s, time from t = 0 to first contact, ascending.
    generation_index : (n,) int, order in which each centre was accepted.
    radius : m (nominal). speed : m/s (nominal). angle_deg : deg. half_width_x (a), half_width_y (b) : m.
    seed : the sequence. n_rejected : candidates discarded by the 2R rule.
    radii : (n,) m and speeds : (n,) m/s, each shot's (the nominal ones without spreads);
    diameter_spread, velocity_spread : relative standard deviations (1) they were drawn with.
    """

    centres: np.ndarray = field(repr=False)
    velocities: np.ndarray = field(repr=False)
    landing: np.ndarray = field(repr=False)
    arrival_time: np.ndarray = field(repr=False)
    generation_index: np.ndarray = field(repr=False)
    radius: float
    speed: float
    angle_deg: float
    half_width_x: float
    half_width_y: float
    seed: int
    n_rejected: int = 0
    radii: np.ndarray | None = field(default=None, repr=False)
    speeds: np.ndarray | None = field(default=None, repr=False)
    diameter_spread: float = 0.0
    velocity_spread: float = 0.0

    @property
    def spread(self) -> bool:
        """Whether the shots differ in size or speed."""
        return self.diameter_spread > 0.0 or self.velocity_spread > 0.0

    @property
    def n_shots(self) -> int:
        return int(self.centres.shape[0])

    def first(self, n: int) -> "ShotStream":
        """The first ``n`` shots to arrive: a valid n-shot stream (see module docstring)."""
        if not 0 <= n <= self.n_shots:
            raise ValueError(f"n must be in [0, {self.n_shots}], got {n}")
        return ShotStream(
            self.centres[:n], self.velocities[:n], self.landing[:n], self.arrival_time[:n],
            self.generation_index[:n], self.radius, self.speed, self.angle_deg,
            self.half_width_x, self.half_width_y, self.seed, self.n_rejected,
            None if self.radii is None else self.radii[:n], None if self.speeds is None else self.speeds[:n],
            self.diameter_spread, self.velocity_spread,
        )


def generate_centres(
    n_shots: int,
    radius: float,
    half_width_x: float,
    half_width_y: float,
    angle_deg: float = 90.0,
    seed: int = 0,
    *,
    literal_eq3: bool = False,
    max_attempts_per_shot: int = 1000,
    radii: np.ndarray | None = None,
) -> tuple[np.ndarray, int]:
    """Initial centres (n, 3) m in generation order, eqs. (2)-(3), and the rejection count.

    ``z = -R (1 + 2 (N - 1) r_z)``, ``y = b (2 r_y - 1)``,
    ``x = a (2 r_x - 1) + (z + R)/tan θ`` (eq. 3 corrected for uniform landing;
    ``(z - R)`` with ``literal_eq3=True``). θ = 90° reduces to eq. (2).
    ``radii`` (n,) m: each shot's own radius (a size spread, module docstring): its centre is moved
    by ``-(R_i - R)`` in z and ``+(R_i - R)/tan θ`` in x, and two centres must be ``R_i + R_j`` apart.
    Raises ValueError if the 2R rule cannot be met (surface too small for N shots).
    """
    if n_shots < 0:
        raise ValueError("n_shots must be >= 0")
    if not (radius > 0 and half_width_x > 0 and half_width_y > 0):
        raise ValueError("radius and half widths must be positive")
    if radii is not None and np.shape(radii) != (n_shots,):
        raise ValueError(f"radii must be ({n_shots},), got {np.shape(radii)}")
    cot = _cot(angle_deg)
    R, a, b = float(radius), float(half_width_x), float(half_width_y)
    sign = -1.0 if literal_eq3 else 1.0
    rng = np.random.Generator(np.random.PCG64(seed))
    centres = np.empty((n_shots, 3))
    min_d2 = (2.0 * R) ** 2
    k = attempts = 0
    limit = max_attempts_per_shot * max(n_shots, 1)
    while k < n_shots:
        if attempts >= limit:
            raise ValueError(
                f"could not place {n_shots} shots 2R apart (placed {k} in {attempts} draws): "
                "the peening surface is too small for this shot number and radius"
            )
        attempts += 1
        rx, ry, rz = rng.random(3)
        z = -R * (1.0 + 2.0 * (n_shots - 1) * rz)
        c = (a * (2.0 * rx - 1.0) + (z + sign * R) * cot, b * (2.0 * ry - 1.0), z)
        if radii is not None:
            dr = float(radii[k]) - R
            c = (c[0] + dr * cot, c[1], z - dr)
        if k:
            d = centres[:k] - c
            d2 = np.einsum("ij,ij->i", d, d)
            if radii is None:
                if np.min(d2) < min_d2:
                    continue
            elif np.any(d2 < (radii[:k] + radii[k]) ** 2):
                continue
        centres[k] = c
        k += 1
    return centres, attempts - n_shots


def landing_points(centres, radius, angle_deg: float) -> np.ndarray:
    """(n, 2) m: where shots starting at ``centres`` (n, 3) first touch z = 0 (``radius`` m: one, or (n,)).

    The centre is moved along the travel direction to z = -R; the lowest point
    of the sphere then touches the plane directly below it.
    """
    c = np.asarray(centres, dtype=float)
    u = impingement_direction(angle_deg)
    s = (-radius - c[:, 2]) / u[2]
    return np.column_stack([c[:, 0] + s * u[0], c[:, 1]])


def shot_stream(
    n_shots: int,
    radius: float,
    half_width_x: float,
    half_width_y: float,
    angle_deg: float,
    speed: float,
    seed: int,
    *,
    literal_eq3: bool = False,
    diameter_spread: float = 0.0,
    velocity_spread: float = 0.0,
) -> ShotStream:
    """A reproducible random shot stream sorted by arrival (module docstring).

    Parameters: N shots, shot radius R (m), peening surface half widths a, b (m),
    impingement angle θ (deg, 90 = normal), shot speed (m/s), sequence seed (int);
    ``diameter_spread`` and ``velocity_spread``: relative standard deviations (1) of each shot's size
    and speed (0: every shot nominal, the stream of eqs. 2-3 bit for bit).
    """
    if not speed > 0:
        raise ValueError("speed must be positive")
    radii = speeds = None
    if diameter_spread > 0.0 or velocity_spread > 0.0:
        factors = np.random.Generator(np.random.PCG64([seed, 1]))
        radii = float(radius) * spread_factors(n_shots, diameter_spread, factors)
        speeds = float(speed) * spread_factors(n_shots, velocity_spread, factors)
    centres, rejected = generate_centres(
        n_shots, radius, half_width_x, half_width_y, angle_deg, seed, literal_eq3=literal_eq3, radii=radii
    )
    u = impingement_direction(angle_deg)
    r = radius if radii is None else radii
    path = (-r - centres[:, 2]) / u[2]
    t = path / (speed if speeds is None else speeds)
    order = np.argsort(t, kind="stable")
    land = landing_points(centres, r, angle_deg)
    vel = np.broadcast_to(speed * u, centres.shape) if speeds is None else speeds[:, None] * u
    return ShotStream(
        centres=_ro(centres[order]),
        velocities=_ro(vel[order]),
        landing=_ro(land[order]),
        arrival_time=_ro(t[order]),
        generation_index=_ro(order, int),
        radius=float(radius),
        speed=float(speed),
        angle_deg=float(angle_deg),
        half_width_x=float(half_width_x),
        half_width_y=float(half_width_y),
        seed=seed,
        n_rejected=int(rejected),
        radii=_ro(np.full(n_shots, float(radius)) if radii is None else radii[order]),
        speeds=_ro(np.full(n_shots, float(speed)) if speeds is None else speeds[order]),
        diameter_spread=float(diameter_spread),
        velocity_spread=float(velocity_spread),
    )
