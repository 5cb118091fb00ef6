"""The Python API for analysis.

    >>> import peenflow
    >>> ds = peenflow.open_result("studies/quickstart.toml", "saturation")
    >>> ds.intensity_m.sel(angle_deg=90).plot()

Results are plain xarray Datasets; the store can also be read with
``xr.open_dataset`` directly (``peenflow show`` prints the file paths).
"""

from __future__ import annotations

import os
from pathlib import Path

import xarray as xr

from tasks.pipeline import build_graph

from .engine import DirectoryStore, Graph, load_graph, stage_result
from .engine.store import default_root

STORE_ENV = "PEENFLOW_STORE"


def default_store_path(study_path: str | os.PathLike) -> Path:
    """``$PEENFLOW_STORE`` if set, else ``.peenflow/`` beside the study file."""
    env = os.environ.get(STORE_ENV)
    if env:
        return Path(env)
    return default_root(study_path)


def load_study_graph(study_path: str | os.PathLike) -> Graph:
    """The study's graph: its ``pipeline =`` plug-in if it names one, else the methodology's."""
    return load_graph(Path(study_path), build_graph)


def open_store(study_path, store: str | os.PathLike | None = None) -> DirectoryStore:
    return DirectoryStore(store if store is not None else default_store_path(study_path))


def open_result(study_path: str | os.PathLike, stage: str, store: str | os.PathLike | None = None,
                allow_partial: bool = False, lazy: bool = True) -> xr.Dataset:
    """A stage's results as one Dataset (a swept stage combined along its sweep dims).

    Lazy by default: the values are dask arrays, read from the files when
    computed (``.load()`` reads them all).  Provenance attributes are kept
    (``peenflow_*``; a combined stage lists each point's in ``peenflow_points``).
    """
    graph = load_study_graph(study_path)
    return stage_result(graph, open_store(study_path, store), stage, allow_partial=allow_partial, lazy=lazy)
