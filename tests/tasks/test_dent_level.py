"""The target's dent at its own, finer element size (fidelity.dent_element_size_um, issue 10 §1/§4)
through `peenflow run` on a micro target (100 um REV, 80 um dent): the single impact and its
ellipse run at the dent's size, the REV runs at the study's; the dent's single impact is the one a
study at that element size computes (same key: shared), so N_f and N_c are that study's; every
result says which element size made it, and the headline names the dent's."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from peenflow.api import load_study_graph
from peenflow.engine import DirectoryStore, plan
from peenflow.engine.reasons import State
from peenflow.testing import run_study

HERE = Path(__file__).parent
H_REV, H_DENT = 100e-6, 80e-6


def _run(study: Path, *args) -> str:
    return run_study(study, *args)


def _items(study: Path, until: str):
    graph = load_study_graph(study)
    store = DirectoryStore(study.parent / ".peenflow")
    return {i.node.stage: i for i in plan(graph, store, graph.until(until))}, store


def _open(study: Path, stage: str):
    items, store = _items(study, stage)
    item = items[stage]
    assert item.state is State.DONE, (stage, item.state)
    return store.open(item.node.task.name, item.key)


def _variant(study: Path, name: str, element_um: float | None, dent: bool) -> Path:
    """A copy of the study in the same folder (same store) with another element size or no dent key."""
    text = study.read_text()
    if element_um is not None:
        text = text.replace("element_size_um = 100.0", f"element_size_um = {element_um!r}")
    if not dent:
        text = text.replace("dent_element_size_um = 80.0\n", "")
    assert ("dent_element_size_um = " in text) == dent
    path = study.with_name(name)
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    d = tmp_path_factory.mktemp("dent_level")
    study = d / "micro_dent.toml"
    shutil.copy(HERE / "micro_dent.toml", study)
    return study, _run(study)


def _spacing(x) -> float:
    return float(np.diff(np.asarray(x)).min())


def test_the_dent_runs_at_its_size_and_the_rev_at_the_study_s(run):
    study, _ = run
    impact = _open(study, "target_impact")
    assert _spacing(impact.x_node_full.values) == pytest.approx(H_DENT, rel=1e-9)
    runs = _open(study, "target_runs")
    # the REV's fine zone: uniform layers of the study's element size under the surface
    top = np.diff(runs.z_edge_m.values.ravel()[:4])
    assert np.allclose(top, H_REV, rtol=1e-9), top
    # the REV ran N_c shots of the coverage curve made from the fine dent
    cov = _open(study, "coverage_curve")
    assert int(runs.coverage_shots.max()) == int(cov.coverage_shots_rounded.max())


def test_the_dent_is_the_one_a_study_at_that_size_computes(run):
    study, _ = run
    fine = _variant(study, "micro_80.toml", 80.0, dent=False)
    items, _ = _items(fine, "coverage_curve")
    # nothing of the dent's chain left to compute: the same keys as the dent level's
    assert items["target_impact"].state is State.DONE and items["target_indentation"].state is State.DONE
    _run(fine, "--until", "coverage_curve")
    n_f = float(_open(study, "coverage_curve").full_coverage_shots)
    assert float(_open(fine, "coverage_curve").full_coverage_shots) == n_f
    # without the key the dent is the REV's (100 um): another impact, another ellipse, another N_f
    plain = _variant(study, "micro_100.toml", None, dent=False)
    items, _ = _items(plain, "coverage_curve")
    assert items["target_impact"].state is not State.DONE
    _run(plain, "--until", "coverage_curve")
    assert _spacing(_open(plain, "target_impact").x_node_full.values) == pytest.approx(H_REV, rel=1e-9)
    assert float(_open(plain, "coverage_curve").full_coverage_shots) != n_f


def test_each_result_says_which_element_size_made_it(run):
    study, out = run
    for stage in ("target_impact", "target_indentation"):
        made = _open(study, stage).attrs["peenflow_fidelity"]
        assert "80 um elements" in made and "dent ellipse gives N_f and N_c" in made, made
    for stage in ("coverage_curve", "target_runs", "residual_profile"):
        made = _open(study, stage).attrs["peenflow_fidelity"]
        assert "100 um elements" in made and "dent ellipse (N_f, N_c) from a single impact at 80 um" in made, made
    dent_row = next(ln for ln in out.splitlines() if ln.strip().startswith("target dent"))
    assert "single impact on 80 um elements" in dent_row, dent_row


def test_a_core_under_the_impact_through_peenflow_run(run):
    """``dent_refinement = "core"``: the single impact keeps the study's 100 um block and refines a
    core under the impact to 80 um; its dent, N_f and N_c differ from the 100 um block's, and every
    result says how the dent was made."""
    study, _ = run
    text = study.read_text().replace("dent_element_size_um = 80.0\n",
                                     'dent_element_size_um = 80.0\ndent_refinement = "core"\n')
    cored = study.with_name("micro_core.toml")
    cored.write_text(text)
    out = _run(cored, "--until", "coverage_curve")
    impact = _open(cored, "target_impact")
    assert impact.attrs["dent_refinement"] == "core"
    x = impact.x_node_full.values
    d = np.diff(x)
    centre = np.abs(0.5 * (x[1:] + x[:-1])) < impact.attrs["dent_core_half_width_m"]
    assert np.allclose(d[centre], H_DENT, rtol=1e-9)  # the core: 80 um elements
    assert np.any(np.isclose(d, H_REV, rtol=1e-9))  # the fine zone beyond it: the block's 100 um
    plain = _variant(study, "micro_100.toml", None, dent=False)
    _run(plain, "--until", "coverage_curve")
    assert float(_open(cored, "target_indentation").dent_semi_axis_along_m) != \
        float(_open(plain, "target_indentation").dent_semi_axis_along_m)
    made = impact.attrs["peenflow_fidelity"]
    assert "100 um elements, a core of 80 um elements under the impact" in made, made
    made = _open(cored, "coverage_curve").attrs["peenflow_fidelity"]
    assert "from a single impact at 80 um (a core under the impact in 100 um elements)" in made, made
    dent_row = next(ln for ln in out.splitlines() if ln.strip().startswith("target dent"))
    assert "single impact with a core of 80 um elements under it" in dent_row, dent_row
