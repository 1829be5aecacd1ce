"""Predictions for every candidate cut (pose × redundancy angle × direction × speed × depth ×
feed), each with an interval carried from the identified quantities' uncertainty.

* **Stability margin** a_crit/a − 1, a_crit the regenerative model's critical depth
  (:mod:`robomill.plan.stability`: the zero-order lobes of every mode at the cut's pose, over
  the members of a bootstrap of the modes, the joint stiffness and the cutting coefficients,
  weighted by the study's verdicts): the impact test's modes in the cut frame, those below
  ``robot_mode_max_hz`` (the robot's structure) moved to the pose by
  :func:`robomill.plan.tooltip.mode_scalings` (stiffness k_r(q) = k_r·k_φ(q)/k_φ(q_ref),
  k_φ = 1/(φᵀ C(q) φ) the joint model's stiffness along the mode shape; modal mass by the
  cell file's documented masses, held without them), the spindle/tool modes a stated prior.
  Interval: the members' weighted quantiles at the ``level``; the lower end is the
  pessimistic margin.
* **Static deflection** δ = C(q) F̄ along the wall normal and the tool axis, C(q) the tool
  tip's static compliance at the pose (:mod:`robomill.plan.tooltip`: the impact test's modes
  moved with the joints; the joint model alone without an impact test), F̄ the mean cutting
  force (Altintas 2012 eq. 2.25, :func:`robomill.forces.mean_milling_forces`) rotated from
  the cut frame to the base frame; interval over the modes', the joints' and the force's
  ends.
* **Force** |F̄| with a new cut's prediction interval (:func:`force_interval`; the
  coefficients' confidence corners when the identifying cuts' means are not given);
  deflection's ends are the stiffness ends times the force's ends.
* **Waviness** from the gear elements' joint amplitudes
  (:func:`robomill.plan.measured.waviness_um`): ``waviness_ident_low/high_um`` the spread
  between the identifying runs (the wall's waviness, constrained and in the form error),
  ``waviness_low/high_um`` per feed the interval the next tracker run reads, widened by the
  tracker's noise at that record (``waviness_noise_um``, :mod:`robomill.plan.noise`).
* **Feed marks** c²/(8R) for a feed per tooth c = v/(N n) and tool radius R; **removal
  rate** a·a_e·v [mm³/s].
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from robomill.chatter.model import immersion_angles
from robomill.forces import CuttingCoefficients, mean_milling_forces
from robomill.kinematics import SerialRobot
from robomill.plan.feasible import pose_check_vars
from robomill.plan.measured import (
    Measured,
    coefficient_bounds,
    missing_predictions,
    waviness_um,
)
from robomill.plan.poses import (
    cut_frames,
    solve_grid,
)
from robomill.plan.request import PlanRequest
from robomill.plan.tooltip import mode_scalings, nominal_key, static_compliance_m_N
from robomill.xrvars import attrs, var


@dataclass(frozen=True)
class Cell:
    """What the planner needs of the cell: the robot, the tool orientation R0 (θ = 0), the IK
    seed, the reference point of the impact test (where the modes were measured), the
    gear elements' orders ``{(joint, stage, order): cycles per joint revolution}`` and the
    robot's documented masses as a rigid-body model (:mod:`robomill.inertia`; None where the
    cell file states none)."""

    robot: SerialRobot
    R0: np.ndarray
    q_seed_rad: np.ndarray
    reference_point_mm: np.ndarray
    gear_orders: dict | None = None
    joint_limits_deg: np.ndarray | None = None
    joint_speed_limits_deg_s: np.ndarray | None = None
    rigid_body: Any = None


def engagement(req: PlanRequest) -> tuple[float, float]:
    """Entry and exit angles of the request's operation (slot: 0 … π)."""
    return (0.0, float(np.pi)) if req.milling == "slot" else immersion_angles(
        req.radial_immersion, req.milling)


def critical_depth_m(measured: Measured, cell: Cell, req: PlanRequest, q_rad: np.ndarray,
                     frames: np.ndarray, spindle_rpm: np.ndarray, *,
                     corners: bool = True, members: bool = False
                     ) -> dict[str, np.ndarray] | None:
    """Critical depth ``(B, S)`` [m] at postures ``q_rad`` ``(B, n)`` with cut frames
    ``frames`` ``(B, 3, 3)`` (columns feed, normal, axis) of the stability model
    (:mod:`robomill.plan.stability`): ``nominal``, ``low``, ``high`` (the weighted central
    ``measured.level`` range of the members; their weights from the study's verdicts,
    ``measured.stability_evidence``, else equal). None when the modes or the coefficients
    were not measured. Without ``corners`` only the nominal member (``low`` = ``high`` =
    nominal). ``members``: also ``members`` ``(E, B, S)`` and their ``weights`` ``(E,)``."""
    from robomill.plan.stability import draw_members, member_depths_m, summary

    mem = draw_members(measured, req.stability)
    if mem is None:
        return None
    ent, ext = engagement(req)
    fn = mem.f_hz[0]
    scalings = mode_scalings(measured, cell, q_rad, fn < req.robot_mode_max_hz, mem.shapes,
                             corners=corners)
    a = member_depths_m(mem, scalings, frames, np.atleast_1d(spindle_rpm), flutes=req.flutes,
                        entry_rad=ent, exit_rad=ext,
                        which=None if corners else slice(0, 1))
    if not corners:
        return {"nominal": a[0], "low": a[0], "high": a[0]}
    w = member_weights(measured, a.shape[0])
    out = summary(a, w, float(measured.level))
    if members:
        out.update({"members": a, "weights": w})
    return out


def solver_error(measured: Measured, cell: Cell, req: PlanRequest, q_rad: np.ndarray,
                 frame: np.ndarray, spindle_rpm: float) -> float:
    """The stated error of the zero-order solution at one cut (posture ``q_rad`` ``(n,)``,
    cut frame ``(3, 3)``, speed): the relative difference of the nominal member's critical
    depth against semi-discretization (:func:`robomill.plan.stability.zoa_error`); NaN
    without a stability model."""
    from robomill.plan.stability import draw_members, zoa_error

    mem = draw_members(measured, req.stability)
    if mem is None:
        return float("nan")
    ent, ext = engagement(req)
    sc = mode_scalings(measured, cell, np.asarray(q_rad, float)[None],
                       mem.f_hz[0] < req.robot_mode_max_hz, mem.shapes, corners=False)
    return zoa_error(mem, sc, np.asarray(frame, float), [float(spindle_rpm)], flutes=req.flutes,
                     entry_rad=ent, exit_rad=ext)


def member_weights(measured: Measured, n: int) -> np.ndarray:
    """The members' weights: from the study's verdicts (``measured.stability_evidence``,
    :class:`robomill.plan.stability.VerdictEvidence`), else equal."""
    ev = measured.stability_evidence
    if ev is not None and len(ev.weights) == n:
        return np.asarray(ev.weights, float)
    return np.full(n, 1.0 / n)


def mean_forces_N(coeffs: CuttingCoefficients, req: PlanRequest, spindle_rpm, depth_mm,
                  feed_mm_s) -> np.ndarray:
    """Mean cutting force in the cut frame ``(S, A, V, 3)`` for speeds × depths × feeds."""
    n = np.asarray(spindle_rpm, float)[:, None, None]
    a = np.asarray(depth_mm, float)[None, :, None]
    v = np.asarray(feed_mm_s, float)[None, None, :]
    c = v * 60.0 / (req.flutes * n)
    ent, ext = engagement(req)
    return mean_milling_forces(c, a, coeffs, flutes=req.flutes, entry_rad=ent, exit_rad=ext)


def force_interval(measured: Measured, req: PlanRequest, nominal_N: np.ndarray
                   ) -> dict[str, np.ndarray]:
    """|F̄| ``(S, A, V)``: the nominal (from the coefficients) and the two ends of a new cut's
    prediction interval at the measured level, evaluated at each candidate's chip load and
    engagement (:func:`robomill.forces.prediction.predict_mean_force`: the coefficient
    regression's residual scatter between cuts plus its coefficients' uncertainty)."""
    from robomill.forces.prediction import predict_mean_force

    n = np.asarray(req.spindle_rpm, float)[:, None, None]
    a = np.asarray(req.depth_mm, float)[None, :, None]
    v = np.asarray(req.feed_mm_s, float)[None, None, :]
    c = v * 60.0 / (req.flutes * n)
    ent, ext = engagement(req)
    p = predict_mean_force(measured.force_regression, c, a, flutes=req.flutes, entry_rad=ent,
                           exit_rad=ext, level=measured.level)
    return {"nominal": nominal_N,
            "low": np.maximum(nominal_N - (p["magnitude_N"] - p["low_N"]), 0.0),
            "high": nominal_N + (p["high_N"] - p["magnitude_N"])}


def _p_stable(members_mm: np.ndarray, weights: np.ndarray, depth_mm: np.ndarray,
              ok: np.ndarray) -> np.ndarray:
    """p_stable ``(P, R, D, S, A)`` of members ``(E, P, R, D, S)`` [mm] (NaN unreachable)."""
    from robomill.plan.stability import p_stable

    p = p_stable(members_mm[..., None], weights, np.asarray(depth_mm, float))
    return np.where(ok[..., None, None], p, np.nan)


def solve_request(req: PlanRequest, cell: Cell):
    """The request's candidate poses (:func:`robomill.plan.poses.solve_grid` with the
    request's stations, the cell's joint limits and the request's margins)."""
    return solve_grid(cell.robot, req.placements_mm, req.rotations_deg, req.direction_deg,
                      req.length_mm, R0=cell.R0, q_seed_rad=cell.q_seed_rad,
                      stations=req.path_stations, limits_deg=cell.joint_limits_deg,
                      limit_margin_deg=req.joint_limit_margin_deg,
                      min_wrist_angle_deg=req.min_wrist_angle_deg)


def predict_grid(req: PlanRequest, measured: Measured, cell: Cell, *,
                 corners: bool = True) -> xr.Dataset:
    """Every candidate of the request with its predictions and intervals (the variables of
    ``results/plan/candidates.nc``; docs/artefacts.md). Predictions that cannot be made are
    NaN and listed in the ``missing_predictions`` attribute."""
    missing = missing_predictions(measured)
    poses = solve_request(req, cell)
    P, R, D = poses.reachable.shape
    S, A, V = len(req.spindle_rpm), len(req.depth_mm), len(req.feed_mm_s)
    frames = cut_frames(req.direction_deg)                                  # (D, 3, 3)
    q = poses.q_mid_rad                                                     # (P, R, D, n)
    ok = poses.reachable
    prd = ("placement", "rotation", "direction")
    full = prd + ("spindle_rpm", "depth_mm", "feed_mm_s")
    nan_full = np.full((P, R, D, S, A, V), np.nan)
    data = {"reachable": (prd, ok, attrs("1", "inverse kinematics converges along the cut"))}
    data["q_deg"] = var(prd + ("joint",), np.rad2deg(q), "deg", "posture at the cut's middle")
    data["q_path_deg"] = var(prd + ("station", "joint"), np.rad2deg(poses.q_rad), "deg",
                             "posture at each station along the cut")
    data.update(pose_check_vars(poses.checks, prd))
    # stability (robomill.plan.stability): the members, their interval and p_stable
    a_crit = None
    if ok.any():
        fb = np.broadcast_to(frames[None, None], (P, R, D, 3, 3))[ok]
        a_crit = critical_depth_m(measured, cell, req, q[ok], fb, req.spindle_rpm,
                                  corners=corners, members=corners)
    if a_crit is not None and "members" in a_crit:
        E = a_crit["members"].shape[0]
        mem = np.full((E, P, R, D, S), np.nan)
        mem[:, ok] = a_crit["members"]
        data["a_crit_members_mm"] = var(("member",) + prd + ("spindle_rpm",), mem * 1e3, "mm",
                                        "critical axial depth of each member of the stability "
                                        "model (robomill.plan.stability)")
        data["member_weight"] = var(("member",), a_crit["weights"], "1",
                                    "weight of each member from the study's verdicts")
    depth_m = req.depth_mm[None, :] * 1e-3
    for key, suffix in (("nominal", ""), ("low", "_low"), ("high", "_high")):
        a_full = np.full((P, R, D, S), np.nan)
        if a_crit is not None:
            a_full[ok] = a_crit[key]
        data[f"a_crit{suffix}_mm"] = var(prd + ("spindle_rpm",), a_full * 1e3, "mm",
                                         f"critical axial depth (regenerative lobes, {key})")
        data[f"stability_margin{suffix}"] = var(
            full, np.broadcast_to((a_full[..., None] / depth_m - 1)[..., None], nan_full.shape),
            "1", f"stability margin a_crit/a - 1 ({key})")
    if "a_crit_members_mm" in data:
        data["p_stable"] = var(prd + ("spindle_rpm", "depth_mm"),
                               _p_stable(data["a_crit_members_mm"][1], a_crit["weights"],
                                         req.depth_mm, ok), "1",
                               "probability of a stable cut: weighted share of the members "
                               "deeper than the cut")
    # forces and deflection
    Fmag = {k: np.full((S, A, V), np.nan) for k in ("nominal", "low", "high")}
    defl = {(ax, k): nan_full.copy() for ax in ("normal", "axial") for k in Fmag}
    stiff = {ax: np.full((P, R, D), np.nan) for ax in ("normal", "axial")}
    if measured.has("coefficients"):
        cb = coefficient_bounds(measured.coefficients)
        Fc = {k: mean_forces_N(cb[k], req, req.spindle_rpm, req.depth_mm, req.feed_mm_s)
              for k in ("nominal", "low", "high")}
        mags = np.stack([np.linalg.norm(f, axis=-1) for f in Fc.values()])
        Fmag = {"nominal": mags[0], "low": mags.min(0), "high": mags.max(0)}
        if measured.force_regression is not None:  # a new cut's prediction interval
            Fmag = force_interval(measured, req, mags[0])
        comp = (static_compliance_m_N(measured, cell, q[ok], req.robot_mode_max_hz,
                                      corners=corners) if ok.any() else None)
        if comp is not None:
            Fb = {k: np.einsum("dij,saj->dsai", frames, f.reshape(S, A * V, 3))
                  .reshape(D, S, A, V, 3) for k, f in Fc.items()}
            nkey = nominal_key(comp)
            keys = [nkey] + [key for key in comp if key != nkey]
            for ax, col in (("normal", 1), ("axial", 2)):
                vals = []
                for ck in keys:
                    C = np.zeros((P, R, D, 3, 3))
                    C[ok] = comp[ck]                                          # (P, R, D, 3, 3)
                    row = np.einsum("di,prdij->prdj", frames[:, :, col], C)   # (P, R, D, 3)
                    if ck == nkey:
                        with np.errstate(divide="ignore"):
                            stiff[ax] = np.where(ok, 1.0 / np.einsum("prdj,dj->prd", row,
                                                                     frames[:, :, col]), np.nan)
                    fks = (("nominal",) if measured.force_regression is not None
                           else ("nominal", "low", "high"))
                    for fk in fks:
                        vals.append(np.abs(np.einsum("prdj,dsavj->prdsav", row, Fb[fk])) * 1e6)
                vals = np.stack(vals)
                if measured.force_regression is not None:  # δ ∝ F: the force's ends scale it
                    with np.errstate(divide="ignore", invalid="ignore"):
                        r_lo = np.nan_to_num(Fmag["low"] / Fmag["nominal"], nan=1.0)
                        r_hi = np.nan_to_num(Fmag["high"] / Fmag["nominal"], nan=1.0)
                    vals = np.concatenate([vals[:1], vals * r_lo, vals * r_hi])
                for k, v in (("nominal", vals[0]), ("low", vals.min(0)), ("high", vals.max(0))):
                    defl[(ax, k)] = np.where(ok[..., None, None, None], v, np.nan)
    for k, suffix in (("nominal", ""), ("low", "_low"), ("high", "_high")):
        data[f"force{suffix}_N"] = var(("spindle_rpm", "depth_mm", "feed_mm_s"), Fmag[k], "N",
                                       f"mean cutting force magnitude ({k})")
        for ax, what in (("normal", "normal to the wall"), ("axial", "along the tool axis")):
            data[f"deflection_{ax}{suffix}_um"] = var(full, defl[(ax, k)], "um",
                                                      f"static deflection {what} ({k})")
    data["k_normal_N_m"] = var(prd, stiff["normal"], "N/m", "static tool-tip stiffness normal "
                               "to the wall (robomill.plan.tooltip)")
    data["k_axial_N_m"] = var(prd, stiff["axial"], "N/m", "static tool-tip stiffness along the "
                              "tool axis (robomill.plan.tooltip)")
    # waviness: the identification interval, and the interval of the next tracker run's read
    wav = {k: np.full((P, R, D), np.nan) for k in ("nominal", "low", "high")}
    wav.update({k: np.full((P, R, D, V), np.nan) for k in ("read_low", "read_high", "noise")})
    if measured.has("gears"):
        n_vec = np.broadcast_to(frames[None, None, :, :, 1], (P, R, D, 3))
        u_vec = np.broadcast_to(frames[None, None, :, :, 0], (P, R, D, 3))
        w = waviness_um(cell.robot, q, n_vec, measured.gears, direction=u_vec,
                        length_mm=req.length_mm, orders=cell.gear_orders,
                        feed_mm_s=req.feed_mm_s, coverage=measured.waviness_coverage,
                        level=measured.level, min_cycles=measured.waviness_min_cycles)
        w.setdefault("read_low", w["low"][..., None] + np.zeros(V))
        w.setdefault("read_high", w["high"][..., None] + np.zeros(V))
        wav.update({k: np.where(ok if v.ndim == 3 else ok[..., None], v, np.nan)
                    for k, v in w.items()})
    data["waviness_um"] = var(prd, wav["nominal"], "um", "gear-line waviness normal to the "
                              "wall, in-phase sum (nominal)")
    for k in ("low", "high"):
        data[f"waviness_ident_{k}_um"] = var(prd, wav[k], "um", "gear-line waviness normal to "
                                             f"the wall, in-phase sum ({k} end of the "
                                             "identifying runs' spread)")
    pv = prd + ("feed_mm_s",)
    data["waviness_noise_um"] = var(pv, wav["noise"], "um", "tracker noise per spectrum bin "
                                    "at the cut's record (largest over the counted lines)")
    for k in ("low", "high"):
        data[f"waviness_{k}_um"] = var(pv, wav[f"read_{k}"], "um", "waviness the next tracker "
                                       f"run reads ({k}): identification spread widened by "
                                       "the tracker noise")
    # feed marks and removal rate
    c_mm = req.feed_mm_s[None, :] * 60.0 / (req.flutes * req.spindle_rpm[:, None])
    data["feed_per_tooth_mm"] = var(("spindle_rpm", "feed_mm_s"), c_mm, "mm", "feed per tooth")
    data["feed_mark_um"] = var(("spindle_rpm", "feed_mm_s"),
                               c_mm**2 / (8 * req.tool_diameter_mm / 2) * 1e3, "um",
                               "feed-mark height c^2/(8R)")
    data["mrr_mm3_s"] = var(("depth_mm", "feed_mm_s"),
                            req.depth_mm[:, None] * req.width_mm * req.feed_mm_s[None, :],
                            "mm3/s", "material removal rate a a_e v")
    coords = _coords(req, poses)
    coords["station"] = ("station", poses.s_mm, attrs("mm", "path abscissa from the cut's start"))
    ds = xr.Dataset(data, coords=coords)
    ds = form_error(ds)
    ds.attrs["missing_predictions"] = "; ".join(f"{k}: {v}" for k, v in missing.items())
    return ds


def form_error(ds: xr.Dataset) -> xr.Dataset:
    """Predicted form error of the wall: static deflection normal to the wall plus the gear
    waviness (a missing term counts as 0), nominal and upper bound [µm]. The waviness' upper
    bound is the identification interval's (the wall's waviness: the tracker's noise widens
    only the interval its reading is checked against)."""
    for suffix, wname in (("", "waviness_um"), ("_high", "waviness_ident_high_um")):
        d = ds[f"deflection_normal{suffix}_um"].fillna(0.0)
        w = ds[wname].fillna(0.0)
        fe = (d + w).where(ds["reachable"])
        ds[f"form_error{suffix}_um"] = fe.assign_attrs(attrs(
            "um", "predicted form error: normal deflection + waviness"))
    return ds


def _coords(req: PlanRequest, poses) -> dict:
    P = req.placements_mm
    return {
        "placement": ("placement", np.arange(len(P)), attrs("1", "placement index")),
        "placement_x_mm": ("placement", P[:, 0], attrs("mm", "cut midpoint x (base frame)")),
        "placement_y_mm": ("placement", P[:, 1], attrs("mm", "cut midpoint y (base frame)")),
        "placement_z_mm": ("placement", P[:, 2], attrs("mm", "cut midpoint z (base frame)")),
        "rotation": ("rotation", req.rotations_deg,
                     attrs("deg", "redundancy angle about the tool axis")),
        "direction": ("direction", list(req.direction_names), attrs("1", "feed direction")),
        "direction_deg": ("direction", req.direction_deg,
                          attrs("deg", "feed direction angle in the base XY plane")),
        "spindle_rpm": ("spindle_rpm", req.spindle_rpm, attrs("rpm", "spindle speed")),
        "depth_mm": ("depth_mm", req.depth_mm, attrs("mm", "axial depth of cut")),
        "feed_mm_s": ("feed_mm_s", req.feed_mm_s, attrs("mm/s", "feed rate")),
        "joint": ("joint", np.arange(1, poses.q_rad.shape[-1] + 1), attrs("1", "joint")),
    }


def apply_extrapolation(ds: xr.Dataset, req: PlanRequest, measured: Measured, cell: Cell,
                        reach) -> xr.Dataset:
    """Flag the candidates outside what the study measured and widen their intervals with
    the distance from the evidence (:mod:`robomill.plan.extrapolation`: the reasons and the
    stated law; the critical depth's members widened, :mod:`robomill.plan.stability`)."""
    from robomill.plan.extrapolation import extrapolation_code, widen

    code, excess, excess_stab = extrapolation_code(ds, req, reach)
    ds = ds.assign_attrs(interval_level=float(measured.level))
    return form_error(widen(ds, code, excess, excess_stab))
