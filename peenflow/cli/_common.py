"""Shared by the verbs: loading a study and its store, with clean errors."""

from __future__ import annotations

from pathlib import Path

from ..api import default_store_path, load_study_graph
from ..engine import DirectoryStore, Graph
from ..units import reading_unit


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


def _scale(graph, dim: str) -> tuple[float, str]:
    factor, unit = reading_unit(graph.coord_attrs.get(dim, {}).get("units", "1"))
    return factor, f" {unit}" if unit else ""


def _values(graph, dim: str) -> list:
    return sorted({n.coords[dim] for n in graph.nodes if dim in n.coords})


def dim_value(graph, dim: str, value) -> str:
    """One value of a process dimension as the study gives it: a name, the shop notation, or a number with
    its unit (mm, MPa)."""
    a = graph.coord_attrs.get(dim, {})
    if a.get("flag_meanings"):
        return a["flag_meanings"].split()[int(value)]
    if a.get("shop_notation"):
        return a["shop_notation"].split()[_values(graph, dim).index(value)]
    scale, unit = _scale(graph, dim)
    return f"{value * scale:g}{unit}"


def dim_values(graph, dim: str) -> str:
    """All values of a process dimension: names, shop notations, or numbers with their unit once at the end."""
    a = graph.coord_attrs.get(dim, {})
    if a.get("flag_meanings") or a.get("shop_notation"):
        return ", ".join(dim_value(graph, dim, v) for v in _values(graph, dim))
    scale, unit = _scale(graph, dim)
    return ", ".join(f"{v * scale:g}" for v in _values(graph, dim)) + unit
