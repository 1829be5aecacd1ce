"""The structure the cut shakes: the robot's modes at the cut's pose plus the spindle and tool.

The planted tool-tip modes (``synth.modes``, thesis §3.3: 20–72 Hz) are the robot's modes *at
the impact test's pose* q_ref (``synth.process.reference_point_mm``; null: the centre of the
study's cuts, :func:`robomill.io.synthetic_layout.impact_tcp_mm`): there each keeps its
planted frequency, damping ratio and tool-tip modal stiffness. What the pose changes follows
from the planted robot: its joint stiffness K_θ (the ``synth.loadtests`` entry that bears the
cell robot's name, the same planted robot the load tests measure) and its rigid-body mass
matrix M(q) (the robot's true point masses, :mod:`robomill.synth.inertia`, with the inertia
calibrated once at q_ref, :mod:`robomill.synth.jointmodes`).

**Modes at a pose** (the robot has joint stiffness and masses). At each pose q the arm's modes
are the generalized eigenproblem K_θ ψ_j = ω_j² M̃(q) ψ_j [Géradin & Rixen 2015, §2.4],
mapped to the tool tip through the Jacobian: shape u_j(q) ∝ J_v(q) ψ_j, modal stiffness
κ_j(q) = ω_j²/‖J_v ψ_j‖² (:func:`robomill.synth.jointmodes.eigenmodes`). Planted mode r is
eigenmode r at q_ref (the lowest ones, in order: the calibration puts them at the planted
frequencies, so they are the modes the impact test's 10–100 Hz band sees), and at another
pose the eigenmode that continues its joint motion (largest mass-weighted correlation,
:func:`robomill.synth.jointmodes.track`). Mode r at q takes

.. math:: φ_r(q) = u_r(q), \\qquad ω_r(q) = ω_r \\frac{ω^{eig}_r(q)}{ω^{eig}_r(q_{ref})},
          \\qquad k_r(q) = k_r \\frac{κ_r(q)}{κ_r(q_{ref})},

with ω_r, k_r and ζ_r planted (ζ_r kept with the mode: a modal damping ratio per planted
mode). The shape is the eigenproblem's at every pose, q_ref included (the planted ``shape``
serves only cells without a mass model); it turns, and modes mix, with the pose. The joints
act in series with the rest of the structure (links, spindle mount), so each mode's tool-tip
stiffness is the planted one scaled by the joint model's change, not the joint model's own
value (whose static compliance J_v K_θ⁻¹ J_vᵀ [Dumas et al. 2011] is that of the joints
alone). The ratio of frequencies is 1 where the calibration is exact (it is, to 1e-9, on the
shipped cells) and keeps the planted frequencies at q_ref where it is not.

**Without masses** (the configuration states none): each planted mode keeps its shape and
mass, and its stiffness follows the joints' tool-tip compliance C(q) = J_v K_θ⁻¹ J_vᵀ along
it, k_r(q) = k_r (φ_rᵀ C(q_ref) φ_r)/(φ_rᵀ C(q) φ_r). Without joint stiffness the planted
modes hold at every pose.

The spindle and tool add pose-independent modes above the robot's 10–100 Hz band
(``synth.process.spindle_modes``, *assumed*: no source gives them; stiff, so that at the
thesis' depths they do not limit the cut).

Géradin, M.; Rixen, D. J. *Mechanical Vibrations: Theory and Application to Structural
Dynamics*, 3rd ed. Wiley, 2015.
Dumas, C.; Caro, S.; Garnier, S.; Furet, B. Joint stiffness identification of six-revolute
industrial serial robots. *Robotics and Computer-Integrated Manufacturing* 27(4), 881–888, 2011.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from robomill.synth.jointmodes import (
    InertiaCalibration,
    JointModes,
    calibrate_inertia,
    calibrated_mass,
    eigenmodes,
    track,
)


def joint_stiffness_Nm_rad(config: Mapping[str, Any]) -> np.ndarray | None:
    """Planted joint stiffness K_θ of the cell's robot: the ``synth.loadtests.robots`` entry
    named like ``cell.robot`` (None without one: the modes do not change with the pose)."""
    name = config["cell"]["robot"].get("name")
    for e in (config["synth"].get("loadtests") or {}).get("robots", []) or []:
        if e.get("name") == name and e.get("k_Nm_rad"):
            return np.asarray(e["k_Nm_rad"], float)
    return None


@dataclass(frozen=True)
class RobotStructure:
    """The planted arm's vibration model (module docstring): the calibrated inertia and the
    eigenmodes at the reference pose; ``count`` planted robot modes."""

    calibration: InertiaCalibration
    reference: JointModes
    count: int


def robot_structure(cell) -> RobotStructure | None:
    """The arm's calibrated eigenmodel at ``cell.q_reference_rad`` (None where the cell has no
    joint stiffness, reference pose or mass model: the modes then follow the simpler laws of
    the module docstring)."""
    from robomill.synth.inertia import mass_matrix_kg_m2

    if (cell.joint_stiffness_Nm_rad is None or cell.q_reference_rad is None
            or cell.rigid_body_model is None or not cell.modes):
        return None
    q = np.asarray(cell.q_reference_rad, float)
    M = mass_matrix_kg_m2(cell.rigid_body_model, q)
    cal = calibrate_inertia(cell.joint_stiffness_Nm_rad, M, [m.f_hz for m in cell.modes])
    ref = eigenmodes(cell.joint_stiffness_Nm_rad, calibrated_mass(M, cal), _jv(cell, q))
    return RobotStructure(cal, ref, len(cell.modes))


def _jv(cell, q: np.ndarray) -> np.ndarray:
    from robomill.stiffness.model import jacobian_m

    return jacobian_m(cell.robot, np.asarray(q, float))[:3]


def _compliance_along(cell, q: np.ndarray, shape: np.ndarray) -> float:
    """φᵀ C(q) φ [m/N]: the joints' tool-tip compliance along a unit shape."""
    from robomill.stiffness.model import jacobian_m, translational_compliance_m_N

    J = jacobian_m(cell.robot, np.asarray(q, float))
    c_rad_Nm = 1.0 / np.asarray(cell.joint_stiffness_Nm_rad, float)
    phi = np.asarray(shape, float)
    return float(phi @ translational_compliance_m_N(J, c_rad_Nm) @ phi)


def robot_modes_at(cell, q_rad: np.ndarray) -> list:
    """The robot's modes at pose q (module docstring): from the eigenproblem where the cell
    has joint stiffness and masses; else the planted modes, their stiffness moved along
    their shape by the joints' compliance where the cell has joint stiffness."""
    import dataclasses

    if cell.joint_stiffness_Nm_rad is None or cell.q_reference_rad is None:
        return list(cell.modes)
    q = np.asarray(q_rad, float)
    structure = cell.robot_structure
    if structure is None:
        if np.allclose(q, cell.q_reference_rad, rtol=0.0, atol=1e-12):
            return list(cell.modes)
        out = []
        for m in cell.modes:
            ratio = (_compliance_along(cell, cell.q_reference_rad, m.shape)
                     / _compliance_along(cell, q, m.shape))
            out.append(dataclasses.replace(m, k_N_m=m.k_N_m * ratio,
                                           f_hz=m.f_hz * float(np.sqrt(ratio))))
        return out
    from robomill.synth.inertia import mass_matrix_kg_m2

    ref = structure.reference
    M = calibrated_mass(mass_matrix_kg_m2(cell.rigid_body_model, q), structure.calibration)
    here = eigenmodes(cell.joint_stiffness_Nm_rad, M, _jv(cell, q))
    which = track(ref, M, here, structure.count)
    out = []
    for r, (m, j) in enumerate(zip(cell.modes, which, strict=True)):
        shape = here.tip_shape[j]
        # one sign per mode: the joint motion's continuation of the reference mode's
        if float(ref.psi[:, r] @ M @ here.psi[:, j]) < 0.0:
            shape = -shape
        if not np.isfinite(shape).all():  # the mode moves no tool tip at this pose
            shape, k = np.asarray(m.shape, float), np.inf
        else:
            k = m.k_N_m * here.k_tip_N_m[j] / ref.k_tip_N_m[r]
        out.append(dataclasses.replace(
            m, f_hz=float(m.f_hz * here.f_hz[j] / ref.f_hz[r]), k_N_m=float(k),
            shape=tuple(float(v) for v in shape)))
    return out


def modes_at(cell, q_rad: np.ndarray) -> list:
    """Every mode of the structure at pose q: the robot's (:func:`robot_modes_at`) and the
    spindle's and tool's (``cell.spindle_modes``)."""
    return robot_modes_at(cell, q_rad) + list(cell.spindle_modes)


def reference_pose_rad(cell, config: Mapping[str, Any]) -> np.ndarray:
    """The impact test's pose q_ref: the TCP at the impact test's point
    (:func:`robomill.io.synthetic_layout.impact_tcp_mm`: ``synth.process.reference_point_mm``,
    null: the mean of the midpoints of the study's cuts; the point the impact files' manifest
    entries carry as ``tcp_mm``) with the cell's tool orientation, inverse kinematics nearest
    the home posture."""
    from robomill.io.synthetic_layout import impact_tcp_mm

    T = np.eye(4)
    T[:3, :3] = cell.tool_rotation()
    T[:3, 3] = impact_tcp_mm(config)
    return cell.robot.ik_path(T[None], cell.q_home_rad)[0]
