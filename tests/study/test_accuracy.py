"""The fidelity statement every result carries (peenflow/study/accuracy.py): its numbers are the
measured ones of BENCHMARKS.md 4c, it says when a size was not measured, and results and the
headline carry it."""

import re
from pathlib import Path

from peenflow.study import load_study
from peenflow.study.accuracy import SINGLE_IMPACT, STUDY_LEVEL_INTENSITY, statement

REPO = Path(__file__).resolve().parents[2]


def _benchmarks_summary() -> dict:
    """Physical-element rows of the 'Worst |error|' table of BENCHMARKS.md 4c."""
    text = (REPO / "BENCHMARKS.md").read_text()
    table = text[text.index("Worst |error| over the four cases per element size"):]
    header = next(ln for ln in table.splitlines() if ln.startswith("| form |"))
    cols = [c.strip() for c in header.strip("|").split("|")]
    out = {}
    for ln in table.splitlines()[table.splitlines().index(header) + 2:]:
        if not ln.startswith("|"):
            break
        cells = dict(zip(cols, (c.strip() for c in ln.strip("|").split("|"))))
        if cells["form"] == "physical":
            num = lambda k: float(re.sub(r"[ %]", "", cells[k]))  # noqa: E731
            out[float(cells["h um"])] = (num("dent"), num("σxx peak"), num("zero crossing"), num("restitution"),
                                         num("profile RMS"))
    return out


def test_the_numbers_are_the_measured_ones():
    assert SINGLE_IMPACT == _benchmarks_summary()


def test_a_measured_size_states_its_error_and_an_unmeasured_one_says_so(tmp_path):
    study = load_study(REPO / "studies" / "quickstart.toml")  # coarse, 60 um
    s = statement(study.fidelity)
    assert s["peenflow_fidelity"].startswith("coarse") and "60 um" in s["peenflow_fidelity"]
    assert "dent depth <= 8.4 %" in s["peenflow_fidelity_error"]
    assert "Almen intensity -10.6 ... -9.3 % at 60 um" in s["peenflow_fidelity_error"]
    micro = load_study(REPO / "tests" / "tasks" / "micro.toml")  # 100 um
    assert "not measured at 100 um" in statement(micro.fidelity)["peenflow_fidelity_error"]



def test_the_study_level_numbers_are_the_measured_ones():
    """STUDY_LEVEL_INTENSITY equals what benchmarks/reference/study_level.json gives by the benchmark's
    own rule (Richardson on the three finest levels if monotone with order in [0.5, 4], else the finest
    level), to the 0.1 % it is rounded to."""
    import json
    import sys

    sys.path.insert(0, str(REPO / "benchmarks"))
    from bench_reference import OUT, richardson

    data = json.loads(OUT.read_text())
    errors = {h: [] for h in STUDY_LEVEL_INTENSITY}
    for point in ("strip_90_55", "strip_67_35"):
        hs = [40.0, 25.0, 16.0]
        fs = [data[f"{point}/{h:g}"]["intensity_mm"] for h in hs]
        ref, _ = richardson(hs, fs)
        ref = fs[-1] if ref is None else ref
        for h in STUDY_LEVEL_INTENSITY:
            errors[h].append(100.0 * (data[f"{point}/{h:g}"]["intensity_mm"] / ref - 1.0))
    for h, (lo, hi) in STUDY_LEVEL_INTENSITY.items():
        assert (round(min(errors[h]), 1), round(max(errors[h]), 1)) == (lo, hi), (h, errors[h])
