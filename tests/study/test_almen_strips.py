"""Reading measured Almen strips from CSV: units, comments, replicates, and every bad file named by line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from peenflow.study.almen_strips import AlmenStripsError, MeasuredStrips, read_almen_strips, shop_notation, strip_types
from peenflow.study.intensity import parse_intensity
from tasks.measured_intensity import almen_strips_intensity

TEMPLATE = Path(__file__).resolve().parents[2] / "studies" / "data" / "almen_strips_template.csv"
INCH = 0.0254

# SAE J2597-2017 validation data set 1 (source: tests/methods/test_measured_strips.py)
SET1_MIN = [4, 6, 8, 12]
SET1_IN = [0.0060, 0.0069, 0.0070, 0.0070]


def write(tmp_path, text: str, name: str = "strips.csv") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def rows(header: str, xs, ys) -> str:
    return header + "\n" + "".join(f"{x},{y}\n" for x, y in zip(xs, ys))


@pytest.mark.parametrize("column,factor", [("arc_height_in", 1.0), ("arc_height_mm", 25.4), ("arc_height_thou", 1000.0)])
def test_arc_height_units_give_the_same_strips_and_intensity(tmp_path, column, factor):
    strips = read_almen_strips(write(tmp_path, rows(f"time_min,{column}", SET1_MIN,
                                                    [round(v * factor, 6) for v in SET1_IN])))
    assert strips.arc_height_m == pytest.approx([v * INCH for v in SET1_IN], rel=1e-12)
    assert strips.exposure == (240.0, 360.0, 480.0, 720.0) and strips.exposure_unit == "s"
    result = almen_strips_intensity(strips)
    assert abs(result.intensity_m - 0.0064 * INCH) <= 0.001 * INCH  # J2597's target and tolerance


@pytest.mark.parametrize("column,unit,factor", [("passes", "pass", 1.0), ("shots", "shot", 1.0),
                                                ("coverage_percent", "1", 0.01)])
def test_exposure_kinds_and_their_units(tmp_path, column, unit, factor):
    strips = read_almen_strips(write(tmp_path, rows(f"{column},arc_height_in", SET1_MIN, SET1_IN)))
    assert strips.exposure_unit == unit and strips.exposure == pytest.approx([x * factor for x in SET1_MIN])
    in_minutes = almen_strips_intensity(read_almen_strips(write(tmp_path, rows("time_min,arc_height_in", SET1_MIN,
                                                                               SET1_IN), "m.csv")))
    result = almen_strips_intensity(strips)
    # the fit does not care what the exposure counts: same intensity, T in proportion
    assert result.intensity_m == pytest.approx(in_minutes.intensity_m, rel=1e-6)
    assert result.saturation_exposure == pytest.approx(in_minutes.saturation_exposure / 60 * factor, rel=1e-6)


def test_comments_blank_lines_bom_column_order_case_and_replicates(tmp_path):
    text = ("\ufeff# shop test 2024-03, nozzle 3\n\n ARC_HEIGHT_THOU , Time_Min \n"
            "6.0,4\n# second strip at 4 min\n6.2,4\n6.9,6\n\n7.0,8\n7.0,12\n7.1,12\n")
    strips = read_almen_strips(write(tmp_path, text))
    assert strips.line == (4, 6, 7, 9, 10, 11)
    assert strips.exposure == (240.0, 240.0, 360.0, 480.0, 720.0, 720.0)
    assert strips.arc_height_m == pytest.approx([v * INCH * 1e-3 for v in (6.0, 6.2, 6.9, 7.0, 7.0, 7.1)])
    result = almen_strips_intensity(strips)
    assert result.n_strips == 6 and result.n_exposures == 4


def test_shop_notation_reads_back():
    assert shop_notation(0.3048e-3, "a") == "12.0A"
    assert shop_notation(0.0064 * INCH, "N") == "6.4N"
    mm, letter = parse_intensity(shop_notation(0.2e-3, "C"))
    assert letter == "C" and mm == pytest.approx(0.2, abs=0.05e-3 * 25.4)  # one decimal of a thousandth


def test_strip_library_types():
    assert set(strip_types()) == {"N", "A", "C"}


def test_canonical_round_trip(tmp_path):
    strips = read_almen_strips(write(tmp_path, rows("time_min,arc_height_in", SET1_MIN, SET1_IN)))
    again = MeasuredStrips.from_canonical(strips.__canonical__())
    assert again.exposure == strips.exposure and again.arc_height_m == strips.arc_height_m
    assert again.exposure_column == "time_min"
    assert almen_strips_intensity(again).intensity_m == almen_strips_intensity(strips).intensity_m


def test_template_header_is_accepted(tmp_path):
    with pytest.raises(AlmenStripsError, match="has a header but no data rows"):
        read_almen_strips(TEMPLATE)
    text = TEMPLATE.read_text() + "".join(f"{x},{1000 * y}\n" for x, y in zip(SET1_MIN, SET1_IN))
    assert read_almen_strips(write(tmp_path, text)).line == (7, 8, 9, 10)


BAD = [
    # (file text, pieces the one-line message must hold)
    ("# only comments\n", ["no header row", "time_min"]),
    ("time,arc_height_in\n4,0.006\n", ["column 'time' does not name its unit", "expected time_min"]),
    ("time_min,arc_height\n4,0.006\n", ["column 'arc_height' does not name its unit", "arc_height_thou"]),
    ("time_min,height\n4,0.006\n", ["column 'height' does not name its unit"]),
    ("time_min,arc_hieght_mm\n4,0.006\n", ["unknown column 'arc_hieght_mm'", 'did you mean "arc_height_mm"']),
    ("time_min,arc_height_in,operator\n4,0.006,jo\n", ["unknown column 'operator'"]),
    ("time_mins,arc_height_in\n4,0.006\n", ['did you mean "time_min"']),
    ("time_min,passes,arc_height_in\n4,1,0.006\n", ["2 exposure columns (time_min, passes); expected one"]),
    ("arc_height_in\n0.006\n", ["no exposure column"]),
    ("time_min\n4\n", ["no arc-height column"]),
    ("time_min,arc_height_in,arc_height_mm\n4,0.006,0.15\n", ["2 arc-height columns"]),
    ("time_min,time_min,arc_height_in\n4,4,0.006\n", ["column 'time_min' given twice"]),
    ("time_min,time_min\n4,4\n", ["column 'time_min' given twice", "no arc-height column"]),
    ("time_min,arc_height_in\n", ["header but no data rows"]),
    ("time_min,arc_height_in\n4,0.0060\n6,abc\n", ["line 3: arc_height_in = 'abc' is not a number",
                                                   "arc height >= 0 in inches"]),
    ("time_min,arc_height_in\n4,0.0060\nsix,0.0069\n", ["line 3: time_min = 'six' is not a number",
                                                       "exposure > 0 in min"]),
    ("time_min,arc_height_mm\n4,0.15\n6,-0.17\n", ["line 3: arc_height_mm = -0.17 is negative", "in mm"]),
    ("time_min,arc_height_mm\n-4,0.15\n", ["line 2: time_min = -4; expected an exposure > 0"]),
    ("time_min,arc_height_mm\n0,0\n", ["line 2: time_min = 0; expected an exposure > 0", "unpeened strip"]),
    ("time_min,arc_height_mm\n4,nan\n", ["line 2: arc_height_mm = 'nan'"]),
    ("time_min,arc_height_mm\n4,inf\n", ["line 2: arc_height_mm = 'inf'"]),
    ("time_min,arc_height_mm\n4\n", ["line 2: arc_height_mm is missing"]),
    ("time_min,arc_height_mm\n4,0.1,7\n", ["line 2: 3 values under a header of 2 columns"]),
]


@pytest.mark.parametrize("text,pieces", BAD, ids=[b[1][0][:40] for b in BAD])
def test_bad_files_are_refused_naming_what_and_where(tmp_path, text, pieces):
    with pytest.raises(AlmenStripsError) as info:
        read_almen_strips(write(tmp_path, text))
    message = str(info.value)
    assert "\n" not in message and message.startswith("strips.csv")
    for piece in pieces:
        assert piece in message, message


def test_every_bad_line_is_named_up_to_five(tmp_path):
    text = "time_min,arc_height_mm\n" + "".join(f"{i},x\n" for i in range(1, 9))
    with pytest.raises(AlmenStripsError) as info:
        read_almen_strips(write(tmp_path, text))
    assert len(info.value.problems) == 6 and "line 6:" in info.value.problems[4]
    assert info.value.problems[5].endswith("... (3 more bad lines)")


def test_a_trailing_comma_is_not_a_value(tmp_path):
    strips = read_almen_strips(write(tmp_path, "time_min,arc_height_in,\n4,0.006,\n"))
    assert strips.exposure == (240.0,)
    with pytest.raises(AlmenStripsError, match="line 2: 3 values under a header of 2 columns"):
        read_almen_strips(write(tmp_path, "time_min,arc_height_in,\n4,0.006,7\n"))


def test_not_utf8_refused(tmp_path):
    path = tmp_path / "strips.csv"
    path.write_bytes(b"time_min,arc_height_in\n4,0.006\xff\n")
    with pytest.raises(AlmenStripsError, match="not a UTF-8 text file"):
        read_almen_strips(path)


def test_series_problems_name_file_lines_and_units(tmp_path):
    # falling: 7.0 at 8 min, then 5.5 at 12 min (lines 6 and 7 of the file)
    text = "# test\ntime_min,arc_height_thou\n4,6.0\n6,6.9\n8,7.0\n12,5.5\n"
    with pytest.raises(AlmenStripsError, match=r"strips.csv: arc height falls with exposure: 0.1397 mm at 12 min "
                                               r"\(line 6\) against 0.1778 mm at the shorter 8 min \(line 5\)"):
        almen_strips_intensity(read_almen_strips(write(tmp_path, text)), "strips.csv")
    text = "passes,arc_height_thou\n2,6.0\n2,6.1\n4,6.9\n8,7.0\n"
    with pytest.raises(AlmenStripsError, match=r"3 distinct exposure\(s\): 2 passes \(line 2, line 3\); 4 passes"):
        almen_strips_intensity(read_almen_strips(write(tmp_path, text)))


def test_exposure_in_messages_is_in_the_files_unit(tmp_path):
    t = np.array([1, 2, 3, 4, 5, 6.0])
    text = rows("time_min,arc_height_mm", t, np.round(0.3 * -np.expm1(-0.5 * t), 6))
    result = almen_strips_intensity(read_almen_strips(write(tmp_path, text)))
    assert not result.qualified and "2T = 9.21 min beyond the longest exposure 6 min" in result.reason
    assert result.saturation_exposure == pytest.approx(60 * np.log(10) / 0.5, rel=1e-4)  # stored in s
