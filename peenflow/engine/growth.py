"""Sweep dimensions that grow: add points while the results so far ask for more.

A sweep declared with ``grow=Grow(dim, start, until)`` starts with the first
``start`` values of ``dim`` in every group of its other dims (for example the
first two random sequences of each (angle, velocity) point).  Once every point
of a group is stored, ``until(datasets, coords)`` -- supplied by the tasks;
the engine knows nothing of what it computes -- says whether the group needs
the next value; it is asked again when that point is stored, up to the last
value the sweep was given.

Why this shape:

* every point stays its own cached, checkpointed result, and its key does not
  depend on how many points its group grew to, so growing reuses all work and
  points of different groups still run in parallel;
* the decision is a pure function of stored results, asked only when all of a
  group's points are stored, so an interrupted run, a resumed one, ``status``
  and ``clean`` all see the same points;
* what consumes a group (a fit over its sequences) runs only once the group is
  decided, never on a partial group.

``resolve`` grows a graph from what a store holds (``plan`` calls it, so
every verb sees the grown graph); ``held`` names the points waiting on an
undecided group (``execute`` runs the rest, resolves again, and repeats).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from .canonical import canonical_json
from .graph import Graph, Group, Node, Sweep
from .point_states import plan_items
from .reasons import State


@dataclass(frozen=True)
class GrowVerdict:
    """``more``: add the next value; ``reason``: one sentence for the record."""

    more: bool
    reason: str


@dataclass(frozen=True)
class Grow:
    """A growing sweep dimension.

    dim : the sweep dimension that grows (its values, in order, are the most it may take).
    start : how many of its values every group starts with (>= 1).
    until : ``until(datasets, coords) -> GrowVerdict | bool``: the group's stored results in
        the order of ``dim``'s values, and the group's other coordinates; True / ``more``
        asks for the next value.
    """

    dim: str
    start: int
    until: Callable


@dataclass
class GroupState:
    """Where one group of a growing sweep stands: ``waiting`` (points not all stored),
    ``more`` (the next point was added), ``done`` (until said enough), ``cap``
    (every value used and until still asked for more) or ``error`` (until raised:
    the group is held, ``reason`` says why)."""

    sweep: Sweep
    coords: dict
    members: list[Node]
    state: str
    reason: str = ""


def group_label(node: Node, dim: str) -> str:
    return canonical_json({k: v for k, v in node.coords.items() if k != dim})


def _groups(sweep: Sweep) -> dict[str, list[Node]]:
    out: dict[str, list[Node]] = {}
    for n in sweep.nodes:
        out.setdefault(group_label(n, sweep.grow.dim), []).append(n)
    return out


def _stored(graph: Graph, store, members: list[Node]) -> list | None:
    """The members' stored Datasets (in order), or None if any is not stored yet."""
    items = {id(i.node): i for i in plan_items(graph, store, graph.ancestors(members))}
    out = []
    for n in members:
        it = items[id(n)]
        if it.state not in (State.DONE, State.STALE):
            return None
        out.append((n, it.key, it.content_hash))
    return out


def _ask(graph: Graph, store, sweep: Sweep, stored: list, coords: dict) -> GrowVerdict:
    cache = graph.growth_verdicts
    memo = (sweep.stage, tuple(h for _, _, h in stored))
    if memo not in cache:
        from .conventions import retag_point, squeeze_point

        # as a task would receive them: the point's sweep values as 0-d coordinates
        datasets = [squeeze_point(retag_point(store.open(n.task.name, key), n.coords), n.coords)
                    for n, key, _ in stored]
        v = sweep.grow.until(datasets, coords)
        cache[memo] = v if isinstance(v, GrowVerdict) else GrowVerdict(bool(v), "")
    return cache[memo]


def _add(graph: Graph, sweep: Sweep, coords: dict) -> Node:
    node = sweep.make_node(coords)
    last = max(graph.nodes.index(n) for n in sweep.nodes)
    graph.nodes.insert(last + 1, node)  # after its siblings: still a topological order
    sweep.nodes.append(node)
    for selected, group in sweep.groups:
        if all(canonical_json(node.coords[k]) == canonical_json(v) for k, v in selected.items()):
            group.nodes.append(node)
    return node


def resolve(graph: Graph, store) -> list[Node]:
    """Add every point the stored results ask for; the added points, in graph order.

    Records each group's :class:`GroupState` in ``graph.growth`` (by stage, then group label).
    """
    added: list[Node] = []
    states: dict[str, dict[str, GroupState]] = {}
    for sweep in graph.growing:
        dim = sweep.grow.dim
        per = states.setdefault(sweep.stage, {})
        for label, members in _groups(sweep).items():
            coords = {k: v for k, v in members[0].coords.items() if k != dim}
            while True:
                stored = _stored(graph, store, members)
                if stored is None:
                    per[label] = GroupState(sweep, coords, members, "waiting",
                                            f"{len(members)} of {dim} so far, not all stored")
                    break
                try:
                    verdict = _ask(graph, store, sweep, stored, coords)
                except Exception as exc:  # the tasks' rule failed: hold the group, say why
                    per[label] = GroupState(sweep, coords, members, "error",
                                            f"deciding whether {sweep.stage} needs more {dim} failed: "
                                            f"{type(exc).__name__}: {exc}")
                    break
                if not verdict.more:
                    per[label] = GroupState(sweep, coords, members, "done", verdict.reason)
                    break
                if len(members) >= len(sweep.grow_values):
                    per[label] = GroupState(sweep, coords, members, "cap",
                                            f"all {len(members)} values of {dim} used; {verdict.reason}")
                    break
                node = _add(graph, sweep, {**members[0].coords, dim: sweep.grow_values[len(members)]})
                members.append(node)
                added.append(node)
                per[label] = GroupState(sweep, coords, members, "more", verdict.reason)
    graph.growth = states
    order = {id(n): i for i, n in enumerate(graph.nodes)}
    return sorted(added, key=lambda n: order[id(n)])


def held(graph: Graph) -> list[Node]:
    """Points that consume an undecided group (``waiting`` / ``more``), and what depends on them."""
    undecided = set()
    for per in graph.growth.values():
        for st in per.values():
            if st.state in ("waiting", "more", "error"):
                undecided.update(id(n) for n in st.members)
    if not undecided:
        return []
    consumers = [n for n in graph.nodes
                 if any(isinstance(up, Group) and any(id(m) in undecided for m in up.nodes)
                        for up in n.upstream.values())]
    return graph.descendants(consumers)


def with_grown(graph: Graph, nodes: list[Node], added: list[Node]) -> list[Node]:
    """``nodes`` plus the ``added`` points whose sweep already had a point in ``nodes`` (graph order)."""
    if not added:
        return nodes
    chosen = {id(n) for n in nodes}
    for sweep in graph.growing:
        if any(id(n) in chosen for n in sweep.nodes):
            chosen.update(id(n) for n in added if n in sweep.nodes)
    return [n for n in graph.nodes if id(n) in chosen]
