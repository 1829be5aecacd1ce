"""Feasible robot poses: inside the joint limits with a margin, away from singularities, and in
one named arm/elbow/wrist configuration.

* **Joint limits.** A posture is inside when every joint lies within ``[low + m, high − m]``
  of the cell's working range (``robot.joint_limits_deg``) for the stated margin m; the
  inverse kinematics' angles are first moved by whole turns into the range, nearest a
  reference posture (:func:`into_limits`).
* **Singularity.** Two measures per posture: the wrist angle β between the axes of joints 4
  and 6 (a spherical wrist is singular at β = 0, where those axes align [Siciliano et al.
  2009, §3.3]), and the smallest singular value σ_min of the geometric Jacobian with its
  linear rows divided by the robot's reach (dimensionless; 0 at any singularity [Yoshikawa
  1985]). A posture with β below the stated minimum is refused; σ_min is reported.
* **Configuration.** Three binary choices name the inverse-kinematics branch, in the terms
  robot controllers use [ABB RAPID reference, *confdata*]: the wrist centre in front of or
  behind joint 1's axis (``front``/``back``), the elbow above or below the line from the
  shoulder to the wrist centre (``up``/``down``), and the sign of the wrist bend about joint 5
  (``w+``/``w-``).
  A path keeps one configuration: a change between stations is a flip through a singularity
  that the controller cannot make along a straight cut.
"""

from __future__ import annotations

import numpy as np

from robomill.kinematics import SerialRobot, reach_mm

REASONS = ("ok", "ik", "joint_limit", "singularity", "configuration_change")
"""Pose status codes (index = code): reachable, inverse kinematics did not converge, outside
the joint limits with the margin, wrist angle below the minimum, configuration changes along
the cut (first failing reason, in this order)."""


def into_limits(q_rad: np.ndarray, limits_deg: np.ndarray | None,
                ref_rad: np.ndarray | None = None) -> np.ndarray:
    """Each joint angle moved by whole turns 2πk into its limits, nearest ``ref_rad`` (or the
    range's middle); an angle no turn brings inside is left as it is (it fails the limits)."""
    q = np.asarray(q_rad, float)
    if limits_deg is None:
        return q
    lim = np.deg2rad(np.asarray(limits_deg, float))
    ref = lim.mean(1) if ref_rad is None else np.asarray(ref_rad, float)
    k = np.arange(-2, 3)[:, None]
    cand = q[..., None, :] + 2 * np.pi * k                                    # (..., 5, n)
    inside = (cand >= lim[:, 0]) & (cand <= lim[:, 1])
    dist = np.where(inside, np.abs(cand - np.broadcast_to(ref, q.shape)[..., None, :]), np.inf)
    best = np.argmin(dist, axis=-2)
    pick = np.take_along_axis(cand, best[..., None, :], axis=-2)[..., 0, :]
    return np.where(np.isfinite(np.min(dist, axis=-2)), pick, q)


def limit_clearance_deg(q_rad: np.ndarray, limits_deg: np.ndarray | None) -> np.ndarray:
    """Smallest distance of any joint to its nearest limit [deg] (negative: outside);
    +inf when the cell states no limits."""
    q = np.rad2deg(np.asarray(q_rad, float))
    if limits_deg is None:
        return np.full(q.shape[:-1], np.inf)
    lim = np.asarray(limits_deg, float)
    return np.min(np.minimum(q - lim[:, 0], lim[:, 1] - q), axis=-1)


def wrist_angle_deg(robot: SerialRobot, q_rad: np.ndarray) -> np.ndarray:
    """Wrist angle β [deg] between the axes of joints 4 and 6 (0 at the wrist singularity;
    folded to 0–90°, as antiparallel axes are singular too)."""
    z, _ = robot.joint_axes(q_rad)
    c = np.clip(np.abs(np.einsum("...i,...i->...", z[..., 3, :], z[..., 5, :])), 0.0, 1.0)
    return np.rad2deg(np.arccos(c))


def sigma_min(robot: SerialRobot, q_rad: np.ndarray) -> np.ndarray:
    """Smallest singular value of the Jacobian with linear rows over the reach (1)."""
    J = robot.jacobian(q_rad).copy()
    J[..., :3, :] /= reach_mm(robot)
    return np.linalg.svd(J, compute_uv=False)[..., -1]


def configuration(robot: SerialRobot, q_rad: np.ndarray) -> np.ndarray:
    """Configuration code ``(...)`` in 0..7: 4·back + 2·down + wrist− (module docstring).

    * back: the wrist centre (on joint 5's axis) lies behind joint 1's axis, i.e. against the
      direction of frame 1's x axis;
    * down: the elbow (joint 3's axis) lies below the line from the shoulder (joint 2's axis)
      to the wrist centre (the base z component of its offset from that line is negative);
    * wrist−: the wrist bends the negative way about joint 5's axis, (z₄ × z₆)·z₅ < 0.
    """
    q = np.asarray(q_rad, float)
    F = robot.frames(q)
    z, o = robot.joint_axes(q)
    wc = o[..., 4, :]
    x1 = F[..., 1, :3, 0]
    back = np.einsum("...i,...i->...", wc - o[..., 0, :], x1) < 0
    line = wc - o[..., 1, :]
    elbow = o[..., 2, :] - o[..., 1, :]
    t = (np.einsum("...i,...i->...", elbow, line)
         / np.maximum(np.einsum("...i,...i->...", line, line), 1e-300))
    down = (elbow - t[..., None] * line)[..., 2] < 0
    bend = np.einsum("...i,...i->...", np.cross(z[..., 3, :], z[..., 5, :]), z[..., 4, :])
    return 4 * back.astype(int) + 2 * down.astype(int) + (bend < 0).astype(int)


def configuration_name(code: int) -> str:
    """``front/up/w+`` … for a :func:`configuration` code."""
    code = int(code)
    return "/".join(("back" if code & 4 else "front", "down" if code & 2 else "up",
                     "w-" if code & 1 else "w+"))


def pose_checks(robot: SerialRobot, q_rad: np.ndarray, converged: np.ndarray, *,
                limits_deg: np.ndarray | None, limit_margin_deg: float,
                min_wrist_angle_deg: float) -> dict[str, np.ndarray]:
    """Per posture ``(..., n)``: ``clearance_deg``, ``wrist_deg``, ``sigma_min``,
    ``configuration`` and ``status`` (index into :data:`REASONS`; the configuration change
    is a property of a path, judged by the caller)."""
    clear = limit_clearance_deg(q_rad, limits_deg)
    wrist = wrist_angle_deg(robot, q_rad)
    status = np.zeros(clear.shape, np.int8)
    status = np.where(wrist < min_wrist_angle_deg, 3, status)
    status = np.where(clear < limit_margin_deg, 2, status)
    status = np.where(np.asarray(converged, bool), status, 1).astype(np.int8)
    return {"clearance_deg": clear, "wrist_deg": wrist, "sigma_min": sigma_min(robot, q_rad),
            "configuration": configuration(robot, q_rad), "status": status}


def path_status(status: np.ndarray, config: np.ndarray) -> np.ndarray:
    """Status of whole cuts from their stations (last axis): the first station's failure in
    :data:`REASONS` order, else ``configuration_change`` when the stations' configurations
    differ, else ok."""
    st = np.asarray(status)
    worst = np.where(st > 0, st, 127).min(-1)
    worst = np.where(worst == 127, 0, worst)
    same = np.all(config == config[..., :1], axis=-1)
    return np.where(worst > 0, worst, np.where(same, 0, 4)).astype(np.int8)


def pose_check_vars(checks: dict, dims: tuple[str, ...]) -> dict:
    """The candidate dataset's variables of the pose checks ``(P, R, D, S)``: the cut's status
    (:data:`REASONS`), configuration (at its middle station), smallest wrist angle, joint-limit
    clearance and σ_min along it."""
    from robomill.xrvars import attrs, var

    mid = checks["configuration"].shape[-1] // 2
    return {
        "pose_status": (dims, checks["path_status"],
                        attrs("1", "pose check of the cut: " + ", ".join(
                            f"{i} {r}" for i, r in enumerate(REASONS)))),
        "configuration": (dims, checks["configuration"][..., mid].astype(np.int8),
                          attrs("1", "arm/elbow/wrist configuration code at the cut's middle "
                                "(4 back + 2 down + wrist-)")),
        "wrist_angle_deg": var(dims, checks["wrist_deg"].min(-1), "deg",
                               "smallest wrist angle along the cut (0: singular)"),
        "limit_clearance_deg": var(dims, checks["clearance_deg"].min(-1), "deg",
                                   "smallest distance of a joint to its limit along the cut"),
        "sigma_min": var(dims, checks["sigma_min"].min(-1), "1",
                         "smallest singular value of the reach-scaled Jacobian along the cut"),
    }
