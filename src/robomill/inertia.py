"""A robot's inertia at a pose: its joint-space mass matrix from point masses on its links
(Pinocchio), as a cell file documents them (``cell.yaml`` ``mass_model``, manufacturer's data
or CAD).

Each point mass is a body on its link at its zero-configuration centre of mass, without
rotational inertia of its own (the cell documents none). Point masses leave a wrist joint
without inertia where every mass it carries sits on its axis, so M(q) may be singular: use it
for the kinetic energy ½ ψᵀ M(q) ψ of a joint motion ψ, never M⁻¹.

The kinematic tree follows the robot's D-H (or modified D-H) parameters exactly, so that the
rigid-body library's frames are the analysis kinematics' frames
(:class:`robomill.kinematics.SerialRobot`): joint i turns about z of D-H frame i−1 (frame i
for modified D-H). The mass matrix is Pinocchio's composite-rigid-body algorithm
[Featherstone 2008, §6.2], M(q) with kinetic energy ½ q̇ᵀ M(q) q̇. The virtual cell builds its
robot's true masses with it (:mod:`robomill.synth.inertia`), the planner the documented ones
(:mod:`robomill.plan.tooltip`).

Featherstone, R. *Rigid Body Dynamics Algorithms*. Springer, 2008.
Carpentier, J. et al. The Pinocchio C++ library. *IEEE/SICE International Symposium on System
Integration*, 2019, 614–619.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from pinocchio.utils import rotate

from robomill.kinematics import SerialRobot


def _rot(axis: str, angle_rad: float) -> pin.SE3:
    return pin.SE3(rotate(axis, float(angle_rad)), np.zeros(3))


def _trans(axis: int, length_m: float) -> pin.SE3:
    t = np.zeros(3)
    t[axis] = length_m
    return pin.SE3(np.eye(3), t)


def rigid_body_model(robot: SerialRobot, link: np.ndarray, mass_kg: np.ndarray,
                     com_mm: np.ndarray) -> pin.Model:
    """A Pinocchio model of ``robot`` (SI units) carrying point masses ``mass_kg`` on links
    ``link`` (1..n) at zero-configuration centres ``com_mm`` (base frame).

    Joint i's placement in its parent joint's frame is the fixed part of the D-H transform
    that precedes its rotation: ``base · Rz(θ₀,₁)`` for the first, then
    ``Tz(d) Tx(a) Rx(α)`` of the previous link and ``Rz(θ₀,ᵢ)`` (D-H), or
    ``Tz(d)`` of the previous link and ``Rx(α) Tx(a) Rz(θ₀,ᵢ)`` (modified D-H).
    """
    n = robot.n_joints
    a, d = robot.a_mm * 1e-3, robot.d_mm * 1e-3
    alpha, off = robot.alpha_rad, robot.theta_offset_rad
    base = np.asarray(robot.base, float)
    placement = pin.SE3(base[:3, :3], base[:3, 3] * 1e-3)
    model = pin.Model()
    parent = 0
    for i in range(n):
        if robot.convention == "dh":
            before = _rot("z", off[i])
            after = _trans(2, d[i]) * _trans(0, a[i]) * _rot("x", alpha[i])
        else:
            before = _rot("x", alpha[i]) * _trans(0, a[i]) * _rot("z", off[i])
            after = _trans(2, d[i])
        parent = model.addJoint(parent, pin.JointModelRZ(), placement * before, f"joint{i + 1}")
        placement = after
    data = model.createData()
    pin.forwardKinematics(model, data, np.zeros(n))
    for j, m, c in zip(np.asarray(link, int), np.asarray(mass_kg, float),
                       np.asarray(com_mm, float).reshape(-1, 3), strict=True):
        if m <= 0.0:
            continue
        local = data.oMi[int(j)].actInv(np.asarray(c, float) * 1e-3)
        model.appendBodyToJoint(int(j), pin.Inertia(float(m), local, np.zeros((3, 3))),
                                pin.SE3.Identity())
    return model


def mass_matrix_kg_m2(model: pin.Model, q_rad: np.ndarray) -> np.ndarray:
    """Joint-space mass matrix M(q) ``(n, n)`` by the composite-rigid-body algorithm
    (kg·m², symmetric)."""
    data = model.createData()
    M = np.array(pin.crba(model, data, np.asarray(q_rad, float)))
    return np.triu(M) + np.triu(M, 1).T


def documented_rigid_body_model(robot: SerialRobot, mass_model) -> pin.Model | None:
    """The rigid-body model of a cell file's ``mass_model``
    (:class:`robomill.io.cell.CellMassModel`, links first, then the tool on the last link);
    None without one."""
    if mass_model is None:
        return None
    points = mass_model.point_masses()
    if not points:
        return None
    return rigid_body_model(robot, np.array([p.link for p in points], int),
                            np.array([p.mass_kg for p in points], float),
                            np.array([p.com_mm for p in points], float).reshape(-1, 3))


def rayleigh_stiffness_mass(robot: SerialRobot, compliance_rad_Nm: np.ndarray,
                            rigid_body: pin.Model | None, q_rad: np.ndarray,
                            shape: np.ndarray) -> tuple[float, float]:
    """κ [N/m] and μ [kg] of a tool-tip shape φ at pose q: Rayleigh's quotient of the joints'
    eigenproblem K_θ ψ = ω² M(q) ψ [Géradin & Rixen 2015] on the joint motion that a unit
    tool-tip motion along φ asks of the elastic joints (their static deflection under a load
    along φ, scaled),

    .. math:: ψ(q) = \\frac{C_θ J_v(q)^T φ}{φ^T C(q) φ}, \\qquad
              κ(q) = \\frac{1}{φ^T C(q) φ}, \\qquad μ(q) = ψ^T M(q)\\, ψ,

    C(q) = J_v C_θ J_vᵀ the joints' tool-tip compliance, C_θ the joint compliances
    ``compliance_rad_Nm`` [rad/(N·m)] (0: a rigid joint). μ is NaN without a rigid-body model,
    and κ infinite (μ NaN) where no elastic joint moves the tool tip along φ.
    The virtual cell moves its planted modes with its planted joints and true masses
    (:mod:`robomill.synth.structure`), the planner the identified joints and the documented
    masses (:func:`robomill.plan.tooltip.mass_ratios`).

    Géradin, M.; Rixen, D. J. *Mechanical Vibrations: Theory and Application to Structural
    Dynamics*, 3rd ed. Wiley, 2015.
    """
    from robomill.stiffness.model import jacobian_m, translational_compliance_m_N

    q = np.asarray(q_rad, float)
    phi = np.asarray(shape, float)
    c = np.asarray(compliance_rad_Nm, float)
    J = jacobian_m(robot, q)
    flexibility_m_N = float(phi @ translational_compliance_m_N(J, c) @ phi)
    if not flexibility_m_N > 0.0:           # no elastic joint moves the tool tip along φ
        return float("inf"), float("nan")
    if rigid_body is None:
        return 1.0 / flexibility_m_N, float("nan")
    psi = c * (J[:3].T @ phi) / flexibility_m_N
    return 1.0 / flexibility_m_N, float(psi @ mass_matrix_kg_m2(rigid_body, q) @ psi)
