"""Stages ``strip_dmin`` and ``target_dmin`` (task ``dmin``): the smallest distance at which two
impacts do not interact (paper §3.1, eq. 4).

Two shots land at (+-d/2, 0) on a plate of the target material.  Their
eq. (4) regions (top-surface von Mises residual >= 5 % of its maximum) are
compared: d_min is the smallest d at which they are separate.  Instead of
the paper's linear scan, the search (``method = "bisection"``, the default)
brackets d_min from the single-impact region (2 x its radius) and bisects
to the requested resolution; ``method = "scan"`` is the paper's linear scan
from the bracket's lower end in steps of the resolution. Every two-shot run
is checkpointed, so a killed search resumes where it stopped.

Normal impacts use a quarter model: the symmetry plane x = 0 mirrors the
shot at +d/2 onto -d/2 (the two land together).  Oblique impacts use a half
model (plane y = 0) with both shots, the second landing after the first has
settled.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from peenflow.methods import (bracket_from_radius, find_dmin, regions_overlap, scan_dmin,
                              single_impact_region_radius)

from . import _kernel as K
from ._common import peening_task, var
from .outputs import Output, Outputs
from .params import DminParams, FidelityParams, MaterialParams, ShotParams
from .single_impact import OUTPUTS as IMPACT

OUTPUTS = Outputs(
    "dmin",
    d_min_m=Output((), "m", "smallest separation without interaction (eq. 4)"),
    resolution_m=Output((), "m", "d_min is within this above the true value"),
    bracket_lower_m=Output((), "m", "lower end of the final bisection bracket"),
    bracket_upper_m=Output((), "m", "upper end of the final bisection bracket"),
    single_region_radius_m=Output((), "m", "eq. (4) region radius of one impact"),
    overlap=Output(("run",), "1", "1 if the regions touch",
                   attrs={"flag_values": np.array([0, 1]), "flag_meanings": "separate touching"}),
)


def two_shot_surface(material: MaterialParams, shot: ShotParams, fidelity: FidelityParams, speed, angle_deg, d,
                     half_width, thickness, threads):
    """(x_cell (n,), y_cell (m,), von Mises (n, m)) of the top layer, full surface."""
    normal = angle_deg == 90.0
    mesh = K.impact_block(fidelity, half_width, thickness, fine_half=0.5 * d + 0.3 * half_width,
                          symmetric_x=normal, symmetric_y=True)
    if normal:
        c, v = shot.aimed(speed, angle_deg, (0.5 * d, 0.0))
        centres, velocities = [c], [v]
    else:
        c1, v1 = shot.aimed(speed, angle_deg, (-0.5 * d, 0.0))
        c2, v2 = shot.aimed(speed, angle_deg, (0.5 * d, 0.0))
        centres, velocities = [c1, c2], [v1, v2]
    res = K.run_impacts(fidelity.boundary(mesh, impact_block=True), material.to_kernel(),
                        shot.shots(centres, velocities), fidelity.options(shot, threads))
    stress, _ = K.grid_fields(mesh, res.stress, res.eps_p)
    vm = K.von_mises(stress[0]).T
    xc, yc, _ = K.cell_centres(mesh)
    vm, yc = K.mirror_cells(vm, 1), np.concatenate([-yc[::-1], yc])
    if normal:
        vm, xc = K.mirror_cells(vm, 0), np.concatenate([-xc[::-1], xc])
    return xc, yc, vm


@peening_task(version="1")
def dmin(impact: xr.Dataset, *, material: MaterialParams, shot: ShotParams, fidelity: FidelityParams,
         angle_deg: float, thickness_m: float, search: DminParams, ctx=None) -> xr.Dataset:
    """d_min at the single impact's velocity and angle (read from ``impact``), by
    bisection or linear scan (``search.method``)."""
    threshold, resolution_m = search.threshold, search.resolution_m
    min_distance_m, max_distance_m, method = search.min_distance_m, search.max_distance_m, search.method
    velocity_m_s = float(impact.attrs["velocity_m_s"])
    radius = single_impact_region_radius(impact.x_cell_full.values, impact.y_cell_full.values,
                                         IMPACT.surface_von_mises_Pa.read(impact), (0.0, 0.0), threshold)
    lower, upper = bracket_from_radius(radius)
    lower = float(np.clip(lower, min_distance_m, max_distance_m))
    upper = float(np.clip(upper, lower + resolution_m, max_distance_m))
    done: dict[float, bool] = {}
    if ctx is not None and (ck := ctx.load_checkpoint()) is not None:
        if "distance_m" in ck.variables and "overlap" in ck.variables:
            done = {float(d): bool(o) for d, o in zip(ck.distance_m.values, ck.overlap.values)}
        else:
            ctx.discard_checkpoint("it has no distance_m/overlap: written by another task")
    threads = ctx.threads if ctx else 1

    def overlaps(d: float) -> bool:
        key = float(f"{d:.9g}")
        if key not in done:
            half = max(0.5 * d + 1.5 * radius + 0.2 * d, 2.0 * radius)
            xc, yc, vm = two_shot_surface(material, shot, fidelity, velocity_m_s, angle_deg, d, half,
                                          thickness_m, threads)
            done[key] = bool(regions_overlap(xc, yc, vm, ((-0.5 * d, 0.0), (0.5 * d, 0.0)), threshold))
            if ctx is not None:
                ds_ = sorted(done)
                ctx.save_checkpoint(xr.Dataset({"overlap": ("run", [int(done[k]) for k in ds_])},
                                               coords={"distance_m": ("run", ds_)}))
                ctx.progress(len(done), None, "two-shot runs", f"d = {d * 1e3:.3f} mm")
                if ctx.stop_requested:
                    ctx.stop(f"after two-shot run {len(done)} (d = {d * 1e3:.3f} mm)")
        return done[key]

    if method == "scan":
        found = scan_dmin(overlaps, lower, upper, resolution_m, floor=min_distance_m, ceiling=max_distance_m)
    else:
        found = find_dmin(overlaps, lower, upper, resolution_m, floor=min_distance_m)
    runs = sorted(done)
    return OUTPUTS.dataset(
        {"d_min_m": found.d_min, "resolution_m": found.resolution, "bracket_lower_m": found.lower,
         "bracket_upper_m": found.upper, "single_region_radius_m": radius,
         "overlap": np.array([int(done[d]) for d in runs])},
        coords={"distance_m": var(np.array(runs), ("run",), "m", "two-shot separation of the run")},
        attrs={"angle_deg": angle_deg, "velocity_m_s": velocity_m_s, "threshold": threshold, "method": method},
    )
