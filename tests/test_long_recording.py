"""Long force recordings: the per-cut analysis holds bounded memory at any length, and the
segmented low band of a long record measures what the whole-record one does."""

import json
import subprocess
import sys

import numpy as np
import pytest

from robomill.forces import ForceAnalysisSettings, ForceSpectrumAccumulator
from robomill.longrecord import write_record


def _low_band(x: np.ndarray, fs_hz: float, **settings):
    acc = ForceSpectrumAccumulator(fs_hz, x.shape[0], ForceAnalysisSettings(**settings))
    for i0 in range(0, x.shape[0], 50_000):
        acc.add(np.arange(i0, min(i0 + 50_000, x.shape[0])) / fs_hz, x[i0:i0 + 50_000])
    return acc.result()


def test_segmented_low_band_equals_whole_record_on_a_stationary_line():
    """A 40 Hz line (on the bin grid of both the 20 s record and 4 s segments): the whole-record
    thesis power P(k) and the mean over 4 s segments give the same line power, A²/4 per side
    summed to A²/2 over ±f, and the segmented grid is 1/4 s⁻¹."""
    fs, amp = 5000.0, 3.0
    t = np.arange(int(20 * fs)) / fs
    x = np.column_stack([10 + amp * np.sin(2 * np.pi * 40.0 * t), np.zeros_like(t),
                         np.zeros_like(t)])
    whole = _low_band(x, fs, decimation=10, lowband_hz=100.0, welch_nperseg=4096)
    seg = _low_band(x, fs, decimation=10, lowband_hz=100.0, welch_nperseg=4096,
                    lowband_max_s=4.0)
    assert whole["lowband_segments"] == 1 and seg["lowband_segments"] == 5
    assert np.diff(whole["f_low"])[0] == pytest.approx(1 / 20.0)
    assert np.diff(seg["f_low"])[0] == pytest.approx(1 / 4.0)
    p_whole = whole["power_low"][0, np.argmin(np.abs(whole["f_low"] - 40.0))]
    p_seg = seg["power_low"][0, np.argmin(np.abs(seg["f_low"] - 40.0))]
    assert p_seg == pytest.approx(p_whole, rel=1e-3)
    # within 0.5 %: the anti-alias filter starts from rest on the line's first samples
    assert p_whole == pytest.approx(amp**2 / 2, rel=5e-3)


def _analyse_in_fresh_process(path) -> dict:
    out = subprocess.run([sys.executable, "-m", "robomill.longrecord", "analyse", str(path)],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_peak_memory_does_not_grow_with_record_length(tmp_path):
    """8× the samples (60 s → 480 s at 25 kHz, 36 M values more than 200 MB as float64) must
    not raise the analysing process's peak RSS by more than the bounded buffers (one low-band
    segment, the read block): the record is streamed, never held."""
    short = _analyse_in_fresh_process(write_record(tmp_path / "short.h5", 60.0))
    long = _analyse_in_fresh_process(write_record(tmp_path / "long.h5", 480.0))
    assert long["n_samples"] == 8 * short["n_samples"] == 12_000_000
    grown_data_mib = (long["n_samples"] - short["n_samples"]) * 3 * 8 / 2**20
    grown_rss_mib = long["peak_rss_mib"] - short["peak_rss_mib"]
    assert grown_data_mib > 200
    assert grown_rss_mib < 48, (short, long)
    assert long["lowband_segments"] == 1  # 480 s > lowband_max_s (300 s): one full segment
    np.testing.assert_allclose(long["mean_N"], 30.0, atol=0.01)
