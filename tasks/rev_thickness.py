"""Stage ``target_rev_thickness``: how thick the REV of a thick part must be (issue: rev_size).

The paper models its 9.5 mm disk through its whole thickness.  Peening
stresses live in the top few tenths of a millimetre, and the REV's fixed
bottom only needs to be deep enough not to change them.  This stage finds the
thinnest block that does not, by a single-impact convergence check:

1. the plastic depth ``d_p`` of one impact (deepest element layer whose
   largest equivalent plastic strain exceeds 1 % of the maximum) on a block
   ``h_0 = max(4 d_p, 2 element layers)`` thick — checked on the first
   candidate itself;
2. candidates ``h_k = h_0 2^k``: one impact on a block ``h_k`` and one on
   ``2 h_k`` thick (same lateral block, same shot); ``h_k`` is accepted when
   the residual σxx and σyy under the dent (averaged over the element columns
   within the dent radius, fine-zone layers down to ``2 d_p``) differ by at most
   ``tolerance`` of their peak, and the dent depth by at most ``tolerance``;
3. the REV thickness is the accepted ``h_k``, or the part thickness when no
   candidate thinner than the part passes.

Output: ``thickness_m`` and every candidate's differences, in SI.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from . import _kernel as K
from ._common import peening_task, var
from .indentation import OUTPUTS as DENT
from .outputs import Output, Outputs
from .params import FidelityParams, MaterialParams, ShotParams
from .single_impact import run_single_impact
from .target_velocity import OUTPUTS as VELOCITY

PLASTIC_FRACTION = 0.01

OUTPUTS = Outputs(
    "rev_thickness",
    thickness_m=Output((), "m", "REV thickness from the single-impact convergence check"),
    plastic_depth_m=Output((), "m", f"deepest layer with eps_p > {PLASTIC_FRACTION:g} x max"),
    candidate_thickness_m=Output(("candidate",), "m", "candidate REV thickness h"),
    stress_difference=Output(("candidate",), "1", "max |sigma(h) - sigma(2h)| / max |sigma(2h)| under the dent"),
    dent_depth_difference=Output(("candidate",), "1", "|dent(h) - dent(2h)| / dent(2h)"),
)


def _column_profile(mesh, result, radius: float, depth: float) -> tuple[np.ndarray, np.ndarray]:
    """(z centroids, (n_layer, 2) σxx σyy) averaged over columns within ``radius`` of the axis, z <= depth."""
    xc, yc, zc = K.cell_centres(mesh)
    nx, ny, nz = xc.size, yc.size, zc.size
    stress = result.stress.reshape(nz, ny, nx, 6)  # element order: x fastest, then y, then z
    inside = (xc[None, :] ** 2 + yc[:, None] ** 2) <= radius**2
    if not inside.any():  # radius below one element: the column at the axis
        inside[np.argmin(np.abs(yc)), np.argmin(np.abs(xc))] = True
    layers = zc <= depth
    prof = stress[layers][:, inside, :2].mean(axis=1)
    return zc[layers], prof


def _plastic_depth(mesh, result) -> float:
    zc = K.cell_centres(mesh)[2]
    eps = result.eps_p.reshape(zc.size, -1).max(axis=1)
    deep = np.nonzero(eps > PLASTIC_FRACTION * eps.max())[0]
    return float(mesh.z[deep[-1] + 1])


def _dent_depth(result) -> float:
    return float(np.max(result.displacement[:, 2]))


@peening_task(version="1")
def rev_thickness(velocity: xr.Dataset, dent: xr.Dataset, *, material: MaterialParams, shot: ShotParams,
                  fidelity: FidelityParams, angle_deg: float, half_width_m: float, part_thickness_m: float,
                  tolerance: float = 0.02,
                  ctx=None) -> xr.Dataset:
    """``velocity``: target_velocity result; ``dent``: the target's indentation (radius for the columns)."""
    speed = VELOCITY.velocity_m_s.read(velocity)
    radius = max(DENT.dent_semi_axis_along_m.read(dent), DENT.dent_semi_axis_across_m.read(dent))
    threads = ctx.threads if ctx else 1

    def impact(h):
        return run_single_impact(material, shot, fidelity, speed, angle_deg, half_width_m, h,
                                 threads=threads, record=False)

    h_min = 2.0 * fidelity.element_size_m
    # d_p on a block as thick as the shot diameter is enough: the plastic zone
    # of one impact is a fraction of the contact radius deep.
    first = min(part_thickness_m, max(h_min, 2.0 * shot.radius_m))
    mesh, res = impact(first)
    d_p = _plastic_depth(mesh, res)
    # Compare where both blocks have the same (fine-zone) layers.
    depth = min(2.0 * d_p, fidelity.fine_depth_m)
    if depth < d_p:
        raise ValueError(f"the fine zone ({fidelity.fine_depth_m:.3g} m) is shallower than the plastic depth of "
                         f"one impact ({d_p:.3g} m): raise fidelity.fine_depth_D or fine_depth_mm")
    h = min(part_thickness_m, max(h_min, 4.0 * d_p))
    tried, stress_diff, dent_diff = [], [], []
    chosen = part_thickness_m
    while h < part_thickness_m * (1 - 1e-9):
        thick = min(part_thickness_m, 2.0 * h)
        m1, r1 = impact(h)
        m2, r2 = impact(thick)
        z1, p1 = _column_profile(m1, r1, radius, depth)
        z2, p2 = _column_profile(m2, r2, radius, depth)
        n = min(z1.size, z2.size)
        ds = float(np.max(np.abs(p1[:n] - p2[:n])) / np.max(np.abs(p2[:n])))
        dent_thick = _dent_depth(r2)
        dd = abs(_dent_depth(r1) - dent_thick) / dent_thick
        tried.append(h)
        stress_diff.append(ds)
        dent_diff.append(dd)
        if ctx:
            ctx.progress(len(tried), None, "thickness candidates", f"h = {h * 1e3:.3g} mm: stress {ds:.2%}")
        if ds <= tolerance and dd <= tolerance:
            chosen = h
            break
        h = thick
    return OUTPUTS.dataset(
        {"thickness_m": chosen, "plastic_depth_m": d_p, "candidate_thickness_m": np.array(tried),
         "stress_difference": np.array(stress_diff), "dent_depth_difference": np.array(dent_diff)},
        coords={"candidate": var(np.arange(len(tried)), ("candidate",), "1", "candidate number")},
        attrs={"tolerance": tolerance, "part_thickness_m": part_thickness_m,
               "rule": "converged" if chosen < part_thickness_m else "part thickness (no thinner block converged)"},
    )
