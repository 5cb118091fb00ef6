"""Stage ``sensitivity``: what the answer depends on -- each input's change of the part's velocity and profile.

Reads the process map of a study with a ``[sensitivity]`` table: its points are the study as written
(``baseline``) and the study with one input changed (``KEY@VALUE``, :mod:`peenflow.study.variants`).  For
every changed point and every feature -- the shot velocity read off the control curve for the part's
intensity, the sigma_xx surface stress, the peak compressive stress and its depth, the compressive depth,
N_f and N_c -- the change against the baseline (SI, and in % of the baseline's magnitude), per coverage level
and per combination of the map's other dimensions.  Beside them the baseline's sequence spread of the peak
stress: a change smaller than it is not told apart from sequence noise.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from peenflow.study.variants import BASELINE, SENSITIVITY_DIM

from ._common import peening_task
from .outputs import Output, Outputs

_X = ("change",)
_XC = ("change", "coverage_percent")

#: feature -> (process-map variable, CF units, long name, per coverage level)
FEATURES = {
    "velocity": ("velocity_m_s", "m s-1", "shot velocity for the part's intensity", False),
    "surface_stress": ("surface_stress_xx_Pa", "Pa", "sigma_xx at the surface", True),
    "peak_compressive_stress": ("peak_compressive_xx_Pa", "Pa", "peak compressive sigma_xx", True),
    "peak_depth": ("peak_compressive_xx_depth_m", "m", "depth of the peak compressive sigma_xx", True),
    "compressive_depth": ("compressive_depth_xx_m", "m", "depth of the compressive layer (sigma_xx)", True),
    "full_coverage_shots": ("full_coverage_shots", "1", "N_f", False),
    "coverage_shots": ("coverage_shots", "1", "N_c", True),
}


def _outputs() -> dict:
    out = {}
    for name, (_, units, long_name, per_level) in FEATURES.items():
        dims = _XC if per_level else _X
        out[f"{name}_baseline"] = Output(dims[1:], units, f"{long_name} of the baseline")
        out[f"{name}_change"] = Output(dims, units, f"change of the {long_name} against the baseline")
        out[f"{name}_change_percent"] = Output(dims, "%", f"change of the {long_name}, % of the baseline's magnitude")
    out["peak_sequence_spread"] = Output(("coverage_percent",), "Pa", "the baseline's std over sequences of sigma_xx "
                                                                       "at its peak (the noise floor)")
    out["input_value"] = Output(_X, "1", "the value the input was changed to (in the study file's units)")
    return out


OUTPUTS = Outputs("sensitivity", **_outputs())


def changes(process_map: xr.Dataset) -> list[str]:
    """The names of the changed points (``KEY@VALUE``), in the map's order."""
    return [label for label in process_map[SENSITIVITY_DIM].attrs["flag_meanings"].split() if label != BASELINE]


@peening_task(version="1")
def sensitivity(process_map: xr.Dataset) -> xr.Dataset:
    """The changes (module docstring) from the ``process_map`` result of a study with ``[sensitivity]``."""
    pmap = process_map
    labels = pmap[SENSITIVITY_DIM].attrs["flag_meanings"].split()
    base = pmap.isel({SENSITIVITY_DIM: labels.index(BASELINE)})
    changed = [i for i, label in enumerate(labels) if label != BASELINE]
    names = [labels[i] for i in changed]
    other = [d for d in pmap.attrs.get("process_dims", "").split() if d and d != SENSITIVITY_DIM]
    data = {}
    for name, (var, _, _, _) in FEATURES.items():
        b = base[var].transpose(*other, ...)
        c = (pmap[var].isel({SENSITIVITY_DIM: changed}).rename({SENSITIVITY_DIM: "change"}) - b).transpose(
            *other, "change", ...)
        data[f"{name}_baseline"] = b.values
        data[f"{name}_change"] = c.values
        with np.errstate(divide="ignore", invalid="ignore"):
            data[f"{name}_change_percent"] = 100.0 * c.values / np.abs(b.values)
    data["peak_sequence_spread"] = base["peak_compressive_xx_spread_Pa"].transpose(*other, ...).values
    data["input_value"] = np.broadcast_to(np.array([float(n.rpartition("@")[2]) for n in names]),
                                          [pmap.sizes[d] for d in other] + [len(names)]).copy()
    coords = {"change": xr.Variable(_X, np.arange(len(names)), attrs={
                  "long_name": "the one input changed (KEY@VALUE)", "units": "1",
                  "flag_values": np.arange(len(names)), "flag_meanings": " ".join(names)}),
              "coverage_percent": pmap.coverage_percent}
    coords.update({d: pmap[d] for d in other})
    return OUTPUTS.dataset(data, coords=coords, lead=other, attrs={
        "baseline": "the study as written; each change sets one key to one value, all else as written"})
