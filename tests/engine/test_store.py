"""The store never trusts a damaged file, never loses a finished one."""

import pytest
import xarray as xr
from engine_helpers import statuses, peenflow, write_toy

from peenflow.engine import DirectoryStore, load_graph, plan
from peenflow.engine.reasons import State


def _item(study, stage):
    graph = load_graph(study, "unused:unused")
    store = DirectoryStore(study.parent / ".peenflow")
    return store, next(i for i in plan(graph, store) if i.node.stage == stage)


@pytest.mark.parametrize("damage", ["truncate", "flip"])
def test_corrupted_result_is_detected_and_recomputed(tmp_path, damage):
    study = write_toy(tmp_path / "s")
    peenflow("run", study)
    store, item = _item(study, "source")
    path = store.result_path("source", item.key)
    good = path.read_bytes()
    content = store.manifest("source", item.key).content_hash
    if damage == "truncate":
        path.write_bytes(good[: len(good) // 2])
    else:  # same size, one byte changed in the middle
        mid = len(good) // 2
        path.write_bytes(good[:mid] + bytes([good[mid] ^ 0xFF]) + good[mid + 1:])
    _, again = _item(study, "source")
    assert again.state is State.PENDING and again.reason.value == "incomplete"
    assert ("truncated" in again.detail) if damage == "truncate" else ("checksum" in again.detail)
    out = peenflow("run", study).stdout
    assert statuses(out)["source"] == "computed"
    assert store.manifest("source", item.key).content_hash == content  # same data again
    with xr.open_dataset(path) as ds:
        assert ds.value.values.tolist() == [0.0, 1.0, 4.0, 9.0, 16.0]


def test_provenance_is_recorded(tmp_path):
    study = write_toy(tmp_path / "s")
    peenflow("run", study)
    store, item = _item(study, "scale")
    ds = store.open("scale", item.key)
    for attr in ("peenflow_task", "peenflow_version", "peenflow_params", "peenflow_upstream",
                 "peenflow_source_hash", "peenflow_versions", "peenflow_started", "peenflow_finished",
                 "peenflow_wall_s", "peenflow_host"):
        assert attr in ds.attrs, attr
    assert ds.attrs["peenflow_version"] == "1"
    assert '"factor":1' in ds.attrs["peenflow_params"]
