"""Stage ``residual_profile``: the part's residual-stress profile with its spread (paper §5, Fig. 19).

σx(z), σy(z) averaged over the REV's measuring region, per sequence, then
the mean and spread over sequences; compared with a measured profile when
the study gives one (interpolated onto the measured depths: difference,
RMS difference, peak compressive stress and its depth side by side).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ._common import MPA, peening_task, var


def _peak(depth, values):
    k = int(np.nanargmin(values))
    return float(values[k]), float(depth[k])


@peening_task(version="1")
def residual_profile(runs: xr.Dataset, *, measured: dict | None = None) -> xr.Dataset:
    """``runs``: target REV results combined over ``sequence``; ``measured``:
    {"depth_m": [...], "stress_Pa": [...], "component": "xx"} or None."""
    depth = np.asarray(runs.depth_m.values)
    if depth.ndim > 1:
        depth = depth.reshape(-1, depth.shape[-1])[0]
    out = {}
    for c in ("xx", "yy"):
        s = runs[f"stress_{c}_Pa"].transpose("sequence", "layer").values
        out[f"stress_{c}_MPa"] = var(s / MPA, ("sequence", "layer"), "MPa", f"sigma_{c} per sequence")
        out[f"stress_{c}_mean_MPa"] = var(s.mean(axis=0) / MPA, ("layer",), "MPa", f"mean sigma_{c}")
        spread = s.std(axis=0, ddof=1) if s.shape[0] > 1 else np.zeros(s.shape[1])
        out[f"stress_{c}_spread_MPa"] = var(spread / MPA, ("layer",), "MPa", "std over sequences")
        peak, at = _peak(depth, s.mean(axis=0) / MPA)
        out[f"peak_compressive_{c}_MPa"] = var(peak, (), "MPa")
        out[f"peak_compressive_{c}_depth_m"] = var(at, (), "m")
    out["depth_m"] = var(depth, ("layer",), "m", "layer mid-depth below the peened surface")
    coords = {"sequence": runs.sequence.values}
    attrs = {"measured_profile": "none"}
    if measured:
        comp = measured.get("component", "xx")
        md = np.asarray(measured["depth_m"], dtype=float)
        ms = np.asarray(measured["stress_Pa"], dtype=float) / MPA
        ours = np.interp(md, depth, out[f"stress_{comp}_mean_MPa"].values)
        coords["measured_point"] = np.arange(md.size)
        out["measured_depth_m"] = var(md, ("measured_point",), "m")
        out["measured_stress_MPa"] = var(ms, ("measured_point",), "MPa", f"measured sigma_{comp}")
        out["predicted_at_measured_MPa"] = var(ours, ("measured_point",), "MPa")
        out["rms_difference_MPa"] = var(float(np.sqrt(np.mean((ours - ms) ** 2))), (), "MPa")
        mpeak, mat = _peak(md, ms)
        out["measured_peak_compressive_MPa"] = var(mpeak, (), "MPa")
        out["measured_peak_depth_m"] = var(mat, (), "m")
        attrs["measured_profile"] = f"component {comp}, {md.size} points"
    return xr.Dataset(out, coords=coords, attrs=attrs)
