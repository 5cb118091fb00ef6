"""A target intensity given as measured Almen strips (``target.almen_strips_csv``), through ``peenflow run``.

The strips are an exact SAE J2597 two-parameter curve h(t) = a (1 - exp(-b t)): its saturation point T has
h(2T) = 1.1 h(T), so exp(-b T) = 0.1 and the intensity is h(T) = 0.9 a -- the solver must return it, the
velocity must be read off the control curve at it, and the result must say which fit made it."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import pytest

import peenflow

HERE = Path(__file__).parent
MAP = (HERE / "micro_map.toml").read_text()
INTENSITY_MM = 0.33  # inside the micro control curve (0.30 and 0.38 mm are mapped there)
T_MIN = 4.0


def _strips(path: Path, exposures=(1.0, 2.0, 4.0, 8.0, 16.0)) -> Path:
    a, b = INTENSITY_MM / 0.9, math.log(10.0) / T_MIN
    rows = [f"{t:g},{a * (1 - math.exp(-b * t)):.6f}" for t in exposures]
    path.write_text("# exact exp2 strips\ntime_min,arc_height_mm\n" + "\n".join(rows) + "\n")
    return path


def _study(d: Path, target_lines: str) -> Path:
    text = MAP.replace('name = "micro_map"', 'name = "strips"').replace(
        "almen_intensity_mm = [0.30, 0.38]\nalmen_strip = \"A\"", target_lines).replace(
        "coverage_percent = [100.0, 200.0]", "coverage_percent = 100.0")
    path = d / "strips.toml"
    path.write_text(text)
    return path


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "peenflow.cli", *map(str, args)], capture_output=True, text=True,
                          timeout=900)


def test_measured_strips_set_the_target_intensity_and_the_result_records_the_fit(tmp_path):
    _strips(tmp_path / "strips.csv")
    study = _study(tmp_path, 'almen_strips_csv = "strips.csv"\nalmen_strip = "A"')
    proc = _cli("run", study, "--until", "target_velocity")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    vel = peenflow.open_result(study, "target_velocity").load()
    assert float(vel.intensity_m) == pytest.approx(INTENSITY_MM * 1e-3, rel=1e-4)
    source = vel.attrs["peenflow_target_intensity_source"]
    assert source.startswith("measured strips strips.csv") and "5 strips at 5 exposures" in source
    assert "NOT QUALIFIED" not in source
    # the verb reads the same file to the same intensity
    verb = _cli("intensity", tmp_path / "strips.csv", "--strip", "A")
    assert verb.returncode == 0 and f"{float(vel.intensity_m) * 1e3:.4f} mm" in verb.stdout
    # the velocity lies between the mapped intensities' (0.30 and 0.38 mm at 90 deg)
    control = peenflow.open_result(study, "control_curve").load().sel(angle_deg=90.0)
    assert control.velocity_m_s.values.min() < float(vel.velocity_m_s) < control.velocity_m_s.values.max()


@pytest.mark.parametrize("target_lines, csv_exposures, expected", [
    ('almen_strips_csv = "strips.csv"\nalmen_strip = "A"', (1.0, 2.0, 4.0),
     "target.almen_strips_csv: "),  # fewer than 4 exposures: the solver's refusal, named by the key
    ('almen_strips_csv = "strips.csv"', (1.0, 2.0, 4.0, 8.0, 16.0), "target.almen_strips_csv needs target.almen_strip"),
    ('almen_strips_csv = "strips.csv"\nalmen_intensity_mm = 0.3\nalmen_strip = "A"', (1.0, 2.0, 4.0, 8.0, 16.0),
     "give exactly one of"),
    ('almen_strips_csv = "nowhere.csv"\nalmen_strip = "A"', (1.0, 2.0, 4.0, 8.0, 16.0), "measured strips not found"),
])
def test_unusable_strips_are_refused_before_compute(tmp_path, target_lines, csv_exposures, expected):
    _strips(tmp_path / "strips.csv", csv_exposures)
    study = _study(tmp_path, target_lines)
    proc = _cli("check", study)
    assert proc.returncode == 2 and expected in proc.stdout + proc.stderr, proc.stdout + proc.stderr
    assert "Traceback" not in proc.stderr
    assert not (tmp_path / ".peenflow").exists()
