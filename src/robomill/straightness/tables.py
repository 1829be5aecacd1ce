"""Chapter 3.2 tables computed from the straightness artefacts: the cross-check against the
surface peaks, the band-to-floor ratios, the per-run summary, and the tables as the chapter
shows them (direction labels, yes/no flags: :func:`mesh_table`, :func:`attribution_table`,
:func:`truth_table`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
import xarray as xr

from robomill.experiment import DIRECTION_LABELS

ATTRIBUTION_COLUMNS = ["direction", "feed_mm_s", "joint", "stage", "order", "f_spatial_per_mm",
                       "amplitude_um", "on_surface", "surface_f_per_mm", "merged",
                       "candidates"]
"""The columns of the chapter's peak → gear attribution table (:func:`attribution_table`)."""


def direction_text(direction: str) -> str:
    """A tracker path direction as printed: ``+Y`` for a named one (``py``), ``45°`` for one
    given in degrees (``"45 deg"``, ``"d45"``)."""
    d = str(direction)
    return DIRECTION_LABELS.get(d) or f"{float(d.lstrip('d').split()[0]):g}°"


def with_labels(table: pd.DataFrame) -> pd.DataFrame:
    """``table`` with its ``direction`` column printed (:func:`direction_text`)."""
    return table.assign(direction=table["direction"].map(direction_text))


def surface_tolerance_per_mm(tracker_resolution_per_mm: Sequence[float] | np.ndarray,
                             surface_peaks: pd.DataFrame | None, tol_bins: float) -> float:
    """The match tolerance between a tracker peak and a surface peak: ``tol_bins`` bins of the
    coarser of the two resolutions, the coarsest tracker run's 1/L and the finest resolution
    of the surface peaks (``resolution_per_mm`` of ``results/surface/peaks.csv``: 1/L of the
    profiles their waviness comes from)."""
    res = float(np.nanmax(np.asarray(tracker_resolution_per_mm, float)))
    if surface_peaks is not None and "resolution_per_mm" in surface_peaks and len(surface_peaks):
        res = max(res, float(pd.to_numeric(surface_peaks["resolution_per_mm"]).min()))
    return float(tol_bins) * res


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


def mesh_table(gears: pd.DataFrame) -> pd.DataFrame:
    """The tooth-mesh spatial frequency of every gear stage [1/mm], one column per path
    direction (``results/straightness/gears.csv``, ``order == mesh``; mean over the runs of a
    direction), rounded to 4 decimals."""
    mesh = gears[gears["order"] == "mesh"]
    return (mesh.pivot_table(index=["joint", "stage"], columns="direction",
                             values="f_spatial_per_mm", aggfunc="mean")
            .rename(columns=direction_text).round(4))


def attribution_table(gear_peaks: pd.DataFrame, surface_peaks: pd.DataFrame | None, *,
                      tolerance_per_mm: float) -> pd.DataFrame:
    """The gear-attributed peaks with their presence on the surface
    (:func:`surface_cross_check`; ``surface_peaks`` ``None`` where no surface was profiled:
    none on it) as the chapter shows them: :data:`ATTRIBUTION_COLUMNS` (``merged``/
    ``candidates`` where ``peaks.csv`` has them), directions printed, flags yes/no, rounded
    to 4 decimals."""
    if surface_peaks is None:
        surface_peaks = pd.DataFrame({"cut": pd.Series(dtype=str),
                                      "f_spatial_per_mm": pd.Series(dtype=float)})
    xc = surface_cross_check(gear_peaks, surface_peaks, tolerance_per_mm=tolerance_per_mm)
    yes_no = {True: "yes", False: "no"}
    out = with_labels(xc).assign(on_surface=xc["on_surface"].map(yes_no))
    if {"candidates", "merged"} <= set(out.columns):
        out["merged"] = out["merged"].astype(bool).map(yes_no)
        out["candidates"] = out["candidates"].astype(object).fillna("")
    return out[[c for c in ATTRIBUTION_COLUMNS if c in out.columns]].round(4)


def truth_table(truth_check: pd.DataFrame) -> pd.DataFrame:
    """``results/straightness/truth_check.csv`` as the chapter shows it: the elements in band
    (``class`` not ``out_of_band``), directions printed, rounded to 4 decimals."""
    shown = with_labels(truth_check[truth_check["class"] != "out_of_band"])
    if "merged_into" in shown:
        shown = shown.assign(merged_into=shown["merged_into"].astype(object).fillna(""))
    return shown.round(4)


def read_peaks(path) -> pd.DataFrame:
    """``results/straightness/peaks.csv`` as the chapter uses it: empty ``stage``/``order``
    as ``""``, ``joint`` an integer column with gaps."""
    peaks = pd.read_csv(path, keep_default_na=False, na_values=[""])
    peaks[["stage", "order"]] = peaks[["stage", "order"]].fillna("")
    peaks["joint"] = peaks["joint"].astype("Int64")
    return peaks


def run_values_table(profiles: xr.Dataset, peaks: pd.DataFrame
                     ) -> tuple[pd.DataFrame, list[str]]:
    """The per-run summary (:func:`run_summary_table`) as the chapter groups it by what varies
    (:func:`robomill.pipeline.design_tables.per_cut_table`): the table (``run, direction,
    feed_mm_s`` and the values) and the value columns in order (RMS per component, the
    largest peak, the peaks per mechanism)."""
    table = run_summary_table(profiles, peaks)
    values = [c for c in table.columns if c.startswith("rms_")] + [
        "largest_peak_um", "largest_peak_wavelength_mm", "largest_peak_mechanism",
        *[c for c in table.columns if c.endswith("_peaks")]]
    return table[["run", "direction", "feed_mm_s", *values]], values
