"""One rule says what a key's checkpoint is worth (checkpoint.judge), and the run, `status` and `clean` act on
it alike: a leftover goes, an unreadable one is dropped by the next run, a resumable one is resumed."""

import os

import pytest
import xarray as xr
from engine_helpers import peenflow, write_toy

from peenflow.engine import DirectoryStore, load_graph, plan
from peenflow.engine.checkpoint import Checkpoints, CheckpointState, judge

#: the toy counter after 4 of 6 steps (it adds up 0..steps-1): what its own checkpoint would hold
STEP_4 = xr.Dataset({"step": ((), 4), "acc": ((), 6.0)})
GARBAGE = b"\x89HDF\r\n\x1a\n" + bytes(range(256)) * 4


def _counter(study, store):
    return next(i for i in plan(load_graph(study, "x:y"), store) if i.node.stage == "counter")


def _age(folder, seconds_before: float) -> None:
    for f in folder.iterdir():
        os.utime(f, (seconds_before, seconds_before))


def test_the_rule_without_a_result(tmp_path):
    study = write_toy(tmp_path / "s", steps=6)
    peenflow("run", study, "--until", "source")
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    key = _counter(study, store).key
    assert judge(store, key, "counter").state is CheckpointState.ABSENT  # no folder
    store.checkpoint_dir(key).mkdir(parents=True)
    assert judge(store, key, "counter").state is CheckpointState.ABSENT  # a save killed before its rename
    store.checkpoints(key).save(STEP_4, {"done": 4, "total": 6, "unit": "steps"})
    v = judge(store, key, "counter")
    assert v.state is CheckpointState.RESUMABLE and v.position == {"done": 4.0, "total": 6.0, "unit": "steps"}
    (store.checkpoint_dir(key) / "checkpoint.nc").write_bytes(GARBAGE)
    v = judge(store, key, "counter")
    assert v.state is CheckpointState.UNREADABLE and v.why


def test_a_checkpoint_older_than_its_valid_result_is_a_leftover_a_newer_one_is_not(tmp_path):
    study = write_toy(tmp_path / "s", steps=6)
    peenflow("run", study)
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    key = _counter(study, store).key
    stored = store.stored_at(key, "counter")
    assert stored == store.stored_at(key)  # found under its task without being told it
    ck = store.checkpoints(key)
    ck.directory.mkdir(parents=True)
    assert judge(store, key).state is CheckpointState.LEFTOVER  # an empty folder holds nothing to resume
    Checkpoints(ck.directory).save(STEP_4)
    _age(ck.directory, stored - 60)  # the run that stored the result was killed before removing it
    assert judge(store, key, "counter").state is judge(store, key).state is CheckpointState.LEFTOVER
    _age(ck.directory, stored + 60)  # a forced rerun killed after its own save: its work, kept
    assert judge(store, key, "counter").state is CheckpointState.RESUMABLE
    _age(ck.directory, stored - 60)
    path = store.result_path("counter", key)
    path.write_bytes(path.read_bytes()[:100])  # no valid result any more: nothing makes it a leftover
    assert store.stored_at(key) is None and judge(store, key).state is CheckpointState.RESUMABLE


@pytest.mark.parametrize("saved", ["readable", "garbage"])
def test_status_clean_and_the_run_decide_alike(tmp_path, saved):
    study = write_toy(tmp_path / "s", steps=6)
    peenflow("run", study, "--until", "source")
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    key = _counter(study, store).key
    store.checkpoints(key).save(STEP_4, {"done": 4, "total": 6, "unit": "steps"})
    if saved == "garbage":
        (store.checkpoint_dir(key) / "checkpoint.nc").write_bytes(GARBAGE)
    status = next(ln for ln in peenflow("status", study, "--why").stdout.splitlines() if " counter  (" in ln)
    cleaned = peenflow("clean", study).stdout
    assert "kept 1 checkpoint of an unfinished point" in cleaned and store.checkpoints(key).exists()
    ran = next(ln for ln in peenflow("run", study).stdout.splitlines() if " counter " in ln)
    resumed = store.open("counter", key).attrs["peenflow_resumed"]
    if saved == "readable":
        assert "the next run resumes from its checkpoint after 4/6 steps" in status, status
        assert "resuming from checkpoint after 4/6 steps" in ran and resumed == 1, ran
    else:
        assert "its checkpoint cannot be read: the next run starts over" in status and "resumes" not in status
        assert "checkpoint unreadable, starting over" in ran and "resuming" not in ran and resumed == 0, ran
    assert float(store.open("counter", key).acc) == sum(range(6))
    assert not store.checkpoint_dir(key).exists()  # removed once the result is stored
