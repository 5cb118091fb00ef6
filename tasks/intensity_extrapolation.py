"""Stage ``intensity_extrapolation``: each Almen intensity extrapolated to zero element size.

With ``fidelity.extrapolate_intensity_from_um`` the strips run at two element sizes
with the same shot streams (``saturation`` at the study's element size h_f,
``coarse_saturation`` at the coarser h_c); per (angle, velocity)

    I0 = I_f + k mean_s (I_f,s - I_c,s),   k = h_f^p / (h_c^p - h_f^p)

(peenflow/methods/mesh_extrapolation.py, eqs. R1-R3): the fine level's intensity (eq. 11
on its sequence-mean curve) plus the paired mesh correction from the sequences both levels
ran.  p is the study's ``fidelity.intensity_extrapolation_order`` or the measured order of
the strip references.  The control curve and ``target_velocity`` read these intensities;
the result keeps both levels' intensities beside them so the correction can be checked.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from peenflow.methods import paired_correction

from ._common import peening_task, var
from .outputs import Output, Outputs
from .params import ExtrapolationParams
from .saturation import OUTPUTS as SATURATION

#: the saturation stage's outputs the control curve reads, with their names and meaning, and the two levels'
OUTPUTS = Outputs(
    "intensity_extrapolation",
    intensity_m=Output((), "m", "Almen intensity extrapolated to zero element size (paired two-level)"),
    fine_intensity_m=Output((), "m", "Almen intensity at the fine level (eq. 11)"),
    coarse_intensity_m=Output((), "m", "Almen intensity at the coarse level (eq. 11)"),
    mesh_correction_m=Output((), "m", "k times the mean paired fine-minus-coarse per-sequence intensity"),
    mesh_correction_standard_error_m=Output((), "m", "standard error of that correction (NaN from one pair)"),
    paired_sequences=Output((), "1", "sequences with an intensity at both levels"),
    intensity_std_m=Output((), "m", "spread over sequences at the fine level (ddof=1)"),
    saturation_shots=Output((), "1", "saturation point T at the fine level: N solving Ah(2N) = 1.1 Ah(N)"),
    coarse_saturation_shots=Output((), "1", "saturation point T at the coarse level"),
    intensity_extrapolated=Output((), "1", "1 if the saturation point lies outside the shot ladder at either level",
                                  attrs={"flag_values": np.array([0, 1]),
                                         "flag_meanings": "within_ladder extrapolated"}),
)


@peening_task(version="1")
def intensity_extrapolation(fine: xr.Dataset, coarse: xr.Dataset, *, extrapolation: ExtrapolationParams,
                            angle_deg: float | None = None, velocity_m_s: float | None = None) -> xr.Dataset:
    """``fine`` / ``coarse``: the ``saturation`` results of one (angle, velocity) at the two levels
    (``intensity_m``, ``sequence_intensity_m`` (sequence,), ...).  Returns intensities in m; the
    variables the control curve reads (intensity_m, intensity_std_m, intensity_extrapolated,
    saturation_shots, shots) have the saturation stage's names and meaning."""
    e = extrapolation
    per = [dict(zip(ds.sequence.values.tolist(), SATURATION.sequence_intensity_m.read(ds).ravel().tolist()))
           for ds in (fine, coarse)]
    c = paired_correction(*per, e.coarse_element_size_m, e.fine_element_size_m, e.order)
    i_fine = SATURATION.intensity_m.read(fine)
    # eq. (11) outside the ladder at either level makes the extrapolated value as uncertain
    beyond = max(int(SATURATION.intensity_extrapolated.read(level)) for level in (fine, coarse))
    return OUTPUTS.dataset(
        {"intensity_m": i_fine + c.correction, "fine_intensity_m": i_fine,
         "coarse_intensity_m": SATURATION.intensity_m.read(coarse), "mesh_correction_m": c.correction,
         "mesh_correction_standard_error_m": c.standard_error, "paired_sequences": c.pairs,
         "intensity_std_m": SATURATION.intensity_std_m.read(fine),
         "saturation_shots": SATURATION.saturation_shots.read(fine),
         "coarse_saturation_shots": SATURATION.saturation_shots.read(coarse), "intensity_extrapolated": beyond},
        coords={"shots": var(fine.shots.values, ("shots",), "1", "number of shots N (the fine level's ladder)")},
        attrs={"extrapolation": e.describe(), "extrapolation_factor": c.factor,
               "coarse_element_size_m": e.coarse_element_size_m, "fine_element_size_m": e.fine_element_size_m,
               "order": e.order},
    )
