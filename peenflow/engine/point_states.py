"""Each point's state and the reason it would run, from the store alone: what ``plan`` reports.

The rules are the runner's (``keys.reason_against_slot``, ``store.check``,
the checkpoint rule ``checkpoint.judge``, the lease verdict) applied without computing anything.  A point whose upstream
is not yet computed has no key yet (keys include upstream *content*); it is
shown as pending with the reason judged from what is known.  Growing sweeps
are not grown here (:mod:`.planner` grows them first; :mod:`.growth` asks
this module which members are stored).
"""

from __future__ import annotations

from dataclasses import dataclass

from .checkpoint import CheckpointState, describe_position, judge
from .graph import Graph, Group, Node
from .keys import KeyParts, reason_against_slot
from .lease import STALE_AFTER_S
from .reasons import Reason, State
from .store import DirectoryStore


@dataclass
class PlanItem:
    node: Node
    key: str | None
    state: State
    reason: Reason
    detail: str = ""
    content_hash: str | None = None
    progress: dict | None = None


def _upstream_hashes(node: Node, items: dict) -> dict | None:
    out = {}
    for name, up in node.upstream.items():
        if isinstance(up, Group):
            pairs = []
            for n in up.nodes:
                h = items[id(n)].content_hash
                if h is None:
                    return None
                pairs.append([n.label, h])
            out[name] = sorted(pairs)
        else:
            h = items[id(up)].content_hash
            if h is None:
                return None
            out[name] = h
    return out


def plan_items(graph: Graph, store: DirectoryStore, nodes: list[Node] | None = None,
               forced: set[str] = frozenset()) -> list[PlanItem]:
    """:func:`plan` of the graph as it stands (no growth)."""
    nodes = graph.nodes if nodes is None else nodes
    items: dict[int, PlanItem] = {}
    for node in nodes:
        task = node.task
        code = task.code_id()
        slot = store.slot(graph.name, node.stage, node.label)
        ups = _upstream_hashes(node, items)
        is_forced = node.node_id in forced
        if ups is None:
            blocked = [u.node_id for u in node.upstream_nodes()
                       if items[id(u)].state in (State.FAILED, State.BLOCKED)]
            if is_forced:
                reason, detail = Reason.FORCED, "rerun requested"
            else:
                reason, detail = reason_against_slot(slot, task.name, code, node.params, None)
            state = State.BLOCKED if blocked else State.PENDING
            if blocked:
                detail = f"{detail}; waiting on failed upstream {', '.join(blocked[:3])}"
            items[id(node)] = PlanItem(node, None, state, reason, detail)
            continue
        parts = KeyParts(task.name, code, node.params, ups)
        key = parts.key
        manifest, problem = store.check(task.name, key)
        if manifest is not None and not is_forced:
            if task.version is not None and manifest.source_hash != task.source_hash():
                item = PlanItem(node, key, State.STALE, Reason.STALE,
                                f"code changed under version {task.version}; `peenflow rerun` to refresh",
                                manifest.content_hash)
            else:
                item = PlanItem(node, key, State.DONE, Reason.UP_TO_DATE, "", manifest.content_hash)
            items[id(node)] = item
            continue
        if is_forced:
            reason, detail = Reason.FORCED, "rerun requested"
        else:
            reason, detail = reason_against_slot(slot, task.name, code, node.params, ups)
            if reason is Reason.INCOMPLETE and problem != "missing":
                detail = problem
        checkpoint = judge(store, key, task.name) if not is_forced else None
        if checkpoint is not None and checkpoint.state is CheckpointState.RESUMABLE:
            # where the next run resumes: the checkpoint's position, not a killed run's own count
            where = describe_position(checkpoint.position)
            reason, detail = Reason.INCOMPLETE, (f"the next run resumes from its checkpoint {where}" if where
                                                 else "checkpoint present; will resume from it")
        elif checkpoint is not None and checkpoint.state is CheckpointState.UNREADABLE:
            detail = "; ".join(d for d in (detail, "its checkpoint cannot be read: the next run starts over") if d)
        state = State.PENDING
        progress = None  # a live run's own count (a dead run's is not where anything resumes)
        # The runner's rule (lease.verdict): running while the holder lives; another host's lease
        # without a recent heartbeat blocks; a dead one is broken by the next run.
        lease, alive, why = store.leases.verdict(key)
        if lease is not None and (alive or (alive is None and lease.heartbeat_age_s <= STALE_AFTER_S)):
            state = State.RUNNING
            detail = lease.describe()
            progress = store.progress(key)
        elif lease is not None and alive is None:
            state = State.BLOCKED
            detail = f"{lease.describe()}; if that run is dead, run `peenflow unlock`"
        else:
            if lease is not None:
                detail = f"{detail}; dead lease ({why}): the next run breaks it"
            failure = store.failure(task.name, key)
            if failure is not None:
                state = State.FAILED
                detail = f"last attempt failed: {failure.get('error', '?')}"
        items[id(node)] = PlanItem(node, key, state, reason, detail, None, progress)
    return [items[id(n)] for n in nodes]
