"""The loaded study: resolved sections, stages, canonical form.

A :class:`Study` is what :func:`peenflow.study.load_study` returns: frozen,
validated, with library references replaced by the objects themselves
(``study.target.material`` is a :class:`Material`, not a name).
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Optional

from pydantic import Field, model_validator

from .canonical import canonical, canonical_json
from .fidelity import Fidelity, expand_preset
from .measured_profile import ProfileError, read_measured_profile
from .sections import Almen, Coverage, Dmin, Execution, Seeds, ShotSection, Target
from .types import Name, StudyModel

__all__ = ["Study", "StudyInfo", "SCHEMA_VERSION"]

SCHEMA_VERSION = 1

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
        # Fix the measured profile's content now (the loader has parsed it
        # already): the key must not change under a loaded study.
        if self.target is not None and self.target.measured_profile_csv and self.target.measured_profile is None:
            try:
                self.target._measured = read_measured_profile(Path(self.target.measured_profile_csv))
            except (OSError, ProfileError) as exc:
                raise ValueError(f"target.measured_profile_csv: {exc}") from None
        return self

    @model_validator(mode="after")
    def _periodic_rev_fits_a_contact(self) -> "Study":
        """Periodic REV faces: each shot's contact zone -- the kernel's search box (1.25 R each
        side), an oblique shot's tangential travel during the contact, and 2 elements -- must fit in
        half a period (``bounds.periodic_contact_half_m``, the kernel's own test, so that a REV that
        would stop the kernel is refused before anything is computed)."""
        if self.fidelity.lateral_boundary != "periodic":
            return self
        from .bounds import periodic_contact_half_m, rev_lateral_step_bound_m

        for name, section in (("almen", self.almen), ("target", self.target)):
            size = getattr(section, "rev_size_mm", None) if section is not None else None
            if size is None:
                continue
            h_um = self.fidelity.strip_element_size_um if name == "almen" else self.fidelity.element_size_um
            # the REV's own lateral step: the side in a whole number of elements
            step = rev_lateral_step_bound_m(size * 1e-3, h_um * 1e-6)
            mat = section.strip.material if name == "almen" else section.material
            if name == "almen":
                cases = [(v, a) for v in section.velocities_m_s for a in section.angles_deg]
            elif section.velocity_m_s is not None:
                cases = [(section.velocity_m_s, section.angle_deg)]
            elif self.almen is not None:  # read off the control curve: at most its fastest velocity
                cases = [(max(self.almen.velocities_m_s), section.angle_deg)]
            else:
                cases = []
            for v, angle in cases:
                half = periodic_contact_half_m(self.shot.radius_m, self.shot.density_kg_m3, v, angle,
                                               mat.youngs_modulus_Pa, mat.poisson_ratio, mat.johnson_cook.A_Pa,
                                               step)
                if size * 1e-3 <= 2.0 * half:
                    travel = 2.0 * half - 1.25 * self.shot.diameter_m - 4.0 * step
                    raise ValueError(
                        f'{name}.rev_size_mm = {size}: with fidelity.lateral_boundary = "periodic" the REV side must '
                        f"exceed 1.25 D + 4 elements ({step * 1e6:.4g} um: {h_um:g} um fitted to the side) + twice "
                        "the tangential travel during the "
                        f"contact ({travel * 1e3:.3g} mm at {v:g} m/s, {angle:g} deg) = {2.0 * half * 1e3:.3g} mm "
                        "(a shot's contact zone must fit in half a period)")
        return self

    @model_validator(mode="after")
    def _extrapolation_needs_strips(self) -> "Study":
        if self.fidelity.extrapolate_intensity_from_um is not None and self.almen is None:
            raise ValueError("fidelity.extrapolate_intensity_from_um extrapolates the Almen intensities of the "
                             "[almen] strip runs, and this study has no [almen] section: add one, or delete the key")
        return self

    @model_validator(mode="after")
    def _dent_level_needs_target(self) -> "Study":
        if self.fidelity.dent_element_size_um is not None and self.target is None:
            raise ValueError("fidelity.dent_element_size_um refines the single impact of the [target] section, "
                             "whose dent gives N_f and N_c, and this study has no [target] section: add one, or "
                             "delete the key")
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
