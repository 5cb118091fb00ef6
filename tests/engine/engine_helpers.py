"""Helpers for the engine tests: a toy study in a temporary directory, the real CLI."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).parent


def write_toy(directory: Path, name: str = "toy", **toy) -> Path:
    cfg = {"n": 5, "factors": [1, 2, 3], "steps": 3}
    cfg.update(toy)
    directory.mkdir(parents=True, exist_ok=True)
    shutil.copy(HERE / "toy_pipeline.py", directory / "toy_pipeline.py")
    lines = ["[study]", f'name = "{name}"', 'pipeline = "toy_pipeline:build"', "", "[toy]"]
    for k, v in cfg.items():
        lines.append(f"{k} = {v!r}".replace("'", '"'))
    path = directory / "toy.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def peenflow(*args, env=None, check=True, timeout=120, **kw) -> subprocess.CompletedProcess:
    """Run the real ``peenflow`` command in a subprocess."""
    full_env = dict(os.environ)
    full_env.update(env or {})
    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", *map(str, args)], capture_output=True,
                          text=True, env=full_env, timeout=timeout, **kw)
    if check and proc.returncode != 0:
        raise AssertionError(f"peenflow {' '.join(map(str, args))} exited {proc.returncode}\n"
                             f"stdout:\n{proc.stdout}\nstderr:\n{proc.stderr}")
    return proc


def live_entries(directory: Path) -> list[Path]:
    """The entries of a store folder (``runs/``, ``leases/``, ...) that are not being removed (a released
    lease is renamed to a dot-name first); [] while the folder does not exist yet (it is made by the first
    run that registers or takes a lease)."""
    return [p for p in directory.iterdir() if not p.name.startswith(".")] if directory.exists() else []


def result_files(store: Path) -> dict[str, bytes]:
    """{file name: bytes} of every result file in the store at ``store``."""
    from peenflow.engine import DirectoryStore

    return {p.name: p.read_bytes() for _, _, p in DirectoryStore(store).all_results()}



def statuses(run_output: str) -> dict[str, str]:
    """{point: 'computed' | 'reused' | 'failed' | ...} parsed from `peenflow run` output."""
    out = {}
    for line in run_output.splitlines():
        parts = line.split()
        if len(parts) >= 3 and parts[0] in "+=!-#" and len(parts[0]) == 1:
            point = parts[4] if parts[1] == "computed" else parts[2]
            out[point] = parts[1]
    return out


def stop_with(proc: subprocess.Popen, sig: int, timeout: float = 30.0) -> tuple[str, str, float]:
    """Send ``sig`` to a running ``peenflow`` (started with ``start_new_session=True``) and wait for it to
    exit: (stdout, stderr, seconds from the signal to the exit); its process group is killed if it does not."""
    import signal
    import time

    t0 = time.time()
    try:
        os.kill(proc.pid, sig)
        out, err = proc.communicate(timeout=timeout)
        return out, err, time.time() - t0
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
