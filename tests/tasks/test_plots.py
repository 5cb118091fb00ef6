"""Figures from partial results: a failed point must not take the other points' figure with it."""

import numpy as np
import xarray as xr

import peenflow.report.plots as plots


def test_saturation_figure_survives_a_failed_fit(tmp_path, monkeypatch):
    # arc heights at two velocities, a saturation fit only at 55 m/s (the 30 m/s fit
    # failed with "cannot saturate", so the partial stage result has no 30 m/s row)
    shots = np.array([3, 6, 12, 24])
    arc = xr.Dataset(
        {"arc_height_m": (("angle_deg", "velocity_m_s", "sequence", "shots"),
                          1e-3 * np.array([[[[0.05, 0.09, 0.15, 0.24]], [[0.10, 0.16, 0.21, 0.24]]]]))},
        coords={"angle_deg": [90.0], "velocity_m_s": [30.0, 55.0], "sequence": [0], "shots": shots})
    fine = np.geomspace(3, 24, 20)
    sat = xr.Dataset(
        {"fit_arc_height_m": (("angle_deg", "velocity_m_s", "shots_fine"),
                              0.25e-3 * (1 - np.exp(-fine / 8))[None, None]),
         "saturation_shots": (("angle_deg", "velocity_m_s"), [[14.0]]),
         "intensity_m": (("angle_deg", "velocity_m_s"), [[0.22e-3]])},
        coords={"angle_deg": [90.0], "velocity_m_s": [55.0], "shots_fine": fine})
    results = {"arc_height": arc, "saturation": sat}
    monkeypatch.setattr(plots, "_result", lambda graph, store, stage: results.get(stage))
    written = plots.write_plots(None, None, tmp_path)
    assert [p.name for p in written] == ["saturation.png"]
    assert (tmp_path / "saturation.png").stat().st_size > 1000


def test_residual_stress_figure_says_what_it_shows(tmp_path, monkeypatch):
    """One sequence: no spread band and no 'mean +- spread' claim; markers on the layers;
    surface value, peak and compressive depth annotated; material and intensity named."""
    import matplotlib.collections
    import matplotlib.pyplot as plt

    z = np.array([0.03, 0.09, 0.15, 0.21, 0.27, 0.33, 0.39]) * 1e-3
    sxx = np.array([-422.0, -440.0, -450.0, -381.0, -233.0, -49.0, -2.4]) * 1e6
    prof = xr.Dataset(
        {"stress_xx_mean_Pa": ("layer", sxx), "stress_yy_mean_Pa": ("layer", sxx + 3e6),
         "stress_xx_spread_Pa": ("layer", np.zeros(7)), "stress_yy_spread_Pa": ("layer", np.zeros(7)),
         "stress_xx_Pa": (("sequence", "layer"), sxx[None]),
         "peak_compressive_xx_Pa": ((), -450e6), "peak_compressive_xx_depth_m": ((), 0.15e-3)},
        coords={"depth_m": ("layer", z), "sequence": [0]})
    tv = xr.Dataset({"velocity_m_s": ((), 47.2), "intensity_m": ((), 0.4e-3)})
    results = {"residual_profile": prof, "target_velocity": tv}
    monkeypatch.setattr(plots, "_result", lambda graph, store, stage: results.get(stage))
    figures = []
    monkeypatch.setattr(plt.Figure, "savefig", lambda self, *a, **k: figures.append(self))
    plots.write_plots(None, None, tmp_path, {"target_material": "Al7075-T73", "shot": "S230"})
    (ax,) = figures[0].axes
    title = ax.get_title()
    assert "one sequence" in title and "±" not in title and "+-" not in title
    assert "Al7075-T73" in title and "0.4 mm" in title and "held" in title
    assert not any(isinstance(c, matplotlib.collections.PolyCollection) for c in ax.collections)  # no band
    assert all(line.get_marker() not in (None, "None", "") for line in ax.get_lines()[:2])
    notes = " ".join(t.get_text() for t in ax.texts)
    assert "surface -422 MPa" in notes and "peak -450 MPa at 0.150 mm" in notes
    assert any("compressive to" in t.get_text() for t in ax.get_legend().get_texts())


def test_control_curve_figure_shows_both_levels_of_an_extrapolation(tmp_path, monkeypatch):
    """With an intensity extrapolation the figure plots the extrapolated intensities and, beside them,
    each level's (at their values) and names the levels and the order in the legend."""
    import matplotlib.pyplot as plt

    v = np.array([25.0, 35.0])
    dims = ("angle_deg", "velocity_m_s")
    control = xr.Dataset(
        {"intensity_m": (dims, [[0.30e-3, 0.36e-3]]), "intensity_std_m": (dims, [[0.0, 0.0]]),
         "curve_intensity_m": (("angle_deg", "velocity_fine_m_s"), [[0.30e-3, 0.36e-3]])},
        coords={"angle_deg": [67.5], "velocity_m_s": v, "velocity_fine_m_s": v})
    ext = xr.Dataset({"fine_intensity_m": (dims, [[0.285e-3, 0.347e-3]]),
                      "coarse_intensity_m": (dims, [[0.266e-3, 0.331e-3]])},
                     coords={"angle_deg": [67.5], "velocity_m_s": v},
                     attrs={"coarse_element_size_m": 40e-6, "fine_element_size_m": 25e-6, "order": 1.85})
    results = {"control_curve": control, "intensity_extrapolation": ext}
    monkeypatch.setattr(plots, "_result", lambda graph, store, stage: results.get(stage))
    figures = []
    monkeypatch.setattr(plt.Figure, "savefig", lambda self, *a, **k: figures.append(self))
    plots.write_plots(None, None, tmp_path)
    (ax,) = figures[0].axes
    ys = [np.round(np.asarray(line.get_ydata(), float), 4).tolist() for line in ax.get_lines()]
    assert [0.285, 0.347] in ys and [0.266, 0.331] in ys
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "25 um level" in labels and "40 um level" in labels
    assert any("extrapolated to zero element size (order 1.85)" in t for t in labels)
