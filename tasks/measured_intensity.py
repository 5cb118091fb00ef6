"""The intensity of measured Almen strips: the study's reading of the CSV
(:mod:`peenflow.study.almen_strips`) handed to the SAE J2597 solver
(:mod:`peenflow.methods.measured_strips`)."""

from __future__ import annotations

from peenflow.methods.measured_strips import StripDataError, StripIntensity, strip_intensity
from peenflow.study.almen_strips import AlmenStripsError, MeasuredStrips


def almen_strips_intensity(strips: MeasuredStrips, source: str = "") -> StripIntensity:
    """The intensity of measured strips (the solver of :mod:`peenflow.methods.measured_strips`).

    The saturation exposure comes back in ``strips.exposure_unit`` (s for time);
    messages show exposures in the file's unit (min for ``time_min``).
    Raises :class:`AlmenStripsError` where the strips cannot define one, naming
    the lines (``source``, e.g. the file name, prefixes the message).
    """
    labels = [f"line {n}" for n in strips.line] if len(strips.line) == len(strips.exposure) else None
    try:
        return strip_intensity(strips.exposure, strips.arc_height_m, labels, strips.shown_as)
    except StripDataError as exc:
        raise AlmenStripsError([f"{source}: {exc}" if source else str(exc)]) from None
