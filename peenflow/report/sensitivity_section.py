"""The report's "Sensitivity" section: what the answer depends on, from a ``[sensitivity]`` study.

* ``sensitivity_tornado.png``  one panel per feature (the velocity for the part's intensity, the peak
  compressive stress, the compressive depth, the surface stress, N_f): per input a bar from its smallest to its
  largest change in % of the baseline, the inputs sorted by the bar's length, each value marked
* a table: per changed input, every feature's change in the units people read
"""

from __future__ import annotations

import base64
import html
from pathlib import Path

import numpy as np

from peenflow.units import MM, MPA

FIGURE = "sensitivity_tornado.png"

#: (result feature, panel title)
PANELS = (("velocity", "velocity for the part's intensity"), ("peak_compressive_stress", "peak compressive σxx"),
          ("compressive_depth", "compressive depth"), ("surface_stress", "surface σxx"),
          ("full_coverage_shots", "N_f"))


def _e(x) -> str:
    return html.escape(str(x))


def _first(da):
    """The first point of every dimension but ``change`` (other map dimensions, the first coverage level)."""
    return da.isel({d: 0 for d in da.dims if d != "change"})


def _by_input(result) -> dict[str, list[tuple[str, int]]]:
    """{input key: [(value as given, index along change)]} in the result's order."""
    out: dict[str, list] = {}
    for k, label in enumerate(result.change.attrs["flag_meanings"].split()):
        key, _, value = label.rpartition("@")
        out.setdefault(key, []).append((value, k))
    return out


def write_sensitivity_plot(result, save, plt) -> list:
    """The tornado figure (module docstring), saved with ``save(fig, name)``; [] without a result."""
    if result is None:
        return []
    inputs = _by_input(result)
    fig, axes = plt.subplots(2, 3, figsize=(15, 2 * (0.45 * len(inputs) + 1.6)))
    axes = axes.ravel()
    axes[-1].axis("off")
    for ax, (feature, title) in zip(axes, PANELS):
        pct = _first(result[f"{feature}_change_percent"]).values
        rows = sorted(inputs.items(), key=lambda kv: -np.nanmax(np.abs([pct[k] for _, k in kv[1]] + [0.0])))
        for y, (key, values) in enumerate(reversed(rows)):
            changes = [pct[k] for _, k in values]
            lo, hi = min(0.0, np.nanmin(changes)), max(0.0, np.nanmax(changes))
            ax.barh(y, hi - lo, left=lo, height=0.6, color="0.75")
            for (value, k) in values:
                ax.plot(pct[k], y, "k|", ms=10)
                ax.annotate(value, (pct[k], y), xytext=(0, 7), textcoords="offset points", ha="center", fontsize=7)
        ax.axvline(0, color="k", lw=0.8)
        ax.set_yticks(range(len(rows)))
        ax.set_yticklabels([key.replace("johnson_cook.", "JC ") for key, _ in reversed(rows)], fontsize=7)
        ax.set(xlabel="change from the baseline (%)", title=title)
    save(fig, FIGURE)
    return [FIGURE]


def _cell(result, feature: str, k: int, scale: float, digits: int) -> str:
    d = float(_first(result[f"{feature}_change"]).values[k])
    p = float(_first(result[f"{feature}_change_percent"]).values[k])
    if not np.isfinite(d):
        return "-"
    return f"{d / scale:+.{digits}f} ({p:+.1f} %)"


def sensitivity_section(result, images: list[Path], table) -> list[str]:
    """HTML parts of the section (nothing without a result): ``table(header, rows, num_cols)`` draws a table."""
    if result is None:
        return []
    base = {f: float(_first(result[f"{f}_baseline"])) for f, _ in PANELS}
    parts = ["<h2 id=\"sensitivity\">Sensitivity</h2>",
             "<p>Each row changes one input of the study as written and keeps everything else; the change of "
             f"each feature against the baseline (velocity {base['velocity']:.1f} m/s, peak σxx "
             f"{base['peak_compressive_stress'] / MPA:.0f} MPa, compressive depth "
             f"{base['compressive_depth'] / MM:.3f} mm, N_f {base['full_coverage_shots']:.0f}), at the first "
             "coverage level. The baseline's sequence spread of the peak stress, "
             f"{float(_first(result.peak_sequence_spread)) / MPA:.0f} MPa, is the noise floor of a stress change.</p>"]
    for img in images:
        if Path(img).name == FIGURE:
            data = base64.b64encode(Path(img).read_bytes()).decode("ascii")
            parts.append(f"<figure><img alt=\"sensitivity tornado\" src=\"data:image/png;base64,{data}\">"
                         f"<figcaption>{FIGURE}</figcaption></figure>")
    rows = []
    for k, label in enumerate(result.change.attrs["flag_meanings"].split()):
        rows.append([_e(label), _e(_cell(result, "velocity", k, 1.0, 2)),
                     _e(_cell(result, "surface_stress", k, MPA, 0)),
                     _e(_cell(result, "peak_compressive_stress", k, MPA, 0)),
                     _e(_cell(result, "peak_depth", k, MM, 3)),
                     _e(_cell(result, "compressive_depth", k, MM, 3)),
                     _e(_cell(result, "full_coverage_shots", k, 1.0, 0))])
    parts.append(table(["input changed to", "velocity (m/s)", "surface σxx (MPa)", "peak σxx (MPa)",
                        "peak depth (mm)", "compressive depth (mm)", "N_f (shots)"], rows,
                       num_cols=tuple(range(1, 7))))
    return parts
