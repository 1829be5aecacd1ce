"""Straightness profile and its spectrum (thesis §3.2, steps 1–2): a tracker time series
re-ordered in space along its best line, resampled on a uniform grid, and its Hann-windowed
amplitude / power / PSD spectrum in mm⁻¹ (thesis eqs. 2.1–2.3), with the spectral peaks.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill import spectra

COMPONENTS = ("lateral", "vertical")
"""Perpendicular deviation components: horizontal (Z × path direction) and vertical."""

# ---------------------------------------------------------------------------------------------
# 1. spatial re-ordering
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Profile:
    """A straightness profile re-ordered in space.

    Attributes
    ----------
    s_mm
        Uniform abscissa along the best line, from the first sample's projection [mm].
    deviation_um
        ``(2, n)`` perpendicular deviation from the best line [µm], rows ``COMPONENTS``.
    start_mm, end_mm
        The best line's points at the start and the end of the motion [mm] (3-vectors).
    direction
        Unit vector of the motion along the best line.
    ds_mm
        Grid step [mm].
    speed_mm_s
        Median speed along the line (from the raw samples) [mm/s]; NaN without a time base.
    """

    s_mm: np.ndarray
    deviation_um: np.ndarray
    start_mm: np.ndarray
    end_mm: np.ndarray
    direction: np.ndarray
    ds_mm: float
    speed_mm_s: float
    trim_mm: float = 0.0
    """Length dropped at each end [mm] (``trim_mm`` asked, at most
    :data:`TRIM_MAX_FRACTION` of the path)."""

    @property
    def length_mm(self) -> float:
        return float(self.s_mm[-1] - self.s_mm[0] + self.ds_mm)


def fit_line(points_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Best (total least squares) straight line through ``points_mm`` ``(n, 3)``.

    Returns the centroid and the unit direction (first right singular vector of the centred
    points), which minimises the sum of squared perpendicular distances.
    """
    p = np.asarray(points_mm, float)
    c = p.mean(axis=0)
    _, _, vt = np.linalg.svd(p - c, full_matrices=False)
    return c, vt[0]


def perpendicular_axes(direction: np.ndarray) -> np.ndarray:
    """``(2, 3)`` unit vectors perpendicular to ``direction``: lateral (horizontal, Z × u) and
    vertical (completing the right-handed set u, lateral, vertical; +Z-ish for a horizontal
    path). For a vertical path the lateral axis falls back to X × u."""
    u = np.asarray(direction, float) / np.linalg.norm(direction)
    lat = np.cross([0.0, 0.0, 1.0], u)
    if np.linalg.norm(lat) < 1e-6:
        lat = np.cross([1.0, 0.0, 0.0], u)
    lat /= np.linalg.norm(lat)
    vert = np.cross(u, lat)
    return np.stack([lat, vert])


def resample_uniform(s: np.ndarray, y: np.ndarray, ds: float,
                     s0: float | None = None, s1: float | None = None) -> tuple[np.ndarray,
                                                                                np.ndarray]:
    """Resample ``y(s)`` (``s`` sorted, ``y`` ``(..., n)``) on a uniform grid of step ``ds``.

    Where the samples are denser than the grid they are averaged per grid cell (a boxcar
    anti-alias filter, so noise is not folded back); empty cells are linearly interpolated
    from their neighbours.
    """
    s = np.asarray(s, float)
    y = np.atleast_2d(np.asarray(y, float))
    s0 = s[0] if s0 is None else s0
    s1 = s[-1] if s1 is None else s1
    n = int(np.floor((s1 - s0) / ds)) + 1
    grid = s0 + ds * np.arange(n)
    idx = np.clip(np.round((s - s0) / ds).astype(int), 0, n - 1)
    count = np.bincount(idx, minlength=n)
    out = np.empty((y.shape[0], n))
    filled = count > 0
    for k in range(y.shape[0]):
        mean = np.bincount(idx, weights=y[k], minlength=n)[filled] / count[filled]
        out[k] = np.interp(grid, grid[filled], mean)
    return grid, out


TRIM_MAX_FRACTION = 0.1
"""The end trim (speed ramps) takes at most this share of the path at each end (assumed:
10 %), so that a short record (a tracker export of a few mm) keeps 80 % of its path instead
of being refused; the 40 mm thesis runs trim the full ``trim_mm``."""


def spatial_profile(t_s: np.ndarray | None, points_mm: np.ndarray, *, ds_mm: float,
                    trim_mm: float = 0.0, detrend_order: int = 1) -> Profile:
    """Re-order a tracker time series in space (thesis §3.2).

    Parameters
    ----------
    t_s
        Sample times [s], increasing; ``None`` for a stream without a time base
        (``time_base: none``): the acquisition order orients the line and the speed is NaN.
    points_mm
        ``(n, 3)`` measured positions [mm].
    ds_mm
        Step of the uniform spatial grid [mm].
    trim_mm
        Length dropped at each end of the path (acceleration/deceleration) [mm], at most
        ``TRIM_MAX_FRACTION`` of the path (a shorter trim is logged by the rule).
    detrend_order
        Degree of the polynomial removed from each resampled component (1: the best line
        only, as the thesis; 3 also removes components with less than about one cycle over
        the record, whose spectral leakage would otherwise raise false low-frequency peaks).

    Returns
    -------
    Profile
        Distance along the best line and the perpendicular deviation (lateral, vertical),
        resampled uniformly after removing the best line (the deviation has zero mean and no
        linear trend in either component by construction of the total-least-squares line).

    Notes
    -----
    ``s_k = (p_k − c)·u`` with c, u the centroid and direction of the best line; the
    deviation is ``(p_k − c) − s_k u`` projected on the two perpendicular axes. The samples
    are sorted by ``s`` (space order), whatever their time order.
    """
    p = np.asarray(points_mm, float)
    t = np.arange(p.shape[0], dtype=float) if t_s is None else np.asarray(t_s, float)
    c, u = fit_line(p)
    s = (p - c) @ u
    if np.polyfit(t, s, 1)[0] < 0:  # orient the line along the motion
        u, s = -u, -s
    axes = perpendicular_axes(u)
    dev = ((p - c) @ axes.T).T * 1e3  # (2, n) µm
    order = np.argsort(s, kind="stable")
    s, dev = s[order], dev[:, order]
    trim_mm = min(float(trim_mm), TRIM_MAX_FRACTION * float(s[-1] - s[0]))
    s0, s1 = s[0] + trim_mm, s[-1] - trim_mm
    if s1 - s0 < 4 * ds_mm:
        raise ValueError(f"path of {s[-1] - s[0]:.3g} mm is too short for the grid step "
                         f"{ds_mm} mm after trimming {trim_mm:.3g} mm at each end")
    keep = (s >= s0 - ds_mm) & (s <= s1 + ds_mm)
    grid, dev_u = resample_uniform(s[keep], dev[:, keep], ds_mm, s0, s1)
    # remove what is left of the line on the trimmed span (and, with detrend_order > 1, the
    # slowest curvature), per component
    x = np.linspace(-1.0, 1.0, grid.size)
    V = np.polynomial.legendre.legvander(x, int(detrend_order))
    coef, *_ = np.linalg.lstsq(V, dev_u.T, rcond=None)
    dev_u = dev_u - (V @ coef).T
    speed = np.nan if t_s is None else _speed(t, (p - c) @ u)
    return Profile(s_mm=grid - grid[0], deviation_um=dev_u, start_mm=c + s0 * u,
                   end_mm=c + s1 * u, direction=u, ds_mm=float(ds_mm), speed_mm_s=speed,
                   trim_mm=trim_mm)


def _speed(t: np.ndarray, s: np.ndarray) -> float:
    """Median speed along the line over lags of 1/50 of the record (robust to noise)."""
    lag = max(1, t.size // 50)
    return float(np.median(np.abs(s[lag:] - s[:-lag]) / (t[lag:] - t[:-lag])))


# ---------------------------------------------------------------------------------------------
# 2. spectrum in mm⁻¹
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ProfileSpectrum:
    """Spectrum of a straightness profile (one-sided)."""

    f_per_mm: np.ndarray
    """Frequency grid (zero-padded: ``pad`` points per resolution bin 1/L) [mm⁻¹]."""
    amplitude_um: np.ndarray
    """``(2, nf)`` sinusoid amplitude per component (Hann, amplitude-corrected) [µm]."""
    power_um2: np.ndarray
    """``(nf,)`` power of the perpendicular deviation, lateral + vertical, A²/2 [µm²]."""
    psd_um2_mm: np.ndarray
    """``(nf,)`` power spectral density of the perpendicular deviation [µm²·mm]."""
    resolution_per_mm: float
    """Frequency resolution 1/L of the record [mm⁻¹]."""


def profile_spectrum(profile: Profile, *, nfft: int | None = None,
                     pad: int = 8) -> ProfileSpectrum:
    """Amplitude and power spectra of a profile in mm⁻¹ (thesis eqs. 2.1–2.3).

    The profile is multiplied by a Hann window, zero-padded to ``nfft`` points (default
    ``pad × n`` rounded up to a power of two) and transformed with
    :func:`robomill.spectra.thesis_spectrum`; the amplitudes are divided by the window's
    coherent gain (mean of the window), so a sinusoid of amplitude ``a`` gives a peak of
    height ``a`` (within 0.1 % with 8× padding). ``power_um2 = Σ_components A²/2`` and the
    PSD is ``power / ENBW`` with the Hann equivalent noise bandwidth ``1.5/L``.
    """
    dev = profile.deviation_um
    n = dev.shape[-1]
    if nfft is None:
        nfft = int(2 ** np.ceil(np.log2(pad * n)))
    if nfft < n:
        raise ValueError(f"nfft={nfft} is shorter than the profile ({n} samples)")
    import scipy.signal  # here, not at the top: the plan's chapter uses this module's
    # geometry (perpendicular_axes) and should not pay SciPy's signal package (~1 s)

    w = scipy.signal.get_window("hann", n, fftbins=True)
    padded = np.zeros((dev.shape[0], nfft))
    padded[:, :n] = dev * w
    spec = spectra.thesis_spectrum(padded, fs=1.0 / profile.ds_mm)
    amp = spec.amplitude * nfft / n / w.mean()
    power = 0.5 * (amp**2).sum(axis=0)
    length = n * profile.ds_mm
    enbw = n * np.sum(w**2) / np.sum(w) ** 2 / length
    return ProfileSpectrum(spec.f, amp, power, power / enbw, 1.0 / length)


def spectrum_peaks(spec: ProfileSpectrum, *, fmin_per_mm: float, fmax_per_mm: float,
                   threshold: float, n_peaks: int, local_ratio: float = 0.0,
                   floor_halfwidth_bins: float = 0.0) -> pd.DataFrame:
    """Peaks of the combined perpendicular power within [fmin, fmax].

    A peak is a local maximum that exceeds ``threshold`` × the median power of the band (the
    noise floor) and whose prominence is at least ``local_ratio`` × its local floor, the
    median power within ±``floor_halfwidth_bins`` resolution bins 1/L
    (:func:`robomill.spectra.find_peaks_spectrum`): never a bump on the skirt of a stronger
    line; near ``fmin``, where the neighbourhood below holds what the removed line leaks, on
    its upper side alone. The ``n_peaks`` strongest are kept; none qualifying: an empty
    table. Local maxima
    are searched from two resolution bins below ``fmin`` (so a peak right at the band edge is
    still a local maximum) and kept from ``fmin`` up.

    Returns ``f_spatial_per_mm`` (interpolated within the bin,
    :func:`robomill.spectra.interpolate_peak`: it is compared with the gear lines),
    ``amplitude_um`` (``sqrt(2·power)`` at the peak bin: the amplitude of the perpendicular
    oscillation), ``component`` (the larger of lateral/vertical there) and ``snr``
    (power / floor).
    """
    f_grid, power = spec.f_per_mm, spec.power_um2
    sel = (f_grid >= fmin_per_mm) & (f_grid <= fmax_per_mm)
    floor = float(np.median(power[sel])) if sel.any() else np.nan
    df = float(f_grid[1] - f_grid[0])
    found = spectra.find_peaks_spectrum(
        f_grid, power, fmin=fmin_per_mm, fmax=fmax_per_mm, n=n_peaks,
        prominence_ratio=threshold, floor=floor, local_ratio=local_ratio,
        halfwidth_points=int(round(floor_halfwidth_bins * spec.resolution_per_mm / df)),
        search_from=max(0.0, fmin_per_mm - 2 * spec.resolution_per_mm),
        envelope_points=int(round(spec.resolution_per_mm / df)), one_sided_below=fmin_per_mm)
    rows = []
    for f, p in found:
        k = int(np.argmin(np.abs(f_grid - f)))
        comp = COMPONENTS[int(np.argmax(spec.amplitude_um[:, k]))]
        rows.append({"f_spatial_per_mm": spectra.interpolate_peak(f_grid, power, k),
                     "amplitude_um": float(np.sqrt(2 * p)), "component": comp,
                     "snr": p / floor})
    return pd.DataFrame(rows, columns=["f_spatial_per_mm", "amplitude_um", "component", "snr"])


def profile_dataset(prof: Profile, spec: ProfileSpectrum, *, fmax_store_per_mm: float,
                    attrs: Mapping[str, Any]) -> xr.Dataset:
    """One run's profile and spectrum as a labelled dataset (coordinates ``s``, ``f``)."""
    keep = spec.f_per_mm <= fmax_store_per_mm
    comp = ("component", list(COMPONENTS), {"units": "1",
                                             "long_name": "perpendicular component"})
    return xr.Dataset(
        {
            "deviation_um": (("component", "s"), prof.deviation_um,
                             {"units": "um", "long_name": "deviation perpendicular to the "
                              "best line (re-ordered in space, uniform grid)"}),
            "amplitude_um": (("component", "f"), spec.amplitude_um[:, keep],
                             {"units": "um", "long_name": "sinusoid amplitude spectrum "
                              "(Hann, zero-padded)"}),
            "power_um2": ("f", spec.power_um2[keep],
                          {"units": "um^2", "long_name": "power of the perpendicular "
                           "deviation (lateral + vertical)"}),
            "psd_um2_mm": ("f", spec.psd_um2_mm[keep],
                           {"units": "um^2 mm", "long_name": "power spectral density of the "
                            "perpendicular deviation"}),
        },
        coords={
            "component": comp,
            "s": ("s", prof.s_mm, {"units": "mm", "long_name": "distance along the path"}),
            "f": ("f", spec.f_per_mm[keep], {"units": "1/mm",
                                             "long_name": "spatial frequency"}),
        },
        attrs={**attrs, "resolution_per_mm": spec.resolution_per_mm,
               "length_mm": prof.length_mm, "speed_mm_s": prof.speed_mm_s,
               "ds_mm": prof.ds_mm, "start_mm": list(map(float, prof.start_mm)),
               "end_mm": list(map(float, prof.end_mm))},
    )
