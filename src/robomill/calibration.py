"""Robot calibration by the single-joint (circle point) method (thesis ch. 1, SPEC §1).

Everything is expressed in one fixed measurement frame (the C-Track frame, registered to the
robot base; gravity along −z). The chain of the chapter:

1. **Circle fits** (:func:`fit_circle`): a target on link i, joint i rotated alone, traces a
   circle; plane by SVD, circle by least squares → axis e_i and centre O_i (Stone 1986).
2. **Vector model** (:class:`VectorModel`): a'_i = O_{i+1} − O_i, a_0 = O_1, a'_n = P − O_n and
   eq. 1.4 with the Rodrigues rotations of eq. 1.3 (:func:`robomill.kinematics.geometric_model`).
3. **Joint positioning errors** (:func:`joint_angle_eq15`): eq. 1.5 on positions that are the
   mean of both approach directions (cancels backlash); a regression model of the error versus
   joint angle (:class:`JointErrorFit`: Fourier terms at the gear orders + a low-order
   polynomial, chosen on held-out steps).
4. **Joint compliance** (:func:`fit_compliance`) from load-disc tests: Δp = Σ_j c_j Δτ_j
   e_j × (p − O_j); **base deflection** eq. 1.6 (:func:`base_deflection_eq16`), linear in the
   joint-2 torque and lumped into joint 2.
5. **Accuracy** (:func:`accuracy_table`) of the nominal, geometric and full models on points
   not used for identification.

Lengths in mm, angles in rad, torques in N·m, compliances in rad/(N·m).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import xarray as xr

from robomill.kinematics import geometric_model, rodrigues

G_MM_S2 = np.array([0.0, 0.0, -9.81])
"""Gravity acceleration [m/s²] in the measurement frame (z up)."""


# ---- 1. circle fit ----------------------------------------------------------------------


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


# ---- 2. the vector model (eq. 1.3, 1.4) -----------------------------------------------------


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


# ---- gravity torques ---------------------------------------------------------------------


@dataclass
class MassModel:
    """Point masses fixed to links (zero-configuration positions in the measurement frame).

    ``link`` is 1..n (the link a mass rides on); torques about joint j come from every mass on
    links ≥ j.
    """

    link: np.ndarray
    mass_kg: np.ndarray
    com_mm: np.ndarray

    def __post_init__(self):
        self.link = np.asarray(self.link, int)
        self.mass_kg = np.asarray(self.mass_kg, float)
        self.com_mm = np.asarray(self.com_mm, float).reshape(-1, 3)

    def plus(self, link: int, mass_kg: float, com_mm: np.ndarray) -> MassModel:
        """A copy with one more point mass (payload, load discs)."""
        return MassModel(np.r_[self.link, link], np.r_[self.mass_kg, mass_kg],
                         np.vstack([self.com_mm, np.asarray(com_mm, float)]))


def gravity_torques_Nm(model: VectorModel, masses: MassModel, theta: np.ndarray) -> np.ndarray:
    """Joint torques ``(..., n)`` [N·m] of gravity on the point masses at ``theta``.

    .. math:: τ_j = e_j · \\sum_{k: link_k ≥ j} (c_k − O_j) × m_k g

    (the torque gravity applies about axis j; a compliant joint deflects by c_j τ_j).
    """
    theta = np.asarray(theta, float)
    R, t = model.link_poses(theta)
    e, o = model.joint_lines(theta)
    tau = np.zeros(theta.shape)
    for link, m, c0 in zip(masses.link, masses.mass_kg, masses.com_mm, strict=True):
        c = np.einsum("...ij,j->...i", R[..., link - 1, :, :], c0) + t[..., link - 1, :]
        F = m * G_MM_S2
        for j in range(link):
            tau[..., j] += np.einsum("...i,...i->...", e[..., j, :],
                                     np.cross(c - o[..., j, :], F)) * 1e-3
    return tau


def mass_model_from_mapping(spec: Mapping, n_links: int | None = None) -> MassModel:
    """``{links: [{link, mass_kg, com_mm}], tool: {mass_kg, com_mm}}`` → :class:`MassModel`.

    The tool (spindle and tool, optional) rides on the last link: ``n_links`` when given,
    else the highest link listed.
    """
    links = list(spec["links"])
    n = n_links or max(int(x["link"]) for x in links)
    mm = MassModel([int(x["link"]) for x in links], [float(x["mass_kg"]) for x in links],
                   np.array([x["com_mm"] for x in links], float))
    tool = spec.get("tool")
    if tool:
        mm = mm.plus(n, float(tool["mass_kg"]), np.asarray(tool["com_mm"], float))
    return mm


def mass_model_from_cell(cell) -> MassModel | None:
    """The gravity model of a :class:`robomill.io.cell.Cell`: its ``mass_model`` (links, then
    the tool on the last link) as a :class:`MassModel`, or None when the cell file states no
    mass model (the identification then runs without the gravity term, :func:`identify`)."""
    spec = cell.mass_model
    if spec is None:
        return None
    points = spec.point_masses()
    return MassModel([m.link for m in points], [m.mass_kg for m in points],
                     np.array([m.com_mm for m in points], float))


def no_masses() -> MassModel:
    """An empty :class:`MassModel` (gravity torques identically zero)."""
    return MassModel(np.zeros(0, int), np.zeros(0), np.zeros((0, 3)))


# ---- 3. joint angles (eq. 1.5) and the joint-error regression ---------------------------------


def joint_angle_eq15(centre: np.ndarray, axis: np.ndarray, p0: np.ndarray,
                     pm: np.ndarray) -> np.ndarray:
    """Actual rotation of joint i between target positions P_0 and P_m (thesis eq. 1.5).

    .. math:: θ_m = \\arccos \\frac{O_iP_0 · O_iP_m}{|O_iP_0|^2}

    signed by the rotation direction about e_i. Evaluated as
    ``atan2(e·(v0 × vm), v0·vm)`` on the vectors projected onto the circle plane: the same
    angle for points on the circle, but well conditioned near 0 and robust to noise along the
    axis.
    """
    e = np.asarray(axis, float)
    v0 = np.asarray(p0, float) - centre
    vm = np.asarray(pm, float) - centre
    v0 = v0 - (v0 @ e)[..., None] * e
    vm = vm - (vm @ e)[..., None] * e
    return np.arctan2(np.cross(v0, vm) @ e, np.sum(v0 * vm, axis=-1))


def _design(q: np.ndarray, orders: Sequence[float], degree: int) -> np.ndarray:
    q = np.asarray(q, float)
    cols = [q**k for k in range(degree + 1)] if degree >= 0 else []
    for k in orders:
        cols += [np.sin(k * q), np.cos(k * q)]
    return np.stack(cols, -1) if cols else np.zeros(q.shape + (0,))


@dataclass
class JointErrorFit:
    """Regression of one joint's positioning error on its angle.

    .. math:: Δθ(q) = \\sum_{k=0}^{d} p_k q^k + \\sum_{r} (s_r \\sin rq + c_r \\cos rq)

    The Fourier orders r are the gear orders (revolutions of each transmission element per
    joint revolution, and those times the tooth count): eccentricity and tooth-mesh errors are
    periodic at exactly these orders (Slamani & Bonev 2013), so a handful of terms represents
    them without the oscillation a high-degree polynomial would need; the polynomial (degree
    chosen on held-out steps) takes the slow, non-periodic remainder (the constant −b/2 of the
    reference approach, residual elasticity). Like the thesis' model it is numerical: the
    terms are not interpreted one by one.
    """

    joint: int
    orders: np.ndarray
    degree: int
    poly: np.ndarray
    sin: np.ndarray
    cos: np.ndarray
    train_rms_rad: float = np.nan
    validation_rms_rad: float = np.nan
    validation: dict = field(default_factory=dict)

    def __call__(self, q: np.ndarray) -> np.ndarray:
        q = np.asarray(q, float)
        out = sum(p * q**k for k, p in enumerate(self.poly)) + np.zeros_like(q)
        for r, s, c in zip(self.orders, self.sin, self.cos, strict=True):
            out = out + s * np.sin(r * q) + c * np.cos(r * q)
        return out


def _lstsq_fit(q, y, orders, degree):
    A = _design(q, orders, degree)
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    return coef


def _split_coef(coef, orders, degree):
    nd = degree + 1
    return coef[:nd], coef[nd::2][:len(orders)], coef[nd + 1::2][:len(orders)]


def fit_joint_error(joint: int, q: np.ndarray, err: np.ndarray, orders: Sequence[float], *,
                    max_degree: int = 3, holdout_every: int = 4) -> JointErrorFit:
    """Fit :class:`JointErrorFit` to measured errors ``err`` at angles ``q`` [rad].

    Every ``holdout_every``-th step (offset by half) is held out; the polynomial degree
    (0..``max_degree``) with the smallest held-out RMS is chosen (ties to the lower degree),
    then the model is refitted on all steps. ``validation`` records the held-out RMS of the
    candidate forms: polynomial only (degree 3), Fourier only (+ constant), Fourier + poly.
    """
    q, err = np.asarray(q, float), np.asarray(err, float)
    orders = np.asarray(orders, float)
    idx = np.arange(len(q))
    test = (idx % holdout_every) == (holdout_every // 2)
    train = ~test

    def val_rms(ords, deg):
        coef = _lstsq_fit(q[train], err[train], ords, deg)
        return float(np.sqrt(np.mean((_design(q[test], ords, deg) @ coef - err[test]) ** 2)))

    scores = [val_rms(orders, d) for d in range(max_degree + 1)]
    best = min(scores)
    tol = 1e-3 * best + 1e-15
    degree = next(d for d, s in enumerate(scores) if s <= best + tol)
    validation = {"polynomial": val_rms([], max_degree), "fourier": val_rms(orders, 0),
                  "fourier+polynomial": scores[degree]}
    coef = _lstsq_fit(q, err, orders, degree)
    poly, s, c = _split_coef(coef, orders, degree)
    fit = JointErrorFit(joint, orders, degree, poly, s, c, validation=validation,
                        validation_rms_rad=scores[degree])
    fit.train_rms_rad = float(np.sqrt(np.mean((fit(q) - err) ** 2)))
    return fit


# ---- 4. compliance and base deflection --------------------------------------------------------


def compliance_displacement(model: VectorModel, theta: np.ndarray, dtau_Nm: np.ndarray,
                            compliance: np.ndarray, p: np.ndarray,
                            upto: int | None = None) -> np.ndarray:
    """Displacement ``(..., 3)`` of point(s) p from joint deflections c_j Δτ_j (first order):
    Σ_j c_j Δτ_j e_j × (p − O_j), over joints j ≤ ``upto`` (default all)."""
    e, o = model.joint_lines(theta)
    n = upto or model.n_joints
    d = np.asarray(compliance[:n]) * dtau_Nm[..., :n]
    arm = np.cross(e[..., :n, :], p[..., None, :] - o[..., :n, :])
    return np.einsum("...j,...ji->...i", d, arm)


def fit_compliance(model: VectorModel, masses: MassModel, theta: np.ndarray,
                   load_kg: np.ndarray, load_point_mm: np.ndarray, dp_mm: np.ndarray,
                   *, link: int | None = None, min_relative: float = 1e-3
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Joint compliances from load-disc tests (linear least squares).

    Each test k: pose ``theta[k]``, discs of mass ``load_kg[k]`` hung at the fixture point
    (zero-configuration position ``load_point_mm`` on the last link), displacement
    ``dp_mm[k]`` of a target at that point relative to the unloaded pose. Model:
    Δp = Σ_j c_j Δτ_j e_j × (p − O_j), Δτ from the discs' weight alone.

    Returns ``(c, identifiable)``: joints whose regressor is negligible (e.g. a vertical
    joint 1, which gravity never loads) get c = 0 and ``identifiable = False``.
    """
    link = link or model.n_joints
    disc = MassModel([link], [1.0], [load_point_mm])
    tau1 = gravity_torques_Nm(model, disc, theta)  # per kg of disc
    dtau = tau1 * np.asarray(load_kg, float)[:, None]
    e, o = model.joint_lines(theta)
    p = model.point(theta, load_point_mm, link)
    cols = dtau[:, None, :] * np.swapaxes(np.cross(e, p[:, None, :] - o), -1, -2)  # (k,3,n)
    A = cols.reshape(-1, model.n_joints)
    norms = np.linalg.norm(A, axis=0)
    ok = norms > min_relative * norms.max()
    c = np.zeros(model.n_joints)
    c[ok], *_ = np.linalg.lstsq(A[:, ok], np.asarray(dp_mm, float).reshape(-1), rcond=None)
    return c, ok


def base_deflection_eq16(p1_ref: np.ndarray, p2_ref: np.ndarray, p1: np.ndarray,
                         p2: np.ndarray, axis: np.ndarray | None = None) -> np.ndarray:
    """Rotational deflection of the robot base from two target groups (thesis eq. 1.6).

    .. math:: δθ_{base} = \\arccos \\frac{P_2P_1 · P_2'P_1'}{|P_2P_1|^2}

    evaluated as ``atan2(|v × v'|, v·v')`` (the same angle, well conditioned for the
    µrad-scale deflections); signed positive about ``axis`` when given.
    """
    v = np.asarray(p1_ref, float) - p2_ref
    w = np.asarray(p1, float) - p2
    cr = np.cross(v, w)
    ang = np.arctan2(np.linalg.norm(cr, axis=-1), np.einsum("...i,...i->...", v * np.ones_like(w),
                                                             w))
    if axis is not None:
        ang = ang * np.sign(cr @ np.asarray(axis, float) + 0.0)
    return ang


# ---- the calibrated model -----------------------------------------------------------------


@dataclass
class CalibratedModel:
    """Geometric model + joint-error regression + joint compliance (thesis §1.4).

    Joint angles fed to eq. 1.4 for commanded angles q:
    θ = q + f(q) + c ⊙ (τ(q) − τ_home), τ from gravity on the robot and its tool;
    the geometry was identified at home, so the home torques' deflections are already in it.
    """

    geometry: VectorModel
    errors: list[JointErrorFit]
    compliance: np.ndarray
    masses: MassModel
    tau_home_Nm: np.ndarray

    def joint_angles(self, q: np.ndarray, *, joint_errors: bool = True,
                     elasticity: bool = True) -> np.ndarray:
        q = np.asarray(q, float)
        th = q.copy()
        if joint_errors:
            for f in self.errors:
                th[..., f.joint - 1] += f(q[..., f.joint - 1])
        if elasticity:
            tau = gravity_torques_Nm(self.geometry, self.masses, th)
            th = th + self.compliance * (tau - self.tau_home_Nm)
        return th

    def tcp(self, q: np.ndarray, **kw) -> np.ndarray:
        return self.geometry.tcp(self.joint_angles(q, **kw))


# ---- identification from the C-Track tables ----------------------------------------------------


def _compliance_corrected(model, masses, compliance, q_rows, x, link):
    """Remove from target positions x (link ``link``, poses q_rows) the deflection of joints
    ≤ link caused by the change of gravity torque from the home pose."""
    tau = gravity_torques_Nm(model, masses, q_rows)
    tau0 = gravity_torques_Nm(model, masses, np.zeros(model.n_joints))
    return x - compliance_displacement(model, q_rows, tau - tau0, compliance, x, upto=link)


def _home_rows(n, joint, q):
    rows = np.zeros((len(q), n))
    rows[:, joint - 1] = q
    return rows


def identify_geometry(circles: pd.DataFrame, tcp_home_mm: np.ndarray, *, masses: MassModel,
                      compliance: np.ndarray | None = None,
                      model: VectorModel | None = None) -> tuple[VectorModel, list[CircleFit]]:
    """Axes and centres from the joint circles (optionally compliance-corrected with a prior
    ``model``), then the vector model with the measured home TCP."""
    joints = sorted(circles["joint"].unique())
    fits = []
    for j in joints:
        g = circles[circles["joint"] == j].sort_values("q_deg")
        x = g[["x_mm", "y_mm", "z_mm"]].to_numpy()
        if compliance is not None and model is not None:
            rows = _home_rows(len(joints), j, np.deg2rad(g["q_deg"].to_numpy()))
            x = _compliance_corrected(model, masses, compliance, rows, x, j)
        fits.append(fit_circle(x))
    vm = VectorModel([f.axis for f in fits], [f.centre for f in fits], tcp_home_mm)
    return vm, fits


def step_errors(steps: pd.DataFrame, model: VectorModel, *, masses: MassModel,
                compliance: np.ndarray, orders: Mapping[int, Sequence[float]] | None = None,
                ref_degree: int = 3) -> pd.DataFrame:
    """Joint positioning errors by eq. 1.5 from the step tests.

    Each position P_m is the mean of the two approach directions (backlash cancels); P_0 is
    the home position approached in the positive direction (the state of the circle
    measurements, which the geometry refers to). Positions are first corrected for the
    deflection that the changing gravity torque causes (compliance ``compliance``), so the
    error left is the kinematic one. A single reading of P_0 carries the full target noise
    into every angle, so the home reference is the value at q = 0 of a smooth fit (gear
    ``orders`` + polynomial of ``ref_degree``) to all positive-approach angles.
    Returns ``joint, q_rad, error_rad, error_plus_rad, backlash_rad``.
    """
    out = []
    n = model.n_joints
    for j, g in steps.groupby("joint"):
        j = int(j)
        xyz = ["x_mm", "y_mm", "z_mm"]
        plus = g[g["direction"] > 0].sort_values("q_deg")
        minus = g[g["direction"] < 0].set_index("q_deg").loc[plus["q_deg"].to_numpy()]
        q = np.deg2rad(plus["q_deg"].to_numpy())
        rows = _home_rows(n, j, q)
        xp = _compliance_corrected(model, masses, compliance, rows, plus[xyz].to_numpy(), j)
        xm = _compliance_corrected(model, masses, compliance, rows, minus[xyz].to_numpy(), j)
        i0 = int(np.argmin(np.abs(q)))
        e, o = model.axes[j - 1], model.centres[j - 1]
        pm = 0.5 * (xp + xm)
        q = q - q[i0]
        err = joint_angle_eq15(o, e, xp[i0], pm) - q
        err_plus = joint_angle_eq15(o, e, xp[i0], xp) - q
        back = joint_angle_eq15(o, e, xm, xp)
        # P_0 is one noisy reading: take the home angle from a smooth fit of all + approaches
        ords = orders.get(j, []) if orders else []
        coef, *_ = np.linalg.lstsq(_design(q, ords, ref_degree), err_plus, rcond=None)
        ref = float((_design(np.zeros(1), ords, ref_degree) @ coef)[0])
        out.append(pd.DataFrame({"joint": j, "q_rad": q, "error_rad": err - ref,
                                 "error_plus_rad": err_plus - ref, "backlash_rad": back}))
    return pd.concat(out, ignore_index=True)


def base_deflection(base: pd.DataFrame, model: VectorModel, masses: MassModel) -> pd.DataFrame:
    """Base rotation (eq. 1.6) at every pose of the base test against the first pose, with the
    joint-2 gravity torque (same arm weight loads the base): ``pose, q2_rad, tau2_Nm,
    deflection_rad``."""
    qcols = [f"q{i}_deg" for i in range(1, model.n_joints + 1)]
    poses = base.groupby("pose")
    g1 = poses.apply(lambda g: g.loc[g["group"] == 1, ["x_mm", "y_mm", "z_mm"]].mean(),
                     include_groups=False)
    g2 = poses.apply(lambda g: g.loc[g["group"] == 2, ["x_mm", "y_mm", "z_mm"]].mean(),
                     include_groups=False)
    q = np.deg2rad(poses[qcols].first().to_numpy())
    tau = gravity_torques_Nm(model, masses, q)[:, 1]
    e2, _ = model.joint_lines(q)
    ref = 0
    d = base_deflection_eq16(g1.to_numpy()[ref], g2.to_numpy()[ref], g1.to_numpy(),
                             g2.to_numpy(), axis=e2[ref, 1])
    return pd.DataFrame({"pose": g1.index.to_numpy(), "q2_rad": q[:, 1],
                         "tau2_Nm": tau - tau[ref], "deflection_rad": d})


def linear_fit(x: np.ndarray, y: np.ndarray) -> tuple[float, float, float]:
    """Least-squares line y = a + b x; returns (a, b, R²)."""
    A = np.c_[np.ones_like(x), x]
    (a, b), *_ = np.linalg.lstsq(A, y, rcond=None)
    ss = np.sum((y - y.mean()) ** 2)
    r2 = 1 - np.sum((y - a - b * x) ** 2) / ss if ss > 0 else 1.0
    return float(a), float(b), float(r2)


@dataclass
class Identification:
    """Everything the identification produced."""

    model: CalibratedModel
    circle_fits: list[CircleFit]
    steps: pd.DataFrame
    base: pd.DataFrame
    base_compliance: float
    base_r2: float
    compliance_identifiable: np.ndarray
    backlash_rad: np.ndarray
    gravity: bool = True


GRAVITY_NONE = ("none: the cell file states no mass_model, so the identification ran without "
                "the gravity term (no self-weight compliance corrections, tau = 0, base "
                "compliance not identified; compliance from the load discs alone)")
"""The ``gravity_model`` attribute of ``model.nc`` when the cell states no mass model."""


def identify(circles: pd.DataFrame, home: pd.DataFrame, steps: pd.DataFrame,
             loads: pd.DataFrame, base: pd.DataFrame, *, masses: MassModel | None,
             fixture_offset_mm: np.ndarray, orders: Mapping[int, Sequence[float]],
             max_degree: int = 3, holdout_every: int = 4, iterations: int = 3
             ) -> Identification:
    """The whole chapter-1 identification from the C-Track tables.

    Alternates (``iterations`` times): circle fits (compliance-corrected after the first
    pass) → vector model → compliance from the load tests with that model. Then the step
    errors (eq. 1.5, two-direction mean, compliance-corrected) and their regressions, and the
    base deflection (eq. 1.6) against the joint-2 torque. The base deflection is reported but
    not added: it is proportional to the joint-2 torque and rotates the arm about an axis
    parallel to joint 2, so the load tests already include it in c_2 (lumped, thesis §1.4.1).

    ``masses`` None (the cell file states no mass model): the gravity term is left out. The
    joint compliances are still identified from the load tests (the discs' weight is known),
    but the robot's self-weight torques are taken as zero: no compliance corrections of the
    circles and steps, ``tau_home_Nm`` = 0, the full model adds no self-weight deflection, and
    the base compliance and its R² are NaN (its regressor, the joint-2 torque, is unknown);
    ``Identification.gravity`` is False.
    """
    gravity = masses is not None
    masses = masses if gravity else no_masses()
    xyz = ["x_mm", "y_mm", "z_mm"]
    tcp_home = home[xyz].to_numpy().mean(axis=0)
    n = int(circles["joint"].max())
    qcols = [f"q{i}_deg" for i in range(1, n + 1)]
    compliance = None
    model = None
    ident = np.zeros(n, bool)
    for _ in range(iterations):
        model, fits = identify_geometry(circles, tcp_home, masses=masses, compliance=compliance,
                                        model=model)
        ref = loads[loads["load_kg"] == 0].groupby("test")[xyz].mean()
        loaded = loads[loads["load_kg"] > 0]
        dp = loaded[xyz].to_numpy() - ref.loc[loaded["test"].to_numpy()].to_numpy()
        th = np.deg2rad(loaded[qcols].to_numpy())
        load_point = tcp_home + np.asarray(fixture_offset_mm, float)
        compliance, ident = fit_compliance(model, masses, th, loaded["load_kg"].to_numpy(),
                                           load_point, dp)
    errs = step_errors(steps, model, masses=masses, compliance=compliance, orders=orders,
                       ref_degree=max_degree)
    fits_err = []
    backlash = np.zeros(n)
    for j, g in errs.groupby("joint"):
        fits_err.append(fit_joint_error(int(j), g["q_rad"].to_numpy(), g["error_rad"].to_numpy(),
                                        orders.get(int(j), []), max_degree=max_degree,
                                        holdout_every=holdout_every))
        backlash[int(j) - 1] = float(g["backlash_rad"].mean())
    tau_home = gravity_torques_Nm(model, masses, np.zeros(n))
    bd = base_deflection(base, model, masses)
    if gravity:
        _, c_base, r2 = linear_fit(bd["tau2_Nm"].to_numpy(), bd["deflection_rad"].to_numpy())
    else:
        bd["tau2_Nm"] = np.nan
        c_base = r2 = float("nan")
    cal = CalibratedModel(model, fits_err, compliance, masses, tau_home)
    return Identification(cal, fits, errs, bd, c_base, r2, ident, backlash, gravity)


# ---- 5. accuracy ----------------------------------------------------------------------------


def accuracy_points(acc: pd.DataFrame, cal: CalibratedModel) -> pd.DataFrame:
    """Per accuracy point: the mean reached (measured) point over its visits, and the error
    of each model's prediction at the commanded joints [mm].

    ``nominal``: the commanded point (the controller's nominal model); ``geometric``: eq. 1.4
    with the identified geometry; ``full``: + joint-error regression + compliance.
    """
    n = cal.geometry.n_joints
    qcols = [f"q{i}_deg" for i in range(1, n + 1)]
    g = acc.groupby("point")
    meas = g[["x_mm", "y_mm", "z_mm"]].mean().to_numpy()
    cmd = g[["x_cmd_mm", "y_cmd_mm", "z_cmd_mm"]].first().to_numpy()
    q = np.deg2rad(g[qcols].first().to_numpy())
    geo = cal.geometry.tcp(q)
    full = cal.tcp(q)
    return pd.DataFrame({
        "point": g.size().index.to_numpy(), "visits": g.size().to_numpy(),
        "x_cmd_mm": cmd[:, 0], "y_cmd_mm": cmd[:, 1], "z_cmd_mm": cmd[:, 2],
        "err_nominal_mm": np.linalg.norm(meas - cmd, axis=1),
        "err_geometric_mm": np.linalg.norm(meas - geo, axis=1),
        "err_full_mm": np.linalg.norm(meas - full, axis=1),
    })


MODELS = ("nominal", "geometric", "full")


def error_stats(err: np.ndarray) -> dict[str, float]:
    err = np.asarray(err, float)
    return {"mean_mm": float(err.mean()), "rms_mm": float(np.sqrt(np.mean(err**2))),
            "p95_mm": float(np.percentile(err, 95)), "max_mm": float(err.max()),
            "n_points": int(err.size)}


def accuracy_table(points: pd.DataFrame) -> pd.DataFrame:
    """``model, mean_mm, rms_mm, p95_mm, max_mm, n_points`` for nominal, geometric, full."""
    return pd.DataFrame([{"model": m, **error_stats(points[f"err_{m}_mm"])} for m in MODELS])


def workspace_regions(points: pd.DataFrame, reach_edges_mm: Sequence[float],
                      height_edges_mm: Sequence[float]) -> pd.Series:
    """Region label per point from the commanded reach (distance from the base z axis) and
    height: ``reach<800/z<400`` style labels."""
    reach = np.hypot(points["x_cmd_mm"], points["y_cmd_mm"])

    def label(v, edges, name):
        edges = list(edges)
        k = np.searchsorted(edges, v, side="right")
        names = ([f"{name}<{edges[0]:g}"] if edges else []) + \
            [f"{name}{a:g}-{b:g}" for a, b in zip(edges[:-1], edges[1:], strict=True)] + \
            ([f"{name}>={edges[-1]:g}"] if edges else [f"{name}:all"])
        return np.array(names)[k]

    return pd.Series(np.char.add(np.char.add(label(reach, reach_edges_mm, "reach"), "/"),
                                 label(points["z_cmd_mm"].to_numpy(), height_edges_mm, "z")),
                     index=points.index, name="region")


def accuracy_by_region(points: pd.DataFrame, regions: pd.Series) -> pd.DataFrame:
    """Accuracy statistics per workspace region and model."""
    rows = []
    for reg, g in points.groupby(regions):
        for m in MODELS:
            rows.append({"region": reg, "model": m, **error_stats(g[f"err_{m}_mm"])})
    return pd.DataFrame(rows)


# ---- artefacts -------------------------------------------------------------------------------


def model_to_dataset(ident: Identification) -> xr.Dataset:
    """``results/calibration/model.nc``: axes, centres, a'_i vectors, joint-error model
    coefficients, compliances, base compliance, backlash, and the mass model used (the cell
    file's ``mass_model``; none, and attribute ``gravity_model`` saying so, without one)."""
    cal = ident.model
    geo = cal.geometry
    n = geo.n_joints
    a0, a = geo.a_vectors()
    kmax = max((len(f.orders) for f in cal.errors), default=0)
    dmax = max((len(f.poly) for f in cal.errors), default=0)
    orders = np.full((n, kmax), np.nan)
    s = np.full((n, kmax), np.nan)
    c = np.full((n, kmax), np.nan)
    poly = np.full((n, dmax), np.nan)
    deg = np.full(n, -1)
    val = np.full((n, 3), np.nan)
    train = np.full(n, np.nan)
    forms = ["polynomial", "fourier", "fourier+polynomial"]
    for f in cal.errors:
        i = f.joint - 1
        k = len(f.orders)
        orders[i, :k], s[i, :k], c[i, :k] = f.orders, f.sin, f.cos
        poly[i, :len(f.poly)] = f.poly
        deg[i] = f.degree
        val[i] = [f.validation[m] for m in forms]
        train[i] = f.train_rms_rad

    def v(dims, data, units, long_name, **attrs):
        return (dims, np.asarray(data), {"units": units, "long_name": long_name, **attrs})

    J, X = "joint", "xyz"
    return xr.Dataset(
        {
            "axis": v((J, X), geo.axes, "1", "joint axis e_i at the home configuration"),
            "centre_mm": v((J, X), geo.centres, "mm", "joint centre O_i (circle centre)"),
            "a0_mm": v((X,), a0, "mm", "a_0: C-Track origin to O_1"),
            "a_prime_mm": v((J, X), a, "mm", "a'_i: O_i to O_i+1 (a'_6: O_6 to the tool tip)"),
            "tcp_home_mm": v((X,), geo.tcp_mm, "mm", "tool tip P at home"),
            "circle_radius_mm": v((J,), [f.radius for f in ident.circle_fits], "mm",
                                  "radius of the joint circle"),
            "circle_rms_mm": v((J,), [f.rms_mm for f in ident.circle_fits], "mm",
                               "RMS distance of the targets from the fitted circle"),
            "circle_points": v((J,), [f.n_points for f in ident.circle_fits], "1",
                               "targets in the circle fit"),
            "compliance_rad_per_Nm": v((J,), cal.compliance, "rad/(N m)",
                                       "joint compliance (joint 2 includes the base)"),
            "compliance_identifiable": v((J,), ident.compliance_identifiable.astype(bool), "1",
                                         "the load tests load this joint"),
            "tau_home_Nm": v((J,), cal.tau_home_Nm, "N m", "gravity torque at home"),
            "backlash_rad": v((J,), ident.backlash_rad, "rad",
                              "mean difference of the + and - approaches"),
            "base_compliance_rad_per_Nm": v((), ident.base_compliance, "rad/(N m)",
                                            "base rotation per joint-2 torque (eq. 1.6 fit), "
                                            "lumped into joint 2"),
            "base_fit_r2": v((), ident.base_r2, "1", "R^2 of the linear base-deflection fit"),
            "error_order": v((J, "harmonic"), orders, "1",
                             "Fourier order of the joint-error model (per joint revolution)"),
            "error_sin_rad": v((J, "harmonic"), s, "rad", "sine coefficient"),
            "error_cos_rad": v((J, "harmonic"), c, "rad", "cosine coefficient"),
            "error_poly_rad": v((J, "power"), poly, "rad/rad^k",
                                "polynomial coefficient of q^k (q in rad)"),
            "error_degree": v((J,), deg, "1", "polynomial degree chosen on held-out steps"),
            "error_train_rms_rad": v((J,), train, "rad", "RMS residual on all steps"),
            "error_validation_rms_rad": v((J, "form"), val, "rad",
                                          "held-out RMS residual of each candidate form"),
            "mass_link": v(("mass",), cal.masses.link, "1", "link carrying the point mass"),
            "mass_kg": v(("mass",), cal.masses.mass_kg, "kg", "point mass"),
            "mass_com_mm": v(("mass", X), cal.masses.com_mm, "mm",
                             "point-mass position at the zero configuration"),
        },
        coords={
            J: (J, np.arange(1, n + 1), {"units": "1", "long_name": "joint"}),
            X: (X, ["x", "y", "z"], {"units": "1", "long_name": "C-Track axis"}),
            "harmonic": ("harmonic", np.arange(kmax), {"units": "1", "long_name": "term"}),
            "power": ("power", np.arange(dmax), {"units": "1", "long_name": "power k of q"}),
            "form": ("form", forms, {"units": "1", "long_name": "candidate regression form"}),
            "mass": ("mass", np.arange(len(cal.masses.link)), {"units": "1",
                                                                "long_name": "point mass"}),
        },
        attrs={"base_lumped_into_joint": 2,
               "model": "eq. 1.4 with theta = q + f(q) + c (tau - tau_home)",
               "gravity_model": "cell mass_model" if ident.gravity else GRAVITY_NONE},
    )


def model_from_dataset(ds: xr.Dataset) -> CalibratedModel:
    """Rebuild the :class:`CalibratedModel` stored by :func:`model_to_dataset`."""
    geo = VectorModel(ds["axis"].values, ds["centre_mm"].values, ds["tcp_home_mm"].values)
    fits = []
    for i, j in enumerate(ds["joint"].values):
        deg = int(ds["error_degree"].values[i])
        if deg < 0:
            continue
        o = ds["error_order"].values[i]
        ok = np.isfinite(o)
        fits.append(JointErrorFit(int(j), o[ok], deg, ds["error_poly_rad"].values[i, :deg + 1],
                                  ds["error_sin_rad"].values[i][ok],
                                  ds["error_cos_rad"].values[i][ok]))
    masses = MassModel(ds["mass_link"].values, ds["mass_kg"].values, ds["mass_com_mm"].values)
    return CalibratedModel(geo, fits, ds["compliance_rad_per_Nm"].values, masses,
                           ds["tau_home_Nm"].values)


def joint_error_table(ident: Identification, holdout_every: int) -> pd.DataFrame:
    """Measured joint errors with the model's prediction and the held-out flag."""
    out = []
    fits = {f.joint: f for f in ident.model.errors}
    for j, g in ident.steps.groupby("joint"):
        g = g.copy()
        g["model_rad"] = fits[int(j)](g["q_rad"].to_numpy())
        idx = np.arange(len(g))
        g["held_out"] = (idx % holdout_every) == (holdout_every // 2)
        out.append(g)
    return pd.concat(out, ignore_index=True)


def circle_table(circles: pd.DataFrame, ident: Identification) -> pd.DataFrame:
    """Circle points with their in-plane coordinates about the fitted centre (u, v [mm]) and
    residuals (radial and out-of-plane [mm]), for the figures of the joint circles."""
    out = []
    for f, (j, g) in zip(ident.circle_fits, circles.groupby("joint"), strict=True):
        d = g[["x_mm", "y_mm", "z_mm"]].to_numpy() - f.centre
        u = d[0] - (d[0] @ f.axis) * f.axis
        u = u / np.linalg.norm(u)
        v = np.cross(f.axis, u)
        h = d @ f.axis
        out.append(pd.DataFrame({"joint": int(j), "q_deg": g["q_deg"].to_numpy(),
                                 "u_mm": d @ u, "v_mm": d @ v,
                                 "radial_residual_mm": np.hypot(d @ u, d @ v) - f.radius,
                                 "normal_residual_mm": h}))
    return pd.concat(out, ignore_index=True)


def improvement_ratios(accuracy: pd.DataFrame, *, baseline: str = "nominal") -> pd.Series:
    """How many times smaller each model's RMS positioning error is than ``baseline``'s.

    Parameters
    ----------
    accuracy
        ``results/calibration/accuracy.csv`` indexed by ``model`` (column ``rms_mm``).

    Returns
    -------
    pandas.Series
        Per model ``rms_baseline / rms_model`` (1 for the baseline itself).
    """
    rms = accuracy["rms_mm"].astype(float)
    return float(rms.loc[baseline]) / rms


def region_table(regions: pd.DataFrame,
                 models: Sequence[str] = ("nominal", "geometric", "full")) -> pd.DataFrame:
    """RMS positioning error [mm] per workspace region (rows) and model (columns), with the
    number of validation points per region.

    Parameters
    ----------
    regions
        ``results/calibration/accuracy_by_region.csv`` (``region, model, rms_mm,
        n_points``, long form).
    models
        The model columns, in order (models absent from ``regions`` are left out).
    """
    tab = regions.pivot_table(index="region", columns="model", values="rms_mm")
    tab = tab[[m for m in models if m in tab.columns]]
    tab["n_points"] = regions.groupby("region")["n_points"].first()
    return tab
