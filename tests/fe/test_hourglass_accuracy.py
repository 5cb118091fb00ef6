"""Single-impact accuracy of the physical hourglass form against the converged references.

The references (6.25 um physical element, Richardson-extrapolated where the
25 / 12.5 / 6.25 um sequence converges cleanly) are those of the stored runs
(peenflow/validation/data/single_impact.json, made by ``benchmarks/single_impact.py``;
docs/validation.md section 4). Each test reruns one case at a coarse element size
with the same setup and metrics and asserts its error. Where the issue's goal
(13 §1) is met the goal is the tolerance; where it is not, the tolerance is the
measured error rounded up, named ``MISSED`` so the gap stays visible
(docs/validation.md section 4).
"""

import math

import pytest

from peenflow.validation import goals as G
from peenflow.validation import readings as rd
from peenflow.validation import runs
from peenflow.validation import single_impact as si

DATA = runs.load("single_impact")
KIND = {key: kind for key, _, kind in si.QUANTITIES}  # relative error, or a difference (restitution)

# relative tolerances (restitution: absolute) at 25 um: the goal of issue 13 §1
GOAL_25 = dict(dent_um=0.03, dent_radius_mm=0.03, sxx_peak_mpa=0.03, zero_depth_mm=0.03, crest_radius_mm=0.05,
               crest_height_um=0.15, restitution=0.02, profile_rms=0.04)
# at 50 um the pile-up crest is two elements wide and not resolved (errors of 15-130 %, docs/validation.md section 4):
# the 50 um tests hold the dent, the stress and the rebound
GOAL_50 = dict(dent_um=0.08, dent_radius_mm=0.08, sxx_peak_mpa=0.08, zero_depth_mm=0.08, restitution=0.02,
               profile_rms=0.08)
# where the physical element misses the goal: (case, h um, quantity) -> the measured |error| + 0.5 %
# rounded up to whole per cent (restitution: absolute; hg_over_int: the ratio itself); docs/validation.md section 4.
# Measured 2026-12-01 with the surface line interpolated by a makima spline and the sigma_xx column
# centred on the dent (peenflow/validation/readings.py); every entry is at or below the one it replaces.
# Crest position and height and the 25 m/s dent's edge are near the sampling limit of a 25 um
# surface (test_surface_metric_on_a_coarser_sampling_of_the_same_line); the sigma_xx peak under the
# 45 deg dent converges slowly (+14 / +5 % at 25 / 12.5 um, order ~0.6).
# Since 2026-12-02 sigma_xx(z) is read on the curve recovered from the layer means (peak, its depth,
# zero crossing, profile RMS; readings.profile_curve): the 45 deg entries are those of that
# reading, and the profile RMS joins the checked quantities (goal 4 % at 25 um, 8 % at 50 um: now
# met at 25 um on three of four cases, 1.2-3.9 %, where the straight lines between mid-depths read
# 2.1-7.7 %). Read so, a perfect element seen through 25 um layers is within 1.9 % on the peak and
# 0.9 % on the zero crossing (straight lines: 1.1 / 0.9 %), so the new entries below are the
# element's: the 25 m/s zero crossing -4.8 % (-2.6 % read by straight lines) and peak +3.4 %
# (+2.4 %), the 45 deg peak +14.4 % (+13.0 %); at 50 um the entries moved both ways.
# Since 2026-12-02 (later) the dent depth is read between nodes on the surface spline
# (readings.dent_bottom; within 0.9 % on a 25 um sampling of the converged lines): the 45 deg
# dent's -3.5 % became -1.7 % (goal met, entry removed), the 25 m/s dent (deepest point on a node)
# stays -4.5 %.
MISSED = {
    ('al-47-65', 25, 'crest_radius_mm'): 0.11,
    ('sae-25-90', 25, 'dent_radius_mm'): 0.07,
    ('sae-25-90', 25, 'dent_um'): 0.05,
    ('sae-25-90', 25, 'hg_over_int'): 0.08,
    ('sae-25-90', 25, 'sxx_peak_mpa'): 0.04,
    ('sae-25-90', 25, 'zero_depth_mm'): 0.06,
    ('sae-25-90', 50, 'dent_radius_mm'): 0.33,
    ('sae-25-90', 50, 'profile_rms'): 0.13,
    ('sae-25-90', 50, 'restitution'): 0.07,
    ('sae-25-90', 50, 'sxx_peak_mpa'): 0.14,
    ('sae-25-90', 50, 'zero_depth_mm'): 0.15,
    # 30 deg: the sigma_xx peak under the dent converges at order ~1.3 (+34.8 / +14.4 / +5.9 % at
    # 25 / 12.5 / 6.25 um against the Richardson reference), the friction hump of the 45 deg case
    # stronger (docs/validation.md, shallow angles); dent, its radius, zero crossing and rebound meet
    # the goals
    ('sae-55-30', 25, 'crest_height_um'): 0.44,
    ('sae-55-30', 25, 'hg_over_int'): 0.09,
    ('sae-55-30', 25, 'profile_rms'): 0.14,
    ('sae-55-30', 25, 'sxx_peak_mpa'): 0.36,
    ('sae-55-30', 50, 'profile_rms'): 0.21,
    ('sae-55-30', 50, 'sxx_peak_mpa'): 0.50,
    ('sae-55-45', 25, 'crest_height_um'): 0.26,
    ('sae-55-45', 25, 'crest_radius_mm'): 0.15,
    ('sae-55-45', 25, 'dent_radius_mm'): 0.06,
    ('sae-55-45', 25, 'hg_over_int'): 0.07,
    ('sae-55-45', 25, 'profile_rms'): 0.08,
    ('sae-55-45', 25, 'sxx_peak_mpa'): 0.15,
    ('sae-55-45', 50, 'dent_radius_mm'): 0.15,
    ('sae-55-45', 50, 'profile_rms'): 0.17,
    ('sae-55-45', 50, 'sxx_peak_mpa'): 0.29,
    ('sae-55-45', 50, 'zero_depth_mm'): 0.09,
    ('sae-55-90', 25, 'crest_height_um'): 0.18,
    ('sae-55-90', 25, 'crest_radius_mm'): 0.11,
    ('sae-55-90', 50, 'profile_rms'): 0.16,
    ('sae-55-90', 50, 'zero_depth_mm'): 0.12,
}


# the shot aimed half an element off a node (benchmarks/single_impact.py offsets; docs/validation.md section 4, "Shots
# between nodes"): the worst aim of the 25 m/s dent for its crest and rebound; its dent, read between
# nodes, is as far off as aimed at a node (-4.3 %; the deepest node alone read -7.1 %)
MISSED_BETWEEN_NODES = {
    ('sae-25-90', 25, 'crest_height_um'): 0.19,
    ('sae-25-90', 25, 'crest_radius_mm'): 0.16,
    ('sae-25-90', 25, 'dent_um'): 0.05,
    ('sae-25-90', 25, 'hg_over_int'): 0.08,
    ('sae-25-90', 25, 'restitution'): 0.03,
    ('sae-25-90', 25, 'zero_depth_mm'): 0.04,
}


def _check(case, h_um, goal, offset=0.0):
    ref, _ = si.reference(DATA, case)
    assert ref, f"no reference for {case} in {runs.path('single_impact')}"
    got = si.run(case, "physical", h_um, offset)
    missed = MISSED_BETWEEN_NODES if offset else MISSED
    errors = {}
    for key, tol in goal.items():
        tol = missed.get((case, h_um, key), tol)
        err = rd.profile_rms(got, ref) if key == "profile_rms" else si.error(got, ref, key, KIND[key])
        errors[key] = err
        assert abs(err) <= tol, f"{case} at {h_um} um: {key} error {err:+.4g} (tolerance {tol:g})"
    return got, errors


@pytest.mark.parametrize("case", ["sae-55-90", "sae-25-90"])
def test_normal_impacts_at_25um(case):
    got, _ = _check(case, 25, GOAL_25)
    assert got["energy_error"] < 0.005
    assert got["hg_over_int"] <= MISSED.get((case, 25, "hg_over_int"), 0.05)


def test_normal_impact_between_nodes_at_25um():
    """In a REV shots land anywhere on the element grid: aimed half an element off a node (on the
    half model), the 25 m/s dent's deepest point falls between nodes; read on the surface spline there
    its depth is as far off as aimed at a node (-4.3 against -4.5 %), its crest and rebound move; the
    sigma_xx profile stays within the goal."""
    got, _ = _check("sae-25-90", 25, GOAL_25, offset=0.5)
    assert got["energy_error"] < 0.005
    assert got["hg_over_int"] <= MISSED_BETWEEN_NODES[("sae-25-90", 25, "hg_over_int")]


@pytest.mark.slow
@pytest.mark.parametrize("case", ["sae-55-45", "sae-55-30", "al-47-65"])
def test_oblique_impacts_at_25um(case):
    got, _ = _check(case, 25, GOAL_25)
    assert got["energy_error"] < 0.005
    assert got["hg_over_int"] <= MISSED.get((case, 25, "hg_over_int"), 0.05)
    if case.startswith("sae-55-"):
        _assert_coulomb(got, case)


@pytest.mark.parametrize("case", list(si.CASES))
def test_impacts_at_50um(case):
    got, _ = _check(case, 50, GOAL_50)
    assert got["energy_error"] < 0.01


def _assert_coulomb(got, case):
    """Coulomb's law read off the shot's rebound (si.friction): the friction impulse (from the spin it
    gave the shot) is at most mu = 0.2 of the normal impulse, within 3 % for the normals the dent's
    walls tilt. At 30 deg the shot slides throughout (rigid-body theory: v_t / v_n = 1.73 above
    7/2 mu (1 + e) = 1.1): the ratio is mu itself and the contact point still slides at separation, at
    about the rigid sphere's speed (16.9 m/s at 25 um); at 45 deg (1.0 against 1.05) the contact
    reaches rolling: the contact point leaves at under a tenth of the shot's tangential speed."""
    _, speed, angle = si.CASES[case]
    f = si.friction(got, case)
    v_t = speed * math.cos(math.radians(angle))
    assert f["ratio"] <= 0.2 * 1.03, (case, f)
    if f["slip_rigid"] > 0.1 * v_t:
        assert f["ratio"] == pytest.approx(0.2, rel=0.03), (case, f)
        assert 0.25 * v_t < f["slip_out"] <= f["slip_rigid"] * 1.05, (case, f)
    else:
        assert abs(f["slip_out"]) < 0.1 * v_t, (case, f)


@pytest.mark.parametrize("case", [c for c, (_, _, a) in si.CASES.items() if a < 50.0])
def test_shallow_impacts_balance_energy_and_obey_coulomb_at_50um(case):
    """The shallow cases (45 and 30 deg) on the 50 um block: the energy balance closes within 0.5 % of
    the impact energy (measured 0.37 / 0.21 % at 45 / 30 deg) and the friction follows Coulomb (:func:`_assert_coulomb`)."""
    got = si.run(case, "physical", 50)
    assert got["energy_error"] < 0.005
    _assert_coulomb(got, case)


def test_surface_metric_on_a_coarser_sampling_of_the_same_line():
    """The metric itself, not the element: each stored 6.25 um surface line taken at every 4th node
    (25 um spacing, each of the 4 offsets) must read the dent radius and the crest radius close to
    the full line's. The bounds are the measured sampling errors rounded up (docs/validation.md section 4): the
    dent edge within 3.5 um on average (the straight-line rule read it 3.6-6.2 um too far out), the
    crest within 9 um (4-8 % of its radius, so a 25 um surface cannot show the 5 % goal on every
    case whatever the element)."""
    rows = rd.sampling_bias(DATA, step=4)
    assert {r["run"].split("/")[0] for r in rows} == set(si.CASES)
    for r in rows:
        assert abs(r["dent_radius_bias_um"]) <= 3.5, r
        assert r["dent_radius_worst_um"] <= 7.5, r
        assert abs(r["crest_radius_bias_um"]) <= 9.0, r
        assert r["crest_radius_worst_um"] <= 15.0, r


def test_dent_depth_read_between_nodes_on_a_coarser_sampling_of_the_same_line():
    """The dent depth reading (readings.dent_bottom), not the element: each stored 6.25 um
    line, whole (a quarter model's mirrored about its axis), taken at every 4th node from each of the
    4 offsets -- a 25 um grid with the dent bottom on a node, or 1/4, 1/2, 3/4 of an element off.
    Read on the surface spline between nodes the depth is within 1 % of the full line's at every
    offset (measured -0.26 ... -0.87 % at worst; the flatter 30 deg dent within 1.1 %, -1.03 %), the
    3 % goal is the element's to meet; the deepest node alone misses by up to 4 % on the normal dents (a parabolic bottom read h / 2 off its vertex),
    which the old reading charged the element with."""
    import numpy as np

    rows = rd.sampling_bias(DATA, step=4)
    assert {r["run"].split("/")[0] for r in rows} == set(si.CASES)
    for r in rows:
        # the 30 deg dent, 7.3 um deep over a 66 um radius, the flattest: -1.03 % at worst
        worst = 0.011 if r["run"].startswith("sae-55-30/") else 0.01
        assert -worst <= r["dent_worst"] <= r["dent_bias"] <= 0.0, r
    v = DATA["sae-25-90/physical/6.25"]
    x, u = rd.whole_line(np.array(v["surface_x_mm"]) * 1e-3, np.array(v["surface_uz_um"]) * 1e-6)
    node_only = min(u[o::4].max() / u.max() - 1.0 for o in range(4))
    assert node_only < -0.03
    assert rd.dent_bottom(x, u) == pytest.approx(u.max(), rel=1e-3)  # on the full line: its deepest node


def test_profile_reading_on_coarser_layers_of_the_same_profile():
    """The sigma_xx(z) reading itself, not the element: each stored 6.25 um column profile averaged
    over 25 um layers (what a perfect 25 um element would give: one-point elements hold their
    element's mean). Read on the curve recovered from the layer means it stays within 3 % (RMS of
    the peak) of the full profile on every case, below the 4 % goal (measured 0.3-2.7 %); joined
    by straight lines between mid-depths it was 2.5-7.8 % off, at least twice as far, so that
    reading charged the element with most of its 25 um profile error (docs/validation.md section 4)."""
    rows = rd.profile_sampling_bias(DATA, step=4)
    assert {r["run"].split("/")[0] for r in rows} == set(si.CASES)
    for r in rows:
        assert r["recovered"] <= 0.03, r
        assert r["lines"] >= 2.0 * r["recovered"], r


def test_goals_below_the_resolution_of_the_mesh():
    """Which of issue 13 §1's goals no element can show at 25 / 50 um (docs/validation.md section 4, "Goal
    by goal"): the converged 6.25 um fields read at that spacing (surface line at every 4th / 8th
    node from each offset; sigma_xx averaged over 25 / 50 um layers) against themselves in full.
    At 50 um the dent radius reads >= 8 % off on average over where the shot lands on the three SAE
    dents and the crest radius and height on all four cases (measured 9.5-20 %, 15-23 %, 13-29 %);
    at 25 um the crest radius >= 5 % on three of the four (6.0-8.7 %; 55 m/s normal 4.3 %), while the
    dent depth, sigma_xx peak and zero crossing are readable to <= 2 % at 25 um: those goals are the
    element's to meet."""
    lim25 = {c: rd.resolution_limit(DATA[f"{c}/physical/6.25"], 4) for c in si.CASES}
    lim50 = {c: rd.resolution_limit(DATA[f"{c}/physical/6.25"], 8) for c in si.CASES}
    for c in ("sae-25-90", "sae-55-90", "sae-55-45"):
        assert lim50[c]["dent_radius_mm"][0] >= GOAL_50["dent_radius_mm"], (c, lim50[c])
    for c in si.CASES:
        for key in ("crest_radius_mm", "crest_height_um"):  # the 8 % (GOAL_50 leaves the crest out)
            assert lim50[c][key][0] >= G.GOALS[50.0][key], (c, key, lim50[c][key])
        for key in ("dent_um", "sxx_peak_mpa", "zero_depth_mm"):
            assert lim25[c][key][0] <= 0.02, (c, key, lim25[c][key])
        assert lim25[c]["profile_rms"][0] <= 0.03, (c, lim25[c]["profile_rms"])
    assert sum(lim25[c]["crest_radius_mm"][0] >= GOAL_25["crest_radius_mm"] for c in si.CASES) == 3, lim25
