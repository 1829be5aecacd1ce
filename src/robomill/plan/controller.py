"""The robot model seen through the controller's conventions: its joint angles, its flange,
the tool frame and load in that flange, and the configuration data the controller expects
with each Cartesian target.

The cell file states the conventions (``controller_frames``, :mod:`robomill.io.controller`):
``q_controller = sign · q_model + offset``, and the controller's flange (ABB ``tool0``, KUKA
``$FLANGE``) in the model's last frame. The tool data are the model's tool frame moved into
that flange. KUKA's tool direction is the tool frame's x axis (``$TOOL_DIRECTION`` default
``#X``) [KUKA System Software 8, *Tool direction*], so for KUKA the tool frame and every
target are turned by Ry(−90°) about the tool point, putting x on the spindle axis; ABB's tool
axis is z [ABB RAPID reference, *tooldata*].

Configuration data, from the controller's joint angles as printed and the wrist centre W
(the intersection of the wrist axes):

* ABB ``confdata`` [ABB RAPID reference, *confdata*]: cf1, cf4, cf6 the quadrant
  ⌊q/90°⌋ of axes 1, 4 and 6; cfx = 4·(W behind axis 1) + 2·(W behind the lower arm) +
  (axis 5 negative);
* KUKA Status [KUKA System Software 8, *Status*]: bit 0 W in the overhead area (its x in the
  A1 coordinate system negative); bit 1 A3 ≥ φ, φ the A3 at which W lies on the line of the
  link arm (axes 2 → 3) extended; bit 2 A5 in [−180°, 0°) or ≥ 180°. Turn: bit j set when axis
  j + 1 is negative.

"In front of / behind the lower arm" is the side of the lower arm's line (axis 2 → axis 3, in
the plane normal to axis 2) on which W lies, "in front" being the side W lies on at the
controller's zero posture; the A1 coordinate system turns with axis 1 and equals the base
frame at its zero.

References: [ABB RAPID reference] ABB Robotics, *Technical reference manual — RAPID
Instructions, Functions and Data types* (3HAC050917-001), data types ``confdata``,
``tooldata``, ``loaddata``; [KUKA System Software 8] KUKA Roboter GmbH, *KUKA System Software
8.x — Operating and Programming Instructions for System Integrators*, sections *Status*,
*Turn*, *Tool direction*, *$LOAD*. The frames of the shipped IRB 1600 were checked against the
ROS-Industrial description ``abb_irb1600_support`` (``link_6 → tool0`` rpy (0, 90°, 0)).
"""

from __future__ import annotations

import numpy as np

KUKA_TOOL_DIRECTION = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
"""Ry(−90°): the tool frame turned so that its x axis is the spindle axis (KUKA #X)."""

DECIMALS = 6
"""Decimals the programs print joint angles, positions and Euler angles with."""


def printed(x) -> np.ndarray:
    """Values as the programs print them (rounded to :data:`DECIMALS`, no −0)."""
    return np.round(np.asarray(x, float), DECIMALS) + 0.0


def _hom(R, p) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def tcp_turn(controller: str | None) -> np.ndarray:
    """Rotation appended to the tool frame for the controller's tool direction."""
    return KUKA_TOOL_DIRECTION if controller == "kuka" else np.eye(3)


def tool_in_flange(robot, frames, controller: str | None) -> np.ndarray:
    """The tool frame (4×4) in the controller's flange: ``inv(flange_in_model) · tool``,
    turned to the controller's tool direction."""
    T = np.linalg.inv(frames.flange_in_model) @ _hom(robot.tool_R, robot.tool_mm)
    T[:3, :3] = T[:3, :3] @ tcp_turn(controller)
    return T


def cog_in_flange(robot, frames, com_base_zero_mm) -> np.ndarray:
    """A centre of mass given in the base frame at the model's zero posture, in the
    controller's flange frame [mm]."""
    F0 = robot.frames(np.zeros(robot.n_joints))[-1] @ frames.flange_in_model
    return (np.asarray(com_base_zero_mm, float) - F0[:3, 3]) @ F0[:3, :3]


def _geometry(robot, q_model_deg):
    F = robot.frames(np.deg2rad(np.asarray(q_model_deg, float)))
    p2, p3, w = F[..., 1, :3, 3], F[..., 2, :3, 3], F[..., 4, :3, 3]
    return F, p2, p3, w, F[..., 1, :3, 2]


def _a1_front(robot, frames, q_model_deg) -> np.ndarray:
    """x of the wrist centre in the A1 coordinate system (base x turned with axis 1)."""
    q = np.asarray(q_model_deg, float)
    F, *_, w = _geometry(robot, q)[:4]
    base = robot.base
    zero_q1 = frames.model_deg(np.zeros(robot.n_joints))[0]
    d = np.deg2rad(q[..., 0] - zero_q1)
    x0, z0 = base[:3, 0], base[:3, 2]
    xa1 = (np.cos(d)[..., None] * x0 + np.sin(d)[..., None] * np.cross(z0, x0))
    return np.einsum("...i,...i->...", w - base[:3, 3], xa1)


def _arm_angle_deg(robot, q_model_deg) -> np.ndarray:
    """Signed angle [deg] about axis 2 from the link arm (axis 2 → 3) to axis 3 → W."""
    _, p2, p3, w, ax2 = _geometry(robot, q_model_deg)
    u, v = p3 - p2, w - p3
    s = np.einsum("...i,...i->...", np.cross(u, v), ax2)
    return np.rad2deg(np.arctan2(s, np.einsum("...i,...i->...", u, v)))


def _lower_arm_side(robot, q_model_deg) -> np.ndarray:
    _, p2, p3, w, ax2 = _geometry(robot, q_model_deg)
    return np.einsum("...i,...i->...", np.cross(p3 - p2, w - p2), ax2)


def abb_confdata(robot, frames, q_model_deg) -> np.ndarray:
    """ABB [cf1, cf4, cf6, cfx] ``(..., 4)`` (module docstring)."""
    q = np.asarray(q_model_deg, float)
    qc = printed(frames.joints_deg(q))
    quad = np.floor(qc[..., [0, 3, 5]] / 90.0).astype(int)
    behind1 = _a1_front(robot, frames, q) < 0
    zero = frames.model_deg(np.zeros(robot.n_joints))
    side0 = _lower_arm_side(robot, zero)
    behind_arm = _lower_arm_side(robot, q) * side0 < 0
    cfx = 4 * behind1.astype(int) + 2 * behind_arm.astype(int) + (qc[..., 4] < 0).astype(int)
    return np.concatenate([quad, cfx[..., None]], axis=-1)


def kuka_phi_deg(robot, frames) -> float:
    """φ: the A3 [deg] at which the wrist centre lies on the link arm's line extended."""
    zero = frames.model_deg(np.zeros(robot.n_joints))
    one = zero.copy()
    one[2] = frames.model_deg(np.eye(robot.n_joints)[2])[2]      # A3 = 1°
    g0, g1 = float(_arm_angle_deg(robot, zero)), float(_arm_angle_deg(robot, one))
    slope = np.sign(((g1 - g0 + 180.0) % 360.0) - 180.0)
    phi = -g0 / slope
    return float((phi + 180.0) % 360.0 - 180.0)


def kuka_status_turn(robot, frames, q_model_deg) -> tuple[np.ndarray, np.ndarray]:
    """KUKA Status and Turn ``(...)`` integers (module docstring)."""
    q = np.asarray(q_model_deg, float)
    qc = printed(frames.joints_deg(q))
    overhead = _a1_front(robot, frames, q) < 0
    arm = qc[..., 2] >= kuka_phi_deg(robot, frames)
    a5 = qc[..., 4]
    wrist = ((a5 >= -180.0) & (a5 < 0.0)) | (a5 >= 180.0)
    status = overhead.astype(int) + 2 * arm.astype(int) + 4 * wrist.astype(int)
    turn = np.sum((qc < 0).astype(int) << np.arange(qc.shape[-1]), axis=-1)
    return status, turn
