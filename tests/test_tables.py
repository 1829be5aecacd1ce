"""The shared CSV reader names file, row and column for every malformed input."""

import numpy as np
import pytest

from robomill.io import RawDataError
from robomill.io.tables import check_uniform, read_numeric_csv


def _write(tmp_path, text):
    p = tmp_path / "f.csv"
    p.write_text(text)
    return p


def test_good_file(tmp_path):
    df = read_numeric_csv(_write(tmp_path, "x_mm,z_um\n0,1\n1,2\n"), ["x_mm", "z_um"])
    assert df["z_um"].tolist() == [1.0, 2.0]


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("", "empty"),
        ("x_mm,z_um\n", "header only"),
        ("x_mm,z_mm\n0,1\n", "column 'z_um' is missing.*unit 'mm'"),
        ("x_mm,zz_um\n0,1\n", "misspelling"),
        ("x_mm,z_um\n0,abc\n", r"row 2, column z_um.*'abc' is not a number"),
        ("x_mm,z_um\n0,1\n1,nan\n", "row 3, column z_um"),
        ("x_mm,z_um\n0,1\n1,inf\n", "not finite"),
        ("x_mm,z_um\n0,1\n1\n", "row 3.*truncated"),
        ("x_mm;z_um\n0;1\n", "separated by semicolons; the contract requires commas"),
        ("x_mm\tz_um\n0\t1\n", "separated by tabs"),
    ],
)
def test_bad_files_are_explained(tmp_path, text, match):
    p = _write(tmp_path, text)
    with pytest.raises(RawDataError, match=match) as info:
        read_numeric_csv(p, ["x_mm", "z_um"])
    assert str(p) in str(info.value)


def test_uniform_axis_checks(tmp_path):
    p = tmp_path / "f.csv"
    assert check_uniform(p, np.arange(10) * 0.5, "x_mm") == pytest.approx(0.5)
    with pytest.raises(RawDataError, match="not uniformly spaced"):
        check_uniform(p, np.array([0, 1, 2, 3.5, 4.5]), "x_mm")
    with pytest.raises(RawDataError, match="not strictly increasing"):
        check_uniform(p, np.array([0, 1, 0.5]), "x_mm")
    with pytest.raises(RawDataError, match="from the manifest"):
        check_uniform(p, np.arange(10) * 0.5, "t_s", step=0.25)
