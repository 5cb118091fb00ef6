"""Console reporting: a line per finished point, progress with ETA, a summary.

Two ways to show progress, chosen by where the output goes:

* a terminal: live progress bars (``rich``): one for the run's points
  (done / total, elapsed, ETA) and one per running point that reports
  progress (e.g. shots done / total, ETA); finished points print their
  line above the bars;
* anything else (CI, a log file, a pipe): plain lines, each starting with a
  UTC timestamp: the point's progress with elapsed time and ETA, and the
  run's points done / total with its ETA.

ETAs are linear extrapolations of the rate seen so far (the run's from its
finished points, a point's from its own progress records).
"""

from __future__ import annotations

import sys
import threading
import time
from collections import defaultdict
from datetime import datetime, timezone

from .runner import Outcome

SYMBOL = {"computed": "+", "reused": "=", "failed": "!", "skipped": "-", "blocked": "#", "interrupted": "x"}


def duration(seconds: float | None) -> str:
    """``1h02m``, ``3m05s``, ``42s``; ``?`` when unknown."""
    if seconds is None or seconds != seconds or seconds < 0:
        return "?"
    s = int(round(seconds))
    if s >= 3600:
        return f"{s // 3600}h{(s % 3600) // 60:02d}m"
    if s >= 60:
        return f"{s // 60}m{s % 60:02d}s"
    return f"{s}s"


def eta(done: float, total: float | None, elapsed: float) -> float | None:
    """Seconds left at the rate so far (None before any progress or without a total)."""
    if not total or done <= 0 or elapsed <= 0:
        return None
    return max(0.0, (total - done) * elapsed / done)


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


class Reporter:
    """``live``: progress bars (True), plain timestamped lines (False), or decided by
    whether ``stream`` is a terminal (None)."""

    def __init__(self, stream=None, quiet: bool = False, live: bool | None = None):
        self.stream = stream or sys.stdout
        self.quiet = quiet
        self.live = _is_terminal(self.stream) if live is None else live
        self.outcomes: list[Outcome] = []
        self._lock = threading.RLock()
        self.started = time.time()
        self._expected: dict[str, int] = {}
        self._finished: dict[str, int] = defaultdict(int)
        self._total = 0
        self._point_start: dict[str, tuple[float, float]] = {}  # point -> (time, done) first seen
        self._point_eta: dict[str, tuple[float, float]] = {}  # running point -> (its ETA s, when)
        self._bars = None  # rich Progress while live
        self._bar_ids: dict[str, int] = {}
        self._overall = None
        # points per value of the dimensions a person follows (group_by)
        self._group_dims: list[str] = []
        self._label = None
        self._point_values: dict[str, list[tuple[str, object]]] = {}
        self._group_expected: dict[tuple, int] = defaultdict(int)
        self._group_finished: dict[tuple, int] = defaultdict(int)

    def group_by(self, dims, label=None) -> None:
        """Count the points of each value of ``dims`` (coordinate names) in the run's progress line;
        ``label(dim, value) -> str`` shows a value (default: the value)."""
        self._group_dims = list(dims)
        self._label = label or (lambda d, v: str(v))

    #: how often the executor polls progress records for this reporter (s)
    @property
    def poll_s(self) -> float:
        return 1.0 if self.live else 10.0

    def expect(self, nodes) -> None:
        """Tell the reporter how many points each stage has (for ``[k/n]`` counters and the ETA)."""
        for n in nodes:
            self._expected[n.stage] = self._expected.get(n.stage, 0) + 1
            self._total += 1
            values = [(d, n.coords[d]) for d in self._group_dims if d in n.coords]
            if values:
                self._point_values[n.node_id] = values
                for dv in values:
                    self._group_expected[dv] += 1
        if self.live and not self.quiet and self._bars is None:
            self._start_bars()

    def _start_bars(self) -> None:
        from rich.console import Console
        from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TaskProgressColumn, TextColumn,
                                   TimeElapsedColumn, TimeRemainingColumn)

        console = Console(file=self.stream, force_terminal=True, highlight=False)
        self._bars = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                              TextColumn("{task.fields[unit]}"), TaskProgressColumn(), TimeElapsedColumn(),
                              TextColumn("ETA"), TimeRemainingColumn(), console=console, transient=True)
        self._overall = self._bars.add_task("points", total=self._total, unit="points")
        self._bars.start()

    def finish(self) -> None:
        """Stop the progress bars (the executor calls it when the run ends)."""
        with self._lock:
            if self._bars is not None:
                self._bars.stop()
                self._bars = None

    def line(self, text: str) -> None:
        with self._lock:
            if self._bars is not None:
                self._bars.console.print(text, markup=False, highlight=False, soft_wrap=True)
            else:
                print(text, file=self.stream, flush=True)

    def notice(self, text: str) -> None:
        """Something a running point says at once (e.g. whom it waits for), stamped like progress lines."""
        if not self.quiet:
            self.line(text if self.live else f"{self._stamp()}  {text}")

    def _stamp(self) -> str:
        return datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M:%S")

    def outcome(self, o: Outcome) -> None:
        with self._lock:
            self.outcomes.append(o)
            self._finished[o.stage] += 1
            for dv in self._point_values.get(o.node_id, ()):
                self._group_finished[dv] += 1
            self._point_eta.pop(o.node_id, None)
            if self._bars is not None:
                self._bars.advance(self._overall)
                bar = self._bar_ids.pop(o.node_id, None)
                if bar is not None:
                    self._bars.remove_task(bar)
        if self.quiet:
            return
        why = o.reason + (f": {o.detail}" if o.detail else "")
        wall = f"{o.wall_s:8.1f} s" if o.status == "computed" else " " * 10
        stale = "  [STALE]" if o.stale else ""
        n = self._expected.get(o.stage, 0)
        count = f"  [{self._finished[o.stage]}/{n} of {o.stage}]" if n > 1 else ""
        self.line(f"{SYMBOL.get(o.status, '?')} {o.status:8s} {wall}  {o.node_id}  ({why}){stale}{count}")
        if o.status == "failed" and o.error:
            self.line(f"      error: {o.error.strip().splitlines()[-1]}")

    def overall(self) -> str:
        """``points 7/15 done, 1m02s elapsed, ETA 1m30s`` (and, with :meth:`group_by`,
        ``; by target_material: Al7075-T73 5/9, Ti6Al4V 2/9``).

        The ETA is the rate of computed points so far (reused ones cost
        nothing), but never less than the longest ETA of a running point: one
        long point (a REV run) outlasts any number of quick ones.
        """
        done = len(self.outcomes)
        now = time.time()
        elapsed = now - self.started
        computed = [o for o in self.outcomes if o.status == "computed"]
        left = eta(len(computed), len(computed) + self._total - done, elapsed) if done < self._total else 0.0
        running = [e - (now - t) for e, t in self._point_eta.values()]
        if running and done < self._total:
            left = max(left or 0.0, max(running))
        by = ""
        for d in self._group_dims:
            values = [v for dim, v in self._group_expected if dim == d]
            if values:
                by += f"; by {d}: " + ", ".join(
                    f"{self._label(d, v)} {self._group_finished[(d, v)]}/{self._group_expected[(d, v)]}"
                    for v in values)
        return f"points {done}/{self._total} done, {duration(elapsed)} elapsed, ETA {duration(left)}{by}"

    def progress(self, point: str, rec: dict) -> None:
        if self.quiet:
            return
        total = rec.get("total")
        done = rec.get("done") or 0
        now = rec.get("time") or time.time()
        t0, d0 = self._point_start.setdefault(point, (now, done))
        # the point's own start (and, resumed, where it resumed) when the record
        # says; else from when we first saw it
        start = rec.get("started", t0)
        base = rec.get("base", d0)
        left = eta(done - base, (total - base) if total else None, now - start)
        unit = rec.get("unit") or ""
        with self._lock:
            if left is not None:
                self._point_eta[point] = (left, time.time())
            if self._bars is not None:
                bar = self._bar_ids.get(point)
                if bar is None:
                    bar = self._bar_ids[point] = self._bars.add_task(point, total=total, unit=unit)
                self._bars.update(bar, completed=done, total=total)
                return
        frac = f" ({100.0 * done / total:.0f}%)" if total else ""
        of = f"/{total:g}" if total else ""
        note = f", {rec['note']}" if rec.get("note") else ""
        timing = f", {duration(now - start)} elapsed, ETA {duration(left)}" if total else ""
        self.line(f"{self._stamp()}  ... {point}: {done:g}{of}{' ' + unit if unit else ''}{frac}{timing}{note}")

    def tick(self) -> None:
        """Called by the progress poll while points run: the run's own progress line (plain output)."""
        if self.quiet or self.live or not self._total:
            return
        self.line(f"{self._stamp()}  {self.overall()}")

    def summary(self) -> str:
        rows = defaultdict(lambda: defaultdict(int))
        wall = defaultdict(float)
        order = []
        for o in self.outcomes:
            if o.stage not in rows:
                order.append(o.stage)
            rows[o.stage][o.status] += 1
            wall[o.stage] += o.wall_s
        cols = ["computed", "reused", "failed", "skipped", "blocked"]
        if any(o.status == "interrupted" for o in self.outcomes):
            cols.append("interrupted")
        width = max([len(s) for s in order] + [5])
        out = [f"{'stage':{width}s}  points " + " ".join(f"{c:>8s}" for c in cols) + "   compute s"]
        for s in order:
            n = sum(rows[s].values())
            out.append(f"{s:{width}s}  {n:6d} " + " ".join(f"{rows[s][c]:8d}" for c in cols)
                       + f"   {wall[s]:9.1f}")
        total = {c: sum(rows[s][c] for s in order) for c in cols}
        out.append(f"{'(all)':{width}s}  {len(self.outcomes):6d} " + " ".join(f"{total[c]:8d}" for c in cols)
                   + f"   {sum(wall.values()):9.1f}")
        out.append(f"wall time {time.time() - self.started:.1f} s")
        problems = [o for o in self.outcomes if o.status in ("failed", "blocked")
                    or (o.status == "interrupted" and o.key is not None)]
        if problems:
            out.append("")
            out.append("not finished:")
            for o in problems:
                out.append(f"  {o.status}: {o.node_id}: {o.error or o.detail}")
        return "\n".join(out)
