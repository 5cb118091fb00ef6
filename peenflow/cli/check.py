"""Validate a study file and list the stages it expands into (computes nothing)."""

from __future__ import annotations

from collections import Counter

from ._common import add_study, load

NAME = "check"
HELP = "validate a study file and show its stages"


def add_arguments(p) -> None:
    add_study(p)


def main(args) -> int:
    graph, _ = load(args)
    counts = Counter(n.stage for n in graph.nodes)
    print(f"study {graph.name}: valid; {len(graph.nodes)} points in {len(counts)} stages")
    for stage, n in counts.items():
        print(f"  {stage}: {n}")
    return 0
