"""The store: one directory holding results and the records of the runs that made them.

It is the only module that builds paths inside a store; every other module
asks it for a location or a record.  Two small interfaces, the way Hamilton
splits its cache into a result store and a metadata store:

* :class:`ResultStore` -- the results: ``write_result`` / ``check`` / ``open``,
  their manifests, and the failure record of a point that could not be
  computed;
* :class:`RunRecords` -- what runs leave while they work: slots (each
  point's last attempt), progress records, checkpoints, per-key leases, the
  registry of live runs and the locks of destructive verbs.

:class:`DirectoryStore` is both on one directory, plus what concerns the
whole directory (stray temporaries, report folders).

Layout under the store root::

    results/<task>/<key>.nc     the Dataset, with provenance attrs
    results/<task>/<key>.json   its manifest: size and SHA-256 of the file,
                                content hash, key parts; written *after* the
                                .nc is in place, so a result counts as done
                                only when both exist and agree
    failures/<task>/<key>.json  error and traceback of a failed point
    slots/<study>/<stage>/<id>.json
                                the last attempt of each point of a study
                                (what key it had, and why) -- the memory that
                                lets ``status`` say *why* something reruns
    checkpoints/<key>/          intermediate state of a long task
    progress/<key>.json         progress of a running task
    leases/<key>/               see lease.py
    runs/<host>.<pid>.<id>/     one per live run (a lease without a key): what ``clean`` must respect
    locks/clean/                held while ``clean`` deletes; a run starting meanwhile waits for it
    reports/<name>/             plots and report.html of a study

Inside ``checkpoints/<key>/`` and ``leases/<key>/`` the layout belongs to
checkpoint.py and lease.py, which get their directory from here.

A result whose file is missing, truncated or altered (size or SHA-256 differ
from the manifest), or whose manifest's content hash is not the hash of the
file's content (an altered manifest would otherwise silently change every
downstream key), is never trusted: the planner treats it as incomplete and
recomputes it.  The content is hashed once per file version and process.
"""

from __future__ import annotations

import hashlib
import os
import time
from dataclasses import dataclass
from pathlib import Path

import xarray as xr

from .atomic import TMP_SUFFIX, fsync_file, read_json, temporary_sibling, write_json_atomic
from .canonical import digest
from .checkpoint import Checkpoints
from .content import dataset_content_hash
from .lease import LeaseTable
from .netcdf_io import open_lazy, read_dataset, write_dataset
from .space import no_space, remove_partial


class StoreError(RuntimeError):
    pass


@dataclass(frozen=True)
class Manifest:
    task: str
    key: str
    content_hash: str
    file_sha256: str
    file_bytes: int
    parts: dict
    source_hash: str
    created: float

    def to_dict(self) -> dict:
        return dict(self.__dict__)


def file_sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def slot_id(label: str) -> str:
    return digest(label or "-", 16)


#: the lock ``clean`` holds while it deletes (``locks/clean/``)
CLEAN_LOCK = "clean"
#: the store's folder beside a study file, when neither ``--store`` nor ``$PEENFLOW_STORE`` names one
DEFAULT_DIRNAME = ".peenflow"


def default_root(study_path: str | os.PathLike) -> Path:
    """The store of a study file by default: ``.peenflow/`` beside it."""
    return Path(study_path).resolve().parent / DEFAULT_DIRNAME


def _files(base: Path, pattern: str):
    return sorted(base.glob(pattern)) if base.exists() else []


class ResultStore:
    """The results of a store: each a netCDF file with its manifest, or the failure record of a point."""

    def __init__(self, root: Path):
        self.root = root
        self._verified: dict[tuple, bool] = {}

    def result_path(self, task: str, key: str) -> Path:
        return self.root / "results" / task / f"{key}.nc"

    def manifest_path(self, task: str, key: str) -> Path:
        return self.root / "results" / task / f"{key}.json"

    def failure_path(self, task: str, key: str) -> Path:
        return self.root / "failures" / task / f"{key}.json"

    def manifest(self, task: str, key: str) -> Manifest | None:
        data = read_json(self.manifest_path(task, key))
        if not isinstance(data, dict):
            return None
        try:
            m = Manifest(**data)
        except TypeError:
            return None
        if not isinstance(m.file_bytes, int) or not isinstance(m.content_hash, str):
            return None
        return m

    def check(self, task: str, key: str) -> tuple[Manifest | None, str]:
        """(manifest, "") for a valid result; (None, problem) otherwise."""
        path = self.result_path(task, key)
        m = self.manifest(task, key)
        exists = path.exists()
        if m is None and not exists:
            return None, "missing"
        if m is None:
            return None, "result file has no manifest (writer killed before finishing)"
        if not exists:
            return None, "result file missing (manifest present)"
        st = path.stat()
        if st.st_size != m.file_bytes:
            return None, f"result file is {st.st_size} bytes, expected {m.file_bytes} (truncated?)"
        stamp = (str(path), st.st_mtime_ns, st.st_size, m.file_sha256, m.content_hash)
        if stamp not in self._verified:
            self._verified[stamp] = self._verify(path, m)
        problem = self._verified[stamp]
        if problem:
            return None, problem
        return m, ""

    @staticmethod
    def _verify(path: Path, m: Manifest) -> str:
        """"" when the file matches its manifest (SHA-256 and content hash), else the problem."""
        if file_sha256(path) != m.file_sha256:
            return "result file checksum does not match its manifest (corrupted)"
        try:
            content = dataset_content_hash(read_dataset(path))
        except (OSError, ValueError, RuntimeError, KeyError) as exc:
            return f"result file cannot be read ({type(exc).__name__}: {exc})"
        if content != m.content_hash:
            return "manifest content hash does not match the file's content (manifest altered)"
        return ""

    def stored_at(self, key: str, task: str | None = None) -> float | None:
        """When the valid result of ``key`` (of ``task``; of any task when None) was completed: its
        manifest's modification time; None without a valid result."""
        tasks = [task] if task is not None else [p.parent.name for p in
                                                 _files(self.root / "results", f"*/{key}.nc")]
        for t in tasks:
            if self.check(t, key)[0] is not None:
                try:
                    return self.manifest_path(t, key).stat().st_mtime
                except OSError:  # removed meanwhile
                    return None
        return None

    def write_result(self, task: str, key: str, ds: xr.Dataset, parts: dict, source_hash: str,
                     replace: bool = False) -> Manifest:
        """Write ``ds`` atomically; return its manifest.

        A valid result already stored under ``key`` is kept as it is (another
        run computed the same inputs first).  With ``replace`` (a forced
        rerun) it is replaced only if the new content differs, and the old
        file is kept beside it as ``<key>.superseded-<time>.nc`` -- nothing
        computed is ever silently overwritten.
        """
        final = self.result_path(task, key)
        final.parent.mkdir(parents=True, exist_ok=True)
        tmp = temporary_sibling(final)
        try:
            write_dataset(ds, tmp)
            fsync_file(tmp)
        except (TypeError, ValueError) as exc:
            tmp.unlink(missing_ok=True)
            raise StoreError(f"task {task!r} returned a Dataset that cannot be stored as netCDF: {exc}") from exc
        except (OSError, RuntimeError) as exc:  # netCDF says "HDF error" for a full disk
            remove_partial(tmp)
            raise no_space(exc, final.parent, ds.nbytes, "this point's result") or exc
        # Hash what was written, as it reads back: later readers see exactly this.
        content = dataset_content_hash(read_dataset(tmp))
        sha = file_sha256(tmp)
        size = tmp.stat().st_size
        existing, _ = self.check(task, key)
        if existing is not None and (not replace or existing.content_hash == content):
            # Same inputs computed already (by another run, or identically now): keep the file.
            tmp.unlink(missing_ok=True)
            return existing
        if existing is not None:
            stamp = time.strftime("%Y%m%dT%H%M%S", time.gmtime())
            os.replace(final, final.with_name(f"{key}.superseded-{stamp}.nc"))
        os.replace(tmp, final)
        manifest = Manifest(task, key, content, sha, size, parts, source_hash, time.time())
        try:
            write_json_atomic(self.manifest_path(task, key), manifest.to_dict())
        except OSError as exc:  # the file without its manifest is never trusted: the next run recomputes it
            raise no_space(exc, final.parent, 2e3, "this point's manifest") or exc
        return manifest

    def open(self, task: str, key: str) -> xr.Dataset:
        """The stored Dataset, loaded into memory (the file is closed again)."""
        return read_dataset(self.result_path(task, key))

    def open_lazy(self, task: str, key: str) -> xr.Dataset:
        """The stored Dataset on dask arrays (read when computed)."""
        return open_lazy(self.result_path(task, key))

    def discard(self, task: str, key: str) -> None:
        """Remove an invalid result (never called on a valid one)."""
        self.manifest_path(task, key).unlink(missing_ok=True)
        self.result_path(task, key).unlink(missing_ok=True)

    def all_results(self):
        """(task, key, path) of every result file (valid or not; a superseded one's key ends in
        ``.superseded-<time>``)."""
        for p in _files(self.root / "results", "*/*.nc"):
            yield p.parent.name, p.stem, p

    # -- failures ---------------------------------------------------------------
    def write_failure(self, task: str, key: str, record: dict) -> None:
        write_json_atomic(self.failure_path(task, key), record)

    def failure(self, task: str, key: str) -> dict | None:
        rec = read_json(self.failure_path(task, key))
        return rec if isinstance(rec, dict) else None

    def clear_failure(self, task: str, key: str) -> None:
        self.failure_path(task, key).unlink(missing_ok=True)

    def all_failures(self):
        """(task, key) of every failure record."""
        for p in _files(self.root / "failures", "*/*.json"):
            yield p.parent.name, p.stem


class RunRecords:
    """What runs leave in a store while they work: slots, progress, checkpoints, leases, live runs, locks."""

    def __init__(self, root: Path):
        self.root = root
        #: one lease per key being computed (lease.py)
        self.leases = LeaseTable(root / "leases")
        #: one entry per live ``execute`` (so ``clean`` leaves alone what a running run writes)
        self.runs = LeaseTable(root / "runs")
        #: store-wide locks of destructive verbs (``clean``)
        self.locks = LeaseTable(root / "locks")

    def slot_path(self, study: str, stage: str, label: str) -> Path:
        return self.root / "slots" / study / stage / f"{slot_id(label)}.json"

    def checkpoint_dir(self, key: str) -> Path:
        return self.root / "checkpoints" / key

    def progress_path(self, key: str) -> Path:
        return self.root / "progress" / f"{key}.json"

    # -- slots ------------------------------------------------------------------
    def write_slot(self, study: str, stage: str, label: str, record: dict) -> None:
        write_json_atomic(self.slot_path(study, stage, label), record)

    def slot(self, study: str, stage: str, label: str) -> dict | None:
        rec = read_json(self.slot_path(study, stage, label))
        return rec if isinstance(rec, dict) and isinstance(rec.get("parts", {}), dict) else None

    def slots(self):
        """(path, record) of every slot record of every study in the store."""
        for p in _files(self.root / "slots", "*/*/*.json"):
            rec = read_json(p)
            if isinstance(rec, dict):
                yield p, rec

    # -- progress ---------------------------------------------------------------
    def write_progress(self, key: str, record: dict) -> None:
        write_json_atomic(self.progress_path(key), record)

    def progress(self, key: str) -> dict | None:
        """The progress record of ``key``, or None (also for a damaged one: progress is only shown)."""
        rec = read_json(self.progress_path(key))
        if not isinstance(rec, dict):
            return None
        number = lambda v: isinstance(v, (int, float)) and not isinstance(v, bool)  # noqa: E731
        if not number(rec.get("done")) or not (rec.get("total") is None or number(rec.get("total"))):
            return None
        return rec

    def clear_progress(self, key: str) -> None:
        self.progress_path(key).unlink(missing_ok=True)

    def progress_keys(self) -> list[str]:
        """The keys that have a progress record."""
        return [p.stem for p in _files(self.root / "progress", "*.json")]

    # -- checkpoints ------------------------------------------------------------
    def checkpoints(self, key: str) -> Checkpoints:
        """The checkpoint of ``key`` (whether one is saved or not)."""
        return Checkpoints(self.checkpoint_dir(key))

    def checkpoint_keys(self) -> list[str]:
        """The keys that have a checkpoint folder."""
        base = self.root / "checkpoints"
        return [d.name for d in sorted(base.iterdir())] if base.exists() else []


class DirectoryStore(ResultStore, RunRecords):
    """Embedded, server-less store on a (possibly shared) directory: its results and its run records."""

    def __init__(self, root: str | os.PathLike):
        resolved = Path(root).resolve()
        ResultStore.__init__(self, resolved)
        RunRecords.__init__(self, resolved)

    def create(self) -> None:
        """Make the store's directory (a run does before it registers)."""
        self.root.mkdir(parents=True, exist_ok=True)

    def report_dir(self, name: str) -> Path:
        """The folder of the reports called ``name`` (one per study file)."""
        return self.root / "reports" / name

    def temporary_files(self):
        """Every temporary file a writer left (atomic.py names them), in the whole store."""
        if not self.root.exists():
            return []
        return sorted(p for p in self.root.rglob(f".*{TMP_SUFFIX}"))
