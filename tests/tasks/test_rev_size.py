"""Stage rev_size: the three REV rules, and a measuring region that is the whole face (periodic
lateral faces, almen.measure_size_mm = rev_size_mm) accepted as the study loader and the docs allow."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

from peenflow.api import load_study_graph
from peenflow.engine import DirectoryStore, plan
from tasks.params import RevParams
from tasks.rev_size import rev_size

HERE = Path(__file__).parent
D = 0.58e-3


def test_rules_give_the_papers_sides():
    paper = rev_size.fn(rev=RevParams("paper", 1.29e-3, D, None, None))
    assert float(paper.rev_side_m) == pytest.approx(6 * D) and float(paper.measure_side_m) == pytest.approx(2 * D)
    explicit = rev_size.fn(rev=RevParams("explicit", 1.29e-3, D, 1.8e-3, None))
    assert float(explicit.measure_side_m) == pytest.approx(0.6e-3)  # a third by default


def test_the_whole_face_is_a_valid_measuring_region_and_more_is_refused():
    whole = rev_size.fn(rev=RevParams("explicit", 1.29e-3, D, 1.2e-3, 1.2e-3))
    assert float(whole.measure_side_m) == float(whole.rev_side_m) == pytest.approx(1.2e-3)
    with pytest.raises(ValueError, match="at most the REV side"):
        rev_size.fn(rev=RevParams("explicit", 1.29e-3, D, 1.2e-3, 1.3e-3))


def test_a_periodic_study_measuring_the_whole_face_runs_its_rev_stage(tmp_path):
    text = (HERE / "micro.toml").read_text().replace("measure_size_mm = 0.4", "measure_size_mm = 1.2")
    text = re.sub(r"(?m)^\[fidelity\]\n", '[fidelity]\nlateral_boundary = "periodic"\n', text)
    study = tmp_path / "micro.toml"
    study.write_text(text)
    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", "run", str(study), "--until", "strip_rev"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    graph = load_study_graph(study)
    store = DirectoryStore(tmp_path / ".peenflow")
    (item,) = [i for i in plan(graph, store, graph.until("strip_rev")) if i.node.stage == "strip_rev"]
    ds = store.open("rev_size", item.key)
    assert float(ds.measure_side_m.squeeze()) == float(ds.rev_side_m.squeeze()) == pytest.approx(1.2e-3)
