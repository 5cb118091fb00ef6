"""The loaded study: resolved sections, stages, canonical form.

A :class:`Study` is what :func:`peenflow.study.load_study` returns: frozen,
validated, with library references replaced by the objects themselves
(``study.target.material`` is a :class:`Material`, not a name).
"""

from __future__ import annotations

import bisect
import hashlib
from pathlib import Path
from typing import Optional

from pydantic import Field, model_validator

from .canonical import canonical, canonical_json
from .fidelity import Fidelity, expand_preset
from .sections import Almen, Coverage, Dmin, Execution, Seeds, ShotSection, Target
from .types import Name, StudyModel

__all__ = ["Study", "StudyInfo", "STAGES", "SCHEMA_VERSION"]

SCHEMA_VERSION = 1

#: Every stage a study can ask for, in dependency order.
#:  strip_dmin      two-shot search on the Almen strip (almen.rev_rule = "dmin")
#:  control_curves  strip REV runs -> arc heights -> saturation -> intensity vs velocity
#:  target_dmin     two-shot search on the target (no target.rev_size_mm)
#:  coverage        single impact on the target -> dent -> Monte Carlo coverage -> N_f, N_c
#:  residual_stress final target REV runs (N_c shots, target.sequences sequences)
#:  comparison      residual stress vs the measured profile (target.measured_profile_csv)
STAGES: tuple[str, ...] = (
    "strip_dmin", "control_curves", "target_dmin", "coverage", "residual_stress", "comparison",
)


class StudyInfo(StudyModel):
    """[study]: name, description, and where the rest came from."""

    name: Name = Field(description="study name (letters, digits, _ . + -)")
    description: str = ""
    include: tuple[str, ...] = Field(("peenflow:library",), description="library files included (resolved)")
    extends: Optional[str] = Field(None, description="parent study file, as written")
    allow_outside_bounds: tuple[str, ...] = Field(
        (), description="keys allowed outside their validated range (docs/study-files.md, Bounds); not inherited")


class Study(StudyModel):
    """A validated study. Fields mirror the file's sections."""

    info: StudyInfo
    path: Path = Field(Path(), description="absolute path of the study file")
    extends_chain: tuple[Path, ...] = Field((), description="the study file, then its parents (absolute paths)")
    shot: ShotSection
    almen: Optional[Almen] = None
    dmin: Dmin = Field(default_factory=Dmin)
    coverage: Coverage = Field(default_factory=Coverage)
    target: Optional[Target] = None
    fidelity: Fidelity = Field(default_factory=lambda: Fidelity.model_validate(expand_preset({})))
    seeds: Seeds = Field(default_factory=Seeds)
    execution: Execution = Field(default_factory=Execution)

    @model_validator(mode="after")
    def _share_shot_diameter(self) -> "Study":
        d = self.shot.diameter_m
        for section in (self.almen, self.dmin, self.target, self.fidelity):
            if section is not None:
                section._shot_diameter_m = d
        # Fix the measured profile's content now: the key must not change under a loaded study.
        if self.target is not None and self.target.measured_profile_csv:
            csv = Path(self.target.measured_profile_csv)
            if csv.is_file():
                self.target._profile_sha256 = hashlib.sha256(csv.read_bytes()).hexdigest()
        return self

    @model_validator(mode="after")
    def _periodic_rev_fits_a_contact(self) -> "Study":
        """Periodic REV faces: each shot's contact zone (the kernel's search box,
        1.25 R each side, plus 2 elements) must fit in half a period."""
        if self.fidelity.lateral_boundary != "periodic":
            return self
        need = 1.25 * self.shot.diameter_m + 4.0 * self.fidelity.element_size_m
        for name, section in (("almen", self.almen), ("target", self.target)):
            size = getattr(section, "rev_size_mm", None) if section is not None else None
            if size is not None and size * 1e-3 <= need:
                raise ValueError(
                    f'{name}.rev_size_mm = {size}: with fidelity.lateral_boundary = "periodic" the REV side must '
                    f"exceed 1.25 D + 4 elements = {need * 1e3:.3g} mm (a shot's contact zone must fit in half "
                    "a period)")
        return self

    # --- identity --------------------------------------------------------
    @property
    def name(self) -> str:
        return self.info.name

    @property
    def description(self) -> str:
        return self.info.description

    @property
    def directory(self) -> Path:
        """The study file's folder (the default store lives beside it)."""
        return self.path.parent

    # --- what to run -----------------------------------------------------
    def stages(self) -> tuple[str, ...]:
        """The stages this study runs, in dependency order (a subset of STAGES).

        No [target] -> stops at the control curves; no [almen] (target with
        velocity_m_s) -> no control curves; a target REV size given -> no
        target d_min search; no measured profile -> no comparison.
        """
        out: list[str] = []
        if self.almen is not None:
            if self.almen.rev_rule == "dmin":
                out.append("strip_dmin")
            out.append("control_curves")
        if self.target is not None:
            if self.target.rev_size_mm is None:
                out.append("target_dmin")
            out += ["coverage", "residual_stress"]
            if self.target.measured_profile_csv:
                out.append("comparison")
        return tuple(out)

    def runs(self, stage: str) -> bool:
        if stage not in STAGES:
            raise ValueError(f"unknown stage {stage!r}; stages are {', '.join(STAGES)}")
        return stage in self.stages()

    # --- target <-> control curves ---------------------------------------
    def control_angles(self) -> tuple[tuple[float, float], ...]:
        """(almen angle in deg, weight) pairs that give the target's control curve.

        "nearest": the computed angle closest to target.angle_deg (ties go to
        the larger, more normal angle), weight 1. "interpolate": the two
        bracketing angles with linear weights (one angle, weight 1, on a hit).
        Empty when the target gives velocity_m_s directly.
        """
        if self.target is None or self.almen is None or self.target.velocity_m_s is not None:
            return ()
        angles = self.almen.angles_deg
        theta = self.target.angle_deg
        if self.target.control_angle_rule == "nearest":
            best = min(angles, key=lambda a: (abs(a - theta), -a))
            return ((best, 1.0),)
        if theta in angles:
            return ((theta, 1.0),)
        i = bisect.bisect_left(angles, theta)
        lo, hi = angles[i - 1], angles[i]  # validated: theta inside the computed range
        w_hi = (theta - lo) / (hi - lo)
        return ((lo, 1.0 - w_hi), (hi, w_hi))

    # --- canonical form ----------------------------------------------------
    def to_canonical_dict(self) -> dict:
        """JSON-able, sorted dict of everything that determines the results.

        Excludes the name, description, paths and [execution] (they do not
        change results) and the fidelity preset name (its resolved values are
        in). The target intensity appears resolved (almen_intensity_mm,
        almen_strip) whichever notation the file used; a measured profile
        appears as the SHA-256 of its content.
        """
        out: dict = {"schema_version": SCHEMA_VERSION}
        for key in ("shot", "almen", "dmin", "coverage", "target", "fidelity", "seeds"):
            section = getattr(self, key)
            out[key] = None if section is None else section.model_dump(mode="python")
        target = out["target"]
        if target is not None:
            target.pop("almen_intensity")
            target["almen_intensity_mm"] = self.target.intensity_mm
            target["almen_strip"] = self.target.intensity_strip
            target.pop("measured_profile_csv")
            target["measured_profile_sha256"] = self.target.measured_profile_sha256
        return canonical(out)

    def canonical_json(self) -> str:
        return canonical_json(self.to_canonical_dict())

    def digest(self) -> str:
        """SHA-256 of canonical_json(): equal for studies that compute the same thing."""
        return hashlib.sha256(self.canonical_json().encode()).hexdigest()
