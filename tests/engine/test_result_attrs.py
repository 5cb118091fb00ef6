"""graph.result_attrs (engine/graph.py): attributes a study writes on every result it computes,
outside every key and content hash."""

import pytest
from engine_helpers import HERE

from peenflow.engine import load_graph, plan
from peenflow.engine.reasons import State


def _toy_study(d, name):
    """The engine tests' toy pipeline as a study in ``d``."""
    import shutil

    d.mkdir()
    shutil.copy(HERE / "toy_pipeline.py", d / "toy_pipeline.py")
    study = d / "toy.toml"
    study.write_text(f'[study]\nname = "{name}"\npipeline = "toy_pipeline:build"\n\n[toy]\nn = 3\nfactors = [1, 2]\n'
                     "steps = 1\n")
    return study


def test_result_attrs_are_written_outside_keys_and_content(tmp_path):
    from peenflow.engine import DirectoryStore, Reporter, execute
    from peenflow.engine.content import dataset_content_hash as dataset_hash

    d = tmp_path / "a"
    study = _toy_study(d, "attrs")
    g1 = load_graph(study, "unused:unused")
    g1.result_attrs = {"peenflow_fidelity_note": "measured: 1 %"}
    store = DirectoryStore(d / ".peenflow")
    execute(g1, store, list(g1.nodes), reporter=Reporter(quiet=True))
    items = plan(g1, store)
    ds = store.open("total", next(i.key for i in items if i.node.stage == "total"))
    assert ds.attrs["peenflow_fidelity_note"] == "measured: 1 %"
    g2 = load_graph(study, "unused:unused")  # without the attrs: same keys, same content, all reused
    items2 = plan(g2, store)
    assert [i.key for i in items2] == [i.key for i in items] and all(i.state is State.DONE for i in items2)
    stripped = ds.copy()
    stripped.attrs.pop("peenflow_fidelity_note")
    assert dataset_hash(stripped) == dataset_hash(ds)
    g2.result_attrs = {"fidelity_note": "x"}
    with pytest.raises(ValueError, match="must start with 'peenflow_'"):
        execute(g2, store, list(g2.nodes), reporter=Reporter(quiet=True))


def test_stage_result_attrs_replace_the_graph_s_on_their_stage_only(tmp_path):
    """A stage computed at another fidelity says so on its own results; the other stages keep the
    graph's attrs, and keys do not change."""
    from peenflow.engine import DirectoryStore, Reporter, execute

    d = tmp_path / "b"
    study = _toy_study(d, "attrs2")
    g = load_graph(study, "unused:unused")
    g.result_attrs = {"peenflow_note": "graph", "peenflow_other": "kept"}
    g.stage_result_attrs = {"total": {"peenflow_note": "stage"}}
    store = DirectoryStore(d / ".peenflow")
    execute(g, store, list(g.nodes), reporter=Reporter(quiet=True))
    items = plan(g, store)
    plain = plan(load_graph(study, "unused:unused"), store)  # no attrs: same keys, all reused
    assert [i.key for i in plain] == [i.key for i in items] and all(i.state is State.DONE for i in plain)
    for i in items:
        attrs = store.open(i.node.task.name, i.key).attrs
        assert attrs["peenflow_note"] == ("stage" if i.node.stage == "total" else "graph"), i.node.stage
        assert attrs["peenflow_other"] == "kept"
    assert {i.node.stage for i in items} - {"total"}  # the toy has other stages
    g.stage_result_attrs = {"total": {"note": "x"}}
    with pytest.raises(ValueError, match="must start with 'peenflow_'"):
        execute(g, DirectoryStore(d / ".other"), list(g.nodes), reporter=Reporter(quiet=True))
