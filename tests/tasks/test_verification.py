"""``[requirements] verify = true`` through ``peenflow run`` on the micro map (tests/tasks/micro_map.toml).

A suggestion on a map level must compute to exactly what the map holds there (the verification reruns the
map's own shot stream and stops at that level's N_c); a suggestion between two levels is computed at its own
N_c = (coverage / 100) N_f, and its compressive depth must lie between the two levels' (the compressive layer
deepens with coverage); a verification that cannot be made is refused before compute."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import peenflow

from .conftest import cli

HERE = Path(__file__).parent
MAP = (HERE / "micro_map.toml").read_text()




def _study(d: Path, name: str, requirements: str) -> Path:
    i, j = MAP.index("[requirements]"), MAP.index("[fidelity]")
    path = d / f"{name}.toml"
    path.write_text(MAP[:i].replace('name = "micro_map"', f'name = "{name}"') + requirements + "\n" + MAP[j:])
    return path


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Two studies beside one store (the map is computed once): a suggestion on the 100 % level and one
    between 100 and 200 %."""
    d = tmp_path_factory.mktemp("verify")
    on_level = _study(d, "on_level", '[requirements]\ncompressive_depth_mm = { min = 0.2 }\n'
                                     'surface_stress_MPa = { max = -250.0 }\nminimise = "coverage_percent"\n'
                                     'verify = true\n')
    between = _study(d, "between", '[requirements]\ncompressive_depth_mm = { min = 0.38 }\n'
                                   'minimise = "coverage_percent"\nverify = true\n')
    return {s.stem: (s, cli("run", s, "--workers", "2").stdout) for s in (on_level, between)}


def test_a_suggestion_on_a_map_level_computes_to_the_maps_value(runs):
    study, out = runs["on_level"]
    sug = peenflow.open_result(study, "suggested_settings").load()
    v = peenflow.open_result(study, "verified_settings").load()
    assert int(sug.met) == 1 and float(sug.attrs["selected_coverage_percent"]) == 100.0
    assert int(v.verified) == 1 and int(v.met_computed) == 1
    np.testing.assert_allclose(v.computed_value.values, v.predicted_value.values, rtol=1e-9)
    # only the chosen point's runs were made: the others returned at once
    vr = peenflow.open_result(study, "verify_runs").load()
    assert int(vr.selected.sum()) == 1 and "suggestion computed" in out


def test_a_suggestion_between_levels_is_computed_at_its_own_coverage(runs):
    study, out = runs["between"]
    sug = peenflow.open_result(study, "suggested_settings").load()
    v = peenflow.open_result(study, "verified_settings").load()
    level = float(sug.attrs["selected_coverage_percent"])
    assert 100.0 < level < 200.0
    pmap = peenflow.open_result(study, "process_map").load()
    point = pmap.isel(almen_intensity_m=int(sug.attrs["selected_index_almen_intensity_m"]))
    n_f = float(point.full_coverage_shots)
    assert int(v.attrs["coverage_shots"]) == math.ceil(level / 100.0 * n_f)
    depth = float(v.computed_value.values[0])
    low, high = (float(point.compressive_depth_xx_m.sel(coverage_percent=c)) for c in (100.0, 200.0))
    assert low < depth < high
    assert "computed at" in v.attrs["verdict"] and "predicted" in v.attrs["verdict"]
    report = next((study.parent / ".peenflow" / "reports").glob("between-*/report.html")).read_text()
    assert "The suggestion computed" in report and "predicted by the map" in report


def test_verify_needs_a_coverage_to_minimise(tmp_path):
    study = _study(tmp_path, "bad", '[requirements]\ncompressive_depth_mm = { min = 0.2 }\n'
                                    'minimise = "almen_intensity_m"\nverify = true\n')
    proc = cli("run", study, check=False)
    assert proc.returncode != 0 and "requirements" in proc.stderr and 'minimise = "coverage_percent"' in proc.stderr
    assert not (tmp_path / ".peenflow" / "results").exists()
