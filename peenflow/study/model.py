"""The loaded study: resolved sections, stages, canonical form.

A :class:`Study` is what :func:`peenflow.study.load_study` returns: frozen,
validated, with library references replaced by the objects themselves
(``study.target.material`` is a :class:`Material`, not a name).
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Optional

from pydantic import Field, PrivateAttr, model_validator

from .canonical import canonical, canonical_json
from .fidelity import Fidelity, expand_preset
from .almen_strips import AlmenStripsError, read_almen_strips
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

    # a study with lists ([target] lists, [targets.NAME], [sweep]) is a family of single-point studies
    # (peenflow.study.variants): this one is the first of them, and these say what the family is
    _dims: tuple = PrivateAttr(default=())
    _variants: tuple = PrivateAttr(default=())
    _requirements: object = PrivateAttr(default=None)

    @property
    def dims(self) -> tuple:
        """The process dimensions (:class:`peenflow.study.variants.Dim`), in order; () for a single point."""
        return self._dims

    @property
    def variants(self) -> tuple:
        """((coords, Study), ...) of every combination of the dimensions' values; ((), self) for one point."""
        return self._variants or (({}, self),)

    @property
    def requirements(self):
        """The [requirements] (:class:`peenflow.study.requirements.Requirements`), or None."""
        return self._requirements

    @model_validator(mode="after")
    def _share_shot_diameter(self) -> "Study":
        d = self.shot.diameter_mm
        for section in (self.almen, self.dmin, self.target, self.fidelity):
            if section is not None:
                section._shot_diameter_mm = d
        # Fix the measured profile's content now (the loader has parsed it
        # already): the key must not change under a loaded study.
        if self.target is not None and self.target.measured_profile_csv and self.target.measured_profile is None:
            try:
                self.target._measured = read_measured_profile(Path(self.target.measured_profile_csv))
            except (OSError, ProfileError) as exc:
                raise ValueError(f"target.measured_profile_csv: {exc}") from None
        if self.target is not None and self.target.almen_strips_csv and self.target.almen_strips is None:
            try:
                self.target._strips = read_almen_strips(Path(self.target.almen_strips_csv))
            except AlmenStripsError as exc:
                raise ValueError(f"target.almen_strips_csv: {'; '.join(exc.problems)}") from None
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
            out[key] = None if section is None else section.model_dump(mode="python", warnings=False)
        target = out["target"]
        if target is not None:
            target.pop("almen_intensity")
            target["almen_intensity_mm"] = self.target.intensity_mm
            target["almen_strip"] = self.target.intensity_strip
            target.pop("measured_profile_csv")
            target["measured_profile_sha256"] = self.target.measured_profile_sha256
            if target.pop("almen_strips_csv"):  # the strips by their content
                target["almen_strips_sha256"] = self.target.almen_strips.sha256
        return canonical(out)

    def canonical_json(self) -> str:
        return canonical_json(self.to_canonical_dict())

    def digest(self) -> str:
        """SHA-256 of canonical_json(): equal for studies that compute the same thing."""
        return hashlib.sha256(self.canonical_json().encode()).hexdigest()
