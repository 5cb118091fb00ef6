"""Ctrl-C on a ``--scheduler`` run reaches the dask workers: the points they run stop at their next
checkpoint, the client exits as a local stop does, and the next run resumes them."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import xarray as xr
from engine_helpers import live_entries, peenflow, statuses, stop_with, write_toy

STEPS, STEP_S = 25, 0.2  # a lane alone takes 5 s


def _steps(log: Path) -> list[tuple[int, int, int]]:
    """(lane, step, pid) of every step saved so far, in order."""
    if not log.exists():
        return []
    out = []
    for line in log.read_text().splitlines():
        event, what, pid, _ = line.split()
        if event == "step":
            lane, step = map(int, what.split("/"))
            out.append((lane, step, int(pid)))
    return out


def _per_lane(steps) -> dict[int, int]:
    """Steps saved per lane."""
    return dict(Counter(lane for lane, _, _ in steps))


def _hashes(store: Path) -> dict:
    return {f"{m.parent.name}/{m.stem}": json.loads(m.read_text())["content_hash"]
            for m in store.glob("results/*/*.json")}


def test_ctrl_c_on_a_cluster_run_stops_the_workers_points_at_a_checkpoint_and_the_next_run_resumes(
        tmp_path, monkeypatch):
    """Two worker processes run two of three lanes of checkpointed steps; SIGINT to the client: the two stop
    at their next checkpoint within seconds, the third never starts, and the next run finishes all three from where they were."""
    from distributed import Client, LocalCluster

    # three lanes of 25 checkpointed steps on two single-threaded worker processes: two lanes run, one waits
    study = write_toy(tmp_path / "s", lanes=3, steps=STEPS, counter_delay_s=STEP_S)
    store = study.parent / ".peenflow"
    log = tmp_path / "steps.log"
    # the workers are spawned from this process: they import the toy from the study's folder and log to TOY_LOG
    monkeypatch.syspath_prepend(str(study.parent))
    monkeypatch.setenv("TOY_LOG", str(log))
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            worker_pids = set(client.run(os.getpid).values())
        address = cluster.scheduler_address
        proc = subprocess.Popen([sys.executable, "-m", "peenflow.cli", "run", str(study), "--scheduler", address],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
        t0 = time.time()
        while sum(n >= 3 for n in _per_lane(_steps(log)).values()) < 2:
            if proc.poll() is not None or time.time() - t0 > 60:
                proc.kill()
                raise AssertionError(f"two lanes never got running: {proc.communicate()}")
            time.sleep(0.05)
        at_signal = _per_lane(_steps(log))
        out, err, took = stop_with(proc, signal.SIGINT)
        stopped = _steps(log)
        print(f"client exited {took:.2f} s after SIGINT; steps per lane at the signal {at_signal}, "
              f"at the stop {_per_lane(stopped)}")
        time.sleep(5 * STEP_S)  # five steps' time: a lane still computing on a worker would log more
        assert _steps(log) == stopped, "the workers went on computing after the client exited"

        # the client: the exit code, messages and per-point lines of a local stop, within a few steps' time
        assert proc.returncode == 130, (out, err)
        assert took < 5.0, f"took {took:.1f} s to stop"
        assert "Traceback" not in out + err
        assert "SIGINT: stopping" in err
        assert "interrupted: finished results and the checkpoints of stopped points are kept; run again to resume" \
            in out
        reached = _per_lane(stopped)
        assert len(reached) == 2 and all(3 <= n < STEPS for n in reached.values()), reached  # none finished
        assert {pid for _, _, pid in stopped} <= worker_pids
        assert len({pid for _, _, pid in stopped}) == 2  # one lane in each worker process
        for lane, n in reached.items():  # each stopped right after the checkpoint of its last step
            line = next(x for x in out.splitlines() if f"lane_counter[lane={lane}]" in x)
            assert line.startswith("x interrupted") and f"stopped after step {n} of {STEPS}; checkpoint saved" in line
        waiting = ({0, 1, 2} - set(reached)).pop()
        line = next(x for x in out.splitlines() if f"lane_counter[lane={waiting}]" in x)
        assert line.startswith("x interrupted") and "not started: SIGINT received" in line  # the client's reason
        checkpoints = sorted(int(xr.open_dataset(p).step.item()) for p in store.glob("checkpoints/*/checkpoint.nc"))
        assert checkpoints == sorted(reached.values())
        assert not list(store.glob("results/lane_counter/*")) and not list(store.glob("failures/*/*.json"))
        assert not live_entries(store / "leases") and not live_entries(store / "runs")

        # the next run resumes the stopped lanes from their checkpoints and computes the waiting one
        resumed = peenflow("run", study, "--scheduler", address, timeout=120).stdout
    st = statuses(resumed)
    assert all(st[f"lane_counter[lane={lane}]"] == "computed" for lane in range(3)), resumed
    for lane in reached:
        assert "resuming from checkpoint" in next(x for x in resumed.splitlines() if f"lane_counter[lane={lane}]" in x)
    second = _steps(log)[len(stopped):]
    for lane in range(3):  # every step saved exactly once over both runs: nothing lost, nothing recomputed
        done = [s for ln, s, _ in stopped + second if ln == lane]
        assert sorted(done) == list(range(STEPS)) and Counter(done).most_common(1)[0][1] == 1
        assert min(s for ln, s, _ in second if ln == lane) == reached.get(lane, 0)
    for f in store.glob("results/lane_counter/*.nc"):
        with xr.open_dataset(f) as ds:
            assert ds.attrs["peenflow_pid"] in worker_pids
            assert ds.attrs["peenflow_resumed"] == int(int(ds.lane.item()) in reached)
    assert not list(store.glob("checkpoints/*/checkpoint.nc"))

    # the same store as a run never stopped
    reference = write_toy(tmp_path / "ref", lanes=3, steps=STEPS, counter_delay_s=STEP_S)
    peenflow("run", reference, "--workers", "3", env={"TOY_LOG": ""}, timeout=120)
    assert len(_hashes(store)) == 8  # source, 3 scale, total, 3 lanes
    assert _hashes(store) == _hashes(reference.parent / ".peenflow")


def _read_stop(name: str) -> str:
    """What a point on a worker reads as its run's stop reason."""
    from peenflow.engine.cluster_stop import worker_check

    return worker_check(name)()


def test_the_relay_passes_the_reason_on_and_leaves_nothing_on_the_scheduler_after_a_finished_run():
    from distributed import Client, LocalCluster, Variable

    from peenflow.engine import interrupt
    from peenflow.engine.cluster_stop import StopRelay, variable_name

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        finished, stopped, abandoned = variable_name(), variable_name(), variable_name()
        def held(name):
            return client.run_on_scheduler(lambda dask_scheduler: name in dask_scheduler.extensions["variables"]
                                           .variables)

        with StopRelay(client, finished):
            assert client.submit(_read_stop, finished, pure=False).result() == ""  # no stop asked
            assert held(finished)
        assert not held(finished)
        try:
            with StopRelay(client, stopped):
                interrupt.request_stop("SIGTERM received")
                t0 = time.time()
                while client.submit(_read_stop, stopped, pure=False).result() == "":
                    assert time.time() - t0 < 5
                    time.sleep(0.05)
                assert client.submit(_read_stop, stopped, pure=False).result() == "SIGTERM received"
        finally:
            interrupt.reset()
        try:  # a client that gives up (an error, a KeyboardInterrupt) leaves its abandoned points a stop
            with StopRelay(client, abandoned):
                raise KeyboardInterrupt
        except KeyboardInterrupt:
            pass
        assert Variable(abandoned, client=client).get(timeout=5) == "the run's client stopped (KeyboardInterrupt)"
