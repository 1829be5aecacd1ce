"""Each planned cut on its own stretch of material: slots as segments with a width, and
whether two of them overlap on the part.

A slot milled by a tool of diameter D along the segment P₀P₁ removes the points closer than
D/2 to the segment (a capsule), so two slots overlap exactly when the shortest distance
between their segments is below the sum of their half-widths, D for one tool. The segments'
shortest distance is the minimum of |P(s) − Q(t)| over s, t ∈ [0, 1] (a convex quadratic;
Ericson, *Real-Time Collision Detection*, 2005, §5.1.9).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def slot_segment(mid_mm, direction_deg: float, length_mm: float) -> np.ndarray:
    """Start and end ``(2, 3)`` [mm] of a cut of ``length_mm`` fed along ``direction_deg`` in
    the base XY plane with its midpoint at ``mid_mm``."""
    a = np.deg2rad(float(direction_deg))
    u = np.array([np.cos(a), np.sin(a), 0.0])
    m = np.asarray(mid_mm, float)
    return np.stack([m - length_mm / 2 * u, m + length_mm / 2 * u])


def segment_distance_mm(a: np.ndarray, b: np.ndarray) -> float:
    """Shortest distance between segments ``a`` and ``b`` (each ``(2, 3)`` start, end)."""
    p, q = np.asarray(a, float), np.asarray(b, float)
    d1, d2, r = p[1] - p[0], q[1] - q[0], p[0] - q[0]
    aa, ee, ff = d1 @ d1, d2 @ d2, d2 @ r
    if aa <= 1e-12 and ee <= 1e-12:
        return float(np.linalg.norm(r))
    if aa <= 1e-12:
        s, t = 0.0, float(np.clip(ff / ee, 0, 1))
    else:
        c = d1 @ r
        if ee <= 1e-12:
            s, t = float(np.clip(-c / aa, 0, 1)), 0.0
        else:
            bb = d1 @ d2
            den = aa * ee - bb * bb
            s = float(np.clip((bb * ff - c * ee) / den, 0, 1)) if den > 1e-12 else 0.0
            t = (bb * s + ff) / ee
            if t < 0:
                s, t = float(np.clip(-c / aa, 0, 1)), 0.0
            elif t > 1:
                s, t = float(np.clip((bb - c) / aa, 0, 1)), 1.0
    return float(np.linalg.norm(p[0] + s * d1 - (q[0] + t * d2)))


def overlaps(segment: np.ndarray, others: Sequence[np.ndarray], width_mm: float) -> bool:
    """Whether a slot of ``width_mm`` along ``segment`` overlaps any of the slots of the same
    width along ``others`` (segment distance below the width; touching is not overlapping)."""
    return any(segment_distance_mm(segment, o) < width_mm - 1e-9 for o in others)
