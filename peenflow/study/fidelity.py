"""Numerical fidelity: mesh, time step, window, tolerances, lateral faces.

A study picks a named preset (``[fidelity] preset = "standard"``) and may
override any key; the loaded :class:`Fidelity` holds every resolved value, so
a result records exactly which fidelity made it. Preset numbers are starting
points; the benchmarks (run time vs error) are where they get tuned.
"""

from __future__ import annotations

from typing import Annotated, Literal, Optional

from pydantic import Field, field_validator, model_validator

from .types import GradingRatio, NonNegative, OpenFraction, Positive, SafetyFactor, ShotScaled, check

__all__ = ["Fidelity", "PRESETS", "DEFAULT_PRESET", "REMOVED_KEYS", "expand_preset"]

#: Keys that reached nothing in the kernel and were removed; a study that
#: still gives one is told why (issue 9: every documented key takes effect or
#: is refused).
REMOVED_KEYS = {
    "contact_stiffness_factor": "removed: the kernel's contact is kinematic (nodes are put back on the shot's "
                                "surface, no penalty slope), so there is no contact stiffness to set; delete the key",
    "precision": "removed: the kernel runs in float64 only (float32 state was measured and not kept, "
                 "docs/performance.md section 1); delete the key",
}

DEFAULT_PRESET = "standard"

#: the smallest ratio of the coarse to the fine level of an intensity extrapolation: with order 1.85,
#: 1.25 already multiplies the fine-minus-coarse difference by k = 1 / (1.25^1.85 - 1) = 1.9
EXTRAPOLATION_RATIO_MIN = 1.25

# Resolved values of every preset. "paper" is the paper's resolution (25 um
# fine mesh) with no unmeasured shortcut (window off).
PRESETS: dict[str, dict[str, object]] = {
    "coarse": {
        "element_size_um": 60.0,
        "fine_depth_D": 0.75,
        "grading_ratio": 1.2,
        "time_step_safety": 0.9,
        "window_contact_radii": 3.0,
        "settle_tolerance": 1e-4,
        "relaxation_tolerance": 1e-6,
        "lateral_boundary": "symmetric",
    },
    "standard": {
        "element_size_um": 40.0,
        "fine_depth_D": 1.0,
        "grading_ratio": 1.15,
        "time_step_safety": 0.8,
        "window_contact_radii": 4.0,
        "settle_tolerance": 1e-6,
        "relaxation_tolerance": 1e-8,
        "lateral_boundary": "symmetric",
    },
    "paper": {
        "element_size_um": 25.0,
        "fine_depth_D": 1.0,
        "grading_ratio": 1.1,
        "time_step_safety": 0.8,
        "window_contact_radii": 6.0,
        "settle_tolerance": 1e-6,
        "relaxation_tolerance": 1e-9,
        "lateral_boundary": "symmetric",
    },
}

# Keys of which a study gives one or the other; a user value for one drops
# the preset's value for its partner.
_EXCLUSIVE = {"fine_depth_D": "fine_depth_mm", "fine_depth_mm": "fine_depth_D"}


def expand_preset(raw: dict) -> dict:
    """The user's [fidelity] table laid over its preset's values.

    An unknown preset name is left for validation to report; the standard
    preset's values fill in meanwhile, so other keys are still checked.
    """
    preset = raw.get("preset", DEFAULT_PRESET)
    base = dict(PRESETS.get(preset, PRESETS[DEFAULT_PRESET])) if isinstance(preset, str) else dict(PRESETS[DEFAULT_PRESET])
    for key, partner in _EXCLUSIVE.items():
        if key in raw:
            base.pop(partner, None)
    merged = {**base, **raw}
    merged.setdefault("preset", DEFAULT_PRESET)
    overrides = tuple(sorted(k for k in raw if k != "preset" and base.get(k, object()) != raw[k]))
    merged["overrides"] = overrides
    return merged


class Fidelity(ShotScaled):
    """Resolved fidelity settings (preset values with the study's overrides)."""

    preset: Literal["coarse", "standard", "paper"] = Field(
        DEFAULT_PRESET, description='a preset name: "coarse", "standard" or "paper"', exclude=True
    )
    overrides: tuple[str, ...] = Field((), exclude=True)
    element_size_um: Positive = Field(description="edge of the cubic elements of the fine zone in um")
    fine_depth_D: Optional[Positive] = Field(None, description="depth of the uniform fine zone in shot diameters")
    fine_depth_mm: Optional[Positive] = Field(None, description="depth of the uniform fine zone in mm")
    grading_ratio: GradingRatio = Field(description="size ratio of neighbouring elements outside the fine zone, in [1, 1.2]")
    time_step_safety: SafetyFactor = Field(description="stable time step multiplier in (0, 1]")
    window_contact_radii: NonNegative = Field(
        description="half width and depth of the active window around an impact, in estimated contact "
                    "radii (0 = whole REV every step)"
    )
    settle_tolerance: OpenFraction = Field(
        description="target kinetic energy, as a fraction of one shot's, below which the next shot may arrive"
    )
    relaxation_tolerance: OpenFraction = Field(
        description="kinetic energy fraction at which the final dynamic relaxation stops"
    )
    lateral_boundary: Literal["symmetric", "periodic"] = Field(
        description='lateral REV faces: "symmetric" (the paper) or "periodic"'
    )
    extrapolate_intensity_from_um: Optional[Positive] = Field(
        None, description="a coarser element size in um: the strips run at it too, with the same shot streams, and "
                          "each Almen intensity is extrapolated to zero element size from the two levels "
                          "(peenflow/methods/mesh_extrapolation.py); the control curve and the target velocity "
                          "use the extrapolated intensities")
    intensity_extrapolation_order: Optional[Positive] = Field(
        None, description="the order p of I(h) = I0 + c h^p used by that extrapolation (default: the measured "
                          "order of the strip references, peenflow.study.accuracy.INTENSITY_ORDER)")
    dent_element_size_um: Optional[Positive] = Field(
        None, description="a finer element size in um for the target's single impact, whose dent ellipse gives the "
                          "coverage curve, N_f and N_c (the pile-up crest that bounds the dent converges at first "
                          "order in the element size); the REV runs stay at element_size_um")
    dent_refinement: Literal["block", "core"] = Field(
        "block", description='where dent_element_size_um applies: "block" (the single impact\'s whole fine zone) '
                             'or "core" (a core under the impact, 1.5 estimated contact radii wide and one deep, '
                             'graded back to element_size_um; the same N_f within 0.1 % at 0.37 x the CPU at 6.25 um, '
                             'docs/validation.md section 9)')

    @model_validator(mode="after")
    def _one_depth(self) -> "Fidelity":
        if (self.fine_depth_D is None) == (self.fine_depth_mm is None):
            raise ValueError("give exactly one of fine_depth_D and fine_depth_mm")
        if self.window_contact_radii != 0.0 and self.window_contact_radii < 2.0:
            raise ValueError(
                f"window_contact_radii = {self.window_contact_radii!r}: expected 0 (no window) or at least 2 "
                "contact radii (a smaller window cuts into the plastic zone)"
            )
        return self

    @field_validator("extrapolate_intensity_from_um")
    @classmethod
    def _coarser(cls, hc, info):
        h = info.data.get("element_size_um")
        if hc is not None and h is not None and not hc >= EXTRAPOLATION_RATIO_MIN * h:
            raise ValueError(
                f"expected a coarser level than element_size_um = {h:g} um, at least {EXTRAPOLATION_RATIO_MIN:g} x "
                f"that = {EXTRAPOLATION_RATIO_MIN * h:g} um (closer levels amplify the sequences' noise in the "
                "extrapolation)")
        return hc

    @field_validator("dent_element_size_um")
    @classmethod
    def _finer_dent(cls, hd, info):
        h = info.data.get("element_size_um")
        if hd is not None and h is not None and not hd <= h:
            raise ValueError(
                f"expected an element size no coarser than element_size_um = {h:g} um (the dent is refined to make "
                "N_f converge; a coarser dent would only add error)")
        return hd

    @field_validator("dent_refinement")
    @classmethod
    def _core_needs_finer_dent(cls, where, info):
        hd, h = info.data.get("dent_element_size_um"), info.data.get("element_size_um")
        if where == "core" and hd is None:
            raise ValueError('"core" refines a core under the target\'s single impact to dent_element_size_um, '
                             'which is not given: set it (finer than element_size_um), or delete the key')
        if where == "core" and h is not None and not hd < h:
            raise ValueError(f'"core" needs dent_element_size_um = {hd:g} um finer than element_size_um = {h:g} um '
                             '(a core of the block\'s own size is the block): set a smaller dent_element_size_um, '
                             'or delete the key')
        return where

    @field_validator("intensity_extrapolation_order")
    @classmethod
    def _order_needs_levels(cls, p, info):
        if p is not None and info.data.get("extrapolate_intensity_from_um") is None:
            raise ValueError("given without fidelity.extrapolate_intensity_from_um: set the coarse level, or "
                             "delete the order")
        return p

    @property
    def intensity_order(self) -> float:
        """The order of the intensity extrapolation: the study's, or the measured one."""
        from .accuracy import INTENSITY_ORDER

        p = self.intensity_extrapolation_order
        return INTENSITY_ORDER if p is None else p

    @property
    def strip_element_size_um(self) -> float:
        """The largest element size the strips run at: the coarse level of an intensity extrapolation, if any."""
        return max(self.element_size_um, self.extrapolate_intensity_from_um or 0.0)

    def describe(self) -> str:
        """'standard' or 'standard + element_size_um=30' (for logs and provenance)."""
        if not self.overrides:
            return self.preset
        return self.preset + " + " + ", ".join(f"{k}={getattr(self, k)!r}" for k in self.overrides)
