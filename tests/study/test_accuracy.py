"""The fidelity statement every result carries (peenflow/study/accuracy.py): its numbers are the
measured ones of docs/validation.md section 4, it says when a size was not measured, and results and the
headline carry it."""

import re
from pathlib import Path

from peenflow.study import load_study
from peenflow.study.accuracy import SINGLE_IMPACT, STUDY_LEVEL, statement
from peenflow.validation import runs

REPO = Path(__file__).resolve().parents[2]


def _validation_rows(marker: str, first_column: str) -> list[dict]:
    """The rows ({column: cell}) of the first docs/validation.md table after ``marker`` whose header
    starts with ``first_column``."""
    text = (REPO / "docs" / "validation.md").read_text()
    lines = text[text.index(marker):].splitlines()
    header = next(ln for ln in lines if ln.startswith(f"| {first_column} |"))
    cols = [c.strip() for c in header.strip("|").split("|")]
    rows = []
    for ln in lines[lines.index(header) + 2:]:
        if not ln.startswith("|"):
            break
        rows.append(dict(zip(cols, (c.strip() for c in ln.strip("|").split("|")))))
    return rows


def _errors(cells: dict) -> tuple[float, ...]:
    """(dent %, sigma_xx peak %, zero crossing %, restitution, profile RMS %) of a table row."""
    return tuple(float(re.sub(r"[ %]", "", cells[k]))
                 for k in ("dent", "σxx peak", "zero crossing", "restitution", "profile RMS"))


def _validation_summary() -> dict:
    """The 'Worst |error| over the 5 cases and the four aims' table of docs/validation.md section 4 (the
    physical element, the shot aimed on a node and 1/4, 1/2, 3/4 of an element off it)."""
    rows = _validation_rows("Worst |error| over the 5 cases and the four aims per element size", "h um")
    return {float(cells["h um"]): _errors(cells) for cells in rows}


def test_the_numbers_are_the_measured_ones():
    assert SINGLE_IMPACT == _validation_summary()


def test_a_measured_size_states_its_error_and_an_unmeasured_one_says_so(tmp_path):
    study = load_study(REPO / "studies" / "quickstart.toml")  # coarse, 60 um
    s = statement(study.fidelity)
    assert s["peenflow_fidelity"].startswith("coarse") and "60 um" in s["peenflow_fidelity"]
    assert f"dent depth <= {SINGLE_IMPACT[60.0][0]:g} %" in s["peenflow_fidelity_error"]
    lo, hi, v12a = STUDY_LEVEL[60.0]
    assert f"Almen intensity {lo:+.1f} ... {hi:+.1f} %, velocity for 12A {v12a:+.1f} % at 60 um" in s["peenflow_fidelity_error"]
    micro = load_study(REPO / "tests" / "tasks" / "micro.toml")  # 100 um
    assert "not measured at 100 um" in statement(micro.fidelity)["peenflow_fidelity_error"]



def test_the_study_level_numbers_are_the_measured_ones():
    """STUDY_LEVEL equals what the reference levels (peenflow/validation/data/study_level.json) give by
    the benchmark's own rule (per point, Richardson on the three finest levels if monotone with order
    in [0.5, 4], else the finest level; the 12A velocity by the target_velocity stage's PCHIP inverse),
    to the 0.1 % it is rounded to."""
    from peenflow.validation.study_level import study_level_errors

    measured = study_level_errors()
    for h, (lo, hi, v12a) in STUDY_LEVEL.items():
        row = measured[h]
        got = (round(row["intensity_pct"][0], 1), round(row["intensity_pct"][1], 1), round(row["velocity_12a_pct"], 1))
        assert got == (lo, hi, v12a), (h, row)


def test_the_12a_velocity_inverts_the_curve_the_stage_uses():
    """study_level.velocity_12a on a straight control curve gives the analytic velocity for 0.30 mm."""
    from peenflow.validation.study_level import velocity_12a

    # I = 0.2 mm + 0.01 mm per m/s above 20 m/s: 0.30 mm at 30 m/s (PCHIP of collinear points is the line)
    assert abs(velocity_12a({25.0: 0.25, 30.0: 0.30, 35.0: 0.35}) - 30.0) < 1e-9
    assert abs(velocity_12a({25.0: 0.25, 35.0: 0.35, 45.0: 0.45}) - 30.0) < 1e-9


def test_two_level_extrapolation_recovers_an_exact_power_law():
    """The paired two-level extrapolation (peenflow.validation.study_level): on levels that follow
    I(h) = I_inf - c h^p exactly (the same p at every point), the leave-one-out order is p and the
    40 / 25 um extrapolation is I_inf, so its intensity and 12A-velocity errors against the
    Richardson references are zero."""
    from peenflow.validation.study_level import CURVE, STRIP_POINTS, study_level_errors

    p, c = 1.7, 2e-5
    limits = {"strip_90_55": 0.47, "strip_67_25": 0.29, "strip_67_30": 0.33, "strip_67_35": 0.36}
    assert set(limits) == set(STRIP_POINTS) and set(CURVE.values()) <= set(limits)
    data = {}
    for point, inf in limits.items():
        for h in (60.0, 40.0, 25.0, 16.0):
            # two sequences off the mean by -+ 0.004 mm at every level: paired, they cancel
            i = inf - c * h**p
            data[f"{point}/{h:g}"] = {"intensity_mm": i, "sequence_intensity_mm": [i - 0.004, i + 0.004],
                                      "cpu_s": 1.0}
    for h in (40.0, 25.0):  # a target is required by the table; its values do not enter the strip errors
        data[f"al7075_30/{h:g}"] = {"full_coverage_shots": 100.0, "peak_MPa": -500.0, "zero_depth_mm": 0.4,
                                    "peak_depth_mm": 0.06, "z_mm": [0.05, 0.15], "sxx_MPa": [-500.0, 0.0],
                                    "sequence_sxx_MPa": [[-500.0, 0.0]],
                                    "cpu_s": 1.0}
    errors = study_level_errors(data)
    ext = errors["extrapolated"]
    assert all(abs(o - p) < 1e-6 for o in ext["orders"].values()) and abs(ext["order_all"] - p) < 1e-6
    assert max(map(abs, ext["intensity_pct"])) < 1e-6 and abs(ext["velocity_12a_pct"]) < 1e-6
    # while the 25 um level alone is low by c 25^p / I_inf
    assert errors[25.0]["intensity_pct"][0] < -0.5


def test_the_extrapolated_numbers_and_the_order_are_the_measured_ones():
    """STUDY_LEVEL_EXTRAPOLATED and INTENSITY_ORDER equal what the reference levels give by the
    benchmark's rule (the studies' own formula, each point with the other points' mean order), to the
    0.1 % and 0.01 they are rounded to."""
    from peenflow.validation.study_level import (STRIP_POINTS, intensity_order, point_levels, study_level_errors,
                                                 two_level)

    from peenflow.study.accuracy import INTENSITY_ORDER, STUDY_LEVEL_EXTRAPOLATED

    data = runs.load("study_level")
    strips = {p: point_levels(data, p) for p in STRIP_POINTS}
    assert round(intensity_order(strips), 2) == INTENSITY_ORDER
    ref = study_level_errors(data)["reference"]
    for (hc, hf), (lo, hi, v12a) in STUDY_LEVEL_EXTRAPOLATED.items():
        row = two_level(strips, ref["intensity_mm"], ref["velocity_12a_m_s"], hc, hf)
        got = (round(row["intensity_pct"][0], 1), round(row["intensity_pct"][1], 1), round(row["velocity_12a_pct"], 1))
        assert got == (lo, hi, v12a), (hc, hf, row)


def test_an_extrapolating_study_states_the_extrapolation_s_error(tmp_path):
    """The fidelity statement of a study that extrapolates 40 & 25 um: the measured extrapolated error;
    one that gives its own order says the error was measured with the default one."""
    from peenflow.study.accuracy import INTENSITY_ORDER, STUDY_LEVEL_EXTRAPOLATED

    lo, hi, v12a = STUDY_LEVEL_EXTRAPOLATED[(40.0, 25.0)]
    text = (REPO / "studies" / "paper_fast_25um.toml").read_text().replace(
        "element_size_um = 25.0", "element_size_um = 25.0\nextrapolate_intensity_from_um = 40.0")
    (tmp_path / "paper_fast.toml").write_text((REPO / "studies" / "paper_fast.toml").read_text())
    p = tmp_path / "x.toml"
    p.write_text(text)
    s = statement(load_study(p).fidelity)
    assert "extrapolated to zero element size from 40 and 25 um" in s["peenflow_fidelity"]
    assert (f"Almen intensity {lo:+.1f} ... {hi:+.1f} %, velocity for 12A {v12a:+.1f} %"
            in s["peenflow_fidelity_error"]) and "measured with order" not in s["peenflow_fidelity_error"]
    p.write_text(text.replace("extrapolate_intensity_from_um = 40.0",
                              "extrapolate_intensity_from_um = 40.0\nintensity_extrapolation_order = 2.0"))
    s2 = statement(load_study(p).fidelity)
    assert f"measured with order {INTENSITY_ORDER:g} where this study gives 2" in s2["peenflow_fidelity_error"]
    coarse = statement(load_study(p).fidelity, element_size_um=40.0)
    assert "40 um elements" in coarse["peenflow_fidelity"] and "coarse level" in coarse["peenflow_fidelity"]
    lo40, hi40, v40 = STUDY_LEVEL[40.0]
    assert f"Almen intensity {lo40:+.1f} ... {hi40:+.1f} %" in coarse["peenflow_fidelity_error"]


def test_the_target_numbers_are_the_measured_ones():
    """N_F_LIMIT, DENT_LEVEL_NF and TARGET_PROFILE equal what peenflow.validation.study_level computes
    from the reference levels (the dent levels' first-order N_f limit; the target's first-sequence profile
    against the converged one: the 0.9 mm REV's Richardson peak and its 12.5 um level), to the 0.1 %
    they are rounded to; studies state them, a study with
    fidelity.dent_element_size_um its dent's N_f error."""
    from peenflow.validation.study_level import n_f_reference, target_errors, target_reference

    from peenflow.study.accuracy import (DENT_CORE_LEVEL_NF, DENT_LEVEL_NF, N_F_LIMIT, TARGET_PROFILE,
                                         TARGET_PROFILE_PEAK_MPA)

    assert round(target_reference()["peak_MPa"], 1) == TARGET_PROFILE_PEAK_MPA  # the converged peak stated

    nref = n_f_reference()
    assert round(nref["n0"], 1) == N_F_LIMIT
    assert {h: round(e, 1) for h, e in nref["error_pct"].items()} == DENT_LEVEL_NF
    assert {k: round(e, 1) for k, e in nref["core_error_pct"].items()} == DENT_CORE_LEVEL_NF
    measured = target_errors()
    assert set(measured) == set(TARGET_PROFILE)
    for key, want in TARGET_PROFILE.items():
        row = measured[key]
        assert tuple(round(row[k], 1) for k in ("peak_pct", "zero_depth_pct", "profile_rms_pct")) == want, key
        assert round(row["n_f_pct"], 1) == DENT_LEVEL_NF[key[1]], key  # the level's N_f is its dent's
    s = statement(load_study(REPO / "studies" / "paper_fast_25um.toml").fidelity)["peenflow_fidelity_error"]
    pk, cd, rms = TARGET_PROFILE[(25.0, 25.0)]
    assert f"N_f {DENT_LEVEL_NF[25.0]:+.1f} % (dent at 25 um" in s and f"sigma_xx peak {pk:+.1f} %" in s, s
    p = REPO / "studies" / "paper_fast_extrapolated.toml"
    fid = load_study(p).fidelity
    assert fid.dent_element_size_um == 6.25  # the shipped whole-paper study takes its dent from 6.25 um
    s = statement(fid)["peenflow_fidelity_error"]
    pk, cd, rms = TARGET_PROFILE[(25.0, 6.25)]
    assert f"N_f {DENT_LEVEL_NF[6.25]:+.1f} % (dent at 6.25 um" in s and f"sigma_xx peak {pk:+.1f} %" in s, s


def test_a_core_study_states_the_core_s_error(tmp_path):
    """With fidelity.dent_refinement = "core" the REV results state the N_f error measured for a core
    of the dent's size in the study's block, and the dent's own results the single-impact error of
    that core (docs/validation.md sections 4 and 9), not those of the block refined throughout."""
    from peenflow.study.accuracy import DENT_CORE_LEVEL_NF, DENT_LEVEL_NF, SINGLE_IMPACT_CORE, TARGET_PROFILE

    (tmp_path / "paper_fast_25um.toml").write_text((REPO / "studies" / "paper_fast_25um.toml").read_text())
    (tmp_path / "paper_fast.toml").write_text((REPO / "studies" / "paper_fast.toml").read_text())
    p = tmp_path / "core.toml"
    p.write_text((REPO / "studies" / "paper_fast_extrapolated.toml").read_text().replace(
        "dent_element_size_um = 6.25", 'dent_element_size_um = 6.25\ndent_refinement = "core"'))
    fid = load_study(p).fidelity
    rev = statement(fid)
    assert "(a core under the impact in 25 um elements)" in rev["peenflow_fidelity"], rev
    err = rev["peenflow_fidelity_error"]
    nf = DENT_CORE_LEVEL_NF[(25.0, 6.25)]
    assert f"N_f {nf:+.1f} % (dent from a core of 6.25 um elements in a 25 um block" in err, err
    assert f"N_f {DENT_LEVEL_NF[6.25]:+.1f} % (dent at 6.25 um" not in err, err
    pk = TARGET_PROFILE[(25.0, 6.25)][0]
    assert f"sigma_xx peak {pk:+.1f} %" in err and "measured with the dent refined throughout" in err, err
    dent = statement(fid, element_size_um=6.25, level="dent")
    assert "25 um elements, a core of 6.25 um elements under the impact" in dent["peenflow_fidelity"], dent
    d, peak, *_ = SINGLE_IMPACT_CORE[(25.0, 6.25)]
    assert (f"single impact with a core of 6.25 um elements in a 25 um block (worst of 4 cases, docs/validation.md, "
            f"single impact): dent depth <= {d:g} %, sigma_xx peak <= {peak:g} %") in dent["peenflow_fidelity_error"]


def test_the_core_numbers_are_the_measured_ones():
    """SINGLE_IMPACT_CORE equals the study-core rows of docs/validation.md section 4 ("The cores a study makes")."""
    from peenflow.study.accuracy import SINGLE_IMPACT_CORE

    found = {}
    for cells in _validation_rows("**The cores a study makes", "mesh"):
        m = re.fullmatch(r"([\d.]+) µm, study core ([\d.]+) µm", cells["mesh"])
        if m:
            found[(float(m[1]), float(m[2]))] = _errors(cells)
    assert found == SINGLE_IMPACT_CORE


def test_a_50_um_study_with_a_dent_core_states_the_core_s_errors(tmp_path):
    """A study at 50 um elements taking its dent from a 6.25 um core states the core's measured
    N_f error (docs/validation.md section 9, the 50 um block: -6.3 %, not the 50 um dent's -42.6 %) on its
    REV results, and the 50 um block's core error (section 4) on the dent's own results."""
    from peenflow.study.accuracy import DENT_CORE_LEVEL_NF, DENT_LEVEL_NF, SINGLE_IMPACT_CORE

    p = tmp_path / "core50.toml"
    p.write_text((REPO / "studies" / "paper_fast.toml").read_text().replace(
        'preset = "standard"                   # 40 um',
        'preset = "standard"\nelement_size_um = 50.0\ndent_element_size_um = 6.25\ndent_refinement = "core"'))
    fid = load_study(p).fidelity
    assert fid.element_size_um == 50.0 and fid.dent_refinement == "core"
    err = statement(fid)["peenflow_fidelity_error"]
    assert f"N_f {DENT_CORE_LEVEL_NF[(50.0, 6.25)]:+.1f} % (dent from a core of 6.25 um elements in a 50 um block" in err
    assert f"N_f {DENT_LEVEL_NF[50.0]:+.1f} %" not in err, err
    dent = statement(fid, element_size_um=6.25, level="dent")
    d, peak, *_ = SINGLE_IMPACT_CORE[(50.0, 6.25)]
    assert (f"single impact with a core of 6.25 um elements in a 50 um block (worst of 4 cases, docs/validation.md, "
            f"single impact): dent depth <= {d:g} %, sigma_xx peak <= {peak:g} %") in dent["peenflow_fidelity_error"]


def test_the_window_bias_is_the_measured_one_and_every_statement_names_it():
    """WINDOW_STUDY equals the paired levels of peenflow/validation/data/study_level.json: each point's
    40 um intensity with the default 4-radius window over the same point's with every impact on the
    whole mesh (level ``40w0``), to the 0.1 % it is rounded to; and a standard-preset study (4 radii)
    states it, a whole-mesh study does not."""
    from peenflow.study.accuracy import WINDOW_STUDY

    data = runs.load("study_level")
    point = {(30.0, 55.0): "strip_30_55", (67.5, 30.0): "strip_67_30", (90.0, 55.0): "strip_90_55"}
    (radii, rows), = WINDOW_STUDY.items()
    assert radii == 4.0
    for angle, speed, h, pct in rows:
        name = point[(angle, speed)]
        windowed, whole = data[f"{name}/{h:g}"]["intensity_mm"], data[f"{name}/{h:g}w0"]["intensity_mm"]
        assert round(100.0 * (windowed / whole - 1.0), 1) == pct, (name, windowed, whole)
    study = load_study(REPO / "studies" / "paper_fast.toml")
    assert study.fidelity.window_contact_radii == 4.0
    lo, hi = min(r[3] for r in rows), max(r[3] for r in rows)
    assert f"reads the Almen intensity {lo:+.1f} ... {hi:+.1f} % above the whole mesh" in (
        statement(study.fidelity)["peenflow_fidelity_error"])
    whole_mesh = study.fidelity.model_copy(update={"window_contact_radii": 0.0})
    assert "window" not in statement(whole_mesh)["peenflow_fidelity_error"]
