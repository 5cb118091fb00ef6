"""The clean policy: what ``peenflow clean`` removes from a store, and what it keeps and why.

What is KEPT, always:

* every result the given graph uses now: the keys of its whole graph,
  planned from the study file itself (not from the last run under its name --
  a copy of the study with the same name may have run since);
* every result another study's last run refers to (its slot records);
* anything under a live lease, and anything written after a live run began
  (runs register in the store's run records; a run that starts while a clean
  deletes waits for it: :func:`clean_lock`);
* checkpoints of unfinished points, unless asked (a killed run resumes from
  them); a leftover checkpoint (:func:`.checkpoint.judge`) goes;
* a temporary file whose writer is alive here, or (another host's) younger
  than ``TMP_GRACE_S``.

Everything else of the store goes: results nothing uses, superseded files,
failure records, progress records, stray temporaries, dead leases and the
records of killed runs.  :class:`CleanPlan` decides before anything is
touched; :meth:`CleanPlan.carry_out` removes.
"""

from __future__ import annotations

import os
import shutil
import socket
import time
from collections import Counter
from pathlib import Path

from .checkpoint import CheckpointState, judge
from .lease import verdict
from .planner import plan
from .store import CLEAN_LOCK, DirectoryStore

#: a temporary file of another host (whose writer cannot be asked) is kept this long
TMP_GRACE_S = 24 * 3600
#: a file written this close to (or after) the start of a live run is treated as that run's
MTIME_SLACK_S = 2.0


class CleanBusy(RuntimeError):
    """Another clean is deleting in the same store."""


def _tmp_in_use(path: Path) -> bool:
    # .<name>.<host>.<pid>.<rand>.tmp (atomic.py): keep a live writer's file.
    parts = path.name.split(".")
    try:
        host, pid = parts[-4], int(parts[-3])
    except (IndexError, ValueError):
        return time.time() - path.stat().st_mtime < TMP_GRACE_S
    if host == socket.gethostname().split(".")[-1] or host == socket.gethostname():
        try:
            os.kill(pid, 0)
            return True
        except ProcessLookupError:
            return False
        except PermissionError:
            return True
    return time.time() - path.stat().st_mtime < TMP_GRACE_S


def _mtime(path: Path) -> float:
    try:
        return path.stat().st_mtime
    except OSError:
        return 0.0


class CleanPlan:
    """What a clean of ``store`` for ``graph`` removes and keeps; ``with_checkpoints``: also the checkpoints
    of unfinished points.

    ``doomed``: the files and folders to remove; ``dead_leases`` and ``dead_runs``: (key, why) of the
    leases and run records whose holder is dead; ``kept``: how many things are kept, by reason;
    ``n_runs``: the live runs on the store.
    """

    def __init__(self, graph, store: DirectoryStore, with_checkpoints: bool):
        self.store = store
        self.doomed: list[Path] = []
        self.kept: Counter = Counter()
        leases = [(i, verdict(i)) for i in store.leases.all()]
        self.live_keys = {i.key for i, (alive, _) in leases if alive is not False}
        self.dead_leases = [(i.key, why) for i, (alive, why) in leases if alive is False]
        runs = [(i, verdict(i)) for i in store.runs.all()]
        live_runs = [i for i, (alive, _) in runs if alive is not False]
        self.dead_runs = [(i.key, why) for i, (alive, why) in runs if alive is False]
        # Anything written since the oldest live run began is that run's: never ours to judge.
        self.cutoff = min((i.started for i in live_runs), default=float("inf")) - MTIME_SLACK_S
        self.n_runs = len(live_runs)
        self.study_keys = {it.key for it in plan(graph, store) if it.key}
        self.slot_keys = {rec.get("key") for _, rec in store.slots() if rec.get("state") == "done"}
        self._results()
        self._failures()
        self._checkpoints(with_checkpoints)
        self._progress()
        self.doomed += [p for p in store.temporary_files() if not _tmp_in_use(p) and _mtime(p) < self.cutoff]

    def _spared(self, key: str, *paths: Path) -> str:
        if key in self.live_keys:
            return "under a live lease"
        if any(_mtime(p) >= self.cutoff for p in paths):
            return "written since a live run began"
        return ""

    def _results(self) -> None:
        for task, key, path in self.store.all_results():
            manifest = self.store.manifest_path(task, key)
            superseded = ".superseded-" in path.name
            real_key = key.split(".superseded-")[0]
            if not superseded and key in self.study_keys:
                self.kept["used by this study"] += 1
                continue
            if not superseded and key in self.slot_keys:
                self.kept["referenced by the last run of a study on this store"] += 1
                continue
            why = self._spared(real_key, path, manifest)
            if why:
                self.kept[f"result {why}"] += 1
                continue
            self.doomed.append(path)
            if not superseded and manifest.exists():
                self.doomed.append(manifest)

    def _failures(self) -> None:
        for task, key in self.store.all_failures():
            path = self.store.failure_path(task, key)
            why = self._spared(key, path)
            if why:
                self.kept[f"failure record {why}"] += 1
            else:
                self.doomed.append(path)

    def _checkpoints(self, all_unfinished: bool) -> None:
        for key in self.store.checkpoint_keys():
            folder = self.store.checkpoint_dir(key)
            why = self._spared(key, *(list(folder.glob("*")) or [folder]))
            if why:
                self.kept[f"checkpoint {why}"] += 1
            elif all_unfinished or judge(self.store, key).state is CheckpointState.LEFTOVER:
                self.doomed.append(folder)
            else:
                self.kept["checkpoint of an unfinished point (--checkpoints removes it)"] += 1

    def _progress(self) -> None:
        for key in self.store.progress_keys():
            path = self.store.progress_path(key)
            if not self._spared(key, path):
                self.doomed.append(path)

    def carry_out(self) -> None:
        """Remove what was decided: break the dead leases and run records, delete the doomed paths."""
        for key, _ in self.dead_leases:
            self.store.leases.break_if_dead(key)
        for key, _ in self.dead_runs:
            self.store.runs.break_if_dead(key)
        for p in self.doomed:
            if p.is_dir():
                shutil.rmtree(p, ignore_errors=True)
            else:
                p.unlink(missing_ok=True)


def clean_lock(store: DirectoryStore):
    """The store's clean lock (a lease; release it when done); :class:`CleanBusy` while another clean holds
    it.  A run that starts meanwhile waits for it (executor.register_run)."""
    for _ in range(2):
        lock = store.locks.try_acquire(CLEAN_LOCK, "peenflow clean")
        if lock is not None:
            return lock
        if not store.locks.break_if_dead(CLEAN_LOCK):
            break
    info = store.locks.info(CLEAN_LOCK)
    raise CleanBusy(f"another clean is running on {store.root} ({info.describe() if info else '?'}); "
                    "try again when it has finished")
