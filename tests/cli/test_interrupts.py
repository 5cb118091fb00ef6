"""Issue 12 items 3 and 5: a signal stops a run at its next checkpoint within seconds; a second one exits
at once without a traceback; no lease is left; the next run (or rerun) resumes from the checkpoint."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest
import xarray as xr
from engine_helpers import live_entries as _live, peenflow, statuses, write_toy

from peenflow.engine import DirectoryStore, load_graph, plan
from peenflow.engine.checkpoint import Checkpoints


def _start(*args):
    return subprocess.Popen([sys.executable, "-m", "peenflow.cli", *map(str, args), "--workers", "1"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)


def _wait_for_step(store, at_least, timeout=60.0):
    t0 = time.time()
    while time.time() - t0 < timeout:
        for p in store.glob("checkpoints/*/checkpoint.nc"):
            try:
                if xr.open_dataset(p).step.item() >= at_least:
                    return
            except (OSError, ValueError, KeyError, AttributeError):
                pass
        time.sleep(0.05)
    raise AssertionError("the counter never got that far")


def _counter(study, store):
    item = next(i for i in plan(load_graph(study, "x:y"), DirectoryStore(store)) if i.node.stage == "counter")
    return item


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP], ids=lambda s: s.name)
def test_one_signal_stops_at_the_next_checkpoint_and_the_next_run_resumes(tmp_path, sig):
    # counter: 16 steps of 0.25 s, a checkpoint after each; it runs alone (the toy's other points are quick)
    study = write_toy(tmp_path / "s", steps=16, counter_delay_s=0.25)
    store = tmp_path / "s" / ".peenflow"
    proc = _start("run", study)
    try:
        _wait_for_step(store, 3)
        t0 = time.time()
        os.kill(proc.pid, sig)
        out, err = proc.communicate(timeout=30)
        took = time.time() - t0
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 128 + sig, (out, err)
    assert took < 5.0, f"took {took:.1f} s to stop"  # one step is 0.25 s: it did not compute on
    assert "Traceback" not in err and "Traceback" not in out
    assert f"{sig.name}: stopping" in err
    assert "x interrupted" in out and "checkpoint saved" in out and "failed" not in out.split("stage")[0]
    assert not _live(store / "leases") and not _live(store / "runs")
    stopped_at = int(xr.open_dataset(next(store.glob("checkpoints/*/checkpoint.nc"))).step.item())
    assert 3 <= stopped_at < 16
    assert not list(store.glob("failures/*/*.json"))  # an interrupt is not a failure
    st = statuses(peenflow("run", study).stdout)
    assert st["counter"] == "computed"
    ds = DirectoryStore(store).open("counter", _counter(study, store).key)
    assert int(ds.started_at_step) == stopped_at  # resumed where it stopped ...
    assert float(ds.acc) == sum(range(16))  # ... with the uninterrupted answer


def _owner(lease: Path) -> str:
    """A lease's owner record, or '' once it is gone: a finished point releases its lease at any moment,
    so the folder listed a moment ago may have lost its record since."""
    try:
        return (lease / "owner.json").read_text()
    except FileNotFoundError:
        return ""


def test_a_second_ctrl_c_exits_at_once_without_traceback_and_releases_the_lease(tmp_path):
    # a point that never checks for a stop: the first Ctrl-C cannot stop it, the second must
    study = write_toy(tmp_path / "s", factors=[1], delay_s=30.0)
    store = tmp_path / "s" / ".peenflow"
    proc = _start("run", study)
    try:
        t0 = time.time()
        while not any("scale" in _owner(p) for p in _live(store / "leases")):
            time.sleep(0.05)
            assert time.time() - t0 < 60
        time.sleep(0.3)
        os.kill(proc.pid, signal.SIGINT)
        time.sleep(0.5)
        assert proc.poll() is None  # still computing the 30 s point
        t1 = time.time()
        os.kill(proc.pid, signal.SIGINT)
        out, err = proc.communicate(timeout=10)
        took = time.time() - t1
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130
    assert took < 2.0
    assert "Traceback" not in err and "SIGINT again: exiting now" in err
    assert not _live(store / "leases") and not _live(store / "runs")


def test_a_killed_rerun_resumes_its_own_checkpoint(tmp_path):
    study = write_toy(tmp_path / "s", steps=16, counter_delay_s=0.15)
    store = tmp_path / "s" / ".peenflow"
    peenflow("run", study, timeout=120)
    proc = _start("rerun", study, "counter")
    try:
        _wait_for_step(store, 5)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    reached = int(xr.open_dataset(next(store.glob("checkpoints/*/checkpoint.nc"))).step.item())
    assert reached >= 5
    out = peenflow("rerun", study, "counter", timeout=120).stdout
    assert "resuming its own checkpoint" in out
    ds = DirectoryStore(store).open("counter", _counter(study, store).key)
    assert int(ds.started_at_step) >= reached and float(ds.acc) == sum(range(16))


@pytest.mark.parametrize("damage", ["garbage", "truncated"])
def test_an_unreadable_checkpoint_is_said_in_one_line_and_the_point_starts_over(tmp_path, damage):
    study = write_toy(tmp_path / "s", steps=6)
    store = tmp_path / "s" / ".peenflow"
    peenflow("run", study, "--until", "source")
    key = _counter(study, store).key
    ck = DirectoryStore(store).checkpoint_dir(key)
    if damage == "garbage":
        ck.mkdir(parents=True)
        (ck / "checkpoint.nc").write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(range(256)) * 4)
    else:  # a real checkpoint at step 4, cut in half (a full disk, a crash of the disk itself)
        Checkpoints(ck).save(xr.Dataset({"step": ((), 4), "acc": ((), 6.0)}))
        data = (ck / "checkpoint.nc").read_bytes()
        (ck / "checkpoint.nc").write_bytes(data[: len(data) // 2])
    proc = peenflow("run", study)
    line = next(x for x in proc.stdout.splitlines() if " counter " in x)
    assert line.startswith("+ computed") and "checkpoint unreadable, starting over" in line
    assert "resuming" not in line
    assert proc.stderr == ""  # no UserWarning and its source line
    ds = DirectoryStore(store).open("counter", key)
    assert ds.attrs["peenflow_resumed"] == 0
    assert int(ds.started_at_step) == 0 and float(ds.acc) == sum(range(6))
    assert not ck.exists()
