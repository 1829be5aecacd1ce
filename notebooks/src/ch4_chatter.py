# %% [markdown]
# # Chapter 4 — Chatter
#
# The thesis names regenerative chatter and mode coupling (§3.3) but gives no vibration model
# and no chatter-free parameters. This chapter supplies them: stability lobes for any machine
# by two independent methods (zero-order analytical, Altintas & Budak; a spectral-element
# time-domain discretization, Khasawneh & Mann 2011, converged at every speed to
# `chatter.accuracy` and stored with its error), the time-domain robot–tool–surface model of
# seed 002 with FFT chatter detection and adaptive depth, and the lobes and recommendations for
# the thesis robot from the modes and cutting coefficients this pipeline identified.
#
# **Conventions.** x = feed direction, y = normal direction (the seed's z); the cutter angle φ
# is measured clockwise from +y; up-milling enters at φ = 0, down-milling exits at φ = π;
# slotting is radial immersion 1.0. Chip h = (Δx sin φ + Δy cos φ) g(φ), Δ = current minus
# one-tooth-period-delayed displacement.

# %% tags=["parameters"]
cases: list = None  # results/chatter/cases/<name>.nc
simulation: str = None  # results/chatter/simulation.nc
lobes: str = None  # results/chatter/lobes.nc
recommendations: str = None  # results/chatter/recommendations.csv
templates: str = None  # notebooks/templates/ch4.yaml: the sentences of this chapter
findings: str = None  # results/chatter/findings.yaml: every number and verdict stated here
fig_dir: str = None  # folder for this chapter's figures
thesis_study: bool = None  # unused: the comparison rows come with the findings

# %%
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import Markdown, display

from robomill.chatter.report import coupling_table, onset_table
from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.prose import Prose, comparison_table, load_templates
from robomill.plotting import save_figure

found = read_findings(findings)
say = Prose(load_templates("ch4", templates), found)

if isinstance(cases, str):
    cases = [cases]
case_ds = {open_artefact(p).attrs["case_name"]: open_artefact(p) for p in cases}
sim = open_artefact(simulation)
th = open_artefact(lobes)
rec = pd.read_csv(recommendations)
name = "insperger2004_down005" if "insperger2004_down005" in case_ds else next(iter(case_ds))
HAS_SLOT = "insperger2004_slot" in case_ds

num = Numbering("4")
num.figure("benchmark_lobes", f"Stability lobes of case {name}: zero-order and spectral "
           "element, flip lobes marked", number=1, part="a", stem="fig4_1_benchmark_lobes")
num.figure("benchmark_error", f"Case {name}: estimated discretization error of the spectral "
           "element per speed, against chatter.accuracy", number=1, part="b",
           stem="fig4_1b_benchmark_error")
if HAS_SLOT:
    num.figure("slot", "Slotting benchmark (insperger2004_slot): zero-order and spectral "
               "element agree", number=2, stem="fig4_2_slotting_agreement")
num.figure("seed_lobes", "Seed 002: lobes of the closed-loop tool point (ZOA and SDM), a* and "
           "the two operating points", number=3, stem="fig4_3_seed_lobes")
num.figure("seed_time", "Seed 002: tool vibration x_s over time in the three runs", number=4,
           stem="fig4_4_seed_time_histories")
num.figure("seed_spectra", "Seed 002: amplitude spectrum of the resultant horizontal force, "
           "last window", number=5, stem="fig4_5_seed_spectra")
num.figure("detection", "Seed 002: chatter indicator per window; red: the adaptations of the "
           "logic block", number=6, stem="fig4_6_detection")
num.figure("thesis_lobes", "The identified robot: lobes per slot direction with the "
           "spectral element's error band; red: the configured depths, dotted: its spindle "
           "speed", number=7, stem="fig4_7_thesis_lobes")
num.table("onset", "Time domain against the lobes just below and above the SDM boundary",
          number=1)
num.table("coupling", "Mode coupling and regenerative chatter per slot direction, beside the "
          "force peaks", number=2)
num.table("recommendations", "Stability margins of the configured cuts and the "
          "recommended chatter-free depths", number=3)

# %% [markdown]
# ## 4.1 Lobes for any machine: the published benchmark
#
# Case `insperger2004_down005` is the 1-DOF benchmark of Insperger & Stépán (2004), also
# computed by Ding et al. (2010).

# %%
display(Markdown(say("bench_case")))
ds = case_ds[name]
rpm = ds.spindle_rpm.values
a_z = ds.a_crit_mm.sel(solver="zoa").values
a_s = ds.a_crit_mm.sel(solver="sem").values
err = ds.a_crit_error_mm.values
kind = ds.bifurcation.values.astype(str)
fig, ax = plt.subplots()
ax.plot(rpm, a_z, "-", color="0.5", label="zero-order (ZOA)")
ax.plot(rpm, a_s, "k-", lw=1.2,
        label=f"spectral element (error ≤ {100 * ds.attrs['accuracy']:.1f} %)")
flip = kind == "flip"
ax.plot(rpm[flip], a_s[flip], "r.", ms=4, label="flip (period doubling)")
ax.set_xlabel("spindle speed [rpm]")
ax.set_ylabel("critical axial depth [mm]")
ax.set_ylim(0, ds.attrs["depth_max_mm"])
ax.set_title(f"Case {name}")
ax.legend()
save_figure(fig, fig_dir, num.file("benchmark_lobes"))
plt.show()
display(num.caption("benchmark_lobes"))
display(Markdown(say("bench_lobes", "bench_flip",
                     ref_benchmark_lobes=num.ref("benchmark_lobes"))))

# %% [markdown]
# **How converged is it?** Each depth carries its estimated discretization error
# `a_crit_error_mm`: the difference between the collocation orders p − 2 and p at which it
# was accepted, plus the root tolerance. The method converges spectrally (the error falls more
# than tenfold per two added nodes on this benchmark, tests/test_chatter_sem.py), so the
# estimate bounds the error of the reported value by a wide margin.

# %%
display(Markdown(say("convergence_sources")))
rel = 100 * err / a_s
fig, ax = plt.subplots()
ax.semilogy(rpm, rel, "k.", ms=3, label="estimated error of the spectral element")
ax.axhline(100 * ds.attrs["accuracy"], color="r", ls="--", label="chatter.accuracy")
ax.set_xlabel("spindle speed [rpm]")
ax.set_ylabel("relative error of a_crit [%]")
ax.set_title(f"Case {name}: discretization error per speed")
ax.legend()
save_figure(fig, fig_dir, num.file("benchmark_error"))
plt.show()
display(num.caption("benchmark_error"))
display(Markdown(say("bench_error", "bench_checks",
                     ref_benchmark_error=num.ref("benchmark_error"))))

# %% [markdown]
# Slotting (`insperger2004_slot`, symmetric x/y, 4 teeth): the directional matrix is nearly
# constant, so the zero-order method is accurate and both methods must agree.

# %%
if HAS_SLOT:
    sl = case_ds["insperger2004_slot"]
    az, asd = (sl.a_crit_mm.sel(solver=s).values for s in ("zoa", "sem"))
    fig, ax = plt.subplots()
    ax.plot(sl.spindle_rpm, az, color="0.5", label="ZOA")
    ax.plot(sl.spindle_rpm, asd, "k--", label="spectral element")
    ax.set_xlabel("spindle speed [rpm]")
    ax.set_ylabel("critical axial depth [mm]")
    ax.legend()
    save_figure(fig, fig_dir, num.file("slot"))
    plt.show()
    display(num.caption("slot"))
display(Markdown(say("slot", ref_slot=num.ref("slot") if HAS_SLOT else "")))

# %% [markdown]
# ## 4.2 Seed 002: robot–tool–surface in the time domain
#
# The seed's model (its parameters below, from `chatter.seed`). The lobes below use the
# closed-loop horizontal tool-point dynamics (arm + velocity PID + suspension); the seed drew
# its diagram by D-partition, which is the frequency-domain (zero-order) boundary. This
# diagram, the seed's boundary at n and the onset checks use the first-order
# semi-discretization (SDM) with `chatter.seed.sdm_steps_per_period` steps.

# %%
display(Markdown(say("seed_model")))
sp = sim.spindle_rpm.values
fig, ax = plt.subplots()
ax.plot(sp, sim.seed_a_crit_mm.sel(solver="zoa"), color="0.5", label="ZOA (D-partition)")
ax.plot(sp, sim.seed_a_crit_mm.sel(solver="sdm"), "k-", label="SDM")
ax.axhline(sim.attrs["a_star_mm"], color="b", ls=":", label="a* (stable at every speed)")
n0 = sim.attrs["spindle_rpm_seed"]
ax.plot([n0], [sim.attrs["point1_depth_mm"]], "go", label="point 1")
ax.plot([n0], [sim.attrs["point2_depth_mm"]], "rs", label="point 2")
ax.set_xlabel("spindle speed n [rpm]")
ax.set_ylabel("critical axial depth a_cr [mm]")
ax.legend()
save_figure(fig, fig_dir, num.file("seed_lobes"))
plt.show()
display(num.caption("seed_lobes"))
display(Markdown(say("seed_lobes", "seed_sdm_error", ref_seed_lobes=num.ref("seed_lobes"))))

# %%
fig, axes = plt.subplots(3, 1, figsize=(7.5, 8), sharex=True)
for ax, run in zip(axes, sim.run.values, strict=True):
    ax.plot(sim.time, sim.xs_vib_um.sel(run=run), lw=0.4)
    ax.set_ylabel("x_s [µm]")
    ax.set_title(str(run))
axes[-1].set_xlabel("t [s]")
save_figure(fig, fig_dir, num.file("seed_time"))
plt.show()
display(num.caption("seed_time"))

fig, ax = plt.subplots()
for run in sim.run.values:
    ax.plot(sim.frequency, sim.spectrum_N.sel(run=run), lw=0.8, label=str(run))
ax.set_xlim(0, 600)
ax.set_xlabel("frequency [Hz]")
ax.set_ylabel("amplitude of R [N]")
ax.set_title("Amplitude spectrum of the resultant horizontal force, last window")
ax.legend()
save_figure(fig, fig_dir, num.file("seed_spectra"))
plt.show()
display(num.caption("seed_spectra"))

fig, ax = plt.subplots()
for run in sim.run.values:
    ax.semilogy(sim.window_end, sim.indicator_N.sel(run=run), label=str(run))
for t_a in np.atleast_1d(sim.attrs["adaptation_times_s"]):
    ax.axvline(t_a, color="r", ls=":")
ax.set_xlabel("end of window [s]")
ax.set_ylabel("chatter indicator [N]")
ax.legend()
save_figure(fig, fig_dir, num.file("detection"))
plt.show()
display(num.caption("detection"))

# %%
display(Markdown(say("seed_runs", "point1", "point2", ref_seed_time=num.ref("seed_time"),
                     ref_seed_spectra=num.ref("seed_spectra"),
                     ref_detection=num.ref("detection"))))
display(Markdown(say("why_frequency", "growth", "settling", sep="\n\n")))

# %% [markdown]
# **Time domain vs lobes.** Fixed-setpoint simulations just below and above the SDM boundary,
# with the growth rate of the unstable ones beside the SDM Floquet exponent σ = ln ρ/τ
# (negative σ: how fast a disturbance decays):

# %%
onset = onset_table(sim)
display(Markdown(say("onset", ref_onset=num.ref("onset"))))
display(num.caption("onset"))
onset.round(4)

# %%
display(Markdown(say("robot_title")))
fig, axes = plt.subplots(1, 3, figsize=(11, 3.8), sharey=True)
for ax, d in zip(axes, th.direction.values, strict=True):
    ax.plot(th.spindle_rpm, th.a_crit_mm.sel(direction=d, solver="zoa"), "-", label="zoa")
    a_d = th.a_crit_mm.sel(direction=d, solver="sem")
    e_d = th.a_crit_error_mm.sel(direction=d)
    ax.plot(th.spindle_rpm, a_d, "--", label="sem")
    ax.fill_between(th.spindle_rpm, a_d - e_d, a_d + e_d, color="C1", alpha=0.3,
                    label="sem ± error")
    for dep in np.atleast_1d(th.attrs["thesis_depths_mm"]):
        ax.axhline(dep, color="r", lw=0.6)
    ax.axvline(th.attrs["thesis_spindle_rpm"], color="0.6", ls=":")
    ax.set_title(f"slot {d}")
    ax.set_xlabel("spindle speed [rpm]")
axes[0].set_ylabel("critical axial depth [mm]")
axes[0].legend()
save_figure(fig, fig_dir, num.file("thesis_lobes"))
plt.show()
display(num.caption("thesis_lobes"))

# %%
display(Markdown(say("robot_lobes", ref_thesis_lobes=num.ref("thesis_lobes"))))

# %%
mc = coupling_table(th)
display(Markdown(f"{num.ref('coupling')}: the mode-coupling limit per slot direction and the "
                 "coupled pair of modes, beside the regenerative chatter frequency."))
display(num.caption("coupling"))
mc.round(3)

# %%
display(Markdown(say("recommendations_intro", ref_recommendations=num.ref("recommendations"))))
display(num.caption("recommendations"))
rec.round(3)

# %%
display(Markdown(say("choices", "choice_lines", sep="\n")))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("against", ref_coupling=num.ref("coupling"))))
comparison_table(found) if found.comparisons else None

# %%
num.check()
