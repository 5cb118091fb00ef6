"""Typed stage parameters: the one translation from a validated study to the stages and the kernel.

A study file holds values in the units its users think in (mm, um, GPa,
MPa), and the study models keep them; the stages and the FE/DEM kernel work
in SI.  This module is where a study becomes SI (with the factors of
:mod:`peenflow.units`): :func:`study_params` reads a validated
:class:`peenflow.study.Study` once into frozen dataclasses in SI (m, Pa,
kg m-3, m s-1, s), and each dataclass has

* one canonical form, ``__canonical__()`` -- every field, by its own name --
  which is what the engine hashes into the result key (so a key follows
  every field, and nothing outside the key reaches a stage: the engine
  calls the stage with the parameters rebuilt from that canonical form by
  ``from_canonical``, see :mod:`peenflow.engine.task`);
* where the kernel needs one, one conversion to the kernel's object
  (:meth:`MaterialParams.to_kernel` -> :class:`peenflow.fe.johnson_cook.Material`,
  :meth:`FidelityParams.options` -> :class:`peenflow.fe.impact.Options`,
  :meth:`FidelityParams.boundary` -> :class:`peenflow.fe.model.Target`,
  :meth:`ShotParams.shots` -> :class:`peenflow.fe.shots.Shots`).

No default is set here a second time: a value the study leaves out is the
study schema's default (``peenflow.study``), or -- where the study says
nothing (``room_temperature_K`` without a thermal term) -- the kernel's own.

Length: the one translation, kept whole on purpose: every stage's typed
record (about twenty, each a few fields with its unit) and the functions that
fill them are in this module so that no unit is converted anywhere else.
"""

from __future__ import annotations

import math
import typing
from dataclasses import dataclass, fields
from functools import cache
from pathlib import Path

import numpy as np

from peenflow.fe.impact import Options
from peenflow.fe.johnson_cook import Material
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots
from peenflow.methods import RevGeometry, impingement_direction
from peenflow.study.measured_profile import MeasuredProfile
from peenflow.units import GPA, MM, MPA, UM

__all__ = ["StageParams", "MaterialParams", "ShotParams", "FidelityParams", "DminParams", "CoverageParams",
           "StripParams", "LadderParams", "SequencesParams", "RevParams", "TargetParams", "PlateParams", "MeasuredProfile",
           "StripSweep", "TargetPlan", "FidelityLevels", "StudyParams", "study_params", "StudyFamily", "study_family",
           "RequirementParams", "requirements_params"]


@dataclass(frozen=True)
class StageParams:
    """Base of the typed parameters: the canonical form and its inverse.

    Fields are numbers, strings, booleans, None, tuples of them, or nested
    :class:`StageParams`; tuples come back from the canonical form (JSON
    lists) as tuples.
    """

    def __canonical__(self) -> dict:
        """Every field by name (nested parameters as their own canonical dicts)."""
        return {f.name: _canonical_field(getattr(self, f.name)) for f in fields(self)}

    @classmethod
    def from_canonical(cls, value):
        """The parameters from their canonical form (a dict of every field), or ``value`` if already typed."""
        if isinstance(value, cls):
            return value
        if not isinstance(value, dict):
            raise TypeError(f"{cls.__name__}: expected a dict of its fields, got {type(value).__name__}")
        names = {f.name for f in fields(cls)}
        if set(value) != names:
            raise TypeError(f"{cls.__name__}: fields {sorted(value)} given, expected {sorted(names)}")
        hints = _hints(cls)
        return cls(**{k: _from_canonical_field(hints[k], v) for k, v in value.items()})


def _canonical_field(v):
    if isinstance(v, StageParams):
        return v.__canonical__()
    if isinstance(v, tuple):
        return [_canonical_field(x) for x in v]
    return v


@cache
def _hints(cls) -> dict:
    return typing.get_type_hints(cls)


def _from_canonical_field(hint, v):
    if v is None:
        return None
    for t in typing.get_args(hint) or (hint,):  # X | None: the non-None member
        if isinstance(t, type) and issubclass(t, StageParams):
            return t.from_canonical(v)
    if isinstance(v, list):
        return tuple(v)
    return v


# -- materials, shot, mesh and kernel settings --------------------------------------------------------------
@dataclass(frozen=True)
class MaterialParams(StageParams):
    """Isotropic elastic + Johnson-Cook plastic material (paper eq. 1), SI.

    ``youngs_modulus_Pa`` E (Pa), ``poisson_ratio`` nu (1), ``density_kg_m3``;
    ``A_Pa``, ``B_Pa`` (Pa), ``n``, ``C``, ``m`` (1), ``reference_strain_rate_1_s``
    (s-1); ``room_temperature_K`` / ``melt_temperature_K`` (K, None: the
    study gave none, m = 0, and the kernel's own values apply).
    """

    youngs_modulus_Pa: float
    poisson_ratio: float
    density_kg_m3: float
    A_Pa: float
    B_Pa: float
    n: float
    C: float
    m: float
    reference_strain_rate_1_s: float
    room_temperature_K: float | None
    melt_temperature_K: float | None

    @classmethod
    def from_study(cls, material) -> "MaterialParams":
        """From a study :class:`peenflow.study.items.Material` (GPa, MPa there)."""
        jc = material.johnson_cook
        return cls(material.youngs_modulus_GPa * GPA, material.poisson_ratio, material.density_kg_m3,
                   jc.A_MPa * MPA, jc.B_MPa * MPA, jc.n, jc.C, jc.m, jc.reference_strain_rate_1_s,
                   jc.room_temperature_K, jc.melt_temperature_K)

    def kernel_kwargs(self) -> dict:
        """The keyword arguments of the kernel's :class:`~peenflow.fe.johnson_cook.Material` (SI); the
        temperatures only where the study gives them (the kernel's own otherwise)."""
        temperatures = {k: v for k, v in (("T_room", self.room_temperature_K), ("T_melt", self.melt_temperature_K))
                        if v is not None}
        return dict(E=self.youngs_modulus_Pa, nu=self.poisson_ratio, density=self.density_kg_m3, A=self.A_Pa,
                    B=self.B_Pa, n=self.n, C=self.C, m=self.m, ref_strain_rate=self.reference_strain_rate_1_s,
                    **temperatures)

    def to_kernel(self) -> Material:
        return Material(**self.kernel_kwargs())


@dataclass(frozen=True)
class ShotParams(StageParams):
    """A rigid spherical shot: ``radius_m`` (m), ``density_kg_m3``, Coulomb ``friction_coefficient`` (1)."""

    radius_m: float
    density_kg_m3: float
    friction_coefficient: float

    @classmethod
    def from_study(cls, shot) -> "ShotParams":
        """From a study's ``[shot]`` section (diameter in mm there)."""
        return cls(0.5 * shot.diameter_mm * MM, shot.density_kg_m3, shot.friction_coefficient)

    @property
    def diameter_m(self) -> float:
        return 2.0 * self.radius_m

    def aimed(self, speed: float, angle_deg: float, landing_xy=(0.0, 0.0), gap: float | None = None) -> tuple:
        """(centre (3,) m, velocity (3,) m s-1) of a shot at ``speed`` (m s-1) that first
        touches z = 0 at ``landing_xy`` (m), starting ``gap`` (m; 2 % of the radius) away."""
        u = impingement_direction(angle_deg)
        gap = 0.02 * self.radius_m if gap is None else gap
        centre = np.array([landing_xy[0], landing_xy[1], -self.radius_m]) - gap / u[2] * u
        return centre, speed * u

    def shots(self, centres, velocities, radii=None) -> Shots:
        """The kernel's shots: centres (n, 3) m, velocities (n, 3) m s-1, and each shot's radius (n,) m
        where a stream has a size spread (None: every shot ``radius_m``)."""
        return Shots(np.asarray(centres, float).reshape(-1, 3), np.asarray(velocities, float).reshape(-1, 3),
                     self.radius_m if radii is None else np.asarray(radii, float), self.density_kg_m3)


@dataclass(frozen=True)
class StreamParams(StageParams):
    """How a REV run's shots scatter (``[shot]`` spreads): ``diameter_spread`` and ``velocity_spread``,
    relative standard deviations (1) of each shot's diameter and speed about the nominal ones (0: the
    paper's stream of identical shots; :func:`peenflow.methods.shot_stream`)."""

    diameter_spread: float
    velocity_spread: float

    @classmethod
    def from_study(cls, shot) -> "StreamParams":
        """From a study's ``[shot]`` section (per cent there)."""
        return cls(shot.diameter_spread_percent / 100.0, shot.velocity_spread_percent / 100.0)

    @property
    def any(self) -> bool:
        return self.diameter_spread > 0.0 or self.velocity_spread > 0.0


@dataclass(frozen=True)
class FidelityParams(StageParams):
    """Mesh and kernel settings of ``[fidelity]``, SI.

    ``element_size_m`` (fine element edge), ``fine_depth_m`` (depth of the fine
    zone), ``grading_ratio`` (1), ``time_step_safety`` (fraction of the
    stable step), ``window_contact_radii`` (active window half size in
    estimated contact radii; 0 = whole mesh), ``settle_tolerance`` /
    ``relaxation_tolerance`` (kinetic energy / impact energy at rest),
    ``lateral_boundary`` ("symmetric" | "periodic", REV lateral faces).
    """

    element_size_m: float
    fine_depth_m: float
    grading_ratio: float
    time_step_safety: float
    window_contact_radii: float
    settle_tolerance: float
    relaxation_tolerance: float
    lateral_boundary: str

    @classmethod
    def from_study(cls, f) -> "FidelityParams":
        """From a study's ``[fidelity]`` (um, mm or shot diameters there)."""
        fine_depth = f.fine_depth_mm * MM if f.fine_depth_mm is not None else \
            f.fine_depth_D * (f.shot_diameter_mm * MM)
        return cls(f.element_size_um * UM, fine_depth, f.grading_ratio, f.time_step_safety,
                   f.window_contact_radii, f.settle_tolerance, f.relaxation_tolerance, f.lateral_boundary)

    def options(self, shot: ShotParams, threads: int = 1, record: bool = False, record_every: int = 1) -> Options:
        """The kernel's options.

        The window is sized in the kernel's estimated contact radius, so one
        setting suits steel strips and soft targets alike (0: no window, the
        kernel's own window sizes unused).  Settling and relaxation end when
        the kinetic energy falls below the tolerance times the impact energy
        and every nodal speed below ``0.1 sqrt(tolerance)`` times the shot
        speed (the kernel's two rest criteria; the standard preset gives the
        kernel's defaults).  The window's minimum size (in elements and in
        wave travel) is the kernel's own (``Options.window_min_elements``,
        ``window_min_wave``).
        """
        w = self.window_contact_radii
        window = {"window": True, "window_lateral": w, "window_depth": w} if w > 0 else {"window": False}
        return Options(
            dt_safety=self.time_step_safety, friction=shot.friction_coefficient, **window,
            rest_ke_fraction=self.settle_tolerance, rest_v_fraction=0.1 * math.sqrt(self.settle_tolerance),
            relax_ke_fraction=self.relaxation_tolerance, relax_v_fraction=0.1 * math.sqrt(self.relaxation_tolerance),
            threads=threads, record=record, record_every=record_every,
            # a preset's window is its measured choice: the result records when it
            # lies outside the kernel's validated envelope instead of a warning per call
            window_warning=False,
        )

    def boundary(self, mesh, impact_block: bool = False) -> Target:
        """The kernel's target: fixed bottom; lateral faces from ``lateral_boundary`` for a REV.

        An impact block (single impact, two shots) is a quarter / half model
        whose faces through the impact are symmetry planes, so its lateral
        faces stay symmetric whatever the key says ("periodic" needs the REV's
        uniform lateral spacing, and would tie a symmetry plane to the far face).
        """
        return Target(mesh, lateral="symmetric" if impact_block else self.lateral_boundary, bottom="fixed")


# -- the method's settings ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class DminParams(StageParams):
    """The two-shot d_min search (eq. 4): ``threshold`` (fraction of the peak von Mises),
    ``resolution_m``, ``min_distance_m``, ``max_distance_m`` (m), ``method`` ("bisection" | "scan")."""

    threshold: float
    resolution_m: float
    min_distance_m: float
    max_distance_m: float
    method: str

    @classmethod
    def from_study(cls, d) -> "DminParams":
        """From a study's ``[dmin]`` (mm or shot diameters there)."""
        D = d.shot_diameter_mm * MM
        resolution = d.resolution_mm * MM if d.resolution_mm is not None else d.resolution_D * D
        return cls(d.threshold, resolution, d.min_distance_D * D, d.max_distance_D * D, d.method)


@dataclass(frozen=True)
class CoverageParams(StageParams):
    """The Monte-Carlo coverage curve (eq. 5): ``shot_radius_m`` (m), ``grid_points`` per side of
    the measuring grid, ``max_shots`` or ``shot_counts`` (None: automatic), ``sequences`` and
    their ``seeds``, ``full_coverage_percent`` (%, the coverage of N_f)."""

    shot_radius_m: float
    grid_points: int
    max_shots: int | None
    shot_counts: tuple[int, ...] | None
    sequences: int
    seeds: tuple[int, ...]
    full_coverage_percent: float


@dataclass(frozen=True)
class StripParams(StageParams):
    """The Almen strip as the arc height sees it (eqs. 6-9): ``width_m``, ``thickness_m``,
    ``gauge_span_m`` (m), ``youngs_modulus_Pa`` (Pa) of its material."""

    width_m: float
    thickness_m: float
    youngs_modulus_Pa: float
    gauge_span_m: float

    @classmethod
    def from_study(cls, strip) -> "StripParams":
        """From a study's strip (mm, GPa there)."""
        return cls(strip.width_mm * MM, strip.thickness_mm * MM, strip.material.youngs_modulus_GPa * GPA,
                   strip.gauge_span_mm * MM)


@dataclass(frozen=True)
class LadderParams(StageParams):
    """A strip ladder that extends itself (``almen.shot_counts = "auto"``): doubling from
    ``first_shots`` to at most ``max_shots``, stopping by the saturation ``fit``'s verdict
    on the arc heights of ``strip``."""

    first_shots: int
    max_shots: int
    fit: str
    strip: StripParams


@dataclass(frozen=True)
class SequencesParams(StageParams):
    """Adaptive sequences (``almen.sequence_tolerance_mm``): from ``start`` to at most ``cap``
    sequences per (angle, velocity), until the 95 % upper bound of the standard error of the
    per-sequence intensities (eq. 11 by ``fit`` on the arc heights of ``strip``) is at most
    ``tolerance_m`` (m)."""

    tolerance_m: float
    start: int
    cap: int
    fit: str
    strip: StripParams

    def verdict(self, intensities_m):
        """:func:`peenflow.methods.sequences_verdict` of the per-sequence intensities so far (m)."""
        from peenflow.methods import sequences_verdict

        return sequences_verdict(intensities_m, self.tolerance_m, n_min=self.start, n_max=self.cap)

    def describe(self) -> str:
        return (f"tolerance {self.tolerance_m / MM:g} mm on the standard error (95 % bound), "
                f"{self.start} to {self.cap} sequences")


@dataclass(frozen=True)
class ExtrapolationParams(StageParams):
    """Paired two-level extrapolation of the Almen intensities (``fidelity.extrapolate_intensity_from_um``):
    element sizes of the ``coarse_element_size_m`` and ``fine_element_size_m`` levels (m) and the
    ``order`` p of I(h) = I0 + c h^p; ``order_measured``: whether p is the measured default
    (peenflow.study.accuracy.INTENSITY_ORDER) rather than the study's own."""

    coarse_element_size_m: float
    fine_element_size_m: float
    order: float
    order_measured: bool

    def describe(self) -> str:
        how = "measured order" if self.order_measured else "order given by the study"
        return (f"extrapolated to zero element size from {self.coarse_element_size_m / UM:g} and "
                f"{self.fine_element_size_m / UM:g} um, paired sequences, {how} {self.order:g}")


@dataclass(frozen=True)
class RevParams(StageParams):
    """The REV rule's inputs: ``rule`` ("dmin" | "paper" | "explicit"), ``thickness_m``,
    ``shot_diameter_m``, and the given ``side_m`` / ``measure_side_m`` (m, None: by the rule)."""

    rule: str
    thickness_m: float
    shot_diameter_m: float
    side_m: float | None
    measure_side_m: float | None

    def geometry(self, d_min: float | None = None) -> RevGeometry:
        """The REV's top surface by the rule (:meth:`peenflow.methods.RevGeometry.by_rule`); ``d_min`` m."""
        return RevGeometry.by_rule(self.rule, self.shot_diameter_m, d_min=d_min, side=self.side_m,
                                   measuring_side=self.measure_side_m)


@dataclass(frozen=True)
class TargetParams(StageParams):
    """How the target's velocity is found: given (``velocity_m_s``, m s-1), or read off
    the control curve at ``intensity_m`` (m, Almen arc height) and ``angle_deg`` by
    ``rule`` ("nearest" | "interpolate") through the ``interpolation`` ("pchip" |
    "linear") the control curve uses; ``allow_extrapolated`` accepts points
    saturated beyond their ladder."""

    angle_deg: float
    velocity_m_s: float | None
    intensity_m: float | None
    rule: str
    interpolation: str | None
    allow_extrapolated: bool


@dataclass(frozen=True)
class PlateParams(StageParams):
    """The part as a plate peened on one face, for its free profile: ``thickness_m`` (m),
    ``youngs_modulus_Pa`` (Pa), ``poisson_ratio`` (1)."""

    thickness_m: float
    youngs_modulus_Pa: float
    poisson_ratio: float


# -- what the graph is built from, besides the stage parameters ---------------------------------------------
@dataclass(frozen=True)
class StripSweep:
    """The strip side of the graph (``[almen]``, ``[dmin]``): what it sweeps and how it reads the strips.

    ``angles_deg`` x ``velocities_m_s`` (deg, m s-1) are the control-curve points; ``seeds[k]`` is the shot
    stream of sequence k (``sequences_cap`` of them: every sequence a point may grow to); ``shot_counts``
    the given ladder (None: it extends itself, :class:`LadderParams`); ``dmin_angles_deg`` /
    ``dmin_velocity_m_s`` the two-shot search's (None unless ``rev_rule`` is "dmin")."""

    angles_deg: tuple[float, ...]
    velocities_m_s: tuple[float, ...]
    sequences_cap: int
    seeds: tuple[int, ...]
    shot_counts: tuple[int, ...] | None
    saturation_fit: str
    interpolation: str
    rev_rule: str
    dmin_angles_deg: tuple[float, ...] | None
    dmin_velocity_m_s: float | None


@dataclass(frozen=True)
class TargetPlan:
    """The target side of the graph (``[target]``) beyond :class:`TargetParams`: the coverage levels
    ``coverage_levels_percent`` (%, ascending: one REV run per sequence reaches them all), ``sequences`` REV
    runs with shot streams ``seeds``, the part's ``thickness_m`` and the REV's ``rev_thickness_m`` (m; with
    ``rev_thickness_auto`` the most the convergence check may return); ``intensity_source``: where the target
    intensity came from when it was not given as a number (measured strips: the file, the fit and its verdict;
    recorded on the velocity's result), else ""."""

    coverage_levels_percent: tuple[float, ...]
    sequences: int
    seeds: tuple[int, ...]
    thickness_m: float
    rev_thickness_m: float
    rev_thickness_auto: bool
    intensity_source: str = ""


@dataclass(frozen=True)
class FidelityLevels:
    """What made a result, for its fidelity statement (:func:`peenflow.study.accuracy.statement`): the
    preset and its overrides (``describe()``), the element sizes of each level (um, as the file gives
    them and as the measured errors are tabled), the order of an intensity extrapolation, the dent's
    refinement, the lateral faces and the active window's size (contact radii; 0: the whole mesh)."""

    description: str
    element_size_um: float
    lateral_boundary: str
    extrapolate_intensity_from_um: float | None
    intensity_order: float
    dent_element_size_um: float | None
    dent_refinement: str
    window_contact_radii: float

    def describe(self) -> str:
        return self.description


@dataclass(frozen=True)
class StudyParams:
    """Every parameter the graph is built from (None where its section is absent): the stage
    parameters (hashed into result keys) and what the graph sweeps, seeds and labels (not hashed)."""

    #: the study's name and file (its reports go beside its store, one folder per file)
    name: str
    path: Path
    shot: ShotParams
    #: the REV runs' shot scatter (size and speed spreads)
    stream: StreamParams
    fidelity: FidelityParams
    dmin: DminParams
    strip_material: MaterialParams | None
    strip: StripParams | None
    strip_rev: RevParams | None
    ladder: LadderParams | None
    sequences: SequencesParams | None
    coverage: CoverageParams
    target_material: MaterialParams | None
    target: TargetParams | None
    target_rev: RevParams | None
    plate: PlateParams | None
    measured: MeasuredProfile | None
    #: the strip side's sweep (None without ``[almen]``) and the target's (None without ``[target]``)
    strips: StripSweep | None
    target_plan: TargetPlan | None
    #: the fidelity as its statement names it
    levels: FidelityLevels
    #: execution defaults (``[execution]``; None: the command line's or the machine's)
    workers: int | None
    threads: int | None
    #: names a person reads in the plots: shot, strip, target material (None where absent)
    names: dict
    #: the intensity extrapolation and its coarse level's fidelity (None without one)
    extrapolation: ExtrapolationParams | None = None
    coarse_fidelity: FidelityParams | None = None
    #: the fidelity of the target's single impact (its dent ellipse, N_f, N_c): the study's, or that at
    #: ``fidelity.dent_element_size_um``
    dent_fidelity: FidelityParams | None = None
    #: the element size (m) of a core under the target's single impact (``fidelity.dent_refinement = "core"``;
    #: its block is then at ``dent_fidelity``, the study's), else None
    dent_core_element_size_m: float | None = None


def study_params(study) -> StudyParams:
    """All stage parameters of a validated study, in SI (module docstring)."""
    shot = ShotParams.from_study(study.shot)
    D = shot.diameter_m
    c = study.coverage
    coverage = CoverageParams(
        shot_radius_m=shot.radius_m, grid_points=c.grid_points, max_shots=c.max_shots,
        shot_counts=None if c.shot_counts is None else tuple(int(n) for n in c.shot_counts), sequences=c.sequences,
        seeds=tuple(study.seeds.seeds("coverage", c.sequences)), full_coverage_percent=c.full_coverage_percent)
    strip_material = strip = strip_rev = ladder = sequences = strips = None
    if (a := study.almen) is not None:
        strip_material = MaterialParams.from_study(a.strip.material)
        strip = StripParams.from_study(a.strip)
        # the strip REV is as thick as the strip (section 4.1)
        strip_rev = RevParams(a.rev_rule, strip.thickness_m, D, _mm(a.rev_size_mm), _mm(a.measure_size_mm))
        if a.ladder_auto:
            ladder = LadderParams(a.ladder_first_shots, a.ladder_max_shots, a.saturation_fit, strip)
        if a.sequences_adaptive:
            sequences = SequencesParams(a.sequence_tolerance_mm * MM, a.sequences, a.sequences_cap,
                                        a.saturation_fit, strip)
        by_dmin = a.rev_rule == "dmin"
        strips = StripSweep(
            angles_deg=tuple(a.angles_deg), velocities_m_s=tuple(a.velocities_m_s), sequences_cap=a.sequences_cap,
            seeds=tuple(study.seeds.seeds("almen", a.sequences_cap)),
            shot_counts=None if a.ladder_auto else tuple(int(n) for n in a.shot_counts),
            saturation_fit=a.saturation_fit, interpolation=a.interpolation, rev_rule=a.rev_rule,
            dmin_angles_deg=tuple(study.dmin.strip_angles_deg) if by_dmin else None,
            dmin_velocity_m_s=study.dmin.strip_velocity_m_s if by_dmin else None)
    target_material = target = target_rev = plate = measured = target_plan = None
    if (t := study.target) is not None:
        target_material = MaterialParams.from_study(t.material)
        given = t.velocity_m_s is not None
        intensity_m, source = _target_intensity(study, t)
        target = TargetParams(
            angle_deg=t.angle_deg, velocity_m_s=t.velocity_m_s, intensity_m=intensity_m,
            rule=t.control_angle_rule, interpolation=None if given else study.almen.interpolation,
            allow_extrapolated=bool(study.almen and study.almen.allow_extrapolated_intensity))
        rev_thickness_m = t.rev_thickness_given_mm * MM
        target_rev = RevParams("dmin" if t.rev_size_mm is None else "explicit", rev_thickness_m, D,
                               _mm(t.rev_size_mm), _mm(t.measure_size_mm))
        plate = PlateParams(t.thickness_mm * MM, target_material.youngs_modulus_Pa, target_material.poisson_ratio)
        measured = t.measured_profile
        target_plan = TargetPlan(coverage_levels_percent=t.coverage_levels_percent, sequences=t.sequences,
                                 seeds=tuple(study.seeds.seeds("target", t.sequences)), thickness_m=t.thickness_mm * MM,
                                 rev_thickness_m=rev_thickness_m, rev_thickness_auto=t.rev_thickness_auto,
                                 intensity_source=source)
    f = study.fidelity
    fidelity = FidelityParams.from_study(f)
    levels = FidelityLevels(f.describe(), f.element_size_um, f.lateral_boundary, f.extrapolate_intensity_from_um,
                            f.intensity_order, f.dent_element_size_um, f.dent_refinement, f.window_contact_radii)
    extrapolation = coarse_fidelity = None
    if (hc := f.extrapolate_intensity_from_um) is not None:
        extrapolation = ExtrapolationParams(hc * UM, fidelity.element_size_m, f.intensity_order,
                                            f.intensity_extrapolation_order is None)
        # computed as a study at that element size computes it, so such a study's strip results are shared
        coarse_fidelity = FidelityParams.from_study(f.model_copy(update={"element_size_um": hc}))
    dent_fidelity, dent_core = fidelity, None
    if (hd := f.dent_element_size_um) is not None:
        if f.dent_refinement == "core":  # the study's block, a core of hd under the impact
            dent_core = hd * UM
        else:  # as a study at that element size computes its single impact, so the two share it
            dent_fidelity = FidelityParams.from_study(f.model_copy(update={"element_size_um": hd}))
    ex = study.execution
    names = {"shot": study.shot.name, "strip": a.strip.name if a is not None else None,
             "target_material": t.material.name if t is not None else None}
    return StudyParams(
        name=study.name, path=Path(study.path), shot=shot, stream=StreamParams.from_study(study.shot),
        fidelity=fidelity,
        dmin=DminParams.from_study(study.dmin), strip_material=strip_material, strip=strip, strip_rev=strip_rev,
        ladder=ladder, sequences=sequences, coverage=coverage, target_material=target_material, target=target,
        target_rev=target_rev, plate=plate, measured=measured, strips=strips, target_plan=target_plan,
        levels=levels, workers=ex.workers if isinstance(ex.workers, int) else None,
        threads=ex.threads_per_worker if isinstance(ex.threads_per_worker, int) else None, names=names,
        extrapolation=extrapolation, coarse_fidelity=coarse_fidelity, dent_fidelity=dent_fidelity,
        dent_core_element_size_m=dent_core)


def _target_intensity(study, t) -> tuple[float | None, str]:
    """The target intensity (m; None with a given velocity) and where it came from ("" for a number in the
    file). Measured strips (``target.almen_strips_csv``) are solved here by SAE J2597
    (:func:`tasks.measured_intensity.almen_strips_intensity`); strips no fit can use raise
    :class:`peenflow.study.StudyError` naming the key, before compute."""
    if t.velocity_m_s is not None:
        return None, ""
    if t.almen_strips is None:
        return t.intensity_mm * MM, ""
    from peenflow.study import StudyError
    from peenflow.study.almen_strips import AlmenStripsError, shop_notation

    from .measured_intensity import almen_strips_intensity

    name = Path(t.almen_strips_csv).name
    try:
        fit = almen_strips_intensity(t.almen_strips, name)
    except AlmenStripsError as exc:
        raise StudyError(study.path, [f"target.almen_strips_csv: {p}" for p in exc.problems]) from None
    return fit.intensity_m, (f"measured strips {name} (sha256 {t.almen_strips.sha256[:12]}): "
                             f"{fit.intensity_m / MM:.4f} mm = {shop_notation(fit.intensity_m, t.almen_strip)} by "
                             f"the {fit.model} fit of {fit.n_strips} strips at {fit.n_exposures} exposures"
                             f"{'' if fit.qualified else ' (NOT QUALIFIED)'}; {fit.reason}")


def _mm(value: float | None) -> float | None:
    return None if value is None else value * MM


# -- a family of studies: the process dimensions ------------------------------------------------------------
@dataclass(frozen=True)
class StudyFamily:
    """A study with process dimensions (``[target]`` lists, ``[targets.NAME]``, ``[sweep]``): its ``dims``
    (:class:`peenflow.study.variants.Dim`, SI), one :class:`StudyParams` per combination with its coordinates
    (``points``: ``(coords, params)``, the last dimension fastest; a named value -- a material, a named
    target -- is its index in the dimension's values), and the ``[requirements]`` (None without)."""

    dims: tuple
    points: tuple
    requirements: object = None

    @property
    def first(self) -> StudyParams:
        return self.points[0][1]


def study_family(study) -> StudyFamily:
    """Every combination of a validated study's process dimensions, in SI (a single point: one, no dims)."""
    dims = tuple(study.dims)
    points = []
    for coords, variant in study.variants:
        coords = {d.name: (d.values.index(coords[d.name]) if d.labels else coords[d.name]) for d in dims}
        points.append((coords, study_params(variant)))
    return StudyFamily(dims, tuple(points), study.requirements)


@dataclass(frozen=True)
class RequirementParams(StageParams):
    """``[requirements]`` in SI: ``bounds``, one ``(map variable, CF units, min, max, the file's key)`` per
    feature (min / max None where not given), and the setting to minimise (a process dimension,
    ``coverage_percent``, or ``shots``: N_c)."""

    bounds: tuple[tuple, ...]
    minimise: str


def requirements_params(requirements, dims=()) -> RequirementParams:
    """The typed requirements of a validated ``[requirements]`` table."""
    from peenflow.study.requirements import FEATURES

    bounds = []
    for key, b in sorted(requirements.bounds.items()):
        variable, units, factor, _ = FEATURES[key]
        bounds.append((variable, units, None if b.min is None else b.min * factor,
                       None if b.max is None else b.max * factor, key))
    return RequirementParams(tuple(bounds), requirements.minimise)
