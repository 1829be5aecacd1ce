"""Calibration artefacts: the identified model as ``results/calibration/model.nc`` and back
(:func:`model_to_dataset`, :func:`model_from_dataset`), and the tables of the joint errors
and joint circles for the chapter's figures.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import xarray as xr

from robomill.calibration.geometry import VectorModel
from robomill.calibration.gravity import MassModel
from robomill.calibration.identification import GRAVITY_NONE, CalibratedModel, Identification
from robomill.calibration.joint_errors import JointErrorFit
from robomill.xrvars import var as v


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
