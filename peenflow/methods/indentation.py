"""The dent ellipse of a single impact (paper §3.2.2, Figs. 8-10).

The indentation area used for coverage is delimited by an ellipse (a circle
for a normal impact) passing through the highest points of the pile-up around
the impact. Input is the deformed top surface of a single-impact run on a
structured grid; z points into the target, so the dent has ``uz > 0`` and the
pile-up ``uz < 0``.

Method, and why:

1. A bicubic spline of ``uz`` (``RectBivariateSpline``) gives a smooth surface
   so that crests are located *between* grid nodes; with ``noise > 0`` it
   becomes a smoothing spline, which keeps mesh noise from creating false
   crests (``s = n_nodes * noise^2``, the expected residual sum of squares).
2. Rays are cast from the bottom of the dent (the deepest point, refined on the
   spline), every ``360 / n_rays`` degrees. Along each ray the crest is the
   lowest ``uz`` (highest pile-up), refined by a parabola through the three
   samples around it. Rays along +x and -x are independent, so the fore/aft
   asymmetry of an oblique impact moves the fitted centre away from the impact
   point instead of being averaged out.
3. An axis-aligned ellipse (axes along and across the impingement direction,
   x and y) is least-squares fitted to the crest points (algebraic form
   ``α x² + β y² + γ x + δ y = 1``), once more after discarding points whose
   normalised radius deviates by more than 3 robust standard deviations.

Rays whose lowest point lies on the grid boundary (crest not inside the grid)
or that have no pile-up (``min uz >= 0``) are discarded. ``rim="edge"``
instead uses the first zero crossing of ``uz`` (the dent edge), for materials
that sink in and show no pile-up.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import RectBivariateSpline, RegularGridInterpolator
from scipy.optimize import minimize

from ._arrays import read_only as _ro


@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class DentEllipse:
    """The indentation area of one impact.

    centre_x, centre_y : m, ellipse centre (input frame).
    impact_x, impact_y : m, the impact (landing) point of the single-impact run.
    semi_axis_along : m, along the impingement direction projected on the surface (x).
    semi_axis_across : m, across it (y).
    depth : m, maximum dent depth (uz > 0).
    pileup_height : m, highest pile-up on the crest (-uz), 0 for ``rim="edge"`` without pile-up.
    crest_x, crest_y : (k,) m, the rim points the ellipse was fitted to.
    fit_rms : m, rms distance of those points from the ellipse (normalised radius × mean axis).
    """

    centre_x: float
    centre_y: float
    impact_x: float
    impact_y: float
    semi_axis_along: float
    semi_axis_across: float
    depth: float
    pileup_height: float
    crest_x: np.ndarray = field(repr=False, default=None)
    crest_y: np.ndarray = field(repr=False, default=None)
    fit_rms: float = 0.0

    @property
    def offset(self) -> tuple[float, float]:
        """(dx, dy) m: ellipse centre minus impact point; apply to any landing point."""
        return self.centre_x - self.impact_x, self.centre_y - self.impact_y

    @property
    def area(self) -> float:
        """π a b, m²."""
        return float(np.pi * self.semi_axis_along * self.semi_axis_across)



def dent_ellipse(
    x,
    y,
    uz,
    impact_point: tuple[float, float] = (0.0, 0.0),
    *,
    noise: float = 0.0,
    n_rays: int = 180,
    max_radius: float | None = None,
    rim: str = "crest",
    min_pileup_fraction: float = 0.01,
) -> DentEllipse:
    """Fit the dent ellipse of a single impact.

    Parameters
    ----------
    x : (nx,) m, y : (ny,) m, strictly increasing node coordinates.
    uz : (nx, ny) m, displacement into the target (dent > 0, pile-up < 0).
    impact_point : (x, y) m, where the shot landed (reference for ``offset``).
    noise : m, standard deviation of mesh noise on uz; > 0 turns on spline smoothing.
    n_rays : number of rays (even, so that ±x and ±y are sampled).
    max_radius : m, ignore the surface farther than this from the dent bottom.
    rim : "crest" (paper: highest pile-up) or "edge" (first uz = 0 crossing).
    min_pileup_fraction : a crest counts only if its height exceeds this fraction
        of the dent depth, so that spline ringing at a pile-up-free dent edge
        (a fraction of a percent of the depth) is not taken for a crest; real
        pile-ups are typically 10-30 % of the depth.

    Returns a DentEllipse. Raises ValueError if fewer than 5 rays find a rim.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    uz = np.asarray(uz, dtype=float)
    if x.ndim != 1 or y.ndim != 1 or uz.shape != (x.size, y.size):
        raise ValueError(f"need x (nx,), y (ny,), uz (nx, ny); got {x.shape}, {y.shape}, {uz.shape}")
    if x.size < 5 or y.size < 5 or np.any(np.diff(x) <= 0) or np.any(np.diff(y) <= 0):
        raise ValueError("x and y must be strictly increasing with at least 5 nodes")
    if rim not in ("crest", "edge"):
        raise ValueError("rim must be 'crest' or 'edge'")
    if not np.max(uz) > 0:
        raise ValueError("no dent: uz has no positive value (z points into the target)")
    spline = RectBivariateSpline(x, y, uz, kx=3, ky=3, s=uz.size * noise**2)
    h = min(np.min(np.diff(x)), np.min(np.diff(y)))

    # 1. dent bottom, refined on the spline within one cell of the deepest node
    i, j = np.unravel_index(np.argmax(uz), uz.shape)
    x0, y0 = x[i], y[j]
    res = minimize(
        lambda p: -float(spline.ev(p[0], p[1])), [x0, y0], method="L-BFGS-B",
        bounds=[(max(x[0], x0 - h), min(x[-1], x0 + h)), (max(y[0], y0 - h), min(y[-1], y0 + h))],
    )
    ox, oy = res.x
    depth = float(spline.ev(ox, oy))

    # 2. rays: common samples in t, masked where outside the grid (or max_radius)
    phi = np.arange(n_rays) * (2 * np.pi / n_rays)
    c, s = np.cos(phi), np.sin(phi)
    with np.errstate(divide="ignore"):
        tx = np.where(c > 0, (x[-1] - ox) / c, np.where(c < 0, (x[0] - ox) / c, np.inf))
        ty = np.where(s > 0, (y[-1] - oy) / s, np.where(s < 0, (y[0] - oy) / s, np.inf))
    tmax = np.minimum(tx, ty)
    if max_radius is not None:
        tmax = np.minimum(tmax, max_radius)
    ds = h / 4.0
    t = np.arange(0.0, float(tmax.max()) + ds, ds)
    X = ox + np.outer(c, t)
    Y = oy + np.outer(s, t)
    valid = t[None, :] <= tmax[:, None]
    U = np.where(valid, spline.ev(np.clip(X, x[0], x[-1]), np.clip(Y, y[0], y[-1])), np.inf)

    rows = np.arange(n_rays)
    if rim == "crest":
        k = np.argmin(U, axis=1)
        last = valid.sum(axis=1) - 1
        ok = (U[rows, k] < -min_pileup_fraction * depth) & (k > 0) & (k < last)
        k = np.clip(k, 1, U.shape[1] - 2)
        um, u0, up = U[rows, k - 1], U[rows, k], U[rows, k + 1]
        with np.errstate(invalid="ignore", divide="ignore"):
            curv = um - 2 * u0 + up
            shift = np.clip(np.where(ok & (curv > 0), 0.5 * (um - up) / curv, 0.0), -1, 1)
            height = -(u0 - 0.25 * (um - up) * shift)  # parabola vertex value
        tc = t[k] + shift * ds
        # The crest must also be in the data, not only in the spline: a bicubic
        # spline rings (overshoots below 0) next to the kink of a pile-up-free dent edge.
        lin = RegularGridInterpolator((x, y), uz, method="linear")
        px_, py_ = np.clip(ox + c * tc, x[0], x[-1]), np.clip(oy + s * tc, y[0], y[-1])
        ok &= lin(np.column_stack([px_, py_])) < 0
    else:
        neg = (U < 0) & valid
        ok = neg.any(axis=1)
        k = np.argmax(neg, axis=1)
        ok &= k > 0
        k = np.clip(k, 1, None)
        ua, ub = U[rows, k - 1], U[rows, k]
        with np.errstate(invalid="ignore", divide="ignore"):
            frac = np.where(ok, ua / (ua - ub), 0.0)
        tc = t[k - 1] + frac * ds
        height = np.zeros(n_rays)
    if ok.sum() < 5:
        raise ValueError(
            f"only {int(ok.sum())} of {n_rays} rays found a {'pile-up crest' if rim == 'crest' else 'dent edge'} "
            "inside the grid; enlarge the grid, or use rim='edge' if the surface shows no pile-up"
        )
    px, py = ox + c[ok] * tc[ok], oy + s[ok] * tc[ok]
    height = height[ok]

    # 3. ellipse fit, with one robust pass
    cx, cy, a, b = _fit_axis_ellipse(px, py, ox, oy)
    rho = np.hypot((px - cx) / a, (py - cy) / b) - 1.0
    mad = 1.4826 * np.median(np.abs(rho - np.median(rho)))
    keep = np.abs(rho) <= max(3 * mad, 1e-12)
    if 5 <= keep.sum() < keep.size:
        px, py, height = px[keep], py[keep], height[keep]
        cx, cy, a, b = _fit_axis_ellipse(px, py, ox, oy)
        rho = np.hypot((px - cx) / a, (py - cy) / b) - 1.0
    return DentEllipse(
        centre_x=float(cx),
        centre_y=float(cy),
        impact_x=float(impact_point[0]),
        impact_y=float(impact_point[1]),
        semi_axis_along=float(a),
        semi_axis_across=float(b),
        depth=depth,
        pileup_height=float(max(np.max(height), 0.0)),
        crest_x=_ro(px),
        crest_y=_ro(py),
        fit_rms=float(np.sqrt(np.mean(rho**2)) * 0.5 * (a + b)),
    )


def _fit_axis_ellipse(px, py, ox, oy):
    """Least-squares axis-aligned ellipse through points; returns (cx, cy, a, b)."""
    L = max(float(np.max(np.hypot(px - ox, py - oy))), 1e-300)  # scale for conditioning
    u, v = (px - ox) / L, (py - oy) / L
    M = np.column_stack([u * u, v * v, u, v])
    (al, be, ga, de), *_ = np.linalg.lstsq(M, np.ones_like(u), rcond=None)
    if not (al > 0 and be > 0):
        raise ValueError("rim points do not outline an ellipse (degenerate fit)")
    cu, cv = -ga / (2 * al), -de / (2 * be)
    F = 1.0 + ga * ga / (4 * al) + de * de / (4 * be)
    return ox + cu * L, oy + cv * L, np.sqrt(F / al) * L, np.sqrt(F / be) * L
