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

**The mass model.** M(q) is the robot's point masses by the composite-rigid-body algorithm
(:mod:`robomill.synth.inertia`). Point masses carry no rotational inertia of their own and no
motor: the wrist joints see almost no inertia, and the documented mass split is an
assumption, so M(q) alone puts the wrist modes at hundreds of Hz to kHz where the thesis
measured six modes at 20–72 Hz. The virtual cell therefore completes it once, at the impact
test's pose, with link scales, rotor inertias and link rotational inertias fitted to the
planted frequencies and tool-tip shapes (:mod:`robomill.synth.shapecal`); the same inertia
holds at every pose, so the frequencies, shapes and mixing away from q_ref are the model's.

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
