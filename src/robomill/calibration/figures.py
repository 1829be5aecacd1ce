"""Chapter 1's figures, drawn from the calibration stage's artefacts (each function returns
the figure; the chapter saves, shows and captions it): a joint circle of the single-joint
method (Stone 1986) with every joint's residuals, the vector model (eq. 1.4), the joint
positioning errors and their regression (eq. 1.5), the base deflection (eq. 1.6) and the
positioning error of the three models on the accuracy points."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import xarray as xr

from robomill.calibration.identification import CalibratedModel

ARCSEC_RAD = np.pi / 180 / 3600
CIRCLE_JOINT = 2
"""The joint whose circle is drawn in its plane (the one that carries the arm's weight)."""
VECTOR_TURN_DEG = 90.0
"""Joint-1 angle of the second chain drawn in the vector-model figure."""
AXIS_ARROW_MM = 150.0
HISTOGRAM_BINS = 60


def joint_circle_figure(model: xr.Dataset, circles: pd.DataFrame,
                        joint: int = CIRCLE_JOINT) -> plt.Figure:
    """(a) The targets of ``joint`` in their circle plane (u, v about the fitted centre,
    ``results/calibration/circles.csv``) with the fitted circle of radius
    ``circle_radius_mm``; (b) the distance of every joint's targets from their circle,
    √(radial² + normal²) residual, against the joint angle."""
    fig, axs = plt.subplots(1, 2, figsize=(10, 4.2))
    g = circles[circles["joint"] == joint]
    t = np.linspace(0, 2 * np.pi, 400)
    r = float(model["circle_radius_mm"].sel(joint=joint))
    axs[0].plot(r * np.cos(t), r * np.sin(t), "-", color="0.7", label="fitted circle")
    axs[0].plot(g["u_mm"], g["v_mm"], "o", ms=3, label="C-Track target")
    axs[0].plot(0, 0, "k+", ms=12, label=f"centre O_{joint} (axis e_{joint} out of the page)")
    axs[0].set_aspect("equal")
    axs[0].set_xlabel("u [mm]")
    axs[0].set_ylabel("v [mm]")
    axs[0].legend(fontsize=8)
    for j, gj in circles.groupby("joint"):
        axs[1].plot(gj["q_deg"],
                    1000 * np.hypot(gj["radial_residual_mm"], gj["normal_residual_mm"]), ".",
                    ms=3, label=f"joint {j}")
    axs[1].set_xlabel("joint angle [deg]")
    axs[1].set_ylabel("distance from the fitted circle [µm]")
    axs[1].legend(fontsize=7, ncol=2)
    fig.suptitle(f"Single-joint method: circle of joint {joint} and the residuals of every "
                 "joint")
    return fig


def vector_model_figure(cal: CalibratedModel,
                        turn_deg: float = VECTOR_TURN_DEG) -> plt.Figure:
    """The centres O_i joined by the vectors a'_i with the axes e_i (red), at home and with
    joint 1 turned by ``turn_deg`` (eq. 1.4: a_i = R_1…R_i a'_i)."""
    geo = cal.geometry
    fig = plt.figure(figsize=(7, 6))
    ax = fig.add_subplot(projection="3d")
    for th1, style in ((0.0, "o-"), (np.deg2rad(turn_deg), "s--")):
        q = np.zeros(geo.n_joints)
        q[0] = th1
        e, o = geo.joint_lines(q)
        chain = np.vstack([[0, 0, 0], o, geo.tcp(q)])
        ax.plot(*chain.T, style, label=f"θ1 = {np.rad2deg(th1):.0f}°")
        for k in range(len(o)):
            ax.quiver(*o[k], *(AXIS_ARROW_MM * e[k]), color="C3", lw=1)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.legend()
    ax.set_title("Centres O_i, vectors a'_i and axes e_i (red)")
    return fig


def joint_errors_figure(joint_errors: pd.DataFrame) -> plt.Figure:
    """Per joint (``results/calibration/joint_errors.csv``): the measured positioning error
    (eq. 1.5), the held-out steps and the regression model, in arcsec."""
    groups = list(joint_errors.groupby("joint"))
    fig, axs = plt.subplots(2, (len(groups) + 1) // 2, figsize=(12, 6), squeeze=False)
    for ax, (j, g) in zip(axs.ravel(), groups, strict=False):
        q = np.rad2deg(g["q_rad"])
        ax.plot(q, g["error_rad"] / ARCSEC_RAD, ".", ms=1, color="0.6",
                label="measured (eq. 1.5)")
        ho = g[g["held_out"].astype(bool)]
        ax.plot(np.rad2deg(ho["q_rad"]), ho["error_rad"] / ARCSEC_RAD, ".", ms=1, color="C1",
                label="held out")
        ax.plot(q, g["model_rad"] / ARCSEC_RAD, "-", color="C0", lw=1, label="regression")
        ax.set_title(f"joint {j}")
        ax.set_xlabel("q [deg]")
        ax.set_ylabel("error [arcsec]")
    axs[0, 0].legend(fontsize=7)
    fig.suptitle("Joint positioning errors (measured − commanded) and the regression model")
    return fig


def base_deflection_figure(model: xr.Dataset, base: pd.DataFrame, *,
                           gravity: bool) -> plt.Figure:
    """The base deflection (``results/calibration/base.csv``, eq. 1.6) against the joint-2
    angle; with a ``gravity`` model also against the joint-2 gravity torque with the linear
    fit ``base_compliance_rad_per_Nm`` (R² ``base_fit_r2``)."""
    fig, axs = plt.subplots(1, 2 if gravity else 1, figsize=(10 if gravity else 5, 4),
                            squeeze=False)
    axs = axs[0]
    axs[0].plot(np.rad2deg(base["q2_rad"]), base["deflection_rad"] / ARCSEC_RAD, "o")
    axs[0].set_xlabel("joint-2 angle, arm stretched [deg]")
    axs[0].set_ylabel("base deflection δθ_base [arcsec]")
    if gravity:
        c_base = float(model["base_compliance_rad_per_Nm"])
        axs[1].plot(base["tau2_Nm"], base["deflection_rad"] / ARCSEC_RAD, "o", label="eq. 1.6")
        x = np.linspace(base["tau2_Nm"].min(), base["tau2_Nm"].max(), 10)
        axs[1].plot(x, c_base * x / ARCSEC_RAD, "-",
                    label=f"linear fit, R² = {float(model['base_fit_r2']):.3f}")
        axs[1].set_xlabel("joint-2 gravity torque change [N·m]")
        axs[1].set_ylabel("base deflection [arcsec]")
        axs[1].legend()
    fig.suptitle("Base deflection while joint 2 turns the stretched arm")
    return fig


def accuracy_histogram_figure(points: pd.DataFrame) -> plt.Figure:
    """Histograms of the positioning error of the nominal, geometric and full models on the
    accuracy points (``results/calibration/accuracy_points.csv``, ``err_<model>_mm``)."""
    fig, ax = plt.subplots()
    bins = np.linspace(0, points[["err_nominal_mm"]].to_numpy().max() * 1.02, HISTOGRAM_BINS)
    for m, col in (("nominal", "C3"), ("geometric", "C1"), ("full", "C0")):
        ax.hist(points[f"err_{m}_mm"], bins=bins, alpha=0.6, color=col, label=m)
    ax.set_xlabel("positioning error [mm]")
    ax.set_ylabel("points")
    ax.set_yscale("log")
    ax.legend()
    ax.set_title("Positioning error on the accuracy points (not used for identification)")
    return fig
