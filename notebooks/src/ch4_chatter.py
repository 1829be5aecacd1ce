# %% [markdown]
# # Chapter 4 — Chatter
#
# The thesis names regenerative chatter and mode coupling (§3.3) but gives no vibration model
# and no chatter-free parameters. This chapter supplies them: stability lobes for any machine
# by two independent methods (zero-order analytical, Altintas & Budak; a spectral-element
# time-domain discretization, Khasawneh & Mann 2011, converged at every speed to
# `chatter.accuracy` and stored with its error), the time-domain robot–tool–surface model of
# seed 002 with FFT chatter detection and adaptive depth, and the lobes and recommendations for
# the identified robot from the modes and cutting coefficients this pipeline identified.
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
import pandas as pd
from IPython.display import Markdown, display

from robomill.chatter import figures
from robomill.chatter.findings import load_cases
from robomill.chatter.tables import coupling_table, onset_table
from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.prose import Prose, comparison_table, load_templates
from robomill.plotting import save_figure

found = read_findings(findings)
F = found.values()
say = Prose(load_templates("ch4", templates), found)
case_ds = load_cases(cases or [], open_artefact)
bench = case_ds.get(F.get("bench_case"))
slot = case_ds.get("insperger2004_slot") if F.get("has_slot") else None
sim = open_artefact(simulation)
th = open_artefact(lobes)
rec = pd.read_csv(recommendations)

num = Numbering("4")
if bench is not None:
    num.figure("benchmark_lobes", f"Stability lobes of case {F['bench_case']}: zero-order and "
               "spectral element, flip lobes marked", number=1, part="a",
               stem="fig4_1_benchmark_lobes")
    num.figure("benchmark_error", f"Case {F['bench_case']}: estimated discretization error of "
               "the spectral element per speed, against chatter.accuracy", number=1, part="b",
               stem="fig4_1b_benchmark_error")
if slot is not None:
    num.figure("slot", "Slotting benchmark (insperger2004_slot): zero-order and spectral "
               "element agree", number=2, stem="fig4_2_slotting_agreement")
num.figure("seed_lobes", "Seed 002: lobes of the closed-loop tool point (ZOA and SDM), a* and "
           "the two operating points", number=3, stem="fig4_3_seed_lobes")
num.figure("seed_time", "Seed 002: tool vibration x_s over time, one panel per run", number=4,
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


def show(fig, name):
    """Save the figure under this chapter's numbering, show it and its caption."""
    save_figure(fig, fig_dir, num.file(name))
    plt.show()
    display(num.caption(name))


# %% [markdown]
# ## 4.1 Lobes for any machine: a benchmark case

# %%
display(Markdown(say("bench_case", "bench_published", "bench_diagram")))
if bench is not None:
    show(figures.case_lobes_figure(bench), "benchmark_lobes")
display(Markdown(say("bench_lobes", "bench_flip", ref_benchmark_lobes=num.ref("benchmark_lobes")
                     if bench is not None else "")))

# %% [markdown]
# **How converged is it?** Each depth carries its estimated discretization error
# `a_crit_error_mm`: the difference between the collocation orders p − 2 and p at which it
# was accepted, plus the root tolerance. The method converges spectrally (Khasawneh & Mann
# 2011; tests/test_chatter_sem.py checks it on the benchmark), so the estimate bounds the error
# of the reported value.

# %%
display(Markdown(say("convergence_sources")))
if bench is not None:
    show(figures.case_error_figure(bench), "benchmark_error")
display(Markdown(say("bench_error", "bench_checks", ref_benchmark_error=num.ref("benchmark_error")
                     if bench is not None else "")))

# %%
display(Markdown(say("slot_case", slot_symmetry=say("slot_symmetry"))))
if slot is not None:
    show(figures.slot_figure(slot), "slot")
display(Markdown(say("slot", ref_slot=num.ref("slot") if slot is not None else "")))

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
show(figures.seed_lobes_figure(sim), "seed_lobes")
display(Markdown(say("seed_lobes", "seed_sdm_error", ref_seed_lobes=num.ref("seed_lobes"))))
show(figures.seed_time_figure(sim), "seed_time")
show(figures.seed_spectra_figure(sim), "seed_spectra")
show(figures.detection_figure(sim), "detection")
display(Markdown(say("seed_runs", "point1", "point2", ref_seed_time=num.ref("seed_time"),
                     ref_seed_spectra=num.ref("seed_spectra"),
                     ref_detection=num.ref("detection"))))
display(Markdown(say("why_frequency", "growth", "settling", sep="\n\n")))

# %% [markdown]
# **Time domain vs lobes.** Fixed-setpoint simulations just below and above the SDM boundary,
# with the growth rate of the unstable ones beside the SDM Floquet exponent σ = ln ρ/τ
# (negative σ: how fast a disturbance decays):

# %%
display(Markdown(say("onset", ref_onset=num.ref("onset"))))
display(num.caption("onset"))
onset_table(sim).round(4)

# %%
display(Markdown(say("robot_title")))
show(figures.robot_lobes_figure(th), "thesis_lobes")
display(Markdown(say("robot_lobes", ref_thesis_lobes=num.ref("thesis_lobes"))))

# %%
display(Markdown(say("coupling", ref_coupling=num.ref("coupling"))))
display(num.caption("coupling"))
coupling_table(th).round(3)

# %%
display(Markdown(say("recommendations_intro", ref_recommendations=num.ref("recommendations"))))
display(num.caption("recommendations"))
display(rec.round(3))
display(Markdown(say("choices", "choice_lines", sep="\n")))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("against", ref_coupling=num.ref("coupling"))))
comparison_table(found) if found.comparisons else None

# %%
num.check()
