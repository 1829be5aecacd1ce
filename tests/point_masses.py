"""The kinetic energy of point masses carried by a robot's links, written without a rigid-body
library: the mass centres move with the analysis kinematics' own D-H frames and are
differentiated numerically (the independent truth of the mass-matrix tests)."""

from __future__ import annotations

import numpy as np


def kinetic_energy_J(robot, link, mass_kg, com_mm, q, qdot, eps=1e-6) -> float:
    """½ Σ m |v|² [J] at joint angles ``q`` and joint velocity ``qdot`` of masses ``mass_kg`` on
    links ``link`` (1..n) whose centres are ``com_mm`` at the zero configuration (base frame)."""
    F0 = robot.frames(np.zeros(robot.n_joints))

    def centres(qq):
        F = robot.frames(qq)
        return np.array([((F[j] @ np.linalg.inv(F0[j]))[:3] @ np.r_[c, 1.0]) * 1e-3
                         for j, c in zip(link, com_mm, strict=True)])

    v = (centres(q + eps * qdot) - centres(q - eps * qdot)) / (2 * eps)
    return 0.5 * float(np.sum(np.asarray(mass_kg) * np.sum(v**2, axis=1)))


def rotational_kinetic_energy_J(robot, second_moment_kg_m2, q, qdot, eps=1e-6) -> float:
    """½ Σ_l ω_lᵀ I_l ω_l [J] of rigid links with rotational inertia I_l = tr(Σ_l)·1 − Σ_l
    about their centres (Σ_l ``(n, 3, 3)``, second moment of mass in the frame that turns with
    joint l about its axis: D-H frame l without its twist α_l, or modified D-H frame l),
    ω_l from numerical derivatives of the analysis kinematics' frame rotations."""
    n = robot.n_joints

    def rotations(qq):
        R = robot.frames(qq)[1:, :3, :3]
        if robot.convention == "dh":
            # undo the twist Rx(α_l) that D-H frame l carries after the joint's rotation
            c, s = np.cos(robot.alpha_rad), np.sin(robot.alpha_rad)
            Rx_inv = np.zeros((n, 3, 3))
            Rx_inv[:, 0, 0] = 1.0
            Rx_inv[:, 1, 1], Rx_inv[:, 1, 2] = c, s
            Rx_inv[:, 2, 1], Rx_inv[:, 2, 2] = -s, c
            R = R @ Rx_inv
        return R

    R = rotations(q)
    dR = (rotations(q + eps * qdot) - rotations(q - eps * qdot)) / (2 * eps)
    energy = 0.0
    for Rl, dRl, S in zip(R, dR, np.asarray(second_moment_kg_m2, float), strict=True):
        W = Rl.T @ dRl                       # body angular velocity, skew-symmetric
        w = np.array([W[2, 1], W[0, 2], W[1, 0]])
        energy += 0.5 * float(w @ (np.trace(S) * np.eye(3) - S) @ w)
    return energy


def calibrated_mass_matrix(cell, mass_model_mapping, q) -> np.ndarray:
    """M̃(q) of a cell under the eigen law, by polarization of its calibrated bodies' kinetic
    energy (no rigid-body library): the point masses of ``mass_model_mapping`` (the config's
    ``cell.mass_model``) scaled per link, the links' rotational inertia and the rotors
    (robomill.synth.shapecal), 2T(v) = vᵀ M̃ v."""
    from robomill.calibration.gravity import mass_model_from_mapping

    cal = cell.robot_structure.calibration
    n = cell.robot.n_joints
    mm = mass_model_from_mapping(mass_model_mapping, n)
    scaled = mm.mass_kg * cal.link_scale[np.asarray(mm.link, int) - 1]

    def two_t(v):
        return 2.0 * (kinetic_energy_J(cell.robot, mm.link, scaled, mm.com_mm, q, v)
                      + rotational_kinetic_energy_J(cell.robot, cal.second_moment_kg_m2, q, v)
                      + 0.5 * float(v @ (cal.rotor_kg_m2 * v)))

    E = np.eye(n)
    M = np.array([[0.5 * (two_t(E[i] + E[j]) - two_t(E[i]) - two_t(E[j])) for j in range(n)]
                  for i in range(n)])
    return (M + M.T) / 2
