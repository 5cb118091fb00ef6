"""Issue 12 items 1, 2 and 4: clean never removes what the given study uses, never touches what a live
run writes, and removes what a finished point left behind (dead lease, leftover checkpoint)."""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

from engine_helpers import live_entries, peenflow, result_files, statuses, write_toy

from peenflow.engine import DirectoryStore, load_graph, plan
from peenflow.engine.reasons import State


def _states(study, store):
    return {i.node.node_id: i.state for i in plan(load_graph(study, "x:y"), DirectoryStore(store))}


def test_clean_keeps_what_the_given_study_uses_after_a_same_named_copy_ran(tmp_path):
    study = write_toy(tmp_path / "s", n=5)
    store = tmp_path / "s" / ".peenflow"
    peenflow("run", study)
    # a copy with the same [study] name and a changed parameter, on the same store
    copy_dir = tmp_path / "s" / "copy"
    copy = write_toy(copy_dir, n=4)
    peenflow("run", copy, "--store", store)
    assert all(s is State.DONE for s in _states(study, store).values())  # status: done (up to date)
    mine = {f"{i.key}.nc" for i in plan(load_graph(study, "x:y"), DirectoryStore(store))}
    dry = peenflow("clean", study, "--dry-run").stdout
    assert not [line for line in dry.splitlines() if any(k[:-3] in line for k in mine)], dry
    assert "kept 6 used by this study" in dry
    assert "kept 5 referenced by the last run of a study on this store" in dry  # the copy's source, 3 scale, total
    before = result_files(store)
    peenflow("clean", study)
    assert result_files(store) == before  # nothing either study uses was removed
    assert all(v == "reused" for v in statuses(peenflow("run", study).stdout).values())
    assert all(v == "reused" for v in statuses(peenflow("run", copy, "--store", store).stdout).values())


def test_clean_racing_a_run_never_breaks_it(tmp_path):
    # 8 slow points, long enough for several cleans on a loaded machine; the study file changes under
    # the run (n=4 -> the running n=5 results are unreferenced
    # by the file, which is exactly what a racing clean would delete)
    study = write_toy(tmp_path / "s", n=5, factors=list(range(1, 9)), delay_s=0.3, steps=40, counter_delay_s=0.3)
    store = tmp_path / "s" / ".peenflow"
    proc = subprocess.Popen([sys.executable, "-m", "peenflow.cli", "run", str(study), "--workers", "2"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
                            env={**os.environ, "TOY_FAIL_FACTOR": "1"})  # one point fails early, on purpose
    other = tmp_path / "other"
    shutil.copytree(tmp_path / "s", other, ignore=shutil.ignore_patterns(".peenflow"))
    other_study = write_toy(other, n=4)
    cleans = 0
    try:
        failures = lambda: list(store.glob("failures/scale/*.json"))  # noqa: E731
        spared = 0
        while proc.poll() is None:
            had = bool(failures())
            out = peenflow("clean", other_study, "--store", store).stdout
            cleans += "removed" in out
            # still registered after the clean (it registers once, deregisters when its points are done):
            # the run was executing through the whole clean, so its failure record must still be there
            # (none while runs/ does not exist: a clean may finish before the run's interpreter has started)
            registered = live_entries(store / "runs")
            if had and registered:
                assert failures(), out
                spared += 1
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert cleans >= 3
    assert proc.returncode == 1, out + err  # the one point that fails on purpose ...
    st = statuses(out)
    assert st["scale[factor=1]"] == "failed" and st["total"] == "skipped"
    assert all(v == "computed" for k, v in st.items() if k not in ("scale[factor=1]", "total")), out
    assert spared >= 1  # its failure record, written during the run, survived the cleans while it ran
    # everything it computed is there for the next run
    st = statuses(peenflow("run", study).stdout)
    assert st["scale[factor=1]"] == "computed" and st["total"] == "computed"
    assert all(v == "reused" for k, v in st.items() if k not in ("scale[factor=1]", "total"))


def test_clean_spares_a_result_under_a_live_lease_or_written_since_a_live_run_began(tmp_path):
    study = write_toy(tmp_path / "s", n=5)
    peenflow("run", study)
    write_toy(tmp_path / "s", n=4)  # the n=5 source result is now used by nobody ...
    peenflow("run", study, "--until", "source")
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    old = next(p for p in store.root.glob("results/source/*.nc")
               if p.stem not in {i.key for i in plan(load_graph(study, "x:y"), store)})
    lease = store.leases.try_acquire(old.stem, "a live run computing it")  # ... but a live run holds its key
    out = peenflow("clean", study, "--dry-run").stdout
    assert old.stem not in out and "kept 1 result under a live lease" in out
    lease.release()
    run = store.runs.try_acquire("test-run", "a live run")  # a run began; then the file is (re)written
    time.sleep(0.05)
    os.utime(old)
    out = peenflow("clean", study, "--dry-run").stdout
    assert old.stem not in out and "kept 1 result written since a live run began" in out
    run.release()
    assert f"would remove results/source/{old.name}" in peenflow("clean", study, "--dry-run").stdout


def test_a_run_waits_for_a_running_clean(tmp_path):
    study = write_toy(tmp_path / "s")
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    lock = store.locks.try_acquire("clean", "test clean")  # a clean in progress (this process, alive)
    proc = subprocess.Popen([sys.executable, "-m", "peenflow.cli", "run", str(study)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # registered (on a loaded machine the interpreter and its imports alone take seconds: poll, do not guess)
    t0 = time.time()
    while not live_entries(store.root / "runs"):
        assert proc.poll() is None and time.time() - t0 < 60, "the run never registered"
        time.sleep(0.05)
    time.sleep(1.0)  # and it keeps waiting for the clean: it computes nothing
    assert proc.poll() is None and not (store.root / "results").exists()
    assert len(live_entries(store.root / "runs")) == 1
    lock.release()
    out, _ = proc.communicate(timeout=60)
    assert proc.returncode == 0 and "computed" in out


def _dead_pid():
    pid = 2 ** 22 + 4321
    assert not os.path.exists(f"/proc/{pid}")
    return pid


def test_what_a_run_killed_after_its_manifest_left_is_removed_by_the_next_run_and_by_clean(tmp_path):
    study = write_toy(tmp_path / "s")
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    peenflow("run", study)
    items = [i for i in plan(load_graph(study, "x:y"), store) if i.node.stage in ("counter", "source")]

    def leave_behind(key):
        # as a SIGKILL between write_result and the cleanup leaves them: a lease of a dead pid, a checkpoint
        # older than the manifest, a progress record
        lease = store.leases.path(key)
        lease.mkdir(parents=True)
        (lease / "owner.json").write_text(json.dumps(
            {"host": socket.gethostname(), "pid": _dead_pid(), "started": 0, "point": "killed"}))
        ck = store.checkpoint_dir(key)
        ck.mkdir(parents=True)
        (ck / "checkpoint.nc").write_bytes(b"old")
        old = os.path.getmtime(store.manifest_path(next(i.node.task.name for i in items if i.key == key), key)) - 60
        os.utime(ck / "checkpoint.nc", (old, old))
        store.write_progress(key, {"study": "toy", "point": "x", "done": 1, "total": 3})

    counter, source = (next(i for i in items if i.node.stage == s) for s in ("counter", "source"))
    leave_behind(counter.key)
    leave_behind(source.key)
    out = peenflow("run", study).stdout
    assert "removed the checkpoint a finished run left behind" in out and "broke a dead lease" in out
    for key in (counter.key, source.key):
        assert not store.leases.path(key).exists() and not store.checkpoint_dir(key).exists()
        assert not store.progress_path(key).exists()
    leave_behind(counter.key)  # clean (without --checkpoints) removes the same
    out = peenflow("clean", study).stdout
    assert f"removed lease {counter.key[:12]}" in out and f"removed checkpoints/{counter.key}" in out
    assert not store.leases.path(counter.key).exists() and not store.checkpoint_dir(counter.key).exists()
    assert all(v == "reused" for v in statuses(peenflow("run", study).stdout).values())


def test_clean_keeps_an_unfinished_checkpoint_unless_asked(tmp_path):
    study = write_toy(tmp_path / "s", steps=3)
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    peenflow("run", study, "--until", "source")
    counter = next(i for i in plan(load_graph(study, "x:y"), store) if i.node.stage == "counter")
    store.checkpoint_dir(counter.key).mkdir(parents=True)
    (store.checkpoint_dir(counter.key) / "checkpoint.nc").write_bytes(b"x")
    out = peenflow("clean", study).stdout
    assert "kept 1 checkpoint of an unfinished point" in out and store.checkpoint_dir(counter.key).exists()
    peenflow("clean", study, "--checkpoints")
    assert not store.checkpoint_dir(counter.key).exists()
