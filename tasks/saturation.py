"""Stage ``saturation``: saturation curve fits and the Almen intensity (paper eqs. 10-11).

Per (angle, velocity): each sequence's arc heights Ah(N) are fitted (eq. 10
by least squares, or the SAE J2597-style exponentials), the saturation point
solves Ah(2N) = 1.1 Ah(N) (eq. 11), and the intensity is Ah there.  The
curve of the sequence-mean arc heights is fitted too; its intensity is the
one the control curve uses, the per-sequence spread is reported beside it.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from peenflow.methods import fit_sequences

from ._common import peening_task, var
from .outputs import Output, Outputs
from .params import SequencesParams

MODELS = {"paper": "eq10", "exponential_2p": "exp2", "exponential_3p": "exp3"}

_EXTRAPOLATED = {"flag_values": np.array([0, 1]), "flag_meanings": "within_ladder extrapolated"}

OUTPUTS = Outputs(
    "saturation",
    intensity_m=Output((), "m", "Almen intensity from the mean curve (eq. 11)"),
    saturation_shots=Output((), "1", "saturation point T: N solving Ah(2N) = 1.1 Ah(N)"),
    intensity_extrapolated=Output((), "1", "1 if the saturation point lies outside the shot ladder",
                                  attrs=_EXTRAPOLATED),
    sequence_intensity_m=Output(("sequence",), "m", "per-sequence intensity"),
    sequence_saturation_shots=Output(("sequence",), "1", "per-sequence saturation point T"),
    sequence_extrapolated=Output(("sequence",), "1", "1 if the sequence's saturation point lies outside the shot "
                                                     "ladder", attrs=_EXTRAPOLATED),
    intensity_std_m=Output((), "m", "spread over sequences (ddof=1)"),
    fit_arc_height_m=Output(("shots_fine",), "m", "fitted mean curve"),
    mean_arc_height_m=Output(("shots",), "m", "arc height, mean over sequences"),
    fit_residual_rms_m=Output((), "m", "RMS residual of the mean-curve fit"),
    intensity_standard_error_m=Output((), "m", "standard error of the per-sequence intensities' mean",
                                      optional=True),
    intensity_standard_error_bound_m=Output((), "m", "95 % upper confidence bound of that standard error",
                                            optional=True),
    sequence_tolerance_met=Output((), "1", "1 if the bound is within the tolerance", optional=True,
                                  attrs={"flag_values": np.array([0, 1]), "flag_meanings": "not_met met"}),
)


@peening_task(version="2")  # 2: intensities and arc heights stored in m (was mm)
def saturation(arc: xr.Dataset, *, fit: str, angle_deg: float | None = None,
               velocity_m_s: float | None = None, sequences: SequencesParams | None = None) -> xr.Dataset:
    """``arc``: arc_height_m with dims (sequence, shots) for the point (angle_deg, velocity_m_s).

    With adaptive sequences (``sequences``) the verdict of the rule that grew
    them is recorded: whether the standard error met the tolerance, the
    standard error and its 95 % bound (tasks/strip_sequences.py).

    Returns intensities (arc heights) in m."""
    counts = arc.shots.values.astype(float)
    ah_m = arc.arc_height_m.transpose("sequence", "shots").values
    result = fit_sequences(counts, ah_m, MODELS[fit])
    per_seq = np.array([f.intensity if f is not None else np.nan for f in result.fits])
    n_sat = np.array([f.saturation_shots if f is not None else np.nan for f in result.fits])
    extrap = np.array([bool(f.extrapolated) if f is not None else True for f in result.fits])
    mean = result.mean_fit
    n_fine = np.geomspace(max(1.0, counts.min() / 2), counts.max() * 1.5, 80)
    errors = [e or "" for e in result.errors]
    rule, why = {}, {}
    if sequences is not None:
        v = sequences.verdict(per_seq)
        rule = {"intensity_standard_error_m": v.standard_error, "intensity_standard_error_bound_m": v.bound,
                "sequence_tolerance_met": int(v.met)}
        why = {"sequences_rule": f"{sequences.describe()}: {v.reason}"}
    return OUTPUTS.dataset(
        {"intensity_m": mean.intensity, "saturation_shots": mean.saturation_shots,
         "intensity_extrapolated": int(mean.extrapolated), "sequence_intensity_m": per_seq,
         "sequence_saturation_shots": n_sat, "sequence_extrapolated": extrap.astype(int),
         "intensity_std_m": result.intensity_std, "fit_arc_height_m": mean.arc_height(n_fine),
         "mean_arc_height_m": np.nanmean(ah_m, axis=0), "fit_residual_rms_m": mean.residual_rms, **rule},
        coords={"sequence": var(arc.sequence.values, ("sequence",), "1", "random shot sequence number"),
                "shots": var(counts, ("shots",), "1", "number of shots N"),
                "shots_fine": var(n_fine, ("shots_fine",), "1", "number of shots N (fine grid of the fitted curve)")},
        attrs={"fit_model": mean.model,
               "fit_parameters": ", ".join(f"{k}={v:.6g}" for k, v in mean.parameters.items()),
               "sequence_fit_errors": " | ".join(errors),
               **why},
    )
