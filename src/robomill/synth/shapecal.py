"""The planted arm's inertia calibrated to the planted modes' frequencies *and* tool-tip
shapes at the impact test's pose.

The eigen law of the virtual cell (:mod:`robomill.synth.structure`) takes the robot's modes
at a pose q from K_θ ψ = ω² M̃(q) ψ (:mod:`robomill.synth.jointmodes`). The joint stiffness
K_θ is the planted truth and stays fixed; the mass matrix is the robot's point masses
(:mod:`robomill.synth.inertia`), which carry no rotational inertia and no motors, so it is
completed here, once, at the impact pose q_ref, by physically meaningful inertia of the same
rigid bodies:

.. math:: \\tilde M(q) = \\sum_l s_l\\, J_l^T Y_l J_l + \\operatorname{diag}(a)
          + \\sum_l J_{ω,l}^T \\left(\\operatorname{tr}(Σ_l)\\,\\mathbf 1 - Σ_l\\right) J_{ω,l},
          \\qquad Σ_l = L_l L_l^T

[Featherstone 2008, §2.13 and §6.2]: J_l the link's body Jacobian and Y_l the spatial
inertia of its point masses (their sum is Pinocchio's CRBA M(q)), s_l > 0 a scale of link
l's documented masses (the mass split is an assumption), a_i > 0 the rotor inertia of joint
i's motor and gears, and the rotational inertia of link l about its centre of mass in its
own frame written through its second moment of mass Σ_l (positive semidefinite by the
Cholesky factor L_l), which makes every link's inertia physically realizable (its principal
moments obey the triangle inequality) [Wensing, Kim & Slotine 2018]. 6 + 6 + 36 = 48
unknowns for a six-joint arm; the same values hold at every pose, so the frequencies, the
shapes and their mixing away from q_ref are the rigid bodies'.

**Objective.** With ω_r, ψ_r the r-th lowest eigenpair at q_ref, u_r = J_v ψ_r/‖J_v ψ_r‖
its tool-tip shape and φ_r the planted unit shape (``synth.modes`` ``shape``, r = 1..m),
the calibration minimizes, by least squares (:func:`scipy.optimize.least_squares`, analytic
Jacobian from the eigenpair derivatives ∂ω_r²/∂p = −ω_r² ψ_rᵀ M̃_p ψ_r and
∂ψ_r/∂p = −Σ_{s≠r} ψ_s ω_r² ψ_sᵀ M̃_p ψ_r/(ω_r² − ω_s²) − ½ ψ_r ψ_rᵀ M̃_p ψ_r
[Nelson 1976]),

.. math:: \\sum_r \\left(\\frac{\\ln(ω_r/ω^{pl}_r)}{σ_f}\\right)^2
          + \\sum_r \\frac{\\lVert u_r - \\operatorname{sign}(u_r·φ_r)\\, φ_r\\rVert^2}{σ_u^2}
          + λ^2 \\lVert x - x_0 \\rVert^2

with σ_f = ``SIGMA_F`` (0.1 % in frequency), σ_u = ``SIGMA_U`` (0.1; the shape term is
2(1 − |cos|), so 1 − |cos| = 0.005 weighs like a 0.1 % frequency error) and a small pull
λ = ``PULL`` of the log-parameters x towards the start x_0 (no scale, rotors of 1 % of the
mean joint inertia, links of no rotational inertia beyond 5 cm radii of gyration), which picks
one solution where the data leave several. The fit starts from x_0 and from ``STARTS`` − 1
seeded random perturbations of it (the objective has several local minima), screens each for
``SCREEN_NFEV`` evaluations and polishes the lowest.

A second stage, from that fit, adds the planted tool-tip stiffness (``synth.modes``
``k_N_m``) of each mode at q_ref, Σ_r (ln(κ_r/k_r)/σ_k)² with κ_r = ω_r²/‖J_v ψ_r‖² and
σ_k = ``SIGMA_K`` (0.5: a factor 1.65). Without it a mode can match its frequency and shape
while barely moving the tool tip at q_ref, and the eigen law's stiffness ratio
κ_r(q)/κ_r(q_ref) (:mod:`robomill.synth.structure`) then makes it up to 40× softer a few
centimetres away (measured on the default cell: 0.04·10⁶ N/m at study poses against the
planted 1.5·10⁶). The three kinds of planted data are not all consistent with the planted
joint stiffness (below), so the stage trades shape for stiffness where they conflict; the
residual is stated: the fitted frequencies, the MAC = (u_r·φ_r)² and κ_r of each mode
(:class:`ShapeCalibration`). Only the planted frequencies, shapes and stiffnesses at q_ref
enter; never a prediction or an identified mode.

**Shapes no mass matrix holds.** With K_θ fixed, the tool-tip shapes of a full set of modes
are bound by Σ_j u_j u_jᵀ/κ_j = J_v K_θ⁻¹ J_vᵀ (the static compliance, :mod:`jointmodes`):
planted shapes that violate it for every κ_j > 0 cannot all be matched by any mass matrix;
the fit then spreads the error by the objective above, and the MACs say where it went.
**A planted mode that moves no tool tip** (a wrist joint spinning about an axis through the
TCP, its tip motion below :data:`robomill.synth.jointmodes.TIP_RTOL` of the largest) is
kept by the rule of :func:`robomill.synth.structure.robot_modes_at`: no compliance at the
tip; its shape residual counts as ‖φ_r‖ = 1 and :attr:`ShapeCalibration.tip_visible` says so.

Featherstone, R. *Rigid Body Dynamics Algorithms*. Springer, 2008.
Wensing, P. M.; Kim, S.; Slotine, J.-J. E. Linear matrix inequalities for physically
consistent inertial parameter identification. *IEEE Robotics and Automation Letters* 3(1),
60–67, 2018.
Nelson, R. B. Simplified calculation of eigenvector derivatives. *AIAA Journal* 14(9),
1201–1205, 1976.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robomill.synth.jointmodes import TIP_RTOL

SIGMA_F = 1e-3
SIGMA_U = 0.1
SIGMA_K = 0.5
PULL = 1e-3
STARTS = 12
SEED = 0
MAX_NFEV = 400
SCREEN_NFEV = 40
GYRATION_M = 0.05
BOUND = 6.0
_TRIL = np.tril_indices(3)


@dataclass(frozen=True)
class ShapeCalibration:
    """The fitted inertia (module docstring): ``link_scale`` s_l ``(n,)``, ``rotor_kg_m2``
    a_i ``(n,)``, ``second_moment_kg_m2`` Σ_l ``(n, 3, 3)`` (link frame); the fit's residual
    at q_ref: ``f_hz`` ``(m,)`` against the planted ``f_target_hz``, ``mac`` ``(m,)``,
    ``tip_visible`` ``(m,)``, the eigenmodes' tool-tip stiffness ``k_tip_N_m`` ``(m,)``, and
    ``cost`` (the objective above, halved)."""

    link_scale: np.ndarray
    rotor_kg_m2: np.ndarray
    second_moment_kg_m2: np.ndarray
    f_hz: np.ndarray
    f_target_hz: np.ndarray
    mac: np.ndarray
    tip_visible: np.ndarray
    k_tip_N_m: np.ndarray
    cost: float

    @property
    def f_error_rel(self) -> float:
        """The largest relative error of the fitted frequencies."""
        return float(np.max(np.abs(self.f_hz / self.f_target_hz - 1.0)))


@dataclass(frozen=True)
class _Bodies:
    """The pose's building blocks of M̃: point-mass parts ``P`` ``(n, n, n)`` and the
    angular body Jacobians ``W`` ``(n, 3, n)``."""

    P: np.ndarray
    W: np.ndarray


def _bodies(model, q_rad: np.ndarray) -> _Bodies:
    import pinocchio as pin

    data = model.createData()
    pin.computeJointJacobians(model, data, np.asarray(q_rad, float))
    n = model.nv
    J = [np.asarray(pin.getJointJacobian(model, data, i, pin.LOCAL)) for i in range(1, n + 1)]
    P = np.array([Ji.T @ model.inertias[i + 1].matrix() @ Ji for i, Ji in enumerate(J)])
    return _Bodies(P, np.array([Ji[3:] for Ji in J]))


def _rotational(W: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """Σ_l J_ω,lᵀ (tr Σ_l 1 − Σ_l) J_ω,l."""
    WW = np.einsum("lai,laj->lij", W, W)
    tr = np.trace(sigma, axis1=1, axis2=2)
    return np.einsum("l,lij->ij", tr, WW) - np.einsum("lai,lab,lbj->ij", W, sigma, W)


def shape_calibrated_mass(model, q_rad: np.ndarray, cal: ShapeCalibration) -> np.ndarray:
    """M̃(q) of the module docstring for the rigid-body ``model`` at pose ``q_rad``."""
    b = _bodies(model, q_rad)
    return (np.einsum("l,lij->ij", cal.link_scale, b.P) + np.diag(cal.rotor_kg_m2)
            + _rotational(b.W, cal.second_moment_kg_m2))


def _unpack(x: np.ndarray, n: int):
    s, a = np.exp(x[:n]), np.exp(x[n:2 * n])
    L = np.zeros((n, 3, 3))
    L[:, _TRIL[0], _TRIL[1]] = x[2 * n:].reshape(n, 6)
    return s, a, L


class _Fit:
    """Residuals and their Jacobian at q_ref (module docstring)."""

    def __init__(self, b: _Bodies, K: np.ndarray, Jv: np.ndarray, f_hz: np.ndarray,
                 shapes: np.ndarray, k_N_m: np.ndarray | None):
        self.b, self.K, self.Jv = b, K, Jv
        self.n = K.size
        self.w_target = 2 * np.pi * f_hz
        self.phi = shapes / np.linalg.norm(shapes, axis=1, keepdims=True)
        self.m = f_hz.size
        self.log_k = None if k_N_m is None else np.log(np.asarray(k_N_m, float))
        self.with_stiffness = False
        self._memo = (None, None)

    def mass_and_derivatives(self, x):
        n, b = self.n, self.b
        s, a, L = _unpack(x, n)
        sigma = np.einsum("lik,ljk->lij", L, L)
        M = np.einsum("l,lij->ij", s, b.P) + np.diag(a) + _rotational(b.W, sigma)
        WW = np.einsum("lai,laj->lij", b.W, b.W)
        rows, cols = _TRIL
        v = L[:, :, cols]                                   # (n, 3, 6): column b of L_l
        Wv = np.einsum("lai,lak->lki", b.W, v)               # W_lᵀ L_l[:, b]
        Wa = b.W[:, rows, :]                                # (n, 6, n): row a of W_l
        dL = (2 * L[:, rows, cols][:, :, None, None] * WW[:, None]
              - np.einsum("lki,lkj->lkij", Wa, Wv) - np.einsum("lki,lkj->lkij", Wv, Wa))
        eye = np.eye(n)
        dM = np.concatenate([s[:, None, None] * b.P, a[:, None, None] * eye[:, :, None] * eye,
                             dL.reshape(6 * n, n, n)])
        return M, dM

    def evaluate(self, x):
        if self._memo[0] is not None and np.array_equal(self._memo[0], x):
            return self._memo[1]
        M, dM = self.mass_and_derivatives(x)
        Li = np.linalg.inv(np.linalg.cholesky(M))
        lam, V = np.linalg.eigh(Li @ np.diag(self.K) @ Li.T)
        psi = Li.T @ V                                      # unit modal mass
        G = np.einsum("ir,pij,js->prs", psi, dM, psi)
        idx = np.arange(self.n)
        gap = lam[None, :] - lam[:, None]                   # [s, r]: λ_r − λ_s
        gap[idx, idx] = np.inf
        C = -lam[None, None, :] * G / gap[None]
        C[:, idx, idx] = -0.5 * G[:, idx, idx]
        m = self.m
        dlam = -lam[None, :m] * G[:, idx[:m], idx[:m]]
        t = self.Jv @ psi[:, :m]
        dt = np.einsum("ki,is,psr->pkr", self.Jv, psi, C[:, :, :m])
        norm = np.linalg.norm(t, axis=0)
        visible = norm > TIP_RTOL * max(norm.max(), 1e-300)
        safe = np.where(visible, norm, 1.0)
        u = np.where(visible, t / safe, 0.0)
        du = np.where(visible, (dt - u * np.einsum("kr,pkr->pr", u, dt)[:, None, :]) / safe,
                      0.0)
        sign = np.where(np.einsum("kr,rk->r", u, self.phi) < 0.0, -1.0, 1.0)
        res = np.r_[(0.5 * np.log(lam[:m]) - np.log(self.w_target)) / SIGMA_F,
                    ((u - sign * self.phi.T) / SIGMA_U).T.ravel()]
        jac = np.vstack([(0.5 * dlam / lam[None, :m] / SIGMA_F).T,
                         (du / SIGMA_U).transpose(2, 1, 0).reshape(3 * m, -1)])
        if self.log_k is not None and self.with_stiffness:
            # ln κ_r = ln ω_r² − 2 ln‖J_v ψ_r‖ (visible modes only)
            log_kappa = np.log(lam[:m]) - 2 * np.log(safe)
            dlog_kappa = dlam / lam[None, :m] - 2 * np.einsum("kr,pkr->pr", u, dt) / safe
            res = np.r_[res, np.where(visible, log_kappa - self.log_k, 0.0) / SIGMA_K]
            jac = np.vstack([jac, np.where(visible, dlog_kappa, 0.0).T / SIGMA_K])
        out = (res, jac, lam, u, visible, safe)
        self._memo = (x.copy(), out)
        return out


def calibrate_shapes(model, q_ref_rad: np.ndarray, K_Nm_rad: np.ndarray, Jv_m: np.ndarray,
                     f_target_hz, shapes, k_N_m=None) -> ShapeCalibration:
    """Fit the inertia of the module docstring so that the lowest ``len(f_target_hz)``
    eigenmodes at ``q_ref_rad`` have the planted frequencies ``f_target_hz`` (ascending)
    and tool-tip shapes ``shapes`` ``(m, 3)`` (and, where given, tool-tip stiffness
    ``k_N_m`` ``(m,)``: the second stage); ``Jv_m`` the TCP's translational Jacobian at
    q_ref. Deterministic (seeded starts)."""
    from scipy.optimize import least_squares

    K = np.asarray(K_Nm_rad, float)
    f = np.asarray(f_target_hz, float)
    order = np.argsort(f, kind="stable")
    if not np.array_equal(order, np.arange(f.size)):
        raise ValueError("synth.modes: the planted robot modes must be listed by ascending "
                         "f_hz (expected ascending frequencies)")
    n = K.size
    if f.size > n:
        raise ValueError(f"synth.modes: {f.size} planted robot modes, but the robot's {n} "
                         f"joints give {n} (expected at most {n})")
    b = _bodies(model, q_ref_rad)
    fit = _Fit(b, K, np.asarray(Jv_m, float), f, np.asarray(shapes, float).reshape(-1, 3),
               k_N_m)
    M0 = b.P.sum(axis=0)
    a0 = 1e-2 * np.trace(M0) / n
    if not a0 > 0.0:
        a0 = float(np.mean(K)) / (2 * np.pi * f[0]) ** 2
    link_kg = np.array([model.inertias[i + 1].mass for i in range(n)])
    g = GYRATION_M * np.sqrt(np.maximum(link_kg, 1e-3 * max(link_kg.max(), 1.0)))
    x0 = np.r_[np.zeros(n), np.full(n, np.log(a0)),
               np.tile([1.0, 0.0, 1.0, 0.0, 0.0, 1.0], (n, 1)).ravel() * np.repeat(g, 6)]

    def fun(x):
        return np.r_[fit.evaluate(x)[0], PULL * (x - x0)]

    def jac(x):
        return np.vstack([fit.evaluate(x)[1], PULL * np.eye(x.size)])

    # the log-parameters within e^±BOUND of the start; the Cholesky factors within
    # BOUND × GYRATION_M-scaled magnitudes
    lo = np.r_[x0[:2 * n] - BOUND, np.repeat(-BOUND * 10 * g, 6)]
    hi = np.r_[x0[:2 * n] + BOUND, np.repeat(BOUND * 10 * g, 6)]
    rng = np.random.default_rng(SEED)
    best = None
    for k in range(STARTS):
        start = x0 if k == 0 else np.clip(x0 + rng.normal(0.0, 1.0, x0.size), lo, hi)
        r = least_squares(fun, start, jac=jac, bounds=(lo, hi), max_nfev=SCREEN_NFEV,
                          tr_solver="lsmr")
        if best is None or r.cost < best.cost:
            best = r
    best = least_squares(fun, best.x, jac=jac, bounds=(lo, hi), max_nfev=MAX_NFEV,
                         tr_solver="lsmr")
    if fit.log_k is not None:
        # second stage: from the shapes' fit, the tool-tip stiffness joins the objective
        fit.with_stiffness, fit._memo = True, (None, None)
        best = least_squares(fun, best.x, jac=jac, bounds=(lo, hi), max_nfev=MAX_NFEV,
                             tr_solver="lsmr")
    _, _, lam, u, visible, tip_norm = fit.evaluate(best.x)
    s, a, L = _unpack(best.x, n)
    mac = np.einsum("kr,rk->r", u, fit.phi) ** 2
    kappa = np.where(visible, lam[:f.size] / tip_norm**2, np.inf)
    return ShapeCalibration(s, a, np.einsum("lik,ljk->lij", L, L),
                            np.sqrt(lam[:f.size]) / (2 * np.pi), f, mac, visible, kappa,
                            float(best.cost))
