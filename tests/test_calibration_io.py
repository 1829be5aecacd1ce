"""Bad C-Track files get a clear RawDataError naming the file and the field."""

import pytest

from robomill.io import RawDataError
from robomill.io.ctrack import read_circles, read_steps


def _circles(tmp_path, rows):
    p = tmp_path / "circles.csv"
    p.write_text("joint,q_deg,x_mm,y_mm,z_mm\n" + "\n".join(rows) + "\n")
    return p


def _full_circles():
    return [f"{j},{q},{100 + q},{j},{q * 2}" for j in range(1, 7) for q in (0, 10, 20, 30)]


def test_good_circles_read(tmp_path):
    assert len(read_circles(_circles(tmp_path, _full_circles()))) == 24


def test_nan_coordinate_is_named(tmp_path):
    rows = _full_circles()
    rows[5] = "2,10,nan,2,20"
    with pytest.raises(RawDataError, match=r"circles\.csv.*row 7, column x_mm.*not a number"):
        read_circles(_circles(tmp_path, rows))


def test_too_few_points_for_a_circle(tmp_path):
    rows = [r for r in _full_circles() if not (r.startswith("3,") and ",20," in r or
                                               r.startswith("3,30"))]
    with pytest.raises(RawDataError, match=r"circles\.csv.*joint = 3.*joint 3 has 2 circle"):
        read_circles(_circles(tmp_path, rows))


def test_step_from_one_direction_only(tmp_path):
    p = tmp_path / "steps.csv"
    rows = ["joint,step,q_deg,direction,x_mm,y_mm,z_mm"]
    for j in range(1, 3):
        for k, q in enumerate((0.0, 0.5, 1.0)):
            for d in (1, -1):
                if j == 2 and q == 0.5 and d == -1:
                    continue
                rows.append(f"{j},{k},{q},{d},1,2,3")
    p.write_text("\n".join(rows) + "\n")
    with pytest.raises(RawDataError, match=r"steps\.csv.*column direction.*joint 2 step at "
                                           r"q = 0.5 deg is measured from one direction only"):
        read_steps(p)
