"""Serial-robot kinematics shared by every chapter (one implementation for every robot).

* Rodrigues rotation about an axis (thesis eq. 1.3) and the vector geometric model (eq. 1.4);
* Denavit–Hartenberg (``dh``: T_i = Rz(θ_i+offset) Tz(d) Tx(a) Rx(α)) and Craig's modified
  D-H (``mdh``: T_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i+offset) Tz(d_i)) forward kinematics;
* the geometric Jacobian by the vector-product method [Yi 2025], and
* numerical inverse kinematics (damped least squares) for any posture, and along a measured
  path with an error that names the data file when the path is out of reach.

Lengths are in millimetres and angles in radians inside this module; :func:`robot_from_mapping`
converts the documented robot file (``docs/data-contract.md``, kind ``robot``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from robomill.errors import RawDataError


def skew(v: np.ndarray) -> np.ndarray:
    """Cross-product matrix E of a 3-vector (E @ x == v × x); broadcasts over leading axes."""
    v = np.asarray(v, dtype=float)
    z = np.zeros(v.shape[:-1])
    return np.stack([
        np.stack([z, -v[..., 2], v[..., 1]], -1),
        np.stack([v[..., 2], z, -v[..., 0]], -1),
        np.stack([-v[..., 1], v[..., 0], z], -1),
    ], -2)


def rodrigues(axis: np.ndarray, theta: np.ndarray | float) -> np.ndarray:
    """Rotation matrix about unit ``axis`` by ``theta`` (thesis eq. 1.3).

    .. math:: R = e e^T + \\cos\\theta (I - e e^T) + \\sin\\theta E

    ``theta`` may be an array; the result then has shape ``theta.shape + (3, 3)``.
    """
    e = np.asarray(axis, dtype=float)
    e = e / np.linalg.norm(e)
    th = np.asarray(theta, dtype=float)[..., None, None]
    eet = np.outer(e, e)
    return eet + np.cos(th) * (np.eye(3) - eet) + np.sin(th) * skew(e)


def _rot_z(t):
    # filled in place (not nested np.stack): the same entries, a fraction of the overhead
    # in the per-pose inverse-kinematics loop
    t = np.asarray(t, dtype=float)
    c, s = np.cos(t), np.sin(t)
    R = np.zeros(t.shape + (3, 3))
    R[..., 0, 0], R[..., 0, 1], R[..., 1, 0], R[..., 1, 1] = c, -s, s, c
    R[..., 2, 2] = 1.0
    return R


def _rot_x(t):
    t = np.asarray(t, dtype=float)
    c, s = np.cos(t), np.sin(t)
    R = np.zeros(t.shape + (3, 3))
    R[..., 0, 0] = 1.0
    R[..., 1, 1], R[..., 1, 2], R[..., 2, 1], R[..., 2, 2] = c, -s, s, c
    return R


def _homog(R, p):
    T = np.zeros(R.shape[:-2] + (4, 4))
    T[..., :3, :3] = R
    T[..., :3, 3] = p
    T[..., 3, 3] = 1.0
    return T


@dataclass
class SerialRobot:
    """A serial robot in D-H or modified D-H form.

    Attributes
    ----------
    name
        Identifier (e.g. ``irb1600``).
    convention
        ``"dh"`` or ``"mdh"``.
    a_mm, alpha_rad, d_mm, theta_offset_rad
        One entry per joint, base to flange.
    tool_mm
        TCP in the flange frame.
    tool_R
        Orientation of the tool frame (z: the spindle axis) in the flange frame; identity for a
        spindle on the flange axis (the tool frame of ``cell.yaml``'s ``robot.tool``,
        :mod:`robomill.io.tool_frame`).
    base
        4×4 transform of the robot base in the world frame (identity by default).
    """

    name: str
    convention: str
    a_mm: np.ndarray
    alpha_rad: np.ndarray
    d_mm: np.ndarray
    theta_offset_rad: np.ndarray
    tool_mm: np.ndarray = field(default_factory=lambda: np.zeros(3))
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool_R: np.ndarray = field(default_factory=lambda: np.eye(3))

    def __post_init__(self):
        if self.convention not in ("dh", "mdh"):
            raise ValueError(f"convention must be 'dh' or 'mdh', not {self.convention!r}")
        for name in ("a_mm", "alpha_rad", "d_mm", "theta_offset_rad", "tool_mm", "base",
                     "tool_R"):
            setattr(self, name, np.asarray(getattr(self, name), dtype=float))
        n = self.n_joints
        for name in ("alpha_rad", "d_mm", "theta_offset_rad"):
            if getattr(self, name).shape != (n,):
                raise ValueError(f"{name} must have {n} entries")

    @property
    def n_joints(self) -> int:
        return int(self.a_mm.shape[0])

    def link_transforms(self, q: np.ndarray) -> np.ndarray:
        """Per-joint transforms ``(..., n, 4, 4)`` for joint angles ``q`` ``(..., n)`` [rad]."""
        q = np.asarray(q, dtype=float)
        th = q + self.theta_offset_rad
        if self.convention == "dh":
            R = _rot_z(th) @ _rot_x(np.broadcast_to(self.alpha_rad, th.shape))
            ct, st = np.cos(th), np.sin(th)
            p = np.stack([self.a_mm * ct, self.a_mm * st,
                          np.broadcast_to(self.d_mm, th.shape)], -1)
        else:
            Rx = _rot_x(np.broadcast_to(self.alpha_rad, th.shape))
            R = Rx @ _rot_z(th)
            dz = np.stack([np.zeros_like(th), np.zeros_like(th),
                           np.broadcast_to(self.d_mm, th.shape)], -1)
            p = np.stack([np.broadcast_to(self.a_mm, th.shape), np.zeros_like(th),
                          np.zeros_like(th)], -1) + np.einsum("...ij,...j->...i", Rx, dz)
        return _homog(R, p)

    def frames(self, q: np.ndarray) -> np.ndarray:
        """World transforms of frames 0..n (``(..., n+1, 4, 4)``), frame 0 = base."""
        A = self.link_transforms(q)
        n = self.n_joints
        out = np.empty(A.shape[:-3] + (n + 1, 4, 4))
        out[..., 0, :, :] = self.base
        for i in range(n):
            out[..., i + 1, :, :] = out[..., i, :, :] @ A[..., i, :, :]
        return out

    def fk(self, q: np.ndarray) -> np.ndarray:
        """TCP pose ``(..., 4, 4)`` in the world frame [mm]."""
        return self._tcp(self.frames(q))

    def _tcp(self, F: np.ndarray) -> np.ndarray:
        """TCP pose from the frames of :meth:`frames` (flange pose times the tool frame)."""
        return F[..., -1, :, :] @ _homog(self.tool_R, self.tool_mm)

    def joint_axes(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint axis directions and points ``(..., n, 3)`` in the world frame.

        For ``dh`` joint i rotates about z of frame i−1; for ``mdh`` about z of frame i.
        """
        return self._axes(self.frames(q))

    def _axes(self, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        sel = F[..., :-1, :, :] if self.convention == "dh" else F[..., 1:, :, :]
        return sel[..., :3, 2], sel[..., :3, 3]

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """Geometric Jacobian ``(..., 6, n)`` at the TCP by the vector-product method.

        Rows 0–2: linear velocity [mm/rad]; rows 3–5: angular velocity [1]. Column i is
        ``[z_i × (p − o_i); z_i]`` (for revolute joints [Yi 2025]).
        """
        F = self.frames(q)
        return self._jacobian(F, self._tcp(F))

    def _jacobian(self, F: np.ndarray, T: np.ndarray) -> np.ndarray:
        """Jacobian from the frames F and the TCP pose T (one forward pass serves both)."""
        z, o = self._axes(F)
        r = T[..., None, :3, 3] - o
        Jv = np.empty(np.broadcast_shapes(z.shape, r.shape))  # z × r, as np.cross computes it
        Jv[..., 0] = z[..., 1] * r[..., 2] - z[..., 2] * r[..., 1]
        Jv[..., 1] = z[..., 2] * r[..., 0] - z[..., 0] * r[..., 2]
        Jv[..., 2] = z[..., 0] * r[..., 1] - z[..., 1] * r[..., 0]
        return np.concatenate([np.swapaxes(Jv, -1, -2), np.swapaxes(z, -1, -2)], axis=-2)

    def ik(self, target: np.ndarray, q0: np.ndarray, *, tol_mm: float = 1e-9,
           tol_rad: float = 1e-11, max_iter: int = 200, damping: float = 1e-6) -> np.ndarray:
        """Joint angles reaching the 4×4 ``target`` TCP pose, starting from ``q0``.

        Damped least-squares Newton iterations on the 6-D pose error; converges to the
        posture (branch) nearest ``q0``. Raises ``RuntimeError`` if the pose is not reached.
        """
        q = np.array(q0, dtype=float)
        target = np.asarray(target, dtype=float)
        for _ in range(max_iter):
            F = self.frames(q)
            T = self._tcp(F)
            dp = target[:3, 3] - T[:3, 3]
            Rerr = target[:3, :3] @ T[:3, :3].T
            dw = 0.5 * np.array([Rerr[2, 1] - Rerr[1, 2], Rerr[0, 2] - Rerr[2, 0],
                                 Rerr[1, 0] - Rerr[0, 1]])
            if np.linalg.norm(dp) < tol_mm and np.linalg.norm(dw) < tol_rad:
                return q
            J = self._jacobian(F, T)
            err = np.concatenate([dp, dw])
            JJt = J @ J.T + damping * np.eye(6)
            q = q + J.T @ np.linalg.solve(JJt, err)
        raise RuntimeError(f"IK for {self.name} did not converge: position error "
                           f"{np.linalg.norm(dp):.3g} mm, orientation error "
                           f"{np.linalg.norm(dw):.3g} rad")

    def ik_path(self, targets: np.ndarray, q0: np.ndarray, **kw: Any) -> np.ndarray:
        """IK along a sequence of poses ``(m, 4, 4)``, each solution seeding the next."""
        out = np.empty((len(targets), self.n_joints))
        q = np.asarray(q0, dtype=float)
        for k, T in enumerate(targets):
            q = self.ik(T, q, **kw)
            out[k] = q
        return out


def robot_from_mapping(spec: Mapping[str, Any]) -> SerialRobot:
    """Build a :class:`SerialRobot` from the robot-file mapping (data contract, kind ``robot``).

    ``{name, convention: dh|mdh, length_unit: mm|m, angle_unit: deg|rad, joints: [{a, alpha, d,
    theta_offset}], tool: [x, y, z] | {xyz_mm, rpy_deg}}`` (the tool frame,
    :func:`robomill.io.tool_frame.tool_frame`).
    """
    from robomill.io.tool_frame import tool_frame

    length = {"mm": 1.0, "m": 1000.0}[spec.get("length_unit", "mm")]
    angle = {"deg": np.pi / 180.0, "rad": 1.0}[spec.get("angle_unit", "deg")]
    joints = spec["joints"]
    tool_mm, tool_R = tool_frame(spec.get("tool"), length_mm=length)
    return SerialRobot(
        name=str(spec.get("name", "robot")),
        convention=str(spec.get("convention", "dh")),
        a_mm=np.array([j["a"] for j in joints], float) * length,
        alpha_rad=np.array([j["alpha"] for j in joints], float) * angle,
        d_mm=np.array([j["d"] for j in joints], float) * length,
        theta_offset_rad=np.array([j.get("theta_offset", 0.0) for j in joints], float) * angle,
        tool_mm=tool_mm, tool_R=tool_R,
    )


def geometric_model(theta: np.ndarray, a0: np.ndarray, a_vectors: Sequence[np.ndarray],
                    axes: Sequence[np.ndarray]) -> np.ndarray:
    """TCP position by the vector model of thesis eq. 1.4.

    .. math:: p = a_0 + R_1 a'_1 + R_1 R_2 a'_2 + \\dots + R_1 \\cdots R_n a'_n

    with :math:`R_i` the Rodrigues rotation (eq. 1.3) about the zero-configuration axis
    :math:`e_i` by :math:`\\theta_i`. ``a_vectors[i-1]`` is :math:`a'_i` (O_i → O_{i+1}, the
    last one O_n → P). ``theta`` may have leading batch axes ``(..., n)``.
    """
    theta = np.asarray(theta, dtype=float)
    p = np.broadcast_to(np.asarray(a0, float), theta.shape[:-1] + (3,)).copy()
    R = np.broadcast_to(np.eye(3), theta.shape[:-1] + (3, 3)).copy()
    for i, (e, a) in enumerate(zip(axes, a_vectors, strict=True)):
        R = R @ rodrigues(e, theta[..., i])
        p = p + np.einsum("...ij,j->...i", R, np.asarray(a, float))
    return p


def vector_model_from_robot(robot: SerialRobot) -> tuple[np.ndarray, list, list]:
    """(a0, a'_i, e_i) of eq. 1.4 for a D-H robot, from its zero configuration.

    O_i is the point of axis i in the zero configuration; a0 = O_1 − origin,
    a'_i = O_{i+1} − O_i, a'_n = P − O_n.
    """
    q0 = np.zeros(robot.n_joints)
    z, o = robot.joint_axes(q0)
    p = robot.fk(q0)[:3, 3]
    a0 = o[0]
    a_vecs = [o[i + 1] - o[i] for i in range(robot.n_joints - 1)] + [p - o[-1]]
    return a0, a_vecs, [z[i] for i in range(robot.n_joints)]


def ik_batch(robot: SerialRobot, targets: np.ndarray, q0: np.ndarray, *, tol_mm: float = 1e-6,
             tol_rad: float = 1e-9, max_iter: int = 100, damping: float = 1e-6,
             max_step_rad: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """Damped least-squares IK for many TCP poses at once (vectorized :meth:`SerialRobot.ik`).

    Parameters
    ----------
    robot
        The robot.
    targets
        TCP poses ``(m, 4, 4)`` [mm].
    q0
        Start postures ``(m, n)`` or one ``(n,)`` for all [rad].
    max_step_rad
        Largest joint step per iteration (keeps far targets from diverging).

    Returns
    -------
    q, converged
        Joint angles ``(m, n)`` [rad] and a boolean mask ``(m,)`` of the poses reached
        within ``tol_mm`` / ``tol_rad`` (the others are left at their last iterate).
    """
    targets = np.asarray(targets, dtype=float)
    m = targets.shape[0]
    q = np.broadcast_to(np.asarray(q0, float), (m, robot.n_joints)).copy()
    done = np.zeros(m, bool)
    eye = np.eye(6)
    for _ in range(max_iter):
        T = robot.fk(q)
        dp = targets[:, :3, 3] - T[:, :3, 3]
        Rerr = targets[:, :3, :3] @ np.swapaxes(T[:, :3, :3], -1, -2)
        dw = 0.5 * np.stack([Rerr[:, 2, 1] - Rerr[:, 1, 2], Rerr[:, 0, 2] - Rerr[:, 2, 0],
                             Rerr[:, 1, 0] - Rerr[:, 0, 1]], -1)
        done = (np.linalg.norm(dp, axis=-1) < tol_mm) & (np.linalg.norm(dw, axis=-1) < tol_rad)
        if done.all():
            break
        act = ~done
        J = robot.jacobian(q[act])
        err = np.concatenate([dp[act], dw[act]], -1)
        JJt = J @ np.swapaxes(J, -1, -2) + damping * eye
        step = np.einsum("mji,mj->mi", J, np.linalg.solve(JJt, err[..., None])[..., 0])
        norm = np.linalg.norm(step, axis=-1, keepdims=True)
        step *= np.minimum(1.0, max_step_rad / np.maximum(norm, 1e-300))
        q[act] += step
    return q, done


def reach_mm(robot: SerialRobot) -> float:
    """Upper bound of the TCP distance from the base origin [mm] (sum of link lengths)."""
    total = sum(abs(float(a)) + abs(float(d)) for a, d in zip(robot.a_mm, robot.d_mm, strict=True))
    return total + float(np.linalg.norm(robot.tool_mm))


def reachable_joint_path_rad(robot: SerialRobot, targets: np.ndarray, q0_rad: np.ndarray, *,
                             data_file: str | Path, instrument: str,
                             cell_file: str | Path) -> np.ndarray:
    """Inverse kinematics along measured TCP poses ``(m, 4, 4)`` [mm] in the base frame, each
    solution seeding the next (:meth:`SerialRobot.ik_path`, from ``q0_rad``).

    Parameters
    ----------
    data_file, instrument
        The file the poses were measured in and its instrument (``"tracker"``): named by the
        error when a pose is out of reach.
    cell_file
        The cell file that describes ``robot`` (where the instrument's frame is registered).

    Raises
    ------
    RawDataError
        Naming ``data_file`` when a pose is out of the robot's reach (:func:`reach_mm`): the
        points are then not in this robot's base frame, and the cell file's
        ``base_from_instrument`` must register them.
    """
    try:
        return robot.ik_path(targets, q0_rad)
    except RuntimeError:
        p = np.asarray(targets, float)[:, :3, 3]
        far = float(np.max(np.linalg.norm(p, axis=1)))
        raise RawDataError(
            data_file, f"points are not reachable by robot '{robot.name}' of "
            f"{cell_file} (up to {far:.0f} mm from its base, reach about {reach_mm(robot):.0f} mm)",
            where=f"{instrument} points in the robot base frame",
            expected=f"points in the base frame of this robot: register the {instrument} "
                     f"frame with base_from_instrument.{instrument} "
                     "{rotation, translation_mm} in cell.yaml") from None
