"""Stage ``target_runs``: the part's REV peened at the control-curve velocity, to every coverage level (paper §5).

One point per random sequence.  The run is carried to the largest level's N_c
and snapshotted at each level's N_c -- and at N_c / 4 and N_c / 2 of each, which
show how the profile converges with exposure -- so a list of coverage levels
costs one run, not one per level.  A snapshot is the same, bit for bit, as a
separate run of its shots (:mod:`tasks._rev_run`), so the profile at a level
is that of a run stopped there.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ._common import peening_task, var
from ._rev_run import RUN, run_rev
from .coverage_curve import OUTPUTS as COVERAGE
from .outputs import Output
from .params import FidelityParams, MaterialParams, ShotParams, StreamParams
from .rev_size import OUTPUTS as REV
from .target_velocity import OUTPUTS as VELOCITY

#: a REV run's result with its profiles at each coverage level's N_c on their own, the ladder's as ``ladder_*``
OUTPUTS = RUN.derive(
    "target_runs", drop=("stress_xx_Pa", "stress_yy_Pa"),
    stress_xx_Pa=Output(("coverage_percent", "layer"), "Pa", "sigma_xx profile at each coverage level's N_c"),
    stress_yy_Pa=Output(("coverage_percent", "layer"), "Pa", "sigma_yy profile at each coverage level's N_c"),
    coverage_shots=Output(("coverage_percent",), "1", "N_c: shots of each coverage level"),
    ladder_stress_xx_Pa=Output(("shots", "layer"), "Pa", "sigma_xx profile at N_c / 4, N_c / 2 and N_c of each level"),
    ladder_stress_yy_Pa=Output(("shots", "layer"), "Pa", "sigma_yy profile at N_c / 4, N_c / 2 and N_c of each level"),
)


def coverage_ladder(n_c) -> list[int]:
    """The rungs of a run to the coverage levels whose shots are ``n_c``: N_c / 4, N_c / 2 and N_c of each."""
    return sorted({r for n in (int(x) for x in n_c) for r in (max(1, math.ceil(n / 4)), max(1, math.ceil(n / 2)), n)})


@peening_task(version="2")  # 2: one run to the largest coverage level, a profile at each level
def target_runs(rev: xr.Dataset, velocity: xr.Dataset, coverage: xr.Dataset, *, material: MaterialParams,
                shot: ShotParams, fidelity: FidelityParams, angle_deg: float, sequence: int, seed: int,
                stream: StreamParams | None = None, ctx=None) -> xr.Dataset:
    n_c = COVERAGE.coverage_shots_rounded.read(coverage).astype(int)
    levels = np.asarray(coverage.coverage_percent.values, dtype=float)
    speed = VELOCITY.velocity_m_s.read(velocity)
    ds = run_rev(ctx, material=material, shot=shot, fidelity=fidelity, side_m=REV.rev_side_m.read(rev),
                 measure_side_m=REV.measure_side_m.read(rev), thickness_m=REV.thickness_m.read(rev),
                 angle_deg=angle_deg, velocity_m_s=speed, seed=seed, ladder=coverage_ladder(n_c), stream=stream)
    at_levels = ds[["stress_xx_Pa", "stress_yy_Pa"]].sel(shots=list(n_c)).rename({"shots": "coverage_percent"})
    ds = ds.rename({"stress_xx_Pa": "ladder_stress_xx_Pa", "stress_yy_Pa": "ladder_stress_yy_Pa"})
    ds = ds.assign_coords(coverage_percent=var(levels, ("coverage_percent",), "%", "coverage level"))
    for c in ("xx", "yy"):
        ds[f"ladder_stress_{c}_Pa"].attrs["long_name"] = getattr(OUTPUTS, f"ladder_stress_{c}_Pa").long_name
        ds[f"stress_{c}_Pa"] = getattr(OUTPUTS, f"stress_{c}_Pa").variable(at_levels[f"stress_{c}_Pa"].values)
    ds["coverage_shots"] = OUTPUTS.coverage_shots.variable(n_c)
    ds.attrs.update({"velocity_m_s": speed})
    return ds
