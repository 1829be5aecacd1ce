"""The tracker's measurement noise in the waviness prediction: its level near each gear line
of the identifying runs, scaled to the next cut's record, and the interval of the amplitude
the next run's spectrum will read at the predicted lines.

**The noise level.** The tracker samples at f_s with white noise of variance s² per axis. A
record of duration T = L/v (path length L, feed v) holds N = f_s T samples; the spatial
resampling of the profile (:func:`robomill.straightness.profile.resample_uniform`) averages
or interpolates them but keeps their noise density at the gear lines, far below the raw
Nyquist frequency. The Hann-windowed, coherent-gain corrected amplitude spectrum (thesis eqs.
2.1–2.3, :func:`robomill.straightness.profile_spectrum`), A(f) = 2 |Σₙ wₙ xₙ e^{−i2πfn/f_s}|
/ Σₙ wₙ, of that noise is a complex Gaussian N(f) with

    σ² = E|N(f)|² = 4 s² Σw² / (Σw)² = 4 s² (3N/8) / (N/2)² = 6 s² / N,

at every frequency of the (zero-padded) grid, so σ = s √(6/(f_s T)): the product σ √T =
s √(6/f_s) is the instrument's own constant, and the same tracker records the next cut of
duration T' with σ' = σ √(T/T') — the amplitude per bin falls as 1/√(number of samples along
the path). (Noise along the path makes the grid cells' sample counts vary, and their
unweighted means lose a little of the samples' information: the floor rises by ~10 % at a
few samples per cell, tests/test_plan_waviness_noise.py; the identifying runs' floors carry
it, the scaling to another feed does not.)

:func:`noise_floor_um` estimates σ from a run's spectrum: |N| is Rayleigh distributed,
P(|N| > x) = exp(−x²/σ²), with median σ √(ln 2), so σ̂ = median/√(ln 2) over a band of
± ``band_bins`` resolution bins 1/L around the line, without the Hann main lobe
(± ``exclude_bins`` = 2 bins) of the line itself and of every other detected peak, and above
the run's lowest resolvable frequency (the median ignores the few undetected lines left).

**The read amplitude.** The outcome (:func:`robomill.plan.check.waviness_outcomes`) reads a
line as the largest |a W(f − f₀) e^{iφ} + N(f)| over the K grid points within ±0.5 bins of the
predicted frequency (:func:`robomill.plan.measured.spectrum_amplitude_um`), W the window's
normalised response (|W| ≤ 1, 1 at the line). Two bounds give its interval:

* **below**, the grid point nearest the line reads |a e^{iφ} + N|, Rice distributed with
  ν = a and per-quadrature σ/√2 (Rice 1944; Papoulis & Pillai 2002, §7-4): the read is at
  least that point's, so its β-quantile R_β(a, σ) (:func:`rice_quantile_um`) bounds the read's
  from below — above a for a ≲ σ: noise alone reads ≈ 0.83 σ (median);
* **above**, |a W e^{iφ} + N| ≤ a + max_k |N_k| and, by the union bound over the K points,
  P(max_k |N_k| > x) ≤ K exp(−x²/σ²), so a + σ √(ln(K/β)) is exceeded with probability ≤ β
  whatever the points' correlation (the max-over-bins bias included).

For a cut whose prediction sums G lines (in phase, :func:`robomill.plan.measured.waviness_um`)
each line takes β = (1 − coverage)/(2G) on either side; by Bonferroni the sum of the reads
falls outside the sum of the lines' intervals with probability ≤ 1 − coverage, given the
lines' amplitudes within their identification interval [a_low, a_high]. Lines closer than
the merge distance are read once over their joint window (more grid points but one noise
term, fewer than the G terms the sum adds). The interval is widened, never narrowed: its low
end is min(a_low, R_β) per line, its high end a_high + σ √(ln(K/β)). Both bounds and
Bonferroni are conservative: planted lines in white noise fall inside in more than the nominal
fraction (all of 300 seeded draws at a nominal 0.95, tests/test_plan_waviness_noise.py).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from robomill.settings import schema_default

RAYLEIGH_MEDIAN = float(np.sqrt(np.log(2.0)))
"""Median of |N| / σ for complex Gaussian N with E|N|² = σ² (Rayleigh)."""

SPECTRUM_PAD = 8
"""Zero-padding of :func:`robomill.straightness.profile_spectrum`: nfft = 2^⌈log₂(8 n)⌉, so
a resolution bin 1/L holds nfft/n < 2·8 grid points."""

READ_HALFWIDTH_BINS = 0.5
"""Half width of the outcome's read around a line (``halfwidth_bins`` of
:func:`robomill.plan.measured.spectrum_amplitude_um`)."""

READ_POINTS = 2 * int(np.floor(READ_HALFWIDTH_BINS * 2 * SPECTRUM_PAD)) + 1
"""K: the most grid points the read's window holds (17: fewer than 16 points per bin)."""


def record_duration_s(length_mm, feed_mm_s):
    """Duration T = L / v of a record along a path of ``length_mm`` at ``feed_mm_s`` [s]."""
    return np.asarray(length_mm, float) / np.asarray(feed_mm_s, float)


def noise_floor_um(profiles, run: str, f_per_mm: float, *, component: str = "lateral",
                   exclude_per_mm: Iterable[float] = (),
                   band_bins: float = schema_default("plan.waviness_noise", "band_bins"),
                   exclude_bins: float = schema_default("plan.waviness_noise", "exclude_bins")
                   ) -> float:
    """Per-bin noise level σ (RMS of the complex noise amplitude, E|N|² = σ²) of one component
    of a tracker run's amplitude spectrum near ``f_per_mm`` [µm]: σ̂ = median(|A|)/√(ln 2)
    over ± ``band_bins`` resolution bins 1/L around it, above the run's ``fmin_per_mm``,
    without ± ``exclude_bins`` around ``f_per_mm`` and every frequency of ``exclude_per_mm``
    (the run's detected peaks). NaN where the run is absent or nothing is left."""
    runs = [str(r) for r in profiles["run"].values]
    if run not in runs:
        return float("nan")
    k = runs.index(run)
    res = float(profiles["resolution_per_mm"].values[k])
    fmin = float(profiles["fmin_per_mm"].values[k]) if "fmin_per_mm" in profiles else 0.0
    f = profiles["f"].values.astype(float)
    amp = profiles["amplitude_um"].isel(run=k).sel(component=component).values
    keep = (np.abs(f - f_per_mm) <= band_bins * res) & (f >= fmin) & np.isfinite(amp)
    for fx in [f_per_mm, *exclude_per_mm]:
        keep &= np.abs(f - float(fx)) > exclude_bins * res
    return float(np.median(amp[keep]) / RAYLEIGH_MEDIAN) if keep.any() else float("nan")


def run_duration_s(profiles, run: str) -> float:
    """Duration of a tracker run's record [s]: its profile length over its median speed (the
    nominal feed where the run has no time base); NaN where the run is absent."""
    runs = [str(r) for r in profiles["run"].values]
    if run not in runs:
        return float("nan")
    k = runs.index(run)
    v = float(profiles["speed_mm_s"].values[k]) if "speed_mm_s" in profiles else np.nan
    if not (np.isfinite(v) and v > 0) and "feed_mm_s" in profiles:
        v = float(profiles["feed_mm_s"].values[k])
    return float(record_duration_s(float(profiles["length_mm"].values[k]), v))


def rice_quantile_um(q, nu_um, sigma_um):
    """β-quantile of |ν e^{iφ} + N| for complex Gaussian N with E|N|² = σ² (Rice: ν, σ/√2 per
    quadrature) [µm]; ν where σ is 0 or NaN."""
    from scipy.stats import rice

    nu, sig = np.broadcast_arrays(np.asarray(nu_um, float), np.asarray(sigma_um, float))
    ok = np.isfinite(sig) & (sig > 0) & np.isfinite(nu)
    scale = np.where(ok, sig / np.sqrt(2.0), 1.0)
    out = rice.ppf(np.broadcast_to(q, nu.shape), np.where(ok, nu, 0.0) / scale, scale=scale)
    return np.where(ok, out, nu)


def read_interval_um(a_low_um, a_high_um, sigma_um, beta, *, points: int = READ_POINTS):
    """One line's interval of the read amplitude [µm]: (min(a_low, R_β(a_low, σ)),
    a_high + σ √(ln(K/β))), each end exceeded with probability ≤ β (module docstring); the
    identification ends where σ is NaN (no noise estimate)."""
    a_lo, a_hi = np.asarray(a_low_um, float), np.asarray(a_high_um, float)
    sig = np.asarray(sigma_um, float)
    known = np.isfinite(sig)
    s = np.where(known, sig, 0.0)
    lo = np.minimum(a_lo, rice_quantile_um(beta, a_lo, np.where(known, sig, np.nan)))
    hi = a_hi + s * np.sqrt(np.log(points / np.asarray(beta, float)))
    return lo, hi
