"""Figures from partial results: a failed point must not take the other points' figure with it."""

import numpy as np
import xarray as xr

import tasks.plots as plots


def test_saturation_figure_survives_a_failed_fit(tmp_path, monkeypatch):
    # arc heights at two velocities, a saturation fit only at 55 m/s (the 30 m/s fit
    # failed with "cannot saturate", so the partial stage result has no 30 m/s row)
    shots = np.array([3, 6, 12, 24])
    arc = xr.Dataset(
        {"arc_height_mm": (("angle_deg", "velocity_m_s", "sequence", "shots"),
                           np.array([[[[0.05, 0.09, 0.15, 0.24]], [[0.10, 0.16, 0.21, 0.24]]]]))},
        coords={"angle_deg": [90.0], "velocity_m_s": [30.0, 55.0], "sequence": [0], "shots": shots})
    fine = np.geomspace(3, 24, 20)
    sat = xr.Dataset(
        {"fit_arc_height_mm": (("angle_deg", "velocity_m_s", "shots_fine"), 0.25 * (1 - np.exp(-fine / 8))[None, None]),
         "saturation_shots": (("angle_deg", "velocity_m_s"), [[14.0]]),
         "intensity_mm": (("angle_deg", "velocity_m_s"), [[0.22]])},
        coords={"angle_deg": [90.0], "velocity_m_s": [55.0], "shots_fine": fine})
    results = {"arc_height": arc, "saturation": sat}
    monkeypatch.setattr(plots, "_result", lambda graph, store, stage: results.get(stage))
    written = plots.write_plots(None, None, tmp_path)
    assert [p.name for p in written] == ["saturation.png"]
    assert (tmp_path / "saturation.png").stat().st_size > 1000
