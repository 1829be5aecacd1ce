"""The structure the cut shakes: the robot's modes at the cut's pose plus the spindle and tool.

The planted tool-tip modes (``synth.modes``, thesis §3.3: 20–72 Hz) are the robot's modes *at
the impact test's pose* q_ref (``synth.process.reference_point_mm``; null: the centre of the
study's cuts). Elsewhere the arm is stiffer or softer, and heavier or lighter, as its joints
see the tool-tip motion through other lever arms. Both follow from the planted robot: its joint
stiffness K_θ (the ``synth.loadtests`` entry that bears the cell robot's name, the same planted
robot the load tests measure) and its rigid-body mass matrix M(q) (the robot's true point
masses, :mod:`robomill.synth.inertia`, the same masses whose weight the C-Track simulator's
joints carry).

Each planted mode r keeps its tool-tip shape φ_r and damping ratio; its stiffness and mass at
pose q are moved by the Rayleigh quotient of the joints' generalized eigenproblem
K_θ ψ = ω² M(q) ψ [Géradin & Rixen 2015, Rayleigh's method] evaluated on the joint motion
that the mode's tool-tip motion asks of the elastic joints: the static joint deflection under
a tool-tip load along φ_r, scaled to a unit tool-tip motion along φ_r,

.. math:: ψ_r(q) = \frac{K_θ^{-1} J_v(q)^T φ_r}{φ_r^T C(q) φ_r}, \\qquad
          C(q) = J_v(q)\\, K_θ^{-1} J_v(q)^T

(C the joints' tool-tip compliance of the load tests; Dumas et al. 2011), whose stiffness and
mass are

.. math:: κ_r(q) = ψ_r^T K_θ ψ_r = \frac{1}{φ_r^T C(q) φ_r}, \\qquad
          μ_r(q) = ψ_r^T M(q)\\, ψ_r .

The joints act in series with the rest of the structure, so each mode's stiffness and mass
change in proportion:

.. math:: k_r(q) = k_r \frac{κ_r(q)}{κ_r(q_{ref})}, \\qquad
          m_r(q) = m_r \frac{μ_r(q)}{μ_r(q_{ref})}, \\qquad
          ω_r(q) = \\sqrt{k_r(q)/m_r(q)} .

At q_ref these are exactly the planted modes. Where the configuration states no masses (or the
shape moves none of them at q or q_ref: point masses leave the wrist without inertia) the
modal masses are held. (The joints also couple the modes where their compliance changes across
shapes; the planted shapes are not orthogonal, several nearly parallel, and that coupling would
mix them into modes no measurement supports, so each mode is moved alone.)

The spindle and tool add pose-independent modes above the robot's 10–100 Hz band
(``synth.process.spindle_modes``, *assumed*: no source gives them; stiff, so that at the
thesis' depths they do not limit the cut).

Géradin, M.; Rixen, D. J. *Mechanical Vibrations: Theory and Application to Structural
Dynamics*, 3rd ed. Wiley, 2015.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np


def joint_stiffness_Nm_rad(config: Mapping[str, Any]) -> np.ndarray | None:
    """Planted joint stiffness K_θ of the cell's robot: the ``synth.loadtests.robots`` entry
    named like ``cell.robot`` (None without one: the modes do not change with the pose)."""
    name = config["cell"]["robot"].get("name")
    for e in (config["synth"].get("loadtests") or {}).get("robots", []) or []:
        if e.get("name") == name and e.get("k_Nm_rad"):
            return np.asarray(e["k_Nm_rad"], float)
    return None


def rayleigh_stiffness_mass(cell, q_rad: np.ndarray, shape: np.ndarray
                            ) -> tuple[float, float]:
    """κ_r(q) [N/m] and μ_r(q) [kg] of a tool-tip shape φ_r at pose q (module docstring);
    μ is NaN where the cell has no rigid-body model."""
    from robomill.stiffness.model import jacobian_m, translational_compliance_m_N
    from robomill.synth.inertia import mass_matrix_kg_m2

    q = np.asarray(q_rad, float)
    phi = np.asarray(shape, float)
    J = jacobian_m(cell.robot, q)
    c_rad_Nm = 1.0 / np.asarray(cell.joint_stiffness_Nm_rad, float)
    flexibility_m_N = float(phi @ translational_compliance_m_N(J, c_rad_Nm) @ phi)
    Jv = J[:3]
    if cell.rigid_body_model is None:
        return 1.0 / flexibility_m_N, float("nan")
    psi = c_rad_Nm * (Jv.T @ phi) / flexibility_m_N
    return 1.0 / flexibility_m_N, float(psi @ mass_matrix_kg_m2(cell.rigid_body_model, q) @ psi)


def robot_modes_at(cell, q_rad: np.ndarray) -> list:
    """The robot's modes at pose q (module docstring); the planted modes themselves where the
    cell has no joint stiffness or q is the reference pose."""

    import dataclasses

    if cell.joint_stiffness_Nm_rad is None or cell.q_reference_rad is None:
        return list(cell.modes)
    q = np.asarray(q_rad, float)
    if np.allclose(q, cell.q_reference_rad, rtol=0.0, atol=1e-12):
        return list(cell.modes)
    out = []
    for m in cell.modes:
        kappa_ref, mu_ref = rayleigh_stiffness_mass(cell, cell.q_reference_rad, m.shape)
        kappa_q, mu_q = rayleigh_stiffness_mass(cell, q, m.shape)
        k_q = m.k_N_m * kappa_q / kappa_ref
        # the mass ratio where both poses move mass along the shape; else the mass is held
        moved = np.isfinite([mu_ref, mu_q]).all() and min(mu_ref, mu_q) > 0.0
        m_q = m.m_kg * (mu_q / mu_ref if moved else 1.0)
        out.append(dataclasses.replace(m, f_hz=float(np.sqrt(k_q / m_q) / (2 * np.pi)),
                                       k_N_m=k_q))
    return out


def modes_at(cell, q_rad: np.ndarray) -> list:
    """Every mode of the structure at pose q: the robot's (:func:`robot_modes_at`) and the
    spindle's and tool's (``cell.spindle_modes``)."""
    return robot_modes_at(cell, q_rad) + list(cell.spindle_modes)


def reference_pose_rad(cell, config: Mapping[str, Any]) -> np.ndarray:
    """The impact test's pose q_ref: the TCP at ``synth.process.reference_point_mm`` (base
    frame; null: the mean of the midpoints of the study's cuts) with the cell's tool
    orientation, inverse kinematics nearest the home posture."""
    point = config["synth"]["process"].get("reference_point_mm")
    if point is None:
        from robomill.io.synthetic_layout import synthetic_cuts

        mids = [np.mean(cell.cut_endpoints_mm(c), axis=0) for c in synthetic_cuts(config)]
        point = np.mean(mids, axis=0)
    T = np.eye(4)
    T[:3, :3] = cell.tool_rotation()
    T[:3, 3] = np.asarray(point, float)
    return cell.robot.ik_path(T[None], cell.q_home_rad)[0]
