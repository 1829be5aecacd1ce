"""The planted robot's vibration modes at a pose: the generalized eigenproblem of its joint
stiffness and its mass matrix, mapped to the tool tip.

The arm is rigid links on elastic joints (the planted joint stiffness K_θ, diagonal, the one
the load tests measure). Its free vibration at pose q solves the generalized eigenproblem
[Géradin & Rixen 2015, §2.4; Craig & Kurdila 2006, §10.2]

.. math:: K_θ ψ_j = ω_j^2 \\tilde M(q)\\, ψ_j, \\qquad ψ_j^T \\tilde M(q)\\, ψ_k = δ_{jk}

(:func:`scipy.linalg.eigh`), with ψ_j the joint motion of mode j normalized to unit modal mass.
The tool tip moves along J_v(q) ψ_j (J_v the translational Jacobian at the TCP), so mode j's
tool-tip shape, modal mass and modal stiffness along that shape are

.. math:: u_j = \\frac{J_v ψ_j}{\\lVert J_v ψ_j \\rVert}, \\qquad
          μ_j = \\frac{1}{\\lVert J_v ψ_j \\rVert^2}, \\qquad κ_j = ω_j^2 μ_j

(the tool-tip receptance of the arm is Σ_j u_j u_jᵀ/(κ_j (1 − ω²/ω_j² + …)); at ω → 0 it sums to
the joints' static compliance J_v K_θ⁻¹ J_vᵀ of the load tests [Dumas et al. 2011]). The
shapes turn, and the modes mix, as the pose changes the mass matrix and the Jacobian.

**The mass model and its calibration.** M(q) is the robot's point masses by the
composite-rigid-body algorithm (:mod:`robomill.synth.inertia`). Point masses carry no
rotational inertia of their own and no motor: the wrist joints see almost no inertia, and the
documented mass split is an assumption, so M(q) alone puts the wrist modes at hundreds of Hz to
kHz where the thesis measured six modes at 20–72 Hz. The cell's inertia is therefore
calibrated once, at the impact test's pose q_ref, so that its lowest eigenfrequencies are the
planted ones (``synth.modes`` ``f_hz``, thesis §3.3): each joint i gets an inertia scale s_i and
a rotor inertia a_i (the reflected inertia of its motor and gears, which point masses lack),

.. math:: \\tilde M(q) = S^{1/2} \\left(M(q) + \\operatorname{diag}(a)\\right) S^{1/2},
          \\qquad S = \\operatorname{diag}(s),

solved by least squares on the log-frequencies (12 unknowns for at most 6 frequencies: a
small pull of log s towards 0 and of log a towards 1 % of the mean joint inertia picks one
solution, then the frequencies are solved exactly from it; the Jacobian is the eigenvalue's
derivative ∂ω_r²/∂p = −ω_r² ψ_rᵀ (∂M̃/∂p) ψ_r). The calibration uses the planted
frequencies only, never a prediction or an identified mode. The same s and a hold at every
pose, so the frequencies, shapes and mixing away from q_ref are the model's.

Géradin, M.; Rixen, D. J. *Mechanical Vibrations: Theory and Application to Structural
Dynamics*, 3rd ed. Wiley, 2015.
Craig, R. R.; Kurdila, A. J. *Fundamentals of Structural Dynamics*, 2nd ed. Wiley, 2006.
Dumas, C.; Caro, S.; Garnier, S.; Furet, B. Joint stiffness identification of six-revolute
industrial serial robots. *Robotics and Computer-Integrated Manufacturing* 27(4), 881–888, 2011.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class JointModes:
    """The arm's modes at one pose: frequencies ``f_hz`` ``(n,)`` ascending, joint shapes
    ``psi`` ``(n, n)`` (columns, unit modal mass), tool-tip unit shapes ``tip_shape``
    ``(n, 3)`` and modal stiffness along them ``k_tip_N_m`` ``(n,)``."""

    f_hz: np.ndarray
    psi: np.ndarray
    tip_shape: np.ndarray
    k_tip_N_m: np.ndarray


@dataclass(frozen=True)
class InertiaCalibration:
    """Per-joint inertia scale ``scale`` (s_i) and rotor inertia ``rotor_kg_m2`` (a_i) of the
    calibrated mass matrix (module docstring); ``f_error_rel``: the largest relative error of
    the calibrated eigenfrequencies at q_ref against the planted ones."""

    scale: np.ndarray
    rotor_kg_m2: np.ndarray
    f_error_rel: float


def calibrated_mass(M_kg_m2: np.ndarray, cal: InertiaCalibration | None) -> np.ndarray:
    """S^½ (M + diag(a)) S^½ (module docstring); M itself without a calibration."""
    M = np.asarray(M_kg_m2, float)
    if cal is None:
        return M
    s = np.sqrt(cal.scale)
    return s[:, None] * (M + np.diag(cal.rotor_kg_m2)) * s[None, :]


TIP_RTOL = 1e-9  # tip motion below this share of the largest mode's: the mode moves no tip


def eigenmodes(K_Nm_rad: np.ndarray, M_kg_m2: np.ndarray, Jv_m: np.ndarray) -> JointModes:
    """Solve K_θ ψ = ω² M ψ (K diagonal ``(n,)`` or ``(n, n)``, M positive definite) and map
    each mode to the tool tip through the translational Jacobian ``Jv_m`` ``(3, n)``
    (module docstring). A mode that moves no tool tip has NaN shape and infinite stiffness:
    one whose tip motion is below ``TIP_RTOL`` of the largest mode's, which is the rounding of
    J_v ψ (a wrist joint spinning about an axis through the TCP moves it by about 1e-16 of the
    others), so that no shape or stiffness is made of rounding noise."""
    import scipy.linalg

    K = np.asarray(K_Nm_rad, float)
    K = np.diag(K) if K.ndim == 1 else K
    w2, psi = scipy.linalg.eigh(K, np.asarray(M_kg_m2, float))
    tip = np.asarray(Jv_m, float) @ psi
    norm = np.linalg.norm(tip, axis=0)
    moving = norm > TIP_RTOL * (norm.max() if norm.size else 0.0)
    shape = np.full((psi.shape[1], 3), np.nan)
    shape[moving] = (tip[:, moving] / norm[moving]).T
    k = np.full(psi.shape[1], np.inf)
    k[moving] = w2[moving] / norm[moving] ** 2
    return JointModes(np.sqrt(np.clip(w2, 0.0, None)) / (2 * np.pi), psi, shape, k)


def calibrate_inertia(K_Nm_rad: np.ndarray, M_ref_kg_m2: np.ndarray,
                      f_target_hz: np.ndarray, pull: float = 1e-3) -> InertiaCalibration:
    """Per-joint inertia scale and rotor inertia so that the lowest ``len(f_target_hz)``
    eigenfrequencies of K_θ ψ = ω² M̃ ψ at the reference pose are ``f_target_hz`` (ascending)
    (module docstring)."""
    import scipy.linalg
    from scipy.optimize import least_squares

    K = np.diag(np.asarray(K_Nm_rad, float))
    M = np.asarray(M_ref_kg_m2, float)
    n = K.shape[0]
    target = np.sort(np.asarray(f_target_hz, float))
    m = target.size
    if m > n:
        raise ValueError(f"synth.modes: {m} planted robot modes, but the robot's {n} joints "
                         f"give {n} (expected at most {n})")

    def unpack(x):
        return InertiaCalibration(np.exp(x[:n]), np.exp(x[n:]), np.nan)

    def log_ratio(x):
        w2 = scipy.linalg.eigh(K, calibrated_mass(M, unpack(x)), eigvals_only=True)
        return 0.5 * np.log(w2[:m]) - np.log(2 * np.pi * target)

    def log_ratio_jac(x):
        # d(½ ln ω_r²)/dp = −½ ψ_rᵀ (∂M̃/∂p) ψ_r for ψ_r of unit modal mass
        cal = unpack(x)
        Mt = calibrated_mass(M, cal)
        psi = scipy.linalg.eigh(K, Mt)[1][:, :m]
        d_scale = psi * (Mt @ psi)                   # ∂M̃/∂ln s_i = ½(e_i e_iᵀ M̃ + M̃ e_i e_iᵀ)
        d_rotor = psi**2 * (cal.scale * cal.rotor_kg_m2)[:, None]   # ∂M̃/∂ln a_i = s_i a_i e_i e_iᵀ
        return -0.5 * np.vstack([d_scale, d_rotor]).T

    # start: no scale, a rotor of 1 % of the mean joint inertia (where the point masses give
    # the joints no inertia at all, the inertia that puts the mean stiffness at the lowest
    # target)
    a0 = 1e-2 * np.trace(M) / n
    if not a0 > 0.0:
        a0 = float(np.mean(np.diag(K))) / (2 * np.pi * target[0]) ** 2
    x0 = np.r_[np.zeros(n), np.full(n, np.log(a0))]
    pulled = least_squares(lambda x: np.r_[log_ratio(x), pull * (x - x0)], x0,
                           jac=lambda x: np.vstack([log_ratio_jac(x), pull * np.eye(2 * n)]))
    exact = least_squares(log_ratio, pulled.x, jac=log_ratio_jac, xtol=1e-15, ftol=1e-15,
                          gtol=1e-15)
    cal = unpack(exact.x)
    err = float(np.max(np.abs(np.expm1(log_ratio(exact.x)))))
    return InertiaCalibration(cal.scale, cal.rotor_kg_m2, err)


def track(reference: JointModes, M_kg_m2: np.ndarray, modes: JointModes,
          count: int) -> np.ndarray:
    """Which of ``modes`` (at another pose) continues each of the ``count`` lowest reference
    modes: the assignment that maximizes the summed mass-weighted correlation
    |ψ_refᵀ M̃(q) ψ_q| (each column unit modal mass, so a correlation of 1 is the same joint
    motion; Hungarian algorithm, :func:`scipy.optimize.linear_sum_assignment`), so that a
    planted mode keeps its damping where two frequencies cross. Returns indices ``(count,)``."""
    from scipy.optimize import linear_sum_assignment

    corr = np.abs(reference.psi[:, :count].T @ np.asarray(M_kg_m2, float) @ modes.psi)
    _, cols = linear_sum_assignment(-corr)
    return np.asarray(cols, int)
