# %% [markdown]
# # Chapter 3.2 — Path straightness and the gear-mesh frequencies
#
# A laser tracker followed a target on the robot flange while the robot moved, without
# cutting, along the cut paths at the cut feeds (thesis §3.2, with a FARO tracker). The
# time series is re-ordered in space: distance along the best straight line, deviation
# perpendicular to it (a horizontal *lateral* and a *vertical* component), resampled on a
# uniform grid. Its spectrum in mm⁻¹ is compared with the spatial frequencies of every gear
# of every joint during that run (revolutions per mm of path, from the joint rates along the
# path), and peaks at a constant *temporal* frequency (a servo ripple) are told apart from
# constant-*spatial*-frequency ones by comparing the feeds. What the thesis finds closes the
# chapter ("Against the thesis").

# %% tags=["parameters"]
peaks: str = None  # results/straightness/peaks.csv
gears: str = None  # results/straightness/gears.csv
profiles: str = None  # results/straightness/profiles.nc
truth_check: str = None  # results/straightness/truth_check.csv
surface_peaks: str = None  # results/surface/peaks.csv (chapter 2)
settings: dict = None  # config straightness section
templates: str = None  # robomill/data/templates/ch3_straightness.yaml: sentences of the findings
findings: str = None  # results/straightness/findings.yaml: every number and verdict stated
fig_dir: str = None  # folder for this chapter's figures

# %%
import pandas as pd
from IPython.display import Markdown, display

from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.design_tables import per_cut_table
from robomill.pipeline.prose import Prose, comparison_table, load_templates
from robomill.straightness.figures import (
    deviation_figure,
    figure_numbers,
    mechanism_figure,
    psd_figure,
)
from robomill.straightness.tables import (
    attribution_table,
    band_floor_table,
    direction_text,
    mesh_table,
    read_peaks,
    run_values_table,
    truth_table,
    with_labels,
)

found = read_findings(findings)
F = found.values()
say = Prose(load_templates("ch3_straightness", templates), found)
prof = open_artefact(profiles)
pk = read_peaks(peaks)
MAIN, EXTRA, HIGH = F["main_directions"], F["extra_directions"], F["high_band_direction"]

# the thesis' numbers (Figs 3.12–3.17, Tables 3.2, 3.5–3.8; 3.1, 3.3, 3.4 are in chapter 3.1)
num = Numbering.for_chapter("ch3_straightness", fig_dir=fig_dir)
for key, (number, part, stem) in figure_numbers(F["directions"], F["thesis_layout"]).items():
    kind, d = key.split("_", 1)
    num.figure(key, say(f"cap_{kind}", direction=direction_text(d)), number=number,
               part=part, stem=stem)
num.figure("psd_high", say("cap_high", direction=direction_text(HIGH)), number=16,
           stem=f"fig3_16_psd_high_{HIGH.replace(' ', '')}")
num.table("band_floor", "Peak-to-floor ratio of the motion spectrum in the surface band and "
          "in an equally wide band where nothing is expected", number=5)
num.figure("temporal_vs_spatial", "Peaks by mechanism: spatial and temporal frequency against "
           "feed", number=17)
num.table("mesh", "Mesh spatial frequencies [mm⁻¹] of every gear stage, per direction",
          number=6)
num.table("attribution", "Peak → gear attribution, and presence on the surface", number=2)
if not F["thesis_layout"]:
    num.table("runs_by_design", "Per tracker run, grouped by direction and feed: RMS "
              "deviation from the best line per component, the largest peak and its "
              "wavelength, and the peaks by mechanism", number=8)
if F["has_truth"]:
    num.table("truth", "Attribution against the planted gear elements (synthetic data)",
              number=7)



def direction_figures(directions):  # the deviation and its spectrum in the gears' band
    for d in directions:
        num.show(deviation_figure(prof, d), f"deviation_{d}")
        num.show(psd_figure(prof, pk, d), f"psd_{d}")


display(Markdown(say("overview", "untimed")))

# %% [markdown]
# ## Deviation profiles and their spectra

# %%
display(Markdown(say("deviation", ref_deviation=", ".join(num.ref(f"deviation_{d}") for d in MAIN),
                     ref_psd=", ".join(num.ref(f"psd_{d}") for d in MAIN))))
direction_figures(MAIN)
display(Markdown(say("more", ref_more=" and ".join(num.ref(f"{k}_{d}") for d in EXTRA
                                                   for k in ("deviation", "psd")))))
direction_figures(EXTRA)
display(Markdown(say("gear_peaks")))

# %% [markdown]
# ## The motion spectrum at higher frequencies

# %%
display(Markdown(say("high", ref_psd_high=num.ref("psd_high"))))
num.show(psd_figure(prof, pk, HIGH, fmax_per_mm=float(settings["fmax_store_per_mm"]),
                title="motion spectrum up to the roughness band"), "psd_high")
display(Markdown(say("surface_band", "surface_band_verdict",
                     ref_band_floor=num.ref("band_floor"))))
display(num.caption("band_floor"))
display(with_labels(band_floor_table(prof, pk, tuple(F["surface_band_per_mm"]),
                                     tuple(F["quiet_band_per_mm"]))).round(2))

# %% [markdown]
# ## Constant temporal vs constant spatial frequency

# %%
display(Markdown(say("mechanisms", ref_temporal_vs_spatial=num.ref("temporal_vs_spatial"))))
num.show(mechanism_figure(pk, F["feeds_mm_s"]), "temporal_vs_spatial")
display(Markdown(say("temporal")))

# %% [markdown]
# ## Gear spatial frequencies per direction

# %%
display(Markdown(say("mesh", ref_mesh=num.ref("mesh"))))
display(num.caption("mesh"))
display(mesh_table(pd.read_csv(gears)))

# %% [markdown]
# ## Peak → gear attribution, and presence on the surface
#
# A tracker peak is on the surface when chapter 2 lists a waviness peak, within the coarser of
# the two resolutions, on the surface of the cut whose path its run followed.

# %%
display(Markdown(say("on_surface", "merged", ref_attribution=num.ref("attribution"))))
display(num.caption("attribution"))
surface = pd.read_csv(surface_peaks) if F["has_surface_peaks"] else None
display(attribution_table(pk[pk["mechanism"] == "gear"], surface,
                          tolerance_per_mm=F.get("surface_match_tol_per_mm") or 0.0))

# %% [markdown]
# ## Per run, grouped by what varies

# %%
if not F["thesis_layout"]:
    display(num.caption("runs_by_design"))
    display(per_cut_table(*run_values_table(prof, pk), key="run").round(4))
    display(Markdown(say("runs_by_design", ref_runs_by_design=num.ref("runs_by_design"))))

# %% [markdown]
# ## Check against the planted truth (synthetic data)

# %%
display(Markdown(say("truth_classes", "truth", "truth_merged",
                     ref_truth=num.ref("truth") if F["has_truth"] else "")))
if F["has_truth"]:
    display(num.caption("truth"))
    display(truth_table(pd.read_csv(truth_check)))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("thesis_says", "against")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
