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
line as the largest |a W(δ_k) e^{iφ} + N(δ_k)| over the K grid points δ_k within ±0.5 bins of
the predicted frequency (:func:`robomill.plan.measured.spectrum_amplitude_um`), W the Hann
window's normalised response (|W| ≤ 1, 1 at the line) and N the noise at those points,
complex Gaussian with E|N|² = σ² and the correlation of the Hann-windowed spectrum between
points Δ bins apart, C(Δ) = Σ w_n² e^{−i2πΔn/M} / Σ w_n² [Harris 1978] (points within a bin
are nearly one: the read is not the largest of K independent values).

**The interval of the sum of the reads** (:func:`read_sum_interval_um`) is the central
``coverage`` range of its distribution, computed by Monte Carlo over a fixed set of seeded
draws (common to every candidate, so the interval is a deterministic function of its inputs):
per line g, its amplitude a_g drawn from its identification interval [a_low, a_high] (a split
normal about the nominal: its ends at the interval's level ``level``, truncated at 0), a phase
φ_g, and the window's correlated noise scaled by σ_g; the read is the largest over the window,
and the reads add over the lines. The identification uncertainty and the read's noise then
combine as the independent errors they are, and the lines' noises as independent terms of a
sum, instead of adding each term's end at its own extreme: the bounds the interval had before
(each line's Rice β-quantile below, a + σ √(ln(K/β)) above by the union bound over the K
points, β = (1 − coverage)/(2G) by Bonferroni over the lines, added to the identification
ends) held every one of 300 planted draws at a nominal 0.95, where this range holds the
nominal share and is narrower (``tests/test_plan_waviness_noise.py``). On a default-study plan
whose planned cuts (20–30 mm/s) carry one gear line each, the bounds gave half-widths of
91–127 % of the prediction and this range 59–77 % (recomputed from their ``plan.csv`` rows).
What stays wide is the noise itself: a record of 40 mm at 20–30 mm/s lasts 1.3–2 s, and its
per-bin noise σ (0.36–0.47 µm) is comparable to a 1 µm line. :func:`read_interval_um` keeps
the bounds for one line.

Harris 1978: Harris, F. J. On the use of windows for harmonic analysis with the discrete
Fourier transform. *Proceedings of the IEEE* 66(1), 51–83, 1978.
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


READ_DRAWS = 1000
"""Draws of the Monte Carlo of :func:`read_sum_interval_um` (the 2.5 % quantile then has a
standard error of 0.5 % in probability)."""

READ_SEED = 20240607
"""Seed of those draws (fixed: the interval is a deterministic function of its inputs)."""

_WINDOW_LENGTH = 4096
"""Samples of the Hann window whose response and noise correlation the draws use (both converge
as the record grows; at 4096 within 1e-6 of their limits at the read's offsets)."""


def read_window_offsets_bins(points: int = READ_POINTS) -> np.ndarray:
    """The K grid points of the read's window, evenly over ±``READ_HALFWIDTH_BINS`` [bins]."""
    return np.linspace(-READ_HALFWIDTH_BINS, READ_HALFWIDTH_BINS, int(points))


def hann_response(offsets_bins, length: int = _WINDOW_LENGTH) -> np.ndarray:
    """The Hann window's normalised complex response W(δ) = Σ w_n e^{−i2πδn/M} / Σ w_n at
    offsets δ [bins] (1 at 0) [Harris 1978]."""
    n = np.arange(length)
    w = 0.5 - 0.5 * np.cos(2 * np.pi * n / length)
    d = np.asarray(offsets_bins, float)
    return np.exp(-2j * np.pi * np.multiply.outer(d, n) / length) @ w / w.sum()


def window_noise_draws(n_draws: int = READ_DRAWS, *, seed: int = READ_SEED,
                       points: int = READ_POINTS) -> np.ndarray:
    """``(n_draws, K)`` complex Gaussian noise at the read window's K points, E|N|² = 1 at each
    and the Hann spectrum's correlation C(δ_k − δ_l) = Σ w_n² e^{−i2π(δ_k−δ_l)n/M} / Σ w_n²
    between them (module docstring)."""
    d = read_window_offsets_bins(points)
    n = np.arange(_WINDOW_LENGTH)
    w2 = (0.5 - 0.5 * np.cos(2 * np.pi * n / _WINDOW_LENGTH)) ** 2
    C = np.exp(-2j * np.pi * np.subtract.outer(d, d)[..., None] * n / _WINDOW_LENGTH) @ w2
    C = C / w2.sum()
    vals, vecs = np.linalg.eigh(C)                       # Hermitian, positive semi-definite
    root = vecs * np.sqrt(np.clip(vals, 0.0, None))
    rng = np.random.default_rng(seed)
    z = (rng.standard_normal((n_draws, d.size)) + 1j * rng.standard_normal((n_draws, d.size)))
    return (z / np.sqrt(2.0)) @ root.T


def read_sum_interval_um(a_um, a_low_um, a_high_um, sigma_um, *, coverage: float,
                         level: float, n_draws: int = READ_DRAWS, seed: int = READ_SEED,
                         chunk: int = 64):
    """The central ``coverage`` interval of the sum over the lines of the reads the outcome
    makes, by Monte Carlo (module docstring) [µm].

    Parameters
    ----------
    a_um, a_low_um, a_high_um
        ``(..., G)``: each line's nominal amplitude and its identification interval at the
        two-sided ``level`` (a line with nominal 0 and no interval is absent).
    sigma_um
        ``(..., G)``: each line's per-bin noise σ at the record (NaN: no noise known, the line
        enters with its amplitude alone).

    Returns
    -------
    tuple of numpy.ndarray
        ``(low, high)`` of shape ``(...)``.
    """
    from scipy.stats import norm

    a, lo, hi, sig = np.broadcast_arrays(*(np.asarray(x, float) for x in
                                           (a_um, a_low_um, a_high_um, sigma_um)))
    shape, G = a.shape[:-1], a.shape[-1]
    a, lo, hi = a.reshape(-1, G), lo.reshape(-1, G), hi.reshape(-1, G)
    sig = np.nan_to_num(sig.reshape(-1, G), nan=0.0)
    z_level = float(norm.ppf(0.5 + level / 2))
    s_lo = np.clip(a - lo, 0.0, None) / z_level
    s_hi = np.clip(hi - a, 0.0, None) / z_level
    rng = np.random.default_rng(seed + 1)
    za = rng.standard_normal((n_draws, G))                  # the lines' amplitudes
    phase = np.exp(2j * np.pi * rng.uniform(size=(n_draws, G)))
    noise = np.stack([window_noise_draws(n_draws, seed=seed + 2 + g) for g in range(G)], 1)
    W = hann_response(read_window_offsets_bins())             # (K,)
    q = [(1.0 - coverage) / 2, (1.0 + coverage) / 2]
    used = np.any((a > 0) | (hi > 0) | (sig > 0), axis=0)     # lines present somewhere
    a, lo, hi, sig = a[:, used], lo[:, used], hi[:, used], sig[:, used]
    s_lo, s_hi, za, phase, noise = s_lo[:, used], s_hi[:, used], za[:, used], \
        phase[:, used], noise[:, used]
    out = np.zeros((a.shape[0], 2))
    for start in range(0, a.shape[0] if used.any() else 0, chunk):
        sl = slice(start, start + chunk)
        amp = a[sl, None, :] + za * np.where(za > 0, s_hi[sl, None, :], s_lo[sl, None, :])
        amp = np.clip(amp, 0.0, None)                          # (c, D, G)
        line = (amp * phase)[..., None] * W                    # (c, D, G, K)
        reads = np.abs(line + sig[sl, None, :, None] * noise).max(-1)
        out[sl] = np.quantile(reads.sum(-1), q, axis=1).T
    return out[:, 0].reshape(shape), out[:, 1].reshape(shape)
