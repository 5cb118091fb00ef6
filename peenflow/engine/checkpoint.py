"""Checkpoints: the intermediate state of a long task, kept through a kill.

A checkpoint belongs to a result *key*: change a parameter and the old
checkpoint no longer applies.  It is written atomically (temporary name,
then rename), so a kill during a save leaves the previous checkpoint intact.
It is removed once the task's result is stored.
"""

from __future__ import annotations

import shutil
import warnings
from pathlib import Path

import xarray as xr

from .atomic import fsync_file, temporary_sibling
from .netcdf_io import read_dataset, write_dataset

CHECKPOINT_FILE = "checkpoint.nc"


class Checkpoints:
    def __init__(self, directory: Path):
        self.directory = directory
        self.path = directory / CHECKPOINT_FILE

    def exists(self) -> bool:
        return self.path.exists()

    def save(self, state: xr.Dataset) -> None:
        self.directory.mkdir(parents=True, exist_ok=True)
        tmp = temporary_sibling(self.path)
        write_dataset(state, tmp)
        fsync_file(tmp)
        tmp.replace(self.path)

    def load(self) -> xr.Dataset | None:
        """The last checkpoint, or None (an unreadable one is ignored, with a warning)."""
        if not self.path.exists():
            return None
        try:
            return read_dataset(self.path)
        except (OSError, ValueError, RuntimeError) as exc:  # pragma: no cover - defensive
            warnings.warn(f"ignoring unreadable checkpoint {self.path}: {exc}")
            return None

    def clear(self) -> None:
        shutil.rmtree(self.directory, ignore_errors=True)
