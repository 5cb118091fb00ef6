"""docs/results.md is the rendering of the one data file of measured figures
(peenflow/study/data/results.toml), the file peenflow.study.accuracy reads the statement on every
result from: a figure changed in one place changes in both, or this fails."""

import fnmatch
import subprocess
import sys
import tomllib
from pathlib import Path

from peenflow.study import accuracy

REPO = Path(__file__).resolve().parents[2]
PAGE = REPO / "docs" / "results.md"


def test_the_results_page_is_the_rendering_of_the_data_file():
    assert PAGE.read_text(encoding="utf-8") == accuracy.markdown(), (
        "docs/results.md differs from the data file: run "
        "`python -m peenflow.study.accuracy --markdown > docs/results.md`")


def test_the_renderer_command_prints_the_page():
    out = subprocess.run([sys.executable, "-m", "peenflow.study.accuracy", "--markdown"], capture_output=True,
                         text=True, check=True, cwd=REPO).stdout
    assert out == PAGE.read_text(encoding="utf-8")


def test_every_statement_figure_is_on_the_page():
    """The numbers the statement states (the module's tables) are the page's rows, as rendered."""
    page = PAGE.read_text(encoding="utf-8")
    for h, (dent, peak, zero, rest, rms) in accuracy.SINGLE_IMPACT.items():
        assert f"| {h:g} | {dent:.1f} % | {peak:.1f} % | {zero:.1f} % | {rest:.3f} | {rms:.1f} % |" in page, h
    for h, (lo, hi, v12a) in accuracy.STUDY_LEVEL.items():
        assert f"| {lo:+.1f} % … {hi:+.1f} % | {v12a:+.1f} % |" in page, h
    for (hr, hd), (pk, cd, rms) in accuracy.TARGET_PROFILE.items():
        assert f"| {hr:g} | {hd:g} | {pk:+.1f} % | {cd:+.1f} % | {rms:.1f} % |" in page, (hr, hd)
    assert f"N_f = {accuracy.N_F_LIMIT:g}" in page and f"σxx = {accuracy.TARGET_PROFILE_PEAK_MPA:g} MPa" in page


def test_the_data_file_is_package_data():
    """The data file lies inside the package and matches pyproject's package-data, so it installs."""
    rel = accuracy.DATA_FILE.relative_to(REPO / "peenflow" / "study").as_posix()
    globs = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]["peenflow.study"]
    assert any(fnmatch.fnmatch(rel, g) for g in globs), (rel, globs)
