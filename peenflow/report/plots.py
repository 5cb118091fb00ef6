"""The figures a run writes (PNG, matplotlib), from whatever stages are done.

* ``saturation.png``      arc height vs shot number, per angle and velocity, with the fits (paper Fig. 16)
* ``control_curves.png``  Almen intensity vs velocity per angle, spread over sequences (Fig. 17); with an
  intensity extrapolation, the two levels' intensities beside the extrapolated ones
* ``coverage.png``        Monte-Carlo coverage, eq. (5) fit, closed form, N_f (Fig. 18)
* ``residual_stress.png`` σx, σy vs depth with the spread over sequences, and the measured profile (Fig. 19)

Plots are views of stored results, remade after every run, and live in the
store (``<store>/reports/<study>-<id>/``, :func:`peenflow.report.report_dir`): never in a
tracked folder, and two studies never share a folder.

``about``: names the figures print (``strip``, ``shot``, ``target_material``,
``coverage_percent``): the graph's ``labels``, given by the pipeline from the study.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np

from peenflow.methods.profile_features import compressive_depth
from peenflow.units import MM, MPA, UM

from .headline import point_name
from .reading import stage_or_none as _result


def _sequences(ds) -> int:
    return int(ds.sizes.get("sequence", 1))


def write_plots(graph, store, out_dir: Path, about: dict | None = None) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    about = about or {}
    strip = f"type {about['strip']} strip" if about.get("strip") else "Almen strip"
    shot = about.get("shot", "")
    out_dir = Path(out_dir)
    written = []

    def save(fig, name):
        out_dir.mkdir(parents=True, exist_ok=True)
        path = out_dir / name
        fig.tight_layout()
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)

    process_dims = list(about.get("process_dims") or [])

    def first_point(ds):
        """A strip-side result of a family whose dimensions reach the strips: its first map point."""
        if ds is None:
            return None
        return ds.isel({d: 0 for d in process_dims if d in ds.dims})

    arc = first_point(_result(graph, store, "arc_height"))
    sat = first_point(_result(graph, store, "saturation"))
    if arc is not None:
        angles = arc.angle_deg.values
        fig, axes = plt.subplots(1, len(angles), figsize=(6 * len(angles), 4.5), squeeze=False)
        for ax, a in zip(axes[0], angles):
            for v in arc.velocity_m_s.values:
                ah = arc.arc_height_m.sel(angle_deg=a, velocity_m_s=v) / MM
                if not np.isfinite(ah).any():
                    continue
                n = arc.shots.values
                label = f"{v:g} m/s"
                fitted = None
                # a partial result lacks the points whose fit failed (e.g. "cannot saturate")
                if (sat is not None and "fit_arc_height_m" in sat and a in sat.angle_deg.values
                        and v in sat.velocity_m_s.values):
                    s = sat.sel(angle_deg=a, velocity_m_s=v)
                    if np.isfinite(s.fit_arc_height_m).any():
                        fitted = s
                        label += f": I = {float(s.intensity_m) / MM:.3f} mm at T = {float(s.saturation_shots):.0f}"
                        if "intensity_extrapolated" in s and int(s.intensity_extrapolated):
                            label += " (T beyond the ladder)"
                line = ax.plot(n, ah.mean("sequence"), "o", label=label)[0]
                ax.plot(np.repeat(n[None], ah.sizes["sequence"], 0).ravel(), ah.values.ravel(), ".",
                        color=line.get_color(), alpha=0.3)
                if fitted is not None:
                    ax.plot(fitted.shots_fine, fitted.fit_arc_height_m / MM, "-", color=line.get_color())
                    ax.plot(float(fitted.saturation_shots), float(fitted.intensity_m) / MM, "*", ms=13,
                            color=line.get_color(), mec="k")
            ax.set_xscale("log")
            key = [Line2D([], [], color="0.3", marker="o", ls="", label="mean over sequences"),
                   Line2D([], [], color="0.3", marker=".", ls="", alpha=0.4,
                          label=f"each sequence ({_sequences(arc)})"),
                   Line2D([], [], color="0.3", ls="-", label="fit of the mean (eq. 10)"),
                   Line2D([], [], color="0.3", marker="*", ms=11, mec="k", ls="",
                          label="saturation point T, intensity I (eq. 11)")]
            handles, _ = ax.get_legend_handles_labels()
            ax.legend(handles=handles + key, fontsize=7, loc="lower right")
            ax.set(xlabel="shots N", ylabel="arc height (mm)",
                   title=f"saturation curves, {strip}, {shot} at {a:g} deg".replace(" ,", ","))
        save(fig, "saturation.png")

    control_all = _result(graph, store, "control_curve")
    ext = first_point(_result(graph, store, "intensity_extrapolation"))
    if control_all is not None:
        fig, ax = plt.subplots(figsize=(6.5, 4.5))
        n_seq = _sequences(sat) if sat is not None else 1
        # a family's control curves: one per combination of the dimensions that reach them
        extra = [d for d in process_dims if d in control_all.intensity_m.dims]
        combos = [dict(zip(extra, k)) for k in itertools.product(*[range(control_all.sizes[d]) for d in extra])]
        for a, at in itertools.product(control_all.angle_deg.values, combos):
            control = control_all.isel(at)
            c = control.sel(angle_deg=a)
            of = f" ({point_name(control_all, at)})" if at else ""
            line = ax.errorbar(c.velocity_m_s, c.intensity_m / MM, yerr=np.nan_to_num(c.intensity_std_m) / MM,
                               fmt="o", capsize=3, label=f"{a:g} deg{of}")
            ax.plot(c.velocity_fine_m_s, c.curve_intensity_m / MM, "-", color=line[0].get_color())
            if ext is not None and not at:  # the two levels the intensities were extrapolated from
                e = ext.sel(angle_deg=a)
                ax.plot(e.velocity_m_s, e.fine_intensity_m / MM, "v", mfc="none", color=line[0].get_color())
                ax.plot(e.velocity_m_s, e.coarse_intensity_m / MM, "x", color=line[0].get_color())
        if ext is not None:
            hc, hf = ext.attrs["coarse_element_size_m"] / UM, ext.attrs["fine_element_size_m"] / UM
            ax.plot([], [], "ko", label=f"extrapolated to zero element size (order {ext.attrs['order']:g})")
            ax.plot([], [], "kv", mfc="none", label=f"{hf:g} um level")
            ax.plot([], [], "kx", label=f"{hc:g} um level")
        title = f"control curves, {strip}"
        tv = _result(graph, store, "target_velocity")
        if tv is not None and "intensity_m" in tv:  # every target intensity of the study and its velocity
            targets = zip(np.atleast_1d(tv.intensity_m.values).ravel(), np.atleast_1d(tv.velocity_m_s.values).ravel())
            for i, v in targets:
                ax.plot([v], [i / MM], "kx", ms=8)
                ax.annotate(f"{i / MM:g} mm -> {v:.1f} m/s", (v, i / MM), xytext=(6, -10),
                            textcoords="offset points", fontsize=8)
        ax.plot([], [], " ", label=f"error bars: std over {n_seq} sequence(s)" if n_seq > 1
                else "one sequence: no spread")
        ax.set(xlabel="shot velocity (m/s)", ylabel="Almen intensity (mm)", title=title)
        ax.legend(fontsize=8)
        save(fig, "control_curves.png")

    family = bool(about.get("process_dims"))  # a map: its own figures (peenflow.report.map_plots)
    cov = None if family else _result(graph, store, "coverage_curve")
    if cov is not None:
        fig, ax = plt.subplots(figsize=(6.5, 4.5))
        n = cov.shots.values
        for s in cov.sequence.values:
            ax.plot(n, cov.coverage_curve_percent.sel(sequence=s), "-", color="0.8", lw=0.8)
        ax.plot([], [], "-", color="0.8", label=f"each sequence ({_sequences(cov)})")
        ax.plot(n, cov.coverage_mean_percent, "o", ms=3, label="Monte Carlo (mean)")
        ax.plot(n, cov.avrami_coverage_percent, "-", label=f"eq. (5), A = {float(cov.avrami_rate):.3g} per shot")
        ax.plot(n, cov.uniform_closed_form_percent, "--", label="closed form, uniform landings")
        full = cov.attrs["full_coverage_percent"]
        ax.axhline(full, ls="-.", color="0.4", lw=0.8, label=f"{full:g} % (full coverage)")
        n_f = float(cov.full_coverage_shots)
        levels, shots = cov.coverage_percent.values, np.atleast_1d(cov.coverage_shots.values)
        ax.axvline(n_f, ls=":", color="k", label=f"N_f = {n_f:.0f}")
        side_mm = float(np.sqrt(float(cov.peening_area_m2))) * 1e3
        dent_r_mm = float(np.sqrt(float(cov.dent_area_m2) / np.pi)) * 1e3
        cover_text = ", ".join(f"N_c ({c:g} %) = {n:.0f}" for c, n in zip(levels, shots))
        ax.set(xlabel="shots N", ylabel="coverage (%)",
               title=f"coverage on the {side_mm:.2f} mm REV, dent radius {dent_r_mm:.3f} mm (equal area)\n"
                     f"N_f = {n_f:.0f}, {cover_text}")
        ax.legend(fontsize=8, loc="lower right")
        save(fig, "coverage.png")

    prof = None if family else _result(graph, store, "residual_profile")
    if prof is not None:
        # the largest coverage level (the study's coverage when it gives one)
        prof = prof.isel(coverage_percent=-1) if "coverage_percent" in prof.dims else prof
        fig, ax = plt.subplots(figsize=(7, 4.8))
        z = np.asarray(prof.depth_m.values).reshape(-1) / MM
        n_seq = _sequences(prof)
        for c in ("xx", "yy"):
            m = prof[f"stress_{c}_mean_Pa"].values / MPA
            s = prof[f"stress_{c}_spread_Pa"].values / MPA
            line = ax.plot(z, m, "-o", ms=3, label=f"sigma_{c}" + (" (mean)" if n_seq > 1 else ""))[0]
            if n_seq > 1:
                ax.fill_between(z, m - s, m + s, color=line.get_color(), alpha=0.2)
            if f"stress_{c}_free_mean_Pa" in prof:
                ax.plot(z, prof[f"stress_{c}_free_mean_Pa"].values / MPA, "--", color=line.get_color(),
                        label=f"sigma_{c}, free part")
        if "measured_stress_Pa" in prof:
            yy = prof.measured_component.values == 1
            for sel, marker, c in ((~yy, "ks", "xx"), (yy, "k^", "yy")):
                if sel.any():
                    ax.plot(prof.measured_depth_m.values[sel] / MM, prof.measured_stress_Pa.values[sel] / MPA, marker,
                            mfc="none", label=f"measured sigma_{c}")
        # Show the peened layer, not the whole (mostly unstressed) REV depth:
        # 1.5 times the depth where |mean sigma_xx| last exceeds 5 % of its peak.
        mean = prof.stress_xx_mean_Pa.values / MPA
        significant = np.nonzero(np.abs(mean) > 0.05 * np.abs(mean).max())[0]
        if significant.size:
            ax.set_xlim(0, min(z[-1], 1.5 * z[significant[-1]] + (z[1] - z[0] if z.size > 1 else 0)))
        peak, at = float(prof.peak_compressive_xx_Pa) / MPA, float(prof.peak_compressive_xx_depth_m) / MM
        ax.annotate(f"peak {peak:.0f} MPa at {at:.3f} mm", (at, peak), xytext=(10, -5),
                    textcoords="offset points", fontsize=8)
        ax.annotate(f"surface {mean[0]:.0f} MPa", (z[0], mean[0]), xytext=(10, 12), textcoords="offset points",
                    fontsize=8)

        zc, _ = compressive_depth(z, mean)
        if zc is not None:
            ax.axvline(zc, ls=":", color="0.5", lw=0.8, label=f"compressive to {zc:.3f} mm")
        ax.axhline(0, color="k", lw=0.5)
        tv = _result(graph, store, "target_velocity")
        what = [about.get("target_material", ""), shot]
        if tv is not None:
            if "intensity_m" in tv:
                what.append(f"{float(tv.intensity_m) / MM:g} mm intensity")
            what.append(f"{float(tv.velocity_m_s):.1f} m/s")
        if about.get("coverage_percent"):
            what.append(f"{about['coverage_percent']:g} % coverage")
        spread = f"mean ± std over {n_seq} sequences" if n_seq > 1 else "one sequence (no spread)"
        ax.set(xlabel="depth (mm)", ylabel="residual stress (MPa)",
               title="residual stress, REV held at its bottom face; " + spread + "\n"
                     + ", ".join(w for w in what if w))
        ax.legend(fontsize=8, loc="lower right")
        save(fig, "residual_stress.png")
    if family:
        from .map_plots import write_map_plots

        written += write_map_plots(_result(graph, store, "process_map"), _result(graph, store, "suggested_settings"),
                                   out_dir, save, plt)
        from .sensitivity_section import write_sensitivity_plot

        write_sensitivity_plot(_result(graph, store, "sensitivity"), save, plt)
    return written
