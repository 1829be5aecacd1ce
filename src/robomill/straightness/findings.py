"""Chapter 3.2's findings: every number, range and verdict the chapter states, computed here
and rendered by the chapter (:mod:`robomill.pipeline.prose`):

- the runs (:func:`_runs`): how many, their directions (in the figures' order) and feeds,
  the analysed length and resolution 1/L, the measured speed against the commanded feed, the
  peaks by mechanism and the runs without a time base;
- where the gear-attributed peaks lie, the peaks of constant temporal frequency (a servo
  ripple), and whether the motion has a component in the surface's roughness band — a
  verdict against ``straightness.threshold``, the same threshold that makes a peak;
- how many gear peaks are also surface-waviness peaks (:func:`_surface`, chapter 2's
  ``peaks.csv``) and which merge gear lines closer than the resolution;
- the RMS deviation from the best line per component (:func:`_per_run`);
- in a synthetic study, the attribution against the planted gears (:func:`_truth`);
- the thesis' numbers its closing section names (:func:`_sources`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
import xarray as xr

from robomill import catalogue, references
from robomill.findings import Findings
from robomill.settings import schema_default
from robomill.straightness.attribution import NO_TIME_BASE
from robomill.straightness.tables import (
    band_floor_table,
    direction_text,
    run_summary_table,
    surface_cross_check,
    surface_tolerance_per_mm,
)
from robomill.straightness.truth import attribution_counts

_PEAKS = catalogue.artefact("straightness.peaks")
_PROFILES = catalogue.artefact("straightness.profiles")
_SURFACE_PEAKS = catalogue.artefact("surface.peaks")
_TRUTH_CHECK = catalogue.artefact("straightness.truth_check")
_REFERENCES = "src/robomill/data/references.yaml"
THESIS_DIRECTIONS = ("py", "my", "px")
"""The thesis' order of the path directions in its figures (±Y, then +X)."""


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
                          threshold: float, surface_peaks: pd.DataFrame | None = None,
                          truth_check: pd.DataFrame | None = None,
                          tol_bins: float = schema_default("straightness", "tol_bins"),
                          fmin_cycles: float | None = None, truth_margin: float | None = None,
                          thesis_design: bool | None = None) -> Findings:
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
    surface_peaks
        Chapter 2's ``results/surface/peaks.csv`` (``cut, f_spatial_per_mm``, optionally
        ``resolution_per_mm``); ``None`` where the study profiled no surface
        (:func:`_surface`).
    truth_check
        ``results/straightness/truth_check.csv``; ``None`` or empty with real data
        (:func:`_truth`).
    tol_bins, fmin_cycles, truth_margin
        ``straightness.tol_bins`` (the match tolerance in bins of 1/L),
        ``straightness.fmin_cycles`` and ``straightness.truth_margin`` (the classes of the
        planted elements, :func:`robomill.straightness.truth.evaluate_attribution`).
    thesis_design
        Whether the study is the thesis' design (its figures: ±Y, then +X); ``None``
        (unknown) is read as the thesis' layout.

    Returns
    -------
    Findings
        The findings of :func:`_runs`; ``n_gear_peaks, gear_f_range_per_mm,
        gear_main_wavelength_mm_range`` (the largest gear peak of each run);
        ``n_temporal, temporal_hz_mean, temporal_hz_std, temporal_wavelength_mm_range,
        temporal_amplitude_um_range``; ``surface_band_per_mm, quiet_band_per_mm,
        n_surface_band_peaks, surface_band_peak_to_floor_max,
        quiet_band_peak_to_floor_range`` and the verdict ``motion_in_surface_band``; then
        those of :func:`_surface`, :func:`_per_run`, :func:`_truth` and :func:`_sources`.
    """
    found = Findings("straightness")
    _runs(found, profiles, peaks, thesis_design)
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
    _surface(found, profiles, gear, surface_peaks, tol_bins)
    _per_run(found, profiles, peaks)
    _truth(found, truth_check, fmin_cycles, truth_margin)
    _sources(found)
    return found


def figure_directions(directions: Sequence[str], thesis_layout: bool) -> list[str]:
    """The path directions in the order of the chapter's figures: the thesis' (+Y, −Y, +X)
    in its layout, else sorted."""
    present = list(dict.fromkeys(str(d) for d in directions))
    if thesis_layout:
        return [d for d in THESIS_DIRECTIONS if d in present]
    return sorted(present)


def _runs(found: Findings, profiles: xr.Dataset, peaks: pd.DataFrame,
          thesis_design: bool | None) -> None:
    """The runs: ``n_runs``, ``feeds_mm_s`` (each feed once) and ``feed_range_mm_s``;
    ``thesis_layout`` (the thesis' design: its figures' order and numbers),
    ``directions``/``direction_labels`` (the figures' order, :func:`figure_directions`),
    ``main_directions`` (the figures of the deviation section: ±Y in the thesis' layout, every
    direction otherwise) and ``extra_directions``/``extra_direction_labels`` (the others),
    ``high_band_direction`` (the spectrum shown up to the roughness band: −Y where there is
    one); ``length_mm_mean``, ``resolution_per_mm_mean`` (1/L), ``speed_error_pct_max``
    (largest |measured speed / feed − 1|, %), ``n_peaks``, ``n_spatial``,
    ``n_unclassified`` and ``untimed_runs`` (runs without a time base, whose peaks cannot be
    classified temporal or spatial, and why: ``untimed_reason``)."""
    feeds = np.asarray(profiles["feed_mm_s"].values, float)
    found.add("n_runs", int(profiles.sizes["run"]), artefact=_PROFILES, what="run")
    found.add("feeds_mm_s", sorted({float(v) for v in feeds}), "mm/s", artefact=_PROFILES,
              what="feed_mm_s")
    found.add("feed_range_mm_s", _span(feeds), "mm/s", artefact=_PROFILES, what="feed_mm_s")
    layout = thesis_design is not False
    dirs = figure_directions(profiles["direction"].values, layout)
    main = [d for d in dirs if d in ("py", "my")] if layout else dirs
    extra = [d for d in dirs if d not in main]
    found.add("thesis_layout", layout, artefact=catalogue.artefact("ingest.study"),
              what="the thesis' design (robomill.experiment.is_thesis_design)")
    found.add("directions", dirs, artefact=_PROFILES, what="direction, the figures' order")
    found.add("direction_labels", [direction_text(d) for d in dirs], artefact=_PROFILES,
              what="direction, printed")
    found.add("main_directions", main, artefact=_PROFILES, what="direction")
    found.add("extra_directions", extra, artefact=_PROFILES, what="direction")
    found.add("extra_direction_labels", [direction_text(d) for d in extra],
              artefact=_PROFILES, what="direction, printed")
    found.add("high_band_direction", "my" if "my" in dirs else dirs[0] if dirs else None,
              artefact=_PROFILES, what="direction")
    for key, coord, unit, what in (
            ("length_mm_mean", "length_mm", "mm", "length_mm, mean over the runs"),
            ("resolution_per_mm_mean", "resolution_per_mm", "1/mm",
             "resolution_per_mm (1/L), mean over the runs")):
        if coord in profiles.coords:
            found.add(key, float(np.mean(profiles[coord].values)), unit, artefact=_PROFILES,
                      what=what)
    if "speed_mm_s" in profiles.coords:
        ratio = np.asarray(profiles["speed_mm_s"].values, float) / feeds - 1.0
        found.add("speed_error_pct_max",
                  100 * float(np.nanmax(np.abs(ratio))) if np.isfinite(ratio).any() else None,
                  "%", artefact=_PROFILES, what="100 |speed_mm_s / feed_mm_s - 1|, largest")
    mech = peaks["mechanism"].astype(str)
    found.add("n_peaks", int(len(peaks)), artefact=_PEAKS, what="rows")
    found.add("n_spatial", int((mech == "spatial").sum()), artefact=_PEAKS,
              what="mechanism = spatial (no gear)")
    found.add("n_unclassified", int((mech == "unclassified").sum()), artefact=_PEAKS,
              what="mechanism = unclassified")
    untimed = ([str(r) for r, t in zip(profiles["run"].values, profiles["time_base"].values,
                                       strict=True) if str(t) == "none"]
               if "time_base" in profiles.coords else [])
    found.add("untimed_runs", untimed, artefact=_PROFILES, what="run[time_base = none]")
    if untimed:
        found.add("untimed_reason", NO_TIME_BASE, artefact=_PROFILES,
                  what="robomill.straightness.attribution.NO_TIME_BASE")


def _surface(found: Findings, profiles: xr.Dataset, gear: pd.DataFrame,
             surface_peaks: pd.DataFrame | None, tol_bins: float) -> None:
    """The gear peaks on the surface: ``has_surface_peaks``; with chapter 2's peaks
    ``n_surface_peaks``, ``surface_match_tol_per_mm``
    (:func:`~robomill.straightness.tables.surface_tolerance_per_mm`, ``straightness.tol_bins``
    bins) and ``n_gear_on_surface`` (gear peaks with a surface peak of their run's cut within
    it, :func:`~robomill.straightness.tables.surface_cross_check`); ``n_merged`` and
    ``merged_peaks`` (each gear peak whose candidate gear lines lie closer than the
    resolution: direction, feed, frequency and the candidates) where ``peaks.csv`` has the
    ``merged`` column."""
    found.add("has_surface_peaks", surface_peaks is not None, artefact=_SURFACE_PEAKS)
    if surface_peaks is not None and "resolution_per_mm" in profiles.coords:
        tol = surface_tolerance_per_mm(profiles["resolution_per_mm"].values, surface_peaks,
                                       tol_bins)
        xc = surface_cross_check(gear, surface_peaks, tolerance_per_mm=tol)
        found.add("n_surface_peaks", int(len(surface_peaks)), artefact=_SURFACE_PEAKS,
                  what="rows")
        found.add("surface_match_tol_per_mm", tol, "1/mm", artefact=_SURFACE_PEAKS,
                  what="straightness.tol_bins × max(1/L of the runs, resolution_per_mm)")
        found.add("n_gear_on_surface", int(xc["on_surface"].sum()), artefact=_PEAKS,
                  what="gear peaks with a surface peak of their cut within the tolerance")
    if "merged" not in gear:
        return
    merged = gear[gear["merged"].astype(bool)]
    found.add("n_merged", int(len(merged)), artefact=_PEAKS, what="merged[mechanism = gear]")
    found.add("merged_peaks",
              [f"{direction_text(r.direction)} at {float(r.feed_mm_s):g} mm/s, "
               f"{float(r.f_spatial_per_mm):.3f} mm⁻¹: {str(r.candidates).replace(';', ', ')}"
               for r in merged.itertuples()], artefact=_PEAKS,
              what="direction, feed_mm_s, f_spatial_per_mm, candidates[merged]")


def _per_run(found: Findings, profiles: xr.Dataset, peaks: pd.DataFrame) -> None:
    """``rms_<component>_um_range``: the RMS deviation from the best line over the runs, per
    component (:func:`~robomill.straightness.tables.run_summary_table`)."""
    if "deviation_um" not in profiles:
        return
    table = run_summary_table(profiles, peaks)
    for col in (c for c in table.columns if c.startswith("rms_")):
        found.add(f"{col}_range", _span(table[col]), "um", artefact=_PROFILES,
                  what=f"RMS over s of deviation_um[component = "
                       f"{col.removeprefix('rms_').removesuffix('_um')}]")


def _truth(found: Findings, truth_check: pd.DataFrame | None, fmin_cycles: float | None,
           truth_margin: float | None) -> None:
    """Against the planted gears (synthetic studies): ``has_truth``; the class limits
    ``truth_margin`` (``straightness.truth_margin``) and ``fmin_cycles``; the counts of
    :func:`~robomill.straightness.truth.attribution_counts` as ``truth_<count>``, and
    ``truth_merged_elements`` (each merged element and the one its peak was attributed to)."""
    has = truth_check is not None and len(truth_check) > 0
    found.add("has_truth", has, artefact=_TRUTH_CHECK, what="rows (synthetic data only)")
    for key, value in (("truth_margin", truth_margin), ("fmin_cycles", fmin_cycles)):
        if value is not None:
            found.add(key, float(value), artefact="config.yaml", what=f"straightness.{key}",
                      config_key=f"straightness.{key}")
    if not has:
        return
    for key, n in attribution_counts(truth_check).items():
        found.add(f"truth_{key}", n, artefact=_TRUTH_CHECK, what=key)
    shown = truth_check[truth_check["class"] != "out_of_band"]
    into = (shown[shown["merged"].astype(bool)] if "merged_into" in shown else shown.iloc[:0])
    found.add("truth_merged_elements",
              [f"{r.joint}:{r.stage}:{r.order} ({direction_text(r.direction)}, "
               f"{float(r.feed_mm_s):g} mm/s) → {r.merged_into}" for r in into.itertuples()],
              artefact=_TRUTH_CHECK, what="joint, stage, order, merged_into[merged]")


def _sources(found: Findings) -> None:
    """The thesis' numbers the chapter's "Against the thesis" names
    (``robomill/data/references.yaml``); ``ref_dominant_wavelength_min_mm`` is 1 / the
    spatial frequency below which its dominant path irregularities lie."""
    for key, ref in (("ref_dominant_below_per_mm", "thesis.straightness.dominant_below_per_mm"),
                     ("ref_surface_waviness_mm", "thesis.straightness.surface_waviness_mm"),
                     ("ref_surface_marks_per_mm", "thesis.straightness.surface_marks_per_mm"),
                     ("ref_surface_marks_feeds_mm_s",
                      "thesis.straightness.surface_marks_feeds_mm_s")):
        found.add(key, references.value(ref), references.reference(ref)["unit"],
                  artefact=_REFERENCES, what=ref)
    below = references.value("thesis.straightness.dominant_below_per_mm")
    found.add("ref_dominant_wavelength_min_mm", 1.0 / float(below), "mm",
              artefact=_REFERENCES, what="1 / thesis.straightness.dominant_below_per_mm")
