"""Checkpoints: the intermediate state of a long task, kept through a kill.

A checkpoint belongs to a result *key*: change a parameter and the old
checkpoint no longer applies.  It is written atomically (temporary name,
then rename), so a kill during a save leaves the previous checkpoint intact.
It is removed once the task's result is stored.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import xarray as xr

from .atomic import fsync_file, temporary_sibling
from .netcdf_io import read_dataset, write_dataset
from .space import no_space, remove_partial

CHECKPOINT_FILE = "checkpoint.nc"


class Checkpoints:
    def __init__(self, directory: Path):
        self.directory = directory
        self.path = directory / CHECKPOINT_FILE
        self.unreadable = ""  # why the last load found the checkpoint unreadable ("" if it did not)

    def exists(self) -> bool:
        return self.path.exists()

    def save(self, state: xr.Dataset) -> None:
        self.directory.mkdir(parents=True, exist_ok=True)
        tmp = temporary_sibling(self.path)
        try:
            write_dataset(state, tmp)
            fsync_file(tmp)
        except (OSError, RuntimeError) as exc:  # netCDF says "HDF error", HDF5 "Permission denied" when full
            remove_partial(tmp)
            raise no_space(exc, self.directory, state.nbytes, "this point's checkpoint") or exc
        tmp.replace(self.path)

    def load(self) -> xr.Dataset | None:
        """The last checkpoint, or None: none saved, or one that cannot be read (garbage, truncated by a
        full disk or a crash of the disk itself), whose error is then in :attr:`unreadable`."""
        self.unreadable = ""
        if not self.path.exists():
            return None
        try:
            return read_dataset(self.path)
        except (OSError, ValueError, RuntimeError) as exc:
            self.unreadable = f"{type(exc).__name__}: {exc}"
            return None

    def clear(self) -> None:
        shutil.rmtree(self.directory, ignore_errors=True)
