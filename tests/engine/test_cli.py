"""The verbs: failures isolated, rerun scope, stale versions, until, clean, unlock."""

import json
import os
import socket

from engine_helpers import peenflow, statuses, write_toy

from peenflow.engine import DirectoryStore


def test_a_failing_point_is_recorded_and_does_not_stop_the_others(tmp_path):
    study = write_toy(tmp_path / "s")
    proc = peenflow("run", study, check=False, env={"TOY_FAIL_FACTOR": "2"})
    assert proc.returncode == 1
    st = statuses(proc.stdout)
    assert st["scale[factor=1]"] == "computed" and st["scale[factor=3]"] == "computed"
    assert st["scale[factor=2]"] == "failed"
    assert st["total"] == "skipped" and st["counter"] == "computed"
    assert "not finished:" in proc.stdout and "factor 2 fails on purpose" in proc.stdout
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    failures = [key for task, key in store.all_failures() if task == "scale"]
    assert len(failures) == 1
    rec = store.failure("scale", failures[0])
    assert "RuntimeError: factor 2 fails on purpose" in rec["traceback"]
    status = peenflow("status", study, "--why").stdout
    assert "failed" in status and "last attempt failed: RuntimeError" in status
    # Condition gone: only the failed point and what waits on it run again.
    st = statuses(peenflow("run", study).stdout)
    assert st["scale[factor=2]"] == "computed" and st["total"] == "computed"
    assert st["scale[factor=1]"] == "reused" and st["source"] == "reused"


def test_rerun_recomputes_exactly_the_stage_and_its_downstream(tmp_path):
    study = write_toy(tmp_path / "s")
    peenflow("run", study)
    st = statuses(peenflow("rerun", study, "scale").stdout)
    assert {k for k, v in st.items() if v == "computed"} == {
        "scale[factor=1]", "scale[factor=2]", "scale[factor=3]", "total"}
    assert st["source"] == "reused" and st["counter"] == "reused"
    # identical content: the old files were kept rather than replaced
    assert not [key for _, key, _ in DirectoryStore(tmp_path / "s" / ".peenflow").all_results()
                if ".superseded-" in key]


def test_until_runs_only_what_the_stage_needs_and_dry_run_computes_nothing(tmp_path):
    study = write_toy(tmp_path / "s")
    dry = peenflow("run", study, "--dry-run").stdout
    assert "pending" in dry and "missing: never computed" in dry
    assert not (tmp_path / "s" / ".peenflow" / "results").exists()
    st = statuses(peenflow("run", study, "--until", "scale").stdout)
    assert set(st) == {"source", "scale[factor=1]", "scale[factor=2]", "scale[factor=3]"}


def test_code_change_under_same_version_is_flagged_stale_not_recomputed(tmp_path):
    study = write_toy(tmp_path / "s")
    peenflow("run", study)
    pipeline = tmp_path / "s" / "toy_pipeline.py"
    # scale has version="1": edit its code without bumping the version.
    text = pipeline.read_text().replace('src.value * factor', 'src.value * factor * 1.0 + 0.0')
    pipeline.write_text(text)
    status = peenflow("status", study, "--why").stdout
    assert "stale" in status and "code changed under version 1" in status
    st = statuses(peenflow("run", study).stdout)
    assert st["scale[factor=1]"] == "reused"
    # total has no version: its code fingerprint decides; a comment is not a change
    pipeline.write_text(text.replace("def total(", "# a comment\ndef total("))
    assert statuses(peenflow("run", study).stdout)["total"] == "reused"
    pipeline.write_text(text.replace('scaled.scaled.sum("i")', 'scaled.scaled.sum("i") * 1'))
    out = peenflow("run", study).stdout
    assert statuses(out)["total"] == "computed" and "code changed: source" in out


def test_clean_removes_only_unreferenced_results(tmp_path):
    study = write_toy(tmp_path / "s")
    peenflow("run", study)
    write_toy(tmp_path / "s", n=4)
    peenflow("run", study)  # the n=5 results are now unreferenced
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    n_before = len(list(store.all_results()))
    dry = peenflow("clean", study, "--dry-run").stdout
    assert "would remove 10 item(s)" in dry  # 5 old results + their 5 manifests (counter unchanged)
    assert len(list(store.all_results())) == n_before
    peenflow("clean", study)
    assert len(list(store.all_results())) == n_before - 5
    assert all(v == "reused" for v in statuses(peenflow("run", study).stdout).values())


def test_unlock_removes_a_lease_left_by_a_dead_process(tmp_path):
    study = write_toy(tmp_path / "s")
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    lease = store.leases.path("deadbeef" * 4)
    lease.mkdir(parents=True)
    (lease / "owner.json").write_text(json.dumps(
        {"host": "other-host", "pid": 1, "started": 0, "point": "toy:scale[factor=1]"}))
    listing = peenflow("unlock", study).stdout
    assert "held by other-host pid 1" in listing
    assert "held by other-host" in peenflow("status", study).stdout
    peenflow("unlock", study, "deadbeef")
    assert not lease.exists()


def _leased_scale_point(tmp_path):
    """A toy study whose first scale point is leased by nobody alive: (study, point, lease dir)."""
    from peenflow.engine import load_graph, plan

    study = write_toy(tmp_path / "s")
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    peenflow("run", study, "--until", "source")
    item = next(i for i in plan(load_graph(study, "x:y"), store) if i.node.stage == "scale")
    lease = store.leases.path(item.key)
    lease.mkdir(parents=True)
    return study, item, lease


def test_a_lease_of_a_dead_local_process_is_broken_automatically(tmp_path):
    study, item, lease = _leased_scale_point(tmp_path)
    dead_pid = 2 ** 22 + 12345
    assert not os.path.exists(f"/proc/{dead_pid}")
    (lease / "owner.json").write_text(json.dumps(
        {"host": socket.gethostname(), "pid": dead_pid, "started": 0, "point": "killed run"}))
    st = statuses(peenflow("run", study, timeout=60).stdout)
    assert st[item.node.node_id] == "computed"


def test_a_lease_left_without_owner_by_a_killed_run_is_broken(tmp_path):
    """A run killed between mkdir and writing owner.json must not block the next run."""
    from peenflow.engine.lease import OWNERLESS_GRACE_S

    study, item, lease = _leased_scale_point(tmp_path)
    old = os.path.getmtime(lease) - 2 * OWNERLESS_GRACE_S
    os.utime(lease, (old, old))
    st = statuses(peenflow("run", study, timeout=60).stdout)
    assert st[item.node.node_id] == "computed"
