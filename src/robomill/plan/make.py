"""One plan from one request: predict every candidate, refuse or choose, give each chosen cut a
free place on the block (:mod:`robomill.plan.slots`) and a path a robot can run, its rotation
about the tool axis chosen station by station (:mod:`robomill.plan.cutpath`), and put the plan
beside the study's own cuts."""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.experiment import Cut
from robomill.plan.binding import binding_interval, same_cut_stability_width, same_cut_width
from robomill.plan.choose import PlanInfeasible, check_needs, choose, feasible
from robomill.plan.compare import (
    comparison_table,
    rotation_effect_pct,
    stability_evidence,
    study_cuts_table,
)
from robomill.plan.cutpath import plan_cut_path
from robomill.plan.measured import Measured, missing_predictions
from robomill.plan.outputs import (
    next_config,
    next_manifest,
    p_stable_map,
    plan_table,
    pose_map,
)
from robomill.plan.pathout import (
    floor_starts,
    follow_paths,
    manifest_path,
    path_columns,
    path_map,
    path_summary,
    pose_failure_table,
    rotations_meeting_constraints,
)
from robomill.plan.poses import cut_frames
from robomill.plan.predict import Cell, apply_extrapolation, predict_grid, solver_error
from robomill.plan.request import PlanRequest
from robomill.plan.slots import separate_slots
from robomill.plan.slots import study_slots as study_slot_segments
from robomill.plan.workobject import BASE

if TYPE_CHECKING:  # robomill.study reads the manifest: typing only
    from robomill.study import StudyCut


@dataclass
class Plan:
    """Everything the plan rule writes."""

    candidates: xr.Dataset
    pose_map: xr.Dataset
    plan: pd.DataFrame
    pareto: pd.DataFrame
    study: pd.DataFrame
    comparison: pd.DataFrame
    manifest: dict[str, Any]
    config: dict[str, Any]
    paths: list = field(default_factory=list)
    path_summary: pd.DataFrame | None = None
    binding: dict[str, Any] = field(default_factory=dict)
    evidence: pd.DataFrame | None = None
    """The study's cuts whose chatter verdicts conditioned the stability limit
    (``results/plan/evidence_used.csv``, :mod:`robomill.plan.conditioning`)."""


def after_study_ids(ids: Sequence[str], study_ids: Sequence[str]) -> list[str]:
    """The planned cut ids ``plan_NN`` numbered on after the study's own ``plan_NN`` cuts (a
    study that merged an earlier plan's run, ``data.raw_dirs``), so that no planned id names a
    cut of the study; unchanged where the study has none."""
    taken = [int(m.group(1)) for s in study_ids if (m := re.fullmatch(r"plan_(\d+)", s))]
    k = max(taken, default=0)
    return [f"plan_{k + int(c[len('plan_'):]):02d}" if k and re.fullmatch(r"plan_\d+", c)
            else c for c in ids]


def learn_plan(cand: xr.Dataset, req: PlanRequest, measured: Measured, occupied, reach,
               robot_name: str) -> tuple[pd.DataFrame, pd.DataFrame, pd.Series | None]:
    """The learn design (:func:`robomill.plan.learn.learn_design`) aimed at the production
    plan's binding cut (its largest removal rate; none when no candidate is feasible), the
    production Pareto front beside it (empty then) and that binding cut."""
    from robomill.plan.extrapolation import reason_text
    from robomill.plan.learn import learn_design

    try:
        prod, front = choose(cand, req, robot_name, occupied=occupied)
    except PlanInfeasible:
        prod, front = None, pd.DataFrame()
    chosen = learn_design(cand, req, occupied=occupied,
                          midpoints_mm=None if reach is None else reach.midpoints_mm,
                          regression=measured.force_regression,
                          binding=None if prod is None or prod.empty else prod.iloc[0])
    if chosen.empty:
        raise PlanInfeasible(f"{req.path}: purpose learn: no reachable candidate to learn from "
                             "(no stability limit inside the requested depths, no pose or "
                             "feed within the other constraints)")
    if "extrapolation_code" in chosen:
        chosen["extrapolation_reason"] = [reason_text(c) for c in chosen["extrapolation_code"]]
    return chosen, front, None if prod is None or prod.empty else prod.iloc[0]


def verdict_conditioned(measured: Measured, req: PlanRequest, cell: Cell,
                        cuts: Sequence[StudyCut | Cut],
                        experiment: Mapping[str, Any], stability: pd.Series | None):
    """``measured`` with the stability model's members weighted by the study's verdicts
    (:func:`robomill.plan.compare.stability_evidence`), and that evidence (None without
    verdicts or a stability prediction)."""
    if stability is None or not len(stability):
        return measured, None
    evidence = stability_evidence(cuts, experiment, req, measured, cell, stability)
    if evidence is None:
        return measured, None
    return replace(measured, stability_evidence=evidence), evidence


def make_plan(req: PlanRequest, measured: Measured, cell: Cell,
              cuts: Sequence[StudyCut | Cut],
              experiment: Mapping[str, Any], *, robot_name: str = "the robot",
              reach=None, study_slots=None, binding_constraint: str | None = None,
              stability: pd.Series | None = None,
              binding_before: pd.DataFrame | None = None,
              impact_tcp_mm: np.ndarray | None = None) -> Plan:
    """The whole plan (raises :class:`robomill.plan.choose.PlanInfeasible` with one line when a
    constraint needs a missing measurement, no candidate meets the constraints, or every
    candidate is extrapolated and the request does not allow it). ``cuts``: the study's
    cuts (:class:`robomill.study.StudyCut`, their process as the ingestion rule resolved
    it), each predicted as a planning candidate (:mod:`robomill.plan.candidate`). ``reach``
    (:class:`robomill.plan.extrapolation.StudyReach`): flag and widen what lies outside it;
    ``study_slots``: the study's cuts as segments ``(2, 3)`` [mm], which no planned slot may
    overlap (:mod:`robomill.plan.material`); ``binding_constraint``: the constraint whose
    interval :attr:`Plan.binding` measures (an earlier plan's; default the one that binds,
    :func:`robomill.plan.binding.binding_interval`; ``binding_before``: that plan's
    ``binding.csv``, whose binding cut the narrowing is measured at); ``stability``: the
    study's chatter verdicts per cut (1 stable, 0 chatter, NaN undetermined;
    :func:`robomill.plan.evidence.verdict_stability`), which condition every critical-depth
    interval of the plan (:mod:`robomill.plan.conditioning`); ``impact_tcp_mm``: where the
    study's impact test was made, from its files (the next run's cell stands there:
    :func:`robomill.plan.outputs.next_config`)."""
    missing = missing_predictions(measured)
    check_needs(req, missing)
    measured, evidence = verdict_conditioned(measured, req, cell, cuts, experiment, stability)
    cand = predict_grid(req, measured, cell)
    if reach is not None:  # what the study measured (robomill.plan.extrapolation)
        cand = apply_extrapolation(cand, req, measured, cell, reach)
    occupied = [] if study_slots is None else list(study_slots)
    if req.purpose == "learn":
        chosen, front, prod_first = learn_plan(cand, req, measured, occupied, reach,
                                               robot_name)
    else:
        chosen, front = choose(cand, req, robot_name, occupied=occupied)
        prod_first = chosen.iloc[0]
    study_ids = [c.id for c in cuts]
    chosen["cut"] = after_study_ids(list(chosen["cut"].astype(str)), study_ids)
    if prod_first is not None:
        prod_first = prod_first.copy()
        prod_first["cut"] = after_study_ids([str(prod_first["cut"])], study_ids)[0]
    binding = ({} if prod_first is None
               else binding_interval(cand, req, prod_first, binding_constraint))
    if binding:  # the earlier plan's binding prediction at its own binding cut, now
        binding["width_same_cut"] = same_cut_width(cand, req, binding_before)
        binding["a_crit_width_same_cut_mm"] = same_cut_stability_width(cand, req,
                                                                       binding_before)
    wobj = req.work_object or BASE
    own = [c if isinstance(c, Cut) else c.cut for c in cuts]  # a StudyCut carries its Cut
    chosen, slot_notes = separate_slots(chosen, cand, req,
                                        study_slot_segments(own, experiment, wobj), wobj)
    # the slots' renumbering (plan_01 …) again after the study's own plan_NN cuts
    chosen["cut"] = after_study_ids(list(chosen["cut"].astype(str)), study_ids)
    if not len(chosen):
        raise PlanInfeasible(f"{req.path}: no chosen cut has a free place on the block: every "
                             "slot would cross the study's or leave the block "
                             "(work_object.block_mm)")
    if req.purpose == "learn":  # the learn cuts' own constraints: no stability margin
        from robomill.plan.learn import learn_allowed
        mask = learn_allowed(cand, req)
    else:
        mask = feasible(cand, req)
    cut_paths = [plan_cut_path(str(r["cut"]), np.array([r["placement_x_mm"],
                                                        r["placement_y_mm"],
                                                        r["placement_z_mm"]], float),
                               float(r["direction_deg"]), float(r["depth_mm"]),
                               float(r["feed_mm_s"]), float(r["spindle_rpm"]), req, measured,
                               cell, wobj, rotations_meeting_constraints(mask, r), reach)
                 for _, r in chosen.iterrows()]
    chosen = follow_paths(chosen, cand, mask, cut_paths)
    paths = [manifest_path(p, cand["station"].values) for p in cut_paths]
    q = [cand["q_deg"].isel(placement=int(r["i_placement"]), rotation=int(r["i_rotation"]),
                            direction=int(r["i_direction"])).values
         for _, r in chosen.iterrows()]
    chosen["tooth_passing_hz"] = chosen["spindle_rpm"].to_numpy(float) * req.flutes / 60.0
    table = path_columns(plan_table(chosen), cut_paths)
    study = study_cuts_table(cuts, experiment, req, measured, cell, reach, stability)
    manifest = next_manifest(chosen, req, dict(experiment), cand.attrs["missing_predictions"],
                             np.asarray(q), paths)
    floor_starts(manifest, cut_paths)
    cand.attrs["request"] = req.path
    cand.attrs["interval_level"] = float(measured.level)
    cand.attrs["purpose"] = req.purpose
    cand.attrs["extrapolation_harmonics"] = int(req.extrapolation["harmonics"])
    if reach is not None and reach.modal_band_hz is not None:
        cand.attrs["modal_band_hz"] = np.asarray(reach.modal_band_hz, float)
    cand.attrs.update(evidence_attrs(evidence))
    if prod_first is not None:  # the zero-order solution's error at the binding cut
        at = {"placement": int(prod_first["i_placement"]),
              "rotation": int(prod_first["i_rotation"]),
              "direction": int(prod_first["i_direction"])}
        cand.attrs["stability_solver_error"] = solver_error(
            measured, cell, req, np.deg2rad(cand["q_deg"].isel(at).values),
            cut_frames(np.array([float(prod_first["direction_deg"])]))[0],
            float(prod_first["spindle_rpm"]))
    cand.attrs["constraints"] = "; ".join(f"{k}={v}" for k, v in req.constraints.items()
                                          if v is not None)
    pmap = path_map(pose_map(cand, chosen.iloc[0]), cut_paths[0] if cut_paths else None, req,
                    measured, cell)
    pmap = pmap.merge(p_stable_map(cand, chosen.iloc[0]))
    effect = rotation_effect_pct(pmap)
    return Plan(cand, pmap, table, plan_table(front), study,
                comparison_table(table, study, effect, pmap.sizes["rotation"]), manifest,
                next_config(manifest, impact_tcp_mm=impact_tcp_mm), cut_paths,
                path_summary(pose_failure_table(cand), table, effect, slot_notes), binding,
                None if evidence is None else evidence.table)


def evidence_attrs(evidence) -> dict[str, Any]:
    """The attributes of ``candidates.nc`` that say what conditioned the critical depth:
    ``stability_evidence_cuts`` (cuts whose verdict entered), ``stability_members`` and
    ``stability_members_kept`` (members of the model, and their effective number after the
    verdicts' weights, Kish's (Σw)²/Σw²), ``stability_verdict_error`` (the assumed rate of
    a wrong verdict), ``stability_evidence_note`` (one line when the prior interval does not
    admit some verdicts)."""
    if evidence is None:
        return {"stability_evidence_cuts": 0, "stability_members": 0,
                "stability_members_kept": 0, "stability_evidence_note": ""}
    from robomill.plan.conditioning import contradiction_note

    return {"stability_evidence_cuts": evidence.n_used,
            "stability_members": len(evidence.weights),
            "stability_members_kept": round(evidence.effective_members),
            "stability_verdict_error": float(evidence.error_rate),
            "stability_evidence_note": contradiction_note(evidence.table)}
