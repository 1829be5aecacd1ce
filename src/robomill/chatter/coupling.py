"""The tool tip's receptance as a modal sum, its state space, and the delay-free
mode-coupling depth: the one routine of each that chapter 4, the planner's stability model
(:mod:`robomill.plan.stability`) and its diagnostics use.

The receptance of modes (f_r, ζ_r, k_r, shape φ_r: in-plane, or with its axial component) is
the modal sum G(jω) = Σ_r φ_r,xy φ_rᵀ / (k_r (1 − ρ² + 2jζ_r ρ)), ρ = ω/ω_r [Ewins 2000]:
the in-plane response to each force component (the FRF of
:func:`robomill.chatter.model.tool_from_modes`).

The mode-coupling depth is the smallest depth a at which ṡ = (A + a B W̄ C) s, the modes
with the oriented cutting stiffness acting on the current displacement and no delay, has an
unstable eigenvalue (Tlusty's mode coupling; [Pan et al. 2006] for robots). It drops the
regenerative factor (1 − e^{−jωτ}) that a slot's chip always carries, so it is a diagnostic
(chapter 4), never a stability limit of a plan.
"""

from __future__ import annotations

import numpy as np

from robomill.chatter.model import CuttingModel, conform_rows


def receptance(f_hz: np.ndarray, fn_hz: np.ndarray, zeta: np.ndarray, k_N_m: np.ndarray,
               shape: np.ndarray) -> np.ndarray:
    """Modal-sum receptance ``(B, nf, 2, d)`` [m/N] of B tool models.

    Parameters
    ----------
    f_hz
        Frequencies ``(nf,)``.
    fn_hz, k_N_m
        ``(B, M)`` natural frequencies and modal stiffnesses.
    zeta
        ``(M,)`` or ``(B, M)`` damping ratios.
    shape
        ``(B, M, d)`` mode shapes (feed, normal) or (feed, normal, axis).
    """
    f = np.asarray(f_hz, float)
    r = f[None, :, None] / np.asarray(fn_hz, float)[:, None, :]          # (B, nf, M)
    z = np.broadcast_to(np.asarray(zeta, float), np.shape(fn_hz))[:, None, :]
    h = 1.0 / (np.asarray(k_N_m, float)[:, None, :] * ((1 - r**2) + 2j * z * r))
    phi = np.asarray(shape, float)
    d = phi.shape[-1]
    outer = (phi[:, :, :2, None] * phi[:, :, None, :]).reshape(phi.shape[0], phi.shape[1], 2 * d)
    # the sum over modes as a stacked matrix product (BLAS): a third of the time of the same
    # sum by einsum on the planner's grid, equal to it within rounding (1e-16 relative)
    return np.matmul(h, outer.astype(h.dtype)).reshape(h.shape[:2] + (2, d))


def state_space(fn_hz: np.ndarray, zeta: np.ndarray, k_N_m: np.ndarray, shape: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Modal state-space matrices of B tool models at once (as
    :func:`robomill.chatter.model.tool_from_modes`): A ``(B, 2M, 2M)``, B ``(B, 2M, d)``,
    C ``(B, 2, 2M)`` for shapes ``(B, M, d)``."""
    fn = np.atleast_2d(np.asarray(fn_hz, float))
    nb, M = fn.shape
    w = 2 * np.pi * fn
    z = np.broadcast_to(np.asarray(zeta, float), fn.shape)
    k = np.atleast_2d(np.asarray(k_N_m, float))
    phi = np.asarray(shape, float)
    phi = phi.reshape(nb, M, phi.shape[-1])
    A = np.zeros((nb, 2 * M, 2 * M))
    Bm = np.zeros((nb, 2 * M, phi.shape[-1]))
    C = np.zeros((nb, 2, 2 * M))
    i = 2 * np.arange(M)
    A[:, i, i + 1] = 1.0
    A[:, i + 1, i] = -(w**2)
    A[:, i + 1, i + 1] = -2 * z * w
    Bm[:, i + 1, :] = phi / (k / w**2)[..., None]
    C[:, :, i] = np.swapaxes(phi[..., :2], 1, 2)
    return A, Bm, C


def coupling_depth(fn_hz: np.ndarray, zeta: np.ndarray, k_N_m: np.ndarray, shape: np.ndarray,
                   cut: CuttingModel, *, depth_max_m: float = 0.02, n_scan: int = 60,
                   rtol: float = 1e-4, upper: bool = False
                   ) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Mode-coupling depth ``(B,)`` [m] of B tool models (module docstring): a log scan of
    ``n_scan`` depths from ``depth_max_m``/10⁴ to ``depth_max_m``, then bisection of the first
    unstable interval until its width is below ``rtol`` of its upper end; the middle of that
    interval; +inf where stable up to ``depth_max_m``. ``upper``: also the interval's upper
    end (the shallowest depth found unstable)."""
    A, Bm, C = state_space(fn_hz, zeta, k_N_m, shape)
    BWC = Bm @ conform_rows(cut.mean_matrix(), Bm.shape[-1]) @ C

    def unstable(a, idx):
        lam = np.linalg.eigvals(A[idx] + np.asarray(a)[:, None, None] * BWC[idx])
        return lam.real.max(-1) > 0

    nb = len(A)
    every = np.arange(nb)
    scan = np.geomspace(depth_max_m / 1e4, depth_max_m, n_scan)
    bad = np.stack([unstable(np.full(nb, a), every) for a in scan], 1)        # (B, n_scan)
    first = np.where(bad.any(1), np.argmax(bad, 1), -1)
    hi = np.where(first >= 0, scan[np.maximum(first, 0)], np.inf)
    lo = np.where(first > 0, scan[np.maximum(first - 1, 0)], 0.0)
    todo = np.isfinite(hi) & (hi - lo > rtol * hi)
    while todo.any():
        idx = np.flatnonzero(todo)
        mid = 0.5 * (lo[idx] + hi[idx])
        u = unstable(mid, idx)
        hi[idx] = np.where(u, mid, hi[idx])
        lo[idx] = np.where(u, lo[idx], mid)
        todo = np.isfinite(hi) & (hi - lo > rtol * hi)
    mid = np.where(np.isfinite(hi), 0.5 * (lo + hi), np.inf)
    return (mid, hi) if upper else mid
