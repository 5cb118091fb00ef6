"""Issue 12 items 6 and 7: a lease never deadlocks a run, and a damaged lease or progress record crashes
nothing; status, run, clean and unlock judge a lease by one rule."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time

import pytest
from engine_helpers import peenflow, statuses, write_toy

from peenflow.engine import DirectoryStore, load_graph, plan
from peenflow.engine import lease as L
from peenflow.engine.reasons import State


def _scale_point(tmp_path):
    study = write_toy(tmp_path / "s")
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    peenflow("run", study, "--until", "source")
    item = next(i for i in plan(load_graph(study, "x:y"), store) if i.node.stage == "scale")
    return study, store, item


def _owner(store, key, record, age_s=0.0):
    d = store.leases.path(key)
    d.mkdir(parents=True, exist_ok=True)
    path = d / "owner.json"
    path.write_text(record if isinstance(record, str) else json.dumps(record))
    if age_s:
        t = time.time() - age_s
        os.utime(path, (t, t))
        os.utime(d, (t, t))
    return d


def _state(study, store, item):
    return next(i for i in plan(load_graph(study, "x:y"), store) if i.node.node_id == item.node.node_id)


@pytest.fixture
def unrelated_process():
    proc = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])
    yield proc
    proc.kill()
    proc.wait()


def test_the_verdict_rule(unrelated_process):
    me, host = os.getpid(), socket.gethostname()
    start = L.process_start_time(unrelated_process.pid)
    info = lambda **kw: L.LeaseInfo(**{"key": "k", "host": host, "pid": unrelated_process.pid, "started": 0.0,  # noqa: E731
                                       "heartbeat_age_s": 1.0, "point": "p", "pid_start": start, **kw})
    assert L.verdict(info())[0] is True
    alive, why = L.verdict(info(heartbeat_age_s=7200.0))  # live but unrelated pid, heartbeat 2 h old
    assert alive is False and "no heartbeat for 7200 s" in why
    alive, why = L.verdict(info(pid_start=start + 1))  # the pid now belongs to another process
    assert alive is False and "another process" in why
    alive, why = L.verdict(info(pid=me, pid_start=L.process_start_time(me), token="not-ours"))
    assert alive is False and "pid reused" in why  # names this very process, which never took it
    assert L.verdict(info(pid=2 ** 22 + 777))[0] is False
    assert L.verdict(info(host="elsewhere", heartbeat_age_s=30.0))[0] is None
    assert L.verdict(info(host="elsewhere", heartbeat_age_s=L.REMOTE_DEAD_AFTER_S + 1))[0] is False
    bad = info(host="?", pid=-1, problem="no owner record")
    assert L.verdict(bad)[0] is True and L.verdict(info(host="?", pid=-1, problem="x", heartbeat_age_s=11.0))[0] is False


def test_a_lease_naming_this_host_and_the_run_s_own_pid_does_not_block_it(tmp_path):
    """pid reuse after a restart: the stale lease names the pid the new run gets.  The run's pid is not known
    before it starts, so the run is started in-process here (same pid as the lease)."""
    study, store, item = _scale_point(tmp_path)
    _owner(store, item.key, {"host": socket.gethostname(), "pid": os.getpid(), "started": 0, "point": "old run",
                             "pid_start": L.process_start_time(os.getpid()), "token": "from-before-the-restart"})
    from peenflow.cli import main

    t0 = time.time()
    assert main(["run", str(study), "--quiet"]) == 0
    assert time.time() - t0 < 30
    assert _state(study, store, item).state is State.DONE


def test_a_live_unrelated_pid_with_an_old_heartbeat_is_not_running_forever(tmp_path, unrelated_process):
    study, store, item = _scale_point(tmp_path)
    _owner(store, item.key, {"host": socket.gethostname(), "pid": unrelated_process.pid, "started": 0,
                             "point": "old run"}, age_s=7200)
    st = _state(study, store, item)
    assert st.state is State.PENDING and "dead lease" in st.detail and "no heartbeat for 7200 s" in st.detail
    assert "[dead" in peenflow("status", study).stdout
    out = peenflow("run", study, timeout=60).stdout
    assert statuses(out)[item.node.node_id] == "computed" and "broke a dead lease" in out


@pytest.mark.parametrize("record", ['{"point": "x"}', "[1, 2, 3]", '{"host": "h", "pid": "twelve"}', "not json {"])
def test_a_damaged_owner_record_crashes_no_verb_and_is_broken_safely(tmp_path, capsys, record):
    # the verbs in-process (main() returns, or raises: a crash fails the test)
    from peenflow.cli import main

    study, store, item = _scale_point(tmp_path)
    lease = _owner(store, item.key, record)
    for verb in (["status", str(study), "--why"], ["unlock", str(study)], ["clean", str(study), "--dry-run"]):
        assert main(verb) == 0, verb
    status = capsys.readouterr().out
    assert "unreadable owner record" in status or "no owner record" in status
    # young: being written right now, so running for status and waited on by run (one rule)
    assert _state(study, store, item).state is State.RUNNING
    t = time.time() - 2 * L.OWNERLESS_GRACE_S
    os.utime(lease / "owner.json", (t, t))
    assert _state(study, store, item).state is State.PENDING  # the same grace for status as for run
    assert main(["run", str(study)]) == 0
    out = capsys.readouterr().out
    assert statuses(out)[item.node.node_id] == "computed" and "broke a dead lease" in out
    # unlock --all removes a damaged one too
    lease = _owner(store, "f" * 32, record, age_s=2 * L.OWNERLESS_GRACE_S)
    assert main(["unlock", str(study), "--all"]) == 0
    assert "removed" in capsys.readouterr().out and not lease.exists()


@pytest.mark.parametrize("record", ["[1]", '{"done": "half", "total": 3}', "{", '{"done": 1, "total": "x"}'])
def test_a_garbage_progress_record_crashes_no_status(tmp_path, record):
    study, store, item = _scale_point(tmp_path)
    store.progress_path(item.key).parent.mkdir(parents=True, exist_ok=True)
    store.progress_path(item.key).write_text(record)
    proc = peenflow("status", study, "--why", check=False)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr


def test_a_released_lease_never_removes_the_one_another_run_took_since(tmp_path):
    store = DirectoryStore(tmp_path / "store")
    mine = store.leases.try_acquire("k" * 32, "first")
    L._remove_dir(store.leases.path("k" * 32))  # broken while we were stopped (e.g. Ctrl-Z for too long)
    theirs = store.leases.try_acquire("k" * 32, "second")
    mine.release()
    assert store.leases.path("k" * 32).exists() and store.leases.info("k" * 32).point == "second"
    theirs.release()
    assert not store.leases.path("k" * 32).exists()


def test_a_run_waiting_for_a_live_holder_says_at_once_whom_and_how_long_in_a_pipe(tmp_path, unrelated_process):
    """A lease held by a live process with a fresh heartbeat: `run` (output to a pipe, not a terminal)
    names the holder and the longest wait within seconds, not after the 60 s it takes to judge it dead."""
    import queue
    import threading

    study, store, item = _scale_point(tmp_path)
    pid, host = unrelated_process.pid, socket.gethostname()
    lease = _owner(store, item.key, {"host": host, "pid": pid, "pid_start": L.process_start_time(pid),
                                     "started": time.time(), "point": f"toy:{item.node.node_id}"})
    proc = subprocess.Popen([sys.executable, "-m", "peenflow.cli", "run", str(study)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    lines: queue.Queue = queue.Queue()
    reader = threading.Thread(target=lambda: [lines.put(x) for x in proc.stdout], daemon=True)
    reader.start()
    t0 = time.time()
    try:
        while True:
            line = lines.get(timeout=max(0.1, 30 - (time.time() - t0)))
            if "waiting for" in line:
                break
        said_after = time.time() - t0
        beating = time.time()
        while time.time() - beating < 3.0:  # the holder goes on beating: the run goes on waiting
            os.utime(lease / "owner.json")
            time.sleep(0.5)
        assert proc.poll() is None
        L._remove_dir(lease)  # the holder ends without a result: the run computes the point itself
        proc.wait(timeout=60)
        reader.join(timeout=10)
    finally:
        if proc.poll() is None:
            proc.kill()
    took = time.time() - t0
    assert said_after < 15.0  # at once (the rest is the interpreter starting)
    assert line.split()[2:4] == ["waiting", "for"] and line[:4].isdigit()  # timestamped like progress lines
    assert f"waiting for {item.node.node_id}: pid {pid} on host {host} computes it (last heartbeat " in line
    assert f"at most {L.LOCAL_DEAD_AFTER_S:.0f} s after it stops, then this run takes the point over" in line
    assert proc.returncode == 0 and "Traceback" not in proc.stderr.read()
    rest = [lines.get() for _ in range(lines.qsize())]
    done = next(x for x in rest if f" {item.node.node_id} " in x)
    assert done.startswith("+ computed") and "waited" in done
    assert took < L.LOCAL_DEAD_AFTER_S  # it never had to wait for the holder to be judged dead
