"""Checkpoints: the intermediate state of a long task, kept through a kill.

A checkpoint belongs to a result *key*: change a parameter and the old
checkpoint no longer applies.  It is written atomically (temporary name,
then rename), so a kill during a save leaves the previous checkpoint intact.
It is removed once the task's result is stored.

A checkpoint also records how far the task had got (its last progress
report: done, total, unit, e.g. 12 of 24 shots) in its attributes, so
``peenflow status`` can say where the next run resumes without the dead
run's own count, which may be past the checkpoint.

One rule (:func:`judge`) says what a key's checkpoint is worth, for the
run (which resumes from it, or tidies it away), ``status`` (which says where
the next run resumes) and ``clean`` (which removes leftovers):

* *absent*: no checkpoint saved (no folder, or a folder without
  ``checkpoint.nc``: a save killed before its rename);
* *leftover*: the key has a valid result completed after everything in the
  folder was written (or the folder is empty): the run that made the result
  was killed before it removed its checkpoint.  A checkpoint *newer* than
  the result belongs to a killed forced rerun and is not a leftover;
* *unreadable*: it cannot be read whole (garbage, truncated by a full disk
  or a crash of the disk itself): the next run drops it and starts over;
* *resumable*: the next run resumes from it (at its position, if saved with one).
"""

from __future__ import annotations

import enum
import shutil
from dataclasses import dataclass
from pathlib import Path

import xarray as xr

from .atomic import fsync_file, temporary_sibling
from .netcdf_io import read_dataset, write_dataset
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

    def clear(self) -> None:
        shutil.rmtree(self.directory, ignore_errors=True)


class CheckpointState(enum.Enum):
    ABSENT = "absent"
    LEFTOVER = "leftover"
    UNREADABLE = "unreadable"
    RESUMABLE = "resumable"


@dataclass(frozen=True)
class CheckpointVerdict:
    state: CheckpointState
    #: RESUMABLE: how far the task had got (:func:`position_of`; None if saved without one)
    position: dict | None = None
    #: UNREADABLE: the read error
    why: str = ""


def judge(store, key: str, task: str | None = None) -> CheckpointVerdict:
    """What the checkpoint of ``key`` in ``store`` is worth (the module's rule); ``task``: the key's task if
    known (else a valid result of ``key`` under any task makes the checkpoint a leftover)."""
    checkpoints = store.checkpoints(key)
    try:
        files = list(checkpoints.directory.iterdir())
    except OSError:  # no folder (or removed meanwhile)
        return CheckpointVerdict(CheckpointState.ABSENT)
    stored_at = store.stored_at(key, task)
    if stored_at is not None and max(map(_mtime, files), default=float("-inf")) <= stored_at:
        return CheckpointVerdict(CheckpointState.LEFTOVER)
    if not checkpoints.exists():
        return CheckpointVerdict(CheckpointState.ABSENT)
    state = checkpoints.load()
    if state is None:
        return CheckpointVerdict(CheckpointState.UNREADABLE, why=checkpoints.unreadable) \
            if checkpoints.unreadable else CheckpointVerdict(CheckpointState.ABSENT)
    return CheckpointVerdict(CheckpointState.RESUMABLE, position_of(state.attrs))


def _mtime(path: Path) -> float:
    try:
        return path.stat().st_mtime
    except OSError:  # removed meanwhile: counts as old
        return 0.0
