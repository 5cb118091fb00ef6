"""Measured Almen strips, read once from their CSV, and their intensity.

File format (``studies/data/almen_strips_template.csv``): lines starting with
``#`` and blank lines are comments; a header row naming two columns, in any
order -- the exposure and the arc height, each with its unit in its name:

* exposure: ``time_min`` (minutes), ``passes``, ``shots`` or ``coverage_percent``;
* arc height: ``arc_height_mm``, ``arc_height_in`` or ``arc_height_thou``
  (thousandths of an inch, the shop's unit: 0.012 in = 12).

One row per strip; several strips may share an exposure. Exposures are > 0,
arc heights >= 0. Any other column, a column without its unit or a second
exposure column is refused, naming it, before anything is fitted.

:func:`read_almen_strips` parses and checks the file (every bad row with its
line number); :func:`almen_strips_intensity` runs the saturation solver of
:mod:`peenflow.methods.measured_strips` on the result.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from pathlib import Path

from .._toml import load_toml
from ._csv import CsvFileError, read_commented_csv
from .errors import suggest
from .intensity import INCH_MM

__all__ = ["EXPOSURE_COLUMNS", "ARC_HEIGHT_COLUMNS", "AlmenStripsError", "MeasuredStrips", "read_almen_strips",
           "almen_strips_intensity", "shop_notation", "strip_types"]

#: exposure column -> (factor to the stored unit, stored unit, unit as the user reads it)
EXPOSURE_COLUMNS = {
    "time_min": (60.0, "s", "min"),
    "passes": (1.0, "pass", "passes"),
    "shots": (1.0, "shot", "shots"),
    "coverage_percent": (0.01, "1", "% coverage"),
}
#: arc-height column -> factor to m
ARC_HEIGHT_COLUMNS = {
    "arc_height_mm": 1e-3,
    "arc_height_in": INCH_MM * 1e-3,
    "arc_height_thou": INCH_MM * 1e-6,
}
_EXPECTED = ("one exposure column (time_min, passes, shots or coverage_percent) and one arc-height column "
             "(arc_height_mm, arc_height_in or arc_height_thou)")
_SHOWN = 5  # bad lines listed in a message before "..."
_STRIP_LIBRARY = Path(__file__).resolve().parent / "library" / "strips.toml"


class AlmenStripsError(CsvFileError):
    """The strips CSV cannot be used; ``problems`` lists each reason (with line numbers)."""


@dataclass(frozen=True)
class MeasuredStrips:
    """Measured strips, SI: ``exposure`` (n,) in ``exposure_unit`` ("s" for time,
    "pass", "shot", "1" for coverage as a fraction), ``arc_height_m`` (n,) m,
    ``line`` (n,) each strip's line in the file; ``exposure_column`` the column the
    exposures came from (its unit is the one to show them in); ``sha256`` of the
    file's bytes ("" when rebuilt from stage parameters).

    A stage parameter as it is (``__canonical__`` / ``from_canonical``, see
    :mod:`peenflow.engine.task`): the key holds the points, not the file.
    """

    exposure: tuple[float, ...]
    exposure_unit: str
    exposure_column: str
    arc_height_m: tuple[float, ...]
    line: tuple[int, ...] = ()
    sha256: str = ""

    @property
    def shown_as(self) -> tuple[str, float]:
        """(unit, factor): the file column's unit ("min", "passes", ...) and the factor that
        takes a stored exposure to it (1/60 for s -> min)."""
        factor, _, unit = EXPOSURE_COLUMNS[self.exposure_column]
        return unit, 1.0 / factor

    def __canonical__(self) -> dict:
        """The stage parameters (SI): the points and the exposure's kind."""
        return {"exposure": list(self.exposure), "exposure_unit": self.exposure_unit,
                "exposure_column": self.exposure_column, "arc_height_m": list(self.arc_height_m)}

    @classmethod
    def from_canonical(cls, value) -> "MeasuredStrips":
        if isinstance(value, cls):
            return value
        return cls(tuple(value["exposure"]), value["exposure_unit"], value["exposure_column"],
                   tuple(value["arc_height_m"]))


def _unknown_column(name: str) -> str:
    bare = name.replace(" ", "_").replace("-", "_")
    if bare in ("arc_height", "height", "arc", "archeight"):
        return (f"column {name!r} does not name its unit; expected arc_height_mm, arc_height_in or arc_height_thou "
                "(thousandths of an inch)")
    if bare in ("time", "exposure", "exposure_time"):
        return f"column {name!r} does not name its unit; expected time_min (minutes), passes, shots or coverage_percent"
    if bare == "coverage":
        return f"column {name!r}: expected coverage_percent"
    return f"unknown column {name!r}{suggest(name, [*EXPOSURE_COLUMNS, *ARC_HEIGHT_COLUMNS])}; expected {_EXPECTED}"


def _header(header: list[str], fname: str) -> tuple[str, str]:
    problems, seen = [], set()
    for name in header:
        if name in seen:
            problems.append(f"column {name!r} given twice")
        seen.add(name)
        if name not in EXPOSURE_COLUMNS and name not in ARC_HEIGHT_COLUMNS:
            problems.append(_unknown_column(name) if name else "a column with an empty name")
    exposure = [h for h in dict.fromkeys(header) if h in EXPOSURE_COLUMNS]
    height = [h for h in dict.fromkeys(header) if h in ARC_HEIGHT_COLUMNS]
    if len(exposure) > 1:
        problems.append(f"{len(exposure)} exposure columns ({', '.join(exposure)}); expected one")
    if len(height) > 1:
        problems.append(f"{len(height)} arc-height columns ({', '.join(height)}); expected one")
    # an unknown column's message says already what is expected
    unknown = any(h not in EXPOSURE_COLUMNS and h not in ARC_HEIGHT_COLUMNS for h in header)
    if not exposure and not unknown:
        problems.append("no exposure column; expected time_min, passes, shots or coverage_percent")
    if not height and not unknown:
        problems.append("no arc-height column; expected arc_height_mm, arc_height_in or arc_height_thou")
    if problems:
        raise AlmenStripsError([f"{fname}: header {', '.join(header)}: {'; '.join(problems)}"])
    return exposure[0], height[0]


def _cell(row: list[str], idx: int, column: str, what: str) -> tuple[float | None, str | None]:
    """(value, None) or (None, why) for one cell."""
    text = row[idx].strip() if idx < len(row) else ""
    if not text:
        return None, f"{column} is missing; expected {what}"
    try:
        value = float(text)
    except ValueError:
        return None, f"{column} = {text!r} is not a number; expected {what}"
    if not math.isfinite(value):
        return None, f"{column} = {text!r}; expected {what}"
    return value, None


def read_almen_strips(path: Path) -> MeasuredStrips:
    """Parse and check the CSV; raises :class:`AlmenStripsError` naming every bad line."""
    path = Path(path)
    raw, rows = read_commented_csv(path, AlmenStripsError, _EXPECTED)
    header = [h.strip().lower() for h in rows[0][1]]
    while header and not header[-1]:  # spreadsheets write trailing separators
        header.pop()
    ex_col, ah_col = _header(header, path.name)
    i_ex, i_ah = header.index(ex_col), header.index(ah_col)
    ex_unit = EXPOSURE_COLUMNS[ex_col][2]
    ah_unit = {"arc_height_mm": "mm", "arc_height_in": "inches", "arc_height_thou": "thousandths of an inch"}[ah_col]
    exposure, height, line_no, problems = [], [], [], []
    for n, row in rows[1:]:
        why = []
        if len(row) > len(header) and any(c.strip() for c in row[len(header):]):
            why.append(f"{len(row)} values under a header of {len(header)} columns")
        ex, e1 = _cell(row, i_ex, ex_col, f"an exposure > 0 in {ex_unit}")
        ah, e2 = _cell(row, i_ah, ah_col, f"an arc height >= 0 in {ah_unit}")
        why += [e for e in (e1, e2) if e]
        if ex is not None and ex <= 0:
            why.append(f"{ex_col} = {ex:g}; expected an exposure > 0 in {ex_unit} (an unpeened strip belongs to no "
                       "saturation curve: the fits pass through zero)")
        if ah is not None and ah < 0:
            why.append(f"{ah_col} = {ah:g} is negative; expected an arc height >= 0 in {ah_unit}, measured on the "
                       "peened side")
        if why:
            problems.append(f"line {n}: {', '.join(why)}")
            continue
        exposure.append(ex * EXPOSURE_COLUMNS[ex_col][0])
        height.append(ah * ARC_HEIGHT_COLUMNS[ah_col])
        line_no.append(n)
    if problems:
        shown = problems[:_SHOWN] + ([f"... ({len(problems) - _SHOWN} more bad lines)"] if len(problems) > _SHOWN else [])
        raise AlmenStripsError([f"{path.name} {p}" for p in shown])
    if not exposure:
        raise AlmenStripsError([f"{path.name} has a header but no data rows; expected one row per strip"])
    return MeasuredStrips(tuple(exposure), EXPOSURE_COLUMNS[ex_col][1], ex_col, tuple(height), tuple(line_no),
                          hashlib.sha256(raw).hexdigest())


def shop_notation(intensity_m: float, strip: str) -> str:
    """Arc height in thousandths of an inch and the strip letter: 0.3048e-3 m, "A" -> "12.0A"
    (the form :func:`peenflow.study.intensity.parse_intensity` reads back)."""
    return f"{intensity_m * 1e3 / INCH_MM * 1e3:.1f}{strip.upper()}"


def strip_types() -> dict[str, str]:
    """The packaged strip library's types (SAE J442): letter -> description."""
    return {name: item.get("description", "") for name, item in load_toml(_STRIP_LIBRARY)["strips"].items()}
