"""Almen intensity: shop-floor notation and plain millimetres.

Almen intensity is the saturation arc height of an Almen strip (SAE J443).
On the shop floor it is written as the arc height in thousandths of an inch
followed by the strip letter: ``"12A"`` = 0.012 in = 0.3048 mm on an A strip
(the paper rounds it to 0.3 mm). Metric practice writes ``"0.30 mmA"``.
Accepted forms:

* ``"12A"``, ``"8.5 N"``      thousandths of an inch (number >= 1)
* ``"0.30 mmA"``, ``"0.3mm A"`` millimetres
* ``"0.012 inA"``             inches

A bare number below 1 with a letter (``"0.3A"``) is ambiguous (inch or mm?)
and is rejected with a hint, rather than silently misread.
"""

from __future__ import annotations

import re

__all__ = ["INCH_MM", "parse_intensity"]

INCH_MM = 25.4

_PATTERN = re.compile(r"^\s*(\d+(?:\.\d*)?|\.\d+)\s*(mm|in)?\s*([A-Za-z])\s*$")


def parse_intensity(text: str) -> tuple[float, str]:
    """``"12A"`` -> (0.3048, "A"): arc height in mm and strip type letter.

    Raises ValueError with a user-facing message for anything else.
    """
    match = _PATTERN.match(text)
    if not match:
        raise ValueError(
            'expected Almen intensity notation such as "12A" (thousandths of an inch, '
            'strip A), "0.30 mmA" or "0.012 inA"'
        )
    number, unit, letter = float(match.group(1)), match.group(2), match.group(3).upper()
    if unit == "mm":
        value_mm = number
    elif unit == "in":
        value_mm = number * INCH_MM
    elif number >= 1.0:
        value_mm = number * 1e-3 * INCH_MM
    else:
        raise ValueError(
            f'ambiguous unit: write "{number:g} mm{letter}" for millimetres or "{number:g} in{letter}" '
            f'for inches (shop notation "12{letter}" means 0.012 in)'
        )
    if value_mm <= 0.0:
        raise ValueError("expected an arc height > 0")
    return value_mm, letter
