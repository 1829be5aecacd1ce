"""Poses of the milling robot for the stiffness study [Yi 2025, §4.2–4.4]: the free rotation
about the tool axis, batch inverse kinematics toward TCP points, the deflection at a posture
under an end load, and the stiffness-optimal pose per milling height.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from robomill.kinematics import SerialRobot, ik_batch
from robomill.stiffness.model import GRAVITY_M_S2, jacobian_m, translational_compliance_m_N


def tool_rotation_redundancy(R0: np.ndarray, angle_rad: float | np.ndarray) -> np.ndarray:
    """Tool orientation for redundancy angle θ_r: rotation about the tool axis (z),
    R = R0 Rz(θ_r) (milling leaves that rotation free, [Yi 2025, §4.2])."""
    a = np.asarray(angle_rad, float)
    c, s = np.cos(a), np.sin(a)
    Rz = np.zeros(a.shape + (3, 3))
    Rz[..., 0, 0], Rz[..., 0, 1], Rz[..., 1, 0], Rz[..., 1, 1] = c, -s, s, c
    Rz[..., 2, 2] = 1.0
    return np.asarray(R0, float) @ Rz


def solve_poses(robot: SerialRobot, points_mm: np.ndarray, R_tool: np.ndarray,
                q_seed_rad: np.ndarray, *, limits_rad: np.ndarray | None = None,
                **ik_kw) -> tuple[np.ndarray, np.ndarray]:
    """Joint angles reaching TCP ``points_mm`` ``(m, 3)`` with orientation ``R_tool``
    (``(3, 3)`` or ``(m, 3, 3)``), by batch IK seeded at ``q_seed_rad`` with joint 1 turned
    toward each point. Returns ``q (m, n)`` and a reachability mask (IK converged and, if
    ``limits_rad`` ``(n, 2)`` is given, inside the joint limits)."""
    P = np.asarray(points_mm, float).reshape(-1, 3)
    T = np.broadcast_to(np.eye(4), (len(P), 4, 4)).copy()
    T[:, :3, :3] = R_tool
    T[:, :3, 3] = P
    q0 = np.broadcast_to(np.asarray(q_seed_rad, float), (len(P), robot.n_joints)).copy()
    q0[:, 0] = np.arctan2(P[:, 1], P[:, 0]) + q0[:, 0]
    q, ok = ik_batch(robot, T, q0, **ik_kw)
    q = (q + np.pi) % (2 * np.pi) - np.pi
    if limits_rad is not None:
        lim = np.asarray(limits_rad, float)
        ok &= np.all((q >= lim[:, 0] - 1e-9) & (q <= lim[:, 1] + 1e-9), axis=-1)
    return q, ok


def deformation_m(robot: SerialRobot, q_rad: np.ndarray, compliance: np.ndarray,
                  force_N: Sequence[float]) -> np.ndarray:
    """TCP deflection ``(..., 3)`` [m] under ``force_N`` at postures ``q_rad``
    (e.g. the 60 kg end load, [Yi 2025, §4.4.1])."""
    C = translational_compliance_m_N(jacobian_m(robot, q_rad), compliance)
    return np.einsum("...ij,j->...i", C, np.asarray(force_N, float))


def optimal_poses(robot: SerialRobot, compliance: np.ndarray, maps, *, load_kg: float,
                  random_poses: int, rng: np.random.Generator):
    """Stiffness-optimal pose per milling height [Yi 2025, §4.3]: the argmax of the
    comprehensive index over the plane grid and the redundancy angles, beside
    ``random_poses`` random reachable poses (seed Tables 2–4), each with its deformation
    under the end load ``load_kg`` hanging at the TCP."""
    import pandas as pd

    F = np.array([0.0, 0.0, -load_kg * GRAVITY_M_S2])
    rows = []
    for h in maps["height_mm"].values:
        mh = maps.sel(height_mm=h)
        S = mh["S_N_m"].values  # (redundancy, y, x)
        flat = np.where(np.isfinite(S), S, -np.inf).ravel()
        picks = [("optimal", int(np.argmax(flat)))]
        valid = np.flatnonzero(np.isfinite(S.ravel()))
        if random_poses and valid.size:
            for i, k in enumerate(rng.choice(valid, size=min(random_poses, valid.size),
                                             replace=False)):
                picks.append((f"random_{i + 1}", int(k)))
        for kind, k in picks:
            ir, iy, ix = np.unravel_index(k, S.shape)
            q = mh["q_deg"].values[ir, iy, ix]
            d = deformation_m(robot, np.deg2rad(q), compliance, F) * 1e6
            kx, ky, kz = mh["k_N_m"].values[ir, iy, ix]
            row = {"height_mm": float(h), "pose": kind,
                   "redundancy_deg": float(mh["redundancy_deg"].values[ir]),
                   "x_mm": float(mh["x"].values[ix]), "y_mm": float(mh["y"].values[iy]),
                   "kx_N_m": kx, "ky_N_m": ky, "kz_N_m": kz, "S_N_m": S[ir, iy, ix],
                   "dx_um": d[0], "dy_um": d[1], "dz_um": d[2],
                   "deformation_um": float(np.linalg.norm(d))}
            row.update({f"q{j + 1}_deg": q[j] for j in range(robot.n_joints)})
            rows.append(row)
    return pd.DataFrame(rows)
