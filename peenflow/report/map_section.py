"""The report's "Process map" section: the map's figures, its features per point, and the suggestion.

Tables are in the units a person reads (MPa, mm, shop notation, m/s) with the
digits the numbers carry: stresses to 1 MPa, depths to 1 um, N_c to one shot.
Each point's stated numerical error is its own: measured for its material,
shot and fidelity, or said to be unmeasured with the measured case named.
"""

from __future__ import annotations

import base64
import html
import itertools
from pathlib import Path

import numpy as np

from peenflow.units import MM, MPA

from .headline import point_name

#: the map's figures (:mod:`peenflow.report.map_plots`), shown in this section
FIGURES = ("map_profiles.png", "map_features.png")


def _e(x) -> str:
    return html.escape(str(x))


def _pm(mean: float, spread: float, scale: float, digits: int) -> str:
    m = f"{mean / scale:.{digits}f}"
    return m if not np.isfinite(spread) or spread == 0 else f"{m} ± {spread / scale:.{digits}f}"


def _error(p) -> str:
    if not int(p.error_measured):
        return "unmeasured"
    return (f"peak {float(p.peak_error_percent):.1f} %, depth {float(p.compressive_depth_error_percent):.1f} %, "
            f"profile {float(p.profile_error_percent):.1f} %")


def feature_rows(pmap) -> list[list[str]]:
    """One row per map point and coverage level: the point, sigma_xx at the surface and its peak (with the
    spread over sequences), the peak's depth, the compressive depth, N_c, the velocity, the stated error."""
    dims = [d for d in pmap.attrs.get("process_dims", "").split() if d] + ["coverage_percent"]
    rows = []
    for combo in itertools.product(*[range(pmap.sizes[d]) for d in dims]):
        sel = dict(zip(dims, combo))
        p = pmap.isel(sel)
        spread = float(p.stress_xx_spread_Pa.values[0])
        rows.append([
            _e(point_name(pmap, sel)),
            _e(_pm(float(p.surface_stress_xx_Pa), spread, MPA, 0)),
            _e(_pm(float(p.peak_compressive_xx_Pa), float(p.peak_compressive_xx_spread_Pa), MPA, 0)),
            _e(f"{float(p.peak_compressive_xx_depth_m) / MM:.3f}"),
            _e(f"{float(p.compressive_depth_xx_m) / MM:.3f}"),
            _e(f"{float(p.surface_stress_yy_Pa) / MPA:.0f}"),
            _e(f"{float(p.coverage_shots):.0f}"),
            _e(f"{float(p.velocity_m_s):.1f}"),
            _e(_error(p)),
        ])
    return rows


FEATURE_HEADER = ["point", "surface σxx (MPa)", "peak σxx (MPa)", "peak depth (mm)", "compressive depth (mm)",
                  "surface σyy (MPa)", "N_c (shots)", "velocity (m/s)", "stated error"]


def requirement_rows(suggestion) -> list[list[str]]:
    """Per requirement: the feature, its value at the suggestion (or the closest point), and its margin."""
    names = suggestion.requirement.attrs.get("flag_meanings", "").split()
    units = suggestion.attrs.get("requirement_units", "").split()
    rows = []
    for k, name in enumerate(names):
        value = float(suggestion.requirement_value.values[k])
        unit = units[k] if k < len(units) else "1"
        shown = {"Pa": f"{value / MPA:.0f} MPa", "m": f"{value / MM:.3f} mm"}.get(unit, f"{value:.4g}")
        margin = float(suggestion.requirement_margin.values[k])
        rows.append([_e(name), _e(shown), _e(f"{margin:+.1%}" + ("" if margin >= 0 else " (missed)"))])
    return rows


def verification_rows(suggestion, verification) -> list[list[str]]:
    """Per requirement: predicted by the map at the suggestion, computed there, their difference, the margin."""
    names = verification.requirement.attrs.get("flag_meanings", "").split()
    units = verification.attrs.get("requirement_units", "").split()
    rows = []
    for k, name in enumerate(names):
        unit = units[k] if k < len(units) else "1"
        scale, shown = {"Pa": (MPA, "MPa"), "m": (MM, "mm")}.get(unit, (1.0, ""))
        p, c = float(verification.predicted_value.values[k]), float(verification.computed_value.values[k])
        m = float(verification.computed_margin.values[k])
        rows.append([_e(name), _e(f"{p / scale:.4g} {shown}"), _e(f"{c / scale:.4g} {shown}"),
                     _e(f"{(c - p) / abs(p):+.1%}"), _e(f"{m:+.1%}" + ("" if m >= 0 else " (missed)"))])
    return rows


def map_section(pmap, suggestion, images: list[Path], table, verification=None) -> list[str]:
    """HTML parts of the section (nothing without a map): ``table(header, rows, num_cols)`` draws a table."""
    if pmap is None:
        return []
    dims = [d for d in pmap.attrs.get("process_dims", "").split() if d]
    parts = ["<h2 id=\"process-map\">Process map</h2>",
             f"<p>{len(dims) and ', '.join(_e(d) for d in dims) or 'one point'} × coverage "
             f"{', '.join(f'{c:g}' for c in pmap.coverage_percent.values)} %; mean over sequences ± their spread. "
             f"Stated errors: {_e(pmap.attrs.get('error_basis', ''))}.</p>"]
    for img in images:
        if Path(img).name in FIGURES:
            data = base64.b64encode(Path(img).read_bytes()).decode("ascii")
            parts.append(f"<figure><img alt=\"{_e(Path(img).stem)}\" src=\"data:image/png;base64,{data}\">"
                         f"<figcaption>{_e(Path(img).name)}</figcaption></figure>")
    parts.append(table(FEATURE_HEADER, feature_rows(pmap), num_cols=tuple(range(1, 8))))
    if suggestion is not None:
        parts.append(f"<h3>Suggested settings</h3><p>{_e(suggestion.attrs.get('verdict', ''))}</p>")
        parts.append(table(["requirement", "value there", "margin to its bound"], requirement_rows(suggestion),
                           num_cols=(1, 2)))
    if verification is not None and int(verification.verified):
        parts.append(f"<h3>The suggestion computed</h3><p>{_e(verification.attrs.get('verdict', ''))}</p>")
        parts.append(table(["requirement", "predicted by the map", "computed", "difference", "computed margin"],
                           verification_rows(suggestion, verification), num_cols=(1, 2, 3, 4)))
    return parts
