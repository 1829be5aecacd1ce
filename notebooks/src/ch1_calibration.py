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
templates: str = None  # notebooks/templates/ch1.yaml: the sentences rendered from findings
findings: str = None  # results/calibration/findings.yaml: the numbers this chapter states
thesis_study: bool = None  # unused: the comparison rows come with the findings
fig_dir: str = None  # folder for this chapter's figures

# %%
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import Markdown, display

from robomill.calibration.accuracy import region_table
from robomill.calibration.dataset import model_from_dataset
from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.prose import Prose, comparison_table, load_templates
from robomill.plotting import save_figure

found = read_findings(findings)
say = Prose(load_templates("ch1", templates), found)
num = Numbering("1")
num.figure("joint_circle", "Single-joint method: the circle of joint 2 in its plane and the "
           "distance of every joint's targets from their fitted circle", number=4)
num.figure("vector_model", "The vector model: centres O_i, vectors a'_i and axes e_i at home "
           "and with joint 1 turned by 90° (eq. 1.4)", number=5)
num.table("a_prime", "The identified vectors a'_i and their lengths")
num.figure("joint_errors", "Joint positioning errors (measured − commanded, eq. 1.5) and their "
           "regression model; held-out steps in orange", number=6)
num.table("validation", "Held-out RMS of the three regression forms, the chosen degree and "
          "the backlash [arcsec]")
num.figure("base_deflection", "Base deflection while joint 2 turns the stretched arm, against "
           "the joint-2 angle and the gravity torque (thesis Figs. 1.7–1.8, eq. 1.6)", number=8)
num.table("compliance", "Joint compliances identified from the load discs")
num.figure("accuracy_histograms", "Positioning error on the accuracy points (not used for "
           "identification), nominal, geometric and full model", number=9)
num.table("accuracy", "Positioning accuracy of the three models on the accuracy points")
num.table("regions", "RMS positioning error [mm] by workspace region")

ARCSEC = np.pi / 180 / 3600
ds = open_artefact(model)
acc = pd.read_csv(accuracy).set_index("model")
reg = pd.read_csv(regions)
pts = pd.read_csv(points)
je = pd.read_csv(joint_errors)
bd = pd.read_csv(base)
cir = pd.read_csv(circles)
cal = model_from_dataset(ds)

# %% [markdown]
# ## A joint circle and its axis

# %%
display(Markdown(
    f"{num.ref('joint_circle')} shows the targets of joint 2 in their circle plane (u, v about "
    "the fitted centre) and the distance of every joint's targets from their fitted circle."))
fig, axs = plt.subplots(1, 2, figsize=(10, 4.2))
g = cir[cir["joint"] == 2]
t = np.linspace(0, 2 * np.pi, 400)
r = float(ds["circle_radius_mm"].sel(joint=2))
axs[0].plot(r * np.cos(t), r * np.sin(t), "-", color="0.7", label="fitted circle")
axs[0].plot(g["u_mm"], g["v_mm"], "o", ms=3, label="C-Track target")
axs[0].plot(0, 0, "k+", ms=12, label="centre O_2 (axis e_2 out of the page)")
axs[0].set_aspect("equal")
axs[0].set_xlabel("u [mm]")
axs[0].set_ylabel("v [mm]")
axs[0].legend(fontsize=8)
for j, gj in cir.groupby("joint"):
    axs[1].plot(gj["q_deg"], 1000 * np.hypot(gj["radial_residual_mm"], gj["normal_residual_mm"]),
                ".", ms=3, label=f"joint {j}")
axs[1].set_xlabel("joint angle [deg]")
axs[1].set_ylabel("distance from the fitted circle [µm]")
axs[1].legend(fontsize=7, ncol=2)
fig.suptitle("Single-joint method: circle of joint 2 and the residuals of every joint")
save_figure(fig, fig_dir, num.file("joint_circle"))
plt.show()
display(num.caption("joint_circle"))
display(Markdown(say("circles")))

# %% [markdown]
# ## The vector model

# %%
display(Markdown(
    f"{num.ref('vector_model')} joins the identified centres O_i by the vectors a'_i at the "
    "home configuration, and shows the same chain with joint 1 turned by 90° (eq. 1.4: "
    f"a_i = R_1…R_i a'_i); {num.ref('a_prime')} lists the vectors."))
geo = cal.geometry
fig = plt.figure(figsize=(7, 6))
ax = fig.add_subplot(projection="3d")
for th1, style in ((0.0, "o-"), (np.pi / 2, "s--")):
    q = np.zeros(6)
    q[0] = th1
    e, o = geo.joint_lines(q)
    chain = np.vstack([[0, 0, 0], o, geo.tcp(q)])
    ax.plot(*chain.T, style, label=f"θ1 = {np.rad2deg(th1):.0f}°")
    for k in range(6):
        ax.quiver(*o[k], *(150 * e[k]), color="C3", lw=1)
ax.set_xlabel("x [mm]")
ax.set_ylabel("y [mm]")
ax.set_zlabel("z [mm]")
ax.legend()
ax.set_title("Centres O_i, vectors a'_i and axes e_i (red)")
save_figure(fig, fig_dir, num.file("vector_model"))
plt.show()
display(num.caption("vector_model"))
a = ds["a_prime_mm"].to_pandas()
a["|a'| [mm]"] = np.linalg.norm(a.to_numpy(), axis=1)
display(num.caption("a_prime"))
display(a.round(3))

# %% [markdown]
# ## Joint positioning errors and their regression

# %%
display(Markdown(
    f"{num.ref('joint_errors')}: each step position is the mean of both approach directions "
    "(backlash cancels). The model is Fourier terms at the gear orders plus a low-order "
    "polynomial; the degree is chosen on the held-out steps (every 4th), and three candidate "
    "forms are compared there."))
fig, axs = plt.subplots(2, 3, figsize=(12, 6), sharex=False)
for ax, (j, g) in zip(axs.ravel(), je.groupby("joint"), strict=False):
    q = np.rad2deg(g["q_rad"])
    ax.plot(q, g["error_rad"] / ARCSEC, ".", ms=1, color="0.6", label="measured (eq. 1.5)")
    ho = g[g["held_out"].astype(bool)]
    ax.plot(np.rad2deg(ho["q_rad"]), ho["error_rad"] / ARCSEC, ".", ms=1, color="C1",
            label="held out")
    ax.plot(q, g["model_rad"] / ARCSEC, "-", color="C0", lw=1, label="regression")
    ax.set_title(f"joint {j}")
    ax.set_xlabel("q [deg]")
    ax.set_ylabel("error [arcsec]")
axs[0, 0].legend(fontsize=7)
fig.suptitle("Joint positioning errors (measured − commanded) and the regression model")
save_figure(fig, fig_dir, num.file("joint_errors"))
plt.show()
display(num.caption("joint_errors"))
val = ds["error_validation_rms_rad"].to_pandas() / ARCSEC
val["chosen degree"] = ds["error_degree"].values
val["backlash [arcsec]"] = ds["backlash_rad"].values / ARCSEC
display(num.caption("validation"))
display(val.round(2))

# %%
display(Markdown(say("regression", ref_validation=num.ref("validation"))))

# %% [markdown]
# ## Base deflection versus joint-2 rotation (eq. 1.6)

# %%
c_base = float(ds["base_compliance_rad_per_Nm"])
r2 = float(ds["base_fit_r2"])
# the cell file may state no mass model: then the calibration ran without the gravity term
GRAVITY = bool(found.values()["has_gravity_model"])
fig, axs = plt.subplots(1, 2 if GRAVITY else 1, figsize=(10 if GRAVITY else 5, 4), squeeze=False)
axs = axs[0]
axs[0].plot(np.rad2deg(bd["q2_rad"]), bd["deflection_rad"] / ARCSEC, "o")
axs[0].set_xlabel("joint-2 angle, arm stretched [deg]")
axs[0].set_ylabel("base deflection δθ_base [arcsec]")
if GRAVITY:
    axs[1].plot(bd["tau2_Nm"], bd["deflection_rad"] / ARCSEC, "o", label="eq. 1.6")
    x = np.linspace(bd["tau2_Nm"].min(), bd["tau2_Nm"].max(), 10)
    axs[1].plot(x, c_base * x / ARCSEC, "-", label=f"linear fit, R² = {r2:.3f}")
    axs[1].set_xlabel("joint-2 gravity torque change [N·m]")
    axs[1].set_ylabel("base deflection [arcsec]")
    axs[1].legend()
fig.suptitle("Base deflection while joint 2 turns the stretched arm")
save_figure(fig, fig_dir, num.file("base_deflection"))
plt.show()
display(num.caption("base_deflection"))
c = ds["compliance_rad_per_Nm"].values
display(Markdown(say("base", "base_share", ref_base_deflection=num.ref("base_deflection"),
                     ref_compliance=num.ref("compliance"))))
comp = pd.DataFrame({"compliance [µrad/(N·m)]": c * 1e6,
                     "identifiable": ds["compliance_identifiable"].values.astype(bool),
                     "torque at home [N·m]": ds["tau_home_Nm"].values},
                    index=pd.Index(ds["joint"].values, name="joint"))
display(num.caption("compliance"))
display(comp.round(3))

# %% [markdown]
# ## Accuracy before and after calibration

# %%
fig, ax = plt.subplots()
bins = np.linspace(0, pts[["err_nominal_mm"]].to_numpy().max() * 1.02, 60)
for m, col in (("nominal", "C3"), ("geometric", "C1"), ("full", "C0")):
    ax.hist(pts[f"err_{m}_mm"], bins=bins, alpha=0.6, color=col, label=m)
ax.set_xlabel("positioning error [mm]")
ax.set_ylabel("points")
ax.set_yscale("log")
ax.legend()
ax.set_title("Positioning error on the accuracy points (not used for identification)")
save_figure(fig, fig_dir, num.file("accuracy_histograms"))
plt.show()
display(num.caption("accuracy_histograms"))
display(num.caption("accuracy"))
display(acc.round(4))

# %%
display(Markdown(say("accuracy", ref_accuracy_histograms=num.ref("accuracy_histograms"),
                     ref_accuracy=num.ref("accuracy"), ref_regions=num.ref("regions"))))

# %%
tab = region_table(reg)
display(num.caption("regions"))
display(tab.round(4))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("against")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
