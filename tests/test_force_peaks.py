"""Peaks that are peaks (issue 32.1, forces): a reported peak is a local maximum standing out
of its local floor, never the skirt of an excluded line; none qualifying gives NaN; its
frequency is interpolated within the bin. Truth is planted in synthetic records."""

import numpy as np
import pandas as pd
import pytest

from robomill.forces.peaks import dominant_peak
from robomill.forces.settings import ForceAnalysisSettings
from robomill.forces.stream import analyse_force_record
from robomill.forces.study import force_cut_dataset, gather_force_study
from robomill.spectra import peak_offset_bins, prominent_peaks, thesis_spectrum

FS = 10_000.0
RPM = 5994.0  # a 2-tooth spindle a little slow: tooth passing 199.8 Hz, the spindle 99.9 Hz
CUT = {"id": "s1_g1_py", "set": 1, "segment": 1, "direction": "py", "feed_mm_s": 5.0,
       "depth_mm": 3.0}


def _record(seconds=1.0, weak_hz=None, weak_N=2.0, seed=7):
    """A strong tooth-passing line (100 N at 199.8 Hz, its frequency wandering ±0.6 Hz so
    that its skirt spreads over several bins with ripples, the spindle's 99.9 Hz line at
    30 N), white noise of 0.5 N rms, and optionally a weak line elsewhere."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(seconds * FS))) / FS
    tp = RPM / 60 * 2
    phase = 2 * np.pi * tp * t + 0.6 / 0.7 * np.sin(2 * np.pi * 0.7 * t)
    y = 100.0 * np.cos(phase) + 30.0 * np.cos(np.pi * tp * t + 0.4)
    if weak_hz is not None:
        y = y + weak_N * np.cos(2 * np.pi * weak_hz * t + 1.0)
    F = np.column_stack([0.5 * y, y, 0.2 * y]) + rng.normal(0.0, 0.5, (t.size, 3))
    return t, F + np.array([40.0, -60.0, 20.0])


def _cut_dataset(t, F):
    res = analyse_force_record([(t, F)], FS, t.size, ForceAnalysisSettings())
    return res, force_cut_dataset(res, cut=CUT, fs_hz=FS, n_samples=t.size, spindle_rpm=RPM,
                                  flutes=2, n_harmonics=5)


def _old_rule(res):
    """The former pick: the largest bin of the band, harmonics ±2.5 bins left out."""
    f, P = res["f_low"], res["power_low"].sum(axis=0)
    ok = (f >= 15) & (f <= 250)
    for k in range(1, 4):
        ok &= np.abs(f - k * RPM / 60) > 2.5 * res["lowband_resolution_hz"]
    return f[np.flatnonzero(ok)[np.argmax(P[ok])]]


def test_skirt_of_an_excluded_line_is_not_a_peak_and_a_weak_real_line_is():
    t, F = _record(weak_hz=137.4)
    res, ds = _cut_dataset(t, F)
    # the former rule picked the skirt beside the 199.8 Hz line
    assert abs(_old_rule(res) - 199.8) < 5.0
    # now the weak real line (2 N against a 100 N line) is the dominant peak, interpolated
    assert float(ds["dominant_hz"]) == pytest.approx(137.4, abs=0.1)
    assert not bool(ds["dominant_below_resolution"])


def test_no_peak_beside_an_excluded_line_is_empty():
    t, F = _record(weak_hz=None)
    res, ds = _cut_dataset(t, F)
    assert abs(_old_rule(res) - 199.8) < 5.0  # what the old rule reported: leakage
    assert np.isnan(float(ds["dominant_hz"])) and np.isnan(float(ds["dominant_power"]))
    assert bool(ds["dominant_below_resolution"])  # a missing peak is flagged
    # the kinematic band (0.3-1 1/mm at 5 mm/s: 1.5-5 Hz) holds only noise: empty too
    assert np.isnan(float(ds["kinematic_per_mm"]))
    # and the study's peaks table carries the empties
    other = dict(CUT, id="s1_g1_px", direction="px", feed_mm_s=10.0)
    ds2 = force_cut_dataset(res, cut=other, fs_hz=FS, n_samples=t.size, spindle_rpm=RPM,
                            flutes=2, n_harmonics=5)
    third = dict(CUT, id="s1_g1_my", direction="my", feed_mm_s=15.0)
    ds3 = force_cut_dataset(res, cut=third, fs_hz=FS, n_samples=t.size, spindle_rpm=RPM,
                            flutes=2, n_harmonics=5)
    peaks = gather_force_study([ds, ds2, ds3], flutes=2)[1]
    assert isinstance(peaks, pd.DataFrame) and peaks["dominant_hz"].isna().all()


def test_ripple_on_a_skirt_is_not_prominent():
    """A skirt falling from a strong line with a ripple (a local maximum) on it, 1 Hz bins."""
    f = np.arange(0.0, 251.0)
    P = 1.0 + 1e4 / (1.0 + ((f - 200.0) / 0.8) ** 2)
    P[206] *= 1.5  # a ripple: a local maximum of the skirt, far above the floor
    assert P[205] < P[206] > P[207]
    P[137] = 300.0  # a real line on the floor
    idx = prominent_peaks(f, P, (15, 250), prominence_db=15.0, floor_half_width=25.0,
                          exclude=[200.0], exclude_width=2.5)
    assert f[idx].tolist() == [137.0]
    # it is the prominence over the floor that leaves the ripple out: with none required it
    # is a peak
    assert 206.0 in f[prominent_peaks(f, P, (15, 250), prominence_db=0.0, floor_half_width=25.0,
                                      exclude=[200.0], exclude_width=2.5)]
    assert np.isnan(dominant_peak(f, np.where(f == 137, 1.0, P), (15, 250),
                                  exclude_hz=[200.0], exclude_width_hz=2.5)[0])


@pytest.mark.parametrize("offset_hz", [0.0, 0.2, 0.3, 0.5, 0.7, 0.85])
def test_off_bin_line_is_interpolated_within_a_tenth_of_a_bin(offset_hz):
    """A line at 200 Hz + offset in a 1 s record (1 Hz bins): the bin alone is up to half a
    bin off; the interpolated peak is within 0.1 Hz (the log-parabola alone gave 199.87 for
    a real 200 Hz line at 199.8 + 0.2 bins)."""
    t = np.arange(10_000) / FS
    f0 = 200.0 + offset_hz
    x = 3.0 * np.cos(2 * np.pi * f0 * t + 0.3)
    x = x + np.random.default_rng(1).normal(0, 0.05, t.size)
    spec = thesis_spectrum(x, FS)
    f_hat, _ = dominant_peak(spec.f, spec.power, (15.0, 400.0))
    assert f_hat == pytest.approx(f0, abs=0.1)


def test_grid_offset_record_of_a_200_hz_line():
    """10 001 samples at 10 kHz (a DynoWare 1 s window): bins of 0.9999 Hz, 200 Hz between
    them; the estimate is 199.9-200.1 Hz."""
    t = np.arange(10_001) / FS
    spec = thesis_spectrum(np.cos(2 * np.pi * 200.0 * t), FS)
    f_hat, _ = dominant_peak(spec.f, spec.power, (15.0, 400.0))
    assert 199.9 <= f_hat <= 200.1


def test_broad_peak_takes_the_log_parabola():
    """A resonance over many bins (Gaussian top, centre 0.37 bin off): the log-parabola is
    exact for it, the rectangular line formula would not be."""
    k = np.arange(-20.0, 21.0)
    P = np.exp(-0.5 * ((k - 0.37) / 3.0) ** 2)
    assert peak_offset_bins(P, 20, window="rect") == pytest.approx(0.37, abs=1e-9)
    assert peak_offset_bins(P, 20, window="hann") == pytest.approx(0.37, abs=1e-9)


def test_hann_windowed_line_uses_the_log_parabola():
    n = 4096
    w = np.hanning(n)
    for d in (0.1, 0.25, 0.4):
        x = np.cos(2 * np.pi * (300 + d) * np.arange(n) / n) * w
        P = np.abs(np.fft.rfft(x)) ** 2
        assert 300 + peak_offset_bins(P, 300, window="hann") == pytest.approx(300 + d, abs=0.02)


def test_no_peak_has_no_nearest_mode():
    from robomill.forces.peaks import nearest_modes

    modes = pd.DataFrame({"mode": [1, 2], "f_n_hz": [60.0, 85.0]})
    t = nearest_modes(np.array([61.0, np.nan, 84.0]), modes)
    assert t["nearest_mode"].tolist() == [1, None, 2]
    assert np.isnan(t["nearest_mode_hz"].iloc[1]) and np.isnan(t["offset_hz"].iloc[1])
    np.testing.assert_allclose(t["offset_hz"].iloc[[0, 2]], [1.0, -1.0])
