"""The process map's figures: profile families along each dimension, and a feature map over two.

* ``map_profiles.png``  mean sigma_xx(z) of every map point, one panel per coverage level, a line per
  combination of the other dimensions (shaded: the spread over sequences)
* ``map_features.png``  the compressive depth and the surface stress over the first two dimensions of
  the map (the coverage level among them), with the suggested setting marked when there is one
"""

from __future__ import annotations

import itertools

import numpy as np

from peenflow.units import MM, MPA

from .headline import point_name


def write_map_plots(pmap, suggestion, out_dir, save, plt) -> list:
    """The two figures (module docstring), saved with ``save(fig, name)``; [] without a map."""
    if pmap is None:
        return []
    before = []
    dims = [d for d in pmap.attrs.get("process_dims", "").split() if d]
    z = pmap.depth_m.values / MM
    levels = pmap.coverage_percent.values
    fig, axes = plt.subplots(1, len(levels), figsize=(5.5 * len(levels), 4.4), squeeze=False, sharey=True)
    for k, (ax, level) in enumerate(zip(axes[0], levels)):
        for combo in itertools.product(*[range(pmap.sizes[d]) for d in dims]):
            sel = dict(zip(dims, combo))
            p = pmap.isel(sel).isel(coverage_percent=k)
            m, s = p.stress_xx_mean_Pa.values / MPA, p.stress_xx_spread_Pa.values / MPA
            line = ax.plot(z, m, "-", label=point_name(pmap, sel) or "the part")[0]
            ax.fill_between(z, m - s, m + s, color=line.get_color(), alpha=0.15)
        ax.axhline(0, color="k", lw=0.5)
        ax.set(xlabel="depth (mm)", title=f"{level:g} % coverage")
    axes[0][0].set_ylabel("mean residual sigma_xx (MPa)")
    axes[0][-1].legend(fontsize=7, loc="lower right")
    save(fig, "map_profiles.png")

    # a feature map over two axes: the first process dimension and the coverage level
    x_dim = dims[0] if dims else None
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4))
    for ax, (name, scale, unit, label) in zip(axes, (("compressive_depth_xx_m", MM, "mm", "compressive depth"),
                                                     ("surface_stress_xx_Pa", MPA, "MPa", "surface sigma_xx"))):
        v = pmap[name]
        rest = [d for d in dims[1:]]
        v = v.isel({d: 0 for d in rest}) if rest else v
        xs = np.arange(pmap.sizes[x_dim]) if x_dim else np.array([0])
        grid = (v.transpose(x_dim, "coverage_percent").values if x_dim else v.values[None, :]) / scale
        im = ax.imshow(grid.T, origin="lower", aspect="auto", cmap="viridis")
        for i in range(grid.shape[0]):
            for j in range(grid.shape[1]):
                ax.text(i, j, f"{grid[i, j]:.3g}", ha="center", va="center", fontsize=8, color="w")
        ax.set_xticks(xs, [point_name(pmap, {x_dim: i}) for i in xs] if x_dim else [""], fontsize=7)
        ax.set_yticks(range(len(levels)), [f"{c:g} %" for c in levels])
        ax.set(ylabel="coverage", title=f"{label} ({unit})" + (f"; other dims at their first value" if rest else ""))
        fig.colorbar(im, ax=ax)
    if suggestion is not None and int(suggestion.met):
        fig.suptitle("suggested: " + suggestion.attrs.get("verdict", ""), fontsize=8)
    save(fig, "map_features.png")
    return before
