"""Study-level references: the strip points and the section 5 target refined until their intensities
and profiles stop changing, and what each element size's study-level figures are off by.

Points (study files ``benchmarks/reference/studies/POINT.toml``): the strip points
``strip_90_55``, ``strip_67_25``, ``strip_67_30``, ``strip_67_35`` (periodic 1.2 mm REV, the standard
preset's settings with only the element size varied, paired shot streams) and the target
``al7075_30`` (Al 7075-T73, 65 deg, 30 m/s, 200 %); the shallow-angle strip point ``strip_30_55``
(:data:`SHALLOW_POINTS`: 30 deg, 55 m/s, beyond the paper's angles; not among the points every
study's statement is measured on). A level's key is ``POINT/LEVEL``; a LEVEL is
``H[@SIDE][wW][dHD][sN]`` (:func:`parse_level`): element size um, a larger periodic REV side mm, a
window of W contact radii (0: the whole mesh), the element size um of the target's dent, the target's
first N sequences only; the target's single
impact alone is ``POINT/dent/H[cC]`` (:func:`parse_dent_level`: a core of C um under the impact).
The measured levels: :func:`peenflow.validation.runs.load` ``("study_level")``; the driver that
makes them: ``benchmarks/study_reference.py``; the tables of the errors: ``benchmarks/presets.py``.

For every element size all strip points were run at, what a user reads off a study is compared with
its reference (:func:`study_level_errors`):

- **Almen intensity** (eq. 11) of the strip points, against each point's reference (Richardson on
  the three finest levels where they converge monotonically with an order in [0.5, 4], else the
  finest level: :func:`reference_value`);
- **velocity for 12A** (0.30 mm, type A) on the 67.5 deg control curve through the 25 / 30 / 35 m/s
  points (PCHIP, as the ``target_velocity`` stage inverts it), against the same inversion of the
  reference intensities (:func:`velocity_12a`);
- for the target: **N_f** against the first-order limit of its dent levels (:func:`n_f_reference`),
  the **profile's peak** sigma_xx, its compressive depth and the **profile RMS** against the
  converged profile (:func:`target_errors`, :func:`target_reference`);
- **cost**: the process CPU seconds of the level summed over the points (one core each).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from . import runs

#: the strip points, and those of the 67.5 deg control curve by velocity m/s
STRIP_POINTS = ("strip_90_55", "strip_67_25", "strip_67_30", "strip_67_35")
#: strip points at angles beyond the paper's, run the same way (docs/validation.md, shallow angles)
SHALLOW_POINTS = ("strip_30_55",)
CURVE = {25.0: "strip_67_25", 30.0: "strip_67_30", 35.0: "strip_67_35"}
#: the section 5 target
TARGET = "al7075_30"
#: the intensity of 12A (type A), mm
INTENSITY_12A_MM = 0.30
#: depth (mm) the target's profile RMS is taken over
RMS_DEPTH_MM = 0.3


def parse_level(text: str) -> tuple[float, float | None, int | None, float | None]:
    """``H[@SIDE][wW][dHD][sN]`` -> (element size um, REV side mm or None, target sequences or None,
    the target's dent element size um or None); the window ``wW``: :func:`level_window`."""
    text, _, seqs = text.partition("s")
    text, _, dent = text.partition("d")
    text = text.partition("w")[0]
    h, _, side = text.partition("@")
    return float(h), (float(side) if side else None), (int(seqs) if seqs else None), (float(dent) if dent else None)


def level_window(text: str) -> float | None:
    """The ``fidelity.window_contact_radii`` of a level ``...wW...`` (``40w0``: 40 um, the whole mesh
    integrated at every impact: the window against the full mesh), or None (the point's own)."""
    win = text.partition("s")[0].partition("d")[0].partition("w")[2]
    return float(win) if win else None


def level_name(h_um: float, side_mm: float | None, sequences: int | None = None,
               dent_um: float | None = None, window: float | None = None) -> str:
    """The name :func:`parse_level` and :func:`level_window` read."""
    name = f"{h_um:g}" if side_mm is None else f"{h_um:g}@{side_mm:g}"
    if window is not None:
        name += f"w{window:g}"
    if dent_um is not None:
        name += f"d{dent_um:g}"
    return name if sequences is None else f"{name}s{sequences}"


def profile_figures(z_m: np.ndarray, s_pa: np.ndarray) -> dict:
    """Surface value, peak (most compressive), its depth and the first zero crossing below it
    (linear between layer centres) of a sigma_xx(z) profile (z m from the top, Pa)."""
    k = int(np.argmin(s_pa))
    zero = float("nan")
    for i in range(k, len(s_pa) - 1):
        if s_pa[i] < 0.0 <= s_pa[i + 1]:
            zero = float(z_m[i] + (z_m[i + 1] - z_m[i]) * (-s_pa[i]) / (s_pa[i + 1] - s_pa[i]))
            break
    return {"surface_MPa": float(s_pa[0] / 1e6), "peak_MPa": float(s_pa[k] / 1e6),
            "peak_depth_mm": float(z_m[k] * 1e3), "zero_depth_mm": zero * 1e3}


def stage_results(study: Path, *stages: str):
    """The finished results (Datasets) of ``stages`` of a study file, from its store (``.peenflow``
    beside it)."""
    from peenflow.api import load_study_graph
    from peenflow.engine import DirectoryStore, stage_result
    from peenflow.engine.store import default_root

    graph = load_study_graph(study)
    store = DirectoryStore(default_root(study))
    return [stage_result(graph, store, s) for s in stages]


def parse_dent_level(name: str) -> tuple[float, float | None]:
    """(block element size um, core element size um or None) of a ``dent`` level: ``25`` or ``25c6.25``."""
    block, _, core = name.partition("c")
    return float(block), (float(core) if core else None)


def dent_level_name(h_um: float, core_um: float | None) -> str:
    """The name :func:`parse_dent_level` reads."""
    return f"{h_um:g}" if core_um is None else f"{h_um:g}c{core_um:g}"


def extrapolate(f_coarse, f_fine, h_coarse, h_fine, p):
    """The limit of ``f(h) = f0 + c h^p`` through two levels: ``f_fine + (f_fine - f_coarse) h_fine^p /
    (h_coarse^p - h_fine^p)`` (works on arrays): :func:`peenflow.methods.two_level_limit`, the formula
    the studies' ``fidelity.extrapolate_intensity_from_um`` uses."""
    from peenflow.methods import two_level_limit

    return two_level_limit(f_coarse, f_fine, h_coarse, h_fine, p)


def richardson(hs, fs, p_range=(0.5, 4.0)):
    """(extrapolated value, order) from three levels h1 > h2 > h3, or (None, None) when not monotone
    or the order is outside ``p_range``."""
    (h1, h2, h3), (f1, f2, f3) = hs, fs
    if not (f1 - f2) * (f2 - f3) > 0:
        return None, None
    target = (f1 - f2) / (f2 - f3)
    g = lambda p: (h1**p - h2**p) / (h2**p - h3**p) - target  # noqa: E731 - increasing in p
    lo, hi = p_range
    if g(lo) * g(hi) > 0:
        return None, None
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(lo) * g(mid) > 0 else (lo, mid)
    p = 0.5 * (lo + hi)
    return extrapolate(f2, f3, h2, h3, p), p


def point_levels(data: dict, point: str) -> dict[float, dict]:
    """{element size um: level} of a point's levels on its own REV and window (no ``@SIDE``, ``wW``,
    ``sN``)."""
    return {float(k.split("/")[1]): v for k, v in data.items()
            if k.startswith(point + "/") and not set(k.split("/")[1]) & set("@sw")}


def target_levels(data: dict) -> dict[float, dict]:
    """The target's levels, each on the first n sequences, n the fewest any level ran (a level
    ``HsN`` runs only the first N: the same shot streams as every level's first N, so the levels
    compare paired); the profile figures recomputed from those sequences' mean profile."""
    from peenflow.methods.profile_features import compressive_depth

    by_h: dict[float, dict] = {}
    for k, v in data.items():
        if k.startswith(TARGET + "/") and k.count("/") == 1:
            h, side, _, dent = parse_level(k.split("/")[1])
            more = len(v.get("sequence_sxx_MPa", [])) > len(by_h.get(h, {}).get("sequence_sxx_MPa", []))
            if side is None and dent is None and more:
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
        out[h] = {**v, **profile_figures(z * 1e-3, mean * 1e6), "zero_depth_mm": depth_m * 1e3,
                  "sxx_MPa": mean.tolist(), "sequences_compared": n}
    return out


#: Richardson only from levels down to this size: from 60 / 40 / 25 um alone the strip intensities
#: extrapolated 1-8 % too high (pre-asymptotic; docs/validation.md section 9), so coarser triples give no limit
RICHARDSON_FINEST_UM = 16.0


def richardson_estimate(levels: dict[float, float]) -> tuple[float | None, float | None]:
    """(limit, order) of Richardson on the three finest levels (monotone, order in [0.5, 4]), or
    (None, None)."""
    hs = sorted(levels, reverse=True)[-3:]
    if len(hs) < 3:
        return None, None
    return richardson(hs, [levels[h] for h in hs])


def reference_value(levels: dict[float, float]) -> float:
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


def profile_rms(level: dict, ref: dict) -> float:
    """RMS (% of the reference's peak) over 0-:data:`RMS_DEPTH_MM` of a level's sigma_xx(z)
    (``z_mm`` / ``sxx_MPa``, straight lines between layer centres) minus the reference's, at the
    reference's layer centres."""
    z = np.asarray(ref["z_mm"])
    keep = z <= RMS_DEPTH_MM
    mine = np.interp(z[keep], level["z_mm"], level["sxx_MPa"])
    return float(100.0 * np.sqrt(np.mean((mine - np.asarray(ref["sxx_MPa"])[keep]) ** 2)) / abs(ref["peak_MPa"]))


def study_level_errors(data: dict | None = None) -> dict[float, dict]:
    """{element size um: {quantity: error}} for every size all points were run at (module docstring):
    ``intensity_pct`` (min, max) over the strip points, ``velocity_12a_pct``, ``n_f_pct``,
    ``peak_pct``, ``peak_depth_mm`` (difference), ``zero_depth_pct``, ``profile_rms_pct``, ``cpu_s``,
    and the references themselves under ``"reference"``."""
    data = runs.load("study_level") if data is None else data
    strips = {p: point_levels(data, p) for p in STRIP_POINTS}
    target = target_levels(data)
    sizes = sorted(set.intersection(*(set(v) for v in strips.values())), reverse=True)
    ref_i = {p: reference_value({h: v["intensity_mm"] for h, v in lv.items()}) for p, lv in strips.items()}
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
    out["extrapolated"] = two_level(strips, ref_i, ref_v)
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


def two_level(strips: dict, ref_i: dict, ref_v: float, coarse: float = 40.0, fine: float = 25.0) -> dict:
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
#: dent is found at node resolution, so N_f(h) = N0 + c h; docs/validation.md section 9)
DENT_FIT_COARSEST_UM = 16.0


def _dent_entries(data: dict) -> list[tuple[float, float | None, dict]]:
    """(block element size um, core element size um or None, entry) of each ``study_reference.py dent`` level."""
    return [(*parse_dent_level(k.split("/")[2]), v) for k, v in data.items() if k.startswith(TARGET + "/dent/")]


def dent_levels(data: dict) -> dict[float, dict]:
    """{element size um of the target's single impact, refined throughout: its entry}
    (``study_reference.py dent``)."""
    return {h: v for h, core, v in _dent_entries(data) if core is None}


def dent_core_levels(data: dict) -> dict[tuple[float, float], dict]:
    """{(block element size um, core element size um): its entry}: the target's single impact with a
    finer core under it (``study_reference.py dent HcC``, ``fidelity.dent_refinement = "core"``)."""
    return {(h, core): v for h, core, v in _dent_entries(data) if core is not None}


def n_f_reference(data: dict | None = None) -> dict:
    """The limit of the target's N_f at zero element size of its dent: the least-squares fit
    N_f(h) = N0 + c h over the dent levels h <= :data:`DENT_FIT_COARSEST_UM` (``n0``, its standard
    error ``n0_se``, ``slope`` per um), beside the other estimates a user could make from the same
    levels (``free_order``: N0 and p of a fit N0 + c h^p; ``richardson``: {levels: (N0, order)} of
    every triple of the three finest and of the 16 / 10 / 6.25 um levels) and the per-level errors
    against ``n0`` in % (``error_pct``)."""
    from scipy.optimize import curve_fit

    data = runs.load("study_level") if data is None else data
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
#: 25 / 16 / 12.5 um (first sequence; docs/validation.md section 9): the peak by
#: :func:`reference_value` over the three (Richardson, -548.3 MPa), the compressive depth and the shape
#: (profile RMS) those of the finest
TARGET_REFERENCE_LEVELS = ("25@0.9d12.5s1", "16@0.9d12.5s1", "12.5@0.9d12.5s1")


def target_errors(data: dict | None = None) -> dict[tuple[float, float], dict]:
    """{(REV element size um, dent element size um): errors} of the §5 target on its first sequence
    (every level's first sequence is the same shot stream) on the 1.2 mm REV: ``n_f_pct`` against the
    dent levels' first-order limit (:func:`n_f_reference`), ``peak_pct`` against the converged peak,
    ``zero_depth_pct`` (the compressive depth: where sigma_xx rises above 5 % of its peak, the
    headline's rule) and ``profile_rms_pct`` (over 0-0.3 mm, in % of the converged peak) against the
    finest level of :data:`TARGET_REFERENCE_LEVELS`; ``n_c`` and ``cpu_s`` (the level's whole chain,
    one core). The reference REV is 0.9 mm wide, so the profile comparisons also carry the scatter of
    one sequence against another (about 6 MPa on the peak, docs/validation.md section 9)."""
    data = runs.load("study_level") if data is None else data
    nref = n_f_reference(data)
    if not nref or any(f"{TARGET}/{lvl}" not in data for lvl in TARGET_REFERENCE_LEVELS):
        return {}

    ref = target_reference(data)
    out = {}
    for k, v in data.items():
        if not (k.startswith(TARGET + "/") and k.count("/") == 1):
            continue
        h, side, _, dent = parse_level(k.split("/")[1])
        if side is not None:
            continue
        t = first_sequence(v)
        out[(h, dent or h)] = {
            "n_f_pct": 100.0 * (v["full_coverage_shots"] / nref["n0"] - 1.0),
            "peak_pct": 100.0 * (t["peak_MPa"] / ref["peak_MPa"] - 1.0),
            "zero_depth_pct": 100.0 * (t["zero_depth_mm"] / ref["zero_depth_mm"] - 1.0),
            "profile_rms_pct": profile_rms(t, ref),
            "n_c": v["coverage_shots"], "cpu_s": v["cpu_s"]}
    return dict(sorted(out.items(), key=lambda kv: (-kv[0][0], -kv[0][1])))


def first_sequence(v: dict) -> dict:
    """A target level's first-sequence profile and its figures (compressive depth by the headline's rule)."""
    from peenflow.methods.profile_features import compressive_depth

    z, sxx = np.asarray(v["z_mm"]), np.asarray(v["sequence_sxx_MPa"][0])
    depth_m, _ = compressive_depth(z * 1e-3, sxx * 1e6)
    return {**profile_figures(z * 1e-3, sxx * 1e6), "zero_depth_mm": depth_m * 1e3, "z_mm": z.tolist(),
            "sxx_MPa": sxx.tolist()}


def target_reference(data: dict | None = None) -> dict:
    """The converged profile :func:`target_errors` compares with: the finest level of
    :data:`TARGET_REFERENCE_LEVELS` (its first sequence, :func:`first_sequence`) with ``peak_MPa``
    replaced by :func:`reference_value` over the three levels' peaks, and its name under ``level``."""
    data = runs.load("study_level") if data is None else data
    levels = {parse_level(lvl)[0]: first_sequence(data[f"{TARGET}/{lvl}"]) for lvl in TARGET_REFERENCE_LEVELS}
    return dict(levels[min(levels)], peak_MPa=reference_value({h: v["peak_MPa"] for h, v in levels.items()}),
                level=TARGET_REFERENCE_LEVELS[-1])


