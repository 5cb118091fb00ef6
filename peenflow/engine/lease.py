"""Per-key leases: one computation of a key at a time, across processes and hosts.

A lease is a directory ``leases/<key>/`` created with ``mkdir``, which is
atomic on local and network filesystems (NFS included), holding
``owner.json`` (host, pid, the pid's process start time, start time, point,
a random token).  The holder touches ``owner.json`` every ``HEARTBEAT_S``
seconds (the heartbeat).

One rule (:meth:`LeaseTable.verdict`), used alike by ``run``, ``status``,
``clean`` and ``unlock``, decides whether a holder is alive:

* this host: dead when its pid no longer exists, when that pid now belongs
  to another process (its start time differs from the one recorded: pid
  reuse after a restart, common in containers), when the pid is this very
  process but the lease is not one this process holds, or when the
  heartbeat is older than ``LOCAL_DEAD_AFTER_S`` (a live process whose
  heartbeat stopped is not computing the key);
* another host: dead when the heartbeat is older than
  ``REMOTE_DEAD_AFTER_S`` (generous: a shared disk may show another
  machine's writes late); between ``STALE_AFTER_S`` and that, a waiting
  run reports the point as *blocked* instead of waiting;
* an owner record that is missing, not JSON, not a table, or lacks a
  numeric host/pid is *unreadable*: its lease is dead once older than
  ``OWNERLESS_GRACE_S`` (an owner writes the record right after ``mkdir``).

A dead lease is broken (with a message saying why) by the next run that
needs the key, by ``clean`` and by ``unlock --all``.  Releasing checks the
token first, so a holder whose lease was broken while it was stopped never
removes the lease another run took since.
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
#: another host's lease with a heartbeat older than this: a waiting run reports it blocked
STALE_AFTER_S = 60.0
#: a lease of this host whose holder is alive but silent this long (12 missed heartbeats) is dead
LOCAL_DEAD_AFTER_S = 60.0
#: a lease of another host with no heartbeat for this long is dead
REMOTE_DEAD_AFTER_S = 600.0
#: an owner writes owner.json right after mkdir; a lease still without a readable one after
#: this long belongs to a run killed in between (or was damaged)
OWNERLESS_GRACE_S = 10.0

# Leases this process holds (directory -> Lease): a lease naming our own pid that is not
# in here was left by an earlier process that had the same pid.
_HELD: dict[str, "Lease"] = {}
_HELD_LOCK = threading.Lock()


def process_start_time(pid: int) -> int | None:
    """Start time of process ``pid`` in clock ticks since boot (Linux ``/proc``), or None."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            text = f.read().decode("ascii", "replace")
        return int(text[text.rindex(")") + 2:].split()[19])
    except (OSError, ValueError, IndexError):
        return None


def _pid_alive(pid: int) -> bool:
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    except OverflowError:
        return False
    return True


@dataclass(frozen=True)
class LeaseInfo:
    """What a lease directory says.  ``problem`` is "" for a readable owner record."""

    key: str
    host: str
    pid: int
    started: float
    heartbeat_age_s: float
    point: str
    pid_start: int | None = None
    token: str = ""
    problem: str = ""

    def describe(self) -> str:
        if self.problem:
            return f"{self.problem}, {self.heartbeat_age_s:.0f} s old"
        return (f"held by {self.host} pid {self.pid} for {self.point}, "
                f"last heartbeat {self.heartbeat_age_s:.0f} s ago")


def verdict(info: LeaseInfo) -> tuple[bool | None, str]:
    """(alive, why): True = a live holder, False = dead (why says how we know), None = undecidable."""
    if info.problem:
        if info.heartbeat_age_s > OWNERLESS_GRACE_S:
            return False, f"{info.problem} for {info.heartbeat_age_s:.0f} s (limit {OWNERLESS_GRACE_S:.0f} s)"
        return True, "being created"
    if info.host == socket.gethostname():
        if not _pid_alive(info.pid):
            return False, f"its process {info.pid} on this host no longer exists"
        if info.pid == os.getpid():
            with _HELD_LOCK:
                ours = any(lease.token == info.token for lease in _HELD.values())
            if not ours:
                return False, f"it names this process ({info.pid}) but this process never took it (pid reused)"
        elif info.pid_start is not None:
            now_start = process_start_time(info.pid)
            if now_start is not None and now_start != info.pid_start:
                return False, f"pid {info.pid} now belongs to another process (started at a different time)"
        if info.heartbeat_age_s > LOCAL_DEAD_AFTER_S:
            return False, (f"no heartbeat for {info.heartbeat_age_s:.0f} s (limit {LOCAL_DEAD_AFTER_S:.0f} s; "
                           f"pid {info.pid} is alive but not computing it)")
        return True, "holder alive on this host"
    if info.heartbeat_age_s > REMOTE_DEAD_AFTER_S:
        return False, f"no heartbeat from {info.host} for {info.heartbeat_age_s:.0f} s (limit {REMOTE_DEAD_AFTER_S:.0f} s)"
    return None, f"held by another host ({info.host})"


def wait_text(info: LeaseInfo, alive: bool | None) -> str:
    """Who a run waiting for a lease waits for, and for how long at most (by :func:`verdict`'s rule)."""
    if info.problem:
        return (f"its lease has {info.problem} ({info.heartbeat_age_s:.0f} s old; an owner writes it right after "
                f"taking the lease): at most {OWNERLESS_GRACE_S:.0f} s, then this run takes the point over")
    holder = (f"pid {info.pid} on host {info.host} computes it (last heartbeat {info.heartbeat_age_s:.0f} s ago, "
              f"every {HEARTBEAT_S:.0f} s)")
    if alive is None:  # another host: judged by its heartbeat alone
        return (f"{holder}: as long as that run's heartbeat goes on; if it stops for {STALE_AFTER_S:.0f} s the point "
                "is reported blocked")
    return (f"{holder}: as long as that run's heartbeat goes on, and at most {LOCAL_DEAD_AFTER_S:.0f} s after it "
            "stops, then this run takes the point over")


class Lease:
    """A held lease; release it with :meth:`release` (or use as context manager)."""

    def __init__(self, directory: Path, token: str):
        self.directory = directory
        self.token = token
        self._stop = threading.Event()
        with _HELD_LOCK:
            _HELD[str(directory)] = self
        self._thread = threading.Thread(target=self._beat, daemon=True)
        self._thread.start()

    def _still_ours(self) -> bool:
        owner = read_json(self.directory / "owner.json")
        return isinstance(owner, dict) and owner.get("token") == self.token

    def _beat(self) -> None:
        owner = self.directory / "owner.json"
        while not self._stop.wait(HEARTBEAT_S):
            if not self._still_ours():
                return  # broken by someone else (we were stopped too long): do not touch theirs
            try:
                os.utime(owner)
            except OSError:
                continue  # a slow or briefly failing disk: try again at the next beat

    def release(self) -> None:
        self._stop.set()
        with _HELD_LOCK:
            _HELD.pop(str(self.directory), None)
        if self._still_ours():
            _remove_dir(self.directory)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.release()


def release_all_held() -> int:
    """Release every lease this process holds (a hard exit on a second Ctrl-C); their count."""
    with _HELD_LOCK:
        held = list(_HELD.values())
    for lease in held:
        lease.release()
    return len(held)


def _remove_dir(directory: Path) -> None:
    # Rename first so a concurrent acquirer never sees a half-deleted lease.
    graveyard = directory.with_name(f".{directory.name}.released.{uuid.uuid4().hex[:8]}")
    try:
        os.rename(directory, graveyard)
    except OSError:
        return
    shutil.rmtree(graveyard, ignore_errors=True)


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


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
        token = uuid.uuid4().hex
        write_json_atomic(directory / "owner.json", {
            "host": socket.gethostname(), "pid": os.getpid(), "pid_start": process_start_time(os.getpid()),
            "started": time.time(), "point": point, "token": token,
        })
        return Lease(directory, token)

    def info(self, key: str) -> LeaseInfo | None:
        """The lease of ``key`` (None if there is none); never raises on a damaged record."""
        directory = self.path(key)
        owner_path = directory / "owner.json"
        try:
            dir_mtime = directory.stat().st_mtime
        except OSError:
            return None
        owner = read_json(owner_path)
        try:
            age = time.time() - owner_path.stat().st_mtime
        except OSError:
            age = time.time() - dir_mtime
        problem = ""
        if owner is None:
            problem = "no owner record" if not owner_path.exists() else "unreadable owner record (not JSON)"
        elif not isinstance(owner, dict):
            problem = f"unreadable owner record (a JSON {type(owner).__name__}, expected a table)"
        elif not isinstance(owner.get("host"), str) or not _number(owner.get("pid")) \
                or not float(owner["pid"]).is_integer():
            problem = "unreadable owner record (no host or no whole-number pid)"
        if problem:
            return LeaseInfo(key, "?", -1, time.time() - age, age, "?", problem=problem)
        started = owner.get("started")
        pid_start = owner.get("pid_start")
        return LeaseInfo(key, owner["host"], int(owner["pid"]), float(started) if _number(started) else 0.0, age,
                         str(owner.get("point", "?")), int(pid_start) if _number(pid_start) else None,
                         str(owner.get("token", "")))

    def verdict(self, key: str) -> tuple[LeaseInfo | None, bool | None, str]:
        """(info, alive, why) of the lease of ``key``; info None when there is no lease."""
        info = self.info(key)
        if info is None:
            return None, None, "no lease"
        alive, why = verdict(info)
        return info, alive, why

    def break_if_dead(self, key: str) -> str:
        """Remove the lease of ``key`` if its holder is dead; the reason ("" if kept or absent)."""
        info, alive, why = self.verdict(key)
        if info is None or alive is not False:
            return ""
        _remove_dir(self.path(key))
        return f"broke a dead lease ({info.describe()}): {why}"

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

    def live_keys(self) -> set[str]:
        """Keys whose lease holder is alive or cannot be judged from here (another host)."""
        return {i.key for i in self.all() if verdict(i)[0] is not False}

    def unlock(self, key: str) -> None:
        _remove_dir(self.path(key))
