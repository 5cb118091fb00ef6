"""Stage trends on tiny scenes, through the real command: faster shots leave
bigger dents and need a larger d_min; the arc height saturates with N."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import peenflow

HERE = Path(__file__).parent


def _study(tmp_path: Path, name: str, replace: dict) -> Path:
    text = (HERE / "trends.toml").read_text().replace('name = "trends"', f'name = "{name}"')
    for old, new in replace.items():
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def _run(study: Path, until: str) -> None:
    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", "run", str(study), "--until", until, "--quiet"],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr


@pytest.fixture(scope="module")
def by_velocity(tmp_path_factory):
    """Single impact, dent and d_min search at 30 and 55 m/s (60 um elements)."""
    out = {}
    for v in (30.0, 55.0):
        study = _study(tmp_path_factory.mktemp(f"v{v:g}"), f"trend{v:g}",
                       {"strip_velocity_m_s = 55.0": f"strip_velocity_m_s = {v}"})
        _run(study, "strip_dmin")
        _run(study, "strip_indentation")
        out[v] = (peenflow.open_result(study, "strip_indentation").squeeze(),
                  peenflow.open_result(study, "strip_dmin").squeeze())
    return out


def test_the_dent_grows_with_velocity(by_velocity):
    slow, fast = by_velocity[30.0][0], by_velocity[55.0][0]
    assert float(fast.dent_semi_axis_along_m) > float(slow.dent_semi_axis_along_m)
    # Johnson's fully plastic depth scales as V (deeper by 55/30 = 1.8); hardening
    # and spring-back reduce it, but the dent must deepen by well over 30 %.
    assert float(fast.dent_depth_m) > 1.3 * float(slow.dent_depth_m)


def test_dmin_grows_with_velocity_by_more_than_the_search_resolution(by_velocity):
    slow, fast = by_velocity[30.0][1], by_velocity[55.0][1]
    assert float(fast.d_min_m) - float(slow.d_min_m) > 2 * float(fast.resolution_m)


def test_arc_height_saturates_on_a_small_strip_rev(tmp_path):
    """On a 1.2 mm REV full coverage takes ~100 shots at 55 m/s: over the ladder
    6 ... 384 the first doublings add most of the arc height, the last two add
    less than eq. (11)'s 10 % each, and eq. (11)'s T lies inside the ladder."""
    study = _study(tmp_path, "saturating", {
        'sequences = 1\n': 'sequences = 1\nrev_rule = "explicit"\nrev_size_mm = 1.2\nmeasure_size_mm = 0.4\n',
        "element_size_um = 60.0": "element_size_um = 100.0"})
    _run(study, "saturation")
    sat = peenflow.open_result(study, "saturation").squeeze()
    h = sat.mean_arc_height_m.values
    n = sat.shots.values
    assert np.all(h > 0)
    assert h[1] > 1.5 * h[0]  # the first doubling adds more than half
    assert (h[-1] / h[-3]) ** 0.5 - 1.0 < 0.10  # the last two doublings: < 10 % each on average
    assert n[0] <= float(sat.saturation_shots) <= n[-1] and int(sat.intensity_extrapolated) == 0
