"""The lower envelope of the zero-order lobes' branches on a spindle-speed grid, compiled
(numba): the inner loop of :func:`robomill.chatter.lobes_zoa.zoa_envelope`.

Each branch (tool model b, eigenvalue e, lobe k) is the curve n_k(f) = 60 f / (N (ε(f) +
2πk)), a(f) over the chatter frequencies [Altintas & Budak 1995]; each of its segments
(consecutive frequencies) lowers the envelope at the grid speeds it spans by linear
interpolation along the segment. The loop computes each segment's speeds and interpolated
depths in place, where array passes built index and value arrays for every lobe; the
arithmetic of each depth is the same (the planner's default plan: 87 s → 65 s with the stacked
products of :mod:`robomill.chatter.coupling`). The envelope is a minimum, so the order of the
visits cannot change it; where equal depths of two segments meet at a speed, the chatter
frequency is the first one's.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, error_model="numpy")  # IEEE division: ±inf, NaN as numpy
def _lower(env, hz, want_hz, a, eps, f_hz, n_t, teeth, n_lobes):
    """Lower ``env`` ``(B, ns)`` (and, with ``want_hz``, set ``hz``) by every branch segment of
    the depths ``a`` and phases ``eps`` ``(B, nf, E)`` on the sorted speeds ``n_t``."""
    nb, nf, ne = a.shape
    n_first, n_last = n_t[0], n_t[-1]
    two_pi = 2 * np.pi
    for k in range(n_lobes):
        for b in range(nb):
            for f in range(nf - 1):
                for e in range(ne):
                    a0 = a[b, f, e]
                    a1 = a[b, f + 1, e]
                    # n = 60 · 2π f / (N (ε + 2πk)), evaluated left to right
                    n0 = 60.0 * 2 * np.pi * f_hz[f] / (teeth * (eps[b, f, e] + two_pi * k))
                    n1 = 60.0 * 2 * np.pi * f_hz[f + 1] / (teeth * (eps[b, f + 1, e]
                                                                    + two_pi * k))
                    if not (np.isfinite(a0) and np.isfinite(a1) and np.isfinite(n0)
                            and np.isfinite(n1)):
                        continue
                    lo = min(n0, n1)
                    hi = max(n0, n1)
                    if hi < n_first or lo > n_last:
                        continue
                    span = n1 - n0
                    for t in range(np.searchsorted(n_t, lo, side="left"),
                                   np.searchsorted(n_t, hi, side="right")):
                        w = (n_t[t] - n0) / span if span != 0 else 0.0
                        value = a0 + w * (a1 - a0)
                        if value < env[b, t]:
                            env[b, t] = value
                            if want_hz:
                                hz[b, t] = f_hz[f] + w * (f_hz[f + 1] - f_hz[f])


def lower_envelope(env: np.ndarray, hz: np.ndarray | None, a: np.ndarray, eps: np.ndarray,
                   f_hz: np.ndarray, n_t: np.ndarray, teeth: int, n_lobes: int) -> None:
    """Lower the envelope ``env`` ``(B, ns)`` in place by every branch of lobes 0 … n_lobes − 1
    of the depths ``a`` and phases ``eps`` ``(B, nf, E)`` (module docstring) on the sorted
    speeds ``n_t`` [rpm]; ``hz`` (when given) gets the chatter frequency of the branch that
    sets each lowered depth."""
    from robomill.kernels import ready

    ready(__name__)  # the kernel compiled once per environment (robomill.kernels)
    want = hz is not None
    _lower(env, hz if want else np.empty((0, 0)), want,
           np.ascontiguousarray(a, float), np.ascontiguousarray(eps, float),
           np.ascontiguousarray(f_hz, float), np.ascontiguousarray(n_t, float),
           float(teeth), int(n_lobes))


def warm_kernels() -> None:
    """Lower a tiny envelope (compiles :func:`_lower`, or loads it from the cache;
    :func:`robomill.kernels.ready`), with and without the chatter frequency."""
    a = np.array([[[1e-3], [2e-3], [1.5e-3]]])
    eps = np.array([[[0.5], [1.0], [1.5]]])
    f = np.array([100.0, 200.0, 300.0])
    n_t = np.array([1000.0, 5000.0, 10000.0])
    for want in (False, True):
        _lower(np.full((1, 3), np.inf), np.full((1, 3), np.nan), want, a, eps, f, n_t, 2.0, 3)
