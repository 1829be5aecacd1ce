# %% [markdown]
# # Chapter 2 — Surface irregularities
#
# A stylus profilometer traced the floor of every cut along the feed direction (thesis §2.2).
# Each profile is detrended (stylus tilt), split by the ISO 16610-21 Gaussian filter into
# waviness and roughness, and analysed with the thesis' spectra (eqs. 2.1–2.3: normalized
# amplitude A(k) and power P(k), one-sided, frequency k·fs/N in mm⁻¹) and its RMS by
# Parseval (eq. 2.6) on equal segments (`surface.waviness_segment_mm` for waviness,
# `surface.roughness_segment_mm` for roughness: the thesis' Tables 2.1 and 2.2 for its design;
# per cut for any other). Dominant peaks are classified across feeds: constant *spatial*
# frequency → kinematic (it follows the path); constant *temporal* frequency → dynamic (it
# follows time).

# %% tags=["parameters"]
waviness: str = None  # results/surface/table_2_1_waviness_rms.csv (thesis design)
roughness: str = None  # results/surface/table_2_2_roughness_rms.csv (thesis design)
comparison: str = None  # results/surface/thesis_comparison.csv (thesis design)
by_design: str = None  # results/surface/metrics_by_design.csv (any other design)
cuts: str = None  # results/ingest/cuts.csv
peaks: str = None  # results/surface/peaks.csv
metrics: str = None  # results/surface/metrics.csv
spectra: str = None  # results/surface/spectra.nc
profiles: str = None  # results/surface/profiles.nc
recovery: str = None  # results/surface/recovery.csv (synthetic data only)
reference: str = None  # results/surface/reference_comparison.csv (files stating parameters)
areal: str = None  # results/surface/areal.csv (a folder with areal scans)
areal_spectra: str = None  # results/surface/areal_spectra.nc (a folder with areal scans)
profile_vs_areal: str = None  # results/surface/profile_vs_areal.csv (cuts measured both ways)
templates: str = None  # robomill/data/templates/ch2.yaml: sentences from findings
findings: str = None  # results/surface/findings.yaml: every number and verdict stated here
settings: dict = None  # config surface section (the figures' frequency ranges)
experiment: dict = None  # the manifest's experiment defaults (spindle_rpm, flutes, ...)
fig_dir: str = None  # folder for this chapter's figures

# %%
import pandas as pd
from IPython.display import Markdown, display

import robomill.surface.figures as figures
from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.design_tables import dominant_wavelengths, per_cut_table
from robomill.pipeline.prose import Prose, comparison_table, load_templates
from robomill.surface.tables import DIRECTION_ORDER, path_label, peak_counts, plot_groups

found = read_findings(findings)
F = found.values()
say = Prose(load_templates("ch2", templates), found)
prof = open_artefact(profiles)
spec = open_artefact(spectra)
met = pd.read_csv(metrics)
pk = pd.read_csv(peaks)
THESIS_LAYOUT = F["thesis_layout"]  # Tables 2.1/2.2, one figure per set and direction
directions, sets, c0 = F["directions"], F["sets"] or [], F["example_cut"]
OFFSET, SEG_W, SEG_R = (figures.PROFILE_OFFSET_UM, settings["waviness_segment_mm"],
                        settings["roughness_segment_mm"])


def part(i, n):
    return "abcdefghijklmnopqrstuvwxyz"[i] if n > 1 else ""


num = Numbering.for_chapter("ch2", fig_dir=fig_dir)
num.figure("detrend", "A measured profile and the same profile detrended (stylus tilt "
           "removed)", number=9)
num.figure("waviness", f"Waviness of that profile: the ISO 16610-21 Gaussian filter, "
           f"λc = {F['lambda_c_mm']:g} mm", number=11)
num.figure("roughness_feed", "Roughness over the first millimetre at the lowest and the "
           "highest feed", number=12)
for i, (d, label) in enumerate(zip(directions, F["direction_labels"], strict=True)):
    if THESIS_LAYOUT:
        num.figure(f"profiles_{d}", f"Profiles of set {F['profiles_set']} along {label}, every "
                   f"feed (offset {OFFSET:g} µm per feed)", number=13 + DIRECTION_ORDER.index(d))
    else:
        num.figure(f"profiles_{d}", f"Profiles of the cuts along {label} (offset {OFFSET:g} µm "
                   "per cut)", number=13, part=part(i, len(directions)))
num.figure("spectrum", "Normalized amplitude spectrum A(k) of one profile, waviness and "
           "roughness ranges (eq. 2.1)", number=16)
for i, s in enumerate(sets):
    num.figure(f"spectra_set{s}", f"Power spectra P(k) of every cut of set {s} (eq. 2.2), "
               "waviness (left) and roughness (right)", number=17, part=part(i, len(sets)))
if THESIS_LAYOUT:
    num.table("waviness_rms", f"RMS of waviness [µm] by the segment method ({SEG_W:g} mm "
              "segments), the layout of the thesis' Table 2.1", number=1)
    num.table("roughness_rms", f"RMS of roughness [µm] by the segment method ({SEG_R:g} mm "
              "segments), the layout of the thesis' Table 2.2", number=2)
else:
    num.figure("spectra_all", "Power spectra P(k) of every cut (eq. 2.2), one row per "
               "direction, waviness (left) and roughness (right)", number=17)
    num.table("rms_by_design", "Per cut, grouped by what varies: waviness and roughness RMS "
              f"by the segment method ({SEG_W:g} mm and {SEG_R:g} mm segments), Wq, Rq, Ra [µm] "
              "and the wavelengths of the largest waviness and roughness peaks [mm]", number=1)
num.figure("rms_vs_feed", "Waviness and roughness RMS against feed, by direction", number=22)
num.table("peak_counts", "Dominant spectral peaks by band and mechanism")
num.figure("peak_mechanisms", "Spatial and temporal frequency of every peak against feed, by "
           "mechanism", number=23)
if F["has_recovery"]:
    num.table("recovery", "Planted against recovered RMS per cut (synthetic data)")
if F.get("has_areal"):
    num.table("areal", "Areal scans: ISO 25178-2 height parameters after form removal, with "
              "what each instrument states")
    num.figure("areal_psd", "Areal scans: radially averaged areal PSD, and PSDs along and "
               "across the feed")
if F.get("has_profile_vs_areal"):
    num.table("profile_vs_areal", "Cuts measured both ways: the stylus profile's parameters "
              "beside those of the scan's profile along the feed")
if F.get("has_reference"):
    num.table("reference", "Ours against the parameters the profile files state about "
              "themselves, with the filter of each")



display(Markdown(say("measured", "source", "design")))

# %% [markdown]
# ## Measured and detrended profile

# %%
num.show(figures.detrend_figure(prof, c0), "detrend")
display(Markdown(say("detrend", ref_detrend=num.ref("detrend"))))

# %% [markdown]
# ## Waviness, and roughness at low and high feed

# %%
num.show(figures.waviness_figure(prof, c0, F["lambda_c_mm"]), "waviness")
num.show(figures.roughness_feed_figure(prof, [F["low_feed_cut"], F["high_feed_cut"]]),
     "roughness_feed")
display(Markdown(say("waviness", ref_waviness=num.ref("waviness"),
                     ref_roughness_feed=num.ref("roughness_feed"))))

# %% [markdown]
# ## Profiles per direction

# %%
display(Markdown(say("profiles", ref_profiles=", ".join(num.ref(f"profiles_{d}")
                                                       for d in directions))))
for d, rows in plot_groups(met, directions, THESIS_LAYOUT, F["profiles_set"]).items():
    title = (f"Set {F['profiles_set']}, direction {path_label(d)}" if THESIS_LAYOUT
             else f"Direction {path_label(d)}")
    num.show(figures.profiles_figure(prof, rows, title, per_feed=THESIS_LAYOUT), f"profiles_{d}")

# %% [markdown]
# ## One spectrum

# %%
num.show(figures.spectrum_figure(spec, c0, settings), "spectrum")
spectra_figures = ({f"spectra_set{s}": (s, f"Power spectra, set {s}") for s in sets}
                   if THESIS_LAYOUT else {"spectra_all": (None, "Power spectra of every cut")})
display(Markdown(say("spectrum", ref_spectrum=num.ref("spectrum"),
                     ref_spectra=", ".join(num.ref(k) for k in spectra_figures))))

# %% [markdown]
# ## Spectra of every cut

# %%
for key, (s, title) in spectra_figures.items():
    num.show(figures.spectra_figure(spec, plot_groups(met, directions, THESIS_LAYOUT, s), title,
                                settings, per_feed=THESIS_LAYOUT), key)

# %% [markdown]
# ## RMS by the segment method

# %%
if THESIS_LAYOUT:
    for key, path in (("waviness_rms", waviness), ("roughness_rms", roughness)):
        display(num.caption(key))
        display(pd.read_csv(path, index_col="segment").round(2))
    ref_rms = f"{num.ref('waviness_rms')} and {num.ref('roughness_rms')}"
else:
    per_cut = met.merge(dominant_wavelengths(pk).reset_index(), on="cut", how="left")
    values = ["waviness_rms_um", "roughness_rms_um", "Wq_um", "Rq_um", "Ra_um"] + [
        c for c in ("waviness_wavelength_mm", "roughness_wavelength_mm") if c in per_cut]
    display(num.caption("rms_by_design"))
    display(per_cut_table(per_cut[["cut", *values]], values, pd.read_csv(cuts),
                          experiment).round(3))
    ref_rms = num.ref("rms_by_design")
display(Markdown(say("rms", ref_rms=ref_rms)))

# %%
num.show(figures.rms_vs_feed_figure(met), "rms_vs_feed")
display(Markdown(say("by_direction", "feed_correlation", ref_rms_vs_feed=num.ref("rms_vs_feed"))))

# %% [markdown]
# ## Peaks and their mechanism

# %%
display(num.caption("peak_counts"))
display(peak_counts(pk))
num.show(figures.peak_mechanisms_figure(pk), "peak_mechanisms")
display(Markdown(say("peaks", "kinematic", "dynamic", ref_peak_counts=num.ref("peak_counts"),
                     ref_peak_mechanisms=num.ref("peak_mechanisms"))))
display(Markdown(say("resolution")))

# %% [markdown]
# ## Planted vs recovered (synthetic data only)

# %%
display(Markdown(say("recovery", ref_recovery=num.ref("recovery") if F["has_recovery"] else "")))
if F["has_recovery"]:
    display(num.caption("recovery"))
    display(pd.read_csv(recovery).round(3))

# %%
if F.get("has_areal"):  # only for a folder with areal scans
    display(Markdown("## Areal scans"))
    display(Markdown(say("areal", ref_areal=num.ref("areal"),
                         ref_areal_psd=num.ref("areal_psd"))))
    display(num.caption("areal"))
    display(pd.read_csv(areal).round(4))
    num.show(figures.areal_psd_figure(open_artefact(areal_spectra)), "areal_psd")
if F.get("has_profile_vs_areal"):
    display(Markdown(say("profile_vs_areal",
                         ref_profile_vs_areal=num.ref("profile_vs_areal"))))
    display(num.caption("profile_vs_areal"))
    display(pd.read_csv(profile_vs_areal).round(4))

# %%
if F.get("has_reference"):  # only where a profile file states its own parameters
    display(Markdown("## Against the files' own parameters"))
    display(Markdown(say("reference", ref_reference=num.ref("reference"))))
    display(num.caption("reference"))
    display(pd.read_csv(reference).round(4))

# %% [markdown]
# ## What it means

# %%
display(Markdown(say("mechanism_waviness", "mechanism_roughness", "levels")))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("against", "thesis_tables", "rows")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
