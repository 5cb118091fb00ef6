"""What a fidelity is measured to cost in accuracy: the statement every result of a study carries.

The figures are read from the one data file ``peenflow/study/data/results.toml`` (installed with
the package), which also renders ``docs/results.md`` (``python -m peenflow.study.accuracy
--markdown``; a test keeps the page equal to the rendering). How each was measured is in
``docs/validation.md``:

Single impact (``single_impact``: ``benchmarks/single_impact.py offsets``): the worst error over
five cases -- S230 on SAE 1070 at 25 and 55 m/s normal and at 55 m/s, 45 and 30 deg; on Al 7075-T73 at
47 m/s, 65 deg -- and over four aims of the shot on the element grid (on a node, 1/4, 1/2 and 3/4
of an element off it along the plane of incidence: in a REV shots land anywhere), of the kernel's
default element (physical hourglass stabilisation) at each element size, against converged
references (6.25 um, Richardson where the order is clean).  Dent depth, sigma_xx peak and
zero-crossing depth in per cent of the reference, restitution as a difference, the sigma_xx(z)
profile as its RMS over 0-0.3 mm in per cent of the reference peak; sigma_xx(z) read on the curve
recovered from the layer means (``DepthProfile.point_values``).

Study level (``study_level``: ``benchmarks/presets.py`` on the levels of
``benchmarks/study_reference.py``): the Almen intensity of four strip points (90 deg / 55 m/s;
67.5 deg at 25, 30 and 35 m/s; periodic 1.2 mm REV, standard preset values, only the element size
varied, paired shot streams) and the velocity for 12A on the 67.5 deg control curve through them,
against references: per point the Richardson extrapolation of the three finest levels (40 / 25 /
16 um) where they converge monotonically with an order in [0.5, 4], else the finest level; the 12A
velocity from the reference intensities by the same PCHIP inverse the ``target_velocity`` stage
uses.  A statement of what was measured, not a bound.  The section 5 target: N_f against the
first-order limit of its dent levels (the dent ellipse is bounded by the pile-up crest, found at
node resolution; ``fidelity.dent_element_size_um`` takes it from a finer single impact), and the
residual-stress profile against the converged one: the 0.9 mm REV at a fixed N_c refined to
12.5 um (its peak by Richardson over 25 / 16 / 12.5 um, order 3.0, a correction below the last
change; its compressive depth and shape from 12.5 um). The REVs differ (1.2 mm against 0.9 mm), so
the profile figures also hold one sequence's scatter against another (about 6 MPa on the peak).

The window (``window_study``: ``benchmarks/study_reference.py`` levels ``40w0``): every figure above
was measured with the active window (4 contact radii, held faces); three strip points at 40 um with
every impact on the whole mesh read the intensity 4.1-8.0 % lower, growing with obliquity. The
statement names this bias beside the study-level figures.

A statement is written on every result a study computes (the engine's ``graph.result_attrs``:
outside keys and content hashes) and printed with the headline numbers.
"""

from __future__ import annotations

import sys
import tomllib
from pathlib import Path

__all__ = ["SINGLE_IMPACT", "SINGLE_IMPACT_SOURCE", "STUDY_LEVEL", "STUDY_LEVEL_EXTRAPOLATED", "N_F_LIMIT", "DENT_LEVEL_NF", "DENT_CORE_LEVEL_NF",
           "SINGLE_IMPACT_CORE", "TARGET_PROFILE", "TARGET_PROFILE_PEAK_MPA",
           "INTENSITY_ORDER", "STUDY_LEVEL_SOURCE", "WINDOW_STUDY", "window_error", "DATA_FILE", "single_impact_error", "study_level_error", "statement",
           "markdown"]

#: the one data file of measured figures (this module's constants, and docs/results.md)
DATA_FILE = Path(__file__).with_name("data") / "results.toml"
_DATA = tomllib.loads(DATA_FILE.read_text(encoding="utf-8"))

#: the single-impact errors' columns, in the order of the tuples below
_ERRORS = ("dent_pct", "sxx_peak_pct", "zero_crossing_pct", "restitution", "profile_rms_pct")

#: element size um -> worst error over the five cases and four aims: (dent %, sigma_xx peak %,
#: zero crossing %, restitution, profile RMS %)
SINGLE_IMPACT: dict[float, tuple[float, float, float, float, float]] = {
    r["element_size_um"]: tuple(r[k] for k in _ERRORS) for r in _DATA["single_impact"]["rows"]}
#: (block element size um, core element size um) -> as SINGLE_IMPACT, for the block with the core a
#: study puts under the impact (``fidelity.dent_refinement = "core"``; node-aimed, four cases)
SINGLE_IMPACT_CORE: dict[tuple[float, float], tuple[float, float, float, float, float]] = {
    (r["block_um"], r["core_um"]): tuple(r[k] for k in _ERRORS) for r in _DATA["single_impact_core"]["rows"]}
SINGLE_IMPACT_SOURCE = _DATA["single_impact"]["source"]
#: element size um -> (smallest, largest) intensity error in % over the four strip points, and the
#: error in % of the velocity for 12A on the 67.5 deg curve, against their references (module docstring)
STUDY_LEVEL: dict[float, tuple[float, float, float]] = {
    r["element_size_um"]: (r["intensity_low_pct"], r["intensity_high_pct"], r["velocity_12a_pct"])
    for r in _DATA["study_level"]["rows"]}
STUDY_LEVEL_SOURCE = _DATA["study_level"]["source"]
#: the section 5 target (Al 7075-T73, S230 at 30 m/s, 65 deg, 200 %): the limit of N_f at zero element
#: size of the single impact whose dent gives it (first-order fit over the dent levels 16 ... 6.25 um;
#: the pile-up crest that bounds the dent is found at node resolution)
N_F_LIMIT: float = _DATA["target_nf"]["limit"]
#: element size um of the target's single impact -> the error of its N_f in % against N_F_LIMIT
DENT_LEVEL_NF: dict[float, float] = {r["dent_um"]: r["n_f_pct"] for r in _DATA["target_nf"]["rows"]}
#: (block element size um, core element size um) -> as DENT_LEVEL_NF, the dent from the block with a
#: core of that size under the impact (``fidelity.dent_refinement = "core"``)
DENT_CORE_LEVEL_NF: dict[tuple[float, float], float] = {
    (r["block_um"], r["core_um"]): r["n_f_pct"] for r in _DATA["target_nf_core"]["rows"]}
#: (REV element size um, dent element size um) -> the target's profile on its first sequence (1.2 mm
#: periodic REV) against the converged profile (the 0.9 mm REV refined 25 / 16 / 12.5 um at a fixed
#: N_c: its peak by Richardson, TARGET_PROFILE_PEAK_MPA, its compressive depth and shape from 12.5 um;
#: the two REVs differ by one sequence's scatter, ~6 MPa on the peak), in %: (sigma_xx peak,
#: compressive depth, profile RMS over 0-0.3 mm of the converged peak)
TARGET_PROFILE_PEAK_MPA: float = _DATA["target_profile"]["peak_MPa"]
TARGET_PROFILE: dict[tuple[float, float], tuple[float, float, float]] = {
    (r["rev_um"], r["dent_um"]): (r["sxx_peak_pct"], r["compressive_depth_pct"], r["profile_rms_pct"])
    for r in _DATA["target_profile"]["rows"]}
#: the order p of the intensities' convergence, I(h) = I0 + c h^p: the mean Richardson order of the
#: strip references from 40 / 25 / 16 um (1.99, 1.84, 1.72), the default of
#: ``fidelity.intensity_extrapolation_order``
INTENSITY_ORDER: float = _DATA["study_level_extrapolated"]["order"]
#: (coarse um, fine um) -> as STUDY_LEVEL, for intensities extrapolated from the two levels by the
#: studies' rule (``fidelity.extrapolate_intensity_from_um``; each point with the mean order of the
#: *other* points: cross-validated)
STUDY_LEVEL_EXTRAPOLATED: dict[tuple[float, float], tuple[float, float, float]] = {
    (r["coarse_um"], r["fine_um"]): (r["intensity_low_pct"], r["intensity_high_pct"], r["velocity_12a_pct"])
    for r in _DATA["study_level_extrapolated"]["rows"]}

#: the window's size in contact radii -> (angle deg, velocity m/s, element size um, intensity read with
#: the window above the whole mesh's, %) per strip point measured (paired shot streams)
WINDOW_STUDY: dict[float, tuple[tuple[float, float, float, float], ...]] = {
    _DATA["window_study"]["window_contact_radii"]: tuple(
        (r["angle_deg"], r["velocity_m_s"], r["element_size_um"], r["window_pct"]) for r in _DATA["window_study"]["rows"])}
WINDOW_STUDY_SOURCE = _DATA["window_study"]["source"]


def _same(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-9 * max(abs(a), abs(b))


def _single_impact_sentence(what: str, errors: tuple[float, float, float, float, float]) -> str:
    """``what`` (the mesh and what the worst was taken over) followed by its measured errors."""
    dent, peak, zero, rest, rms = errors
    return (f"single impact {what}, {SINGLE_IMPACT_SOURCE}): dent depth <= {dent:g} %, sigma_xx peak <= {peak:g} %, "
            f"zero crossing <= {zero:g} %, restitution <= {rest:g}, sigma_xx(z) RMS <= {rms:g} % of the peak")


def single_impact_error(element_size_um: float) -> str | None:
    """The measured single-impact error at this element size as one sentence, or None if not measured."""
    for h, errors in SINGLE_IMPACT.items():
        if _same(h, element_size_um):
            return _single_impact_sentence(f"at {h:g} um (worst of 5 cases x 4 aims", errors)
    return None


def single_impact_core_error(block_um: float, core_um: float) -> str | None:
    """As :func:`single_impact_error`, for a core of ``core_um`` elements in a ``block_um`` block."""
    for (hb, hc), errors in SINGLE_IMPACT_CORE.items():
        if _same(hb, block_um) and _same(hc, core_um):
            return _single_impact_sentence(f"with a core of {hc:g} um elements in a {hb:g} um block (worst of 4 cases",
                                           errors)
    return None


def target_error(element_size_um: float, dent_um: float | None = None, dent_core_in_um: float | None = None) -> str:
    """The section 5 target's measured N_f and profile error for a REV at ``element_size_um`` and a
    dent at ``dent_um`` (default: the REV's size) -- with ``dent_core_in_um``, from a core of
    ``dent_um`` elements in a block of that size -- as one clause."""
    dent = element_size_um if dent_um is None else dent_um
    parts = []
    if dent_core_in_um is None:
        for h, nf in DENT_LEVEL_NF.items():
            if _same(h, dent):
                parts.append(f"N_f {nf:+.1f} % (dent at {h:g} um, against the first-order limit {N_F_LIMIT:g} of "
                             "the dent levels)")
    else:
        for (hb, hc), nf in DENT_CORE_LEVEL_NF.items():
            if _same(hb, dent_core_in_um) and _same(hc, dent):
                parts.append(f"N_f {nf:+.1f} % (dent from a core of {hc:g} um elements in a {hb:g} um block, "
                             f"against the first-order limit {N_F_LIMIT:g} of the dent levels)")
    # the profile follows N_c: a core's dent gives the N_c of the dent refined throughout
    # (docs/validation.md section 9)
    for (h, hd), (pk, cd, rms) in TARGET_PROFILE.items():
        if _same(h, element_size_um) and _same(hd, dent):
            parts.append(f"against the converged profile (peak {TARGET_PROFILE_PEAK_MPA:g} MPa) sigma_xx peak "
                         f"{pk:+.1f} %, compressive depth {cd:+.1f} %, profile RMS {rms:g} % of the peak"
                         + (f" (measured with the dent refined throughout, {dent:g} um)" if dent_core_in_um else ""))
    if not parts:
        return "; N_f and the profile not measured at these element sizes"
    return "; the section 5 target (Al 7075-T73, 65 deg, 30 m/s): " + ", ".join(parts)


def study_level_error(element_size_um: float, extrapolated_from_um: float | None = None,
                      order: float = INTENSITY_ORDER, dent_um: float | None = None,
                      dent_core_in_um: float | None = None) -> str:
    """The measured study-level error at this element size as one sentence; with
    ``extrapolated_from_um``, that of the intensities extrapolated from that coarser level
    and this one with ``order``; ``dent_um``: the element size of the target's dent, if not this one
    (``dent_core_in_um``: of a core under the impact in a block of that size, :func:`target_error`)."""
    refs = "4 strip points and the 67.5 deg control curve against references from 40 / 25 / 16 um"
    tail = target_error(element_size_um, dent_um, dent_core_in_um)
    if extrapolated_from_um is not None:
        how = (f"Almen intensities extrapolated from {extrapolated_from_um:g} and {element_size_um:g} um "
               f"(paired, order {order:g})")
        for (hc, hf), (lo, hi, v12a) in STUDY_LEVEL_EXTRAPOLATED.items():
            if _same(hc, extrapolated_from_um) and _same(hf, element_size_um):
                basis = "" if _same(order, INTENSITY_ORDER) else (
                    f", measured with order {INTENSITY_ORDER:g} where this study gives {order:g}")
                return (f"study level ({STUDY_LEVEL_SOURCE}: {refs}): {how}: Almen intensity {lo:+.1f} ... "
                        f"{hi:+.1f} %, velocity for 12A {v12a:+.1f} %{basis}{tail}")
        return f"study level not measured for {how} ({STUDY_LEVEL_SOURCE}){tail}"
    for h, (lo, hi, v12a) in STUDY_LEVEL.items():
        if _same(h, element_size_um):
            return (f"study level ({STUDY_LEVEL_SOURCE}: {refs}): Almen intensity {lo:+.1f} ... {hi:+.1f} %, "
                    f"velocity for 12A {v12a:+.1f} % at {h:g} um{tail}")
    # the target's N_f is its dent's, measured per dent level whether or not its REV level was
    return f"study level not measured at {element_size_um:g} um ({STUDY_LEVEL_SOURCE}){tail}"


def window_error(window_contact_radii: float) -> str:
    """What the active window of ``window_contact_radii`` is measured to add to the Almen intensity
    against the whole mesh, as a clause ('' for no window: every impact on the whole mesh)."""
    if window_contact_radii == 0.0:
        return ""
    (w, rows), = WINDOW_STUDY.items()  # the data file measures one window size
    lo, hi = min(r[3] for r in rows), max(r[3] for r in rows)
    where = (f"{len(rows)} strip points at {', '.join(f'{r[0]:g}' for r in rows)} deg, "
             f"{rows[0][2]:g} um, {WINDOW_STUDY_SOURCE}")
    if _same(w, window_contact_radii):
        return (f"; the active window ({w:g} contact radii) reads the Almen intensity {lo:+.1f} ... "
                f"{hi:+.1f} % above the whole mesh ({where}), not included above")
    return (f"; the active window's bias not measured at {window_contact_radii:g} contact radii (at {w:g}: "
            f"the Almen intensity {lo:+.1f} ... {hi:+.1f} % above the whole mesh, {where})")

def statement(fidelity, element_size_um: float | None = None, extrapolated: bool = True,
              level: str = "coarse") -> dict[str, str]:
    """``peenflow_fidelity`` (what made the result) and ``peenflow_fidelity_error`` (what that is
    measured to cost) for a loaded :class:`~peenflow.study.fidelity.Fidelity`.

    ``element_size_um``: the element size of the result when it is not the study's own (the coarse
    level of an intensity extrapolation); ``extrapolated``: False for results of one level only
    (the strip runs, arc heights and saturation fits of a study that extrapolates its intensities);
    ``level``: what ``element_size_um`` is -- ``"coarse"``, the coarse level of the extrapolation, or
    ``"dent"``, the target's single impact at ``fidelity.dent_element_size_um``."""
    h = fidelity.element_size_um if element_size_um is None else element_size_um
    coarse = fidelity.extrapolate_intensity_from_um if extrapolated and element_size_um is None else None
    order = fidelity.intensity_order
    # a result of the REV level states the error of the study's dent; the dent's own results its level's
    dent = fidelity.dent_element_size_um if element_size_um is None else None
    core = fidelity.dent_element_size_um is not None and fidelity.dent_refinement == "core"
    dent_level_core = level == "dent" and element_size_um is not None and core
    single = (single_impact_core_error(fidelity.element_size_um, h) if dent_level_core else
              single_impact_error(h)) or (
        f"single impact not measured at {h:g} um (measured: "
        + ", ".join(f"{k:g}" for k in SINGLE_IMPACT) + " um; cores: "
        + ", ".join(f"{c:g} in {b:g}" for b, c in SINGLE_IMPACT_CORE) + f" um, {SINGLE_IMPACT_SOURCE})")
    # with a core, the dent (N_f) of the study's REV results, and of the dent's own, is the core's
    dent_core_in = fidelity.element_size_um if core else None
    if dent_level_core:
        made = (f"{fidelity.describe()}: {fidelity.element_size_um:g} um elements, a core of {h:g} um elements "
                f"under the impact, lateral faces {fidelity.lateral_boundary}")
    else:
        made = f"{fidelity.describe()}: {h:g} um elements, lateral faces {fidelity.lateral_boundary}"
    if coarse is not None:
        made += f"; Almen intensities extrapolated to zero element size from {coarse:g} and {h:g} um (order {order:g})"
    elif element_size_um is not None:
        made += (" (the target's single impact, whose dent ellipse gives N_f and N_c)" if level == "dent"
                 else " (the coarse level of the intensity extrapolation)")
    if element_size_um is None and fidelity.dent_element_size_um is not None:
        made += (f"; the target's dent ellipse (N_f, N_c) from a single impact at {fidelity.dent_element_size_um:g} um"
                 + (f" (a core under the impact in {fidelity.element_size_um:g} um elements)" if core else ""))
    return {
        "peenflow_fidelity": made,
        "peenflow_fidelity_error": (f"{single}; {study_level_error(h, coarse, order, dent, dent_core_in)}"
                                    f"{window_error(fidelity.window_contact_radii)}"),
    }


#: the material and shot the section 5 target's errors (TARGET_PROFILE, DENT_LEVEL_NF) were measured for
TARGET_MEASURED_FOR = ("Al7075-T73", "S230")


def target_point_error(material: str, shot: str, element_size_um: float, dent_um: float | None = None,
                       dent_core_in_um: float | None = None) -> dict | None:
    """A process-map point's own stated error: ``{"peak_percent", "compressive_depth_percent",
    "profile_rms_percent", "full_coverage_shots_percent"}`` (%, None where that figure was not measured)
    when the point's material, shot and element sizes are those the section 5 target was measured at;
    None otherwise (see :func:`target_error_basis` for the measured case to name)."""
    if (material, shot) != TARGET_MEASURED_FOR:
        return None
    dent = element_size_um if dent_um is None else dent_um
    out = {"peak_percent": None, "compressive_depth_percent": None, "profile_rms_percent": None,
           "full_coverage_shots_percent": None}
    for (h, hd), (pk, cd, rms) in TARGET_PROFILE.items():
        if _same(h, element_size_um) and _same(hd, dent):
            out.update(peak_percent=pk, compressive_depth_percent=cd, profile_rms_percent=rms)
    table = DENT_LEVEL_NF if dent_core_in_um is None else {
        hc: nf for (hb, hc), nf in DENT_CORE_LEVEL_NF.items() if _same(hb, dent_core_in_um)}
    for h, nf in table.items():
        if _same(h, dent):
            out["full_coverage_shots_percent"] = nf
    return out if any(v is not None for v in out.values()) else None


def target_error_basis() -> str:
    """The measured case a process map's stated errors come from, to name beside an unmeasured point."""
    material, shot = TARGET_MEASURED_FOR
    levels = ", ".join(f"{h:g}/{hd:g} um" for h, hd in TARGET_PROFILE)
    return (f"the section 5 target: {material}, {shot} shot, 65 deg, 30 m/s, against its converged profile "
            f"(peak {TARGET_PROFILE_PEAK_MPA:g} MPa) and N_f limit ({N_F_LIMIT:g}); REV/dent element sizes measured: "
            f"{levels} ({STUDY_LEVEL_SOURCE})")


# -- docs/results.md -----------------------------------------------------------------------------------------
def _pct(v: float, signed: bool = False) -> str:
    return f"{v:+.1f} %" if signed else f"{v:.1f} %"


def _table(header: list[str], rows: list[list[str]]) -> list[str]:
    return ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)] + ["| " + " | ".join(r) + " |" for r in rows]


def _section(d: dict, header: list[str], rows: list[list[str]], extra: str = "") -> list[str]:
    out = [f"### {d['title']}", "", d["about"].strip(), ""]
    if extra:
        out += [extra, ""]
    out += _table(header, rows) + [""]
    if "command" in d:
        out += [f"Command: `{d['command']}`", ""]
    return out


_SINGLE = ["dent", "σxx peak", "zero crossing", "restitution", "profile RMS"]


def _errors(r: dict) -> list[str]:
    return [_pct(r["dent_pct"]), _pct(r["sxx_peak_pct"]), _pct(r["zero_crossing_pct"]), f"{r['restitution']:.3f}",
            _pct(r["profile_rms_pct"])]


def markdown(data: dict | None = None) -> str:
    """docs/results.md: every figure of the data file (default: :data:`DATA_FILE`), as Markdown."""
    d = _DATA if data is None else data
    out = ["# Results", "",
           "<!-- Rendered from peenflow/study/data/results.toml by "
           "`python -m peenflow.study.accuracy --markdown > docs/results.md`: edit the data file, not this page "
           "(tests/study/test_results_doc.py keeps them equal). -->", "",
           "What peenflow gives today: first what each fidelity is measured to cost in accuracy (every result a "
           "study computes states the line that applies to it, attribute `peenflow_fidelity_error`, and the "
           "headline prints it), then what the shipped studies give beside the paper's numbers. How each figure "
           "was measured, with the full tables, is in [validation.md](validation.md); what each run cost, in "
           "[performance.md](performance.md). Where peenflow differs from the paper it says why; nothing is "
           "tuned to match.", "",
           "## What each fidelity is measured to cost", ""]
    s = d["single_impact"]
    out += _section(s, ["element µm"] + _SINGLE, [[f"{r['element_size_um']:g}"] + _errors(r) for r in s["rows"]])
    s = d["single_impact_core"]
    out += _section(s, ["block µm", "core µm"] + _SINGLE,
                    [[f"{r['block_um']:g}", f"{r['core_um']:g}"] + _errors(r) for r in s["rows"]])
    s = d["study_level"]
    out += _section(s, ["element µm", "preset", "Almen intensity", "velocity for 12A"],
                    [[f"{r['element_size_um']:g}", f"`{r['preset']}`",
                      f"{_pct(r['intensity_low_pct'], True)} … {_pct(r['intensity_high_pct'], True)}",
                      _pct(r["velocity_12a_pct"], True)] for r in s["rows"]])
    s = d["study_level_extrapolated"]
    out += _section(s, ["levels µm", "order", "Almen intensity", "velocity for 12A"],
                    [[f"{r['coarse_um']:g} & {r['fine_um']:g}", f"{s['order']:g}",
                      f"{_pct(r['intensity_low_pct'], True)} … {_pct(r['intensity_high_pct'], True)}",
                      _pct(r["velocity_12a_pct"], True)] for r in s["rows"]])
    s = d["window_study"]
    out += _section(s, ["strip point", "element µm", "window", "Almen intensity against the whole mesh"],
                    [[f"{r['angle_deg']:g}°, {r['velocity_m_s']:g} m/s", f"{r['element_size_um']:g}",
                      f"{s['window_contact_radii']:g} contact radii", _pct(r["window_pct"], True)] for r in s["rows"]])
    s = d["target_nf"]
    out += _section(s, ["dent element µm", "N_f"], [[f"{r['dent_um']:g}", _pct(r["n_f_pct"], True)] for r in s["rows"]],
                    extra=f"The limit: N_f = {s['limit']:g}.")
    s = d["target_nf_core"]
    out += _section(s, ["block µm", "core µm", "N_f"],
                    [[f"{r['block_um']:g}", f"{r['core_um']:g}", _pct(r["n_f_pct"], True)] for r in s["rows"]])
    s = d["target_profile"]
    out += _section(s, ["REV element µm", "dent element µm", "σxx peak", "compressive depth", "profile RMS"],
                    [[f"{r['rev_um']:g}", f"{r['dent_um']:g}", _pct(r["sxx_peak_pct"], True),
                      _pct(r["compressive_depth_pct"], True), _pct(r["profile_rms_pct"])] for r in s["rows"]],
                    extra=f"The converged peak: σxx = {s['peak_MPa']:g} MPa.")
    out += ["## What the shipped studies give", "",
            "Each run's headline numbers beside the paper's (**bold**: the figures a study exists to give). "
            "Fidelity and cost are those of the run that made them, on a 2-core machine.", ""]
    for st in d["studies"]:
        out += [f"### {st['title']}", "", f"Study: `{st['study']}`  ",
                f"Command: `{st['command']}`  ", f"Fidelity: {st['fidelity']}  ", f"Cost: {st['cost']}", ""]
        out += _table(["quantity", "paper", "peenflow"], [[r["quantity"], r["paper"], r["peenflow"]] for r in st["rows"]])
        out += [""] + ([st["notes"].strip(), ""] if "notes" in st else [])
    return "\n".join(out)


if __name__ == "__main__":
    if sys.argv[1:] != ["--markdown"]:
        sys.exit("usage: python -m peenflow.study.accuracy --markdown   (prints docs/results.md)")
    sys.stdout.write(markdown())
