"""Robot poses of the candidate cuts: where the part sits, how the spindle turns about the tool
axis, and what the joint model says about each posture.

A candidate cut is a straight line of length L through a placement point p (its midpoint) along
a feed direction u in the part frame (axes parallel to the base frame's). The tool orientation
is the cell's ``tool_rotation`` R0 turned by the redundancy angle θ about the tool axis,
R = R0 Rz(θ) ([Yi 2025, §4.2]; :func:`robomill.stiffness.tool_rotation_redundancy`). A cut is
reachable when inverse kinematics converges at its start, middle and end.

The joint model gives the translational compliance C(q) = J_v diag(c) J_vᵀ ([Yi 2025, eq. 3],
:func:`robomill.stiffness.translational_compliance_m_N`), the inverse of the Schur complement of
the Cartesian stiffness K = J⁻ᵀ K_θ J⁻¹ for a force-only load.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robomill.kinematics import SerialRobot
from robomill.stiffness import (
    jacobian_m,
    solve_poses,
    tool_rotation_redundancy,
    translational_compliance_m_N,
)


def direction_vectors(direction_deg: np.ndarray) -> np.ndarray:
    """Unit feed vectors ``(d, 3)`` in the base XY plane (0° = +X, counter-clockwise)."""
    a = np.deg2rad(np.asarray(direction_deg, float))
    return np.stack([np.cos(a), np.sin(a), np.zeros_like(a)], -1)


def cut_frames(direction_deg: np.ndarray) -> np.ndarray:
    """Cut frames ``(d, 3, 3)`` with columns feed u, wall normal n = ẑ × u and tool axis ẑ
    (:func:`robomill.forces.cut_frame`, :func:`robomill.experiment.cut_axes`)."""
    u = direction_vectors(direction_deg)
    z = np.broadcast_to([0.0, 0.0, 1.0], u.shape)
    return np.stack([u, np.cross(z, u), z], -1)


@dataclass(frozen=True)
class PoseGrid:
    """Postures of every (placement, rotation, direction) at ``stations`` along the cut.

    ``q_rad`` ``(P, R, D, S, n)``; ``reachable`` ``(P, R, D)`` (every station converged);
    ``s_mm`` ``(S,)`` path abscissae from the cut's start; the middle station is
    ``mid``."""

    q_rad: np.ndarray
    reachable: np.ndarray
    s_mm: np.ndarray
    checks: dict | None = None
    """Per station ``(P, R, D, S)`` (:func:`robomill.plan.feasible.pose_checks`) and
    ``path_status`` ``(P, R, D)`` (:data:`robomill.plan.feasible.REASONS`)."""

    @property
    def mid(self) -> int:
        return int(np.argmin(np.abs(self.s_mm - self.s_mm.mean())))

    @property
    def q_mid_rad(self) -> np.ndarray:
        return self.q_rad[:, :, :, self.mid]


def solve_grid(robot: SerialRobot, placements_mm: np.ndarray, rotations_deg: np.ndarray,
               direction_deg: np.ndarray, length_mm: float, *, R0: np.ndarray,
               q_seed_rad: np.ndarray, stations: int = 3, limits_deg: np.ndarray | None = None,
               limit_margin_deg: float = 0.0, min_wrist_angle_deg: float = 0.0) -> PoseGrid:
    """Inverse kinematics of every candidate cut at ``stations`` (≥ 2 → start … end; odd so a
    station is the middle) points along it (:func:`robomill.stiffness.solve_poses`), each
    posture turned into the joint limits and checked (:mod:`robomill.plan.feasible`): a cut is
    reachable when every station converges inside the limits with ``limit_margin_deg``, with
    its wrist angle at least ``min_wrist_angle_deg``, all in one configuration."""
    from robomill.plan.feasible import into_limits, path_status, pose_checks

    P = np.asarray(placements_mm, float).reshape(-1, 3)
    th = np.deg2rad(np.asarray(rotations_deg, float))
    u = direction_vectors(direction_deg)
    n_st = max(int(stations) | 1, 3)
    s = np.linspace(0.0, length_mm, n_st)
    pts = (P[:, None, None, :] + (s - length_mm / 2)[None, None, :, None] * u[None, :, None, :])
    # (P, D, S, 3) → with rotations (P, R, D, S, 3)
    pts = np.broadcast_to(pts[:, None], (len(P), len(th), len(u), n_st, 3))
    R = tool_rotation_redundancy(np.asarray(R0, float), th)                # (R, 3, 3)
    Rb = np.broadcast_to(R[None, :, None, None], pts.shape[:-1] + (3, 3))
    seed = np.asarray(q_seed_rad, float)
    q, ok = solve_poses(robot, pts.reshape(-1, 3), Rb.reshape(-1, 3, 3), seed)
    q = into_limits(q, limits_deg, seed)
    n = robot.n_joints
    q = q.reshape(pts.shape[:-1] + (n,))
    chk = pose_checks(robot, q, ok.reshape(pts.shape[:-1]), limits_deg=limits_deg,
                      limit_margin_deg=limit_margin_deg, min_wrist_angle_deg=min_wrist_angle_deg)
    chk["path_status"] = path_status(chk["status"], chk["configuration"])
    return PoseGrid(q, chk["path_status"] == 0, s, chk)


def compliance_grid(robot: SerialRobot, q_rad: np.ndarray, compliance: np.ndarray) -> np.ndarray:
    """Translational compliance ``(..., 3, 3)`` [m/N] at postures ``q_rad`` ``(..., n)``."""
    return translational_compliance_m_N(jacobian_m(robot, q_rad), compliance)


def directional_ratio(C: np.ndarray, C_ref: np.ndarray, shapes: np.ndarray) -> np.ndarray:
    """Stiffness of each pose along each mode shape relative to the reference pose,
    k_φ(q)/k_φ(q_ref) = (φᵀ C_ref φ)/(φᵀ C(q) φ), ``(..., M)``; 1 where the joint model has
    no compliance along φ."""
    phi = np.asarray(shapes, float)                                       # (M, 3)
    num = np.einsum("mi,ij,mj->m", phi, C_ref, phi)
    den = np.einsum("mi,...ij,mj->...m", phi, C, phi)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = num / den
    return np.where(np.isfinite(r) & (r > 0), r, 1.0)
