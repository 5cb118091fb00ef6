"""Minimum independent shot distance d_min (paper §3.1, eq. 4) and REV sizes.

Eq. (4): the stress region of an impact is the set of top-surface points
where the von Mises residual stress is at least 5 % of its maximum on that
surface. Two impacts are independent when their regions do not overlap;
``d_min`` is the smallest centre distance at which they are independent.

Overlap, defined precisely (``method="connected"``, the default). On the
structured top-surface grid of a two-shot run:

1. ``mask`` = nodes with ``σ_VM >= fraction · max σ_VM`` (max over the whole
   two-shot surface, as eq. 4 is written for the surface of the run);
2. holes are filled (``binary_fill_holes``): a single impact's region is often
   a ring around a dent whose centre is below the threshold, and that ring
   encloses the impact, so the enclosed nodes belong to the region;
3. connected components with 4-connectivity (nodes sharing a grid edge; a
   diagonal contact between two nodes is not a connection, so two regions
   must share an edge of the grid to touch);
4. the region of impact k is the component containing the node nearest to the
   impact point, or, if that node is outside the mask, the component of the
   mask node nearest to it;
5. the impacts overlap iff both regions are the same component.

``method="line"`` is the weaker, cheaper alternative: the impacts overlap iff
every sample of the (hole-filled) mask along the segment joining the two
impact points is inside the mask (nearest-node sampling every half cell). For
two similar impacts the bridge between the regions forms on that segment
first, so both definitions agree except for irregular regions.

The search. ``find_dmin`` brackets and bisects a caller-supplied predicate
``overlaps(d)`` (which runs or looks up a two-shot simulation). It assumes
overlap is monotone in d (overlapping below d_min, independent above), as the
paper's linear scan does implicitly; bisection cannot detect a violation (its
evaluations are consistent by construction), so a caller who doubts it should
probe a few distances above d_min. ``d_min`` returned is
the upper end of the final bracket: the smallest *evaluated* distance known to
give independent impacts, so it is conservative by at most ``resolution``.
``scan_dmin`` is the paper's linear scan: it steps by ``resolution`` from the
bracket's lower end (upwards while the regions overlap, downwards while they
are independent) and so evaluates every distance on its way: it finds the
first change of the predicate from where it starts, where bisection assumes
monotony between its probes, and costs ``|d_min - lower| / resolution`` runs
instead of about ``log2`` of that.

REV sizes (§3.1, §4.1): REV top-surface side 3 d_min, measuring region the
central d_min square; the Almen-strip REV of §4.1 is 6D × 6D with a 2D × 2D
measuring region.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy import ndimage

#: eq. (4) threshold, fraction of the maximum von Mises residual stress
REGION_FRACTION = 0.05


def stress_region(vm, fraction: float = REGION_FRACTION) -> np.ndarray:
    """Eq. (4): boolean (nx, ny) mask of nodes with ``vm >= fraction · max(vm)``.

    vm : (nx, ny) Pa, von Mises residual stress on the top-surface grid.
    """
    vm = np.asarray(vm, dtype=float)
    if vm.ndim != 2:
        raise ValueError("vm must be a 2-D (nx, ny) array")
    vmax = np.max(vm)
    if not vmax > 0:
        raise ValueError("von Mises field has no positive value")
    return vm >= fraction * vmax


def _labels(mask):
    filled = ndimage.binary_fill_holes(mask)
    labels, _ = ndimage.label(filled)  # default structure: 4-connectivity in 2-D
    return filled, labels


def _component_of(labels, x, y, point):
    i = int(np.argmin(np.abs(x - point[0])))
    j = int(np.argmin(np.abs(y - point[1])))
    if labels[i, j] > 0:
        return labels[i, j]
    ii, jj = np.nonzero(labels)
    if ii.size == 0:
        raise ValueError("empty stress region")
    k = np.argmin((x[ii] - point[0]) ** 2 + (y[jj] - point[1]) ** 2)
    return labels[ii[k], jj[k]]


def _check_grid(x, y, vm):
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    vm = np.asarray(vm, dtype=float)
    if vm.shape != (x.size, y.size):
        raise ValueError(f"vm must have shape (len(x), len(y)) = ({x.size}, {y.size}), got {vm.shape}")
    return x, y, vm


def impact_region(x, y, vm, impact_point, fraction: float = REGION_FRACTION) -> np.ndarray:
    """Boolean (nx, ny) region of the impact at ``impact_point`` (definition in the module docstring).

    x : (nx,) m, y : (ny,) m, vm : (nx, ny) Pa, impact_point : (x, y) m.
    """
    x, y, vm = _check_grid(x, y, vm)
    _, labels = _labels(stress_region(vm, fraction))
    return labels == _component_of(labels, x, y, impact_point)


def single_impact_region_radius(x, y, vm, impact_point=(0.0, 0.0), fraction: float = REGION_FRACTION) -> float:
    """Largest distance (m) from the impact point to a node of its eq. (4) region.

    Two such regions (of equal size) start to touch at a centre distance of
    about twice this radius; :func:`bracket_from_radius` turns it into a
    starting bracket for :func:`find_dmin`.
    """
    x, y, vm = _check_grid(x, y, vm)
    reg = impact_region(x, y, vm, impact_point, fraction)
    ii, jj = np.nonzero(reg)
    return float(np.sqrt(np.max((x[ii] - impact_point[0]) ** 2 + (y[jj] - impact_point[1]) ** 2)))


def regions_overlap(
    x, y, vm, impacts, fraction: float = REGION_FRACTION, method: str = "connected"
) -> bool:
    """Do the eq. (4) regions of two impacts overlap? (definitions in the module docstring)

    x : (nx,) m, y : (ny,) m, vm : (nx, ny) Pa von Mises residual of the two-shot run,
    impacts : ((x1, y1), (x2, y2)) m, method : "connected" or "line".
    """
    x, y, vm = _check_grid(x, y, vm)
    (p1, p2) = (np.asarray(impacts[0], dtype=float), np.asarray(impacts[1], dtype=float))
    filled, labels = _labels(stress_region(vm, fraction))
    if method == "connected":
        return bool(_component_of(labels, x, y, p1) == _component_of(labels, x, y, p2))
    if method == "line":
        h = min(np.min(np.diff(x)), np.min(np.diff(y)))
        n = max(int(np.ceil(np.hypot(*(p2 - p1)) / (0.5 * h))), 1) + 1
        s = np.linspace(0.0, 1.0, n)[:, None]
        pts = p1 + s * (p2 - p1)
        i = np.abs(x[None, :] - pts[:, :1]).argmin(axis=1)
        j = np.abs(y[None, :] - pts[:, 1:]).argmin(axis=1)
        return bool(np.all(filled[i, j]))
    raise ValueError("method must be 'connected' or 'line'")


def bracket_from_radius(radius: float, margin: float = 0.5) -> tuple[float, float]:
    """Starting bracket ``(2r(1 - margin), 2r(1 + margin))`` m for d_min from a region radius r."""
    if not radius > 0 or not 0 < margin < 1:
        raise ValueError("need radius > 0 and 0 < margin < 1")
    return 2 * radius * (1 - margin), 2 * radius * (1 + margin)


@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class DminSearch:
    """Outcome of :func:`find_dmin`.

    d_min : m, smallest evaluated distance with independent impacts (= upper).
    lower : m, largest evaluated distance with overlapping regions.
    upper : m. resolution : m, requested bracket width (upper - lower <= resolution).
    evaluations : ((d, overlaps), ...) in evaluation order, for caching by the caller.
    """

    d_min: float
    lower: float
    upper: float
    resolution: float
    evaluations: tuple


def _recorded(overlaps: Callable[[float], bool], max_evaluations: int, what: str):
    """``(ev, evals)``: ``ev(d)`` calls ``overlaps`` and appends ``(d, result)``
    to ``evals``, refusing to run more than ``max_evaluations`` times."""
    evals: list[tuple[float, bool]] = []

    def ev(d):
        if len(evals) >= max_evaluations:
            raise ValueError(f"d_min {what} exceeded {max_evaluations} evaluations; evaluations so far: {evals}")
        r = bool(overlaps(float(d)))
        evals.append((float(d), r))
        return r

    return ev, evals


def find_dmin(overlaps: Callable[[float], bool], lower: float, upper: float, resolution: float, *,
              floor: float = 0.0, max_evaluations: int = 60) -> DminSearch:
    """Bracket and bisect the overlap predicate for d_min.

    overlaps : d (m) -> True if two impacts at centre distance d have overlapping
        eq. (4) regions (e.g. a two-shot run followed by :func:`regions_overlap`).
    lower, upper : m, starting bracket (e.g. :func:`bracket_from_radius`); if
        ``overlaps(lower)`` is False or ``overlaps(upper)`` is True the bracket
        is moved (with a doubling step) until it holds.
    resolution : m, stop when ``upper - lower <= resolution``.
    floor : m, smallest admissible distance (e.g. 2R: adjacent shots); if the
        regions are independent even there, ValueError is raised.
    """
    if not (upper > lower >= floor) or not resolution > 0:
        raise ValueError("need floor <= lower < upper and resolution > 0")
    ev, evals = _recorded(overlaps, max_evaluations, "search")

    step = upper - lower
    if not ev(lower):
        # lower is already independent: search downwards
        upper = lower
        while True:
            if upper <= floor:
                raise ValueError(
                    f"impacts are independent even at the smallest distance {floor} m; d_min <= {floor} m"
                )
            cand = max(floor, upper - step)
            step *= 2
            if ev(cand):
                lower = cand
                break
            upper = cand
    else:
        while ev(upper):
            lower = upper
            upper = upper + step
            step *= 2
    while upper - lower > resolution:
        mid = 0.5 * (lower + upper)
        if ev(mid):
            lower = mid
        else:
            upper = mid
    return DminSearch(float(upper), float(lower), float(upper), float(resolution), tuple(evals))


def scan_dmin(overlaps: Callable[[float], bool], lower: float, upper: float, resolution: float, *,
              floor: float = 0.0, ceiling: float = float("inf"), max_evaluations: int = 200) -> DminSearch:
    """The paper's linear scan for d_min in steps of ``resolution`` (m).

    Starts at ``lower`` (m, e.g. from :func:`bracket_from_radius`; ``upper`` is
    unused but kept for the same call as :func:`find_dmin`) and steps up while
    the regions overlap, or down (not below ``floor``) while they are
    independent, until the predicate changes; d_min is the first independent
    distance of the scan. ValueError if the scan leaves ``[floor, ceiling]``
    or takes more than ``max_evaluations`` runs.
    """
    del upper
    if not resolution > 0 or lower < floor:
        raise ValueError("need lower >= floor and resolution > 0")
    ev, evals = _recorded(overlaps, max_evaluations, "scan")

    # distances as lower +- k resolution (no drift from repeated addition)
    at = lambda k: float(lower) + k * resolution  # noqa: E731
    if ev(at(0)):
        k = 0
        while True:
            if at(k + 1) > ceiling:
                raise ValueError(f"impacts still overlap at the largest distance {at(k):.6g} m; d_min > {at(k):.6g} m")
            if not ev(at(k + 1)):
                return DminSearch(at(k + 1), at(k), at(k + 1), float(resolution), tuple(evals))
            k += 1
    k = 0
    while True:
        if at(k) <= floor:
            raise ValueError(f"impacts are independent even at the smallest distance {floor} m; d_min <= {floor} m")
        below = max(floor, at(k - 1))
        if ev(below):
            return DminSearch(at(k), below, at(k), float(resolution), tuple(evals))
        k -= 1


@dataclass(frozen=True)
class RevGeometry:
    """Top-surface sizes of a representative elementary volume (square), m.

    side : REV top-surface side. measuring_side : side of the central measuring region.
    """

    side: float
    measuring_side: float

    @classmethod
    def from_dmin(cls, d_min: float) -> "RevGeometry":
        """§3.1: side 3 d_min, measuring region d_min × d_min at the centre."""
        return cls(3.0 * d_min, d_min)

    @classmethod
    def almen_strip(cls, shot_diameter: float) -> "RevGeometry":
        """§4.1: strip REV 6D × 6D (× h), measuring region 2D × 2D."""
        return cls(6.0 * shot_diameter, 2.0 * shot_diameter)

    @classmethod
    def by_rule(cls, rule: str, shot_diameter: float, d_min: float | None = None, side: float | None = None,
                measuring_side: float | None = None) -> "RevGeometry":
        """The REV of a study's rule, m: the one place the rule is written.

        ``"dmin"``: :meth:`from_dmin` (``d_min`` needed); ``"paper"``:
        :meth:`almen_strip`; ``"explicit"``: the given ``side`` with a
        measuring region of ``side / 3``. A given ``measuring_side``
        replaces the rule's.
        """
        if rule == "dmin":
            if d_min is None:
                raise ValueError("REV rule 'dmin' needs the d_min from a two-shot search")
            geometry = cls.from_dmin(d_min)
        elif rule == "paper":
            geometry = cls.almen_strip(shot_diameter)
        elif rule == "explicit":
            if side is None:
                raise ValueError("REV rule 'explicit' needs the REV side")
            geometry = cls(side, side / 3.0)
        else:
            raise ValueError(f"unknown REV rule {rule!r}; expected 'dmin', 'paper' or 'explicit'")
        if measuring_side is not None:
            geometry = cls(geometry.side, measuring_side)
        # == side: the whole face (periodic lateral faces have no edge to keep away from)
        if not 0 < geometry.measuring_side <= geometry.side:
            raise ValueError(f"measuring region {geometry.measuring_side:.4g} m must be > 0 and at most the REV "
                             f"side {geometry.side:.4g} m")
        return geometry

    @property
    def measuring_region(self) -> tuple[float, float, float, float]:
        """(x0, x1, y0, y1) m of the central measuring square (origin at the REV centre)."""
        h = 0.5 * self.measuring_side
        return (-h, h, -h, h)
