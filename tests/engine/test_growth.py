"""Growing sweep dimensions (engine/growth.py): a group gains points while its results ask for more.

The toy: draw[factor, rep] has the value factor * (rep + 1); a factor's group grows
until its values add up to ``target``; pooled[factor] sums the group.  With
target T a factor f needs the smallest n with f * n (n + 1) / 2 >= T, so the
expected counts follow from arithmetic, not from a run.
"""

import math

import pytest
from engine_helpers import HERE, peenflow, statuses

from peenflow.engine import DirectoryStore, Graph, load_graph, plan, task
from peenflow.engine.growth import Grow
from peenflow.engine.reasons import State


def _study(tmp_path, **toy):
    import shutil

    d = tmp_path / "g"
    d.mkdir(parents=True, exist_ok=True)
    shutil.copy(HERE / "toy_pipeline.py", d / "toy_pipeline.py")
    cfg = {"factors": [1, 2, 5], "target": 10.0, "max_reps": 8, "start": 1}
    cfg.update(toy)
    lines = ["[study]", 'name = "grow"', 'pipeline = "toy_pipeline:build_growing"', "", "[toy]"]
    lines += [f"{k} = {v!r}" for k, v in cfg.items()]
    path = d / "grow.toml"
    path.write_text("\n".join(lines) + "\n")
    return path, d / ".peenflow"


def needed(f, target, cap, start=1):
    n = max(start, next(n for n in range(1, 100) if f * n * (n + 1) / 2 >= target))
    return min(n, cap)


def _log_lines(path):
    return [ln.split()[:2] for ln in path.read_text().splitlines()] if path.exists() else []


def test_groups_grow_until_their_results_say_enough_and_consumers_see_only_the_final_group(tmp_path):
    study, store_dir = _study(tmp_path)
    log = tmp_path / "log.txt"
    out = peenflow("run", study, "--workers", "2", env={"TOY_LOG": str(log)}).stdout
    expect = {f: needed(f, 10.0, 8) for f in (1, 2, 5)}  # 1 -> 4, 2 -> 3, 5 -> 2
    assert expect == {1: 4, 2: 3, 5: 2}
    st = statuses(out)
    for f, n in expect.items():
        assert [st.get(f"draw[factor={f},rep={r}]") for r in range(n)] == ["computed"] * n
        assert f"draw[factor={f},rep={n}]" not in st  # not one point more than needed
    # each pooled point computed once, on the whole group (never on a partial one)
    pooled = [int(w[1]) for w in _log_lines(log) if w[0] == "pooled"]
    assert sorted(pooled) == sorted(expect.values())
    graph = load_graph(study, "unused:unused")
    store = DirectoryStore(store_dir)
    items = plan(graph, store)
    assert all(i.state is State.DONE for i in items), [(i.node.node_id, i.state) for i in items]
    assert sum(1 for i in items if i.node.stage == "draw") == sum(expect.values())
    for i in items:
        if i.node.stage == "pooled":
            ds = store.open("pooled", i.key)
            f = i.node.coords["factor"]
            n = expect[f]
            assert int(ds.reps.item()) == n and ds["sum"].item() == pytest.approx(f * n * (n + 1) / 2)
    states = {lab: st.state for lab, st in graph.growth["draw"].items()}
    assert set(states.values()) == {"done"}
    # a second run reuses every point and computes nothing
    again = statuses(peenflow("run", study).stdout)
    assert set(again.values()) == {"reused"} and len(again) == len(items)


def test_a_group_stops_at_the_last_value_it_was_given(tmp_path):
    study, store_dir = _study(tmp_path, factors=[1], target=1000.0, max_reps=3)
    peenflow("run", study)
    graph = load_graph(study, "unused:unused")
    items = plan(graph, DirectoryStore(store_dir))
    assert [i.node.node_id for i in items if i.node.stage == "draw"] == [f"draw[factor=1,rep={r}]" for r in range(3)]
    (st,) = graph.growth["draw"].values()
    assert st.state == "cap" and "all 3 values of rep used" in st.reason


def test_a_failed_point_holds_its_consumer_and_a_later_run_grows_on(tmp_path):
    study, store_dir = _study(tmp_path, factors=[1, 5])
    first = peenflow("run", study, env={"TOY_FAIL_DRAW": "1/1"}, check=False)
    assert first.returncode == 1
    st = statuses(first.stdout)
    assert st["draw[factor=1,rep=1]"] == "failed"
    assert "pooled[factor=1]" not in st  # never computed on the partial group
    assert st["pooled[factor=5]"] == "computed"  # the other group is not held back
    graph = load_graph(study, "unused:unused")
    items = {i.node.node_id: i for i in plan(graph, DirectoryStore(store_dir))}
    assert items["pooled[factor=1]"].state is State.BLOCKED  # waiting on the failed draw
    assert graph.growth["draw"]['{"factor":1}'].state == "waiting"
    second = statuses(peenflow("run", study).stdout)
    assert second["draw[factor=1,rep=1]"] == "computed"
    assert [second.get(f"draw[factor=1,rep={r}]") for r in (2, 3)] == ["computed", "computed"]
    assert second["pooled[factor=1]"] == "computed" and second["draw[factor=1,rep=0]"] == "reused"


def test_start_is_honoured_and_keys_do_not_depend_on_the_group_size(tmp_path):
    study, store_dir = _study(tmp_path, factors=[5], start=3)
    peenflow("run", study)
    graph = load_graph(study, "unused:unused")
    items = plan(graph, DirectoryStore(store_dir))
    draws = [i for i in items if i.node.stage == "draw"]
    assert len(draws) == 3  # 5 alone needed 2; the group starts with 3
    # the key of rep 0 is the same as in a study whose group stopped at 2
    other, other_store = _study(tmp_path / "b", factors=[5], start=1)
    peenflow("run", other)
    g2 = load_graph(other, "unused:unused")
    k2 = {i.node.node_id: i.key for i in plan(g2, DirectoryStore(other_store))}
    assert k2["draw[factor=5,rep=0]"] == next(i.key for i in draws if i.node.coords["rep"] == 0)
    assert "draw[factor=5,rep=2]" not in k2


def test_bad_grow_declarations_are_refused():
    @task()
    def t(*, a: int, b: int):  # pragma: no cover - never run
        raise AssertionError

    g = Graph("x")
    with pytest.raises(ValueError, match="not one of its dims"):
        g.sweep(t, dims={"a": [1], "b": [0, 1]}, grow=Grow("c", 1, lambda d, c: False))
    with pytest.raises(ValueError, match="grow.start = 3"):
        Graph("y").sweep(t, dims={"a": [1], "b": [0, 1]}, grow=Grow("b", 3, lambda d, c: False), stage="t2")
    assert math.isfinite(needed(1, 10, 8))

