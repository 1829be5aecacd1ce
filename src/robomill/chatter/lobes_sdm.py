"""First-order semi-discretization of the regenerative milling model (Insperger & Stépán 2004).

The periodic delay-differential equation ṡ = (A + a B W(t) C) s − a B W(t) C s(t − τ)
(:mod:`robomill.chatter.model`) is discretized on m equal steps h = τ/m per tooth period:
on [t_i, t_{i+1}] the periodic coefficient is replaced by its exact average W̄_i and the
delayed output d = C s by the linear interpolation of d_{i−m}, d_{i−m+1}
(Insperger & Stépán 2004, IJNME 61, eqs. 8–12, "first-order" semi-discretization). With
P_i = e^{A_i h}, J0 = ∫₀ʰ e^{A_i u} du, J1 = ∫₀ʰ e^{A_i(h−s)} s/h ds (one block exponential):

.. math:: s_{i+1} = P_i s_i + (J_0 - J_1) B_i d_{i-m} + J_1 B_i d_{i-m+1},
          \\quad B_i = -a B \\bar W_i,\\ A_i = A + a B \\bar W_i C

Only the 2-D delayed output is stored, so the monodromy matrix Φ over one period has size
n_s + 2m. The cut is asymptotically stable when the spectral radius ρ(Φ) < 1; a critical
multiplier μ = +1 is a fold, μ = −1 a flip (period doubling), complex μ a secondary Hopf.
"""

from __future__ import annotations

from collections import OrderedDict
from functools import lru_cache

import numpy as np
import scipy.linalg

from robomill.chatter.model import CuttingModel, LinearTool, conform_rows, lobe_parameters
from robomill.settings import schema_default

STEPS_PER_PERIOD = 40
"""Default steps per tooth period (the value of Insperger & Stépán 2004 and Ding et al. 2010).
The method is second order: on the a_e/D = 0.05 benchmark at 6400 rpm m = 40 is +3.1 % above
the converged depth, m = 80 +0.75 %, m = 160 +0.18 % (tests/test_chatter_sem.py); converged
lobes come from :mod:`robomill.chatter.lobes_sem`."""


SCAN_CHUNK = 2
"""Depths of the scan evaluated per batch, lowest first: the scan stops at the first unstable
one (the depths above it are not needed), so a boundary in the lower half of the scan costs
half the eigenvalue problems. Each depth's numbers do not depend on the batch it is in."""
_EIGEN_CACHE: OrderedDict[tuple, tuple] = OrderedDict()
_EIGEN_CACHE_SIZE = 16


def _eigen_parts(Ai: np.ndarray):
    """Eigenvalues λ, eigenvectors V, V⁻¹ and the well-conditioned mask of a stack of A_i.

    A_i = A + a B W̄_i C does not depend on the speed (only h = τ/m does), and every speed of a
    lobe diagram scans the same depths: a scan batch's decomposition is kept
    (:data:`_EIGEN_CACHE`, keyed by the shape and bytes of the stack, so a hit returns exactly
    what the decomposition would) and each further speed only rescales the eigenvalues by h."""
    key = (Ai.shape, Ai.tobytes()) if Ai.shape[0] > 1 else None  # bisections never recur
    if key is not None and key in _EIGEN_CACHE:
        _EIGEN_CACHE.move_to_end(key)
        return _EIGEN_CACHE[key]
    lam, V = np.linalg.eig(Ai)
    cond = np.linalg.cond(V)
    ok = np.isfinite(cond) & (cond < 1e8)
    Vinv = np.linalg.inv(np.where(ok[..., None, None], V, np.eye(V.shape[-1])))
    parts = (lam, V, Vinv, ok)
    if key is not None:
        _EIGEN_CACHE[key] = parts
        while len(_EIGEN_CACHE) > _EIGEN_CACHE_SIZE:
            _EIGEN_CACHE.popitem(last=False)
    return parts


def _exp_integrals(Ai: np.ndarray, h: float):
    """e^{A h}, J0 = ∫₀ʰ e^{Au} du and J1 = ∫₀ʰ e^{A(h−s)} s/h ds for a stack of matrices.

    Through the eigen-decomposition A = V Λ V⁻¹ (φ-functions of the eigenvalues, with series
    near λh = 0; :func:`_eigen_parts`); matrices whose eigenvector basis is ill-conditioned
    (near-defective) fall back to the block exponential
    expm([[A, I, 0], [0, 0, I], [0, 0, 0]] h) (Van Loan 1978).
    """
    lam, V, Vinv, ok = _eigen_parts(Ai)
    z = lam * h
    small = np.abs(z) < 1e-5
    zs = np.where(small, 1.0, z)
    e = np.exp(z)
    f0 = np.where(small, h * (1 + z / 2 + z**2 / 6), (e - 1) / zs * h)
    f1 = np.where(small, h * (0.5 + z / 6 + z**2 / 24), (e - 1 - zs) / zs**2 * h)

    def back(d):
        return ((V * d[..., None, :]) @ Vinv).real

    P, J0, J1 = back(e), back(f0), back(f1)
    if not ok.all():
        n = Ai.shape[-1]
        bad = ~ok
        M = np.zeros(Ai[bad].shape[:-2] + (3 * n, 3 * n))
        M[..., :n, :n] = Ai[bad] * h
        M[..., :n, n:2 * n] = np.eye(n) * h
        M[..., n:2 * n, 2 * n:] = np.eye(n) * h
        E = scipy.linalg.expm(M)
        P[bad], J0[bad], J1[bad] = E[..., :n, :n], E[..., :n, n:2 * n], E[..., :n, 2 * n:] / h
    return P, J0, J1


@lru_cache(maxsize=32)
def _interval_means(cut: CuttingModel, m: int) -> np.ndarray:
    """:meth:`CuttingModel.interval_means`, once per cutting model and m (it depends on
    neither the speed nor the depth); read-only, as it is shared."""
    Wm = cut.interval_means(m)
    Wm.setflags(write=False)
    return Wm


def _step_matrices(tool: LinearTool, Wm: np.ndarray, depths_m: np.ndarray, h: float):
    """P, R0 = (J0 − J1)B_i, R1 = J1 B_i for every depth and step: ``(na, m, n, n|2)``."""
    a = np.asarray(depths_m, float)[:, None, None, None]
    BW = np.einsum("ik,mkl->mil", tool.B, conform_rows(Wm, tool.n_inputs))  # (m, n, 2)
    Ai = tool.A[None, None] + a * np.einsum("mil,lj->mij", BW, tool.C)[None]
    P, J0, J1 = _exp_integrals(Ai, h)
    Bi = -a * BW[None]  # (na, m, n, 2)
    return P, (J0 - J1) @ Bi, J1 @ Bi


def monodromy(tool: LinearTool, cut: CuttingModel, spindle_rpm: float, depths_m: np.ndarray,
              m: int = STEPS_PER_PERIOD) -> np.ndarray:
    """Monodromy matrices Φ(a) over one tooth period, ``(len(depths), n_s + 2m, n_s + 2m)``.

    Propagates all basis vectors at once (a column recursion over the m steps), so the cost is
    m small matrix products per depth instead of m dense products of the full Φ.
    """
    if m < 2:
        raise ValueError("the semi-discretization needs m >= 2 steps per period")
    depths = np.atleast_1d(np.asarray(depths_m, float))
    tau = 60.0 / (cut.teeth * float(spindle_rpm))
    P, R0, R1 = _step_matrices(tool, _interval_means(cut, m), depths, tau / m)
    n = tool.n_states
    dim = n + 2 * m
    eye = np.broadcast_to(np.eye(dim), (depths.size, dim, dim))
    X = eye[:, :n, :].copy()
    D = [eye[:, n + 2 * j:n + 2 * j + 2, :].copy() for j in range(m)]  # d_{i-1} … d_{i-m}
    C = tool.C
    for i in range(m):
        X_new = P[:, i] @ X + R0[:, i] @ D[m - 1] + R1[:, i] @ D[m - 2]
        D = [C @ X] + D[:-1]
        X = X_new
    return np.concatenate([X, *D], axis=1)


def sdm_spectral_radius(tool: LinearTool, cut: CuttingModel, spindle_rpm: float,
                        depths_m: np.ndarray, m: int = STEPS_PER_PERIOD
                        ) -> tuple[np.ndarray, np.ndarray]:
    """Spectral radius ρ(Φ) and the critical multiplier μ for each depth (ρ < 1: stable)."""
    mu = np.linalg.eigvals(monodromy(tool, cut, spindle_rpm, depths_m, m))
    idx = np.argmax(np.abs(mu), axis=-1)
    crit = np.take_along_axis(mu, idx[:, None], -1)[:, 0]
    return np.abs(crit), crit


def classify_multiplier(mu: complex, tol_rad: float = 1e-3) -> str:
    """``fold`` (μ real > 0), ``flip`` (μ real < 0, period doubling) or ``hopf``."""
    ang = abs(np.angle(mu))
    if ang < tol_rad:
        return "fold"
    if abs(ang - np.pi) < tol_rad:
        return "flip"
    return "hopf"


def multiplier_frequency_hz(mu: complex, tau_s: float, f_ref_hz: float) -> float:
    """Chatter frequency from the critical multiplier: f = (arg μ/2π + k)/τ (k integer, both
    signs of arg μ), the candidate nearest f_ref (Insperger et al. 2003 frequency families)."""
    base = abs(np.angle(mu)) / (2 * np.pi)
    k = np.arange(-1, int(f_ref_hz * tau_s) + 3)
    cand = np.concatenate([(base + k) / tau_s, (k + 1 - base) / tau_s])
    cand = cand[cand > 0]
    return float(cand[np.argmin(np.abs(cand - f_ref_hz))])


def reference_frequencies_hz(tool: LinearTool, n_speeds: int,
                             f_ref_hz: np.ndarray | None = None) -> np.ndarray:
    """Reference frequency per speed for naming a multiplier's chatter frequency
    (:func:`multiplier_frequency_hz`): ``f_ref_hz`` where finite, else the tool's lowest
    natural frequency; without ``f_ref_hz`` the most flexible natural frequency (largest summed
    |H| at resonance) at every speed."""
    fn = tool.natural_frequencies_hz()
    if f_ref_hz is None:
        mag = np.abs(tool.frf(fn)).sum(axis=(0, 1))
        return np.full(n_speeds, fn[np.argmax(mag)])
    return np.where(np.isfinite(f_ref_hz), f_ref_hz, fn[0])


def critical_depth(tool: LinearTool, cut: CuttingModel, spindle_rpm: float, *,
                   depth_max_m: float, m: int = STEPS_PER_PERIOD, n_scan: int = 16,
                   rtol: float = schema_default("chatter.seed", "rtol"),
                   depth_min_m: float | None = None
                   ) -> tuple[float, complex]:
    """Smallest unstable axial depth at one speed: a geometric scan of ``n_scan`` depths up to
    ``depth_max_m`` finds the first unstable one (so unstable islands above a stable band are
    not missed at the scan resolution), then bisection to a relative bracket ``rtol``.

    Returns
    -------
    a_crit_m, mu : the bracket midpoint (nan if stable up to ``depth_max_m``) and the critical
        multiplier at the unstable end of the bracket.
    """
    lo_scan = depth_min_m if depth_min_m is not None else depth_max_m / 300.0
    scan = np.geomspace(lo_scan, depth_max_m, n_scan)
    for start in range(0, n_scan, SCAN_CHUNK):  # lowest depths first, up to the first unstable
        rho, mu = sdm_spectral_radius(tool, cut, spindle_rpm, scan[start:start + SCAN_CHUNK], m)
        bad = np.nonzero(rho >= 1.0)[0]
        if bad.size:
            break
    if bad.size == 0:
        return float("nan"), complex(mu[-1])
    j = start + int(bad[0])
    hi, mu_hi = scan[j], complex(mu[bad[0]])
    lo = scan[j - 1] if j > 0 else 0.0
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        r, u = sdm_spectral_radius(tool, cut, spindle_rpm, [mid], m)
        if r[0] >= 1.0:
            hi, mu_hi = mid, complex(u[0])
        else:
            lo = mid
    return 0.5 * (lo + hi), mu_hi


@lobe_parameters
def sdm_lobes(tool: LinearTool, cut: CuttingModel, spindle_rpm: np.ndarray, *,
              depth_max_m: float, m: int = STEPS_PER_PERIOD, n_scan: int = 16,
              rtol: float = schema_default("chatter.seed", "rtol"),
              f_ref_hz: np.ndarray | None = None,
              progress=None):
    """Semi-discretization lobe diagram on a speed grid.

    Parameters
    ----------
    {lobe: tool, cut; spindle_rpm; depth_max_m}
    m
        Steps per tooth period (see :data:`STEPS_PER_PERIOD`).
    rtol
        Relative resolution of the critical depth (0.005 = 0.5 %).
    {lobe: f_ref_hz}

    Returns
    -------
    a_crit_m, chatter_hz, kind : arrays over the speeds (kind: fold, flip, hopf or '').
    """
    n_t = np.atleast_1d(np.asarray(spindle_rpm, float))
    f_ref = reference_frequencies_hz(tool, n_t.size, f_ref_hz)
    a_out = np.full(n_t.shape, np.nan)
    f_out = np.full(n_t.shape, np.nan)
    kind = np.full(n_t.shape, "", dtype=object)
    for i, n in enumerate(n_t):
        if progress is not None:  # fraction of the speed grid done (for long maps' logs)
            progress(i / len(n_t))
        a, mu = critical_depth(tool, cut, n, depth_max_m=depth_max_m, m=m, n_scan=n_scan,
                               rtol=rtol)
        a_out[i] = a
        if np.isfinite(a):
            tau = 60.0 / (cut.teeth * n)
            kind[i] = classify_multiplier(mu)
            f_out[i] = multiplier_frequency_hz(mu, tau, f_ref[i])
    return a_out, f_out, kind.astype(str)
