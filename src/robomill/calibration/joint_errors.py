"""Joint positioning errors (thesis §1.4, eq. 1.5) and their regression on the joint angle.

Eq. 1.5 (:func:`joint_angle_eq15`) on positions that are the mean of both approach
directions (cancels backlash, :func:`step_errors`); a regression model of the error versus
joint angle (:class:`JointErrorFit`: Fourier terms at the gear orders + a low-order
polynomial, chosen on held-out steps, :func:`fit_joint_error`). Angles in rad.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from robomill.calibration.compliance import compliance_corrected, single_joint_poses
from robomill.calibration.geometry import VectorModel
from robomill.calibration.gravity import MassModel


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
        rows = single_joint_poses(n, j, q)
        xp = compliance_corrected(model, masses, compliance, rows, plus[xyz].to_numpy(), j)
        xm = compliance_corrected(model, masses, compliance, rows, minus[xyz].to_numpy(), j)
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
