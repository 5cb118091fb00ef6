"""Paired two-level mesh extrapolation of a study-level output (issue 10 §3-§4).

A quantity computed on meshes of element size h converges as

    f(h) = f0 + c h^p + o(h^p)                                               (R1)

so two levels h_c > h_f give the limit (Richardson extrapolation with a known order)

    f0 ~= f_f + (f_f - f_c) h_f^p / (h_c^p - h_f^p) = f_f + k (f_f - f_c),   (R2)
    k = h_f^p / (h_c^p - h_f^p).

Why paired: both levels run the *same* random shot streams (the same seeds), so a
sequence's fine-minus-coarse difference is almost free of the sampling noise of the
sequences themselves (the per-sequence intensities of one point spread by 0.001-0.008 mm,
their fine-minus-coarse differences by 0.001-0.003 mm: the study-level references,
peenflow/validation/data/study_level.json).
The correction is therefore taken from per-sequence differences over the sequences both
levels ran, and added to the fine level's own value:

    f0 ~= f_f + k mean_s (f_f,s - f_c,s)                                       (R3)

with the standard error of that mean times k as the correction's sampling error.  The
order p is not fitted from the two levels (two levels cannot give it): it is measured
once on converged references (40 / 25 / 16 um strip points, docs/validation.md section 9) and
stated with every result.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["extrapolation_factor", "two_level_limit", "PairedCorrection", "paired_correction"]


def extrapolation_factor(h_coarse: float, h_fine: float, order: float) -> float:
    """k of eq. (R2): h_f^p / (h_c^p - h_f^p); needs h_coarse > h_fine > 0 and order > 0."""
    if not (h_coarse > h_fine > 0.0) or not order > 0.0:
        raise ValueError(f"two-level extrapolation needs h_coarse > h_fine > 0 and order > 0; got "
                         f"h_coarse = {h_coarse!r}, h_fine = {h_fine!r}, order = {order!r}")
    return h_fine**order / (h_coarse**order - h_fine**order)


def two_level_limit(f_coarse, f_fine, h_coarse: float, h_fine: float, order: float):
    """The limit f0 of eq. (R1) through two levels, eq. (R2) (works on arrays; any unit)."""
    return f_fine + extrapolation_factor(h_coarse, h_fine, order) * (np.asarray(f_fine) - np.asarray(f_coarse))


@dataclass(frozen=True)
class PairedCorrection:
    """Eq. (R3): ``correction`` (added to the fine level's value), its ``standard_error``
    (NaN from a single pair), ``factor`` k, and ``pairs``: how many sequences both levels have."""

    correction: float
    standard_error: float
    factor: float
    pairs: int


def paired_correction(fine_by_sequence: dict, coarse_by_sequence: dict, h_coarse: float, h_fine: float,
                      order: float) -> PairedCorrection:
    """Eq. (R3) from ``{sequence: value}`` of each level (NaN values are skipped).

    Raises ValueError when the levels share no sequence with finite values (the
    correction would not be paired, or not defined).
    """
    k = extrapolation_factor(h_coarse, h_fine, order)
    common = sorted(set(fine_by_sequence) & set(coarse_by_sequence))
    diffs = np.array([fine_by_sequence[s] - coarse_by_sequence[s] for s in common], dtype=float)
    diffs = diffs[np.isfinite(diffs)]
    if diffs.size == 0:
        raise ValueError(f"no sequence has a finite value at both levels (fine: {sorted(fine_by_sequence)}, "
                         f"coarse: {sorted(coarse_by_sequence)}): the correction cannot be paired")
    se = float(np.std(diffs, ddof=1) / np.sqrt(diffs.size)) if diffs.size > 1 else float("nan")
    return PairedCorrection(float(k * diffs.mean()), k * se, k, int(diffs.size))
