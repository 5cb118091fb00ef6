"""Stage ``target_runs``: the part's REV peened with N_c shots at the control-curve velocity (paper §5).

One point per random sequence.  Snapshots at N_c/4, N_c/2 and N_c show how
the profile converges with exposure; the profile at N_c is the answer.
"""

from __future__ import annotations

import math

import xarray as xr

from ._common import peening_task, scalar
from ._rev_run import run_rev
from .params import FidelityParams, MaterialParams, ShotParams


@peening_task(version="1")
def target_runs(rev: xr.Dataset, velocity: xr.Dataset, coverage: xr.Dataset, *, material: MaterialParams,
                shot: ShotParams, fidelity: FidelityParams, angle_deg: float, sequence: int, seed: int,
                ctx=None) -> xr.Dataset:
    n_c = int(scalar(coverage, "coverage_shots_rounded"))
    ladder = sorted({max(1, math.ceil(n_c / 4)), max(1, math.ceil(n_c / 2)), n_c})
    ds = run_rev(ctx, material=material, shot=shot, fidelity=fidelity, side_m=scalar(rev, "rev_side_m"),
                 measure_side_m=scalar(rev, "measure_side_m"), thickness_m=scalar(rev, "thickness_m"),
                 angle_deg=angle_deg, velocity_m_s=scalar(velocity, "velocity_m_s"), seed=seed, ladder=ladder)
    final = ds[["stress_xx_Pa", "stress_yy_Pa"]].isel(shots=-1, drop=True)
    ds = ds.rename({"stress_xx_Pa": "ladder_stress_xx_Pa", "stress_yy_Pa": "ladder_stress_yy_Pa"})
    ds["stress_xx_Pa"] = final.stress_xx_Pa
    ds["stress_yy_Pa"] = final.stress_yy_Pa
    ds.attrs.update({"coverage_shots": n_c, "velocity_m_s": scalar(velocity, "velocity_m_s")})
    return ds
