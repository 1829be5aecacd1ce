# %% [markdown]
# # Chapter 6.3 — Reference study: hexapod dynamics and force errors
#
# A reproduction of a source paper that uses no data of this study. Rybak, Gaponenko and
# Mamaev [Rybak n.d.] argue for high-speed milling on parallel-kinematics machines and gives
# a dynamic model of a Stewart–Gough hexapod: the inverse problem
# **M(X) Ẇ + C(W, X) + G = τ** and the forward problem **V̇ₚ = A_m⁻¹ (J_rᵀ Γ − h_m)**
# (seed eqs 1–8), built from the six leg models (inertia A_xi, bias h_xi at the leg tip) and
# the platform's Newton–Euler equations. We implement that model (`robomill.hexapod`), run the
# seed's acceleration programme through the inverse dynamics, replay the forces through the
# forward dynamics, and repeat the seed's experiment: a vertical move in which one actuator
# delivers slightly too much force. The numbers below come from
# `results/hexapod/findings.yaml`; the seed's, from `src/robomill/data/references.yaml`, are set
# against ours at the end.

# %% tags=["parameters"]
trajectory: str = None  # results/hexapod/trajectory.nc
forces: str = None  # results/hexapod/forces.nc
sensitivity: str = None  # results/hexapod/sensitivity.nc
force_accuracy: str = None  # results/hexapod/force_accuracy.csv
templates: str = None  # robomill/data/templates/ch6_hexapod.yaml: sentences from findings
findings: str = None  # results/hexapod/findings.yaml: every number stated here
fig_dir: str = None  # folder for this chapter's figures

# %%
import pandas as pd
from IPython.display import Markdown, display

from robomill.findings import read_findings
from robomill.hexapod.figures import (
    drift_map_figure,
    forces_figure,
    seed_table1,
    trajectory_figure,
    vertical_figure,
    vertical_table,
)
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.prose import Prose, comparison_table, load_templates

found = read_findings(findings)
say = Prose(load_templates("ch6_hexapod", templates), found)
# chapter 6 is numbered across its three pages (the chapter registry's first_figure/first_table)
num = Numbering.for_chapter("ch6_hexapod", fig_dir=fig_dir)
num.table("seed_table1", "High-speed against conventional ball-end milling, as printed in "
          "[Rybak n.d., Table 1]")
num.figure("trajectory", "The seed's acceleration programme through the inverse dynamics and "
           "its open-loop replay (left), and the round-trip error (right)")
num.figure("actuator_forces", "Actuator forces of the programme (seed Fig. 4)")
num.figure("drift_vs_exact", "The vertical move with exact forces and with one actuator's "
           "force off (seed Fig. 5): height, drift and Euler angles")
num.table("vertical", "The vertical move: the seed's printed numbers beside ours")
num.figure("drift_map", "Final drift and tilt of the vertical move over force error × "
           "actuator")
num.table("force_accuracy", "Force accuracy each position tolerance needs "
          "(results/hexapod/force_accuracy.csv)")
display(Markdown(say("assumed")))



# %% [markdown]
# ## Context — high-speed machining (seed Table 1)
#
# The seed's case for parallel kinematics: high-speed milling needs light, fast axes.

# %%
display(Markdown(say("table1", ref_seed_table1=num.ref("seed_table1"))))
display(num.caption("seed_table1"))
display(seed_table1(found.values()))

# %% [markdown]
# ## The seed's acceleration programme

# %%
traj = open_artefact(trajectory)
display(Markdown(say("programme", ref_trajectory=num.ref("trajectory"))))
num.show(trajectory_figure(traj), "trajectory")
display(Markdown(say("replay", "unstable")))

# %% [markdown]
# ## Actuator forces of the programme

# %%
num.show(forces_figure(open_artefact(forces)), "actuator_forces")
display(Markdown(say("forces", ref_actuator_forces=num.ref("actuator_forces"))))

# %% [markdown]
# ## The vertical move with one actuator's force off

# %%
num.show(vertical_figure(traj), "drift_vs_exact")
display(num.caption("vertical"))
display(vertical_table(found.values()).round(4))
display(Markdown(say("vertical", ref_drift_vs_exact=num.ref("drift_vs_exact"),
                     ref_vertical=num.ref("vertical"))))

# %% [markdown]
# ## Drift map, and the force accuracy a tolerance needs

# %%
num.show(drift_map_figure(open_artefact(sensitivity)), "drift_map")
display(num.caption("force_accuracy"))
display(pd.read_csv(force_accuracy).rename(columns={
    "position_tolerance_mm": "position tolerance [mm]",
    "force_accuracy_pct": "force accuracy needed [%]",
    "force_accuracy_mN": "force accuracy needed [mN]"})[
    ["position tolerance [mm]", "force accuracy needed [%]", "force accuracy needed [mN]"]
].round(4))
display(Markdown(say("drift", "antisymmetry", "accuracy", "accuracy_growth",
                     ref_drift_map=num.ref("drift_map"),
                     ref_force_accuracy=num.ref("force_accuracy"))))

# %% [markdown]
# ## Against the source

# %%
display(Markdown(say("against", "against_rows", sep="\n\n")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
