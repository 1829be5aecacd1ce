"""Chapter 3.2's findings: what the tracker runs' peaks say, computed here and rendered by the
chapter (:mod:`robomill.pipeline.prose`): where the gear-attributed peaks lie, the peaks of
constant temporal frequency (a servo ripple), and whether the motion has a component in the
surface's roughness band — a verdict against ``straightness.threshold``, the same threshold
that makes a peak (thesis §3.2: the small surface irregularities near 8 mm⁻¹ do not come from
the path)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
import xarray as xr

from robomill.findings import Findings
from robomill.straightness.tables import band_floor_table

_PEAKS = "results/straightness/peaks.csv"
_PROFILES = "results/straightness/profiles.nc"


def _span(values: np.ndarray) -> list[float] | None:
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    return [float(v.min()), float(v.max())] if v.size else None


def quiet_band(surface_band_per_mm: Sequence[float], fmax_store_per_mm: float
               ) -> tuple[float, float]:
    """A band as wide as the surface band at the top of the stored spectrum, where no source
    is planted or expected: the reference for the surface band's peak-to-floor ratio."""
    lo, hi = (float(b) for b in surface_band_per_mm)
    return (float(fmax_store_per_mm) - (hi - lo), float(fmax_store_per_mm))


def straightness_findings(profiles: xr.Dataset, peaks: pd.DataFrame, *,
                          surface_band_per_mm: Sequence[float], fmax_store_per_mm: float,
                          threshold: float) -> Findings:
    """The findings of the straightness stage.

    Parameters
    ----------
    profiles
        ``results/straightness/profiles.nc`` (``power_um2(run, f)``; ``direction``,
        ``feed_mm_s`` on ``run``).
    peaks
        ``results/straightness/peaks.csv`` (``run, direction, feed_mm_s, f_spatial_per_mm,
        f_temporal_hz, amplitude_um, mechanism``; ``run`` joins a peak to its run).
    surface_band_per_mm, fmax_store_per_mm
        ``straightness.surface_band_per_mm`` (the roughness band of the surfaces) and
        ``straightness.fmax_store_per_mm`` (the top of the stored spectra).
    threshold
        ``straightness.threshold``: a peak's power over the band median. The verdict
        ``motion_in_surface_band`` is ``none`` when no run has a peak in the surface band
        (the motion has no component there), else ``peaks``.

    Returns
    -------
    Findings
        ``n_runs, feeds_mm_s``; ``n_gear_peaks, gear_f_range_per_mm,
        gear_main_wavelength_mm_range`` (the largest gear peak of each run);
        ``n_temporal, temporal_hz_mean, temporal_hz_std, temporal_wavelength_mm_range,
        temporal_amplitude_um_range``; ``surface_band_per_mm, quiet_band_per_mm,
        n_surface_band_peaks, surface_band_peak_to_floor_max,
        quiet_band_peak_to_floor_range`` and the verdict ``motion_in_surface_band``.
    """
    found = Findings("straightness")
    feeds = np.asarray(profiles["feed_mm_s"].values, float)
    found.add("n_runs", int(profiles.sizes["run"]), artefact=_PROFILES, what="run")
    found.add("feeds_mm_s", sorted({float(v) for v in feeds}), "mm/s", artefact=_PROFILES,
              what="feed_mm_s")
    gear = peaks[peaks["mechanism"] == "gear"]
    found.add("n_gear_peaks", int(len(gear)), artefact=_PEAKS, what="mechanism = gear")
    found.add("gear_f_range_per_mm", _span(gear["f_spatial_per_mm"]), "1/mm", artefact=_PEAKS,
              what="f_spatial_per_mm[mechanism = gear]")
    main = (gear.loc[gear.groupby("run")["amplitude_um"].idxmax()]
            if len(gear) else gear)
    found.add("gear_main_wavelength_mm_range",
              _span(1.0 / main["f_spatial_per_mm"].to_numpy(float)) if len(main) else None,
              "mm", artefact=_PEAKS, what="1 / f_spatial_per_mm of each run's largest gear peak")
    temporal = peaks[peaks["mechanism"] == "temporal"]
    f_t = temporal["f_temporal_hz"].to_numpy(float)
    found.add("n_temporal", int(len(temporal)), artefact=_PEAKS, what="mechanism = temporal")
    found.add("temporal_hz_mean", float(f_t.mean()) if f_t.size else None, "Hz",
              artefact=_PEAKS, what="f_temporal_hz[mechanism = temporal]")
    found.add("temporal_hz_std", float(f_t.std()) if f_t.size else None, "Hz",
              artefact=_PEAKS, what="f_temporal_hz[mechanism = temporal], population")
    found.add("temporal_wavelength_mm_range",
              _span(1.0 / temporal["f_spatial_per_mm"].to_numpy(float)) if len(temporal)
              else None, "mm", artefact=_PEAKS)
    found.add("temporal_amplitude_um_range", _span(temporal["amplitude_um"]), "um",
              artefact=_PEAKS)
    band = tuple(float(b) for b in surface_band_per_mm)
    quiet = quiet_band(band, fmax_store_per_mm)
    hi = band_floor_table(profiles, peaks, band, quiet)
    n_band = int(hi["peaks_in_band"].sum()) if len(hi) else 0
    found.add("surface_band_per_mm", list(band), "1/mm")
    found.add("quiet_band_per_mm", list(quiet), "1/mm")
    found.add("n_surface_band_peaks", n_band, artefact=_PEAKS, what="peaks in the surface band")
    found.add("surface_band_peak_to_floor_max",
              float(hi["peak_to_floor_in_band"].max()) if len(hi) else None,
              artefact=_PROFILES, what="largest power in the band over the run's noise floor")
    found.add("quiet_band_peak_to_floor_range", _span(hi["peak_to_floor_noise_band"]),
              artefact=_PROFILES, what="the same in the quiet band, over the runs")
    if len(hi):
        found.add("motion_in_surface_band", n_band > 0,
                  verdict="peaks" if n_band else "none", threshold=float(threshold),
                  config_key="straightness.threshold", artefact=_PEAKS,
                  what="a peak (power over threshold × the band median) in the surface band")
    return found
