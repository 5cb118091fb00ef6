"""Issue 10 §2: each element size's study-level error against the converged references, and its cost
(prints its figures and writes a Pareto plot; not a test).

Usage (from the repository root)::

    PYTHONPATH=. python benchmarks/bench_presets.py [PLOT.png]

Reads ``benchmarks/reference/study_level.json`` (written by
``benchmarks/bench_reference.py run``; every level there varies only the element
size of the standard preset's settings, with paired shot streams). For every
element size that all points were run at, it gives the error of what a user reads
off a study:

- **Almen intensity** (eq. 11) of the strip points ``strip_90_55``, ``strip_67_25``,
  ``strip_67_30``, ``strip_67_35``, against each point's reference (Richardson on
  the three finest levels where they converge monotonically with an order in
  [0.5, 4], else the finest level: ``bench_reference.richardson``);
- **velocity for 12A** (0.30 mm, type A) on the 67.5 deg control curve through the
  25 / 30 / 35 m/s points (PCHIP, as the ``target_velocity`` stage inverts it),
  against the same inversion of the reference intensities;
- for the §5 target ``al7075_30`` (Al 7075-T73, 65 deg, 30 m/s, 200 %): **N_f**
  (shots for 98 % coverage, from the level's own dent), the **profile's peak**
  sigma_xx, its depth and the zero crossing, and the **profile RMS** (mean
  sigma_xx(z) minus the reference's, over 0-0.3 mm, in % of the reference peak),
  against the finest level (or Richardson, as above, for the scalars);
- **cost**: the process CPU seconds of the level summed over the points (one
  core each; the study's own cost scales with it).

The error of a preset is that of its element size (``coarse`` 60 um, ``standard``
40 um, ``paper`` 25 um): the presets' other settings (window, grading) were
measured separately at the single-impact level (BENCHMARKS.md §4c, §2).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
from bench_reference import OUT, extrapolate, parse_dent_level, richardson  # noqa: E402

STRIP_POINTS = ("strip_90_55", "strip_67_25", "strip_67_30", "strip_67_35")
CURVE = {25.0: "strip_67_25", 30.0: "strip_67_30", 35.0: "strip_67_35"}  # the 67.5 deg control curve
TARGET = "al7075_30"
INTENSITY_12A_MM = 0.30
RMS_DEPTH_MM = 0.3
PRESET_OF = {60.0: "coarse", 40.0: "standard", 25.0: "paper"}


def _levels(data: dict, point: str) -> dict[float, dict]:
    return {float(k.split("/")[1]): v for k, v in data.items()
            if k.startswith(point + "/") and not set(k.split("/")[1]) & set("@s")}


def _target_levels(data: dict) -> dict[float, dict]:
    """The target's levels, each on the first n sequences, n the fewest any level ran (a level
    ``HsN`` runs only the first N: the same shot streams as every level's first N, so the levels
    compare paired); the profile figures recomputed from those sequences' mean profile."""
    from bench_reference import _parse_level, profile_metrics

    from peenflow.methods.profile_features import compressive_depth

    by_h: dict[float, dict] = {}
    for k, v in data.items():
        if k.startswith(TARGET + "/") and k.count("/") == 1:
            h, side, _, dent = _parse_level(k.split("/")[1])
            if side is None and dent is None and len(v.get("sequence_sxx_MPa", [])) > len(by_h.get(h, {}).get("sequence_sxx_MPa", [])):
                by_h[h] = v
    if not by_h:
        return {}
    n = min(len(v["sequence_sxx_MPa"]) for v in by_h.values())
    out = {}
    for h, v in by_h.items():
        mean = np.mean(np.asarray(v["sequence_sxx_MPa"][:n]), axis=0)
        z = np.asarray(v["z_mm"])
        # a held REV has no balancing tension: its profile decays to zero through noise, so the
        # compressive depth is the headline's (where it rises above 5 % of its peak), not a zero crossing
        depth_m, _ = compressive_depth(z * 1e-3, mean * 1e6)
        out[h] = {**v, **profile_metrics(z * 1e-3, mean * 1e6), "zero_depth_mm": depth_m * 1e3,
                  "sxx_MPa": mean.tolist(), "sequences_compared": n}
    return out


#: Richardson only from levels down to this size: from 60 / 40 / 25 um alone the strip intensities
#: extrapolated 1-8 % too high (pre-asymptotic; BENCHMARKS.md §9), so coarser triples give no limit
RICHARDSON_FINEST_UM = 16.0


def richardson_estimate(levels: dict[float, float]) -> tuple[float | None, float | None]:
    """(limit, order) of Richardson on the three finest levels (monotone, order in [0.5, 4]), or
    (None, None)."""
    hs = sorted(levels, reverse=True)[-3:]
    if len(hs) < 3:
        return None, None
    return richardson(hs, [levels[h] for h in hs])


def _reference(levels: dict[float, float]) -> float:
    """Richardson on the three finest levels if clean -- monotone, order in [0.5, 4], the finest
    at most :data:`RICHARDSON_FINEST_UM`, and a correction no larger than the last level's change
    (a limit further out than that is mostly extrapolation: the Al target's N_f and peak, orders
    0.6-0.7, would move 2.7x their last change) -- else the finest value."""
    hs = sorted(levels, reverse=True)
    ext, _ = richardson_estimate(levels)
    if ext is not None and hs[-1] <= RICHARDSON_FINEST_UM + 1e-9:
        if abs(ext - levels[hs[-1]]) <= abs(levels[hs[-1]] - levels[hs[-2]]):
            return ext
    return levels[hs[-1]]


def velocity_12a(intensity_by_velocity: dict[float, float]) -> float:
    """m/s for 12A on the curve through ``{velocity m/s: intensity mm}`` (PCHIP inverse, no extrapolation)."""
    from peenflow.methods.control_curve import ControlCurve

    v = np.array(sorted(intensity_by_velocity))
    curve = ControlCurve(67.5, v, np.array([intensity_by_velocity[x] for x in v]) * 1e-3)
    return float(curve.velocity(INTENSITY_12A_MM * 1e-3))


def _profile_rms(level: dict, ref: dict) -> float:
    z = np.asarray(ref["z_mm"])
    keep = z <= RMS_DEPTH_MM
    mine = np.interp(z[keep], level["z_mm"], level["sxx_MPa"])
    return float(100.0 * np.sqrt(np.mean((mine - np.asarray(ref["sxx_MPa"])[keep]) ** 2)) / abs(ref["peak_MPa"]))


def study_level_errors(data: dict | None = None) -> dict[float, dict]:
    """{element size um: {quantity: error}} for every size all points were run at (module docstring):
    ``intensity_pct`` (min, max) over the strip points, ``velocity_12a_pct``, ``n_f_pct``,
    ``peak_pct``, ``peak_depth_mm`` (difference), ``zero_depth_pct``, ``profile_rms_pct``, ``cpu_s``,
    and the references themselves under ``"reference"``."""
    data = json.loads(OUT.read_text()) if data is None else data
    strips = {p: _levels(data, p) for p in STRIP_POINTS}
    target = _target_levels(data)
    sizes = sorted(set.intersection(*(set(v) for v in strips.values())), reverse=True)
    ref_i = {p: _reference({h: v["intensity_mm"] for h, v in lv.items()}) for p, lv in strips.items()}
    ref_v = velocity_12a({vel: ref_i[p] for vel, p in CURVE.items()})
    terr = target_errors(data)
    nref = n_f_reference(data)
    out: dict = {"reference": {"intensity_mm": ref_i, "velocity_12a_m_s": ref_v, "strip_finest_um": min(sizes),
                               "n_f": nref.get("n0"), "target_level": TARGET_REFERENCE_LEVELS[-1]}}
    for h in sizes[:-1]:  # the finest level is (part of) the reference
        ierr = [100.0 * (strips[p][h]["intensity_mm"] / ref_i[p] - 1.0) for p in STRIP_POINTS]
        row = {
            "intensity_pct": (min(ierr), max(ierr)),
            "velocity_12a_pct": 100.0 * (velocity_12a({vel: strips[p][h]["intensity_mm"]
                                                        for vel, p in CURVE.items()}) / ref_v - 1.0),
            "cpu_s": sum(strips[p][h]["cpu_s"] for p in STRIP_POINTS) + target.get(h, {}).get("cpu_s", 0.0),
        }
        t = terr.get((h, h))  # the target with its own dent
        if t is not None:
            row.update({k: t[k] for k in ("n_f_pct", "peak_pct", "zero_depth_pct", "profile_rms_pct")})
        out[h] = row
    out["extrapolated"] = _two_level(strips, ref_i, ref_v)
    return out


def reference_orders(strips: dict) -> dict[str, float]:
    """{point: Richardson order of its 40 / 25 / 16 um intensities} where they converge cleanly;
    ``strips``: {point: {element size um: level entry}}."""
    hs = [40.0, 25.0, 16.0]
    orders = {}
    for p, lv in strips.items():
        if all(h in lv for h in hs):
            _, order = richardson(hs, [lv[h]["intensity_mm"] for h in hs])
            if order is not None:
                orders[p] = order
    return orders


def intensity_order(strips: dict, leave_out: str | None = None) -> float:
    """The order p of the two-level extrapolation: the mean Richardson order of the strip references
    (:func:`reference_orders`), without ``leave_out``'s own (cross-validation)."""
    return float(np.mean([o for q, o in reference_orders(strips).items() if q != leave_out]))


def _two_level(strips: dict, ref_i: dict, ref_v: float, coarse: float = 40.0, fine: float = 25.0) -> dict:
    """Errors of the paired two-level extrapolation from the ``coarse`` and ``fine`` levels (the same
    shot streams), by the rule the studies use (``fidelity.extrapolate_intensity_from_um``,
    tasks/intensity_extrapolation.py): the fine level's intensity plus ``k`` times the mean per-sequence
    fine-minus-coarse difference, ``k = h_f^p / (h_c^p - h_f^p)``, with each point's order ``p`` the
    mean of the Richardson orders (40 / 25 / 16 um) of the *other* points (leave one out: no point
    is extrapolated with its own reference's order). Cost: both levels."""
    from peenflow.methods import paired_correction

    ext, used = {}, {}
    for p, lv in strips.items():
        if coarse not in lv or fine not in lv:
            return {}
        k = used[p] = intensity_order(strips, leave_out=p)
        per = [dict(enumerate(lv[h]["sequence_intensity_mm"])) for h in (fine, coarse)]
        ext[p] = lv[fine]["intensity_mm"] + paired_correction(*per, coarse, fine, k).correction
    ierr = [100.0 * (ext[p] / ref_i[p] - 1.0) for p in STRIP_POINTS]
    return {"intensity_pct": (min(ierr), max(ierr)),
            "velocity_12a_pct": 100.0 * (velocity_12a({v: ext[p] for v, p in CURVE.items()}) / ref_v - 1.0),
            "cpu_s": sum(strips[p][h]["cpu_s"] for p in STRIP_POINTS for h in (coarse, fine)),
            "orders": used, "levels_um": (coarse, fine), "order_all": intensity_order(strips)}


#: the finest dent levels N_f's limit is fitted to (first order: the pile-up crest that bounds the
#: dent is found at node resolution, so N_f(h) = N0 + c h; BENCHMARKS.md §9)
DENT_FIT_COARSEST_UM = 16.0


def _dent_entries(data: dict) -> list[tuple[float, float | None, dict]]:
    """(block element size um, core element size um or None, entry) of each ``bench_reference.py dent`` level."""
    return [(*parse_dent_level(k.split("/")[2]), v) for k, v in data.items() if k.startswith(TARGET + "/dent/")]


def dent_levels(data: dict) -> dict[float, dict]:
    """{element size um of the target's single impact, refined throughout: its entry}
    (``bench_reference.py dent``)."""
    return {h: v for h, core, v in _dent_entries(data) if core is None}


def dent_core_levels(data: dict) -> dict[tuple[float, float], dict]:
    """{(block element size um, core element size um): its entry}: the target's single impact with a
    finer core under it (``bench_reference.py dent HcC``, ``fidelity.dent_refinement = "core"``)."""
    return {(h, core): v for h, core, v in _dent_entries(data) if core is not None}


def n_f_reference(data: dict | None = None) -> dict:
    """The limit of the target's N_f at zero element size of its dent: the least-squares fit
    N_f(h) = N0 + c h over the dent levels h <= :data:`DENT_FIT_COARSEST_UM` (``n0``, its standard
    error ``n0_se``, ``slope`` per um), beside the other estimates a user could make from the same
    levels (``free_order``: N0 and p of a fit N0 + c h^p; ``richardson``: {levels: (N0, order)} of
    every triple of the three finest and of the 16 / 10 / 6.25 um levels) and the per-level errors
    against ``n0`` in % (``error_pct``)."""
    from scipy.optimize import curve_fit

    data = json.loads(OUT.read_text()) if data is None else data
    lv = dent_levels(data)
    hs = np.array(sorted(h for h in lv if h <= DENT_FIT_COARSEST_UM + 1e-9))
    if hs.size < 3:
        return {}
    nf = np.array([lv[h]["full_coverage_shots"] for h in hs])
    a = np.vstack([np.ones_like(hs), hs]).T
    coef, *_ = np.linalg.lstsq(a, nf, rcond=None)
    resid = nf - a @ coef
    cov = (resid @ resid / (hs.size - 2)) * np.linalg.inv(a.T @ a)
    out = {"n0": float(coef[0]), "n0_se": float(np.sqrt(cov[0, 0])), "slope": float(coef[1]),
           "levels_um": hs.tolist()}
    out["free_order"] = None
    if hs.size >= 4:  # three parameters: a fourth level is the least that tests the fit
        import warnings

        from scipy.optimize import OptimizeWarning
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", OptimizeWarning)
            try:
                (n0p, _, p), _ = curve_fit(lambda h, n0, c, p: n0 + c * h ** p, hs, nf,
                                           p0=(coef[0], coef[1], 1.0), maxfev=20000)
                out["free_order"] = (float(n0p), float(p))
            except RuntimeError:
                pass
    triples = [tuple(hs[:3][::-1])] + ([(16.0, 10.0, 6.25)] if {16.0, 10.0, 6.25} <= set(lv) else [])
    out["richardson"] = {t: richardson(list(t), [lv[h]["full_coverage_shots"] for h in t]) for t in triples}
    out["error_pct"] = {h: 100.0 * (v["full_coverage_shots"] / out["n0"] - 1.0) for h, v in sorted(lv.items())}
    out["core_error_pct"] = {k: 100.0 * (v["full_coverage_shots"] / out["n0"] - 1.0)
                             for k, v in sorted(dent_core_levels(data).items())}
    return out


#: the target's converged profile: the 0.9 mm periodic REV at a fixed N_c (dent at 12.5 um) refined
#: 25 / 16 / 12.5 um (first sequence; BENCHMARKS.md §9): the peak by :func:`_reference` over the three
#: (Richardson, -548.3 MPa), the compressive depth and the shape (profile RMS) those of the finest
TARGET_REFERENCE_LEVELS = ("25@0.9d12.5s1", "16@0.9d12.5s1", "12.5@0.9d12.5s1")


def target_errors(data: dict | None = None) -> dict[tuple[float, float], dict]:
    """{(REV element size um, dent element size um): errors} of the §5 target on its first sequence
    (every level's first sequence is the same shot stream) on the 1.2 mm REV: ``n_f_pct`` against the
    dent levels' first-order limit (:func:`n_f_reference`), ``peak_pct`` against the converged peak,
    ``zero_depth_pct`` (the compressive depth: where sigma_xx rises above 5 % of its peak, the
    headline's rule) and ``profile_rms_pct`` (over 0-0.3 mm, in % of the converged peak) against the
    finest level of :data:`TARGET_REFERENCE_LEVELS`; ``n_c`` and ``cpu_s`` (the level's whole chain,
    one core). The reference REV is 0.9 mm wide, so the profile comparisons also carry the scatter of
    one sequence against another (about 6 MPa on the peak, §9)."""
    from bench_reference import _parse_level

    data = json.loads(OUT.read_text()) if data is None else data
    nref = n_f_reference(data)
    if not nref or any(f"{TARGET}/{lvl}" not in data for lvl in TARGET_REFERENCE_LEVELS):
        return {}

    ref = target_reference(data)
    out = {}
    for k, v in data.items():
        if not (k.startswith(TARGET + "/") and k.count("/") == 1):
            continue
        h, side, _, dent = _parse_level(k.split("/")[1])
        if side is not None:
            continue
        t = _first_sequence(v)
        out[(h, dent or h)] = {
            "n_f_pct": 100.0 * (v["full_coverage_shots"] / nref["n0"] - 1.0),
            "peak_pct": 100.0 * (t["peak_MPa"] / ref["peak_MPa"] - 1.0),
            "zero_depth_pct": 100.0 * (t["zero_depth_mm"] / ref["zero_depth_mm"] - 1.0),
            "profile_rms_pct": _profile_rms(t, ref),
            "n_c": v["coverage_shots"], "cpu_s": v["cpu_s"]}
    return dict(sorted(out.items(), key=lambda kv: (-kv[0][0], -kv[0][1])))


def _first_sequence(v: dict) -> dict:
    """A target level's first-sequence profile and its figures (compressive depth by the headline's rule)."""
    from bench_reference import profile_metrics

    from peenflow.methods.profile_features import compressive_depth

    z, sxx = np.asarray(v["z_mm"]), np.asarray(v["sequence_sxx_MPa"][0])
    depth_m, _ = compressive_depth(z * 1e-3, sxx * 1e6)
    return {**profile_metrics(z * 1e-3, sxx * 1e6), "zero_depth_mm": depth_m * 1e3, "z_mm": z.tolist(),
            "sxx_MPa": sxx.tolist()}


def target_reference(data: dict | None = None) -> dict:
    """The converged profile :func:`target_errors` compares with: the finest level of
    :data:`TARGET_REFERENCE_LEVELS` (its first sequence, :func:`_first_sequence`) with ``peak_MPa``
    replaced by :func:`_reference` over the three levels' peaks, and its name under ``level``."""
    from bench_reference import _parse_level

    data = json.loads(OUT.read_text()) if data is None else data
    levels = {_parse_level(lvl)[0]: _first_sequence(data[f"{TARGET}/{lvl}"]) for lvl in TARGET_REFERENCE_LEVELS}
    return dict(levels[min(levels)], peak_MPa=_reference({h: v["peak_MPa"] for h, v in levels.items()}),
                level=TARGET_REFERENCE_LEVELS[-1])


def worst_pct(row: dict) -> float:
    """The largest |error| in % over the quantities with a converged reference: the intensity and the
    12A velocity."""
    return max(abs(row["intensity_pct"][0]), abs(row["intensity_pct"][1]), abs(row["velocity_12a_pct"]))


def main(plot: str | None) -> None:
    data = json.loads(OUT.read_text())
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
        print(f"\n{TARGET}: N_f against the element size of its dent (bench_reference.py dent): limit "
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
        ax.set_title("Study-level error against cost (benchmarks/bench_presets.py)")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(plot, dpi=120)
        print(f"wrote {plot}")

if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
