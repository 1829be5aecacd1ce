# %% [markdown]
# # Chapter 0 — The experiment
#
# The cuts of the run's data (from its manifest), what varies between them, and the
# quantities every later chapter uses: feed per tooth c = v / (N n) and tooth-passing
# frequency N n / 60.

# %% tags=["parameters"]
cuts: str = None  # results/ingest/cuts.csv
experiment: dict = None  # the manifest's experiment defaults (spindle_rpm, flutes, ...)
thesis_design: bool = None  # the thesis' design (robomill.experiment.is_thesis_design)
thesis_study: bool = None  # the thesis' study (robomill.experiment.is_thesis_study)
fig_dir: str = None  # folder for this chapter's figures

# %%
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import Markdown, display
from matplotlib.patches import Patch

from robomill.pipeline.captions import Numbering
from robomill.pipeline.design_tables import (
    describe_design,
    design_factors,
    format_factor,
    per_cut_table,
    thesis_gate,
    with_design,
)
from robomill.plotting import save_figure

vs_thesis = thesis_gate(thesis_study)
THESIS_LAYOUT = thesis_design is not False  # sets x U segments (+Y, +X, -Y)
table = pd.read_csv(cuts)
design = design_factors(table, experiment)

num = Numbering("0")
if THESIS_LAYOUT:
    num.table("plan", "The cut plan: the cuts of every segment, its feed, depth and feed per "
              "tooth")
    num.figure("feed_per_tooth", "Feed per tooth c = v / (N n) of every segment, per set")
else:
    num.table("plan", "The cut plan: every cut, grouped by what varies ("
              + (", ".join(design.grouping) or "nothing") + "), with its feed per tooth and "
              "tooth-passing frequency")
    num.figure("feed_per_tooth", "Feed per tooth c = v / (N n) and tooth-passing frequency "
               "of every cut, grouped by what varies")

if THESIS_LAYOUT:
    display(Markdown(
        "An ABB IRB 1600-6/1.45 robot slot-milled an Al 6061-T6 block on a Kistler 9255B "
        "dynamometer with a 2-flute end mill (thesis §2.1). Three sets of five U-shaped "
        "segments; each segment is three straight cuts, **+Y, +X, −Y**."
        if vs_thesis.shown else
        "The cuts follow the thesis' layout (ids `s{set}_g{segment}_{dir}`: sets of U-shaped "
        "segments, directions px, py, my) with this study's own process."))
display(Markdown(f"**Design:** {describe_design(table, experiment)}."))
spindle_hz = table["spindle_hz"]
tooth_hz = table["tooth_passing_hz"]
speed = (f"spindle {spindle_hz.iloc[0]:.1f} Hz ({60 * spindle_hz.iloc[0]:.0f} rpm), tooth "
         f"passing {tooth_hz.iloc[0]:.1f} Hz" if spindle_hz.nunique() == 1 and
         tooth_hz.nunique() == 1 else
         f"spindle {60 * spindle_hz.min():.0f}–{60 * spindle_hz.max():.0f} rpm, tooth passing "
         f"{tooth_hz.min():.1f}–{tooth_hz.max():.1f} Hz")
groups = (f" in {table['set'].nunique()} sets" if THESIS_LAYOUT and "set" in table else "")
display(Markdown(
    f"**{len(table)} cuts**{groups}; {speed}. Feed per tooth ranges from "
    f"{table.feed_per_tooth_um.min():.2f} µm to {table.feed_per_tooth_um.max():.2f} µm"
    + vs_thesis(" (thesis: 1.07 µm at 1 mm/s, 10.7 µm at 10 mm/s)")
    + f". {num.ref('plan')} lists the cuts and {num.ref('feed_per_tooth')} shows the feed "
    "per tooth of every " + ("segment." if THESIS_LAYOUT else "cut.")))

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
    first = design.grouping[0] if design.grouping else None
    colour = ({v: f"C{i}" for i, v in enumerate(rows[first].unique())} if first else {})
    fig, axs = plt.subplots(1, 2, figsize=(10, 3.8), sharey=True)
    y = np.arange(len(rows))
    label = rows["cut"] if "cut" in rows else rows.iloc[:, 0]
    for ax, col, xlabel in ((axs[0], "feed_per_tooth_um", "feed per tooth c [µm]"),
                            (axs[1], "tooth_passing_hz", "tooth-passing frequency [Hz]")):
        ax.barh(y, rows[col], color=[colour.get(v, "C0") for v in
                                     (rows[first] if first else [None] * len(rows))])
        ax.set_xlabel(xlabel)
    axs[0].set_yticks(y, label)
    axs[0].invert_yaxis()
    if first:
        axs[1].legend(handles=[Patch(color=c, label=format_factor(first, v))
                               for v, c in colour.items()], fontsize=8, title=first)
    fig.suptitle("Feed per tooth c = v / (N n) and tooth passing N n / 60, per cut")
    fig.tight_layout()
save_figure(fig, fig_dir, num.file("feed_per_tooth"))
plt.show()
display(num.caption("feed_per_tooth"))
if not THESIS_LAYOUT:
    filled = with_design(table, experiment)
    display(Markdown(
        f"{num.ref('feed_per_tooth')}: "
        + "; ".join(f"{format_factor(first, v)}: c {g.feed_per_tooth_um.min():.2f}–"
                    f"{g.feed_per_tooth_um.max():.2f} µm, tooth passing "
                    f"{g.tooth_passing_hz.min():.0f}–{g.tooth_passing_hz.max():.0f} Hz"
                    for v, g in filled.groupby(first, sort=True)) + "."
        if design.grouping else
        f"{num.ref('feed_per_tooth')}: every cut has the same feed per tooth."))
num.check()
