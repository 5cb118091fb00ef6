"""Small things a newcomer meets first: the version, and a scheduler that is not there."""

import os
import socket
import subprocess
import sys
from pathlib import Path

import peenflow

MICRO = Path(__file__).resolve().parents[1] / "tasks" / "micro.toml"


def cli(*args, env=None):
    return subprocess.run([sys.executable, "-m", "peenflow.cli", *map(str, args)], capture_output=True, text=True,
                          timeout=120, env=dict(os.environ, **(env or {})))


def test_version():
    proc = cli("--version")
    assert proc.returncode == 0 and proc.stdout.strip() == f"peenflow {peenflow.__version__}"


def test_an_unreachable_scheduler_is_one_line_naming_the_address_and_what_to_check(tmp_path):
    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    study = tmp_path / "micro.toml"
    study.write_text(MICRO.read_text())
    proc = cli("run", study, "--scheduler", f"tcp://127.0.0.1:{port}", env={"PEENFLOW_SCHEDULER_TIMEOUT_S": "2"})
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert f"tcp://127.0.0.1:{port}" in lines[0] and "dask scheduler" in lines[0] and "port" in lines[0]
    assert "Traceback" not in proc.stderr
    assert not list(tmp_path.glob(".peenflow/results/*/*.nc"))  # nothing computed


def test_a_scheduler_is_not_contacted_when_every_point_is_stored(tmp_path):
    """A finished study run again with --scheduler: every point reused here, no connection attempted (the
    address is one no scheduler could be at), the summary printed; a changed point does need it."""
    from engine_helpers import statuses, write_toy

    study = write_toy(tmp_path / "s")
    assert cli("run", study).returncode == 0
    proc = cli("run", study, "--scheduler", "tcp://nowhere:1", env={"PEENFLOW_SCHEDULER_TIMEOUT_S": "2"})
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "cannot reach" not in proc.stdout + proc.stderr
    assert "every point is stored: reused here, the scheduler at tcp://nowhere:1 is not contacted" in proc.stdout
    st = statuses(proc.stdout)
    assert len(st) == 6 and set(st.values()) == {"reused"}, proc.stdout
    assert "(all)         6        0        6" in proc.stdout  # the summary: 6 points, 0 computed, 6 reused
    write_toy(tmp_path / "s", n=6)  # the source changes: now there is work for the cluster
    proc = cli("run", study, "--scheduler", "tcp://nowhere:1", env={"PEENFLOW_SCHEDULER_TIMEOUT_S": "2"})
    assert proc.returncode == 2 and "cannot reach the dask scheduler at tcp://nowhere:1" in proc.stderr
