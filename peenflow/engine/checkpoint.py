"""Checkpoints: the intermediate state of a long task, kept through a kill.

A checkpoint belongs to a result *key*: change a parameter and the old
checkpoint no longer applies.  It is written atomically (temporary name,
then rename), so a kill during a save leaves the previous checkpoint intact.
It is removed once the task's result is stored.

A checkpoint also records how far the task had got (its last progress
report: done, total, unit, e.g. 12 of 24 shots) in its attributes, so
``peenflow status`` can say where the next run resumes without the dead
run's own count, which may be past the checkpoint.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import xarray as xr

from .atomic import fsync_file, temporary_sibling
from .netcdf_io import read_attrs, read_dataset, write_dataset
from .space import no_space, remove_partial

CHECKPOINT_FILE = "checkpoint.nc"
#: the attributes of a checkpoint that hold its position (a progress report's fields)
POSITION_ATTRS = {"done": "peenflow_checkpoint_done", "total": "peenflow_checkpoint_total",
                  "unit": "peenflow_checkpoint_unit"}


def position_of(attrs: dict) -> dict | None:
    """{"done", "total", "unit"} recorded in a checkpoint's ``attrs``, or None (saved without progress)."""
    if POSITION_ATTRS["done"] not in attrs:
        return None
    total = attrs.get(POSITION_ATTRS["total"])
    return {"done": float(attrs[POSITION_ATTRS["done"]]), "total": None if total is None else float(total),
            "unit": str(attrs.get(POSITION_ATTRS["unit"], ""))}


def describe_position(position: dict | None) -> str:
    """``after 12/24 shots``; "" without a position."""
    if not position:
        return ""
    total = "" if position.get("total") is None else f"/{position['total']:g}"
    return f"after {position['done']:g}{total} {position.get('unit') or ''}".rstrip()


class Checkpoints:
    def __init__(self, directory: Path):
        self.directory = directory
        self.path = directory / CHECKPOINT_FILE
        self.unreadable = ""  # why the last load found the checkpoint unreadable ("" if it did not)

    def exists(self) -> bool:
        return self.path.exists()

    def save(self, state: xr.Dataset, position: dict | None = None) -> None:
        """Replace the checkpoint by ``state``; ``position``: how far the task had got ({"done", "total",
        "unit"}, as its progress reports it)."""
        if position is not None:
            state = state.assign_attrs({POSITION_ATTRS[k]: position[k] for k in POSITION_ATTRS
                                        if position.get(k) is not None})
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

    def position(self) -> dict | None:
        """How far the task had got at the last checkpoint (:func:`position_of`), or None: none saved, one
        saved without a position, or one that cannot be read."""
        try:
            return position_of(read_attrs(self.path)) if self.path.exists() else None
        except (OSError, ValueError, RuntimeError):
            return None

    def clear(self) -> None:
        shutil.rmtree(self.directory, ignore_errors=True)
