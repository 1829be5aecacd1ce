"""The planned paths as the plan's artefacts: per-station angles and path columns in
``plan.csv``, each cut's path in the next manifest, slot starts on the slot floor, the path
over the rotation × station plane in the pose map, and the candidates' pose failures counted
by reason (``results/plan/pose_failures.csv``)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.plan.feasible import REASONS
from robomill.xrvars import attrs

MARGIN = "stability_margin_low"
STIFFNESS = "k_normal_low_N_m"


def manifest_path(p, station_mm) -> dict[str, Any]:
    """A cut's path for the next manifest's ``plan.cuts[id]``."""
    st = p.stations
    cut = st[st["move"] == "cut"] if len(st) else st
    out = {"station_mm": [float(s) for s in (cut["s_mm"] if len(cut) else station_mm)],
           "redundancy_path_deg": [float(a) for a in cut["rotation_deg"]] if len(cut) else [],
           "redundancy_path_score": p.summary.get("score", "none"),
           "configuration": p.summary.get("configuration", "")}
    if p.refused:
        out["refused"] = p.refused
    return out


def path_columns(table: pd.DataFrame, paths: Sequence) -> pd.DataFrame:
    """``plan.csv`` with each cut's path: ``configuration``, ``redundancy_path_deg`` (the
    rotation at each station, ``;``-separated), the best fixed rotation, the worst pessimistic
    margin and stiffness along the path and at that fixed rotation, their ratios
    (``path_gain_a_crit`` = (1 + margin) ratio, the critical depth's; ``path_gain_stiffness``),
    the smallest wrist angle, joint-limit clearance and σ_min along the path, and why a cut is
    refused (empty when it runs)."""
    t = table.copy()
    rows = []
    for p in paths:
        s = p.summary
        r = {"configuration": s.get("configuration", ""),
             "redundancy_path_deg": s.get("rotation_path_deg", ""),
             "fixed_rotation_deg": s.get("fixed_rotation_deg", np.nan)}
        for name, short in ((MARGIN, "margin"), (STIFFNESS, "k_normal_N_m")):
            pw, fw = s.get(f"path_worst_{name}", np.nan), s.get(f"fixed_worst_{name}", np.nan)
            r[f"path_worst_{short}"], r[f"fixed_worst_{short}"] = pw, fw
        r["path_gain_a_crit"] = _ratio(1 + r["path_worst_margin"], 1 + r["fixed_worst_margin"])
        r["path_gain_stiffness"] = _ratio(r["path_worst_k_normal_N_m"],
                                          r["fixed_worst_k_normal_N_m"])
        r.update({k: s.get(k, np.nan) for k in ("min_wrist_angle_deg", "min_limit_clearance_deg",
                                                "min_sigma")})
        r["path_refused"] = p.refused or ""
        rows.append(r)
    extra = pd.DataFrame(rows, index=t.index)
    for c in extra:
        t[c] = extra[c]
    return t


def _ratio(a: float, b: float) -> float:
    return float(a / b) if np.isfinite(a) and np.isfinite(b) and b > 0 else np.nan


def floor_starts(manifest: dict[str, Any], paths: Sequence) -> None:
    """Each planned cut's ``start_mm`` in the manifest set to its path's first station on the
    slot floor (base frame; refused cuts keep theirs)."""
    for entry, p in zip(manifest["cuts"], paths, strict=True):
        st = p.stations
        if p.refused or not len(st):
            continue
        first = st[st["move"] == "cut"].iloc[0]
        entry["start_mm"] = [round(float(first[f"{a}_base_mm"]), 6) for a in "xyz"]


def path_map(pmap: xr.Dataset, p, req, measured, cell) -> xr.Dataset:
    """The pose map with the best cut's stations × rotations: its scores, the feasible nodes
    and the chosen rotation at each station (``path_rotation_deg``; NaN when refused)."""
    if p is None or not p.nodes:
        return pmap
    nd = p.nodes
    out = pmap.copy()
    out = out.assign_coords(path_station_mm=("path_station_mm", np.asarray(nd["s_mm"], float),
                                             attrs("mm", "station along the best cut")))
    dims = ("path_station_mm", "rotation")
    if not np.array_equal(np.asarray(nd["rotation_deg"]), out["rotation"].values):
        return pmap
    for name, what in ((MARGIN, "pessimistic stability margin"),
                       (STIFFNESS, "pessimistic stiffness normal to the wall [N/m]")):
        if name in nd:
            out[f"path_{name}"] = (dims, np.asarray(nd[name], float),
                                   attrs("1" if name == MARGIN else "N/m",
                                         f"{what} at each station and rotation of the best cut"))
    out["path_feasible"] = (dims, np.asarray(nd["feasible"], bool),
                            attrs("1", "feasible pose (limits, wrist) at the station"))
    rot = (np.full(len(nd["s_mm"]), np.nan) if nd["path"] is None
           else np.asarray(nd["rotation_deg"], float)[nd["path"]])
    out["path_rotation_deg"] = (("path_station_mm",), rot,
                                attrs("deg", "chosen rotation about the tool axis at each "
                                      "station of the best cut"))
    out.attrs["path_cut"] = p.cut
    return out


def pose_failure_table(cand: xr.Dataset) -> pd.DataFrame:
    """``pose_failures.csv``: the candidate cuts (placement × rotation × direction) by pose
    status (:data:`robomill.plan.feasible.REASONS`), count and share."""
    if "pose_status" not in cand:
        return pd.DataFrame({"reason": list(REASONS), "count": 0, "share": np.nan})
    st = np.asarray(cand["pose_status"].values).ravel()
    n = max(st.size, 1)
    counts = [int(np.sum(st == i)) for i in range(len(REASONS))]
    return pd.DataFrame({"reason": list(REASONS), "count": counts,
                         "share": [c / n for c in counts]})


def path_summary(failures: pd.DataFrame, plan: pd.DataFrame, rotation_effect_pct: float,
                 slot_notes: Sequence[str] = ()) -> pd.DataFrame:
    """``results/plan/path_summary.csv`` (``key, value``), what chapter 7 says of the paths:
    the candidates by pose status (``candidates``, ``candidates_<reason>``), the planned cuts
    that run and that are refused, the chosen cuts moved or dropped so that no slot crosses
    another or leaves the block (``slots_moved``, ``slots_dropped``;
    :mod:`robomill.plan.slots`), the largest path gain over the best fixed rotation (critical
    depth and stiffness ratios, and the cut), the runnable cuts no rotation held fixed can run
    (``cuts_path_only``, ``path_only_cuts``: only the path runs them, no ratio exists; the
    gain case ``path_only`` when no cut has a ratio), the tie resolution ``tie_rel`` and the
    case of
    the chosen rotations: ``nominal_tie`` (every cut at 0° everywhere and no rotation changes a
    prediction by more than the tie resolution: the spindle sits on the flange axis),
    ``nominal_best`` (every cut at 0°, the rotation mattering elsewhere) or ``turned``."""
    from robomill.plan.path import TIE_REL

    rows: list[tuple[str, Any]] = [("candidates", int(failures["count"].sum()))]
    rows += [(f"candidates_{r}", int(c)) for r, c in zip(failures["reason"], failures["count"],
                                                         strict=True)]
    runs = plan["path_refused"].fillna("").astype(str) == "" if len(plan) else pd.Series([])
    rows += [("cuts_planned", int(len(plan))), ("cuts_runnable", int(runs.sum())),
             ("cuts_refused", int((~runs).sum()))]
    for col in ("path_gain_a_crit", "path_gain_stiffness"):
        v = plan[col].astype(float) if col in plan else pd.Series(dtype=float)
        ok = v[np.isfinite(v)]
        rows.append((f"{col}_max", float(ok.max()) if len(ok) else np.nan))
        rows.append((f"{col}_cut", str(plan.loc[ok.idxmax(), "cut"]) if len(ok) else ""))
    gains = [v for k, v in rows if k in ("path_gain_a_crit_max", "path_gain_stiffness_max")
             and np.isfinite(v)]
    fixed = (plan["fixed_rotation_deg"].astype(float) if "fixed_rotation_deg" in plan
             else pd.Series(np.nan, index=plan.index))
    only = plan.loc[runs.to_numpy(bool) & ~np.isfinite(fixed.to_numpy()), "cut"] if len(plan) \
        else pd.Series([], dtype=str)
    rows += [("cuts_path_only", int(len(only))),
             ("path_only_cuts", ";".join(str(c) for c in only))]
    rows.append(("path_gain_case", "path_only" if not gains and len(only) else
                 "" if not gains else "gain" if max(gains) > 1 + TIE_REL else "none"))
    angles = [float(a) for s in plan.get("redundancy_path_deg", pd.Series([], dtype=str))
              .fillna("").astype(str) for a in s.split(";") if a != ""]
    at_zero = bool(angles) and all(a == 0.0 for a in angles)
    effect = rotation_effect_pct / 100.0 if np.isfinite(rotation_effect_pct) else np.nan
    case = ("turned" if not at_zero else
            "nominal_tie" if np.isfinite(effect) and effect <= TIE_REL else "nominal_best")
    rows += [("slots_moved", sum("moved" in n for n in slot_notes)),
             ("slots_dropped", sum("dropped" in n for n in slot_notes))]
    rows += [("tie_rel", TIE_REL), ("rotation_effect_pct", rotation_effect_pct),
             ("rotation_case", case)]
    return pd.DataFrame(rows, columns=["key", "value"])


def summary_values(table: pd.DataFrame) -> dict[str, Any]:
    """``path_summary.csv`` as the fields of chapter 7's sentences (numbers as floats, the
    rest as text; empty text as None)."""
    out: dict[str, Any] = {}
    for k, v in zip(table["key"], table["value"], strict=True):
        try:
            out[str(k)] = float(v)
        except (TypeError, ValueError):
            out[str(k)] = None if v is None or str(v) in ("", "nan") else str(v)
    return out


def _index(mask: xr.DataArray, row) -> dict[str, int]:
    return {d: int(row[f"i_{d}"]) for d in mask.dims if d != "rotation"}


def rotations_meeting_constraints(mask: xr.DataArray, row) -> np.ndarray:
    """``(R,)``: the rotations at which a chosen cut (its placement, direction, speed, depth
    and feed) meets every constraint of the request (the feasible mask of the choice)."""
    return np.asarray(mask.isel(_index(mask, row)).transpose("rotation").values, bool)


def follow_paths(chosen: pd.DataFrame, ds: xr.Dataset, mask: xr.DataArray,
                 paths: Sequence) -> pd.DataFrame:
    """The chosen cuts with each row's rotation (and so its predictions, the manifest's
    ``redundancy_deg`` and the virtual cell's cut) moved to its path's rotation at the middle
    station; a refused cut keeps its own."""
    from robomill.plan.choose import feasible_table

    rows = []
    rot = ds["rotation"].values
    for (_, r), p in zip(chosen.iterrows(), paths, strict=True):
        st = p.stations
        if p.refused or not len(st):
            rows.append(r)
            continue
        cut = st[st["move"] == "cut"]
        mid = float(cut["rotation_deg"].iloc[len(cut) // 2])
        i_rot = int(np.flatnonzero(rot == mid)[0])
        if i_rot == int(r["i_rotation"]):
            rows.append(r)
            continue
        one = xr.zeros_like(mask)
        one[{**_index(mask, r), "rotation": i_rot}] = True
        new = feasible_table(ds, one & mask).iloc[0]
        new = new.reindex(r.index)
        new["rank"], new["cut"] = r["rank"], r["cut"]
        rows.append(new)
    return pd.DataFrame(rows).reset_index(drop=True)[chosen.columns]
