"""Gathering the per-cut profile analyses into the chapter-2 artefacts (metrics, tables,
peaks with mechanism, spectra and profiles of every cut).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.surface.peaks import attribute_mechanisms
from robomill.surface.psd import common_join, spectra_dataset
from robomill.surface.tables import (
    compare_with_thesis,
    design_table,
    load_thesis_tables,
    path_direction,
    rms_table,
)

#: per-cut scalars gathered into results/surface/metrics.csv (one column each)
METRIC_COLUMNS = ("Wt_um", "Wq_um", "Rq_um", "Ra_um", "Rz_um", "waviness_rms_um",
                  "roughness_rms_um", "parseval_rms_um", "tilt_um_per_mm")
#: results/surface/peaks.csv columns
PEAK_TABLE_COLUMNS = ["cut", "f_spatial_per_mm", "f_temporal_hz", "amplitude_um", "mechanism",
                      "band", "feed_mm_s", "power_um2", "n_witnesses", "n_kinematic_support",
                      "n_dynamic_support", "resolution_per_mm", "below_resolution"]

def gather_surface(per_cut: Sequence[xr.Dataset], cuts: pd.DataFrame,
                   peaks: Sequence[pd.DataFrame], options: Mapping[str, Any], *,
                   processes: Mapping[str, Mapping[str, Any]] | None = None
                   ) -> dict[str, Any]:
    """Gather the per-cut profile analyses into the chapter-2 artefacts.

    Parameters
    ----------
    per_cut
        :func:`analyse_profile` datasets, each with ``attrs["cut"]`` (any order).
    cuts
        The study plan, one row per cut (``cut``, ``set``, ``segment``, ``direction``,
        ``feed_mm_s``, ``depth_mm``, …).
    peaks
        :func:`profile_peaks` tables of the cuts (with a ``cut`` column).
    options
        :func:`settings` (``match_tolerance``, ``min_feed_ratio``).
    processes
        For a design other than the thesis' (:func:`robomill.experiment.is_thesis_design`):
        cut id → :func:`robomill.experiment.cut_process` (the cut's own speed, flutes, feed per
        tooth, tooth passing, immersion, milling mode, direction). Then there are no thesis
        tables and no thesis comparison: ``by_design`` (:func:`design_table`) instead;
        ``metrics`` gains the process columns and ``path_direction``, the peaks are attributed
        among the cuts of the same path direction and gain ``tooth_passing_hz`` and
        ``tooth_passing_order`` (f_temporal / the cut's own tooth passing: an integer for
        feed marks).

    Returns
    -------
    dict
        ``metrics`` (one row per cut, plan order), ``waviness`` and ``roughness`` (Tables
        2.1/2.2 by the segment method, :func:`rms_table`), ``comparison`` (both against the
        thesis, :func:`compare_with_thesis`), ``peaks`` (with mechanism,
        :func:`attribute_mechanisms`), ``spectra`` (:func:`spectra_dataset`) and ``profiles``
        (measured, detrended, waviness and roughness along ``cut``, with the plan's
        ``feed_mm_s``, ``set``, ``segment``, ``direction``).
    """
    by_id = {c: i for i, c in enumerate(cuts["cut"])}
    unknown = [d.attrs.get("cut") for d in per_cut if d.attrs.get("cut") not in by_id]
    if unknown:
        raise ValueError(f"gather_surface: cut(s) {unknown} are not in the plan")
    per_cut = sorted(per_cut, key=lambda d: by_id[d.attrs["cut"]])
    ids = [d.attrs["cut"] for d in per_cut]
    metrics = pd.DataFrame([{"cut": c, **{k: float(d[k]) for k in METRIC_COLUMNS}}
                            for c, d in zip(ids, per_cut, strict=True)])
    grouping = [k for k in ("set", "segment") if k in cuts and cuts[k].notna().all()]
    if processes is None:
        metrics = metrics.merge(cuts[["cut", "set", "segment", "direction", "feed_mm_s",
                                      "depth_mm"]], on="cut")
    else:
        cuts = cuts.copy()
        none = [None] * len(cuts)
        cuts["path_direction"] = [path_direction(d, g) for d, g in
                                  zip(cuts.get("direction", none),
                                      cuts.get("direction_deg", none), strict=True)]
        proc_cols = ("spindle_rpm", "flutes", "tool_diameter_mm", "radial_immersion",
                     "milling", "direction_deg", "feed_per_tooth_mm", "tooth_passing_hz")
        for k in proc_cols:
            cuts[k] = [processes[c][k] for c in cuts["cut"]]
        metrics = metrics.merge(cuts[["cut", *grouping, "path_direction", "feed_mm_s",
                                      "depth_mm", *proc_cols]], on="cut")
    out: dict[str, Any] = {"metrics": metrics}
    if processes is None:
        thesis = load_thesis_tables()
        comparisons = []
        for name, key, value in (("waviness", "table_2_1_waviness_rms_um", "waviness_rms_um"),
                                 ("roughness", "table_2_2_roughness_rms_um",
                                  "roughness_rms_um")):
            out[name] = rms_table(metrics, value)
            comparisons.append(compare_with_thesis(out[name], thesis[key], key))
        out["comparison"] = pd.concat(comparisons, ignore_index=True)
    else:
        out["by_design"] = design_table(metrics)
    found = attribute_mechanisms(pd.concat(list(peaks), ignore_index=True), cuts,
                                 tolerance=float(options["match_tolerance"]),
                                 min_feed_ratio=float(options["min_feed_ratio"]),
                                 group_by=("set", "direction") if processes is None
                                 else ("path_direction",))
    out["peaks"] = found[PEAK_TABLE_COLUMNS]
    if processes is not None:
        tp = np.array([float(processes[c]["tooth_passing_hz"]) for c in found["cut"]])
        out["peaks"] = out["peaks"].assign(tooth_passing_hz=tp,
                                           tooth_passing_order=found["f_temporal_hz"] / tp)
    out["spectra"] = spectra_dataset(per_cut, ids)
    keep = ["z_measured", "z", "waviness", "roughness"]
    profiles = xr.concat([d[keep].astype("float32") for d in per_cut], dim="cut",
                         join=common_join(per_cut, "x"), compat="override", coords="minimal")
    for k in keep:
        profiles[k].attrs = per_cut[0][k].attrs
    profiles = profiles.assign_coords(cut=("cut", ids, {"units": "1", "long_name": "cut"}))
    plan = cuts.set_index("cut").loc[ids]
    cols = [("feed_mm_s", "mm/s"), ("set", "1"), ("segment", "1"), ("direction", "1")]
    if processes is not None:
        cols = [(c, u) for c, u in cols if c not in ("set", "segment") or c in grouping]
        cols[-1] = ("path_direction", "1")
    for col, units in cols:
        profiles[col] = ("cut", plan[col].to_numpy(), {"units": units, "long_name": col})
    out["profiles"] = profiles
    return out
