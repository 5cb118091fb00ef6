"""One input at a time (``[sensitivity]``) through ``peenflow run`` on the micro meshes.

The friction reaches the strips and the part, the part's Johnson-Cook A the part only; a change that does not
reach a stage shares the baseline's point there. Physics the changes must show: a softer part (lower A) takes
larger dents, so fewer shots cover it (N_f falls) and keeps a smaller residual stress (the peak compression
scales with the flow stress); a harder one the reverse; the velocity for the intensity is the strips' alone."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

import peenflow

from .conftest import cli

HERE = Path(__file__).parent
FRICTION = ("shot.friction_coefficient@0.1", "shot.friction_coefficient@0.4")
SOFT, HARD = "materials.Al7075-T73.johnson_cook.A_MPa@300", "materials.Al7075-T73.johnson_cook.A_MPa@600"




@pytest.fixture(scope="module")
def run(tmp_path_factory):
    d = tmp_path_factory.mktemp("sensitivity")
    shutil.copy(HERE / "micro_sensitivity.toml", d / "s.toml")
    return d / "s.toml", cli("check", d / "s.toml").stdout, cli("run", d / "s.toml", "--workers", "2").stdout


def _points(check_out: str) -> dict[str, int]:
    out = {}
    for line in check_out.splitlines():
        parts = line.split()
        if len(parts) >= 2 and parts[0].endswith(":") and parts[1].isdigit():
            out[parts[0][:-1]] = int(parts[1])
    return out


def test_one_at_a_time_costs_one_point_per_change_and_shares_what_a_change_does_not_reach(run):
    _, check, _ = run
    assert "sensitivity: baseline, " + ", ".join([*FRICTION, SOFT, HARD]) in check  # 0.2 is the baseline
    n = _points(check)
    assert n["strip_runs"] == 2 * 3  # two velocities x (baseline + two friction changes): A does not reach them
    assert n["control_curve"] == 3
    assert n["target_runs"] == 5 and n["target_impact"] == 5  # every change reaches the part
    assert n["sensitivity"] == 1


def test_the_changes_have_the_physics_of_their_inputs(run):
    study, _, _ = run
    s = peenflow.open_result(study, "sensitivity").load()
    names = s.change.attrs["flag_meanings"].split()
    assert names == [*FRICTION, SOFT, HARD]
    at = {n: k for k, n in enumerate(names)}
    dv = s.velocity_change.values
    assert dv[at[SOFT]] == 0.0 and dv[at[HARD]] == 0.0  # the part's material does not touch the control curve
    assert dv[at[FRICTION[0]]] != 0.0 and dv[at[FRICTION[1]]] != 0.0
    nf = s.full_coverage_shots_change.values
    assert nf[at[SOFT]] < 0 < nf[at[HARD]]
    peak = s.peak_compressive_stress_change.values.ravel()  # Pa; the peak is negative: + is less compression
    assert peak[at[SOFT]] > 0 > peak[at[HARD]]
    # the change is against the baseline's own map point, in % of its magnitude
    pmap = peenflow.open_result(study, "process_map").load()
    labels = pmap.sensitivity.attrs["flag_meanings"].split()
    base, hard = (float(pmap.full_coverage_shots.isel(sensitivity=labels.index(n))) for n in ("baseline", HARD))
    assert float(s.full_coverage_shots_change.values[at[HARD]]) == pytest.approx(hard - base, rel=1e-12)
    assert float(s.full_coverage_shots_change_percent.values[at[HARD]]) == pytest.approx(
        100 * (hard - base) / base, rel=1e-12)
    assert s.input_value.values.tolist() == [0.1, 0.4, 300.0, 600.0]


def test_the_report_has_the_tornado_and_the_table(run):
    study, _, out = run
    report = next((study.parent / ".peenflow" / "reports").glob("s-*/report.html"))
    html = report.read_text()
    assert "<h2 id=\"sensitivity\">Sensitivity</h2>" in html and "sensitivity_tornado.png" in html
    assert all(f"<td>{n}</td>" in html for n in (*FRICTION, SOFT, HARD))
    assert (report.parent / "sensitivity_tornado.png").stat().st_size > 10_000
    assert "headline numbers  failed" not in out and "report failed" not in out


@pytest.mark.parametrize("extra, expected", [
    ('[sweep]\n"shot.friction_coefficient" = [0.3]\n', 'sensitivity."shot.friction_coefficient": '
                                                        "shot.friction_coefficient is also in [sweep]"),
    (None, "sensitivity: every value given is the study's own"),
    ("NO_TARGET", "it needs a [target]"),
])
def test_bad_sensitivity_tables_are_refused_before_compute(tmp_path, extra, expected):
    text = (HERE / "micro_sensitivity.toml").read_text()
    if extra is None:
        i, j = text.index("[sensitivity]"), text.index("[fidelity]")
        text = text[:i] + '[sensitivity]\n"shot.friction_coefficient" = [0.2]\n\n' + text[j:]
    elif extra == "NO_TARGET":
        i, j = text.index("[target]"), text.index("[sensitivity]")
        text = text[:i] + text[j:]
    else:
        text += extra
    (tmp_path / "s.toml").write_text(text)
    proc = cli("run", tmp_path / "s.toml", check=False)
    assert proc.returncode != 0 and expected in proc.stdout + proc.stderr, proc.stdout + proc.stderr
    assert not (tmp_path / ".peenflow" / "results").exists()
