"""Remove what nothing uses: old results, superseded files, failure records, stray temporaries, dead leases.

What is KEPT, always:

* every result the given study file uses now: the keys of its whole graph,
  planned from the file itself (not from the last run under its name -- a
  copy of the study with the same name may have run since);
* every result another study's last run refers to (its slot records);
* anything under a live lease, and anything written after a live run began
  (runs register in ``runs/``; a run that starts while ``clean`` deletes
  waits for it);
* checkpoints of unfinished points, unless ``--checkpoints`` is given (a
  killed run resumes from them); a checkpoint older than its key's finished
  result is a leftover and goes.

``clean`` prints what it removes, and what it keeps and why.
"""

from __future__ import annotations

import os
import shutil
import socket
import time
from collections import Counter
from pathlib import Path

from ..engine import plan
from ..engine.lease import verdict
from ._common import UserError, add_study, load

NAME = "clean"
HELP = "remove unreferenced or failed results (see --dry-run)"

TMP_GRACE_S = 24 * 3600
#: a file written this close to (or after) the start of a live run is treated as that run's
MTIME_SLACK_S = 2.0


def add_arguments(p) -> None:
    add_study(p)
    p.add_argument("--dry-run", action="store_true", help="list what would be removed")
    p.add_argument("--checkpoints", action="store_true", help="also remove checkpoints of unfinished runs")


def _tmp_in_use(path) -> bool:
    # .<name>.<host>.<pid>.<rand>.tmp: keep a live writer's file.
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


class _Plan:
    """What clean removes and keeps, decided before anything is touched."""

    def __init__(self, graph, store, with_checkpoints: bool):
        self.store = store
        self.doomed: list[Path] = []
        self.kept: Counter = Counter()
        self.dead_leases: list[tuple[str, str]] = []
        leases = [(i, verdict(i)) for i in store.leases.all()]
        self.live_keys = {i.key for i, (alive, _) in leases if alive is not False}
        self.dead_leases = [(i.key, why) for i, (alive, why) in leases if alive is False]
        runs = [i for i in store.runs.all() if verdict(i)[0] is not False]
        # Anything written since the oldest live run began is that run's: never ours to judge.
        self.cutoff = min((i.started for i in runs), default=float("inf")) - MTIME_SLACK_S
        self.n_runs = len(runs)
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
        base = self.store.root / "failures"
        for p in sorted(base.glob("*/*.json")) if base.exists() else ():
            why = self._spared(p.stem, p)
            if why:
                self.kept[f"failure record {why}"] += 1
            else:
                self.doomed.append(p)

    def _checkpoints(self, all_unfinished: bool) -> None:
        base = self.store.root / "checkpoints"
        for d in sorted(base.iterdir()) if base.exists() else ():
            files = list(d.glob("*")) or [d]
            why = self._spared(d.name, *files)
            if why:
                self.kept[f"checkpoint {why}"] += 1
            elif all_unfinished or self._finished(d.name, files):
                self.doomed.append(d)
            else:
                self.kept["checkpoint of an unfinished point (--checkpoints removes it)"] += 1

    def _finished(self, key: str, files: list[Path]) -> bool:
        """True when ``key`` has a valid result written after its checkpoint (a leftover)."""
        newest = max(_mtime(f) for f in files)
        for task, k, path in self.store.all_results():
            if k == key and self.store.check(task, key)[0] is not None:
                return newest <= _mtime(self.store.manifest_path(task, key))
        return False

    def _progress(self) -> None:
        base = self.store.root / "progress"
        for p in sorted(base.glob("*.json")) if base.exists() else ():
            if not self._spared(p.stem, p):
                self.doomed.append(p)


def main(args) -> int:
    graph, store = load(args)
    if not store.root.is_dir():
        print(f"nothing to clean: no store at {store.root}")
        return 0
    lock = None
    if not args.dry_run:
        lock = _take_lock(store)
    try:
        decided = _Plan(graph, store, args.checkpoints)
        verb = "would remove" if args.dry_run else "removed"
        for key, why in decided.dead_leases:
            if not args.dry_run:
                store.leases.break_if_dead(key)
            print(f"{verb} lease {key[:12]}: {why}")
        for info in store.runs.all():  # the records of killed runs
            if verdict(info)[0] is False:
                if not args.dry_run:
                    store.runs.break_if_dead(info.key)
                print(f"{verb} runs/{info.key}: {verdict(info)[1]}")
        for p in decided.doomed:
            if not args.dry_run:
                if p.is_dir():
                    shutil.rmtree(p, ignore_errors=True)
                else:
                    p.unlink(missing_ok=True)
            print(f"{verb} {p.relative_to(store.root)}")
        print(f"{verb} {len(decided.doomed) + len(decided.dead_leases)} item(s)")
        for why, n in sorted(decided.kept.items()):
            print(f"kept {n} {why}")
        if decided.n_runs:
            print(f"({decided.n_runs} run(s) are live on this store: what they wrote is kept)")
    finally:
        if lock is not None:
            lock.release()
    return 0


def _take_lock(store):
    for _ in range(2):
        lock = store.locks.try_acquire("clean", "peenflow clean")
        if lock is not None:
            return lock
        if not store.locks.break_if_dead("clean"):
            break
    info = store.locks.info("clean")
    raise UserError(f"another clean is running on {store.root} ({info.describe() if info else '?'}); "
                    "try again when it has finished")
