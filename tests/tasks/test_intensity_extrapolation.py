"""Intensities extrapolated to zero element size (fidelity.extrapolate_intensity_from_um, issue 10 §3-§4)
through `peenflow run` on the micro strips (100 and 125 um): each extrapolated intensity is eq. (R3)
of the two levels' stored saturation results; the coarse level is the work a study at that element
size does (same keys: a plain study there reuses it); the control curve and the target velocity
read the extrapolated intensities; every result says which level made it."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from peenflow.api import load_study_graph
from peenflow.engine import DirectoryStore, plan
from peenflow.engine.conventions import squeeze_point
from peenflow.engine.reasons import State
from peenflow.testing import run_study
from peenflow.methods import ControlCurve, extrapolation_factor
from peenflow.study.accuracy import INTENSITY_ORDER

HERE = Path(__file__).parent
H_FINE, H_COARSE = 100e-6, 125e-6


def _run(study: Path, *args) -> str:
    return run_study(study, *args)


def _results(study: Path, stage: str):
    graph = load_study_graph(study)
    store = DirectoryStore(study.parent / ".peenflow")
    items = [i for i in plan(graph, store, graph.until(stage)) if i.node.stage == stage]
    assert items and all(i.state is State.DONE for i in items), [(i.node.node_id, i.state) for i in items]
    return {tuple(sorted(i.node.coords.items())): squeeze_point(store.open(i.node.task.name, i.key), i.node.coords)
            for i in items}, items


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    d = tmp_path_factory.mktemp("extrapolated")
    study = d / "micro_extrapolated.toml"
    shutil.copy(HERE / "micro_extrapolated.toml", study)
    out = _run(study, "--until", "control_curve")
    return study, out


def test_each_intensity_is_the_paired_two_level_limit_of_the_stored_levels(run):
    study, _ = run
    ext, _ = _results(study, "intensity_extrapolation")
    fine, _ = _results(study, "saturation")
    coarse, _ = _results(study, "coarse_saturation")
    k = extrapolation_factor(H_COARSE, H_FINE, INTENSITY_ORDER)
    assert len(ext) == 2
    for point, e in ext.items():
        f, c = fine[point], coarse[point]
        per_f = dict(zip(f.sequence.values.tolist(), f.sequence_intensity_m.values.ravel().tolist()))
        per_c = dict(zip(c.sequence.values.tolist(), c.sequence_intensity_m.values.ravel().tolist()))
        diffs = [per_f[s] - per_c[s] for s in per_f if s in per_c and np.isfinite(per_f[s] - per_c[s])]
        assert diffs and int(e.paired_sequences) == len(diffs)
        want = float(f.intensity_m) + k * np.mean(diffs)
        assert float(e.intensity_m) == pytest.approx(want, rel=1e-12)
        assert float(e.fine_intensity_m) == float(f.intensity_m) and float(e.coarse_intensity_m) == float(c.intensity_m)
        assert e.attrs["order"] == INTENSITY_ORDER and e.attrs["extrapolation_factor"] == pytest.approx(k, rel=1e-12)
    control, _ = _results(study, "control_curve")
    (cc,) = control.values()
    for point, e in ext.items():
        v = dict(point)["velocity_m_s"]
        assert float(cc.intensity_m.sel(angle_deg=90.0, velocity_m_s=v)) == float(e.intensity_m)


def test_both_levels_run_the_same_shot_streams(run):
    study, _ = run
    graph = load_study_graph(study)
    fine = {n.node_id.split("[", 1)[1]: n.params for n in graph.stage_nodes("strip_runs")}
    coarse = {n.node_id.split("[", 1)[1]: n.params for n in graph.stage_nodes("coarse_strip_runs")}
    assert fine.keys() == coarse.keys() and len(fine) == 4
    for point in fine:
        assert fine[point]["seed"] == coarse[point]["seed"]
        assert fine[point]["fidelity"]["element_size_m"] == pytest.approx(H_FINE)
        assert coarse[point]["fidelity"]["element_size_m"] == pytest.approx(H_COARSE)
        rest = lambda p: {k: v for k, v in p.items() if k != "fidelity"}  # noqa: E731
        assert rest(fine[point]) == rest(coarse[point])


def test_a_study_at_the_coarse_size_reuses_the_coarse_level(run):
    """The same study at 125 um without the extrapolation: its strip runs, arc heights and saturation
    fits are the extrapolating study's coarse level, so a run into the same store computes none of them."""
    study, _ = run
    text = study.read_text().replace("element_size_um = 100.0\nextrapolate_intensity_from_um = 125.0",
                                     "element_size_um = 125.0")
    text = text.replace('allow_outside_bounds = ["fidelity.extrapolate_intensity_from_um"]',
                        'allow_outside_bounds = ["fidelity.element_size_um", "target.rev_size_mm"]')
    assert "element_size_um = 125.0" in text and "extrapolate_intensity_from_um =" not in text
    plain = study.with_name("micro_125um.toml")
    plain.write_text(text)
    out = _run(plain, "--until", "saturation")
    for stage in ("strip_runs", "arc_height", "saturation"):
        row = re.search(rf"(?m)^{stage}\s+(\d+)\s+(\d+)\s+(\d+)", out)
        assert row and int(row.group(1)) > 0 and int(row.group(2)) == 0 and int(row.group(3)) == int(row.group(1)), out


def test_every_result_says_which_level_made_it(run):
    study, out = run
    for stage, want in (("coarse_strip_runs", "the coarse level of the intensity extrapolation"),
                        ("intensity_extrapolation", "extrapolated to zero element size from 125 and 100 um"),
                        ("control_curve", "extrapolated to zero element size from 125 and 100 um")):
        results, _ = _results(study, stage)
        for ds in results.values():
            assert want in ds.attrs["peenflow_fidelity"], (stage, ds.attrs["peenflow_fidelity"])
    for ds in _results(study, "saturation")[0].values():  # one level: no extrapolation claimed
        assert "100 um elements" in ds.attrs["peenflow_fidelity"] and "extrapolated" not in ds.attrs["peenflow_fidelity"]
    assert "to zero element size from" in out and "study level not measured for Almen intensities extrapolated" in out


def test_the_target_velocity_is_read_off_the_extrapolated_curve(run):
    """A target intensity halfway along the extrapolated curve: the velocity is that curve's PCHIP
    inverse, not the fine level's."""
    study, _ = run
    (cc,) = _results(study, "control_curve")[0].values()
    ints = cc.intensity_m.sel(angle_deg=90.0).values
    v = cc.velocity_m_s.values.astype(float)
    assert np.all(np.isfinite(ints)) and ints[1] > ints[0]
    wanted = 0.5 * (ints[0] + ints[1])
    text = study.read_text()
    text = re.sub(r"(?m)^almen_intensity_mm = .*$", f"almen_intensity_mm = {float(wanted) / 1e-3!r}", text)
    target = study.with_name("micro_extrapolated_target.toml")
    target.write_text(text)
    out = _run(target, "--until", "target_velocity")
    assert re.search(r"(?m)^control_curve\s+1\s+0\s+1", out), out  # the strips and curve are reused
    (tv,) = _results(target, "target_velocity")[0].values()
    want = ControlCurve(90.0, v, ints, "pchip").velocity(wanted)
    assert float(tv.velocity_m_s) == pytest.approx(float(want), rel=1e-12)
    fine = [float(ds.intensity_m) for _, ds in sorted(_results(study, "saturation")[0].items())]
    assert np.min(np.abs(ints - np.array(fine))) > 1e-6  # the curve read is not the fine level's (m)
