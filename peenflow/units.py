"""Units: the one place a length, stress or modulus changes unit.

Study files speak in the units their users think in (mm, um, MPa, GPa); the
kernel, the stages and the store work in SI (m, Pa, kg m-3, m s-1, s); people
read mm, um and MPa again in the headline, plots, report and ``show``.  Each
of those edges converts with these factors -- the value in SI is the file's
value times the factor of its unit (``thickness_mm * MM`` is m, ``stress_Pa /
MPA`` is MPa) -- and nothing else converts.  The study models keep the file's
units; :mod:`tasks.params` is where a study becomes SI.
"""

from __future__ import annotations

__all__ = ["MM", "UM", "MPA", "GPA", "INCH", "THOU", "reading_unit"]

#: one millimetre in m
MM = 1e-3
#: one micrometre in m
UM = 1e-6
#: one megapascal in Pa
MPA = 1e6
#: one gigapascal in Pa
GPA = 1e9
#: one inch in m (Almen arc heights in shop notation are thousandths of an inch)
INCH = 25.4e-3
#: one thousandth of an inch in m
THOU = 25.4e-6


#: the unit a person reads a stored (SI, CF-spelled) unit in: stored unit -> (factor, unit shown)
_READING = {"m": (1 / MM, "mm"), "m2": (1 / MM**2, "mm2"), "Pa": (1 / MPA, "MPa"), "m s-1": (1.0, "m/s"),
            "degree": (1.0, "deg")}


def reading_unit(units: str) -> tuple[float, str]:
    """(factor, unit) in which a value stored in ``units`` is read: m as mm, m2 as mm2, Pa as MPa, m s-1 as m/s;
    any other unit as it is, a dimensionless one ("1" or "") as "" (the stored value times the factor is
    the value shown)."""
    return _READING.get(units, (1.0, "" if units in ("", "1") else units))
