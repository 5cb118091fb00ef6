"""The DAG of task instances ("points") a study expands into.

A *stage* is one task in the graph; it has one point, or one point per
combination of its sweep coordinates.  Upstream links:

* ``graph.add(t, upstream={"impact": node})`` -- one upstream result;
* ``graph.sweep(t, dims={...}, upstream={"run": other_sweep})`` -- when an
  upstream is a sweep, each point of this sweep receives the upstream points
  that agree with it on the shared dims; dims the upstream has and this
  sweep does not are *combined* into one Dataset along those dims (e.g. a
  per-(angle, velocity) saturation fit receives all sequences of its strip
  runs as one Dataset with a ``sequence`` dim).

A *family* of graphs (one per combination of a study's process dimensions)
is built into one graph inside :meth:`Graph.variant` blocks: a point whose
task, parameters and upstream points are those of a point already in the
graph *is* that point, so what a dimension does not reach is computed once
and shared; :meth:`Graph.settle_variants` then gives every point the
dimension values all the combinations that reach it agree on.

The engine knows nothing about what the tasks compute.
"""

from __future__ import annotations

import contextlib
import itertools
from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping

from .canonical import canonical_json, canonical_value
from .task import Task


def point_label(coords: Mapping[str, Any]) -> str:
    """``angle_deg=45,velocity_m_s=25`` -- stable, human-readable point name."""
    return ",".join(f"{k}={canonical_json(v)}" for k, v in coords.items())


@dataclass(eq=False)
class Node:
    """One point: a task, its canonical parameters and its upstream links."""

    task: Task
    stage: str
    params: dict
    upstream: dict  # name -> Node | Group
    coords: dict = field(default_factory=dict)  # sweep coordinates of this point
    #: attributes written on this point's result besides the graph's and its stage's (outside its key)
    result_attrs: dict = field(default_factory=dict)

    @property
    def label(self) -> str:
        return point_label(self.coords)

    @property
    def node_id(self) -> str:
        return f"{self.stage}[{self.label}]" if self.coords else self.stage

    def identity(self) -> tuple:
        """What makes two points the same point: task, stage, parameters and upstream points (by identity)."""
        ups = []
        for name, up in sorted(self.upstream.items()):
            members = up.nodes if isinstance(up, Group) else [up]
            ups.append((name, tuple(id(n) for n in members), tuple(up.dims) if isinstance(up, Group) else None))
        return (self.task.name, self.stage, canonical_json(self.params), tuple(ups))

    def upstream_nodes(self) -> list["Node"]:
        out: list[Node] = []
        for up in self.upstream.values():
            out.extend(up.nodes if isinstance(up, Group) else [up])
        return out


@dataclass(eq=False)
class Group:
    """Several upstream points combined into one Dataset along ``dims``."""

    nodes: list[Node]
    dims: tuple[str, ...]


@dataclass(eq=False)
class Sweep:
    """The points of one swept stage, with their coordinates.

    A growing sweep (``grow``, see :mod:`.growth`) starts with the first
    ``grow.start`` values of ``grow.dim`` and gains the next value per group of
    its other dims when ``grow.until`` asks for it: ``make_node(coords)``
    builds such a point the way :meth:`Graph.sweep` built the others, and every
    :class:`Group` handed downstream is kept in ``groups`` (with the coordinates
    it was selected by) so a new point joins the groups it belongs to.
    """

    stage: str
    dims: tuple[str, ...]
    nodes: list[Node]
    grow: Any = None  # growth.Grow | None
    grow_values: list = field(default_factory=list)  # every value grow.dim may take, in order
    make_node: Any = None  # coords -> Node (growing sweeps only)
    groups: list = field(default_factory=list)  # growing sweeps: [(selecting coords, Group)] handed downstream

    def select(self, **coords) -> Group | Node:
        """Points matching ``coords``; a single point if every dim is fixed."""
        picked = [
            n for n in self.nodes
            if all(canonical_value(n.coords[k]) == canonical_value(v) for k, v in coords.items())
        ]
        rest = tuple(d for d in self.dims if d not in coords)
        if not rest and len(picked) == 1:
            return picked[0]
        return self._handed_down(Group(picked, rest), coords)

    def all(self) -> Group:
        return self._handed_down(Group(list(self.nodes), self.dims), {})

    def _handed_down(self, group: Group, coords: dict) -> Group:
        if self.grow is not None:  # a later point of this sweep must join the groups it belongs to
            self.groups.append((dict(coords), group))
        return group


class Graph:
    """An ordered collection of points; insertion order is a topological order."""

    def __init__(self, name: str):
        self.name = name
        self.nodes: list[Node] = []
        self._stages: dict[str, Task] = {}
        #: execution defaults a study may set (``workers``, ``threads``); command-line flags win
        self.execution: dict = {}
        #: names a person reads in views of the results (never part of a key): ``{what: name}``
        self.labels: dict = {}
        #: attributes of sweep coordinates in stored results, ``{dim: {"units": ..., "long_name": ...}}``
        self.coord_attrs: dict = {}
        #: attributes written on every result this graph computes, outside every key and content
        #: hash (a study's statement about its own fidelity, say): names start with ``peenflow_``,
        #: the provenance prefix; a result reused from another study keeps its own
        self.result_attrs: dict[str, str] = {}
        #: per stage, attributes that replace or add to ``result_attrs`` on that stage's results
        #: (``{stage: {name: value}}``: a stage computed at another fidelity says so)
        self.stage_result_attrs: dict[str, dict[str, str]] = {}
        #: sweeps with a growing dimension (:mod:`.growth`), in graph order
        self.growing: list[Sweep] = []
        #: where each group of a growing sweep stands after the last ``growth.resolve``
        #: (``{stage: {group label: growth.GroupState}}``)
        self.growth: dict = {}
        #: the growth rules' verdicts, by (stage, content hashes of the group's points): asked once each
        self.growth_verdicts: dict = {}
        #: building a family (:meth:`variant`): the coordinates of the combination being built, the points
        #: by identity, and per point the combinations that reached it
        self._variant: dict | None = None
        self._interned: dict[tuple, Node] = {}
        self._sweeps: dict[str, list[Sweep]] = {}
        #: the points the combination being built reached (:meth:`variant`)
        self.variant_nodes: list[Node] = []
        self._reached: dict[int, list[dict]] = {}

    # -- families -----------------------------------------------------------
    @contextlib.contextmanager
    def variant(self, coords: dict):
        """Build one combination of a family (module docstring): points equal to existing ones are shared."""
        self._variant = dict(coords)
        self.variant_nodes = []
        try:
            yield self
        finally:
            self._variant = None

    def _intern(self, node: Node) -> tuple[Node, bool]:
        """(the point, whether it is new); inside a family every point is interned by its identity."""
        key = node.identity()
        existing = self._interned.get(key)
        if existing is not None:
            node = existing
        else:
            self._interned[key] = node
        if self._variant is not None:
            self._reached.setdefault(id(node), []).append(self._variant)
            self.variant_nodes.append(node)
        return node, existing is None

    def settle_variants(self, dims) -> None:
        """Give each point of a family the values of ``dims`` that every combination reaching it agrees on
        (labels and stored coordinates; never parameters, so a shared point keeps its key)."""
        for node in self.nodes:
            reached = self._reached.get(id(node))
            if not reached:
                continue
            for d in dims:
                values = {canonical_json(c[d]) for c in reached if d in c}
                if len(values) == 1 and all(d in c for c in reached) and d not in node.coords:
                    node.coords[d] = reached[0][d]
        # A family that is not a product (one value changed at a time) can reach some points of a stage along
        # a dimension and share one point among the other combinations: that shared point is stored under
        # the first combination that reached it, so the stage still combines along the dimension.
        for d in dims:
            by_stage: dict[str, list] = {}
            for node in self.nodes:
                by_stage.setdefault(node.stage, []).append(node)
            for nodes in by_stage.values():
                if any(d in n.coords for n in nodes) and not all(d in n.coords for n in nodes):
                    for n in nodes:
                        reached = self._reached.get(id(n))
                        if d not in n.coords and reached and d in reached[0]:
                            n.coords[d] = reached[0][d]

    # -- building -----------------------------------------------------------
    def _register_stage(self, task: Task, stage: str | None) -> str:
        stage = stage or task.name
        if stage in self._stages:
            if self._variant is not None and self._stages[stage] is task:  # another combination of a family
                return stage
            raise ValueError(f"stage {stage!r} added twice; pass stage=... to name the second one")
        self._stages[stage] = task
        return stage

    def add(self, task: Task, params: Mapping | None = None, upstream: Mapping | None = None,
            stage: str | None = None) -> Node:
        stage = self._register_stage(task, stage)
        up = {k: (v.all() if isinstance(v, Sweep) else v) for k, v in (upstream or {}).items()}
        node, new = self._intern(Node(task, stage, canonical_value(dict(params or {})), up))
        if new:
            self.nodes.append(node)
        return node

    def sweep(self, task: Task, dims: Mapping[str, Iterable], params: Mapping | None = None,
              upstream: Mapping | None = None, stage: str | None = None,
              point_params=None, grow=None) -> Sweep:
        """One point per combination of ``dims`` (their values become parameters too).

        ``point_params(coords) -> dict`` may add parameters that depend on the point.
        ``grow``: a :class:`.growth.Grow` on one of ``dims`` -- only its first
        ``grow.start`` values get points now; the others are added per group of
        the remaining dims while ``grow.until`` asks for more (``plan`` and
        ``execute`` do that, from stored results).  A point's parameters and
        key do not depend on how many values its dim has grown to.
        """
        stage = self._register_stage(task, stage)
        names = tuple(dims)
        values = [list(dims[d]) for d in names]
        for d, vals in zip(names, values):
            if len({canonical_json(v) for v in vals}) != len(vals):
                raise ValueError(f"sweep dim {d!r} of stage {stage!r} has repeated values: {vals}")
        upstream = dict(upstream or {})

        def make_node(coords: dict) -> Node:
            p = dict(params or {})
            p.update(coords)
            if point_params is not None:
                p.update(point_params(coords))
            up = {k: self._align(v, coords) for k, v in upstream.items()}
            return Node(task, stage, canonical_value(p), up, coords=dict(coords))

        sweep = Sweep(stage, names, [])
        if grow is not None:
            if grow.dim not in names:
                raise ValueError(f"stage {stage!r} grows dim {grow.dim!r}, which is not one of its dims {names}")
            i = names.index(grow.dim)
            if not 1 <= grow.start <= len(values[i]):
                raise ValueError(f"stage {stage!r}: grow.start = {grow.start} must be between 1 and the "
                                 f"{len(values[i])} values of {grow.dim!r}")
            sweep.grow, sweep.grow_values, sweep.make_node = grow, values[i], make_node
            values[i] = values[i][:grow.start]
            self.growing.append(sweep)
        for combo in itertools.product(*values):
            node, new = self._intern(make_node(dict(zip(names, combo))))
            sweep.nodes.append(node)
            if new:
                self.nodes.append(node)
        # another combination of a family whose points are all those of an earlier sweep: that sweep (it
        # grows once)
        for earlier in self._sweeps.get(stage, []):
            if [id(n) for n in earlier.nodes[:len(sweep.nodes)]] == [id(n) for n in sweep.nodes]:
                if grow is not None:
                    self.growing.remove(sweep)
                return earlier
        self._sweeps.setdefault(stage, []).append(sweep)
        return sweep

    @staticmethod
    def _align(up, coords):
        if isinstance(up, Sweep):
            shared = {k: v for k, v in coords.items() if k in up.dims}
            return up.select(**shared) if shared else up.all()
        return up

    # -- queries ------------------------------------------------------------
    @property
    def stages(self) -> list[str]:
        return list(self._stages)

    def stage_nodes(self, stage: str) -> list[Node]:
        if stage not in self._stages:
            raise KeyError(f"no stage {stage!r}; stages are: {', '.join(self._stages)}")
        return [n for n in self.nodes if n.stage == stage]

    def ancestors(self, nodes: Iterable[Node]) -> list[Node]:
        """``nodes`` and everything they depend on, in graph order."""
        keep: set[int] = set()
        stack = list(nodes)
        while stack:
            n = stack.pop()
            if id(n) in keep:
                continue
            keep.add(id(n))
            stack.extend(n.upstream_nodes())
        return [n for n in self.nodes if id(n) in keep]

    def descendants(self, nodes: Iterable[Node]) -> list[Node]:
        """``nodes`` and everything that depends on them, in graph order."""
        keep = {id(n) for n in nodes}
        for n in self.nodes:
            if any(id(u) in keep for u in n.upstream_nodes()):
                keep.add(id(n))
        return [n for n in self.nodes if id(n) in keep]

    def until(self, stage: str) -> list[Node]:
        return self.ancestors(self.stage_nodes(stage))
