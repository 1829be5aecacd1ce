"""Chapter 2's findings: every number, flag and verdict the surface chapter states, computed
from the stage's artefacts and rendered by the chapter (:mod:`robomill.pipeline.prose`): the
profiles measured, the example cuts of the figures, the segment-method RMS (eq. 2.6) by
direction and against the feed, the peaks and their mechanism with the verdict per band
(``surface.mechanism_share_min``), the resolution sanity flag (``surface.min_peak_cycles``),
the recovery of the planted levels (synthetic data) and, for the thesis' design, the cells of
Tables 2.1/2.2 within the comparison factor."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill import catalogue
from robomill.findings import Findings
from robomill.surface.tables import (
    example_cut,
    figure_directions,
    path_label,
    with_directions,
)

_METRICS = catalogue.artefact("surface.metrics")
_PEAKS = catalogue.artefact("surface.peaks")
_PROFILES = catalogue.artefact("surface.profiles")
_RECOVERY = catalogue.artefact("surface.recovery")
_COMPARISON = catalogue.artefact("surface.thesis_comparison")


def _span(values) -> list[float] | None:
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    return [float(v.min()), float(v.max())] if v.size else None


def _mechanism_verdict(band: pd.DataFrame, share_min: float) -> tuple[str, dict[str, float]]:
    """The band's mechanism: the one (kinematic, dynamic) that at least ``share_min`` of its
    peaks have, ``mixed`` when neither does, ``none`` without peaks."""
    if not len(band):
        return "none", {}
    share = {m: float((band["mechanism"] == m).mean()) for m in ("kinematic", "dynamic")}
    best = max(share, key=share.get)
    return (best if share[best] >= share_min else "mixed"), share


def surface_findings(metrics: pd.DataFrame, peaks: pd.DataFrame, profiles: xr.Dataset, *,
                     settings: Mapping[str, Any], thesis_layout: bool, synthetic: bool,
                     design: str | None = None, comparison: pd.DataFrame | None = None,
                     recovery: pd.DataFrame | None = None,
                     reference: pd.DataFrame | None = None,
                     areal: pd.DataFrame | None = None,
                     profile_vs_areal: pd.DataFrame | None = None) -> Findings:
    """The findings of the surface stage.

    Parameters
    ----------
    metrics, peaks
        ``results/surface/metrics.csv`` (``cut, set, segment, direction`` or a free design's
        ``path_direction``, ``feed_mm_s, tilt_um_per_mm, waviness_rms_um, roughness_rms_um,
        Ra_um``) and ``results/surface/peaks.csv`` (``cut, band, mechanism,
        f_spatial_per_mm, f_temporal_hz, feed_mm_s``, the sanity flag ``below_resolution``
        with ``resolution_per_mm``).
    profiles
        ``results/surface/profiles.nc`` (``x`` [mm]: the sampling of every profile).
    settings
        ``config.yaml: surface`` (:func:`robomill.surface.options.settings`): ``lambda_c_mm,
        filter_end, match_tolerance, min_feed_ratio``; ``min_peak_cycles`` decides the verdict
        ``peaks_resolved`` (pass: no peak has fewer periods in the length its spectrum
        covers), ``mechanism_share_min`` the verdicts ``waviness_mechanism`` and
        ``roughness_mechanism`` (``kinematic``/``dynamic`` when at least that share of the
        band's resolved peaks, those not ``below_resolution``, have it, ``mixed`` otherwise,
        ``none`` without a resolved peak) and
        ``temporal_quantiles`` the spread of the dynamic peaks' temporal frequency.
    thesis_layout, synthetic
        The profiled cuts follow the thesis' design (Tables 2.1/2.2 exist); the data come from
        the virtual cell.
    design
        One line describing the design of the profiled cuts
        (:func:`robomill.pipeline.design_tables.describe_design`), or ``None``.
    comparison
        ``results/surface/thesis_comparison.csv`` (thesis' design only): per table the cells
        ``within_<f>x`` of the thesis' value and the median ratio.
    recovery
        ``results/surface/recovery.csv`` (synthetic data only): recovered over planted RMS.
    reference
        ``results/surface/reference_comparison.csv`` (where profile files state their own
        parameters): :func:`robomill.surface.reference.add_reference_findings`, verdict
        ``reference_agreement`` against ``surface.reference_rtol``.
    areal, profile_vs_areal
        ``results/surface/areal.csv`` and ``profile_vs_areal.csv`` (where the folder has
        areal scans): :func:`robomill.surface.areal_study.add_areal_findings`.

    Returns
    -------
    Findings
        See ``docs/artefacts.md`` (``results/surface/findings.yaml``) for every key.
    """
    found = Findings("surface")
    m = with_directions(metrics)
    x = np.asarray(profiles["x"].values, float)
    found.add("n_profiles", int(len(m)), artefact=_METRICS, what="rows")
    found.add("n_samples", int(x.size), artefact=_PROFILES, what="x")
    found.add("sampling_per_mm", float(1.0 / (x[1] - x[0])) if x.size > 1 else None, "1/mm",
              artefact=_PROFILES, what="1 / (x[1] - x[0])")
    found.add("profile_length_mm", float(x[-1] - x[0]) if x.size else None, "mm",
              artefact=_PROFILES, what="x[-1] - x[0]")
    found.add("lambda_c_mm", float(settings["lambda_c_mm"]), "mm")
    found.add("filter_end", str(settings["filter_end"]))
    found.add("synthetic", bool(synthetic))
    found.add("thesis_layout", bool(thesis_layout))
    found.add("design", design)

    # the figures' example cuts
    c0 = example_cut(m, thesis_layout)
    found.add("example_cut", c0, artefact=_METRICS, what="cut")
    found.add("example_tilt_um_per_mm", float(m.set_index("cut").loc[c0, "tilt_um_per_mm"]),
              "um/mm", artefact=_METRICS, what=f"tilt_um_per_mm[cut = {c0}]")
    d0 = m[m["direction"] == m["direction"].iloc[0]]
    lo, hi = d0.loc[d0["feed_mm_s"].idxmin()], d0.loc[d0["feed_mm_s"].idxmax()]
    found.add("low_feed_cut", str(lo["cut"]), artefact=_METRICS,
              what="lowest feed_mm_s of the first cut's direction")
    found.add("high_feed_cut", str(hi["cut"]), artefact=_METRICS,
              what="highest feed_mm_s of the first cut's direction")
    found.add("low_feed_mm_s", float(lo["feed_mm_s"]), "mm/s", artefact=_METRICS)
    found.add("high_feed_mm_s", float(hi["feed_mm_s"]), "mm/s", artefact=_METRICS)
    dirs = figure_directions(m, thesis_layout)
    found.add("directions", dirs, artefact=_METRICS, what="direction")
    found.add("direction_labels", [path_label(d) for d in dirs])
    found.add("profiles_set", int(m["set"].min()) if thesis_layout else None,
              artefact=_METRICS, what="set, the first")
    found.add("sets", sorted(int(s) for s in m["set"].unique()) if thesis_layout else None,
              artefact=_METRICS, what="set")

    # RMS by the segment method (eq. 2.6), by direction and against the feed
    for col, key in (("waviness_rms_um", "waviness_rms_um_range"),
                     ("roughness_rms_um", "roughness_rms_um_range"), ("Ra_um", "Ra_um_range")):
        found.add(key, _span(m[col]) if col in m else None, "um", artefact=_METRICS, what=col)
    means = m.groupby("label")[["waviness_rms_um", "roughness_rms_um"]].mean()
    wav = means["waviness_rms_um"].sort_values(kind="stable")
    found.add("waviness_by_direction_labels", list(wav.index), artefact=_METRICS,
              what="direction, by mean waviness_rms_um, smallest first")
    found.add("waviness_by_direction_um", wav.to_numpy(), "um", artefact=_METRICS,
              what="waviness_rms_um, mean per direction")
    found.add("smallest_waviness_direction", str(wav.index[0]), artefact=_METRICS)
    found.add("largest_waviness_direction", str(wav.index[-1]), artefact=_METRICS)
    rough = means["roughness_rms_um"].sort_values(kind="stable")
    found.add("roughness_by_direction_labels", list(rough.index), artefact=_METRICS,
              what="direction, by mean roughness_rms_um, smallest first")
    found.add("roughness_by_direction_um", rough.to_numpy(), "um", artefact=_METRICS,
              what="roughness_rms_um, mean per direction")
    varies = len(m) > 1 and m["feed_mm_s"].nunique() > 1
    for band in ("waviness", "roughness"):
        r = (float(np.corrcoef(m["feed_mm_s"], m[f"{band}_rms_um"])[0, 1]) if varies
             else None)
        found.add(f"feed_correlation_{band}", r, artefact=_METRICS,
                  what=f"Pearson r of {band}_rms_um with feed_mm_s (none: one feed)")

    # peaks and their mechanism across feeds
    found.add("match_tolerance", float(settings["match_tolerance"]))
    found.add("min_feed_ratio", float(settings["min_feed_ratio"]))
    found.add("n_peaks", int(len(peaks)), artefact=_PEAKS, what="rows")
    wv = peaks[peaks["band"] == "waviness"]
    rg = peaks[peaks["band"] == "roughness"]
    kin = wv[wv["mechanism"] == "kinematic"]
    dyn = rg[rg["mechanism"] == "dynamic"]
    found.add("n_waviness_peaks", int(len(wv)), artefact=_PEAKS, what="band = waviness")
    found.add("n_roughness_peaks", int(len(rg)), artefact=_PEAKS, what="band = roughness")
    found.add("n_kinematic_waviness", int(len(kin)), artefact=_PEAKS,
              what="band = waviness, mechanism = kinematic")
    f_kin = kin["f_spatial_per_mm"].to_numpy(float)
    found.add("kinematic_wavelength_mm", float(1.0 / np.median(f_kin)) if f_kin.size else None,
              "mm", artefact=_PEAKS, what="1 / median f_spatial_per_mm[waviness, kinematic]")
    found.add("kinematic_f_range_per_mm", _span(f_kin), "1/mm", artefact=_PEAKS,
              what="f_spatial_per_mm[waviness, kinematic]")
    found.add("kinematic_feed_range_mm_s", _span(kin["feed_mm_s"]), "mm/s", artefact=_PEAKS,
              what="feed_mm_s[waviness, kinematic]")
    found.add("n_dynamic_roughness", int(len(dyn)), artefact=_PEAKS,
              what="band = roughness, mechanism = dynamic")
    q = [float(v) for v in settings["temporal_quantiles"]]
    found.add("temporal_quantiles_pct", [100.0 * v for v in q], "%")
    f_dyn = dyn["f_temporal_hz"].to_numpy(float)
    found.add("dynamic_hz_spread", [float(np.quantile(f_dyn, v)) for v in q]
              if f_dyn.size else None, "Hz", artefact=_PEAKS,
              what="quantiles of f_temporal_hz[roughness, dynamic]")
    share_min = float(settings["mechanism_share_min"])
    # a peak below resolution is no evidence of a mechanism (the sanity flag below)
    resolved = (~peaks["below_resolution"].astype(bool) if "below_resolution" in peaks
                else pd.Series(True, index=peaks.index))
    for band, rows in (("waviness", wv), ("roughness", rg)):
        verdict, share = _mechanism_verdict(rows[resolved[rows.index]], share_min)
        found.add(f"{band}_kinematic_share", share.get("kinematic"), artefact=_PEAKS,
                  what=f"share of mechanism = kinematic, resolved peaks of band = {band}")
        found.add(f"{band}_dynamic_share", share.get("dynamic"), artefact=_PEAKS,
                  what=f"share of mechanism = dynamic, resolved peaks of band = {band}")
        found.add(f"{band}_mechanism", verdict, verdict=verdict, threshold=share_min,
                  config_key="surface.mechanism_share_min", artefact=_PEAKS,
                  what=f"mechanism of at least the threshold's share of the resolved peaks "
                       f"of band = {band}")

    # sanity flag: peaks with too few periods in the length their spectrum covers
    cycles = float(settings["min_peak_cycles"])
    found.add("has_resolution_flag", "below_resolution" in peaks, artefact=_PEAKS,
              what="column below_resolution")
    if "below_resolution" in peaks:
        low = peaks[peaks["below_resolution"].astype(bool)]
        found.add("n_below_resolution", int(len(low)), artefact=_PEAKS,
                  what="below_resolution")
        found.add("n_below_resolution_waviness", int((low["band"] == "waviness").sum()),
                  artefact=_PEAKS)
        found.add("n_below_resolution_roughness", int((low["band"] == "roughness").sum()),
                  artefact=_PEAKS)
        found.add("below_resolution_precision_pct", 50.0 / cycles, "%",
                  what="half a bin over min_peak_cycles periods")
        if len(low):
            first = low.iloc[0]
            found.add("below_resolution_example_cut", str(first["cut"]), artefact=_PEAKS)
            found.add("below_resolution_example_per_mm", float(first["f_spatial_per_mm"]),
                      "1/mm", artefact=_PEAKS)
            found.add("below_resolution_example_resolution_per_mm",
                      float(first["resolution_per_mm"]), "1/mm", artefact=_PEAKS)
        found.add("peaks_resolved", not len(low), verdict="fail" if len(low) else "pass",
                  threshold=cycles, config_key="surface.min_peak_cycles", artefact=_PEAKS,
                  what="no peak below_resolution")

    # recovery of the planted levels (synthetic data)
    found.add("has_recovery", recovery is not None and len(recovery) > 0, artefact=_RECOVERY)
    if recovery is not None and len(recovery):
        for band in ("waviness", "roughness"):
            ratio = recovery[f"{band}_ratio"].to_numpy(float)
            found.add(f"recovery_{band}_ratio_range", _span(ratio), artefact=_RECOVERY,
                      what=f"{band}_ratio")
            found.add(f"recovery_{band}_worst_pct", float(100 * np.nanmax(np.abs(ratio - 1))),
                      "%", artefact=_RECOVERY, what=f"max |{band}_ratio - 1|")
        found.add("recovery_waviness_below_planted",
                  int((recovery["waviness_ratio"] < 1).sum()), artefact=_RECOVERY,
                  what="waviness_ratio < 1")

    # the thesis' Tables 2.1/2.2: cells within the comparison factor (thesis' design only)
    found.add("has_thesis_tables", comparison is not None and len(comparison) > 0,
              artefact=_COMPARISON)
    if comparison is not None and len(comparison):
        within = next(c for c in comparison.columns if c.startswith("within_"))
        found.add("thesis_factor", float(within.removeprefix("within_").removesuffix("x")),
                  artefact=_COMPARISON, what=f"column {within}")
        for band, table in (("waviness", "table_2_1_waviness_rms_um"),
                            ("roughness", "table_2_2_roughness_rms_um")):
            rows = comparison[comparison["table"] == table]
            found.add(f"{band}_cells", int(len(rows)), artefact=_COMPARISON,
                      what=f"table = {table}")
            found.add(f"{band}_cells_within", int(rows[within].astype(bool).sum()),
                      artefact=_COMPARISON, what=f"{within}[table = {table}]")
            found.add(f"{band}_median_ratio", float(rows["ratio"].median()) if len(rows)
                      else None, artefact=_COMPARISON, what=f"median ratio[table = {table}]")
    # ours against the parameters profile files state about themselves (where any do)
    if reference is not None:
        from robomill.surface.reference import add_reference_findings

        add_reference_findings(found, reference, float(settings["reference_rtol"]))
    # areal scans (where the folder has any), and stylus against scan for cuts with both
    if areal is not None:
        from robomill.surface.areal_study import add_areal_findings

        add_areal_findings(found, areal, profile_vs_areal)
    return found

