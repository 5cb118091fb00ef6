"""Per-key leases: one computation of a key at a time, across processes and hosts.

A lease is a directory ``leases/<key>/`` created with ``mkdir``, which is
atomic on local and network filesystems (NFS included), holding
``owner.json`` (host, pid, start time, point).  The holder touches
``owner.json`` every few seconds (the heartbeat).

A lease whose holder is on *this* host and whose pid no longer exists is
broken automatically (the process was killed).  A lease from another host is
never broken automatically, however old its heartbeat -- the other machine
may just be slow to write to the shared disk; ``peenflow unlock`` removes it
once the user knows that run is dead.
"""

from __future__ import annotations

import os
import shutil
import socket
import threading
import time
import uuid
from dataclasses import dataclass
from pathlib import Path

from .atomic import read_json, write_json_atomic

HEARTBEAT_S = 5.0
STALE_AFTER_S = 60.0
#: an owner writes owner.json right after mkdir; a lease still without one after
#: this long belongs to a run killed in between
OWNERLESS_GRACE_S = 10.0


@dataclass(frozen=True)
class LeaseInfo:
    key: str
    host: str
    pid: int
    started: float
    heartbeat_age_s: float
    point: str

    @property
    def holder_alive(self) -> bool | None:
        """True/False when decidable from this host, None for another host."""
        if self.host != socket.gethostname():
            return None
        return _pid_alive(self.pid)

    def describe(self) -> str:
        return (f"held by {self.host} pid {self.pid} for {self.point}, "
                f"last heartbeat {self.heartbeat_age_s:.0f} s ago")


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


class Lease:
    """A held lease; release it with :meth:`release` (or use as context manager)."""

    def __init__(self, directory: Path):
        self.directory = directory
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._beat, daemon=True)
        self._thread.start()

    def _beat(self) -> None:
        owner = self.directory / "owner.json"
        while not self._stop.wait(HEARTBEAT_S):
            try:
                os.utime(owner)
            except OSError:
                return

    def release(self) -> None:
        self._stop.set()
        _remove_dir(self.directory)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.release()


def _remove_dir(directory: Path) -> None:
    # Rename first so a concurrent acquirer never sees a half-deleted lease.
    graveyard = directory.with_name(f".{directory.name}.released.{uuid.uuid4().hex[:8]}")
    try:
        os.rename(directory, graveyard)
    except OSError:
        return
    shutil.rmtree(graveyard, ignore_errors=True)


class LeaseTable:
    """The leases of one store."""

    def __init__(self, root: Path):
        self.root = root

    def path(self, key: str) -> Path:
        return self.root / key

    def try_acquire(self, key: str, point: str) -> Lease | None:
        directory = self.path(key)
        self.root.mkdir(parents=True, exist_ok=True)
        try:
            os.mkdir(directory)
        except FileExistsError:
            return None
        write_json_atomic(directory / "owner.json", {
            "host": socket.gethostname(), "pid": os.getpid(),
            "started": time.time(), "point": point,
        })
        return Lease(directory)

    def info(self, key: str) -> LeaseInfo | None:
        directory = self.path(key)
        owner_path = directory / "owner.json"
        owner = read_json(owner_path)
        if owner is None:
            try:
                age = time.time() - directory.stat().st_mtime
            except OSError:
                return None
            # Being created right now, or its creator was killed before writing owner.json.
            return LeaseInfo(key, "?", -1, time.time() - age, age, "?")
        try:
            age = time.time() - owner_path.stat().st_mtime
        except OSError:
            return None
        return LeaseInfo(key, owner["host"], int(owner["pid"]), float(owner["started"]), age,
                         owner.get("point", "?"))

    def break_if_dead(self, key: str) -> bool:
        """Remove a lease whose holder was on this host and has died, or that never got an owner."""
        info = self.info(key)
        if info is None:
            return False
        if info.holder_alive is False or (info.pid == -1 and info.heartbeat_age_s > OWNERLESS_GRACE_S):
            _remove_dir(self.path(key))
            return True
        return False

    def all(self) -> list[LeaseInfo]:
        if not self.root.exists():
            return []
        out = []
        for d in sorted(self.root.iterdir()):
            if d.is_dir() and not d.name.startswith("."):
                info = self.info(d.name)
                if info is not None:
                    out.append(info)
        return out

    def unlock(self, key: str) -> None:
        _remove_dir(self.path(key))
