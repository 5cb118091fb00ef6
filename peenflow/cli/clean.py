"""Remove what nothing uses: old results, superseded files, failure records, stray temporaries, dead leases.

The policy -- what is kept, always, and why -- is the engine's
(:mod:`peenflow.engine.housekeeping`): results the given study file uses,
results another study's last run refers to, anything under a live lease or
written since a live run began, and checkpoints of unfinished points unless
``--checkpoints`` is given.  This verb prints what it removes, and what it
keeps and why.
"""

from __future__ import annotations

from ..engine.housekeeping import CleanBusy, CleanPlan, clean_lock
from ._common import UserError, add_study, load

NAME = "clean"
HELP = "remove unreferenced or failed results (see --dry-run)"


def add_arguments(p) -> None:
    add_study(p)
    p.add_argument("--dry-run", action="store_true", help="list what would be removed")
    p.add_argument("--checkpoints", action="store_true", help="also remove checkpoints of unfinished runs")


def main(args) -> int:
    graph, store = load(args)
    if not store.root.is_dir():
        print(f"nothing to clean: no store at {store.root}")
        return 0
    try:
        lock = None if args.dry_run else clean_lock(store)
    except CleanBusy as exc:
        raise UserError(str(exc)) from None
    try:
        decided = CleanPlan(graph, store, args.checkpoints)
        if not args.dry_run:
            decided.carry_out()
        verb = "would remove" if args.dry_run else "removed"
        for key, why in decided.dead_leases:
            print(f"{verb} lease {key[:12]}: {why}")
        for key, why in decided.dead_runs:
            print(f"{verb} {store.runs.path(key).relative_to(store.root)}: {why}")
        for p in decided.doomed:
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
