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
