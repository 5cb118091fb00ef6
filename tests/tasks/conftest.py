"""The micro study, run once per test session through the real command, for every test that reads its results."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).parent


def cli(*args, check=True) -> subprocess.CompletedProcess:
    """``peenflow ARGS`` in a subprocess (text output); raises with its output when it fails and ``check``."""
    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", *map(str, args)], capture_output=True, text=True,
                          timeout=900)
    if check and proc.returncode != 0:
        raise AssertionError(proc.stdout + proc.stderr)
    return proc


@pytest.fixture(scope="session")
def micro(tmp_path_factory):
    """Path of a copy of ``micro.toml`` whose whole chain has run (store ``.peenflow/`` beside it)."""
    d = tmp_path_factory.mktemp("micro")
    shutil.copy(HERE / "micro.toml", d / "micro.toml")
    study = d / "micro.toml"
    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", "run", str(study), "--workers", "2"],
                          capture_output=True, text=True, timeout=900)
    if proc.returncode != 0:
        raise AssertionError(proc.stdout + proc.stderr)
    study.with_name("run.log").write_text(proc.stdout)
    return study
