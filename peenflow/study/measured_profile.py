"""A measured residual-stress profile, read once from its CSV.

File format (``studies/data/measured_profile_template.csv``): lines starting
with ``#`` and blank lines are comments; a header row naming the columns
``depth_mm``, ``stress_MPa``, ``component`` (any order, other columns
ignored); one row per measurement. ``component`` is ``xx`` (in the
impingement plane) or ``yy``: the two in-plane components the final REV run
averages over its measuring region. Depths are >= 0 and finite, stresses
finite.

The study loader parses the file with :func:`read_measured_profile` while
validating (every bad row is reported with its line number, before any
compute) and keeps the parsed profile, so the pipeline never reads the file
again and the result key is that of the content that was validated.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from pathlib import Path

from ._csv import CsvFileError, read_commented_csv

PROFILE_COLUMNS = ("depth_mm", "stress_MPa", "component")
PROFILE_COMPONENTS = ("xx", "yy")


class ProfileError(CsvFileError):
    """The profile CSV cannot be used; ``problems`` lists each reason (with line numbers)."""


@dataclass(frozen=True)
class MeasuredProfile:
    """Measured points, SI: ``depth_m`` (n,) m below the surface, ``stress_Pa``
    (n,) Pa, ``component`` (n,) "xx" | "yy"; ``sha256`` of the file's bytes
    ("" when rebuilt from the stage parameters, which hold the points only).

    A stage parameter as it is (``__canonical__`` / ``from_canonical``, see
    :mod:`peenflow.engine.task`): the key holds the points, not the file's
    name or hash, so the same measurements give the same result.
    """

    depth_m: tuple[float, ...]
    stress_Pa: tuple[float, ...]
    component: tuple[str, ...]
    sha256: str = ""

    def __canonical__(self) -> dict:
        """The stage parameters (SI): the points."""
        return {"depth_m": list(self.depth_m), "stress_Pa": list(self.stress_Pa), "component": list(self.component)}

    @classmethod
    def from_canonical(cls, value) -> "MeasuredProfile":
        if isinstance(value, cls):
            return value
        return cls(tuple(value["depth_m"]), tuple(value["stress_Pa"]), tuple(value["component"]))


def read_measured_profile(path: Path) -> MeasuredProfile:
    """Parse and check the CSV; raises :class:`ProfileError` naming every bad row."""
    path = Path(path)
    raw, rows = read_commented_csv(path, ProfileError, ", ".join(PROFILE_COLUMNS))
    header = [h.strip() for h in rows[0][1]]
    missing = [c for c in PROFILE_COLUMNS if c not in header]
    if missing:
        raise ProfileError([f"{path.name}: header {header} lacks column(s) {', '.join(missing)}; "
                            f"expected {', '.join(PROFILE_COLUMNS)}"])
    idx = {c: header.index(c) for c in PROFILE_COLUMNS}
    depth, stress, comp, bad = [], [], [], []
    for n, row in rows[1:]:
        try:
            d = float(row[idx["depth_mm"]])
            s = float(row[idx["stress_MPa"]])
            c = row[idx["component"]].strip()
        except (ValueError, IndexError):
            bad.append(n)
            continue
        if not (math.isfinite(d) and math.isfinite(s) and d >= 0.0 and c in PROFILE_COMPONENTS):
            bad.append(n)
            continue
        depth.append(d * 1e-3)
        stress.append(s * 1e6)
        comp.append(c)
    problems = []
    if bad:
        shown = ", ".join(map(str, bad[:5])) + (" ..." if len(bad) > 5 else "")
        problems.append(f"{path.name}: bad data on line(s) {shown}; expected depth_mm a finite number >= 0, "
                        f"stress_MPa a finite number, component one of {', '.join(PROFILE_COMPONENTS)}")
    elif not depth:
        problems.append(f"{path.name} has a header but no data rows; expected at least one measurement")
    if problems:
        raise ProfileError(problems)
    return MeasuredProfile(tuple(depth), tuple(stress), tuple(comp), hashlib.sha256(raw).hexdigest())
