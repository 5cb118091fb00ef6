"""The numbers a study exists to give, read from whatever stages are done.

Printed at the end of every run and tabled in the report: the control
curve's intensities (mean over sequences ± their standard deviation), the
velocity for the target intensity, d_min and the REV, the dent, N_f and N_c,
and the residual-stress profile's surface value, peak, depth of the peak and
compressive depth.  Each row is ``(quantity, value with unit, note)``.

The last row names the fidelity and its measured error
(:mod:`peenflow.study.accuracy`), as every result of the study records it.
"""

from __future__ import annotations

import itertools

import numpy as np

from peenflow.methods.profile_features import compressive_depth
from peenflow.units import MM, MPA, UM, reading_unit

from .reading import stage_or_none as _result


def _pm(mean: float, std: float, unit: str, digits: int = 3) -> str:
    if np.isfinite(std) and std > 0:
        return f"{mean:.{digits}f} ± {std:.{digits}f} {unit}"
    return f"{mean:.{digits}f} {unit}"


def headline_numbers(graph, store) -> list[tuple[str, str, str]]:
    rows: list[tuple[str, str, str]] = []

    def get(stage):
        return _result(graph, store, stage)

    control = get("control_curve")
    ext = get("intensity_extrapolation")
    if ext is not None:
        hc, hf = ext.attrs["coarse_element_size_m"] / UM, ext.attrs["fine_element_size_m"] / UM
    if control is not None:
        # a family's control curves also run along the process dimensions that reach them
        extra = [d for d in control.intensity_m.dims if d not in ("angle_deg", "velocity_m_s")]
        for a, v, combo in itertools.product(control.angle_deg.values, control.velocity_m_s.values,
                                             itertools.product(*[range(control.sizes[d]) for d in extra])):
            at = dict(zip(extra, combo))
            of = f" ({point_name(control, at)})" if at else ""
            c = control.sel(angle_deg=a, velocity_m_s=v).isel(at)
            i = float(c.intensity_m) / MM
            if not np.isfinite(i):
                continue
            note = f"saturation T = {float(c.saturation_shots):.0f} shots"
            if int(c.intensity_extrapolated):
                note += ", beyond the ladder (extrapolated)"
            if ext is not None:
                e = ext.sel(angle_deg=a, velocity_m_s=v)
                e = e.isel({d: k for d, k in at.items() if d in e.dims})
                note += (f"; to zero element size from {float(e.fine_intensity_m) / MM:.3f} mm at {hf:g} um and "
                         f"{float(e.coarse_intensity_m) / MM:.3f} mm at {hc:g} um "
                         f"(correction {_pm(float(e.mesh_correction_m) / MM, float(e.mesh_correction_standard_error_m) / MM, 'mm')})")
            rows.append((f"Almen intensity, {a:g} deg, {v:g} m/s{of}", _pm(i, float(c.intensity_std_m) / MM, "mm"),
                         note))
    if graph.labels.get("process_dims"):  # a family: the map says it per point
        rows += map_rows(get("process_map"), get("suggested_settings"), get("verified_settings"))
        fidelity = graph.result_attrs.get("peenflow_fidelity")
        if rows and fidelity:
            preset, _, mesh = fidelity.partition(": ")
            rows.append(("fidelity", preset, f"{mesh} (first point of the map)"))
        return rows
    tv = get("target_velocity")
    if tv is not None:
        if "intensity_m" in tv:
            rows.append((f"velocity for {float(tv.intensity_m) / MM:g} mm intensity",
                         f"{float(tv.velocity_m_s):.1f} m/s", f"read off the control curve ({tv.attrs.get('method', '')})"))
        else:
            rows.append(("shot velocity", f"{float(tv.velocity_m_s):.1f} m/s", "given in the study"))
    for stage, what in (("strip_dmin", "strip"), ("target_dmin", "target")):
        dm = get(stage)
        if dm is None:
            continue
        if "angle_deg" in dm.dims:
            for a in dm.angle_deg.values:
                d = dm.sel(angle_deg=a)
                rows.append((f"{what} d_min, {a:g} deg", f"{float(d.d_min_m) * 1e3:.3f} mm",
                             f"within +{float(d.resolution_m) * 1e3:.3f} mm (bisection)"))
        else:
            rows.append((f"{what} d_min", f"{float(dm.d_min_m) * 1e3:.3f} mm",
                         f"within +{float(dm.resolution_m) * 1e3:.3f} mm (bisection)"))
    for stage, what in (("strip_rev", "strip"), ("target_rev", "target")):
        rev = get(stage)
        if rev is not None:
            rows.append((f"{what} REV", f"{float(rev.rev_side_m) * 1e3:.3f} mm side",
                         f"measuring {float(rev.measure_side_m) * 1e3:.3f} mm, {float(rev.thickness_m) * 1e3:.3g} mm "
                         f"thick, rule {rev.attrs.get('rule', '?')}"))
    dent = get("target_indentation")
    if dent is not None:
        impact = get("target_impact")
        # the dent's own element size (fidelity.dent_element_size_um may make it finer than the REV's)
        made = ""
        if impact is not None:
            finest = np.diff(impact.x_node_full.values).min() * 1e6
            made = (f", single impact on {finest:.3g} um elements" if impact.attrs.get("dent_refinement") != "core"
                    else f", single impact with a core of {finest:.3g} um elements under it")
        rows.append(("target dent", f"{float(dent.dent_semi_axis_along_m) * 1e3:.3f} × "
                     f"{float(dent.dent_semi_axis_across_m) * 1e3:.3f} mm",
                     f"semi-axes along × across, {float(dent.dent_depth_m) * 1e6:.1f} um deep{made}"))
    cov = get("coverage_curve")
    if cov is not None:
        rows.append((f"N_f ({cov.attrs['full_coverage_percent']:g} % coverage)",
                     f"{float(cov.full_coverage_shots):.0f} shots", "eq. (5) fit"))
        for level, n in zip(cov.coverage_percent.values, np.atleast_1d(cov.coverage_shots_rounded.values)):
            rows.append((f"N_c ({level:g} % coverage)", f"{int(n)} shots", "shots of each target REV run to it"))
    full = get("residual_profile")
    levels = full.coverage_percent.values if full is not None and "coverage_percent" in full.dims else [None]
    for level in levels:
        prof = full if level is None else full.sel(coverage_percent=level)
        at = "" if len(levels) == 1 else f" ({level:g} %)"
        if prof is None:
            break
        z = np.asarray(prof.depth_m.values).reshape(-1)
        n = int(prof.sizes.get("sequence", 1))
        spread = f"std over {n} sequences" if n > 1 else "one sequence, no spread"
        for c in ("xx", "yy"):
            m = prof[f"stress_{c}_mean_Pa"].values / MPA
            s = prof[f"stress_{c}_spread_Pa"].values / MPA
            rows.append((f"surface sigma_{c}{at}", _pm(m[0], s[0], "MPa", 0), f"top layer, {z[0] * 1e3:.3f} mm; {spread}"))
            k = int(np.nanargmin(m))
            rows.append((f"peak sigma_{c}{at}", _pm(m[k], s[k], "MPa", 0), f"at {z[k] * 1e3:.3f} mm depth"))
        zc, how = compressive_depth(z, prof.stress_xx_mean_Pa.values)
        rows.append((f"compressive depth (sigma_xx){at}", f"{zc * 1e3:.3f} mm" if zc is not None else "n/a", how))
    rows += map_rows(None, get("suggested_settings"), get("verified_settings"))
    fidelity = graph.result_attrs.get("peenflow_fidelity")
    if rows and fidelity:  # what made these numbers ("preset: mesh"), and its measured error
        preset, _, mesh = fidelity.partition(": ")
        rows.append(("fidelity", preset, f"{mesh}; {graph.result_attrs.get('peenflow_fidelity_error', '')}"))
    return rows



def point_name(pmap, sel: dict) -> str:
    """A map point as a person reads it: ``almen_intensity 12A, target_material Al7075-T73, 200 %``."""
    parts = []
    for d, i in sel.items():
        c = pmap[d]
        v = c.values[i]
        if c.attrs.get("flag_meanings"):
            parts.append(f"{d} {c.attrs['flag_meanings'].split()[int(v)]}")
        elif c.attrs.get("shop_notation"):
            parts.append(c.attrs["shop_notation"].split()[i])
        elif d == "coverage_percent":
            parts.append(f"{float(v):g} %")
        else:
            units = c.attrs.get("units", "")
            scale, shown = reading_unit(units)
            parts.append(f"{d} {float(v) * scale:.4g}{' ' + shown if shown else ''}")
    return ", ".join(parts)


def map_rows(pmap, suggestion, verification=None) -> list[tuple[str, str, str]]:
    """One row per map point (surface and peak sigma_xx, compressive depth, N_c), the suggestion and its
    verification (predicted against computed) when there is one."""
    import itertools

    rows = []
    if pmap is not None:
        dims = [d for d in pmap.attrs.get("process_dims", "").split() if d] + ["coverage_percent"]
        for combo in itertools.product(*[range(pmap.sizes[d]) for d in dims]):
            sel = dict(zip(dims, combo))
            p = pmap.isel(sel)
            zc = float(p.compressive_depth_xx_m)
            rows.append((point_name(pmap, sel),
                         f"{float(p.surface_stress_xx_Pa) / MPA:.0f} / {float(p.peak_compressive_xx_Pa) / MPA:.0f} MPa",
                         f"surface / peak sigma_xx, peak at {float(p.peak_compressive_xx_depth_m) / MM:.3f} mm, "
                         f"compressive to {zc / MM:.3f} mm, N_c {float(p.coverage_shots):.0f}, "
                         f"{float(p.velocity_m_s):.1f} m/s"
                         + ("" if int(p.error_measured) else ", error unmeasured")))
    if suggestion is not None:
        rows.append(("suggested settings", "met" if int(suggestion.met) else "none meets",
                     suggestion.attrs.get("verdict", "")))
    if verification is not None and int(verification.verified):
        rows.append(("suggestion computed", "met" if int(verification.met_computed) else "missed",
                     verification.attrs.get("verdict", "")))
    return rows
