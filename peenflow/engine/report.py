"""Console reporting: a line per finished point, progress of long ones, a summary."""

from __future__ import annotations

import sys
import threading
import time
from collections import defaultdict

from .runner import Outcome

SYMBOL = {"computed": "+", "reused": "=", "failed": "!", "skipped": "-", "blocked": "#", "interrupted": "x"}


class Reporter:
    def __init__(self, stream=None, quiet: bool = False):
        self.stream = stream or sys.stdout
        self.quiet = quiet
        self.outcomes: list[Outcome] = []
        self._lock = threading.Lock()
        self.started = time.time()
        self._expected: dict[str, int] = {}
        self._finished: dict[str, int] = defaultdict(int)

    def expect(self, nodes) -> None:
        """Tell the reporter how many points each stage has (for ``[k/n]`` counters)."""
        for n in nodes:
            self._expected[n.stage] = self._expected.get(n.stage, 0) + 1

    def line(self, text: str) -> None:
        with self._lock:
            print(text, file=self.stream, flush=True)

    def outcome(self, o: Outcome) -> None:
        self.outcomes.append(o)
        self._finished[o.stage] += 1
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

    def progress(self, point: str, rec: dict) -> None:
        if self.quiet:
            return
        total = rec.get("total")
        done = rec.get("done")
        frac = f" ({100.0 * done / total:.0f}%)" if total else ""
        unit = f" {rec['unit']}" if rec.get("unit") else ""
        of = f"/{total:g}" if total else ""
        note = f"  {rec['note']}" if rec.get("note") else ""
        self.line(f"  ... {point}: {done:g}{of}{unit}{frac}{note}")

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
