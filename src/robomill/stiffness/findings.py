"""Chapter 5's findings: every number, range, flag and verdict the stiffness chapter states,
computed from the stage's artefacts and rendered by the chapter
(:mod:`robomill.pipeline.prose`): the Monte-Carlo workspace, the joint-stiffness
identification and its validation [Yi 2025, eqs. 9–10], the directional-stiffness maxima, the
stiffness-optimal poses, the beam-frame model [Cai 2015] and the stiffness along the cuts —
for the thesis' slots beside Table 2.1, with the verdict whether the static stiffness explains
the ±Y waviness asymmetry (``stiffness.slot_asymmetry_pct``). Seed numbers come from
``references.yaml`` (:mod:`robomill.references`), each with its key as evidence.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
import xarray as xr

from robomill import catalogue, references
from robomill.findings import Findings
from robomill.stiffness.cuts import stiffness_spread_pct, waviness_by_direction

_MAPS = catalogue.artefact("stiffness.maps")
_OPTIMAL = catalogue.artefact("stiffness.optimal_poses")
_BEAMFRAME = catalogue.artefact("stiffness.beamframe")
_SLOTS = catalogue.artefact("stiffness.thesis_slots")
_CUTS = catalogue.artefact("stiffness.cut_stiffness")
_WAVINESS = catalogue.artefact("surface.table_2_1_waviness_rms")
_TRUTH = catalogue.artefact("synthetic.truth")
_REFS = "src/robomill/data/references.yaml"
_N_UM = 1e6  # N/m per N/µm
_K_AXES = ("feed", "normal", "axial")


def _span(values) -> list[float] | None:
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    return [float(v.min()), float(v.max())] if v.size else None


def _ref(found: Findings, key: str, ref: str, scale: float = 1.0) -> None:
    """A seed number from references.yaml as a finding (``scale`` converts its unit)."""
    r = references.reference(ref)
    v = r["value"]
    v = [scale * x for x in v] if isinstance(v, list) else scale * v
    found.add(key, v, r["unit"] if scale == 1.0 else "", artefact=_REFS, what=ref)


def _workspace(found: Findings, maps: xr.Dataset) -> None:
    ws = np.asarray(maps["workspace_mm"].values, float)
    wxz = np.asarray(maps["workspace_xz_mm"].values, float)
    found.add("map_robot", str(maps.attrs.get("robot", "robot")), artefact=_MAPS,
              what="attribute robot")
    found.add("workspace_samples", int(ws.shape[0]), artefact=_MAPS, what="sample")
    for key, pts, col, what in (("x", ws, 0, "workspace_mm[axis3 = 0]"),
                                ("y", ws, 1, "workspace_mm[axis3 = 1]"),
                                ("z", ws, 2, "workspace_mm[axis3 = 2]"),
                                ("xz_plane_x", wxz, 0, "workspace_xz_mm[axis3 = 0]"),
                                ("xz_plane_z", wxz, 2, "workspace_xz_mm[axis3 = 2]")):
        found.add(f"workspace_{key}_mm", _span(pts[:, col]), "mm", artefact=_MAPS, what=what)
        _ref(found, f"seed_workspace_{key}_mm", f"seed001.workspace_extent_mm.{key}")
    found.add("annulus_inner_mm", float(np.nanmin(maps["annulus_inner_diameter_mm"].values)),
              "mm", artefact=_MAPS, what="annulus_inner_diameter_mm, smallest over the heights")
    found.add("annulus_outer_mm", float(np.nanmax(maps["annulus_outer_diameter_mm"].values)),
              "mm", artefact=_MAPS, what="annulus_outer_diameter_mm, largest over the heights")
    for edge in ("inner", "outer"):
        _ref(found, f"seed_annulus_{edge}_mm",
             f"seed001.stiffness.maps.annulus_{edge}_diameter_mm.height_mm_1600")


def _identification(found: Findings, robot: str, joints: pd.DataFrame,
                    validation: pd.DataFrame, planted_k_Nm_rad: Sequence[float] | None) -> None:
    src = catalogue.artefact("stiffness.joint_stiffness", robot=robot)
    k = joints["k_Nm_rad"].to_numpy(float)
    found.add("n_joints", int(len(joints)), artefact=src, what="rows")
    found.add("joint_k_kNm_rad", k / 1e3, "kN m/rad", artefact=src, what="k_Nm_rad")
    n = len(joints)
    seed3d = list(references.values("seed001.stiffness.joint_stiffness_3d.k_Nm_rad.").values())
    seed2d = list(references.values("seed001.stiffness.joint_stiffness.k_Nm_rad.").values())
    found.add("seed_k3d_kNm_rad", [v / 1e3 for v in seed3d[:n]], "kN m/rad", artefact=_REFS,
              what="seed001.stiffness.joint_stiffness_3d.k_Nm_rad.*")
    found.add("seed_k_plane_kNm_rad", [v / 1e3 for v in seed2d[:n]], "kN m/rad",
              artefact=_REFS, what="seed001.stiffness.joint_stiffness.k_Nm_rad.*")
    m = min(len(seed3d), len(seed2d))
    found.add("seed_3d_over_plane_pct", _span(
        [100.0 * (a / b - 1.0) for a, b in zip(seed3d[:m], seed2d[:m], strict=True)]), "%",
        artefact=_REFS, what="3-D over plane identification of Yi 2025, per joint")
    has_planted = planted_k_Nm_rad is not None
    found.add("has_planted", has_planted, artefact=_TRUTH, what="stiffness_k_Nm_rad")
    if has_planted:
        planted = np.asarray(planted_k_Nm_rad, float)[:n]
        lo = joints["ci95_low_Nm_rad"].to_numpy(float)
        hi = joints["ci95_high_Nm_rad"].to_numpy(float)
        found.add("planted_k_kNm_rad", planted / 1e3, "kN m/rad", artefact=_TRUTH,
                  what=f"stiffness_k_Nm_rad[stiffness_robot = {robot}]")
        found.add("n_planted_in_ci", int(np.sum((planted >= lo) & (planted <= hi))),
                  artefact=src, what="planted value within ci95_low_Nm_rad … ci95_high_Nm_rad")
    vsrc = catalogue.artefact("stiffness.validation", robot=robot)
    found.add("n_validation_poses", int(validation["pose"].nunique()) if len(validation) else 0,
              artefact=vsrc, what="pose")
    if len(validation):
        err = validation.groupby("model", sort=False)[["error_pct", "vector_error_pct"]].agg(
            lambda s: float(np.abs(s).mean()))
        found.add("validation_models", [str(m) for m in err.index], artefact=vsrc,
                  what="model")
        found.add("validation_error_pct", err["error_pct"].to_numpy(float), "%", artefact=vsrc,
                  what="mean |error_pct| per model")
        found.add("validation_vector_error_pct", err["vector_error_pct"].to_numpy(float), "%",
                  artefact=vsrc, what="mean |vector_error_pct| per model")
    _ref(found, "seed_validation_cube_pct", "seed001.validation_error_pct.cube")
    _ref(found, "seed_validation_plane_pct",
         "seed001.stiffness.validation.vector_error_pct.model_plane.mean")
    _ref(found, "seed_predicted_cube_mm", "seed001.validation_predicted_deflection_mm.cube")
    _ref(found, "seed_predicted_plane_mm", "seed001.validation_predicted_deflection_mm.plane")
    _ref(found, "seed_measured_mm", "seed001.validation_measured_deflection_mm")


def _maxima(found: Findings, maps: xr.Dataset) -> None:
    kmax = maps["k_N_m"].max(dim=("x", "y"))
    kz = float(kmax.sel(axis="Z").max()) / _N_UM
    ky = float(kmax.sel(axis="Y").max()) / _N_UM
    found.add("k_z_max_N_um", kz, "N/um", artefact=_MAPS, what="k_N_m[axis = Z], largest")
    found.add("k_y_max_N_um", ky, "N/um", artefact=_MAPS, what="k_N_m[axis = Y], largest")
    found.add("k_y_over_z", ky / kz, artefact=_MAPS, what="largest k_Y over largest k_Z")
    _ref(found, "seed_z_0deg_N_mm", "seed001.z_stiffness_0deg_N_mm")
    _ref(found, "seed_z_0deg_N_um", "seed001.z_stiffness_0deg_N_mm", scale=1e-3)
    _ref(found, "seed_z_30deg_increase_N_mm", "seed001.z_stiffness_increase_30deg_N_mm")
    seed_y = references.values("seed001.y_stiffness_max_N_m.")
    found.add("seed_y_redundancy_deg",
              [float(k.rsplit("_", 1)[1].removesuffix("deg")) for k in seed_y], "deg",
              artefact=_REFS, what="seed001.y_stiffness_max_N_m.*")
    found.add("seed_y_max_N_m", list(seed_y.values()), "N/m", artefact=_REFS,
              what="seed001.y_stiffness_max_N_m.*")
    seed_y_um = max(seed_y.values()) / _N_UM
    found.add("seed_y_max_N_um", seed_y_um, "N/um", artefact=_REFS,
              what="largest of seed001.y_stiffness_max_N_m.*, as printed (N/m)")
    found.add("seed_y_over_z", seed_y_um / (1e-3 * references.value(
        "seed001.z_stiffness_0deg_N_mm")), artefact=_REFS,
        what="printed Y maximum over the Z stiffness at 0°")


def _optimal(found: Findings, optimal: pd.DataFrame) -> None:
    best = optimal[optimal["pose"] == "optimal"]
    rand = optimal[optimal["pose"] != "optimal"]
    h = best["height_mm"].to_numpy(float)
    found.add("optimal_height_mm", h, "mm", artefact=_OPTIMAL, what="height_mm[pose = optimal]")
    for key, col, scale, unit in (("optimal_x_mm", "x_mm", 1.0, "mm"),
                                  ("optimal_y_mm", "y_mm", 1.0, "mm"),
                                  ("optimal_redundancy_deg", "redundancy_deg", 1.0, "deg"),
                                  ("optimal_S_N_um", "S_N_m", 1 / _N_UM, "N/um"),
                                  ("optimal_deformation_um", "deformation_um", 1.0, "um")):
        found.add(key, best[col].to_numpy(float) * scale, unit, artefact=_OPTIMAL,
                  what=f"{col}[pose = optimal]")
    by_h = rand.groupby("height_mm")["deformation_um"]
    lo, hi = by_h.min(), by_h.max()
    found.add("random_deformation_min_um", [float(lo.get(x, np.nan)) for x in h], "um",
              artefact=_OPTIMAL, what="deformation_um[pose = random_*], smallest per height")
    found.add("random_deformation_max_um", [float(hi.get(x, np.nan)) for x in h], "um",
              artefact=_OPTIMAL, what="deformation_um[pose = random_*], largest per height")
    seed = {}
    for x in h:
        key = ("seed001.stiffness.optimal_poses.deformation_um."
               f"robot_kr360_height_mm_{x:.0f}_pose_optimal")
        try:
            seed[x] = references.value(key)
        except KeyError:
            continue
    found.add("seed_optimal_height_mm", list(seed), "mm", artefact=_REFS,
              what="seed001.stiffness.optimal_poses.deformation_um.*")
    found.add("seed_optimal_deformation_um", list(seed.values()) or None, "um", artefact=_REFS,
              what="seed001.stiffness.optimal_poses.deformation_um.*")


def _beamframe(found: Findings, bf: xr.Dataset) -> None:
    K0 = np.asarray(bf["K0"].values, float)
    eig_min = float(np.linalg.eigvalsh(0.5 * (K0 + K0.T)).min())
    found.add("bf_n_elements", int(bf.sizes["element"]), artefact=_BEAMFRAME, what="element")
    found.add("bf_n_nodes", int(bf.sizes["node"]), artefact=_BEAMFRAME, what="node")
    found.add("bf_K_size", int(K0.shape[0]), artefact=_BEAMFRAME, what="K0 rows")
    _ref(found, "seed_bf_K_size", "seed004.global_stiffness_size")
    found.add("bf_asymmetry", float(np.abs(K0 - K0.T).max() / np.abs(K0).max()),
              artefact=_BEAMFRAME, what="max |K0 - K0ᵀ| / max |K0|")
    found.add("bf_eig_min", eig_min, artefact=_BEAMFRAME, what="smallest eigenvalue of K0")
    found.add("bf_positive_definite", eig_min > 0, artefact=_BEAMFRAME,
              what="smallest eigenvalue of K0 above zero")
    tip, closed = float(bf["cantilever_tip_m"]), float(bf["cantilever_closed_form_m"])
    found.add("cantilever_tip_um", 1e6 * tip, "um", artefact=_BEAMFRAME,
              what="cantilever_tip_m")
    found.add("cantilever_closed_form_um", 1e6 * closed, "um", artefact=_BEAMFRAME,
              what="cantilever_closed_form_m (F L³/3EI)")
    found.add("F_n_N", float(bf["F_n_N"]), "N", artefact=_BEAMFRAME, what="F_n_N")
    found.add("F_v_N", float(bf["F_v_N"]), "N", artefact=_BEAMFRAME, what="F_v_N")


def _cuts(found: Findings, ck: pd.DataFrame | None) -> None:
    found.add("has_cut_stiffness", ck is not None and len(ck) > 0, artefact=_CUTS)
    if ck is None or not len(ck):
        return
    cols = [f"k_{a}_N_m" for a in _K_AXES]
    for a, col in zip(_K_AXES, cols, strict=True):
        found.add(f"cut_k_{a}_N_um", _span(ck[col] / _N_UM), "N/um", artefact=_CUTS, what=col)
    k = ck[cols].to_numpy(float)
    i, j = np.unravel_index(np.nanargmin(k), k.shape)
    found.add("weakest_cut", str(ck["cut"].iloc[i]), artefact=_CUTS,
              what="cut of the smallest k_*_N_m")
    found.add("weakest_axis", _K_AXES[j], artefact=_CUTS, what="its direction")
    found.add("weakest_k_N_um", float(k[i, j]) / _N_UM, "N/um", artefact=_CUTS,
              what="smallest k_*_N_m")


def _slots(found: Findings, slots: pd.DataFrame | None, waviness: pd.DataFrame | None,
           thesis_joints: pd.DataFrame | None, asymmetry_pct: float) -> None:
    has = slots is not None and waviness is not None and len(slots) > 0
    found.add("has_slots", has, artefact=_SLOTS)
    if not has:
        return
    if thesis_joints is not None:
        obs = thesis_joints["observable"].astype(str).str.lower().isin(["true", "1"])
        found.add("unobservable_joints", [int(j) for j in thesis_joints.loc[~obs, "joint"]],
                  artefact="results/stiffness/<thesis robot>/joint_stiffness.csv",
                  what="observable = False")
    comb = (slots[slots["model"] == "combined"].groupby("direction")
            [[f"k_{a}_N_m" for a in _K_AXES]].mean() / _N_UM)
    found.add("slot_directions", [str(d) for d in comb.index], artefact=_SLOTS,
              what="direction")
    for a in _K_AXES:
        found.add(f"slot_k_{a}_N_um", comb[f"k_{a}_N_m"].to_numpy(float), "N/um",
                  artefact=_SLOTS, what=f"mean k_{a}_N_m[model = combined] per direction")
    found.add("slot_weakest_axis", [_K_AXES[int(np.argmin(r))] for r in comb.to_numpy(float)],
              artefact=_SLOTS, what="smallest of k_feed, k_normal, k_axial per direction")
    k_spread = stiffness_spread_pct(comb["k_normal_N_m"])
    found.add("normal_spread_pct", k_spread, "%", artefact=_SLOTS,
              what="100 (k_normal[py] - k_normal[my]) / k_normal[my], model = combined")
    wq = waviness_by_direction(waviness)
    for d in ("px", "py", "my"):
        found.add(f"waviness_{d}_um", wq[d], "um", artefact=_WAVINESS,
                  what=f"mean of the columns s*_{d}")
    w_spread = float(100 * (wq["py"] - wq["my"]) / wq["my"])
    found.add("waviness_spread_pct", w_spread, "%", artefact=_WAVINESS,
              what="100 (waviness[py] - waviness[my]) / waviness[my]")
    if not (np.isfinite(k_spread) and np.isfinite(w_spread)):
        return
    if abs(w_spread) < asymmetry_pct:
        verdict = "none"
    elif abs(k_spread) >= asymmetry_pct and np.sign(k_spread) == -np.sign(w_spread):
        verdict = "explained"  # the rougher side is the less stiff one, by as much
    else:
        verdict = "not_explained"
    found.add("y_asymmetry_explained", verdict == "explained", verdict=verdict,
              threshold=float(asymmetry_pct), config_key="stiffness.slot_asymmetry_pct",
              artefact=_SLOTS, what="waviness_spread_pct against normal_spread_pct")


def stiffness_findings(maps: xr.Dataset, optimal: pd.DataFrame, beamframe: xr.Dataset,
                       joints: pd.DataFrame, validation: pd.DataFrame, *,
                       planted_k_Nm_rad: Sequence[float] | None = None,
                       cut_stiffness: pd.DataFrame | None = None,
                       slots: pd.DataFrame | None = None,
                       waviness: pd.DataFrame | None = None,
                       thesis_joints: pd.DataFrame | None = None,
                       slot_asymmetry_pct: float) -> Findings:
    """The findings of the stiffness stage.

    Parameters
    ----------
    maps, optimal, beamframe
        ``results/stiffness/maps.nc`` (workspace samples, annulus, ``k_N_m(height_mm,
        redundancy_deg, y, x, axis)``), ``optimal_poses.csv`` and ``beamframe.nc``.
    joints, validation
        The map robot's ``joint_stiffness.csv`` and ``validation.csv``.
    planted_k_Nm_rad
        The planted joint stiffness of the map robot (synthetic runs: ``truth.nc``), or None.
    cut_stiffness
        ``results/stiffness/cut_stiffness.csv`` (other designs, the cell's robot tested) or
        None.
    slots, waviness, thesis_joints
        The thesis' design only: ``thesis_slots.csv``, Table 2.1
        (``results/surface/table_2_1_waviness_rms.csv``, index ``segment``) and the thesis
        robot's ``joint_stiffness.csv``; None otherwise.
    slot_asymmetry_pct
        ``stiffness.slot_asymmetry_pct``: a difference between the +Y and −Y slots below this
        [%] is no asymmetry. Verdict ``y_asymmetry_explained``: ``none`` when the mean
        waviness of +Y and −Y differs by less; ``explained`` when their normal stiffness (the
        wall they share) differs by at least as much, the rougher slot the less stiff;
        ``not_explained`` otherwise.

    Returns
    -------
    Findings
        Workspace: ``map_robot, workspace_samples, workspace_{x,y,z,xz_plane_x,
        xz_plane_z}_mm, annulus_{inner,outer}_mm`` and the seed's ``seed_*``; identification:
        ``n_joints, joint_k_kNm_rad, seed_k3d_kNm_rad, seed_k_plane_kNm_rad,
        seed_3d_over_plane_pct, has_planted`` (with it ``planted_k_kNm_rad,
        n_planted_in_ci``), ``n_validation_poses, validation_models, validation_error_pct,
        validation_vector_error_pct``; maps: ``k_z_max_N_um, k_y_max_N_um, k_y_over_z`` and
        the seed's; optimal poses per height (lists); beam frame ``bf_*``, ``cantilever_*``,
        ``F_n_N, F_v_N``; ``has_cut_stiffness`` (with it ``cut_k_{feed,normal,axial}_N_um,
        weakest_cut, weakest_axis, weakest_k_N_um``); ``has_slots`` (with it the slot means,
        the waviness per direction, the spreads and the verdict).
    """
    found = Findings("stiffness")
    _workspace(found, maps)
    robot = found["map_robot"].value
    _identification(found, robot, joints, validation, planted_k_Nm_rad)
    _maxima(found, maps)
    _optimal(found, optimal)
    _beamframe(found, beamframe)
    _cuts(found, cut_stiffness)
    _slots(found, slots, waviness, thesis_joints, slot_asymmetry_pct)
    return found
