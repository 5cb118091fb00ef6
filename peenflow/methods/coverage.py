"""Monte-Carlo coverage and the Avrami law (paper §3.2.2, eq. 5).

Coverage, as in visual inspection: a node of the measuring-surface grid is
covered when it lies inside the dent ellipse of at least one impact; coverage
is the covered fraction of nodes, in percent. Each impact's ellipse is the
single-impact :class:`~peenflow.methods.indentation.DentEllipse` translated
to the impact's landing point (its ``offset`` carries the oblique-impact shift
of the ellipse centre downstream of the landing point).

One pass gives the whole curve: for every node the arrival index of the first
dent that covers it is recorded, so coverage after the first N arrivals is the
fraction of nodes whose index is < N, for all N at once. Each dent only
touches the nodes in its bounding box (``searchsorted`` on the sorted grid
axes), so N = a few thousand dents on a 200 × 200 grid take tens of ms.

Closed form (the check). If landing points are independent and uniform over a
peening surface of area ``A_peen`` and the dent region that covers a given node
(the ellipse reflected about that node) lies inside the peening surface, one
impact covers the node with probability ``q = A_dent / A_peen``, so

    E[C(N)] = 100 (1 - (1 - q)^N),

an Avrami law (eq. 5) with rate ``A = -ln(1 - q) ≈ q``.

Avrami fit of eq. (5). The paper says "MLS" (moving least squares), which is a
local-regression method and cannot produce the single constant A of eq. (5);
ordinary least squares is meant. The fit minimises the squared residuals of
the coverage itself (percent), the measured quantity. The linearised form
``-ln(1 - C/100) = A N`` is only used as the starting value: it weights points
near 100 % (where the log amplifies the Monte-Carlo noise, and is infinite at
C = 100) far too much.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from .indentation import DentEllipse

from ._arrays import read_only as _ro

#: visible coverage regarded as full (100 %) coverage (SAE J2277)
FULL_COVERAGE_PERCENT = 98.0


def _dent_geometry(dent: DentEllipse):
    dx, dy = dent.offset
    a, b = dent.semi_axis_along, dent.semi_axis_across
    if not (a > 0 and b > 0):
        raise ValueError("dent semi-axes must be positive")
    return dx, dy, a, b


def first_cover_index(landing, dent: DentEllipse, grid_x, grid_y) -> np.ndarray:
    """(mx, my) int: arrival index of the first dent covering each grid node.

    landing : (N, 2) m, landing points in arrival order.
    dent : DentEllipse of a single impact (semi-axes, offset from the landing point).
    grid_x : (mx,) m, grid_y : (my,) m, increasing node coordinates of the measuring surface.
    Nodes never covered hold N. A node on the ellipse boundary counts as covered.
    """
    p = np.asarray(landing, dtype=float).reshape(-1, 2)
    gx = np.asarray(grid_x, dtype=float)
    gy = np.asarray(grid_y, dtype=float)
    if np.any(np.diff(gx) <= 0) or np.any(np.diff(gy) <= 0):
        raise ValueError("grid axes must be strictly increasing")
    dx, dy, a, b = _dent_geometry(dent)
    n = p.shape[0]
    first = np.full((gx.size, gy.size), n, dtype=np.int64)
    cx, cy = p[:, 0] + dx, p[:, 1] + dy
    i0 = np.searchsorted(gx, cx - a, side="left")
    i1 = np.searchsorted(gx, cx + a, side="right")
    j0 = np.searchsorted(gy, cy - b, side="left")
    j1 = np.searchsorted(gy, cy + b, side="right")
    hit = np.flatnonzero((i1 > i0) & (j1 > j0))
    # reverse arrival order: an earlier dent overwrites a later one, leaving the first
    for k in hit[::-1]:
        u = ((gx[i0[k]:i1[k]] - cx[k]) / a) ** 2
        v = ((gy[j0[k]:j1[k]] - cy[k]) / b) ** 2
        inside = (u[:, None] + v[None, :]) <= 1.0 + 1e-12
        first[i0[k]:i1[k], j0[k]:j1[k]][inside] = k
    return first


def coverage_percent(landing, dent: DentEllipse, grid_x, grid_y) -> float:
    """Coverage (%) of the measuring grid by the dents at all ``landing`` points (N, 2) m."""
    p = np.asarray(landing, dtype=float).reshape(-1, 2)
    first = first_cover_index(p, dent, grid_x, grid_y)
    return 100.0 * float(np.mean(first < p.shape[0]))


def coverage_curve(landing, dent: DentEllipse, grid_x, grid_y, counts) -> np.ndarray:
    """Coverage (%) after the first N arrivals, for each N in ``counts`` (k,); returns (k,)."""
    p = np.asarray(landing, dtype=float).reshape(-1, 2)
    counts = np.asarray(counts)
    if np.any(counts < 0) or np.any(counts > p.shape[0]):
        raise ValueError(f"counts must lie in [0, {p.shape[0]}] (the number of landing points)")
    first = first_cover_index(p, dent, grid_x, grid_y).ravel()
    # histogram of first-cover indices -> covered node count after N arrivals
    covered = np.concatenate([[0], np.cumsum(np.bincount(first, minlength=p.shape[0] + 1))])
    return 100.0 * covered[counts] / first.size


def coverage_curves(landings, dent: DentEllipse, grid_x, grid_y, counts) -> np.ndarray:
    """(n_seq, k) coverage (%) for several sequences; ``landings`` is a sequence of (N_i, 2)."""
    return np.vstack([coverage_curve(p, dent, grid_x, grid_y, counts) for p in landings])


def measuring_grid(region: tuple[float, float, float, float], n_x: int, n_y: int | None = None):
    """Node axes ``(grid_x (n_x,), grid_y (n_y,))`` of a rectangular region (x0, x1, y0, y1), m."""
    x0, x1, y0, y1 = region
    n_y = n_x if n_y is None else n_y
    return np.linspace(x0, x1, n_x), np.linspace(y0, y1, n_y)


def expected_coverage_uniform(n, dent_area: float, peening_area: float) -> np.ndarray:
    """Closed-form expected coverage (%) ``100 (1 - (1 - q)^N)``, ``q = A_dent / A_peen``.

    Valid for uniform independent landings when every node's covering region
    lies inside the peening surface (module docstring). Areas in m².
    """
    q = dent_area / peening_area
    if not 0 < q < 1:
        raise ValueError("need 0 < dent_area < peening_area")
    return 100.0 * -np.expm1(np.asarray(n, dtype=float) * np.log1p(-q))


@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class AvramiFit:
    """Eq. (5), ``C(N) = 100 (1 - exp(-A N))``, fitted by least squares in C.

    rate : A, 1/shot. residual_rms : %, rms of (data - model).
    counts, coverage : the fitted data (shots, %), flattened over sequences.
    full_percent : %, the visible coverage that counts as full (N_f; 98 by
    SAE J2277 and the paper).
    """

    rate: float
    residual_rms: float
    counts: np.ndarray = field(repr=False)
    coverage: np.ndarray = field(repr=False)
    full_percent: float = FULL_COVERAGE_PERCENT

    def __post_init__(self):
        if not 0.0 < self.full_percent < 100.0:
            raise ValueError(f"full coverage must be a percentage in (0, 100), got {self.full_percent!r}")

    def coverage_at(self, n) -> np.ndarray:
        """Model coverage (%) after n shots."""
        return 100.0 * -np.expm1(-self.rate * np.asarray(n, dtype=float))

    @property
    def full_coverage_shots(self) -> float:
        """N_f: shots for full (``full_percent``) visible coverage, ``-ln(1 - full/100) / A``
        (``ln 50 / A`` at 98 %)."""
        return float(-np.log1p(-self.full_percent / 100.0) / self.rate)

    def shots_for_coverage(self, percent: float) -> float:
        """N_c for a coverage specification in % (SAE J2277 convention, paper §3.2.2).

        * percent >= 100: ``N_c = (percent / 100) · N_f`` (200 % = twice the
          exposure of full coverage), the paper's rule;
        * full <= percent < 100: ``N_f`` (``full_percent``, 98 % by default,
          visible coverage *is* full coverage);
        * percent < full: the Avrami inverse ``-ln(1 - percent/100) / A``.
        Monotone in ``percent``.
        """
        if not percent > 0:
            raise ValueError("coverage must be positive")
        if percent >= 100.0:
            return percent / 100.0 * self.full_coverage_shots
        if percent >= self.full_percent:
            return self.full_coverage_shots
        return float(-np.log1p(-percent / 100.0) / self.rate)


def fit_avrami(counts, coverage, full_percent: float = FULL_COVERAGE_PERCENT) -> AvramiFit:
    """Fit eq. (5) to coverage data.

    counts : (m,) shot numbers. coverage : (m,) or (n_seq, m), %, pooled over
    sequences (NaN entries dropped). full_percent : %, what counts as full
    coverage (N_f). Returns AvramiFit; ValueError if no point has 0 < C.
    """
    n = np.asarray(counts, dtype=float)
    c = np.atleast_2d(np.asarray(coverage, dtype=float))
    if c.shape[-1] != n.size:
        raise ValueError(f"coverage must have last dimension {n.size}, got {c.shape}")
    nn = np.broadcast_to(n, c.shape).ravel()
    cc = c.ravel()
    keep = np.isfinite(cc) & (nn > 0)
    nn, cc = nn[keep], cc[keep]
    if not np.any(cc > 0):
        raise ValueError("no positive coverage value: the Avrami rate is undefined")
    # start from the linearised fit through the origin (points below 100 % only)
    lin = cc < 100.0
    y = -np.log1p(-np.clip(cc[lin], 0.0, 99.999) / 100.0)
    a0 = float(nn[lin] @ y / (nn[lin] @ nn[lin])) if np.any(lin & (cc > 0)) else 10.0 / nn.min()
    a0 = max(a0, 1e-12)
    res = least_squares(
        lambda t: 100.0 * -np.expm1(-np.exp(t[0]) * nn) - cc,
        [np.log(a0)],
        xtol=1e-14,
        ftol=1e-14,
        gtol=1e-14,
    )
    rate = float(np.exp(res.x[0]))
    r = 100.0 * -np.expm1(-rate * nn) - cc
    return AvramiFit(rate, float(np.sqrt(np.mean(r**2))), _ro(nn), _ro(cc), float(full_percent))


