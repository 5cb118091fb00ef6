"""Print a stage's results in full -- every variable's values, units and meaning -- and the file path(s).

STAGE is a stage name (``peenflow check`` lists them) or the name of the task
a stage runs (``single_impact``, ``dmin``...) when one stage runs it.  Arrays
longer than ``--max-values`` are summarised (shape, min, max, mean) unless
``--all`` is given.  Values are shown as a person reads them -- lengths in mm,
stresses in MPa, speeds in m/s, 6 significant digits, whole numbers (shot
counts) without a point -- under the stored SI name and unit
(``intensity_m = 0.000301 m  (0.301 mm)``); ``--exact`` prints the stored SI
values with every digit.
"""

from __future__ import annotations

import sys

import numpy as np

from ..engine import ResultNotReady, plan, stage_result
from ..units import reading_unit
from ._common import UserError, add_study, load

NAME = "show"
HELP = "print a stage's results in full, and their file paths"

MAX_VALUES = 200
#: significant digits a value is shown with (``--exact``: every digit)
DIGITS = 6


def add_arguments(p) -> None:
    add_study(p)
    p.add_argument("stage", help="stage name, or the task name a single stage runs")
    p.add_argument("--all", action="store_true", help="print every value of every array, however long")
    p.add_argument("--max-values", type=int, default=MAX_VALUES, metavar="N",
                   help=f"print arrays up to N values in full, summarise longer ones (default {MAX_VALUES})")
    p.add_argument("--exact", action="store_true",
                   help="print the stored SI values with every digit (default: mm, MPa, m/s, 6 significant digits)")


def resolve_stage(graph, name: str) -> str:
    """``name`` as a stage: a stage name, or a task name that exactly one stage runs."""
    if name in graph.stages:
        return name
    by_task = sorted({n.stage for n in graph.nodes if n.task.name == name})
    if len(by_task) == 1:
        return by_task[0]
    if by_task:
        raise UserError(f"task {name!r} runs in stages {', '.join(by_task)}: name one of them")
    raise UserError(f"no stage {name!r} in study {graph.name!r}; stages: {', '.join(graph.stages)}")


def _text(a: np.ndarray, exact: bool) -> str:
    """An array (or 0-d value) as text: every digit (``exact``), or :data:`DIGITS` significant digits and
    whole numbers (shot counts, velocities given in the study) without a decimal point."""
    if exact or a.dtype.kind != "f":
        with np.printoptions(threshold=sys.maxsize, linewidth=110, floatmode="unique"):
            return np.array2string(a, separator=", ") if a.ndim else repr(a.item())
    finite = a[np.isfinite(a)]
    whole = finite.size and np.all(finite == np.round(finite)) and np.all(np.abs(finite) < 1e15)
    number = (lambda x: f"{x:.0f}" if np.isfinite(x) else f"{x}") if whole else (lambda x: f"{x:.{DIGITS}g}")
    if not a.ndim:
        return number(float(a))
    with np.printoptions(threshold=sys.maxsize, linewidth=110):
        return np.array2string(a, separator=", ", formatter={"float_kind": number})


def _values(v, limit: int | None, exact: bool) -> tuple[str, str]:
    """(the values as a person reads them, the unit they are in): lengths in mm, stresses in MPa
    (:func:`peenflow.units.reading_unit`); ``exact``: in the stored SI unit with every digit."""
    a = np.asarray(v.values)
    factor, unit = (1.0, v.attrs.get("units", "")) if exact else reading_unit(v.attrs.get("units", ""))
    if a.dtype.kind in "fiu" and factor != 1.0:
        a = a * factor
    if limit is not None and a.size > limit and a.dtype.kind in "fiu":
        finite = a[np.isfinite(a)] if a.dtype.kind == "f" else a
        if finite.size:
            stats = ", ".join(f"{what} {_text(np.asarray(f(finite)), exact)}"
                              for what, f in (("min", np.min), ("max", np.max), ("mean", np.mean)))
            return f"{a.size} values: {stats} (--all prints them)", unit
        return f"{a.size} values, all NaN", unit
    return _text(a, exact), unit


def _scalar(v, exact: bool) -> str:
    """``intensity_m = 0.000301 m  (0.301 mm)``: the stored value and unit, and the value as read where
    its unit differs (``--exact``: the stored one alone, every digit)."""
    a = np.asarray(v.values)
    stored = v.attrs.get("units", "")
    si = _text(a, exact) + (f" {stored}" if stored not in ("", "1") else "")
    if exact or a.dtype.kind not in "fiu":
        return si
    factor, unit = reading_unit(stored)
    read = _text(a * factor, False) + (f" {unit}" if unit else "")
    return read if factor == 1.0 else f"{si}  ({read})"


def describe(ds, limit: int | None, exact: bool = False) -> str:
    """Every coordinate, variable and attribute of ``ds``: values as a person reads them (mm, MPa, m/s,
    whole numbers without a point, 6 significant digits), each under its stored SI name and unit;
    ``exact``: in SI with every digit."""
    lines = []
    dims = ", ".join(f"{d}: {n}" for d, n in ds.sizes.items())
    lines.append(f"dimensions: {dims or '(none)'}")
    for title, names in (("coordinates", list(ds.coords)), ("variables", list(ds.data_vars))):
        lines.append(f"{title}:")
        for name in names:
            v = ds[name]
            units = v.attrs.get("units", "")
            meaning = v.attrs.get("long_name", "")
            flags = v.attrs.get("flag_meanings")
            tail = (f"  {meaning}" if meaning else "") + (f"  flags: {flags}" if flags else "")
            if not v.dims:
                lines.append(f"  {name} = {_scalar(v, exact)}{tail}")
                continue
            lines.append(f"  {name} ({', '.join(v.dims)})" + (f" [{units}]" if units else "") + tail)
            body, shown = _values(v, limit, exact)
            if shown and shown != units and reading_unit(units)[0] != 1.0:
                body = f"in {shown}: {body}"
            lines.extend("      " + ln for ln in body.splitlines())
    attrs = {k: v for k, v in ds.attrs.items()}
    if attrs:
        lines.append("attributes:")
        for k, v in attrs.items():
            text = str(v)
            lines.append(f"  {k}: " + text.replace("\n", "\n      "))
    return "\n".join(lines)


def main(args) -> int:
    graph, store = load(args)
    stage = resolve_stage(graph, args.stage)
    try:
        ds = stage_result(graph, store, stage, allow_partial=True)
    except ResultNotReady as exc:
        raise UserError(str(exc)) from None
    print(f"stage {stage}")
    print(describe(ds, None if args.all else args.max_values, args.exact))
    print("\nfiles:")
    for item in plan(graph, store, graph.until(stage)):
        if item.node.stage == stage and item.key:
            print(f"  {item.node.node_id}: {store.result_path(item.node.task.name, item.key)}")
    return 0
