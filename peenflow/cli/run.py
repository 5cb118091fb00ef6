"""Run a study: compute what is missing or changed, reuse the rest."""

from __future__ import annotations

import argparse

from ..engine import Reporter, SchedulerUnreachable, execute
from ..report import headline_rows, write_reports
from ._common import UserError, add_study, dim_value, load, stage_nodes
from ._interrupts import stop_on_signals
from .status import print_plan

NAME = "run"
HELP = "run a study (resumes: finished results are reused)"


def add_arguments(p) -> None:
    add_study(p)
    add_execution(p)
    p.add_argument("--until", metavar="STAGE", help="run only this stage and what it needs")


def positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {value}")
    return value


def add_execution(p) -> None:
    p.add_argument("--dry-run", action="store_true", help="show what would be computed, and why")
    p.add_argument("--workers", type=positive_int, default=None, help="parallel points (default: all cores)")
    p.add_argument("--threads", type=positive_int, default=None,
                   help="compute threads per point (default: all cores for a lone point, cores // workers for a sweep, never more than the cores in all)")
    p.add_argument("--scheduler", metavar="ADDR", default=None,
                   help="dask.distributed scheduler, e.g. tcp://host:8786 (store must be shared)")
    p.add_argument("--quiet", action="store_true", help="only the summary")


def execute_and_report(args, graph, store, nodes, forced=frozenset()) -> int:
    if args.dry_run:
        print_plan(graph, store, nodes, forced, why=True)
        return 0
    reporter = Reporter(quiet=args.quiet)
    reporter.group_by(graph.labels.get("process_dims") or [], lambda d, v: dim_value(graph, d, v))
    reporter.line(f"study {graph.name}: {len(nodes)} points, store {store.root}")
    workers = args.workers or graph.execution.get("workers")
    threads = args.threads or graph.execution.get("threads")
    with stop_on_signals() as stopped:
        try:
            outcomes = execute(graph, store, nodes, forced=set(forced), scheduler=args.scheduler,
                               workers=workers, threads=threads, reporter=reporter)
        except SchedulerUnreachable as exc:
            raise UserError(str(exc)) from None
    reporter.line("")
    reporter.line(reporter.summary())
    if stopped["signal"] is not None:
        reporter.line("interrupted: finished results and the checkpoints of stopped points are kept; "
                      "run again to resume")
        return 128 + stopped["signal"]
    print_headline(graph, store, reporter.line)
    try:
        for path in write_reports(graph, store, args.study):
            reporter.line(f"wrote {path}")
    except Exception as exc:  # a failed plot never hides the run's own outcome
        reporter.line(f"report failed: {type(exc).__name__}: {exc}")
    bad = [o for o in outcomes if not o.ok]
    return 1 if bad else 0


def print_headline(graph, store, emit=print) -> None:
    rows = headline_rows(graph, store)
    if not rows:
        return
    w1 = max(len(r[0]) for r in rows)
    w2 = max(len(r[1]) for r in rows)
    emit("")
    emit("headline numbers:")
    for q, v, note in rows:
        emit(f"  {q:{w1}s}  {v:>{w2}s}  {note}".rstrip())


def main(args) -> int:
    graph, store = load(args)
    nodes = graph.ancestors(stage_nodes(graph, args.until)) if args.until else list(graph.nodes)
    return execute_and_report(args, graph, store, nodes)
