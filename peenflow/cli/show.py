"""Print a stage's Dataset summary and the result file path(s)."""

from __future__ import annotations

from ..engine import ResultNotReady, plan, stage_result
from ._common import UserError, add_study, load, stage_nodes

NAME = "show"
HELP = "print a stage's Dataset and its file paths"


def add_arguments(p) -> None:
    add_study(p)
    p.add_argument("stage")


def main(args) -> int:
    graph, store = load(args)
    stage_nodes(graph, args.stage)
    try:
        ds = stage_result(graph, store, args.stage, allow_partial=True)
    except ResultNotReady as exc:
        raise UserError(str(exc)) from None
    print(ds)
    print("\nfiles:")
    for item in plan(graph, store, graph.until(args.stage)):
        if item.node.stage == args.stage and item.key:
            print(f"  {item.node.node_id}: {store.result_path(item.node.task.name, item.key)}")
    return 0
