"""List leases, and remove those left behind by a killed run."""

from __future__ import annotations

from ..engine.lease import verdict
from ._common import UserError, add_study, load

NAME = "unlock"
HELP = "remove leases left by a killed run"


def add_arguments(p) -> None:
    add_study(p)
    p.add_argument("keys", nargs="*", help="lease keys (prefixes allowed) to remove")
    p.add_argument("--all", action="store_true", help="remove every lease whose holder is not alive here")
    p.add_argument("--force", action="store_true", help="remove even a lease whose holder runs on this host")


def main(args) -> int:
    _, store = load(args)
    leases = store.leases.all()
    if not args.keys and not args.all:
        for info in leases:
            alive, why = verdict(info)
            state = {True: "alive", False: "dead", None: "another host"}[alive]
            print(f"{info.key}  {info.describe()}  [{state}: {why}]")
        print(f"{len(leases)} lease(s); pass keys or --all to remove")
        return 0
    chosen = leases if args.all else [i for i in leases if any(i.key.startswith(k) for k in args.keys)]
    if args.keys and not chosen:
        raise UserError(f"no lease matches {', '.join(args.keys)}")
    for info in chosen:
        alive, why = verdict(info)
        if alive and not args.force:
            print(f"kept {info.key}: {info.describe()}: {why} (use --force)")
            continue
        store.leases.unlock(info.key)
        print(f"removed {info.key} ({info.describe()}{'; ' + why if alive is False else ''})")
    return 0
