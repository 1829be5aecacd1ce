# %% [markdown]
# # Chapter 0 — The experiment
#
# An ABB IRB 1600-6/1.45 robot slot-milled an Al 6061-T6 block on a Kistler 9255B dynamometer
# with a 2-flute end mill (thesis §2.1). Three sets of five U-shaped segments; each segment is
# three straight cuts, **+Y, +X, −Y**. This chapter lists the cuts of the run's data (from its
# manifest) and the quantities every later chapter uses: feed per tooth and tooth-passing
# frequency.

# %% tags=["parameters"]
cuts: str = None  # results/ingest/cuts.csv
fig_dir: str = None  # folder for this chapter's figures

# %%
import matplotlib.pyplot as plt
import pandas as pd
from IPython.display import Markdown, display

from robomill.pipeline.captions import Numbering
from robomill.plotting import save_figure

num = Numbering("0")
num.table("plan", "The cut plan: the cuts of every segment, its feed, depth and feed per tooth")
num.figure("feed_per_tooth", "Feed per tooth c = v / (N n) of every segment, per set")

table = pd.read_csv(cuts)
n_sets = table["set"].nunique()
spindle_hz = table["spindle_hz"].iloc[0]
tooth_hz = table["tooth_passing_hz"].iloc[0]
display(Markdown(
    f"**{len(table)} cuts** in {n_sets} sets; spindle {spindle_hz:.1f} Hz "
    f"({60 * spindle_hz:.0f} rpm), tooth passing {tooth_hz:.1f} Hz. Feed per tooth ranges from "
    f"{table.feed_per_tooth_um.min():.2f} µm to {table.feed_per_tooth_um.max():.2f} µm "
    f"(thesis: 1.07 µm at 1 mm/s, 10.7 µm at 10 mm/s). {num.ref('plan')} lists the cuts and "
    f"{num.ref('feed_per_tooth')} shows the feed per tooth of every segment."
))

# %% [markdown]
# ## The cut plan

# %%
display(num.caption("plan"))
plan = (table.pivot_table(index=["set", "segment"], columns="direction", values="cut",
                          aggfunc="first")
        .join(table.groupby(["set", "segment"])[["feed_mm_s", "depth_mm",
                                                 "feed_per_tooth_um"]].first()))
display(plan.round(3))

# %% [markdown]
# ## Feed per tooth of every segment

# %%
fig, ax = plt.subplots()
for s, grp in table.groupby("set"):
    g = grp.groupby("segment").first()
    ax.plot(g.index, g["feed_per_tooth_um"], "o-",
            label=f"set {s}: depth {g['depth_mm'].iloc[0]:.2f} mm")
ax.set_xlabel("segment")
ax.set_ylabel("feed per tooth c [µm]")
ax.set_title("Feed per tooth c = v / (N n)")
ax.legend()
save_figure(fig, fig_dir, num.file("feed_per_tooth"))
plt.show()
display(num.caption("feed_per_tooth"))
num.check()
