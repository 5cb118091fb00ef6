"""From a study file to a graph.

A study file is TOML.  Its ``[study]`` table names the study and,
optionally, the *pipeline* that turns the file into a graph
(``pipeline = "module:function"``; the function takes the study file's path
and returns a :class:`~peenflow.engine.graph.Graph`, validating the file its
own way first).  The caller supplies the default pipeline, so the engine
itself knows nothing of what the studies are about.  The study file's
directory is importable (after the installed packages, which it cannot
shadow), so a pipeline module may sit beside the study.
"""

from __future__ import annotations

import importlib
import importlib.machinery
import sys
from pathlib import Path

from .._toml import TomlFileError, load_toml
from .graph import Graph


class StudyFileError(ValueError):
    pass


def read_study_table(path: Path) -> dict:
    path = Path(path)
    if not path.exists():
        raise StudyFileError(f"study file {path} does not exist")
    try:
        return load_toml(path)
    except TomlFileError as exc:
        raise StudyFileError(str(exc)) from None
    except OSError as exc:
        raise StudyFileError(f"cannot read study file {path}: {exc.strerror or exc}") from None


def resolve_pipeline(entry: str):
    module, _, func = entry.partition(":")
    if not module or not func:
        raise StudyFileError(f"study.pipeline = {entry!r}: expected 'module:function'")
    try:
        return getattr(importlib.import_module(module), func)
    except (ImportError, AttributeError) as exc:
        raise StudyFileError(f"study.pipeline = {entry!r} cannot be imported: {exc}") from exc


class _StudyFolderFinder:
    """Finds top-level modules in a study's folder, consulted after every other
    finder: a module beside the study (say a ``tasks.py``) cannot shadow an
    installed package of the same name, editable installs included (their
    finder sits on ``sys.meta_path`` behind ``sys.path``, so a folder put on
    ``sys.path``, even at its end, would still win)."""

    def __init__(self, folder: Path):
        self.folder = str(folder)

    def find_spec(self, name, path=None, target=None):
        if path is not None or "." in name:
            return None
        return importlib.machinery.PathFinder.find_spec(name, [self.folder])


def _import_after_installed(folder: Path) -> None:
    if not any(isinstance(f, _StudyFolderFinder) and f.folder == str(folder) for f in sys.meta_path):
        sys.meta_path.append(_StudyFolderFinder(folder))


def load_graph(path: str | Path, default_pipeline) -> Graph:
    """The graph of the study file at ``path``, by its ``[study] pipeline = "module:function"`` or by
    ``default_pipeline`` (a function of the path, or such a string)."""
    path = Path(path).resolve()
    data = read_study_table(path)
    entry = data.get("study", {}).get("pipeline", default_pipeline)
    _import_after_installed(path.parent)
    builder = resolve_pipeline(entry) if isinstance(entry, str) else entry
    graph = builder(path)
    if not isinstance(graph, Graph):
        raise StudyFileError(f"pipeline {entry} returned {type(graph).__name__}, expected a Graph")
    return graph
