"""Validate a study file and list the stages it expands into (computes nothing)."""

from __future__ import annotations

from collections import Counter

from ._common import add_study, dim_values, load

NAME = "check"
HELP = "validate a study file and show its stages"


def add_arguments(p) -> None:
    add_study(p)


def main(args) -> int:
    graph, _ = load(args)
    counts = Counter(n.stage for n in graph.nodes)
    print(f"study {graph.name}: valid; {len(graph.nodes)} points in {len(counts)} stages")
    dims = graph.labels.get("process_dims") or []
    if dims:
        print("process dimensions:")
        for d in dims:
            a = graph.coord_attrs.get(d, {})
            print(f"  {d}: {dim_values(graph, d)}  ({a.get('peenflow_study_key', '')})")
    levels = graph.labels.get("coverage_levels_percent") or []
    if len(levels) > 1:
        print(f"coverage levels: {', '.join(f'{c:g}' for c in levels)} % (one REV run per sequence reaches them all)")
    for stage, n in counts.items():
        per = [d for d in dims if any(d in node.coords for node in graph.stage_nodes(stage))]
        print(f"  {stage}: {n}" + (f"  (per {', '.join(per)})" if per else ""))
    return 0
