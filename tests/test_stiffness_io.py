"""Readers of the robot file and the load tests: bad files named with file and field."""

import numpy as np
import pytest
import yaml

from robomill.io import RawDataError
from robomill.io.robots import read_load_tests, read_robot_file

GOOD = {"name": "kr360", "convention": "mdh", "length_unit": "mm", "angle_unit": "deg",
        "joints": [{"a": 0.0, "alpha": 0.0, "d": 1045.0, "theta_offset": 0.0}] * 6,
        "tool": [150.0, 0.0, 690.0]}


def _robot(tmp_path, **change):
    spec = {**GOOD, **change}
    p = tmp_path / "kr360.yaml"
    p.write_text(yaml.safe_dump(spec))
    return p


def _tests(tmp_path, header=None, rows=None, n=6):
    header = header or (["pose", "role"] + [f"q{i}_deg" for i in range(1, n + 1)]
                        + ["Fx_N", "Fy_N", "Fz_N", "dx_mm", "dy_mm", "dz_mm"])
    rows = rows or [["cube_01", "identify"] + ["1.0"] * (len(header) - 2)]
    p = tmp_path / "load_tests_kr360.csv"
    p.write_text("\n".join(",".join(r) for r in [header, *rows]) + "\n")
    return p


def test_good_files_read(tmp_path):
    robot, spec = read_robot_file(_robot(tmp_path))
    assert robot.convention == "mdh" and robot.n_joints == 6
    assert np.allclose(robot.tool_mm, [150, 0, 690])
    df = read_load_tests(_tests(tmp_path))
    assert df["q6_deg"].dtype == float and df["role"].iloc[0] == "identify"


@pytest.mark.parametrize("change, field", [
    ({"convention": "dh2"}, "convention"),
    ({"joints": GOOD["joints"][:5]}, "joints"),
    ({"joints": [{"a": "x", "alpha": 0, "d": 0}] + GOOD["joints"][1:]}, "joints[0].a"),
    ({"joints": [{"a": 0, "d": 0}] + GOOD["joints"][1:]}, "joints[0]"),
    ({"length_unit": "inch"}, "length_unit"),
    ({"tool": [1.0, 2.0]}, "tool"),
])
def test_bad_robot_file_names_file_and_field(tmp_path, change, field):
    path = _robot(tmp_path, **change)
    with pytest.raises(RawDataError) as exc:
        read_robot_file(path)
    assert str(path) in str(exc.value) and field in str(exc.value)


def test_wrong_joint_count_in_load_tests(tmp_path):
    path = _tests(tmp_path, n=5)
    with pytest.raises(RawDataError, match="q1_deg, q2_deg, q3_deg, q4_deg, q5_deg") as exc:
        read_load_tests(path, 6)
    assert str(path) in str(exc.value) and "6 joints" in str(exc.value)


def test_missing_column_named(tmp_path):
    header = ["pose", "role"] + [f"q{i}_deg" for i in range(1, 7)] + [
        "Fx_N", "Fy_N", "Fz_N", "dx_mm", "dy_mm"]
    path = _tests(tmp_path, header=header)
    with pytest.raises(RawDataError, match="dz_mm") as exc:
        read_load_tests(path)
    assert str(path) in str(exc.value)


def test_non_numeric_value_named(tmp_path):
    row = ["cube_01", "identify"] + ["1.0"] * 6 + ["abc"] + ["1.0"] * 5
    path = _tests(tmp_path, rows=[row])
    with pytest.raises(RawDataError, match="row 2, column Fx_N"):
        read_load_tests(path)


def test_bad_role_named(tmp_path):
    row = ["cube_01", "calibrate"] + ["1.0"] * 12
    with pytest.raises(RawDataError, match="column role"):
        read_load_tests(_tests(tmp_path, rows=[row]))
