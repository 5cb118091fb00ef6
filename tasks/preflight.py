"""Checks that need the kernel's own rules, run on a study right after it is read, before any compute.

The study package validates what a file says (keys, types, ranges, sections
that agree); some limits are the kernel's, and the kernel states them on
floats: its contact estimate (:func:`peenflow.fe.window.contact_estimate`),
how far a contact reaches across a periodic seam
(:func:`peenflow.fe.periodic.contact_reach`) and the REV's uniform lateral
step (:func:`peenflow.fe.mesh.uniform_lateral_step_bound`).  They are applied
here, to the typed parameters (SI), with messages in the file's keys and units,
so a study the kernel would stop on is refused before anything runs -- by the
very rule the kernel applies, never a copy of it.
"""

from __future__ import annotations

import math
from pathlib import Path

from peenflow.fe.mesh import uniform_lateral_step_bound
from peenflow.fe.periodic import contact_reach
from peenflow.fe.shots import sphere_mass
from peenflow.fe.window import contact_estimate
from peenflow.methods import largest_factor
from peenflow.study import StudyError, load_study, validate_study
from peenflow.study.bounds import ELEMENTS_PER_CONTACT_RADIUS_MAX
from peenflow.study.errors import Problem, format_value
from peenflow.units import MM, UM

from .params import MaterialParams, ShotParams, StudyParams, study_params

__all__ = ["problems", "check_before_compute", "study_problems"]

_HINT = '; to go beyond it on purpose, add "{}" to [study] allow_outside_bounds'


def contact_radius(shot: ShotParams, material: MaterialParams, normal_speed: float) -> float:
    """The kernel's contact-radius estimate (m) at ``normal_speed`` (m s-1)."""
    return contact_estimate(shot.radius_m, sphere_mass(shot.radius_m, shot.density_kg_m3), normal_speed,
                            material.youngs_modulus_Pa, material.poisson_ratio, material.A_Pa)[0]


def periodic_contact_half(shot: ShotParams, material: MaterialParams, speed: float, angle_deg: float,
                          element: float) -> float:
    """Half the period (m) a shot's contact zone needs along its direction of travel on a periodic REV
    whose lateral step is ``element`` (m): :func:`peenflow.fe.periodic.contact_reach` with the kernel's
    contact time at the normal speed and the tangential speed of ``speed`` (m s-1) at ``angle_deg``."""
    a = math.radians(angle_deg)
    t = contact_estimate(shot.radius_m, sphere_mass(shot.radius_m, shot.density_kg_m3), speed * math.sin(a),
                         material.youngs_modulus_Pa, material.poisson_ratio, material.A_Pa)[1]
    return contact_reach(shot.radius_m, t, speed * math.cos(a), element)


def _extreme(p: StudyParams, largest: bool) -> tuple[ShotParams, float]:
    """(the smallest or largest shot a stream can draw, its speed factor): the nominal shot without
    spreads; with them the truncated normals' extremes (:func:`peenflow.methods.largest_factor`)."""
    d, v = largest_factor(p.stream.diameter_spread), largest_factor(p.stream.velocity_spread)
    d, v = (d, v) if largest else (2.0 - d, 2.0 - v)
    if d == 1.0:
        return p.shot, v
    return ShotParams(p.shot.radius_m * d, p.shot.density_kg_m3, p.shot.friction_coefficient), v


def problems(study, p: StudyParams) -> list[Problem]:
    """Every kernel limit the study breaks (module docstring), except bounds it opts out of."""
    allowed = set(study.info.allow_outside_bounds)
    return _element_size_in_contact_radii(study, p, allowed) + _periodic_rev_fits_a_contact(study, p)


def check_before_compute(study, p: StudyParams) -> None:
    """Raise :class:`StudyError` listing :func:`problems` and the cost guard's (:mod:`tasks.cost_guard`: an
    impact no mesh of the study resolves, a point no worker can afford, a REV smaller than a dent), if any."""
    from .cost_guard import problems as cost_problems
    from .single_impact import IMPACT_BLOCK_D

    found = [pr.render(study.path) for pr in problems(study, p)] + cost_problems(study, p, IMPACT_BLOCK_D)
    if found:
        raise StudyError(study.path, found)


def study_problems(path: str | Path) -> list[str]:
    """Every problem of the study file at ``path``: the study's own (:func:`peenflow.study.validate_study`)
    and, when it has none, the kernel's limits."""
    found = validate_study(path)
    if found:
        return found
    study = load_study(path)
    try:  # study_params refuses measured strips no fit can use
        check_before_compute(study, study_params(study))
    except StudyError as exc:
        return exc.problems
    return []


def _impacts(study, p: StudyParams, strips_only: bool):
    """(velocities m s-1, material, where) of the impacts the study runs (``strips_only``: the strips')."""
    if p.strips is not None:
        yield p.strips.velocities_m_s, p.strip_material, f"{study.almen.strip.name} strip"
    if p.target is not None and not strips_only:
        if p.target.velocity_m_s is not None:
            yield (p.target.velocity_m_s,), p.target_material, "target"
        elif p.strips is not None:  # read off the control curve, so inside the almen velocities
            yield (min(p.strips.velocities_m_s),), p.target_material, "target, slowest control-curve velocity"


def _element_size_in_contact_radii(study, p: StudyParams, allowed: set) -> list[Problem]:
    """An element at most :data:`ELEMENTS_PER_CONTACT_RADIUS_MAX` estimated contact radii at the slowest
    impact of each level (the strips' coarse level too)."""
    f = study.fidelity
    levels = [("fidelity.element_size_um", f.element_size_um, p.fidelity.element_size_m, False)]
    if p.coarse_fidelity is not None:
        levels.append(("fidelity.extrapolate_intensity_from_um", f.extrapolate_intensity_from_um,
                       p.coarse_fidelity.element_size_m, True))
    out = []
    for key, h_um, h, strips_only in levels:
        if key in allowed:
            continue
        worst = None
        shot, slow = _extreme(p, largest=False)  # the smallest, slowest shot makes the smallest contact
        for velocities, material, where in _impacts(study, p, strips_only):
            for v in velocities:
                v = v * slow
                a = contact_radius(shot, material, v)
                if worst is None or h / a > worst[0]:
                    worst = (h / a, v, a, where)
        if worst is not None and worst[0] > ELEMENTS_PER_CONTACT_RADIUS_MAX:
            ratio, v, a, where = worst
            out.append(Problem(key, f"{ratio:.3g} estimated contact radii ({a / UM:.3g} um at {v:g} m/s, {where}); "
                                    f"the validated range is at most {ELEMENTS_PER_CONTACT_RADIUS_MAX:g} (the stability "
                                    "sweep reaches 7.3: 1 m/s on 100 um, SAE 1070)" + _HINT.format(key),
                               None, format_value(h_um)))
    return out


def _periodic_rev_fits_a_contact(study, p: StudyParams) -> list[Problem]:
    """Periodic REV faces: each shot's contact zone -- the kernel's search box (1.25 R each side), an
    oblique shot's tangential travel during the contact, and 2 elements -- must fit in half a period
    (the kernel's own test in :func:`peenflow.fe.periodic.seam_shift`)."""
    if p.fidelity.lateral_boundary != "periodic":
        return []
    out = []
    strip_h = (p.coarse_fidelity or p.fidelity).element_size_m  # the strips also run at the coarse level
    sides = []
    if p.strips is not None and p.strip_rev.side_m is not None:
        cases = [(v, a) for v in p.strips.velocities_m_s for a in p.strips.angles_deg]
        sides.append(("almen", study.almen.rev_size_mm, p.strip_rev.side_m, strip_h, p.strip_material, cases))
    if p.target is not None and p.target_rev.side_m is not None:
        if p.target.velocity_m_s is not None:
            cases = [(p.target.velocity_m_s, p.target.angle_deg)]
        elif p.strips is not None:  # read off the control curve: at most its fastest velocity
            cases = [(max(p.strips.velocities_m_s), p.target.angle_deg)]
        else:
            cases = []
        sides.append(("target", study.target.rev_size_mm, p.target_rev.side_m, p.fidelity.element_size_m,
                      p.target_material, cases))
    shot, fast = _extreme(p, largest=True)  # the largest, fastest shot makes the widest contact zone
    big = f"the stream's largest shot has D = {shot.diameter_m / MM:.4g} mm at {fast:.3g} x the velocity; " \
        if p.stream.any else ""
    for name, size_mm, side, h, material, cases in sides:
        step = uniform_lateral_step_bound(side, h)  # the REV's own lateral step: the side in whole elements
        for v, angle in cases:
            v = v * fast
            half = periodic_contact_half(shot, material, v, angle, step)
            if side <= 2.0 * half:
                travel = 2.0 * half - 1.25 * shot.diameter_m - 4.0 * step
                out.append(Problem(
                    f"{name}.rev_size_mm",
                    'with fidelity.lateral_boundary = "periodic" the REV side must exceed 1.25 D + 4 elements '
                    f"({big}{step / UM:.4g} um: {h / UM:g} um fitted to the side) + twice the tangential travel during "
                    f"the contact ({travel / MM:.3g} mm at {v:g} m/s, {angle:g} deg) = {2.0 * half / MM:.3g} mm "
                    "(a shot's contact zone must fit in half a period)", None, format_value(size_mm)))
                break  # one message per REV: its worst case is what to fix
    return out
