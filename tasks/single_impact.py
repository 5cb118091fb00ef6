"""Stage ``single_impact``: one shot on a block of the target material (paper §3.1, §3.2.2).

The block is centred on the impact point; a normal impact uses a quarter
model (both vertical planes through the impact are symmetry planes), an
oblique one a half model (symmetric about the plane of incidence y = 0).
Surface fields are returned mirrored to the full block.

Output (SI): the relaxed residual stress on the structured element grid
(z, y, x, component), equivalent plastic strain, the deformed top surface
uz(x, y) (positive into the target), the top-layer von Mises stress, the
shot's rebound, and the energy balance of the impact.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import xarray as xr

from peenflow.methods import VOIGT

from . import _kernel as K
from ._impact_core import ImpactCore, core_for, cored_block
from ._common import COMPONENT_LONG_NAME, depth, labels, peening_task, var
from .outputs import Output, Outputs
from .params import FidelityParams, MaterialParams, ShotParams
from .target_velocity import OUTPUTS as VELOCITY

OUTPUTS = Outputs(
    "single_impact",
    stress_Pa=Output(("z_cell", "y_cell", "x_cell", "component"), "Pa", "relaxed residual stress (model part)"),
    plastic_strain=Output(("z_cell", "y_cell", "x_cell"), "1", "equivalent plastic strain"),
    surface_uz_m=Output(("x_node_full", "y_node_full"), "m", "top-surface displacement, + into target"),
    surface_von_mises_Pa=Output(("x_cell_full", "y_cell_full"), "Pa", "top-layer von Mises residual"),
    restitution=Output((), "1", "coefficient of restitution -v_out,z / v_in,z"),
    peak_force_N=Output((), "N", "peak contact force on the model part"),
    max_approach_m=Output((), "m", "deepest point of the shot below z = 0"),
    contact_time_s=Output((), "s", "duration of contact"),
    rebound_velocity_m_s=Output(("xyz",), "m s-1", "shot velocity after the impact"),
    energy_error=Output((), "1", "energy balance error / impact energy"),
    hourglass_ratio=Output((), "1", "hourglass / internal energy"),
    impact_x_m=Output((), "m", "impact point x"),
    impact_y_m=Output((), "m", "impact point y"),
    # the contact's history, when the impact was recorded
    contact_force_N=Output(("time_s",), "N", "normal contact force on the whole shot", optional=True),
    shot_z_m=Output(("time_s",), "m", "shot centre z, positive into the target", optional=True),
)


#: single-impact / two-shot block: half width and depth in shot diameters
IMPACT_BLOCK_D = 2.0

#: the fine zone of a single impact's block, as a fraction of its half width
FINE_HALF_FRACTION = 0.6


def impact_core(material: MaterialParams, shot: ShotParams, fidelity: FidelityParams, speed: float,
                angle_deg: float, half_width_m: float, thickness_m: float, core_element_size_m: float):
    """The core of ``core_element_size_m`` (m) elements under the impact (:mod:`tasks._impact_core`), or
    None if it and its grading back to the block's elements do not fit in the block's fine zone."""
    centre, velocity = shot.aimed(speed, angle_deg)
    core = core_for(material.to_kernel(), shot.shots(centre, velocity), speed, angle_deg, core_element_size_m)
    try:
        cored_block(_block(fidelity, half_width_m, thickness_m, angle_deg), core, fidelity.element_size_m,
                    fidelity.grading_ratio)
    except ValueError:
        return None
    return core


def _block(fidelity: FidelityParams, half_width_m: float, thickness_m: float, angle_deg: float):
    """The single impact's block: a quarter model for a normal shot, a half model for an oblique one."""
    return K.impact_block(fidelity, half_width_m, thickness_m, fine_half=FINE_HALF_FRACTION * half_width_m,
                          symmetric_x=angle_deg == 90.0, symmetric_y=True)


def run_single_impact(material: MaterialParams, shot: ShotParams, fidelity: FidelityParams, speed: float,
                      angle_deg: float, half_width_m: float, thickness_m: float, threads: int = 1,
                      record: bool = True, core: ImpactCore | None = None):
    """(mesh, kernel result) of one shot at ``speed`` (m s-1) on a block ``half_width_m`` x ``thickness_m`` (m);
    ``core``: a finer core under the impact (:func:`impact_core`)."""
    mesh = _block(fidelity, half_width_m, thickness_m, angle_deg)
    if core is not None:
        mesh = cored_block(mesh, core, fidelity.element_size_m, fidelity.grading_ratio)
    centre, velocity = shot.aimed(speed, angle_deg)
    result = K.run_impacts(fidelity.boundary(mesh, impact_block=True), material.to_kernel(),
                           shot.shots(centre, velocity),
                           fidelity.options(shot, threads, record=record, record_every=4))
    return mesh, result


def impact_dataset(mesh, result, normal: bool) -> xr.Dataset:
    stress, eps = K.grid_fields(mesh, result.stress, result.eps_p)
    xc, yc, zc = K.cell_centres(mesh)
    uz = K.surface_uz(mesh, result.displacement)  # (nnx, nny)
    vm_top = K.von_mises(stress[0]).T  # (nx, ny)
    xs, ys, xcs, ycs = mesh.x, mesh.y, xc, yc
    # mirror to the full surface (the model keeps x >= 0 if normal, and y >= 0)
    uz = K.mirror_nodes(uz, 1)
    vm_top = K.mirror_cells(vm_top, 1)
    ys, ycs = K.mirror_axis(ys), np.concatenate([-ycs[::-1], ycs])
    if normal:
        uz = K.mirror_nodes(uz, 0)
        vm_top = K.mirror_cells(vm_top, 0)
        xs, xcs = K.mirror_axis(xs), np.concatenate([-xcs[::-1], xcs])
    shots = result.shots
    hist = result.histories[0] if result.histories else None
    data = {
        "stress_Pa": stress, "plastic_strain": eps, "surface_uz_m": uz, "surface_von_mises_Pa": vm_top,
        "restitution": float(shots["restitution"][0]), "peak_force_N": float(shots["peak_force"][0]),
        "max_approach_m": float(shots["max_approach"][0]), "contact_time_s": float(shots["contact_duration"][0]),
        "rebound_velocity_m_s": np.array([shots["vout_x"][0], shots["vout_y"][0], shots["vout_z"][0]]),
        "energy_error": float(result.energy_error), "hourglass_ratio": float(result.hourglass_ratio),
        "impact_x_m": 0.0, "impact_y_m": 0.0,
    }
    coords = {"x_cell": var(xc, ("x_cell",), "m", "element centre x (model part)"),
              "y_cell": var(yc, ("y_cell",), "m", "element centre y (model part)"),
              "z_cell": depth(zc, "z_cell", "element centre depth below the surface"),
              "component": labels(VOIGT, "component", COMPONENT_LONG_NAME),
              "x_node_full": var(xs, ("x_node_full",), "m", "surface node x (full block)"),
              "y_node_full": var(ys, ("y_node_full",), "m", "surface node y (full block)"),
              "x_cell_full": var(xcs, ("x_cell_full",), "m", "top-layer element centre x (full block)"),
              "y_cell_full": var(ycs, ("y_cell_full",), "m", "top-layer element centre y (full block)"),
              "xyz": labels("xyz", "xyz", "vector component"),
              "z_node": depth(mesh.z, "z_node", "node layer depth below the surface")}
    if hist is not None:
        coords["time_s"] = var(hist["time"], ("time_s",), "s", "time since the start of the impact")
        data["contact_force_N"] = hist["force"][:, 2] * (4 if normal else 2)
        data["shot_z_m"] = hist["centre"][:, 2]
    return OUTPUTS.dataset(data, coords=coords)


@peening_task(version="1")
def single_impact(velocity: xr.Dataset | None = None, *, material: MaterialParams, shot: ShotParams,
                  fidelity: FidelityParams,
                  angle_deg: float, velocity_m_s: float | None = None, half_width_m: float,
                  thickness_m: float, core_element_size_m: float | None = None, ctx=None) -> xr.Dataset:
    """One impact; the speed is ``velocity_m_s`` or the upstream ``velocity`` result.

    ``core_element_size_m``: elements of that size (m) in a core under the impact only
    (``fidelity.dent_refinement = "core"``, :mod:`tasks._impact_core`); if the core does not fit in
    the block's fine zone, the whole fine zone takes that size (attribute ``dent_refinement``)."""
    speed = velocity_m_s if velocity_m_s is not None else VELOCITY.velocity_m_s.read(velocity)
    core, refinement = None, ""
    if core_element_size_m is not None:
        core = impact_core(material, shot, fidelity, speed, angle_deg, half_width_m, thickness_m,
                           core_element_size_m)
        refinement = "core"
        if core is None:  # the block refined to the core's size: the dent the "block" refinement gives
            fidelity = replace(fidelity, element_size_m=core_element_size_m)
            refinement = "block (the core did not fit in the fine zone)"
    mesh, result = run_single_impact(material, shot, fidelity, speed, angle_deg, half_width_m, thickness_m,
                                     threads=ctx.threads if ctx else 1, core=core)
    ds = impact_dataset(mesh, result, angle_deg == 90.0)
    ds.attrs.update({"velocity_m_s": speed, "angle_deg": angle_deg,
                     "n_elements": int(mesh.n_elements),
                     # "" when the active window lies inside the envelope its error was measured for
                     "window_outside_validated": result.window_outside_validated})
    if refinement:
        ds.attrs.update({"dent_refinement": refinement, "dent_core_element_size_m": core_element_size_m})
    if core is not None:
        ds.attrs.update({"dent_core_half_width_m": core.half_width_m, "dent_core_depth_m": core.depth_m,
                         "dent_core_contact_radius_m": core.contact_radius_m})
    return ds
