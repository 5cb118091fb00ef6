"""Issue 12 items 9 and 12: an altered manifest is caught; environment faults give one line, no traceback."""

from __future__ import annotations

import errno
import json
import os
import shutil
import subprocess
import sys

import pytest
from engine_helpers import peenflow, result_files, statuses, write_toy

from peenflow.engine import DirectoryStore, load_graph, plan
from peenflow.engine.reasons import State


def test_an_altered_manifest_content_hash_is_detected_and_the_result_recomputed(tmp_path):
    study = write_toy(tmp_path / "s")
    store = DirectoryStore(tmp_path / "s" / ".peenflow")
    peenflow("run", study)
    items = plan(load_graph(study, "x:y"), store)
    source = next(i for i in items if i.node.stage == "source")
    downstream = {i.node.node_id: i.key for i in items}
    path = store.manifest_path("source", source.key)
    m = json.loads(path.read_text())
    m["content_hash"] = "0" * 32  # downstream keys would silently change with it
    path.write_text(json.dumps(m))
    again = next(i for i in plan(load_graph(study, "x:y"), DirectoryStore(store.root)) if i.node.stage == "source")
    assert again.state is State.PENDING and "manifest content hash does not match" in again.detail
    st = statuses(peenflow("run", study).stdout)
    assert st["source"] == "computed" and st["scale[factor=1]"] == "reused"  # same content again: no cascade
    assert {i.node.node_id: i.key for i in plan(load_graph(study, "x:y"), DirectoryStore(store.root))} == downstream


def _one_line_error(proc, *expected):
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert "Traceback" not in proc.stderr and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    for text in expected:
        assert text in proc.stderr, proc.stderr


def test_study_path_faults_give_one_line(tmp_path):
    _one_line_error(peenflow("check", tmp_path, check=False), "is a directory")
    binary = tmp_path / "b.toml"
    binary.write_bytes(bytes(range(256)))
    _one_line_error(peenflow("check", binary, check=False), "b.toml", "not a text TOML file")
    dup = write_toy(tmp_path / "d")
    dup.write_text(dup.read_text() + "n = 6\n")  # [toy] n given twice
    _one_line_error(peenflow("run", dup, check=False), "key 'n' is given twice", "line")
    (tmp_path / "missing.toml").unlink(missing_ok=True)
    _one_line_error(peenflow("status", tmp_path / "missing.toml", check=False), "does not exist")


def test_a_store_path_that_is_a_file_gives_one_line(tmp_path):
    study = write_toy(tmp_path / "s")
    (tmp_path / "afile").write_text("x")
    _one_line_error(peenflow("run", study, "--store", tmp_path / "afile", check=False), "is a file, not a directory")


def _in_namespace(script: str) -> subprocess.CompletedProcess:
    """Run ``script`` in a private user+mount namespace (so the test may mount); skip where that is refused."""
    if shutil.which("unshare") is None:
        pytest.skip("needs unshare")
    probe = subprocess.run(["unshare", "-rm", "sh", "-c", "mount -t tmpfs tmpfs /mnt"], capture_output=True)
    if probe.returncode != 0:
        pytest.skip("user namespaces with mounts are not available here")
    return subprocess.run(["unshare", "-rm", "sh", "-c", script], capture_output=True, text=True, timeout=120)


def test_a_read_only_store_serves_a_run_with_nothing_to_compute(tmp_path):
    study = write_toy(tmp_path / "s")
    store = tmp_path / "s" / ".peenflow"
    peenflow("run", study)
    before = result_files(store)
    cli = f"{sys.executable} -m peenflow.cli"
    proc = _in_namespace(f"mount --bind -o ro {store} {store} && {cli} run {study}; echo rc=$?; "
                         f"{cli} clean {study}; echo rc=$?")
    assert [line for line in proc.stdout.splitlines() if line.startswith("rc=")] == ["rc=0", "rc=2"], proc.stderr
    assert all(v == "reused" for v in statuses(proc.stdout).values()) and len(statuses(proc.stdout)) == 6
    assert "Traceback" not in proc.stdout + proc.stderr
    assert "peenflow clean: Read-only file system" in proc.stderr  # one line, not a traceback
    assert result_files(store) == before


def test_a_full_disk_fails_the_points_with_one_line_each(tmp_path):
    study = write_toy(tmp_path / "s", n=20000)  # results larger than the 64 kB disk
    store = tmp_path / "store"
    store.mkdir()
    cli = f"{sys.executable} -m peenflow.cli"
    proc = _in_namespace(f"mount -t tmpfs -o size=64k tmpfs {store} && {cli} run {study} --store {store}; echo rc=$?")
    assert "rc=1" in proc.stdout, proc.stdout + proc.stderr
    assert "Traceback" not in proc.stdout + proc.stderr
    failed = [line for line in proc.stdout.splitlines() if line.startswith("  failed:")]
    # one line each, whose length is the message's and not the store path's (a CI runner's tmp path is long)
    assert failed and all(len(line.replace(str(store), "STORE")) < 400 for line in failed)
    # the cause first ("NetCDF: HDF error" is what netCDF says), what the point needs, that nothing was lost
    assert all(line.split(": ", 2)[2].startswith("no space left on the store's device") for line in failed)
    assert "source: no space left" in proc.stdout and "this point's result needs about 320 kB" in proc.stdout
    assert all("nothing finished was lost" in line for line in failed)
    assert "HDF error" not in proc.stdout


def test_a_full_disk_at_a_result_s_write_names_the_cause_first_and_loses_nothing(tmp_path, monkeypatch, capsys):
    """No space left (ENOSPC) injected at the write of every scale result, in-process through the CLI."""
    from peenflow.cli import main
    from peenflow.engine import store as store_module

    study = write_toy(tmp_path / "s", n=20000)  # each scale result: 2 x 20 000 float64 = 320 kB
    store = tmp_path / "s" / ".peenflow"
    assert main(["run", str(study), "--until", "source", "--quiet"]) == 0
    before = result_files(store)
    real = store_module.write_dataset

    def full_at_scale(ds, path):
        if path.parent.name == "scale":
            path.write_bytes(b"\0" * 4096)  # what a full disk leaves: part of the temporary file
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        real(ds, path)

    monkeypatch.setattr(store_module, "write_dataset", full_at_scale)
    capsys.readouterr()
    assert main(["run", str(study)]) == 1
    out = capsys.readouterr().out
    st = statuses(out)
    assert st["source"] == "reused" and st["counter"] == "computed" and st["total"] == "skipped"
    failed = [line for line in out.splitlines() if line.startswith("  failed:")]
    assert len(failed) == 3 and all(" scale[factor=" in line for line in failed)
    for line in failed:
        cause = line.split(": ", 2)[2]
        assert cause.startswith(f"no space left on the store's device ({store / 'results' / 'scale'}: ")
        assert "this point's result needs about 320 kB; nothing finished was lost" in cause
        assert "Errno" not in cause and "Traceback" not in out
    after = result_files(store)
    assert all(after[name] == data for name, data in before.items())  # what was finished is untouched
    assert DirectoryStore(store).temporary_files() == []  # the partial files were removed
    monkeypatch.setattr(store_module, "write_dataset", real)  # room again: the next run computes the rest
    assert main(["run", str(study)]) == 0
    st = statuses(capsys.readouterr().out)
    assert {st[f"scale[factor={f}]"] for f in (1, 2, 3)} == {"computed"} and st["total"] == "computed"
    assert st["source"] == st["counter"] == "reused"


@pytest.mark.slow
def test_an_unreachable_scheduler_gives_one_line(tmp_path):  # dask waits its 30 s connect timeout
    study = write_toy(tmp_path / "s")
    proc = peenflow("run", study, "--scheduler", "tcp://127.0.0.1:9", check=False, timeout=120)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "cannot reach the dask scheduler at tcp://127.0.0.1:9" in proc.stderr
