import numpy as np
import pytest

from peenflow.engine.canonical import ParameterError, canonical_json


def test_float_noise_and_integral_floats_do_not_change_the_text():
    assert canonical_json({"v": 0.1 + 0.2}) == canonical_json({"v": 0.3})
    assert canonical_json({"v": 55.0}) == canonical_json({"v": 55})
    assert canonical_json({"v": np.float32(0.5)}) == canonical_json({"v": 0.5})


def test_dict_order_does_not_matter_but_values_do():
    assert canonical_json({"a": 1, "b": [1, 2]}) == canonical_json({"b": [1, 2], "a": 1})
    assert canonical_json({"a": 1.0}) != canonical_json({"a": 1.000001})
    assert canonical_json({"a": [1, 2]}) != canonical_json({"a": [2, 1]})


def test_nan_and_inf_are_spelled_out():
    assert canonical_json([float("nan"), float("inf"), -float("inf")]) == '["nan","inf","-inf"]'


def test_objects_are_rejected_with_their_path():
    with pytest.raises(ParameterError, match=r"params.mesh.spacing"):
        canonical_json({"mesh": {"spacing": object()}})


def test_sweep_points_with_ragged_dims_combine_with_padding():
    import xarray as xr

    from peenflow.engine.combine import combine_points

    a = xr.Dataset({"d": ("run", [1.0, 2.0, 3.0])})
    b = xr.Dataset({"d": ("run", [4.0, 5.0])})
    c = combine_points([a, b], [{"angle": 45}, {"angle": 90}], ["angle"])
    assert c.d.shape == (2, 3)
    assert c.d.sel(angle=90).values[:2].tolist() == [4.0, 5.0] and np.isnan(c.d.sel(angle=90).values[2])
