"""Reading what a study has computed so far, for the reports: a stage's results, or None."""

from __future__ import annotations

from peenflow.engine import ResultNotReady, stage_result


def stage_or_none(graph, store, stage: str):
    """The stage's stored results as one Dataset (points not yet done left out), or None when the
    study has no such stage or none of its points is done."""
    if stage not in graph.stages:
        return None
    try:
        return stage_result(graph, store, stage, allow_partial=True)
    except ResultNotReady:
        return None
