"""Two runs on one store at the same time: both finish, nothing is computed twice at once."""

import subprocess
import sys
from collections import defaultdict

from engine_helpers import write_toy

from peenflow.engine import DirectoryStore, load_graph, plan
from peenflow.engine.reasons import State


def test_two_concurrent_runs_share_the_work_safely(tmp_path):
    study = write_toy(tmp_path / "s", factors=[1, 2, 3, 4, 5, 6], delay_s=0.4)
    log = tmp_path / "events.log"
    env = {"TOY_LOG": str(log)}
    import os

    procs = [subprocess.Popen([sys.executable, "-m", "peenflow.cli", "run", str(study), "--workers", "3"],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                              env=dict(os.environ, **env)) for _ in range(2)]
    outs = [p.communicate(timeout=120) for p in procs]
    for p, (out, err) in zip(procs, outs):
        assert p.returncode == 0, out + err

    # Each scale point started exactly once in total: the second run waited on the
    # first one's lease and reused its result instead of computing it again.
    starts = defaultdict(list)
    for line in log.read_text().splitlines():
        event, factor, pid, t = line.split()
        if event == "start":
            starts[factor].append(pid)
    assert sorted(starts) == ["1", "2", "3", "4", "5", "6"]
    assert all(len(v) == 1 for v in starts.values()), starts
    # Every point computed once over both runs (source, 6 x scale, total, counter) ...
    computed = [out.count("+ computed") for out, _ in outs]
    assert sum(computed) == 9
    # ... and the store is complete and valid.
    graph = load_graph(study, "unused:unused")
    items = plan(graph, DirectoryStore(study.parent / ".peenflow"))
    assert all(i.state is State.DONE for i in items)
