"""The plan beside the study: the study's own cuts predicted with the same models and judged by
the same constraints, and the ratio of the plan's best removal rate to theirs (the number
Chapter 7 states)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.experiment import Cut
from robomill.plan.candidate import study_candidate
from robomill.plan.choose import feasible
from robomill.plan.conditioning import study_evidence
from robomill.plan.measured import Measured
from robomill.plan.poses import cut_frames
from robomill.plan.predict import (
    Cell,
    apply_extrapolation,
    critical_depth_m,
    predict_grid,
    solve_request,
)
from robomill.plan.request import PlanRequest
from robomill.plan.stability import VerdictEvidence

if TYPE_CHECKING:  # robomill.study reads the manifest: typing only
    from robomill.study import StudyCut

PREDICTED = ["stability_margin", "stability_margin_low", "stability_margin_high",
             "deflection_normal_um", "deflection_normal_low_um", "deflection_normal_high_um",
             "deflection_axial_um", "deflection_axial_low_um", "deflection_axial_high_um",
             "waviness_um", "waviness_low_um", "waviness_high_um", "force_N", "force_low_N",
             "force_high_N", "form_error_high_um", "waviness_ident_low_um",
             "waviness_ident_high_um", "waviness_noise_um"]
STUDY_COLUMNS = ["cut", "spindle_rpm", "depth_mm", "feed_mm_s", "mrr_mm3_s", "reachable",
                 *PREDICTED, "a_crit_mm", "a_crit_low_mm", "a_crit_high_mm", "p_stable",
                 "feed_per_tooth_mm", "extrapolation", "extrapolation_reason",
                 "limit_clearance_deg", "wrist_angle_deg", "pose_note", "verdict",
                 "feasible"]


def stability_evidence(cuts: Sequence[StudyCut | Cut], experiment: Mapping[str, Any],
                       req: PlanRequest, measured: Measured, cell: Cell, stability: pd.Series,
                       source: str = "results/chatter/verdicts.csv"
                       ) -> VerdictEvidence | None:
    """The study's chatter verdicts as the weights of the stability model's members
    (:mod:`robomill.plan.conditioning`): each cut with a verdict (``stability``: 1 stable,
    0 chatter, NaN undetermined per cut, :func:`robomill.plan.evidence.verdict_stability`)
    and every member's critical depth at the cut's own pose, direction and speed (the cut
    as a planning candidate, :func:`robomill.plan.candidate.study_candidate`); None where the
    modes or the coefficients were not measured."""
    rows, cols, n_members = [], [], None
    for cut in cuts:
        if cut.id not in stability.index:
            continue
        v = float(stability[cut.id])
        c = study_candidate(cut, experiment)
        one = c.grid(req)  # the cut was cut: its pose counts whatever the request's margins
        row = {"cut": c.id, "spindle_rpm": c.spindle_rpm, "depth_mm": c.depth_mm,
               "verdict": "undetermined" if v != v else "stable" if v >= 0.5 else "chatter"}
        poses = solve_request(one, cell)
        a = None
        if bool(poses.reachable.ravel()[0]):
            n = poses.q_mid_rad.shape[-1]
            a = critical_depth_m(replace(measured, stability_evidence=None), cell, one,
                                 poses.q_mid_rad.reshape(-1, n)[:1],
                                 cut_frames(one.direction_deg)[:1], one.spindle_rpm,
                                 members=True)
        else:
            row["why"] = "unreachable: no prediction at the cut's pose"
        if a is not None:
            n_members = a["members"].shape[0]
        rows.append(row)
        cols.append(None if a is None else a["members"][:, 0, 0])
    if n_members is None:
        return None
    mem = np.stack([np.full(n_members, np.nan) if c is None else c for c in cols], 1)
    return study_evidence(rows, mem, float(measured.level), req.stability.verdict_error,
                          source)


def predict_study_cut(cut: StudyCut | Cut, experiment: Mapping[str, Any], req: PlanRequest,
                      measured: Measured, cell: Cell, reach=None) -> dict[str, Any]:
    """One cut at its own place, direction, speed, depth, feed, tool and redundancy angle
    (``redundancy_deg``, 0: the cell's tool orientation), as a planning candidate
    (:func:`robomill.plan.candidate.study_candidate`: the process the ingestion rule
    resolved, never resolved again), with the plan's predictions (with
    ``reach``, flagged and widened as the plan's candidates,
    :func:`robomill.plan.predict.apply_extrapolation`) and whether it meets the request's
    constraints (``feasible``).

    A cut is predicted at its pose whatever the request's pose margins
    (``joint_limit_margin_deg``, ``min_wrist_angle_deg``): its joint-limit clearance and
    wrist angle are reported, and ``pose_note`` says which margin it would break (then
    ``feasible`` is false for that reason, never silently)."""
    from robomill.plan.extrapolation import reason_text

    c = study_candidate(cut, experiment)
    one = c.grid(req)
    ds = predict_grid(one, measured, cell)
    if reach is not None:
        ds = apply_extrapolation(ds, one, measured, cell, reach)
    clear = float(ds["limit_clearance_deg"].values.ravel()[0])
    wrist = float(ds["wrist_angle_deg"].values.ravel()[0])
    notes = []
    if clear < req.joint_limit_margin_deg:
        notes.append(f"joint-limit clearance {clear:.3g} deg below the request's "
                     f"joint_limit_margin_deg {req.joint_limit_margin_deg:g}")
    if wrist < req.min_wrist_angle_deg:
        notes.append(f"wrist angle {wrist:.3g} deg below the request's "
                     f"min_wrist_angle_deg {req.min_wrist_angle_deg:g}")
    row = {"cut": c.id, "spindle_rpm": c.spindle_rpm, "depth_mm": c.depth_mm,
           "feed_mm_s": c.feed_mm_s,
           "mrr_mm3_s": float(ds["mrr_mm3_s"].values.ravel()[0]),
           "reachable": bool(ds["reachable"].values.ravel()[0])}
    for name in (*PREDICTED, "a_crit_mm", "a_crit_low_mm", "a_crit_high_mm", "p_stable",
                 "feed_per_tooth_mm"):
        row[name] = float(ds[name].values.ravel()[0]) if name in ds else np.nan
    code = int(ds["extrapolation_code"].values.ravel()[0]) if "extrapolation_code" in ds \
        else 0
    row.update({"extrapolation": bool(code), "extrapolation_reason": reason_text(code),
                "limit_clearance_deg": clear, "wrist_angle_deg": wrist,
                "pose_note": "; ".join(notes),
                "feasible": bool(feasible(ds, req).values.ravel()[0]) and not notes})
    return row


def study_cuts_table(cuts: Sequence[StudyCut | Cut], experiment: Mapping[str, Any],
                     req: PlanRequest, measured: Measured, cell: Cell, reach=None,
                     stability: pd.Series | None = None) -> pd.DataFrame:
    """Each of the study's cuts predicted as the plan's candidates
    (:func:`predict_study_cut`: the study's cuts were cut, so each is predicted at its pose
    whatever the request's pose margins, which are reported) and ``verdict``: the study's own
    verdict of the cut (``stability``: 1 stable, 0 chatter)."""
    rows = []
    for cut in cuts:
        row = predict_study_cut(cut, experiment, req, measured, cell, reach)
        v = np.nan if stability is None else float(stability.get(cut.id, np.nan))
        row["verdict"] = "" if v != v else "stable" if v >= 0.5 else "chatter"
        rows.append(row)
    return pd.DataFrame(rows, columns=STUDY_COLUMNS)


def rotation_effect_pct(pose_map: xr.Dataset) -> float:
    """The most a rotation about the tool axis changes a pose prediction, in %: over every
    placement and direction, (max − min)/max over the rotations of the stiffness normal to the
    wall and along the tool and of the largest pessimistic critical depth (unreachable poses
    left out). NaN (not computed) when the pose map has fewer than two rotations (the request
    allowed one redundancy angle: nothing to compare) or no reachable pose. Near zero when the
    tool point lies on the last joint's axis: the rotation then only turns that joint, and the
    arm's pose is unchanged."""
    if pose_map.sizes.get("rotation", 0) < 2:
        return np.nan
    spreads = []
    for name in ("k_normal_N_m", "k_axial_N_m", "a_crit_best_low_mm"):
        v = pose_map[name].where(pose_map["reachable"])
        hi, lo = v.max("rotation"), v.min("rotation")
        spreads.append(float((100 * (hi - lo) / hi).max(skipna=True)))
    spreads = [s for s in spreads if s == s]
    return max(spreads) if spreads else np.nan


def comparison_table(plan: pd.DataFrame, study: pd.DataFrame,
                     rotation_effect: float = np.nan, rotations: float = np.nan
                     ) -> pd.DataFrame:
    """Findings: the plan's best removal rate, the best of the study's own cuts, and their
    ratio; ``rotation_effect``: :func:`rotation_effect_pct` of the pose map; ``rotations``:
    how many redundancy angles about the tool axis the request allowed (the pose map's).

    The study's best is the largest removal rate among its cuts judged stable (``verdict``);
    without verdicts, among those meeting the request's constraints; without either, among
    all its cuts (``study_best_basis`` says which). The ratio is NaN only when the study has
    no cut."""
    judged = study[study["verdict"] == "stable"] if "verdict" in study else study.head(0)
    ok = study[study["feasible"].astype(bool)]
    basis, pool = (("judged_stable", judged) if len(judged) else
                   ("feasible", ok) if len(ok) else ("all", study))
    plan_best = float(plan["mrr_mm3_s"].max()) if len(plan) else np.nan
    study_best = float(pool["mrr_mm3_s"].max()) if len(pool) else np.nan
    best_cut = str(pool.loc[pool["mrr_mm3_s"].idxmax(), "cut"]) if len(pool) else ""
    rows = [
        ("plan_best_mrr_mm3_s", plan_best, "mm3/s", str(plan["cut"].iloc[0]) if len(plan) else ""),
        ("study_best_mrr_mm3_s", study_best, "mm3/s", best_cut),
        ("mrr_ratio", plan_best / study_best if study_best > 0 else np.nan, "1", basis),
        ("study_cuts", float(len(study)), "1", ""),
        ("study_cuts_feasible", float(len(ok)), "1", ""),
        ("study_cuts_judged_stable", float(len(judged)), "1", ""),
        ("rotation_effect_pct", float(rotation_effect), "%", ""),
        ("rotations", float(rotations), "1", ""),
    ]
    return pd.DataFrame(rows, columns=["quantity", "value", "unit", "cut"])


def rotation_effect_case(rotation_effect: float | None, rotations: float | None) -> str:
    """Which of Chapter 7's rotation sentences holds: ``changes`` (a spread > 0), ``none`` (0:
    no rotation changed a prediction), ``single_rotation`` (not computed: the request allowed
    at most one redundancy angle), ``not_computed`` (not computed otherwise: no reachable pose,
    or a comparison table without the count of rotations)."""
    if rotation_effect is not None and rotation_effect == rotation_effect:
        return "changes" if rotation_effect > 0 else "none"
    if rotations is not None and rotations == rotations and rotations < 2:
        return "single_rotation"
    return "not_computed"


def comparison_values(comparison: pd.DataFrame) -> dict[str, Any]:
    """The comparison table (indexed by ``quantity``) as the fields of Chapter 7's sentences:
    each quantity's value (None where not computed), ``<quantity>_cut`` and
    ``rotation_effect_case`` (:func:`rotation_effect_case`)."""
    out: dict[str, Any] = {}
    for quantity, row in comparison.iterrows():
        value = row["value"]
        out[str(quantity)] = None if value != value else value
        out[f"{quantity}_cut"] = row["cut"] if isinstance(row["cut"], str) else ""
    out["rotation_effect_case"] = rotation_effect_case(out.get("rotation_effect_pct"),
                                                       out.get("rotations"))
    return out
