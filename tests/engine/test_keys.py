"""Result keys: stable across processes and machines, sensitive to every input."""

import os
import subprocess
import sys

from engine_helpers import peenflow, write_toy

from peenflow.engine import DirectoryStore, Reporter, execute, load_graph, plan
from peenflow.engine.keys import KeyParts


def _keys(study):
    graph = load_graph(study, "unused:unused")
    store = DirectoryStore(study.parent / ".peenflow")
    execute(graph, store, graph.nodes, reporter=Reporter(quiet=True))
    return {i.node.node_id: i.key for i in plan(graph, store)}


def test_same_study_same_keys_in_another_process_and_directory(tmp_path):
    here = _keys(write_toy(tmp_path / "a"))
    other = write_toy(tmp_path / "elsewhere" / "deeper")
    env = dict(os.environ, PYTHONHASHSEED="12345")
    code = (
        "import sys, json, importlib.util; sys.path.insert(0, sys.argv[1]);"
        "from test_keys import _keys; from pathlib import Path;"
        "print(json.dumps(_keys(Path(sys.argv[2]))))"
    )
    out = subprocess.run([sys.executable, "-c", code, os.path.dirname(__file__), str(other)],
                         capture_output=True, text=True, env=env, check=True)
    import json

    there = json.loads(out.stdout.strip().splitlines()[-1])
    assert there == here
    assert len(set(here.values())) == len(here)  # every point has its own key


def test_key_changes_with_any_parameter_code_or_upstream():
    base = KeyParts("scale", "version:1", {"factor": 2, "delay_s": 0}, {"src": "abc"})
    assert KeyParts("scale", "version:1", {"factor": 2, "delay_s": 0}, {"src": "abc"}).key == base.key
    assert KeyParts("scale", "version:1", {"factor": 3, "delay_s": 0}, {"src": "abc"}).key != base.key
    assert KeyParts("scale", "version:2", {"factor": 2, "delay_s": 0}, {"src": "abc"}).key != base.key
    assert KeyParts("scale", "version:1", {"factor": 2, "delay_s": 0}, {"src": "abd"}).key != base.key
    assert KeyParts("shift", "version:1", {"factor": 2, "delay_s": 0}, {"src": "abc"}).key != base.key


def test_parameter_change_invalidates_the_point_and_its_downstream_only(tmp_path):
    study = write_toy(tmp_path / "s")
    before = _keys(study)
    write_toy(tmp_path / "s", n=6)
    after = _keys(study)
    changed = {k for k in before if before[k] != after[k]}
    assert changed == {"source", "scale[factor=1]", "scale[factor=2]", "scale[factor=3]", "total"}


def test_identical_upstream_content_does_not_invalidate_downstream(tmp_path):
    study = write_toy(tmp_path / "s")
    peenflow("run", study)
    write_toy(tmp_path / "s", source_delay_s=0.01)  # new key for source, same content
    lines = peenflow("run", study).stdout.splitlines()
    assert any(l.startswith("+ computed") and "source  (parameters changed: delay_s: 0 -> 0.01)" in l
               for l in lines)
    for f in (1, 2, 3):
        assert any(l.startswith("= reused") and f"scale[factor={f}]" in l for l in lines)


def test_a_parameters_changed_reason_names_each_changed_field_with_old_and_new_values():
    """Nested tables as dotted paths, numbers with the digits that tell them apart, a list whose items
    mostly changed shown whole but abbreviated; one line, at most four changes named."""
    from peenflow.engine.keys import reason_against_slot
    from peenflow.engine.reasons import Reason

    old = {"intensity_m": 0.0003, "material": {"A_Pa": 434e6, "n": 0.3}, "angle_deg": 90.0,
           "velocities_m_s": [30.0, 45.0, 55.0], "seeds": list(range(64)), "note": "a"}
    new = {"intensity_m": 0.00035, "material": {"A_Pa": 500e6, "n": 0.3}, "angle_deg": 90.0,
           "velocities_m_s": [30.0, 47.5, 55.0], "seeds": list(range(1, 65)), "note": "a"}
    slot = {"parts": KeyParts("rev", "version:1", old, {}).to_dict()}
    reason, detail = reason_against_slot(slot, "rev", "version:1", new, {})
    assert reason is Reason.PARAMS_CHANGED
    assert detail == ("intensity_m: 0.0003 -> 0.00035, material.A_Pa: 4.34e8 -> 5e8, "
                      "seeds: [0, 1, 2, ... (64 items)] -> [1, 2, 3, ... (64 items)], velocities_m_s[1]: 45 -> 47.5")
    # a fifth change is counted, not shown; a change in the 9th digit is shown with 9 digits
    new = {**new, "note": "b\nc", "angle_deg": 89.9999999}
    reason, detail = reason_against_slot(slot, "rev", "version:1", new, {})
    assert detail.startswith("angle_deg: 90 -> 89.9999999, intensity_m: ") and detail.endswith(" (+2 more)")
    assert "\n" not in detail
    # a field added or removed reads as none
    _, detail = reason_against_slot(slot, "rev", "version:1", {**old, "extra": 1}, {})
    assert detail == "extra: none -> 1"


def test_status_why_names_the_changed_field(tmp_path):
    study = write_toy(tmp_path / "s")
    peenflow("run", study)
    write_toy(tmp_path / "s", n=6)
    lines = peenflow("status", study, "--why").stdout.splitlines()
    assert any("source  (parameters changed: n: 5 -> 6)" in line for line in lines), lines
