"""The calibrated model and its identification from the C-Track tables (thesis §1.4).

:class:`CalibratedModel` combines the geometry (:mod:`~robomill.calibration.geometry`), the
joint-error regression (:mod:`~robomill.calibration.joint_errors`) and the joint compliance
(:mod:`~robomill.calibration.compliance`) under gravity
(:mod:`~robomill.calibration.gravity`); :func:`identify` runs the whole chapter-1 chain.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from robomill.calibration.compliance import (
    base_deflection,
    compliance_corrected,
    fit_compliance,
    linear_fit,
    single_joint_poses,
)
from robomill.calibration.geometry import CircleFit, VectorModel, fit_circle
from robomill.calibration.gravity import MassModel, gravity_torques_Nm, no_masses
from robomill.calibration.joint_errors import JointErrorFit, fit_joint_error, step_errors
from robomill.settings import schema_default


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
            rows = single_joint_poses(len(joints), j, np.deg2rad(g["q_deg"].to_numpy()))
            x = compliance_corrected(model, masses, compliance, rows, x, j)
        fits.append(fit_circle(x))
    vm = VectorModel([f.axis for f in fits], [f.centre for f in fits], tcp_home_mm)
    return vm, fits


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
             max_degree: int = 3, holdout_every: int = 4,
             iterations: int = schema_default("calibration", "iterations")
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
