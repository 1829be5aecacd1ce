# %% [markdown]
# # Chapter 4 — Chatter
#
# The thesis names regenerative chatter and mode coupling (§3.3) but gives no vibration model
# and no chatter-free parameters. This chapter supplies them for the study's robot: stability
# lobes per slot direction from the modes (chapter 3.3) and cutting coefficients (chapter 3.1)
# this pipeline identified, by the spectral-element method converged at every speed to
# `chatter.accuracy` (the method and its checks on published cases: chapter 6.1), the
# delay-free mode-coupling depth as a diagnostic, and the stability margins of the study's cuts
# with chatter-free depths.

# %% tags=["parameters"]
lobes: str = None  # results/chatter/lobes.nc
recommendations: str = None  # results/chatter/recommendations.csv
templates: str = None  # robomill/data/templates/ch4.yaml: the sentences of this chapter
findings: str = None  # results/chatter/findings.yaml: every number and verdict stated here
fig_dir: str = None  # folder for this chapter's figures
verdicts: str = None  # results/chatter/verdicts.csv: one verdict per cut and record
spectrograms: str = None  # results/chatter/spectrograms.nc: the records' pooled spectrograms
verdict_findings: str = None  # results/chatter/verdict_findings.yaml: the verdicts' findings

# %%
import pandas as pd
from IPython.display import Markdown, display

from robomill.chatter import figures
from robomill.chatter.tables import coupling_table
from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.prose import Prose, load_templates

found = read_findings(findings)
say = Prose(load_templates("ch4", templates), found)
th = open_artefact(lobes)
rec = pd.read_csv(recommendations)

num = Numbering.for_chapter("ch4", fig_dir=fig_dir)
num.figure("thesis_lobes", "The identified robot: lobes per slot direction with the "
           "spectral element's error band; red: the configured depths, dotted: its spindle "
           "speed")
num.table("coupling", "Mode coupling and regenerative chatter per slot direction, beside the "
          "force peaks")
num.table("recommendations", "Stability margins of the configured cuts and the "
          "recommended chatter-free depths")

display(Markdown(say("robot_title")))
num.show(figures.robot_lobes_figure(th), "thesis_lobes")
display(Markdown(say("robot_lobes", ref_thesis_lobes=num.ref("thesis_lobes"))))
display(Markdown(say("axial")))
display(Markdown(say("axial_lines")))

# %%
display(Markdown(say("coupling", ref_coupling=num.ref("coupling"))))
display(num.caption("coupling"))
coupling_table(th).round(3)

# %%
display(Markdown(say("recommendations_intro", ref_recommendations=num.ref("recommendations"))))
display(num.caption("recommendations"))
display(rec.round(3))
display(Markdown(say("choices", "choice_lines", sep="\n")))

# %%
from robomill.chatter.recording_figures import shown_record, spectrogram_figure

vt = pd.read_csv(verdicts)
vs = open_artefact(spectrograms)
hear = Prose(load_templates("ch4", templates), read_findings(verdict_findings))
display(Markdown(hear("recordings_title")))
display(Markdown(hear("recordings_intro", "force_summary")))
shown = shown_record(vt, vs)
if shown is not None:
    num.figure("spectrogram", f"Spectrogram of `{shown}` (pooled cells, largest power of "
               "each): ticks on the right, the tooth-passing harmonics (dotted: the spindle "
               "rotation's where the flutes are unknown); red, the chatter frequency")
    num.show(spectrogram_figure(vs, vt, shown), "spectrogram")
    display(Markdown(hear("spectrogram_ref", ref_spectrogram=num.ref("spectrogram"),
                          shown=shown)))
num.table("verdicts", "Chatter verdict of every record (results/chatter/verdicts.csv)")
display(Markdown(hear("verdicts_ref", ref_verdicts=num.ref("verdicts"))))
display(num.caption("verdicts"))
display(vt[["cut", "verdict", "chatter_hz", "source", "energy_ratio", "line_hz",
            "growth_db_s", "comb_hz", "comb_source", "speeds_rpm"]].round(3))

# %%
display(Markdown(hear("recording_lines")))
display(Markdown(hear("force_lines")))
display(Markdown(hear("forced_lines")))
display(Markdown(hear("comparison")))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("against", ref_coupling=num.ref("coupling"))))

# %%
num.check()
