"""Issue "lab formats", "Done means": a raw folder built only from public real impact files
in the form a lab's software writes them runs ``snakemake -j2 ch3_modal`` with the default
``config.yaml``, and the identified natural frequencies agree within 1 % with the peaks of an
H1 estimate computed here, independently (plain NumPy FFTs of the source samples, not the
stage's windows or pyFRF).

Forms: a LabVIEW ``.lvm`` (force and two accelerations, two hits in one file; lvm-read's
test data), NumPy arrays of time, force and acceleration (two hits, pyFRF's 2016
measurements) through ``robomill import text``, and an analyser-style ``.mat`` H1 with its
coherence (the H1 of those two hits computed here, written with SciPy) through ``robomill
import mat --frf``: an FRF-only test, its band from the coherence. Sources and licences:
``tests/data/real/impact/SOURCE.md``.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import scipy.io
import scipy.signal
import xarray as xr
from conftest import REPO, run_snakemake

pytestmark = [pytest.mark.pipeline]

REAL = REPO / "tests" / "data" / "real" / "impact"
ROBOMILL = Path(sys.executable).parent / "robomill"
LVM = REAL / "lvm_read_long_single_header_multi_ch.lvm"
NPY = [REAL / "pyfrf_measurements_1_0.5s.npy", REAL / "pyfrf_measurements_2_0.5s.npy"]


def robomill(*args) -> None:
    proc = subprocess.run([str(ROBOMILL), *map(str, args)], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, (args, proc.stdout, proc.stderr)


def h1(records, fs_hz):
    """H1 = ΣX·F*/Σ|F|² and the coherence over whole records ``(force, accel)``."""
    sxf = sff = sxx = 0
    for force, acc in records:
        F = np.fft.rfft(force - np.median(force))
        X = np.fft.rfft(acc - np.median(acc))
        sxf, sff, sxx = sxf + X * np.conj(F), sff + np.abs(F) ** 2, sxx + np.abs(X) ** 2
    f = np.fft.rfftfreq(len(records[0][0]), 1 / fs_hz)
    return f, sxf / sff, np.abs(sxf) ** 2 / (sff * sxx)


def strong_peaks(f, h, band, fraction=0.2):
    """Frequencies of the |H| peaks in ``band`` with a prominence above ``fraction`` of the
    largest |H| there."""
    mag = np.where((f > band[0]) & (f < band[1]), np.abs(h), 0.0)
    pk, _ = scipy.signal.find_peaks(mag, prominence=fraction * mag.max())
    return f[pk]


def study(tmp_path, imports):
    raw = tmp_path / "raw"
    robomill("init", raw)
    for fmt, sources, args in imports:
        robomill("import", fmt, *sources, "--to", raw, *args)
    robomill("manifest", raw)
    robomill("check", raw)
    work = tmp_path / "work"
    work.mkdir()
    proc = run_snakemake(work, "-j2", "ch3_modal", "--config", f"data={raw}",
                         configfile=REPO / "config.yaml")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert (work / "results/chapters/ch3_modal.html").exists()
    modes = pd.read_csv(work / "results/modal/modes.csv")
    return work, np.sort(modes["f_n_hz"].to_numpy())


def assert_found(peaks, f_n, rtol=0.01):
    for p in peaks:
        assert np.min(np.abs(f_n / p - 1)) < rtol, (p, f_n)


def test_lvm_hammer_and_two_accelerometers(tmp_path):
    import lvm_read

    work, f_n = study(tmp_path, [("lvm", [LVM], [
        "--hammer", "F:N", "--invert-hammer", "--response", "m_1:X", "--response", "m_2:2X",
        "--direction", "X"])])
    d = lvm_read.read(str(LVM), read_from_pickle=False, dump_file=False)[0]["data"]
    fs = 1 / 0.000977
    for col in (1, 2):  # each accelerometer's H1 over the two 8192-sample halves of the file
        recs = [(-d[s:s + 8192, 0], d[s:s + 8192, col]) for s in (0, 8192)]
        f, h, _ = h1(recs, fs)
        peaks = strong_peaks(f, h, (5.0, 500.0))  # the close pair near 19.7 and 21.1 Hz
        assert peaks.size >= 2, peaks
        assert_found(peaks, f_n)
    frf = xr.open_dataset(work / "results/modal/frf.nc")
    assert frf.attrs["directions_measured"] == "X"
    assert frf.attrs["directions_not_measured"] == "YZ"
    html = (work / "results/chapters/ch3_modal.html").read_text()
    assert "Not measured: Y and Z" in html


def test_numpy_arrays_through_the_text_importer(tmp_path):
    work, f_n = study(tmp_path, [("text", NPY, [
        "--time", "1", "--hammer", "2:N", "--response", "3:X:m/s^2", "--direction", "X"])])
    recs = [(np.load(p)[1], np.load(p)[2]) for p in NPY]
    f, h, _ = h1(recs, 25600.0)
    peaks = strong_peaks(f, h, (20.0, 3400.0))
    assert peaks.size >= 3, peaks
    assert_found(peaks, f_n)
    hits = pd.read_csv(work / "results/modal/hits.csv")
    assert hits["accepted"].all() and sorted(hits["hit"]) == [1, 2]


def test_an_analysers_mat_h1_alone_band_from_its_coherence(tmp_path):
    recs = [(np.load(p)[1], np.load(p)[2]) for p in NPY]
    f, h, coh = h1(recs, 25600.0)
    # 2 Hz … 3.2 kHz: an analyser's span (the hammer tip excites up to about 3.5 kHz here:
    # the time-record study's band from the hammer spectrum ends at 3486 Hz)
    keep = slice(1, 1601)
    src = tmp_path / "analyser_h1.mat"
    scipy.io.savemat(src, {"H1": h[keep, None], "freq": f[keep], "coh": coh[keep, None]})
    work, f_n = study(tmp_path, [("mat", [src], [
        "--frf", "H1", "--freq", "freq", "--coherence", "coh", "--frf-unit", "m/s^2/N",
        "--response", "1:X", "--direction", "X"])])
    synth = xr.open_dataset(work / "results/modal/frf_synth.nc")
    assert synth.attrs["band_source"] == "data"
    lo, hi = synth.attrs["band_hz"]
    peaks = strong_peaks(f, h, (lo, hi))
    assert peaks.size >= 2, (peaks, lo, hi)
    assert_found(peaks, f_n)
    html = (work / "results/chapters/ch3_modal.html").read_text()
    assert "FRFs imported from a modal test system" in html
