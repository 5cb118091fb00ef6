"""Issue 13 section 1's single-impact goals, case by case and figure by figure, against what the
uniform block, the shot landing anywhere on the grid and the cores a study makes measure, and
against what the reading itself resolves (:func:`.readings.resolution_limit`)."""

from __future__ import annotations

from . import runs
from .readings import profile_rms, resolution_limit
from .single_impact import CASES, OFFSETS, error, kind_of, offset_key, reference, study_core_key

#: the goals: relative |error| (restitution: absolute; hg_over_int: the ratio itself) at 25 and 50 um
GOALS = {
    25.0: dict(dent_um=0.03, dent_radius_mm=0.03, sxx_peak_mpa=0.03, zero_depth_mm=0.03, crest_radius_mm=0.05,
               crest_height_um=0.15, restitution=0.02, profile_rms=0.04, hg_over_int=0.05),
    50.0: dict(dent_um=0.08, dent_radius_mm=0.08, sxx_peak_mpa=0.08, zero_depth_mm=0.08, crest_radius_mm=0.08,
               crest_height_um=0.08, restitution=0.02, profile_rms=0.08),
}
#: the cores a study can put under its dent in a block of each size (``study-cores`` runs; key suffix)
GOAL_CORES = {25.0: ((6.25, ""),), 50.0: ((12.5, "/fine0.5"), (6.25, "/fine0.5"))}


def goal_error(v: dict, ref: dict, key: str) -> float:
    """Run ``v``'s error in goal figure ``key`` against ``ref``: as :func:`.single_impact.error`, the
    profile RMS (:func:`.readings.profile_rms`), or the hourglass energy ratio itself."""
    if key == "profile_rms":
        return profile_rms(v, ref)
    if key == "hg_over_int":
        return v[key]
    return error(v, ref, key, kind_of(key))


def goals(data: dict | None = None) -> list[dict]:
    """Issue 13 §1's goals, case by case and figure by figure, at 25 and 50 um: the uniform block's error
    aimed at a node and the largest over the four aims of :data:`OFFSETS`, the resolution limit of the
    figure at that size (:func:`resolution_limit`, mean and largest over the grid offsets), and the
    error with the cores a study can put under its dent (:data:`GOAL_CORES`). ``verdict``: "met" (node
    and every aim within the goal), "resolution" (missed, and a perfect element read at that size
    would miss it too on average over where the shot lands), "element" (missed, the reading allows it)."""
    data = runs.load("single_impact") if data is None else data
    rows = []
    for h, goal in GOALS.items():
        step = int(round(h / 6.25))
        for case in CASES:
            ref, _ = reference(data, case)
            fine = data.get(f"{case}/physical/6.25")
            uniform = data.get(f"{case}/physical/{h:g}")
            if not ref or fine is None or uniform is None:
                continue
            limit = resolution_limit(fine, step)
            aims = [data[k] for k in (offset_key(case, h, o) for o in OFFSETS) if k in data]
            for key, tol in goal.items():
                e = goal_error(uniform, ref, key)
                e_aims = [goal_error(a, ref, key) for a in aims]
                worst = max([abs(e)] + [abs(a) for a in e_aims])
                lim = limit.get(key, (0.0, 0.0))
                cores = {hc: goal_error(c, ref, key) for hc, suffix in GOAL_CORES[h]
                         if (c := data.get(study_core_key(case, h, hc) + suffix)) is not None}
                verdict = "met" if worst <= tol else ("resolution" if lim[0] >= tol else "element")
                rows.append(dict(h_um=h, case=case, figure=key, goal=tol, node=e, worst_aim=worst,
                                 n_aims=len(aims), limit_mean=lim[0], limit_worst=lim[1], cores=cores,
                                 verdict=verdict))
    return rows


