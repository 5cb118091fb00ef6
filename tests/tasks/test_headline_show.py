"""What a run ends with (headline numbers) and what `peenflow show` prints, on the micro study."""

import re

import numpy as np

import peenflow
import peenflow.api


def cli(*args, capsys):
    """The command in this process (a subprocess per stage would cost seconds each)."""
    from types import SimpleNamespace

    from peenflow.cli import main

    capsys.readouterr()
    rc = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return SimpleNamespace(returncode=rc, stdout=out, stderr=err)


def _row(text: str, quantity: str) -> str:
    m = re.search(rf"^  {re.escape(quantity)}\s+(.+?)\s\s", text, re.M)
    assert m, f"no headline row {quantity!r} in:\n{text}"
    return m.group(1).strip()


def test_a_run_ends_with_the_studys_headline_numbers(micro):
    out = micro.with_name("run.log").read_text()
    assert "headline numbers:" in out
    head = out.split("headline numbers:")[1]
    cov = peenflow.open_result(micro, "coverage_curve")
    assert _row(head, "N_f (98 % coverage)") == f"{float(cov.full_coverage_shots):.0f} shots"
    prof = peenflow.open_result(micro, "residual_profile").sel(coverage_percent=100.0)
    assert _row(head, "surface sigma_xx") == f"{float(prof.stress_xx_mean_Pa[0]) / 1e6:.0f} MPa"
    k = int(np.argmin(prof.stress_xx_mean_Pa.values))
    assert _row(head, "peak sigma_xx") == f"{float(prof.stress_xx_mean_Pa[k]) / 1e6:.0f} MPa"
    assert _row(head, "shot velocity") == "45.0 m/s"  # micro gives the target velocity
    ctrl = peenflow.open_result(micro, "control_curve")
    intensity_mm = float(ctrl.intensity_m.sel(angle_deg=90.0, velocity_m_s=55.0)) / 1e-3
    assert _row(head, "Almen intensity, 90 deg, 55 m/s") == f"{intensity_mm:.3f} mm"
    dent = peenflow.open_result(micro, "target_indentation")
    assert f"{float(dent.dent_semi_axis_along_m) * 1e3:.3f}" in _row(head, "target dent")


def test_show_prints_full_values_and_takes_every_stage_and_task_name(micro, capsys):
    graph = peenflow.api.load_study_graph(micro)
    for stage in graph.stages:
        proc = cli("show", micro, stage, capsys=capsys)
        assert proc.returncode == 0, (stage, proc.stderr)
        assert proc.stdout.startswith(f"stage {stage}\n") and "files:" in proc.stdout
    ctrl = peenflow.open_result(micro, "control_curve")
    out = cli("show", micro, "control_curve", "--exact", capsys=capsys).stdout
    for v in ctrl.intensity_m.values.ravel():
        assert repr(float(v)) in out  # --exact: every digit of the stored SI value, not "0.3601 ..."
    assert "[m]  Almen intensity" in out  # the store holds SI
    # a task name a single stage runs stands for that stage; an ambiguous one is refused by name
    assert cli("show", micro, "single_impact", capsys=capsys).stdout.startswith("stage target_impact\n")
    proc = cli("show", micro, "rev_size", capsys=capsys)
    assert proc.returncode == 2 and "strip_rev" in proc.stderr and "target_rev" in proc.stderr
    proc = cli("show", micro, "no_such_stage", capsys=capsys)
    assert proc.returncode == 2 and "residual_profile" in proc.stderr  # lists the stages


def test_show_prints_values_as_a_person_reads_them_under_their_si_names(micro, capsys):
    """Lengths in mm, stresses in MPa, speeds in m/s, 6 significant digits, whole numbers without a point;
    each under the stored SI name and unit, so the variable can be found in the file."""
    ctrl = peenflow.open_result(micro, "control_curve")
    out = cli("show", micro, "control_curve", capsys=capsys).stdout
    mm = ", ".join(f"{v / 1e-3:.6g}" for v in ctrl.intensity_m.values.ravel())
    assert f"  intensity_m (angle_deg, velocity_m_s) [m]  Almen intensity\n      in mm: [[{mm}]]\n" in out, out
    assert "  velocity_m_s (velocity_m_s) [m s-1]  shot velocity\n      [30, 55]\n" in out  # micro's velocities
    assert f"  largest_shot_count = {int(ctrl.largest_shot_count)}  " in out  # 24, not 24.0
    rev = peenflow.open_result(micro, "target_rev")
    out = cli("show", micro, "target_rev", capsys=capsys).stdout
    assert f"  rev_side_m = {float(rev.rev_side_m):.6g} m  ({float(rev.rev_side_m) / 1e-3:.6g} mm)  " in out, out
    assert "  rev_side_m = 0.0012 m  (1.2 mm)  " in out  # micro.toml: target.rev_size_mm = 1.2
    prof = peenflow.open_result(micro, "residual_profile")
    out = cli("show", micro, "residual_profile", capsys=capsys).stdout
    mpa = f"{float(prof.stress_xx_mean_Pa.isel(coverage_percent=0)[0]) / 1e6:.6g}"
    assert re.search(r"  stress_xx_mean_Pa \([^)]*\) \[Pa\][^\n]*\n      in MPa: \[+" + re.escape(mpa) + ",", out), out
    assert "  velocity_m_s = 45 m/s  " in cli("show", micro, "target_velocity", capsys=capsys).stdout


def test_compressive_depth_is_the_zero_crossing_or_where_a_held_profile_fades():
    from peenflow.methods.profile_features import compressive_depth

    z = np.array([0.1, 0.2, 0.3, 0.4])
    depth, how = compressive_depth(z, np.array([-400.0, -200.0, 200.0, 50.0]))
    assert depth == 0.25 and "zero crossing" in how  # halfway between -200 and +200
    # never tensile: where it rises above 5 % of the -400 peak, i.e. -20, between -100 and -10
    depth, how = compressive_depth(z, np.array([-300.0, -400.0, -100.0, -10.0]))
    assert abs(depth - (0.3 + 0.1 * 80.0 / 90.0)) < 1e-12 and "held REV" in how


def test_a_crossing_through_round_off_is_not_a_zero_crossing():
    """A held REV's profile that reaches zero through round-off of either sign (+0.2 MPa after a
    -500 MPa peak) fades where it rises above 5 % of the peak, not at the round-off crossing."""
    from peenflow.methods.profile_features import compressive_depth

    z = np.array([0.1, 0.2, 0.3, 0.4, 0.5])
    depth, how = compressive_depth(z, np.array([-400.0, -500.0, -100.0, -5.0, 0.2]))
    assert abs(depth - (0.3 + 0.1 * 75.0 / 95.0)) < 1e-12 and "held REV" in how
    # real tension beyond the crossing (+40 MPa > 5 % of 500) keeps the zero crossing
    depth, how = compressive_depth(z, np.array([-400.0, -500.0, -100.0, 40.0, 10.0]))
    assert abs(depth - (0.3 + 0.1 * 100.0 / 140.0)) < 1e-12 and "zero crossing" in how
