"""Zero-order analytical stability lobes (Altintas & Budak 1995; Altintas 2012 §4.3).

With the tooth-period average W̄ of the directional matrix, a harmonic chatter vibration at ω
is sustained when det(I − a(1 − e^{−jωτ}) W̄ G(jω)) = 0. For each eigenvalue λ of W̄G(jω),
writing 1/λ = u + jv:

.. math:: a_{lim} = \\frac{u^2 + v^2}{2u}\\ (u > 0),\\qquad
          \\omega\\tau = 2\\,\\mathrm{atan2}(u, v) + 2k\\pi,\\qquad n = \\frac{60}{N\\tau}

which is Altintas' a_lim = −2πΛ_R(1 + κ²)/(N K_t), ψ = atan κ, ε = π − 2ψ, τ = (ε + 2kπ)/ω_c
written with the eigenvalue of W̄G (W̄ = N K_t α/(4π)). For a single mode in one direction it
reduces to the closed form a_lim = 1/(2 W̄_dd Re G_dd).

One routine computes the lobes, :func:`zoa_envelope`, for a stack of receptances (one per
tool model) on a chatter-frequency grid the caller chooses: the 2 × 2 eigenvalues are taken in
closed form, each branch (lobe k, eigenvalue) is a curve (n(f), a(f)), and the lobe diagram is
the lower envelope of every branch, found by scattering each branch segment onto the spindle
speeds it spans (linear interpolation along the segment; compiled,
:mod:`robomill.chatter.envelope_kernel`). :func:`zoa_lobes` is it for one
:class:`~robomill.chatter.model.LinearTool` on :func:`default_frequency_grid`;
:func:`robomill.plan.lobes.batch_zoa_lobes` for many modal tool models on the planner's grid.
"""

from __future__ import annotations

import numpy as np

from robomill.chatter.model import CuttingModel, LinearTool, conform_rows, lobe_parameters


def _left_multiply(W: np.ndarray, G: np.ndarray) -> np.ndarray:
    """W G for a real 2 × 2 ``W`` (one, or a stack broadcasting against ``G`` without its
    last two axes) and a stack ``G`` ``(..., 2, 2)``, written out (faster than a general
    product for 2 × 2 blocks)."""
    out = np.empty_like(G)
    for i in range(2):
        for j in range(2):
            out[..., i, j] = W[..., i, 0] * G[..., 0, j] + W[..., i, 1] * G[..., 1, j]
    return out


#: an eigenvalue below this fraction of the larger one is zero (the closed form's rounding)
EIG_ZERO = 16 * np.finfo(float).eps


def _eig2(A: np.ndarray) -> np.ndarray:
    """Eigenvalues ``(..., 2)`` of 2 × 2 matrices ``(..., 2, 2)`` in closed form.

    An eigenvalue within rounding of zero (below :data:`EIG_ZERO` times the larger one: a
    rank-one W̄G, a tool with modes in one direction only) is returned as exactly zero, as a
    general eigensolver finds it; left at its rounding residue it would be a spurious branch
    of near-infinite depth, joined by the tracking to real branch points."""
    tr = A[..., 0, 0] + A[..., 1, 1]
    det = A[..., 0, 0] * A[..., 1, 1] - A[..., 0, 1] * A[..., 1, 0]
    disc = np.sqrt(tr**2 / 4 - det + 0j)
    lam = np.stack([tr / 2 + disc, tr / 2 - disc], -1)
    size = np.abs(lam)
    return np.where(size <= EIG_ZERO * size.max(-1, keepdims=True), 0.0, lam)


def _oriented(W: np.ndarray, G: np.ndarray) -> np.ndarray:
    """The 2 × 2 matrix whose eigenvalues close the zero-order loop: W̄ G for the planar model;
    with the axial force, G₂₃ W̄₃ (the in-plane response ``G`` ``(..., 2, 3)`` to the force
    W̄₃ Δ, ``W`` ``(..., 3, 2)``), whose eigenvalues are the non-zero ones of W̄₃ G₂₃. ``W``'s
    rows are matched to ``G``'s inputs (:func:`robomill.chatter.model.conform_rows`)."""
    G = np.asarray(G)
    W = conform_rows(W, G.shape[-1])
    if G.shape[-1] == 2:
        return _left_multiply(W, G)
    return np.matmul(G, W.astype(G.dtype))  # stacked (BLAS): a third of einsum's time


def oriented_eigenvalues(W: np.ndarray, G: np.ndarray) -> np.ndarray:
    """Eigenvalues ``(..., 2)`` of W̄ G(jω) for the mean directional matrix ``W`` (2 × 2, or
    3 × 2 with the axial row) and a stack of receptances ``G`` ``(..., 2, 2|3)``: the
    zero-order characteristic equation's eigenvalues [Altintas & Budak 1995], untracked."""
    return _eig2(_oriented(W, G))


def _track(lam: np.ndarray) -> np.ndarray:
    """Order the two eigenvalues along the frequency axis (axis 1 of ``(B, nf, 2)``) so each
    column is a continuous branch (a swap would join points of different lobes): at each
    frequency the pair is swapped when that brings it closer to the previous one.

    Swapping at frequency i is decided by comparing the raw pairs i and i − 1; since a swap at
    i − 1 exchanges both costs, the output is flipped wherever an odd number of raw steps
    preferred the swap: a cumulative parity, without a loop over frequencies."""
    d = lam[:, 1:] - lam[:, :-1]
    keep = np.abs(d[..., 0]) + np.abs(d[..., 1])
    swap = np.abs(lam[:, 1:, 1] - lam[:, :-1, 0]) + np.abs(lam[:, 1:, 0] - lam[:, :-1, 1])
    flip = np.concatenate([np.zeros((lam.shape[0], 1), bool),
                           (np.cumsum(swap < keep, axis=1) % 2).astype(bool)], axis=1)
    return np.where(flip[..., None], lam[..., ::-1], lam)


def zoa_envelope(G: np.ndarray, f_hz: np.ndarray, cut: CuttingModel,
                 spindle_rpm: np.ndarray, *, chatter_frequency: bool = False,
                 mean_matrix: np.ndarray | None = None
                 ) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Zero-order critical axial depth ``(B, len(spindle_rpm))`` [m] of B tool models whose
    receptances ``G`` ``(B, nf, 2, d)`` [m/N] (d = 3: with the response to the axial force,
    :func:`_oriented`) are given on the chatter frequencies ``f_hz``
    ``(nf,)``: the lower envelope of every lobe and eigenvalue branch (module docstring), +inf
    where no branch reaches a speed (no regenerative chatter possible there).

    With ``chatter_frequency``, also the chatter frequency [Hz] of the branch that sets each
    depth (NaN where the depth is +inf). ``mean_matrix`` ``(B, 2|3, 2)``: each tool model's own
    mean directional matrix W̄ (its own coefficients; default ``cut``'s for all; ``cut``
    gives the teeth).
    """
    f = np.asarray(f_hz, float)
    rpm_in = np.atleast_1d(np.asarray(spindle_rpm, float))
    order = np.argsort(rpm_in)
    n_t = rpm_in[order]
    n_lobes = int(np.ceil(f.max() * 60.0 / (cut.teeth * n_t.min()))) + 2
    W = cut.mean_matrix() if mean_matrix is None else np.asarray(mean_matrix)[:, None]
    lam = _track(_eig2(_oriented(W, G)))  # (B, nf, 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / np.where(np.abs(lam) > 0, lam, np.nan)
        u, v = inv.real, inv.imag
        a = np.where(u > 0, (u**2 + v**2) / (2 * u), np.inf)
    # NaN (a zero eigenvalue) is no branch either; +inf stays +inf (np.nan_to_num would make
    # it the largest float, a finite "depth" of 1.8e308 m that segments then interpolate)
    a = np.where(np.isnan(a), np.inf, a)
    eps = 2 * np.arctan2(u, v)
    env = np.full((lam.shape[0], n_t.size), np.inf)
    hz = np.full(env.shape, np.nan) if chatter_frequency else None
    # imported here: numba's import is paid only by a process that computes lobes
    from robomill.chatter.envelope_kernel import lower_envelope

    lower_envelope(env, hz, a, eps, f, n_t, cut.teeth, n_lobes)
    depth = np.empty_like(env)
    depth[:, order] = env
    if hz is None:
        return depth
    freq = np.empty_like(hz)
    freq[:, order] = hz
    return depth, freq


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
    """Critical axial depth and chatter frequency on a spindle-speed grid (zero-order method,
    :func:`zoa_envelope` for this one tool).

    Parameters
    ----------
    {lobe: tool, cut; spindle_rpm}
    f_hz
        Chatter-frequency grid (default :func:`default_frequency_grid`).

    Returns
    -------
    a_crit_m, chatter_hz : ndarray ``(len(spindle_rpm),)``; NaN where no lobe reaches a speed.

    Examples
    --------
    >>> from robomill.chatter.model import ModeXY, tool_from_modes, CuttingModel
    >>> tool = tool_from_modes([ModeXY(500.0, 0.02, 1e7, (0.0, 1.0))])
    >>> cut = CuttingModel.from_immersion(2, 6e8, 0.3, 1.0, "down")
    >>> a, fc = zoa_lobes(tool, cut, [3000.0, 6000.0])
    >>> bool((a > 0).all() and (fc > 500).all())
    True
    """
    f = default_frequency_grid(tool) if f_hz is None else np.asarray(f_hz, float)
    G = np.moveaxis(tool.frf(f), -1, 0)[None]  # (1, nf, 2, n_inputs)
    a, hz = zoa_envelope(G, f, cut, spindle_rpm, chatter_frequency=True)
    a = a[0]
    a[~np.isfinite(a)] = np.nan
    return a, hz[0]
