"""What ``status`` and ``run --dry-run`` show: each point's state and reason.

The planner grows the graph's growing sweeps from what the store holds
(:mod:`.growth`), then states every point (:func:`.point_states.plan_items`).
"""

from __future__ import annotations

from .graph import Graph, Node
from .growth import resolve, with_grown
from .point_states import PlanItem, plan_items
from .store import DirectoryStore

__all__ = ["PlanItem", "plan", "plan_items"]


def plan(graph: Graph, store: DirectoryStore, nodes: list[Node] | None = None,
         forced: set[str] = frozenset()) -> list[PlanItem]:
    """One :class:`PlanItem` per node, in graph order.

    A graph with growing sweeps is first grown from what the store holds
    (:func:`.growth.resolve`); points so added join ``nodes`` where their
    sweep already has a point there.
    """
    if graph.growing:
        added = resolve(graph, store)
        nodes = None if nodes is None else with_grown(graph, nodes, added)
    return plan_items(graph, store, nodes, forced)
