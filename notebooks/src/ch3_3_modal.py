# %% [markdown]
# # Chapter 3.3 — Dynamic behaviour of the tool tip: impact-test modal analysis
#
# Thesis §3.3: an impact hammer (with a force sensor) hits the tool tip along X, Y and Z; a
# triaxial accelerometer beside the tip records the response. Each of the nine FRFs
# H[output, input] is averaged over the accepted hits, and a natural frequency is where the
# real part changes sign between a maximum and a minimum, the imaginary part has an extremum
# and the coherence exceeds a threshold (the thesis' numbers: "Against the thesis" below).
#
# This pipeline goes further: double hits and overloads are rejected automatically, force and
# exponential windows are applied (and the damping the exponential window adds is removed),
# and the modal parameters come from a least-squares complex-frequency (LSCF) fit of all nine
# FRFs with a stabilization chart, then residues by LSFD (sdypy-EMA): natural frequency,
# damping, 3-D mode shape, modal mass and stiffness at the tool tip, for chapter 4.
#
# The chapter shows whatever test was measured: points are (node, ±direction) as in UFF, so a
# single-axis (SISO) test, a roving hammer, a roving accelerometer, tri-axial responses and
# the thesis' 3×3 tool-tip matrix all run; hits may come as CSV or as UFF 58 time histories,
# or the FRFs straight from a modal test system as UFF 58. Mode shapes are complex and
# normalised over the measured points; modal mass and stiffness need a driving point;
# non-physical results (negative modal constants) and modes with poor coherence are flagged.

# %% tags=["parameters"]
frf: str = None  # results/modal/frf.nc
synth: str = None  # results/modal/frf_synth.nc
traces: str = None  # results/modal/hits.nc
hits: str = None  # results/modal/hits.csv
modes: str = None  # results/modal/modes.csv
peaks: str = None  # results/modal/peak_picking.csv
stabilization: str = None  # results/modal/stabilization.csv
shapes: str = None  # results/modal/mode_shapes.csv
mac: str = None  # results/modal/mac.csv
peak_groups: str = None  # results/modal/peak_groups.csv
truth_check: str = None  # results/modal/truth_check.csv
coupling: str = None  # results/modal/coupling.csv
coupling_pairs: str = None  # results/modal/coupling_pairs.csv
templates: str = None  # notebooks/templates/ch3_3.yaml: the sentences of this chapter
findings: str = None  # results/modal/findings.yaml: every number and verdict stated here
fig_dir: str = None  # folder for this chapter's figures
thesis_study: bool = None  # unused: the comparison rows come with the findings

# %%
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import Markdown, display

from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.io.impact import read_frf
from robomill.modal.checks import synthesis_misfit
from robomill.modal.layout import points
from robomill.modal.ncio import join_complex
from robomill.pipeline.captions import Numbering
from robomill.pipeline.prose import Prose, comparison_table, load_templates
from robomill.plotting import save_figure

found = read_findings(findings)
F = found.values()
say = Prose(load_templates("ch3_3", templates), found)
ds = read_frf(frf)
sy = join_complex(open_artefact(synth))
tr = open_artefact(traces)
hit_table = pd.read_csv(hits)
mode_table = pd.read_csv(modes)
peak_table = pd.read_csv(peaks)
stab = pd.read_csv(stabilization)
shape_table = pd.read_csv(shapes)
mac_table = pd.read_csv(mac).set_index("mode")
grouped = pd.read_csv(peak_groups)
check_table = pd.read_csv(truth_check)
coupling_table = pd.read_csv(coupling)
pair_table = pd.read_csv(coupling_pairs)
f = ds["frequency"].values
outs, ins = points(ds, "output"), points(ds, "input")
TOOLTIP_LAYOUT = bool(F["tooltip_layout"])
measured = [(o, i) for o in ds["output"].values.tolist() for i in ds["input"].values.tolist()
            if np.isfinite(ds["H"].sel(output=o, input=i).values[1:]).any()]
band_hz = F["band_hz"]
HAS_TRACES = "time" in tr.dims

num = Numbering("3")
if HAS_TRACES:
    num.figure("impact_test", "The test: the tool tip, the three hammer directions and the "
               "accelerometer; force and accelerations of an accepted hit and of every "
               "rejected one", number=18, stem="fig3_18_impact_test")
num.figure("frf_grid", "Every measured FRF: |H| measured (black), synthesized from the "
           "identified modes (red, dashed) and the coherence (blue)", number=19,
           stem="frf_grid")
FRF_PAIRS = [(o, i) for o in ("XYZ" if TOOLTIP_LAYOUT else "") for i in "XYZ"]
for k, (o, i) in enumerate(FRF_PAIRS):
    num.figure(f"frf_{o}{i}", f"Response {o} / hammer {i}: real part, imaginary part and "
               "coherence of the receptance, measured (H1) and synthesized",
               number=20 + k, stem=f"fig3_{20 + k}_frf_{o}{i}")
num.figure("stabilization", "Stabilization chart of the LSCF fit over all measured FRFs, "
           "on the sum of |H|", number=29, stem="fig3_29_stabilization")
num.figure("mac_shapes", "MAC matrix of the identified shapes, and the shapes over the "
           "measured points", number=30, stem="mac_and_shapes")
num.table("hits", "The recorded hits: accepted or rejected, and why", number=11)
num.table("peak_groups", "The thesis' peak picking: frequencies meeting both criteria, "
          "grouped over the FRFs", number=12)
num.table("modes", "The identified modes: natural frequency, damping, tool-tip shape, modal "
          "mass and stiffness, sanity flags", number=13)
if len(check_table):
    num.table("truth", "Identified against planted modes (synthetic run)", number=14)
num.table("misfit", "Relative misfit of the synthesized FRFs, ‖H_synth − H‖/‖H‖ [%]",
          number=15)
if len(coupling_table):
    num.table("coupling", "Modes against the cutting vibration frequency", number=16)

# %% [markdown]
# ## What was measured

# %%
display(Markdown(say("layout", "tooltip", "band", "band_flag", "hits",
                     ref_hits=num.ref("hits"))))
display(num.caption("hits"))
display(hit_table[["direction", "hit", "accepted", "reason", "peak_force_N"]]
        if len(hit_table) else hit_table)

# %% [markdown]
# ## The test: hammer directions, and the recorded signals
#
# Left: the tool tip, the three hammer directions (base X, Y, Z) and the triaxial
# accelerometer. Right: force and accelerations of an accepted hit, and of each rejected one
# (a double hit shows two force pulses; an overload shows a flat, clipped channel).

# %%
def figure_3_18():
    """The test drawing and the signals of an accepted and of every rejected hit."""
    t = tr["time"].values
    acc_idx = [i for i, a in enumerate(tr["accepted"].values) if a]
    show = acc_idx[:1] + [i for i, a in enumerate(tr["accepted"].values) if not a]
    fig = plt.figure(figsize=(11, 2.6 + 2.2 * len(show)))
    ax0 = fig.add_subplot(1, 3, 1)
    ax0.add_patch(plt.Rectangle((-0.15, 0.0), 0.3, 1.6, color="0.6"))
    ax0.add_patch(plt.Rectangle((-0.06, -0.9), 0.12, 0.9, color="0.3"))
    ax0.add_patch(plt.Rectangle((0.08, -0.5), 0.25, 0.25, color="tab:orange"))
    ax0.text(0.36, -0.38, "accelerometer", fontsize=8)
    for (dx, dy, lab) in [(-1.0, 0.0, "X"), (0.0, -1.0, "Z")]:
        ax0.annotate("", xy=(-0.07 if dx else 0, -0.6 if dx else -0.95),
                     xytext=(dx - 0.07, -0.6 + dy if dx else -1.9),
                     arrowprops=dict(arrowstyle="->", lw=2, color="tab:red"))
        ax0.text(dx - 0.3 if dx else 0.05, -0.5 if dx else -1.8, f"hammer {lab}",
                 color="tab:red", fontsize=8)
    ax0.plot(-0.55, -0.6, "o", ms=9, mfc="none", mec="tab:red")
    ax0.text(-0.85, -0.95, "hammer Y (⊙)", color="tab:red", fontsize=8)
    ax0.set_xlim(-1.4, 1.2)
    ax0.set_ylim(-2.0, 1.8)
    ax0.set_aspect("equal")
    ax0.axis("off")
    ax0.set_title("tool tip, spindle and hits" if TOOLTIP_LAYOUT else
                  "the thesis' tool-tip test (for reference)")
    for r, i in enumerate(show):
        axf = fig.add_subplot(len(show), 3, 3 * r + 2)
        axa = fig.add_subplot(len(show), 3, 3 * r + 3)
        name = str(tr["hit_file"].values[i])
        axf.plot(1e3 * t, tr["force_N"].values[i], "k", lw=0.8)
        t_trig_ms = 1e3 * float(hit_table.set_index("path").loc[name, "trigger_s"])
        axf.set_xlim(t_trig_ms - 10, t_trig_ms + 60)
        axf.set_ylabel("force [N]")
        reason = hit_table.set_index("path").loc[name, "reason"]
        axf.set_title(f"{name}: {reason[:48]}", fontsize=8)
        for c, col in zip(["ax_ms2", "ay_ms2", "az_ms2"],
                          ["tab:blue", "tab:green", "tab:purple"], strict=True):
            axa.plot(t, tr[c].values[i], color=col, lw=0.6, label=c[:2])
        axa.set_ylabel("acceleration [m/s²]")
        axa.legend(fontsize=7, loc="upper right")
    axf.set_xlabel("time [ms]")
    axa.set_xlabel("time [s]")
    fig.tight_layout()
    save_figure(fig, fig_dir, num.file("impact_test"))
    plt.show()
    display(num.caption("impact_test"))


display(Markdown(say("signals", ref_impact_test=num.ref("impact_test") if HAS_TRACES else "")))
if HAS_TRACES:
    figure_3_18()

# %% [markdown]
# ## The FRF grid: every measured FRF
#
# One panel per measured pair H(response point, reference point): |H| of the receptance
# (black), the FRF synthesized from the identified modes (red, dashed) and the coherence
# (blue, right axis) over the analysis band. Empty panels: pairs this layout did not measure.

# %%
band = (f >= band_hz[0]) & (f <= band_hz[1])
n_o, n_i = len(outs), len(ins)
fig, axs = plt.subplots(n_o, n_i, figsize=(min(3.2 * n_i, 14), min(2.2 * n_o, 24)),
                        squeeze=False, sharex=True)
for a, o in enumerate(ds["output"].values.tolist()):
    for b, i in enumerate(ds["input"].values.tolist()):
        ax = axs[a, b]
        if (o, i) not in measured:
            ax.axis("off")
            continue
        h = ds["H"].sel(output=o, input=i).values
        hs = sy["H_synth"].sel(output=o, input=i).values
        ax.semilogy(f[band], np.abs(h[band]), "k", lw=0.8)
        ax.semilogy(f[band], np.abs(hs[band]), "r--", lw=0.8)
        ax.set_title(f"{o} / {i}", fontsize=8)
        if "coherence" in ds:
            ax2 = ax.twinx()
            ax2.plot(f[band], ds["coherence"].sel(output=o, input=i).values[band], "b",
                     lw=0.5, alpha=0.6)
            ax2.set_ylim(0, 1.05)
            ax2.grid(False)
            ax2.tick_params(labelsize=6)
        ax.tick_params(labelsize=6)
for ax in axs[-1]:
    ax.set_xlabel("frequency [Hz]", fontsize=8)
fig.suptitle("|H| [m/N] measured (black), synthesized (red), coherence (blue)", fontsize=9)
fig.tight_layout()
save_figure(fig, fig_dir, num.file("frf_grid"))
plt.show()
display(num.caption("frf_grid"))
display(Markdown(say("frf_grid", ref_frf_grid=num.ref("frf_grid"))))

# %% [markdown]
# ## What was found
#
# ### The nine FRFs: real part, imaginary part, coherence
#
# (The thesis' 3×3 tool-tip layout.) Receptance H1 (m/N) averaged over the accepted hits of
# each hammer direction; the dashed line is the FRF synthesized from the identified modes
# (LSFD).

# %%
display(Markdown(say("frf_nine", **({"ref_frf_first": num.ref(f"frf_{FRF_PAIRS[0][0]}"
                                                               f"{FRF_PAIRS[0][1]}"),
                                     "ref_frf_last": num.ref(f"frf_{FRF_PAIRS[-1][0]}"
                                                              f"{FRF_PAIRS[-1][1]}")}
                                    if FRF_PAIRS else {}))))
for o, i in FRF_PAIRS:
    num.ref(f"frf_{o}{i}")
    h = ds["H"].sel(output=o, input=i).values
    hs = sy["H_synth"].sel(output=o, input=i).values
    coh = ds["coherence"].sel(output=o, input=i).values
    fig, axs = plt.subplots(3, 1, figsize=(7.5, 6.0), sharex=True)
    axs[0].plot(f[band], 1e6 * h.real[band], "k", lw=1, label="measured (H1)")
    axs[0].plot(f[band], 1e6 * hs.real[band], "r--", lw=1, label="synthesized (modes)")
    axs[1].plot(f[band], 1e6 * h.imag[band], "k", lw=1)
    axs[1].plot(f[band], 1e6 * hs.imag[band], "r--", lw=1)
    axs[2].plot(f[band], coh[band], "b", lw=1)
    c_min = F["threshold_n_coherence_ok"]
    axs[2].axhline(c_min, color="tab:orange", ls=":", label=f"modal.coherence_min = {c_min:g}")
    axs[0].set_ylabel("Re H [µm/N]")
    axs[1].set_ylabel("Im H [µm/N]")
    axs[2].set_ylabel("coherence")
    axs[2].set_ylim(0, 1.05)
    axs[2].set_xlabel("frequency [Hz]")
    axs[0].legend(fontsize=8)
    axs[2].legend(fontsize=8, loc="lower right")
    axs[0].set_title(f"response {o} / hammer {i}")
    save_figure(fig, fig_dir, num.file(f"frf_{o}{i}"))
    plt.show()
    display(num.caption(f"frf_{o}{i}"))

# %% [markdown]
# ### Peak picking (the thesis' criteria)
#
# Every extremum of Im H that stands out of its neighbourhood (it rises at least
# `modal.peak_floor_db` above its local floor: a shoulder or a ripple on a stronger peak's
# skirt is none), its frequency interpolated between the FRF lines, with the two criteria
# checked separately. A frequency counts when it meets both on at least one FRF.

# %%
display(Markdown(say("peaks", "peak_groups", ref_peak_groups=num.ref("peak_groups"))
                 + " Peak picking cannot separate modes whose half-power bands overlap on the "
                 "FRF where both respond; the LSCF fit below does."))
display(num.caption("peak_groups"))
grouped.round(2)

# %% [markdown]
# ### Stabilization chart (LSCF, sdypy-EMA)
#
# Poles of every model order; a pole is stable when the previous order has one within the
# configured tolerances in frequency and damping and with a residue vector of high MAC (below).
# The background curve is the sum of |H| over all measured FRFs.

# %%
fig, ax = plt.subplots(figsize=(9, 5))
style = {"new": ("x", "0.7", "new"), "f": ("v", "tab:orange", "stable in f"),
         "fd": ("s", "tab:blue", "stable in f, ζ"), "stable": ("o", "tab:green",
                                                               "stable in f, ζ, MAC")}
for status, (mk, col, lab) in style.items():
    s = stab[stab["status"] == status]
    ax.plot(s["f_hz"], s["order"], mk, color=col, ms=4, mfc="none" if mk != "x" else col,
            label=f"{lab} ({len(s)})")
for fn in mode_table["f_n_hz"]:
    ax.axvline(fn, color="tab:green", lw=0.6, alpha=0.5)
ax2 = ax.twinx()
ax2.semilogy(f[band], np.nansum(np.abs(ds["H"].values), axis=(0, 1))[band], "k", lw=0.8)
ax2.set_ylabel("Σ|H| [m/N]")
ax2.grid(False)
ax.set_xlabel("frequency [Hz]")
ax.set_ylabel("model order")
ax.legend(fontsize=8, loc="upper left")
ax.set_title("Stabilization chart")
save_figure(fig, fig_dir, num.file("stabilization"))
plt.show()
display(num.caption("stabilization"))
display(Markdown(say("stability_tolerances", "stabilization",
                     ref_stabilization=num.ref("stabilization"))))

# %% [markdown]
# ### The modes
#
# Natural frequency, damping (exponential-window damping removed: ζ = ζ_windowed − σ/ω_n to
# first order, exactly by shifting the poles by σ), shape, modal mass and stiffness of the
# unit shape over the measured points (``k = m ω_n²``; only with a driving point). For the
# tool-tip matrix ``rank1`` is near 1 when the residue matrix is the φφᵀ of a single real
# mode. ``flags`` says what is not physical (negative modal mass or stiffness), what could
# not be scaled (no driving point) and which modes have a mean coherence below the threshold.

# %%
display(Markdown(say("modes", ref_modes=num.ref("modes"))))
display(Markdown(say("flags")))
display(num.caption("modes"))
mode_table.round({"f_n_hz": 3, "zeta": 4, "zeta_windowed": 4, "k_modal_N_m": 0,
                  "m_modal_kg": 3, "shape_x": 3, "shape_y": 3, "shape_z": 3, "rank1": 3,
                  "coherence": 3})

# %% [markdown]
# ### MAC matrix and the shapes along the nodes
#
# The modal assurance criterion between every pair of identified shapes (1 on the diagonal;
# off-diagonal values near 1 mean the measured points cannot tell two modes apart), and the
# shapes over the measured points: the real part of the unit complex shape, one line per
# direction along the node numbers (for one node: bars per direction).

# %%
fig, (axm, axs_) = plt.subplots(1, 2, figsize=(11, 4.2))
im = axm.imshow(mac_table.to_numpy(float), vmin=0, vmax=1, cmap="viridis")
axm.set_xticks(range(len(mac_table)), [c.replace("mode_", "") for c in mac_table.columns])
axm.set_yticks(range(len(mac_table)), mac_table.index)
axm.set_xlabel("mode")
axm.set_ylabel("mode")
axm.set_title("MAC")
for a in range(len(mac_table)):
    for b in range(len(mac_table)):
        axm.text(b, a, f"{mac_table.iloc[a, b]:.2f}", ha="center", va="center", fontsize=6,
                 color="w" if mac_table.iloc[a, b] < 0.5 else "k")
fig.colorbar(im, ax=axm, shrink=0.8)
nodes = sorted(shape_table["node"].unique())
for m in mode_table["mode"]:
    st = shape_table[shape_table["mode"] == m]
    for d, ls in ((1, "-"), (2, "--"), (3, ":")):
        sd = st[st["direction"].abs() == d].sort_values("node")
        if sd.empty:
            continue
        y = np.sign(sd["direction"]) * sd["shape_real"]
        if len(nodes) > 1:
            axs_.plot(sd["node"], y, ls, marker="o", ms=3, label=f"mode {m} {'XYZ'[d - 1]}")
        else:
            axs_.bar(m + 0.25 * (d - 2), y.iloc[0], width=0.25,
                     color=["tab:blue", "tab:green", "tab:purple"][d - 1],
                     label="XYZ"[d - 1] if m == mode_table["mode"].iloc[0] else None)
axs_.axhline(0, color="0.5", lw=0.6)
axs_.set_xlabel("node" if len(nodes) > 1 else "mode")
axs_.set_ylabel("Re φ (unit shape, positive axes)")
axs_.legend(fontsize=6, ncol=2)
axs_.set_title("mode shapes over the measured points")
fig.tight_layout()
save_figure(fig, fig_dir, num.file("mac_shapes"))
plt.show()
display(num.caption("mac_shapes"))
display(Markdown(say("mac", ref_mac_shapes=num.ref("mac_shapes"))))

# %% [markdown]
# ### Against the planted truth (synthetic run)

# %%
display(Markdown(say("truth", ref_truth=num.ref("truth") if len(check_table) else "")))
if len(check_table):
    display(num.caption("truth"))
    display(check_table.round(4))

# %% [markdown]
# ### Synthesized against measured FRFs

# %%
err_table = synthesis_misfit(ds, sy["H_synth"].values, band_hz)
display(Markdown(say("misfit", ref_misfit=num.ref("misfit"))))
display(num.caption("misfit"))
err_table.round(2)

# %% [markdown]
# ## What it means: which modes lie near the vibration frequency?
#
# The vibration frequency is the dominant force-spectrum frequency found by chapter 3.1
# (median over the cuts); a mode is "close" when it lies within `modal.coupling_tolerance` of
# it. Close modes are the candidates for mode coupling.

# %%
display(Markdown(say("coupling_layout", "coupling", "close_list", "coupling_pairs",
                     "coupling_none",
                     ref_coupling=num.ref("coupling") if len(coupling_table) else "")))
if len(coupling_table):
    display(num.caption("coupling"))
    display(coupling_table.round(4))

# %% [markdown]
# ## Against the thesis

# %%
display(Markdown(say("thesis_test", "against")))
comparison_table(found) if found.comparisons else None

# %%
num.check()
