"""Kill a run mid-way, run again: finished work is reused untouched, the rest resumes."""

import os
import signal
import subprocess
import sys
import time

import xarray as xr
from engine_helpers import statuses, peenflow, result_files, write_toy

from peenflow.engine import DirectoryStore, load_graph, plan
from peenflow.engine.reasons import State


def _wait_for(cond, timeout=60.0):
    t0 = time.time()
    while time.time() - t0 < timeout:
        if cond():
            return
        time.sleep(0.05)
    raise AssertionError("timed out waiting for the run to make progress")


def test_killed_run_resumes_without_recomputing_finished_work(tmp_path):
    study = write_toy(tmp_path / "s", factors=[1, 2, 3, 4], delay_s=0.6, steps=10, counter_delay_s=0.25)
    store = tmp_path / "s" / ".peenflow"
    proc = subprocess.Popen([sys.executable, "-m", "peenflow.cli", "run", str(study), "--workers", "2"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    ckpt = lambda: list(store.glob("checkpoints/*/checkpoint.nc"))  # noqa: E731
    try:
        # Kill once some results are finished and the long task is part-way through.
        _wait_for(lambda: len(list(store.glob("results/*/*.json"))) >= 2 and ckpt())
        _wait_for(lambda: xr.open_dataset(ckpt()[0]).step.item() >= 2 if ckpt() else False)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()

    before = result_files(store)
    stamps = {p.name: p.stat().st_mtime_ns for p in store.glob("results/*/*.nc")}
    assert 2 <= len(before) < 7, "the kill should land mid-run"

    # status says where the next run resumes: the checkpoint's step, not the dead run's own count (a run
    # that checkpoints every PEENFLOW_CHECKPOINT_EVERY_S gets past its last checkpoint before a kill)
    with xr.open_dataset(ckpt()[0]) as ck:
        saved = int(ck.step)
    key = ckpt()[0].parent.name
    DirectoryStore(store).write_progress(key, {"study": "toy", "point": "counter", "done": saved + 3, "total": 10,
                                               "unit": "steps"})
    line = next(ln for ln in peenflow("status", study, "--why").stdout.splitlines() if " counter  (" in ln)
    assert line.split()[:2] == ["pending", key[:12]], line
    assert f"counter  (incomplete: the next run resumes from its checkpoint after {saved}/10 steps; dead lease" in line
    assert f"{saved + 3}/10" not in line, line

    out = peenflow("run", study, "--workers", "2").stdout
    assert f"counter  (incomplete: resuming from checkpoint after {saved}/10 steps)" in out, out
    computed = [l for l in out.splitlines() if l.startswith("+ computed")]
    reused = [l for l in out.splitlines() if l.startswith("= reused")]
    assert len(computed) + len(reused) == 7
    assert len(reused) == len(before)  # nothing finished is computed again ...
    after = result_files(store)
    for name, data in before.items():  # ... and its file is left byte-for-byte as it was
        assert after[name] == data
    for p in store.glob("results/*/*.nc"):
        if p.name in stamps:
            assert p.stat().st_mtime_ns == stamps[p.name]

    graph = load_graph(study, "unused:unused")
    items = plan(graph, DirectoryStore(store))
    assert all(i.state is State.DONE for i in items)
    counter = next(i for i in items if i.node.stage == "counter")
    ds = DirectoryStore(store).open("counter", counter.key)
    assert int(ds.started_at_step) >= 2  # resumed from its checkpoint, not from scratch
    assert float(ds.acc) == sum(range(10))  # and the answer is the uninterrupted one
    assert not list(store.glob("checkpoints/*"))  # checkpoint removed once the result is stored


def test_a_result_file_without_manifest_is_not_taken_as_done(tmp_path):
    study = write_toy(tmp_path / "s")
    peenflow("run", study)
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    graph = load_graph(study, "unused:unused")
    item = next(i for i in plan(graph, store) if i.node.stage == "total")
    store.manifest_path("total", item.key).unlink()  # as if killed between rename and manifest
    again = next(i for i in plan(graph, store) if i.node.stage == "total")
    assert again.state is State.PENDING and again.reason.value == "incomplete"
    assert "no manifest" in again.detail
    out = peenflow("run", study).stdout
    assert statuses(out)["total"] == "computed"
