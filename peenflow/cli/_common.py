"""Shared by the verbs: loading a study and its store, with clean errors."""

from __future__ import annotations

from pathlib import Path

from ..api import default_store_path, load_study_graph
from ..engine import DirectoryStore, Graph


class UserError(Exception):
    """A problem the user can fix (bad study, unknown stage): printed, no traceback."""


def add_study(p) -> None:
    p.add_argument("study", help="study file (TOML)")
    p.add_argument("--store", default=None,
                   help="results store directory (default: $PEENFLOW_STORE or .peenflow/ beside the study)")


def load(args) -> tuple[Graph, DirectoryStore]:
    path = Path(args.study)
    try:
        graph = load_study_graph(path)
    except ValueError as exc:  # StudyError, StudyFileError: messages written for users
        raise UserError(str(exc)) from None
    store = DirectoryStore(args.store if args.store else default_store_path(path))
    if store.root.exists() and not store.root.is_dir():
        raise UserError(f"the store path {store.root} is a file, not a directory; pass --store DIR "
                        "(or set $PEENFLOW_STORE) to a directory")
    return graph, store


def stage_nodes(graph: Graph, stage: str):
    try:
        return graph.stage_nodes(stage)
    except KeyError:
        raise UserError(f"no stage {stage!r} in study {graph.name!r}; stages: {', '.join(graph.stages)}") from None
