"""Saturation fits: eq. (10) recovery, eq. (11) by substitution, SAE-style fits, errors."""

import numpy as np
import pytest

from peenflow.methods.saturation import GROWTH_RATIO, fit_saturation, fit_sequences

N = np.array([10, 20, 40, 80, 160, 320, 480], dtype=float)  # the paper's ladder (§4)


def eq10_paper(n, B, d, p):
    """Eq. (10) exactly as printed in the paper."""
    return B / (n + d) ** p - B / d**p


@pytest.mark.parametrize("B,d,p", [(-0.3e-3 * 60**0.8, 60.0, 0.8), (-2e-3 * 15**2.5, 15.0, 2.5), (1e-5 * 40**-0.06, 40.0, -0.06)])
def test_eq10_recovers_parameters_and_eq11_holds(B, d, p):
    y = eq10_paper(N, B, d, p)
    fit = fit_saturation(N, y, "eq10")
    q = fit.parameters
    assert q["d"] == pytest.approx(d, rel=1e-4)
    assert q["p"] == pytest.approx(p, rel=1e-4, abs=1e-6)
    assert q["B"] == pytest.approx(B, rel=1e-3)
    assert fit.residual_rms < 1e-8 * np.max(y)
    # eq. (11) by substitution, using the paper's own form of eq. (10)
    ns = fit.saturation_shots
    assert eq10_paper(2 * ns, B, d, p) == pytest.approx(GROWTH_RATIO * eq10_paper(ns, B, d, p), rel=1e-6)
    assert fit.intensity == pytest.approx(eq10_paper(ns, B, d, p), rel=1e-6)


def test_exp2_closed_form_saturation():
    a, b = 0.35e-3, 1 / 70.0
    fit = fit_saturation(N, a * (1 - np.exp(-b * N)), "exp2")
    assert fit.parameters["b"] == pytest.approx(b, rel=1e-6)
    # 1 + exp(-b N) = 1.1  =>  N = ln 10 / b, Ah = 0.9 a
    assert fit.saturation_shots == pytest.approx(np.log(10) / b, rel=1e-6)
    assert fit.intensity == pytest.approx(0.9 * a, rel=1e-6)
    assert not fit.extrapolated


def test_exp3_recovers_and_reduces_to_exp2():
    a, b, c = 0.3e-3, 0.02, 0.7
    y = a * (1 - np.exp(-b * N**c))
    fit = fit_saturation(N, y, "exp3")
    assert fit.parameters["c"] == pytest.approx(c, rel=1e-4)
    ns = fit.saturation_shots
    model = lambda n: a * (1 - np.exp(-b * n**c))  # noqa: E731
    assert model(2 * ns) == pytest.approx(1.1 * model(ns), rel=1e-6)
    y2 = 0.3e-3 * (1 - np.exp(-N / 90.0))
    f3, f2 = fit_saturation(N, y2, "exp3"), fit_saturation(N, y2, "exp2")
    assert f3.parameters["c"] == pytest.approx(1.0, rel=1e-4)
    assert f3.saturation_shots == pytest.approx(f2.saturation_shots, rel=1e-4)


def test_sequences_mean_and_spread():
    # 6 sequences = one eq. (10) curve + independent noise of 1 % of the asymptote.
    rng = np.random.default_rng(7)
    d, p, ainf = 50.0, 1.0, 0.3e-3
    base = ainf * (1 - (1 + N / d) ** -p)
    y = base + 0.01 * ainf * rng.standard_normal((6, N.size))
    res = fit_sequences(N, y, "eq10")
    assert all(e is None for e in res.errors)
    true = fit_saturation(N, base, "eq10").intensity
    vals = np.array([f.intensity for f in res.fits])
    assert res.intensity_std == pytest.approx(vals.std(ddof=1))
    assert res.intensity_min <= res.intensity_mean <= res.intensity_max
    # the per-sequence intensities scatter around the truth: t-test at ~4 standard errors
    assert abs(res.intensity_mean - true) < 4 * res.intensity_std / np.sqrt(6)


def test_decreasing_data_raises():
    with pytest.raises(ValueError, match="does not increase"):
        fit_saturation(N, 1e-3 * np.exp(-N / 100), "eq10")
    with pytest.raises(ValueError, match="does not increase"):
        fit_saturation(N, -1e-4 * np.log(N), "exp2")


def test_too_few_points_raise():
    with pytest.raises(ValueError, match=">= 3 distinct"):
        fit_saturation([10, 20, 20], [1e-4, 2e-4, 2e-4])


def test_unbounded_power_growth_cannot_saturate():
    # Ah ∝ N^0.5 grows by 41 % per doubling for ever: no eq. (11) root.
    with pytest.raises(ValueError, match="cannot saturate"):
        fit_saturation(N, 1e-5 * np.sqrt(N), "eq10")


def test_failed_sequence_is_recorded_not_fatal():
    good = 0.3e-3 * (1 - np.exp(-N / 60))
    bad = np.full(N.size, np.nan)
    bad[:2] = [1e-4, 2e-4]
    res = fit_sequences(N, np.vstack([good, bad]), "exp2")
    assert res.fits[1] is None and ">= 3 distinct" in res.errors[1]
    assert res.fits[0] is not None


def test_ragged_ladders_pool_their_points_and_equal_ladders_fit_the_mean_curve():
    """Sequences that stopped at different rungs (almen.shot_counts = "auto"): NaN-padded rows."""
    B, d, p = -0.3e-3 * 60**0.8, 60.0, 0.8
    exact = fit_saturation(N, eq10_paper(N, B, d, p))
    y = np.vstack([eq10_paper(N, B, d, p)] * 2)
    y[1, 5:] = np.nan  # the second sequence stopped at 160 shots
    ragged = fit_sequences(N, y)
    assert ragged.mean_fit.intensity == pytest.approx(exact.intensity, rel=1e-6)
    assert ragged.mean_fit.saturation_shots == pytest.approx(exact.saturation_shots, rel=1e-6)
    assert ragged.mean_fit.counts.size == 7 + 5  # every measured point once, none invented
    # equal ladders: the mean-curve fit, whose minimiser the pooled least squares shares
    rng = np.random.default_rng(3)
    noisy = eq10_paper(N, B, d, p) * (1 + 0.03 * rng.standard_normal((4, N.size)))
    mean = fit_sequences(N, noisy).mean_fit
    pooled = fit_saturation(np.tile(N, 4), noisy.ravel())
    assert mean.intensity == pytest.approx(pooled.intensity, rel=1e-6)
    assert mean.saturation_shots == pytest.approx(pooled.saturation_shots, rel=1e-5)
