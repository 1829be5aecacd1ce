"""Truth evaluation of the straightness attribution (synthetic runs only): every planted gear
element of ``truth.nc`` classified against the run's noise floor and compared with the peaks
attributed to it.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.settings import section_settings
from robomill.straightness.attribution import element_label, parse_candidates


def evaluate_attribution(peaks: pd.DataFrame, planted: pd.DataFrame, runs: pd.DataFrame, *,
                         threshold: float, tol_bins: float, fmax_per_mm: float,
                         margin: float = 2.0) -> pd.DataFrame:
    """Compare the gear attributions with the planted truth (synthetic runs only).

    Every planted gear element of every run (``planted``: ``run, direction, feed_mm_s,
    joint, stage, order, f_spatial_per_mm, amplitude_um``) is put in one class, from its power
    ``A²/2`` and the run's noise floor ``floor_um2`` (``runs``: ``run, resolution_per_mm,
    fmin_per_mm, floor_um2``; peaks and runs joined to it by ``run``):

    * ``out_of_band`` — below ``fmin`` (fewer cycles than the record resolves) or above
      ``fmax_per_mm``;
    * ``above_noise`` — ``A²/2 ≥ margin·threshold·floor``: it must be found;
    * ``below_noise`` — ``A²/2 < threshold·floor/margin``: it must not be attributed;
    * ``marginal`` — in between (either outcome is acceptable).

    ``found`` is true when a ``gear`` peak of the run is attributed to exactly this element;
    ``merged`` when it is not, but a gear peak of the run lists it among its ``candidates``
    (:func:`match_peaks_to_gears`: merged gear lines, closer than the resolution) or lies
    within the match tolerance of its frequency; ``merged_into`` then names the element that
    peak was attributed to (``joint:stage:order``). ``false_attribution`` marks
    attributed elements that are ``below_noise`` or ``out_of_band`` (the attribution then
    names a gear that did not make the peak).
    """
    rows = []
    gear_peaks = peaks[peaks["mechanism"] == "gear"]
    for _, g in planted.iterrows():
        rid = str(g["run"])
        run = runs[runs["run"].astype(str) == rid]
        if run.empty:
            continue
        run = run.iloc[0]
        power = 0.5 * float(g["amplitude_um"]) ** 2
        floor = float(run["floor_um2"])
        f = float(g["f_spatial_per_mm"])
        if f < float(run["fmin_per_mm"]) or f > fmax_per_mm:
            cls = "out_of_band"
        elif power >= margin * threshold * floor:
            cls = "above_noise"
        elif power < threshold * floor / margin:
            cls = "below_noise"
        else:
            cls = "marginal"
        mine = gear_peaks[gear_peaks["run"].astype(str) == rid]
        exact = mine[(mine["joint"].astype("Int64") == int(g["joint"]))
                     & (mine["stage"] == g["stage"]) & (mine["order"] == g["order"])]
        tol = tol_bins * float(run["resolution_per_mm"])
        near = mine[np.abs(mine["f_spatial_per_mm"].astype(float) - f) <= tol]
        me = (int(g["joint"]), str(g["stage"]), str(g["order"]))
        if "candidates" in mine:
            listed = mine[np.array([me in parse_candidates(c) for c in mine["candidates"]],
                                   dtype=bool)]
            near = pd.concat([listed, near[~near.index.isin(listed.index)]])
        rows.append({"direction": g["direction"], "feed_mm_s": float(g["feed_mm_s"]),
                     "joint": int(g["joint"]),
                     "stage": g["stage"], "order": g["order"], "f_spatial_per_mm": f,
                     "amplitude_um": float(g["amplitude_um"]),
                     "snr_expected": power / floor, "class": cls,
                     "found": not exact.empty, "merged": exact.empty and not near.empty,
                     "merged_into": (element_label(near["joint"].iloc[0], near["stage"].iloc[0],
                                                   near["order"].iloc[0])
                                     if exact.empty and not near.empty else ""),
                     "found_amplitude_um": (float(exact["amplitude_um"].iloc[0])
                                            if not exact.empty else np.nan),
                     "false_attribution": (not exact.empty)
                     and cls in ("below_noise", "out_of_band")})
    return pd.DataFrame(rows)


def attribution_counts(evaluation: pd.DataFrame) -> dict[str, int]:
    """Counts for the report: planted elements above noise, found, merged, missed; false
    attributions."""
    e = evaluation
    above = e["class"] == "above_noise"
    return {
        "planted_elements": int(len(e)),
        "above_noise": int(above.sum()),
        "found": int((above & e["found"]).sum()),
        "merged": int((above & e["merged"]).sum()),
        "missed": int((above & ~e["found"] & ~e["merged"]).sum()),
        "marginal": int((e["class"] == "marginal").sum()),
        "marginal_found": int(((e["class"] == "marginal") & e["found"]).sum()),
        "false_attributions": int(e["false_attribution"].sum()),
    }

#: results/straightness/truth_check.csv columns
TRUTH_CHECK_COLUMNS = ["direction", "feed_mm_s", "joint", "stage", "order", "f_spatial_per_mm",
                       "amplitude_um", "snr_expected", "class", "found", "merged",
                       "found_amplitude_um", "false_attribution", "merged_into"]


def planted_gear_elements(truth: xr.Dataset) -> pd.DataFrame:
    """Every planted gear element × tracker run of the virtual cell's ``truth.nc``: run,
    direction, feed, joint, stage, order, spatial frequency and amplitude perpendicular to
    the path."""
    rows = []
    for k, run in enumerate(truth["tracker_run"].values):
        for g in truth["gear"].values:
            for o in truth["order"].values:
                at = {"tracker_run": run, "gear": g, "order": o}
                rows.append({
                    "run": str(run), "direction": str(truth["tracker_direction"].values[k]),
                    "feed_mm_s": float(truth["tracker_feed_mm_s"].values[k]),
                    "joint": int(truth["gear_joint"].sel(gear=g)),
                    "stage": str(truth["gear_stage"].sel(gear=g).values), "order": str(o),
                    "f_spatial_per_mm": float(truth["tracker_gear_f_spatial_per_mm"].sel(at)),
                    "amplitude_um": float(truth["tracker_gear_amplitude_um"].sel(at))})
    return pd.DataFrame(rows)


def truth_check(peaks: pd.DataFrame | None, truth: xr.Dataset | None,
                profiles: xr.Dataset | None, options: Mapping[str, Any]) -> pd.DataFrame:
    """The attribution against the planted gears (:func:`evaluate_attribution`), columns
    :data:`TRUTH_CHECK_COLUMNS`; an empty table when there is no truth (real data)."""
    if truth is None:
        return pd.DataFrame(columns=TRUTH_CHECK_COLUMNS)
    peaks = peaks.copy()
    peaks[["stage", "order"]] = peaks[["stage", "order"]].fillna("")
    if "candidates" in peaks:
        peaks["candidates"] = peaks["candidates"].fillna("")
    runs = pd.DataFrame({k: profiles[k].values for k in ("run", "direction", "feed_mm_s",
                                                          "resolution_per_mm", "fmin_per_mm",
                                                          "floor_um2")})
    ev = evaluate_attribution(peaks, planted_gear_elements(truth), runs,
                              threshold=options["threshold"], tol_bins=options["tol_bins"],
                              fmax_per_mm=options["fmax_per_mm"],
                              margin=float(section_settings(options, "straightness")[
                                  "truth_margin"]))
    return ev[TRUTH_CHECK_COLUMNS]
