"""What a fidelity is measured to cost in accuracy: the statement every result of a study carries.

Single impact (BENCHMARKS.md section 4c, ``benchmarks/bench_hourglass.py table``):
the worst error over the four cases there -- S230 on SAE 1070 at 25 and 55 m/s
normal and at 55 m/s, 45 deg; on Al 7075-T73 at 47 m/s, 65 deg -- of the
kernel's default element (physical hourglass stabilisation) at each element
size, against converged references (6.25 um, Richardson where the order is
clean).  Dent depth, sigma_xx peak and zero-crossing depth in per cent of the
reference, restitution as a difference, the sigma_xx(z) profile as its RMS
over 0-0.3 mm in per cent of the reference peak.

Study level (BENCHMARKS.md section 9, ``benchmarks/bench_reference.py``):
the Almen intensity of two strip points (90 deg / 55 m/s and 67.5 deg /
35 m/s; periodic 1.2 mm REV, standard preset values, only the element size
varied, paired shot streams) against its reference: the Richardson
extrapolation of the three finest levels (40 / 25 / 16 um) where they
converge monotonically with an order in [0.5, 4], else the finest level.
Two points, so a statement of what was measured, not a bound.  The velocity
for a target intensity, N_f and the profile are not measured yet, and said
so.

A statement is written on every result a study computes (the engine's
``graph.result_attrs``: provenance, outside keys and content hashes), printed
with the headline numbers and tabled in README.md.
"""

from __future__ import annotations

__all__ = ["SINGLE_IMPACT", "SINGLE_IMPACT_SOURCE", "STUDY_LEVEL_INTENSITY", "STUDY_LEVEL_SOURCE",
           "single_impact_error", "study_level_error", "statement"]

#: element size um -> worst error over the four cases: (dent %, sigma_xx peak %, zero crossing %,
#: restitution, profile RMS %), BENCHMARKS.md section 4c
SINGLE_IMPACT: dict[float, tuple[float, float, float, float, float]] = {
    60.0: (8.4, 33.2, 6.3, 0.083, 20.5),
    50.0: (6.2, 23.5, 9.9, 0.059, 17.2),
    40.0: (9.4, 22.4, 2.8, 0.044, 12.3),
    25.0: (4.5, 13.0, 2.6, 0.012, 7.7),
    12.5: (1.2, 5.2, 0.2, 0.006, 3.3),
}
SINGLE_IMPACT_SOURCE = "BENCHMARKS.md section 4c"
#: element size um -> (smallest, largest) intensity error in % over the two strip points, against
#: their references (module docstring), BENCHMARKS.md section 9
STUDY_LEVEL_INTENSITY: dict[float, tuple[float, float]] = {
    60.0: (-10.6, -9.3),
    40.0: (-4.7, -4.5),
    25.0: (-1.8, 0.1),
}
STUDY_LEVEL_SOURCE = "BENCHMARKS.md section 9"


def single_impact_error(element_size_um: float) -> str | None:
    """The measured single-impact error at this element size as one sentence, or None if not measured."""
    for h, (dent, peak, zero, rest, rms) in SINGLE_IMPACT.items():
        if abs(h - element_size_um) <= 1e-9 * h:
            return (f"single impact at {h:g} um (worst of 4 cases, {SINGLE_IMPACT_SOURCE}): dent depth "
                    f"<= {dent:g} %, sigma_xx peak <= {peak:g} %, zero crossing <= {zero:g} %, "
                    f"restitution <= {rest:g}, sigma_xx(z) RMS <= {rms:g} % of the peak")
    return None


def study_level_error(element_size_um: float) -> str:
    """The measured study-level error at this element size as one sentence."""
    for h, (lo, hi) in STUDY_LEVEL_INTENSITY.items():
        if abs(h - element_size_um) <= 1e-9 * h:
            return (f"study level ({STUDY_LEVEL_SOURCE}: 2 strip points against references from 40 / 25 / 16 um): "
                    f"Almen intensity {lo:+.1f} ... {hi:+.1f} % at {h:g} um; the velocity for a target "
                    "intensity, N_f and the profile not measured yet")
    return f"study level not measured at {element_size_um:g} um ({STUDY_LEVEL_SOURCE})"


def statement(fidelity) -> dict[str, str]:
    """``peenflow_fidelity`` (what made the result) and ``peenflow_fidelity_error`` (what that is
    measured to cost) for a loaded :class:`~peenflow.study.fidelity.Fidelity`."""
    h = fidelity.element_size_um
    single = single_impact_error(h) or (
        f"single impact not measured at {h:g} um (measured: "
        + ", ".join(f"{k:g}" for k in SINGLE_IMPACT) + f" um, {SINGLE_IMPACT_SOURCE})")
    return {
        "peenflow_fidelity": f"{fidelity.describe()}: {h:g} um elements, lateral faces {fidelity.lateral_boundary}",
        "peenflow_fidelity_error": f"{single}; {study_level_error(h)}",
    }
