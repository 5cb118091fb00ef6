"""Library items: materials, shots and Almen strips.

These are what ``[materials.NAME]``, ``[shots.NAME]`` and ``[strips.NAME]``
tables define (in the packaged library, an included file or the study file
itself). Fields keep the unit-named values of the file; :mod:`tasks.params`
converts them to SI for the stages and the kernel.
"""

from __future__ import annotations

from typing import Optional

from pydantic import Field, model_validator

from .types import Name, NonNegative, Poisson, Positive, StudyModel

__all__ = ["JohnsonCook", "Material", "Shot", "Strip"]


class JohnsonCook(StudyModel):
    """Johnson-Cook flow stress, standard form (paper eq. (1); its "1 - C ln" is a typo):

    sigma = (A + B eps_p^n) (1 + C ln(rate / reference_rate)) (1 - T*^m),
    T* = (T - T_room) / (T_melt - T_room); no rate effect below the reference rate.
    """

    A_MPa: Positive = Field(description="initial yield stress A in MPa")
    B_MPa: NonNegative = Field(description="hardening modulus B in MPa")
    C: NonNegative = Field(description="strain-rate sensitivity C (dimensionless)")
    n: Positive = Field(description="hardening exponent n (> 0: the kernel's hardening slope B n eps^(n-1) needs it)")
    m: NonNegative = Field(0.0, description="thermal-softening exponent m (0 = no thermal term)")
    reference_strain_rate_1_s: Positive = Field(1.0, description="reference strain rate in 1/s")
    room_temperature_K: Optional[Positive] = Field(None, description="room temperature in K (needed when m != 0)")
    melt_temperature_K: Optional[Positive] = Field(None, description="melting temperature in K (needed when m != 0)")

    @model_validator(mode="after")
    def _temperatures(self) -> "JohnsonCook":
        if self.m != 0.0:
            if self.room_temperature_K is None or self.melt_temperature_K is None:
                raise ValueError(
                    f"johnson_cook.m = {self.m!r} is not 0, so room_temperature_K and "
                    "melt_temperature_K are required"
                )
        # The kernel fills a missing temperature (293 K room, 1793 K melt), starts every run at 293 K and
        # refuses a melt temperature at or below either.
        room = self.room_temperature_K if self.room_temperature_K is not None else 293.0
        melt = self.melt_temperature_K if self.melt_temperature_K is not None else 1793.0
        if melt <= max(room, 293.0):
            raise ValueError(
                f"johnson_cook.melt_temperature_K = {melt!r} must be above "
                f"room_temperature_K = {room!r} and the initial temperature of every run, 293 K (a temperature "
                "not given is 293 K room / 1793 K melt)"
            )
        return self

    @property
    def rate_dependent(self) -> bool:
        """False when C = 0: the kernel need not pay for the rate term."""
        return self.C != 0.0

    @property
    def thermal(self) -> bool:
        """False when m = 0: the kernel need not pay for the thermal term."""
        return self.m != 0.0


class Material(StudyModel):
    """Isotropic elastic + Johnson-Cook plastic material."""

    name: Name = Field(description="material name")
    description: str = ""
    source: str = Field("", description="where the numbers come from")
    youngs_modulus_GPa: Positive = Field(description="Young's modulus E in GPa")
    poisson_ratio: Poisson = Field(description="Poisson's ratio in (-1, 0.5)")
    density_kg_m3: Positive = Field(description="density in kg/m3")
    johnson_cook: JohnsonCook = Field(description="a [johnson_cook] table with A_MPa, B_MPa, C, n, m")


class Shot(StudyModel):
    """A peening shot: a rigid sphere (paper section 2.2)."""

    name: Name = Field(description="shot name, e.g. S230")
    description: str = ""
    source: str = ""
    diameter_mm: Positive = Field(description="shot diameter D in mm")
    density_kg_m3: Positive = Field(description="shot density in kg/m3")


class Strip(StudyModel):
    """An Almen strip (SAE J442): material, dimensions and gauge span."""

    name: Name = Field(description="strip type, e.g. A")
    description: str = ""
    source: str = ""
    material: Material = Field(description="strip material: a library name or an inline table")
    length_mm: Positive = Field(76.0, description="strip length in mm")
    width_mm: Positive = Field(19.0, description="strip width b in mm")
    thickness_mm: Positive = Field(description="strip thickness h in mm")
    gauge_span_mm: Positive = Field(31.75, description="Almen gauge span l in mm (eq. (9))")

    @model_validator(mode="after")
    def _span(self) -> "Strip":
        if self.gauge_span_mm >= self.length_mm:
            raise ValueError(
                f"gauge_span_mm = {self.gauge_span_mm!r} must be shorter than length_mm = {self.length_mm!r}"
            )
        return self
