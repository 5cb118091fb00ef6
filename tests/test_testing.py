"""peenflow.testing: the paper's constants come from the packaged library, and its checks can fail."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from peenflow.fe.johnson_cook import Material
from peenflow.testing import AL7075_T73, S230, SAE1070, _table, assert_cf_variables, assert_results_equal


def test_the_paper_s_materials_and_shot():
    # paper Table 1 (SAE 1070), Table 2 (Al 7075-T73), section 4 (S230: D = 0.58 mm)
    assert SAE1070 == dict(E=205e9, nu=0.29, density=7800.0, A=1408e6, B=600.8e6, n=0.234, C=0.0134, m=0.0,
                           ref_strain_rate=1.0)  # the stages' translation: every field a study sets
    assert (AL7075_T73["E"], AL7075_T73["A"], AL7075_T73["B"], AL7075_T73["n"]) == (71e9, 434e6, 303.58e6, 0.39)
    assert S230.diameter_m == pytest.approx(0.58e-3) and S230.radius_m == pytest.approx(0.29e-3)
    Material(**SAE1070), Material(**AL7075_T73)  # the kernel accepts them


def test_the_library_strips_are_sae_j442():
    strips = _table("strips")
    assert {k: strips[k]["thickness_mm"] for k in "NAC"} == {"N": 0.79, "A": 1.29, "C": 2.39}
    assert all(strips[k]["width_mm"] == 19.0 and strips[k]["gauge_span_mm"] == 31.75 for k in "NAC")


def _result(scale=1.0, units="m"):
    return xr.Dataset({"depth_m": (("layer",), np.array([1e-4, 2e-4]) * scale, {"units": units, "long_name": "d"})})


def test_result_checks_can_fail():
    assert_cf_variables(_result(), si=True)
    with pytest.raises(AssertionError, match="not SI"):
        assert_cf_variables(_result(units="mm"), si=True)
    with pytest.raises(AssertionError, match="no units"):
        assert_cf_variables(xr.Dataset({"x": (("a",), [1.0], {"long_name": "x"})}))
    assert_results_equal(_result(), _result(1 + 1e-13), rtol=1e-12)
    with pytest.raises(AssertionError, match="largest difference"):
        assert_results_equal(_result(), _result(1 + 1e-9), rtol=1e-12)
