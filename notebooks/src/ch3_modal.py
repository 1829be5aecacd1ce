# %% [markdown]
# # Chapter 3.3 — Dynamic behaviour of the tool tip: impact-test modal analysis
#
# Thesis §3.3: an impact hammer (with a force sensor) hits the tool tip along X, Y and Z; a
# triaxial accelerometer beside the tip records the response. Each FRF H[output, input] is
# averaged over the accepted hits (double hits and overloads rejected automatically, force and
# exponential windows applied, the damping the exponential window adds removed). The thesis'
# peak picking (a sign change of the real part, an extremum of the imaginary part, coherence
# above a threshold) is shown beside a least-squares complex-frequency (LSCF) fit of all
# FRFs with a stabilization chart and residues by LSFD (sdypy-EMA): natural frequency,
# damping, mode shape, modal mass and stiffness at the tool tip, for chapter 4.
#
# Any test runs: points are (node, ±direction) as in UFF (SISO, roving hammer or
# accelerometer, tri-axial responses, the thesis' 3×3 tool-tip matrix), hits as CSV or UFF 58
# time histories, or FRFs from a modal test system. Shapes are complex and normalised over the
# measured points; modal mass and stiffness need a driving point; non-physical results and
# modes with poor coherence are flagged. The thesis' numbers: "Against the thesis" below.

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
templates: str = None  # robomill/data/templates/ch3_modal.yaml: the sentences of this chapter
findings: str = None  # results/modal/findings.yaml: every number and verdict stated here
fig_dir: str = None  # folder for this chapter's figures

# %%
import pandas as pd
from IPython.display import Markdown, display

from robomill.findings import read_findings
from robomill.io import open_artefact
from robomill.io.impact import read_frf
from robomill.modal import figures
from robomill.modal.ncio import join_complex
from robomill.modal.shown import misfit_table, shown_hits, shown_modes, shown_peak_groups
from robomill.pipeline.captions import Numbering
from robomill.pipeline.prose import Prose, comparison_table, load_templates

found = read_findings(findings)
F = found.values()
say = Prose(load_templates("ch3_modal", templates), found)
ds = read_frf(frf)
sy = join_complex(open_artefact(synth))
tr = open_artefact(traces)
hit_table = pd.read_csv(hits)
mode_table = pd.read_csv(modes)
check_table = pd.read_csv(truth_check)
coupling_table = pd.read_csv(coupling)
TOOLTIP_LAYOUT = bool(F["tooltip_layout"])
band_hz = F["band_hz"]
HAS_TRACES = "time" in tr.dims

num = Numbering.for_chapter("ch3_modal", fig_dir=fig_dir)
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
display(Markdown(say("layout", "tooltip", "not_measured", "band", "band_flag", "hits",
                     ref_hits=num.ref("hits"))))
display(num.caption("hits"))
display(shown_hits(hit_table))

# %% [markdown]
# ## The test: hammer directions, and the recorded signals
#
# Left: the tool tip, the hammer directions and the accelerometer. Right: an accepted hit and
# each rejected one (a double hit shows two force pulses, an overload a clipped channel).

# %%
display(Markdown(say("signals", ref_impact_test=num.ref("impact_test") if HAS_TRACES else "")))
if HAS_TRACES:
    num.show(figures.impact_test_figure(tr, hit_table, tooltip_layout=TOOLTIP_LAYOUT),
         "impact_test")

# %% [markdown]
# ## The FRF grid: every measured FRF
#
# One panel per pair H(response point, reference point) over the analysis band; empty
# panels: pairs this layout did not measure.

# %%
num.show(figures.frf_grid_figure(ds, sy, band_hz), "frf_grid")
display(Markdown(say("frf_grid", ref_frf_grid=num.ref("frf_grid"))))

# %% [markdown]
# ## What was found
#
# ### The nine FRFs: real part, imaginary part, coherence
#
# (The 3×3 tool-tip layout.) Receptance H1 averaged over the accepted hits of each hammer
# direction; dashed: the FRF synthesized from the identified modes (LSFD).

# %%
display(Markdown(say("frf_nine", **({"ref_frf_first": num.ref("frf_{}{}".format(*FRF_PAIRS[0])),
                                     "ref_frf_last": num.ref("frf_{}{}".format(*FRF_PAIRS[-1]))}
                                    if FRF_PAIRS else {}))))
for o, i in FRF_PAIRS:
    num.ref(f"frf_{o}{i}")
    num.show(figures.frf_pair_figure(ds, sy, o, i, band_hz, F["threshold_n_coherence_ok"]),
         f"frf_{o}{i}")

# %% [markdown]
# ### Peak picking (the thesis' criteria)
#
# Every extremum of Im H rising at least `modal.peak_floor_db` above its local floor (a
# shoulder or a ripple on a stronger peak's skirt is none), its frequency interpolated between
# the lines, the two criteria checked separately; a frequency counts when it meets both on at
# least one FRF.

# %%
display(Markdown(say("peaks", "peak_groups", "peak_limit",
                     ref_peak_groups=num.ref("peak_groups"))))
display(num.caption("peak_groups"))
shown_peak_groups(pd.read_csv(peak_groups))

# %% [markdown]
# ### Stabilization chart (LSCF, sdypy-EMA)
#
# Poles of every model order; a pole is stable when the previous order has one within the
# tolerances in frequency, damping and residue-vector MAC. Background: Σ|H| over the FRFs.

# %%
num.show(figures.stabilization_figure(pd.read_csv(stabilization), mode_table, ds, band_hz),
     "stabilization")
display(Markdown(say("stability_tolerances", "stabilization",
                     ref_stabilization=num.ref("stabilization"))))

# %% [markdown]
# ### The modes
#
# Natural frequency, damping (the exponential window's σ removed by shifting the poles),
# shape, modal mass and stiffness ``k = m ω_n²`` of the unit shape (only with a driving
# point); ``rank1`` near 1: the tool-tip residue matrix is the φφᵀ of one real mode; ``flags``:
# non-physical (negative modal mass), unscaled (no driving point) or poorly coherent modes.

# %%
display(Markdown(say("modes", "flags", sep="\n\n", ref_modes=num.ref("modes"))))
display(num.caption("modes"))
shown_modes(mode_table)

# %% [markdown]
# ### MAC matrix and the shapes along the nodes
#
# The modal assurance criterion between every pair of shapes (off-diagonal values near 1: the
# measured points cannot tell two modes apart), and the real part of the unit shapes along
# the node numbers, one line per direction (for one node: bars per direction).

# %%
num.show(figures.mac_shapes_figure(pd.read_csv(mac).set_index("mode"), pd.read_csv(shapes),
                               mode_table), "mac_shapes")
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
display(Markdown(say("misfit", ref_misfit=num.ref("misfit"))))
display(num.caption("misfit"))
misfit_table(ds, sy, band_hz)

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
