"""Stability limits of many tool-tip models at once (the planner's fast grid).

Zero-order lobes (Altintas & Budak 1995; Altintas 2012 §4.3) by the one routine,
:func:`robomill.chatter.lobes_zoa.zoa_envelope`, given here every pose's modal-sum receptance
(one tool model per robot pose) on the planner's frequency grid (:func:`frequency_grid`), so
a grid of poses × speeds costs a few array passes instead of one solver call per pose. The
receptance is the one modal sum, :func:`robomill.chatter.coupling.receptance`.
"""

from __future__ import annotations

import numpy as np

from robomill.chatter.coupling import receptance
from robomill.chatter.lobes_zoa import zoa_envelope
from robomill.chatter.model import CuttingModel


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
                    chunk: int = 64, mean_matrix: np.ndarray | None = None) -> np.ndarray:
    """Critical axial depth ``(B, len(spindle_rpm))`` [m] of B tool models (zero-order lobes,
    lower envelope of every lobe and eigenvalue branch; +inf where no branch reaches a speed:
    no regenerative chatter possible there). ``shape`` ``(B, M, 2|3)``: in-plane shapes, or
    with their axial component (then the axial force's row of ``cut`` or ``mean_matrix``
    ``(B, 3, 2)`` enters, :mod:`robomill.chatter.model`).

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
    shape = np.asarray(shape, float)
    shape = shape.reshape(fn.shape + (shape.shape[-1],))
    f = frequency_grid(fn) if f_hz is None else np.asarray(f_hz, float)
    z = np.broadcast_to(np.asarray(zeta, float), fn.shape)
    W = (None if mean_matrix is None
         else np.broadcast_to(mean_matrix, (fn.shape[0],) + np.shape(mean_matrix)[-2:]))
    out = [zoa_envelope(receptance(f, fn[sl], z[sl], k[sl], shape[sl]), f, cut, spindle_rpm,
                        mean_matrix=None if W is None else W[sl])
           for sl in (slice(b0, b0 + chunk) for b0 in range(0, fn.shape[0], chunk))]
    return np.concatenate(out, axis=0)
