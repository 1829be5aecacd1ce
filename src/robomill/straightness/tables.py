"""Chapter 3.2 tables computed from the straightness artefacts: the cross-check against the
surface peaks, the band-to-floor ratios and the per-run summary.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import xarray as xr


# ---------------------------------------------------------------------------------------------
# cross-checks (chapter)
# ---------------------------------------------------------------------------------------------
def surface_cross_check(peaks: pd.DataFrame, surface_peaks: pd.DataFrame, *,
                        tolerance_per_mm: float) -> pd.DataFrame:
    """Mark every tracker peak present on the surface (yes/no).

    A tracker peak is on the surface when a peak of ``results/surface/peaks.csv``
    (``cut, f_spatial_per_mm, …``) of the cut whose path its run followed (the peak's
    ``cut``: the join key, no feed compared) lies within ``tolerance_per_mm``. Adds
    ``on_surface`` (bool) and ``surface_f_per_mm`` (nearest).
    """
    sp = surface_peaks[["cut", "f_spatial_per_mm"]]
    on, fnear = [], []
    for _, p in peaks.iterrows():
        cand = sp[sp["cut"].astype(str) == str(p["cut"])]
        if cand.empty:
            on.append(False)
            fnear.append(np.nan)
            continue
        d = np.abs(cand["f_spatial_per_mm"].to_numpy(float) - float(p["f_spatial_per_mm"]))
        k = int(np.argmin(d))
        on.append(bool(d[k] <= tolerance_per_mm))
        fnear.append(float(cand["f_spatial_per_mm"].iloc[k]))
    out = peaks.copy()
    out["on_surface"] = on
    out["surface_f_per_mm"] = fnear
    return out


def band_peak_ratio(f: np.ndarray, power: np.ndarray, band: tuple[float, float],
                    reference: tuple[float, float]) -> float:
    """Largest power in ``band`` divided by the median power in ``reference`` (a peak-to-floor
    ratio: ≈ 5–10 for noise alone, far above for a real peak)."""
    f = np.asarray(f)
    power = np.asarray(power)
    b = (f >= band[0]) & (f <= band[1])
    r = (f >= reference[0]) & (f <= reference[1])
    return float(power[b].max() / np.median(power[r]))

def band_floor_table(profiles: xr.Dataset, peaks: pd.DataFrame, band: tuple[float, float],
                     quiet: tuple[float, float], *,
                     floor_from_per_mm: float = 2.0) -> pd.DataFrame:
    """Peak-to-floor ratio of every run's motion spectrum in the surface band and in a quiet
    band of the same width (thesis §3.2: no motion component near the roughness band).

    For each run of ``profiles`` (``power_um2(run, f)`` with coordinates ``direction,
    feed_mm_s`` on ``run``), :func:`band_peak_ratio` against the median power from
    ``floor_from_per_mm`` to the top of the spectrum, in ``band`` and in ``quiet``, and the
    number of ``peaks`` (``run, f_spatial_per_mm``) of that run in ``band``.

    Returns
    -------
    pandas.DataFrame
        ``direction, feed_mm_s, peak_to_floor_in_band, peak_to_floor_noise_band,
        peaks_in_band``, one row per run.
    """
    rows = []
    for r in profiles["run"].values:
        ds = profiles.sel(run=r)
        ok = np.isfinite(ds["power_um2"].values)
        f, pw = ds["f"].values[ok], ds["power_um2"].values[ok]
        direction, feed = str(ds["direction"].values), float(ds["feed_mm_s"].values)
        ref = (floor_from_per_mm, float(f.max()))
        rows.append({"direction": direction, "feed_mm_s": feed,
                     "peak_to_floor_in_band": band_peak_ratio(f, pw, band, ref),
                     "peak_to_floor_noise_band": band_peak_ratio(f, pw, quiet, ref),
                     "peaks_in_band": int(((peaks["run"].astype(str) == str(r))
                                           & peaks["f_spatial_per_mm"].between(*band)).sum())})
    return pd.DataFrame(rows, columns=["direction", "feed_mm_s", "peak_to_floor_in_band",
                                       "peak_to_floor_noise_band", "peaks_in_band"])


def run_summary_table(profiles: xr.Dataset, peaks: pd.DataFrame) -> pd.DataFrame:
    """One row per tracker run: the RMS deviation from the best line per component, the largest
    peak (amplitude, wavelength 1/f, mechanism) and the number of peaks per mechanism.

    Parameters
    ----------
    profiles
        ``results/straightness/profiles.nc`` (:func:`gather_profiles`): ``deviation_um`` over
        (run, component, s) and the run coordinates ``direction``, ``feed_mm_s``.
    peaks
        ``results/straightness/peaks.csv`` (:func:`gather_peaks`), with ``run``,
        ``amplitude_um``, ``f_spatial_per_mm``, ``mechanism``.

    Returns
    -------
    pandas.DataFrame
        Columns ``run, direction, feed_mm_s``, ``rms_<component>_um`` (RMS over s, NaN
        skipped), ``largest_peak_um``, ``largest_peak_wavelength_mm``,
        ``largest_peak_mechanism`` and ``<mechanism>_peaks``; a run without peaks has NaN
        there and 0 counts.
    """
    table = pd.DataFrame({"run": profiles["run"].values,
                          "direction": profiles["direction"].values,
                          "feed_mm_s": profiles["feed_mm_s"].values.astype(float)})
    dev = profiles["deviation_um"]
    for comp in profiles["component"].values:
        rms = np.sqrt((dev.sel(component=comp) ** 2).mean("s", skipna=True))
        table[f"rms_{comp}_um"] = rms.values
    pk = peaks[peaks["run"].astype(str).isin(table["run"].astype(str))]
    top = pk.loc[pk.groupby("run").amplitude_um.idxmax()] if len(pk) else pk
    table = table.merge(pd.DataFrame({
        "run": top["run"], "largest_peak_um": top["amplitude_um"],
        "largest_peak_wavelength_mm": 1.0 / top["f_spatial_per_mm"].astype(float),
        "largest_peak_mechanism": top["mechanism"]}), on="run", how="left")
    counts = pk.groupby(["run", "mechanism"]).size().unstack(fill_value=0)
    counts.columns = [f"{c}_peaks" for c in counts.columns]
    table = table.merge(counts.reset_index(), on="run", how="left")
    table[list(counts.columns)] = table[list(counts.columns)].fillna(0).astype(int)
    return table
