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
