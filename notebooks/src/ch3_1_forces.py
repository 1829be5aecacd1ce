# %% [markdown]
# # Chapter 3.1 — Cutting forces
#
# The Kistler dynamometer under the block recorded Fx, Fy, Fz during every cut (thesis §3.1).
# The mechanistic model for a small axial depth (thesis eq. 3.1) gives each tooth's forces
# F_t = K_tc a h(φ) + K_te a, F_r = K_rc a h(φ) + K_re a, F_a = K_ac a h(φ) + K_ae a with
# h(φ) = c sin φ between each tooth's entry and exit angles (0 and π in a slot); the force is
# periodic at the tooth-passing frequency of each cut's own spindle speed and flutes (the
# thesis finds its measured forces periodic but not harmonic and explains it by the robot's
# vibration: "Against the thesis" at the end). This chapter shows the model shape
# (Fig 3.2), a record (Fig 3.3) and its full-band spectrum (Fig 3.4), the spectra in spatial
# frequency (Figs 3.5–) and in time frequency 0–250 Hz (Figs 3.8–), the per-cut peak table,
# and the cutting coefficients identified from the mean forces.
# Forces are on the tool, in the block axes (docs/data-contract.md).

# %% tags=["parameters"]
spectra: str = None  # results/forces/spectra.nc
peaks: str = None  # results/forces/peaks.csv
coefficients: str = None  # results/forces/cutting_coefficients.csv
means: str = None  # results/forces/mean_forces.csv
harmonics: str = None  # results/forces/harmonics.csv
cuts: str = None  # results/ingest/cuts.csv
modes: str = None  # results/modal/modes.csv (identified modes, chapter 3.3)
templates: str = None  # notebooks/templates/ch3_1.yaml: the sentences rendered from findings
findings: str = None  # results/forces/findings.yaml: the dominant peak and its verdict
truth: str = None  # results/synthetic/truth.nc (synthetic runs only)
settings: dict = None  # config section forces
synthetic: bool = None
experiment: dict = None  # the manifest's experiment defaults (spindle_rpm, flutes, ...)
thesis_design: bool = None  # the thesis' design (robomill.experiment.is_thesis_design)
thesis_study: bool = None  # the thesis' study (robomill.experiment.is_thesis_study)
fig_dir: str = None  # folder for this chapter's figures

# %%
import os

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import Markdown, display

from robomill.experiment import DIRECTION_LABELS
from robomill.findings import read_findings
from robomill.forces.coefficients import coefficient_flag_sentence
from robomill.forces.peaks import nearest_modes
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.design_tables import (
    describe_design,
    design_factors,
    direction_label,
    per_cut_table,
    span,
    thesis_gate,
    with_design,
)
from robomill.pipeline.prose import Prose, comparison_table, load_templates
from robomill.plotting import save_figure

found = read_findings(findings)
say = Prose(load_templates("ch3_1", templates), found)
vs_thesis = thesis_gate(thesis_study)  # thesis remarks only for a study of its design
sp = open_artefact(spectra)
# the thesis' figures show one set (+Y, +X, -Y); any other design shows every cut
THESIS_LAYOUT = thesis_design is not False and "set" in sp
pk = pd.read_csv(peaks)
coef = pd.read_csv(coefficients)
mf = pd.read_csv(means)
hm = pd.read_csv(harmonics)
settings = settings or {}
plan = pd.read_csv(cuts) if cuts else mf
process = with_design(mf, experiment)  # each cut's own flutes, immersion, milling mode
mode_table = pd.read_csv(modes) if modes and os.path.exists(modes) else None
if THESIS_LAYOUT:
    fig_set = int(settings.get("figure_set", 3))
    if fig_set not in set(sp["set"].values.tolist()):
        fig_set = int(sp["set"].values.max())
    cuts_set = [str(c) for c in sp.cut.values if int(sp["set"].sel(cut=c)) == fig_set]
    dirs_set = [d for d in ("py", "px", "my")
                if any(str(sp["direction"].sel(cut=c).item()) == d for c in cuts_set)]
    which = f"set {fig_set}"
else:
    cuts_set = [str(c) for c in sp.cut.values]
    dirs_set = list(dict.fromkeys(str(v) for v in sp["direction"].values))
    which = "every cut"
    design = design_factors(plan[plan["cut"].isin(cuts_set)], experiment)


def dir_label(d: str) -> str:
    """+X, −Y … for a named direction, 45° for a path direction ``"45 deg"``."""
    return (DIRECTION_LABELS[d] if d in DIRECTION_LABELS
            else direction_label(None, float(d.split()[0])))


first_cut = process.set_index("cut").loc[str(sp.cut.values[0])]
shape = (f"{int(first_cut['flutes'])}-flute "
         + ("slot" if first_cut["milling"] == "slot" else
            f"{first_cut['milling']}-milling cut at a_e/D {first_cut['radial_immersion']:g}")
         if "flutes" in first_cut else "slot")

# thesis numbers (Figs 3.2–3.11, Table 3.1); the extra tables are Tables 3.3 and 3.4 (Table
# 3.2 is in the straightness chapter)
num = Numbering("3")
num.figure("model_force_shape", f"The model's force shape over two revolutions of a {shape}, "
           "with the coefficients identified below (eq. 3.1)", number=2)
num.figure("record", "A measured force record: (a) the whole record as a min–max envelope, "
           "(b) a zoom in its middle", number=3)
num.figure("full_band_psd", "Welch PSD of that record over the full band, sum of the axes",
           number=4)
PARTS = "abcdefghijklmnopqrstuvwxyz"
# thesis Figs 3.5-3.7 and 3.8-3.10; any other design Figs 3.5a, b, ... and 3.8a, b, ...
for kind, first, stem, what in (
        ("spatial", 5, "fig3_5_7_spatial", "Spatial-frequency power of the cuts of {} along {} "
         "(kinematic peak near 0.5 mm⁻¹ dotted)"),
        ("time", 8, "fig3_8_10_time", "Time-frequency power 0–250 Hz of the cuts of {} along {} "
         "(identified modes dotted)")):
    for k, d in enumerate(dirs_set):
        num.figure(f"{kind}_{d}", what.format(which, dir_label(d)),
                   number=first + k if THESIS_LAYOUT else first,
                   part="" if THESIS_LAYOUT or len(dirs_set) == 1 else PARTS[k],
                   stem=f"{stem}_{d.replace(' ', '')}")
num.table("peaks", "Per-cut peaks: dominant low-frequency and kinematic peak, and the nearest "
          "identified mode" + ("" if THESIS_LAYOUT else "; the mean force levels in the cut "
                               "frame; grouped by what varies"), number=1)
num.table("harmonics", "Tooth-passing harmonics: median frequency and power over the cuts"
          " (of each tooth-passing frequency)", number=3)
num.figure("mean_forces_vs_feed", "Mean forces per cut, divided by N·a, against the feed per tooth",
           number=11)
num.table("coefficients", "Identified cutting coefficients with 95 % intervals and their "
          "sanity flags (negative value, fit residual against signal, physical)", number=4)
display(Markdown(
    f"{sp.sizes['cut']} cuts analysed, {int(sp['n_samples'].sum()):,} samples per axis in "
    f"total; tooth passing {span(sp['tooth_passing_hz'].values, '.1f')} Hz."
    + ("" if THESIS_LAYOUT else
       f" Design: {describe_design(plan[plan['cut'].isin(cuts_set)], experiment)}.")))

# %% [markdown]
# ## The model's force shape (eq. 3.1)

# %%
display(Markdown(
    f"{num.ref('model_force_shape')}: two revolutions of a {shape} with the coefficients "
    "identified below" + vs_thesis("; the thesis plots the Z shape only, \"independent of its "
                                   "amplitude\"") + "."))
ang = sp["model_angle"].values
fig, ax = plt.subplots()
for i, lab in enumerate(["F_x (feed)", "F_y (cross-feed)", "F_z (axial)"]):
    ax.plot(ang, sp["model_force"].values[:, i], label=lab, lw=2 if i == 2 else 1)
ax.set_xlabel("rotation angle of tooth 1 [deg]")
ax.set_ylabel("force on the tool [N]")
ax.set_title(f"Eq. 3.1, c = {sp.attrs['model_feed_per_tooth_mm'] * 1e3:.2f} µm, "
             f"a = {sp.attrs['model_depth_mm']:.2f} mm")
ax.legend()
save_figure(fig, fig_dir, num.file("model_force_shape"))
plt.show()
display(num.caption("model_force_shape"))

# %% [markdown]
# ## A measured record, its zoom and its full-band spectrum

# %%
c0 = cuts_set[0]
d0 = sp.sel(cut=c0)
fig, axs = plt.subplots(1, 2, figsize=(11, 4))
for a in ["Fx", "Fy", "Fz"]:
    axs[0].fill_between(d0["envelope_t"], d0["envelope_min"].sel(axis=a),
                        d0["envelope_max"].sel(axis=a), alpha=0.5, label=a)
    axs[1].plot(d0["excerpt_t"] * 1e3, d0["excerpt"].sel(axis=a), lw=0.8, label=a)
axs[0].set_xlabel("t [s]")
axs[0].set_ylabel("force [N] (min–max envelope)")
axs[0].set_title(f"(a) {c0}: whole record")
axs[1].set_xlabel("t [ms]")
axs[1].set_title("(b) zoom, middle of the record")
axs[0].legend()
save_figure(fig, fig_dir, num.file("record"))
plt.show()
display(num.caption("record"))

f = sp["frequency"].values
psd = d0["psd"].sum("axis").values
fig, ax = plt.subplots()
ax.semilogy(f / 1e3, psd, lw=0.7)
ax.set_xlabel("frequency [kHz]")
ax.set_ylabel("PSD, sum of axes [N²/Hz]")
ax.set_title(f"Figure 3.4 — {c0}, Welch PSD over the full band")
save_figure(fig, fig_dir, num.file("full_band_psd"))
plt.show()
display(num.caption("full_band_psd"))
top = f[np.argmax(psd[f > 500]) + np.sum(f <= 500)]
display(Markdown(
    f"{num.ref('record')} shows the record; in {num.ref('full_band_psd')} the largest full-band "
    f"peak of {c0} is at **{top:.0f} Hz**"
    + vs_thesis(" (thesis Fig 3.4: dominant peaks can lie above 10 kHz)")
    + f", {top / float(d0['tooth_passing_hz']):.2f} times the tooth-passing frequency"
    + vs_thesis(" (the thesis attributes such peaks to tooth-passing harmonics amplified by "
                "the dynamometer/block resonance)") + "."))

# %% [markdown]
# ## Spectra in spatial frequency (kinematic peak)


# %%
def per_direction(xkey, xmax, name, title, xlabel, vlines=()):
    for direction in dirs_set:
        cs = [c for c in cuts_set if str(sp["direction"].sel(cut=c).item()) == direction]
        if not cs:
            continue
        fig, axs = plt.subplots(len(cs), 1, figsize=(7.5, 1.8 * len(cs) + 0.8), sharex=True,
                                squeeze=False)
        for axx, c in zip(axs[:, 0], cs, strict=True):
            d = sp.sel(cut=c)
            x = d[xkey].values
            p = d["power_low"].sum("axis").values
            sel = np.isfinite(x) & (x > 0) & (x <= xmax)
            axx.plot(x[sel], p[sel], lw=0.8)
            for v in vlines:
                axx.axvline(v, color="0.6", ls=":", lw=0.8)
            axx.set_ylabel("P [N²]")
            axx.set_title(f"{c}: {float(d['feed_mm_s']):g} mm/s, tooth passing "
                          f"{float(d['tooth_passing_hz']):.0f} Hz", fontsize=9)
        axs[-1, 0].set_xlabel(xlabel)
        fig.suptitle(f"{title} {dir_label(direction)}, {which}")
        save_figure(fig, fig_dir, num.file(f"{name}_{direction}"))
        plt.show()
        display(num.caption(f"{name}_{direction}"))


display(Markdown(
    "The thesis' normalized power P(k) = |Z(k)|²/N² of each whole record, summed over the three "
    "axes, against f/v ("
    + ", ".join(num.ref(f"spatial_{d}") for d in dirs_set) + ")."
    + vs_thesis(" The thesis finds the kinematic irregularity near 0.5 mm⁻¹, as on the "
                "surface.")))
per_direction("f_spatial_low", 1.0, "spatial", "Spatial-frequency power,",
              "spatial frequency f/v [1/mm]", vlines=(0.5,))
kin = pk.set_index("cut")["kinematic_per_mm"]
kin_db = settings.get("kinematic_prominence_db", 10.0)
kin_none = (f"; in {kin.isna().sum()} of {len(kin)} cuts no peak rises {kin_db:g} dB above "
            "its local floor ('none' in the table)" if kin.isna().any() else "")
kin_text = (f"median **{kin.median():.2f} mm⁻¹** over the cuts that have one (range "
            f"{kin.min():.2f}–{kin.max():.2f}" + vs_thesis("; thesis: about 0.5 mm⁻¹")
            + kin_none + ")" if kin.notna().any()
            else f"none: in no cut does a peak rise {kin_db:g} dB above its local floor")
display(Markdown(
    f"Kinematic peak (strongest local maximum in "
    f"{settings.get('kinematic_band_per_mm', [0.3, 1.0])} mm⁻¹, interpolated within its bin): "
    + kin_text + f". The resolution of a {float(sp['feed_mm_s'][0]):g} mm/s record is "
    f"1/L = {float(sp['f_spatial_low'].isel(cut=0, lf_bin=1)):.3f} mm⁻¹."))
# sanity flag: a kinematic peak with too few periods in the record cannot be resolved
if "kinematic_below_resolution" in pk:
    flagged = pk[pk["kinematic_below_resolution"].astype(bool) & pk["kinematic_per_mm"].notna()]
    cycles = settings.get("min_peak_cycles", 10.0)
    if len(flagged):
        display(Markdown(
            f"**Sanity flag: {len(flagged)} of {len(pk)} cuts have a kinematic peak below the "
            f"record's resolution** (fewer than {cycles:g} periods in the record: "
            + ", ".join(f"{r.cut} ({r.kinematic_per_mm:.2f} mm⁻¹ at 1/L = "
                        f"{r.kinematic_resolution_per_mm:.3f} mm⁻¹)"
                        for r in flagged.itertuples())
            + f"). Their kinematic peak (frequency known to worse than ±{50 / cycles:.0f} %, "
              "half a bin) is not evidence of a kinematic irregularity: record longer cuts "
              f"(at least {cycles:g} periods, {cycles / 0.5:g} mm for a 0.5 mm⁻¹ peak)."))
    else:
        display(Markdown(f"Every kinematic peak found has at least {cycles:g} periods in its "
                         "record (resolved; sanity flag `kinematic_below_resolution` in "
                         "peaks.csv)."))

# %% [markdown]
# ## Spectra in time frequency, 0–250 Hz (dominant peak)

# %%
mode_f = (mode_table["f_n_hz"].to_numpy() if mode_table is not None else np.array([]))
display(Markdown("The same records in time frequency, 0–250 Hz: "
                 + ", ".join(num.ref(f"time_{d}") for d in dirs_set) + "."))
per_direction("f_low", 250.0, "time", "Time-frequency power,", "frequency [Hz]",
              vlines=tuple(mode_f))

# %% [markdown]
# ## Per-cut peaks

# %%
tab = pk.merge(mf[["cut", "feed_mm_s", "depth_mm", "direction"]], on="cut")
if mode_table is not None and len(mode_table):
    tab = tab.join(nearest_modes(tab["dominant_hz"], mode_table))
display(num.caption("peaks"))
NONE = {"dominant_hz": "none", "kinematic_per_mm": "none"}  # no peak stands out of its floor
if THESIS_LAYOUT:
    display(tab.round(4).astype({k: object for k in NONE}).fillna(NONE))
else:  # grouped by what varies, with the force levels
    forces_cols = ["F_feed_N", "F_cross_feed_N", "F_axial_N"]
    values = ["dominant_hz", "kinematic_per_mm", *forces_cols] + [
        c for c in ("nearest_mode_hz", "offset_hz") if c in tab]
    per_cut = tab.drop(columns=["feed_mm_s", "depth_mm", "direction"]).merge(
        mf[["cut", *forces_cols]], on="cut")
    shown = per_cut_table(per_cut[["cut", *values]], values, plan, experiment).round(4)
    display(shown.astype({k: object for k in NONE if k in shown}).fillna(
        {k: v for k, v in NONE.items() if k in shown}))
    display(Markdown(
        f"{num.ref('peaks')}, grouped by {', '.join(design.grouping) or 'cut'}: mean force in "
        f"the cut frame: feed {span(mf.F_feed_N)} N, cross-feed {span(mf.F_cross_feed_N)} N, "
        f"axial {span(mf.F_axial_N)} N."))

# %%
display(Markdown(say("dominant", "dominant_none", "modes", "verdict", "no_match", "no_modes",
                     ref_peaks=num.ref("peaks"))))

# %% [markdown]
# ## Tooth-passing harmonics

# %%
hsum = hm.assign(power_N2=hm[["Fx_power_N2", "Fy_power_N2", "Fz_power_N2"]].sum(axis=1))
display(Markdown(f"{num.ref('harmonics')} lists the harmonics of the tooth-passing "
                 "frequency in the dynamometer records."))
display(num.caption("harmonics"))
# medians over the cuts of one tooth-passing frequency (one spindle speed and tool)
by_tp = hsum.merge(plan[["cut", "tooth_passing_hz"]].rename(
    columns={"tooth_passing_hz": "tooth_hz"}), on="cut")
display(by_tp.pivot_table(index=(["harmonic"] if by_tp["tooth_hz"].nunique() == 1
                                 else ["tooth_hz", "harmonic"]),
                          values=["f_hz", "power_N2"], aggfunc="median").round(4))

# %% [markdown]
# ## Cutting-coefficient identification

# %%
slot = "milling" not in process or (process["milling"] == "slot").all()
display(Markdown(
    f"Mean forces per cut in the cut frame, divided by N·a, are linear in the feed per tooth c "
    f"({num.ref('mean_forces_vs_feed')})"
    + (": F̄_y/(Na) = K_tc c/4 + K_te/π, F̄_x/(Na) = −(K_rc c/4 + K_re/π), "
       "F̄_z/(Na) = K_ac c/π + K_ae/2." if slot else
       ", with slopes and intercepts set by each cut's entry and exit angles (the average of "
       "eq. 3.1 over the engaged arc: " + ", ".join(sorted(
           {f"{r.milling} milling, a_e/D {r.radial_immersion:g}"
            for r in process.itertuples()})) + ").")))
fig, axs = plt.subplots(1, 3, figsize=(12, 3.6))
n_teeth = process["flutes"] if "flutes" in process else pd.Series(2, index=mf.index)
for axx, comp, lab in zip(axs, ["F_cross_feed_N", "F_feed_N", "F_axial_N"],
                          ["F̄_y/(Na) (tangential)", "F̄_x/(Na) (radial)", "F̄_z/(Na) (axial)"],
                          strict=True):
    for depth, g in mf.groupby("depth_mm"):
        axx.plot(g["feed_per_tooth_mm"] * 1e3, g[comp] / (n_teeth[g.index] * depth), "o",
                 ms=4, label=f"a = {depth:g} mm")
    axx.set_xlabel("feed per tooth c [µm]")
    axx.set_title(lab, fontsize=10)
axs[0].set_ylabel("N/mm")
axs[0].legend()
save_figure(fig, fig_dir, num.file("mean_forces_vs_feed"))
plt.show()
display(num.caption("mean_forces_vs_feed"))

table = coef.copy()
if truth and os.path.exists(truth):
    tr = open_artefact(truth)
    planted = {k.split("_")[1]: float(tr[k]) for k in tr.data_vars if k.startswith("cutting_")}
    table["planted"] = table["name"].map(planted)
    table["error_pct"] = 100 * (table["value"] / table["planted"] - 1)
display(num.caption("coefficients"))
display(table.set_index("name").round(3))

# %%
worst = table.loc[table["error_pct"].abs().idxmax()] if "error_pct" in table else None
msg = (f"Identified coefficients with 95 % intervals ({num.ref('coefficients')}): " + ", ".join(
    f"{r.name} = {r.value:.1f} [{r.ci_low:.1f}, {r.ci_high:.1f}] {r.unit}"
    for r in coef.itertuples()) + ". ")
if worst is not None:
    msg += (f"Against the planted values of the virtual cell the largest error is "
            f"{worst['error_pct']:+.2f} % ({worst['name']}). ")
msg += coefficient_flag_sentence(coef) + " "
msg += (vs_thesis("The thesis assumes typical aluminium values (Altintas 2012) and does not "
                  "identify them; these are the values the chatter chapter uses.")
        or "These are the values the chatter chapter uses.")
display(Markdown(msg))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("against")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
