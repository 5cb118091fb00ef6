"""Shot size and speed spreads through ``peenflow run`` on the micro study.

The spreads reach the REV runs (strips and part) and what follows them, never the single impact, the dent,
the coverage curve or the REV sizes; the shots of the runs have the stated scatter."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import peenflow

from ..engine.engine_helpers import statuses

HERE = Path(__file__).parent
D_NOMINAL = 0.58e-3  # S230 in the library
TARGET_SPEED = 45.0  # micro.toml's target.velocity_m_s
DIAMETER_SPREAD, VELOCITY_SPREAD = 0.10, 0.05
UPSTREAM = {"target_velocity", "target_rev", "strip_rev", "target_impact", "target_indentation", "coverage_curve"}
# micro's 24-shot ladders are too short for a saturation fit with a scatter, so the run stops at the arc heights
REACHED = {"strip_runs", "arc_height", "target_runs", "residual_profile"}


def _run(study: Path, *args) -> str:
    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", "run", str(study), "--workers", "2", *args],
                          capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return proc.stdout


@pytest.fixture(scope="module")
def spread(micro, tmp_path_factory):
    """The micro study with spreads, run on a copy of the micro study's store: (study, run output)."""
    d = tmp_path_factory.mktemp("spread")
    shutil.copytree(micro.parent / ".peenflow", d / ".peenflow")
    study = d / "micro.toml"
    study.write_text((HERE / "micro.toml").read_text().replace(
        'type = "S230"', f'type = "S230"\ndiameter_spread_percent = {100 * DIAMETER_SPREAD:g}\n'
                         f'velocity_spread_percent = {100 * VELOCITY_SPREAD:g}'))
    return study, _run(study, "--until", "arc_height") + _run(study, "--until", "residual_profile")


def test_spreads_reach_the_rev_runs_and_what_follows_them_only(spread):
    _, out = spread
    st = statuses(out)
    stages = {}
    for point, status in st.items():
        stages.setdefault(point.split("[")[0], set()).add(status)
    assert {s for s in stages if stages[s] & {"reused"}} >= UPSTREAM
    assert all(stages[s] == {"computed"} for s in REACHED), out
    assert not UPSTREAM & {s for s in stages if "computed" in stages[s]}, out


def _scatter(values):
    v = np.concatenate([np.ravel(x) for x in values])
    v = v[np.isfinite(v)]
    return v.size, v.mean(), v.std()


def test_the_runs_shots_have_the_stated_scatter_and_the_nominal_runs_none(spread, micro):
    study, _ = spread
    strips, target = (peenflow.open_result(study, s).load() for s in ("strip_runs", "target_runs"))
    for stage in ("strip_runs", "target_runs"):
        nominal = peenflow.open_result(micro, stage).load()
        assert np.all(nominal.shot_diameter_m.values[np.isfinite(nominal.shot_diameter_m.values)] == D_NOMINAL)
    diameters = [strips.shot_diameter_m.values / D_NOMINAL, target.shot_diameter_m.values / D_NOMINAL]
    speeds = [(strips.impact_speed_m_s / strips.velocity_m_s).values, target.impact_speed_m_s.values / TARGET_SPEED]
    # n draws of a distribution of mean 1 and standard deviation s: within 4 standard errors
    # (s / sqrt(n) for the mean, s / sqrt(2 n) for the standard deviation)
    for values, s in ((diameters, DIAMETER_SPREAD), (speeds, VELOCITY_SPREAD)):
        n, mean, std = _scatter(values)
        assert n >= 100
        assert abs(mean - 1.0) < 4 * s / np.sqrt(n)
        assert abs(std - s) < 4 * s / np.sqrt(2 * n)
