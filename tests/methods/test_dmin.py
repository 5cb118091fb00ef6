"""d_min: eq. (4) regions, overlap definitions, bracketing bisection, REV sizes."""

import math

import numpy as np
import pytest

from peenflow.methods.dmin import (
    RevGeometry,
    bracket_from_radius,
    find_dmin,
    impact_region,
    regions_overlap,
    scan_dmin,
    single_impact_region_radius,
    stress_region,
)

H = 20e-6
X = np.arange(-2e-3, 2e-3 + H / 2, H)
Y = np.arange(-1e-3, 1e-3 + H / 2, H)
XX, YY = np.meshgrid(X, Y, indexing="ij")
S = 0.2e-3
R5 = S * math.sqrt(2 * math.log(20))  # exp(-r²/2s²) = 0.05


def bump(cx, cy=0.0):
    return np.exp(-((XX - cx) ** 2 + (YY - cy) ** 2) / (2 * S**2))


def ring(cx, r0=0.25e-3, w=0.08e-3):
    """Annular von Mises field: low at the dent centre, maximal on a ring (a typical single impact)."""
    r = np.hypot(XX - cx, YY)
    return np.exp(-((r - r0) ** 2) / (2 * w**2))


def test_eq4_threshold_and_region_radius_of_a_bump():
    m = stress_region(300e6 * bump(0.0))
    assert m.sum() > 0 and not m.all()
    assert single_impact_region_radius(X, Y, 300e6 * bump(0.0)) == pytest.approx(R5, abs=H)


def test_ring_region_is_filled_and_has_outer_radius():
    vm = 400e6 * ring(0.1e-3)
    reg = impact_region(X, Y, vm, (0.1e-3, 0.0))
    i, j = np.argmin(np.abs(X - 0.1e-3)), np.argmin(np.abs(Y))
    assert reg[i, j]  # the low-stress centre belongs to the region (holes filled)
    outer = 0.25e-3 + 0.08e-3 * math.sqrt(2 * math.log(20))
    assert single_impact_region_radius(X, Y, vm, (0.1e-3, 0.0)) == pytest.approx(outer, abs=H)


@pytest.mark.parametrize("method", ["connected", "line"])
def test_overlap_switches_where_the_5_percent_discs_touch(method):
    # field = max of two equal bumps: each region is a disc of radius R5, touching at d = 2 R5
    def two(d):
        return np.maximum(bump(-d / 2), bump(d / 2))

    for d in (2 * R5 - 3 * H, 2 * R5 - 2 * H):
        assert regions_overlap(X, Y, two(d), ((-d / 2, 0), (d / 2, 0)), method=method)
    for d in (2 * R5 + 2 * H, 2 * R5 + 3 * H):
        assert not regions_overlap(X, Y, two(d), ((-d / 2, 0), (d / 2, 0)), method=method)


def test_find_dmin_on_an_analytic_predicate():
    true = 2.3456e-3
    calls = []

    def overlaps(d):
        calls.append(d)
        return d < true

    res = find_dmin(overlaps, 1.0e-3, 2.0e-3, 1e-6)  # bracket too low: must expand upwards
    assert res.lower < true <= res.upper
    assert res.upper - res.lower <= 1e-6
    assert res.d_min == res.upper
    assert [d for d, _ in res.evaluations] == calls
    # expansions (lower, 2, 3) + bisection of a 2e-3 wide bracket to 1e-6: ceil(log2(2000)) = 11
    assert len(calls) <= 3 + 11 + 1

    res2 = find_dmin(lambda d: d < true, 3e-3, 4e-3, 1e-6)  # bracket too high: expand downwards
    assert res2.lower < true <= res2.upper and res2.upper - res2.lower <= 1e-6


def test_scan_dmin_steps_by_the_resolution_from_either_side():
    true = 2.3456e-3
    up = scan_dmin(lambda d: d < true, 2.0e-3, 4.0e-3, 0.05e-3)
    # the paper's procedure: every distance from the start in steps of the resolution
    assert [d for d, _ in up.evaluations] == pytest.approx([2.0e-3 + k * 0.05e-3 for k in range(8)], rel=1e-12)
    assert up.lower < true <= up.d_min == up.upper and up.upper - up.lower == pytest.approx(0.05e-3)
    down = scan_dmin(lambda d: d < true, 2.6e-3, 4.0e-3, 0.05e-3)
    assert down.lower < true <= down.d_min and down.d_min - down.lower == pytest.approx(0.05e-3)
    assert len(down.evaluations) == 7  # 2.60, 2.55, ..., 2.35 independent (6); 2.30 overlaps
    # the same answer as the bisection to within one resolution
    bis = find_dmin(lambda d: d < true, 2.0e-3, 4.0e-3, 0.05e-3)
    assert abs(bis.d_min - up.d_min) <= 0.05e-3


def test_scan_dmin_errors():
    with pytest.raises(ValueError, match="independent even at"):
        scan_dmin(lambda d: False, 1.0, 2.0, 0.1, floor=0.8)
    with pytest.raises(ValueError, match="still overlap at the largest distance"):
        scan_dmin(lambda d: True, 1.0, 2.0, 0.1, ceiling=1.5)


def test_find_dmin_errors():
    with pytest.raises(ValueError, match="independent even at"):
        find_dmin(lambda d: False, 1.0, 2.0, 0.01, floor=0.5)
    with pytest.raises(ValueError, match="exceeded"):
        find_dmin(lambda d: True, 1.0, 2.0, 0.01, max_evaluations=10)
    # the floor itself may be the answer's lower end: adjacent shots overlap, d_min just above
    res = find_dmin(lambda d: d < 0.52, 0.6, 0.7, 0.001, floor=0.5)
    assert res.lower < 0.52 <= res.upper and res.lower >= 0.5


def test_find_dmin_with_grid_overlap_matches_analytic_touching_distance():
    def overlaps(d):
        vm = 350e6 * np.maximum(bump(-d / 2), bump(d / 2))
        return regions_overlap(X, Y, vm, ((-d / 2, 0), (d / 2, 0)))

    r = single_impact_region_radius(X, Y, 350e6 * bump(0.0))
    lo, hi = bracket_from_radius(r)
    res = find_dmin(overlaps, lo, hi, H / 4, floor=0.0)
    assert all(r == (d < res.d_min) for d, r in res.evaluations)
    assert res.d_min == pytest.approx(2 * R5, abs=1.5 * H)


def test_rev_geometry_matches_paper():
    g = RevGeometry.from_dmin(1.5e-3)  # §5: d_min = 1.5 mm -> REV 4.5 mm
    assert g.side == pytest.approx(4.5e-3) and g.measuring_side == pytest.approx(1.5e-3)
    s = RevGeometry.almen_strip(0.58e-3)  # §4.1: 6D × 6D, 2D × 2D
    assert s.side == pytest.approx(3.48e-3) and s.measuring_side == pytest.approx(1.16e-3)
    assert s.measuring_region == pytest.approx((-0.58e-3, 0.58e-3, -0.58e-3, 0.58e-3))


def test_rev_rules_in_one_place():
    """The study's three REV rules, with a given measuring region replacing the rule's."""
    D = 0.58e-3
    assert RevGeometry.by_rule("dmin", D, d_min=1.5e-3) == RevGeometry.from_dmin(1.5e-3)
    assert RevGeometry.by_rule("paper", D) == RevGeometry.almen_strip(D)
    assert RevGeometry.by_rule("explicit", D, side=1.2e-3).measuring_side == pytest.approx(0.4e-3)
    assert RevGeometry.by_rule("explicit", D, side=1.2e-3, measuring_side=0.6e-3).measuring_side == 0.6e-3
    with pytest.raises(ValueError, match="needs the d_min"):
        RevGeometry.by_rule("dmin", D)
    # the whole face is a measuring region (periodic faces have no edge to avoid); more is refused
    assert RevGeometry.by_rule("explicit", D, side=1.2e-3, measuring_side=1.2e-3).measuring_side == 1.2e-3
    with pytest.raises(ValueError, match="at most the REV side"):
        RevGeometry.by_rule("explicit", D, side=1.2e-3, measuring_side=1.3e-3)
    with pytest.raises(ValueError, match="unknown REV rule"):
        RevGeometry.by_rule("6D", D)
