"""Stage ``suggested_settings``: the settings that meet every requirement with the least peening.

Reads the process map.  For every combination of the map's other dimensions,
along the dimension to minimise (``[requirements] minimise``: a numeric
process dimension, ``coverage_percent``, or ``shots`` -- N_c, which grows with
coverage) each feature is interpolated by a monotone cubic (PCHIP) through its
map values, and the smallest setting at which every requirement holds is
found on a fine grid between the map's points (never beyond them).  The
suggestion is the least such setting over the other combinations.

Its uncertainty: each feature's band, the spread over sequences plus the
stated numerical error where measured (a feature's error in % of itself; the
profile's RMS error in % of its peak for the surface stress), moves the
setting at which the requirement holds; the setting is reported with the band
(``*_low``: the requirements met by the optimistic edge of every band,
``*_high``: by the pessimistic one; NaN where even that edge never meets them
within the map).

When no map point or setting between them meets every requirement, the
result says so (``met = 0``) and names the map point that comes closest: the
one with the smallest worst violation relative to its bound, and by how much
each requirement misses there.
"""

from __future__ import annotations

import itertools

import numpy as np
import xarray as xr
from scipy.interpolate import PchipInterpolator

from ._common import peening_task
from .outputs import Output, Outputs
from .params import RequirementParams

OUTPUTS = Outputs(
    "suggested_settings",
    met=Output((), "1", "1 if a setting within the map meets every requirement",
               attrs={"flag_values": np.array([0, 1]), "flag_meanings": "not_met met"}),
    minimised_value=Output((), "1", "the least value of the minimised setting that meets every requirement "
                                    "(units: attribute minimised_units; NaN when none does)"),
    minimised_low=Output((), "1", "that least value with every feature at the optimistic edge of its band"),
    minimised_high=Output((), "1", "that least value with every feature at the pessimistic edge of its band"),
    requirement_margin=Output(("requirement",), "1", "at the suggestion (or the closest point): how far each "
                                                     "requirement is met, relative to its bound (< 0: missed)"),
    requirement_value=Output(("requirement",), "1", "the feature's value there, SI (units: attribute "
                                                    "requirement_units)"),
)

#: points of the fine grid between two map points along the minimised dimension
FINE = 64


def _margin(value: float, lo, hi) -> float:
    """How far ``value`` is inside [lo, hi], relative to the bound it is nearest to missing (< 0 outside)."""
    out = np.inf
    if lo is not None:
        out = min(out, (value - lo) / max(abs(lo), 1e-30))
    if hi is not None:
        out = min(out, (hi - value) / max(abs(hi), 1e-30))
    return float(out)


def _band(pmap: xr.Dataset, variable: str) -> xr.DataArray:
    """A feature's uncertainty: the spread over sequences where the map has it, plus its stated error."""
    v = pmap[variable]
    band = xr.zeros_like(v)
    comp = "xx" if "_xx" in variable else "yy"
    if variable.startswith("peak_compressive") and variable.endswith("_Pa"):
        band = band + pmap[f"peak_compressive_{comp}_spread_Pa"]
        band = band + abs(v) * pmap.peak_error_percent.fillna(0.0) / 100.0
    elif variable.startswith("compressive_depth"):
        band = band + abs(v) * pmap.compressive_depth_error_percent.fillna(0.0) / 100.0
    elif variable.startswith("surface_stress"):
        peak = abs(pmap[f"peak_compressive_{comp}_Pa"])
        band = band + peak * pmap.profile_error_percent.fillna(0.0) / 100.0
    return band


@peening_task(version="1")
def suggested_settings(process_map: xr.Dataset, *, requirements: RequirementParams) -> xr.Dataset:
    """The suggestion (module docstring) from the ``process_map`` result, for ``requirements`` (SI)."""
    r = requirements
    dims = [d for d in process_map.attrs.get("process_dims", "").split() if d] + ["coverage_percent"]
    pmap = process_map
    if r.minimise == "shots":
        axis, setting = "coverage_percent", pmap.coverage_shots.broadcast_like(pmap.velocity_m_s)
    else:
        axis, setting = r.minimise, pmap[r.minimise]
    setting = setting.broadcast_like(pmap[r.bounds[0][0]])
    features = [(pmap[var_], _band(pmap, var_), lo, hi, key) for var_, _, lo, hi, key in r.bounds]
    others = [d for d in dims if d != axis]
    best = None  # (value, low, high, point selection, at-axis-value)
    for combo in itertools.product(*[range(pmap.sizes[d]) for d in others]):
        sel = dict(zip(others, combo))
        xs = np.asarray(pmap[axis].values, dtype=float)
        order = np.argsort(xs)
        s = np.asarray(setting.isel(sel).transpose(axis).values, dtype=float)[order]
        vals = [(np.asarray(v.isel(sel).transpose(axis).values, dtype=float)[order],
                 np.asarray(b.isel(sel).transpose(axis).values, dtype=float)[order], lo, hi) for v, b, lo, hi, _ in features]
        found = []
        for edge in (0.0, +1.0, -1.0):  # the values, their optimistic edge, their pessimistic edge
            found.append(_least(xs[order], s, vals, edge))
        if np.isfinite(found[0][0]) and (best is None or found[0][0] < best[0]):
            best = (found[0][0], found[1][0], found[2][0], sel, found[0][1])
    if best is not None:
        value, low, high, sel, at = best
        point = pmap.isel(sel).interp({axis: at}) if pmap.sizes[axis] > 1 else pmap.isel(sel).isel({axis: 0})
        margins = [_margin(float(point[v]), lo, hi) for v, _, lo, hi, _ in r.bounds]
        values = [float(point[v]) for v, _, _, _, _ in r.bounds]
        units = "1" if r.minimise == "shots" else pmap[r.minimise].attrs.get("units", "1")
        where = {**{d: _coordinate(pmap, d, i) for d, i in sel.items()},
                 axis: _readable(float(at), pmap[axis].attrs.get("units", "1"))}
        verdict = (f"met: least {r.minimise} {_readable(value, units)} (band {_readable(low, units)} ... "
                   f"{_readable(high, units)}) at " + ", ".join(f"{d} {v}" for d, v in where.items()))
        met = 1
        # the map point (index along each other dimension) and the axis value: what a verification computes
        selected = {**{f"selected_index_{d}": int(i) for d, i in sel.items()}, f"selected_{axis}": float(at)}
    else:
        value = low = high = np.nan
        met = 0
        # the closest map point: the smallest worst violation relative to its bound
        worst = None
        for combo in itertools.product(*[range(pmap.sizes[d]) for d in dims]):
            sel = dict(zip(dims, combo))
            point = pmap.isel(sel)
            m = [_margin(float(point[v]), lo, hi) for v, _, lo, hi, _ in r.bounds]
            if worst is None or min(m) > min(worst[0]):
                worst = (m, sel, [float(point[v]) for v, _, _, _, _ in r.bounds])
        margins, sel, values = worst
        where = {d: _coordinate(pmap, d, i) for d, i in sel.items()}
        misses = [f"{key} misses by {-m:.1%} of its bound" for m, (_, _, _, _, key) in zip(margins, r.bounds) if m < 0]
        selected = {}
        verdict = ("not met by any setting in the map; closest: " + ", ".join(f"{d} {v}" for d, v in where.items())
                   + ": " + "; ".join(misses))
    units = ("1" if r.minimise == "shots" else pmap[r.minimise].attrs.get("units", "1"))
    return OUTPUTS.dataset(
        {"met": met, "minimised_value": value, "minimised_low": low, "minimised_high": high,
         "requirement_margin": np.array(margins), "requirement_value": np.array(values)},
        coords={"requirement": xr.Variable(("requirement",), np.arange(len(r.bounds)), attrs={
            "long_name": "requirement", "units": "1", "flag_values": np.arange(len(r.bounds)),
            "flag_meanings": " ".join(key for *_, key in r.bounds)})},
        attrs={"verdict": verdict, "minimised": r.minimise, "minimised_units": units,
               "requirement_units": " ".join(u for _, u, _, _, _ in r.bounds),
               **{f"setting_{d}": str(v) for d, v in where.items()}, **selected})


def _coordinate(pmap: xr.Dataset, dim: str, index: int) -> str:
    """A dimension's value at ``index`` as a person reads it: a name, the shop notation, mm or MPa."""
    c = pmap[dim]
    value = c.values[index]
    if c.attrs.get("flag_meanings"):
        return c.attrs["flag_meanings"].split()[int(value)]
    if c.attrs.get("shop_notation"):
        return c.attrs["shop_notation"].split()[index]
    return _readable(float(value), c.attrs.get("units", "1"))


def _readable(value: float, units: str) -> str:
    """``value`` (SI) in the units a person reads: m as mm, Pa as MPa, % and degrees as they are."""
    scale, shown = {"m": (1e3, " mm"), "Pa": (1e-6, " MPa"), "%": (1.0, " %"), "degree": (1.0, " deg"),
                    "m s-1": (1.0, " m/s")}.get(units, (1.0, "" if units == "1" else f" {units}"))
    return f"{value * scale:.4g}{shown}"


def _least(xs: np.ndarray, setting: np.ndarray, features: list, edge: float) -> tuple[float, float]:
    """(least setting, the axis value there) at which every feature, moved by ``edge`` times its band toward
    meeting (+1) or missing (-1) its bounds, meets them; (NaN, NaN) if none within the map."""
    if xs.size == 1:
        ok = all(_inside(v[0] + _toward(edge, lo, hi) * b[0], lo, hi) for v, b, lo, hi in features)
        return (float(setting[0]), float(xs[0])) if ok else (np.nan, np.nan)
    fine = np.concatenate([np.linspace(a, b, FINE, endpoint=False) for a, b in zip(xs[:-1], xs[1:])] + [xs[-1:]])
    ok = np.ones(fine.size, dtype=bool)
    for v, b, lo, hi in features:
        curve = PchipInterpolator(xs, v)(fine) + _toward(edge, lo, hi) * PchipInterpolator(xs, b)(fine)
        ok &= np.array([_inside(c, lo, hi) for c in curve])
    if not ok.any():
        return np.nan, np.nan
    x = float(fine[np.argmax(ok)])
    return float(PchipInterpolator(xs, setting)(x)), x


def _toward(edge: float, lo, hi) -> float:
    """The sign that moves a value toward meeting its bounds (+ for a minimum, - for a maximum), times ``edge``."""
    if lo is not None and hi is None:
        return edge
    if hi is not None and lo is None:
        return -edge
    return 0.0


def _inside(value: float, lo, hi) -> bool:
    return (lo is None or value >= lo) and (hi is None or value <= hi)
