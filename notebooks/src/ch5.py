# %% [markdown]
# # Chapter 5 — Stiffness along the cuts
#
# How stiff the robot was where it cut: the joint-stiffness model (Yi 2025's; its method
# and its reproduction on the seed's robot: chapter 6.2) with the joint stiffness identified
# from this cell's own load tests, evaluated at the middle of every cut along the feed, the
# in-plane normal (the wall) and the tool axis (the floor). For the thesis' design, both
# models of the thesis robot per slot direction, beside the waviness of Table 2.1.

# %% tags=["parameters"]
slots: str = None  # results/stiffness/thesis_slots.csv (thesis design only)
waviness: str = None  # results/surface/table_2_1_waviness_rms.csv (thesis design only)
cut_stiffness: str = None  # results/stiffness/cut_stiffness.csv (other designs; cell robot tested)
cuts: str = None  # results/ingest/cuts.csv (with cut_stiffness)
templates: str = None  # robomill/data/templates/ch5.yaml: sentences from findings
findings: str = None  # results/stiffness/findings.yaml: every number and verdict stated here
experiment: dict = None  # the manifest's experiment defaults (spindle_rpm, flutes, ...)
fig_dir: str = None  # folder for this chapter's figures

# %%
import pandas as pd
from IPython.display import Markdown, display

from robomill.findings import read_findings
from robomill.pipeline.captions import Numbering
from robomill.pipeline.design_tables import per_cut_table
from robomill.pipeline.prose import Prose, load_templates
from robomill.stiffness.cuts import slot_stiffness_table
from robomill.stiffness.figures import slots_figure
from robomill.stiffness.tables import cut_stiffness_um

found = read_findings(findings)
say = Prose(load_templates("ch5", templates), found)
v = found.values()
SLOTS, CUTS_K = v["has_slots"], v["has_cut_stiffness"]

num = Numbering.for_chapter("ch5", fig_dir=fig_dir)
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
# ## 5.1 Along the feed, the wall and the floor

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
    num.show(fig, "thesis_slots")

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("against")))

# %%
num.check()
