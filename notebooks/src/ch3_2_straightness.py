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
# constant-*spatial*-frequency ones by comparing the feeds.

# %% tags=["parameters"]
peaks: str = None  # results/straightness/peaks.csv
gears: str = None  # results/straightness/gears.csv
profiles: str = None  # results/straightness/profiles.nc
truth_check: str = None  # results/straightness/truth_check.csv
surface_peaks: str = None  # results/surface/peaks.csv (chapter 2)
settings: dict = None  # config straightness section
synthetic: bool = None  # data source is the virtual cell
experiment: dict = None  # the manifest's experiment defaults (spindle_rpm, flutes, ...)
thesis_design: bool = None  # the thesis' design (robomill.experiment.is_thesis_design)
thesis_study: bool = None  # the thesis' study (robomill.experiment.is_thesis_study)
templates: str = None  # notebooks/templates/ch3_2.yaml: the sentences rendered from findings
findings: str = None  # results/straightness/findings.yaml: the numbers and verdicts stated
fig_dir: str = None  # folder for this chapter's figures

# %%
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import Markdown, display

from robomill.experiment import DIRECTION_LABELS
from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.design_tables import (
    direction_label,
    per_cut_table,
    span,
    thesis_gate,
)
from robomill.pipeline.prose import Prose, comparison_table, load_templates
from robomill.plotting import save_figure
from robomill.straightness.attribution import NO_TIME_BASE
from robomill.straightness.tables import (
    band_floor_table,
    run_summary_table,
    surface_cross_check,
)
from robomill.straightness.truth import attribution_counts

found = read_findings(findings)
F = found.values()
say = Prose(load_templates("ch3_2", templates), found)
prof = open_artefact(profiles)
pk = pd.read_csv(peaks, keep_default_na=False, na_values=[""])
pk[["stage", "order"]] = pk[["stage", "order"]].fillna("")
pk["joint"] = pk["joint"].astype("Int64")
gr = pd.read_csv(gears)
runs = pd.DataFrame({k: prof[k].values for k in ("direction", "feed_mm_s", "cut",
                                                  "resolution_per_mm", "length_mm",
                                                  "speed_mm_s", "floor_um2")},
                    index=prof["run"].values)
vs_thesis = thesis_gate(thesis_study)
THESIS_LAYOUT = thesis_design is not False  # the thesis' figures: +-Y runs, then +X
present = list(dict.fromkeys(str(d) for d in runs["direction"]))
directions = ([d for d in ("py", "my", "px") if d in present] if THESIS_LAYOUT
              else sorted(present))
LABELS = {d: DIRECTION_LABELS.get(d) or direction_label(None, float(d.lstrip("d").split()[0]))
          for d in present}
gear_pk = pk[pk["mechanism"] == "gear"]
temporal = pk[pk["mechanism"] == "temporal"]
d16 = "my" if "my" in directions else directions[0]

# thesis numbers for ±Y (Figs 3.12–3.17, Table 3.2); the +X runs and the extra tables are
# numbered after them (Tables 3.1, 3.3 and 3.4 are in the forces chapter)
num = Numbering("3")
if THESIS_LAYOUT:
    for d, (n_dev, n_psd) in {"py": (12, 13), "my": (14, 15), "px": (18, 19)}.items():
        if d in directions:
            x = "x" if d == "px" else ""
            num.figure(f"deviation_{d}", f"Deviation from the best line along the path "
                       f"{LABELS[d]}, every feed (0.1 mm running mean in bold)",
                       number=n_dev, stem=f"fig3_{n_dev - 6 if x else n_dev}{x}_deviation_{d}")
            num.figure(f"psd_{d}", f"Power spectrum of the motion along {LABELS[d]} "
                       "(▼ gear peak, ● other peak)", number=n_psd,
                       stem=f"fig3_{n_psd - 6 if x else n_psd}{x}_psd_{d}")
else:  # any design: Figs 3.12 and 3.13, one part per path direction
    part = {d: "abcdefghijklmnopqrstuvwxyz"[i] if len(directions) > 1 else ""
            for i, d in enumerate(directions)}
    for d in directions:
        num.figure(f"deviation_{d}", f"Deviation from the best line along the path "
                   f"{LABELS[d]}, every feed (0.1 mm running mean in bold)", number=12,
                   part=part[d], stem=f"fig3_12{part[d]}_deviation_{d.replace(' ', '')}")
        num.figure(f"psd_{d}", f"Power spectrum of the motion along {LABELS[d]} "
                   "(▼ gear peak, ● other peak)", number=13, part=part[d],
                   stem=f"fig3_13{part[d]}_psd_{d.replace(' ', '')}")
num.figure("psd_high", f"Motion spectrum along {LABELS[d16]} up to the roughness "
           "band", number=16, stem=f"fig3_16_psd_high_{d16.replace(' ', '')}")
num.table("band_floor", "Peak-to-floor ratio of the motion spectrum in the surface band and "
          "in an equally wide band where nothing is expected", number=5)
num.figure("temporal_vs_spatial", "Peaks by mechanism: spatial and temporal frequency against "
           "feed", number=17)
num.table("mesh", "Mesh spatial frequencies [mm⁻¹] of every gear stage, per direction",
          number=6)
num.table("attribution", "Peak → gear attribution, and presence on the surface", number=2)
if not THESIS_LAYOUT:
    num.table("runs_by_design", "Per tracker run, grouped by direction and feed: RMS "
              "deviation from the best line per component, the largest peak and its "
              "wavelength, and the peaks by mechanism", number=8)
tc = pd.read_csv(truth_check)
if synthetic and len(tc):
    num.table("truth", "Attribution against the planted gear elements (synthetic data)",
              number=7)
display(Markdown(
    f"**{len(runs)} tracker runs** ({', '.join(LABELS[d] for d in directions)}; "
    f"feeds {', '.join(f'{v:g}' for v in sorted(runs.feed_mm_s.unique()))} mm/s), analysed "
    f"length {runs.length_mm.mean():.1f} mm, so the frequency resolution is "
    f"1/L = {runs.resolution_per_mm.mean():.4f} mm⁻¹. Measured speeds agree with the "
    f"commanded feeds within "
    f"{100 * np.nanmax(np.abs(runs.speed_mm_s / runs.feed_mm_s - 1)):.2f} %. "
    f"{len(pk)} spectral peaks: {len(gear_pk)} attributed to a gear, {len(temporal)} at a "
    f"constant temporal frequency, {int((pk.mechanism == 'spatial').sum())} spatial without "
    f"a gear, {int((pk.mechanism == 'unclassified').sum())} unclassified."))
untimed = (list(prof["run"].values[prof["time_base"].values == "none"])
           if "time_base" in prof.coords else [])
if untimed:  # spatial-only streams: why their peaks are not classified temporal/spatial
    display(Markdown(f"Run(s) {', '.join(map(str, untimed))}: {NO_TIME_BASE}."))


# %%
def runs_of(direction):
    """The runs (ids, the join key) of a direction, slowest feed first."""
    return runs[runs.direction == direction].sort_values("feed_mm_s", kind="stable").index


def deviation_figure(direction, number, key):
    ids = runs_of(direction)
    fig, axes = plt.subplots(len(ids), 1, figsize=(7.5, 1.6 * len(ids) + 0.6), sharex=True,
                             squeeze=False)
    for ax, r in zip(axes[:, 0], ids, strict=True):
        ds = prof.sel(run=r)
        v = runs.feed_mm_s[r]
        n_avg = max(1, int(round(0.1 / float(ds.attrs.get("ds_mm", prof.s[1] - prof.s[0])))))
        for k, comp in enumerate(ds.component.values):
            y = ds.deviation_um.sel(component=comp).values
            ax.plot(ds.s, y, lw=0.3, alpha=0.35, color=f"C{k}")
            smooth = np.convolve(np.nan_to_num(y), np.ones(n_avg) / n_avg, mode="same")
            ax.plot(ds.s, np.where(np.isfinite(y), smooth, np.nan), lw=0.9, color=f"C{k}",
                    label=f"{comp} (0.1 mm mean)")
        ax.set_ylabel("µm")
        ax.set_title(f"feed {v:g} mm/s", fontsize=9, loc="left")
    axes[0, 0].legend(ncol=2, fontsize=8, loc="upper right")
    axes[-1, 0].set_xlabel("distance along the path s [mm]")
    fig.suptitle(f"Fig 3.{number} — deviation from the best line, path "
                 f"{LABELS[direction]}")
    save_figure(fig, fig_dir, num.file(key))
    plt.show()
    display(num.caption(key))


def psd_figure(direction, number, fmax, key, title):
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    for k, r in enumerate(runs_of(direction)):
        ds, v = prof.sel(run=r), runs.feed_mm_s[r]
        keep = ds.f <= fmax
        ax.semilogy(ds.f[keep], ds.power_um2.where(keep, drop=True), lw=0.7,
                    label=f"{v:g} mm/s", color=f"C{k}")
        mine = pk[pk.run == r]
        for _, p in mine[mine.f_spatial_per_mm <= fmax].iterrows():
            ax.plot(p.f_spatial_per_mm, p.amplitude_um**2 / 2, "v" if p.mechanism == "gear"
                    else "o", color=f"C{k}", ms=5)
    ax.set_xlabel("spatial frequency [mm⁻¹]")
    ax.set_ylabel("power [µm²]")
    ax.set_xlim(0, fmax)
    ax.set_ylim(bottom=max(1e-6, float(prof.floor_um2.min()) / 10))
    ax.legend(fontsize=8, ncol=2)
    ax.set_title(f"Fig 3.{number} — {title}, path {LABELS[direction]} "
                 "(▼ gear, ● other peak)")
    save_figure(fig, fig_dir, num.file(key))
    plt.show()
    display(num.caption(key))


# %% [markdown]
# ## Deviation profiles and their spectra

# %%
ys = [d for d in ("py", "my") if d in directions] if THESIS_LAYOUT else directions
display(Markdown(
    f"The deviation of the path from its best line at {span(runs.feed_mm_s, 'g')} mm/s ("
    + ", ".join(num.ref(f"deviation_{d}") for d in ys) + ") and its power spectrum ("
    + ", ".join(num.ref(f"psd_{d}") for d in ys) + ")."))
numbers = ({"py": (12, 13), "my": (14, 15)} if THESIS_LAYOUT else
           {d: (f"12{part[d]}", f"13{part[d]}") for d in directions})
for d in ys:
    deviation_figure(d, numbers[d][0], f"deviation_{d}")
    psd_figure(d, numbers[d][1], 1.0, f"psd_{d}", "power spectrum of the motion")

# %%
if THESIS_LAYOUT and "px" in directions:
    display(Markdown(
        f"The +X runs (not in the thesis figures) are analysed the same way: "
        f"{num.ref('deviation_px')} and {num.ref('psd_px')}."))
    deviation_figure("px", "12x", "deviation_px")
    psd_figure("px", "13x", 1.0, "psd_px", "power spectrum of the motion")

# %%
display(Markdown(say("gear_peaks")))

# %% [markdown]
# ## The motion spectrum at higher frequencies

# %%
display(Markdown(
    f"{num.ref('psd_high')} shows the motion spectrum up to the surface's roughness band "
    f"({settings['surface_band_per_mm'][0]:g}–{settings['surface_band_per_mm'][1]:g} mm⁻¹); "
    "a servo ripple at f Hz appears at f/v mm⁻¹."))
psd_figure(d16, 16, float(settings["fmax_store_per_mm"]), "psd_high",
           "motion spectrum up to the roughness band")
band = tuple(F["surface_band_per_mm"])
hi = band_floor_table(prof, pk, band, tuple(F["quiet_band_per_mm"]))
display(Markdown(say("surface_band", "surface_band_verdict",
                     ref_band_floor=num.ref("band_floor"))))
display(num.caption("band_floor"))
display(hi.assign(direction=hi.direction.map(lambda d: LABELS.get(d) or direction_label(d)))
        .round(2))

# %% [markdown]
# ## Constant temporal vs constant spatial frequency

# %%
display(Markdown(
    "A peak whose wavelength grows with the feed has a constant temporal frequency (a servo "
    "ripple); a gear peak keeps its spatial frequency at "
    "every feed "
    f"({num.ref('temporal_vs_spatial')})."))
fig, axes = plt.subplots(1, 2, figsize=(9, 3.8))
for mech, mk in (("gear", "v"), ("temporal", "o"), ("spatial", "s"), ("unclassified", "x")):
    sel = pk[pk.mechanism == mech]
    axes[0].plot(sel.feed_mm_s, sel.f_spatial_per_mm, mk, label=mech, ms=5)
    axes[1].plot(sel.feed_mm_s, sel.f_temporal_hz, mk, label=mech, ms=5)
v = np.linspace(runs.feed_mm_s.min(), runs.feed_mm_s.max(), 50)
if len(temporal):
    f_t = temporal.f_temporal_hz.median()
    axes[0].plot(v, f_t / v, "k:", lw=0.8, label=f"{f_t:.2f} Hz / v")
    axes[1].axhline(f_t, color="k", ls=":", lw=0.8)
axes[0].set_yscale("log")
axes[0].set_xlabel("feed [mm/s]")
axes[0].set_ylabel("spatial frequency [mm⁻¹]")
axes[1].set_yscale("log")
axes[1].set_xlabel("feed [mm/s]")
axes[1].set_ylabel("temporal frequency [Hz]")
axes[0].legend(fontsize=8)
fig.suptitle("Fig 3.17 — peaks by mechanism: spatial and temporal frequency vs feed")
fig.tight_layout()
save_figure(fig, fig_dir, num.file("temporal_vs_spatial"))
plt.show()
display(num.caption("temporal_vs_spatial"))
display(Markdown(say("temporal")))

# %% [markdown]
# ## Gear spatial frequencies per direction

# %%
display(Markdown(
    f"{num.ref('mesh')}: revolutions per mm of path of every gear element (runout: once per "
    "revolution; mesh: teeth per revolution) during each run's cut path; independent of the "
    "feed on a given path."))
tab = (gr[gr.order == "mesh"].pivot_table(index=["joint", "stage"], columns="direction",
                                           values="f_spatial_per_mm", aggfunc="mean")
       .rename(columns=LABELS))
display(num.caption("mesh"))
display(tab.round(4))

# %% [markdown]
# ## Peak → gear attribution, and presence on the surface
#
# A tracker peak is on the surface when chapter 2 lists a waviness peak, within the coarser of
# the two resolutions, on the surface of the cut whose path its run followed.

# %%
sp = pd.read_csv(surface_peaks)
tol = float(settings["tol_bins"]) * max(
    float(runs.resolution_per_mm.max()),
    1.0 / 15.0)  # surface profiles of 15 mm or more: 1/15 mm⁻¹ (the thesis' f0)
xc = surface_cross_check(gear_pk, sp, tolerance_per_mm=tol)
HAS_MERGED = {"candidates", "merged"} <= set(xc.columns)  # peaks.csv since issue 21
table = xc.assign(direction=xc.direction.map(lambda d: LABELS.get(d, d)),
                  on_surface=xc.on_surface.map({True: "yes", False: "no"}))[
    ["direction", "feed_mm_s", "joint", "stage", "order", "f_spatial_per_mm", "amplitude_um",
     "on_surface", "surface_f_per_mm", *(("merged", "candidates") if HAS_MERGED else ())]]
if HAS_MERGED:
    table["merged"] = table["merged"].astype(bool).map({True: "yes", False: "no"})
    table["candidates"] = table["candidates"].astype(object).fillna("")
merged_pk = xc[xc["merged"].astype(bool)] if HAS_MERGED else xc.iloc[:0]
display(Markdown(
    f"{num.ref('attribution')}: {int(xc.on_surface.sum())} of {len(xc)} gear peaks are also "
    "surface-waviness peaks "
    f"(tolerance {tol:.3f} mm⁻¹; the surface table has {len(sp)} peaks)."
    + vs_thesis(" The thesis finds that the spatial frequency of the main surface "
                "irregularities agrees with some of the gear spatial frequencies.")
    + ((f" {len(merged_pk)} of them {'is' if len(merged_pk) == 1 else 'are'} **merged**: "
        "their candidate gear lines lie closer "
        "than the run's resolution, so the joint named is only the nearest ("
        + "; ".join(f"{LABELS.get(r.direction, r.direction)} at {r.feed_mm_s:g} mm/s, "
                    f"{r.f_spatial_per_mm:.3f} mm⁻¹: {str(r.candidates).replace(';', ', ')}"
                    for r in merged_pk.itertuples()) + ").") if len(merged_pk) else
       (" No peak merges gear lines closer than the resolution." if HAS_MERGED else ""))))
display(num.caption("attribution"))
display(table.round(4))

# %% [markdown]
# ## Per run, grouped by what varies

# %%
if not THESIS_LAYOUT:
    per_run = run_summary_table(prof, pk)
    values = [c for c in per_run.columns if c.startswith("rms_")] + [
        "largest_peak_um", "largest_peak_wavelength_mm", "largest_peak_mechanism",
        *[c for c in per_run.columns if c.endswith("_peaks")]]
    display(num.caption("runs_by_design"))
    display(per_cut_table(per_run[["run", "direction", "feed_mm_s", *values]], values,
                          key="run").round(4))
    display(Markdown(
        f"{num.ref('runs_by_design')}: RMS deviation from the best line per run and component "
        + ", ".join(f"{c.removeprefix('rms_').removesuffix('_um')} {span(per_run[c])} µm"
                    for c in values if c.startswith("rms_")) + "."))

# %% [markdown]
# ## Check against the planted truth (synthetic data)
#
# Every gear element of every run is classed from its planted amplitude perpendicular to
# the path and the run's noise floor: *above noise* (power ≥ 2 × the detection threshold:
# must be found), *below noise* (≤ half the threshold: must not be attributed), *marginal*
# in between, *out of band* (fewer than the minimum cycles in the record). *Merged*: not
# attributed to itself, but a gear peak lies within the match tolerance (two elements closer
# than the resolution).

# %%
if synthetic and len(tc):
    counts = attribution_counts(tc)
    display(Markdown(
        f"Planted gear elements × runs: {counts['planted_elements']}; above the noise: "
        f"**{counts['above_noise']}**, found **{counts['found']}**, merged with a neighbour "
        f"{counts['merged']}, missed **{counts['missed']}**; marginal {counts['marginal']} "
        f"(found {counts['marginal_found']}). Attributions to a gear that was not planted "
        f"above the noise: **{counts['false_attributions']}** ({num.ref('truth')})."))
    shown = tc[tc["class"] != "out_of_band"].assign(
        direction=lambda t: t.direction.map(lambda d: LABELS.get(d) or direction_label(d)))
    if "merged_into" in shown:
        shown = shown.assign(merged_into=shown["merged_into"].astype(object).fillna(""))
        into = shown[shown["merged"].astype(bool)]
        if len(into):
            display(Markdown("Merged elements, with the element their peak was attributed to: "
                             + "; ".join(f"{r.joint}:{r.stage}:{r.order} ({r.direction}, "
                                         f"{r.feed_mm_s:g} mm/s) → {r.merged_into}"
                                         for r in into.itertuples()) + "."))
    display(num.caption("truth"))
    display(shown.round(4))
else:
    display(Markdown("Real data: no planted truth to compare with."))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("against")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
