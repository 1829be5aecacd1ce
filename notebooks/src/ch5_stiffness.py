# %% [markdown]
# # Chapter 5 — Stiffness and pose
#
# Two stiffness models of a robot arm, from the two source papers, and what they say about the
# thesis robot:
#
# * **Joint-stiffness model** (seed 001, Yi et al. 2025, KUKA KR360): rigid links, elastic
#   joints; TCP deflection X = J K_θ⁻¹ Jᵀ F, identified from load tests as X = A(J, F) k by
#   least squares; Cartesian stiffness K = J⁻ᵀ K_θ J⁻¹; directional stiffness along the tool
#   axes; maps over the milling plane for redundancy angles; the stiffness-optimal pose.
# * **Beam-frame model** (seed 004, Cai et al. 2015, MOTOMAN-HP20): the arm as beam elements
#   with 6 DOF per node, node 1 fixed, δ = K⁻¹F; the pneumatic-wheel load and the vibration
#   predictor σ(t).
#
# The KR360's MD-H table is not printed in seed 001, so its parameters are *assumed* (documented
# in `config.yaml`). The numbers below come from `results/stiffness/findings.yaml`; the seed's
# numbers, from `src/robomill/data/references.yaml`, are set against ours at the end.

# %% tags=["parameters"]
maps: str = None  # results/stiffness/maps.nc
optimal: str = None  # results/stiffness/optimal_poses.csv
beamframe: str = None  # results/stiffness/beamframe.nc
map_joints: str = None  # results/stiffness/<map robot>/joint_stiffness.csv
map_models: str = None  # results/stiffness/<map robot>/identification.csv
map_validation: str = None  # results/stiffness/<map robot>/validation.csv
slots: str = None  # results/stiffness/thesis_slots.csv (thesis design only)
waviness: str = None  # results/surface/table_2_1_waviness_rms.csv (thesis design only)
cut_stiffness: str = None  # results/stiffness/cut_stiffness.csv (other designs; cell robot tested)
cuts: str = None  # results/ingest/cuts.csv (with cut_stiffness)
templates: str = None  # notebooks/templates/ch5.yaml: the sentences rendered from findings
findings: str = None  # results/stiffness/findings.yaml: every number and verdict stated here
experiment: dict = None  # the manifest's experiment defaults (spindle_rpm, flutes, ...)
thesis_design: bool = None  # unused: the findings say which cut table applies
thesis_study: bool = None  # unused: the comparison rows come with the findings
fig_dir: str = None  # folder for this chapter's figures

# %%
import matplotlib.pyplot as plt
import pandas as pd
from IPython.display import Markdown, display

from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.design_tables import per_cut_table
from robomill.pipeline.prose import Prose, comparison_table, load_templates
from robomill.plotting import save_figure
from robomill.stiffness.cuts import slot_stiffness_table
from robomill.stiffness.figures import (
    beamframe_figure,
    maps_figure,
    optimal_figure,
    slots_figure,
    workspace_figure,
)
from robomill.stiffness.tables import (
    cut_stiffness_um,
    joints_table,
    maxima_table,
    validation_table,
    workspace_table,
)

found = read_findings(findings)
say = Prose(load_templates("ch5", templates), found)
v = found.values()
mp = open_artefact(maps)
opt = pd.read_csv(optimal)
bf = open_artefact(beamframe)
heights = mp["height_mm"].values
SLOTS, CUTS_K = v["has_slots"], v["has_cut_stiffness"]

num = Numbering("5")
num.table("workspace_ranges", "Workspace ranges: seed 001 against our Monte-Carlo workspace")
num.figure("workspace", "Monte-Carlo workspace: X–Z projection of the 3-D workspace and the "
           "X–Z plane")
num.table("joints", "Identified joint stiffnesses with 95 % intervals, per model, beside the "
          "seed's 3-D and plane values")
num.table("identification", "The identifications: poses used, condition number, residual")
num.table("validation", "Mean absolute error of the predicted deflection on the validation "
          "poses")
for i, h in enumerate(heights):
    num.figure(f"maps_h{h:.0f}", f"Directional stiffness along the tool axes over the working "
               f"plane, H = {h:.0f} mm, every redundancy angle (seed 001 Fig. 11)", number=2,
               part="abcdefgh"[i] if len(heights) > 1 else "")
num.table("maxima", "Largest directional stiffness per height and redundancy angle")
num.table("optimal", "The stiffness-optimal pose and random poses: deformation under the end "
          "load")
num.figure("optimal_poses", "Deformation under the end load, optimal against random poses "
           "(dashed: the seed's optimum)")
num.figure("beamframe", "Beam-frame model: nodes at t = 0, and the tool displacement with the "
           "predicted σ(t) (seed 004, eq. 17)")
if CUTS_K:
    num.table("cut_stiffness", "The cell's robot (joint model): stiffness along each cut's "
              "feed, in-plane normal and tool axis at the middle of the cut, grouped by what "
              "varies")
if SLOTS:
    num.table("slots", "Thesis robot: mean stiffness along the slot directions beside the "
              "mean waviness of Table 2.1")
    num.figure("thesis_slots", "Thesis robot: stiffness per slot direction against the "
               "waviness RMS of Table 2.1")

# %% [markdown]
# ## 5.1 Workspace (seed 001 §2)

# %%
display(num.caption("workspace_ranges"))
display(workspace_table(v).round(0))
display(Markdown(say("workspace", ref_workspace_ranges=num.ref("workspace_ranges"),
                     ref_workspace=num.ref("workspace"))))

# %%
fig = workspace_figure(mp)
save_figure(fig, fig_dir, num.file("workspace"))
plt.show()
display(num.caption("workspace"))

# %% [markdown]
# ## 5.2 Joint-stiffness identification (seed 001 §3)

# %%
models = pd.read_csv(map_models)
display(num.caption("joints"))
display(joints_table(pd.read_csv(map_joints), models, v).round(4))
display(num.caption("identification"))
display(models[["model", "n_poses", "condition_number", "residual_rms_um", "warnings"]]
        .round(3))
display(Markdown(say("identification", "planted", ref_joints=num.ref("joints"),
                     ref_identification=num.ref("identification"))))

# %%
display(num.caption("validation"))
display(validation_table(pd.read_csv(map_validation), v).round(2))
display(Markdown(say("validation", ref_validation=num.ref("validation"))))

# %% [markdown]
# ## 5.3 Directional stiffness over the working plane (seed 001 §4.2, Fig. 11)

# %%
display(Markdown(say("maps", ref_maps=", ".join(num.ref(f"maps_h{h:.0f}") for h in heights))))
for h in heights:
    fig = maps_figure(mp, h)
    save_figure(fig, fig_dir, num.file(f"maps_h{h:.0f}"))
    plt.show()
    display(num.caption(f"maps_h{h:.0f}"))

# %%
display(num.caption("maxima"))
display(maxima_table(mp, v).round(3))
display(Markdown(say("maxima", ref_maxima=num.ref("maxima"))))

# %% [markdown]
# ## 5.4 The stiffness-optimal pose (seed 001 §4.3–4.4)

# %%
display(num.caption("optimal"))
display(opt.drop(columns=["robot"]).round(1))
display(Markdown(say("optimal", ref_optimal=num.ref("optimal"),
                     ref_optimal_poses=num.ref("optimal_poses"))))

# %%
fig = optimal_figure(opt, v)
save_figure(fig, fig_dir, num.file("optimal_poses"))
plt.show()
display(num.caption("optimal_poses"))

# %% [markdown]
# ## 5.5 Beam-frame model and vibration predictor (seed 004)

# %%
display(Markdown(say("beamframe", "beamframe_definite", "cantilever",
                     ref_beamframe=num.ref("beamframe"))))
fig = beamframe_figure(bf)
save_figure(fig, fig_dir, num.file("beamframe"))
plt.show()
display(num.caption("beamframe"))

# %% [markdown]
# ## 5.6 Stiffness along the cuts

# %%
display(Markdown(say("cuts_intro")))
if CUTS_K:
    ck, cols = cut_stiffness_um(pd.read_csv(cut_stiffness))
    display(num.caption("cut_stiffness"))
    display(per_cut_table(ck, cols, pd.read_csv(cuts), experiment).round(3))
display(Markdown(say("cut_stiffness", "no_cuts",
                     ref_cut_stiffness=num.ref("cut_stiffness") if CUTS_K else "")))

# %%
if SLOTS:
    sl = pd.read_csv(slots)
    display(num.caption("slots"))
    display(slot_stiffness_table(sl, pd.read_csv(waviness, index_col=0)))
    display(Markdown(say("unobservable", "slots", "slot_verdict", ref_slots=num.ref("slots"),
                         ref_thesis_slots=num.ref("thesis_slots"))))
    fig = slots_figure(sl, v)
    save_figure(fig, fig_dir, num.file("thesis_slots"))
    plt.show()
    display(num.caption("thesis_slots"))

# %% [markdown]
# ## Against the source

# %%
display(Markdown(say("against", "against_rows", sep="\n\n")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
