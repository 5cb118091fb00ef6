"""Running one point: decide, lease, compute or reuse, store, record.

``run_node`` is what every dask task executes, locally or on a cluster
worker.  It receives a picklable :class:`PointSpec` (names, not objects) and
the outcomes of its upstream points, and never raises for a task failure:
the failure is recorded in the store and returned, so one bad point of a
sweep does not stop or lose the others.
"""

from __future__ import annotations

import json
import os
import platform
import socket
import sys
import time
import traceback
from dataclasses import dataclass, field
from datetime import datetime, timezone

import xarray as xr

from .. import __version__
from .blas import pin_blas_threads
from .canonical import canonical_json
from .checkpoint import CheckpointState, describe_position, judge
from .cluster_stop import worker_check
from .combine import combine_points
from .context import TaskContext
from .conventions import conform, retag_point, squeeze_point
from .cores import active_budget
from .interrupt import Interrupted, heeding, stop_reason, stop_requested
from .keys import KeyParts, reason_against_slot
from .lease import STALE_AFTER_S, wait_text
from .reasons import Reason
from .space import NoSpaceLeft, is_full, no_space
from .store import DirectoryStore
from .task import resolve_task

LEASE_POLL_S = 0.5


@dataclass(frozen=True)
class UpstreamRef:
    """How a task argument maps onto upstream outcomes (by index in the upstream list)."""

    indices: tuple[int, ...]
    dims: tuple[str, ...] | None  # None: a single point, else combine along dims


@dataclass(frozen=True)
class PointSpec:
    task_module: str
    task_qualname: str
    task_name: str
    stage: str
    node_id: str
    label: str
    coords: dict
    params: dict
    upstream: dict  # name -> UpstreamRef
    store_root: str
    study: str
    forced: bool = False
    threads: int = 1
    #: CF attributes of the sweep coordinates ({dim: {"units": ..., "long_name": ...}})
    sweep_attrs: dict = field(default_factory=dict)
    #: the graph's ``result_attrs``: written on the result, not part of its key
    result_attrs: dict = field(default_factory=dict)
    #: on a cluster: the dask Variable through which the run's client asks its points to stop (cluster_stop.py)
    stop_variable: str | None = None


@dataclass(frozen=True)
class Outcome:
    node_id: str
    stage: str
    label: str
    coords: dict
    task: str
    key: str | None
    status: str  # computed | reused | failed | skipped | blocked | interrupted
    reason: str
    detail: str = ""
    content_hash: str | None = None
    wall_s: float = 0.0
    error: str = ""
    stale: bool = False
    upstream_keys: dict = field(default_factory=dict)
    trace: str = ""  # the traceback of a failure (kept in the failure record, never printed by default)

    @property
    def ok(self) -> bool:
        return self.status in ("computed", "reused")


def upstream_hashes(spec: PointSpec, ups: list[Outcome]) -> dict:
    out = {}
    for name, ref in spec.upstream.items():
        if ref.dims is None:
            out[name] = ups[ref.indices[0]].content_hash
        else:
            out[name] = sorted([ups[i].label, ups[i].content_hash] for i in ref.indices)
    return out


def _versions() -> dict:
    import numpy
    import peenflow

    v = {"peenflow": peenflow.__version__, "python": platform.python_version(),
         "numpy": numpy.__version__, "xarray": xr.__version__}
    try:
        import numba

        v["numba"] = numba.__version__
    except ImportError:  # pragma: no cover
        pass
    return v


def _load_upstream(store: DirectoryStore, spec: PointSpec, ups: list[Outcome]) -> dict:
    args = {}
    for name, ref in spec.upstream.items():
        # Stored points carry their sweep values as length-1 dims (conventions.py);
        # the task gets them as 0-d coordinates, except the dims it combines along.
        if ref.dims is None:
            o = ups[ref.indices[0]]
            args[name] = squeeze_point(retag_point(store.open(o.task, o.key), o.coords), o.coords)
        else:
            datasets = [retag_point(store.open(ups[i].task, ups[i].key), ups[i].coords) for i in ref.indices]
            combined = combine_points(datasets, [ups[i].coords for i in ref.indices], ref.dims)
            fixed = {d for i in ref.indices for d in ups[i].coords if d not in ref.dims}
            args[name] = squeeze_point(combined, sorted(fixed))
    return args


def _outcome(spec, key, status, reason, detail="", **kw) -> Outcome:
    return Outcome(spec.node_id, spec.stage, spec.label, spec.coords, spec.task_name, key,
                   status, reason.value if isinstance(reason, Reason) else reason, detail, **kw)


def run_node(spec: PointSpec, ups: list[Outcome]) -> Outcome:
    """Compute or reuse one point.  Never raises for a failing task."""
    # on a cluster worker the client's stop request is not this process's: heed the run's as well
    with heeding(worker_check(spec.stop_variable) if spec.stop_variable else None):
        try:
            return _run_node(spec, ups)
        except Exception as exc:  # engine-level failure: still report, never lose the others
            error = failure_text(exc, DirectoryStore(spec.store_root))
            return _outcome(spec, None, "failed", "engine error", error, error=error, trace=traceback.format_exc())


def failure_text(exc: BaseException, store: DirectoryStore) -> str:
    """A failure in one line: ``Type: message``, or for a full disk its cause first (:mod:`.space`)."""
    if isinstance(exc, NoSpaceLeft):
        return str(exc)
    if is_full(exc):  # a small record (lease, progress, slot) found the device full
        return str(no_space(exc, store.root, None, "a record of this point"))
    return f"{type(exc).__name__}: {exc}"


def _run_node(spec: PointSpec, ups: list[Outcome]) -> Outcome:
    if stop_requested():
        return _outcome(spec, None, "interrupted", "not started", stop_reason())
    bad = [u for u in ups if not u.ok]
    if bad:
        return _outcome(spec, None, "skipped", "upstream failed",
                        ", ".join(sorted({u.node_id for u in bad})[:3]))
    task = resolve_task(spec.task_module, spec.task_qualname)
    store = DirectoryStore(spec.store_root)
    up_hashes = upstream_hashes(spec, ups)
    code = task.code_id()
    parts = KeyParts(task.name, code, spec.params, up_hashes)
    key = parts.key
    upstream_keys = {name: [ups[i].key for i in ref.indices] for name, ref in spec.upstream.items()}

    slot = store.slot(spec.study, spec.stage, spec.label)
    if spec.forced:
        reason, detail = Reason.FORCED, "rerun requested"
    else:
        reason, detail = reason_against_slot(slot, task.name, code, spec.params, up_hashes)

    notes: list[str] = []

    def reuse(manifest) -> Outcome:
        stale = task.version is not None and manifest.source_hash != task.source_hash()
        if not _slot_says_done(slot, key, manifest.source_hash):
            try:
                _record_slot(store, spec, parts, "done", manifest.source_hash)
            except OSError:
                pass  # a read-only store: the slot only serves `status --why`; the result is what counts
        _tidy_after_finished(store, task.name, key, notes)
        detail = f"code changed under version {task.version}" if stale else ""
        return _outcome(spec, key, "reused", Reason.STALE if stale else Reason.UP_TO_DATE,
                        _join(detail, *notes),
                        content_hash=manifest.content_hash, stale=stale, upstream_keys=upstream_keys)

    manifest, problem = store.check(task.name, key)
    if manifest is not None and not spec.forced:
        return reuse(manifest)
    if manifest is None and problem != "missing" and reason is Reason.INCOMPLETE:
        detail = problem

    # Take the lease; while someone else holds it, wait and then reuse their result.
    waited_for_other = False
    told, waiting_since = None, 0.0
    while True:
        lease = store.leases.try_acquire(key, f"{spec.study}:{spec.node_id}")
        if lease is not None:
            break
        broke = store.leases.break_if_dead(key)
        if broke:
            notes.append(broke)
            continue
        info, alive, _ = store.leases.verdict(key)
        if info is not None and alive is None and info.heartbeat_age_s > STALE_AFTER_S:
            return _outcome(spec, key, "blocked", "lease held elsewhere",
                            f"{info.describe()}; if that run is dead, run `peenflow unlock`",
                            upstream_keys=upstream_keys)
        if stop_requested():
            return _outcome(spec, key, "interrupted", "not started", stop_reason(), upstream_keys=upstream_keys)
        if info is not None and (info.host, info.pid, info.problem) != told:  # said at once, once per holder
            told = (info.host, info.pid, info.problem)
            waiting_since = waiting_since or time.time()
            _notice(f"waiting for {spec.node_id}: {wait_text(info, alive)}{_holder_progress(store, key)}")
        waited_for_other = True
        time.sleep(LEASE_POLL_S)
    if waiting_since:
        notes.append(f"waited {time.time() - waiting_since:.0f} s for the run that held it")

    with lease:
        if waited_for_other or not spec.forced:
            manifest, problem = store.check(task.name, key)
            if manifest is not None:
                return reuse(manifest)
        if problem not in ("missing", "") and not spec.forced:
            store.discard(task.name, key)  # damaged: never trusted, recomputed below
        if notes:
            detail = _join(detail, *notes)
        return _compute(task, store, spec, ups, parts, reason, detail, upstream_keys)


#: where a point's notices go while it runs (a waiting point says whom it waits for): the executor sets
#: its reporter's for a local run; None (a dask.distributed worker): the worker's own log
_NOTICE = None


def set_notice(emit) -> None:
    """Send the notices of points run in this process to ``emit(text)`` (None: to the log)."""
    global _NOTICE
    _NOTICE = emit


def _notice(text: str) -> None:
    emit = _NOTICE
    if emit is not None:
        emit(text)
    else:
        import logging

        logging.getLogger("peenflow").warning(text)


def _holder_progress(store: DirectoryStore, key: str) -> str:
    rec = store.progress(key)
    if not rec or rec.get("total") is None:
        return ""
    return f"; its progress: {rec['done']:g}/{rec['total']:g} {rec.get('unit') or ''}".rstrip()


def _join(*parts: str) -> str:
    return "; ".join(p for p in parts if p)


def _slot_says_done(slot: dict | None, key: str, source_hash: str) -> bool:
    return isinstance(slot, dict) and slot.get("key") == key and slot.get("state") == "done" \
        and slot.get("source_hash") == source_hash


def _tidy_after_finished(store: DirectoryStore, task: str, key: str, notes: list[str]) -> None:
    """Remove what a run killed right after storing ``key`` left behind: its dead lease, its
    checkpoint (one older than the result: a killed *rerun*'s newer checkpoint is kept for the next
    rerun) and progress record; never while a live run holds the key."""
    try:
        broke = store.leases.break_if_dead(key)
        if broke:
            notes.append(broke)
        if store.leases.info(key) is not None:
            return
        if judge(store, key, task).state is CheckpointState.LEFTOVER:
            store.checkpoints(key).clear()
            notes.append("removed the checkpoint a finished run left behind")
        store.clear_progress(key)
    except OSError:
        pass  # a read-only store: nothing we may tidy


def _record_slot(store, spec, parts: KeyParts, state: str, source_hash: str, **extra) -> None:
    rec = {"study": spec.study, "stage": spec.stage, "label": spec.label, "node_id": spec.node_id,
           "key": parts.key, "parts": parts.to_dict(), "source_hash": source_hash, "state": state,
           "time": time.time()}
    rec.update(extra)
    store.write_slot(spec.study, spec.stage, spec.label, rec)


def _compute(task, store, spec, ups, parts: KeyParts, reason, detail, upstream_keys) -> Outcome:
    # Threads come from the process's core budget when the task first reads
    # ctx.threads (see cores.py); a distributed worker has no budget.
    ctx = TaskContext(store, parts.key, spec.node_id, spec.study, spec.threads, active_budget())
    try:
        return _compute_in(ctx, task, store, spec, ups, parts, reason, detail, upstream_keys)
    finally:
        ctx.release_threads()


def _compute_in(ctx, task, store, spec, ups, parts: KeyParts, reason, detail, upstream_keys) -> Outcome:
    key = parts.key
    source_hash = task.source_hash()
    if reason is Reason.FORCED and ctx.resumed and judge(store, key, task.name).state is CheckpointState.LEFTOVER:
        ctx.clear_checkpoint()  # left by the run that made the result: not this rerun's work
        ctx.resumed = False
    planned = (reason, detail)

    def said():
        """(reason, detail) of the outcome: resuming only if the task did resume (an unreadable or
        unusable checkpoint it dropped says so in a note instead)."""
        if not ctx.resumed:
            return planned
        if planned[0] is Reason.FORCED:  # a killed rerun of the same inputs: on from where it stopped
            return Reason.FORCED, f"{planned[1]}; resuming its own checkpoint"
        where = describe_position(ctx.resumed_from)
        return Reason.INCOMPLETE, "resuming from checkpoint" + (f" {where}" if where else "")

    started = time.time()
    try:
        blas_threads = pin_blas_threads()  # same on a dask worker as here: bit-identical results
        kwargs = task.bind(spec.params)
        kwargs.update(_load_upstream(store, spec, ups))
        if task.wants_ctx:
            kwargs["ctx"] = ctx
        result = task.fn(**kwargs)
        if not isinstance(result, xr.Dataset):
            raise TypeError(f"task {task.name!r} returned {type(result).__name__}, expected xarray.Dataset")
        finished = time.time()
        when = datetime.fromtimestamp(finished, timezone.utc).isoformat(timespec="seconds")
        result = conform(
            result, sweep=spec.coords, sweep_attrs=spec.sweep_attrs,
            title=f"peenflow {spec.stage} result",
            history=f"{when}: computed by peenflow {__version__} on {socket.gethostname()} "
                    f"(study {spec.study}, point {spec.node_id})",
            source=f"peenflow {__version__}, task {task.name} ({parts.code}, code fingerprint "
                   f"{source_hash})")
        result.attrs.update(spec.result_attrs)
        result.attrs.update({
            "peenflow_task": task.name,
            "peenflow_stage": spec.stage,
            "peenflow_point": spec.node_id,
            "peenflow_study": spec.study,
            "peenflow_key": key,
            "peenflow_version": task.version or "",
            "peenflow_code": parts.code,
            "peenflow_source_hash": source_hash,
            "peenflow_params": canonical_json(spec.params),
            "peenflow_upstream": json.dumps(upstream_keys, sort_keys=True),
            "peenflow_versions": json.dumps(_versions(), sort_keys=True),
            "peenflow_started": datetime.fromtimestamp(started, timezone.utc).isoformat(),
            "peenflow_finished": datetime.fromtimestamp(finished, timezone.utc).isoformat(),
            "peenflow_wall_s": finished - started,
            "peenflow_host": socket.gethostname(),
            "peenflow_pid": os.getpid(),
            "peenflow_resumed": int(ctx.resumed),
            "peenflow_threads": ctx.granted or 0,
            "peenflow_blas_threads": blas_threads,
        })
        manifest = store.write_result(task.name, key, result, parts.to_dict(), source_hash,
                                      replace=spec.forced)
    except Interrupted as exc:
        # Not a failure: the task saved a checkpoint; the next run resumes from it.
        store.clear_progress(key)
        return _outcome(spec, key, "interrupted", said()[0], f"stopped {exc}; checkpoint saved, run again to resume",
                        wall_s=time.time() - started, upstream_keys=upstream_keys)
    except Exception as exc:
        tb = traceback.format_exc()
        error = failure_text(exc, store)
        try:
            store.write_failure(task.name, key, {
                "node_id": spec.node_id, "study": spec.study, "error": error,
                "traceback": tb, "host": socket.gethostname(), "time": time.time(),
                "python": sys.version.split()[0],
            })
            _record_slot(store, spec, parts, "failed", source_hash, error=error)
            store.clear_progress(key)
        except OSError as exc2:  # disk full or read-only: the outcome still says what failed
            if not (is_full(exc) and is_full(exc2)):  # a full disk is said already
                error = f"{error} (and the failure record could not be written: {exc2})"
        reason, detail = said()
        return _outcome(spec, key, "failed", reason, _join(detail, *ctx.notes), error=error,
                        wall_s=time.time() - started, upstream_keys=upstream_keys, trace=tb)
    ctx.clear_checkpoint()
    store.clear_progress(key)
    store.clear_failure(task.name, key)
    _record_slot(store, spec, parts, "done", source_hash)
    reason, detail = said()
    return _outcome(spec, key, "computed", reason, _join(detail, *ctx.notes),
                    content_hash=manifest.content_hash, wall_s=time.time() - started, upstream_keys=upstream_keys)

