"""Stage ``residual_profile``: the part's residual-stress profile with its spread (paper §5, Fig. 19).

σx(z), σy(z) averaged over the REV's measuring region, per sequence, then
the mean and spread over sequences; compared with a measured profile when
the study gives one (interpolated onto the measured depths: difference,
RMS difference, peak compressive stress and its depth side by side).

The REV is held at its bottom face, so its stresses are those of a part that
cannot bend. When the REV spans the whole part thickness (a plate peened on
one face, like the paper's disk) the stage also gives the profile of the
*free* part: the plate releases its membrane force and bending moment per
unit width (the plate analogue of eqs. 6-8),

    σ_free(z) = σ(z) - N/H - 12 M (z - H/2) / H³,
    N = ∫ σ dz,  M = ∫ σ (z - H/2) dz,

per in-plane component (a stress change linear in z is fixed by its two
resultants, whatever the elastic constants), and the free plate's bow from
plate bending, κx = 12 (M_x - ν M_y) / (E H³), positive when the peened face
turns convex (as an Almen strip does; eq. 9 is the beam form, ν = 0).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from peenflow.methods import DepthProfile, equilibrium_residual

from ._common import depth as depth_coord, peening_task, var
from .coverage_curve import OUTPUTS as COVERAGE
from .outputs import Output, Outputs
from .params import MeasuredProfile, PlateParams
from .target_velocity import OUTPUTS as VELOCITY


def _per_component() -> dict:
    out = {}
    for c in ("xx", "yy"):
        out.update({
            f"stress_{c}_Pa": Output(("sequence", "coverage_percent", "layer"), "Pa", f"sigma_{c} per sequence"),
            f"stress_{c}_mean_Pa": Output(("coverage_percent", "layer"), "Pa", f"mean sigma_{c}"),
            f"stress_{c}_spread_Pa": Output(("coverage_percent", "layer"), "Pa", "std over sequences"),
            f"peak_compressive_{c}_Pa": Output(("coverage_percent",), "Pa", f"most compressive mean sigma_{c}"),
            f"peak_compressive_{c}_depth_m": Output(("coverage_percent",), "m",
                                                    f"depth of the most compressive mean sigma_{c}"),
            # the free part: only when the REV spans the part's thickness
            f"stress_{c}_free_mean_Pa": Output(("coverage_percent", "layer"), "Pa", f"mean sigma_{c} of the free part "
                                               "(membrane force and bending moment released)", optional=True),
            f"bow_curvature_{c}_1_per_m": Output(("coverage_percent",), "m-1", "curvature of the free part, positive "
                                                 "when the peened face is convex", optional=True),
            f"free_relative_force_{c}": Output(("coverage_percent",), "1", "|∫σ dz| / ∫|σ| dz of the free part (0 = "
                                               "equilibrium)", optional=True),
            f"free_relative_moment_{c}": Output(("coverage_percent",), "1", "|∫σ (z-H/2) dz| / ∫|σ||z-H/2| dz of the "
                                                "free part", optional=True),
        })
    return out


#: the measured profile's comparison: only when the study gives one
_MEASURED = {
    "measured_stress_Pa": Output(("measured_point",), "Pa", "measured residual stress", optional=True),
    "measured_component": Output(("measured_point",), "1", "stress component of the measurement", optional=True,
                                 attrs={"flag_values": np.array([0, 1], dtype=np.int8),
                                        "flag_meanings": "sigma_xx sigma_yy"}),
    "predicted_at_measured_Pa": Output(("coverage_percent", "measured_point"), "Pa", "predicted mean stress of the "
                                       "same component at the measured depth", optional=True),
    "rms_difference_Pa": Output(("coverage_percent",), "Pa", "RMS of predicted - measured", optional=True),
    "measured_peak_compressive_Pa": Output((), "Pa", "most compressive measured stress", optional=True),
    "measured_peak_depth_m": Output((), "m", "depth of the most compressive measured stress", optional=True),
}

#: what the map of a process needs beside the profile: the velocity and the exposure that made it
_PROCESS = {
    "velocity_m_s": Output((), "m s-1", "shot velocity of the part's REV runs"),
    "full_coverage_shots": Output((), "1", "N_f: shots for full coverage of the REV (eq. 5)"),
    "coverage_shots": Output(("coverage_percent",), "1", "N_c: shots of each coverage level"),
}

OUTPUTS = Outputs("residual_profile", **_per_component(), **_MEASURED, **_PROCESS)


def _peak(depth, values):
    k = int(np.nanargmin(values))
    return float(values[k]), float(depth[k])


def _one_profile(values: np.ndarray) -> np.ndarray:
    """The first sequence's copy of a per-layer array the runs share."""
    values = np.asarray(values)
    return values.reshape(-1, values.shape[-1])[0] if values.ndim > 1 else values


def _free_plate(z_edges: np.ndarray, stress: dict, part: PlateParams) -> tuple[dict, dict]:
    """Release of a plate of thickness H = ``part.thickness_m`` (module docstring).

    ``stress``: {"xx": (n_layer,) Pa, "yy": ...} layer values; returns the
    released layer values (Pa) per component and the bow per component
    (1/m, positive when the peened face turns convex).
    """
    H = part.thickness_m
    E, nu = part.youngs_modulus_Pa, part.poisson_ratio
    released, moment, balance = {}, {}, {}
    for c, s in stress.items():
        prof = DepthProfile(z_edges, s)
        force, moment[c] = prof.moments(origin=0.5 * H)
        free = prof.minus_linear(force / H, 12.0 * moment[c] / H**3, origin=0.5 * H)
        balance[c] = equilibrium_residual(free, H)
        # minus_linear returns nodal values at both sides of every layer edge;
        # the mean of a layer's two ends is its (linear) layer average.
        released[c] = 0.5 * (free.values[0::2] + free.values[1::2])
    bow = {"xx": 12.0 * (moment["xx"] - nu * moment["yy"]) / (E * H**3),
           "yy": 12.0 * (moment["yy"] - nu * moment["xx"]) / (E * H**3)}
    return released, bow, balance


@peening_task(version="5")  # 5: a profile per coverage level, with the velocity, N_f and N_c beside it
def residual_profile(runs: xr.Dataset, velocity: xr.Dataset, coverage: xr.Dataset, *,
                     measured: MeasuredProfile | None = None, free_part: PlateParams | None = None) -> xr.Dataset:
    """``runs``: target REV results combined over ``sequence`` (profiles per coverage level);
    ``velocity``, ``coverage``: the target's velocity and coverage curve; ``measured``: the measured points
    (SI) or None; ``free_part``: the part as a plate, or None; the released profile and bow are added when
    the REV spans that thickness (a thinner REV does not hold the part's resultants)."""
    depth = _one_profile(runs.depth_m.values)
    levels = np.asarray(runs.coverage_percent.values, dtype=float)
    out = {"velocity_m_s": VELOCITY.velocity_m_s.read(velocity),
           "full_coverage_shots": COVERAGE.full_coverage_shots.read(coverage),
           "coverage_shots": COVERAGE.coverage_shots.read(coverage)}
    means = {}
    for c in ("xx", "yy"):
        s = runs[f"stress_{c}_Pa"].transpose("sequence", "coverage_percent", "layer").values
        means[c] = s.mean(axis=0)
        out[f"stress_{c}_Pa"] = s
        out[f"stress_{c}_mean_Pa"] = means[c]
        out[f"stress_{c}_spread_Pa"] = s.std(axis=0, ddof=1) if s.shape[0] > 1 else np.zeros(s.shape[1:])
        peaks = [_peak(depth, m) for m in means[c]]
        out[f"peak_compressive_{c}_Pa"] = np.array([pk for pk, _ in peaks])
        out[f"peak_compressive_{c}_depth_m"] = np.array([at for _, at in peaks])
    coords = {"sequence": var(runs.sequence.values, ("sequence",), "1", "random shot sequence number"),
              "coverage_percent": var(levels, ("coverage_percent",), "%", "coverage level"),
              "depth_m": depth_coord(depth, "layer", "layer mid-depth below the peened surface")}
    attrs = {"measured_profile": "none", "free_part": "no (the REV is thinner than the part)"}
    z_edges = _one_profile(runs.z_edge_m.values)
    if free_part and abs(z_edges[-1] - free_part.thickness_m) <= 1e-9 * free_part.thickness_m:
        per_level = [_free_plate(z_edges, {c: means[c][k] for c in ("xx", "yy")}, free_part)
                     for k in range(levels.size)]
        for c in ("xx", "yy"):
            out[f"stress_{c}_free_mean_Pa"] = np.array([released[c] for released, _, _ in per_level])
            out[f"bow_curvature_{c}_1_per_m"] = np.array([bow[c] for _, bow, _ in per_level])
            out[f"free_relative_force_{c}"] = np.array([b[c].relative_force for _, _, b in per_level])
            out[f"free_relative_moment_{c}"] = np.array([b[c].relative_moment for _, _, b in per_level])
        attrs["free_part"] = f"plate {free_part.thickness_m * 1e3:g} mm thick, released"
    if measured:
        md = np.asarray(measured.depth_m, dtype=float)
        ms = np.asarray(measured.stress_Pa, dtype=float)
        comp = np.asarray(measured.component)
        # each point against our mean profile of its own component, at every coverage level
        ours = np.empty((levels.size, md.size))
        for c in ("xx", "yy"):
            at = comp == c
            for k in range(levels.size):
                ours[k, at] = np.interp(md[at], depth, means[c][k])
        coords["measured_point"] = var(np.arange(md.size), ("measured_point",), "1", "measured point number")
        coords["measured_depth_m"] = depth_coord(md, "measured_point", "depth of the measured point")
        out["measured_stress_Pa"] = ms
        out["measured_component"] = (comp == "yy").astype(np.int8)
        out["predicted_at_measured_Pa"] = ours
        out["rms_difference_Pa"] = np.sqrt(np.mean((ours - ms) ** 2, axis=1))
        out["measured_peak_compressive_Pa"], out["measured_peak_depth_m"] = _peak(md, ms)
        counts = ", ".join(f"{int((comp == c).sum())} sigma_{c}" for c in ("xx", "yy") if (comp == c).any())
        attrs["measured_profile"] = f"{md.size} points ({counts})"
    return OUTPUTS.dataset(out, coords=coords, attrs=attrs)
