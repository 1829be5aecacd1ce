"""Impact-test importers ``lvm``, ``mat``, ``text`` and the cut-recording importer
``recording``, on real public files (``tests/data/real/impact/SOURCE.md``): hits found and
split with their pre-trigger, units from the file or the command line, the analyser's FRFs,
and every refusal one line naming the file and what was expected, nothing written.

What is checked against what: the hit records written are compared with the source samples
read here with plain NumPy / lvm-read (not the importer's code); the ``.mat`` and text inputs
of the cross-format checks are the real pyFRF arrays written by the test itself (no public
``.mat`` impact record with a licence was found): the same samples must give the same hits
whatever the container.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.io
import yaml

from robomill.cli import main
from robomill.io.impact import read_frf_uff, read_hit_record

REAL = Path(__file__).parent / "data" / "real" / "impact"
LVM = REAL / "lvm_read_long_single_header_multi_ch.lvm"
LVM_SHORT = REAL / "lvm_read_short.lvm"
NPY = [REAL / "pyfrf_measurements_1_0.5s.npy", REAL / "pyfrf_measurements_2_0.5s.npy"]
LVM_ARGS = ["--hammer", "F:N", "--invert-hammer", "--response", "m_1:X", "--response",
            "m_2:2X", "--direction", "X"]
NPY_ARGS = ["--time", "1", "--hammer", "2:N", "--response", "3:X:m/s^2", "--direction", "X"]


def imp(fmt, sources, raw, args, capsys):
    rc = main(["import", fmt, *map(str, sources), "--to", str(raw), *args])
    out = capsys.readouterr().out
    return rc, out


def refused(fmt, sources, tmp_path, args, capsys, match):
    """One line naming the source and ``match``, then 'nothing was written'; no file."""
    raw = tmp_path / "raw"
    before = {p: p.read_bytes() for p in raw.rglob("*") if p.is_file()}
    rc, out = imp(fmt, sources, raw, args, capsys)
    lines = out.strip().splitlines()
    assert rc == 1, out
    assert len(lines) == 2 and lines[1].endswith("nothing was written"), out
    assert lines[0].startswith(str(sources[0])) and match in lines[0], lines[0]
    assert "Traceback" not in out
    assert {p: p.read_bytes() for p in raw.rglob("*") if p.is_file()} == before
    return lines[0]


def manifest(raw):
    return yaml.safe_load((raw / "manifest.yaml").read_text())


def test_lvm_two_hits_split_with_pretrigger_and_units(tmp_path, capsys):
    import lvm_read

    raw = tmp_path / "raw"
    rc, out = imp("lvm", [LVM], raw, LVM_ARGS, capsys)
    assert rc == 0, out
    files = [f for f in manifest(raw)["files"] if f["kind"] == "impact"]
    # two hits, each with a record per response node (m_1 at node 1, m_2 at node 2)
    assert sorted((f["hit"], f["response_node"]) for f in files) == [(1, 1), (1, 2), (2, 1),
                                                                     (2, 2)]
    assert {f["units"]["F"] for f in files} == {"N (command line; the file says g)"}
    assert {f["units"]["m_1"] for f in files} == {"m/s^2 (file)"}
    # the source read independently: F's pulses (negative: polarity reversed) at 85, 8276
    seg = lvm_read.read(str(LVM), read_from_pickle=False, dump_file=False)[0]["data"]
    force = -(seg[:, 0] - np.median(seg[:, 0]))
    pulses = np.flatnonzero(force > 0.1 * force.max())
    assert pulses[0] == 85 and pulses[-1] < 8290 and np.any(pulses > 8200)
    recs = {(f["hit"], f["response_node"]): read_hit_record(raw / f["path"]) for f in files}
    n = {r.force_N.size for r in recs.values()}
    assert len(n) == 1  # one record length
    h1 = recs[(1, 1)]
    pre = int(round(files[0]["pretrigger_s"] * h1.fs_hz))
    assert pre == 85  # all that precedes the first hit is kept
    assert h1.fs_hz == pytest.approx(1 / 0.000977, rel=1e-6)
    np.testing.assert_allclose(h1.force_N, force[:h1.force_N.size], rtol=1e-6, atol=1e-5)
    a2 = seg[:, 2] - np.median(seg[:, 2])
    np.testing.assert_allclose(recs[(1, 2)].accel_ms2[:, 0], a2[:h1.force_N.size], rtol=1e-6,
                               atol=1e-5)
    # hit 2's record starts 85 samples before its trigger
    h2 = recs[(2, 1)].force_N
    assert np.argmax(h2 > 0.1 * h2.max()) == 85


def test_lvm_refusals_are_one_line(tmp_path, capsys):
    refused("lvm", [LVM], tmp_path, ["--hammer", "F", "--response", "m_1:X", "--direction",
                                     "X"], capsys, "channel 'F' is in 'g' (file)")
    refused("lvm", [LVM], tmp_path, ["--hammer", "F:N", "--response", "m_1:X", "--direction",
                                     "X"], capsys, "the hammer pulses are negative")
    refused("lvm", [LVM], tmp_path, [*LVM_ARGS[:3], "--response", "acc:X", "--direction",
                                     "X"], capsys, "channel 'acc' is not in the file")
    refused("lvm", [LVM_SHORT], tmp_path, ["--hammer", "1", "--response", "2:X",
                                           "--direction", "X"], capsys, "no hammer hit")
    refused("lvm", [NPY[0]], tmp_path, LVM_ARGS, capsys, "first line is")
    refused("lvm", [LVM], tmp_path, LVM_ARGS[:-2], capsys, "no hammer direction")
    # X_Columns Multi: the time columns are not channels; a hammer in volts is not a force
    multi = REAL / "lvm_read_multi_time_column.lvm"
    refused("lvm", [multi], tmp_path, ["--hammer", "Voltage", "--response",
                                       "Acceleration:X", "--direction", "X"], capsys,
            "channel 'Voltage' is in 'Volts' (file)")
    refused("lvm", [multi], tmp_path, ["--hammer", "X_Value:N", "--response",
                                       "Acceleration:X", "--direction", "X"], capsys,
            "channel 'X_Value' is not in the file (expected one of 'Voltage', 'Acceleration'")


def test_npy_columns_need_units_and_give_one_hit_each(tmp_path, capsys):
    refused("text", NPY, tmp_path, ["--time", "1", "--hammer", "2", "--response", "3:X",
                                    "--direction", "X"], capsys, "no unit stated")
    raw = tmp_path / "ok"
    rc, out = imp("text", NPY, raw, NPY_ARGS, capsys)
    assert rc == 0, out
    files = manifest(raw)["files"]
    assert sorted(f["hit"] for f in files if f["kind"] == "impact") == [1, 2]
    for f in files:
        if f["kind"] != "impact":
            continue
        src = np.load(REAL / f["source_file"])
        rec = read_hit_record(raw / f["path"])
        assert rec.fs_hz == pytest.approx(25600.0)
        k = int(np.argmax(src[1] > 0.1 * src[1].max()))
        pre = int(round(f["pretrigger_s"] * 25600))
        assert pre == k  # the samples before the trigger are kept
        np.testing.assert_allclose(rec.force_N, (src[1] - np.median(src[1]))[:rec.force_N.size],
                                   rtol=1e-6, atol=1e-4)


def _pyfrf_as(kind: str, path: Path) -> Path:
    """The real pyFRF arrays written in another container (for the cross-format check)."""
    a = np.load(NPY[0])
    if kind == "csv":
        np.savetxt(path, a.T, delimiter=",", header="t [s],force [N],acc_x [m/s^2]",
                   comments="", fmt="%.10g")
    elif kind == "csv_decimal_comma":  # a European spreadsheet: ';' and decimal commas
        rows = [";".join(f"{v:.10g}".replace(".", ",") for v in row) for row in a.T]
        path.write_text("Zeit (s);Kraft (N);Beschl (m/s^2)\n" + "\n".join(rows) + "\n")
    elif kind == "mat5":
        scipy.io.savemat(path, {"force": a[1], "acc": a[2][:, None] * np.array([[1.0, 2.0]]),
                                "fs": 25600.0})
    elif kind == "mat73":
        import h5py

        with h5py.File(path, "w", userblock_size=512) as h5:
            h5["data"] = np.vstack([a[1], a[2]])  # stored transposed, as MATLAB does
            h5["Fs"] = np.array([[25600.0]])
        with open(path, "r+b") as fh:
            fh.write(b"MATLAB 7.3 MAT-file, written by the test".ljust(116))
    return path


@pytest.mark.parametrize("kind,fmt,args", [
    ("csv", "text", ["--hammer", "force", "--response", "acc_x:X"]),
    ("csv_decimal_comma", "text", ["--time", "Zeit", "--hammer", "Kraft", "--response",
                                   "Beschl:X"]),
    ("mat5", "mat", ["--hammer", "force:N", "--response", "acc[1]:X:m/s^2"]),
    ("mat73", "mat", ["--hammer", "1:N", "--response", "2:X:m/s^2"]),
])
def test_same_samples_same_hits_in_text_and_mat(tmp_path, capsys, kind, fmt, args):
    src = _pyfrf_as(kind, tmp_path / f"hit.{'mat' if kind.startswith('mat') else 'csv'}")
    raw = tmp_path / "raw"
    rc, out = imp(fmt, [src], raw, [*args, "--direction", "X"], capsys)
    assert rc == 0, out
    ref_raw = tmp_path / "ref"
    imp("text", [NPY[0]], ref_raw, NPY_ARGS, capsys)
    got = read_hit_record(raw / manifest(raw)["files"][-1]["path"])
    ref = read_hit_record(ref_raw / manifest(ref_raw)["files"][-1]["path"])
    assert got.fs_hz == pytest.approx(ref.fs_hz)
    np.testing.assert_allclose(got.force_N, ref.force_N, rtol=1e-6, atol=1e-4)
    np.testing.assert_allclose(got.accel_ms2, ref.accel_ms2, rtol=1e-6, atol=1e-3)


def test_mat_refusals_are_one_line(tmp_path, capsys):
    src = _pyfrf_as("mat5", tmp_path / "hit.mat")
    refused("mat", [src], tmp_path, ["--hammer", "force", "--response", "acc[1]:X",
                                     "--direction", "X"], capsys, "no unit stated")
    refused("mat", [src], tmp_path, ["--hammer", "hammer:N", "--response", "acc[1]:X:g",
                                     "--direction", "X"], capsys,
            "variable 'hammer' is not in the file")
    refused("mat", [src], tmp_path, ["--hammer", "force:N", "--response", "acc[3]:X:g",
                                     "--direction", "X"], capsys, "column 3 of 'acc'")
    refused("mat", [src], tmp_path, ["--direction", "X"], capsys,
            "no --hammer (time records) and no --frf (an analyser's FRFs)")
    junk = tmp_path / "notes.mat"
    scipy.io.savemat(junk, {"note": "hammer test of 3 May"})
    refused("mat", [junk], tmp_path, ["--hammer", "1:N", "--response", "2:X:g",
                                      "--direction", "X"], capsys, "no numeric variable")
    text = tmp_path / "text.mat"
    text.write_text("not a mat file\n")
    refused("mat", [text], tmp_path, ["--hammer", "1:N", "--response", "2:X:g",
                                      "--direction", "X"], capsys, "not a readable MAT file")


def _h1_from_pyfrf():
    """H1 and coherence of the two real pyFRF hits, by plain FFTs (an analyser's export)."""
    sxf = sff = sxx = 0
    for p in NPY:
        a = np.load(p)
        F = np.fft.rfft(a[1] - np.median(a[1]))
        X = np.fft.rfft(a[2] - np.median(a[2]))
        sxf, sff, sxx = sxf + X * np.conj(F), sff + np.abs(F) ** 2, sxx + np.abs(X) ** 2
    f = np.fft.rfftfreq(a.shape[1], 1 / 25600.0)
    return f, sxf / sff, np.abs(sxf) ** 2 / (sff * sxx)


@pytest.mark.parametrize("version", ["v5", "v7.3"])
def test_mat_frf_with_coherence_becomes_a_uff_frf_file(tmp_path, capsys, version):
    f, h1, coh = _h1_from_pyfrf()
    keep = slice(1, 4001)  # 2 Hz … 8 kHz
    src = tmp_path / "analyser.mat"
    if version == "v5":
        scipy.io.savemat(src, {"H1": h1[keep, None], "freq": f[keep], "coh": coh[keep, None]})
    else:  # MATLAB v7.3: HDF5, arrays transposed, complex as a (real, imag) compound
        import h5py

        cplx = np.dtype([("real", "f8"), ("imag", "f8")])
        h = np.empty((1, h1[keep].size), cplx)
        h["real"], h["imag"] = h1[keep].real, h1[keep].imag
        with h5py.File(src, "w", userblock_size=512) as h5:
            h5["H1"] = h
            h5["freq"] = f[keep][None, :]
            h5["coh"] = coh[keep][None, :]
        with open(src, "r+b") as fh:
            fh.write(b"MATLAB 7.3 MAT-file, written by the test".ljust(116))
    raw = tmp_path / "raw"
    rc, out = imp("mat", [src], raw, ["--frf", "H1", "--freq", "freq", "--coherence", "coh",
                                      "--frf-unit", "m/s^2/N", "--response", "1:X",
                                      "--direction", "X"], capsys)
    assert rc == 0, out
    e = manifest(raw)["files"][-1]
    assert e["path"].endswith(".uff") and e["uff_content"] == "frf"
    ds = read_frf_uff(raw / e["path"])
    jw = 2j * np.pi * f[keep]
    np.testing.assert_allclose(ds["H"].values[0, 0], h1[keep] / jw**2, rtol=1e-5)
    np.testing.assert_allclose(ds["coherence"].values[0, 0], coh[keep], rtol=1e-6)
    refused("mat", [src], tmp_path / "x", ["--frf", "H1", "--freq", "freq", "--response",
                                           "1:X", "--direction", "X"], capsys,
            "FRF unit not stated")


def test_recording_attached_to_a_cut_with_its_air_pass(tmp_path, capsys):
    sound = Path(__file__).parent / "data" / "real" / "chatter_sound"
    raw = tmp_path / "raw"
    rc, out = imp("recording", [sound / "rahimi_chatter_12500rpm_z4.flac"], raw,
                  ["--cut", "c1", "--spindle-rpm", "12500", "--flutes", "4"], capsys)
    assert rc == 0, out
    rc, out = imp("recording", [sound / "rahimi_nochatter.flac"], raw, ["--cut", "c1",
                                                                          "--air"], capsys)
    assert rc == 0, out
    rc, out = imp("recording", [LVM], raw, ["--cut", "c2", "--channel", "m_1"], capsys)
    assert rc == 0, out
    files = {f["path"]: f for f in manifest(raw)["files"]}
    assert files["sound/c1.flac"]["kind"] == "sound" and "pass" not in files["sound/c1.flac"]
    assert files["sound/c1_air.flac"]["pass"] == "air" and files["sound/c1_air.flac"]["cut"] == "c1"
    # the chatter verdicts read the imported entry as the cut's air pass
    from robomill.chatter.recordings import is_air_pass
    assert is_air_pass(files["sound/c1_air.flac"]) and not is_air_pass(files["sound/c1.flac"])
    vib = files["vibration/c2.csv"]
    assert vib["kind"] == "vibration" and vib["fs_hz"] == pytest.approx(1 / 0.000977)
    from robomill.io.recordings import read_vibration

    rec = read_vibration(raw / "vibration/c2.csv", fs_hz=vib["fs_hz"])
    assert rec.samples.shape == (16384, 1)
    assert main(["check", str(raw)]) in (0, 1)  # the manifest is read (cuts still lack keys)
    capsys.readouterr()
    refused("recording", [REAL / "LICENSE.lvm_read"], tmp_path, ["--cut", "c3"], capsys,
            "unknown file type")
    # the cut's conditions from a sidecar the lab wrote beside the recording
    side = tmp_path / "c4.yaml"
    side.write_text("spindle_rpm: 12500\nflutes: 4\nfeed_mm_min: 600\ndepth_mm: 0.5\n"
                    "tool_diameter_mm: 6\ndirection: px\n")
    rc, out = imp("recording", [sound / "rahimi_nochatter.flac"], raw,
                  ["--cut", "c4", "--sidecar", str(side)], capsys)
    assert rc == 0, out
    cut = next(c for c in manifest(raw)["cuts"] if c["id"] == "c4")
    assert cut["spindle_rpm"] == 12500 and cut["flutes"] == 4 and cut["depth_mm"] == 0.5
    assert cut["feed_mm_s"] == pytest.approx(10.0) and cut["direction"] == "px"
    side.write_text("rpm: 12500\n")
    rc, out = imp("recording", [sound / "rahimi_nochatter.flac"], tmp_path / "r7",
                  ["--cut", "c5", "--sidecar", str(side)], capsys)
    assert rc == 1 and out.splitlines()[0].startswith(f"{side}: sidecar key(s) rpm unknown")
    assert not (tmp_path / "r7").exists()
    refused("recording", [LVM], tmp_path, ["--cut", "c3", "--channel", "acc"], capsys,
            "channel 'acc' is not in the file")


@pytest.mark.parametrize("fmt", ["lvm", "mat", "text", "recording"])
def test_registered_and_help_says_what_it_reads(fmt, capsys):
    from robomill.importers import load_importer

    mod = load_importer(fmt)
    assert mod.FORMAT == fmt
    assert main(["import", fmt, "--help"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert " ".join(mod.DESCRIPTION.split()) in out
    assert ("--air" if fmt == "recording" else "--response CH:DIR[:unit]") in out


def test_mat_struct_fields_are_read_as_name_dot_field(tmp_path):
    """A MATLAB struct (an analyser's export groups channels so) gives one array per field."""
    import scipy.io

    from robomill.importers.mat import read_mat

    src = tmp_path / "rec.mat"
    force = np.linspace(0.0, 1.0, 7)
    scipy.io.savemat(src, {"rec": {"force": force, "acc": np.ones((7, 2)), "note": "hit"}})
    out = read_mat(src)
    np.testing.assert_array_equal(out["rec.force"], force)
    assert out["rec.acc"].shape == (7, 2) and "rec.note" not in out
