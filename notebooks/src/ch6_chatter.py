# %% [markdown]
# # Chapter 6.1 — Reference study: chatter models (published benchmarks and Shagniev 2019)
#
# Reproductions that use no data of this study: stability lobes for any machine by two
# independent methods (zero-order analytical, Altintas & Budak; a spectral-element time-domain
# discretization, Khasawneh & Mann 2011, converged at every speed to `chatter.accuracy` and
# stored with its error) on the published cases of `config.yaml: chatter.cases`, and the
# time-domain robot–tool–surface model of Shagniev 2019 with FFT chatter detection and adaptive
# depth. Chapter 4 applies the same lobe method to the study's own robot.
#
# **Conventions.** x = feed direction, y = normal direction (the seed's z); the cutter angle φ
# is measured clockwise from +y; up-milling enters at φ = 0, down-milling exits at φ = π;
# slotting is radial immersion 1.0. Chip h = (Δx sin φ + Δy cos φ) g(φ), Δ = current minus
# one-tooth-period-delayed displacement.

# %% tags=["parameters"]
cases: list = None  # results/chatter/cases/<name>.nc
simulation: str = None  # results/chatter/simulation.nc
templates: str = None  # robomill/data/templates/ch6_chatter.yaml: the sentences of this chapter
findings: str = None  # results/chatter/findings.yaml: every number and verdict stated here
fig_dir: str = None  # folder for this chapter's figures

# %%
from IPython.display import Markdown, display

from robomill.chatter import figures
from robomill.chatter.findings import load_cases
from robomill.chatter.tables import onset_table
from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.prose import Prose, comparison_table, load_templates

found = read_findings(findings)
F = found.values()
say = Prose(load_templates("ch6_chatter", templates), found)
case_ds = load_cases(cases or [], open_artefact)
bench = case_ds.get(F.get("bench_case"))
slot = case_ds.get("insperger2004_slot") if F.get("has_slot") else None

# chapter 6 is numbered across its three pages (the chapter registry's first_figure/first_table)
num = Numbering.for_chapter("ch6_chatter", fig_dir=fig_dir)
if bench is not None:
    num.figure("benchmark_lobes", f"Stability lobes of case {F['bench_case']}: zero-order and "
               "spectral element, flip lobes marked", number=1, part="a")
    num.figure("benchmark_error", f"Case {F['bench_case']}: estimated discretization error of "
               "the spectral element per speed, against chatter.accuracy", number=1, part="b")
if slot is not None:
    num.figure("slot", "Slotting benchmark (insperger2004_slot): zero-order and spectral "
               "element agree", number=2)
num.figure("seed_lobes", "Shagniev 2019: lobes of the closed-loop tool point (ZOA and SDM), a* and "
           "the two operating points", number=3)
num.figure("seed_time", "Shagniev 2019: tool vibration x_s over time, one panel per run", number=4)
num.figure("seed_spectra", "Shagniev 2019: amplitude spectrum of the resultant horizontal force, "
           "last window", number=5)
num.figure("detection", "Shagniev 2019: chatter indicator per window; red: the adaptations of the "
           "logic block", number=6)
num.table("onset", "Time domain against the lobes just below and above the SDM boundary",
          number=1)
sim = open_artefact(simulation)



# %% [markdown]
# ## 6.1.1 Lobes for any machine: a benchmark case

# %%
display(Markdown(say("bench_case", "bench_published", "bench_diagram")))
if bench is not None:
    num.show(figures.case_lobes_figure(bench), "benchmark_lobes")
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
    num.show(figures.case_error_figure(bench), "benchmark_error")
display(Markdown(say("bench_error", "bench_checks", ref_benchmark_error=num.ref("benchmark_error")
                     if bench is not None else "")))

# %%
display(Markdown(say("slot_case", slot_symmetry=say("slot_symmetry"))))
if slot is not None:
    num.show(figures.slot_figure(slot), "slot")
display(Markdown(say("slot", ref_slot=num.ref("slot") if slot is not None else "")))

# %% [markdown]
# ## 6.1.2 Shagniev 2019: robot–tool–surface in the time domain
#
# The seed's model (its parameters below, from `chatter.seed`). The lobes below use the
# closed-loop horizontal tool-point dynamics (arm + velocity PID + suspension); the seed drew
# its diagram by D-partition, which is the frequency-domain (zero-order) boundary. This
# diagram, the seed's boundary at n and the onset checks use the first-order
# semi-discretization (SDM) with `chatter.seed.sdm_steps_per_period` steps.

# %%
display(Markdown(say("seed_model")))
num.show(figures.seed_lobes_figure(sim), "seed_lobes")
display(Markdown(say("seed_lobes", "seed_sdm_error", ref_seed_lobes=num.ref("seed_lobes"))))
num.show(figures.seed_time_figure(sim), "seed_time")
num.show(figures.seed_spectra_figure(sim), "seed_spectra")
num.show(figures.detection_figure(sim), "detection")
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

# %% [markdown]
# ## Against the sources

# %%
display(Markdown(say("against")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
