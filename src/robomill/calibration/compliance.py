"""Joint compliance and base deflection (thesis §1.4.1, eq. 1.6).

Joint compliances from load-disc tests (:func:`fit_compliance`):
Δp = Σ_j c_j Δτ_j e_j × (p − O_j); the base deflection of eq. 1.6
(:func:`base_deflection_eq16`, :func:`base_deflection`), linear in the joint-2 torque and
lumped into joint 2; the compliance correction of measured target positions
(:func:`compliance_corrected`). Lengths in mm, torques in N·m, compliances in rad/(N·m).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from robomill.calibration.geometry import VectorModel
from robomill.calibration.gravity import MassModel, gravity_torques_Nm


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


def compliance_corrected(model: VectorModel, masses: MassModel, compliance: np.ndarray,
                         q_rows: np.ndarray, x: np.ndarray, link: int) -> np.ndarray:
    """Remove from target positions x (link ``link``, poses q_rows) the deflection of joints
    ≤ link caused by the change of gravity torque from the home pose."""
    tau = gravity_torques_Nm(model, masses, q_rows)
    tau0 = gravity_torques_Nm(model, masses, np.zeros(model.n_joints))
    return x - compliance_displacement(model, q_rows, tau - tau0, compliance, x, upto=link)


def single_joint_poses(n: int, joint: int, q: np.ndarray) -> np.ndarray:
    """Poses ``(len(q), n)`` with joint ``joint`` (1..n) at angles ``q`` and the others at 0."""
    rows = np.zeros((len(q), n))
    rows[:, joint - 1] = q
    return rows


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
