"""Show each stage's points: done, pending, running, failed, stale -- and why."""

from __future__ import annotations

from collections import Counter

from ..engine import plan
from ..engine.lease import verdict
from ._common import add_study, dim_value, load

NAME = "status"
HELP = "what is done, pending, running, failed or stale (--why: the reasons)"


def add_arguments(p) -> None:
    add_study(p)
    p.add_argument("--why", action="store_true", help="one line per point with the reason")


def print_plan(graph, store, nodes, forced=frozenset(), why=False) -> list:
    items = plan(graph, store, nodes, set(forced))
    by_stage: dict[str, list] = {}
    for it in items:
        by_stage.setdefault(it.node.stage, []).append(it)
    width = max([len(s) for s in by_stage] + [5])
    print(f"study {graph.name}  (store {store.root})")
    for stage, its in by_stage.items():
        counts = Counter(i.state.value for i in its)
        summary = ", ".join(f"{n} {s}" for s, n in sorted(counts.items()))
        print(f"  {stage:{width}s}  {len(its):4d} point(s): {summary}")
        for dim in graph.labels.get("process_dims") or []:
            values = sorted({i.node.coords[dim] for i in its if dim in i.node.coords})
            if len(values) > 1:
                done = Counter(i.node.coords[dim] for i in its if dim in i.node.coords and i.state.value == "done")
                total = Counter(i.node.coords[dim] for i in its if dim in i.node.coords)
                print(f"  {'':{width}s}        by {dim}: " + ", ".join(
                    f"{dim_value(graph, dim, v)} {done[v]}/{total[v]} done" for v in values))
        if why:
            for i in its:
                key = i.key[:12] if i.key else "-" * 12
                detail = f": {i.detail}" if i.detail else ""
                prog = ""
                if i.progress and i.progress.get("total"):
                    prog = f"  [{i.progress['done']:g}/{i.progress['total']:g} {i.progress.get('unit', '')}]"
                print(f"      {i.state.value:8s} {key}  {i.node.node_id}  ({i.reason.value}{detail}){prog}")
    leases = store.leases.all()
    if leases:
        print("leases:")
        for info in leases:
            alive, why = verdict(info)
            state = {True: "alive", False: "dead (the next run or `peenflow unlock --all` removes it)",
                     None: "another host"}[alive]
            print(f"  {info.key[:12]}  {info.describe()}  [{state}: {why}]")
    return items


def main(args) -> int:
    graph, store = load(args)
    print_plan(graph, store, list(graph.nodes), why=args.why)
    return 0
