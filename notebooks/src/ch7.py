# %% [markdown]
# # Chapter 7 — The next cuts
#
# The study identified the robot's modes (impact test), its joint stiffness (load tests), the
# cutting coefficients (dynamometer) and the gear lines printed on its paths (tracker). This
# chapter turns them into a plan (`robomill.plan`, request `plan.yaml`): every candidate cut —
# where the part sits, how the spindle turns about the tool axis, the feed direction, speed,
# depth and feed — with its predicted critical depth and probability of a stable cut (the
# regenerative lobes of every identified mode at the pose, the robot's low-frequency modes
# scaled with the pose through the joint stiffness, and a stated prior of the spindle/tool modes
# above the impact test's band, under the tangential, radial and axial cutting forces; a
# bootstrap of members weighted by the study's own chatter verdicts, `robomill.plan.stability`),
# static deflection (mean cutting force over the pose's stiffness), waviness (the gear lines
# carried through the Jacobian to the new pose), force, feed marks and removal rate, each with
# an interval from the identified quantities' uncertainty. The waviness has two: the spread
# between the tracker runs that identified its gear lines (the wall's waviness), and the
# interval the next tracker run's reading falls in, that spread combined with the tracker's
# noise at the cut's record (`robomill.plan.noise`). The constraints are checked on the
# pessimistic end of each interval (the waviness' identification interval). Every number below
# comes from the plan's artefacts.

# %% tags=["parameters"]
candidates: str = None  # results/plan/candidates.nc
pose_map: str = None  # results/plan/pose_map.nc
plan: str = None  # results/plan/plan.csv
pareto: str = None  # results/plan/pareto.csv
study: str = None  # results/plan/study_cuts.csv
comparison: str = None  # results/plan/comparison.csv
path_summary: str = None  # results/plan/path_summary.csv
binding: str = None  # results/plan/binding.csv
evidence: str = None  # results/plan/evidence_used.csv
check: str = None  # results/plan/check.csv
check_summary: str = None  # results/plan/check_summary.csv
misses: str = None  # results/plan/misses.csv: each out-of-sample miss and why
program: str = None  # results/plan/next/program: the controller program and its stations.csv
cell: str = None  # the cell file (joint limits)
request: str = None  # the planning request (limit margin, wrist angle, work object)
templates: str = None  # robomill/data/templates/ch7.yaml: sentences from check_summary
fig_dir: str = None  # folder for this chapter's figures

# %%
import matplotlib.pyplot as plt
import pandas as pd
from IPython.display import Markdown, display

from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.prose import Prose, load_templates
from robomill.plan.compare import comparison_values
from robomill.plan.evidence import coverage_case
from robomill.plan.extrapolation import reach_values
from robomill.plan.pathout import summary_values

num = Numbering.for_chapter("ch7", fig_dir=fig_dir)
num.figure("pareto", "Removal rate against the predicted form error (upper bound): the "
           "plan's Pareto front and the study's own cuts")
num.figure("p_stable", "Probability of a stable cut over spindle speed × depth at the plan's "
           "best cut's pose, before (left) and after (right) weighting the stability model's "
           "members by the study's verdicts; the study's judged cuts marked (o stable, x "
           "chatter)")
num.figure("pose_map", "Pose map: the largest pessimistic critical depth over the speed range "
           "(top) and the upper deflection normal to the wall at the best cut's speed, depth "
           "and feed (bottom), over placement × rotation about the tool axis")
num.table("plan", "The chosen cuts, ranked by removal rate (results/plan/plan.csv)")
num.table("paths", "The chosen cuts' paths: configuration, rotation at each station, the best "
          "fixed rotation and the path's gain over it (results/plan/plan.csv)")
num.table("comparison", "The plan's best removal rate beside the study's best at equal "
          "constraints (results/plan/comparison.csv)")
num.table("check", "Each prediction beside the outcome recorded under the same cut id "
          "(results/plan/check.csv)")
why = pd.read_csv(misses)
if len(why):
    num.table("misses", "The out-of-sample outcomes outside their stated interval, with the "
              "evidence of the run's files and what the prediction did not model "
              "(results/plan/misses.csv)")

cand = open_artefact(candidates, load=False)
pmap = open_artefact(pose_map)
chosen = pd.read_csv(plan)
front = pd.read_csv(pareto)
own = pd.read_csv(study)
cmp_ = pd.read_csv(comparison).set_index("quantity")
chk = pd.read_csv(check)
summary = pd.read_csv(check_summary).set_index("key")["value"].to_dict()
say = Prose(load_templates("ch7", templates), summary)
paths_say = Prose(load_templates("ch7", templates), summary_values(pd.read_csv(path_summary)))

# %% [markdown]
# ## What the plan could predict

# %%
display(Markdown(say("request", "missing_predictions",
                     **{k: cand.attrs.get(k, "") for k in ("request", "constraints",
                                                            "missing_predictions")})))

# %% [markdown]
# ## Removal rate against form error

# %%
fig, ax = plt.subplots(figsize=(7, 4.5))
ax.plot(front["form_error_high_um"], front["mrr_mm3_s"], "o-", label="plan: Pareto front")
ax.plot(chosen["form_error_high_um"], chosen["mrr_mm3_s"], "s", mfc="none", ms=11,
        label="plan: chosen cuts")
ok = own["feasible"].astype(bool)
ax.plot(own.loc[ok, "form_error_high_um"], own.loc[ok, "mrr_mm3_s"], "^", color="tab:green",
        label="study cuts meeting the constraints")
ax.plot(own.loc[~ok, "form_error_high_um"], own.loc[~ok, "mrr_mm3_s"], "x", color="tab:red",
        label="study cuts outside them")
ax.set_xlabel("predicted form error, upper bound [µm]")
ax.set_ylabel("material removal rate [mm³/s]")
ax.legend(fontsize=8)
fig.tight_layout()
num.show(fig, "pareto")
display(Markdown(say("pareto", ref_pareto=num.ref("pareto"))))

# %% [markdown]
# ## The pose map

# %%
dirs = list(pmap["direction"].values)
fig, axes = plt.subplots(2, len(dirs), figsize=(5 * len(dirs), 7), squeeze=False)
for j, d in enumerate(dirs):
    for i, (name, label) in enumerate((("a_crit_best_low_mm", "a_crit (low) [mm]"),
                                       ("deflection_normal_high_um", "δ normal (high) [µm]"))):
        v = pmap[name].sel(direction=d).transpose("placement", "rotation")
        im = axes[i, j].pcolormesh(pmap["rotation"].values, pmap["placement"].values, v.values,
                                   shading="nearest")
        fig.colorbar(im, ax=axes[i, j], label=label)
        axes[i, j].set_title(f"direction {d}")
        axes[i, j].set_xlabel("rotation about the tool axis [deg]")
        axes[i, j].set_ylabel("placement")
fig.tight_layout()
num.show(fig, "pose_map")
display(Markdown(say("pose_map", ref_pose_map=num.ref("pose_map"))))

# %% [markdown]
# ## The chosen cuts

# %%
display(Markdown(say("plan_table", ref_plan=num.ref("plan"))))
display(num.caption("plan"))
cols = ["cut", "placement_x_mm", "placement_y_mm", "placement_z_mm", "direction",
        "rotation_deg", "redundancy_path_deg", "spindle_rpm", "depth_mm", "feed_mm_s",
        "mrr_mm3_s", "stability_margin_low", "deflection_normal_high_um",
        "deflection_axial_high_um", "waviness_ident_high_um", "force_low_N", "force_high_N",
        "feed_mark_um", "extrapolation_reason"]
display(chosen[[c for c in cols if c in chosen]])

# %% [markdown]
# ## How sure the plan is
#
# Every interval is a prediction interval for the next cut at the stated level: the force
# carries the scatter of the identifying cuts' mean forces about the cutting law and the
# coefficients' uncertainty at the new cut's chip load and engagement; the stability margin
# the modes' intervals (`results/modal/modes.csv`), the coefficients' and the joint
# stiffness'; the deflection the force's and the stiffness' together. A candidate outside
# what the study measured is flagged `extrapolation` with its reason, and its interval widens
# by the rule of `robomill.plan.extrapolation`.

# %%
display(Markdown(Prose(load_templates("ch7", templates), reach_values(chosen, cand.attrs))(
    "reach_level", "reach_extrapolated", "reach_direction", "reach_band")))

# %% [markdown]
# ## A path a robot can run
#
# Every candidate pose is checked against the cell's joint limits (less a margin), the wrist
# singularity (the angle between the axes of joints 4 and 6) and its arm/elbow/wrist
# configuration; a chosen cut then gets its rotation about the tool axis station by station,
# by dynamic programming over stations × rotations: the path's worst pessimistic stability
# margin first, then its worst stiffness normal to the wall, then the smallest change from
# the nominal tool orientation, within the request's rotation step and the axes' speeds
# (`robomill.plan.path`). The program for the cell's controller and every station's joints and
# poses are in `results/plan/next/program/`.

# %%
display(Markdown(paths_say("pose_checks", "path_cuts", "path_gain", "path_only",
                           "rotation_case")))
if "path_rotation_deg" in pmap:
    num.figure("path", "The best cut's path: the pessimistic score over station × rotation "
               "about the tool axis, and the chosen rotation at each station")
    score = next((v for v in ("path_stability_margin_low", "path_k_normal_low_N_m")
                  if v in pmap), None)
    fig, ax = plt.subplots(figsize=(7, 4))
    if score is not None:
        z = pmap[score].where(pmap["path_feasible"]).transpose("rotation", "path_station_mm")
        im = ax.pcolormesh(pmap["path_station_mm"].values, pmap["rotation"].values, z.values,
                           shading="nearest")
        fig.colorbar(im, ax=ax, label=("pessimistic margin a_crit/a − 1"
                                       if score == "path_stability_margin_low"
                                       else "stiffness normal to the wall (low) [N/m]"))
    ax.plot(pmap["path_station_mm"].values, pmap["path_rotation_deg"].values, "o-", color="w",
            mec="k", label="chosen rotation")
    ax.set_xlabel("station along the cut [mm]")
    ax.set_ylabel("rotation about the tool axis [deg]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    num.show(fig, "path")
    display(Markdown(paths_say("path_map", ref_path=num.ref("path"),
                               path_cut=pmap.attrs.get("path_cut", ""))))
display(Markdown(paths_say("paths_table", ref_paths=num.ref("paths"))))
display(num.caption("paths"))
pcols = ["cut", "configuration", "redundancy_path_deg", "fixed_rotation_deg",
         "path_worst_margin", "fixed_worst_margin", "path_gain_a_crit", "path_gain_stiffness",
         "min_wrist_angle_deg", "min_limit_clearance_deg", "path_refused"]
display(chosen[[c for c in pcols if c in chosen]])

# %% [markdown]
# ## What the programmer looks at before running
#
# The program (`results/plan/next/program/`) moves home, then per cut to a safe point above
# the part, starts the spindle, approaches, ramps into the slot along the feed direction,
# feeds through the cut's stations without stopping, retracts along the tool axis and leaves
# over the safe point (`robomill.plan.motion`); every target is in `stations.csv`.

# %%
from pathlib import Path

from robomill.io.cell import read_cell
from robomill.plan.pathplot import joints_figure, path_figure
from robomill.plan.request import read_request

stations_file = Path(program) / "stations.csv"
stations = pd.read_csv(stations_file) if stations_file.exists() else pd.DataFrame()
if len(stations):
    req = read_request(request)
    wobj = req.work_object
    num.figure("program_path", "Each planned cut's moves on the part (part frame): the path "
               "in the x–y plane over the block, and the height of every move target")
    num.figure("program_joints", "Each planned cut's joint angles at every move target "
               "against the cell's joint limits (solid) less the request's margin (dashed), "
               "and the wrist angle at the cut's stations against the smallest allowed")
    num.show(path_figure(stations, None if wobj is None else wobj.block_min_mm,
                         None if wobj is None else wobj.block_max_mm), "program_path")
    num.show(joints_figure(stations, read_cell(cell).joint_limits_deg,
                           req.joint_limit_margin_deg, req.min_wrist_angle_deg),
             "program_joints")
    display(Markdown(paths_say("program_figures", ref_program_path=num.ref("program_path"),
                               ref_program_joints=num.ref("program_joints"))))

# %% [markdown]
# ## What a learn round narrows
#
# The production plan is bound by the prediction that stops a larger removal rate at its
# largest-removal-rate cut: the one the grid's next depth (else feed) breaks there
# (`robomill.plan.binding`). The cuts of a learn plan
# (`purpose: learn`), once run, join the identification (their raw folder added to
# `data.raw_dirs`), and the next production plan states the same prediction's interval again.

# %% [markdown]
# Every cut of the study with a chatter verdict (`results/chatter/verdicts.csv`, the learn
# cuts' among them once their folder joined the study) is evidence on the stability limit at
# its own pose, speed and depth: stable, the true limit there is at least its depth; chatter,
# at most; undetermined, nothing. The critical-depth interval is the weighted central range of
# a set of members over the uncertain parameters: each member of the stability model is
# weighted by the likelihood of the verdicts, each taken as wrong with a stated probability
# (`robomill.plan.conditioning`); which
# cuts entered is in `results/plan/evidence_used.csv`.

# %%
from robomill.plan.conditioning import evidence_values

used = pd.read_csv(evidence)
display(Markdown(Prose(load_templates("ch7", templates),
                       evidence_values(used, cand.attrs))("stability_evidence")))
outside = used[used["used"].astype(str).str.lower().eq("true")
               & used["prior_admits"].astype(str).str.lower().eq("false")]
if len(outside):
    display(outside.sort_values("outside_factor", ascending=False)[
        ["cut", "verdict", "spindle_rpm", "depth_mm", "a_crit_low_mm", "a_crit_high_mm",
         "outside_factor"]])

# %% [markdown]
# The probability of a stable cut at the plan's best cut's pose, over speed and depth: the
# share of the stability model's members whose critical depth lies above the depth, each
# member weighted equally (before) and by the likelihood of the study's verdicts (after).

# %%
if "p_stable_post" in pmap:
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for ax, name, title in ((axes[0], "p_stable_prior", "before the verdicts"),
                            (axes[1], "p_stable_post", "after the verdicts")):
        v = pmap[name].transpose("map_depth_mm", "spindle_rpm")
        im = ax.pcolormesh(pmap["spindle_rpm"].values, pmap["map_depth_mm"].values, v.values,
                           shading="nearest", vmin=0, vmax=1, cmap="RdYlGn")
        ax.set_yscale("log")
        ax.set_xlabel("spindle speed [rpm]")
        ax.set_title(title)
        judged = used[used["used"].astype(str).str.lower().eq("true")]
        for verdict, marker in (("stable", "o"), ("chatter", "x")):
            j = judged[judged["verdict"] == verdict]
            ax.plot(j["spindle_rpm"], j["depth_mm"], marker, color="k", mfc="none", ms=5)
    axes[0].set_ylabel("axial depth [mm]")
    fig.colorbar(im, ax=axes, label="p_stable")
    num.show(fig, "p_stable")
    display(Markdown(say("p_stable_map", ref_p_stable=num.ref("p_stable"))))
err = cand.attrs.get("stability_solver_error")
display(Markdown(say("solver_error", stability_solver_error_percent=None if err is None
                     else 100 * float(err))))

# %%
from robomill.plan.binding import binding_values

display(Markdown(Prose(load_templates("ch7", templates),
                       binding_values(pd.read_csv(binding)))("binding",
                                                              "binding_stability")))

# %% [markdown]
# ## The plan beside the study

# %%
display(Markdown(say("comparison_table", ref_comparison=num.ref("comparison"))))
display(num.caption("comparison"))
display(cmp_)
display(Markdown(Prose(load_templates("ch7", templates), comparison_values(cmp_))(
    "comparison", "rotation_effect")))

# %% [markdown]
# ## Closing the loop
#
# Each prediction beside the outcome its run's files recorded under the same cut id. The planned
# cuts are cut as any study's (`snakemake -j2 all --configfile results/plan/next/config.yaml`,
# in their own folder `results/plan/next/run/`, beside the study; on the virtual cell, or from
# a lab's files of the planned cuts), each planned path tracked twice, loaded and in the air;
# the next `snakemake -j2 plan` reads that run's files only: stability from its chatter
# verdicts (else its force spectrum), force from its dynamometer's means, deflection from the
# loaded minus the air tracker path, waviness from its loaded tracker runs. A `stability` row
# gives the predicted margin a_crit/a − 1 with its interval, the probability of a stable cut
# `p_stable` and the outcome 1 (stable) or 0 (chatter), judged on the critical depth: the
# outcome says on which side of the true a_crit the cut's depth lies, and the row holds where
# the predicted a_crit interval reaches that side (`decisive`: the depth inside that interval,
# so that the outcome tests the critical depth, not only the sign of the margin); `held` says
# whether the outcome fell inside the stated interval, `in_sample` whether its data identified
# a model the prediction rests on.

# %%
display(Markdown(say("check_stability_plan", "check_stability_study", "check_decisive",
                     "check_deflection",
                     "check_force", "check_waviness")))
display(Markdown(Prose(load_templates("ch7", templates),
                       {**summary, "coverage_case": coverage_case(summary)})(
    "check_evidence", "check_coverage", "check_brier", "check_sharpness", "check_sharpness_oos",
    "check_sharpness_stability", "check_sharpness_stability_oos")))
display(Markdown(say("check_table", ref_check=num.ref("check"))))
display(num.caption("check"))
if len(chk):
    display(chk)
    if len(why):
        display(Markdown(say("check_misses", ref_misses=num.ref("misses"))))
        display(num.caption("misses"))
        display(why)
    else:
        display(Markdown(say("check_no_misses")))
else:
    display(Markdown(say("check_none")))
num.check()
