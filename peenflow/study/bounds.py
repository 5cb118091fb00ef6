"""Validated ranges: numeric study keys inside what the kernel and methods have been checked for.

The section models refuse what is impossible (a negative velocity, an angle
above 90 deg). The bounds here refuse what is possible but has never been
validated and has been seen to fail or run away (a 1e6 m/s shot hung a run;
10 000 % coverage ran away at shot 2413; a REV smaller than an element failed
deep in ``coverage_curve``): every value is refused before any compute, with
the key, the value, the range and where the range comes from.

A study may go outside a bound only explicitly, naming the key in
``[study] allow_outside_bounds = ["target.coverage_percent", ...]``; that
list never enters a result's key (it changes no result, only what is
allowed). ``docs/study-files.md`` lists every bound (a test checks it).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterator

from peenflow.units import MM, UM

__all__ = ["Bound", "BOUNDS", "RELATIVE_BOUNDS", "ELEMENTS_PER_CONTACT_RADIUS_MAX", "bound_keys", "check_bounds",
           "check_table_bounds"]


@dataclass(frozen=True)
class Bound:
    """``low <= value <= high`` (None: no limit on that side) for the key path ``key``."""

    key: str  # e.g. "almen.velocities_m_s" (each item of a list is checked)
    low: float | None
    high: float | None
    unit: str
    basis: str  # where the range comes from

    def describe(self) -> str:
        lo = "-inf" if self.low is None else f"{self.low:g}"
        hi = "inf" if self.high is None else f"{self.high:g}"
        return f"[{lo}, {hi}]{' ' + self.unit if self.unit else ''}"


_V = "the kernel's stability sweep (docs/validation.md §8: 1-400 m/s on 25-100 um meshes, all finish)"
_A = ("single impacts (energy, convergence, Coulomb slip) and strip points run at 30, 45, 67.5 and 90 deg (docs/validation.md, "
      "shallow angles: at 30 deg the window reads the intensity +8 % above the whole mesh); below 30 deg nothing was run")
_H = "meshes run so far: 6.25 um (convergence, docs/validation.md §3) to 100 um (stability sweep, micro study)"
_MAT = "engineering metals (a typo by a factor of 1000 lands outside)"

BOUNDS: tuple[Bound, ...] = (
    *(Bound(key, 1.0, 400.0, "m/s", _V)
      for key in ("almen.velocities_m_s", "target.velocity_m_s", "dmin.strip_velocity_m_s")),
    *(Bound(key, 30.0, 90.0, "deg", _A) for key in ("almen.angles_deg", "target.angle_deg", "dmin.strip_angles_deg")),
    Bound("target.coverage_percent", 1.0, 1000.0, "%",
          "a 1000 % sequence finishes on the coarsest mesh (micro study, 100 um, 3 seeds); 10 000 % there ran "
          "away at 4100-5200 % (runaway energy, plastic strain near 10; docs/validation.md §8)"),
    Bound("almen.shot_counts", 1.0, 5120.0, "shots", "the longest strip ladder run (paper_al7075_coarse.toml)"),
    Bound("almen.first_shots", 1.0, 1280.0, "shots", "a ladder of >= 3 doubling rungs within almen.max_shots"),
    Bound("almen.max_shots", 1.0, 5120.0, "shots", "as almen.shot_counts"),
    Bound("almen.sequences", 1.0, 64.0, "", "cost: each sequence is a full ladder of REV runs"),
    Bound("almen.max_sequences", 2.0, 64.0, "", "as almen.sequences"),
    Bound("almen.sequence_tolerance_mm", 1e-4, 0.05, "mm",
          "1e-4 mm is below any arc-height resolution; above 0.05 mm (10 % of a typical intensity) the "
          "rule stops at the first two sequences"),
    Bound("target.sequences", 1.0, 64.0, "", "cost: each sequence is a full REV run"),
    Bound("coverage.sequences", 1.0, 10000.0, "", "Monte Carlo cost"),
    Bound("coverage.grid_points", 2.0, 2001.0, "", "memory of the measuring grid (points^2)"),
    Bound("coverage.max_shots", 1.0, 1e6, "shots", "Monte Carlo cost"),
    Bound("fidelity.element_size_um", 6.25, 100.0, "um", _H),
    Bound("fidelity.extrapolate_intensity_from_um", 6.25, 40.0, "um",
          "40 & 25 um extrapolated are within -0.6 ... +3.5 % of the strip references; a 60 um level is "
          "pre-asymptotic (60 & 40 um: -11.3 ... +0.9 %, 12A velocity +14.7 %; docs/validation.md §9)"),
    Bound("fidelity.dent_element_size_um", 6.25, 40.0, "um",
          "the target's N_f measured from dents at 6.25-40 um (docs/validation.md §9); it refines the "
          "dent, so a level coarser than the studies' 40 um adds only error"),
    Bound("fidelity.intensity_extrapolation_order", 0.5, 4.0, "",
          "the strip references converge with orders 1.72-1.99; outside [0.5, 4] no level triple was accepted "
          "as converging (benchmarks/study_reference.py)"),
    Bound("fidelity.fine_depth_D", 0.25, 4.0, "D", "shipped presets use 0.75-1 D: the plastic zone is ~0.5 D deep"),
    Bound("fidelity.fine_depth_mm", 0.05, 10.0, "mm", "the same as fine_depth_D for 0.1-2.5 mm shot"),
    Bound("fidelity.time_step_safety", 0.1, 1.0, "",
          "stability sweep 0.5-1.0; smaller is stable, only slower (below 0.1: 10x the cost for nothing)"),
    Bound("fidelity.window_contact_radii", 0.0, 20.0, "contact radii",
          "0 = whole mesh; shipped presets 3-6; a wider window only costs time"),
    Bound("fidelity.settle_tolerance", 1e-9, 1e-3, "",
          "strip_rev settle: 1e-6 default, 1e-4 coarse; looser lets the next shot hit a ringing target"),
    Bound("fidelity.relaxation_tolerance", 1e-12, 1e-3, "",
          "against a strict solve, 6D REV snapshots: the averaged profile within 0.009 % of its peak at 1e-5 "
          "(1.4-1.7 impacts), 0.21 % and every stress within 14 MPa at 1e-3 (0.9-1.2 impacts; docs/performance.md §3); looser is unmeasured"),
    Bound("shot.friction_coefficient", 0.0, 0.6, "", "the paper's 0.2; measured steel-on-steel 0.1-0.6"),
    Bound("target.thickness_mm", 0.1, 1000.0, "mm", "parts and strips (0.79-2.39 mm) of real size"),
    Bound("shots.diameter_mm", 0.1, 3.0, "mm", "SAE J444 cast shot S70-S780 (0.18-2 mm), with margin"),
    Bound("shots.density_kg_m3", 1000.0, 20000.0, "kg/m3", "glass (2500) to tungsten carbide (15 600)"),
    Bound("materials.youngs_modulus_GPa", 1.0, 1200.0, "GPa", _MAT),
    Bound("materials.density_kg_m3", 500.0, 25000.0, "kg/m3", _MAT),
    Bound("materials.poisson_ratio", 0.0, 0.49, "", "metals 0.25-0.35; near 0.5 the bulk modulus and the step blow up"),
    Bound("materials.johnson_cook.A_MPa", 10.0, 5000.0, "MPa", _MAT),
    Bound("materials.johnson_cook.B_MPa", 0.0, 10000.0, "MPa", _MAT),
    Bound("materials.johnson_cook.n", 0.01, 2.0, "", "Johnson-Cook fits of metals (0.1-1); the kernel refuses n <= 0"),
    Bound("materials.johnson_cook.C", 0.0, 0.5, "", "Johnson-Cook fits of metals (0-0.1)"),
    Bound("materials.johnson_cook.m", 0.0, 5.0, "", "Johnson-Cook fits of metals (0.5-2)"),
)

#: bounds relative to other values: (key, what, basis); checked in :func:`check_bounds`
RELATIVE_BOUNDS: tuple[tuple[str, str, str], ...] = (
    ("fidelity.element_size_um", "at most D / 5 (shot diameter)",
     "the dents computed so far have radii of 0.2-0.26 D (docs/results.md): D / 5 keeps at least one element per dent radius"),
    ("fidelity.element_size_um", "at most 7.5 estimated contact radii at the study's lowest velocity",
     "the stability sweep reaches 7.3 (1 m/s on 100 um elements, SAE 1070; stability.py low)"),
    ("fidelity.extrapolate_intensity_from_um", "at most D / 5 and 7.5 estimated contact radii at the lowest "
     "almen velocity, as fidelity.element_size_um", "its level runs the strips (as fidelity.element_size_um)"),
    ("almen.rev_size_mm", "at least 1 D and 10 elements (of the coarse level too, with an intensity extrapolation)", "a REV must hold one dent; fewer elements "
     "leave no measuring region (a REV smaller than one element failed in coverage_curve)"),
    ("target.rev_size_mm", "at least 1 D and 10 elements", "as almen.rev_size_mm"),
    ("almen.measure_size_mm", "at least 2 elements (as almen.rev_size_mm)", "the profile averages over the region's elements"),
    ("target.measure_size_mm", "at least 2 elements", "as almen.measure_size_mm"),
)

#: the largest element size in estimated contact radii (see RELATIVE_BOUNDS)
ELEMENTS_PER_CONTACT_RADIUS_MAX = 7.5


def bound_keys() -> list[str]:
    return sorted({b.key for b in BOUNDS} | {k for k, _, _ in RELATIVE_BOUNDS})


Problem = tuple[str, object, str]  # (key, value, message)


def _values(study_sections: dict, key: str) -> Iterator[tuple[str, object]]:
    """(shown key, value) pairs at ``key`` in the sections (validated models or the file's tables; list
    items one by one)."""
    section, _, rest = key.partition(".")
    obj = study_sections.get(section)
    for part in rest.split("."):
        if obj is None:
            return
        obj = obj.get(part) if isinstance(obj, dict) else getattr(obj, part, None)
    if obj is None:
        return
    if isinstance(obj, (tuple, list)):
        for i, v in enumerate(obj):
            yield f"{key}[{i}]", v
    else:
        yield key, obj


def _materials(s: dict) -> Iterator[tuple[str, object]]:
    """(key prefix, Material) of every material the study uses."""
    target, almen = s.get("target"), s.get("almen")
    if target is not None:
        yield f"materials.{target.material.name}", target.material
    if almen is not None:
        yield f"materials.{almen.strip.material.name}", almen.strip.material


def _outside(bound: Bound, shown: str, value, allowed: set[str]) -> list[Problem]:
    """[the problem] when the number ``value`` breaks ``bound`` and the study does not allow it, else []."""
    if bound.key in allowed or not isinstance(value, (int, float)) or isinstance(value, bool):
        return []
    if (bound.low is not None and value < bound.low) or (bound.high is not None and value > bound.high):
        return [(shown, value, f"outside the validated range {bound.describe()} ({bound.basis}); "
                 f'to go beyond it on purpose, add "{bound.key}" to [study] allow_outside_bounds')]
    return []


def check_table_bounds(section: str, table: dict, allowed: set[str]) -> list[Problem]:
    """The bounds on the keys of ``section`` that the file's table ``table`` breaks, for a section whose
    model refused some other key: its values that are numbers are still checked, so one ``check`` lists
    both kinds of problem (a value that is not a number has its own problem already)."""
    out: list[Problem] = []
    for bound in BOUNDS:
        if bound.key.startswith(section + "."):
            for shown, value in _values({section: table}, bound.key):
                out += _outside(bound, shown, value, allowed)
    return out


def check_bounds(s: dict, allowed: set[str]) -> list[Problem]:
    """Every bound the validated sections ``s`` break, except those named in ``allowed``."""
    out: list[Problem] = []

    def test(bound: Bound, shown: str, value) -> None:
        out.extend(_outside(bound, shown, value, allowed))

    shot = s.get("shot")
    for bound in BOUNDS:
        if bound.key.startswith("materials."):
            for prefix, mat in _materials(s):
                obj = mat
                for part in bound.key.split(".")[1:]:
                    obj = getattr(obj, part)
                test(bound, prefix + bound.key[len("materials"):], obj)
        elif bound.key.startswith("shots.") and shot is not None:
            attr = bound.key[len("shots."):]
            test(bound, f"shots.{shot.name}.{attr}", getattr(shot.type, attr))
        else:
            for shown, value in _values(s, bound.key):
                test(bound, shown, value)
    out += _relative(s, allowed)
    return out


def _relative(s: dict, allowed: set[str]) -> list[Problem]:
    out: list[Problem] = []
    shot, fid = s.get("shot"), s.get("fidelity")
    if shot is None or fid is None:
        return out
    d_mm = shot.diameter_mm
    hint = '; to go beyond it on purpose, add "{}" to [study] allow_outside_bounds'
    # every element size the study runs at: the strips also at the coarse level of an extrapolation
    levels = [("fidelity.element_size_um", fid.element_size_um, False)]
    coarse = getattr(fid, "extrapolate_intensity_from_um", None)
    if coarse is not None and s.get("almen") is not None:
        levels.append(("fidelity.extrapolate_intensity_from_um", coarse, True))
    for key, h_um, strips_only in levels:
        if key in allowed:
            continue
        h_mm = h_um * UM / MM
        if h_mm > d_mm / 5.0:
            out.append((key, h_um, f"larger than D / 5 = {d_mm / 5 * MM / UM:.4g} um for the "
                        f"{shot.name} shot (dents of 0.2-0.26 D radius need at least one element across their radius)" + hint.format(key)))
    for name in ("almen", "target"):
        sec = s.get(name)
        if sec is None:
            continue
        # the strips' REV must hold the coarse level's elements too
        h_um = fid.strip_element_size_um if name == "almen" else fid.element_size_um
        h_mm = h_um * UM / MM
        rev, meas = getattr(sec, "rev_size_mm", None), getattr(sec, "measure_size_mm", None)
        k = f"{name}.rev_size_mm"
        if rev is not None and k not in allowed and (rev < d_mm or rev < 10 * h_mm):
            out.append((k, rev, f"smaller than max(1 D = {d_mm:g} mm, 10 elements of {h_um:g} um = {10 * h_mm:g} mm): "
                        "a REV must hold a dent and a measuring region" + hint.format(k)))
        k = f"{name}.measure_size_mm"
        if meas is not None and k not in allowed and meas < 2 * h_mm:
            out.append((k, meas, f"smaller than 2 elements of {h_um:g} um ({2 * h_mm:g} mm): nothing to average over"
                        + hint.format(k)))
    return out
