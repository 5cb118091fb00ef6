"""Paired two-level mesh extrapolation (peenflow/methods/mesh_extrapolation.py, eqs. R1-R3)."""

import numpy as np
import pytest

from peenflow.methods import extrapolation_factor, paired_correction, two_level_limit


@pytest.mark.parametrize("p", [1.0, 1.85, 2.0, 3.0])
def test_an_exact_power_law_gives_its_limit(p):
    """f(h) = f0 + c h^p through any two levels extrapolates to f0 exactly (to rounding)."""
    f0, c = 0.30e-3, -2.0e-5 * 1e6**p  # m, per m^p: ~ -0.06 mm at 40 um for p = 1.85
    f = lambda h: f0 + c * h**p  # noqa: E731
    for hc, hf in ((40e-6, 25e-6), (60e-6, 40e-6), (25e-6, 16e-6)):
        assert two_level_limit(f(hc), f(hf), hc, hf, p) == pytest.approx(f0, rel=1e-12, abs=1e-18)


def test_the_factor_is_the_richardson_one():
    # k = h_f^p / (h_c^p - h_f^p): ratio 2 and order 2 give the classical 1/3
    assert extrapolation_factor(2.0, 1.0, 2.0) == pytest.approx(1.0 / 3.0, rel=1e-15)
    assert extrapolation_factor(40e-6, 25e-6, 1.85) == pytest.approx(1.0 / (1.6**1.85 - 1.0), rel=1e-12)


@pytest.mark.parametrize("bad", [(25e-6, 40e-6, 1.85), (25e-6, 25e-6, 1.85), (40e-6, 25e-6, 0.0)])
def test_levels_in_the_wrong_order_are_refused(bad):
    with pytest.raises(ValueError, match="h_coarse > h_fine"):
        extrapolation_factor(*bad)


def test_pairing_removes_noise_common_to_both_levels():
    """Sequences whose intensities carry the same sampling noise at both levels (same shot streams):
    the paired correction is the exact mesh correction k (I_f - I_c) of the noise-free values, with
    zero standard error, whatever the noise."""
    rng = np.random.default_rng(3)
    noise = rng.normal(0.0, 5e-6, 6)  # m, per sequence
    i_f, i_c, hc, hf, p = 0.30e-3, 0.28e-3, 40e-6, 25e-6, 1.85
    fine = {s: i_f + n for s, n in enumerate(noise)}
    coarse = {s: i_c + n for s, n in enumerate(noise)}
    c = paired_correction(fine, coarse, hc, hf, p)
    k = extrapolation_factor(hc, hf, p)
    assert c.correction == pytest.approx(k * (i_f - i_c), rel=1e-9)
    assert c.standard_error == pytest.approx(0.0, abs=1e-15) and c.pairs == 6 and c.factor == k


def test_only_sequences_both_levels_ran_are_paired():
    """The fine level grew a third sequence, the coarse one lost one to NaN: the correction comes from
    the one sequence with a value at both levels; with none it is refused."""
    fine = {0: 3.0, 1: 3.1, 2: 2.0}
    coarse = {0: 2.5, 1: np.nan}
    c = paired_correction(fine, coarse, 2.0, 1.0, 2.0)
    assert c.pairs == 1 and c.correction == pytest.approx((3.0 - 2.5) / 3.0) and np.isnan(c.standard_error)
    with pytest.raises(ValueError, match="no sequence has a finite value at both levels"):
        paired_correction({0: 1.0}, {1: 1.0}, 2.0, 1.0, 2.0)
