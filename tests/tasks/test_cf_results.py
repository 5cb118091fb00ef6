"""Every stored result of the micro study follows the CF conventions and opens with standard xarray tools."""

import ctypes.util
import re
import shutil
import subprocess
import sys
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

import peenflow
from peenflow.engine.conventions import cf_problems, units_ok
from peenflow.testing import assert_cf_variables

#: the offline CF tables the checker reads instead of downloading them (empty tables: tests/data/cf-tables/README.md)
STUB_TABLES = Path(__file__).resolve().parents[1] / "data" / "cf-tables"
#: standard names we use that are in the CF table; the offline stub table is
#: empty, so the checker reports them as unknown -- the only error it may give
KNOWN_STANDARD_NAMES = {"depth"}


def result_files(study: Path) -> list[Path]:
    files = sorted((study.parent / ".peenflow" / "results").glob("*/*.nc"))
    assert len(files) >= 15, files  # every point of the micro study
    return files


def test_units_rule_accepts_udunits_and_refuses_what_the_issue_found():
    for good in ("1", "m", "m s-1", "m/s", "Pa", "MPa", "mm", "N m", "m2", "%", "degree", "s", "m-1", "N"):
        assert units_ok(good), good
    for bad in ("shots", "1/shot", "", "mm/shots", "MPa per m"):
        assert not units_ok(bad), bad


def test_every_result_follows_the_conventions(micro):
    """The checker's rules stated explicitly, so the default suite checks CF without cfchecker."""
    for f in result_files(micro):
        with xr.open_dataset(f) as ds:
            assert cf_problems(ds) == [], f"{f.parent.name}/{f.name}"
            assert ds.attrs["source"].startswith(f"peenflow {peenflow.__version__}")
            assert ds.attrs["peenflow_source_hash"] in ds.attrs["source"]  # the code fingerprint
        with netCDF4.Dataset(f) as nc:  # on disk: no variable-length strings at all
            for name, v in nc.variables.items():
                assert v.dtype is not str, f"{f.name}: {name} is a variable-length string"


def test_the_store_is_si(micro):
    """Lengths in m, stresses in Pa, speeds in m s-1 (no mm, um or MPa): the display units are the edges' job."""
    for f in result_files(micro):
        with xr.open_dataset(f) as ds:
            assert_cf_variables(ds, si=True)


def test_depth_is_a_downward_coordinate_and_sweep_values_are_dimensions(micro):
    runs = sorted((micro.parent / ".peenflow" / "results" / "strip_runs").glob("*.nc"))
    assert len(runs) == 2
    for f in runs:
        with xr.open_dataset(f) as ds:
            for d in ("angle_deg", "velocity_m_s", "sequence"):
                assert ds.sizes[d] == 1 and d in ds.indexes, d
            assert ds.angle_deg.attrs["units"] == "degree" and ds.velocity_m_s.attrs["units"] == "m s-1"
            assert "depth_m" in ds.coords and ds.depth_m.attrs["positive"] == "down"
            z = ds.depth_m.squeeze().values
            assert z[0] > 0 and np.all(np.diff(z) > 0)  # increasing downward from the peened surface
            names = ds.component.attrs["flag_meanings"].split()
            assert names[:2] == ["xx", "yy"] and list(ds.component.values) == list(range(6))
            # the flagged component 0 is sigma_xx: the same numbers as the stress_xx_Pa profile
            np.testing.assert_array_equal(ds.stress_mean_Pa.sel(component=0).values, ds.stress_xx_Pa.values)


def test_open_mfdataset_by_coords_assembles_the_strip_sweep(micro):
    files = sorted((micro.parent / ".peenflow" / "results" / "strip_runs").glob("*.nc"))
    with xr.open_mfdataset(files, combine="by_coords", data_vars="minimal", coords="minimal",
                           compat="override", combine_attrs="drop_conflicts") as mf:
        assert mf.sizes["velocity_m_s"] == 2 and list(mf.velocity_m_s.values) == [30.0, 55.0]
        ours = peenflow.open_result(micro, "strip_runs")
        np.testing.assert_array_equal(mf.stress_xx_Pa.transpose(*ours.stress_xx_Pa.dims).values,
                                      ours.stress_xx_Pa.values)


def test_open_result_is_lazy_and_keeps_provenance(micro):
    import dask.array

    runs = peenflow.open_result(micro, "strip_runs")
    assert isinstance(runs.stress_xx_Pa.data, dask.array.Array)  # nothing read yet
    assert runs.attrs["Conventions"] == "CF-1.11"
    assert runs.attrs["peenflow_task"] == "strip_runs"  # shared by the points
    import json

    points = json.loads(runs.attrs["peenflow_points"])
    assert sorted(p["peenflow_point"] for p in points) == [
        "strip_runs[angle_deg=90,velocity_m_s=30,sequence=0]", "strip_runs[angle_deg=90,velocity_m_s=55,sequence=0]"]
    assert all(p["peenflow_wall_s"] > 0 and p["peenflow_host"] for p in points)
    eager = peenflow.open_result(micro, "strip_runs", lazy=False)
    xr.testing.assert_identical(runs.load(), eager)


def _cfchecker_or_skip():
    if ctypes.util.find_library("udunits2") is None:
        pytest.skip("the udunits2 C library is missing; install Debian's libudunits2-0 (.ci/run does)")
    try:
        from cfchecker import cfchecks  # noqa: F401  (loads udunits2 through cfunits)
    except ImportError as exc:
        pytest.skip(f"cfchecker is not installed ({exc}); `pip install cfchecker` runs the external CF check")
    except (OSError, AttributeError) as exc:  # a udunits2 that cannot be loaded
        pytest.skip(f"cfchecker cannot load udunits2 ({exc}); install Debian's libudunits2-0")
    exe = Path(sys.executable).with_name("cfchecks")
    return str(exe) if exe.exists() else shutil.which("cfchecks")


def test_the_offline_cf_tables_ship_with_the_tests():
    """The checker's offline tables are in the repository, so a fresh clone runs the CF check (with udunits2)."""
    for name in ("standard_name_table.xml", "area_type_table.xml", "region_names.xml"):
        assert (STUB_TABLES / name).is_file(), STUB_TABLES / name


def test_cf_checker_finds_no_errors_or_warnings(micro, tmp_path):
    """cfchecker 4.1 on every result.  It knows the rules up to CF-1.8 and refuses
    the newer version string, so it checks a copy declared CF-1.8 (the rules
    from 1.9 to 1.11 add nothing these files use)."""
    exe = _cfchecker_or_skip()
    for f in result_files(micro):
        copy = tmp_path / f.name
        shutil.copy(f, copy)
        with netCDF4.Dataset(copy, "a") as nc:
            nc.Conventions = "CF-1.8"
        out = subprocess.run([exe, "-s", str(STUB_TABLES / "standard_name_table.xml"),
                              "-a", str(STUB_TABLES / "area_type_table.xml"),
                              "-r", str(STUB_TABLES / "region_names.xml"), "-v", "1.8", str(copy)],
                             capture_output=True, text=True, timeout=300).stdout
        errors = [e for e in re.findall(r"^ERROR: (.*)$", out, re.M)
                  if not any(e == f"(3.3): Invalid standard_name: {n}" for n in KNOWN_STANDARD_NAMES)]
        warnings = re.findall(r"^WARN: (.*)$", out, re.M)
        assert "ERRORS detected" in out, out[-2000:]
        assert errors == [] and warnings == [], f"{f.parent.name}/{f.name}: {errors} {warnings}"
