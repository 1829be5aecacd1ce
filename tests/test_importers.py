"""Importers: native exports → contract files, on real public files, on files
constructed from the published layouts, on generated files with planted values, and on a
bad-input corpus (truncated, wrong format, missing channel) that must give one RawDataError
naming the source file and the field.

The contract files written are read back with the pipeline's own readers
(``robomill.io.forces``, ``io.tracker``, ``io.profiles``, ``io.impact``).
"""

from __future__ import annotations

import argparse
import hashlib
import importlib
import re
import zipfile
from pathlib import Path

import numpy as np
import pytest

from robomill.io import RawDataError
from robomill.io.forces import read_forces
from robomill.io.impact import read_hit
from robomill.io.profiles import read_profile
from robomill.io.tracker import read_tracker

DATA = Path(__file__).parent / "data"
REAL = DATA / "real"
BUILT = DATA / "constructed"
DYNO = BUILT / "dynoware" / "slot_s1_g1_px.txt"
DYNO25 = BUILT / "dynoware" / "dynoware25_window.csv"
TDMS = REAL / "tdms" / "raw1.tdms"
LAND = REAL / "x3p" / "sample-land_rows4-7.x3p"
SA = BUILT / "spatialanalyzer" / "py_f2.txt"
SA24 = BUILT / "spatialanalyzer" / "px_f2_sa2024.txt"
FARO = BUILT / "faro" / "px_f1.csv"
SINE = BUILT / "smats" / "sine.txt"
SDF = BUILT / "smats" / "two_profiles.sdf"
MM11_INT = REAL / "smats" / "mm11_iso1_ascii_int32.sdf"
MM11_F64 = REAL / "smats" / "mm11_iso1_ascii_binary64.sdf"
SMATS_XML = BUILT / "smats" / "milled_profile.xml"
SMATS_NIST = BUILT / "smats" / "nist_layout_reference.xml"

FORMATS = ("dynoware", "tdms", "spatialanalyzer", "faro", "smats", "x3p")


def module(fmt: str):
    return importlib.import_module(f"robomill.importers.{fmt}")


def run(fmt: str, sources, staging: Path, argv=()) -> list[dict]:
    """Parse ``argv`` as the command would (``--cut`` plus the importer's options) and
    convert."""
    mod = module(fmt)
    parser = argparse.ArgumentParser()
    parser.add_argument("--cut", default=None)
    mod.add_arguments(parser)
    args = parser.parse_args(list(argv))
    return mod.convert([Path(s) for s in sources], staging, args)


def one_error(fmt, source, tmp_path, argv=(), match=""):
    """The conversion raises exactly one RawDataError naming ``source``, matching ``match``;
    nothing is written."""
    staging = tmp_path / "staging"
    with pytest.raises(RawDataError) as info:
        run(fmt, [source], staging, argv)
    msg = str(info.value)
    assert msg.startswith(str(source)), msg
    assert re.search(match, msg), msg
    assert not staging.exists() or not any(p.is_file() for p in staging.rglob("*"))
    return msg


@pytest.mark.parametrize("fmt", FORMATS)
def test_interface(fmt):
    mod = module(fmt)
    assert mod.FORMAT == fmt
    assert mod.KIND in ("force", "tracker", "profile")
    assert mod.DESCRIPTION and callable(mod.convert) and callable(mod.add_arguments)


# --------------------------------------------------------------------------- DynoWare


def test_dynoware_constructed_export(tmp_path):
    entries = run("dynoware", [DYNO], tmp_path, ["--cut", "s1_g1_px"])
    assert entries == [{"path": "forces/s1_g1_px.csv", "kind": "force", "cut": "s1_g1_px",
                        "fs_hz": 10000.0}]
    t, F = read_forces(tmp_path / entries[0]["path"], 10000.0)
    assert t.size == 2000 and t[0] == 0.0 and t[-1] == pytest.approx(0.1999)
    # planted tool force 40 + 25 cos, -15 + 20 sin, 8 + 3 cos 2φ (plate reads minus that)
    np.testing.assert_allclose(F.mean(axis=0), [40.0, -15.0, 8.0], atol=0.05)
    phase = 2 * np.pi * 200.0 * t
    assert np.corrcoef(F[:, 0], np.cos(phase))[0, 1] > 0.99
    assert np.corrcoef(F[:, 1], np.sin(phase))[0, 1] > 0.99


def test_dynoware_axes_mapping(tmp_path):
    default = run("dynoware", [DYNO], tmp_path / "a", ["--cut", "c"])
    turned = run("dynoware", [DYNO], tmp_path / "b", ["--cut", "c", "--axes=y,-x,z"])
    _, Fd = read_forces(tmp_path / "a" / default[0]["path"], 10000.0)
    _, Ft = read_forces(tmp_path / "b" / turned[0]["path"], 10000.0)
    plate = -Fd  # the default inverts every axis
    np.testing.assert_allclose(Ft, np.column_stack([plate[:, 1], -plate[:, 0], plate[:, 2]]),
                               atol=1e-3)


def _dyno_text(rows, *, sep="\t", comma=False, header=None, units=("s", "N", "N", "N"),
               names=("Time", "Fx", "Fy", "Fz")):
    head = header if header is not None else ["Kistler DynoWare", "Sampling rate: 2 kHz",
                                              f"Number of samples: {len(rows)}"]
    out = list(head) + [sep.join(names)]
    if units:
        out.append(sep.join(units))
    for r in rows:
        s = sep.join(f"{v:.6f}" for v in r)
        out.append(s.replace(".", ",") if comma else s)
    return "\n".join(out) + "\n"


def test_dynoware_generated_semicolon_decimal_comma_kn(tmp_path):
    fs = 2000.0
    t = np.arange(400) / fs
    plate_kn = np.column_stack([0.1 * np.sin(2 * np.pi * 50 * t), 0.02 + 0 * t, -0.3 + 0 * t])
    src = tmp_path / "cut.txt"
    src.write_text(_dyno_text(np.column_stack([t, plate_kn]), sep=";", comma=True,
                              units=("s", "kN", "kN", "kN")), encoding="cp1252")
    e = run("dynoware", [src], tmp_path / "out")
    assert e[0]["cut"] == "cut" and e[0]["fs_hz"] == 2000.0
    _, F = read_forces(tmp_path / "out" / "forces" / "cut.csv", fs)
    np.testing.assert_allclose(F, -1e3 * plate_kn, atol=1e-3)


def test_dynoware_without_time_column_uses_the_rate(tmp_path):
    src = tmp_path / "c.txt"
    rows = np.column_stack([np.ones(100), 2 * np.ones(100), 3 * np.ones(100)])
    src.write_text(_dyno_text(rows, names=("Fx", "Fy", "Fz"), units=("N", "N", "N")))
    e = run("dynoware", [src], tmp_path / "o")
    t, F = read_forces(tmp_path / "o" / e[0]["path"], 2000.0)
    np.testing.assert_allclose(t, np.arange(100) / 2000.0)
    np.testing.assert_allclose(F[0], [-1, -2, -3])


def test_dynoware_bad_inputs(tmp_path):
    lines = DYNO.read_text().splitlines()
    # truncated: the export stops in the middle of a row
    trunc = tmp_path / "trunc.txt"
    trunc.write_text("\n".join(lines[:500]) + "\n" + lines[500][:9] + "\n")
    one_error("dynoware", trunc, tmp_path,
              match=r"line 501: row has 2 fields, the channel row has 4 \(truncated last row\?\)")
    # truncated between rows: fewer samples than the header announces
    short = tmp_path / "short.txt"
    short.write_text("\n".join(lines[:800]) + "\n")
    one_error("dynoware", short, tmp_path,
              match=r"header 'Number of samples': 789 samples, the header announces 2000 "
                    r"\(truncated export\?\)")
    # wrong format: a contract CSV, and a binary file
    one_error("dynoware", DATA / "bad" / "forces" / "missing_column.csv", tmp_path,
              match=r"no channel row naming Fx, Fy, Fz")
    one_error("dynoware", TDMS, tmp_path, match=r"binary file, not a text export")
    # missing channel
    nofz = tmp_path / "nofz.txt"
    nofz.write_text("\n".join(ln.rsplit("\t", 1)[0] if i >= 9 else ln
                              for i, ln in enumerate(lines)) + "\n")
    one_error("dynoware", nofz, tmp_path,
              match=r"channel row \(line 10\): channel Fz is missing \(the channel row has "
                    r"Time, Fx, Fy\)")
    # text in a sample, a unit that is not a force, a rate that disagrees, a bad --axes
    text = tmp_path / "text.txt"
    fields = lines[20].split("\t")
    fields[2] = "abc"
    text.write_text("\n".join(lines[:20] + ["\t".join(fields)] + lines[21:]) + "\n")
    one_error("dynoware", text, tmp_path,
              match=r"line 21, column Fy: value 'abc' is not a number")
    unit = tmp_path / "unit.txt"
    unit.write_text("\n".join(lines[:10] + ["s\tN\tmV\tN"] + lines[11:]) + "\n")
    one_error("dynoware", unit, tmp_path,
              match=r"units row \(line 11\), column Fy: channel Fy is in unit 'mv'")
    one_error("dynoware", DYNO, tmp_path, ["--fs-hz", "5000"],
              match=r"header: header sampling rate 10000 Hz \(expected --fs-hz 5000")
    one_error("dynoware", DYNO, tmp_path, ["--axes=-x,-x,-z"],
              match=r"option --axes: --axes '-x,-x,-z' does not name each axis once")
    norate = tmp_path / "norate.txt"
    norate.write_text(_dyno_text(np.ones((10, 3)), header=["DynoWare"],
                                 names=("Fx", "Fy", "Fz"), units=("N", "N", "N")))
    one_error("dynoware", norate, tmp_path,
              match=r"column Time: no time stamps and no sampling rate \(expected --fs-hz")


def test_dynoware_25_channel_export_window(tmp_path):
    """The layout of the real DynoWare 2.5.1.2 CSV export found in public (see
    tests/data/real/dynoware/SOURCE.md): 18 ``Key:,value`` lines with ``Sampling rate
    [Hz]:,10000`` and ``Samples per channel:,200001`` (the whole 20 s measurement), then an
    exported window from 8 s with times printed to 4 decimals."""
    entries = run("dynoware", [DYNO25], tmp_path, ["--cut", "s1_g1_px"])
    assert entries[0]["fs_hz"] == 10000.0
    t, F = read_forces(tmp_path / entries[0]["path"], 10000.0)
    assert t.size == 1000 and t[0] == 0.0 and t[-1] == pytest.approx(0.0999)
    # planted tool force 60 + 80 cos, -40 + 90 sin, 55 + 20 cos 2φ (the plate reads minus it)
    np.testing.assert_allclose(F.mean(axis=0), [60.0, -40.0, 55.0], atol=0.1)
    assert np.corrcoef(F[:, 1], np.sin(2 * np.pi * 200.0 * t))[0, 1] > 0.999
    # the header's rate is read from the key's bracket and checked against the time column
    one_error("dynoware", DYNO25, tmp_path, ["--fs-hz", "5000"],
              match=r"header: header sampling rate 10000 Hz \(expected --fs-hz 5000")


def test_dynoware_25_bad_inputs(tmp_path):
    lines = DYNO25.read_text().splitlines()
    # more rows than the measurement has samples
    long = tmp_path / "long.csv"
    long.write_text("\n".join(ln.replace("200001", "999") for ln in lines) + "\n")
    one_error("dynoware", long, tmp_path,
              match=r"header 'Samples per channel': 1000 samples, the header announces 999")
    # a window that starts at 0 s and is shorter than the measurement: truncated, unless the
    # user says it is a window
    zero = tmp_path / "zero.csv"
    rows = [ln.split(",", 1) for ln in lines[20:]]
    zero.write_text("\n".join(lines[:20] + [f"{float(r[0]) - 8:.4f},{r[1]}" for r in rows])
                    + "\n")
    one_error("dynoware", zero, tmp_path,
              match=r"1000 samples, the header announces 200001 \(truncated export\?\) "
                    r"\(expected 200001 sample rows \(or --window")
    assert run("dynoware", [zero], tmp_path / "w", ["--window"])[0]["fs_hz"] == 10000.0
    # DynoWare 3.2 with the Windows list separator and decimal symbol both a comma
    comma = tmp_path / "comma.csv"
    comma.write_text("\n".join(lines[:20] + [ln.replace(".", ",") for ln in lines[20:]])
                     + "\n")
    one_error("dynoware", comma, tmp_path,
              match=r"line 21: row has 7 fields, the channel row has 4: a comma as decimal "
                    r"mark in a comma-separated export is ambiguous")
    # a rate in a unit that is not a frequency
    unit = tmp_path / "unit.csv"
    unit.write_text("\n".join(ln.replace("Sampling rate [Hz]", "Sampling rate [s]")
                              for ln in lines) + "\n")
    one_error("dynoware", unit, tmp_path,
              match=r"header line 11: sampling rate '10000' in 's' is not a rate")


# --------------------------------------------------------------------------- TDMS

FORCE_CH = ["--fx", "First  Channel", "--fy", "Second Chan", "--fz", "Layer Data/Third Chan"]


def test_tdms_real_file_as_force_record(tmp_path):
    from nptdms import TdmsFile

    e = run("tdms", [TDMS], tmp_path, ["--cut", "s1_g1_px", "--n-per-unit", "100", *FORCE_CH])
    assert e == [{"path": "forces/s1_g1_px.csv", "kind": "force", "cut": "s1_g1_px",
                  "fs_hz": 50000.0}]
    t, F = read_forces(tmp_path / e[0]["path"], 50000.0)
    g = TdmsFile.read(TDMS)["Layer Data"]
    assert t.size == 2000
    np.testing.assert_allclose(F[:, 0], -100 * g["First  Channel"][:], rtol=1e-5, atol=1e-4)
    np.testing.assert_allclose(F[:, 2], -100 * g["Third Chan"][:], rtol=1e-5, atol=1e-4)


def test_tdms_real_file_as_impact_hit(tmp_path):
    e = run("tdms", [TDMS], tmp_path,
            ["--record", "impact", "--force", "First  Channel", "--ax", "Second Chan",
             "--ay", "Third Chan", "--az", "Fourth Chan", "--direction", "Y", "--hit", "3",
             "--force-n-per-unit", "10", "--accel-ms2-per-unit", "9.81"])
    assert e == [{"path": "impact/hitY_3.csv", "kind": "impact", "direction": "Y", "hit": 3}]
    fs, force, acc = read_hit(tmp_path / e[0]["path"])[:3]
    assert fs == pytest.approx(50000.0) and force.shape == (2000,) and acc.shape == (2000, 3)


def test_tdms_generated_planted_sinusoid(tmp_path):
    from nptdms import ChannelObject, TdmsWriter

    fs = 4096.0
    t = np.arange(2048) / fs
    fx = 3.0 * np.sin(2 * np.pi * 96.0 * t)
    src = tmp_path / "gen.tdms"
    props = {"wf_increment": 1 / fs, "wf_start_offset": 0.0, "unit_string": "N"}
    with TdmsWriter(src) as w:
        w.write_segment([ChannelObject("Dyno", n, v, properties=props)
                         for n, v in (("Fx", fx), ("Fy", 0 * fx + 1.0), ("Fz", 0 * fx - 2.0))])
    e = run("tdms", [src], tmp_path / "o", ["--fx", "Fx", "--fy", "Fy", "--fz", "Fz",
                                            "--axes=x,y,z"])
    assert e[0]["fs_hz"] == 4096.0 and e[0]["cut"] == "gen"
    tt, F = read_forces(tmp_path / "o" / e[0]["path"], fs)
    spec = np.abs(np.fft.rfft(F[:, 0]))
    assert np.fft.rfftfreq(tt.size, 1 / fs)[np.argmax(spec)] == pytest.approx(96.0)
    np.testing.assert_allclose(F[:, 1:], [[1.0, -2.0]] * tt.size, atol=1e-6)
    # channels of unequal length: one clear error
    bad = tmp_path / "unequal.tdms"
    with TdmsWriter(bad) as w:
        w.write_segment([ChannelObject("Dyno", "Fx", fx, properties=props),
                         ChannelObject("Dyno", "Fy", fx[:100], properties=props),
                         ChannelObject("Dyno", "Fz", fx, properties=props)])
    one_error("tdms", bad, tmp_path, ["--fx", "Fx", "--fy", "Fy", "--fz", "Fz"],
              match=r"Dyno/Fy: channel 'Dyno/Fy' has 100 samples, the first has 2048 "
                    r"\(truncated acquisition\?\)")


def test_tdms_bad_inputs(tmp_path):
    raw = TDMS.read_bytes()
    half = tmp_path / "half.tdms"
    half.write_bytes(raw[: len(raw) // 2])
    one_error("tdms", half, tmp_path, FORCE_CH,
              match=r"last data segment: the last segment is incomplete .*truncated copy")
    one_error("tdms", DYNO, tmp_path, FORCE_CH,
              match=r"bytes 0-3: lead-in tag is b'Kist' \(expected an NI TDMS file")
    msg = one_error("tdms", TDMS, tmp_path, ["--fx", "First  Channel", "--fy", "Second Chan",
                                             "--fz", "Fz"],
                    match=r"option --fz: channel 'Fz' is missing \(expected one of "
                          r"'Layer Data/First  Channel'")
    assert msg.count("RawDataError") == 0
    one_error("tdms", TDMS, tmp_path, ["--fx", "First  Channel", "--fy", "Second Chan"],
              match=r"option --fz: no channel given for --fz")
    one_error("tdms", TDMS, tmp_path, ["--record", "impact", "--force", "First  Channel"],
              match=r"option --direction: no hammer direction")


# --------------------------------------------------------------------------- X3P


def _land_rows():
    with zipfile.ZipFile(LAND) as z:
        return np.frombuffer(z.read("sample-land/bindata/data.bin"), "<f8").reshape(4, 918)


def test_x3p_real_scan_longest_valid_run(tmp_path):
    e = run("x3p", [LAND], tmp_path, ["--cut", "s2_g1_px", "--row", "2",
                                      "--dropouts", "longest"])
    assert e == [{"path": "profiles/s2_g1_px.csv", "kind": "profile", "cut": "s2_g1_px"}]
    x, z, fs_per_mm = read_profile(tmp_path / e[0]["path"])
    assert x.size == 879 and fs_per_mm == pytest.approx(1 / 0.00258, rel=1e-6)
    row = _land_rows()[2]
    np.testing.assert_allclose(z, row[39:918] * 1e6, rtol=1e-5)


def test_x3p_real_scan_dropouts_refused_by_default(tmp_path):
    one_error("x3p", LAND, tmp_path, ["--row", "2"],
              match=r"row 2, point \d+: 7 invalid point\(s\) inside the profile "
                    r"\(expected a profile without dropouts")
    one_error("x3p", LAND, tmp_path, ["--row", "9"],
              match=r"option --row: --row 9 is outside the surface \(expected 0 … 3\)")


def test_x3p_opengps_samples_xml_and_int16():
    from robomill.importers.x3p import read_x3p

    x1, z1, i1 = read_x3p(REAL / "x3p" / "ISO5436-sample1.x3p")
    x4, z4, i4 = read_x3p(REAL / "x3p" / "ISO5436-sample4_bin.x3p")
    assert i1["feature"] == "SUR" and i1["size"] == (4, 4) and i1["row"] == 2
    np.testing.assert_allclose(x1, x4)
    np.testing.assert_allclose(x1, [0, 16.016, 32.032, 48.048], rtol=1e-9)
    # the int16 file is the same surface quantised to 1000 µm steps of CZ/Increment
    assert np.max(np.abs(z4 - z1)) <= 500.0 + 1e-6
    # row 1 ends in the invalid point: an empty Datum in the XML, a clear bit in valid.bin
    xa, za, ia = read_x3p(REAL / "x3p" / "ISO5436-sample1.x3p", row=1)
    xb, zb, ib = read_x3p(REAL / "x3p" / "ISO5436-sample1_bin.x3p", row=1)
    assert ia["cropped"] == ib["cropped"] == (0, 1)
    np.testing.assert_array_equal(za, zb)
    with pytest.raises(RawDataError, match=r"row 1, points 3…3: invalid points at the ends "
                                           r"of the profile"):
        read_x3p(REAL / "x3p" / "ISO5436-sample1_bin.x3p", row=1, crop=False)


def write_x3p(path: Path, z_m: np.ndarray, *, dx_m=1e-6, feature="PRF", dtype="D",
              data: bytes | None = None, md5: str | None = None, drop: str | None = None,
              main_name="main.xml"):
    """A minimal ISO 25178-72 X3P (main.xml + bindata/data.bin), for generated tests."""
    raw = data if data is not None else z_m.astype({"D": "<f8", "F": "<f4"}[dtype]).tobytes()
    ny = 1 if z_m.ndim == 1 else z_m.shape[0]
    nx = z_m.shape[-1]
    cx = ("<CX><AxisType>I</AxisType><DataType>D</DataType>"
          + ("" if drop == "Increment" else f"<Increment>{dx_m!r}</Increment>")
          + "<Offset>0</Offset></CX>")
    xml = (f'<?xml version="1.0" encoding="UTF-8"?><p:ISO5436_2 '
           f'xmlns:p="http://www.opengps.eu/2008/ISO5436_2"><Record1><Revision>ISO5436 - 2000'
           f"</Revision><FeatureType>{feature}</FeatureType><Axes>{cx}<CY><AxisType>I"
           f"</AxisType><DataType>D</DataType><Increment>1e-6</Increment><Offset>0</Offset>"
           f"</CY><CZ><AxisType>A</AxisType><DataType>{dtype}</DataType></CZ></Axes>"
           f"</Record1><Record3><MatrixDimension><SizeX>{nx}</SizeX><SizeY>{ny}</SizeY>"
           f"<SizeZ>1</SizeZ></MatrixDimension><DataLink><PointDataLink>bindata/data.bin"
           f"</PointDataLink><MD5ChecksumPointData>{md5 or hashlib.md5(raw).hexdigest()}"
           f"</MD5ChecksumPointData></DataLink></Record3></p:ISO5436_2>")
    with zipfile.ZipFile(path, "w") as zf:
        zf.writestr(main_name, xml)
        zf.writestr("bindata/data.bin", raw)
    return path


def test_x3p_generated_profile_planted_sine(tmp_path):
    x_m = np.arange(1000) * 0.8e-6
    z_m = 0.4e-6 * np.sin(2 * np.pi * x_m / 80e-6)
    src = write_x3p(tmp_path / "prf.x3p", z_m, dx_m=0.8e-6, dtype="F")
    e = run("x3p", [src], tmp_path / "o")
    x, z, fs = read_profile(tmp_path / "o" / e[0]["path"])
    assert fs == pytest.approx(1250.0) and x.size == 1000
    np.testing.assert_allclose(z, 0.4 * np.sin(2 * np.pi * x / 0.08), atol=1e-6)


def test_x3p_bad_inputs(tmp_path):
    z = np.zeros(200)
    raw = z.tobytes()
    trunc = write_x3p(tmp_path / "trunc.x3p", z, data=raw[:-80])
    one_error("x3p", trunc, tmp_path,
              match=r"archive member bindata/data.bin: bindata/data.bin has 1520 bytes, "
                    r"200×1×1 points of type D need 1600 \(truncated\?\)")
    damaged = write_x3p(tmp_path / "md5.x3p", z, md5="0" * 32)
    one_error("x3p", damaged, tmp_path,
              match=r"Record3/DataLink/MD5ChecksumPointData: bindata/data.bin MD5 is")
    cut_zip = tmp_path / "cut.x3p"
    cut_zip.write_bytes(LAND.read_bytes()[:5000])
    one_error("x3p", cut_zip, tmp_path, match=r"(not a zip archive|damaged zip archive)")
    one_error("x3p", SINE, tmp_path, match=r"file: not a zip archive \(expected an X3P file")
    nomain = write_x3p(tmp_path / "nomain.x3p", z, main_name="header.xml")
    one_error("x3p", nomain, tmp_path, match=r"archive: no main.xml in the archive")
    noinc = write_x3p(tmp_path / "noinc.x3p", z, drop="Increment")
    one_error("x3p", noinc, tmp_path,
              match=r"main.xml: Record1/Axes/CX/Increment: element Record1/Axes/CX/Increment "
                    r"is missing")
    pcl = write_x3p(tmp_path / "pcl.x3p", z, feature="PCL")
    one_error("x3p", pcl, tmp_path,
              match=r"main.xml: Record1/FeatureType: feature type is PCL")


# --------------------------------------------------------------------------- SMATS / SDF


def test_smats_ascii_constructed(tmp_path):
    e = run("smats", [SINE], tmp_path, ["--cut", "s1_g1_py"])
    x, z, fs = read_profile(tmp_path / e[0]["path"])
    assert x.size == 1600 and fs == pytest.approx(800.0)  # 1.25 µm spacing
    A = np.column_stack([np.sin(2 * np.pi * x / 0.1), np.cos(2 * np.pi * x / 0.1),
                         np.ones_like(x)])
    amp = np.linalg.lstsq(A, z, rcond=None)[0]
    assert np.hypot(amp[0], amp[1]) == pytest.approx(0.5, abs=0.01)


def test_smats_sdf_second_profile(tmp_path):
    e = run("smats", [SDF], tmp_path, ["--cut", "s1_g2_py", "--profile", "1"])
    x, z, fs = read_profile(tmp_path / e[0]["path"])
    assert x.size == 512 and fs == pytest.approx(800.0)
    np.testing.assert_allclose(z, 0.150 * np.cos(2 * np.pi * x / 0.05), atol=0.0006)


def test_smats_bad_inputs(tmp_path):
    lines = SDF.read_text().splitlines()
    trunc = tmp_path / "trunc.sdf"
    trunc.write_text("\n".join(lines[:40]) + "\n")
    one_error("smats", trunc, tmp_path,
              match=r"data section: 416 height values, the header announces 512×2 = 1024 "
                    r"\(truncated\?\)")
    nokey = tmp_path / "nokey.sdf"
    nokey.write_text("\n".join(ln for ln in lines if not ln.startswith("Zscale")) + "\n")
    one_error("smats", nokey, tmp_path, match=r"header: SDF header key Zscale is missing")
    xml = tmp_path / "p.xml"
    xml.write_text('<?xml version="1.0"?><SMATS><Profile/></SMATS>\n')
    msg = one_error("smats", xml, tmp_path, match=r"line 1: XML root <SMATS> is not <DATA>")
    assert "binary SDF is not read" in msg and "robomill import x3p" in msg
    x3p_main = tmp_path / "main.xml"
    with zipfile.ZipFile(REAL / "x3p" / "ISO5436-sample1.x3p") as z:
        x3p_main.write_bytes(z.read("main.xml"))
    one_error("smats", x3p_main, tmp_path,
              match=r"line 1: the main.xml of an X3P \(ISO 25178-72\) file \(expected the "
                    r".x3p archive itself: robomill import x3p")
    one_error("smats", TDMS, tmp_path, match=r"binary file, not a text export")
    text = tmp_path / "text.txt"
    text.write_text("1.25\n0.1\n0.2\nabc\n0.3\n")
    one_error("smats", text, tmp_path, match=r"line 4: value 'abc' is not a number")
    one_error("smats", SDF, tmp_path, ["--profile", "2"],
              match=r"option --profile: --profile 2 outside the file \(expected 0 … 1\)")


def test_smats_xml_constructed_pq(tmp_path):
    """SMATS XML (constructed, tests/data/constructed/smats/make_smats_xml.py): µm converted
    to the contract's x_mm/z_um, the part name kept in the entry, and Pq of the surface
    analysis within 1 % of sqrt(0.8²/2 + 0.12²/2) µm, the RMS of the two planted cosines."""
    from robomill.surface import analyse_profile

    e = run("smats", [SMATS_XML], tmp_path, ["--cut", "s1_g1_px"])
    assert e == [{"path": "profiles/s1_g1_px.csv", "kind": "profile", "cut": "s1_g1_px",
                  "part": "RM-constructed-001", "process": "end milled (constructed profile)",
                  "measurement": "stylus profile, 1 mm",
                  "source_filename": "milled_profile.smd"}]
    x, z, fs = read_profile(tmp_path / e[0]["path"])
    assert x.size == 4000 and x[-1] == pytest.approx(3999 * 0.25e-3)
    assert fs == pytest.approx(4000.0)  # 0.25 µm spacing = 4000 points per mm
    pq_truth = np.sqrt(0.8**2 / 2 + 0.12**2 / 2)
    pq = float(analyse_profile(x, z)["parseval_rms_um"])
    assert pq == pytest.approx(pq_truth, rel=0.01)
    # the same profile written in nm (spacing 250 nm) reads the same in µm
    text = SMATS_XML.read_text()
    head, values, tail = re.split(r"</?DATA_POINT_VALUES>", text)
    nm = tmp_path / "nm.xml"
    nm.write_text(head.replace("<UNITS>um", "<UNITS>nm").replace("<SPACING>0.25", "<SPACING>250")
                  + "<DATA_POINT_VALUES>\n"
                  + "\n".join(f"{float(v) * 1e3:.2f}" for v in values.split())
                  + "\n</DATA_POINT_VALUES>" + tail)
    x_nm, z_nm = module("smats").read_smats(nm)
    np.testing.assert_allclose(x_nm, x, rtol=1e-9)
    np.testing.assert_allclose(z_nm, z, atol=1e-5)


def _smats_xml_variant(tmp_path, name, old, new):
    text = SMATS_XML.read_text()
    assert old in text
    path = tmp_path / name
    path.write_text(text.replace(old, new))
    return path


@pytest.mark.parametrize("name, old, new, match", [
    ("count.xml", "<NUMPOINTS>4000", "<NUMPOINTS>4001",
     r"DATA/DATAFILE/NUMPOINTS: 4000 values in DATA_POINT_VALUES, NUMPOINTS says 4001 "
     r"\(truncated\?\) \(expected 4001 heights, one per line\)"),
    ("unit.xml", "<UNITS>um", "<UNITS>furlong",
     r"DATA/DATAFILE/UNITS: unit 'furlong' is unknown \(expected one of um, "),
    ("3d.xml", "<DATA_TYPE>2D", "<DATA_TYPE>3D",
     r"DATA/DATAFILE/DATA_TYPE: DATA_TYPE is '3D' \(not a profile\) \(expected 2D"),
    ("nospacing.xml", "<SPACING>0.25</SPACING>", "",
     r"DATA/DATAFILE/SPACING: element SPACING is missing \(expected a SMATS XML profile"),
    ("nopart.xml", "<PART>RM-constructed-001</PART>", "",
     r"DATA/PART: element PART is missing"),
    ("kcal.xml", "<KCAL>1<", "<KCAL>0.98<",
     r"DATA/DATAFILE/KCAL: KCAL is 0.98: whether the heights are to be scaled by it is not "
     r"stated in the file \(expected KCAL 1, or --kcal apply"),
    ("text.xml", "3.92000\n", "3.92000\nabc\n",
     r"DATA/DATAFILE/DATA_POINT_VALUES, value 1: value 'abc' is not a number"),
    ("broken.xml", "</DATA>", "</DAT>", r"file: XML cannot be parsed"),
])
def test_smats_xml_bad_inputs(tmp_path, name, old, new, match):
    one_error("smats", _smats_xml_variant(tmp_path, name, old, new), tmp_path, match=match)


def test_smats_xml_kcal_options(tmp_path):
    path = _smats_xml_variant(tmp_path, "kcal.xml", "<KCAL>1<", "<KCAL>0.5<")
    read = module("smats").read_smats
    _, z_ref = read(SMATS_XML)
    _, z_apply = read(path, kcal="apply")
    _, z_ignore = read(path, kcal="ignore")
    np.testing.assert_allclose(z_apply, 0.5 * z_ref)
    np.testing.assert_allclose(z_ignore, z_ref)


def test_smats_xml_nist_header_fields_and_reference_parameters(tmp_path):
    """SMATS XML with the header fields as NIST writes them (lengths with units, KCAL
    '1.0000 um/um', UNITS 'micrometers') and the file's own parameter sections
    (constructed: tests/data/constructed/smats/make_smats_reference_xml.py, whose values come
    from the planted components and the filter's published transmission, not from our
    filter): the entry carries them, and ours agree within 1 %, Pq of every profile among
    them."""
    from robomill.surface.reference import reference_comparison

    e = run("smats", [SMATS_NIST], tmp_path, ["--cut", "c1"])
    ref = e[0]["reference"]
    assert set(ref) == {"primary", "roughness", "waviness"}
    assert ref["roughness"]["lambda_c_mm"] == pytest.approx(0.25)
    assert ref["roughness"]["filter"] == {"FILTER": "Gaussian", "CUTOFF": "0.25 mm"}
    assert ref["primary"] == {"Pq_um": pytest.approx(np.sqrt(2.0**2 / 2 + 0.4**2 / 2))}
    x, z, fs = read_profile(tmp_path / e[0]["path"])
    assert x.size == 8000 and fs == pytest.approx(2000.0)  # 0.5 um written '0.5 um'
    table = reference_comparison(x, z, ref, lambda_c_mm=0.8, rtol=0.01, cut="c1")
    assert len(table) == 8 and table["within_tolerance"].all(), table
    pq = table[table["parameter"] == "Pq"].set_index("profile")
    assert set(pq.index) == {"primary", "roughness", "waviness"}
    assert (pq["ours"] / pq["file_value"] - 1).abs().max() < 0.01
    assert table.loc[table["profile"] == "roughness", "filter"].iloc[0] == (
        "the file's: FILTER Gaussian, CUTOFF 0.25 mm")
    # a section without a cut-off is computed at ours, and says so
    ref2 = {"roughness": {"Pq_um": 0.28}}
    row = reference_comparison(x, z, ref2, lambda_c_mm=0.8, rtol=0.01).iloc[0]
    assert row["lambda_c_mm"] == 0.8 and "not stated in the file" in row["filter"]


@pytest.mark.parametrize("kcal, argv, scale", [
    ("1000 nm/um", (), 1.0),            # a length ratio equal to 1
    ("0.5 nm/count", (), 0.5e-3),       # values are counts of 0.5 nm
    ("0.998 um/um", ("--kcal", "apply"), 0.998),
    ("0.998 um/um", ("--kcal", "ignore"), 1.0),
])
def test_smats_xml_unit_bearing_kcal(tmp_path, kcal, argv, scale):
    path = tmp_path / "k.xml"
    path.write_text(SMATS_NIST.read_text().replace("<KCAL>1.0000 um/um<", f"<KCAL>{kcal}<"))
    _, z_ref = module("smats").read_smats(SMATS_NIST)
    _, z = module("smats").read_smats(path, kcal=dict([argv]).get("--kcal", "refuse")
                                      if argv else "refuse")
    np.testing.assert_allclose(z, z_ref * scale, rtol=1e-12)


@pytest.mark.parametrize("old, new, match", [
    ("<KCAL>1.0000 um/um<", "<KCAL>0.998 um/um<",
     r"DATA/DATAFILE/KCAL: KCAL is 0\.998 um/um: whether the heights are to be scaled"),
    ("<KCAL>1.0000 um/um<", "<KCAL>1.0 kg/m<",
     r"DATA/DATAFILE/KCAL: KCAL '1\.0 kg/m': unit 'kg/m' is not understood \(expected a "
     r"number, a number and a ratio of lengths"),
    ("<SPACING>0.5 um<", "<SPACING>0.5 parsec<",
     r"DATA/DATAFILE/SPACING: SPACING '0\.5 parsec' is not a length"),
    ("<PQ>1.442221 um<", "<PQ>n/a<",
     r"PRIMARY_SURFACE_PARAMETERS/PQ: PQ 'n/a' is not a number with a length unit"),
])
def test_smats_xml_nist_fields_bad_inputs(tmp_path, old, new, match):
    one_error("smats", _smats_xml_variant_of(SMATS_NIST, tmp_path, old, new), tmp_path,
              match=match)


def test_smats_xml_units_as_attributes(tmp_path):
    text = SMATS_NIST.read_text().replace("<SPACING>0.5 um<", '<SPACING unit="nm">500<')
    text = text.replace("<PQ>1.442221 um<", '<PQ units="nm">1442.221<')
    path = tmp_path / "attr.xml"
    path.write_text(text)
    x, _, meta = module("smats").read_smats_file(path)
    x0, _, meta0 = module("smats").read_smats_file(SMATS_NIST)
    np.testing.assert_allclose(x, x0, rtol=1e-12)
    assert meta["reference"]["primary"]["Pq_um"] == pytest.approx(1.442221, rel=1e-12)


def test_smats_xml_tags_in_any_case(tmp_path):
    text = SMATS_NIST.read_text()
    lower = re.sub(r"</?[A-Z_]+>", lambda m: m.group(0).lower(), text)
    path = tmp_path / "lower.xml"
    path.write_text(lower)
    x, z, meta = module("smats").read_smats_file(path)
    x0, z0, meta0 = module("smats").read_smats_file(SMATS_NIST)
    np.testing.assert_array_equal(z, z0)
    assert meta == meta0


def _smats_xml_variant_of(source, tmp_path, old, new):
    text = source.read_text()
    assert old in text
    path = tmp_path / "variant.xml"
    path.write_text(text.replace(old, new))
    return path


@pytest.mark.parametrize("path, zscale", [(MM11_INT, 1e-14), (MM11_F64, 1e-12)])
def test_smats_real_mountainsmap_sdf_exports(tmp_path, path, zscale):
    """Real ISO 25178-71 ASCII SDF files exported by Digital Surf MountainsMap 11 (sdfio's
    interop samples, MIT): 20 profiles × 30 points, heights (30 p + i) nm, 1 µm spacing,
    several values per line, CRLF, and a 'BAD' point at the end of the first profile."""
    assert path.stat().st_size < 200_000
    head = path.read_bytes().split(b"\r\n")
    assert head[0] == b"aISO-1.0" and head[8].split() == [b"Zscale", b"=",
                                                          f"{zscale:g}".encode()]
    # profile 0: its last point is BAD, dropped at the end (30 points are too few for a
    # contract profile, so the values are checked on the reader)
    read_smats = module("smats").read_smats
    x, z = read_smats(path)
    assert x.size == 29 and x[0] == 0.0
    np.testing.assert_allclose(np.diff(x), 1e-3)  # 1 µm spacing in mm
    np.testing.assert_allclose(z, np.arange(29) * 1e-3, atol=1e-8)  # µm
    # profile 7: complete, (210 + i) nm; the import writes it
    e = run("smats", [path], tmp_path / "p7", ["--cut", "s1_g1_px", "--profile", "7"])
    written = np.loadtxt(tmp_path / "p7" / e[0]["path"], delimiter=",", skiprows=1)
    assert written.shape == (30, 2) and written[-1, 0] == pytest.approx(0.029)
    np.testing.assert_allclose(written[:, 1], (210 + np.arange(30)) * 1e-3, atol=1e-8)
    # the BAD point refused where it cannot be dropped
    one_error("smats", path, tmp_path, ["--no-crop"],
              match=r"profile 0, points 29…29: 'BAD' points at the ends of the profile")
    one_error("smats", path, tmp_path, ["--profile", "20"],
              match=r"option --profile: --profile 20 outside the file \(expected 0 … 19\)")


def test_smats_sdf_bad_points_inside(tmp_path):
    lines = MM11_INT.read_text().splitlines()
    # a BAD point in the middle of profile 1 (line 16 holds it)
    fields = lines[15].split()
    fields[10] = "BAD"
    inner = tmp_path / "inner.sdf"
    inner.write_text("\n".join(lines[:15] + [" ".join(fields)] + lines[16:]) + "\n")
    one_error("smats", inner, tmp_path, ["--profile", "1"],
              match=r"profile 1, point 10: 1 'BAD' point\(s\) inside the profile \(expected a "
                    r"profile without dropouts")
    x, z = module("smats").read_smats(inner, profile=1, dropouts="longest")
    assert x.size == 19 and x[0] == 0.0  # points 11 … 29 of (30 + i) nm
    np.testing.assert_allclose(z, (41 + np.arange(19)) * 1e-3, atol=1e-8)
    # the spellings of the NIST and NPL pages, and a binary SDF
    for magic in ("aBC-1.0", "aNPL-V1.0", "aISO-2.0"):
        other = tmp_path / f"{magic}.sdf"
        other.write_text("\n".join([magic] + lines[1:]) + "\n")
        assert run("smats", [other], tmp_path / magic)[0]["kind"] == "profile"
    binary = tmp_path / "b.sdf"
    binary.write_text("\n".join(["bISO-1.0"] + lines[1:]) + "\n")
    one_error("smats", binary, tmp_path, match=r"line 1: binary SDF \(bISO-1.0\)")


# --------------------------------------------------------------------------- trackers

SA_ARGS = ["--direction", "py", "--feed-mm-s", "2", "--fs-hz", "815"]
FARO_ARGS = ["--direction", "px", "--feed-mm-s", "1", "--fs-hz", "815"]


def imported_run(fmt, src, tmp_path, args, *, n):
    """Import one tracker export with ``args`` (direction, feed, rate); check the manifest
    entry it adds and that the stamps are rebuilt as t0 + k/fs for ``n`` points; return the
    contract file's (t, points)."""
    direction, feed, fs = (args[args.index(k) + 1] for k in ("--direction", "--feed-mm-s",
                                                              "--fs-hz"))
    e = run(fmt, [src], tmp_path, args)
    assert e == [{"path": f"tracker/{direction}_f{feed}.csv", "kind": "tracker",
                  "direction": direction, "feed_mm_s": float(feed), "fs_hz": float(fs)}]
    t, p = read_tracker(tmp_path / e[0]["path"], fs_hz=float(fs))
    np.testing.assert_allclose(t, np.arange(n) / float(fs), atol=1e-9)
    return t, p


def test_spatialanalyzer_coarse_stamps_rebuilt(tmp_path):
    t, p = imported_run("spatialanalyzer", SA, tmp_path, SA_ARGS, n=1000)
    # planted: y = 1200 + 2 t (mm)
    assert np.polyfit(t, p[:, 1], 1)[0] == pytest.approx(2.0, abs=1e-3)


SA24_ARGS = ["--direction", "px", "--feed-mm-s", "2", "--fs-hz", "200"]


def test_spatialanalyzer_2024_export_without_header_row(tmp_path):
    """The layout of the real SA 2024.2 stream export found in public (see
    tests/data/real/spatialanalyzer/SOURCE.md): three ``//`` lines, no header row,
    ``Collection, Group, Target, X, Y, Z, MM/DD/YY HH:MM:SS`` with stamps to the second."""
    t, p = imported_run("spatialanalyzer", SA24, tmp_path, SA24_ARGS, n=640)
    # planted: x = 1520 + 2 t mm, y, z constant (2 µm noise); the first point as printed
    assert np.polyfit(t, p[:, 0], 1)[0] == pytest.approx(2.0, abs=1e-3)
    np.testing.assert_allclose(p[0], [1519.999355, -845.250903, 312.498005])
    assert p[:, 1].std() < 0.005
    # inches from the AXES line
    inch = tmp_path / "inch.txt"
    inch.write_text(SA24.read_text().replace("Z (mm)", "Z (in)"))
    e = run("spatialanalyzer", [inch], tmp_path / "in", SA24_ARGS)
    _, p_in = read_tracker(tmp_path / "in" / e[0]["path"], fs_hz=200.0)
    np.testing.assert_allclose(p_in[0], 25.4 * p[0], rtol=1e-9)


def test_spatialanalyzer_2024_bad_inputs(tmp_path):
    lines = SA24.read_text().splitlines()
    # no rate: the stamps (to the second) suggest one
    one_error("spatialanalyzer", SA24, tmp_path, ["--direction", "px", "--feed-mm-s", "2"],
              match=r"column Time: time stamps are coarse or uneven \(finest step 1 s\) and no "
                    r"rate was stated; 640 samples over 3 s of stamps suggest about 160 Hz")
    # 30 points dropped inside one second: that second's count is not the rate's
    drop = tmp_path / "drop.txt"
    drop.write_text("\n".join(lines[:3 + 150] + lines[3 + 180:]) + "\n")
    one_error("spatialanalyzer", drop, tmp_path, SA24_ARGS,
              match=r"sample 70, column Time: the stamp at 1 s holds 170 samples, 200 Hz gives "
                    r"200 \(1 of 2 inner stamps differ")
    # a second point group in the export, picked with --group
    two = tmp_path / "two.txt"
    two.write_text("\n".join(lines + ["pose1,  Satz1,  1,  2296.6,  -2416.2,  -442.8,  "
                                      "02/12/26 09:25:15"]) + "\n")
    one_error("spatialanalyzer", two, tmp_path, SA24_ARGS,
              match=r"line 644: rows of 2 point groups \(stream_px_f2::feed2: 640 rows, "
                    r"pose1::Satz1: 1 rows\) \(expected one point stream per export, or --group")
    e = run("spatialanalyzer", [two], tmp_path / "g", SA24_ARGS + ["--group", "feed2"])
    assert e[0]["fs_hz"] == 200.0
    one_error("spatialanalyzer", two, tmp_path, SA24_ARGS + ["--group", "nope"],
              match=r"option --group: no rows of point group 'nope'")
    # cylindrical coordinates, the wrong number of name fields, a row cut short
    cyl = tmp_path / "cyl.txt"
    cyl.write_text(SA24.read_text().replace("CARTESIAN: X,  Y,  Z", "CYLINDRICAL: R,  Theta,  Z"))
    one_error("spatialanalyzer", cyl, tmp_path, SA24_ARGS,
              match=r"line 3: coordinates are CYLINDRICAL \(expected a Cartesian export")
    one_error("spatialanalyzer", SA24, tmp_path, SA24_ARGS + ["--name-fields", "1"],
              match=r"line 4: no header row naming X, Y, Z, and the first row has no X, Y, Z "
                    r"after 1 name field\(s\)")
    trunc = tmp_path / "trunc.txt"
    trunc.write_text("\n".join(lines[:300] + [lines[300][:40]]) + "\n")
    one_error("spatialanalyzer", trunc, tmp_path, SA24_ARGS,
              match=r"line 301: row has 4 fields, the first row has 7 \(truncated last row\?\)")


def test_faro_ms_stamps_and_units(tmp_path):
    e = run("faro", [FARO], tmp_path, FARO_ARGS)
    t, p = read_tracker(tmp_path / e[0]["path"], fs_hz=815.0)
    assert t.size == 1500 and np.polyfit(t, p[:, 0], 1)[0] == pytest.approx(1.0, abs=1e-3)
    # the same export in metres, without time stamps: rebuilt from --fs-hz, converted to mm
    src = tmp_path / "m.csv"
    rows = [ln.split(",") for ln in FARO.read_text().splitlines()[4:]]
    src.write_text("FARO export\nUnits: m\nName,X,Y,Z\n" + "".join(
        f"{r[0]},{float(r[1]) / 1e3:.7f},{float(r[2]) / 1e3:.7f},{float(r[3]) / 1e3:.7f}\n"
        for r in rows))
    e2 = run("faro", [src], tmp_path / "m", FARO_ARGS)
    t2, p2 = read_tracker(tmp_path / "m" / e2[0]["path"], fs_hz=815.0)
    np.testing.assert_allclose(p2, p, atol=1e-4)
    np.testing.assert_allclose(t2, np.arange(1500) / 815.0, atol=1e-9)


def test_tracker_fine_stamps_give_the_rate(tmp_path):
    src = tmp_path / "fine.csv"
    t = np.arange(500) / 1000.0
    src.write_text("Name,X,Y,Z,Time\n" + "".join(
        f"P{k},{k * 0.01:.4f},0,0,{tk:.6f}\n" for k, tk in enumerate(t)))
    e = run("faro", [src], tmp_path / "o", ["--direction", "px", "--feed-mm-s", "10"])
    assert e[0]["fs_hz"] == 1000.0


def test_tracker_bad_inputs(tmp_path):
    one_error("spatialanalyzer", SA, tmp_path, ["--direction", "py", "--feed-mm-s", "2"],
              match=r"column Timestamp: time stamps are coarse or uneven .* and no rate was "
                    r"stated; 1000 samples over 1.22 s of stamps suggest about 81[0-9] Hz "
                    r"\(expected --fs-hz RATE")
    one_error("spatialanalyzer", SA, tmp_path, ["--direction", "py", "--feed-mm-s", "2",
                                                "--fs-hz", "400"],
              match=r"column Timestamp: time stamps span 1.2[0-9]* s, 1000 samples at 400 Hz "
                    r"span 2.4975 s")
    lines = FARO.read_text().splitlines()
    trunc = tmp_path / "trunc.csv"
    trunc.write_text("\n".join(lines[:300] + [lines[300][:12]]) + "\n")
    one_error("faro", trunc, tmp_path, FARO_ARGS,
              match=r"line 301: row has 2 fields, the header has 5 \(truncated last row\?\)")
    noz = tmp_path / "noz.csv"
    noz.write_text("\n".join(",".join(ln.split(",")[:3]) for ln in lines) + "\n")
    one_error("faro", noz, tmp_path, FARO_ARGS,
              match=r"header \(first 200 lines\): no header row naming X, Y, Z")
    one_error("faro", TDMS, tmp_path, FARO_ARGS, match=r"binary file, not a text export")
    one_error("faro", FARO, tmp_path, ["--feed-mm-s", "1"],
              match=r"option --direction: no feed direction \(expected --direction px, mx, py or "
                    r"my, or --direction-deg DEG\)")
    text = tmp_path / "text.csv"
    fields = lines[10].split(",")
    fields[2] = "abc"
    text.write_text("\n".join(lines[:10] + [",".join(fields)] + lines[11:]) + "\n")
    one_error("faro", text, tmp_path, FARO_ARGS,
              match=r"line 11, column Y \(mm\): value 'abc' is not a number")


def test_cut_given_for_several_sources(tmp_path):
    with pytest.raises(RawDataError, match=r"option --cut: --cut c given for 2 source files"):
        run("smats", [SINE, SDF], tmp_path, ["--cut", "c"])


def test_time_axis_rebuilds_checks_and_refuses(tmp_path):
    from robomill.importers._common import time_axis

    src = tmp_path / "stream.txt"
    fs = 815.0
    true = 0.25 + np.arange(2000) / fs
    ms = np.round(true, 3)  # stamps printed to the millisecond: 1 or 2 ms steps
    t, rate, jitter = time_axis(src, ms, ms.size, fs, column="Time")
    np.testing.assert_allclose(t - t[0], np.arange(2000) / fs, atol=1e-12)
    assert rate == fs and jitter <= 1e-3
    fine = np.round(true, 7)  # fine stamps: the grid is kept and gives the rate
    t2, rate2, jitter2 = time_axis(src, fine, fine.size, None, column="Time")
    assert rate2 == fs and jitter2 < 1e-7
    with pytest.raises(RawDataError, match=r"column Time: time stamps give 815 Hz \(expected "
                                           r"--fs-hz 800 within 0.1 %"):
        time_axis(src, fine, fine.size, 800.0, column="Time")
    gap = np.delete(ms, np.arange(1000, 1005))
    with pytest.raises(RawDataError, match=r"sample 1000, column Time: gap of 0.00[67]\d* s "
                                           r"between two samples"):
        time_axis(src, gap, gap.size, fs, column="Time")
    with pytest.raises(RawDataError, match=r"sample 10, column Time: time goes backwards"):
        time_axis(src, np.r_[ms[:10], ms[8:]], ms.size, fs, column="Time")
