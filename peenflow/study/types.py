"""Constrained scalar types for study files, each with a user-facing message.

Every constraint says what is expected in words and units, so a problem
reads ``almen.angles_deg[1] = 120.0: expected an impingement angle in (0, 90] deg``
rather than a bare "greater than" code.
"""

from __future__ import annotations

import math
import re
from typing import Annotated, Any, Callable

from pydantic import AfterValidator, BaseModel, ConfigDict, PrivateAttr

__all__ = [
    "StudyModel", "ShotScaled", "check", "Positive", "NonNegative", "Angle", "Velocity", "Poisson",
    "OpenFraction", "PositiveInt", "NonNegativeInt", "GradingRatio", "SafetyFactor",
    "Name", "strictly_increasing", "unique_sorted",
]


class StudyModel(BaseModel):
    """Base of all study-file models: frozen, strict types, unknown keys rejected."""

    model_config = ConfigDict(strict=True, extra="forbid", frozen=True, allow_inf_nan=False)


class ShotScaled(StudyModel):
    """A section with lengths given in shot diameters (``*_D`` keys).

    The loaded Study tells it the shot diameter (mm), so lengths in D can be read.
    """

    _shot_diameter_mm: float | None = PrivateAttr(default=None)

    @property
    def shot_diameter_mm(self) -> float:
        if self._shot_diameter_mm is None:
            raise RuntimeError("shot diameter unknown: use the section of a loaded Study")
        return self._shot_diameter_mm


def check(predicate: Callable[[Any], bool], expected: str):
    """An AfterValidator raising ``expected ...`` when predicate(value) is false."""

    def _validate(value: Any) -> Any:
        if not predicate(value):
            raise ValueError(f"expected {expected}")
        return value

    return AfterValidator(_validate)


def _finite(x: float) -> bool:
    return math.isfinite(x)


Positive = Annotated[float, check(lambda x: _finite(x) and x > 0, "a value > 0")]
NonNegative = Annotated[float, check(lambda x: _finite(x) and x >= 0, "a value >= 0")]
Angle = Annotated[float, check(lambda x: 0 < x <= 90, "an impingement angle in (0, 90] deg (90 = normal impact)")]
Velocity = Annotated[float, check(lambda x: _finite(x) and x > 0, "a shot velocity > 0 m/s")]
Poisson = Annotated[float, check(lambda x: -1 < x < 0.5, "a Poisson ratio in (-1, 0.5)")]
OpenFraction = Annotated[float, check(lambda x: 0 < x < 1, "a fraction in (0, 1)")]
PositiveInt = Annotated[int, check(lambda x: x > 0, "an integer > 0")]
NonNegativeInt = Annotated[int, check(lambda x: x >= 0, "an integer >= 0")]
GradingRatio = Annotated[float, check(lambda x: 1.0 <= x <= 1.2, "a grading ratio in [1, 1.2] (1 = uniform mesh)")]
SafetyFactor = Annotated[float, check(lambda x: 0 < x <= 1, "a time-step safety factor in (0, 1]")]

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+-]*$")
Name = Annotated[
    str,
    check(lambda s: bool(_NAME.match(s)), "a name of letters, digits and _ . + - (no spaces)"),
]


def strictly_increasing(what: str):
    """AfterValidator: a sequence strictly increasing (e.g. a shot-count ladder)."""

    def _validate(values: tuple) -> tuple:
        for i in range(1, len(values)):
            if values[i] <= values[i - 1]:
                raise ValueError(
                    f"expected {what} strictly increasing; item [{i}] = {values[i]!r} "
                    f"is not greater than item [{i - 1}] = {values[i - 1]!r}"
                )
        return values

    return AfterValidator(_validate)


def unique_sorted(what: str):
    """AfterValidator: no duplicates; stored sorted so file order does not matter."""

    def _validate(values: tuple) -> tuple:
        seen = set()
        for i, v in enumerate(values):
            if v in seen:
                raise ValueError(f"expected distinct {what}; item [{i}] = {v!r} is repeated")
            seen.add(v)
        return tuple(sorted(values))

    return AfterValidator(_validate)
