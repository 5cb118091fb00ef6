"""Opening results for analysis: one Dataset per stage, sweeps combined."""

from __future__ import annotations

import xarray as xr

from .combine import combine_points
from .conventions import retag_point
from .graph import Graph
from .planner import plan
from .reasons import State
from .store import DirectoryStore


class ResultNotReady(LookupError):
    pass


def stage_result(graph: Graph, store: DirectoryStore, stage: str, allow_partial: bool = False,
                 lazy: bool = False) -> xr.Dataset:
    """The stage's Dataset; a swept stage's points combined along its sweep dims.

    ``lazy``: dask-backed (values read when computed), else loaded into memory.
    Provenance attributes are kept: a combined stage keeps those its points
    share, and every point's own in ``peenflow_points`` (JSON).
    """
    nodes = graph.stage_nodes(stage)
    items = [i for i in plan(graph, store, graph.until(stage)) if i.node.stage == stage]
    ready = [i for i in items if i.state in (State.DONE, State.STALE)]
    if not ready or (len(ready) < len(items) and not allow_partial):
        missing = [i.node.node_id for i in items if i not in ready]
        raise ResultNotReady(
            f"stage {stage!r}: {len(ready)} of {len(items)} points done; not done: "
            + ", ".join(missing[:5]) + ("..." if len(missing) > 5 else "")
            + f" -- run `peenflow run` first"
        )
    opener = store.open_lazy if lazy else store.open
    datasets = [retag_point(opener(i.node.task.name, i.key), i.node.coords) for i in ready]
    if len(nodes) == 1 and not nodes[0].coords:
        return datasets[0]
    dims = list(dict.fromkeys(d for n in nodes for d in n.coords))
    return combine_points(datasets, [i.node.coords for i in ready], dims)
