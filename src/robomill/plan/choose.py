"""The choice among the candidates: the constraints, the largest removal rate inside them, the
Pareto front of removal rate against predicted form error, a redundancy angle that varies
smoothly along a path, and — when nothing is feasible — one line naming the constraint that
binds.

Constraints are checked on the pessimistic end of each prediction's interval (the lower
stability margin, the upper deflection, waviness and force; the waviness' upper end of its
identification interval, the wall's waviness, not the tracker-noise-widened interval its
reading is checked against).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
import xarray as xr

from robomill.plan.path import prefer_nominal
from robomill.plan.request import PlanRequest

CONSTRAINT_VARS = {
    "min_stability_margin": ("stability_margin_low", "min", "stability margin"),
    "min_p_stable": ("p_stable", "min", "probability of a stable cut"),
    "min_feed_per_tooth_mm": ("feed_per_tooth_mm", "min", "feed per tooth [mm]"),
    "max_deflection_normal_um": ("deflection_normal_high_um", "max",
                                 "deflection normal to the wall [um]"),
    "max_deflection_axial_um": ("deflection_axial_high_um", "max",
                                "deflection along the tool axis [um]"),
    "max_waviness_um": ("waviness_ident_high_um", "max", "waviness [um]"),
    "max_force_N": ("force_high_N", "max", "mean cutting force [N]"),
}
"""Constraint key → (variable checked, bound kind, what it is)."""

NEEDS = {"min_stability_margin": "stability_margin", "min_p_stable": "stability_margin",
         "max_deflection_normal_um": "deflection",
         "max_deflection_axial_um": "deflection", "max_waviness_um": "waviness",
         "max_force_N": "force"}
"""The prediction each constraint needs (:data:`robomill.plan.measured.PREDICTIONS`)."""


class PlanInfeasible(ValueError):
    """No plan: one line saying which constraint binds (or which measurement is missing)."""


def check_needs(req: PlanRequest, missing: dict[str, str]) -> None:
    """Refuse a request whose constraints need a prediction that cannot be made.

    Raises
    ------
    PlanInfeasible
        ``constraints.max_waviness_um needs the waviness prediction: no tracker runs …``.
    """
    for key, pred in NEEDS.items():
        if req.constrained(key) and pred in missing:
            raise PlanInfeasible(f"{req.path}: constraints.{key} needs the {pred} prediction: "
                                 f"{missing[pred]} (measure it, or remove the constraint to "
                                 "plan without it)")


def constraint_masks(ds: xr.Dataset, req: PlanRequest) -> dict[str, xr.DataArray]:
    """Per constrained key, where it holds (broadcast over the candidates' dims)."""
    out = {}
    for key, (name, kind, _) in CONSTRAINT_VARS.items():
        lim = req.constraints.get(key)
        if lim is None or name not in ds:
            continue
        v = ds[name]
        out[key] = (v >= lim) if kind == "min" else (v <= lim)
    return out


def feasible(ds: xr.Dataset, req: PlanRequest) -> xr.DataArray:
    """Reachable candidates meeting every constraint (full candidate dims)."""
    m = ds["reachable"] & xr.ones_like(ds["mrr_mm3_s"], dtype=bool)
    m = m & xr.ones_like(ds["feed_mark_um"], dtype=bool)
    for mask in constraint_masks(ds, req).values():
        m = m & mask
    if not req.extrapolation.get("allow", True) and "extrapolation" in ds:
        m = m & ~ds["extrapolation"]
    return m.transpose("placement", "rotation", "direction", "spindle_rpm", "depth_mm",
                       "feed_mm_s")


def binding_constraint(ds: xr.Dataset, req: PlanRequest, robot_name: str = "the robot") -> str:
    """One line saying why no candidate is feasible: no reachable placement, no stable speed
    in range, or the constraint whose removal alone would leave candidates (with the best value
    reached beside its limit)."""
    if not bool(ds["reachable"].any()):
        n = ds.sizes
        return (f"no reachable placement: none of the {n['placement']} placements × "
                f"{n['rotation']} rotations × {n['direction']} directions of {req.path} is "
                f"reachable by {robot_name} (inverse kinematics at the cut's start, middle "
                "and end)")
    masks = constraint_masks(ds, req)
    base = ds["reachable"] & xr.ones_like(ds["mrr_mm3_s"], dtype=bool)
    base = base & xr.ones_like(ds["feed_mark_um"], dtype=bool)
    if not req.extrapolation.get("allow", True) and "extrapolation" in ds:
        inside = base & ~ds["extrapolation"]
        if not bool(inside.any()):
            from robomill.plan.extrapolation import reason_text
            codes = np.unique(ds["extrapolation_code"].where(base.any(
                [d for d in base.dims if d not in ds["extrapolation_code"].dims]), 0).values)
            why = reason_text(int(np.bitwise_or.reduce(codes.astype(int))))
            return (f"every reachable candidate of {req.path} is extrapolated ({why} outside "
                    "what the study measured) and extrapolation.allow is false: measure "
                    "there first, or allow extrapolation with its widened intervals")
        base = inside
    for key in masks:
        others = base
        for k2, m2 in masks.items():
            if k2 != key:
                others = others & m2
        if not bool(others.any()):
            continue
        name, kind, what = CONSTRAINT_VARS[key]
        v = ds[name].where(others)
        best = float(v.max() if kind == "min" else v.min())
        lim = req.constraints[key]
        if key == "min_stability_margin":
            a = ds["a_crit_low_mm"].where(ds["reachable"])
            return (f"no stable speed in range: the largest pessimistic critical depth over "
                    f"spindle_rpm {float(ds.spindle_rpm.min()):g}-{float(ds.spindle_rpm.max()):g}"
                    f" is {float(a.max()):.4g} mm, so the best stability margin {best:.3g} at "
                    f"the smallest depth_mm {float(ds.depth_mm.min()):g} is below "
                    f"constraints.min_stability_margin {lim:g}")
        return (f"constraints.{key} binds: the best {what} among the candidates meeting every "
                f"other constraint is {best:.4g}, the limit is {lim:g}")
    keys = ", ".join(f"constraints.{k}" for k in masks)
    return f"no candidate meets {keys} together (each one alone leaves none either)"


def shortfall_line(ds: xr.Dataset, req: PlanRequest, mask: xr.DataArray, n_chosen: int,
                   n_front: int) -> str:
    """One line when fewer than ``n_cuts`` cuts are planned: how many removal rates the
    Pareto front offers, and the constraint that binds the next larger removal rate (the one
    refusing the most reachable candidates of a larger removal rate than the plan's best);
    "" when ``n_cuts`` are planned."""
    if n_chosen >= req.n_cuts:
        return ""
    best = float(ds["mrr_mm3_s"].where(mask.any(("placement", "rotation", "direction",
                                                 "spindle_rpm"))).max())
    larger = ds["reachable"] & (ds["mrr_mm3_s"] > best)
    counts = {}
    for key, m in constraint_masks(ds, req).items():
        counts[key] = int((larger & ~m).sum())
    why = ("no larger removal rate is requested" if not bool(larger.any()) or not counts
           else None)
    if why is None:
        key = max(counts, key=counts.get)
        why = (f"constraints.{key} binds every larger removal rate" if counts[key] ==
               int(larger.sum()) else f"constraints.{key} refuses most candidates of a larger "
               f"removal rate ({counts[key]} of {int(larger.sum())})")
    where = ("the Pareto front of removal rate against form error holds "
             f"{n_front} removal rate{'s' if n_front != 1 else ''} within the constraints"
             if n_front < req.n_cuts else "the others' slots overlap the study's or each other")
    return f"{n_chosen} of n_cuts {req.n_cuts} planned: {where}; {why} (best {best:g} mm3/s)"


def pareto_front(mrr: np.ndarray, error: np.ndarray) -> np.ndarray:
    """Indices of the non-dominated points (largest removal rate, smallest form error), sorted
    by decreasing removal rate: a point stays when no other has at least its rate with a
    smaller error."""
    mrr, error = np.asarray(mrr, float), np.asarray(error, float)
    order = np.lexsort((error, -mrr))
    keep, best = [], np.inf
    for i in order:
        if error[i] < best:
            keep.append(i)
            best = error[i]
    return np.asarray(keep, int)


def feasible_table(ds: xr.Dataset, mask: xr.DataArray) -> pd.DataFrame:
    """The feasible candidates as rows with every prediction (indices and coordinates)."""
    dims = mask.dims
    idx = np.nonzero(mask.values)
    rows = {f"i_{d}": i for d, i in zip(dims, idx, strict=True)}
    sel = {d: xr.DataArray(i, dims="c") for d, i in zip(dims, idx, strict=True)}
    out = pd.DataFrame(rows)
    for d in dims:
        out[d if d != "rotation" else "rotation_deg"] = ds[d].values[out[f"i_{d}"]]
    for extra in ("placement_x_mm", "placement_y_mm", "placement_z_mm", "direction_deg"):
        out[extra] = ds[extra].values[out[f"i_{ds[extra].dims[0]}"]]
    for name, v in ds.data_vars.items():
        if set(v.dims) <= set(dims) and name not in ("reachable",):
            out[name] = v.isel({d: sel[d] for d in v.dims}).values
    return out


def choose(ds: xr.Dataset, req: PlanRequest, robot_name: str = "the robot",
           occupied: Sequence[np.ndarray] = ()) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The chosen cuts and the Pareto front.

    For each removal rate (depth × feed) the feasible candidate of smallest upper form error
    (ties: largest pessimistic margin, then the smallest rotation about the tool axis)
    represents it; the Pareto front of those against the
    form error is the menu, and the chosen cuts are its ``n_cuts`` highest removal rates,
    ranked by removal rate (rank 1 = the plan's best). Each cut goes on its own stretch of
    material: a removal rate takes its best candidate whose slot (width the tool's diameter)
    overlaps neither a cut chosen before it nor the ``occupied`` slots (the study's cuts,
    segments ``(2, 3)`` [mm]; :mod:`robomill.plan.material`); a removal rate with no such
    candidate is left out.

    Raises
    ------
    PlanInfeasible
        No feasible candidate (:func:`binding_constraint`).
    """
    mask = feasible(ds, req)
    if not bool(mask.any()):
        raise PlanInfeasible(binding_constraint(ds, req, robot_name))
    t = prefer_nominal(feasible_table(ds, mask))  # rotation ties: the nominal orientation
    margin = t["stability_margin_low"].fillna(np.inf)
    t = t.assign(_m=-margin, _r=t["rotation_deg"].abs()).sort_values(
        ["mrr_mm3_s", "form_error_high_um", "_m", "_r"], ascending=[False, True, True, True],
        kind="stable")
    best = t.groupby(["depth_mm", "feed_mm_s"], sort=False).head(1).drop(columns=["_m", "_r"])
    front = best.iloc[pareto_front(best["mrr_mm3_s"].to_numpy(),
                                   best["form_error_high_um"].to_numpy())].reset_index(drop=True)
    chosen = apart(t, front, req, occupied)
    if chosen.empty:
        raise PlanInfeasible(f"{req.path}: every feasible candidate's slot overlaps a cut of the "
                             "study on the part (no stretch of material left at the requested "
                             "placements: move the placement box)")
    if "extrapolation_code" in front:
        from robomill.plan.extrapolation import reason_text
        for tab in (front, chosen):
            tab["extrapolation_reason"] = [reason_text(c) for c in tab["extrapolation_code"]]
    ds.attrs["shortfall"] = shortfall_line(ds, req, mask, len(chosen), len(front))
    chosen.insert(0, "rank", np.arange(1, len(chosen) + 1))
    chosen.insert(0, "cut", [f"plan_{i:02d}" for i in chosen["rank"]])
    return chosen.reset_index(drop=True), front


def apart(table: pd.DataFrame, front: pd.DataFrame, req: PlanRequest,
          occupied: Sequence[np.ndarray] = ()) -> pd.DataFrame:
    """The front's removal rates in order, each at its best candidate (``table``'s order)
    whose slot overlaps no slot taken before (:func:`robomill.plan.material.overlaps`), up to
    ``n_cuts``."""
    from robomill.plan.material import overlaps, slot_segment

    taken = [np.asarray(o, float) for o in occupied]
    rows = []
    for _, fr in front.iterrows():
        same = table[(table["depth_mm"] == fr["depth_mm"])
                     & (table["feed_mm_s"] == fr["feed_mm_s"])]
        for _, r in same.drop_duplicates(["placement", "direction"]).iterrows():
            seg = slot_segment([r["placement_x_mm"], r["placement_y_mm"], r["placement_z_mm"]],
                               r["direction_deg"], req.length_mm)
            if not overlaps(seg, taken, req.tool_diameter_mm):
                taken.append(seg)
                rows.append(r)
                break
        if len(rows) == req.n_cuts:
            break
    out = pd.DataFrame(rows).reset_index(drop=True) if rows else front.head(0).copy()
    return out[list(front.columns)].copy()

