"""The figures a run writes (PNG, matplotlib), from whatever stages are done.

* ``saturation.png``      arc height vs shot number, per angle and velocity, with the fits (paper Fig. 16)
* ``control_curves.png``  Almen intensity vs velocity per angle, spread over sequences (Fig. 17)
* ``coverage.png``        Monte-Carlo coverage, eq. (5) fit, closed form, N_f (Fig. 18)
* ``residual_stress.png`` σx, σy vs depth with the spread over sequences, and the measured profile (Fig. 19)

Plots live beside the study (``<study>_plots/``), outside the store: they
are views of stored results, remade after every run.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from peenflow.engine import ResultNotReady, stage_result


def _result(graph, store, stage):
    if stage not in graph.stages:
        return None
    try:
        return stage_result(graph, store, stage, allow_partial=True)
    except ResultNotReady:
        return None


def write_plots(graph, store, out_dir: Path) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    written = []

    def save(fig, name):
        out_dir.mkdir(parents=True, exist_ok=True)
        path = out_dir / name
        fig.tight_layout()
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)

    arc = _result(graph, store, "arc_height")
    sat = _result(graph, store, "saturation")
    if arc is not None:
        angles = arc.angle_deg.values
        fig, axes = plt.subplots(1, len(angles), figsize=(5 * len(angles), 4), squeeze=False)
        for ax, a in zip(axes[0], angles):
            for v in arc.velocity_m_s.values:
                ah = arc.arc_height_mm.sel(angle_deg=a, velocity_m_s=v)
                if not np.isfinite(ah).any():
                    continue
                n = arc.shots.values
                line = ax.plot(n, ah.mean("sequence"), "o", label=f"{v:g} m/s")[0]
                ax.plot(np.repeat(n[None], ah.sizes["sequence"], 0).ravel(), ah.values.ravel(), ".",
                        color=line.get_color(), alpha=0.3)
                # a partial result lacks the points whose fit failed (e.g. "cannot saturate")
                if (sat is not None and "fit_arc_height_mm" in sat and a in sat.angle_deg.values
                        and v in sat.velocity_m_s.values):
                    s = sat.sel(angle_deg=a, velocity_m_s=v)
                    if np.isfinite(s.fit_arc_height_mm).any():
                        ax.plot(s.shots_fine, s.fit_arc_height_mm, "-", color=line.get_color())
                        ax.plot(float(s.saturation_shots), float(s.intensity_mm), "*", ms=12,
                                color=line.get_color())
            ax.set_xscale("log")
            ax.set(xlabel="shots N", ylabel="arc height (mm)", title=f"saturation, {a:g} deg (* = eq. 11)")
            ax.legend(fontsize=8)
        save(fig, "saturation.png")

    control = _result(graph, store, "control_curve")
    if control is not None:
        fig, ax = plt.subplots(figsize=(6, 4))
        for a in control.angle_deg.values:
            c = control.sel(angle_deg=a)
            line = ax.errorbar(c.velocity_m_s, c.intensity_mm, yerr=np.nan_to_num(c.intensity_std_mm), fmt="o",
                               capsize=3, label=f"{a:g} deg")
            ax.plot(c.velocity_fine_m_s, c.curve_intensity_mm, "-", color=line[0].get_color())
        tv = _result(graph, store, "target_velocity")
        if tv is not None and "intensity_mm" in tv:
            ax.axhline(float(tv.intensity_mm), ls=":", color="k")
            ax.axvline(float(tv.velocity_m_s), ls=":", color="k")
            ax.set_title(f"control curves; target {float(tv.intensity_mm):g} mm -> {float(tv.velocity_m_s):.1f} m/s")
        else:
            ax.set_title("control curves")
        ax.set(xlabel="shot velocity (m/s)", ylabel="Almen intensity (mm)")
        ax.legend()
        save(fig, "control_curves.png")

    cov = _result(graph, store, "coverage_curve")
    if cov is not None:
        fig, ax = plt.subplots(figsize=(6, 4))
        n = cov.shots.values
        for s in cov.sequence.values:
            ax.plot(n, cov.coverage_percent.sel(sequence=s), "-", color="0.7", lw=0.8)
        ax.plot(n, cov.coverage_mean_percent, "o", ms=3, label="Monte Carlo (mean)")
        ax.plot(n, cov.avrami_coverage_percent, "-", label=f"eq. (5), A = {float(cov.avrami_rate):.3g}")
        ax.plot(n, cov.uniform_closed_form_percent, "--", label="closed form, uniform landings")
        ax.axvline(float(cov.full_coverage_shots), ls=":", color="k")
        ax.set(xlabel="shots N", ylabel="coverage (%)",
               title=f"coverage; N_f = {float(cov.full_coverage_shots):.0f}, N_c = {float(cov.coverage_shots):.0f}")
        ax.legend()
        save(fig, "coverage.png")

    prof = _result(graph, store, "residual_profile")
    if prof is not None:
        fig, ax = plt.subplots(figsize=(6, 4))
        z = prof.depth_m.values * 1e3
        for c in ("xx", "yy"):
            m = prof[f"stress_{c}_mean_MPa"].values
            s = prof[f"stress_{c}_spread_MPa"].values
            line = ax.plot(z, m, "-", label=f"sigma_{c}")[0]
            ax.fill_between(z, m - s, m + s, color=line.get_color(), alpha=0.2)
            if f"stress_{c}_free_mean_MPa" in prof:
                ax.plot(z, prof[f"stress_{c}_free_mean_MPa"].values, "--", color=line.get_color(),
                        label=f"sigma_{c}, free part")
        if "measured_stress_MPa" in prof:
            yy = prof.measured_component.values == 1
            for sel, marker, c in ((~yy, "ks", "xx"), (yy, "k^", "yy")):
                if sel.any():
                    ax.plot(prof.measured_depth_m.values[sel] * 1e3, prof.measured_stress_MPa.values[sel], marker,
                            mfc="none", label=f"measured sigma_{c}")
        # On a thick part the peened layer is a small fraction of the depth:
        # show 2.5 times the depth where |sigma_xx| last exceeds 5 % of its peak.
        mean = np.abs(prof.stress_xx_mean_MPa.values)
        significant = np.nonzero(mean > 0.05 * mean.max())[0]
        if significant.size and 2.5 * z[significant[-1]] < z[-1]:
            ax.set_xlim(0, 2.5 * z[significant[-1]])
        ax.axhline(0, color="k", lw=0.5)
        ax.set(xlabel="depth (mm)", ylabel="residual stress (MPa)", title="residual stress (mean +- spread)")
        ax.legend()
        save(fig, "residual_stress.png")
    return written
