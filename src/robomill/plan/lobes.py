"""Zero-order stability lobes of many tool-tip models at once (the planner's fast grid).

The same method as :mod:`robomill.chatter.lobes_zoa` (Altintas & Budak 1995; Altintas 2012
§4.3): for each eigenvalue λ of W̄ G(jω), 1/λ = u + jv, a sustained chatter at ω needs
a_lim = (u² + v²)/(2u) (u > 0) at the spindle speed n = 60/(N τ), ωτ = 2 atan2(u, v) + 2kπ;
the lobe diagram is the lower envelope of all branches. Here every array carries a leading
batch axis (one tool model per robot pose), the 2 × 2 eigenvalues are taken in closed form,
and the envelope is found by scattering each branch segment onto the speeds it spans, so a
grid of poses × speeds costs a few array passes instead of one solver call per pose.

The receptance of modes (f_r, ζ_r, k_r, in-plane shape φ_r) is the modal sum
G(jω) = Σ_r φ_r φ_rᵀ / (k_r (1 − ρ² + 2jζ_r ρ)), ρ = ω/ω_r (the FRF of
:func:`robomill.chatter.model.tool_from_modes`).
"""

from __future__ import annotations

import numpy as np

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


def _left_multiply(W: np.ndarray, G: np.ndarray) -> np.ndarray:
    """W G for one real 2 × 2 ``W`` and a stack ``(..., 2, 2)``, written out (faster than a
    general product for 2 × 2 blocks)."""
    out = np.empty_like(G)
    for i in range(2):
        for j in range(2):
            out[..., i, j] = W[i, 0] * G[..., 0, j] + W[i, 1] * G[..., 1, j]
    return out


def _eig2(A: np.ndarray) -> np.ndarray:
    """Eigenvalues ``(..., 2)`` of 2 × 2 matrices ``(..., 2, 2)`` in closed form."""
    tr = A[..., 0, 0] + A[..., 1, 1]
    det = A[..., 0, 0] * A[..., 1, 1] - A[..., 0, 1] * A[..., 1, 0]
    disc = np.sqrt(tr**2 / 4 - det + 0j)
    return np.stack([tr / 2 + disc, tr / 2 - disc], -1)


def _track(lam: np.ndarray) -> np.ndarray:
    """Order the two eigenvalues along the frequency axis (axis 1 of ``(B, nf, 2)``) so each
    column is a continuous branch (the rule of :func:`robomill.chatter.lobes_zoa._track`).

    Swapping at frequency i is decided by comparing the raw pairs i and i − 1; since a swap at
    i − 1 exchanges both costs, the output is flipped wherever an odd number of raw steps
    preferred the swap: a cumulative parity, without a loop over frequencies."""
    d = lam[:, 1:] - lam[:, :-1]
    keep = np.abs(d[..., 0]) + np.abs(d[..., 1])
    swap = np.abs(lam[:, 1:, 1] - lam[:, :-1, 0]) + np.abs(lam[:, 1:, 0] - lam[:, :-1, 1])
    flip = np.concatenate([np.zeros((lam.shape[0], 1), bool),
                           (np.cumsum(swap < keep, axis=1) % 2).astype(bool)], axis=1)
    return np.where(flip[..., None], lam[..., ::-1], lam)


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
    n_t = np.sort(np.atleast_1d(np.asarray(spindle_rpm, float)))
    order = np.argsort(np.atleast_1d(np.asarray(spindle_rpm, float)))
    f = frequency_grid(fn) if f_hz is None else np.asarray(f_hz, float)
    W = cut.mean_matrix()
    n_lobes = int(np.ceil(f.max() * 60.0 / (cut.teeth * n_t.min()))) + 2
    out = np.full((fn.shape[0], n_t.size), np.inf)
    z = np.broadcast_to(np.asarray(zeta, float), fn.shape)
    for b0 in range(0, fn.shape[0], chunk):
        sl = slice(b0, b0 + chunk)
        G = receptance(f, fn[sl], z[sl], k[sl], shape[sl])
        lam = _track(_eig2(_left_multiply(W, G)))               # (b, nf, 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / np.where(np.abs(lam) > 0, lam, np.nan)
            u, v = inv.real, inv.imag
            a = np.where(u > 0, (u**2 + v**2) / (2 * u), np.inf)
        a = np.nan_to_num(a, nan=np.inf)
        eps = 2 * np.arctan2(u, v)
        nb = lam.shape[0]
        env = np.full((nb, n_t.size), np.inf)
        for kk in range(n_lobes):
            with np.errstate(divide="ignore", invalid="ignore"):
                rpm = 60.0 * 2 * np.pi * f[None, :, None] / (cut.teeth * (eps + 2 * np.pi * kk))
            _scatter_min(env, rpm, a, n_t)
        out[sl] = env
    res = np.empty_like(out)
    res[:, order] = out
    return res


def _scatter_min(env: np.ndarray, rpm: np.ndarray, a: np.ndarray, n_t: np.ndarray) -> None:
    """Lower the envelope ``env`` ``(b, ns)`` with every branch segment (consecutive
    frequencies of ``rpm``, ``a`` ``(b, nf, e)``) at the sorted speeds ``n_t`` it spans, by
    linear interpolation along the segment (as :func:`robomill.chatter.lobes_zoa.zoa_lobes`)."""
    n0, n1 = rpm[:, :-1], rpm[:, 1:]
    a0, a1 = a[:, :-1], a[:, 1:]
    ok = np.isfinite(a0) & np.isfinite(a1) & np.isfinite(n0) & np.isfinite(n1)
    lo, hi = np.minimum(n0, n1), np.maximum(n0, n1)
    ok &= (hi >= n_t[0]) & (lo <= n_t[-1])
    bi, fi, ei = np.nonzero(ok)
    if bi.size == 0:
        return
    lo_s, hi_s = lo[bi, fi, ei], hi[bi, fi, ei]
    i0 = np.searchsorted(n_t, lo_s, "left")
    i1 = np.searchsorted(n_t, hi_s, "right")
    cnt = i1 - i0
    keep = cnt > 0
    if not keep.any():
        return
    bi, fi, ei, i0, cnt = bi[keep], fi[keep], ei[keep], i0[keep], cnt[keep]
    rep = np.repeat(np.arange(bi.size), cnt)
    offs = np.arange(rep.size) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    ti = i0[rep] + offs
    b, f_, e = bi[rep], fi[rep], ei[rep]
    N0, N1 = n0[b, f_, e], n1[b, f_, e]
    A0, A1 = a0[b, f_, e], a1[b, f_, e]
    span = N1 - N0
    w = np.where(span != 0, (n_t[ti] - N0) / np.where(span != 0, span, 1.0), 0.0)
    np.minimum.at(env, (b, ti), A0 + w * (A1 - A0))


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
    as :func:`robomill.chatter.thesis.mode_coupling`), by a log scan up to ``depth_max_m`` and
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
