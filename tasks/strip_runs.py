"""Stage ``strip_runs``: Almen-strip REV runs, one per (angle, velocity, sequence) (paper §4.1).

The strip REV (side from ``strip_rev``, the strip's thickness, SAE 1070) is
peened by one sequence of shots up to the largest N of the saturation
ladder; a relaxed snapshot at every rung gives σ(z) for every N from one
run (the paper runs each N separately: 7 x the work).

With ``almen.shot_counts = "auto"`` the graph passes ``extend`` instead of a
ladder the user guessed: the run doubles its ladder from ``almen.first_shots``
and stops at the first rung where eq. (11) holds inside its own data
(:func:`peenflow.methods.ladder_verdict`), or at ``almen.max_shots``.
"""

from __future__ import annotations

import xarray as xr

from ._common import peening_task
from ._rev_run import RUN, run_rev
from .params import FidelityParams, LadderParams, MaterialParams, ShotParams, StreamParams
from .rev_size import OUTPUTS as REV

OUTPUTS = RUN.derive("strip_runs")


@peening_task(version="1")
def strip_runs(rev: xr.Dataset, *, material: MaterialParams, shot: ShotParams, fidelity: FidelityParams,
               angle_deg: float, velocity_m_s: float, sequence: int, seed: int, shot_counts: list | None = None,
               extend: LadderParams | None = None, stream: StreamParams | None = None, ctx=None) -> xr.Dataset:
    return run_rev(ctx, material=material, shot=shot, fidelity=fidelity, side_m=REV.rev_side_m.read(rev),
                   measure_side_m=REV.measure_side_m.read(rev), thickness_m=REV.thickness_m.read(rev),
                   angle_deg=angle_deg, velocity_m_s=velocity_m_s, seed=seed, ladder=shot_counts, extend=extend,
                   stream=stream)
