"""Residual-stress depth profiles: averaging over a measuring region, integrals, equilibrium.

A *depth profile* is a stress component as a function of depth ``z`` below the
peened surface (``z = 0`` on the peened surface, growing into the target, as in
the paper). Two exact representations are supported, because the FE kernel
delivers element (layer) values while analytic profiles and released stresses
are naturally continuous:

* ``kind="layers"``: ``z`` holds the ``n + 1`` layer boundaries, ``values`` the
  ``n`` layer values; the stress is constant inside each layer (one-point
  hexahedra give one stress per element, i.e. per layer after averaging).
* ``kind="linear"``: ``z`` holds ``n`` nodes (non-decreasing; a repeated depth
  encodes a jump), ``values`` the ``n`` nodal values; the stress is linear
  between nodes.

Integrals (force and moment per unit width) are evaluated *exactly* for the
representation, so that equilibrium checks (paper eqs. 6-8) hold to round-off
instead of to a quadrature error.

Voigt order of the 6 stress components everywhere in peenflow:
``xx, yy, zz, yz, xz, xy``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._arrays import read_only as _frozen

VOIGT = ("xx", "yy", "zz", "yz", "xz", "xy")



@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class DepthProfile:
    """One stress component through the depth.

    Attributes
    ----------
    z : (n + 1,) for ``kind="layers"`` (layer boundaries) or (n,) for
        ``kind="linear"`` (nodes), m, depth below the peened surface,
        non-decreasing.
    values : (n,), Pa. Layer values or nodal values.
    kind : ``"layers"`` or ``"linear"``.
    """

    z: np.ndarray
    values: np.ndarray
    kind: str = "layers"

    def __post_init__(self):
        z = _frozen(self.z)
        v = _frozen(self.values)
        if self.kind not in ("layers", "linear"):
            raise ValueError(f"kind must be 'layers' or 'linear', got {self.kind!r}")
        if z.ndim != 1 or v.ndim != 1:
            raise ValueError("z and values must be 1-D arrays")
        expected = v.size + 1 if self.kind == "layers" else v.size
        if z.size != expected:
            raise ValueError(
                f"kind={self.kind!r} needs len(z) == {'len(values) + 1' if self.kind == 'layers' else 'len(values)'}; "
                f"got len(z)={z.size}, len(values)={v.size}"
            )
        if v.size < 1 or (self.kind == "linear" and v.size < 2):
            raise ValueError("profile needs at least one layer or two nodes")
        if not (np.all(np.isfinite(z)) and np.all(np.isfinite(v))):
            raise ValueError("profile contains non-finite depths or values")
        if np.any(np.diff(z) < 0):
            raise ValueError("depths z must be non-decreasing")
        object.__setattr__(self, "z", z)
        object.__setattr__(self, "values", v)

    @property
    def depth_range(self) -> tuple[float, float]:
        """(top, bottom) depths covered by the profile, m."""
        return float(self.z[0]), float(self.z[-1])

    def moments(self, origin: float = 0.0) -> tuple[float, float]:
        """Exact ``(∫ σ dz, ∫ σ (z - origin) dz)`` over the profile's depth range.

        Units: N/m (force per unit width) and N (moment per unit width).
        Outside the profile's depth range the stress is taken as zero.
        """
        z = self.z - origin
        v = self.values
        if self.kind == "layers":
            dz = np.diff(z)
            f0 = np.sum(v * dz)
            # ∫_{z_k}^{z_k+1} z dz = (z_k+1^2 - z_k^2)/2 exactly
            f1 = np.sum(v * 0.5 * (z[1:] ** 2 - z[:-1] ** 2))
        else:
            za, zb = z[:-1], z[1:]
            va, vb = v[:-1], v[1:]
            dz = zb - za
            f0 = np.sum(0.5 * dz * (va + vb))
            # exact integral of a linear function times z over [za, zb]
            f1 = np.sum(dz / 6.0 * (va * (2 * za + zb) + vb * (za + 2 * zb)))
        return float(f0), float(f1)

    def __call__(self, depth) -> np.ndarray:
        """Evaluate the profile at depths (any shape), Pa; NaN outside the range.

        For layers, a depth on a boundary takes the deeper layer's value.
        """
        d = np.asarray(depth, dtype=float)
        out = np.full(d.shape, np.nan)
        inside = (d >= self.z[0]) & (d <= self.z[-1])
        if self.kind == "layers":
            k = np.clip(np.searchsorted(self.z, d[inside], side="right") - 1, 0, self.values.size - 1)
            out[inside] = self.values[k]
        else:
            out[inside] = np.interp(d[inside], self.z, self.values)
        return out

    def point_values(self, depth) -> np.ndarray:
        """The point-wise stress recovered from layer means, Pa, at depths (any shape); NaN outside.

        A one-point hexahedron's stress is the mean of the field over its element, so after
        averaging over a region a layer value is the mean of σ(z) over the layer, not σ at its
        mid-depth: read by straight lines between mid-depths, a profile of curvature σ'' comes
        out h²σ''/8 off between the mid-depths, and its peak is blunted. Here the running
        integral F(z) = ∫ σ dz from the top, known exactly at every layer boundary (the sum of
        mean × thickness), is interpolated by the not-a-knot cubic spline through those values,
        and σ(z) = F'(z) (a C¹ piecewise quadratic: a histospline). Every layer keeps its mean
        exactly, a profile quadratic in z is recovered exactly, and for a smooth profile the
        error falls as h³ (tests/methods/test_residual_profile.py). It assumes σ smooth across
        layers (a jump rings over a layer or two either side). Three layers or more; with two
        the line, with one the constant that keeps the means. ``kind="linear"``: the profile.
        """
        if self.kind == "linear":
            return self(depth)
        from scipy.interpolate import CubicSpline

        d = np.asarray(depth, dtype=float)
        out = np.full(d.shape, np.nan)
        inside = (d >= self.z[0]) & (d <= self.z[-1])
        thick = np.diff(self.z) > 0  # a layer of zero thickness holds no integral
        if not np.any(thick):
            return out
        edges = np.concatenate([self.z[:1], self.z[1:][thick]])
        running = np.concatenate([[0.0], np.cumsum(self.values[thick] * np.diff(edges))])
        if edges.size == 2:
            out[inside] = self.values[thick][0]
            return out
        spline = CubicSpline(edges, running, bc_type="not-a-knot")
        out[inside] = spline(d[inside], 1)
        return out

    def to_linear(self) -> "DepthProfile":
        """The same function as a ``kind="linear"`` profile (jumps as repeated nodes)."""
        if self.kind == "linear":
            return self
        z = np.repeat(self.z, 2)[1:-1]
        v = np.repeat(self.values, 2)
        return DepthProfile(z, v, "linear")

    def minus_linear(self, c0: float, c1: float, origin: float = 0.0) -> "DepthProfile":
        """Exact profile ``σ(z) - (c0 + c1 (z - origin))`` (kind ``linear``)."""
        lin = self.to_linear()
        return DepthProfile(lin.z, lin.values - (c0 + c1 * (lin.z - origin)), "linear")


@dataclass(frozen=True, eq=False)  # holds arrays: identity, not element-wise, equality
class LayerAverage:
    """Stress averaged over a measuring region, per depth layer.

    Attributes
    ----------
    z_edges : (nz + 1,) m, layer boundaries (depth below the peened surface).
    mean : (nz, 6) Pa, region average per layer, Voigt order ``xx yy zz yz xz xy``.
    std : (nz, 6) Pa, (weighted) standard deviation over the region per layer:
        the lateral spread of the field, not an error of the mean.
    count : (nz,) int, number of elements averaged per layer.
    """

    z_edges: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    count: np.ndarray

    def component(self, name: str = "xx") -> DepthProfile:
        """The averaged profile of one component (``"xx"``, ...), ``kind="layers"``."""
        return DepthProfile(self.z_edges, self.mean[:, VOIGT.index(name)], "layers")


def average_over_region(
    centroids,
    stress,
    z_edges,
    region: tuple[float, float, float, float],
    weights=None,
) -> LayerAverage:
    """Average an element stress field over a lateral measuring region, per depth layer.

    Parameters
    ----------
    centroids : (n, 3) m, element centroids (x, y, z), undeformed, z = depth.
    stress : (n, 6) Pa, element stress, Voigt order ``xx yy zz yz xz xy``.
    z_edges : (nz + 1,) m, increasing layer boundaries of the structured mesh.
    region : (x_min, x_max, y_min, y_max) m; an element belongs to the region
        when its centroid lies inside (boundaries included). On a structured
        mesh whose element faces line up with the region boundary this is the
        exact region.
    weights : (n,) optional element weights (e.g. volumes or areas). Default:
        equal weights, which is the area average on a laterally uniform mesh.

    Returns
    -------
    LayerAverage with the per-layer mean, spread and count. Raises ValueError
    if a layer has no element inside the region.
    """
    c = np.asarray(centroids, dtype=float)
    s = np.asarray(stress, dtype=float)
    edges = np.asarray(z_edges, dtype=float)
    if c.ndim != 2 or c.shape[1] != 3:
        raise ValueError(f"centroids must have shape (n, 3), got {c.shape}")
    if s.shape != (c.shape[0], 6):
        raise ValueError(f"stress must have shape ({c.shape[0]}, 6), got {s.shape}")
    if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0):
        raise ValueError("z_edges must be a strictly increasing 1-D array of length >= 2")
    w = np.ones(c.shape[0]) if weights is None else np.asarray(weights, dtype=float)
    if w.shape != (c.shape[0],) or np.any(w < 0):
        raise ValueError("weights must be a non-negative (n,) array")
    x0, x1, y0, y1 = region
    inside = (c[:, 0] >= x0) & (c[:, 0] <= x1) & (c[:, 1] >= y0) & (c[:, 1] <= y1)
    nz = edges.size - 1
    layer = np.searchsorted(edges, c[:, 2], side="right") - 1
    ok = inside & (layer >= 0) & (layer < nz)
    layer, sw, ww = layer[ok], s[ok], w[ok]
    wsum = np.bincount(layer, weights=ww, minlength=nz)
    count = np.bincount(layer, minlength=nz)
    empty = np.flatnonzero(wsum <= 0)
    if empty.size:
        raise ValueError(
            f"no element of layers {empty.tolist()} lies inside the region {region}; "
            "check the region and the layer boundaries"
        )
    mean = np.empty((nz, 6))
    std = np.empty((nz, 6))
    for j in range(6):
        m = np.bincount(layer, weights=ww * sw[:, j], minlength=nz) / wsum
        var = np.bincount(layer, weights=ww * (sw[:, j] - m[layer]) ** 2, minlength=nz) / wsum
        mean[:, j] = m
        std[:, j] = np.sqrt(var)
    return LayerAverage(_frozen(edges), _frozen(mean), _frozen(std), _frozen(count, int))


@dataclass(frozen=True)
class EquilibriumResidual:
    """Net force and moment of a through-thickness profile.

    force_per_width : N/m, ∫ σ dz over [0, h].
    moment_per_width : N, ∫ σ (z - h/2) dz, about the mid-plane.
    relative_force : |∫ σ dz| / ∫ |σ| dz (0 for perfect self-equilibrium).
    relative_moment : |∫ σ (z - h/2) dz| / ∫ |σ| |z - h/2| dz.
    """

    force_per_width: float
    moment_per_width: float
    relative_force: float
    relative_moment: float

    def is_self_equilibrated(self, rtol: float = 1e-6) -> bool:
        return self.relative_force <= rtol and self.relative_moment <= rtol


def equilibrium_residual(profile: DepthProfile, thickness: float) -> EquilibriumResidual:
    """Net force and moment (about the mid-plane) of a profile over thickness ``h`` (m).

    A released (free) strip or plate must carry a self-equilibrated stress: zero
    net force and zero net moment (paper eq. 8 is built to achieve this).
    The relative measures are normalised by the integrals of ``|σ|`` so that a
    tolerance can be stated independently of the stress level.
    """
    _check_within(profile, thickness)
    mid = 0.5 * thickness
    f, m = profile.moments(origin=mid)
    lin = profile.to_linear()
    # |σ| of a piecewise-linear function is not piecewise linear; a fine
    # resampling is enough for a normalisation constant.
    zz = np.linspace(lin.z[0], lin.z[-1], 4001)
    a = np.abs(lin(zz))
    fa = np.trapezoid(a, zz)
    ma = np.trapezoid(a * np.abs(zz - mid), zz)
    rf = abs(f) / fa if fa > 0 else 0.0
    rm = abs(m) / ma if ma > 0 else 0.0
    return EquilibriumResidual(f, m, float(rf), float(rm))


def _check_within(profile: DepthProfile, thickness: float, rtol: float = 1e-9) -> None:
    if not thickness > 0:
        raise ValueError(f"thickness must be positive, got {thickness}")
    top, bottom = profile.depth_range
    tol = rtol * thickness
    if top < -tol or bottom > thickness + tol:
        raise ValueError(
            f"profile depths [{top}, {bottom}] m lie outside the thickness [0, {thickness}] m"
        )
