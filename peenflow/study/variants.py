"""A study's process dimensions: lists in [target], named [targets.NAME], the [sweep] of any key, and the
[sensitivity] table's one-at-a-time changes.

A study with lists is a family of single-point studies, one per combination
of the listed values (a *variant*).  This module reads the lists from a
study's merged raw tables and gives

* the dimensions (:class:`Dim`): their names in the store (CF-safe, SI: a
  list of ``thickness_mm`` is the dimension ``target_thickness_m`` in m; the
  shop notation of an intensity is kept as an attribute), values and units;
* the variants: per combination, its coordinates, its ``[target]`` table and
  the ``[sweep]`` values to set (:func:`apply_overrides`);
* ``[sensitivity]`` (same form as ``[sweep]``): not a product but one key
  changed at a time from the study as written, the points named
  ``baseline`` and ``KEY@VALUE`` in one dimension ``sensitivity`` (so ten
  values of five keys cost eleven points, not 2^5 or 3^5).

Every variant is then validated as the single-point study it is.  What a
list may not be is refused here, with the key and what is expected.
Coverage levels (a list of ``coverage_percent``) are not a dimension of the
graph: one REV run per sequence is carried to the largest and snapshotted at
each (``Target.coverage_levels_percent``).
"""

from __future__ import annotations

import copy
import itertools
import math
import re
from dataclasses import dataclass
from typing import Any

from ..units import GPA, MM, MPA, UM
from .intensity import parse_intensity

__all__ = ["Dim", "Variant", "TARGET_LIST_KEYS", "BASELINE", "SENSITIVITY_DIM", "expand", "apply_overrides",
           "sensitivity_label", "sweep_dim_name"]

#: [target] keys that take a list (each a dimension): key -> (dimension name, SI factor or None, units, long name)
TARGET_LIST_KEYS: dict[str, tuple[str, float | None, str, str]] = {
    "almen_intensity": ("almen_intensity_m", MM, "m", "target Almen intensity (arc height)"),
    "almen_intensity_mm": ("almen_intensity_m", MM, "m", "target Almen intensity (arc height)"),
    "velocity_m_s": ("target_velocity_m_s", 1.0, "m s-1", "shot velocity on the part, as given"),
    "angle_deg": ("target_angle_deg", 1.0, "degree", "impingement angle on the part (90 = normal)"),
    "material": ("target_material", None, "1", "part material"),
    "thickness_mm": ("target_thickness_m", MM, "m", "part thickness"),
}

#: a key's unit suffix -> (factor to SI, the SI suffix, CF units)
_SUFFIXES = (("_mm", MM, "_m", "m"), ("_um", UM, "_m", "m"), ("_MPa", MPA, "_Pa", "Pa"), ("_GPa", GPA, "_Pa", "Pa"),
             ("_m_s", 1.0, "_m_s", "m s-1"), ("_deg", 1.0, "_deg", "degree"), ("_percent", 1.0, "_percent", "%"),
             ("_kg_m3", 1.0, "_kg_m3", "kg m-3"), ("_1_s", 1.0, "_1_s", "s-1"), ("_K", 1.0, "_K", "K"))

#: sections and library kinds whose numeric keys may be swept
SWEEPABLE_TOP = ("shot", "almen", "dmin", "coverage", "target", "fidelity", "seeds", "materials", "shots", "strips")


@dataclass(frozen=True)
class Dim:
    """One process dimension: ``name`` in the store, the study ``key`` it comes from, ``values`` (SI numbers,
    or names when ``labels``), the values as the file wrote them (``given``), CF ``units`` and ``long_name``."""

    name: str
    key: str
    values: tuple
    given: tuple
    units: str
    long_name: str
    labels: bool = False


@dataclass(frozen=True)
class Variant:
    """One combination: ``coords`` {dimension name: value}, its ``[target]`` table (None: the study's own or
    none) and the ``[sweep]`` values to set, {dotted key: value}."""

    coords: dict
    target: dict | None
    overrides: dict


class ListProblem(ValueError):
    """A list that cannot be a dimension: ``key`` and the message."""

    def __init__(self, key: str, message: str, value: Any = None):
        super().__init__(message)
        self.key, self.message, self.value = key, message, value


def sweep_dim_name(key: str) -> tuple[str, float, str]:
    """(dimension name, factor to SI, CF units) of a swept study key: dots and dashes become
    underscores, a unit suffix becomes its SI one (``fidelity.element_size_um`` -> ``fidelity_element_size_m``)."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", key)
    for suffix, factor, si, units in _SUFFIXES:
        if name.endswith(suffix):
            return name[: -len(suffix)] + si, factor, units
    return name, 1.0, "1"


def _check_list(key: str, values) -> list:
    if not isinstance(values, list):
        raise ListProblem(key, "expected a list of values", values)
    if not values:
        raise ListProblem(key, "an empty list: expected at least one value", values)
    seen = []
    for v in values:
        marker = repr(sorted(v.items())) if isinstance(v, dict) else repr(v)
        if marker in seen:
            raise ListProblem(key, f"duplicate value {v!r}: each value once", values)
        seen.append(marker)
    return values


def _material_label(v, k: int) -> str:
    if isinstance(v, str):
        return v
    if isinstance(v, dict):
        return str(v.get("name", f"inline-material-{k}"))
    raise ListProblem("target.material", "expected material names or inline tables", v)


def _target_dims(table: dict, where: str) -> tuple[list[Dim], list[dict]]:
    """The dims of one [target] table's lists and its scalar tables, one per combination."""
    dims, axes = [], []
    listed = [k for k in TARGET_LIST_KEYS if isinstance(table.get(k), list)]
    for k in listed:
        values = _check_list(f"{where}.{k}", table[k])
        name, factor, units, long_name = TARGET_LIST_KEYS[k]
        if k == "material":
            labels = tuple(_material_label(v, i) for i, v in enumerate(values))
            dims.append(Dim(name, f"{where}.{k}", labels, tuple(values), units, long_name, labels=True))
        elif k == "almen_intensity":
            try:
                si = tuple(parse_intensity(v)[0] * factor for v in values)
            except (ValueError, TypeError) as exc:
                raise ListProblem(f"{where}.{k}", str(exc), values) from None
            dims.append(Dim(name, f"{where}.{k}", si, tuple(values), units, long_name))
        else:
            if not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in values):
                raise ListProblem(f"{where}.{k}", "expected a list of numbers", values)
            dims.append(Dim(name, f"{where}.{k}", tuple(float(v) * factor for v in values), tuple(values), units,
                            long_name))
        axes.append(values)
    tables = []
    for combo in itertools.product(*axes):
        t = copy.deepcopy(table)
        t.update({k: copy.deepcopy(v) for k, v in zip(listed, combo)})
        tables.append(t)
    return dims, tables


def _coverage_levels(table: dict, where: str) -> None:
    if isinstance(table.get("coverage_percent"), list):
        _check_list(f"{where}.coverage_percent", table["coverage_percent"])


def expand(data: dict) -> tuple[list[Dim], list[Variant]]:
    """The process dimensions and the variants of a study's merged raw tables (``data`` is not changed).

    Raises :class:`ListProblem` for a list that cannot be a dimension."""
    target, named, sweep = data.get("target"), data.get("targets"), data.get("sweep")
    if named is not None and target is not None:
        raise ListProblem("targets", "give one [target] table or named [targets.NAME] tables, not both")
    dims: list[Dim] = []
    target_points: list[tuple[dict, dict | None]] = [({}, None)]
    if isinstance(target, dict):
        _coverage_levels(target, "target")
        tdims, tables = _target_dims(target, "target")
        dims += tdims
        target_points = [({d.name: _value(d, t) for d in tdims}, t) for t in tables]
    elif named is not None:
        if not isinstance(named, dict) or not named or not all(isinstance(v, dict) for v in named.values()):
            raise ListProblem("targets", "expected named tables [targets.NAME], each a full [target] table", named)
        per = {}
        for name, table in named.items():
            _coverage_levels(table, f"targets.{name}")
            per[name] = _target_dims(table, f"targets.{name}")
        first = next(iter(per.values()))[0]
        for name, (tdims, _) in per.items():
            if [(d.name, d.given) for d in tdims] != [(d.name, d.given) for d in first]:
                raise ListProblem(f"targets.{name}", "lists in named targets must be the same in every one (the "
                                  "same keys and values): they are the map's dimensions")
        names = tuple(named)
        dims.append(Dim("target", "targets", names, names, "1", "named target (a REV of the part)", labels=True))
        dims += [Dim(d.name, d.key.replace(f"targets.{names[0]}", "targets.*"), d.values, d.given, d.units,
                     d.long_name, d.labels) for d in first]
        target_points = [({"target": name, **{d.name: _value(d, t) for d in per[name][0]}}, t)
                         for name in names for t in per[name][1]]
    sweep_dims, sweep_points = _sweep(sweep, data)
    dims += sweep_dims
    one_dims, one_points = _sensitivity(data.get("sensitivity"), data, sweep)
    dims += one_dims
    sweep_points = [({**sc, **oc}, {**so, **oo}) for (sc, so), (oc, oo) in itertools.product(sweep_points, one_points)]
    taken = [d.name for d in dims]
    for name in set(taken):
        if taken.count(name) > 1:
            raise ListProblem(next(d.key for d in dims if d.name == name),
                              f"two lists make the same dimension {name!r}: sweep one of them")
    variants = [Variant({**tc, **sc}, t, ov) for (tc, t), (sc, ov) in itertools.product(target_points, sweep_points)]
    return dims, variants


def _value(dim: Dim, table: dict):
    """The dimension's value (SI, or the name) of a combination's scalar table."""
    return dim.values[dim.given.index(table[dim.key.rpartition(".")[2]])]


def _check_key(table: str, key: str, values, data: dict) -> list:
    """A ``[sweep]`` or ``[sensitivity]`` entry: a dotted numeric study key and a list of numbers."""
    where = f"{table}.{key}" if "." not in key else f'{table}."{key}"'
    values = _check_list(where, values)
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in values):
        raise ListProblem(where, "expected a list of numbers (only numeric keys can be swept)", values)
    top, _, rest = key.partition(".")
    if top in ("study", "execution"):
        raise ListProblem(where, f"{key} cannot be swept: [{top}] changes no result")
    if top not in SWEEPABLE_TOP or not rest:
        raise ListProblem(where, f"{key} is not a study key (expected a dotted path such as "
                          '"shot.friction_coefficient" or "materials.SAE1070.johnson_cook.C")')
    if top == "target":
        field = rest.partition(".")[0]
        if field in TARGET_LIST_KEYS or field == "coverage_percent":
            raise ListProblem(where, f"target.{field} is swept as a list in [target] itself "
                              f"(target.{field} = [...]); give it there")
        if isinstance(data.get("target"), dict) and isinstance(data["target"].get(field), list):
            raise ListProblem(where, f"target.{field} is already a list in [target]")
    current = _lookup(data, key)
    if isinstance(current, list):
        raise ListProblem(where, f"{key} is already a list (a sweep of its own): it cannot be swept again")
    if current is not None and (not isinstance(current, (int, float)) or isinstance(current, bool)):
        raise ListProblem(where, f"{key} = {current!r} is not a number: only numeric keys can be swept")
    return values


def _sweep(sweep, data: dict) -> tuple[list[Dim], list[tuple[dict, dict]]]:
    if sweep is None:
        return [], [({}, {})]
    if not isinstance(sweep, dict) or not sweep:
        raise ListProblem("sweep", 'expected a table of dotted study keys and lists, e.g. '
                          '"shot.friction_coefficient" = [0.1, 0.2, 0.4]', sweep)
    dims, axes = [], []
    for key, values in sweep.items():
        values = _check_key("sweep", key, values, data)
        name, factor, units = sweep_dim_name(key)
        dims.append(Dim(name, key, tuple(float(v) * factor for v in values), tuple(values), units,
                        f"swept study key {key}"))
        axes.append(values)
    points = [({d.name: d.values[d.given.index(v)] for d, v in zip(dims, combo)},
               {d.key: v for d, v in zip(dims, combo)}) for combo in itertools.product(*axes)]
    return dims, points


#: the dimension of a [sensitivity] table and the name of its unchanged point
SENSITIVITY_DIM, BASELINE = "sensitivity", "baseline"


def sensitivity_label(key: str, value) -> str:
    """The name of the point that changes ``key`` to ``value`` (CF flag-meaning characters only)."""
    return f"{key}@{value:g}"


def _sensitivity(table, data: dict, sweep) -> tuple[list[Dim], list[tuple[dict, dict]]]:
    """One input at a time: the study as written (``baseline``) and, for every key and value of the
    table, the study with that one key changed; one labelled dimension ``sensitivity``."""
    if table is None:
        return [], [({}, {})]
    if not isinstance(table, dict) or not table:
        raise ListProblem("sensitivity", 'expected a table of dotted study keys and the values to try one at a '
                          'time, e.g. "shot.friction_coefficient" = [0.1, 0.4]', table)
    labels, overrides = [BASELINE], [{}]
    for key, values in table.items():
        values = _check_key("sensitivity", key, values, data)
        if isinstance(sweep, dict) and key in sweep:
            raise ListProblem(f'sensitivity."{key}"', f"{key} is also in [sweep]: vary it in one of them")
        current = _lookup(data, key)
        for v in values:
            if current is not None and float(v) == float(current):
                continue  # the baseline itself
            labels.append(sensitivity_label(key, v))
            overrides.append({key: v})
    if len(labels) == 1:
        raise ListProblem("sensitivity", "every value given is the study's own: give values to change to")
    dim = Dim(SENSITIVITY_DIM, "sensitivity", tuple(labels), tuple(labels), "1",
              "the one input changed from the study as written (baseline: none)", labels=True)
    return [dim], [({SENSITIVITY_DIM: lab}, ov) for lab, ov in zip(labels, overrides)]


def _lookup(data: dict, key: str):
    obj = data
    for part in key.split("."):
        if not isinstance(obj, dict) or part not in obj:
            return None
        obj = obj[part]
    return obj


def apply_overrides(data: dict, overrides: dict) -> None:
    """Set each dotted ``key: value`` of ``overrides`` in ``data`` (tables created on the way)."""
    for key, value in overrides.items():
        obj = data
        parts = key.split(".")
        for part in parts[:-1]:
            if not isinstance(obj.get(part), dict):
                obj[part] = {}
            obj = obj[part]
        obj[parts[-1]] = value
