"""Refuse, before any compute, a point the kernel cannot resolve or a worker cannot afford.

A study may take a key beyond its validated range (``[study]
allow_outside_bounds``); what it then asks for can be an impact no mesh of
the study resolves (1e6 m/s: the shot crosses 124 elements of the micro study per
time step, and the kernel ran its whole step budget, 6.5 min on a shared
2-core machine, before it failed) or a point that would run for days.  Every point that runs the kernel
is checked here, opted out or not, right after the study is read:

* the shot must move less than one element per time step
  (:func:`peenflow.fe.cost.shot_travel_per_step`);
* its predicted CPU time (:func:`peenflow.fe.cost.impact_cost`: steps per
  impact from the stable step and the estimated contact time, x elements in
  the active window on the point's own mesh, x its shots) must be at most
  :data:`POINT_CPU_LIMIT_S`;
* a REV of a given size must be larger than one dent (the estimated contact
  area), or its coverage cannot grow shot by shot.

A refused point is reported like any study problem (a
:class:`peenflow.study.StudyError`: ``peenflow check`` and ``run`` print it
and exit 2), with the prediction and the keys to change.  Where a size is
only known after an upstream stage (a REV from d_min, the target's N_c) the
prediction takes its largest value the study allows, or the closed form the
stage itself uses, and says so.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, replace
from types import SimpleNamespace

import numpy as np

from peenflow.fe import cost as C
from peenflow.fe.mesh import BoxMesh
from peenflow.fe.window import window_size
from peenflow.methods.coverage import AvramiFit
from peenflow.units import MM

from . import _kernel as K
from .params import FidelityParams, MaterialParams, StudyParams
from .single_impact import _block

#: The most CPU time one point may be predicted to need (s): three days, over three times the costliest
#: point of the shipped studies (a 25 um REV run of studies/paper_al7075.toml, about 19 h predicted:
#: tests/tasks/test_cost_guard.py), so a shipped study keeps room for more coverage or shots, while a
#: mistake is refused (elements ten times finer cost up to 10 000 times more: ten times the steps,
#: a thousand times the window).  A point runs on one worker, a single impact or a two-shot search
#: without a progress line.
POINT_CPU_LIMIT_S = 72 * 3600.0
#: environment variable that replaces :data:`POINT_CPU_LIMIT_S` (seconds; tests set a tiny one)
LIMIT_ENV = "PEENFLOW_POINT_CPU_LIMIT_S"


def point_cpu_limit_s() -> float:
    """:data:`POINT_CPU_LIMIT_S`, or ``$PEENFLOW_POINT_CPU_LIMIT_S`` when set."""
    text = os.environ.get(LIMIT_ENV)
    if not text:
        return POINT_CPU_LIMIT_S
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not value > 0:
        raise ValueError(f"${LIMIT_ENV} = {text!r}: expected a number of seconds > 0 (the most CPU time one "
                         "point may be predicted to need)")
    return value


@dataclass(frozen=True)
class KernelPoint:
    """A point (or the like points of one stage) that runs the kernel, as the guard sees it.

    ``speed_key``: the study key its velocity comes from; ``mesh``: the model it runs on (its landing
    point at x = y = 0); ``element_size_m``: its smallest element; ``shots``: impacts in the point,
    ``shots_from``: how that count is known; ``cheaper``: the keys that make it cheaper."""

    point: str
    speed_key: str
    speed_m_s: float
    angle_deg: float
    material: MaterialParams
    fidelity: FidelityParams
    mesh: BoxMesh
    shots: int
    shots_from: str
    cheaper: str

    @property
    def element_size_m(self) -> float:
        return self.fidelity.element_size_m


def predict(kp: KernelPoint, shot) -> C.ImpactCost:
    """The predicted work of ``kp`` (:func:`peenflow.fe.cost.impact_cost`) for ``shot`` (ShotParams)."""
    m = kp.material
    normal = kp.speed_m_s * math.sin(math.radians(kp.angle_deg))
    a, t = C.contact_estimate(shot.radius_m, shot.density_kg_m3, normal, m.youngs_modulus_Pa, m.poisson_ratio,
                              m.density_kg_m3, m.A_Pa)
    return C.impact_cost(element_size_m=kp.element_size_m, youngs_modulus_Pa=m.youngs_modulus_Pa,
                         poisson_ratio=m.poisson_ratio, density_kg_m3=m.density_kg_m3,
                         time_step_safety=kp.fidelity.time_step_safety, contact_time_s=t, speed_m_s=kp.speed_m_s,
                         window_elements=window_elements(kp, shot, a, t), shots=kp.shots)


def window_elements(kp: KernelPoint, shot, a_est: float, t_est: float) -> int:
    """Elements of the active window the kernel integrates for ``kp``'s impact at the mesh origin: its
    own window rule (:func:`peenflow.fe.window.window_size`) on the point's mesh, plus the shot's
    tangential travel during 1.5 contact times downstream, clipped to the mesh (as
    ``Model.window_box``); the whole mesh without a window."""
    mesh = kp.mesh
    nx, ny, nz = mesh.shape_elements
    options = kp.fidelity.options(shot)
    if not options.window:
        return nx * ny * nz
    lat_x, lat_y, depth = window_size(SimpleNamespace(mesh=mesh), kp.material.to_kernel(), options, a_est, t_est,
                                      0.0, 0.0)
    travel = 1.5 * t_est * kp.speed_m_s * abs(math.cos(math.radians(kp.angle_deg)))
    ni = _elements_within(mesh.x, -lat_x, lat_x + travel)
    nj = _elements_within(mesh.y, -lat_y, lat_y)
    nk = max(1, min(nz, int(np.searchsorted(mesh.z, depth, side="left"))))
    return ni * nj * nk


def _elements_within(axis: np.ndarray, lo: float, hi: float) -> int:
    i0 = max(0, int(np.searchsorted(axis, lo, side="right")) - 1)
    i1 = min(len(axis) - 1, int(np.searchsorted(axis, hi, side="left")))
    return max(i1 - i0, 1)


def kernel_points(study, p: StudyParams, block_half_width_D: float) -> list[KernelPoint]:
    """Every kind of point of ``study`` that runs the kernel (one per stage and distinct velocity and
    angle: the sequences of a sweep cost the same); ``block_half_width_D``: the single-impact block's
    half width in shot diameters (``tasks.pipeline.IMPACT_BLOCK_D``)."""
    D = p.shot.diameter_m
    half = block_half_width_D * D
    out: list[KernelPoint] = []
    search = p.dmin
    span = (search.max_distance_m - search.min_distance_m) / search.resolution_m
    dmin_runs = int(math.ceil(span)) + 1 if search.method == "scan" else int(math.ceil(math.log2(max(span, 1.0)))) + 2
    dmin_from = f"at most {dmin_runs} two-shot runs ({search.method} over dmin.min/max_distance at its resolution)"

    def impact(point, key, v, angle, mat, fid, thickness, shots=1, shots_from="one impact", cheaper=""):
        mesh = _block(fid, half, thickness, angle)
        out.append(KernelPoint(point, key, v, angle, mat, fid, mesh, shots, shots_from, cheaper))

    def rev(point, key, v, angle, mat, fid, side, thickness, shots, shots_from, cheaper):
        out.append(KernelPoint(point, key, v, angle, mat, fid, K.rev_mesh(fid, side, thickness), shots, shots_from,
                               cheaper))

    size = "fidelity.element_size_um"
    if (a := study.almen) is not None:
        h = p.strip.thickness_m
        if a.rev_rule == "dmin":
            v = study.dmin.strip_velocity_m_s
            for angle in study.dmin.strip_angles_deg:
                impact(f"strip_impact[angle_deg={angle:g}]", "dmin.strip_velocity_m_s", v, angle, p.strip_material,
                       p.fidelity, min(h, half), cheaper=f"a larger {size}")
                impact(f"strip_dmin[angle_deg={angle:g}]", "dmin.strip_velocity_m_s", v, angle, p.strip_material,
                       p.fidelity, h, dmin_runs * (1 if angle == 90.0 else 2), dmin_from,
                       f"a larger {size}, a coarser dmin.resolution_D")
        # a REV from d_min is at most 3 x the search's largest distance
        d_max = search.max_distance_m if a.rev_rule == "dmin" else None
        side = p.strip_rev.geometry(d_max).side
        side_from = " (REV side at most 3 dmin.max_distance_D)" if d_max is not None else ""
        if p.ladder is not None:
            shots, shots_from, shots_key = p.ladder.max_shots, "almen.max_shots", "almen.max_shots"
        else:
            shots, shots_from, shots_key = max(a.shot_counts), "the largest of almen.shot_counts", "almen.shot_counts"
        levels = [("strip_runs", p.fidelity, size)]
        if p.coarse_fidelity is not None:
            levels.append(("coarse_strip_runs", p.coarse_fidelity, "fidelity.extrapolate_intensity_from_um"))
        for stage, fid, size_key in levels:
            for angle in a.angles_deg:
                for v in a.velocities_m_s:
                    rev(f"{stage}[angle_deg={angle:g},velocity_m_s={v:g}]", "almen.velocities_m_s", v, angle,
                        p.strip_material, fid, side, h, shots, shots_from + side_from,
                        f"a larger {size_key}, fewer shots ({shots_key}), a smaller REV (almen.rev_size_mm)")
    if (t := study.target) is not None:
        if t.velocity_m_s is not None:
            key, v = "target.velocity_m_s", t.velocity_m_s
        else:  # read off the control curve: inside the almen velocities
            key, v = "almen.velocities_m_s", max(study.almen.velocities_m_s)
        dent_fid, dent_size = p.dent_fidelity, ("fidelity.dent_element_size_um"
                                                if study.fidelity.dent_element_size_um is not None else size)
        if p.dent_core_element_size_m is not None:  # the core's elements set the step; counted as a whole block
            dent_fid = replace(dent_fid, element_size_m=p.dent_core_element_size_m)
        impact("target_impact", key, v, t.angle_deg, p.target_material, dent_fid, min(p.target_plan.rev_thickness_m, half),
               cheaper=f"a larger {dent_size}")
        if t.rev_thickness_auto:
            first = min(p.target_plan.thickness_m, max(2.0 * p.fidelity.element_size_m, D))
            runs = 2 * max(1, int(math.ceil(math.log2(max(p.target_plan.thickness_m / first, 1.0))))) + 1
            impact("target_rev_thickness", key, v, t.angle_deg, p.target_material, p.fidelity, p.target_plan.thickness_m,
                   runs, f"at most {runs} single impacts (doubling block thickness up to target.thickness_mm)",
                   f"a larger {size}, a given target.rev_thickness_mm")
        if p.target_rev.rule == "dmin":
            impact("target_dmin", key, v, t.angle_deg, p.target_material, p.fidelity,
                   min(p.target_plan.rev_thickness_m, 2 * half), dmin_runs * (1 if t.angle_deg == 90.0 else 2), dmin_from,
                   f"a larger {size}, a coarser dmin.resolution_D")
        d_max = search.max_distance_m if p.target_rev.rule == "dmin" else None
        side = p.target_rev.geometry(d_max).side
        n_c = target_coverage_shots(study, p, side, v)
        rev("target_runs", key, v, t.angle_deg, p.target_material, p.fidelity, side, p.target_plan.rev_thickness_m, n_c,
            f"N_c for target.coverage_percent = {t.coverage_levels_percent[-1]:g} %, estimated from the contact area",
            f"a larger {size}, a lower target.coverage_percent, a smaller target.rev_size_mm")
    return out


def _contact_radius_m(p: StudyParams, material: MaterialParams, speed: float, angle_deg: float) -> float:
    normal = speed * math.sin(math.radians(angle_deg))
    return C.contact_estimate(p.shot.radius_m, p.shot.density_kg_m3, normal, material.youngs_modulus_Pa,
                              material.poisson_ratio, material.density_kg_m3, material.A_Pa)[0]


def target_coverage_shots(study, p: StudyParams, side_m: float, speed: float) -> int:
    """N_c of the target's REV runs before ``coverage_curve`` has run: eq. (5) with the rate of uniform
    landings, ``-ln(1 - A_dent / A_REV)``, the dent a circle of the estimated contact radius."""
    t = study.target
    a = _contact_radius_m(p, p.target_material, speed, t.angle_deg)
    q = min(math.pi * a * a / side_m ** 2, 1.0 - 1e-9)
    fit = AvramiFit(-math.log1p(-q), 0.0, np.zeros(0), np.zeros(0), p.coverage.full_coverage_percent)
    return max(1, int(math.ceil(fit.shots_for_coverage(t.coverage_levels_percent[-1]))))


def _duration(seconds: float) -> str:
    if seconds >= 3600.0:
        return f"{seconds / 3600.0:.3g} h"
    if seconds >= 60.0:
        return f"{seconds / 60.0:.3g} min"
    return f"{seconds:.3g} s"


def problems(study, p: StudyParams, block_half_width_D: float, limit_s: float | None = None) -> list[str]:
    """What the guard refuses in ``study`` (module docstring), one line each; ``limit_s``: the CPU
    limit per point (default :func:`point_cpu_limit_s`)."""
    limit = point_cpu_limit_s() if limit_s is None else limit_s
    unresolved: dict[tuple, list[str]] = {}  # one line per cause, naming every point it stops
    out: list[str] = []
    for kp in kernel_points(study, p, block_half_width_D):
        c = predict(kp, p.shot)
        if not c.resolved:
            cause = (kp.speed_key, kp.speed_m_s, kp.element_size_m, kp.fidelity.time_step_safety, c.travel_per_step,
                     c.time_step_s)
            unresolved.setdefault(cause, []).append(kp.point)
        elif c.cpu_s > limit:
            out.append(
                f"{kp.speed_key} = {kp.speed_m_s:g} ({kp.point}): predicted {_duration(c.cpu_s)} of CPU, above the "
                f"limit of {_duration(limit)} per point: {c.steps_per_impact:.3g} steps per impact (contact time "
                f"{c.contact_time_s:.3g} s over the stable step {c.time_step_s:.3g} s) x {c.window_elements:.3g} "
                f"elements in the active window x {c.shots:g} shots ({kp.shots_from}) = {c.element_updates:.3g} "
                f"element updates at {C.ELEMENT_UPDATES_PER_CPU_S / 1e6:g} M per CPU second. What to change: a "
                f"lower {kp.speed_key}, {kp.cheaper} or a smaller fidelity.window_contact_radii (a point this long "
                f"on purpose: set ${LIMIT_ENV} to its CPU seconds)")
    for (key, speed, h, safety, travel, dt), points in unresolved.items():
        out.insert(0,
            f"{key} = {speed:g} ({', '.join(points)}): the shot moves {travel:.3g} elements of {h * 1e6:g} um per "
            f"time step ({dt:.3g} s, the stable step at fidelity.time_step_safety = {safety:g}); the contact is "
            f"resolved only below one element per step (here below {speed / travel:.4g} m/s; in the validated "
            "1-400 m/s a shot moves at most 0.06), above it the elements under the shot are crushed within a step. "
            f"What to change: a lower {key} (validated 1-400 m/s)")
    if not any(k[0].startswith("target.") for k in unresolved):
        out += _rev_smaller_than_a_dent(study, p)
    return out


def _rev_smaller_than_a_dent(study, p: StudyParams) -> list[str]:
    """A REV of a given size whose top surface is smaller than one dent (the estimated contact area)."""
    t = study.target
    if t is None or p.target_rev.side_m is None:
        return []
    speed = t.velocity_m_s if t.velocity_m_s is not None else min(study.almen.velocities_m_s)
    a = _contact_radius_m(p, p.target_material, speed, t.angle_deg)
    side = p.target_rev.side_m
    if math.pi * a * a < side * side:
        return []
    return [f"target.rev_size_mm = {side * 1e3:g}: the REV's top surface ({side * 1e3:g} mm square, "
            f"{side * side * 1e6:.3g} mm2) is smaller than one dent (estimated contact radius {a * 1e3:.3g} mm at "
            f"{speed:g} m/s: {math.pi * a * a * 1e6:.3g} mm2), so the REV holds less than one dent and its "
            f"coverage cannot grow shot by shot. What to change: a larger target.rev_size_mm (at least 1 D = "
            f"{p.shot.diameter_m / MM:g} mm and 10 elements)"]
