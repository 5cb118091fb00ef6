"""Stage ``process_map``: the part's residual-stress answer over every process dimension, in one Dataset.

The ``residual_profile`` results of every combination of the study's process
dimensions (``[target]`` lists, named targets, ``[sweep]`` keys), and its
coverage levels, laid on one grid:

* the mean sigma_xx and sigma_yy profiles and their spread over sequences on a
  common depth grid (the first point's layer mid-depths, as deep as the
  shallowest REV reaches; other meshes are interpolated linearly);
* per point and coverage level the features an engineer specifies: the surface
  stress (top layer), the most compressive stress and its depth, the depth of
  the compressive layer (:func:`peenflow.methods.profile_features.compressive_depth`),
  N_f, N_c and the shot velocity;
* each feature's stated numerical error where its material, shot and fidelity
  were measured (:mod:`peenflow.study.accuracy`), NaN where they were not, with
  ``error_measured`` saying which and the attribute ``error_basis`` naming the
  measured case.

Dimensions are the study's (SI, CF attributes on their coordinates), then
``coverage_percent`` and ``depth``.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from peenflow.methods.profile_features import compressive_depth

from ._common import depth as depth_coord, peening_task
from .outputs import Output, Outputs
from .residual_profile import OUTPUTS as PROFILE

_C = ("coverage_percent",)


def _features() -> dict:
    out = {}
    for c in ("xx", "yy"):
        out.update({
            f"stress_{c}_mean_Pa": Output(("coverage_percent", "depth"), "Pa", f"mean sigma_{c} over sequences"),
            f"stress_{c}_spread_Pa": Output(("coverage_percent", "depth"), "Pa", f"std of sigma_{c} over sequences"),
            f"surface_stress_{c}_Pa": Output(_C, "Pa", f"mean sigma_{c} in the top layer"),
            f"peak_compressive_{c}_Pa": Output(_C, "Pa", f"most compressive mean sigma_{c}"),
            f"peak_compressive_{c}_depth_m": Output(_C, "m", f"depth of the most compressive mean sigma_{c}"),
            f"compressive_depth_{c}_m": Output(_C, "m", f"depth of the compressive layer of the mean sigma_{c}"),
            f"peak_compressive_{c}_spread_Pa": Output(_C, "Pa", f"std over sequences of sigma_{c} at its mean's peak"),
        })
    return out


OUTPUTS = Outputs(
    "process_map", **_features(),
    velocity_m_s=Output((), "m s-1", "shot velocity"),
    full_coverage_shots=Output((), "1", "N_f: shots for full coverage of the REV"),
    coverage_shots=Output(_C, "1", "N_c: shots of each coverage level on the REV"),
    error_measured=Output((), "1", "1 where the stated errors were measured for this material, shot and fidelity",
                          attrs={"flag_values": np.array([0, 1]), "flag_meanings": "unmeasured measured"}),
    peak_error_percent=Output((), "%", "stated error of the peak compressive stress (NaN: unmeasured)"),
    compressive_depth_error_percent=Output((), "%", "stated error of the compressive depth (NaN: unmeasured)"),
    profile_error_percent=Output((), "%", "stated RMS error of the profile, in % of its peak (NaN: unmeasured)"),
    full_coverage_shots_error_percent=Output((), "%", "stated error of N_f (NaN: unmeasured)"),
)

#: what a point's stated error holds (tasks.pipeline builds it per point from peenflow.study.accuracy)
ERROR_FIELDS = ("peak_percent", "compressive_depth_percent", "profile_rms_percent", "full_coverage_shots_percent")


def common_depths(depths: list[np.ndarray]) -> np.ndarray:
    """The first grid, cut where the shallowest one ends (m)."""
    deepest_shared = min(float(np.nanmax(d)) for d in depths)
    first = depths[0][np.isfinite(depths[0])]
    return first[first <= deepest_shared * (1 + 1e-12)]


@peening_task(version="1")
def process_map(profiles: xr.Dataset, *, dims: list, errors: list, error_basis: str) -> xr.Dataset:
    """``profiles``: the ``residual_profile`` results combined along ``dims`` (the study's process dimensions, in
    order); ``errors``: per point (in the order of the combinations, the last dimension fastest) a dict of
    :data:`ERROR_FIELDS` (None: unmeasured); ``error_basis``: the measured case those errors come from."""
    dims = list(dims)
    if dims:
        stacked = profiles.stack(point=dims)
        points = [stacked.isel(point=k) for k in range(stacked.sizes["point"])]
    else:  # one point: a single study with requirements
        points = [profiles]
    n = len(points)
    depth_per = [np.asarray(pt.depth_m.values, dtype=float) for pt in points]
    grid = common_depths(depth_per)
    levels = np.asarray(profiles.coverage_percent.values, dtype=float)
    out: dict[str, list] = {}

    def put(name, value):
        out.setdefault(name, []).append(value)

    for k, pt in enumerate(points):
        z = depth_per[k]
        ok = np.isfinite(z)
        for c in ("xx", "yy"):
            mean = np.asarray(pt[f"stress_{c}_mean_Pa"].transpose("coverage_percent", "layer").values)[:, ok]
            spread = np.asarray(pt[f"stress_{c}_spread_Pa"].transpose("coverage_percent", "layer").values)[:, ok]
            put(f"stress_{c}_mean_Pa", np.array([np.interp(grid, z[ok], m) for m in mean]))
            put(f"stress_{c}_spread_Pa", np.array([np.interp(grid, z[ok], s) for s in spread]))
            put(f"surface_stress_{c}_Pa", mean[:, 0])
            put(f"peak_compressive_{c}_Pa", np.asarray(pt[f"peak_compressive_{c}_Pa"].values, dtype=float))
            at = np.asarray(pt[f"peak_compressive_{c}_depth_m"].values, dtype=float)
            put(f"peak_compressive_{c}_depth_m", at)
            put(f"compressive_depth_{c}_m", np.array([_or_nan(compressive_depth(z[ok], m)[0]) for m in mean]))
            put(f"peak_compressive_{c}_spread_Pa",
                np.array([float(np.interp(a, z[ok], s)) for a, s in zip(at, spread)]))
        put("velocity_m_s", PROFILE.velocity_m_s.read(pt))
        put("full_coverage_shots", PROFILE.full_coverage_shots.read(pt))
        put("coverage_shots", np.asarray(pt.coverage_shots.transpose("coverage_percent").values, dtype=float))
        e = errors[k] if k < len(errors) else None
        put("error_measured", int(e is not None))
        for name, field in zip(("peak_error_percent", "compressive_depth_error_percent", "profile_error_percent",
                                "full_coverage_shots_error_percent"), ERROR_FIELDS):
            put(name, np.nan if e is None or e.get(field) is None else float(e[field]))

    shape = [profiles.sizes[d] for d in dims]
    data = {}
    for name, values in out.items():
        arr = np.asarray(values, dtype=float)
        data[name] = arr.reshape(shape + list(arr.shape[1:]))
    coords = {d: profiles[d] for d in dims}
    coords["coverage_percent"] = profiles.coverage_percent
    coords["depth_m"] = depth_coord(grid, "depth", "depth below the peened surface (common grid of the map)")
    return OUTPUTS.dataset(data, coords=coords, lead=dims, attrs={
        "error_basis": error_basis,
        "depth_grid": "the first point's layer mid-depths, to the shallowest REV's depth; profiles interpolated "
                      "linearly"})


def _or_nan(x):
    return np.nan if x is None else float(x)
