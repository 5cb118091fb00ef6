"""Stage ``target_runs``: the part's REV peened with N_c shots at the control-curve velocity (paper §5).

One point per random sequence.  Snapshots at N_c/4, N_c/2 and N_c show how
the profile converges with exposure; the profile at N_c is the answer.
"""

from __future__ import annotations

import math

import xarray as xr

from ._common import peening_task
from ._rev_run import RUN, run_rev
from .coverage_curve import OUTPUTS as COVERAGE
from .outputs import Output
from .params import FidelityParams, MaterialParams, ShotParams
from .rev_size import OUTPUTS as REV
from .target_velocity import OUTPUTS as VELOCITY

#: a REV run's result with its profiles at N_c on their own, the ladder's as ``ladder_*``
OUTPUTS = RUN.derive(
    "target_runs", drop=("stress_xx_Pa", "stress_yy_Pa"),
    stress_xx_Pa=Output(("layer",), "Pa", "sigma_xx profile at N_c"),
    stress_yy_Pa=Output(("layer",), "Pa", "sigma_yy profile at N_c"),
    ladder_stress_xx_Pa=Output(("shots", "layer"), "Pa", "sigma_xx profile at N_c / 4, N_c / 2 and N_c"),
    ladder_stress_yy_Pa=Output(("shots", "layer"), "Pa", "sigma_yy profile at N_c / 4, N_c / 2 and N_c"),
)


@peening_task(version="1")
def target_runs(rev: xr.Dataset, velocity: xr.Dataset, coverage: xr.Dataset, *, material: MaterialParams,
                shot: ShotParams, fidelity: FidelityParams, angle_deg: float, sequence: int, seed: int,
                ctx=None) -> xr.Dataset:
    n_c = int(COVERAGE.coverage_shots_rounded.read(coverage))
    speed = VELOCITY.velocity_m_s.read(velocity)
    ladder = sorted({max(1, math.ceil(n_c / 4)), max(1, math.ceil(n_c / 2)), n_c})
    ds = run_rev(ctx, material=material, shot=shot, fidelity=fidelity, side_m=REV.rev_side_m.read(rev),
                 measure_side_m=REV.measure_side_m.read(rev), thickness_m=REV.thickness_m.read(rev),
                 angle_deg=angle_deg, velocity_m_s=speed, seed=seed, ladder=ladder)
    final = ds[["stress_xx_Pa", "stress_yy_Pa"]].isel(shots=-1, drop=True)
    ds = ds.rename({"stress_xx_Pa": "ladder_stress_xx_Pa", "stress_yy_Pa": "ladder_stress_yy_Pa"})
    for c in ("xx", "yy"):
        ds[f"ladder_stress_{c}_Pa"].attrs["long_name"] = getattr(OUTPUTS, f"ladder_stress_{c}_Pa").long_name
        ds[f"stress_{c}_Pa"] = getattr(OUTPUTS, f"stress_{c}_Pa").variable(final[f"stress_{c}_Pa"].values)
    ds.attrs.update({"coverage_shots": n_c, "velocity_m_s": speed})
    return ds
