"""Zero-order analytical stability lobes (Altintas & Budak 1995; Altintas 2012 §4.3).

With the tooth-period average W̄ of the directional matrix, a harmonic chatter vibration at ω
is sustained when det(I − a(1 − e^{−jωτ}) W̄ G(jω)) = 0. For each eigenvalue λ of W̄G(jω),
writing 1/λ = u + jv:

.. math:: a_{lim} = \\frac{u^2 + v^2}{2u}\\ (u > 0),\\qquad
          \\omega\\tau = 2\\,\\mathrm{atan2}(u, v) + 2k\\pi,\\qquad n = \\frac{60}{N\\tau}

which is Altintas' a_lim = −2πΛ_R(1 + κ²)/(N K_t), ψ = atan κ, ε = π − 2ψ, τ = (ε + 2kπ)/ω_c
written with the eigenvalue of W̄G (W̄ = N K_t α/(4π)). For a single mode in one direction it
reduces to the closed form a_lim = 1/(2 W̄_dd Re G_dd).
"""

from __future__ import annotations

import numpy as np

from robomill.chatter.model import CuttingModel, LinearTool, lobe_parameters


def _track(lam: np.ndarray) -> np.ndarray:
    """Order the two eigenvalues at each frequency so each column is a continuous branch
    (eigvals returns them in arbitrary order; a swap would join points of different lobes)."""
    out = lam.copy()
    for i in range(1, len(out)):
        keep = abs(out[i, 0] - out[i - 1, 0]) + abs(out[i, 1] - out[i - 1, 1])
        swap = abs(out[i, 1] - out[i - 1, 0]) + abs(out[i, 0] - out[i - 1, 1])
        if swap < keep:
            out[i] = out[i, ::-1]
    return out


def zoa_branches(tool: LinearTool, cut: CuttingModel, f_hz: np.ndarray, n_lobes: int):
    """Lobe branches: for every chatter frequency f, eigenvalue e and lobe k the spindle speed
    and the limiting depth.

    Returns
    -------
    rpm, a_m : ndarray ``(n_lobes, n_eig, nf)``; a_m is +inf where no chatter is possible
        (u ≤ 0).
    """
    f = np.asarray(f_hz, float)
    G = tool.frf(f)  # (2, 2, nf)
    WG = np.einsum("ij,jkf->fik", cut.mean_matrix(), G)
    lam = _track(np.linalg.eigvals(WG))  # (nf, 2), continuous branches
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / np.where(np.abs(lam) > 0, lam, np.nan)
    u, v = inv.real, inv.imag
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(u > 0, (u**2 + v**2) / (2 * u), np.inf)
    eps = 2 * np.arctan2(u, v)  # in (0, π·2) when u > 0
    k = np.arange(n_lobes)[:, None, None]
    tau = (eps.T[None] + 2 * np.pi * k) / (2 * np.pi * f[None, None, :])
    rpm = 60.0 / (cut.teeth * tau)
    a = np.broadcast_to(np.nan_to_num(a.T, nan=np.inf), rpm.shape)
    return rpm, a


def default_frequency_grid(tool: LinearTool, n: int = 3000) -> np.ndarray:
    """Chatter-frequency grid: log-spaced over [0.3 f_min, 3 f_max] of the tool's poles plus a
    fine linear grid (±20 %) around each natural frequency."""
    fn = tool.natural_frequencies_hz()
    grids = [np.geomspace(0.3 * fn.min(), 3 * fn.max(), n)]
    grids += [np.linspace(0.8 * f, 1.2 * f, max(n // 4, 50)) for f in fn]
    return np.unique(np.concatenate(grids))


@lobe_parameters
def zoa_lobes(tool: LinearTool, cut: CuttingModel, spindle_rpm: np.ndarray,
              f_hz: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Critical axial depth and chatter frequency on a spindle-speed grid (zero-order method).

    Every branch (lobe k, eigenvalue e) is a curve (n(f), a(f)); the lobe diagram is the lower
    envelope of all branches, evaluated at each requested speed by linear interpolation along
    the branch segments that cross it.

    Parameters
    ----------
    {lobe: tool, cut; spindle_rpm}
    f_hz
        Chatter-frequency grid (default :func:`default_frequency_grid`).

    Returns
    -------
    a_crit_m, chatter_hz : ndarray ``(len(spindle_rpm),)``.

    Examples
    --------
    >>> from robomill.chatter.model import ModeXY, tool_from_modes, CuttingModel
    >>> tool = tool_from_modes([ModeXY(500.0, 0.02, 1e7, (0.0, 1.0))])
    >>> cut = CuttingModel.from_immersion(2, 6e8, 0.3, 1.0, "down")
    >>> a, fc = zoa_lobes(tool, cut, [3000.0, 6000.0])
    >>> bool((a > 0).all() and (fc > 500).all())
    True
    """
    n_t = np.atleast_1d(np.asarray(spindle_rpm, float))
    f = default_frequency_grid(tool) if f_hz is None else np.asarray(f_hz, float)
    n_lobes = int(np.ceil(f.max() * 60.0 / (cut.teeth * n_t.min()))) + 2
    rpm, a = zoa_branches(tool, cut, f, n_lobes)
    best_a = np.full(n_t.shape, np.inf)
    best_f = np.full(n_t.shape, np.nan)
    for k in range(rpm.shape[0]):
        for e in range(rpm.shape[1]):
            n0, n1 = rpm[k, e, :-1], rpm[k, e, 1:]
            a0, a1 = a[k, e, :-1], a[k, e, 1:]
            ok = np.isfinite(a0) & np.isfinite(a1)
            if not ok.any():
                continue
            n0, n1, a0, a1 = n0[ok], n1[ok], a0[ok], a1[ok]
            f0, f1 = f[:-1][ok], f[1:][ok]
            lo, hi = np.minimum(n0, n1), np.maximum(n0, n1)
            if hi.max() < n_t.min() or lo.min() > n_t.max():
                continue
            inside = (n_t[:, None] >= lo[None]) & (n_t[:, None] <= hi[None])
            ti, si = np.nonzero(inside)
            if ti.size == 0:
                continue
            span = n1[si] - n0[si]
            w = np.where(span != 0, (n_t[ti] - n0[si]) / np.where(span != 0, span, 1), 0.0)
            a_i = a0[si] + w * (a1[si] - a0[si])
            f_i = f0[si] + w * (f1[si] - f0[si])
            order = np.lexsort((a_i, ti))
            ti, a_i, f_i = ti[order], a_i[order], f_i[order]
            first = np.r_[True, ti[1:] != ti[:-1]]
            ti, a_i, f_i = ti[first], a_i[first], f_i[first]
            better = a_i < best_a[ti]
            best_a[ti[better]] = a_i[better]
            best_f[ti[better]] = f_i[better]
    best_a[~np.isfinite(best_a)] = np.nan
    return best_a, best_f
