# %% [markdown]
# # Chapter 6.2 — Reference study: the stiffness models of Yi 2025 and Cai 2015
#
# Two stiffness models of a robot arm, reproduced from their source papers on their own robots
# (no data of this study; chapter 5 applies the joint model to the study's cuts):
#
# * **Joint-stiffness model** ([Yi 2025], KUKA KR360): rigid links, elastic
#   joints; TCP deflection X = J K_θ⁻¹ Jᵀ F, identified from load tests as X = A(J, F) k by
#   least squares; Cartesian stiffness K = J⁻ᵀ K_θ J⁻¹; directional stiffness along the tool
#   axes; maps over the milling plane for redundancy angles; the stiffness-optimal pose.
# * **Beam-frame model** ([Cai 2015], MOTOMAN-HP20): the arm as beam elements
#   with 6 DOF per node, node 1 fixed, δ = K⁻¹F; the pneumatic-wheel load and the vibration
#   predictor σ(t).
#
# The KR360's MD-H table is not printed in Yi 2025, so its parameters are *assumed* (documented
# in `config.yaml`). The numbers below come from `results/stiffness/findings.yaml`; the seed's
# numbers, from `src/robomill/data/references.yaml`, are set against ours at the end.

# %% tags=["parameters"]
maps: str = None  # results/stiffness/maps.nc
optimal: str = None  # results/stiffness/optimal_poses.csv
beamframe: str = None  # results/stiffness/beamframe.nc
map_joints: str = None  # results/stiffness/<map robot>/joint_stiffness.csv
map_models: str = None  # results/stiffness/<map robot>/identification.csv
map_validation: str = None  # results/stiffness/<map robot>/validation.csv
templates: str = None  # robomill/data/templates/ch6_stiffness.yaml: the sentences of the findings
findings: str = None  # results/stiffness/findings.yaml: every number and verdict stated here
fig_dir: str = None  # folder for this chapter's figures

# %%
import pandas as pd
from IPython.display import Markdown, display

from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.prose import Prose, comparison_table, load_templates
from robomill.stiffness.figures import (
    beamframe_figure,
    maps_figure,
    optimal_figure,
    workspace_figure,
)
from robomill.stiffness.tables import (
    joints_table,
    maxima_table,
    validation_table,
    workspace_table,
)

found = read_findings(findings)
say = Prose(load_templates("ch6_stiffness", templates), found)
v = found.values()
mp = open_artefact(maps)
opt = pd.read_csv(optimal)
heights = mp["height_mm"].values

# chapter 6 is numbered across its three pages (the chapter registry's first_figure/first_table)
num = Numbering.for_chapter("ch6_stiffness", fig_dir=fig_dir)
num.table("workspace_ranges", "Workspace ranges: Yi 2025 against our Monte-Carlo workspace")
num.figure("workspace", "Monte-Carlo workspace: X–Z projection of the 3-D workspace and the "
           "X–Z plane")
num.table("joints", "Identified joint stiffnesses with 95 % intervals, per model, beside the "
          "seed's 3-D and plane values")
num.table("identification", "The identifications: poses used, condition number, residual")
num.table("validation", "Mean absolute error of the predicted deflection on the validation "
          "poses")
for i, h in enumerate(heights):
    num.figure(f"maps_h{h:.0f}", f"Directional stiffness along the tool axes over the working "
               f"plane, H = {h:.0f} mm, every redundancy angle [Yi 2025, Fig. 11]", number=8,
               part="abcdefgh"[i] if len(heights) > 1 else "")
num.table("maxima", "Largest directional stiffness per height and redundancy angle")
num.table("optimal", "The stiffness-optimal pose and random poses: deformation under the end "
          "load")
num.figure("optimal_poses", "Deformation under the end load, optimal against random poses "
           "(dashed: the seed's optimum)", number=9)
num.figure("beamframe", "Beam-frame model: nodes at t = 0, and the tool displacement with the "
           "predicted σ(t) [Cai 2015, eq. 17]", number=10)
bf = open_artefact(beamframe)

# %% [markdown]
# ## 6.2.1 Workspace [Yi 2025, §2]

# %%
display(num.caption("workspace_ranges"))
display(workspace_table(v).round(0))
display(Markdown(say("workspace", ref_workspace_ranges=num.ref("workspace_ranges"),
                     ref_workspace=num.ref("workspace"))))

# %%
fig = workspace_figure(mp)
num.show(fig, "workspace")

# %% [markdown]
# ## 6.2.2 Joint-stiffness identification [Yi 2025, §3]

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
# ## 6.2.3 Directional stiffness over the working plane [Yi 2025, §4.2, Fig. 11]

# %%
display(Markdown(say("maps", ref_maps=", ".join(num.ref(f"maps_h{h:.0f}") for h in heights))))
for h in heights:
    fig = maps_figure(mp, h)
    num.show(fig, f"maps_h{h:.0f}")

# %%
display(num.caption("maxima"))
display(maxima_table(mp, v).round(3))
display(Markdown(say("maxima", ref_maxima=num.ref("maxima"))))

# %% [markdown]
# ## 6.2.4 The stiffness-optimal pose [Yi 2025, §4.3–4.4]

# %%
display(num.caption("optimal"))
display(opt.drop(columns=["robot"]).round(1))
display(Markdown(say("optimal", ref_optimal=num.ref("optimal"),
                     ref_optimal_poses=num.ref("optimal_poses"))))

# %%
fig = optimal_figure(opt, v)
num.show(fig, "optimal_poses")

# %% [markdown]
# ## 6.2.5 Beam-frame model and vibration predictor [Cai 2015]

# %%
display(Markdown(say("beamframe", "beamframe_definite", "cantilever",
                     ref_beamframe=num.ref("beamframe"))))
fig = beamframe_figure(bf)
num.show(fig, "beamframe")

# %% [markdown]
# ## Against the source

# %%
display(Markdown(say("against", "against_rows", sep="\n\n")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
