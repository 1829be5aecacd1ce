"""The structure the cut shakes: the robot's modes at the cut's pose plus the spindle and tool.

The planted tool-tip modes (``synth.modes``, thesis §3.3: 20–72 Hz) are the robot's modes *at
the impact test's pose* q_ref (``synth.process.reference_point_mm``; null: the centre of the
study's cuts). Elsewhere the arm is stiffer or softer as its joints see the tool-tip load
through other lever arms: the robot's Cartesian stiffness at the tool tip follows from the
planted joint stiffness K_θ of the cell's robot (the ``synth.loadtests`` entry that bears the
cell robot's name, the same planted robot the load tests measure) through the Jacobian: its
tool-tip compliance is

.. math:: C(q) = J_v(q)\\, K_θ^{-1} J_v(q)^T

(the joint-stiffness model of the load tests; Dumas et al. 2011). The joints act in series
with the rest of the structure: each planted mode's flexibility 1/k_r changes in proportion to
the joints' compliance along its shape,

.. math:: k_r(q) = k_r \frac{φ_r^T C(q_{ref}) φ_r}{φ_r^T C(q) φ_r}, \\qquad
          ω_r(q) = \\sqrt{k_r(q)/m_r}

with the planted modal masses m_r = k_r/ω_r² held (the mass model; *assumed*: over the small
workspace of a block the arm's inertia changes little), the shape φ_r and the damping ratio
kept. At q_ref these are exactly the planted modes. (The joints also couple the modes where
their compliance changes across shapes; the planted shapes are not orthogonal, several nearly
parallel, and that coupling would mix them into modes no measurement supports, so it is left
out.)

The spindle and tool add pose-independent modes above the robot's 10–100 Hz band
(``synth.process.spindle_modes``, *assumed*: no source gives them; stiff, so that at the
thesis' depths they do not limit the cut).

No rigid-body library (Pinocchio, the Robotics Toolbox) is used: the cell documents only point
masses (``cell.mass_model``, no link inertias), from which a joint-space mass matrix would be
singular at the wrist; the planted modal masses are the mass model instead.
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


def compliance_m_N(robot, q_rad: np.ndarray, k_Nm_rad: np.ndarray) -> np.ndarray:
    """Tool-tip translational compliance ``(3, 3)`` [m/N] of the joints at pose q:
    ``J_v K_θ⁻¹ J_vᵀ`` (:func:`robomill.stiffness.model.translational_compliance_m_N`)."""
    from robomill.stiffness.model import jacobian_m, translational_compliance_m_N

    return translational_compliance_m_N(jacobian_m(robot, np.asarray(q_rad, float)),
                                        1.0 / np.asarray(k_Nm_rad, float))


def robot_modes_at(cell, q_rad: np.ndarray) -> list:
    """The robot's modes at pose q (module docstring); the planted modes themselves where the
    cell has no joint stiffness or q is the reference pose."""

    import dataclasses

    if cell.joint_stiffness_Nm_rad is None or cell.q_reference_rad is None:
        return list(cell.modes)
    q = np.asarray(q_rad, float)
    if np.allclose(q, cell.q_reference_rad, rtol=0.0, atol=1e-12):
        return list(cell.modes)
    C_ref = compliance_m_N(cell.robot, cell.q_reference_rad, cell.joint_stiffness_Nm_rad)
    C_q = compliance_m_N(cell.robot, q, cell.joint_stiffness_Nm_rad)
    out = []
    for m in cell.modes:
        phi = np.asarray(m.shape, float)
        k_q = m.k_N_m * float(phi @ C_ref @ phi) / float(phi @ C_q @ phi)
        out.append(dataclasses.replace(m, f_hz=float(np.sqrt(k_q / m.m_kg) / (2 * np.pi)),
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
