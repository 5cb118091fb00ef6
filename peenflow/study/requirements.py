"""[requirements]: what the part needs of its residual-stress profile, and what to spend least on.

::

    [requirements]
    compressive_depth_mm = { min = 0.25 }
    surface_stress_MPa = { max = -250 }
    minimise = "coverage_percent"     # a process dimension, or "shots"

Each feature key is one of :data:`FEATURES` (the process map's features, in
the units a person reads them in); a bound is ``min`` and/or ``max``.  The
``suggested_settings`` stage reads the process map and reports the settings
that meet every requirement with the least of ``minimise``.
"""

from __future__ import annotations

import math
from typing import Optional

from pydantic import Field, model_validator

from .types import StudyModel

__all__ = ["FEATURES", "Bound", "Requirements"]

#: feature key in a [requirements] table -> (the process map's variable, its SI unit, factor to SI, what it is)
FEATURES: dict[str, tuple[str, str, float, str]] = {
    "surface_stress_MPa": ("surface_stress_xx_Pa", "Pa", 1e6, "sigma_xx at the surface (top layer)"),
    "peak_compressive_stress_MPa": ("peak_compressive_xx_Pa", "Pa", 1e6, "most compressive sigma_xx"),
    "peak_depth_mm": ("peak_compressive_xx_depth_m", "m", 1e-3, "depth of the most compressive sigma_xx"),
    "compressive_depth_mm": ("compressive_depth_xx_m", "m", 1e-3, "depth of the compressive layer of sigma_xx"),
    "surface_stress_yy_MPa": ("surface_stress_yy_Pa", "Pa", 1e6, "sigma_yy at the surface (top layer)"),
    "peak_compressive_stress_yy_MPa": ("peak_compressive_yy_Pa", "Pa", 1e6, "most compressive sigma_yy"),
    "compressive_depth_yy_mm": ("compressive_depth_yy_m", "m", 1e-3, "depth of the compressive layer of sigma_yy"),
}

#: what ``minimise`` may name besides a process dimension: the shots a REV of the part takes (N_c)
MINIMISE_SHOTS = "shots"


class Bound(StudyModel):
    """``min`` and/or ``max`` on one feature (in the feature key's units)."""

    min: Optional[float] = Field(None, description="the feature must be at least this")
    max: Optional[float] = Field(None, description="the feature must be at most this")

    @model_validator(mode="after")
    def _one_side(self) -> "Bound":
        if self.min is None and self.max is None:
            raise ValueError("expected min and/or max, e.g. { min = 0.25 }")
        for side in ("min", "max"):
            v = getattr(self, side)
            if v is not None and not math.isfinite(v):
                raise ValueError(f"{side} = {v!r}: expected a finite number")
        if self.min is not None and self.max is not None and self.min > self.max:
            raise ValueError(f"min = {self.min!r} is above max = {self.max!r}: no value meets both")
        return self


class Requirements(StudyModel):
    """[requirements]: bounds on process-map features, and the setting to minimise."""

    bounds: dict[str, Bound] = Field(description="feature key -> { min, max }")
    minimise: str = Field(description='a process dimension (e.g. "coverage_percent") or "shots"')
    verify: bool = Field(False, description="compute the part at the suggested coverage and report it beside the "
                                            "map's prediction (minimise = coverage_percent or shots)")

    @classmethod
    def from_table(cls, table: dict) -> "Requirements":
        """From the file's table: feature keys at the top level beside ``minimise``."""
        own = ("minimise", "verify")
        bounds = {k: v for k, v in table.items() if k not in own}
        return cls.model_validate({"bounds": bounds, **{k: table[k] for k in own if k in table}})

    @model_validator(mode="after")
    def _known(self) -> "Requirements":
        unknown = sorted(set(self.bounds) - set(FEATURES))
        if unknown:
            raise ValueError(f"unknown feature {', '.join(unknown)}; expected one of {', '.join(FEATURES)}")
        if not self.bounds:
            raise ValueError(f"no requirement: give at least one feature bound ({', '.join(FEATURES)})")
        if self.verify and self.minimise not in ("coverage_percent", MINIMISE_SHOTS):
            raise ValueError(f'verify = true computes the part at a suggested coverage: it needs minimise = '
                             f'"coverage_percent" or "{MINIMISE_SHOTS}", not {self.minimise!r} (to check a suggested '
                             f"{self.minimise}, add that value to its list and run again)")
        return self
