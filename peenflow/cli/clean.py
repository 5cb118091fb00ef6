"""Remove what no study refers to: old results, superseded files, failure records, stray temporaries.

A result is *referenced* when some study's slot record (the last attempt of
one of its points) names its key.  Checkpoints are kept unless
``--checkpoints`` is given: a killed run resumes from them.
"""

from __future__ import annotations

import os
import shutil
import socket
import time

from ._common import add_study, load

NAME = "clean"
HELP = "remove unreferenced or failed results (see --dry-run)"

TMP_GRACE_S = 24 * 3600


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


def main(args) -> int:
    _, store = load(args)
    referenced = {rec.get("key") for _, rec in store.slots() if rec.get("state") == "done"}
    doomed = []
    for task, key, path in store.all_results():
        if ".superseded-" in path.name or key not in referenced:
            doomed.append(path)
            m = store.manifest_path(task, key)
            if m.exists():
                doomed.append(m)
    failures = store.root / "failures"
    if failures.exists():
        doomed += sorted(failures.glob("*/*.json"))
    doomed += [p for p in store.temporary_files() if not _tmp_in_use(p)]
    if args.checkpoints and (store.root / "checkpoints").exists():
        live = {i.key for i in store.leases.all()}
        doomed += [d for d in sorted((store.root / "checkpoints").iterdir()) if d.name not in live]
    verb = "would remove" if args.dry_run else "removed"
    for p in doomed:
        if not args.dry_run:
            if p.is_dir():
                shutil.rmtree(p, ignore_errors=True)
            else:
                p.unlink(missing_ok=True)
        print(f"{verb} {p.relative_to(store.root)}")
    print(f"{verb} {len(doomed)} item(s)")
    return 0
