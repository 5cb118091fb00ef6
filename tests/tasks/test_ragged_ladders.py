"""Sequences of one point with different ladders (almen.shot_counts = "auto") through the real
combine, arc_height and saturation stages: NaN where a sequence did not go, the exact intensity."""

import numpy as np
import pytest
import xarray as xr

from peenflow.engine.combine import combine_points
from peenflow.methods.saturation import eq10_saturation_x
from tasks.arc_height import arc_height, release
from tasks.params import StripParams
from tasks.saturation import saturation

STRIP = StripParams(width_m=19e-3, thickness_m=1.29e-3, youngs_modulus_Pa=200e9, gauge_span_m=31.75e-3)
B, D, P = -0.3e-3 * 60**0.8, 60.0, 0.8


def _growth(n):
    """Eq. (10) shape (dimensionless): the arc height is linear in the stress, so a profile scaled by it
    has arc heights on that curve."""
    n = np.asarray(n, float)
    return (B / (n + D) ** P - B / D**P) / 1e-4


def _run(ladder, edges, shape):
    return xr.Dataset({"stress_xx_Pa": (("shots", "layer"), _growth(ladder)[:, None] * shape[None, :])},
                      coords={"shots": np.array(ladder), "z_edge_m": ("z_edge", edges)})


def test_ragged_ladders_combine_padded_and_give_the_exact_intensity():
    edges = np.linspace(0.0, 1.29e-3, 27)
    mid = 0.5 * (edges[1:] + edges[:-1])
    shape = np.where(mid < 0.2e-3, -500e6, 60e6)  # compressive layer over a tensile core
    long, short = [10, 20, 40, 80, 160, 320, 640], [10, 20, 40, 80, 160]
    runs = combine_points([_run(long, edges, shape), _run(short, edges, shape)],
                          [{"sequence": 0}, {"sequence": 1}], ["sequence"])
    arc = arc_height(runs, strip=STRIP)
    ah = arc.arc_height_m.transpose("sequence", "shots").values
    assert np.isnan(ah[1, 5:]).all() and np.isfinite(ah[1, :5]).all() and np.isfinite(ah[0]).all()
    unit = release(edges, shape, STRIP)[0]
    np.testing.assert_allclose(ah[0], _growth(long) * unit, rtol=1e-12)
    sat = saturation(arc, fit="paper")
    T = D * eq10_saturation_x(P)
    assert float(sat.saturation_shots) == pytest.approx(T, rel=1e-5)
    assert float(sat.intensity_m) == pytest.approx(_growth(T) * unit, rel=1e-5)
    assert int(sat.intensity_extrapolated) == 0
    # each sequence's own fit: both find T (noiseless), only the long ladder (to 640) brackets T = 380
    np.testing.assert_allclose(sat.sequence_saturation_shots.values, T, rtol=1e-4)
    assert sat.sequence_extrapolated.values.tolist() == [0, 1]
