"""From a study file to a graph.

A study file is TOML.  Its ``[study]`` table names the study and,
optionally, the *pipeline* that turns the file into a graph
(``pipeline = "module:function"``; the function takes the study file's path
and returns a :class:`~peenflow.engine.graph.Graph`, validating the file its
own way first).  The caller supplies the default pipeline, so the engine
itself knows nothing of what the studies are about.  The study file's
directory is importable, so a pipeline module may sit beside the study.
"""

from __future__ import annotations

import importlib
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


def load_graph(path: str | Path, default_pipeline: str) -> Graph:
    path = Path(path).resolve()
    data = read_study_table(path)
    entry = data.get("study", {}).get("pipeline", default_pipeline)
    if str(path.parent) not in sys.path:
        sys.path.insert(0, str(path.parent))
    builder = resolve_pipeline(entry)
    graph = builder(path)
    if not isinstance(graph, Graph):
        raise StudyFileError(f"pipeline {entry} returned {type(graph).__name__}, expected a Graph")
    return graph
