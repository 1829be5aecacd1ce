"""The plan's artefacts as data: the candidate dataset ready to write (single precision,
compressed), the chosen cuts as manifest cuts, the next experiment's manifest and the
configuration overlay that reruns the virtual cell on the planned cuts."""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.plan import NEXT_RUN_DIR
from robomill.plan.predict import Cell
from robomill.plan.request import PlanRequest
from robomill.xrvars import attrs

PREDICTION_COLUMNS = {
    "stability_margin": "1", "a_crit_mm": "mm", "deflection_normal_um": "um",
    "deflection_axial_um": "um", "waviness_um": "um", "force_N": "N",
}
"""Predictions with an interval (``<name>`` nominal, ``_low``/``_high`` ends) in plan.csv."""

SINGLE = ("feed_per_tooth_mm", "feed_mark_um", "mrr_mm3_s", "form_error_um",
          "form_error_high_um")
"""Predictions without an interval (exact given the cut, or a sum of bounds)."""


def _bounds(name: str) -> tuple[str, str]:
    stem, unit = name.rsplit("_", 1) if name.endswith(("_mm", "_um", "_N")) else (name, "")
    return ((f"{stem}_low_{unit}", f"{stem}_high_{unit}") if unit
            else (f"{name}_low", f"{name}_high"))


def compact(ds: xr.Dataset) -> xr.Dataset:
    """Float variables in single precision with gzip compression (the full candidate grid has
    ~10⁶ entries per variable)."""
    out = ds.copy()
    for name, v in out.data_vars.items():
        if v.dtype.kind == "f":
            out[name] = v.astype("float32")
            out[name].encoding = {"zlib": True, "complevel": 4}
    return out


def cut_entries(chosen: pd.DataFrame, req: PlanRequest) -> list[dict[str, Any]]:
    """The chosen cuts as manifest ``cuts`` entries (every design key; ``start_mm`` = the
    placement point − L/2 · feed direction; ``redundancy_deg`` the planned rotation about the
    tool axis, at which the virtual cell's simulators cut it)."""
    out = []
    for _, r in chosen.iterrows():
        a = np.deg2rad(float(r["direction_deg"]))
        u = np.array([np.cos(a), np.sin(a), 0.0])
        mid = np.array([r["placement_x_mm"], r["placement_y_mm"], r["placement_z_mm"]], float)
        start = mid - req.length_mm / 2 * u
        d = {"id": str(r["cut"]), "feed_mm_s": float(r["feed_mm_s"]),
             "depth_mm": float(r["depth_mm"])}
        if str(r["direction"]) in ("px", "py", "mx", "my"):
            d["direction"] = str(r["direction"])
        else:
            d["direction_deg"] = float(r["direction_deg"])
        d.update({"spindle_rpm": float(r["spindle_rpm"]), "flutes": int(req.flutes),
                  "tool_diameter_mm": float(req.tool_diameter_mm),
                  "radial_immersion": float(req.radial_immersion), "milling": req.milling,
                  "start_mm": [round(float(x), 6) for x in start],
                  "redundancy_deg": float(r["rotation_deg"])})
        out.append(d)
    return out


def predictions_of(row: pd.Series) -> dict[str, dict[str, float]]:
    """Each prediction of a plan.csv row as {value, low, high, unit} (NaN where missing)."""
    out = {}
    for name, unit in PREDICTION_COLUMNS.items():
        lo, hi = _bounds(name)
        out[name] = {"value": float(row.get(name, np.nan)), "low": float(row.get(lo, np.nan)),
                     "high": float(row.get(hi, np.nan)), "unit": unit}
    for name in SINGLE:
        out[name] = {"value": float(row.get(name, np.nan))}
    return out


def plan_table(chosen: pd.DataFrame) -> pd.DataFrame:
    """``plan.csv``: the chosen cuts ranked by removal rate, with the pose and every
    prediction; index columns of the candidate grid dropped."""
    keep = [c for c in chosen.columns if not c.startswith("i_")]
    return chosen[keep]


def next_manifest(chosen: pd.DataFrame, req: PlanRequest, experiment: dict, missing: str,
                  q_deg: np.ndarray, paths: list[dict[str, Any]]) -> dict[str, Any]:
    """``results/plan/next/manifest.yaml``: the next experiment as a manifest to fill (files
    empty), its cuts with every design key, and under ``plan`` each cut's pose, redundancy angle
    (and its path along the cut) and predictions."""
    cuts = cut_entries(chosen, req)
    header = {"spindle_rpm": float(chosen["spindle_rpm"].iloc[0]) if len(chosen)
              else float(experiment.get("spindle_rpm", 0.0)),
              "flutes": int(req.flutes), "tool_diameter_mm": float(req.tool_diameter_mm),
              "cut_length_mm": float(req.length_mm)}
    if experiment.get("modal_band_hz") is not None:
        header["modal_band_hz"] = [float(b) for b in experiment["modal_band_hz"]]
    plan: dict[str, Any] = {"request": req.path, "missing_predictions":
                            [m for m in missing.split("; ") if m], "cuts": {}}
    for (_, r), q, path in zip(chosen.iterrows(), q_deg, paths, strict=True):
        plan["cuts"][str(r["cut"])] = {
            "rank": int(r["rank"]),
            "placement_mm": [float(r["placement_x_mm"]), float(r["placement_y_mm"]),
                             float(r["placement_z_mm"])],
            "redundancy_deg": float(r["rotation_deg"]),
            "q_deg": [round(float(x), 6) for x in q],
            **path,
            "predictions": predictions_of(r),
        }
    return {"experiment": header, "cuts": cuts, "files": [], "plan": plan}


def next_config(manifest: dict[str, Any], workdir: str = NEXT_RUN_DIR,
                impact_tcp_mm: Any = None) -> dict[str, Any]:
    """``results/plan/next/config.yaml``: a configuration overlay (``--configfile``) that has the
    virtual cell cut the planned cuts (``experiment.cuts``; robomill.io.synthetic_layout) in their
    own run's folder ``workdir`` (:data:`NEXT_RUN_DIR`; config ``workdir``), not over the study,
    with one tracker run per planned cut (``synth.tracker.per_cut``: each cut has its own pose
    and its own predicted waviness, which one run per direction and feed would check for the
    last cut only), each run loaded (recorded while the tool cuts) and in the air
    (``synth.tracker.air_pass``): the deflection is the loaded path minus the air path. The
    tracker's ``directions`` are the planned cuts' and its ``feeds_mm_s`` all, so that no
    selection of the study's runs leaves a planned cut untracked. Each planned cut is also
    recorded by a spindle accelerometer with its air pass (``synth.recordings``: vibration on,
    its ``air_pass`` default), as a lab checks a new cut for chatter: a line the air pass shows
    unchanged is forced vibration, not chatter (``robomill.chatter.recordings``).

    ``impact_tcp_mm``: where the study's impact test was made (its files' ``tcp_mm``); the
    next run's cell stands where it stood (``synth.process.reference_point_mm``), so that its
    structure is the study's and not one planted where the next cuts lie (the cell's default
    for that key is the centre of the run's own cuts)."""
    dirs = sorted({str(c["direction"]) for c in manifest["cuts"] if c.get("direction")})
    synth: dict[str, Any] = {
        # every planned cut tracked, whatever directions and feeds the study's runs took
        "tracker": {"per_cut": True, "air_pass": True, "directions": dirs, "feeds_mm_s": None},
        "recordings": {"vibration": True}}
    if impact_tcp_mm is not None:
        synth["process"] = {"reference_point_mm": [float(v) for v in
                                                   np.asarray(impact_tcp_mm, float).reshape(3)]}
    return {"workdir": workdir,
            "experiment": {**manifest["experiment"], "cuts": manifest["cuts"]},
            "synth": synth}


def cell_of(cell_file, req: PlanRequest, impact_tcp_mm: np.ndarray | None) -> Cell:
    """The planner's view of the cell: robot, tool orientation, IK seed, and the reference
    point of the modes: where the impact test was made (``impact_tcp_mm``, the point its
    files state, carried by the modal stage as ``frf_synth.nc`` ``impact_tcp_mm``), else
    ``reference_point_mm`` of the request (the documented fallback for impact files without
    it), else the middle of the placement region (where no impact test's modes are moved);
    the robot's documented masses (``mass_model``) as its rigid-body model."""
    if impact_tcp_mm is not None:
        ref = np.asarray(impact_tcp_mm, float).reshape(3)
    elif req.reference_point_mm is not None:
        ref = req.reference_point_mm
    else:
        ref = req.placements_mm.mean(0)
    from robomill.inertia import documented_rigid_body_model
    from robomill.straightness import gear_orders

    orders = {(j, st, o): m for j, st, o, m in gear_orders(cell_file.transmissions)}
    return Cell(cell_file.robot, np.asarray(cell_file.tool_rotation, float),
                cell_file.q_home_rad, np.asarray(ref, float), orders,
                getattr(cell_file, "joint_limits_deg", None),
                getattr(cell_file, "joint_speed_limits_deg_s", None),
                documented_rigid_body_model(cell_file.robot,
                                            getattr(cell_file, "mass_model", None)))


def p_stable_map(cand: xr.Dataset, best: pd.Series, n_depths: int = 80) -> xr.Dataset:
    """Chapter 7's map of the probability of a stable cut over spindle speed × depth at the
    binding pose (the placement, rotation and direction of the plan's best cut,
    ``best``), before the study's verdicts (every member of the stability model weighted
    equally) and after (the verdicts' weights; :mod:`robomill.plan.stability`):
    ``p_stable_prior`` and ``p_stable_post`` over ``spindle_rpm`` × ``map_depth_mm`` (log-spaced
    from a tenth of the smallest to ten times the largest requested depth). Empty without the
    members."""
    from robomill.plan.stability import p_stable

    if "a_crit_members_mm" not in cand or "member_weight" not in cand:
        return xr.Dataset()
    at = {"placement": int(best["i_placement"]), "rotation": int(best["i_rotation"]),
          "direction": int(best["i_direction"])}
    mem = cand["a_crit_members_mm"].isel(at).transpose("member", "spindle_rpm").values
    d = cand["depth_mm"].values
    depths = np.geomspace(0.1 * float(d.min()), 10 * float(d.max()), n_depths)
    w = cand["member_weight"].values.astype(float)
    flat = np.full(len(w), 1.0 / len(w))
    dims = ("spindle_rpm", "map_depth_mm")
    out = xr.Dataset(coords={"spindle_rpm": cand["spindle_rpm"],
                             "map_depth_mm": ("map_depth_mm", depths,
                                              attrs("mm", "axial depth of the map"))})
    for name, weights, what in (("p_stable_prior", flat, "before the study's verdicts"),
                                ("p_stable_post", w / w.sum(), "after the study's verdicts")):
        out[name] = (dims, p_stable(mem[..., None], weights, depths[None, :]),
                     attrs("1", f"probability of a stable cut at the binding pose, {what}"))
    out.attrs.update({f"binding_{k}": v for k, v in at.items()})
    return out


def pose_map(cand: xr.Dataset, best: pd.Series) -> xr.Dataset:
    """Chapter 7's pose map over placement × rotation × direction: the best pessimistic
    critical depth over the speed range, the joint-model stiffness normal to the wall and along
    the tool, and the upper normal deflection and pessimistic margin at the plan's best cut's
    speed, depth and feed."""
    at = {"spindle_rpm": float(best["spindle_rpm"]), "depth_mm": float(best["depth_mm"]),
          "feed_mm_s": float(best["feed_mm_s"])}
    out = xr.Dataset(coords={k: cand[k] for k in ("placement", "placement_x_mm",
                                                  "placement_y_mm", "placement_z_mm",
                                                  "rotation", "direction", "direction_deg")})
    out["a_crit_best_low_mm"] = cand["a_crit_low_mm"].max("spindle_rpm").where(
        cand["reachable"]).assign_attrs(attrs("mm", "largest pessimistic critical depth over "
                                              "the speed range"))
    for name in ("k_normal_N_m", "k_axial_N_m", "reachable"):
        out[name] = cand[name]
    out["deflection_normal_high_um"] = cand["deflection_normal_high_um"].sel(at).drop_vars(
        list(at)).assign_attrs(attrs("um", "upper deflection normal to the wall at the best "
                                     "cut's speed, depth and feed"))
    out["stability_margin_low"] = cand["stability_margin_low"].sel(at).drop_vars(
        list(at)).assign_attrs(attrs("1", "pessimistic stability margin at the best cut's "
                                     "speed, depth and feed"))
    out.attrs.update({f"best_{k}": v for k, v in at.items()})
    return out
