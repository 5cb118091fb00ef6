"""What an impact costs before it runs: time steps, element updates, CPU time (plain floats).

An explicit impact advances its active window in steps of the stable step of
its smallest element, at rest (``element.py``, item 6, with no bulk viscosity)

    dt = time_step_safety * 2 h / (c_p sqrt(4 + f_hg)),    c_p = sqrt((lambda + 2 mu) / rho)

(``f_hg``: :func:`peenflow.fe.element.hourglass_omega2_factor`, 1.6 for
metals; the step shrinks as elements are compressed), and its
contact lasts about the estimated contact time ``t_c``
(:func:`peenflow.fe.window.contact_estimates`: the larger of the Hertz and
the fully plastic durations), so one impact takes at least

    steps = t_c / dt

steps of ``window_elements`` element updates each, and a run of ``shots``
impacts ``steps * window_elements * shots`` element updates, at
:data:`ELEMENT_UPDATES_PER_CPU_S` a CPU second.  The settling after the
contact adds 0.3-3.6x the contact's steps (micro target, 100 um, 5 / 45 /
300 m/s: 171 / 161 / 341 steps against 136 / 88 / 74 predicted) and the
relaxed snapshots of a REV run are not counted, while the elastic elements
of a window update 2-3x faster than the rate assumed.  On the shipped
studies' costliest kinds of point the prediction is 1.7-2.1x the CPU time
measured (docs/performance.md section 7, 2 shared cores): the 25 um REV run of
paper_fast_25um.toml, 369 shots, 1108 s predicted, 520 s measured; the
6.25 um single impact of paper_fast_extrapolated.toml, 366 s and 218 s.  It
is an estimate for refusing what no worker can afford, not a schedule.

The contact is resolved only while the shot moves less than one element per
step (:func:`shot_travel_per_step`): the kinematic contact (``contact.py``)
puts every surface node inside the shot back onto its surface each step, so a
shot that moves an element or more in one step crushes the elements under it
within that step.  In the validated range (1-400 m/s) a shot moves at most
0.06 of an element per step; at 1e6 m/s on 100 um elements it moves 124.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from peenflow.fe.element import hourglass_omega2_factor
from peenflow.fe.impact import Options
from peenflow.fe.johnson_cook import Material
from peenflow.fe.shots import Shots
from peenflow.fe.window import contact_estimates

#: element updates per second of CPU the CPU-time estimate assumes: the plastic element pass on one
#: core (docs/performance.md section 1: 4.6-6.5 M/s; the elastic pass is 2-3x faster)
ELEMENT_UPDATES_PER_CPU_S = 5.0e6


def wave_speed_m_s(youngs_modulus_Pa: float, poisson_ratio: float, density_kg_m3: float) -> float:
    """Dilatational wave speed c_p = sqrt((lambda + 2 mu) / rho), m/s."""
    return _material(youngs_modulus_Pa, poisson_ratio, density_kg_m3, math.inf).wave_speed


def stable_time_step_s(element_size_m: float, youngs_modulus_Pa: float, poisson_ratio: float,
                       density_kg_m3: float, time_step_safety: float) -> float:
    """The kernel's step on an undeformed cube of edge ``element_size_m`` (m) at rest, s (module docstring):
    ``time_step_safety * 2 h / (c_p sqrt(4 + f_hg))``, with the kernel's default hourglass form."""
    material = _material(youngs_modulus_Pa, poisson_ratio, density_kg_m3, math.inf)
    f_hg = hourglass_omega2_factor(material.to_array(hourglass_type=Options.hourglass_type))
    return time_step_safety * 2.0 * element_size_m / (material.wave_speed * math.sqrt(4.0 + f_hg))


def contact_estimate(shot_radius_m: float, shot_density_kg_m3: float, normal_speed_m_s: float,
                     youngs_modulus_Pa: float, poisson_ratio: float, density_kg_m3: float,
                     yield_stress_Pa: float) -> tuple[float, float]:
    """(contact radius m, contact time s) of a shot hitting at ``normal_speed_m_s`` (m/s): the estimate
    the kernel sizes its active window with (:func:`peenflow.fe.window.contact_estimates`; Hertz, or
    Johnson's fully plastic contact at mean pressure 3 ``yield_stress_Pa``, whichever is larger)."""
    shots = Shots(np.zeros((1, 3)), np.zeros((1, 3)), shot_radius_m, shot_density_kg_m3)
    return contact_estimates(shots, _material(youngs_modulus_Pa, poisson_ratio, density_kg_m3, yield_stress_Pa),
                             normal_speed_m_s)


def shot_travel_per_step(speed_m_s: float, time_step_s: float, element_size_m: float) -> float:
    """How far the shot moves in one step, in elements (1): ``v dt / h``; the contact is resolved below 1."""
    return speed_m_s * time_step_s / element_size_m


@dataclass(frozen=True)
class ImpactCost:
    """The predicted work of ``shots`` impacts (module docstring).

    ``time_step_s`` (s), ``contact_time_s`` (s), ``steps_per_impact`` (1, contact phase),
    ``window_elements`` (elements updated per step), ``shots``, ``element_updates``
    (steps x window elements x shots), ``cpu_s`` (s of one core at
    :data:`ELEMENT_UPDATES_PER_CPU_S`), ``travel_per_step`` (elements the shot moves per step)."""

    time_step_s: float
    contact_time_s: float
    steps_per_impact: float
    window_elements: float
    shots: float
    element_updates: float
    cpu_s: float
    travel_per_step: float

    @property
    def resolved(self) -> bool:
        """True when the shot moves less than one element per step."""
        return self.travel_per_step < 1.0


def impact_cost(*, element_size_m: float, youngs_modulus_Pa: float, poisson_ratio: float, density_kg_m3: float,
                time_step_safety: float, contact_time_s: float, speed_m_s: float, window_elements: float,
                shots: float, updates_per_cpu_s: float = ELEMENT_UPDATES_PER_CPU_S) -> ImpactCost:
    """The predicted work of ``shots`` impacts at ``speed_m_s`` (m/s) on elements of ``element_size_m``
    (m, the smallest), each lasting ``contact_time_s`` (s) and updating ``window_elements`` elements a
    step (module docstring)."""
    dt = stable_time_step_s(element_size_m, youngs_modulus_Pa, poisson_ratio, density_kg_m3, time_step_safety)
    steps = math.ceil(contact_time_s / dt)
    updates = float(steps) * float(window_elements) * float(shots)
    return ImpactCost(dt, contact_time_s, float(steps), float(window_elements), float(shots), updates,
                      updates / updates_per_cpu_s, shot_travel_per_step(speed_m_s, dt, element_size_m))


def _material(E: float, nu: float, density: float, yield_stress: float) -> Material:
    return Material(E=E, nu=nu, density=density, A=yield_stress)
