"""Stage ``arc_height``: Almen-strip arc height from the strip REV runs (paper eqs. 6-9).

For one (angle, velocity), every sequence and every rung N of the saturation
ladder: the REV's σx profile averaged over the measuring region is taken as
the clamped strip's induced stress; releasing the strip (eq. 8) gives the
arc height over the gauge span l = 31.75 mm (eq. 9), moment about the
strip's mid-plane.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from peenflow.methods import DepthProfile, release_strip

from ._common import peening_task, var
from .outputs import Output, Outputs
from .params import StripParams

OUTPUTS = Outputs(
    "arc_height",
    arc_height_m=Output(("sequence", "shots"), "m", "arc height over the gauge span (eq. 9)"),
    clamp_force_N=Output(("sequence", "shots"), "N", "F_x held by the fixture (eq. 6)"),
    clamp_moment_Nm=Output(("sequence", "shots"), "N m", "M_y about the strip mid-plane (eq. 7)"),
)


@peening_task(version="2")  # 2: arc heights stored in m (was mm)
def arc_height(runs: xr.Dataset, *, strip: StripParams, angle_deg: float | None = None,
               velocity_m_s: float | None = None) -> xr.Dataset:
    """``runs``: strip REV profiles, dims (sequence, shots, layer), ``stress_xx_Pa`` and ``z_edge_m``.

    Sequences may have different ladders (``almen.shot_counts = "auto"``): the
    combined runs are NaN where a sequence stopped before a rung, and so are
    its arc heights there.

    Returns arc_height_m, clamp_force_N, clamp_moment_Nm with dims (sequence, shots), SI.
    """
    z_edges = np.asarray(runs.z_edge_m.values)
    if z_edges.ndim > 1:  # combined along sequence: identical meshes
        z_edges = z_edges.reshape(-1, z_edges.shape[-1])[0]
    sxx = runs.stress_xx_Pa.transpose("sequence", "shots", "layer").values
    ah, force, moment = np.array([rung_releases(z_edges, seq, strip) for seq in sxx]).transpose(1, 0, 2)
    return OUTPUTS.dataset(
        {"arc_height_m": ah, "clamp_force_N": force, "clamp_moment_Nm": moment},
        coords={"sequence": var(runs.sequence.values, ("sequence",), "1", "random shot sequence number"),
                "shots": var(runs.shots.values, ("shots",), "1", "number of shots N")},
        attrs={"strip_thickness_m": strip.thickness_m, "gauge_span_m": strip.gauge_span_m},
    )


def rung_releases(z_edges, sxx_rungs, strip: StripParams) -> np.ndarray:
    """(arc height m, clamp force N, clamp moment N m), shape (3, rungs), of one sequence's σx profiles
    ``sxx_rungs`` (rungs, layer), Pa; NaN at a rung the sequence's ladder did not reach (a profile
    that is not finite).  What ``arc_height`` computes per sequence, and the adaptive-sequences
    rule per run (tasks/strip_sequences.py)."""
    out = np.full((3, len(sxx_rungs)), np.nan)
    for k, sxx in enumerate(sxx_rungs):
        if np.all(np.isfinite(sxx)):
            out[:, k] = release(z_edges, sxx, strip)
    return out


def release(z_edges, sxx, strip: StripParams) -> tuple[float, float, float]:
    """(arc height m, clamp force N, clamp moment N m) of one σx profile (Pa on layers ``z_edges``, m).

    Shared with the strip runs that extend their own ladder, so both compute
    the same arc height.
    """
    profile = DepthProfile(np.asarray(z_edges), np.asarray(sxx), "layers")
    rel = release_strip(profile, strip.width_m, strip.thickness_m, strip.youngs_modulus_Pa, strip.gauge_span_m)
    return rel.arc_height, rel.force, rel.moment
