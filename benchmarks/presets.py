"""Issue 10 §2: each element size's study-level error against the converged references, and its cost
(prints its figures and writes a Pareto plot; not a test).

Usage (from the repository root)::

    python benchmarks/presets.py [PLOT.png]     # e.g. benchmarks/reference/presets_pareto.png

Reads the study-level reference levels (``peenflow/validation/data/study_level.json``, made by
``benchmarks/study_reference.py``; every level varies only the element size of the standard
preset's settings, with paired shot streams); the errors and the references are those of
:mod:`peenflow.validation.study_level`. The error of a preset is that of its element size
(``coarse`` 60 um, ``standard`` 40 um, ``paper`` 25 um): the presets' other settings (window,
grading) were measured separately at the single-impact level (docs/validation.md sections 4 and 6).
"""

from __future__ import annotations

import argparse

from peenflow.validation import runs
from peenflow.validation.study_level import (TARGET, dent_core_levels, dent_levels, n_f_reference,
                                             study_level_errors, target_errors, target_reference)

PRESET_OF = {60.0: "coarse", 40.0: "standard", 25.0: "paper"}


def worst_pct(row: dict) -> float:
    """The largest |error| in % over the quantities with a converged reference: the intensity and the
    12A velocity."""
    return max(abs(row["intensity_pct"][0]), abs(row["intensity_pct"][1]), abs(row["velocity_12a_pct"]))


def main(plot: str | None) -> None:
    data = runs.load("study_level")
    errors = study_level_errors(data)
    ref = errors.pop("reference")
    print("references: intensity " + ", ".join(f"{p} {v:.4f} mm" for p, v in ref["intensity_mm"].items())
          + f"; 12A at 67.5 deg {ref['velocity_12a_m_s']:.2f} m/s; {TARGET}: N_f {ref['n_f']:.1f} (first-order limit "
          f"of the dent levels), profile against the converged peak and its {ref['target_level']} level")
    print(f"(strip references from levels down to {ref['strip_finest_um']:g} um)")
    extrap = errors.pop("extrapolated", {})
    print("\n| h um | preset | intensity % | 12A velocity % | worst % | CPU s || N_f % | peak σxx % | "
          "compressive depth % | profile RMS % |")
    print("|---|---|---|---|---|---||---|---|---|---|")
    f = lambda r, k, fmt: format(r[k], fmt) if k in r else "-"  # noqa: E731
    for h, r in errors.items():
        print(f"| {h:g} | {PRESET_OF.get(h, '-')} | {r['intensity_pct'][0]:+.1f} ... {r['intensity_pct'][1]:+.1f} | "
              f"{r['velocity_12a_pct']:+.1f} | {worst_pct(r):.1f} | {r['cpu_s']:.0f} || {f(r, 'n_f_pct', '+.1f')} | "
              f"{f(r, 'peak_pct', '+.1f')} | {f(r, 'zero_depth_pct', '+.1f')} | {f(r, 'profile_rms_pct', '.1f')} |")
    if extrap:
        c, fn = extrap["levels_um"]
        print(f"| {c:g} & {fn:g} extrapolated | - | {extrap['intensity_pct'][0]:+.1f} ... {extrap['intensity_pct'][1]:+.1f} | "
              f"{extrap['velocity_12a_pct']:+.1f} | {worst_pct(extrap):.1f} | {extrap['cpu_s']:.0f} || - | - | - | - |")
        print("  orders used (leave-one-out means of the other points' Richardson orders): "
              + ", ".join(f"{p} {o:.2f}" for p, o in extrap["orders"].items())
              + f"; the studies' default (mean of all): {extrap['order_all']:.2f}")
    nref = n_f_reference(data)
    if nref:
        dents = dent_levels(data)
        print(f"\n{TARGET}: N_f against the element size of its dent (study_reference.py dent): limit "
              f"{nref['n0']:.1f} ± {nref['n0_se']:.1f} (first-order fit over "
              + "/".join(f"{h:g}" for h in nref["levels_um"]) + " um)"
              + ("" if not nref["free_order"] else
                 f"; free-order fit {nref['free_order'][0]:.1f} (p {nref['free_order'][1]:.2f})")
              + "".join(f"; Richardson {'/'.join(f'{h:g}' for h in t)}: "
                        + ("-" if v is None else f"{v:.1f} (order {p:.2f})") for t, (v, p) in nref["richardson"].items()))
        print("| dent h um | N_f | error % | CPU s |")
        print("|---|---|---|---|")
        cores = dent_core_levels(data)
        rows = [(h, f"{h:g}", dents[h], e) for h, e in nref["error_pct"].items()]
        rows += [(c, f"core {c:g} in {b:g}", cores[(b, c)], e) for (b, c), e in nref["core_error_pct"].items()]
        for _, name, v, e in sorted(rows, key=lambda r: (-r[0], r[1].startswith("core"), r[1])):
            print(f"| {name} | {v['full_coverage_shots']:.1f} | {e:+.1f} | {v['cpu_s']:.0f} |")
    terr = target_errors(data)
    if terr:
        tref = target_reference(data)
        print(f"\n{TARGET} on the 1.2 mm REV, first sequence: N_f against its limit {nref['n0']:.1f}, the peak "
              f"against the converged {tref['peak_MPa']:.1f} MPa, depth and shape against the {tref['level']} level")
        print("| REV h um | dent h um | N_c | N_f % | peak σxx % | compressive depth % | profile RMS % | CPU s |")
        print("|---|---|---|---|---|---|---|---|")
        for (h, hd), r in terr.items():
            print(f"| {h:g} | {hd:g} | {r['n_c']:.0f} | {r['n_f_pct']:+.1f} | {r['peak_pct']:+.1f} | "
                  f"{r['zero_depth_pct']:+.1f} | {r['profile_rms_pct']:.1f} | {r['cpu_s']:.0f} |")
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        hs = list(errors)
        cost = [errors[h]["cpu_s"] for h in hs]
        ax.plot(cost, [worst_pct(errors[h]) for h in hs], marker="o", label="worst: intensity, 12A velocity")
        ax.plot(cost, [abs(errors[h]["velocity_12a_pct"]) for h in hs], marker="s", label="12A velocity")
        ax.plot(cost, [max(map(abs, errors[h]["intensity_pct"])) for h in hs], marker="^",
                label="intensity (worst of 4 points)")
        prof = [(errors[h]["cpu_s"], errors[h]["profile_rms_pct"]) for h in hs if "profile_rms_pct" in errors[h]]
        if prof:
            ax.plot(*zip(*prof), marker="v", ls=":", label="Al profile RMS vs its 16 um level (not converged)")
        for h in hs:
            ax.annotate(f"{h:g} um ({PRESET_OF.get(h, '-')})", (errors[h]["cpu_s"], worst_pct(errors[h])),
                        textcoords="offset points", xytext=(4, 4), fontsize=8)
        if extrap:
            ax.plot([extrap["cpu_s"]], [worst_pct(extrap)], marker="*", ms=12, ls="none",
                    label=f"{extrap['levels_um'][0]:g} & {extrap['levels_um'][1]:g} um extrapolated")
        ax.axhline(5.0, color="grey", lw=0.8, ls="--")
        ax.set_xscale("log")
        ax.set_xlabel("CPU s of the reference points at this size (one core each)")
        ax.set_ylabel("|error| against the converged reference, %")
        ax.set_title("Study-level error against cost (benchmarks/presets.py)")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(plot, dpi=120)
        print(f"wrote {plot}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("plot", nargs="?", help="write the Pareto plot (error against CPU s) to this PNG")
    main(ap.parse_args().plot)
