"""Joint-stiffness model of a serial robot: identification, Cartesian and directional
stiffness, working-plane maps and the stiffness-optimal pose (seed 001, Yi et al. 2025).

Model (seed 001 eqs. 6–10), rigid links and elastic joints under a quasi-static TCP force:

* joint torques τ = Jᵀ W with the TCP wrench W = [F; 0], joint deflections θ = K_θ⁻¹ τ;
* TCP deflection X = J_v K_θ⁻¹ J_vᵀ F (eq. 9); written linear in the joint compliances
  c_j = 1/k_j it is X = A(J, F) c with column j of A equal to J_{v,j} (J_{v,j} · F) (eq. 10);
* Cartesian stiffness K = J⁻ᵀ K_θ J⁻¹ (eq. 8) for a square, non-singular J.

Units inside this module are SI: Jacobians with linear rows in m/rad (:func:`jacobian_m`),
forces in N, deflections in m, joint stiffness in N·m/rad. A joint whose compliance the tests
cannot observe (its column of A is zero, or a combination of other columns) is reported
with ``observable = False`` and treated as rigid (compliance 0) in predictions.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from robomill.kinematics import SerialRobot, ik_batch

GRAVITY_M_S2 = 9.80665


def jacobian_m(robot: SerialRobot, q_rad: np.ndarray) -> np.ndarray:
    """Geometric Jacobian ``(..., 6, n)`` in SI units (linear rows m/rad, angular rows 1).

    The vector-product Jacobian of :meth:`SerialRobot.jacobian` (seed 001 §1.2) with its
    linear rows converted from mm/rad.
    """
    J = np.array(robot.jacobian(q_rad), dtype=float)
    J[..., :3, :] *= 1e-3
    return J


def design_matrix(J_m: np.ndarray, force_N: np.ndarray) -> np.ndarray:
    """Coefficient matrix A(J, F) of the identification model X = A c (seed 001 eq. 10).

    Parameters
    ----------
    J_m
        Jacobians ``(m, 6, n)`` or their linear rows ``(m, 3, n)`` [m/rad] at the m poses.
    force_N
        TCP forces ``(m, 3)`` [N] in the base frame.

    Returns
    -------
    numpy.ndarray
        ``(3 m, n)``; rows 3i..3i+2 are pose i's X, Y, Z; column j multiplies c_j [rad/(N·m)].
    """
    Jv = np.asarray(J_m, float)[:, :3, :]
    F = np.asarray(force_N, float)
    tau = np.einsum("mij,mi->mj", Jv, F)  # joint torque per unit compliance [N·m]
    A = Jv * tau[:, None, :]
    return A.reshape(-1, Jv.shape[-1])


def predict_deflection_m(J_m: np.ndarray, force_N: np.ndarray,
                         compliance: np.ndarray) -> np.ndarray:
    """TCP deflections ``(m, 3)`` [m]: X = J_v diag(c) J_vᵀ F (seed 001 eq. 9).

    ``compliance`` are c_j = 1/k_j [rad/(N·m)]; a rigid (or unobservable) joint has c_j = 0.
    """
    A = design_matrix(J_m, force_N)
    return (A @ np.asarray(compliance, float)).reshape(-1, 3)


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
                             level: float = 0.95) -> Identification:
    """Joint stiffness by least squares in the task space (seed 001 eqs. 9–10).

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


def translational_compliance_m_N(J_m: np.ndarray, compliance: np.ndarray) -> np.ndarray:
    """Translational compliance ``(..., 3, 3)`` [m/N]: C = J_v diag(c) J_vᵀ (force-only load,
    tool free to rotate); the inverse of the Schur complement of K = J⁻ᵀ K_θ J⁻¹."""
    Jv = np.asarray(J_m, float)[..., :3, :]
    return np.einsum("...ij,j,...kj->...ik", Jv, np.asarray(compliance, float), Jv)


def cartesian_stiffness(J_m: np.ndarray, k_Nm_rad: np.ndarray) -> np.ndarray:
    """Cartesian stiffness K = J⁻ᵀ K_θ J⁻¹ ``(..., 6, 6)`` (seed 001 eq. 8), SI units
    (N/m, N/rad, N·m/m, N·m/rad blocks). Needs a square, non-singular Jacobian."""
    Jinv = np.linalg.inv(np.asarray(J_m, float))
    return np.swapaxes(Jinv, -1, -2) @ (np.asarray(k_Nm_rad, float)[:, None] * Jinv)


def directional_stiffness_N_m(C_m_N: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Stiffness along unit directions (stiffness orientation, Bu et al. 2017, seed 001 §4.1).

    k_u = 1 / (uᵀ C u): the force along u per unit TCP displacement along u.

    Parameters
    ----------
    C_m_N
        Translational compliance ``(..., 3, 3)`` [m/N].
    directions
        Unit vectors as the columns of ``(..., 3, d)`` (e.g. the tool rotation matrix: tool
        X = feed, Y, Z = axial).

    Returns
    -------
    numpy.ndarray
        ``(..., d)`` [N/m].
    """
    U = np.asarray(directions, float)
    return 1.0 / np.einsum("...id,...ij,...jd->...d", U, C_m_N, U)


def comprehensive_index_N_m(k_xyz_N_m: np.ndarray) -> np.ndarray:
    """Comprehensive stiffness index S (seed 001 §4.3; its formula is not printed, *assumed*
    here as the harmonic mean of the three directional stiffnesses),
    S = 3 / (1/k_x + 1/k_y + 1/k_z) [N/m]: dominated by the weakest direction."""
    k = np.asarray(k_xyz_N_m, float)
    return 3.0 / np.sum(1.0 / k, axis=-1)


def tool_rotation_redundancy(R0: np.ndarray, angle_rad: float | np.ndarray) -> np.ndarray:
    """Tool orientation for redundancy angle θ_r: rotation about the tool axis (z),
    R = R0 Rz(θ_r) (milling leaves that rotation free, seed 001 §4.2)."""
    a = np.asarray(angle_rad, float)
    c, s = np.cos(a), np.sin(a)
    Rz = np.zeros(a.shape + (3, 3))
    Rz[..., 0, 0], Rz[..., 0, 1], Rz[..., 1, 0], Rz[..., 1, 1] = c, -s, s, c
    Rz[..., 2, 2] = 1.0
    return np.asarray(R0, float) @ Rz


def solve_poses(robot: SerialRobot, points_mm: np.ndarray, R_tool: np.ndarray,
                q_seed_rad: np.ndarray, *, limits_rad: np.ndarray | None = None,
                **ik_kw) -> tuple[np.ndarray, np.ndarray]:
    """Joint angles reaching TCP ``points_mm`` ``(m, 3)`` with orientation ``R_tool``
    (``(3, 3)`` or ``(m, 3, 3)``), by batch IK seeded at ``q_seed_rad`` with joint 1 turned
    toward each point. Returns ``q (m, n)`` and a reachability mask (IK converged and, if
    ``limits_rad`` ``(n, 2)`` is given, inside the joint limits)."""
    P = np.asarray(points_mm, float).reshape(-1, 3)
    T = np.broadcast_to(np.eye(4), (len(P), 4, 4)).copy()
    T[:, :3, :3] = R_tool
    T[:, :3, 3] = P
    q0 = np.broadcast_to(np.asarray(q_seed_rad, float), (len(P), robot.n_joints)).copy()
    q0[:, 0] = np.arctan2(P[:, 1], P[:, 0]) + q0[:, 0]
    q, ok = ik_batch(robot, T, q0, **ik_kw)
    q = (q + np.pi) % (2 * np.pi) - np.pi
    if limits_rad is not None:
        lim = np.asarray(limits_rad, float)
        ok &= np.all((q >= lim[:, 0] - 1e-9) & (q <= lim[:, 1] + 1e-9), axis=-1)
    return q, ok


def plane_map(robot: SerialRobot, compliance: np.ndarray, x_mm: np.ndarray, y_mm: np.ndarray,
              height_mm: float, redundancy_rad: float, R0: np.ndarray,
              q_seed_rad: np.ndarray, *, limits_rad: np.ndarray | None = None) -> dict:
    """Directional stiffness over the working plane z = H for one redundancy angle
    (seed 001 §4.2, Fig. 11).

    Returns a mapping of arrays on the ``(len(y), len(x))`` grid: ``k_N_m`` ``(ny, nx, 3)``
    along tool X, Y, Z (NaN where unreachable), ``S_N_m`` (comprehensive index), ``q_rad``
    ``(ny, nx, n)`` and ``reachable``.
    """
    X, Y = np.meshgrid(np.asarray(x_mm, float), np.asarray(y_mm, float))
    P = np.stack([X.ravel(), Y.ravel(), np.full(X.size, float(height_mm))], -1)
    R = tool_rotation_redundancy(R0, redundancy_rad)
    q, ok = solve_poses(robot, P, R, q_seed_rad, limits_rad=limits_rad)
    C = translational_compliance_m_N(jacobian_m(robot, q), compliance)
    k = directional_stiffness_N_m(C, np.broadcast_to(R, C.shape))
    k[~ok] = np.nan
    S = comprehensive_index_N_m(k)
    shape = X.shape
    return {"k_N_m": k.reshape(shape + (3,)), "S_N_m": S.reshape(shape),
            "q_rad": q.reshape(shape + (robot.n_joints,)), "reachable": ok.reshape(shape)}


def deformation_m(robot: SerialRobot, q_rad: np.ndarray, compliance: np.ndarray,
                  force_N: Sequence[float]) -> np.ndarray:
    """TCP deflection ``(..., 3)`` [m] under ``force_N`` at postures ``q_rad``
    (e.g. the 60 kg end load, seed 001 §4.4.1)."""
    C = translational_compliance_m_N(jacobian_m(robot, q_rad), compliance)
    return np.einsum("...ij,j->...i", C, np.asarray(force_N, float))


def monte_carlo_workspace(robot: SerialRobot, limits_rad: np.ndarray, n: int,
                          rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Monte-Carlo workspace (seed 001 §2.1): ``n`` uniform joint samples within
    ``limits_rad`` ``(n_joints, 2)``; returns the samples and TCP positions ``(n, 3)`` [mm]."""
    lim = np.asarray(limits_rad, float)
    q = rng.uniform(lim[:, 0], lim[:, 1], size=(n, robot.n_joints))
    return q, robot.fk(q)[:, :3, 3]


# ---- tables and datasets for the pipeline (pure: frames in, frames out) ----------------------

def _attrs(units: str, long_name: str) -> dict[str, str]:
    return {"units": units, "long_name": long_name}


def pose_group(pose: str) -> str:
    """Group of a load-test pose: its name up to the first ``_`` (``cube_03`` → ``cube``)."""
    return pose.split("_", 1)[0] if "_" in pose else "all"


def identify_from_tests(robot: SerialRobot, tests, *, rtol: float = 1e-8,
                        level: float = 0.95) -> dict:
    """Identify K_θ from a load-test table (``robomill.io.robots.read_load_tests``) and
    predict its validate rows (seed 001 §3.2).

    The model ``all`` uses every identify row; when the pose names form several groups
    (``cube_*``, ``plane_*``: seed 001's 3-D vs working-plane identification) each group with
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


def compliance_from_table(joint_table) -> np.ndarray:
    """Joint compliances [rad/(N·m)] from a ``joint_stiffness.csv`` table (0 where not
    observable: treated as rigid)."""
    k = joint_table["k_Nm_rad"].to_numpy(float)
    obs = joint_table["observable"].astype(str).str.lower().isin(["true", "1"]).to_numpy()
    c = np.zeros_like(k)
    ok = obs & np.isfinite(k) & (k > 0)
    c[ok] = 1.0 / k[ok]
    return c


def map_dataset(robot: SerialRobot, compliance: np.ndarray, *, height_mm: float,
                redundancy_deg: float, half_width_mm: float, step_mm: float,
                q_seed_deg: Sequence[float], limits_deg=None):
    """One working-plane map (:func:`plane_map`) as a labelled dataset (dims y, x, axis,
    joint; scalar coordinates ``height_mm`` and ``redundancy_deg``)."""
    import xarray as xr

    g = np.arange(-half_width_mm, half_width_mm + 0.5 * step_mm, step_mm)
    lim = None if limits_deg is None else np.deg2rad(np.asarray(limits_deg, float))
    m = plane_map(robot, compliance, g, g, height_mm, np.deg2rad(redundancy_deg),
                  np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]]),
                  np.deg2rad(q_seed_deg), limits_rad=lim)
    q = np.rad2deg(m["q_rad"])
    q[~m["reachable"]] = np.nan
    return xr.Dataset(
        {"k_N_m": (("y", "x", "axis"), m["k_N_m"],
                   _attrs("N/m", "directional stiffness along the tool axis (X feed, Z axial)")),
         "S_N_m": (("y", "x"), m["S_N_m"],
                   _attrs("N/m", "comprehensive stiffness index (harmonic mean of X, Y, Z)")),
         "q_deg": (("y", "x", "joint"), q, _attrs("deg", "joint angles of the pose")),
         "reachable": (("y", "x"), m["reachable"],
                       _attrs("1", "pose reachable within the joint limits"))},
        coords={"x": ("x", g, _attrs("mm", "TCP x in the base frame")),
                "y": ("y", g, _attrs("mm", "TCP y in the base frame")),
                "axis": ("axis", ["X", "Y", "Z"], _attrs("1", "tool axis")),
                "joint": ("joint", np.arange(1, robot.n_joints + 1), _attrs("1", "joint")),
                "height_mm": ((), float(height_mm), _attrs("mm", "milling height H")),
                "redundancy_deg": ((), float(redundancy_deg),
                                   _attrs("deg", "redundancy angle about the tool axis"))})


def optimal_poses(robot: SerialRobot, compliance: np.ndarray, maps, *, load_kg: float,
                  random_poses: int, rng: np.random.Generator):
    """Stiffness-optimal pose per milling height (seed 001 §4.3): the argmax of the
    comprehensive index over the plane grid and the redundancy angles, beside
    ``random_poses`` random reachable poses (seed Tables 2–4), each with its deformation
    under the end load ``load_kg`` hanging at the TCP."""
    import pandas as pd

    F = np.array([0.0, 0.0, -load_kg * GRAVITY_M_S2])
    rows = []
    for h in maps["height_mm"].values:
        mh = maps.sel(height_mm=h)
        S = mh["S_N_m"].values  # (redundancy, y, x)
        flat = np.where(np.isfinite(S), S, -np.inf).ravel()
        picks = [("optimal", int(np.argmax(flat)))]
        valid = np.flatnonzero(np.isfinite(S.ravel()))
        if random_poses and valid.size:
            for i, k in enumerate(rng.choice(valid, size=min(random_poses, valid.size),
                                             replace=False)):
                picks.append((f"random_{i + 1}", int(k)))
        for kind, k in picks:
            ir, iy, ix = np.unravel_index(k, S.shape)
            q = mh["q_deg"].values[ir, iy, ix]
            d = deformation_m(robot, np.deg2rad(q), compliance, F) * 1e6
            kx, ky, kz = mh["k_N_m"].values[ir, iy, ix]
            row = {"height_mm": float(h), "pose": kind,
                   "redundancy_deg": float(mh["redundancy_deg"].values[ir]),
                   "x_mm": float(mh["x"].values[ix]), "y_mm": float(mh["y"].values[iy]),
                   "kx_N_m": kx, "ky_N_m": ky, "kz_N_m": kz, "S_N_m": S[ir, iy, ix],
                   "dx_um": d[0], "dy_um": d[1], "dz_um": d[2],
                   "deformation_um": float(np.linalg.norm(d))}
            row.update({f"q{j + 1}_deg": q[j] for j in range(robot.n_joints)})
            rows.append(row)
    return pd.DataFrame(rows)


def workspace_dataset(robot: SerialRobot, limits_deg, n: int, rng: np.random.Generator,
                      maps=None):
    """Monte-Carlo workspace (seed 001 §2.1, N samples) as a dataset: TCP points over all
    joints within ``limits_deg``; the X–Z section (joints 1, 5, 6 at 0, joints 2–4 within
    their limits, flange point as the seed's Fig. 2b); and, from ``maps``, the inner and
    outer diameter of the reachable working-plane annulus per height (seed 001 §2.2)."""
    import dataclasses

    import xarray as xr

    lim = np.deg2rad(np.asarray(limits_deg, float))
    _, P = monte_carlo_workspace(robot, lim, n, rng)
    lim_xz = lim.copy()
    lim_xz[[0, 4, 5]] = 0.0
    flange = dataclasses.replace(robot, tool_mm=np.zeros(3))
    _, Pxz = monte_carlo_workspace(flange, lim_xz, n, rng)
    ds = xr.Dataset(
        {"workspace_mm": (("sample", "axis3"), P, _attrs("mm", "Monte-Carlo TCP positions")),
         "workspace_xz_mm": (("sample", "axis3"), Pxz,
                             _attrs("mm", "Monte-Carlo flange positions, joints 1, 5, 6 at 0"))},
        coords={"sample": ("sample", np.arange(n), _attrs("1", "sample")),
                "axis3": ("axis3", ["X", "Y", "Z"], _attrs("1", "base axis"))})
    if maps is not None:
        X, Y = np.meshgrid(maps["x"].values, maps["y"].values)
        r = np.hypot(X, Y)
        inner, outer = [], []
        for h in maps["height_mm"].values:
            ok = maps["reachable"].sel(height_mm=h).values.any(axis=0)
            inner.append(2 * r[ok].min() if ok.any() else np.nan)
            outer.append(2 * r[ok].max() if ok.any() else np.nan)
        ds["annulus_inner_diameter_mm"] = ("height_mm", inner, _attrs(
            "mm", "inner diameter of the reachable working plane (grid resolution)"))
        ds["annulus_outer_diameter_mm"] = ("height_mm", outer, _attrs(
            "mm", "outer diameter of the reachable working plane (grid resolution)"))
        ds = ds.assign_coords(height_mm=("height_mm", maps["height_mm"].values,
                                         _attrs("mm", "milling height H")))
    return ds


def cut_stiffness_table(robot: SerialRobot, compliance: np.ndarray, cuts,
                        q_mid_rad: np.ndarray) -> pd.DataFrame:
    """Joint-model stiffness of the cell's robot at the middle of every cut, along the cut's
    feed, its in-plane normal and the tool axis (:func:`robomill.experiment.cut_axes`).

    The translational compliance C = J diag(c) Jᵀ (seed 001, eq. 3; only the joints' elastic
    deflection) gives the stiffness along a unit direction u as 1 / (uᵀ C u)
    (:func:`directional_stiffness_N_m`). Any design: the direction comes from ``direction``
    or ``direction_deg``.

    Parameters
    ----------
    robot
        The cell's robot (``cell.yaml: robot``).
    compliance
        Joint compliances c_i [rad/(N·m)] (:func:`compliance_from_table`).
    cuts
        :class:`robomill.experiment.Cut` objects.
    q_mid_rad
        ``(len(cuts), n)`` posture at each cut's middle.

    Returns
    -------
    pandas.DataFrame
        One row per cut: ``cut``, ``k_feed_N_m``, ``k_normal_N_m``, ``k_axial_N_m``.
    """
    from robomill.experiment import cut_axes

    rows = []
    for cut, q in zip(cuts, np.asarray(q_mid_rad, float), strict=True):
        C = translational_compliance_m_N(jacobian_m(robot, q), compliance)
        k = directional_stiffness_N_m(C, cut_axes(cut))
        rows.append({"cut": cut.id, "k_feed_N_m": k[0], "k_normal_N_m": k[1],
                     "k_axial_N_m": k[2]})
    return pd.DataFrame(rows, columns=["cut", "k_feed_N_m", "k_normal_N_m", "k_axial_N_m"])


def slot_stiffness_table(slots: pd.DataFrame, waviness: pd.DataFrame) -> pd.DataFrame:
    """Mean directional stiffness per model and slot direction beside the mean waviness.

    Parameters
    ----------
    slots
        ``results/stiffness/slots.csv``-like table: ``model, direction, k_feed_N_m,
        k_normal_N_m, k_axial_N_m`` per slot pose.
    waviness
        Table 2.1 (``results/surface/table_2_1_waviness_rms.csv``, index ``segment``),
        columns ``s<set>_<direction>`` [µm].

    Returns
    -------
    pandas.DataFrame
        Index ``(model, direction)``; ``k feed N/µm, k normal N/µm, k axial N/µm`` (means,
        rounded to 3 decimals) and ``waviness RMS µm (Table 2.1, mean)`` (mean over the sets
        and segments of that direction; NaN when Table 2.1 has none).
    """
    mean_k = (slots.groupby(["model", "direction"])[["k_feed_N_m", "k_normal_N_m",
                                                     "k_axial_N_m"]].mean() / 1e6).round(3)
    mean_k.columns = ["k feed N/µm", "k normal N/µm", "k axial N/µm"]
    wq = waviness_by_direction(waviness)
    mean_k["waviness RMS µm (Table 2.1, mean)"] = [
        wq.get(d, np.nan) for d in mean_k.index.get_level_values(1)]
    return mean_k


def waviness_by_direction(waviness: pd.DataFrame,
                          directions: tuple[str, ...] = ("px", "py", "my")) -> dict[str, float]:
    """Mean of Table 2.1's cells per direction (columns ending ``_<direction>``) [µm];
    NaN for a direction without columns."""
    out = {}
    for d in directions:
        vals = waviness[[c for c in waviness.columns if c.endswith("_" + d)]].to_numpy(float)
        out[d] = float(np.nanmean(vals)) if vals.size else float("nan")
    return out


def stiffness_spread_pct(values: pd.Series, a: str = "py", b: str = "my") -> float:
    """Relative difference ``100 (k_a − k_b)/k_b`` [%] of two slot directions' stiffness
    (thesis §5: the ±Y slots share their normal direction); NaN if either is missing."""
    ka, kb = values.get(a, np.nan), values.get(b, np.nan)
    return float(100 * (ka - kb) / kb)
