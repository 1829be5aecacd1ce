"""The structure the cut shakes: the robot's modes at the cut's pose plus the spindle and tool.

The planted tool-tip modes (``synth.modes``, thesis §3.3: 20–72 Hz) are the robot's modes *at
the impact test's pose* q_ref (``synth.process.reference_point_mm``; null: the centre of the
study's cuts, :func:`robomill.io.synthetic_layout.impact_tcp_mm`): there each keeps its
planted frequency, damping ratio and tool-tip modal stiffness. Elsewhere the arm is stiffer or
softer, and heavier or lighter, as its joints see the tool-tip motion through other lever arms.
Both follow from the planted robot: its joint stiffness K_θ (the ``synth.loadtests`` entry
that bears the cell robot's name, the same planted robot the load tests measure) and its
rigid-body mass matrix M(q) (the robot's true point masses, :mod:`robomill.synth.inertia`, the
same masses whose weight the C-Track simulator's joints carry). How the modes follow them is
the cell's choice, ``synth.process.robot_modes``:

**planted** (shapes fixed). Each planted mode r keeps its tool-tip shape φ_r and damping
ratio; its stiffness and mass at pose q are moved by the Rayleigh quotient of the joints'
generalized eigenproblem K_θ ψ = ω² M(q) ψ [Géradin & Rixen 2015, Rayleigh's method]
evaluated on the joint motion that the mode's tool-tip motion asks of the elastic joints: the
static joint deflection under a tool-tip load along φ_r, scaled to a unit tool-tip motion
along φ_r,

.. math:: ψ_r(q) = \\frac{K_θ^{-1} J_v(q)^T φ_r}{φ_r^T C(q) φ_r}, \\qquad
          C(q) = J_v(q)\\, K_θ^{-1} J_v(q)^T

(C the joints' tool-tip compliance of the load tests; Dumas et al. 2011), whose stiffness and
mass are

.. math:: κ_r(q) = ψ_r^T K_θ ψ_r = \\frac{1}{φ_r^T C(q) φ_r}, \\qquad
          μ_r(q) = ψ_r^T M(q)\\, ψ_r .

The joints act in series with the rest of the structure, so each mode's stiffness and mass
change in proportion:

.. math:: k_r(q) = k_r \\frac{κ_r(q)}{κ_r(q_{ref})}, \\qquad
          m_r(q) = m_r \\frac{μ_r(q)}{μ_r(q_{ref})}, \\qquad
          ω_r(q) = \\sqrt{k_r(q)/m_r(q)} .

At q_ref these are exactly the planted modes, shapes included (a cell whose planted shapes
follow measured ones keeps them there). Where the configuration states no masses (or the
shape moves none of them at q or q_ref: point masses leave the wrist without inertia) the
modal masses are held. (The joints also couple the modes where their compliance changes across
shapes; the planted shapes are not orthogonal, several nearly parallel, and that coupling would
mix them into modes no measurement supports, so each mode is moved alone.)

**eigen** (shapes turn with the pose; the robot has joint stiffness and masses). At each pose
q the arm's modes are the generalized eigenproblem K_θ ψ_j = ω_j² M̃(q) ψ_j [Géradin & Rixen
2015, §2.4] with the inertia fitted once at q_ref to the planted modes' frequencies,
tool-tip shapes and stiffnesses (:mod:`robomill.synth.shapecal`),
mapped to the tool tip through the Jacobian: shape u_j(q) ∝ J_v(q) ψ_j, modal stiffness
κ_j(q) = ω_j²/‖J_v ψ_j‖² (:func:`robomill.synth.jointmodes.eigenmodes`). Planted mode r is
eigenmode r at q_ref (the lowest ones, in order: the fit puts them at the planted
frequencies, so they are the modes the impact test's 10–100 Hz band sees), and at another
pose the eigenmode that continues its joint motion (largest mass-weighted correlation,
:func:`robomill.synth.jointmodes.track`). Mode r at q takes

.. math:: φ_r(q) = u_r(q), \\qquad ω_r(q) = ω_r \\frac{ω^{eig}_r(q)}{ω^{eig}_r(q_{ref})},
          \\qquad k_r(q) = k_r \\frac{κ_r(q)}{κ_r(q_{ref})},

with ω_r, k_r and ζ_r planted (ζ_r kept with the mode). The shape is the eigenproblem's at
every pose, q_ref included (there it is the fit's, with its stated MAC against the planted
``shape``, which otherwise serves only cells without a mass model); it turns, and modes mix,
with the pose. Each mode's tool-tip stiffness is the planted one scaled
by the joint model's change (the joints in series with the rest of the structure). The ratio
of frequencies keeps the planted frequencies at q_ref where the fit misses them (by at most
1e-4 relative on the shipped cells). Without masses the eigen law falls
back to the planted law's stiffness (masses held).

Without joint stiffness the planted modes hold at every pose, under either law.

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

from robomill.synth.jointmodes import JointModes, eigenmodes, track
from robomill.synth.shapecal import ShapeCalibration, calibrate_shapes, shape_calibrated_mass


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

    calibration: ShapeCalibration
    reference: JointModes
    count: int


def robot_structure(cell) -> RobotStructure | None:
    """The arm's calibrated eigenmodel at ``cell.q_reference_rad`` (the eigen law; None where
    the cell has no joint stiffness, reference pose or mass model: the modes then follow the
    planted law of the module docstring)."""
    if (cell.joint_stiffness_Nm_rad is None or cell.q_reference_rad is None
            or cell.rigid_body_model is None or not cell.modes):
        return None
    q = np.asarray(cell.q_reference_rad, float)
    Jv = _jv(cell, q)
    cal = calibrate_shapes(cell.rigid_body_model, q, cell.joint_stiffness_Nm_rad, Jv,
                           [m.f_hz for m in cell.modes], [m.shape for m in cell.modes],
                           [m.k_N_m for m in cell.modes])
    ref = eigenmodes(cell.joint_stiffness_Nm_rad,
                     shape_calibrated_mass(cell.rigid_body_model, q, cal), Jv)
    return RobotStructure(cal, ref, len(cell.modes))


def _jv(cell, q: np.ndarray) -> np.ndarray:
    from robomill.stiffness.model import jacobian_m

    return jacobian_m(cell.robot, np.asarray(q, float))[:3]


def rayleigh_stiffness_mass(cell, q_rad: np.ndarray, shape: np.ndarray
                            ) -> tuple[float, float]:
    """κ_r(q) [N/m] and μ_r(q) [kg] of a tool-tip shape φ_r at pose q (module docstring,
    planted law: :func:`robomill.inertia.rayleigh_stiffness_mass` with the planted joint
    stiffness and the true masses); μ is NaN where the cell has no rigid-body model."""
    from robomill.inertia import rayleigh_stiffness_mass as rayleigh

    return rayleigh(cell.robot, 1.0 / np.asarray(cell.joint_stiffness_Nm_rad, float),
                    cell.rigid_body_model, q_rad, shape)


def robot_modes_at(cell, q_rad: np.ndarray) -> list:
    """The robot's modes at pose q by the cell's law ``cell.robot_modes_law``
    (``synth.process.robot_modes``, module docstring); the planted modes themselves where the
    cell has no joint stiffness, and under the planted law where q is the reference pose."""
    if cell.joint_stiffness_Nm_rad is None or cell.q_reference_rad is None:
        return list(cell.modes)
    if cell.robot_modes_law == "eigen" and cell.robot_structure is not None:
        return _eigen_modes_at(cell, np.asarray(q_rad, float))
    return _planted_modes_at(cell, np.asarray(q_rad, float))


def _planted_modes_at(cell, q: np.ndarray) -> list:
    """The planted law: fixed shapes, stiffness and mass by the Rayleigh quotient."""
    import dataclasses

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


def _eigen_modes_at(cell, q: np.ndarray) -> list:
    """The eigen law: the calibrated eigenproblem's modes at q, tracked from q_ref."""
    import dataclasses

    structure = cell.robot_structure
    ref = structure.reference
    M = shape_calibrated_mass(cell.rigid_body_model, q, structure.calibration)
    here = eigenmodes(cell.joint_stiffness_Nm_rad, M, _jv(cell, q))
    which = track(ref, M, here, structure.count)
    out = []
    for r, (m, j) in enumerate(zip(cell.modes, which, strict=True)):
        shape = here.tip_shape[j]
        # one sign per mode: the joint motion's continuation of the reference mode's
        if float(ref.psi[:, r] @ M @ here.psi[:, j]) < 0.0:
            shape = -shape
        if not (np.isfinite(shape).all() and np.isfinite(ref.k_tip_N_m[r])):
            # the mode moves no tool tip here, or already at q_ref (a spin about an axis
            # through the TCP): no compliance at the tip, never a ratio of rounding values
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
