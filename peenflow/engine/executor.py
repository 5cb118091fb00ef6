"""Executing a graph with dask: local threads by default, or a distributed cluster.

* Local (default): dask's threaded scheduler, no server.  The numba kernels
  release the GIL, so threads give real parallelism without pickling large
  arrays.  Each point asks for ``cores // min(workers, points of its stage)``
  compute threads (all cores for a lone point, one each for a wide sweep) and
  draws them from the process's :class:`~.cores.CoreBudget` when it first
  reads ``ctx.threads``, so kernel threads never exceed the cores.  ``threads=N`` fixes
  every point's count instead (no budget: the user's choice).
* ``scheduler="tcp://HOST:PORT"``: the same graph on a running
  dask.distributed cluster; the store must be on a path every worker sees.
  Workers import the task modules by name, so the project must be installed
  on them.  A stop request of this process (Ctrl-C, SIGTERM, SIGHUP) reaches
  the points on the workers through a dask Variable (cluster_stop.py): they
  stop at their next checkpoint as local ones do.  When every point is
  stored already, the scheduler is not contacted: the points are reused here.

Points are submitted as one dask graph; each runs :func:`runner.run_node`,
which records its own failures, so a failed point never stops the others.
"""

from __future__ import annotations

import os
import socket
import threading
import time
import uuid

from .cluster_stop import StopRelay, variable_name
from .cores import CoreBudget, set_active_budget, wanted_threads
from .graph import Graph, Group, Node
from .lease import STALE_AFTER_S
from .point_states import plan_items
from .progress import Reporter
from .reasons import State
from .runner import Outcome, PointSpec, UpstreamRef, run_node, set_notice
from .store import CLEAN_LOCK, DirectoryStore

#: seconds to wait for a dask scheduler to answer (``$PEENFLOW_SCHEDULER_TIMEOUT_S``)
SCHEDULER_TIMEOUT_S = float(os.environ.get("PEENFLOW_SCHEDULER_TIMEOUT_S", "30"))


class SchedulerUnreachable(ConnectionError):
    """The dask scheduler given by ``--scheduler`` did not answer."""


def available_cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - non-Linux
        return os.cpu_count() or 1


def point_specs(graph: Graph, nodes: list[Node], store: DirectoryStore, forced: set[str],
                threads: int | dict[str, int], stop_variable: str | None = None,
                ) -> dict[str, tuple[PointSpec, list[str]]]:
    """Specs of ``nodes``; ``threads``: one count for all, or per stage; ``stop_variable``: see PointSpec."""
    from .content import PROVENANCE_PREFIX

    bad = [k for k in graph.result_attrs if not k.startswith(PROVENANCE_PREFIX)]
    bad += [k for attrs in graph.stage_result_attrs.values() for k in attrs if not k.startswith(PROVENANCE_PREFIX)]
    if bad:  # a programming error of the pipeline: these would enter the content hashes
        raise ValueError(f"graph.result_attrs names must start with {PROVENANCE_PREFIX!r}: {bad}")
    out = {}
    for node in nodes:
        ups: list[Node] = []
        refs = {}
        for name, up in node.upstream.items():
            members = up.nodes if isinstance(up, Group) else [up]
            idx = tuple(range(len(ups), len(ups) + len(members)))
            ups.extend(members)
            refs[name] = UpstreamRef(idx, tuple(up.dims) if isinstance(up, Group) else None)
        spec = PointSpec(
            task_module=node.task.module, task_qualname=node.task.qualname, task_name=node.task.name,
            stage=node.stage, node_id=node.node_id, label=node.label, coords=dict(node.coords),
            params=node.params, upstream=refs, store_root=str(store.root), study=graph.name,
            forced=node.node_id in forced,
            threads=threads[node.stage] if isinstance(threads, dict) else threads,
            sweep_attrs={d: dict(graph.coord_attrs.get(d, {})) for d in node.coords},
            result_attrs={**graph.result_attrs, **graph.stage_result_attrs.get(node.stage, {}), **node.result_attrs},
            stop_variable=stop_variable,
        )
        out[node.node_id] = (spec, [u.node_id for u in ups])
    return out


class _ProgressMonitor(threading.Thread):
    """Polls the store's progress records (works for remote workers too)."""

    def __init__(self, store: DirectoryStore, study: str, reporter: Reporter, every_s: float):
        super().__init__(daemon=True)
        self.store, self.study, self.reporter, self.every_s = store, study, reporter, every_s
        self.stop = threading.Event()
        self._seen: dict[str, tuple] = {}

    def run(self) -> None:
        while not self.stop.wait(self.every_s):
            moved = False
            for key in self.store.progress_keys():
                rec = self.store.progress(key)
                if not rec or rec.get("study") != self.study:
                    continue
                stamp = (rec.get("done"), rec.get("total"))
                if self._seen.get(key) != stamp:
                    self._seen[key] = stamp
                    self.reporter.progress(rec.get("point", key), rec)
                    moved = True
            if moved:
                self.reporter.tick()


def execute(graph: Graph, store: DirectoryStore, nodes: list[Node], *, forced: set[str] = frozenset(),
            scheduler: str | None = None, workers: int | None = None, threads: int | None = None,
            reporter: Reporter | None = None, progress_every_s: float | None = None) -> list[Outcome]:
    """Run ``nodes`` (an ancestor-closed subset of ``graph``, in graph order)."""
    reporter = reporter or Reporter()
    store.create()
    registration = register_run(store, graph.name)
    try:
        if graph.growing:
            return _execute_growing(graph, store, nodes, forced, scheduler, workers, threads, reporter,
                                    progress_every_s)
        return _execute(graph, store, nodes, forced, scheduler, workers, threads, reporter, progress_every_s)
    finally:
        if registration is not None:
            registration.release()


def _execute_growing(graph, store, nodes, forced, scheduler, workers, threads, reporter, progress_every_s):
    """Rounds: grow the graph from the store, run what is not waiting on an undecided group, repeat.

    Each round runs every point it can in parallel (the new points of all
    groups together); a point runs once per call (a forced one too).  Stops
    when a round has nothing to run: every group decided, or waiting on a
    point that failed or was interrupted.
    """
    from .growth import held, resolve, with_grown
    from .interrupt import stop_requested

    requested = list(nodes)
    ran: dict[str, Outcome] = {}
    outcomes: list[Outcome] = []
    while True:
        requested = with_grown(graph, requested, resolve(graph, store))
        waiting = {id(n) for n in held(graph)}
        todo = [n for n in requested if n.node_id not in ran and id(n) not in waiting]
        if not todo or stop_requested():
            break
        done = _execute(graph, store, todo, set(forced) - set(ran), scheduler, workers, threads, reporter,
                        progress_every_s, previous=ran)
        ran.update((o.node_id, o) for o in done)
        outcomes.extend(done)
    for per in graph.growth.values():
        for st in per.values():
            if st.state == "error":
                reporter.line(f"! {st.sweep.stage} {st.coords}: {st.reason}")
                outcomes.append(Outcome(f"{st.sweep.stage}[growth]", st.sweep.stage, "", st.coords,
                                        st.sweep.nodes[0].task.name, None, "failed", "growth rule failed",
                                        st.reason, error=st.reason))
    return outcomes


CLEAN_WAIT_S = 0.2


def register_run(store: DirectoryStore, study: str):
    """Announce a live run in ``runs/`` (``clean`` spares what it writes), then wait for a running
    ``clean`` to finish.  Registering first closes the race: a clean that starts later sees this run.
    None on a read-only store (nothing can be written there anyway)."""
    try:
        lease = store.runs.try_acquire(f"{socket.gethostname()}.{os.getpid()}.{uuid.uuid4().hex[:8]}", study)
        for other in store.runs.all():  # records of killed runs: nothing else removes them
            store.runs.break_if_dead(other.key)
    except OSError:
        return None
    while True:
        info, alive, _ = store.locks.verdict(CLEAN_LOCK)
        # another host's clean silent for a minute is not deleting any more: do not wait the 10 minutes
        # its lease takes to count as dead (a clean that starts later sees this run anyway)
        if info is None or alive is False or (alive is None and info.heartbeat_age_s > STALE_AFTER_S):
            return lease
        time.sleep(CLEAN_WAIT_S)


def _all_stored(graph, store, nodes, forced) -> bool:
    """True when the runner would reuse every one of ``nodes`` (stored, stale ones kept, none forced)."""
    wanted = {id(n) for n in nodes}
    items = plan_items(graph, store, graph.ancestors(nodes), set(forced))
    return all(i.state in (State.DONE, State.STALE) for i in items if id(i.node) in wanted)


def _execute(graph, store, nodes, forced, scheduler, workers, threads, reporter, progress_every_s, previous=None):
    if scheduler is not None and _all_stored(graph, store, nodes, forced):
        # nothing to compute: reuse here, without a cluster that may be down or busy
        reporter.line(f"every point is stored: reused here, the scheduler at {scheduler} is not contacted")
        scheduler = None
    cores = available_cores()
    budget = None
    if scheduler is None:
        workers = max(1, workers or cores)
        if not threads:
            threads = wanted_threads([n.stage for n in nodes], cores, workers)
            budget = CoreBudget(max(cores, workers))
    else:
        threads = threads or 1
    stop_variable = variable_name() if scheduler is not None else None
    reporter.expect(nodes)
    specs = point_specs(graph, nodes, store, set(forced), threads, stop_variable)
    # upstream points run in an earlier round (growing sweeps) enter as their outcomes
    previous = previous or {}
    dsk = {nid: (run_node, spec, [u if u in specs else previous[u] for u in ups])
           for nid, (spec, ups) in specs.items()}
    keys = list(dsk)
    every = progress_every_s or float(os.environ.get("PEENFLOW_PROGRESS_EVERY_S", 0)) or reporter.poll_s
    monitor = _ProgressMonitor(store, graph.name, reporter, every)
    monitor.start()
    try:
        if scheduler is None:
            set_active_budget(budget)
            set_notice(reporter.notice)
            try:
                outcomes = _run_local(dsk, keys, workers, reporter)
            finally:
                set_active_budget(None)
                set_notice(None)
        else:
            outcomes = _run_distributed(dsk, keys, scheduler, reporter, stop_variable)
    finally:
        monitor.stop.set()
        reporter.finish()
    return outcomes


def _run_local(dsk, keys, workers, reporter) -> list[Outcome]:
    from dask.callbacks import Callback
    from dask.threaded import get

    class _Report(Callback):
        def _posttask(self, key, result, dsk, state, id):
            reporter.outcome(result)

    with _Report():
        return list(get(dsk, keys, num_workers=workers))


def _run_distributed(dsk, keys, address, reporter, stop_variable) -> list[Outcome]:
    from distributed import Client, as_completed

    try:
        client = Client(address, timeout=f"{SCHEDULER_TIMEOUT_S:g}s")
    except (OSError, TimeoutError, ValueError, TypeError) as exc:  # unreachable, refused, malformed
        raise SchedulerUnreachable(
            f"cannot reach the dask scheduler at {address} within {SCHEDULER_TIMEOUT_S:g} s "
            f"({type(exc).__name__}): check that `dask scheduler` runs there, that the address and port are "
            "right (tcp://HOST:PORT, default port 8786) and that no firewall blocks it") from None
    with client, StopRelay(client, stop_variable):
        futures = client.get(dsk, keys, sync=False)
        by_future = dict(zip(futures, keys))
        results = {}
        for fut in as_completed(futures):
            o = fut.result()
            results[by_future[fut]] = o
            reporter.outcome(o)
    return [results[k] for k in keys]
