"""Print a stage's results in full -- every variable's values, units and meaning -- and the file path(s).

STAGE is a stage name (``peenflow check`` lists them) or the name of the task
a stage runs (``single_impact``, ``dmin``...) when one stage runs it.  Arrays
longer than ``--max-values`` are summarised (shape, min, max, mean) unless
``--all`` is given; values are printed at full precision.
"""

from __future__ import annotations

import sys

import numpy as np

from ..engine import ResultNotReady, plan, stage_result
from ._common import UserError, add_study, load

NAME = "show"
HELP = "print a stage's results in full, and their file paths"

MAX_VALUES = 200


def add_arguments(p) -> None:
    add_study(p)
    p.add_argument("stage", help="stage name, or the task name a single stage runs")
    p.add_argument("--all", action="store_true", help="print every value of every array, however long")
    p.add_argument("--max-values", type=int, default=MAX_VALUES, metavar="N",
                   help=f"print arrays up to N values in full, summarise longer ones (default {MAX_VALUES})")


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


def _values(v, limit: int | None) -> str:
    a = np.asarray(v.values)
    if limit is not None and a.size > limit and a.dtype.kind in "fiu":
        finite = a[np.isfinite(a)] if a.dtype.kind == "f" else a
        if finite.size:
            return (f"{a.size} values: min {finite.min()!r}, max {finite.max()!r}, mean {finite.mean()!r}"
                    f" (--all prints them)")
        return f"{a.size} values, all NaN"
    with np.printoptions(threshold=sys.maxsize, linewidth=110, floatmode="unique"):
        text = np.array2string(a, separator=", ") if a.ndim else repr(a.item())
    return text


def describe(ds, limit: int | None) -> str:
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
            head = f"  {name}" + (f" ({', '.join(v.dims)})" if v.dims else "") + (f" [{units}]" if units else "")
            lines.append(head + (f"  {meaning}" if meaning else "") + (f"  flags: {flags}" if flags else ""))
            body = _values(v, limit)
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
    print(describe(ds, None if args.all else args.max_values))
    print("\nfiles:")
    for item in plan(graph, store, graph.until(stage)):
        if item.node.stage == stage and item.key:
            print(f"  {item.node.node_id}: {store.result_path(item.node.task.name, item.key)}")
    return 0
