"""Stages ``verify_runs`` and ``verified_settings``: the part computed at the suggested coverage
(``[requirements] verify = true``), beside what the map predicted there.

``suggested_settings`` interpolates the map's features between its coverage levels.  A verification runs,
at the map point the suggestion chose, every sequence's REV run again to the suggested coverage's N_c --
the same shot stream as the map's runs of that point (drawn for the map's largest level), stopped after
N_c = (coverage / 100) N_f shots and relaxed (:func:`tasks._rev_run.run_rev` with ``sequence_shots``) -- so
the computed profile is what a map level at that coverage would have held.  ``verify_runs`` has one point
per map point and sequence; the points the suggestion did not choose return at once with ``selected = 0``
(no REV run), so the verification costs one map level's runs.  ``verified_settings`` reads the chosen
runs and gives each requirement's predicted and computed value, the difference, and whether the computed
part meets it.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from peenflow.methods.profile_features import compressive_depth

from . import _kernel as K
from ._common import depth as depth_coord
from ._common import peening_task
from ._rev_run import run_rev
from .coverage_curve import OUTPUTS as COVERAGE
from .outputs import Output, Outputs
from .params import FidelityParams, MaterialParams, RequirementParams, ShotParams, StreamParams
from .rev_size import OUTPUTS as REV
from .suggested_settings import OUTPUTS as SUGGESTION
from .suggested_settings import _inside, _margin, _readable
from .target_velocity import OUTPUTS as VELOCITY

RUNS = Outputs(
    "verify_runs",
    selected=Output((), "1", "1 if the suggestion chose this map point (and this run was made)",
                    attrs={"flag_values": np.array([0, 1]), "flag_meanings": "not_chosen chosen"}),
    coverage_percent_run=Output((), "%", "the suggested coverage the run went to (NaN: not chosen)"),
    coverage_shots=Output((), "1", "N_c of that coverage: the shots run (0: not chosen)"),
    stress_xx_Pa=Output(("layer",), "Pa", "sigma_xx profile after N_c shots, relaxed (NaN: not chosen)"),
    stress_yy_Pa=Output(("layer",), "Pa", "sigma_yy profile after N_c shots, relaxed (NaN: not chosen)"),
)


@peening_task(version="1")
def verify_runs(suggestion: xr.Dataset, rev: xr.Dataset, velocity: xr.Dataset, coverage: xr.Dataset, *,
                material: MaterialParams, shot: ShotParams, fidelity: FidelityParams, angle_deg: float,
                sequence: int, seed: int, point: dict, stream: StreamParams | None = None, ctx=None) -> xr.Dataset:
    """One sequence of the map point ``point`` ({process dimension: index}) run to the suggested coverage
    if the suggestion chose that point (module docstring); else ``selected = 0`` at once."""
    chosen = bool(SUGGESTION.met.read(suggestion)) and all(
        int(suggestion.attrs.get(f"selected_index_{d}", -1)) == int(i) for d, i in point.items())
    mesh = K.rev_mesh(fidelity, REV.rev_side_m.read(rev), REV.thickness_m.read(rev))
    z = mesh.z
    depth = depth_coord(0.5 * (z[1:] + z[:-1]), "layer", "layer mid-depth below the peened surface")
    if not chosen:
        nan = np.full(len(z) - 1, np.nan)
        return RUNS.dataset({"selected": 0, "coverage_percent_run": np.nan, "coverage_shots": 0,
                             "stress_xx_Pa": nan, "stress_yy_Pa": nan}, coords={"depth_m": depth})
    level = float(suggestion.attrs["selected_coverage_percent"])
    # N_c by the coverage stage's rule (peenflow.methods.AvramiFit.shots_for_coverage): a suggestion lies
    # between two map levels, both >= the smallest level; below 100 % it is the Avrami inverse
    n_f = COVERAGE.full_coverage_shots.read(coverage)
    full = float(coverage.attrs["full_coverage_percent"])
    rate = COVERAGE.avrami_rate.read(coverage)
    n_c = level / 100.0 * n_f if level >= 100.0 else (n_f if level >= full else -math.log1p(-level / 100.0) / rate)
    n_c = max(1, math.ceil(n_c))
    longest = int(np.max(COVERAGE.coverage_shots_rounded.read(coverage)))
    ds = run_rev(ctx, material=material, shot=shot, fidelity=fidelity, side_m=REV.rev_side_m.read(rev),
                 measure_side_m=REV.measure_side_m.read(rev), thickness_m=REV.thickness_m.read(rev),
                 angle_deg=angle_deg, velocity_m_s=VELOCITY.velocity_m_s.read(velocity), seed=seed,
                 ladder=[n_c], sequence_shots=max(longest, n_c), stream=stream)
    return RUNS.dataset({"selected": 1, "coverage_percent_run": level, "coverage_shots": n_c,
                         "stress_xx_Pa": ds.stress_xx_Pa.sel(shots=n_c).values,
                         "stress_yy_Pa": ds.stress_yy_Pa.sel(shots=n_c).values}, coords={"depth_m": depth})


OUTPUTS = Outputs(
    "verified_settings",
    verified=Output((), "1", "1 if the suggested point was computed (the suggestion met the requirements)",
                    attrs={"flag_values": np.array([0, 1]), "flag_meanings": "not_verified verified"}),
    met_computed=Output((), "1", "1 if the computed part meets every requirement",
                        attrs={"flag_values": np.array([0, 1]), "flag_meanings": "not_met met"}),
    predicted_value=Output(("requirement",), "1", "the map's interpolated feature at the suggestion, SI (units: "
                                                  "attribute requirement_units)"),
    computed_value=Output(("requirement",), "1", "the computed part's feature, SI"),
    computed_margin=Output(("requirement",), "1", "how far the computed feature meets its bound, relative to it "
                                                  "(< 0: missed)"),
    stress_xx_mean_Pa=Output(("layer",), "Pa", "computed mean sigma_xx over sequences (NaN: not verified)"),
    stress_yy_mean_Pa=Output(("layer",), "Pa", "computed mean sigma_yy over sequences (NaN: not verified)"),
)


def profile_features(depth: np.ndarray, xx: np.ndarray, yy: np.ndarray) -> dict:
    """The process map's features (``tasks.process_map``'s variable names, SI) of mean profiles on ``depth``."""
    out = {}
    for c, s in (("xx", xx), ("yy", yy)):
        k = int(np.nanargmin(s))
        zc = compressive_depth(depth, s)[0]
        out.update({f"surface_stress_{c}_Pa": float(s[0]), f"peak_compressive_{c}_Pa": float(s[k]),
                    f"peak_compressive_{c}_depth_m": float(depth[k]),
                    f"compressive_depth_{c}_m": np.nan if zc is None else float(zc)})
    return out


@peening_task(version="1")
def verified_settings(suggestion: xr.Dataset, runs: xr.Dataset, *, requirements: RequirementParams) -> xr.Dataset:
    """The chosen runs of ``runs`` (every map point and sequence, combined) against the suggestion."""
    r = requirements
    n = len(r.bounds)
    flags = RUNS.selected.read(runs) if runs.selected.ndim == 0 else np.asarray(runs.selected.values)
    attrs = {"requirement_units": " ".join(u for _, u, _, _, _ in r.bounds)}
    names = " ".join(key for *_, key in r.bounds)
    coords = {"requirement": xr.Variable(("requirement",), np.arange(n), attrs={
        "long_name": "requirement", "units": "1", "flag_values": np.arange(n), "flag_meanings": names})}
    layer_dims = [d for d in runs.stress_xx_Pa.dims if d != "layer"]
    stacked = runs.stack(_run=layer_dims) if layer_dims else runs.expand_dims(_run=[0])
    chosen = [k for k in range(stacked.sizes["_run"]) if int(stacked.selected.isel(_run=k)) == 1]
    depth = np.asarray(runs.depth_m.values).reshape(-1, runs.sizes["layer"])[0]
    if not chosen:
        nan = np.full(runs.sizes["layer"], np.nan)
        return OUTPUTS.dataset({"verified": 0, "met_computed": 0, "predicted_value": np.full(n, np.nan),
                                "computed_value": np.full(n, np.nan), "computed_margin": np.full(n, np.nan),
                                "stress_xx_mean_Pa": nan, "stress_yy_mean_Pa": nan},
                               coords={**coords, "depth_m": depth_coord(depth, "layer", "layer mid-depth")},
                               attrs={**attrs, "verdict": "nothing to verify: the suggestion met no requirement"})
    xx = np.mean([stacked.stress_xx_Pa.isel(_run=k).values for k in chosen], axis=0)
    yy = np.mean([stacked.stress_yy_Pa.isel(_run=k).values for k in chosen], axis=0)
    features = profile_features(depth, xx, yy)
    predicted = np.asarray(SUGGESTION.requirement_value.read(suggestion), dtype=float)
    computed = np.array([features[v] for v, *_ in r.bounds])
    margins = np.array([_margin(c, lo, hi) for c, (_, _, lo, hi, _) in zip(computed, r.bounds)])
    met = all(_inside(c, lo, hi) for c, (_, _, lo, hi, _) in zip(computed, r.bounds))
    level = float(stacked.coverage_percent_run.isel(_run=chosen[0]))
    shots = int(stacked.coverage_shots.isel(_run=chosen[0]))
    diffs = "; ".join(f"{key}: computed {_readable(c, unit)} against {_readable(p, unit)} predicted "
                      f"({(c - p) / abs(p):+.1%})" for c, p, (_, unit, _, _, key) in zip(computed, predicted, r.bounds))
    verdict = (f"computed at {level:.4g} % coverage (N_c = {shots} shots, {len(chosen)} sequence(s)): " + diffs
               + ("; every requirement met" if met else "; NOT every requirement met by the computed part"))
    return OUTPUTS.dataset({"verified": 1, "met_computed": int(met), "predicted_value": predicted,
                            "computed_value": computed, "computed_margin": margins,
                            "stress_xx_mean_Pa": xx, "stress_yy_mean_Pa": yy},
                           coords={**coords, "depth_m": depth_coord(depth, "layer", "layer mid-depth below the "
                                                                                    "peened surface")},
                           attrs={**attrs, "verdict": verdict, "coverage_percent": level, "coverage_shots": shots})
