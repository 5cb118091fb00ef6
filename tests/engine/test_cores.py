"""Compute threads per point: all cores for a lone point, a share for a sweep, never more than the cores."""

from __future__ import annotations

import pytest

from peenflow.engine import executor
from peenflow.engine.cores import CoreBudget, wanted_threads
from peenflow.engine.plugin import load_graph
from peenflow.engine.store import DirectoryStore

from engine_helpers import write_toy


def test_wanted_threads_share_the_cores_between_a_stage_points():
    stages = ["sweep"] * 6 + ["lone"] + ["pair"] * 2
    assert wanted_threads(stages, cores=8, workers=4) == {"sweep": 2, "lone": 8, "pair": 4}
    assert wanted_threads(stages, cores=2, workers=8) == {"sweep": 1, "lone": 2, "pair": 1}


def test_budget_never_hands_out_more_than_it_holds():
    budget = CoreBudget(4)
    a = budget.acquire(3)
    b = budget.acquire(3)
    assert (a, b) == (3, 1)
    assert budget.in_use == 4
    budget.release(b)
    budget.release(a)
    assert budget.in_use == 0


@pytest.mark.parametrize("cores,workers", [(2, 2), (4, 3)])
def test_lone_point_gets_every_core_and_a_sweep_never_oversubscribes(tmp_path, monkeypatch, cores, workers):
    study = write_toy(tmp_path, name="probe", members=5, hold_s=0.3)
    study.write_text(study.read_text().replace("toy_pipeline:build", "toy_pipeline:build_probe"))
    monkeypatch.setattr(executor, "available_cores", lambda: cores)
    graph = load_graph(study, "toy_pipeline:build_probe")
    store = DirectoryStore(tmp_path / "store")
    import toy_pipeline  # the tasks' module (load_graph put its folder on sys.path)

    toy_pipeline._in_use["peak"] = 0
    outcomes = executor.execute(graph, store, graph.nodes, workers=workers)
    assert all(o.status == "computed" for o in outcomes)

    results = {n.node_id: store.open(n.task.name, o.key) for n, o in zip(graph.nodes, outcomes)}
    lone = [r for nid, r in results.items() if nid.startswith("lone")]
    wide = [r for nid, r in results.items() if nid.startswith("wide")]
    assert lone[0].threads.item() == cores
    # (.item(): a point file holds its sweep value as a length-1 dimension)
    assert {r.threads.item() for r in wide} <= set(range(1, cores // workers + 1))
    assert toy_pipeline._in_use["peak"] <= cores


def test_a_lone_point_beside_a_sweep_takes_only_the_free_cores(tmp_path, monkeypatch):
    """The lone point (wants both cores) runs while sweep points hold threads:
    without the budget 3 threads would run on 2 cores."""
    study = write_toy(tmp_path, name="probe2", members=3, hold_s=0.3, lone_after_wide=0)
    study.write_text(study.read_text().replace("toy_pipeline:build", "toy_pipeline:build_probe"))
    monkeypatch.setattr(executor, "available_cores", lambda: 2)
    graph = load_graph(study, "toy_pipeline:build_probe")
    store = DirectoryStore(tmp_path / "store")
    import toy_pipeline

    toy_pipeline._in_use["peak"] = 0
    outcomes = executor.execute(graph, store, graph.nodes, workers=2)
    assert all(o.status == "computed" for o in outcomes)
    assert toy_pipeline._in_use["peak"] == 2
