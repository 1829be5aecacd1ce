# %% [markdown]
# # Chapter 0 — The experiment
#
# The cuts of the run's data (from its manifest), what varies between them, and the
# quantities every later chapter uses: feed per tooth c = v / (N n) and tooth-passing
# frequency N n / 60. Every number stated here comes from the experiment's findings
# (results/ingest/findings.yaml, robomill.experiment_findings); the thesis' cell and its
# feed per tooth close the chapter ("Against the thesis").

# %% tags=["parameters"]
cuts: str = None  # results/ingest/cuts.csv
experiment: dict = None  # the manifest's experiment defaults (spindle_rpm, flutes, ...)
templates: str = None  # robomill/data/templates/ch0.yaml: sentences from findings
findings: str = None  # results/ingest/findings.yaml: every number stated here
fig_dir: str = None  # folder for this chapter's figures

# %%
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import Markdown, display
from matplotlib.patches import Patch

from robomill.findings import read_findings
from robomill.pipeline.captions import Numbering
from robomill.pipeline.design_tables import format_factor, per_cut_table
from robomill.pipeline.prose import Prose, comparison_table, load_templates, render

found = read_findings(findings)
say = Prose(load_templates("ch0", templates), found)
v = found.values()
THESIS_LAYOUT = v["thesis_layout"]  # sets x U segments (+Y, +X, -Y)
table = pd.read_csv(cuts)

num = Numbering.for_chapter("ch0", fig_dir=fig_dir)
num.table("plan", say("caption_plan", grouped_by=say("grouped_by")))
num.figure("feed_per_tooth", say("caption_feed_per_tooth"))

display(Markdown(say("layout", "design", "missing")))
display(Markdown(say("summary", cut_count=say("cut_count"), speed=say("speed"),
                     shown_per=say("shown_per"), ref_plan=num.ref("plan"),
                     ref_feed_per_tooth=num.ref("feed_per_tooth"))))

# %% [markdown]
# ## The cut plan

# %%
display(num.caption("plan"))
if THESIS_LAYOUT:
    plan = (table.pivot_table(index=["set", "segment"], columns="direction", values="cut",
                              aggfunc="first")
            .join(table.groupby(["set", "segment"])[["feed_mm_s", "depth_mm",
                                                     "feed_per_tooth_um"]].first()))
else:
    plan = per_cut_table(table, ["feed_per_tooth_um", "tooth_passing_hz"],
                         experiment=experiment)
display(plan.round(3))

# %% [markdown]
# ## Feed per tooth

# %%
if THESIS_LAYOUT:
    fig, ax = plt.subplots()
    for s, grp in table.groupby("set"):
        g = grp.groupby("segment").first()
        ax.plot(g.index, g["feed_per_tooth_um"], "o-",
                label=f"set {s}: depth {g['depth_mm'].iloc[0]:.2f} mm")
    ax.set_xlabel("segment")
    ax.set_ylabel("feed per tooth c [µm]")
    ax.set_title("Feed per tooth c = v / (N n)")
    ax.legend()
else:
    rows = plan.reset_index()
    first = v.get("group_by")
    colour = ({lvl: f"C{i}" for i, lvl in enumerate(rows[first].unique())} if first else {})
    fig, axs = plt.subplots(1, 2, figsize=(10, 3.8), sharey=True)
    y = np.arange(len(rows))
    label = rows["cut"] if "cut" in rows else rows.iloc[:, 0]
    for ax, col, xlabel in ((axs[0], "feed_per_tooth_um", "feed per tooth c [µm]"),
                            (axs[1], "tooth_passing_hz", "tooth-passing frequency [Hz]")):
        ax.barh(y, rows[col], color=[colour.get(lvl, "C0") for lvl in
                                     (rows[first] if first else [None] * len(rows))])
        ax.set_xlabel(xlabel)
    axs[0].set_yticks(y, label)
    axs[0].invert_yaxis()
    if first:
        axs[1].legend(handles=[Patch(color=c, label=format_factor(first, lvl))
                               for lvl, c in colour.items()], fontsize=8, title=first)
    fig.suptitle("Feed per tooth c = v / (N n) and tooth passing N n / 60, per cut")
    fig.tight_layout()
num.show(fig, "feed_per_tooth")
group_lines = [render(say.templates["group"], g) for g in v.get("groups") or []]
display(Markdown(say("by_group", "same_feed", ref_feed_per_tooth=num.ref("feed_per_tooth"),
                     group_lines=group_lines)))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("against", "against_rows")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
