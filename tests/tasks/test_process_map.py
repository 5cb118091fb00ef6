"""Process maps end to end through ``peenflow run`` on the micro meshes: a 2 x 2 intensity x coverage map,
coverage levels from one run, a [sweep] of a shot key, named targets, requirements met and not, and every
bad list refused before compute."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import peenflow

from .conftest import cli
import peenflow.api
from peenflow.study import load_study
from peenflow.testing import assert_cf_variables
from tasks._rev_run import run_rev
from tasks.params import study_family
from tasks.target_runs import coverage_ladder

HERE = Path(__file__).parent
MAP = (HERE / "micro_map.toml").read_text()




@pytest.fixture(scope="module")
def mapped(tmp_path_factory):
    """The micro map, run once: (study path, run output)."""
    d = tmp_path_factory.mktemp("map")
    shutil.copy(HERE / "micro_map.toml", d / "micro_map.toml")
    out = cli("run", d / "micro_map.toml", "--workers", "2").stdout
    return d / "micro_map.toml", out


def _write(d: Path, name: str, text: str) -> Path:
    path = d / f"{name}.toml"
    path.write_text(text.replace('name = "micro_map"', f'name = "{name}"'))
    return path


def test_the_map_has_a_dimension_per_list_and_every_feature_in_si(mapped):
    study, _ = mapped
    pmap = peenflow.open_result(study, "process_map").load()
    assert pmap.attrs["process_dims"] == "almen_intensity_m"
    np.testing.assert_allclose(pmap.almen_intensity_m.values, [0.30e-3, 0.38e-3], rtol=1e-12)
    np.testing.assert_array_equal(pmap.coverage_percent.values, [100.0, 200.0])
    assert pmap.stress_xx_mean_Pa.dims == ("almen_intensity_m", "coverage_percent", "depth")
    assert pmap.depth_m.attrs["positive"] == "down" and pmap.depth_m.attrs["units"] == "m"
    assert_cf_variables(pmap, si=True)
    for name in ("surface_stress_xx_Pa", "peak_compressive_xx_Pa", "peak_compressive_xx_depth_m",
                 "compressive_depth_xx_m", "coverage_shots"):
        assert pmap[name].dims == ("almen_intensity_m", "coverage_percent") and np.all(np.isfinite(pmap[name]))
    # compressive at the surface, the peak at least as compressive, inside the part
    assert np.all(pmap.surface_stress_xx_Pa < 0) and np.all(pmap.peak_compressive_xx_Pa <= pmap.surface_stress_xx_Pa)
    assert np.all((pmap.compressive_depth_xx_m > 0) & (pmap.compressive_depth_xx_m < 1e-3))
    # a higher intensity needs a faster shot; twice the coverage twice the shots (N_c = c N_f)
    v = pmap.velocity_m_s.values
    assert v[1] > v[0]
    np.testing.assert_allclose(pmap.coverage_shots.sel(coverage_percent=200.0) / pmap.coverage_shots.sel(
        coverage_percent=100.0), 2.0, rtol=0.02)
    # micro meshes are not where errors were measured: said so, not borrowed
    assert not pmap.error_measured.values.any() and np.isnan(pmap.peak_error_percent.values).all()
    assert "Al7075-T73" in pmap.attrs["error_basis"]
    # the file opens alone with plain xarray
    f = next(Path(p) for p in re.findall(r"\S+\.nc", cli("show", study, "process_map").stdout))
    with xr.open_dataset(f) as alone:
        assert "stress_xx_mean_Pa" in alone


def test_a_coverage_list_costs_one_rev_run_per_intensity_and_sequence(mapped):
    study, out = mapped
    runs = [line for line in out.splitlines() if "computed" in line and "target_runs[" in line]
    assert len(runs) == 2  # 2 intensities x 1 sequence, not x 2 coverage levels
    check = cli("check", study).stdout
    assert re.search(r"target_runs: 2\s+\(per almen_intensity_m\)", check)
    assert "almen_intensity_m: 0.3, 0.38 mm" in check and "coverage levels: 100, 200 %" in check
    # status counts the points per dimension
    status = cli("status", study).stdout
    assert re.search(r"target_runs\s+2 point\(s\): 2 done\n\s+by almen_intensity_m: 0.3 mm 1/1 done, 0.38 mm 1/1 done",
                     status), status


def test_the_largest_level_equals_a_separate_run_to_that_coverage(mapped):
    """A coverage list's run goes to the largest level: its profile there is the one a separate study at that
    coverage alone computes, bit for bit (same seed, same stream, same snapshots)."""
    study, _ = mapped
    single = _write(study.parent, "single", MAP.replace("almen_intensity_mm = [0.30, 0.38]", "almen_intensity_mm = 0.30")
                    .replace("coverage_percent = [100.0, 200.0]", "coverage_percent = 200.0"))
    out = cli("run", single).stdout
    assert "computed" in out and "target_runs[sequence=0]" in out  # its own run, to 200 % only
    alone = peenflow.open_result(single, "target_runs").load()
    family = peenflow.open_result(study, "target_runs").load().sel(almen_intensity_m=0.30e-3, method="nearest")
    assert int(alone.shots.values[-1]) == int(family.coverage_shots.sel(coverage_percent=200.0).values.ravel()[0])
    np.testing.assert_array_equal(np.squeeze(alone.stress_xx_Pa.sel(coverage_percent=200.0).values),
                                  np.squeeze(family.stress_xx_Pa.sel(coverage_percent=200.0).values))


def test_a_snapshot_equals_the_sequence_stopped_at_that_coverage(mapped):
    """The profile at a lower level is the state after that level's N_c shots of the same sequence, relaxed:
    bit for bit the result of that sequence stopped there (the snapshot's relaxation leaves the run untouched)."""
    study, _ = mapped
    s = load_study(study)
    p = study_family(s).first
    family = peenflow.open_result(study, "target_runs").load().sel(almen_intensity_m=0.30e-3, method="nearest")
    rev = peenflow.open_result(study, "target_rev").load()
    n_1, n_2 = (int(family.coverage_shots.sel(coverage_percent=c).values.ravel()[0]) for c in (100.0, 200.0))
    seed = p.target_plan.seeds[0]
    speed = float(peenflow.open_result(study, "target_velocity").sel(almen_intensity_m=0.30e-3, method="nearest")
                  .velocity_m_s)
    common = dict(material=p.target_material, shot=p.shot, fidelity=p.fidelity,
                  side_m=float(rev.rev_side_m.values.ravel()[0]), measure_side_m=float(rev.measure_side_m.values.ravel()[0]),
                  thickness_m=float(rev.thickness_m.values.ravel()[0]), angle_deg=90.0, velocity_m_s=speed, seed=seed)
    through = run_rev(None, ladder=coverage_ladder([n_1, n_2]), **common)  # the map's rungs
    stopped = run_rev(None, ladder=[n_1], sequence_shots=n_2, **common)
    np.testing.assert_array_equal(through.stress_xx_Pa.sel(shots=n_1).values, stopped.stress_xx_Pa.sel(shots=n_1).values)
    np.testing.assert_array_equal(through.stress_yy_Pa.sel(shots=n_1).values, stopped.stress_yy_Pa.sel(shots=n_1).values)
    # and the map's run holds that same state at 100 % (it ran as a lone point on 2 kernel threads, whose sums
    # in another order differ in the last digits: 1e-13 relative, against 1e-2 between sequences)
    np.testing.assert_allclose(np.squeeze(family.stress_xx_Pa.sel(coverage_percent=100.0).values),
                               through.stress_xx_Pa.sel(shots=n_1).values, rtol=1e-11)


def test_a_sweep_of_a_shot_key_shares_what_it_does_not_reach(mapped):
    study, _ = mapped
    swept = _write(study.parent, "swept", MAP.replace("almen_intensity_mm = [0.30, 0.38]", "almen_intensity_mm = 0.30")
                   .replace("[requirements]", '[sweep]\n"shot.friction_coefficient" = [0.1, 0.2]\n\n[requirements]'))
    check = cli("check", swept).stdout
    assert "shot_friction_coefficient: 0.1, 0.2" in check
    assert re.search(r"strip_runs: 4\s+\(per shot_friction_coefficient\)", check)  # friction reaches the strips
    out = cli("run", swept).stdout
    pmap = peenflow.open_result(swept, "process_map").load()
    assert pmap.attrs["process_dims"] == "shot_friction_coefficient"
    base = peenflow.open_result(study, "process_map").load().isel(almen_intensity_m=0)
    # friction 0.2 is the map's own point: reused (nothing of it recomputed), the same numbers
    np.testing.assert_array_equal(pmap.sel(shot_friction_coefficient=0.2).stress_xx_mean_Pa.values,
                                  base.stress_xx_mean_Pa.values)
    assert sum("computed" in line and "strip_runs[" in line for line in out.splitlines()) == 2  # only friction 0.1's
    assert not np.array_equal(pmap.sel(shot_friction_coefficient=0.1).stress_xx_mean_Pa.values,
                              base.stress_xx_mean_Pa.values)


def test_named_targets_are_a_dimension(mapped):
    study, _ = mapped
    target = re.search(r"\[target\]\n(.*?)\n\n", MAP, re.S).group(1)
    web = target.replace("almen_intensity_mm = [0.30, 0.38]", "almen_intensity_mm = 0.30")
    fillet = web.replace("angle_deg = 90.0", "angle_deg = 65.0")
    text = MAP.replace(f"[target]\n{target}\n", f"[targets.web]\n{web}\n\n[targets.fillet]\n{fillet}\n")
    named = _write(study.parent, "named", text)
    cli("run", named)
    pmap = peenflow.open_result(named, "process_map").load()
    assert pmap.target.attrs["flag_meanings"] == "web fillet"
    web_point = pmap.sel(target=0)
    base = peenflow.open_result(study, "process_map").load().isel(almen_intensity_m=0)
    np.testing.assert_array_equal(web_point.stress_xx_mean_Pa.values, base.stress_xx_mean_Pa.values)
    # the oblique fillet: the same shot speed at 65 deg has 0.91 of the normal velocity (0.82 of the normal
    # energy) and leaves a shallower compressive layer, on the in-plane mean of sigma_xx and sigma_yy at
    # each coverage (sigma_xx alone, along the shots' drag, is within one sequence's scatter of the web's)
    def depth(pt):
        return (pt.compressive_depth_xx_m + pt.compressive_depth_yy_m).values / 2

    assert np.all(depth(pmap.sel(target=1)) < depth(web_point))


def test_a_requirement_met_names_the_least_coverage_and_one_not_met_the_closest_point(mapped):
    study, out = mapped
    s = peenflow.open_result(study, "suggested_settings").load()
    pmap = peenflow.open_result(study, "process_map").load()
    ok = (pmap.compressive_depth_xx_m >= 0.2e-3) & (pmap.surface_stress_xx_Pa <= -250e6)
    assert int(s.met) == 1 and bool(ok.any())
    assert float(s.minimised_value) == pytest.approx(float(pmap.coverage_percent.where(ok.any("almen_intensity_m"))
                                                           .min()))
    assert np.all(s.requirement_margin.values >= 0)
    assert "suggested settings" in out and "met: least coverage_percent 100 %" in out
    strict = _write(study.parent, "strict", MAP.replace("{ min = 0.2 }", "{ min = 5.0 }"))
    out = cli("run", strict).stdout
    s = peenflow.open_result(strict, "suggested_settings").load()
    assert int(s.met) == 0 and np.isnan(float(s.minimised_value))
    deepest = float(pmap.compressive_depth_xx_m.max())
    assert "none meets" in out and "compressive_depth_mm misses by" in s.attrs["verdict"]
    # the closest point is the deepest layer: its miss is (5 mm - that depth) / 5 mm
    assert float(s.requirement_margin.min()) == pytest.approx((deepest - 5e-3) / 5e-3, rel=1e-9)


def test_the_report_has_a_process_map_section(mapped):
    """report.html: the map's figures, one feature row per point and coverage level in MPa / mm / shop
    notation, and the suggestion with each requirement's margin."""
    from peenflow.report import report_dir

    study, _ = mapped
    page = (report_dir(peenflow.api.open_store(study), study) / "report.html").read_text()
    section = page[page.index('<h2 id="process-map">'):page.index('<h2 id="figures">')]
    assert section.count("data:image/png;base64,") == 2  # map_profiles.png, map_features.png
    assert "map_profiles.png" not in page[page.index('<h2 id="figures">'):]  # shown once, in its section
    pmap = peenflow.open_result(study, "process_map").load()
    rows = re.findall(r"<tr><td>([^<]*)</td>", section)
    assert len([r for r in rows if r.endswith(" %")]) == pmap.sizes["almen_intensity_m"] * pmap.sizes["coverage_percent"]
    first = pmap.isel(almen_intensity_m=0, coverage_percent=0)
    assert f"{float(first.peak_compressive_xx_Pa) / 1e6:.0f}" in section  # MPa
    assert f"{float(first.compressive_depth_xx_m) * 1e3:.3f}" in section  # mm
    assert "unmeasured" in section and "Suggested settings" in section and "margin to its bound" in section


@pytest.mark.parametrize("old, new, expected", [
    ("almen_intensity_mm = [0.30, 0.38]", "almen_intensity_mm = []", "target.almen_intensity_mm = []: an empty list"),
    ("almen_intensity_mm = [0.30, 0.38]", "almen_intensity_mm = [0.30, 0.30]", "duplicate value 0.3"),
    ("[requirements]", '[sweep]\n"shot.friction" = [0.1, 0.2]\n\n[requirements]', "no key 'friction'"),
    ("[requirements]", '[sweep]\n"execution.workers" = [1, 2]\n\n[requirements]', "changes no result"),
    ("[requirements]", '[sweep]\n"target.angle_deg" = [60.0, 90.0]\n\n[requirements]', "swept as a list in [target]"),
    ("[requirements]", '[sweep]\n"almen.velocities_m_s" = [1.0, 2.0]\n\n[requirements]', "already a list"),
    ("[requirements]", '[sweep]\n"materials.Unobtainium.density_kg_m3" = [1.0, 2.0]\n\n[requirements]',
     "no material 'Unobtainium'"),
    ("[requirements]", '[sweep]\n"materials.Ti6Al4V.johnson_cook.C" = [0.0, 0.01]\n\n[requirements]',
     "reaches no stage"),
    ("almen_strip = \"A\"", "almen_strip = \"A\"\nvelocity_m_s = [40.0, 50.0]", "give exactly one of"),
    ('minimise = "coverage_percent"', 'minimise = "money"', "requirements.minimise"),
    ("{ min = 0.2 }", "{ least = 0.2 }", "requirements"),
])
def test_a_bad_list_is_refused_before_compute(tmp_path, old, new, expected):
    assert old in MAP
    bad = _write(tmp_path, "bad", MAP.replace(old, new, 1))
    proc = cli("check", bad, check=False)
    assert proc.returncode == 2 and expected in proc.stdout + proc.stderr, proc.stdout + proc.stderr
    assert "Traceback" not in proc.stderr
    assert not (tmp_path / ".peenflow").exists()  # nothing computed, nothing stored
