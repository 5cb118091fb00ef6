"""Progress: plain timestamped lines with ETA when the output is not a terminal; live bars when it is."""

import io
import re
from types import SimpleNamespace

from engine_helpers import peenflow, write_toy

from peenflow.engine.progress import Reporter, duration, eta
from peenflow.engine.runner import Outcome

STAMP = r"\d{4}-\d\d-\d\d \d\d:\d\d:\d\d"


def test_eta_is_the_rate_so_far_extrapolated():
    assert eta(25, 100, 10.0) == 30.0  # 25 done in 10 s: 75 more take 30 s
    assert eta(0, 100, 10.0) is None and eta(5, None, 10.0) is None
    assert duration(42) == "42s" and duration(185) == "3m05s" and duration(3720) == "1h02m" and duration(None) == "?"


def test_piped_output_gets_timestamped_progress_lines_with_elapsed_and_eta(tmp_path):
    study = write_toy(tmp_path / "s", steps=6, counter_delay_s=0.4)
    out = peenflow("run", study, env={"PEENFLOW_PROGRESS_EVERY_S": "0.3"}).stdout
    point = re.findall(rf"^{STAMP}  \.\.\. counter: (\d+)/6 steps \(\d+%\), \d+s elapsed, ETA (\d+s|\?)$", out, re.M)
    assert point, out
    overall = re.findall(rf"^{STAMP}  points (\d+)/(\d+) done, \d+s elapsed, ETA \S+$", out, re.M)
    assert overall and all(int(n) == 6 for _, n in overall)  # source, 3 x scale, total, counter
    assert "\x1b[" not in out  # no terminal control codes in a log


def test_a_terminal_gets_live_bars_and_the_finished_points_above_them():
    stream = io.StringIO()
    r = Reporter(stream=stream, live=True)
    r.expect([SimpleNamespace(stage="a"), SimpleNamespace(stage="b")])
    r.progress("a", {"done": 3, "total": 10, "unit": "shots", "time": 2.0, "started": 0.0, "base": 0})
    r.outcome(Outcome("a", "a", "", {}, "t", "k", "computed", "missing", wall_s=1.0))
    r.finish()
    text = stream.getvalue()
    assert "+ computed" in text and "points" in text and "\x1b[" in text



def test_the_runs_eta_is_never_shorter_than_a_running_points():
    import time

    r = Reporter(stream=io.StringIO(), live=False)
    r.expect([SimpleNamespace(stage="quick")] * 3 + [SimpleNamespace(stage="rev")])
    for k in range(3):  # three quick points done: their rate alone says the last one is almost done
        r.outcome(Outcome(f"quick{k}", "quick", "", {}, "t", "k", "computed", "missing", wall_s=0.1))
    now = time.time()
    # the REV point did 100 of 1000 shots in 20 s: 180 s left
    r.progress("rev", {"done": 100, "total": 1000, "unit": "shots", "time": now, "started": now - 20, "base": 0})
    m = re.search(r"points 3/4 done, \S+ elapsed, ETA (\d+)m(\d+)s", r.overall())
    assert m and 170 <= 60 * int(m.group(1)) + int(m.group(2)) <= 180, r.overall()


def test_the_runs_line_counts_the_points_of_each_value_of_a_followed_dimension():
    r = Reporter(stream=io.StringIO(), live=False)
    r.group_by(["material"], lambda d, v: ["steel", "titanium"][v])
    nodes = [SimpleNamespace(stage="shared", node_id="shared", coords={})]  # reached by no value: not counted
    nodes += [SimpleNamespace(stage="run", node_id=f"run[material={m},sequence={s}]", coords={"material": m,
                                                                                            "sequence": s})
              for m in (0, 1) for s in (0, 1, 2)]
    r.expect(nodes)
    for n in nodes[:3]:  # the shared point, then two of steel's three
        r.outcome(Outcome(n.node_id, n.stage, "", n.coords, "t", "k", "computed", "missing", wall_s=0.1))
    assert r.overall().endswith("; by material: steel 2/3, titanium 0/3"), r.overall()
