# %% [markdown]
# # Chapter 1 — Robot calibration and positioning accuracy
#
# The robot's positioning accuracy is the distance between the point its software commands
# and the mean point it actually reaches (thesis §1.3.1). A Creaform C-Track optical CMM
# measures targets on the robot in one fixed frame. Each joint is turned alone while a
# target on its link is measured: the target traces a circle whose normal is the joint axis
# e_i and whose centre O_i lies on it (single-joint method, Stone 1986). The vectors a'_i
# between the centres give the geometric model (eq. 1.4 with the Rodrigues rotations of
# eq. 1.3). Joint positioning errors are measured by stepping each joint from both directions
# (eq. 1.5) and modelled by a regression; joint compliance comes from load-disc tests; the
# base deflection (eq. 1.6) is lumped into joint 2. Accuracy is compared before and after
# calibration on random points that were not used for identification.

# %% tags=["parameters"]
model: str = None  # results/calibration/model.nc
accuracy: str = None  # results/calibration/accuracy.csv
regions: str = None  # results/calibration/accuracy_by_region.csv
points: str = None  # results/calibration/accuracy_points.csv
joint_errors: str = None  # results/calibration/joint_errors.csv
base: str = None  # results/calibration/base.csv
circles: str = None  # results/calibration/circles.csv
templates: str = None  # robomill/data/templates/ch1.yaml: sentences from findings
findings: str = None  # results/calibration/findings.yaml: the numbers this chapter states
fig_dir: str = None  # folder for this chapter's figures

# %%
import pandas as pd
from IPython.display import Markdown, display

from robomill.calibration import figures
from robomill.calibration.accuracy import region_table
from robomill.calibration.dataset import model_from_dataset
from robomill.calibration.tables import a_prime_table, compliance_table, validation_table
from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.prose import Prose, comparison_table, load_templates

found = read_findings(findings)
say = Prose(load_templates("ch1", templates), found)
JOINT, TURN = figures.CIRCLE_JOINT, figures.VECTOR_TURN_DEG
num = Numbering.for_chapter("ch1", fig_dir=fig_dir)
num.figure("joint_circle", f"Single-joint method: the circle of joint {JOINT} in its plane and "
           "the distance of every joint's targets from their fitted circle", number=4)
num.figure("vector_model", "The vector model: centres O_i, vectors a'_i and axes e_i at home "
           f"and with joint 1 turned by {TURN:g}° (eq. 1.4)", number=5)
num.table("a_prime", "The identified vectors a'_i and their lengths")
num.figure("joint_errors", "Joint positioning errors (measured − commanded, eq. 1.5) and their "
           "regression model; held-out steps in orange", number=6)
num.table("validation", "Held-out RMS of the regression forms, the chosen degree and the "
          "backlash [arcsec]")
num.figure("base_deflection", "Base deflection while joint 2 turns the stretched arm, against "
           "the joint-2 angle and the gravity torque (thesis Figs. 1.7–1.8, eq. 1.6)", number=8)
num.table("compliance", "Joint compliances identified from the load discs")
num.figure("accuracy_histograms", "Positioning error on the accuracy points (not used for "
           "identification), nominal, geometric and full model", number=9)
num.table("accuracy", "Positioning accuracy of the three models on the accuracy points")
num.table("regions", "RMS positioning error [mm] by workspace region")
ds = open_artefact(model)



# %% [markdown]
# ## A joint circle and its axis

# %%
display(Markdown(say("circle_intro", circle_joint=JOINT,
                     ref_joint_circle=num.ref("joint_circle"))))
num.show(figures.joint_circle_figure(ds, pd.read_csv(circles), JOINT), "joint_circle")
display(Markdown(say("circles")))

# %% [markdown]
# ## The vector model

# %%
display(Markdown(say("vector_intro", turn_deg=TURN, ref_vector_model=num.ref("vector_model"),
                     ref_a_prime=num.ref("a_prime"))))
num.show(figures.vector_model_figure(model_from_dataset(ds), TURN), "vector_model")
display(num.caption("a_prime"))
display(a_prime_table(ds).round(3))

# %% [markdown]
# ## Joint positioning errors and their regression

# %%
display(Markdown(say("errors_intro", ref_joint_errors=num.ref("joint_errors"))))
num.show(figures.joint_errors_figure(pd.read_csv(joint_errors)), "joint_errors")
display(num.caption("validation"))
display(validation_table(ds).round(2))
display(Markdown(say("regression", ref_validation=num.ref("validation"))))

# %% [markdown]
# ## Base deflection versus joint-2 rotation (eq. 1.6)

# %%
num.show(figures.base_deflection_figure(ds, pd.read_csv(base),
                                    gravity=found.values()["has_gravity_model"]),
     "base_deflection")
display(Markdown(say("base", "base_share", ref_base_deflection=num.ref("base_deflection"),
                     ref_compliance=num.ref("compliance"))))
display(num.caption("compliance"))
display(compliance_table(ds).round(3))

# %% [markdown]
# ## Accuracy before and after calibration

# %%
num.show(figures.accuracy_histogram_figure(pd.read_csv(points)), "accuracy_histograms")
display(num.caption("accuracy"))
display(pd.read_csv(accuracy).set_index("model").round(4))
display(Markdown(say("accuracy", ref_accuracy_histograms=num.ref("accuracy_histograms"),
                     ref_accuracy=num.ref("accuracy"), ref_regions=num.ref("regions"))))
display(num.caption("regions"))
display(region_table(pd.read_csv(regions)).round(4))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("against")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
