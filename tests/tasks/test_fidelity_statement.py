"""Every result of a study records the fidelity that made it and what that fidelity is measured to
cost (peenflow/study/accuracy.py through graph.result_attrs), and the headline says it."""

import glob

import xarray as xr

from peenflow.study import load_study
from peenflow.study.accuracy import statement


def test_every_micro_result_and_the_headline_carry_the_statement(micro):
    want = statement(load_study(micro).fidelity)
    files = glob.glob(str(micro.parent / ".peenflow" / "results" / "*" / "*.nc"))
    assert len(files) >= 15
    for f in files:
        with xr.open_dataset(f) as ds:
            assert ds.attrs["peenflow_fidelity"] == want["peenflow_fidelity"], f
            assert ds.attrs["peenflow_fidelity_error"] == want["peenflow_fidelity_error"], f
    log = micro.with_name("run.log").read_text()
    assert "  fidelity " in log and "not measured at 100 um" in log
