"""Planned slots on the part: inside the block's outline and crossing neither each other nor the
study's own slots.

A slot is the segment its tool centre runs along the floor, widened by the tool radius. Two
slots cross (or touch) when the distance between their centre segments in the part's top
plane is below the sum of their radii. The plan's chosen cuts are taken in rank order; a cut
whose slot would cross an earlier one (the study's, or a planned cut of better rank) or leave
the block is replaced by the next candidate of the same depth and feed in the choice's own
order (smallest upper form error, largest pessimistic margin, nominal rotation) whose slot is
free, and dropped when none is.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
import xarray as xr

from robomill.plan.workobject import WorkObject


def segment_distance_mm(a0, a1, b0, b1) -> float:
    """Smallest distance between the 2-D segments a0–a1 and b0–b1 [mm] (0 when they cross)."""
    a0, a1, b0, b1 = (np.asarray(v, float)[:2] for v in (a0, a1, b0, b1))

    def cross(o, p, q):
        return (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0])

    d1, d2 = cross(b0, b1, a0), cross(b0, b1, a1)
    d3, d4 = cross(a0, a1, b0), cross(a0, a1, b1)
    if d1 * d2 < 0 and d3 * d4 < 0:
        return 0.0

    def point_seg(p, s0, s1):
        v = s1 - s0
        t = 0.0 if not v.any() else float(np.clip(np.dot(p - s0, v) / np.dot(v, v), 0, 1))
        return float(np.linalg.norm(p - (s0 + t * v)))

    return min(point_seg(a0, b0, b1), point_seg(a1, b0, b1), point_seg(b0, a0, a1),
               point_seg(b1, a0, a1))


def slot_of(row, length_mm: float, wobj: WorkObject) -> tuple[np.ndarray, np.ndarray]:
    """Start and end of a candidate's slot on the floor in the part frame [mm]."""
    a = np.deg2rad(float(row["direction_deg"]))
    u = np.array([np.cos(a), np.sin(a), 0.0])
    mid = np.array([row["placement_x_mm"], row["placement_y_mm"], row["placement_z_mm"]], float)
    mid = mid + (wobj.top_z_offset_mm(mid) - float(row["depth_mm"])) * wobj.z_axis
    p = wobj.points_in_part(np.stack([mid - length_mm / 2 * u, mid + length_mm / 2 * u]))
    return p[0], p[1]


def free(start, end, radius_mm: float, taken: Sequence, wobj: WorkObject) -> bool:
    """Whether a slot lies inside the block (its ends and its full width) and clear of every
    ``(start, end, radius)`` in ``taken`` (part frame)."""
    if wobj.block_min_mm is not None:
        lo, hi = wobj.block_min_mm, wobj.block_max_mm
        for p in (start, end):
            if np.any(p[:2] - radius_mm < lo[:2] - 1e-9) or np.any(p[:2] + radius_mm > hi[:2]
                                                                   + 1e-9):
                return False
            if p[2] < lo[2]:
                return False
    return all(segment_distance_mm(start, end, s, e) >= radius_mm + r - 1e-9
               for s, e, r in taken)


def study_slots(cuts, experiment, wobj: WorkObject) -> list[tuple]:
    """The study's own slots ``(start, end, radius)`` in the part frame."""
    from robomill.experiment import cut_endpoints_mm

    out = []
    if not cuts or experiment.get("cut_length_mm") is None:
        return out
    for c in cuts:
        a, b = cut_endpoints_mm(c, experiment)
        d = getattr(c, "tool_diameter_mm", None) or experiment.get("tool_diameter_mm") or 0.0
        pa, pb = wobj.points_in_part(np.stack([a, b]))
        out.append((pa, pb, float(d) / 2))
    return out


def separate_slots(chosen: pd.DataFrame, ds: xr.Dataset, req, taken: list[tuple],
                   wobj: WorkObject) -> tuple[pd.DataFrame, list[str]]:
    """The chosen cuts with every slot free (module docstring), and one line per cut moved or
    dropped."""
    from robomill.plan.choose import feasible, feasible_table
    from robomill.plan.path import prefer_nominal

    radius = req.tool_diameter_mm / 2
    taken = list(taken)
    out, notes = [], []
    table = None
    for _, r in chosen.iterrows():
        s, e = slot_of(r, req.length_mm, wobj)
        if free(s, e, radius, taken, wobj):
            out.append(r)
            taken.append((s, e, radius))
            continue
        if table is None:
            mask = feasible(ds, req)
            table = prefer_nominal(feasible_table(ds, mask))
            m = table["stability_margin_low"].fillna(np.inf)
            table = table.assign(_m=-m, _r=table["rotation_deg"].abs()).sort_values(
                ["form_error_high_um", "_m", "_r"], kind="stable")
        same = table[(table["depth_mm"] == r["depth_mm"]) & (table["feed_mm_s"] == r["feed_mm_s"])]
        pick = None
        for _, alt in same.iterrows():
            s2, e2 = slot_of(alt, req.length_mm, wobj)
            if free(s2, e2, radius, taken, wobj):
                pick = alt.drop(labels=["_m", "_r"])
                taken.append((s2, e2, radius))
                break
        if pick is None:
            notes.append(f"{r['cut']}: dropped, no free place on the block for a slot of depth "
                         f"{r['depth_mm']:g} mm at feed {r['feed_mm_s']:g} mm/s")
            continue
        pick["rank"], pick["cut"] = r["rank"], r["cut"]
        notes.append(f"{r['cut']}: moved to placement {int(pick['placement'])} (its slot "
                     "crossed another slot or left the block)")
        out.append(pick)
    res = pd.DataFrame(out).reset_index(drop=True)
    if len(res):
        res = res[chosen.columns]
        res["rank"] = np.arange(1, len(res) + 1)
        res["cut"] = [f"plan_{i:02d}" for i in res["rank"]]
    return res, notes
