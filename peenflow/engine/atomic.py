"""Atomic file replacement that is safe across processes and hosts.

Every file the store writes goes to a temporary name that is unique across
hosts (hostname, pid, random suffix) in the destination directory, is
flushed to disk, then renamed into place: a reader sees the old file or the
new one, never half of one, and a killed writer leaves only a temporary
file that ``peenflow clean`` removes.
"""

from __future__ import annotations

import json
import os
import socket
import uuid
from pathlib import Path

TMP_SUFFIX = ".tmp"


def temporary_sibling(path: Path) -> Path:
    tag = f"{socket.gethostname()}.{os.getpid()}.{uuid.uuid4().hex[:12]}"
    return path.with_name(f".{path.name}.{tag}{TMP_SUFFIX}")


def fsync_file(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def write_text_atomic(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = temporary_sibling(path)
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
    except OSError:  # a full disk: leave no partial file behind
        tmp.unlink(missing_ok=True)
        raise
    os.replace(tmp, path)


def write_json_atomic(path: Path, data) -> None:
    write_text_atomic(path, json.dumps(data, sort_keys=True, indent=1, default=str))


def read_json(path: Path):
    """Parsed JSON, or None if the file is missing or unreadable."""
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
