# %% [markdown]
# # Chapter 5 — Stiffness and pose
#
# Two stiffness models of a robot arm, from the two source papers, and what they say about the
# thesis robot:
#
# * **Joint-stiffness model** (seed 001, Yi et al. 2025, KUKA KR360): rigid links, elastic
#   joints; TCP deflection X = J K_θ⁻¹ Jᵀ F, identified from load tests as X = A(J, F) k by
#   least squares; Cartesian stiffness K = J⁻ᵀ K_θ J⁻¹; directional stiffness along the tool
#   axes; maps over the milling plane for redundancy angles; the stiffness-optimal pose.
# * **Beam-frame model** (seed 004, Cai et al. 2015, MOTOMAN-HP20): the arm as 7 beam
#   elements with 6 DOF per node, node 1 fixed, δ = K⁻¹F; the pneumatic-wheel load and the
#   vibration predictor σ(t).
#
# The KR360's MD-H table is not printed in seed 001, so its parameters are *assumed* (documented
# in `config.yaml`); the synthetic load tests are drawn from the seed's identified K_θ.

# %% tags=["parameters"]
maps: str = None  # results/stiffness/maps.nc
optimal: str = None  # results/stiffness/optimal_poses.csv
beamframe: str = None  # results/stiffness/beamframe.nc
map_joints: str = None  # results/stiffness/<map robot>/joint_stiffness.csv
map_models: str = None  # results/stiffness/<map robot>/identification.csv
map_validation: str = None  # results/stiffness/<map robot>/validation.csv
thesis_joints: str = None  # results/stiffness/<thesis robot>/joint_stiffness.csv
thesis_validation: str = None  # results/stiffness/<thesis robot>/validation.csv
slots: str = None  # results/stiffness/thesis_slots.csv (thesis design only)
waviness: str = None  # results/surface/table_2_1_waviness_rms.csv (thesis design only)
cut_stiffness: str = None  # results/stiffness/cut_stiffness.csv (other designs; cell robot tested)
cuts: str = None  # results/ingest/cuts.csv (with cut_stiffness)
truth: str = None  # results/synthetic/truth.nc (synthetic runs only)
experiment: dict = None  # the manifest's experiment defaults (spindle_rpm, flutes, ...)
thesis_design: bool = None  # the thesis' design (robomill.experiment.is_thesis_design)
thesis_study: bool = None  # the thesis' study (robomill.experiment.is_thesis_study)
fig_dir: str = None  # folder for this chapter's figures

# %%
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import Markdown, display

from robomill import references as REF
from robomill.io import open_artefact
from robomill.pipeline.captions import Numbering
from robomill.pipeline.design_tables import per_cut_table, span, thesis_gate
from robomill.plotting import save_figure
from robomill.stiffness.cuts import (
    slot_stiffness_table,
    stiffness_spread_pct,
    waviness_by_direction,
)

# The numbers printed by seed 001 (Yi et al. 2025), for comparison: read from the one data file
# of the sources' numbers, each with its citation (src/robomill/data/references.yaml).
SEED_K3D_kNm = [v / 1e3 for v in REF.values(
    "seed001.stiffness.joint_stiffness_3d.k_Nm_rad.").values()]
SEED_K2D_kNm = [v / 1e3 for v in REF.values(
    "seed001.stiffness.joint_stiffness.k_Nm_rad.").values()]
SEED_VALIDATION = {  # % error of the predicted deflection (0.325 mm)
    "cube": REF.value("seed001.validation_error_pct.cube"),
    "plane": REF.value("seed001.stiffness.validation.vector_error_pct.model_plane.mean")}
SEED_DEFORMATION_UM = {h: REF.value("seed001.stiffness.optimal_poses.deformation_um."
                                    f"robot_kr360_height_mm_{h:.0f}_pose_optimal")
                       for h in (1600.0, 1200.0)}
SEED_Y_MAX = {a: REF.value(f"seed001.y_stiffness_max_N_m.angle_{a}deg") for a in (0, 30, 60)}
SEED_Z_0DEG_N_MM = REF.value("seed001.z_stiffness_0deg_N_mm")
SEED_WORKSPACE = {k: tuple(REF.value(f"seed001.workspace_extent_mm.{key}")) for k, key in
                  (("X", "x"), ("Y", "y"), ("Z", "z"), ("XZ_X", "xz_plane_x"),
                   ("XZ_Z", "xz_plane_z"))}
SEED_WORKSPACE["annulus"] = tuple(REF.value(f"seed001.stiffness.maps.annulus_{e}_diameter_mm."
                                            "height_mm_1600") for e in ("inner", "outer"))

mp = open_artefact(maps)
opt = pd.read_csv(optimal)
bf = open_artefact(beamframe)
joints = pd.read_csv(map_joints)
models = pd.read_csv(map_models)
val = pd.read_csv(map_validation)
robot_name = mp.attrs.get("robot", "robot")
heights = mp["height_mm"].values
vs_thesis = thesis_gate(thesis_study)
# 5.6 compares the thesis robot at the thesis' slots with Table 2.1: its design only
SLOTS = thesis_design is not False and slots is not None and waviness is not None
# any other design: the cell's own robot at every cut, when it has load tests
CUTS_K = not SLOTS and cut_stiffness is not None

num = Numbering("5")
num.table("workspace_ranges", "Workspace ranges: seed 001 against our Monte-Carlo workspace")
num.figure("workspace", "Monte-Carlo workspace: X–Z projection of the 3-D workspace and the "
           "X–Z plane")
num.table("joints", "Identified joint stiffnesses with 95 % intervals, per model, beside the "
          "seed's 3-D and plane values")
num.table("identification", "The identifications: poses used, condition number, residual")
num.table("validation", "Mean absolute error of the predicted deflection on the validation "
          "poses")
for i, h in enumerate(heights):
    num.figure(f"maps_h{h:.0f}", f"Directional stiffness along the tool axes over the working "
               f"plane, H = {h:.0f} mm, every redundancy angle (seed 001 Fig. 11)", number=2,
               part="abcdefgh"[i] if len(heights) > 1 else "")
num.table("maxima", "Largest directional stiffness per height and redundancy angle")
num.table("optimal", "The stiffness-optimal pose and random poses: deformation under the end "
          "load")
num.figure("optimal_poses", "Deformation under the end load, optimal against random poses "
           "(dashed: the seed's optimum)")
num.figure("beamframe", "Beam-frame model: nodes at t = 0, and the tool displacement with the "
           "predicted σ(t) (seed 004, eq. 17)")
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
# ## 5.1 Workspace (seed 001 §2)

# %%
ws = mp["workspace_mm"].values
wxz = mp["workspace_xz_mm"].values
rows = [("X (3-D)", *SEED_WORKSPACE["X"], ws[:, 0].min(), ws[:, 0].max()),
        ("Y (3-D)", *SEED_WORKSPACE["Y"], ws[:, 1].min(), ws[:, 1].max()),
        ("Z (3-D)", *SEED_WORKSPACE["Z"], ws[:, 2].min(), ws[:, 2].max()),
        ("X (X–Z plane)", *SEED_WORKSPACE["XZ_X"], wxz[:, 0].min(), wxz[:, 0].max()),
        ("Z (X–Z plane)", *SEED_WORKSPACE["XZ_Z"], wxz[:, 2].min(), wxz[:, 2].max())]
ws_table = pd.DataFrame(rows, columns=["range", "seed min mm", "seed max mm", "ours min mm",
                                       "ours max mm"]).round(0)
display(num.caption("workspace_ranges"))
display(ws_table)
ann = pd.DataFrame({"height_mm": mp["height_mm"].values,
                    "inner diameter mm": mp["annulus_inner_diameter_mm"].values,
                    "outer diameter mm": mp["annulus_outer_diameter_mm"].values})
display(Markdown(
    f"{num.ref('workspace_ranges')} and {num.ref('workspace')}: Monte-Carlo workspace of the "
    f"assumed {robot_name} with N = {len(ws)} samples. The "
    "ranges differ from the seed's by the assumed link lengths, joint limits and end effector "
    "(the seed's MD-H table is not printed). Working-plane annulus with the tool pointing "
    f"down: inner diameter {ann['inner diameter mm'].min():.0f} mm, outer "
    f"{ann['outer diameter mm'].max():.0f} mm (grid resolution; seed: "
    f"{SEED_WORKSPACE['annulus'][0]:g} and {SEED_WORKSPACE['annulus'][1]:g} mm — the seed's plane "
    "also depends on its end-effector orientation and joint limits, which are not given)."))

# %%
fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
axes[0].scatter(ws[:, 0], ws[:, 2], s=1, alpha=0.3)
axes[0].set(xlabel="X [mm]", ylabel="Z [mm]", title="3-D workspace (X–Z projection)")
axes[1].scatter(wxz[:, 0], wxz[:, 2], s=1, alpha=0.3, color="C1")
axes[1].set(xlabel="X [mm]", ylabel="Z [mm]", title="X–Z plane (joints 1, 5, 6 at 0)")
for ax in axes:
    ax.set_aspect("equal")
save_figure(fig, fig_dir, num.file("workspace"))
plt.show()
display(num.caption("workspace"))

# %% [markdown]
# ## 5.2 Joint-stiffness identification (seed 001 §3)

# %%
tab = joints.copy()
tab["k kN·m/rad"] = tab["k_Nm_rad"] / 1e3
tab["95 % CI kN·m/rad"] = [f"{lo / 1e3:.4g} … {hi / 1e3:.4g}" for lo, hi in
                           zip(tab["ci95_low_Nm_rad"], tab["ci95_high_Nm_rad"], strict=True)]
for name in ("cube", "plane"):
    if name in set(models["model"]):
        row = models.set_index("model").loc[name]
        tab[f"{name} kN·m/rad"] = [row[f"k{j}_Nm_rad"] / 1e3 for j in tab["joint"]]
tab["seed 3-D kN·m/rad"] = SEED_K3D_kNm[:len(tab)]
tab["seed plane kN·m/rad"] = SEED_K2D_kNm[:len(tab)]
if truth is not None:
    tr = open_artefact(truth)
    planted = tr["stiffness_k_Nm_rad"].sel(stiffness_robot=robot_name).values[:len(tab)]
    tab["planted kN·m/rad"] = planted / 1e3
display(num.caption("joints"))
display(tab.drop(columns=["k_Nm_rad", "ci95_low_Nm_rad", "ci95_high_Nm_rad"]).round(4))
summary = models[["model", "n_poses", "condition_number", "residual_rms_um", "warnings"]]
display(num.caption("identification"))
display(summary.round(3))
display(Markdown(
    f"{num.ref('joints')} and {num.ref('identification')}: the synthetic load tests are drawn "
    "from the seed's plane-identified K_θ (planted), so "
    "every identification here should find those values within its interval; the seed's "
    "3-D and plane values differ because a real arm is not a pure joint-stiffness model "
    "(link bending, gravity), which the simulator does not add."))

# %%
v = val.groupby("model")[["error_pct", "vector_error_pct"]].agg(lambda s: np.abs(s).mean())
v["seed error %"] = [SEED_VALIDATION.get(m, np.nan) for m in v.index]
display(num.caption("validation"))
display(v.round(2))
if len(val):
    display(Markdown(
        f"{num.ref('validation')}: mean absolute error of the predicted deflection magnitude on "
        f"{val['pose'].nunique()} "
        f"validation poses: {', '.join(f'{m} {e:.2f} %' for m, e in v['error_pct'].items())} "
        "(seed: 4.0 % for the 3-D and 3.1 % for the plane identification at one test pose, "
        "0.338 / 0.335 mm predicted vs 0.325 mm measured)."))
else:
    display(Markdown(f"No validation poses in this run ({num.ref('validation')} is empty)."))

# %% [markdown]
# ## 5.3 Directional stiffness over the working plane (seed 001 §4.2, Fig. 11)

# %%
display(Markdown("Stiffness along the tool axes over the working plane, one figure per "
                 "height: " + ", ".join(num.ref(f"maps_h{h:.0f}") for h in heights) + "."))
axes_names = ["X", "Y", "Z"]
for h in heights:
    red = mp["redundancy_deg"].values
    fig, axs = plt.subplots(len(red), 3, figsize=(11, 3.2 * len(red)), squeeze=False)
    for i, r in enumerate(red):
        for j, a in enumerate(axes_names):
            k = mp["k_N_m"].sel(height_mm=h, redundancy_deg=r, axis=a).values / 1e6
            im = axs[i, j].pcolormesh(mp["x"], mp["y"], k, shading="nearest", cmap="viridis")
            axs[i, j].set_aspect("equal")
            axs[i, j].set_title(f"k_{a}, θr = {r:.0f}°", fontsize=9)
            fig.colorbar(im, ax=axs[i, j], label="N/µm")
    fig.suptitle(f"Directional stiffness along the tool axes, H = {h:.0f} mm")
    fig.tight_layout()
    save_figure(fig, fig_dir, num.file(f"maps_h{h:.0f}"))
    plt.show()
    display(num.caption(f"maps_h{h:.0f}"))

# %%
mx = mp["k_N_m"].max(dim=("x", "y")).to_dataframe().reset_index().pivot_table(
    index=["height_mm", "redundancy_deg"], columns="axis", values="k_N_m") / 1e6
mx.columns = [f"max k_{c} N/µm" for c in mx.columns]
mx["seed max k_Y (printed N/m)"] = [SEED_Y_MAX.get(int(r), np.nan) for _, r in mx.index]
display(num.caption("maxima"))
display(mx.round(3))
display(Markdown(
    f"{num.ref('maxima')}: our Z stiffness reaches {mx['max k_Z N/µm'].max():.2f} N/µm; seed "
    "001 reports "
    f"{SEED_Z_0DEG_N_MM} N/mm = {SEED_Z_0DEG_N_MM / 1e3:.2f} N/µm at θr = 0° (+200.6 N/mm at "
    "30°). The seed's Y maxima are printed as 93 000 N/m, i.e. 0.093 N/µm: far below its "
    "own Z stiffness, so the unit is probably misprinted; ours are in the same range as Z."))

# %% [markdown]
# ## 5.4 The stiffness-optimal pose (seed 001 §4.3–4.4)

# %%
best = opt[opt["pose"] == "optimal"].copy()


def rand_range(h):
    d = opt[(opt["height_mm"] == h) & (opt["pose"] != "optimal")]["deformation_um"]
    return f"{d.min():.0f}–{d.max():.0f}" if len(d) else "none"


best["seed_deformation_um"] = best["height_mm"].map(SEED_DEFORMATION_UM)
display(num.caption("optimal"))
display(opt.drop(columns=["robot"]).round(1))
display(Markdown(f"{num.ref('optimal')} and {num.ref('optimal_poses')}:\n\n" + "\n".join(
    f"* H = {r.height_mm:.0f} mm: optimal pose at ({r.x_mm:.0f}, {r.y_mm:.0f}) mm, "
    f"θr = {r.redundancy_deg:.0f}°, comprehensive index {r.S_N_m / 1e6:.2f} N/µm, deformation "
    f"under the end load {r.deformation_um:.0f} µm (seed: {r.seed_deformation_um:.0f} µm); "
    "random poses: "
    f"{rand_range(r.height_mm)} µm." for r in best.itertuples())))

# %%
fig, ax = plt.subplots()
for h, g in opt.groupby("height_mm"):
    ax.plot(np.arange(len(g)), g["deformation_um"], "o-", label=f"H = {h:.0f} mm")
    if h in SEED_DEFORMATION_UM:
        ax.axhline(SEED_DEFORMATION_UM[h], ls="--", color=ax.lines[-1].get_color(), lw=0.8)
ax.set_xticks(np.arange(len(g)), g["pose"], rotation=30)
ax.set_ylabel("deformation under the end load [µm]")
ax.set_title("Optimal vs random poses (dashed: seed's optimum)")
ax.legend()
save_figure(fig, fig_dir, num.file("optimal_poses"))
plt.show()
display(num.caption("optimal_poses"))

# %% [markdown]
# ## 5.5 Beam-frame model and vibration predictor (seed 004)

# %%
K0 = bf["K0"].values
eig_min = np.linalg.eigvalsh(K0).min()
display(Markdown(
    f"{bf.sizes['element']} beam elements, {bf.sizes['node']} nodes, node 1 fixed: global "
    f"stiffness {K0.shape[0]}×{K0.shape[1]} (seed: 42×42), symmetric to "
    f"{np.abs(K0 - K0.T).max() / np.abs(K0).max():.1e}, smallest eigenvalue {eig_min:.3g} "
    "(positive definite). Cantilever check: beam-frame tip deflection "
    f"{float(bf['cantilever_tip_m']) * 1e6:.4f} µm vs closed form F L³/3EI "
    f"{float(bf['cantilever_closed_form_m']) * 1e6:.4f} µm. Wheel loads F_n = "
    f"{float(bf['F_n_N']):.1f} N, F_v = {float(bf['F_v_N']):.1f} N ({num.ref('beamframe')})."))
fig, axs = plt.subplots(1, 2, figsize=(11, 4))
n = bf["node_m"].values
axs[0].plot(n[:, 0], n[:, 2], "o-")
for i, p in enumerate(n):
    axs[0].annotate(str(i + 1), (p[0], p[2]), fontsize=8)
axs[0].set(xlabel="X [m]", ylabel="Z [m]", title="beam nodes at t = 0")
axs[0].set_aspect("equal")
axs[1].plot(bf["time"], bf["delta_sum_um"], label="δ_sum [µm]")
ax2 = axs[1].twinx()
ax2.plot(bf["time"], bf["sigma_pred"], color="C1", label="σ(t) predicted")
axs[1].set(xlabel="t [s]", ylabel="δ_sum [µm]", title="tool displacement and σ(t), eq. 17")
ax2.set_ylabel("σ(t)")
fig.tight_layout()
save_figure(fig, fig_dir, num.file("beamframe"))
plt.show()
display(num.caption("beamframe"))

# %% [markdown]
# ## 5.6 Stiffness along the cuts
#
# For the thesis' design: both models of the thesis robot at the middle of every thesis cut:
# stiffness along the feed, the in-plane normal to the feed (the slot wall) and the tool axis
# (the slot floor, which the profilometer measures), beside the RMS waviness of Table 2.1.
# For any other design: the joint model of the cell's own robot (when the data hold its load
# tests) at the middle of every cut, along the cut's feed, in-plane normal and tool axis.

# %%
if CUTS_K:
    ck = pd.read_csv(cut_stiffness)
    kcols = {"k_feed_N_m": "k feed N/µm", "k_normal_N_m": "k normal N/µm",
             "k_axial_N_m": "k axial N/µm"}
    ck_um = ck.assign(**{v: ck[k] / 1e6 for k, v in kcols.items()})
    display(num.caption("cut_stiffness"))
    display(per_cut_table(ck_um, list(kcols.values()), pd.read_csv(cuts), experiment).round(3))
    weakest = ck.loc[ck[list(kcols)].min(axis=1).idxmin()]
    display(Markdown(
        f"{num.ref('cut_stiffness')}: the joint stiffness identified from this cell's own load "
        "tests, at the middle of every cut (elastic joints, rigid links: C = J diag(c) Jᵀ). "
        f"Along the feed {span(ck.k_feed_N_m / 1e6, '.3f')} N/µm, normal to it "
        f"{span(ck.k_normal_N_m / 1e6, '.3f')} N/µm, along the tool axis "
        f"{span(ck.k_axial_N_m / 1e6, '.3f')} N/µm; the weakest direction of any cut is the "
        f"{min(kcols, key=lambda k: weakest[k]).split('_')[1]} direction of cut "
        f"`{weakest['cut']}` ({weakest[list(kcols)].min() / 1e6:.3f} N/µm). Chapter 2's "
        "per-cut surface tables are the measured side of the same cuts."))
elif not SLOTS:
    display(Markdown(
        "This study's cuts are not the thesis' slots (chapter 0 describes the design), so the "
        "comparison of the thesis robot's stiffness along the slot directions with Table 2.1 "
        "does not apply. A per-cut table of the stiffness along each cut's feed needs the "
        "joint stiffness of this cell's own robot (a `stiffness` file for the robot of "
        f"`cell.yaml`); the load tests of this run are for the seed robot ({robot_name}) and the "
        "thesis robot only, so there is none."))

# %%
if SLOTS:
    sl = pd.read_csv(slots)
    tj = pd.read_csv(thesis_joints)
    unobs = tj.loc[~tj["observable"].astype(str).str.lower().isin(["true", "1"]), "joint"].tolist()
    wav = pd.read_csv(waviness, index_col=0)
    mean_k = slot_stiffness_table(sl, wav)
    wq = waviness_by_direction(wav)
    display(num.caption("slots"))
    display(mean_k)
    comb = mean_k.loc["combined"]
    kn = comb["k normal N/µm"]
    spread = stiffness_spread_pct(kn)
    display(Markdown(
        f"{num.ref('slots')}, {num.ref('thesis_slots')}: thesis robot joints not observable in its "
        f"load tests: {unobs or 'none'} (treated as "
        "rigid; a tool on the flange axis gives no torque about joint 6). Both models in series: "
        + ", ".join(f"{d} slots k_normal {kn[d]:.3f}, k_feed {comb.loc[d, 'k feed N/µm']:.3f} N/µm"
                    for d in kn.index)
        + f". The +Y and −Y slots share their normal direction (±X), and their normal stiffness "
        f"differs by {spread:+.1f} %, while their mean waviness is {wq['py']:.2f} vs "
        f"{wq['my']:.2f} µm (+X: {wq['px']:.2f} µm). The weak ±X direction is the normal of "
        "both Y slots and the feed of the X slots: static stiffness explains why the Y slots are "
        "worse than the X slots only in part, and cannot explain why +Y is so much rougher than "
        "−Y — that asymmetry points to the direction of travel (gear errors, up- vs down-milling "
        "side of the wall). (On synthetic data the waviness comes from the planted gear errors.)"))

    fig, ax = plt.subplots()
    c = sl[sl["model"] == "combined"].groupby("direction")[["k_feed_N_m", "k_normal_N_m",
                                                             "k_axial_N_m"]].mean() / 1e6
    x = np.arange(len(c))
    for i, col in enumerate(c.columns):
        ax.bar(x + (i - 1) * 0.25, c[col], 0.25, label=col.replace("_N_m", "").replace("k_", ""))
    ax.set_xticks(x, c.index)
    ax.set_ylabel("stiffness [N/µm]")
    ax2 = ax.twinx()
    ax2.plot(x, [wq.get(d, np.nan) for d in c.index], "kD--", label="waviness RMS")
    ax2.set_ylabel("waviness RMS [µm]")
    ax.set_title("Thesis robot: stiffness per slot direction vs Table 2.1")
    ax.legend(loc="upper left")
    save_figure(fig, fig_dir, num.file("thesis_slots"))
    plt.show()
    display(num.caption("thesis_slots"))
num.check()
