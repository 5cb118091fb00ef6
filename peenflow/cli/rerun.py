"""Recompute one stage and everything downstream of it; reuse the rest."""

from __future__ import annotations

from ._common import add_study, load, stage_nodes
from .run import add_execution, execute_and_report

NAME = "rerun"
HELP = "force a stage and its downstream to recompute"


def add_arguments(p) -> None:
    add_study(p)
    p.add_argument("stage", help="stage to recompute")
    add_execution(p)


def main(args) -> int:
    graph, store = load(args)
    forced = {n.node_id for n in graph.descendants(stage_nodes(graph, args.stage))}
    return execute_and_report(args, graph, store, list(graph.nodes), forced)
