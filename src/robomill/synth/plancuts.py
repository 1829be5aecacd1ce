"""The virtual cell cuts the planned cuts: stability in the time domain and static deflection,
from the cell's planted truth at each cut's pose (issue 28, closing the loop).

For each cut (a planned one of ``results/plan/next/manifest.yaml`` at its placement, feed
direction and redundancy angle θ, or one of the study's own at its path with θ = 0):

* **the pose**: inverse kinematics of the cut's middle with the tool orientation
  R = R0 Rz(θ) (:func:`robomill.stiffness.tool_rotation_redundancy`), seeded at the cell's home;
* **the modes at the pose**: the virtual cell's modes (``synth.modes``) hold at the reference
  point where the impact test is made; a mode below ``robot_mode_max_hz`` is the robot's
  structure and follows the planted joint stiffness K_θ (``synth.loadtests`` entry of the cell's
  robot): k_r(q) = k_r k_φ(q)/k_φ(q_ref), f_r(q) = f_r √(k_φ(q)/k_φ(q_ref)) (modal mass kept),
  k_φ = 1/(φᵀ C(q) φ), C = J_v K_θ⁻¹ J_vᵀ (seed 001 eq. 3);
* **stability**: the seed-002 cut on those modes at the cut's speed, depth, feed and
  engagement with the planted cutting coefficients, once regenerative (the seed's chip) and
  once delay-free with the linear chip (mode coupling)
  (:func:`robomill.chatter.modal_timedomain.simulate_modal_cut`), stable when the vibration
  grows in neither and the regenerative run's teeth stay in the cut
  (:func:`robomill.chatter.modal_timedomain.stability_verdict`);
* **deflection**: δ = C(q) F̄ with the planted K_θ and the simulated mean force F̄ (cut frame
  rotated to the base frame), along the wall normal n = ẑ × u and the tool axis.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from robomill.experiment import Cut, cut_endpoints_mm, cut_process, feed_direction

DEFAULTS: dict[str, Any] = {
    "duration_s": 3.0,
    "steps_per_tooth": 32,
    "Kt_noise_fraction": 0.005,
    "noise_seed": 1,
    "band_hz": [5.0, 500.0],
    "harmonic_halfwidth_hz": 5.0,
    "growth_ratio": 3.0,
    "max_out_of_cut_fraction": 0.05,
    "robot_mode_max_hz": 200.0,
    "modes_reference_mm": None,
}
"""Defaults of ``plan.simulate`` (the schema fills the same values)."""

COLUMNS = ["cut", "origin", "redundancy_deg", "spindle_rpm", "depth_mm", "feed_mm_s",
           "reachable", "stable", "growth_regenerative", "growth_coupling", "chatter_hz",
           "indicator_N", "out_of_cut_fraction", "force_N", "F_feed_N", "F_normal_N",
           "F_axial_N", "k_normal_N_m", "deflection_normal_um", "deflection_axial_um"]
"""Columns of ``results/plan/simulated.csv``."""


def settings(section: Mapping[str, Any] | None) -> dict[str, Any]:
    """``plan.simulate`` with defaults filled."""
    return {**DEFAULTS, **dict(section or {})}


@dataclass(frozen=True)
class PosedCut:
    """A cut to cut on the virtual cell: the cut, its experiment header (length, defaults)
    and its redundancy angle; ``origin`` ``plan`` or ``study``."""

    cut: Cut
    experiment: Mapping[str, Any]
    redundancy_deg: float = 0.0
    origin: str = "study"

    @property
    def middle_mm(self) -> np.ndarray:
        a, b = cut_endpoints_mm(self.cut, self.experiment)
        return (a + b) / 2


def planned_cuts(manifest: Mapping[str, Any]) -> list[PosedCut]:
    """The planned cuts of ``results/plan/next/manifest.yaml`` with their redundancy angles
    (each cut's ``redundancy_deg``; a manifest from before that key: ``plan.cuts.<id>``)."""
    exp = dict(manifest["experiment"])
    plan = (manifest.get("plan") or {}).get("cuts") or {}
    out = []
    for c in manifest.get("cuts") or []:
        fields = {k: c.get(k) for k in ("spindle_rpm", "flutes", "tool_diameter_mm",
                                        "radial_immersion", "milling", "direction_deg")}
        start = c.get("start_mm")
        cut = Cut(str(c["id"]), None, None, c.get("direction"), float(c["feed_mm_s"]),
                  float(c["depth_mm"]), **fields,
                  start_mm=None if start is None else tuple(float(x) for x in start))
        theta = c.get("redundancy_deg")  # the cut's own key, else the plan's record of it
        if theta is None:
            theta = (plan.get(cut.id) or {}).get("redundancy_deg", 0.0)
        theta = float(theta)
        out.append(PosedCut(cut, exp, theta, "plan"))
    return out


def planted_compliance(config: Mapping[str, Any]) -> np.ndarray | None:
    """Planted joint compliances 1/K_θ [rad/(N·m)] of the cell's robot (the
    ``synth.loadtests.robots`` entry of ``cell.robot.name``); None when it has none."""
    name = config["cell"]["robot"].get("name")
    for e in (config["synth"].get("loadtests") or {}).get("robots") or []:
        if e.get("name") == name:
            return 1.0 / np.asarray(e["k_Nm_rad"], float)
    return None


def _poses(cell, points_mm: np.ndarray, theta_deg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    from robomill.stiffness import solve_poses, tool_rotation_redundancy

    R = tool_rotation_redundancy(cell.tool_rotation(), np.deg2rad(theta_deg))
    return solve_poses(cell.robot, points_mm, R, cell.q_home_rad)


def modes_at_poses(cell, q_rad: np.ndarray, q_ref_rad: np.ndarray, compliance: np.ndarray | None,
                   robot_mode_max_hz: float) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                      np.ndarray]:
    """The virtual cell's modes at postures ``q_rad`` ``(B, n)``: ``f_hz`` ``(B, M)``,
    ``zeta`` ``(M,)``, ``k_N_m`` ``(B, M)``, ``shape`` ``(M, 3)`` (base frame). Without a
    planted joint stiffness the modes do not move."""
    from robomill.stiffness import jacobian_m, translational_compliance_m_N

    f = np.array([m.f_hz for m in cell.modes])
    z = np.array([m.zeta for m in cell.modes])
    k = np.array([m.k_N_m for m in cell.modes])
    phi = np.array([m.shape for m in cell.modes], float)
    B = len(q_rad)
    if compliance is None:
        return np.tile(f, (B, 1)), z, np.tile(k, (B, 1)), phi
    C = translational_compliance_m_N(jacobian_m(cell.robot, q_rad), compliance)
    C_ref = translational_compliance_m_N(jacobian_m(cell.robot, q_ref_rad), compliance)
    num = np.einsum("mi,ij,mj->m", phi, C_ref, phi)
    den = np.einsum("mi,bij,mj->bm", phi, C, phi)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = num / den
    ratio = np.where(np.isfinite(ratio) & (ratio > 0) & (f < robot_mode_max_hz), ratio, 1.0)
    return f * np.sqrt(ratio), z, k * ratio, phi


def cut_frame(cut: Cut) -> np.ndarray:
    """Columns feed u, wall normal n = ẑ × u, tool axis ẑ (base frame; as the planner's)."""
    u = feed_direction(cut)
    z = np.array([0.0, 0.0, 1.0])
    return np.stack([u, np.cross(z, u), z], -1)


def simulate_cuts(cuts: Sequence[PosedCut], cell, compliance: np.ndarray | None,
                  reference_mm: np.ndarray, section: Mapping[str, Any] | None = None
                  ) -> pd.DataFrame:
    """``results/plan/simulated.csv``: each cut cut on the virtual cell (:data:`COLUMNS`;
    ``stable`` True/False, NaN outcomes where inverse kinematics fails)."""
    from robomill.chatter.modal_timedomain import (
        ModalCut,
        simulate_modal_cut,
        stability_verdict,
    )
    from robomill.chatter.model import immersion_angles
    from robomill.stiffness import jacobian_m, translational_compliance_m_N

    s = settings(section)
    if not cuts:
        return pd.DataFrame(columns=COLUMNS)
    mids = np.array([c.middle_mm for c in cuts])
    q, ok = _poses(cell, mids, np.array([c.redundancy_deg for c in cuts]))
    q_ref, ok_ref = _poses(cell, np.asarray(reference_mm, float)[None], np.array([0.0]))
    fn, zeta, k, phi = modes_at_poses(cell, q, q_ref[0],
                                      compliance if ok_ref[0] else None,
                                      float(s["robot_mode_max_hz"]))
    C = (translational_compliance_m_N(jacobian_m(cell.robot, q), compliance)
         if compliance is not None else None)
    cc = cell.cutting
    rows = []
    for b, pc in enumerate(cuts):
        cut = pc.cut
        p = cut_process(cut, pc.experiment)
        R = cut_frame(cut)
        row = {"cut": cut.id, "origin": pc.origin, "redundancy_deg": pc.redundancy_deg,
               "spindle_rpm": p["spindle_rpm"], "depth_mm": cut.depth_mm,
               "feed_mm_s": cut.feed_mm_s, "reachable": bool(ok[b])}
        if not ok[b]:
            rows.append(row)
            continue
        ent, ext = ((0.0, float(np.pi)) if p["milling"] == "slot"
                    else immersion_angles(p["radial_immersion"], p["milling"]))
        runs = [simulate_modal_cut(
            ModalCut(fn[b], zeta, k[b], phi @ R[:, :2], float(p["spindle_rpm"]),
                     int(p["flutes"]), ent, ext, p["feed_per_tooth_mm"] * 1e-3,
                     cut.depth_mm * 1e-3, cc["Ktc_N_mm2"] * 1e6, cc["Krc_N_mm2"] * 1e6,
                     cc["Kac_N_mm2"] * 1e6, cc["Kte_N_mm"] * 1e3, cc["Kre_N_mm"] * 1e3,
                     cc["Kae_N_mm"] * 1e3, overlap=mu, linear_chip=mu == 0.0),
            duration_s=float(s["duration_s"]), steps_per_tooth=int(s["steps_per_tooth"]),
            Kt_noise_fraction=float(s["Kt_noise_fraction"]), noise_seed=int(s["noise_seed"]))
            for mu in (1.0, 0.0)]
        v = stability_verdict(*runs, float(p["spindle_rpm"]) * int(p["flutes"]) / 60.0,
                              band_hz=tuple(s["band_hz"]),
                              harmonic_halfwidth_hz=float(s["harmonic_halfwidth_hz"]),
                              growth_ratio=float(s["growth_ratio"]),
                              max_out_of_cut_fraction=float(s["max_out_of_cut_fraction"]))
        F = v.mean_force_N
        row.update({"stable": v.stable, "growth_regenerative": v.growth_regenerative,
                    "growth_coupling": v.growth_coupling, "chatter_hz": v.chatter_hz,
                    "indicator_N": v.indicator_N, "out_of_cut_fraction": v.out_of_cut_fraction,
                    "force_N": float(np.linalg.norm(F)),
                    "F_feed_N": F[0], "F_normal_N": F[1], "F_axial_N": F[2]})
        if C is not None:
            d = C[b] @ (R @ F)                                                   # m
            row.update({"k_normal_N_m": float(1.0 / (R[:, 1] @ C[b] @ R[:, 1])),
                        "deflection_normal_um": abs(float(R[:, 1] @ d)) * 1e6,
                        "deflection_axial_um": abs(float(R[:, 2] @ d)) * 1e6})
        rows.append(row)
    return pd.DataFrame(rows, columns=COLUMNS)
