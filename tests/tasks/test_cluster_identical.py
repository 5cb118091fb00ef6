"""A cluster run of the micro study writes bit-identical results to a local run (same keys, same content hashes)."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import xarray as xr

HERE = Path(__file__).parent


def _hashes(store: Path) -> dict:
    """{task/key: content hash} of every stored result."""
    return {f"{m.parent.name}/{m.stem}": json.loads(m.read_text())["content_hash"]
            for m in store.glob("results/*/*.json")}


def test_local_cluster_of_worker_processes_matches_the_local_run(micro, tmp_path):
    """Workers are separate processes (dask gives them one BLAS thread; the local
    run has every core): every key and content hash must agree, which needs the
    BLAS threads pinned alike (engine/blas.py)."""
    from distributed import Client, LocalCluster

    study = tmp_path / "micro.toml"
    shutil.copy(HERE / "micro.toml", study)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            worker_pids = set(client.run(os.getpid).values())
        proc = subprocess.run([sys.executable, "-m", "peenflow.cli", "run", str(study),
                               "--scheduler", cluster.scheduler_address],
                              capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    local = _hashes(micro.parent / ".peenflow")
    remote = _hashes(tmp_path / ".peenflow")
    assert len(local) >= 15
    assert remote.keys() == local.keys()  # same keys: every upstream content hash agreed
    assert remote == local
    for f in (tmp_path / ".peenflow").glob("results/*/*.nc"):
        with xr.open_dataset(f) as ds:  # computed on a worker process, BLAS on one thread
            assert ds.attrs["peenflow_pid"] in worker_pids and ds.attrs["peenflow_blas_threads"] == 1
