"""`peenflow intensity`: measured strips end to end through the command, and bad files as one line, exit 2."""

from __future__ import annotations

import re
import subprocess
import sys

import numpy as np
import pytest

from peenflow.cli import main
from peenflow.study.almen_strips import read_almen_strips
from tasks.measured_intensity import almen_strips_intensity
from peenflow.study.intensity import parse_intensity

INCH_MM = 25.4
# SAE J2597-2017 validation data set 1, target 0.0064 in, +-0.001 in (source: tests/methods/test_measured_strips.py)
SET1 = "# SAE J2597-2017 validation data set 1\ntime_min,arc_height_in\n4,0.0060\n6,0.0069\n8,0.0070\n12,0.0070\n"


def cli(*args):
    return subprocess.run([sys.executable, "-m", "peenflow.cli", "intensity", *map(str, args)],
                          capture_output=True, text=True, timeout=120)


def test_published_set_end_to_end(tmp_path):
    path = tmp_path / "set1.csv"
    path.write_text(SET1)
    proc = cli(path, "--strip", "N")
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    line = next(s for s in out.splitlines() if s.startswith("intensity"))
    mm, shop, model = re.match(r"intensity\s+([\d.]+) mm = (\S+)\s+\((\w+) fit\)", line).groups()
    # the command prints what the library computes, and the shop notation reads back to it
    result = almen_strips_intensity(read_almen_strips(path))
    assert float(mm) == pytest.approx(result.intensity_m * 1e3, abs=5e-5) and model == result.model
    shop_mm, letter = parse_intensity(shop)
    assert letter == "N" and shop_mm == pytest.approx(float(mm), abs=0.05e-3 * INCH_MM)
    assert abs(shop_mm - 0.0064 * INCH_MM) <= 0.001 * INCH_MM  # J2597's target and tolerance
    assert shop == "6.4N"
    # T in the file's unit; each fit's verdict; which one is reported and why
    assert re.search(r"saturation\s+T = [\d.]+ min: doubling the exposure to 2T = [\d.]+ min", out)
    for name in ("exp2", "exp3", "eq10"):
        assert re.search(rf"^  {name} ", out, re.M), name
    assert "p = 50 on its search bound" in out  # eq. (10)'s verdict on this plateau
    assert out.count("<- reported") == 1 and "reported: " in out and "residual standard error" in out


def test_unqualified_intensity_exits_1(tmp_path):
    t = np.array([1, 2, 3, 4, 5, 6.0])  # T = 4.6 min, but no strip at 2T = 9.2 min
    path = tmp_path / "short.csv"
    path.write_text("time_min,arc_height_mm\n" + "".join(f"{x},{0.3 * -np.expm1(-0.5 * x):.6f}\n" for x in t))
    proc = cli(path, "--strip", "A")
    assert proc.returncode == 1, proc.stderr
    assert "NOT QUALIFIED" in proc.stdout and "beyond the longest exposure 6 min" in proc.stdout


def test_a_bad_file_is_one_line_exit_2_no_traceback(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("time_min,arc_height_mm\n4,0.15\n6,-0.17\n")
    proc = cli(path, "--strip", "A")
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert proc.stderr.startswith("peenflow intensity: bad.csv line 3: arc_height_mm = -0.17 is negative")


BAD = [
    ("time_min,arc_height\n4,0.006\n", "does not name its unit"),
    ("time_min,arc_height_in,nozzle\n4,0.006,3\n", "unknown column 'nozzle'"),
    ("time_min,arc_height_in\n4,0.0060\n6,0.0069\n8,x\n", "line 4: arc_height_in = 'x' is not a number"),
    ("time_min,arc_height_in\n4,0.0060\n6,0.0069\n8,0.0070\n", "3 distinct exposure(s)"),
    ("time_min,arc_height_in\n4,0.0060\n6,0.0069\n8,0.0070\n12,0.0050\n", "falls with exposure"),
    ("time_min,arc_height_in\n1,0.001\n2,0.002\n4,0.004\n8,0.008\n", "have not reached saturation"),
    ("time_min,arc_height_in\n", "no data rows"),
]


@pytest.mark.parametrize("text,piece", BAD, ids=[b[1] for b in BAD])
def test_bad_files_in_process(tmp_path, capsys, text, piece):
    path = tmp_path / "strips.csv"
    path.write_text(text)
    assert main(["intensity", str(path), "--strip", "A"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and piece in err and err.startswith("peenflow intensity: strips.csv")


def test_unknown_strip_type_and_missing_file(tmp_path, capsys):
    path = tmp_path / "set1.csv"
    path.write_text(SET1)
    assert main(["intensity", str(path), "--strip", "B"]) == 2
    assert "--strip 'B': expected one of N, A, C" in capsys.readouterr().err
    assert main(["intensity", str(path), "--strip", "a"]) == 0  # the letter in either case
    capsys.readouterr()
    assert main(["intensity", str(tmp_path / "nope.csv"), "--strip", "A"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "nope.csv" in err
