"""Identification of the joint stiffness from load tests [Yi 2025, §3.2, eqs. 9–10]: least
squares in the task space with observability from the SVD, intervals per joint, and the
identify/validate tables of the pipeline.

A joint whose compliance the tests cannot observe (its column of A is zero, or a combination
of other columns) is reported with ``observable = False`` and treated as rigid (compliance 0)
in predictions. SI units inside (m, N, N·m/rad); the tables in mm and µm.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from robomill.kinematics import SerialRobot
from robomill.settings import schema_default
from robomill.stiffness.model import design_matrix, jacobian_m, predict_deflection_m

#: the confidence level of the intervals (config ``stiffness.identification.level``)
LEVEL = schema_default("stiffness.identification", "level")


@dataclass
class Identification:
    """Result of :func:`identify_joint_stiffness`.

    Attributes
    ----------
    k_Nm_rad, ci95_low_Nm_rad, ci95_high_Nm_rad
        Joint stiffness and its 95 % interval (NaN where not observable; the upper bound is
        ``inf`` when the compliance interval reaches zero).
    compliance, compliance_std
        c_j = 1/k_j [rad/(N·m)] used for prediction (0 for unobservable joints) and its
        standard error.
    observable
        Per joint: the tests constrain its compliance.
    condition_number
        Of the column-normalized A over the observable joints.
    residual_rms_m
        RMS of the fit residual per deflection component [m].
    n_poses, dof
        Poses used and residual degrees of freedom.
    messages
        Human-readable warnings (one per unobservable or weakly observed joint).
    """

    k_Nm_rad: np.ndarray
    ci95_low_Nm_rad: np.ndarray
    ci95_high_Nm_rad: np.ndarray
    compliance: np.ndarray
    compliance_std: np.ndarray
    observable: np.ndarray
    condition_number: float
    residual_rms_m: float
    n_poses: int
    dof: int
    messages: list[str] = field(default_factory=list)


def identify_joint_stiffness(J_m: np.ndarray, force_N: np.ndarray, deflection_m: np.ndarray,
                             *, rtol: float = 1e-8, null_share: float = 0.05,
                             level: float = LEVEL) -> Identification:
    """Joint stiffness by least squares in the task space [Yi 2025, eqs. 9–10].

    Solves X = A(J, F) c for the joint compliances c. Observability comes from the SVD of
    A with unit-norm columns: singular values below ``rtol · s_max`` span directions the
    tests do not excite, and every joint with more than ``null_share`` of such a direction
    (or a zero column) is unobservable — it is left out of the fit (treated as rigid),
    reported with ``observable = False`` and a warning, never given an absurd number.
    Intervals: c ± t_{dof} σ √diag((AᵀA)⁻¹), σ² = RSS/dof, mapped to k = 1/c.

    Parameters
    ----------
    J_m
        Jacobians ``(m, 6, n)`` [m/rad] at the identification poses.
    force_N, deflection_m
        Applied TCP force and measured TCP deflection ``(m, 3)`` [N], [m], base frame.
    """
    from scipy import stats

    A = design_matrix(J_m, force_N)
    X = np.asarray(deflection_m, float).reshape(-1)
    n = A.shape[1]
    norms = np.linalg.norm(A, axis=0)
    observable = norms > rtol * max(norms.max(), 1e-300)
    messages = []
    if observable.any():
        As = A[:, observable] / norms[observable]
        _, s, Vt = np.linalg.svd(As, full_matrices=False)
        null = s < rtol * s[0]
        if null.any():
            share = np.sqrt((Vt[null] ** 2).sum(axis=0))
            idx = np.flatnonzero(observable)
            observable[idx[share > null_share]] = False
    for j in np.flatnonzero(~observable):
        messages.append(f"joint {j + 1}: compliance not observable from these tests (no "
                        "torque about its axis, or indistinguishable from other joints); "
                        "reported as NaN and treated as rigid")
    c = np.zeros(n)
    c_std = np.full(n, np.nan)
    cond = np.inf
    rms = np.nan
    dof = A.shape[0] - int(observable.sum())
    if observable.any():
        Ao = A[:, observable]
        sol, *_ = np.linalg.lstsq(Ao, X, rcond=None)
        c[observable] = sol
        resid = X - Ao @ sol
        rms = float(np.sqrt(np.mean(resid**2)))
        s = np.linalg.svd(Ao / np.linalg.norm(Ao, axis=0), compute_uv=False)
        cond = float(s[0] / s[-1])
        sigma2 = float(resid @ resid) / dof if dof > 0 else np.nan
        cov = sigma2 * np.linalg.inv(Ao.T @ Ao)
        c_std[observable] = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    t = stats.t.ppf(0.5 + level / 2, max(dof, 1))
    k = np.full(n, np.nan)
    lo = np.full(n, np.nan)
    hi = np.full(n, np.nan)
    for j in np.flatnonzero(observable):
        cj, dc = c[j], t * c_std[j]
        if cj <= 0:
            messages.append(f"joint {j + 1}: identified compliance {cj:.3g} rad/(N·m) is not "
                            "positive (too little torque about this joint in the tests); "
                            "reported as not observable and treated as rigid")
            observable[j] = False
            c[j] = 0.0
            continue
        k[j] = 1.0 / cj
        lo[j] = 1.0 / (cj + dc)
        hi[j] = 1.0 / (cj - dc) if cj - dc > 0 else np.inf
        if not np.isfinite(hi[j]):
            messages.append(f"joint {j + 1}: weakly observed (95 % interval of its compliance "
                            "includes zero): the upper stiffness bound is unbounded")
    for msg in messages:
        warnings.warn(msg, stacklevel=2)
    return Identification(k, lo, hi, c, c_std, observable.copy(), cond, rms,
                          int(len(X) // 3), int(dof), messages)


def pose_group(pose: str) -> str:
    """Group of a load-test pose: its name up to the first ``_`` (``cube_03`` → ``cube``)."""
    return pose.split("_", 1)[0] if "_" in pose else "all"


def identify_from_tests(robot: SerialRobot, tests, *, rtol: float = 1e-8,
                        level: float = LEVEL) -> dict:
    """Identify K_θ from a load-test table (``robomill.io.robots.read_load_tests``) and
    predict its validate rows [Yi 2025, §3.2].

    The model ``all`` uses every identify row; when the pose names form several groups
    (``cube_*``, ``plane_*``: Yi 2025's 3-D vs working-plane identification) each group with
    enough rows is identified on its own as well.

    Returns
    -------
    dict
        ``joint_stiffness`` (contract table of model ``all``), ``models`` (one row per model:
        poses, condition number, residual, k and interval per joint, warnings),
        ``validation`` (per validate pose and model: measured and predicted deflection, error
        of the magnitude and of the vector in %), ``results`` (the :class:`Identification` per
        model).
    """
    import pandas as pd

    n = robot.n_joints
    q = np.deg2rad(tests[[f"q{i}_deg" for i in range(1, n + 1)]].to_numpy(float))
    J = jacobian_m(robot, q)
    F = tests[["Fx_N", "Fy_N", "Fz_N"]].to_numpy(float)
    X = tests[["dx_mm", "dy_mm", "dz_mm"]].to_numpy(float) * 1e-3
    ident = (tests["role"] == "identify").to_numpy()
    groups = tests["pose"].map(pose_group).to_numpy()
    subsets = {"all": ident}
    names = sorted(set(groups[ident]))
    if len(names) > 1:
        for g in names:
            m = ident & (groups == g)
            if m.sum() * 3 > n:
                subsets[g] = m
    results, rows = {}, []
    for name, m in subsets.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = identify_joint_stiffness(J[m], F[m], X[m], rtol=rtol, level=level)
        results[name] = r
        row = {"model": name, "n_poses": r.n_poses, "dof": r.dof,
               "condition_number": r.condition_number,
               "residual_rms_um": r.residual_rms_m * 1e6}
        for j in range(n):
            row[f"k{j + 1}_Nm_rad"] = r.k_Nm_rad[j]
            row[f"k{j + 1}_ci95_low_Nm_rad"] = r.ci95_low_Nm_rad[j]
            row[f"k{j + 1}_ci95_high_Nm_rad"] = r.ci95_high_Nm_rad[j]
            row[f"observable{j + 1}"] = bool(r.observable[j])
        row["warnings"] = " | ".join(r.messages)
        rows.append(row)
    main = results["all"]
    joint = pd.DataFrame({"joint": np.arange(1, n + 1), "k_Nm_rad": main.k_Nm_rad,
                          "ci95_low_Nm_rad": main.ci95_low_Nm_rad,
                          "ci95_high_Nm_rad": main.ci95_high_Nm_rad,
                          "observable": main.observable})
    val_rows = []
    v = ~ident
    for name, r in results.items():
        if not v.any():
            break
        P = predict_deflection_m(J[v], F[v], r.compliance) * 1e3
        M = X[v] * 1e3
        for i, pose in enumerate(tests["pose"].to_numpy()[v]):
            meas, pred = float(np.linalg.norm(M[i])), float(np.linalg.norm(P[i]))
            val_rows.append({
                "pose": pose, "model": name,
                "dx_mm": M[i, 0], "dy_mm": M[i, 1], "dz_mm": M[i, 2],
                "pred_dx_mm": P[i, 0], "pred_dy_mm": P[i, 1], "pred_dz_mm": P[i, 2],
                "measured_mm": meas, "predicted_mm": pred,
                "error_pct": 100.0 * (pred - meas) / meas,
                "vector_error_pct": 100.0 * float(np.linalg.norm(P[i] - M[i])) / meas})
    cols = ["pose", "model", "dx_mm", "dy_mm", "dz_mm", "pred_dx_mm", "pred_dy_mm",
            "pred_dz_mm", "measured_mm", "predicted_mm", "error_pct", "vector_error_pct"]
    return {"joint_stiffness": joint, "models": pd.DataFrame(rows),
            "validation": pd.DataFrame(val_rows, columns=cols), "results": results}
