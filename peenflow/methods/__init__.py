"""The paper's post-processing mathematics, in numpy/scipy (no FE, no xarray, no I/O).

Arrays in, arrays or frozen dataclasses out, SI units (m, Pa, m/s, s) unless a
name says otherwise (``angle_deg``, ``*_percent``). One concept per module:

* :mod:`.shot_stream`      -- random shot centres (eqs. 2-3), velocities, landing points, arrival order
* :mod:`.indentation`      -- the dent ellipse through the pile-up crest of a single impact (Figs. 8-10)
* :mod:`.coverage`         -- Monte-Carlo coverage, closed form, Avrami fit (eq. 5), N_f and N_c
* :mod:`.dmin`             -- eq. (4) stress regions, two-impact overlap, d_min search, REV sizes
* :mod:`.residual_profile` -- depth profiles, region averaging per layer, self-equilibrium check
* :mod:`.arc_height`       -- Almen strips, clamping force/moment and arc height (eqs. 6-9)
* :mod:`.saturation`       -- saturation fits (eq. 10, SAE J2597 style), eq. (11), intensity
* :mod:`.measured_strips`  -- a shop's measured strips: the three fits judged, one intensity reported
* :mod:`.ladder`           -- a doubling shot ladder and when it may stop (eq. (11) inside its data)
* :mod:`.sequences`        -- adaptive sequences: enough when the intensity's standard error meets a tolerance
* :mod:`.control_curve`    -- intensity vs velocity per angle, inverse, angle interpolation
* :mod:`.mesh_extrapolation` -- paired two-level extrapolation of a study-level output to zero element size
"""

from .arc_height import StripRelease, clamping_force_moment, release_strip
from .control_curve import AngleBlend, ControlCurve, ControlCurveFamily
from .coverage import (
    FULL_COVERAGE_PERCENT,
    AvramiFit,
    coverage_curve,
    coverage_curves,
    coverage_percent,
    expected_coverage_uniform,
    first_cover_index,
    fit_avrami,
    measuring_grid,
)
from .dmin import (
    REGION_FRACTION,
    DminSearch,
    RevGeometry,
    bracket_from_radius,
    find_dmin,
    scan_dmin,
    impact_region,
    regions_overlap,
    single_impact_region_radius,
    stress_region,
)
from .indentation import DentEllipse, dent_ellipse
from .mesh_extrapolation import PairedCorrection, extrapolation_factor, paired_correction, two_level_limit
from .ladder import LadderVerdict, doubling_ladder, ladder_verdict
from .measured_strips import FitVerdict, StripDataError, StripIntensity, strip_intensity
from .residual_profile import VOIGT, DepthProfile, EquilibriumResidual, LayerAverage, average_over_region, equilibrium_residual
from .saturation import GROWTH_RATIO, SaturationFit, SequenceSaturation, fit_saturation, fit_sequences
from .sequences import SequencesVerdict, sequences_verdict
from .shot_stream import (ShotStream, generate_centres, impingement_direction, landing_points, largest_factor, shot_stream,
                          spread_factors)

__all__ = [
    "StripRelease", "clamping_force_moment", "release_strip",
    "AngleBlend", "ControlCurve", "ControlCurveFamily",
    "FULL_COVERAGE_PERCENT", "AvramiFit", "coverage_curve", "coverage_curves", "coverage_percent",
    "expected_coverage_uniform", "first_cover_index", "fit_avrami", "measuring_grid",
    "REGION_FRACTION", "DminSearch", "RevGeometry", "bracket_from_radius", "find_dmin", "scan_dmin", "impact_region",
    "regions_overlap", "single_impact_region_radius", "stress_region",
    "DentEllipse", "dent_ellipse",
    "LadderVerdict", "doubling_ladder", "ladder_verdict",
    "FitVerdict", "StripDataError", "StripIntensity", "strip_intensity",
    "PairedCorrection", "extrapolation_factor", "paired_correction", "two_level_limit",
    "VOIGT", "DepthProfile", "EquilibriumResidual", "LayerAverage", "average_over_region", "equilibrium_residual",
    "GROWTH_RATIO", "SaturationFit", "SequenceSaturation", "fit_saturation", "fit_sequences",
    "SequencesVerdict", "sequences_verdict",
    "ShotStream", "generate_centres", "impingement_direction", "landing_points", "largest_factor", "shot_stream",
    "spread_factors",
]
