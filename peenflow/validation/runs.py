"""The measured validation runs, as compact summaries shipped with the package.

Two summaries, one JSON file each under ``data/``, ``{"about": ..., "runs": {key: figures}}`` with one
run per line (a new or changed run is a one-line diff):

* ``single_impact``: every single-impact run (:mod:`.single_impact`; keys there): its scalar figures
  and its sigma_xx(z) column profile, and for the 6.25 um runs (the references and the readings'
  resolution limits, :mod:`.readings`) its surface line. The sigma_xx(x, z) maps and the other runs'
  surface lines stay in the full records the driver keeps beside the study-level stores
  (``benchmarks/single_impact.py``; git-ignored).
* ``study_level``: every study-level reference level (:mod:`.study_level`): its intensities, the
  sigma_xx(z) figures at each rung, the target's per-sequence profiles, N_f and N_c, CPU s. The
  results themselves are in the level studies' stores (``benchmarks/study_reference.py``; git-ignored).

What a summary keeps, it keeps as measured: every figure a test asserts or a table prints is
recomputed from it exactly as from the full records. The
benchmark drivers write these files (:func:`update`, :func:`write`); tests and tables read them
(:func:`load`).
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
from pathlib import Path

DATA = Path(__file__).resolve().parent / "data"

ABOUT = {
    "single_impact": "Single-impact runs of peenflow.validation.single_impact (key: CASE/ELEMENT/H_UM[/...]): "
                     "figures as peenflow.validation.readings.metrics reads them, the column profile, and the "
                     "surface line of the 6.25 um runs; made by `python benchmarks/single_impact.py run ...` "
                     "(benchmarks/README.md).",
    "study_level": "Study-level reference levels of peenflow.validation.study_level (key: POINT/LEVEL or "
                   "POINT/dent/LEVEL): made by `python benchmarks/study_reference.py run|dent POINT LEVEL ...` "
                   "(benchmarks/README.md).",
}
#: the fields a single-impact run's summary leaves to its full record
FULL_ONLY = ("map_x0_mm", "map_x1_mm", "map_z_mm", "map_mpa", "command")


def path(name: str) -> Path:
    """The summary file of ``name`` (``"single_impact"`` or ``"study_level"``)."""
    if name not in ABOUT:
        raise ValueError(f"no validation summary {name!r}; there are {sorted(ABOUT)}")
    return DATA / f"{name}.json"


def load(name: str) -> dict:
    """``{key: run}`` of the summary ``name``."""
    return json.loads(path(name).read_text())["runs"]


def summarised(name: str, key: str, run: dict) -> dict:
    """``run`` as the summary ``name`` keeps it: a single-impact run without :data:`FULL_ONLY`, and its
    surface line only at 6.25 um; a study level as it is. What it keeps, it keeps as measured."""
    if name != "single_impact":
        return run
    drop = FULL_ONLY if key.endswith("/6.25") else FULL_ONLY + ("surface_x_mm", "surface_uz_um")
    return {k: v for k, v in run.items() if k not in drop}


def write(name: str, runs: dict) -> None:
    """Replace the summary ``name`` by ``runs`` (each summarised), atomically."""
    lines = [f"{json.dumps(k)}: {json.dumps(summarised(name, k, v), sort_keys=True, separators=(',', ':'))}"
             for k, v in sorted(runs.items())]
    text = ('{\n"about": ' + json.dumps(ABOUT[name]) + ',\n"runs": {\n' + ",\n".join(lines) + "\n}\n}\n")
    _replace(path(name), text)


def update(name: str, key: str, run: dict) -> None:
    """Add or replace one run of the summary ``name``; runs made in parallel write one at a time, each
    re-reading the file under the lock."""
    with locked(path(name)):
        runs = load(name) if path(name).exists() else {}
        runs[key] = run
        write(name, runs)


def records_path(root: Path, name: str) -> Path:
    """The full records of ``name`` the drivers keep under the repository ``root`` (git-ignored)."""
    return Path(root) / "benchmarks" / "reference" / "store" / f"{name}.json"


def load_records(root: Path, name: str) -> dict:
    """``{key: run}`` of the full records of ``name`` ({} when there are none)."""
    p = records_path(root, name)
    return json.loads(p.read_text()) if p.exists() else {}


def record(root: Path, name: str, key: str, run: dict) -> None:
    """Store one run: in full in the records of ``name`` and summarised in its summary (:func:`update`)."""
    p = records_path(root, name)
    p.parent.mkdir(parents=True, exist_ok=True)
    with locked(p):
        full = load_records(root, name)  # re-read: runs made in parallel may have written meanwhile
        full[key] = run
        write_records(root, name, full)
    update(name, key, run)


def write_records(root: Path, name: str, full: dict) -> None:
    """Replace the full records of ``name`` by ``full``, atomically (hold :func:`locked` around a
    read-modify-write)."""
    _replace(records_path(root, name), json.dumps(full, indent=1, sort_keys=True))


def _replace(target: Path, text: str) -> None:
    tmp = target.with_suffix(".tmp")
    with open(tmp, "w") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    tmp.replace(target)


@contextlib.contextmanager
def locked(file: Path):
    """An exclusive lock beside ``file`` (``FILE.lock``) held for a read-modify-write of it."""
    with open(Path(file).with_suffix(".lock"), "w") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        yield
