"""Readers that know real exports (item 4): a native file handed to a contract
reader names its format and the import command (``robomill.importers.sniff``)."""

from __future__ import annotations

import ast
import shutil
import sys
from pathlib import Path

import pytest

from robomill.importers import sniff
from robomill.io import RawDataError
from robomill.io.forces import read_forces
from robomill.io.profiles import read_profile
from robomill.io.tables import read_numeric_csv
from robomill.io.tracker import read_tracker

DATA = Path(__file__).parent / "data"
NATIVE = {
    "dynoware": DATA / "constructed" / "dynoware" / "slot_s1_g1_px.txt",
    "tdms": DATA / "real" / "tdms" / "raw1.tdms",
    "x3p": DATA / "real" / "x3p" / "sample-land_rows4-7.x3p",
    "smats": DATA / "constructed" / "smats" / "two_profiles.sdf",
    "spatialanalyzer": DATA / "constructed" / "spatialanalyzer" / "py_f2.txt",
    "faro": DATA / "constructed" / "faro" / "px_f1.csv",
}


@pytest.mark.parametrize("fmt", sorted(NATIVE))
def test_sniff_recognises_each_format(fmt):
    assert sniff.sniff(NATIVE[fmt]) == fmt
    h = sniff.hint(NATIVE[fmt])
    assert h.startswith(f"looks like {sniff.NAMES[fmt]}: run robomill import {fmt} ")
    assert "--to RAW_DIR" in h


@pytest.mark.parametrize("path, fmt", [
    (DATA / "real" / "smats" / "mm11_iso1_ascii_int32.sdf", "smats"),
    (DATA / "constructed" / "dynoware" / "dynoware25_window.csv", "dynoware"),
    (DATA / "constructed" / "spatialanalyzer" / "px_f2_sa2024.txt", "spatialanalyzer"),
    (DATA / "real" / "impact" / "lvm_read_long_single_header_multi_ch.lvm", "lvm"),
    (DATA / "real" / "impact" / "lvm_read_short.lvm", "lvm"),
    (DATA / "real" / "smats" / "npl_sine.xml", "smats"),
])
def test_sniff_recognises_the_real_layouts(path, fmt):
    """A real MountainsMap SDF (CRLF), and the layouts of the real DynoWare 2.5 and SA 2024.2
    exports (tests/data/real/*/SOURCE.md)."""
    assert sniff.sniff(path) == fmt


def test_sniff_leaves_contract_files_alone():
    for p in (DATA / "bad" / "forces" / "missing_column.csv",
              DATA / "constructed" / "smats" / "sine.txt"):
        assert sniff.sniff(p) is None and sniff.hint(p) is None
    assert sniff.sniff(DATA / "does-not-exist.csv") is None


def test_sniff_uff(tmp_path):
    import numpy as np
    import pyuff

    path = tmp_path / "hits.uff"
    ds = pyuff.prepare_58(func_type=1, rsp_node=1, rsp_dir=1, ref_node=1, ref_dir=1,
                          data=np.sin(np.arange(64.0)), x=np.arange(64) / 1000.0, id1="hit",
                          abscissa_spacing=1, abscissa_spec_data_type=17,
                          ordinate_spec_data_type=12, orddenom_spec_data_type=13)
    pyuff.UFF(str(path)).write_sets([ds], mode="overwrite")
    assert sniff.sniff(path) == "uff"
    assert sniff.hint(path) == ("looks like a UFF (universal file format) file: run robomill "
                                "import uff hits.uff --to RAW_DIR")


@pytest.mark.parametrize("fmt", sorted(NATIVE))
def test_force_reader_names_the_format(fmt, tmp_path):
    """The issue's case: a native export renamed forces/<cut>.csv → not a bare 'column t_s is
    missing' but the format and the command."""
    dst = tmp_path / "forces" / "s1_g1_px.csv"
    dst.parent.mkdir()
    shutil.copy(NATIVE[fmt], dst)
    with pytest.raises(RawDataError) as info:
        read_forces(dst, 10000.0)
    msg = str(info.value)
    assert msg.startswith(str(dst))
    assert f"looks like {sniff.NAMES[fmt]}: run robomill import {fmt} s1_g1_px.csv" in msg


def test_messages_per_reader(tmp_path):
    dyno = tmp_path / "forces.csv"
    shutil.copy(NATIVE["dynoware"], dyno)
    with pytest.raises(RawDataError, match=r"header \(row 1\): column 't_s' is missing; looks "
                                           r"like a Kistler DynoWare export: run robomill "
                                           r"import dynoware forces.csv --to RAW_DIR --cut CUT"):
        read_forces(dyno, 10000.0)
    with pytest.raises(RawDataError, match=r"unknown file type '.txt'; looks like a Kistler "
                                           r"DynoWare export: run robomill import dynoware"):
        read_forces(NATIVE["dynoware"], 10000.0)
    with pytest.raises(RawDataError, match=r"unknown file type '.tdms'; looks like an NI TDMS "
                                           r"file: run robomill import tdms raw1.tdms"):
        read_forces(NATIVE["tdms"], 50000.0)
    sa = tmp_path / "py_f2.csv"
    shutil.copy(NATIVE["spatialanalyzer"], sa)
    with pytest.raises(RawDataError, match=r"looks like a SpatialAnalyzer point export: run "
                                           r"robomill import spatialanalyzer py_f2.csv --to "
                                           r"RAW_DIR --direction DIR --feed-mm-s FEED"):
        read_tracker(sa, fs_hz=815.0)
    x3p = tmp_path / "s1_g1_px.csv"
    shutil.copy(NATIVE["x3p"], x3p)
    with pytest.raises(RawDataError, match=r"not UTF-8 text .*; looks like an ISO 25178-72 X3P "
                                           r"file: run robomill import x3p s1_g1_px.csv"):
        read_profile(x3p)
    sdf = tmp_path / "p.csv"
    shutil.copy(NATIVE["smats"], sdf)
    with pytest.raises(RawDataError, match=r"looks like a NIST SMATS / SDF profile"):
        read_numeric_csv(sdf, ["x_mm", "z_um"])


def test_plain_csv_errors_unchanged(tmp_path):
    p = tmp_path / "p.csv"
    p.write_text("x_mm,z_mm\n" + "".join(f"{k},0\n" for k in range(70)))
    with pytest.raises(RawDataError) as info:
        read_profile(p)
    assert "looks like" not in str(info.value)
    assert "column 'z_mm' is in unit 'mm'" in str(info.value)


def test_sniff_imports_only_the_standard_library():
    tree = ast.parse(Path(sniff.__file__).read_text())
    mods = {a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.Import)
            for a in n.names}
    mods |= {n.module.split(".")[0] for n in ast.walk(tree)
             if isinstance(n, ast.ImportFrom) and n.module}
    assert mods <= set(sys.stdlib_module_names) | {"__future__"}, mods
