"""How the single-impact figures are read off a run: the surface line, the sigma_xx(z) column, and how
far each reading itself is from the truth when the fields are seen through a coarser mesh.

Figures (:func:`metrics`, :func:`surface_metrics`, :func:`profile_metrics`): dent depth (the highest
point of the surface spline next to the deepest node, :func:`dent_bottom`); dent radius (along the
plane of incidence: half the distance between the zero crossings of the surface u_z either side of
the dent, on the surface line interpolated between nodes by a modified-Akima spline,
:func:`surface_spline`; from the axis on a quarter model); pile-up crest radius (from the dent centre)
and height (the highest point of that spline next to the highest node downstream of the dent edge);
sigma_xx(z) under the dent (mean over the column |x - xc| <= 50 um, |y| <= 50 um about the dent
centre xc, each element weighted by its overlap with the column, :func:`column_profile`), read as the
point-wise curve recovered from its layer means (:func:`profile_curve`): its peak, the depth of the
peak and of its zero crossing below the peak, and the RMS over 0-0.3 mm of the difference to the
reference's recovered curve / |reference peak| (:func:`profile_rms`).

The readings' own error (:func:`sampling_bias`, :func:`profile_sampling_bias`,
:func:`resolution_limit`): the converged 6.25 um fields taken at a coarser spacing against themselves
in full -- what no element at that spacing can do better than.

Units: figures carry theirs in their names (``dent_um``, ``dent_radius_mm``, ``sxx_peak_mpa``); the
functions on raw lines take metres.
"""

from __future__ import annotations

import numpy as np

from peenflow.fe.mesh import BoxMesh
from peenflow.methods import DepthProfile

#: half width (m) of the column under the dent that sigma_xx(z) is averaged over
AXIS_ZONE = 50e-6
#: depth (m) the profile RMS is taken over
PROFILE_DEPTH = 0.3e-3


def surface_spline(xs, us):
    """The surface line interpolated between its nodes: modified Akima (makima) piecewise cubic.

    The pile-up lip is nearly a kink (steep inner flank that followed the
    shot, gentle outer flank, a rounded cap 10-20 um wide at 6.25 um), which a
    parabola through three nodes reads biased towards the gentle side by up to
    h / 2, and a straight line between nodes reads the zero crossing next to
    the lip too far out. The makima spline is local and does not overshoot at
    kinks or flat parts; on the 6.25 um surfaces subsampled to 25 um spacing it
    reads the crest within +4 ... +5 um and the dent edge within 2.5 % of the
    full-resolution values (parabola: +6 ... +11 um; straight line: +6 %),
    :func:`sampling_bias`; docs/validation.md section 4, "The metrics on known data"."""
    from scipy.interpolate import Akima1DInterpolator

    return Akima1DInterpolator(xs, us, method="makima")


def _crossing(s, x, u):
    """First x where u (>0 at x[0]) reaches 0 on the spline ``s`` (x ascending or descending); x[-1] if never."""
    from scipy.optimize import brentq

    j = int(np.argmax(u <= 0.0))
    if u[j] > 0.0:
        return x[-1]
    if j == 0 or u[j] == 0.0:
        return x[j]
    return brentq(lambda t: float(s(t)), x[j - 1], x[j], xtol=1e-12)


def _spline_max(s, lo, hi, x0, y0):
    """Largest value of the spline ``s`` on [lo, hi] and where (start: the node x0, y0)."""
    best = (x0, y0)
    for r in s.derivative().roots(extrapolate=False):
        if lo <= r <= hi and s(r) > best[1]:
            best = (float(r), float(s(r)))
    return best


def whole_line(xs, us):
    """A quarter model's surface line (x >= 0, first node on the axis x = 0) mirrored about the axis
    to the whole line; a half model's line (it has x < 0 already), or a line that does not start on
    the axis (a subsampling in :func:`sampling_bias`), as it is."""
    if abs(xs[0]) > 1e-12:
        return xs, us
    return np.concatenate([-xs[:0:-1], xs]), np.concatenate([us[:0:-1], us])


def dent_bottom(xs, us) -> float:
    """Dent depth m, read between nodes: the highest point of the surface spline within one element
    of the deepest node (:func:`surface_spline`; a quarter model's line, x >= 0, is mirrored about
    its axis first, so the spline is symmetric there and a node-aimed dent keeps its node value).
    A shot aimed between nodes has its deepest point between them, which the deepest node reads
    too shallow by up to the curvature of the dent bottom times (h / 2)^2 / 2; on the 6.25 um
    lines taken at 25 um spacing this reading is within 0.4 % of the full line on average, 0.9 % at
    worst (``bias``)."""
    xs, us = whole_line(xs, us)
    k = int(np.argmax(us))
    if k == 0 or k == len(xs) - 1:
        return float(us[k])
    return _spline_max(surface_spline(xs, us), xs[k - 1], xs[k + 1], xs[k], us[k])[1]


def surface_metrics(xs, us) -> dict:
    """Dent and pile-up figures from the surface line y = 0 (x m ascending, u_z m, + into the target).

    The line is interpolated by :func:`surface_spline`. Dent centre ``xc``: midway between the
    zero crossings of u_z on either side of the deepest node (the axis ``x = 0`` where the model
    is a quarter, x >= 0); dent radius: half their distance (x_down - xc on a quarter model);
    crest: the highest point of the interpolated surface within one element of the highest node
    downstream of the dent edge, its radius from xc and its height."""
    s = surface_spline(xs, us)
    up = surface_spline(xs, -us)  # the pile-up, positive
    k = int(np.argmax(us))
    dent = dent_bottom(xs, us)
    x_down = _crossing(s, xs[k:], us[k:])
    if xs[0] < -1e-12:  # half model: the upstream side is there
        x_up = _crossing(s, xs[: k + 1][::-1], us[: k + 1][::-1])
        xc = 0.5 * (x_up + x_down)
    else:
        xc = 0.0
    i = int(np.argmin(np.where(xs >= x_down - 1e-12, us, np.inf)))  # highest node beyond the dent edge
    lo = max(xs[max(i - 1, 0)], x_down)
    hi = xs[min(i + 1, len(xs) - 1)]
    x_crest, h_crest = _spline_max(up, lo, hi, xs[i], -us[i])
    return dict(dent_um=dent * 1e6, dent_radius_mm=(x_down - xc) * 1e3, crest_radius_mm=(x_crest - xc) * 1e3,
                crest_height_um=h_crest * 1e6, dent_centre_mm=xc * 1e3)


def surface_samplings(v: dict, step: int) -> tuple[dict, list[dict]]:
    """The surface figures (:func:`surface_metrics`) of run ``v``'s stored line in full, and of that line
    taken at every ``step``-th node from each of the ``step`` offsets; each coarse ``dent_um`` is the dent
    bottom on the *whole* line so sampled (a shot aimed off a node by off / step of an element; a quarter
    line's own offsets would leave the axis out, which no quarter mesh does)."""
    x, u = np.array(v["surface_x_mm"]) * 1e-3, np.array(v["surface_uz_um"]) * 1e-6
    xw, uw = whole_line(x, u)
    coarse = []
    for off in range(step):
        m = surface_metrics(x[off::step], u[off::step])
        m["dent_um"] = dent_bottom(xw[off::step], uw[off::step]) * 1e6
        coarse.append(m)
    return surface_metrics(x, u), coarse


def coarse_layers(v: dict, step: int) -> dict:
    """Run ``v``'s stored column profile averaged over groups of ``step`` layers (thickness-weighted; what
    a one-point element ``step`` times as thick would hold), as ``profile_z_mm`` / ``profile_mpa``."""
    edges = layer_edges(v["profile_z_mm"])
    n = (len(edges) - 1) // step * step
    coarse_edges = edges[: n + 1: step]
    thick = np.diff(edges[: n + 1])
    means = (np.array(v["profile_mpa"][:n]) * thick).reshape(-1, step).sum(1) / np.diff(coarse_edges)
    return dict(profile_z_mm=(0.5 * (coarse_edges[1:] + coarse_edges[:-1])).tolist(), profile_mpa=means.tolist())


def sampling_bias(data: dict, step: int = 4) -> list[dict]:
    """How far :func:`surface_metrics` reads a coarser sampling of the same surface: each stored
    6.25 um surface taken at every ``step``-th node (each offset), its dent radius and crest radius
    against those of the full line (um; the mean over offsets and the largest deviation). Tests
    the metric, not the element: a 25 um mesh can be no closer than this."""
    rows = []
    for key, v in sorted(data.items()):
        if not key.endswith("/6.25") or "surface_x_mm" not in v:
            continue
        full, coarse = surface_samplings(v, step)
        dr = [m["dent_radius_mm"] - full["dent_radius_mm"] for m in coarse]
        cr = [m["crest_radius_mm"] - full["crest_radius_mm"] for m in coarse]
        dd = [m["dent_um"] / full["dent_um"] - 1.0 for m in coarse]
        ch = [m["crest_height_um"] / full["crest_height_um"] - 1.0 for m in coarse]
        rows.append(dict(run=key, dent_radius_mm=full["dent_radius_mm"], crest_radius_mm=full["crest_radius_mm"],
                         dent_radius_bias_um=1e3 * float(np.mean(dr)),
                         dent_radius_worst_um=1e3 * float(np.max(np.abs(dr))),
                         crest_radius_bias_um=1e3 * float(np.mean(cr)),
                         crest_radius_worst_um=1e3 * float(np.max(np.abs(cr))),
                         dent_um=full["dent_um"], dent_bias=float(np.mean(dd)), dent_worst=float(np.min(dd)),
                         crest_height_um=full["crest_height_um"], crest_height_bias=float(np.mean(ch)),
                         crest_height_worst=float(np.min(ch))))
    return rows


def profile_sampling_bias(data: dict, step: int = 4) -> list[dict]:
    """How far the sigma_xx(z) reading is from the converged profile when that profile itself is seen
    through coarser layers: each stored 6.25 um column profile averaged over groups of ``step``
    layers (25 um layers for 4, thickness-weighted), read both ways, against the full profile's
    recovered curve (:func:`profile_rms`). Tests the reading, not the element."""
    rows = []
    for key, v in sorted(data.items()):
        if not key.endswith("/6.25") or "/physical/" not in key:
            continue
        coarse = coarse_layers(v, step)
        rows.append(dict(run=key, recovered=profile_rms(coarse, v), lines=profile_rms(coarse, v, "lines")))
    return rows


MAP_HALF = 0.2e-3  # half length (x, about the dent centre) of the stored sigma_xx(x, z) map, m
MAP_DEPTH = 0.5e-3


def sxx_map(res, mesh: BoxMesh, xc: float) -> dict:
    """sigma_xx(x, z) in the plane of incidence: per element column (its x edges) and centroid depth,
    the mean over the element rows within AXIS_ZONE of y = 0, for |x - xc| <= MAP_HALF."""
    c = res.centroids
    sel = (np.abs(c[:, 1]) <= AXIS_ZONE) & (c[:, 2] <= MAP_DEPTH) & (np.abs(c[:, 0] - xc) <= MAP_HALF)
    xs = np.unique(np.round(c[sel, 0], 12))
    zs = np.unique(np.round(c[sel, 2], 12))
    ix = np.searchsorted(xs, np.round(c[sel, 0], 12))
    iz = np.searchsorted(zs, np.round(c[sel, 2], 12))
    total = np.zeros((len(zs), len(xs)))
    count = np.zeros((len(zs), len(xs)))
    np.add.at(total, (iz, ix), res.stress[sel, 0])
    np.add.at(count, (iz, ix), 1.0)
    edges = np.asarray(mesh.x)
    i = np.searchsorted(edges, xs) - 1  # column i spans edges[i], edges[i + 1]
    return dict(map_x0_mm=(edges[i] * 1e3).tolist(), map_x1_mm=(edges[i + 1] * 1e3).tolist(),
                map_z_mm=(zs * 1e3).tolist(), map_mpa=(total / count / 1e6).tolist())


def column_profile(m: dict, xc_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """sigma_xx(z) (MPa) averaged over the column |x - xc| <= AXIS_ZONE of the map ``m``: each element
    column weighted by its overlap with the column (the exact mean of the element-wise constant
    field; on a quarter model, x >= 0, the column's half that is there). Centred on the dent
    centre, not on a grid line: an oblique dent's centre moves with the mesh (8 um at 25 um,
    14 um at 6.25 um on sae-55-45), and a column fixed in space reads a different part of the
    stress field under each mesh's dent."""
    x0, x1 = np.array(m["map_x0_mm"]), np.array(m["map_x1_mm"])
    a = AXIS_ZONE * 1e3
    w = np.clip(np.minimum(x1, xc_mm + a) - np.maximum(x0, xc_mm - a), 0.0, None)
    return np.array(m["map_z_mm"]), np.array(m["map_mpa"]) @ w / w.sum()


def layer_edges(zs_mm) -> np.ndarray:
    """Layer boundaries (mm) of element layers from their mid-depths, the top layer starting at z = 0."""
    edges = [0.0]
    for z in zs_mm:
        edges.append(2.0 * z - edges[-1])
    edges = np.array(edges)
    if np.any(np.diff(edges) <= 0):
        raise ValueError("mid-depths are not those of layers starting at the surface")
    return edges


def profile_curve(zs_mm, prof_mpa, z_mm) -> np.ndarray:
    """sigma_xx (MPa) at depths ``z_mm`` from the layer values of a column profile: the point-wise
    curve recovered from the layer means (:meth:`DepthProfile.point_values`). A one-point element's
    stress is its element's mean; straight lines between layer mid-depths read even the converged
    6.25 um profile, averaged to 25 um layers, 7.8 % (RMS of the peak) off under the 25 m/s dent,
    where its recovered curve is 2.5 % off (docs/validation.md section 4, "The metrics on known data")."""
    return DepthProfile(layer_edges(zs_mm), np.asarray(prof_mpa, dtype=float)).point_values(z_mm)


PROFILE_STEP_MM = 0.25e-3  # spacing of the depths the recovered profile is read at


def profile_metrics(zs_mm: np.ndarray, prof_mpa: np.ndarray) -> dict:
    """Peak of sigma_xx(z), its depth, and the depth where it is back to 0 below the peak, read on
    the recovered curve (:func:`profile_curve`, sampled every 0.25 um; the crossing linear between
    samples). The layer values are kept as they are (``profile_z_mm`` / ``profile_mpa``)."""
    zs_mm, prof_mpa = np.asarray(zs_mm, dtype=float), np.asarray(prof_mpa, dtype=float)
    z = np.arange(0.0, layer_edges(zs_mm)[-1], PROFILE_STEP_MM)
    s = profile_curve(zs_mm, prof_mpa, z)
    ip = int(np.argmin(s))
    after = np.nonzero(s[ip:] >= 0.0)[0]
    if len(after):
        k = ip + after[0]
        z_zero = z[k - 1] + (0 - s[k - 1]) / (s[k] - s[k - 1]) * (z[k] - z[k - 1])
    else:
        z_zero = float("nan")
    return dict(sxx_peak_mpa=float(s[ip]), sxx_peak_depth_mm=float(z[ip]), zero_depth_mm=float(z_zero),
                profile_z_mm=zs_mm.tolist(), profile_mpa=prof_mpa.tolist())


def profile_rms(v: dict, ref: dict, reading: str = "recovered") -> float:
    """RMS over 0-0.3 mm of a run's sigma_xx(z) minus the reference's, / |reference peak|.

    ``reading="recovered"``: both recovered curves (:func:`profile_curve`) every 0.25 um;
    ``"lines"`` (the former reading, printed beside it): the run's layer values by straight lines between
    mid-depths at the reference's mid-depths, against its layer values."""
    if reading == "lines":
        zr, pr = np.array(ref["profile_z_mm"]), np.array(ref["profile_mpa"])
        sel = zr <= PROFILE_DEPTH * 1e3
        p = np.interp(zr[sel], v["profile_z_mm"], v["profile_mpa"])
        return float(np.sqrt(np.mean((p - pr[sel]) ** 2)) / np.abs(pr[sel]).max())
    z = np.arange(0.0, PROFILE_DEPTH * 1e3 + 1e-12, PROFILE_STEP_MM)
    pr = profile_curve(ref["profile_z_mm"], ref["profile_mpa"], z)
    p = profile_curve(v["profile_z_mm"], v["profile_mpa"], z)
    return float(np.sqrt(np.mean((p - pr) ** 2)) / np.abs(pr).max())


def metrics(res, mesh: BoxMesh) -> dict:
    """Every figure of one single-impact run (``res``: what :func:`peenflow.fe.impact.run_impacts` returns for one shot
    on ``mesh``): the surface figures (:func:`surface_metrics`) read on the line y = 0, which is kept
    (``surface_x_mm`` / ``surface_uz_um``), the sigma_xx(x, z) map (:func:`sxx_map`) and the column profile's
    figures (:func:`profile_metrics`), the shot's contact figures, restitution, rebound velocity (m/s)
    and spin about y (rad/s; the friction's moment, :func:`friction_ratio`), energy error, and the peak
    hourglass / internal energy ratio."""
    nnx, nny, _ = mesh.shape_nodes
    X = res.nodes[: nnx * nny]
    uz = res.displacement[: nnx * nny, 2]
    row = np.abs(X[:, 1]) < 1e-12  # plane of incidence y = 0
    o = np.argsort(X[row, 0])
    xs, us = X[row, 0][o], uz[row][o]
    out = surface_metrics(xs, us)
    out.update(sxx_map(res, mesh, out["dent_centre_mm"] * 1e-3))
    zs, prof = column_profile(out, out["dent_centre_mm"])
    out.update(profile_metrics(zs, prof))
    hist = res.histories[0]
    s = res.shots
    out.update(max_approach_um=float(s["max_approach"][0]) * 1e6, peak_force_n=float(s["peak_force"][0]),
               contact_radius_um=float(s["contact_radius"][0]) * 1e6,
               max_contact_radius_um=float(s["max_contact_radius"][0]) * 1e6)
    out.update(restitution=float(s["restitution"][0]), vout_x=float(s["vout_x"][0]), vout_z=float(s["vout_z"][0]),
               spin_out_y=float(s["spin_out_y"][0]), steps=int(s["steps"][0]),
               hg_over_int=float(np.max(hist["w_hourglass"]) / np.max(hist["w_int"])),
               energy_error=float(s["energy_error"][0]), surface_x_mm=(xs * 1e3).tolist(),
               surface_uz_um=(us * 1e6).tolist())
    return out


#: the surface figures of :func:`surface_metrics` that :func:`resolution_limit` reads on a coarser line
SURFACE_FIGURES = ("dent_um", "dent_radius_mm", "crest_radius_mm", "crest_height_um")


def resolution_limit(v: dict, step: int) -> dict:
    """What a perfect element at ``step`` times the 6.25 um run ``v``'s spacing would still read off, per
    figure: (mean, largest) |relative error| of the figure read from ``v``'s own fields seen at that
    resolution against the figure read from them in full. Surface figures: its surface line taken at
    every ``step``-th node from each of the ``step`` offsets (a shot landing anywhere on the grid,
    :func:`sampling_bias`); sigma_xx figures: its column profile averaged over ``step`` layers (a
    one-point element holds its element's mean, :func:`profile_sampling_bias`), read as the runs are.
    A lower bound on any element's error at that size: it is the reading's, not the element's."""
    full, samplings = surface_samplings(v, step)
    errs: dict = {k: [abs(m[k] / full[k] - 1.0) for m in samplings] for k in SURFACE_FIGURES}
    layers = coarse_layers(v, step)
    coarse = profile_metrics(layers["profile_z_mm"], layers["profile_mpa"])
    fine = profile_metrics(v["profile_z_mm"], v["profile_mpa"])
    for k in ("sxx_peak_mpa", "zero_depth_mm"):
        errs[k] = [abs(coarse[k] / fine[k] - 1.0)]
    errs["profile_rms"] = [profile_rms(coarse, fine)]
    return {k: (float(np.mean(e)), float(np.max(e))) for k, e in errs.items()}

