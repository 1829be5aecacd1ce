"""Stability limits of many tool-tip models at once (the planner's fast grid).

Zero-order lobes (Altintas & Budak 1995; Altintas 2012 §4.3) by the one routine,
:func:`robomill.chatter.lobes_zoa.zoa_envelope`, given here every pose's modal-sum receptance
(one tool model per robot pose) on the planner's frequency grid (:func:`frequency_grid`), so
a grid of poses × speeds costs a few array passes instead of one solver call per pose; and
the delay-free mode-coupling depth (:func:`batch_coupling_depth`).

The receptance of modes (f_r, ζ_r, k_r, in-plane shape φ_r) is the modal sum
G(jω) = Σ_r φ_r φ_rᵀ / (k_r (1 − ρ² + 2jζ_r ρ)), ρ = ω/ω_r (the FRF of
:func:`robomill.chatter.model.tool_from_modes`).
"""

from __future__ import annotations

import numpy as np

from robomill.chatter.lobes_zoa import zoa_envelope
from robomill.chatter.model import CuttingModel


def receptance(f_hz: np.ndarray, fn_hz: np.ndarray, zeta: np.ndarray, k_N_m: np.ndarray,
               shape: np.ndarray) -> np.ndarray:
    """Modal-sum receptance ``(B, nf, 2, 2)`` [m/N] of B tool models.

    Parameters
    ----------
    f_hz
        Frequencies ``(nf,)``.
    fn_hz, k_N_m
        ``(B, M)`` natural frequencies and modal stiffnesses.
    zeta
        ``(M,)`` or ``(B, M)`` damping ratios.
    shape
        ``(B, M, 2)`` in-plane mode shapes (feed, normal).
    """
    f = np.asarray(f_hz, float)
    r = f[None, :, None] / np.asarray(fn_hz, float)[:, None, :]          # (B, nf, M)
    z = np.broadcast_to(np.asarray(zeta, float), np.shape(fn_hz))[:, None, :]
    h = 1.0 / (np.asarray(k_N_m, float)[:, None, :] * ((1 - r**2) + 2j * z * r))
    phi = np.asarray(shape, float)
    outer = (phi[:, :, :, None] * phi[:, :, None, :]).reshape(phi.shape[0], phi.shape[1], 4)
    return np.einsum("bfm,bmi->bfi", h, outer).reshape(h.shape[:2] + (2, 2))


def frequency_grid(fn_hz: np.ndarray, n: int = 3000, n_fine: int = 300) -> np.ndarray:
    """Chatter frequencies covering every batch member's modes: log-spaced over
    [0.3 min f_n, 3 max f_n] plus a fine linear grid around each mode's range of frequencies
    over the batch (±20 %)."""
    fn = np.asarray(fn_hz, float)
    grids = [np.geomspace(0.3 * fn.min(), 3 * fn.max(), n)]
    grids += [np.linspace(0.8 * lo, 1.2 * hi, n_fine) for lo, hi in zip(fn.min(0), fn.max(0),
                                                                          strict=True)]
    return np.unique(np.concatenate(grids))


def batch_zoa_lobes(fn_hz: np.ndarray, zeta: np.ndarray, k_N_m: np.ndarray, shape: np.ndarray,
                    cut: CuttingModel, spindle_rpm: np.ndarray, *, f_hz: np.ndarray | None = None,
                    chunk: int = 64) -> np.ndarray:
    """Critical axial depth ``(B, len(spindle_rpm))`` [m] of B tool models (zero-order lobes,
    lower envelope of every lobe and eigenvalue branch; +inf where no branch reaches a speed:
    no regenerative chatter possible there).

    Examples
    --------
    >>> from robomill.chatter import ModeXY, tool_from_modes, zoa_lobes
    >>> cut = CuttingModel.from_immersion(2, 6e8, 0.3, 1.0, "down")
    >>> rpm = np.array([3000.0, 6000.0])
    >>> a = batch_zoa_lobes([[500.0]], [0.02], [[1e7]], [[[0.0, 1.0]]], cut, rpm)
    >>> a_ref, _ = zoa_lobes(tool_from_modes([ModeXY(500.0, 0.02, 1e7, (0.0, 1.0))]), cut, rpm)
    >>> bool(np.allclose(a[0], a_ref, rtol=1e-3))
    True
    """
    fn = np.atleast_2d(np.asarray(fn_hz, float))
    k = np.atleast_2d(np.asarray(k_N_m, float))
    shape = np.asarray(shape, float).reshape(fn.shape + (2,))
    f = frequency_grid(fn) if f_hz is None else np.asarray(f_hz, float)
    z = np.broadcast_to(np.asarray(zeta, float), fn.shape)
    out = [zoa_envelope(receptance(f, fn[sl], z[sl], k[sl], shape[sl]), f, cut, spindle_rpm)
           for sl in (slice(b0, b0 + chunk) for b0 in range(0, fn.shape[0], chunk))]
    return np.concatenate(out, axis=0)


def state_space(fn_hz: np.ndarray, zeta: np.ndarray, k_N_m: np.ndarray, shape: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Modal state-space matrices of B tool models at once (as
    :func:`robomill.chatter.model.tool_from_modes`): A ``(B, 2M, 2M)``, B ``(B, 2M, 2)``,
    C ``(B, 2, 2M)``."""
    fn = np.atleast_2d(np.asarray(fn_hz, float))
    nb, M = fn.shape
    w = 2 * np.pi * fn
    z = np.broadcast_to(np.asarray(zeta, float), fn.shape)
    k = np.atleast_2d(np.asarray(k_N_m, float))
    phi = np.asarray(shape, float).reshape(nb, M, 2)
    A = np.zeros((nb, 2 * M, 2 * M))
    Bm = np.zeros((nb, 2 * M, 2))
    C = np.zeros((nb, 2, 2 * M))
    i = 2 * np.arange(M)
    A[:, i, i + 1] = 1.0
    A[:, i + 1, i] = -(w**2)
    A[:, i + 1, i + 1] = -2 * z * w
    Bm[:, i + 1, :] = phi / (k / w**2)[..., None]
    C[:, :, i] = np.swapaxes(phi, 1, 2)
    return A, Bm, C


def batch_coupling_depth(fn_hz: np.ndarray, zeta: np.ndarray, k_N_m: np.ndarray,
                         shape: np.ndarray, cut: CuttingModel, *, depth_max_m: float = 0.02,
                         n_scan: int = 40, n_bisect: int = 12) -> np.ndarray:
    """Mode-coupling depth ``(B,)`` [m]: the smallest depth a at which ṡ = (A + a B W̄ C) s has
    an unstable eigenvalue (the delay-free oriented cutting stiffness; Tlusty's mode coupling,
    as :func:`robomill.chatter.slot_model.mode_coupling`), by a log scan up to ``depth_max_m`` and
    bisection; +inf where stable up to ``depth_max_m``. The zero-order lobes miss this limit
    when the tooth frequency is far above the modes (the robot's structure)."""
    A, Bm, C = state_space(fn_hz, zeta, k_N_m, shape)
    BWC = Bm @ cut.mean_matrix() @ C

    def unstable(a):
        lam = np.linalg.eigvals(A + np.asarray(a)[..., None, None] * BWC)
        return lam.real.max(-1) > 0

    scan = np.geomspace(depth_max_m / 1e4, depth_max_m, n_scan)
    bad = np.stack([unstable(np.full(len(A), a)) for a in scan], 1)        # (B, n_scan)
    first = np.where(bad.any(1), np.argmax(bad, 1), -1)
    hi = np.where(first >= 0, scan[np.maximum(first, 0)], np.inf)
    lo = np.where(first > 0, scan[np.maximum(first - 1, 0)], 0.0)
    todo = np.isfinite(hi)
    if todo.any():
        lo_t, hi_t = lo[todo], hi[todo]
        sub = (A[todo], BWC[todo])
        for _ in range(n_bisect):
            mid = 0.5 * (lo_t + hi_t)
            lam = np.linalg.eigvals(sub[0] + mid[:, None, None] * sub[1])
            u = lam.real.max(-1) > 0
            hi_t = np.where(u, mid, hi_t)
            lo_t = np.where(u, lo_t, mid)
        hi[todo] = 0.5 * (lo_t + hi_t)
    return hi
