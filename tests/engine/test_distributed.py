"""The same study on a real dask.distributed scheduler + worker gives the local results."""

import os
import socket
import subprocess
import sys
import time

import pytest
import xarray as xr
from engine_helpers import peenflow, write_toy

from peenflow.engine import DirectoryStore


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait_port(port, timeout=60):
    t0 = time.time()
    while time.time() - t0 < timeout:
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=1):
                return
        except OSError:
            time.sleep(0.2)
    raise AssertionError(f"dask scheduler did not open port {port}")


@pytest.fixture
def cluster(tmp_path):
    port = _free_port()
    # The workers import the study's pipeline module from here; the folder must
    # exist before they start (Python caches a missing sys.path entry as absent).
    (tmp_path / "dist").mkdir()
    bindir = os.path.dirname(sys.executable)
    dask = os.path.join(bindir, "dask")
    env = dict(os.environ, PYTHONPATH=str(tmp_path / "dist") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", str(port),
                               "--no-dashboard"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)]
    try:
        _wait_port(port)
        procs.append(subprocess.Popen([dask, "worker", f"tcp://127.0.0.1:{port}", "--nthreads", "2",
                                       "--nworkers", "1", "--no-dashboard"],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env))
        from distributed import Client

        with Client(f"tcp://127.0.0.1:{port}", timeout="30s") as c:
            c.wait_for_workers(1, timeout=60)
        yield f"tcp://127.0.0.1:{port}"
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()


def test_distributed_run_matches_local_run(tmp_path, cluster):
    local = write_toy(tmp_path / "local")
    dist = write_toy(tmp_path / "dist")
    peenflow("run", local)
    proc = peenflow("run", dist, "--scheduler", cluster, timeout=180)
    assert "failed" not in proc.stdout.split("stage")[0]
    lres = {p.name: p for _, _, p in DirectoryStore(tmp_path / "local" / ".peenflow").all_results()}
    dres = {p.name: p for _, _, p in DirectoryStore(tmp_path / "dist" / ".peenflow").all_results()}
    assert lres.keys() == dres.keys()  # same keys on the cluster as locally
    for name in lres:
        with xr.open_dataset(lres[name]) as a, xr.open_dataset(dres[name]) as b:
            xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())
            # computed on the worker, not in the peenflow process itself
            assert b.attrs["peenflow_pid"] != a.attrs["peenflow_pid"]
