"""The modal analysis band: set by the configuration or the manifest, or found in the data
(hammer spectrum and coherence), and a set band compared with the band the data support."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import xarray as xr

from robomill.settings import schema_default


def band_from_data(ds: xr.Dataset, *, force_spectrum: np.ndarray | None = None,
                   coherence_min: float = schema_default("modal", "coherence_min"),
                   force_drop_db: float = 10.0,
                   smooth_hz: float = 2.0,
                   no_coherence_low_fraction: float = 0.02) -> tuple[float, float]:
    """The analysis band from the data: where the hammer excited the structure and the
    coherence shows it.

    Upper limit: the first line above which the hammer's force auto-spectrum ``force_spectrum``
    (over ``ds.frequency``) stays ``force_drop_db`` below its mean over the lowest 5 % of the
    lines (the usual "10 dB" rule for a hammer tip, Ewins 2000 §3.6), and the last line where
    the median coherence of the measured FRFs (smoothed over ``smooth_hz``) reaches
    ``coherence_min``. Lower limit: the first line above DC where that smoothed median
    coherence reaches ``coherence_min``. Without coherence (FRFs imported without type-6
    sets) the lowest lines cannot be judged, and a receptance converted from an accelerance
    there is noise divided by ω²: the band then starts at ``no_coherence_low_fraction`` of
    its upper limit (assumed 2 %: 20 Hz for a 1 kHz export).

    Returns
    -------
    (f_lo_hz, f_hi_hz)

    Raises
    ------
    ValueError
        When the coherence never reaches ``coherence_min``.
    """
    f = ds["frequency"].values
    lo, hi = float(f[f > 0][0]), float(f[-1])
    if force_spectrum is not None:
        s = np.asarray(force_spectrum, float)
        ref = np.mean(s[(f > 0) & (f <= f[-1] * 0.05 + f[1])])
        above = s >= ref * 10 ** (-force_drop_db / 10)
        above[f <= 0] = True
        below = np.flatnonzero(~above)
        if below.size:
            hi = min(hi, float(f[below[0]]))
    if "coherence" in ds and np.isfinite(ds["coherence"].values).any():
        c = ds["coherence"].transpose("output", "input", "frequency").values
        with warnings.catch_warnings():  # DC and unmeasured pairs are all-NaN lines
            warnings.simplefilter("ignore", RuntimeWarning)
            med = np.nanmedian(c.reshape(-1, f.size), axis=0)
        w = max(1, int(round(smooth_hz / (f[1] - f[0]))))
        med = np.convolve(np.nan_to_num(med), np.ones(w) / w, mode="same")
        good = np.flatnonzero((med >= coherence_min) & (f > 0) & (f <= hi))
        if good.size == 0:
            raise ValueError(f"the coherence never reaches {coherence_min:g}: no usable band "
                             "(set modal.band_hz)")
        lo, hi = max(lo, float(f[good[0]])), min(hi, float(f[good[-1]]))
    else:
        lo = max(lo, float(f[np.searchsorted(f, no_coherence_low_fraction * hi)]))
    return lo, hi


BAND_COVERAGE_MIN = 0.5
"""A set band covering less than this share of the band the data support is flagged
(assumed: half)."""


@dataclass
class BandChoice:
    """The analysis band and where it came from (:func:`choose_band`)."""

    band_hz: tuple[float, float]
    source: str
    """``modal.band_hz``, ``experiment.modal_band_hz`` (the manifest) or ``data``."""
    data_band_hz: tuple[float, float] | None
    """The band from the data (:func:`band_from_data`); None where it cannot be found."""
    coverage: float
    """Share of ``data_band_hz`` inside ``band_hz`` (1 for a band from the data; NaN when
    the data band is unknown)."""
    flag: str
    """A sanity flag (empty when none): a set band covering a small part of the data band."""


def band_coverage(band_hz: Sequence[float], data_band_hz: Sequence[float]) -> float:
    """Share of the interval ``data_band_hz`` that ``band_hz`` covers:
    ``|band ∩ data| / |data|`` (0 when disjoint)."""
    lo, hi = max(band_hz[0], data_band_hz[0]), min(band_hz[1], data_band_hz[1])
    width = float(data_band_hz[1] - data_band_hz[0])
    return max(0.0, float(hi - lo)) / width if width > 0 else float("nan")


def choose_band(ds: xr.Dataset, *, band_hz: Sequence[float] | None = None,
                experiment_band_hz: Sequence[float] | None = None,
                force_spectrum: np.ndarray | None = None,
                coherence_min: float = schema_default("modal", "coherence_min"),
                coverage_min: float = BAND_COVERAGE_MIN) -> BandChoice:
    """The modal analysis band, in order: ``band_hz`` (``config.yaml: modal.band_hz``) if
    set, else ``experiment_band_hz`` (the manifest's ``experiment.modal_band_hz``: the band
    of interest is a choice of the experiment design, e.g. the thesis' 10–100 Hz), else the
    band from the hammer spectrum and the coherence (:func:`band_from_data`).

    A set band (the first two sources) is compared with the band the data support: when it
    covers less than ``coverage_min`` of it (:func:`band_coverage`) the choice carries a
    sanity flag (modes of the measured band may be left out); it is also flagged when the
    data band cannot be found (the coherence never reaches ``coherence_min``).

    Raises
    ------
    ValueError
        When no band is set and the data give none (see :func:`band_from_data`), or a set
        band is not two increasing non-negative frequencies.
    """
    try:
        data_band = band_from_data(ds, force_spectrum=force_spectrum,
                                   coherence_min=coherence_min)
    except ValueError:
        if band_hz is None and experiment_band_hz is None:
            raise
        data_band = None
    for given, source in ((band_hz, "modal.band_hz"),
                          (experiment_band_hz, "experiment.modal_band_hz")):
        if given is None:
            continue
        band = tuple(float(b) for b in given)
        if len(band) != 2 or not 0 <= band[0] < band[1]:
            raise ValueError(f"{source} {list(given)!r} is not a band (expected [f_lo_hz, "
                             "f_hi_hz], 0 <= f_lo_hz < f_hi_hz)")
        if data_band is None:
            return BandChoice(band, source, None, float("nan"),
                              f"{source} {band[0]:.4g}-{band[1]:.4g} Hz: the data give no "
                              f"band to compare with (coherence below {coherence_min:g})")
        cov = band_coverage(band, data_band)
        flag = (f"{source} {band[0]:.4g}-{band[1]:.4g} Hz covers {100 * cov:.0f} % of the "
                f"band the data support ({data_band[0]:.4g}-{data_band[1]:.4g} Hz)"
                if cov < coverage_min else "")
        return BandChoice(band, source, data_band, cov, flag)
    return BandChoice(data_band, "data", data_band, 1.0, "")
