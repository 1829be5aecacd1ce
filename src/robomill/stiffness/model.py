"""Joint-stiffness model of a serial robot [Yi 2025, eqs. 6–10]: rigid links
and elastic joints under a quasi-static TCP force.

* joint torques τ = Jᵀ W with the TCP wrench W = [F; 0], joint deflections θ = K_θ⁻¹ τ;
* TCP deflection X = J_v K_θ⁻¹ J_vᵀ F (eq. 9); written linear in the joint compliances
  c_j = 1/k_j it is X = A(J, F) c with column j of A equal to J_{v,j} (J_{v,j} · F) (eq. 10)
  (:func:`design_matrix`);
* Cartesian stiffness K = J⁻ᵀ K_θ J⁻¹ (eq. 8) for a square, non-singular J; the
  translational compliance C = J_v diag(c) J_vᵀ and the stiffness along a direction
  1 / (uᵀ C u) (Bu et al. 2017).

Units are SI: Jacobians with linear rows in m/rad (:func:`jacobian_m`), forces in N,
deflections in m, joint stiffness in N·m/rad; :func:`compliance_from_table` reads the
compliances c = 1/k back from the identified joint-stiffness table.
"""

from __future__ import annotations

import numpy as np

from robomill.kinematics import SerialRobot

GRAVITY_M_S2 = 9.80665


def jacobian_m(robot: SerialRobot, q_rad: np.ndarray) -> np.ndarray:
    """Geometric Jacobian ``(..., 6, n)`` in SI units (linear rows m/rad, angular rows 1).

    The vector-product Jacobian of :meth:`SerialRobot.jacobian` [Yi 2025, §1.2] with its
    linear rows converted from mm/rad.
    """
    J = np.array(robot.jacobian(q_rad), dtype=float)
    J[..., :3, :] *= 1e-3
    return J


def design_matrix(J_m: np.ndarray, force_N: np.ndarray) -> np.ndarray:
    """Coefficient matrix A(J, F) of the identification model X = A c [Yi 2025, eq. 10].

    Parameters
    ----------
    J_m
        Jacobians ``(m, 6, n)`` or their linear rows ``(m, 3, n)`` [m/rad] at the m poses.
    force_N
        TCP forces ``(m, 3)`` [N] in the base frame.

    Returns
    -------
    numpy.ndarray
        ``(3 m, n)``; rows 3i..3i+2 are pose i's X, Y, Z; column j multiplies c_j [rad/(N·m)].
    """
    Jv = np.asarray(J_m, float)[:, :3, :]
    F = np.asarray(force_N, float)
    tau = np.einsum("mij,mi->mj", Jv, F)  # joint torque per unit compliance [N·m]
    A = Jv * tau[:, None, :]
    return A.reshape(-1, Jv.shape[-1])


def predict_deflection_m(J_m: np.ndarray, force_N: np.ndarray,
                         compliance: np.ndarray) -> np.ndarray:
    """TCP deflections ``(m, 3)`` [m]: X = J_v diag(c) J_vᵀ F [Yi 2025, eq. 9].

    ``compliance`` are c_j = 1/k_j [rad/(N·m)]; a rigid (or unobservable) joint has c_j = 0.
    """
    A = design_matrix(J_m, force_N)
    return (A @ np.asarray(compliance, float)).reshape(-1, 3)


def translational_compliance_m_N(J_m: np.ndarray, compliance: np.ndarray) -> np.ndarray:
    """Translational compliance ``(..., 3, 3)`` [m/N]: C = J_v diag(c) J_vᵀ (force-only load,
    tool free to rotate); the inverse of the Schur complement of K = J⁻ᵀ K_θ J⁻¹."""
    Jv = np.asarray(J_m, float)[..., :3, :]
    return np.einsum("...ij,j,...kj->...ik", Jv, np.asarray(compliance, float), Jv)


def cartesian_stiffness(J_m: np.ndarray, k_Nm_rad: np.ndarray) -> np.ndarray:
    """Cartesian stiffness K = J⁻ᵀ K_θ J⁻¹ ``(..., 6, 6)`` [Yi 2025, eq. 8], SI units
    (N/m, N/rad, N·m/m, N·m/rad blocks). Needs a square, non-singular Jacobian."""
    Jinv = np.linalg.inv(np.asarray(J_m, float))
    return np.swapaxes(Jinv, -1, -2) @ (np.asarray(k_Nm_rad, float)[:, None] * Jinv)


def directional_stiffness_N_m(C_m_N: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Stiffness along unit directions (stiffness orientation, Bu et al. 2017, [Yi 2025, §4.1]).

    k_u = 1 / (uᵀ C u): the force along u per unit TCP displacement along u.

    Parameters
    ----------
    C_m_N
        Translational compliance ``(..., 3, 3)`` [m/N].
    directions
        Unit vectors as the columns of ``(..., 3, d)`` (e.g. the tool rotation matrix: tool
        X = feed, Y, Z = axial).

    Returns
    -------
    numpy.ndarray
        ``(..., d)`` [N/m].
    """
    U = np.asarray(directions, float)
    return 1.0 / np.einsum("...id,...ij,...jd->...d", U, C_m_N, U)


def comprehensive_index_N_m(k_xyz_N_m: np.ndarray) -> np.ndarray:
    """Comprehensive stiffness index S ([Yi 2025, §4.3]; its formula is not printed, *assumed*
    here as the harmonic mean of the three directional stiffnesses),
    S = 3 / (1/k_x + 1/k_y + 1/k_z) [N/m]: dominated by the weakest direction."""
    k = np.asarray(k_xyz_N_m, float)
    return 3.0 / np.sum(1.0 / k, axis=-1)


def compliance_from_table(joint_table) -> np.ndarray:
    """Joint compliances [rad/(N·m)] from a ``joint_stiffness.csv`` table (0 where not
    observable: treated as rigid)."""
    k = joint_table["k_Nm_rad"].to_numpy(float)
    obs = joint_table["observable"].astype(str).str.lower().isin(["true", "1"]).to_numpy()
    c = np.zeros_like(k)
    ok = obs & np.isfinite(k) & (k > 0)
    c[ok] = 1.0 / k[ok]
    return c
