"""A strip run whose ladder extends itself (almen.shot_counts = "auto", issue 10 §3) on the micro
strip REV (100 um elements): it stops at the first rung where eq. (11) holds inside its own data and
not before, says so when the cap stops it instead, and a stopped run resumes bit-identically."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from peenflow.engine import DirectoryStore, TaskContext
from peenflow.engine.interrupt import Interrupted
from peenflow.methods import doubling_ladder, ladder_verdict
from peenflow.study import load_study
from tasks._rev_run import run_rev
from tasks.arc_height import release
from tasks.params import LadderParams, study_params

from .test_limits import _same, _StopAfter

HERE = Path(__file__).parent


@pytest.fixture(scope="module")
def strip():
    s = load_study(HERE / "micro.toml")
    return s, study_params(s), study_params(s).strip


def _run(strip, ctx, cap):
    s, p, params = strip
    return run_rev(ctx, material=p.strip_material, shot=p.shot, fidelity=p.fidelity,
                   side_m=1.2e-3, measure_side_m=0.4e-3, thickness_m=params.thickness_m, angle_deg=90.0,
                   velocity_m_s=55.0, seed=11, ladder=[], extend=LadderParams(3, cap, "paper", params))


@pytest.fixture(scope="module")
def extended(strip):
    return _run(strip, None, 192)


def _verdicts(run, params):
    rungs = run.shots.values.tolist()
    ah = [release(run.z_edge_m.values, run.stress_xx_Pa.values[k], params)[0] for k in range(len(rungs))]
    return [ladder_verdict(rungs[: k + 1], ah[: k + 1]) for k in range(len(rungs))]


def test_the_run_stops_at_the_first_rung_where_its_own_data_saturate(strip, extended):
    rungs = extended.shots.values.tolist()
    assert tuple(rungs) == doubling_ladder(3, 192)[: len(rungs)] and rungs[-1] < 192  # it stopped early
    verdicts = _verdicts(extended, strip[2])
    assert not any(v.stop for v in verdicts[:-1])  # not before
    assert verdicts[-1].stop and verdicts[-1].saturated  # when it should
    T = float(extended.ladder_saturation_shots)
    assert int(extended.ladder_saturated) == 1 and 2 * T <= rungs[-1] and T >= rungs[0]
    assert T == verdicts[-1].saturation_shots
    assert "saturated" in extended.attrs["ladder_stop_reason"]
    assert extended.restitution.size == rungs[-1]  # no shot beyond the rung that settled eq. (11)


def test_the_cap_stops_an_unsaturated_run_and_says_so(strip, extended):
    T = float(extended.ladder_saturation_shots)
    cap = 24
    assert 2 * T > cap  # the uncapped run needed more than this cap allows
    capped = _run(strip, None, cap)
    assert capped.shots.values.tolist() == [3, 6, 12, 24]
    assert int(capped.ladder_saturated) == 0
    assert "cap almen.max_shots = 24" in capped.attrs["ladder_stop_reason"]


def test_a_stopped_extending_run_resumes_bit_identically(strip, extended, tmp_path):
    store = DirectoryStore(tmp_path / "store")
    mid = extended.shots.values[-2] + 5  # inside the last rung: resumes from a shot, not a rung
    ctx = _StopAfter(store, "k" * 32, "p", "study", 1, shots=int(mid))
    with pytest.raises(Interrupted, match=f"after shot {mid} of 192"):
        _run(strip, ctx, 192)
    resumed = TaskContext(store, "k" * 32, "p", "study", 1)
    assert resumed.resumed
    again = _run(strip, resumed, 192)
    _same(again, extended)
    assert again.shots.values.tolist() == extended.shots.values.tolist()
    assert float(again.ladder_saturation_shots) == float(extended.ladder_saturation_shots)


def test_a_micro_study_with_an_auto_ladder_saturates_every_point_inside_its_data(tmp_path):
    """Through the real command: every sequence stops saturated in its own data, the sequences of a
    point may stop at different rungs (NaN-padded arc heights), and no point's intensity is
    extrapolated, so the control curve needs no guessed ladder."""
    import subprocess
    import sys

    import peenflow

    study = tmp_path / "auto.toml"
    study.write_text((HERE / "micro.toml").read_text().replace(
        "shot_counts = [3, 6, 12, 24]", 'shot_counts = "auto"\nfirst_shots = 3\nmax_shots = 384').replace(
        "sequences = 1\nrev_rule", "sequences = 2\nrev_rule"))
    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", "run", str(study), "--until", "control_curve",
                           "--workers", "2"], capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    runs = peenflow.open_result(study, "strip_runs")
    assert (runs.ladder_saturated.values == 1).all()
    T = runs.ladder_saturation_shots.values
    arc = peenflow.open_result(study, "arc_height").arc_height_m
    reached = np.isfinite(arc.values)
    # each sequence's last rung is at >= 2T of its own fit, T not below its first rung
    last = (arc.shots.values * reached).max(axis=-1)
    assert np.all(2 * T <= last) and np.all(T >= 3)
    sat = peenflow.open_result(study, "saturation")
    assert (sat.intensity_extrapolated.values == 0).all()
