"""A full disk, named as such.

A write into a full store fails in words that hide the cause: netCDF says
"NetCDF: HDF error", HDF5 may say "Permission denied" for its temporary file,
and only a later small write says "No space left on device".  The store's
writers (results, checkpoints) ask :func:`no_space` after a failed write,
once their partial file is removed: the failure was a full device when the
error says so (ENOSPC, EDQUOT) or when the device has less room than the
write needed, plus :data:`MARGIN_BYTES`.  They then raise :class:`NoSpaceLeft`,
whose message starts with the cause, says how much the write needs, and that
nothing finished was lost: every write goes to a temporary file first, so a
stored result or checkpoint is either the whole old one or the whole new one.
"""

from __future__ import annotations

import errno
import os
import shutil
from pathlib import Path

#: room a netCDF/HDF5 file takes beyond its data (metadata, chunk and B-tree allocation), with
#: margin: a write that failed while the device had less than this beyond its data failed for room
MARGIN_BYTES = 1 << 20

_FULL = {errno.ENOSPC, getattr(errno, "EDQUOT", errno.ENOSPC)}


class NoSpaceLeft(OSError):
    """The store's device is full (``errno`` ENOSPC); the message says what needed how much."""

    def __init__(self, message: str):
        super().__init__(errno.ENOSPC, message)

    def __str__(self) -> str:  # the message alone: the cause first, not "[Errno 28]"
        return self.strerror


def size_text(nbytes: float) -> str:
    """``320 kB``, ``1.5 MB``: a size for people (powers of 1000)."""
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if nbytes >= scale:
            return f"{nbytes / scale:.3g} {unit}"
    return f"{nbytes:.0f} B"


def free_bytes(directory: Path) -> int | None:
    """Bytes free to this user on ``directory``'s device (its nearest existing parent), or None."""
    path = Path(directory)
    while not path.exists() and path != path.parent:
        path = path.parent
    try:
        return shutil.disk_usage(path).free
    except OSError:
        return None


def no_space(exc: BaseException, directory: Path, needed_bytes: float | None, what: str) -> NoSpaceLeft | None:
    """:class:`NoSpaceLeft` for ``exc``, raised writing ``what`` (``needed_bytes``, None: unknown) into
    ``directory``, if a full device caused it; else None."""
    free = free_bytes(directory)
    said_full = isinstance(exc, OSError) and exc.errno in _FULL
    short = free is not None and needed_bytes is not None and free < needed_bytes + MARGIN_BYTES
    if not (said_full or short):
        return None
    room = f"{size_text(free)} free" if free is not None else "free space unknown"
    needs = f"{what} needs about {size_text(needed_bytes)}" if needed_bytes is not None else f"{what} could not be written"
    return NoSpaceLeft(
        f"no space left on the store's device ({directory}: {room}): {needs}; nothing finished was lost (stored "
        "results and checkpoints are whole, the partial file was removed). Free space there or run with "
        f"--store DIR on a larger disk, then run again")


def is_full(exc: BaseException) -> bool:
    """True for an error that says the device is full (ENOSPC, EDQUOT, or :class:`NoSpaceLeft`)."""
    return isinstance(exc, OSError) and exc.errno in _FULL


def remove_partial(path: Path) -> None:
    """Remove a temporary file a failed write left (its room is what the next write needs)."""
    try:
        os.unlink(path)
    except OSError:
        pass
