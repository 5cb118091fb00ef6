"""The sections of a study file: [shot], [almen], [dmin], [coverage],
[target], [seeds], [execution]. ([fidelity] lives in fidelity.py.)

Each section is a frozen model whose fields are the file's unit-named keys, in
the file's units (:mod:`tasks.params` converts them to SI). Sections with
lengths in shot diameters (``*_D``) know the shot diameter (mm) once the Study
is loaded.
"""

from __future__ import annotations

import hashlib
import math
from typing import Annotated, Any, Literal, Optional

from pydantic import AfterValidator, Field, PrivateAttr, StrictBool, WrapValidator, model_validator

from .intensity import parse_intensity
from .items import Material, Shot, Strip
from .almen_strips import MeasuredStrips
from .measured_profile import MeasuredProfile
from .types import (
    Angle, OpenFraction, Positive, PositiveInt, ShotScaled, StudyModel, Velocity, check,
    strictly_increasing, unique_sorted,
)

__all__ = ["ShotSection", "Almen", "Dmin", "Coverage", "Target", "Seeds", "Execution"]


class ShotSection(StudyModel):
    """[shot]: which shot, and the shot-target friction."""

    type: Shot = Field(description='a shot name from the library (e.g. "S230") or an inline table')
    friction_coefficient: Annotated[
        float, check(lambda x: 0 <= x <= 1, "a Coulomb friction coefficient in [0, 1]")
    ] = Field(0.2, description="Coulomb friction coefficient shot-target")
    diameter_spread_percent: Annotated[
        float, check(lambda x: 0 <= x <= 25, "a standard deviation in per cent of the diameter, in [0, 25]")
    ] = Field(0.0, description="standard deviation of each shot's diameter, % of the nominal diameter "
                               "(0: every shot nominal, the paper's stream); a sieve distribution of cast shot "
                               "is about 10 %")
    velocity_spread_percent: Annotated[
        float, check(lambda x: 0 <= x <= 25, "a standard deviation in per cent of the velocity, in [0, 25]")
    ] = Field(0.0, description="standard deviation of each shot's speed, % of the nominal velocity (0: every "
                               "shot at the nominal velocity); air blast scatters by about 5-10 %")

    # the shot's own properties, as a study reads them
    @property
    def name(self) -> str:
        return self.type.name

    @property
    def diameter_mm(self) -> float:
        return self.type.diameter_mm

    @property
    def density_kg_m3(self) -> float:
        return self.type.density_kg_m3


def _rev_rule_default(data: Any) -> Any:
    if isinstance(data, dict) and data.get("rev_rule") is None:
        data = dict(data)
        data["rev_rule"] = "explicit" if data.get("rev_size_mm") is not None else "dmin"
    return data


def _check_rev(section: str, rule: str, rev_size_mm, measure_size_mm) -> None:
    if rule == "explicit" and rev_size_mm is None:
        raise ValueError(f'{section}.rev_rule = "explicit" needs rev_size_mm')
    if rule != "explicit" and rev_size_mm is not None:
        raise ValueError(
            f'{section}.rev_size_mm is given but rev_rule = "{rule}"; give one or the other '
            '(rev_size_mm alone means rev_rule = "explicit")'
        )
    if rule != "explicit" and measure_size_mm is not None:
        raise ValueError(f"{section}.measure_size_mm is only used with rev_size_mm (rev_rule = \"explicit\")")
    if rev_size_mm is not None and measure_size_mm is not None and measure_size_mm > rev_size_mm:
        raise ValueError(
            f"{section}.measure_size_mm = {measure_size_mm!r} is larger than rev_size_mm = {rev_size_mm!r}"
        )


def _auto_or(value, handler):
    """``"auto"`` as it is (a ladder that extends itself), anything else validated as a ladder.

    (A union type would report every error twice, once per branch.)"""
    if isinstance(value, str):
        if value == "auto":
            return value
        raise ValueError('expected "auto" or a list of shot counts')
    return handler(value)


#: defaults of the "auto" ladder: the paper's first rung; the longest ladder run so far (bounds.py)
FIRST_SHOTS = 10
MAX_SHOTS = 5120
#: default cap of the adaptive sequences: (sigma / tol)^2 ~ 10 with the rule's 1.6x margin (methods/sequences.py)
MAX_SEQUENCES = 16


class Almen(ShotScaled):
    """[almen]: the control-curve sweep on an Almen strip REV (paper section 4).

    For every angle x velocity x sequence, one strip REV run with the shot
    ladder ``shot_counts`` (snapshots of one run, or separate runs) gives arc
    heights (eqs. (6)-(9)), a saturation curve (eqs. (10)-(11)) and so the
    intensity; intensity vs velocity per angle is the control curve.
    """

    strip: Strip = Field(description='an Almen strip name ("N", "A", "C") or an inline table')
    angles_deg: Annotated[tuple[Angle, ...], Field(min_length=1), unique_sorted("angles")] = Field(
        description="impingement angles in degrees, e.g. [45, 67.5, 90]"
    )
    velocities_m_s: Annotated[tuple[Velocity, ...], Field(min_length=1), unique_sorted("velocities")] = Field(
        description="shot velocities in m/s, e.g. [25, 35, 45, 55]"
    )
    shot_counts: Annotated[
        tuple[PositiveInt, ...], Field(min_length=3), strictly_increasing("shot counts"), WrapValidator(_auto_or)
    ] = Field(description='the saturation ladder, e.g. [10, 20, 40, 80, 160, 320, 480] (at least 3 for eq. (10)), '
                          'or "auto": a doubling ladder from first_shots that stops where eq. (11) is satisfied '
                          'inside its own data (a rung at >= 2 T), at most max_shots')
    first_shots: Optional[PositiveInt] = Field(
        None, description='first rung of the "auto" ladder (default 10, the paper\'s first)')
    max_shots: Optional[PositiveInt] = Field(
        None, description='cap of the "auto" ladder: its last rung if saturation is not reached before (default 5120)')
    sequences: PositiveInt = Field(6, description="number of random shot sequences per (angle, velocity); "
                                               "with sequence_tolerance_mm, the number each point starts with")
    sequence_tolerance_mm: Optional[Positive] = Field(
        None, description="adaptive sequences: add sequences to each (angle, velocity), one at a time from "
                          "`sequences` (>= 2), until the 95 % upper bound of the standard error of its "
                          "intensity is at most this (mm), or max_sequences are run")
    max_sequences: Optional[PositiveInt] = Field(
        None, description="cap of the adaptive sequences (default 16); needs sequence_tolerance_mm")
    rev_rule: Literal["dmin", "paper", "explicit"] = Field(
        description='"dmin": side 3 d_min from the two-shot search; "paper": 6D x 6D with a 2D x 2D '
        'measuring region (section 4.1); "explicit": rev_size_mm'
    )
    rev_size_mm: Optional[Positive] = Field(None, description="REV side in mm (implies rev_rule = \"explicit\")")
    measure_size_mm: Optional[Positive] = Field(None, description="measuring-region side in mm (default rev_size_mm / 3)")
    saturation_fit: Literal["paper", "exponential_2p", "exponential_3p"] = Field(
        "paper", description='"paper" (eqs. (10)-(11)) or an SAE J2597-style exponential fit'
    )
    interpolation: Literal["pchip", "linear"] = Field(
        "pchip", description='control-curve interpolation: "pchip" (monotone cubic) or "linear"'
    )
    allow_extrapolated_intensity: StrictBool = Field(
        False, description="read a velocity off control-curve points whose saturation point (eq. 11) lies "
                           "beyond the largest shot count (an extrapolated intensity); off by default"
    )

    _fill_rule = model_validator(mode="before")(_rev_rule_default)

    @model_validator(mode="after")
    def _ladder(self) -> "Almen":
        if not self.ladder_auto:
            for key in ("first_shots", "max_shots"):
                if getattr(self, key) is not None:
                    raise ValueError(f'almen.{key} = {getattr(self, key)!r} needs almen.shot_counts = "auto" '
                                     f"(a given ladder has its own rungs)")
            return self
        first, cap = self.ladder_first_shots, self.ladder_max_shots
        if cap <= 2 * first:
            raise ValueError(f"almen.first_shots = {first}: the ladder to almen.max_shots = {cap} has fewer "
                             f"than the 3 rungs eq. (10) needs (max_shots > 2 x first_shots = {2 * first})")
        return self

    @model_validator(mode="after")
    def _adaptive_sequences(self) -> "Almen":
        if self.sequence_tolerance_mm is None:
            if self.max_sequences is not None:
                raise ValueError(f"almen.max_sequences = {self.max_sequences!r} needs almen.sequence_tolerance_mm "
                                 "(the adaptive sequences it caps)")
            return self
        if self.sequences < 2:
            raise ValueError(f"almen.sequences = {self.sequences}: adaptive sequences (sequence_tolerance_mm) "
                             "start with at least 2 (one sequence has no spread)")
        if self.sequences_cap < self.sequences:
            raise ValueError(f"almen.max_sequences = {self.sequences_cap} is below almen.sequences = "
                             f"{self.sequences}, the number each point starts with")
        return self

    @property
    def sequences_adaptive(self) -> bool:
        """True when sequences are added until the intensity's standard error meets the tolerance."""
        return self.sequence_tolerance_mm is not None

    @property
    def sequences_cap(self) -> int:
        """The most sequences a point may have: max_sequences (default 16) when adaptive, else `sequences`."""
        if not self.sequences_adaptive:
            return self.sequences
        return self.max_sequences or MAX_SEQUENCES

    @property
    def ladder_auto(self) -> bool:
        """True when the strip ladder extends itself (``shot_counts = "auto"``)."""
        return self.shot_counts == "auto"

    @property
    def ladder_first_shots(self) -> int:
        return self.first_shots or FIRST_SHOTS

    @property
    def ladder_max_shots(self) -> int:
        return self.max_shots or MAX_SHOTS

    @model_validator(mode="after")
    def _rev(self) -> "Almen":
        _check_rev("almen", self.rev_rule, self.rev_size_mm, self.measure_size_mm)
        if self.rev_size_mm is not None and self.rev_size_mm > self.strip.width_mm:
            raise ValueError(
                f"almen.rev_size_mm = {self.rev_size_mm!r} is wider than the strip ({self.strip.width_mm!r} mm)"
            )
        return self


def _resolution_default(data: Any) -> Any:
    if isinstance(data, dict) and "resolution_D" not in data and "resolution_mm" not in data:
        data = {**data, "resolution_D": 0.05}
    return data


class Dmin(ShotScaled):
    """[dmin]: the two-shot search for d_min (paper section 3.1, eq. (4), section 4.1).

    Two shots at distance d; impacts are independent when their eq. (4)
    regions (von Mises residual >= threshold x its maximum on the top
    surface) do not overlap. The strip search (when almen.rev_rule = "dmin")
    uses strip_velocity_m_s and strip_angles_deg and keeps the largest d_min;
    the target search (when target.rev_size_mm is absent) uses the target's
    velocity and angle. Both use the search settings below.
    """

    strip_velocity_m_s: Optional[Velocity] = Field(
        None, description="velocity of the strip search in m/s (default: the largest almen velocity)"
    )
    strip_angles_deg: Optional[Annotated[tuple[Angle, ...], Field(min_length=1), unique_sorted("angles")]] = Field(
        None, description="angles of the strip search (default: smallest and largest almen angle)"
    )
    threshold: OpenFraction = Field(0.05, description="eq. (4) fraction of the maximal von Mises residual stress")
    resolution_D: Optional[Positive] = Field(None, description="search resolution in shot diameters (default 0.05)")
    resolution_mm: Optional[Positive] = Field(None, description="search resolution in mm")
    min_distance_D: Positive = Field(1.0, description="smallest distance tried, in shot diameters")
    max_distance_D: Positive = Field(4.0, description="largest distance tried, in shot diameters")
    method: Literal["bisection", "scan"] = Field("bisection", description='"bisection" or "scan"')

    _fill = model_validator(mode="before")(_resolution_default)

    @model_validator(mode="after")
    def _consistent(self) -> "Dmin":
        if self.resolution_D is not None and self.resolution_mm is not None:
            raise ValueError("give one of dmin.resolution_D and dmin.resolution_mm, not both")
        if self.max_distance_D <= self.min_distance_D:
            raise ValueError(
                f"dmin.max_distance_D = {self.max_distance_D!r} must be larger than "
                f"min_distance_D = {self.min_distance_D!r}"
            )
        return self


class Coverage(StudyModel):
    """[coverage]: the Monte Carlo coverage curve on the target REV (section 3.2.2, eq. (5))."""

    grid_points: Annotated[int, check(lambda n: n >= 2, "an integer >= 2")] = Field(
        101, description="measuring-grid points per side of the measuring region"
    )
    shot_counts: Optional[
        Annotated[tuple[PositiveInt, ...], Field(min_length=2), strictly_increasing("shot counts")]
    ] = Field(None, description="shot counts at which to evaluate coverage (default: every N up to max_shots)")
    max_shots: Optional[PositiveInt] = Field(
        None, description="largest shot count of the curve (default: until full coverage is reached)"
    )
    sequences: PositiveInt = Field(6, description="number of random landing sequences")
    full_coverage_percent: Annotated[
        float, check(lambda x: 0 < x < 100, "a percentage in (0, 100)")
    ] = Field(98.0, description="coverage that counts as full (N_f), percent")

    @model_validator(mode="after")
    def _one(self) -> "Coverage":
        if self.shot_counts is not None and self.max_shots is not None:
            raise ValueError("give one of coverage.shot_counts and coverage.max_shots, not both")
        return self


def _intensity_notation(text: str) -> str:
    parse_intensity(text)  # raises ValueError with the user-facing message
    return text


def _coverage_levels(value: Any) -> Any:
    """A coverage in percent, or a tuple of distinct levels (the REV run snapshots each)."""
    def ok(x):
        return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and x > 0

    if ok(value):
        return float(value)
    if isinstance(value, tuple) and value and all(ok(x) for x in value):
        if len(set(value)) != len(value):
            raise ValueError("expected distinct coverage levels (each once)")
        return tuple(float(x) for x in value)
    raise ValueError("expected a coverage in percent > 0, or a non-empty list of them")


def _auto_or_positive_number(value: Any) -> Any:
    if value == "auto":
        return value
    if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value > 0:
        return float(value)
    raise ValueError('expected "auto" or a number > 0')


class Target(ShotScaled):
    """[target]: the real part (paper section 5)."""

    material: Material = Field(description='a material name from the library or an inline table')
    thickness_mm: Positive = Field(description="part thickness in mm")
    angle_deg: Angle = Field(description="impingement angle in degrees (90 = normal)")
    almen_intensity: Optional[Annotated[str, AfterValidator(_intensity_notation)]] = Field(
        None, description='shop-floor notation, e.g. "12A" (0.012 in on an A strip) or "0.30 mmA"'
    )
    almen_intensity_mm: Optional[Positive] = Field(None, description="Almen intensity (arc height) in mm")
    almen_strip: Optional[str] = Field(None, description='strip type of almen_intensity_mm, e.g. "A"')
    velocity_m_s: Optional[Velocity] = Field(
        None, description="shot velocity in m/s; bypasses the control curve (instead of an intensity)"
    )
    almen_strips_csv: str = Field(
        "", description="CSV of measured Almen strips (exposures and arc heights): the target intensity is "
                        "theirs by SAE J2597, with almen_strip (\"\" = none)")
    coverage_percent: Annotated[Any, AfterValidator(_coverage_levels)] = Field(
        description="coverage in percent, e.g. 200, or a list of levels, e.g. [100, 200, 400] (one REV run per "
                    "sequence, snapshotted at each level)")
    sequences: PositiveInt = Field(2, description="number of random shot sequences of the final REV run")
    control_angle_rule: Literal["nearest", "interpolate"] = Field(
        "nearest", description='"nearest" computed control-curve angle, or "interpolate" linearly between two'
    )
    rev_size_mm: Optional[Positive] = Field(None, description="REV side in mm (default 3 d_min from the two-shot search)")
    measure_size_mm: Optional[Positive] = Field(None, description="measuring-region side in mm (default rev_size_mm / 3, or d_min)")
    rev_thickness_mm: Optional[Annotated[Any, AfterValidator(_auto_or_positive_number)]] = Field(
        None, description='REV thickness in mm, or "auto" (a single-impact convergence check; default: the part '
                          'thickness)')
    measured_profile_csv: str = Field(
        "", description="CSV with columns depth_mm, stress_MPa, component for the comparison (\"\" = none)"
    )

    _measured: Optional[MeasuredProfile] = PrivateAttr(default=None)
    _strips: Optional[MeasuredStrips] = PrivateAttr(default=None)

    @model_validator(mode="after")
    def _consistent(self) -> "Target":
        given = [k for k in ("almen_intensity", "almen_intensity_mm", "velocity_m_s") if getattr(self, k) is not None]
        given += ["almen_strips_csv"] if self.almen_strips_csv else []
        if len(given) != 1:
            raise ValueError(
                "give exactly one of target.almen_intensity (e.g. \"12A\"), target.almen_intensity_mm "
                "(with almen_strip), target.almen_strips_csv (with almen_strip) or target.velocity_m_s; got "
                f"{', '.join(given) if given else 'none'}"
            )
        for key in ("almen_intensity_mm", "almen_strips_csv"):
            if getattr(self, key) and self.almen_strip is None:
                raise ValueError(f'target.{key} needs target.almen_strip (e.g. "A")')
        if self.almen_intensity is not None and self.almen_strip is not None:
            letter = parse_intensity(self.almen_intensity)[1]
            if letter != self.almen_strip:
                raise ValueError(
                    f'target.almen_intensity = "{self.almen_intensity}" is on strip {letter} but '
                    f'target.almen_strip = "{self.almen_strip}"'
                )
        if self.velocity_m_s is not None and self.almen_strip is not None:
            raise ValueError("target.almen_strip goes with an intensity, not with target.velocity_m_s")
        if isinstance(self.rev_thickness_mm, float) and self.rev_thickness_mm > self.thickness_mm:
            raise ValueError(
                f"target.rev_thickness_mm = {self.rev_thickness_mm!r} is thicker than the part "
                f"(thickness_mm = {self.thickness_mm!r})"
            )
        if self.measure_size_mm is not None and self.rev_size_mm is None:
            raise ValueError("target.measure_size_mm is only used with target.rev_size_mm")
        if self.rev_size_mm is not None and self.measure_size_mm is not None and self.measure_size_mm > self.rev_size_mm:
            raise ValueError(
                f"target.measure_size_mm = {self.measure_size_mm!r} is larger than rev_size_mm = {self.rev_size_mm!r}"
            )
        return self

    # --- resolved values -------------------------------------------------
    @property
    def measured_profile(self) -> Optional[MeasuredProfile]:
        """The measured profile as parsed when the study was loaded (None if none)."""
        return self._measured

    @property
    def measured_profile_sha256(self) -> str:
        """SHA-256 of the measured-profile CSV as it was when the study was loaded ("" if none)."""
        return self._measured.sha256 if self._measured is not None else ""

    @property
    def almen_strips(self) -> Optional[MeasuredStrips]:
        """The measured strips as read when the study was loaded (None if none): their intensity, by the
        SAE J2597 solver, is the target's (resolved with the stage parameters, :mod:`tasks.params`)."""
        return self._strips

    @property
    def intensity_mm(self) -> float | None:
        """Target Almen intensity (saturation arc height) in mm; None with a velocity override or measured
        strips (whose intensity the solver gives)."""
        if self.almen_intensity is not None:
            return parse_intensity(self.almen_intensity)[0]
        return self.almen_intensity_mm

    @property
    def intensity_strip(self) -> str | None:
        """Strip type of the target intensity ("A" for "12A")."""
        if self.almen_intensity is not None:
            return parse_intensity(self.almen_intensity)[1]
        return self.almen_strip

    @property
    def coverage_levels_percent(self) -> tuple[float, ...]:
        """The coverage levels in percent, ascending (one for a single coverage)."""
        c = self.coverage_percent
        return tuple(sorted(c)) if isinstance(c, tuple) else (c,)

    @property
    def rev_thickness_auto(self) -> bool:
        """True when the REV thickness comes from the convergence check (``"auto"``)."""
        return self.rev_thickness_mm == "auto"

    @property
    def rev_thickness_given_mm(self) -> float:
        """REV thickness in mm: rev_thickness_mm, else the part thickness (as in section 5).

        With ``"auto"`` this is the part thickness, the most the check can return;
        the REV run takes the checked value from its upstream stage."""
        given = self.rev_thickness_mm if isinstance(self.rev_thickness_mm, float) else None
        return given or self.thickness_mm


class Seeds(StudyModel):
    """[seeds]: reproducible random shot sequences."""

    base: Annotated[int, check(lambda n: 0 <= n < 2**63, "an integer in [0, 2**63)")] = Field(
        1, description="base seed; sequence k of a stream uses seed(stream, k)"
    )

    def seed(self, stream: str, k: int) -> int:
        """Seed of sequence k of a named stream ("almen", "coverage", "target", ...).

        A 63-bit integer from SHA-256 of (base, stream, k): the same in every
        process and on every machine, and unrelated between streams. Using the
        same seed for every velocity of a sweep (common random numbers) makes
        control curves smoother than independent draws.
        """
        if k < 0:
            raise ValueError("sequence index k must be >= 0")
        digest = hashlib.sha256(f"peenflow-seed:{self.base}:{stream}:{k}".encode()).digest()
        return int.from_bytes(digest[:8], "little") & (2**63 - 1)

    def seeds(self, stream: str, n: int) -> tuple[int, ...]:
        return tuple(self.seed(stream, k) for k in range(n))


def _auto_or_positive(value: Any) -> Any:
    if value == "auto" or (isinstance(value, int) and not isinstance(value, bool) and value >= 1):
        return value
    raise ValueError('expected "auto" or an integer >= 1')


class Execution(StudyModel):
    """[execution]: how to run (never part of a result's key)."""

    workers: Annotated[Any, AfterValidator(_auto_or_positive)] = Field(
        "auto", description='dask workers: "auto" or an integer >= 1'
    )
    threads_per_worker: Annotated[Any, AfterValidator(_auto_or_positive)] = Field(
        "auto", description='numba threads per worker: "auto" or an integer >= 1'
    )
