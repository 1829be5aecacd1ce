"""Dominant spectral peaks of the surface profiles and their mechanism across feeds: kinematic
(constant spatial frequency: gears) or dynamic (constant temporal frequency: modes, tooth
passing).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.settings import schema_default
from robomill.spectra import (
    below_resolution,
    find_peaks_spectrum,
)
from robomill.surface.options import settings

MECHANISMS = ("kinematic", "dynamic", "unclassified")

def profile_peaks(ds: xr.Dataset, opts: Mapping[str, Any]) -> pd.DataFrame:
    """Dominant peaks of one analysed profile: waviness band from the whole-profile thesis
    spectrum (resolution fs/N), roughness band from the segment-averaged spectrum with
    ``roughness_peak_segment_mm`` segments (variance of a random-vibration spectrum reduced by
    averaging). A peak is a local maximum above ``peak_prominence_ratio`` × the band's median
    power whose prominence is at least ``local_prominence_ratio`` × its local floor (the
    median power within ±``local_floor_halfwidth_bins`` bins; :func:`robomill.spectra.
    find_peaks_spectrum`): never a bump on the skirt of a stronger line; none qualifying, the
    band has no row. ``f_spatial_per_mm``, ``power_um2`` and ``amplitude_um`` (the sinusoid
    amplitude sqrt(2 P)) are the peak bin's: the frequency is compared across feeds within
    ``match_tolerance`` (relative), which ``min_peak_cycles`` ties to half a bin, and these
    spectra are unwindowed and coarse (a 15 mm profile: 1/L = 0.067 mm⁻¹), where the
    parabola on the log power (:func:`robomill.spectra.interpolate_peak`, used for the
    straightness peaks that are compared with gear lines) is biased by up to 0.17 bin and
    pulled apart by unresolved neighbouring lines.

    Sanity flag: ``resolution_per_mm`` is the bin spacing of the spectrum the peak was found
    in (1/L for waviness, 1/segment for roughness) and ``below_resolution`` marks a peak with
    fewer than ``min_peak_cycles`` periods in that length
    (:func:`robomill.spectra.below_resolution`)."""
    rows = []
    opts = settings(opts)
    n, ratio = int(opts["n_peaks"]), float(opts["peak_prominence_ratio"])
    local = float(opts["local_prominence_ratio"])
    half = int(opts["local_floor_halfwidth_bins"])
    cycles = float(opts["min_peak_cycles"])
    for band, f_name, p_name in (("waviness", "f", "power"),
                                 ("roughness", "f_peak", "power_peak")):
        lo, hi = opts[f"{band}_band_per_mm"]
        f_axis = ds[f_name].values
        res = float(f_axis[1] - f_axis[0]) if f_axis.size > 1 else float("nan")
        for f, p in find_peaks_spectrum(f_axis, ds[p_name].values, fmin=lo, fmax=hi, n=n,
                                        prominence_ratio=ratio, local_ratio=local,
                                        halfwidth_points=half):
            rows.append({"band": band, "f_spatial_per_mm": f, "power_um2": p,
                         "resolution_per_mm": res,
                         "below_resolution": bool(below_resolution(f, res,
                                                                   min_cycles=cycles))})
    df = pd.DataFrame(rows, columns=["band", "f_spatial_per_mm", "power_um2",
                                     "resolution_per_mm", "below_resolution"])
    df["amplitude_um"] = np.sqrt(2.0 * df["power_um2"].astype(float))
    return df

def attribute_mechanisms(peaks: pd.DataFrame, cuts: pd.DataFrame, *, tolerance: float = 0.2,
                         min_feed_ratio: float = schema_default("surface", "min_feed_ratio"),
                         group_by: Sequence[str] = ("set", "direction")) -> pd.DataFrame:
    """Classify each peak as kinematic, dynamic or unclassified, with the evidence.

    For a peak at spatial frequency ``f`` in a cut at feed ``v``, every other cut of the same
    set and direction at a feed ``v'`` differing by at least ``min_feed_ratio`` (so that the
    two hypotheses predict different frequencies) is a witness. The kinematic hypothesis
    predicts a peak at ``f`` there, the dynamic one at ``f·v/v'`` (same temporal frequency).
    A witness supports a hypothesis when a peak of the same band lies within ``tolerance``
    (relative, in log frequency) of its prediction. The class is the hypothesis supported by
    more than half of the witnesses and by more witnesses than the other; otherwise
    ``unclassified`` (also when there is no witness).

    Parameters
    ----------
    peaks
        Columns ``cut, band, f_spatial_per_mm, amplitude_um``.
    cuts
        Columns ``cut, feed_mm_s`` and those of ``group_by``.
    group_by
        The columns a witness shares with the cut (the thesis: same set and direction; a free
        design: the same path direction, :func:`path_direction`).

    Returns
    -------
    DataFrame
        ``peaks`` plus ``feed_mm_s, f_temporal_hz, mechanism, n_witnesses,
        n_kinematic_support, n_dynamic_support``.
    """
    meta = cuts.set_index("cut")
    out = peaks.copy()
    out["feed_mm_s"] = [float(meta.loc[c, "feed_mm_s"]) for c in out["cut"]]
    out["f_temporal_hz"] = out["f_spatial_per_mm"] * out["feed_mm_s"]
    tol = np.log1p(tolerance)
    by_cut = {c: g for c, g in out.groupby("cut")}
    mech, n_w, n_k, n_d = [], [], [], []
    for _, p in out.iterrows():
        same = np.ones(len(meta), bool)
        for col in group_by:
            same &= (meta[col] == meta.loc[p["cut"], col]).to_numpy()
        others = meta[same & (meta.index != p["cut"])]
        w = k = dyn = 0
        for c2, m2 in others.iterrows():
            ratio = p["feed_mm_s"] / float(m2["feed_mm_s"])
            if abs(np.log(ratio)) < np.log(min_feed_ratio):
                continue
            w += 1
            g = by_cut.get(c2)
            if g is None:
                continue
            f2 = g.loc[g["band"] == p["band"], "f_spatial_per_mm"].to_numpy(float)
            if f2.size == 0:
                continue
            f = float(p["f_spatial_per_mm"])
            k += bool(np.min(np.abs(np.log(f2 / f))) <= tol)
            dyn += bool(np.min(np.abs(np.log(f2 / (f * ratio)))) <= tol)
        if w and k > w / 2 and k > dyn:
            mech.append("kinematic")
        elif w and dyn > w / 2 and dyn > k:
            mech.append("dynamic")
        else:
            mech.append("unclassified")
        n_w.append(w)
        n_k.append(k)
        n_d.append(dyn)
    out["mechanism"] = mech
    out["n_witnesses"] = n_w
    out["n_kinematic_support"] = n_k
    out["n_dynamic_support"] = n_d
    return out
