"""Adaptive sequences (almen.sequence_tolerance_mm, issue 10 §3) through `peenflow run` on the micro
strip REV (100 um): each (angle, velocity) has exactly as many sequences as the rule
(peenflow.methods.sequences_verdict on the per-sequence intensities) asks for -- it stopped at the
first count where the rule says enough, and not before -- the saturation stage records the same
verdict, a second run computes nothing, and the sequences it shares with a fixed-count study are
the same results (same keys)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from peenflow.api import load_study_graph
from peenflow.engine import DirectoryStore, plan
from peenflow.engine.reasons import State
from peenflow.methods import sequences_verdict

HERE = Path(__file__).parent
TOL_MM, START, CAP = 0.004, 2, 4


def _study(tmp_path: Path, adaptive: bool) -> Path:
    text = (HERE / "micro.toml").read_text()
    extra = f"sequence_tolerance_mm = {TOL_MM}\nmax_sequences = {CAP}\n" if adaptive else ""
    text = re.sub(r"(?m)^sequences = 1\n(rev_rule)", f"sequences = {START}\n{extra}\\1", text, count=1)
    # one velocity, a ladder that extends itself: the micro ladder 3-24 does not saturate
    text = text.replace("velocities_m_s = [30.0, 55.0]", "velocities_m_s = [55.0]")
    text = text.replace("shot_counts = [3, 6, 12, 24]", 'shot_counts = "auto"\nfirst_shots = 3\nmax_shots = 96')
    assert f"sequences = {START}" in text and "max_shots = 96" in text
    d = tmp_path / ("adaptive" if adaptive else "fixed")
    d.mkdir()
    p = d / "micro.toml"
    p.write_text(text)
    return p


def _run(study: Path, *args) -> str:
    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", "run", str(study), "--until", "saturation",
                           "--quiet", *args], capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return proc.stdout


@pytest.fixture(scope="module")
def adaptive(tmp_path_factory):
    study = _study(tmp_path_factory.mktemp("seq"), adaptive=True)
    _run(study)
    graph = load_study_graph(study)
    store = DirectoryStore(study.parent / ".peenflow")
    return study, graph, store, plan(graph, store, graph.until("saturation"))


def test_each_point_has_the_sequences_the_rule_asks_for_no_more_no_fewer(adaptive):
    _, graph, store, items = adaptive
    assert all(i.state is State.DONE for i in items), [(i.node.node_id, i.state.value) for i in items
                                                       if i.state is not State.DONE]
    sats = [i for i in items if i.node.stage == "saturation"]
    assert len(sats) == 1
    for it in sats:
        ds = store.open("saturation", it.key)
        per = np.asarray(ds.sequence_intensity_m).ravel() / 1e-3  # mm, as the tolerance
        n = per.size
        assert START <= n <= CAP
        runs = [i for i in items if i.node.stage == "strip_runs"
                and i.node.coords["velocity_m_s"] == it.node.coords["velocity_m_s"]]
        assert [r.node.coords["sequence"] for r in runs] == list(range(n))
        final = sequences_verdict(per, TOL_MM, n_min=START, n_max=CAP)
        assert final.stop  # when it should
        for k in range(START, n):  # and not before
            assert not sequences_verdict(per[:k], TOL_MM, n_min=START, n_max=CAP).stop, (k, per)
        assert int(ds.sequence_tolerance_met.item()) == int(final.met)
        assert ds.intensity_standard_error_bound_m.item() / 1e-3 == pytest.approx(final.bound, rel=1e-9)
        assert "sequences" in ds.attrs["sequences_rule"]


def test_a_second_run_computes_nothing(adaptive):
    study = adaptive[0]
    out = _run(study)
    assert re.search(r"\(all\)\s+\d+\s+0\s", out), out  # computed column of the summary is 0


def test_shared_sequences_are_the_same_results_as_a_fixed_study(adaptive, tmp_path):
    _, graph, store, items = adaptive
    fixed = _study(tmp_path, adaptive=False)
    g2 = load_study_graph(fixed)
    keys = {i.node.node_id: i.key for i in plan(g2, DirectoryStore(fixed.parent / ".peenflow"),
                                                 g2.until("strip_rev")) if i.key}
    grown = {i.node.node_id: i.key for i in items}
    # the strip REV and everything upstream of the runs is the same work in both studies
    assert keys and all(grown[n] == k for n, k in keys.items())
    # a fixed study's runs (START sequences) have the same parameters as the grown study's first ones
    runs2 = {n.node_id: n.params for n in g2.stage_nodes("strip_runs")}
    runs1 = {n.node_id: n.params for n in graph.stage_nodes("strip_runs")}
    assert runs2 and all(runs1[n] == p for n, p in runs2.items())
