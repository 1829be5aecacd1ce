"""The spectral peaks of a cut's force record (thesis §3.1): the dominant low-frequency
peak, the kinematic (spatial) peak, the tooth-passing harmonics, and the identified mode
nearest to each peak.

A reported peak is a peak: a local maximum of the low-band thesis power (summed over the
three axes) that rises a stated number of dB above its local floor
(:func:`robomill.spectra.prominent_peaks`), never the falling skirt of a line left out of
the search; where no bin qualifies the peak is empty (NaN). Its frequency is interpolated
within the bin (:func:`robomill.spectra.peak_offset_bins`), its power that of its bin.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import pandas as pd

from robomill.forces.settings import ForcePeakSettings
from robomill.spectra import peak_offset_bins, prominent_peaks


def dominant_peak(f_hz: np.ndarray, power: np.ndarray, band_hz: tuple[float, float], *,
                  exclude_hz: Iterable[float] = (), exclude_width_hz: float = 0.0,
                  prominence_db: float = 12.0, floor_halfwidth_hz: float = 25.0
                  ) -> tuple[float, float]:
    """Frequency and power of the strongest peak of ``power`` within ``band_hz`` (inclusive).

    The peak is the most powerful bin of :func:`robomill.spectra.prominent_peaks`: a local
    maximum of the whole spectrum, farther than ``exclude_width_hz`` from each of
    ``exclude_hz`` (the spindle's own harmonics, when a slow spindle puts them in the band),
    at least ``prominence_db`` above the median power within ``±floor_halfwidth_hz``. Its
    frequency is ``f[i] + δ Δf`` with δ from :func:`robomill.spectra.peak_offset_bins` (the
    spectrum is the unwindowed thesis power, so a line uses the rectangular window's
    two-bin ratio, a broader peak the parabola through the log power). ``f_hz`` may be any
    uniform grid (1/mm for the kinematic peak, with ``floor_halfwidth_hz`` in 1/mm).

    Returns
    -------
    tuple of float
        ``(frequency, power of its bin)``; ``(nan, nan)`` when no bin qualifies.

    Examples
    --------
    A line at 80.3 Hz on a flat floor, 1 Hz bins:

    >>> f = np.arange(251.0)
    >>> p = 1e-3 + 1.0 / (f - 80.3) ** 2
    >>> round(dominant_peak(f, p, (15.0, 250.0))[0], 2)
    80.3
    """
    f_hz, power = np.asarray(f_hz, float), np.asarray(power, float)
    exclude = np.asarray(list(exclude_hz), float)
    idx = prominent_peaks(f_hz, power, tuple(band_hz), prominence_db=prominence_db,
                          floor_half_width=floor_halfwidth_hz, exclude=exclude,
                          exclude_width=exclude_width_hz)
    if idx.size == 0:
        return float("nan"), float("nan")
    i = int(idx[0])
    df = float(f_hz[1] - f_hz[0])
    return float(f_hz[i] + peak_offset_bins(power, i, window="rect") * df), float(power[i])


def cut_peaks(f_low_hz: np.ndarray, power_low: np.ndarray, *, feed_mm_s: float,
              spindle_rpm: float, resolution_hz: float, settings: ForcePeakSettings
              ) -> dict[str, float]:
    """The dominant and kinematic peaks of one cut's low band.

    ``power_low`` ``(3, n)`` is summed over the axes. The dominant peak is searched in
    ``settings.dominant_band_hz`` with the spindle's harmonics ``k n/60`` (runout, tooth
    passing: tabulated as harmonics instead) left out ±2.5 bins; with a slow spindle (6000
    rpm, 2 teeth: 100, 200 Hz) they fall in the band (at 28 000 rpm they do not: 467 Hz).
    The kinematic peak is searched in spatial frequency ``f/v`` within
    ``settings.kinematic_band_per_mm``.

    Returns
    -------
    dict
        ``dominant_hz, dominant_power, kinematic_per_mm, kinematic_power`` (NaN where no
        peak qualifies).
    """
    total = np.asarray(power_low, float).sum(axis=0)
    f = np.asarray(f_low_hz, float)
    v = float(feed_mm_s)
    band = settings.dominant_band_hz
    spindle_hz = float(spindle_rpm) / 60.0
    f_dom, p_dom = dominant_peak(
        f, total, tuple(band),
        exclude_hz=spindle_hz * np.arange(1, int(band[1] / spindle_hz) + 2),
        exclude_width_hz=2.5 * float(resolution_hz),
        prominence_db=settings.dominant_prominence_db,
        floor_halfwidth_hz=settings.dominant_floor_halfwidth_hz)
    f_kin, p_kin = dominant_peak(
        f / v, total, tuple(settings.kinematic_band_per_mm),
        prominence_db=settings.kinematic_prominence_db,
        floor_halfwidth_hz=settings.kinematic_floor_halfwidth_per_mm)
    return {"dominant_hz": f_dom, "dominant_power": p_dom,
            "kinematic_per_mm": f_kin, "kinematic_power": p_kin}


def harmonic_powers(f_hz: np.ndarray, psd: np.ndarray, f0_hz: float, n_harmonics: int, *,
                    half_width_bins: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Power [PSD unit × Hz] of harmonics k·f0 (k = 1..n, below Nyquist) of a Welch PSD
    ``(..., nf)``, integrated over ±``half_width_bins`` around the nearest bin (a Hann window
    spreads a line over about 3 bins). Returns ``(k·f0, power (..., n))``."""
    f_hz = np.asarray(f_hz)
    df = f_hz[1] - f_hz[0]
    ks = np.arange(1, n_harmonics + 1)
    fk = ks * f0_hz
    fk = fk[fk <= f_hz[-1] - half_width_bins * df]
    out = []
    for fh in fk:
        i = int(round(fh / df))
        out.append(psd[..., i - half_width_bins:i + half_width_bins + 1].sum(axis=-1) * df)
    return fk, np.stack(out, axis=-1) if out else np.zeros(psd.shape[:-1] + (0,))



def nearest_modes(peaks_hz: np.ndarray, modes: pd.DataFrame) -> pd.DataFrame:
    """The identified mode nearest to each force peak (chapter 3.1, Table 3.1).

    Parameters
    ----------
    peaks_hz
        Peak frequencies [Hz] (the dominant low-frequency peak of each cut).
    modes
        ``results/modal/modes.csv``: columns ``mode`` and ``f_n_hz``.

    Returns
    -------
    DataFrame
        One row per peak: ``nearest_mode``, ``nearest_mode_hz`` and ``offset_hz`` (peak −
        mode); empty where there is no mode or no peak (NaN).
    """
    f = np.asarray(peaks_hz, float)
    f_n = np.asarray(modes["f_n_hz"], float) if len(modes) else np.array([])
    if f_n.size == 0:
        return pd.DataFrame({"nearest_mode": pd.Series([None] * f.size, dtype=object),
                             "nearest_mode_hz": np.full(f.size, np.nan),
                             "offset_hz": np.full(f.size, np.nan)})
    idx = np.abs(np.nan_to_num(f)[:, None] - f_n[None, :]).argmin(axis=1)
    none = np.isnan(f)  # no peak: no nearest mode
    return pd.DataFrame({"nearest_mode": pd.Series(np.where(none, None, modes["mode"].to_numpy(
                             )[idx]), dtype=object),
                         "nearest_mode_hz": np.where(none, np.nan, f_n[idx]),
                         "offset_hz": f - f_n[idx]})
