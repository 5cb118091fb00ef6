"""How many random shot sequences a strip point needs (``almen.sequence_tolerance_mm``; issue 10 §3).

The strip runs of one (angle, velocity) form a growing sweep dimension
(:mod:`peenflow.engine.growth`): each point starts with ``almen.sequences``
sequences and gains one more while :func:`peenflow.methods.sequences_verdict`
-- the 95 % upper confidence bound of the standard error of the per-sequence
intensities -- is above the tolerance, up to ``almen.max_sequences``.  The
per-sequence intensity is computed here exactly as ``arc_height`` and
``saturation`` do (eqs. 6-11 on each sequence's own ladder), so the rule
sees what the saturation stage will report.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from peenflow.engine.growth import GrowVerdict
from peenflow.methods import fit_saturation

from .arc_height import rung_releases
from .params import SequencesParams, StripParams
from .saturation import MODELS


def sequence_intensity_m(run: xr.Dataset, fit: str, strip: StripParams) -> float:
    """Intensity (m, eq. 11) of one strip run's own ladder; NaN where its data cannot define
    saturation (as ``saturation`` records such a sequence; the rule counts it as run).

    ``run``: one ``strip_runs`` result, ``stress_xx_Pa`` with dims (shots, layer) and ``z_edge_m``.
    """
    counts = np.asarray(run.shots.values, dtype=float)
    z_edges = np.asarray(run.z_edge_m.values).reshape(-1)
    ah = rung_releases(z_edges, run.stress_xx_Pa.transpose("shots", "layer").values, strip)[0]
    try:  # NaN rungs are dropped by the fit, as in the saturation stage
        return float(fit_saturation(counts, ah, MODELS[fit]).intensity)
    except ValueError:
        return float("nan")


def sequences_rule(params: SequencesParams):
    """The growth rule of the strip runs' ``sequence`` dimension: ``until(runs, coords) -> GrowVerdict``."""

    def until(runs: list[xr.Dataset], coords: dict) -> GrowVerdict:
        v = params.verdict([sequence_intensity_m(r, params.fit, params.strip) for r in runs])
        return GrowVerdict(not v.stop, v.reason)

    return until
