"""Peaks that are peaks (issue 32.1) in the surface and straightness spectra: local maxima that
stand out of their neighbourhood, never a side lobe or the skirt of a stronger line; none
qualifying gives none; frequencies interpolated within the bin."""

from __future__ import annotations

import numpy as np
import pytest

from robomill.spectra import find_peaks_spectrum, interpolate_peak, thesis_spectrum
from robomill.straightness.profile import Profile, profile_spectrum, spectrum_peaks
from robomill.surface.options import settings
from robomill.surface.peaks import profile_peaks
from robomill.surface.psd import analyse_profile

DS_MM, N = 0.01, 4000  # a 40 mm straightness profile: resolution 1/L = 0.025 1/mm
RES = 1.0 / (N * DS_MM)


def _profile(lines, noise_um=0.002, seed=3) -> Profile:
    """A straightness profile: lateral sinusoids ``(amplitude_um, f_per_mm)`` plus white noise."""
    rng = np.random.default_rng(seed)
    s = np.arange(N) * DS_MM
    lat = sum(a * np.sin(2 * np.pi * f * s + 0.7) for a, f in lines) + rng.normal(0, noise_um, N)
    dev = np.vstack([lat, rng.normal(0, noise_um, N)])
    return Profile(s, dev, np.zeros(3), np.array([N * DS_MM, 0, 0]), np.array([1.0, 0, 0]),
                   DS_MM, 1.0)


def _peaks(prof, **kw):
    spec = profile_spectrum(prof, nfft=32768)
    return spectrum_peaks(spec, fmin_per_mm=0.1, fmax_per_mm=20.0, threshold=25.0, n_peaks=20,
                          **kw)


def test_skirt_bump_is_no_peak_but_a_weak_line_beside_a_strong_one_is():
    f = np.arange(400) * 0.1
    k = np.arange(400)
    power = 1e-3 + 1e3 / (1.0 + (k - 100.0) ** 2)  # a strong line at bin 100 and its skirt
    power[108] *= 1.4  # a bump on the skirt: a local maximum far above the band median
    power[139:142] += [0.2, 5.0, 0.2]  # a genuine weak line at bin 140
    plain = find_peaks_spectrum(f, power, fmin=1.0, fmax=39.0, n=5, prominence_ratio=5.0)
    assert [round(x / 0.1) for x, _ in plain] == [100, 108, 140]  # the old rule: the bump too
    found = find_peaks_spectrum(f, power, fmin=1.0, fmax=39.0, n=5, prominence_ratio=5.0,
                                local_ratio=1.0, halfwidth_points=10)
    assert [round(x / 0.1) for x, _ in found] == [100, 140]


def test_a_monotonic_skirt_alone_gives_no_peak():
    f = np.arange(400) * 0.1
    power = 1e3 / (1.0 + (np.arange(400) + 20.0) ** 2)  # the line lies below the band
    assert find_peaks_spectrum(f, power, fmin=1.0, fmax=39.0, prominence_ratio=5.0,
                               local_ratio=1.0, halfwidth_points=10) == []


def test_straightness_finds_a_weak_line_beside_a_strong_one_and_no_side_lobe():
    f_strong, f_weak = 2.0 + 0.37 * RES, 2.0 + 6.2 * RES  # 40 dB apart, 5.8 bins apart
    prof = _profile([(30.0, f_strong), (0.3, f_weak)])
    plain = _peaks(prof)  # band threshold alone: the strong line's Hann side lobes pass
    assert len(plain) > 2
    pk = _peaks(prof, local_ratio=1.5, floor_halfwidth_bins=25)
    assert len(pk) == 2
    assert pk["f_spatial_per_mm"].to_numpy() == pytest.approx([f_strong, f_weak], abs=0.25 * RES)
    assert pk["amplitude_um"].to_numpy() == pytest.approx([30.0, 0.3], rel=0.15)


def test_straightness_noise_alone_gives_an_empty_table():
    pk = _peaks(_profile([]), local_ratio=1.5, floor_halfwidth_bins=25)
    assert pk.empty
    assert list(pk.columns) == ["f_spatial_per_mm", "amplitude_um", "component", "snr"]


def test_straightness_peak_frequency_is_interpolated_within_the_bin():
    df = 1.0 / (32768 * DS_MM)  # zero-padded grid step (about RES / 8)
    f_true = 250 * df + 0.45 * df  # almost half-way between two grid points
    pk = _peaks(_profile([(5.0, f_true)]), local_ratio=1.5, floor_halfwidth_bins=25)
    assert len(pk) == 1
    f_found = float(pk["f_spatial_per_mm"].iloc[0])
    assert abs(f_found - f_true) < 0.05 * df  # the nearest grid point is 0.45 df away


def test_interpolation_of_an_unpadded_thesis_spectrum_beats_the_bin():
    fs, n = 100.0, 4000  # 40 mm at 100 /mm: bins of 0.025 /mm
    x = np.arange(n) / fs
    f_true = 8.0 + 0.3 * fs / n
    spec = thesis_spectrum(np.sin(2 * np.pi * f_true * x), fs)
    k = int(np.argmax(spec.power))
    assert abs(spec.f[k] - f_true) == pytest.approx(0.3 * fs / n)
    # parabola on the log of a sinc² main lobe: biased, but nearer than the bin (0.17 bin)
    assert abs(interpolate_peak(spec.f, spec.power, k) - f_true) < 0.2 * fs / n


def test_interpolation_falls_back_to_the_bin_at_the_ends_and_on_zero_power():
    f = np.arange(5.0)
    assert interpolate_peak(f, np.array([3.0, 1.0, 0.5, 0.2, 0.1]), 0) == 0.0
    assert interpolate_peak(f, np.array([0.0, 1.0, 2.0, 1.0, 0.0]), 2) == 2.0
    assert interpolate_peak(f, np.array([0.0, 0.0, 2.0, 1.0, 0.5]), 2) == 2.0


def test_surface_profile_without_a_line_in_the_roughness_band_reports_none_there():
    fs = 200.0  # 40 mm at 200 /mm, waviness only (a smooth 0.4 /mm cosine, no noise)
    x = np.arange(8000) / fs
    ds = analyse_profile(x, 4.0 * np.cos(2 * np.pi * 0.4 * x), {"lambda_c_mm": 0.5})
    pk = profile_peaks(ds, settings({}))
    assert (pk["band"] == "roughness").sum() == 0  # only the waviness line's leakage there
    wav = pk[pk["band"] == "waviness"]
    assert wav["f_spatial_per_mm"].tolist() == pytest.approx([0.4], abs=0.1 / 40.0)
