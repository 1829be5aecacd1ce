# %% [markdown]
# # Chapter 3.1 — Cutting forces
#
# The Kistler dynamometer under the block recorded Fx, Fy, Fz during every cut (thesis §3.1).
# The mechanistic model for a small axial depth (thesis eq. 3.1) gives each tooth's forces
# F_t = K_tc a h(φ) + K_te a, F_r = K_rc a h(φ) + K_re a, F_a = K_ac a h(φ) + K_ae a with
# h(φ) = c sin φ between each tooth's entry and exit angles (0 and π in a slot); the force is
# periodic at the tooth-passing frequency of each cut's own spindle speed and flutes. This
# chapter shows the model shape, a record and its full-band spectrum, the spectra in spatial
# and in time frequency, the per-cut peak table, and the cutting coefficients identified from
# the mean forces; what the thesis finds closes it ("Against the thesis").
# Forces are on the tool, in the block axes (docs/data-contract.md).

# %% tags=["parameters"]
spectra: str = None  # results/forces/spectra.nc
peaks: str = None  # results/forces/peaks.csv
coefficients: str = None  # results/forces/cutting_coefficients.csv
means: str = None  # results/forces/mean_forces.csv
harmonics: str = None  # results/forces/harmonics.csv
cuts: str = None  # results/ingest/cuts.csv
modes: str = None  # results/modal/modes.csv (identified modes, chapter 3.3)
templates: str = None  # robomill/data/templates/ch3_forces.yaml: sentences from findings
findings: str = None  # results/forces/findings.yaml: every number and verdict stated here
truth: str = None  # results/synthetic/truth.nc (synthetic runs only)
settings: dict = None  # config section forces
experiment: dict = None  # the manifest's experiment defaults (spindle_rpm, flutes, ...)
fig_dir: str = None  # folder for this chapter's figures

# %%
import os

import pandas as pd
from IPython.display import Markdown, display

from robomill.findings import read_findings
from robomill.forces import figures
from robomill.forces.tables import (
    coefficient_table,
    direction_text,
    harmonic_table,
    peak_table,
    planted_coefficients,
    process_table,
)
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.design_tables import per_cut_table
from robomill.pipeline.prose import Prose, comparison_table, load_templates

found = read_findings(findings)
F = found.values()
say = Prose(load_templates("ch3_forces", templates), found)
sp = open_artefact(spectra)
mf = pd.read_csv(means)
plan = pd.read_csv(cuts) if cuts else mf
mode_table = pd.read_csv(modes) if modes and os.path.exists(modes) else None
planted = planted_coefficients(open_artefact(truth) if truth and os.path.exists(truth)
                               else None)
CUTS, DIRS, THESIS_LAYOUT = F["figure_cuts"], F["figure_directions"], F["thesis_layout"]
# a design that cannot identify the coefficients (one feed per tooth, < 3 cuts): no model shape
IDENTIFIED = not F.get("coefficients_not_identified")

# thesis numbers (Figs 3.2–3.11, Tables 3.1, 3.3, 3.4; Table 3.2 is in chapter 3.2)
num = Numbering.for_chapter("ch3_forces", fig_dir=fig_dir)
if IDENTIFIED:
    num.figure("model_force_shape", f"The model's force shape over two revolutions of a "
               f"{say('model_shape')}, with the coefficients identified below (eq. 3.1)",
               number=2)
num.figure("record", "A measured force record: (a) the whole record as a min–max envelope, "
           "(b) a zoom in its middle", number=3)
num.figure("full_band_psd", "Welch PSD of that record over the full band, sum of the axes",
           number=4)
# one figure per direction (thesis Figs 3.5–3.7, 3.8–3.10); any other design Figs 3.5a, b …
for kind, first, stem in (("spatial", 5, "fig3_5_7_spatial"), ("time", 8, "fig3_8_10_time")):
    for k, d in enumerate(DIRS):
        num.figure(f"{kind}_{d}", say(f"cap_{kind}", which=say("which"),
                                      direction=direction_text(d)),
                   number=first + k if THESIS_LAYOUT else first,
                   part="" if THESIS_LAYOUT or len(DIRS) == 1 else "abcdefghijklmnopqrstuvwxyz"[k],
                   stem=f"{stem}_{d.replace(' ', '')}")
num.table("peaks", "Per-cut peaks: dominant low-frequency and kinematic peak, and the nearest "
          "identified mode" + ("" if THESIS_LAYOUT else "; the mean force levels in the cut "
                               "frame; grouped by what varies"), number=1)
num.table("harmonics", "Tooth-passing harmonics: median frequency and power over the cuts"
          " (of each tooth-passing frequency)", number=3)
num.figure("mean_forces_vs_feed", "Mean forces per cut, divided by N·a, against the feed per tooth",
           number=11)
if IDENTIFIED:
    num.table("coefficients", "Identified cutting coefficients with their intervals and their "
              "sanity flags (negative value, fit residual against signal, physical)", number=4)



display(Markdown(say("overview")))

# %% [markdown]
# ## The model's force shape (eq. 3.1)

# %%
display(Markdown(say("model", shape=say("model_shape"),
                     ref_model_force_shape=num.ref("model_force_shape") if IDENTIFIED else "")))
if IDENTIFIED:
    num.show(figures.model_shape_figure(sp), "model_force_shape")

# %% [markdown]
# ## A measured record, its zoom and its full-band spectrum

# %%
num.show(figures.record_figure(sp, CUTS[0]), "record")
num.show(figures.full_band_figure(sp, CUTS[0]), "full_band_psd")
display(Markdown(say("full_band", ref_record=num.ref("record"),
                     ref_full_band_psd=num.ref("full_band_psd"))))

# %% [markdown]
# ## Spectra in spatial frequency (kinematic peak)

# %%
display(Markdown(say("spatial", ref_spatial=", ".join(num.ref(f"spatial_{d}") for d in DIRS))))
kinematic = [F["kinematic_per_mm_median"]] if F.get("kinematic_per_mm_median") else []
for d in DIRS:
    num.show(figures.direction_figure(sp, CUTS, d, spatial=True,
                                  x_max=F["kinematic_band_per_mm"][1], vlines=kinematic,
                                  which=say("which")), f"spatial_{d}")
display(Markdown(say("kinematic", "kinematic_none", "resolution", "kinematic_flag")))

# %% [markdown]
# ## Spectra in time frequency (dominant peak)

# %%
display(Markdown(say("time", ref_time=", ".join(num.ref(f"time_{d}") for d in DIRS))))
for d in DIRS:
    num.show(figures.direction_figure(sp, CUTS, d, spatial=False, x_max=F["lowband_hz"],
                                  vlines=F["modes_hz"] or [], which=say("which")), f"time_{d}")

# %% [markdown]
# ## Per-cut peaks

# %%
display(num.caption("peaks"))
table = peak_table(pd.read_csv(peaks), mf, mode_table, levels=not THESIS_LAYOUT)
display(table if THESIS_LAYOUT else  # any other design: grouped by what varies
        per_cut_table(table, list(table.columns.drop("cut")), plan, experiment))
display(Markdown(say("grouped", "dominant", "dominant_none", "modes", "verdict", "no_match",
                     "no_modes", "levels", ref_peaks=num.ref("peaks"))))

# %% [markdown]
# ## Tooth-passing harmonics

# %%
display(Markdown(say("harmonics", ref_harmonics=num.ref("harmonics"))))
display(num.caption("harmonics"))
display(harmonic_table(pd.read_csv(harmonics), plan))

# %% [markdown]
# ## Cutting-coefficient identification

# %%
display(Markdown(say("mean_forces", ref_mean_forces_vs_feed=num.ref("mean_forces_vs_feed"))))
num.show(figures.mean_forces_figure(process_table(mf, experiment)), "mean_forces_vs_feed")
if IDENTIFIED:
    display(num.caption("coefficients"))
    display(coefficient_table(pd.read_csv(coefficients), planted))
display(Markdown(say("coefficients", "planted", "directions", "directions_agree", "physical",
                     "physical_ok", "uses",
                     ref_coefficients=num.ref("coefficients") if IDENTIFIED else "")))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("thesis_says", "against")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
