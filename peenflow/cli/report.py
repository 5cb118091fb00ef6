"""Write the study's report (plots and one self-contained report.html) from what is done, computing nothing.

The same files a run writes at its end; the command prints their paths.
The report opens in a browser straight from disk (no server).
"""

from __future__ import annotations

from ..report import applies, write_reports
from ._common import UserError, add_study, load

NAME = "report"
HELP = "write the plots and report.html from what is done (computes nothing)"


def add_arguments(p) -> None:
    add_study(p)


def main(args) -> int:
    graph, store = load(args)
    if not applies(graph):
        raise UserError(f"study {graph.name!r}: its pipeline has none of the stages the report reads")
    if not store.root.exists():
        raise UserError(f"no results yet in {store.root}: run `peenflow run {args.study}` first")
    for path in write_reports(graph, store, args.study):
        print(f"wrote {path}")
    return 0
