"""Geometry of the single-joint (circle point) method (thesis §1.3): circle fits and
the vector model.

A target on link i, joint i rotated alone, traces a circle; plane by SVD, circle by least
squares → axis e_i and centre O_i (:func:`fit_circle`, Stone 1986). The vector model
(:class:`VectorModel`): a'_i = O_{i+1} − O_i, a_0 = O_1, a'_n = P − O_n and eq. 1.4 with the
Rodrigues rotations of eq. 1.3 (:func:`robomill.kinematics.geometric_model`).

Everything is expressed in one fixed measurement frame (the C-Track frame, registered to the
robot base; gravity along −z). Lengths in mm, angles in rad.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robomill.kinematics import geometric_model, rodrigues


@dataclass(frozen=True)
class CircleFit:
    """A circle in space: centre O [mm], unit normal e (joint axis), radius [mm], fit RMS."""

    centre: np.ndarray
    axis: np.ndarray
    radius: float
    rms_mm: float
    n_points: int


def fit_circle(points: np.ndarray, *, refine: bool = True) -> CircleFit:
    """Fit a circle to 3-D points ordered by increasing joint angle (single-joint method).

    The plane is the SVD plane of the centred points (normal = right singular vector of the
    smallest singular value); the circle in that plane is the algebraic least-squares (Kåsa)
    circle, refined by geometric least squares (orthogonal distances) when ``refine``. The
    normal is oriented so that the points turn positively about it (right-hand rule), i.e.
    it is the joint axis e_i for angles increasing along ``points``.

    Parameters
    ----------
    points
        ``(m, 3)`` target positions, m ≥ 3, in rotation order [mm].

    Returns
    -------
    CircleFit

    Examples
    --------
    >>> t = np.linspace(0, 2, 20)
    >>> P = np.c_[100 * np.cos(t), 100 * np.sin(t), np.full_like(t, 5.0)]
    >>> f = fit_circle(P)
    >>> np.round(f.axis, 9).tolist(), round(f.radius, 9)
    ([0.0, 0.0, 1.0], 100.0)
    """
    P = np.asarray(points, float)
    if P.ndim != 2 or P.shape[1] != 3 or P.shape[0] < 3:
        raise ValueError(f"a circle needs at least 3 points of 3 coordinates, got {P.shape}")
    c0 = P.mean(axis=0)
    _, s, Vt = np.linalg.svd(P - c0, full_matrices=False)
    if s[1] <= 1e-12 * max(s[0], 1e-300):
        raise ValueError("points are collinear: no circle")
    u, v, n = Vt[0], Vt[1], Vt[2]
    xy = np.c_[(P - c0) @ u, (P - c0) @ v]
    # Kåsa: x² + y² = 2 a x + 2 b y + c
    A = np.c_[2 * xy, np.ones(len(xy))]
    rhs = (xy**2).sum(1)
    (a, b, c), *_ = np.linalg.lstsq(A, rhs, rcond=None)
    r = np.sqrt(c + a * a + b * b)
    centre2, height = np.array([a, b]), 0.0
    if refine and len(P) > 3:
        def resid(x):
            cc = c0 + x[0] * u + x[1] * v + x[2] * n
            d = P - cc
            h = d @ n
            rad = np.sqrt(np.maximum((d**2).sum(1) - h**2, 0.0))
            return np.r_[rad - x[3], h]

        # the plane offset is fitted too (the SVD plane minimizes the same residuals)
        import scipy.optimize  # here, not at the top: keeps Snakemake's start-up short
        sol = scipy.optimize.least_squares(resid, np.r_[a, b, 0.0, r], method="lm",
                                           xtol=1e-15, ftol=1e-15, gtol=1e-15)
        a, b, height, r = sol.x
        centre2 = np.array([a, b])
    centre = c0 + centre2[0] * u + centre2[1] * v + height * n
    d = P - centre
    turn = np.cross(d[:-1], d[1:]).sum(0)
    if turn @ n < 0:
        n = -n
    h = d @ n
    rad = np.sqrt(np.maximum((d**2).sum(1) - h**2, 0.0))
    rms = float(np.sqrt(np.mean((rad - r) ** 2 + h**2)))
    return CircleFit(centre=centre, axis=n / np.linalg.norm(n), radius=float(r), rms_mm=rms,
                     n_points=len(P))


@dataclass
class VectorModel:
    """The geometric model of thesis eq. 1.4 in the measurement frame.

    Attributes
    ----------
    axes
        ``(n, 3)`` unit joint axes e_i at the zero configuration.
    centres
        ``(n, 3)`` centres O_i (any point of axis i) at the zero configuration [mm].
    tcp_mm
        Tool tip P at the zero configuration [mm].
    """

    axes: np.ndarray
    centres: np.ndarray
    tcp_mm: np.ndarray

    def __post_init__(self):
        self.axes = np.asarray(self.axes, float)
        self.axes = self.axes / np.linalg.norm(self.axes, axis=1, keepdims=True)
        self.centres = np.asarray(self.centres, float)
        self.tcp_mm = np.asarray(self.tcp_mm, float)

    @property
    def n_joints(self) -> int:
        return len(self.axes)

    def a_vectors(self) -> tuple[np.ndarray, np.ndarray]:
        """(a_0, a'_1..a'_n): a_0 = O_1 (from the frame origin), a'_i = O_{i+1} − O_i,
        a'_n = P − O_n (thesis §1.3.2)."""
        a = np.vstack([np.diff(self.centres, axis=0), self.tcp_mm - self.centres[-1]])
        return self.centres[0].copy(), a

    def tcp(self, theta: np.ndarray) -> np.ndarray:
        """Tool-tip position ``(..., 3)`` by eq. 1.4 for joint angles ``(..., n)`` [rad]."""
        a0, a = self.a_vectors()
        return geometric_model(theta, a0, list(a), list(self.axes))

    def link_poses(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Rigid motion of every link: ``R (..., n, 3, 3)``, ``t (..., n, 3)`` such that a point
        x0 of link i (zero configuration) is at ``R[..., i-1] x0 + t[..., i-1]``.

        Each joint turns its outboard links about the zero-configuration line (O_i, e_i); the
        composition is eq. 1.4 written for any point (product of exponentials).
        """
        theta = np.asarray(theta, float)
        lead = theta.shape[:-1]
        R = np.broadcast_to(np.eye(3), lead + (3, 3)).copy()
        t = np.zeros(lead + (3,))
        Rs, ts = [], []
        for i in range(self.n_joints):
            Ri = rodrigues(self.axes[i], theta[..., i])
            Oi = self.centres[i]
            t = t + np.einsum("...ij,...j->...i", R, Oi - np.einsum("...ij,j->...i", Ri, Oi))
            R = R @ Ri
            Rs.append(R)
            ts.append(t)
        return np.stack(Rs, -3), np.stack(ts, -2)

    def joint_lines(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Current axes and centres ``(..., n, 3)`` at ``theta`` (axis i moves with links <i)."""
        R, t = self.link_poses(theta)
        lead = np.asarray(theta).shape[:-1]
        e = np.empty(lead + (self.n_joints, 3))
        o = np.empty_like(e)
        e[..., 0, :], o[..., 0, :] = self.axes[0], self.centres[0]
        e[..., 1:, :] = np.einsum("...kij,kj->...ki", R[..., :-1, :, :], self.axes[1:])
        o[..., 1:, :] = (np.einsum("...kij,kj->...ki", R[..., :-1, :, :], self.centres[1:])
                         + t[..., :-1, :])
        return e, o

    def point(self, theta: np.ndarray, x0: np.ndarray, link: int) -> np.ndarray:
        """Position ``(..., 3)`` of point ``x0`` (zero configuration) fixed to ``link`` (1..n;
        0 = the base)."""
        if link == 0:
            return np.broadcast_to(np.asarray(x0, float), np.asarray(theta).shape[:-1] + (3,))
        R, t = self.link_poses(theta)
        return np.einsum("...ij,j->...i", R[..., link - 1, :, :], np.asarray(x0, float)) + \
            t[..., link - 1, :]

    def position_jacobian(self, theta: np.ndarray, p: np.ndarray | None = None) -> np.ndarray:
        """``(..., 3, n)``: column j is e_j × (p − O_j) at ``theta`` (p defaults to the TCP)."""
        e, o = self.joint_lines(theta)
        p = self.tcp(theta) if p is None else np.asarray(p, float)
        return np.swapaxes(np.cross(e, p[..., None, :] - o), -1, -2)


def vector_model_from_serial(robot) -> VectorModel:
    """The :class:`VectorModel` of a D-H/MD-H :class:`~robomill.kinematics.SerialRobot` at its
    zero configuration (centres at the frame origins on each axis)."""
    z, o = robot.joint_axes(np.zeros(robot.n_joints))
    return VectorModel(z, o, robot.fk(np.zeros(robot.n_joints))[:3, 3])
