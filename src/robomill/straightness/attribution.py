"""Peak attribution (thesis §3.2, steps 4–5): spectral peaks matched to gear lines within a
tolerance tied to the resolution 1/L, and classified across feeds as gear, constant-temporal,
constant-spatial or unclassified.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from typing import Any

import numpy as np
import pandas as pd

MECHANISMS = ("gear", "temporal", "spatial", "unclassified")
"""Peak mechanisms: matched to a gear; constant temporal frequency across feeds; constant
spatial frequency but no gear; not classifiable (seen at one feed only, no gear)."""

# ---------------------------------------------------------------------------------------------
# 4. peak → gear matching
# ---------------------------------------------------------------------------------------------
PEAK_COLUMNS = ["direction", "feed_mm_s", "f_spatial_per_mm", "amplitude_um", "mechanism",
                "joint", "stage", "order", "gear_f_spatial_per_mm", "f_temporal_hz",
                "component", "snr", "cut"]
"""peaks.csv columns: the contract's first seven, then supporting detail."""


def element_label(joint: Any, stage: Any, order: Any) -> str:
    """``joint:stage:order`` of a gear element (``2:motor:mesh``), as listed in ``candidates``."""
    return f"{int(joint)}:{stage}:{order}"


def parse_candidates(text: Any) -> list[tuple[int, str, str]]:
    """The ``(joint, stage, order)`` elements of a ``candidates`` cell (``;``-separated
    :func:`element_label` s; empty or NaN → none)."""
    if not isinstance(text, str) or not text:
        return []
    out = []
    for item in text.split(";"):
        joint, stage, order = item.split(":")
        out.append((int(joint), stage, order))
    return out


def match_peaks_to_gears(peaks: pd.DataFrame, gears: pd.DataFrame, *,
                         tolerance_per_mm: float,
                         resolution_per_mm: float | None = None) -> pd.DataFrame:
    """Attribute each peak to the gear element whose spatial frequency is nearest, if
    within ``tolerance_per_mm`` (tie it to the resolution: a fraction of 1/L).

    Two gear lines closer than the spectral resolution ``resolution_per_mm`` (default
    ``tolerance_per_mm``), or both within the match tolerance of the peak, make one peak: the
    run cannot tell them apart. With the Hann window of :func:`profile_spectrum` that
    resolution is the main lobe's −6 dB width, 2/L (Harris 1978, Table 1: two equal lines
    closer than that show one maximum), so :func:`analyse_run` passes ``merge_bins/L`` with
    ``merge_bins`` = 2. Such a peak is attributed to the nearest element as before, and
    lists every element that may have made it.

    Adds ``joint`` (nullable int), ``stage``, ``order``, ``gear_f_spatial_per_mm``,
    ``n_candidates`` (gear elements within the match tolerance of the peak), ``candidates``
    (the attributed element first, then every element within the tolerance of the peak or
    closer than ``max(tolerance, resolution)`` to the attributed element's line, by distance
    from the peak, as ``;``-separated :func:`element_label` s; empty when not attributed)
    and ``merged`` (True when ``candidates`` lists more than one element: merged gear lines).
    """
    out = peaks.copy()
    sep = max(tolerance_per_mm, resolution_per_mm or 0.0)
    joint, stage, order, fg, ncand, cands, merged = [], [], [], [], [], [], []
    gf = gears["f_spatial_per_mm"].to_numpy(float)
    for f in out["f_spatial_per_mm"].to_numpy(float):
        d = np.abs(gf - f)
        within = np.flatnonzero(d <= tolerance_per_mm)
        ncand.append(int(within.size))
        if within.size:
            k = int(within[np.argmin(d[within])])
            joint.append(int(gears["joint"].iloc[k]))
            stage.append(str(gears["stage"].iloc[k]))
            order.append(str(gears["order"].iloc[k]))
            fg.append(float(gf[k]))
            near = set(within.tolist()) | set(np.flatnonzero(np.abs(gf - gf[k]) <= sep).tolist())
            near = [k] + sorted(near - {k}, key=lambda i: (d[i], i))
            cands.append(";".join(element_label(gears["joint"].iloc[i], gears["stage"].iloc[i],
                                                gears["order"].iloc[i]) for i in near))
            merged.append(len(near) > 1)
        else:
            joint.append(pd.NA)
            stage.append("")
            order.append("")
            fg.append(np.nan)
            cands.append("")
            merged.append(False)
    out["joint"] = pd.array(joint, dtype="Int64")
    out["stage"] = stage
    out["order"] = order
    out["gear_f_spatial_per_mm"] = fg
    out["n_candidates"] = ncand
    out["candidates"] = cands
    out["merged"] = np.array(merged, bool)
    return out


# ---------------------------------------------------------------------------------------------
# 5. temporal vs spatial classification across feeds
# ---------------------------------------------------------------------------------------------
NO_TIME_BASE = ("a stream without a time base (a distance- or event-triggered tracker export, "
                "imported with --spatial-only) is analysed in space only: its peaks are "
                "matched to the gear lines per mm, but whether an unmatched peak keeps its "
                "temporal or its spatial frequency across feeds cannot be told without the "
                "time base, so it stays unclassified")
"""Why the peaks of a run without a time base are not classified temporal/spatial (the
chapter prints it)."""


def classify_peaks(peaks: pd.DataFrame, resolution_per_mm: Mapping[str, float],
                   *, tol_bins: float = 1.0, min_other_feeds: int = 1,
                   untimed: Collection[str] = ()) -> pd.DataFrame:
    """Classify every peak as ``gear``, ``temporal``, ``spatial`` or ``unclassified``.

    For a peak at spatial frequency f in the run (direction d, feed v), the other runs of
    the same direction at another feed are searched for a peak not attributed to a gear at the same
    *temporal* frequency ``f·v`` (within ``tol_bins`` temporal resolutions ``v/L`` of either
    run) and for any peak at the same *spatial* frequency (within ``tol_bins`` spatial
    resolutions 1/L). Seen at the same temporal frequency, and not at the same spatial
    frequency, in at least ``min_other_feeds`` other feeds (``min_other_feeds + 1`` for a
    peak that itself matches a gear, so that a chance coincidence of slow gear peaks does not
    overrule the gear) ⇒ ``temporal`` (a constant-Hz source such as the 13 Hz servo ripple:
    its wavelength grows with the feed). Otherwise a peak attributed to a gear is ``gear``;
    one seen at the same spatial frequency at other feeds but with no gear is ``spatial``;
    the rest ``unclassified``.

    ``peaks`` needs ``run, direction, feed_mm_s, f_spatial_per_mm`` and ``joint`` (from
    :func:`match_peaks_to_gears`); ``resolution_per_mm`` maps each run id to 1/L.
    The runs ``untimed`` (run ids) have no time base (:data:`NO_TIME_BASE`): their
    peaks are ``gear`` or ``unclassified``, never ``temporal``/``spatial``, and witness for
    no other run.
    """
    untimed = {str(r) for r in untimed}
    out = peaks.copy()
    out["f_temporal_hz"] = out["f_spatial_per_mm"] * out["feed_mm_s"]
    mech = []
    for _, p in out.iterrows():
        run, d = str(p["run"]), p["direction"]
        v, f = float(p["feed_mm_s"]), float(p["f_spatial_per_mm"])
        res_p = resolution_per_mm[run]
        if run in untimed:
            mech.append("unclassified" if pd.isna(p["joint"]) else "gear")
            continue
        others = out[(out["direction"] == d) & (out["feed_mm_s"] != v)
                     & ~out["run"].astype(str).isin(untimed)]
        same_t, same_s = set(), set()
        for _, o in others.iterrows():
            vo = float(o["feed_mm_s"])
            res_o = resolution_per_mm[str(o["run"])]
            tol_t = tol_bins * max(res_p * v, res_o * vo)
            tol_s = tol_bins * max(res_p, res_o)
            if abs(float(o["f_temporal_hz"]) - f * v) <= tol_t and pd.isna(o["joint"]):
                same_t.add(vo)
            if abs(float(o["f_spatial_per_mm"]) - f) <= tol_s:
                same_s.add(vo)
        only_t = same_t - same_s
        need = min_other_feeds + (0 if pd.isna(p["joint"]) else 1)
        if len(only_t) >= need and len(only_t) >= len(same_s):
            mech.append("temporal")
        elif not pd.isna(p["joint"]):
            mech.append("gear")
        elif len(same_s) >= min_other_feeds:
            mech.append("spatial")
        else:
            mech.append("unclassified")
    out["mechanism"] = mech
    temporal = out["mechanism"] == "temporal"
    out.loc[temporal, "joint"] = pd.NA
    out.loc[temporal, ["stage", "order"]] = ""
    out.loc[temporal, "gear_f_spatial_per_mm"] = np.nan
    if "candidates" in out:  # a temporal peak is attributed to no gear
        out.loc[temporal, "candidates"] = ""
        out.loc[temporal, "merged"] = False
    return out
