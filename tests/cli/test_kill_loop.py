"""Issue 12 "Done means": random SIGKILLs of a run, each followed by another run, lose nothing: no finished
result is recomputed or changed, no lease, run record or checkpoint is left behind at the end, and the
final results equal an uninterrupted run's."""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time

import pytest
from engine_helpers import live_entries, peenflow, write_toy

from peenflow.engine import DirectoryStore, load_graph, plan
from peenflow.engine.reasons import State

TOY = dict(factors=[1, 2, 3, 4, 5, 6], delay_s=0.4, steps=12, counter_delay_s=0.15, source_delay_s=0.3)


def _contents(study, store):
    """{point: content hash} of every stored result (provenance excluded); for the counter, which records
    where it resumed, its answer."""
    s = DirectoryStore(store)
    out = {}
    for i in plan(load_graph(study, "x:y"), s):
        assert i.state is State.DONE, (i.node.node_id, i.state, i.detail)
        out[i.node.node_id] = (float(s.open("counter", i.key).acc) if i.node.stage == "counter"
                               else s.manifest(i.node.task.name, i.key).content_hash)
    return out


def _kill_loop(tmp_path, kills: int, seed: int):
    rng = random.Random(seed)
    study = write_toy(tmp_path / "killed", **TOY)
    store = tmp_path / "killed" / ".peenflow"
    finished: dict[str, tuple[int, bytes]] = {}
    stretch = 1.0  # on a loaded machine the imports alone can outlast a wait: lengthen it until results land
    for _ in range(kills):
        proc = subprocess.Popen([sys.executable, "-m", "peenflow.cli", "run", str(study), "--workers", "2"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
        time.sleep(stretch * rng.uniform(1.5, 4.5))  # python and the imports take ~1.5 s of it
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        for p in store.glob("results/*/*.nc"):  # a finished result is never touched again
            stamp = (p.stat().st_mtime_ns, p.read_bytes())
            if p.name in finished:
                assert finished[p.name] == stamp, f"{p.name} was rewritten after a kill"
            elif (p.with_suffix(".json")).exists():
                finished[p.name] = stamp
        if not finished:
            stretch = min(2.0 * stretch, 8.0)
    peenflow("run", study, "--workers", "2", timeout=300)
    for name, stamp in finished.items():
        p = next(store.glob(f"results/*/{name}"))
        assert (p.stat().st_mtime_ns, p.read_bytes()) == stamp
    assert not any(live_entries(store / d) for d in ("leases", "runs", "checkpoints", "progress"))
    reference = write_toy(tmp_path / "clean", **TOY)
    peenflow("run", reference, "--workers", "2", timeout=300)
    assert _contents(study, store) == _contents(reference, tmp_path / "clean" / ".peenflow")
    return len(finished)


def test_random_sigkills_lose_nothing(tmp_path):
    assert _kill_loop(tmp_path, kills=4, seed=12) >= 1


@pytest.mark.slow
def test_many_random_sigkills_lose_nothing(tmp_path):
    n = _kill_loop(tmp_path, kills=40, seed=87)
    print(f"40 SIGKILLs: {n} results finished between kills, none rewritten")
    assert n >= 3
