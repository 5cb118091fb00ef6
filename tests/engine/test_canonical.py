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
