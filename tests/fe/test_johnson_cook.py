"""Material point: the stress update reproduces Johnson-Cook (eq. 1) on uniaxial and shear paths."""

import numpy as np
import pytest

from peenflow.fe.johnson_cook import Material, material_point
from peenflow.testing import SAE1070



@pytest.mark.parametrize("rate", [0.5, 1e2, 1e4, 1e6])
def test_uniaxial_follows_jc_curve(rate):
    mat = Material(**SAE1070)
    out = material_point(mat, "uniaxial", rate, 0.2, n_steps=2000)
    pl = out["eps_p"] > 0.02
    # after yield the plastic rate equals the imposed rate minus the (vanishing) elastic rate
    expected = mat.flow_stress(out["eps_p"][pl], rate=out["eps_p_rate"][pl])
    # return mapping: von Mises stress on the JC surface to round-off; sigma_xx
    # equals it to the lateral-stress iteration tolerance
    np.testing.assert_allclose(out["von_mises"][pl], expected, rtol=1e-9)
    np.testing.assert_allclose(out["stress"][pl], expected, rtol=1e-8)
    # the plastic rate is the imposed one less the elastic share, which is
    # about E_t / E = n B eps_p^(n-1) / E ~ 2.5e-3 at eps_p ~ 0.19 (hence 5e-3)
    np.testing.assert_allclose(out["eps_p_rate"][pl][-100:], rate, rtol=5e-3)
    # against the closed form with the nominal rate: sigma = JC(eps_total - sigma/E, rate)
    eps_p_closed = out["strain"][-1] - out["stress"][-1] / mat.E
    assert out["eps_p"][-1] == pytest.approx(eps_p_closed, rel=2e-3)
    assert out["stress"][-1] == pytest.approx(mat.flow_stress(eps_p_closed, rate=rate), rel=1e-3)


def test_rate_term_is_standard_form_and_below_reference_has_no_effect():
    mat = Material(**SAE1070)
    slow = material_point(mat, "uniaxial", 0.5, 0.1)
    ref = material_point(mat, "uniaxial", 1.0, 0.1)
    fast = material_point(mat, "uniaxial", 1e4, 0.1)
    # below the reference rate: identical to the reference (no rate effect)
    assert slow["stress"][-1] == pytest.approx(ref["stress"][-1], rel=1e-6)
    # standard form 1 + C ln(rate): stronger at higher rate, by the JC factor
    ratio = fast["stress"][-1] / ref["stress"][-1]
    eps_ratio = mat.flow_stress(fast["eps_p"][-1]) / mat.flow_stress(ref["eps_p"][-1])
    assert ratio / eps_ratio == pytest.approx(1 + mat.C * np.log(1e4), rel=2e-3)


@pytest.mark.parametrize("rate", [1.0, 1e3, 1e5])
def test_pure_shear_follows_jc_curve(rate):
    mat = Material(**SAE1070)
    out = material_point(mat, "shear", rate, 0.3, n_steps=3000)
    pl = out["eps_p"] > 0.02
    tau = out["stress"][pl]
    expected = mat.flow_stress(out["eps_p"][pl], rate=out["eps_p_rate"][pl]) / np.sqrt(3.0)
    np.testing.assert_allclose(tau, expected, rtol=1e-9)
    # equivalent plastic strain of pure shear: (gamma - tau / mu) / sqrt(3)
    gamma_p = out["strain"][-1] - out["stress"][-1] / mat.mu
    assert out["eps_p"][-1] == pytest.approx(gamma_p / np.sqrt(3.0), rel=1e-6)


def test_elastic_below_yield():
    mat = Material(**SAE1070)
    out = material_point(mat, "uniaxial", 1.0, 0.5 * mat.A / mat.E, n_steps=200)
    assert np.all(out["eps_p"] == 0)
    np.testing.assert_allclose(out["stress"], mat.E * out["strain"], rtol=1e-9)


@pytest.mark.parametrize("key,value", [("A", -1.0), ("E", float("nan")), ("nu", 0.5), ("density", 0.0),
                                       ("n", 0.0), ("C", -0.01), ("T_melt", 200.0), ("taylor_quinney", 1.5)])
def test_parameter_validation_names_the_key(key, value):
    # bad input is refused when the material is made, naming the key and its value
    with pytest.raises(ValueError, match=rf"Material\.{key} = "):
        Material(**{**SAE1070, key: value})
