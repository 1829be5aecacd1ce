"""The rotation about the tool axis along a whole cut: dynamic programming over stations ×
rotations, maximizing the path's worst predicted stability margin, then its worst stiffness,
then keeping closest to the cell's nominal tool orientation.

A path visits one rotation θ per station. It may use a node (station, θ) only when the pose
there is feasible (:mod:`robomill.plan.feasible`) and may step from one station to the next
only when |Δθ| ≤ ``max_rotation_step_deg``, the configuration stays the same and no joint
moves faster than its axis speed over the time the feed takes between the stations.

Among the feasible paths it takes, lexicographically [Bellman 1957; a bottleneck path, Pollack
1960]:

1. the largest worst station score W₁ = max over paths of min over stations (the pessimistic
   stability margin); every node whose score is below W₁ − tol is then dropped, so that every
   remaining path reaches W₁ to within tol;
2. on the remaining nodes, the largest worst second score (the stiffness normal to the wall),
   dropped the same way;
3. on what remains, the path with the smallest Σ|θ − θ_nominal| (integer milli-degrees, so the
   sum is exact), and between equal sums the smaller angle at the earlier station.

``tol`` = :data:`TIE_REL` × the largest |score|: scores closer than that are equal, so a
spindle on the flange axis, whose rotation only turns joint 6 and changes the predicted
stiffness by ~10⁻⁹ of itself (rounding), keeps the nominal orientation exactly.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

TIE_REL = 1e-6
"""Scores within this fraction of the largest |score| are a tie (decided by step 3)."""


def tie_tolerance(score: np.ndarray) -> float:
    """Absolute tolerance of a score array: :data:`TIE_REL` × its largest finite |value|."""
    s = np.asarray(score, float)
    fin = s[np.isfinite(s)]
    return TIE_REL * float(np.max(np.abs(fin))) if fin.size else 0.0


def usable(score: np.ndarray) -> np.ndarray:
    """A score array with +inf (e.g. a margin with no finite critical depth: unconditionally
    stable) replaced by a finite value above every finite one (ties among themselves); NaN
    and −inf stay unusable."""
    s = np.asarray(score, float).copy()
    fin = s[np.isfinite(s)]
    top = min(2.0 * float(np.max(np.abs(fin))) + 1.0, np.finfo(float).max) if fin.size else 1.0
    s[np.isposinf(s)] = top
    return s


def bottleneck_value(score: np.ndarray, allowed: np.ndarray, edge_ok: np.ndarray) -> float:
    """max over allowed paths of min over stations of ``score`` ``(S, R)``; −inf when no path.

    ``edge_ok`` ``(S−1, R, R)``: step from rotation r at station s to r' at s+1 allowed."""
    s = np.where(allowed, np.asarray(score, float), -np.inf)
    best = s[0].copy()
    for i in range(1, len(s)):
        reach = np.where(edge_ok[i - 1], best[:, None], -np.inf).max(0)
        best = np.minimum(reach, s[i])
    return float(best.max()) if best.size else -np.inf


def min_cost_path(cost: np.ndarray, allowed: np.ndarray, edge_ok: np.ndarray
                  ) -> np.ndarray | None:
    """Indices ``(S,)`` of the allowed path of smallest Σ cost[r] (integers, exact), ties to the
    smaller index at the earlier station; None when no allowed path exists."""
    S, R = allowed.shape
    big = np.iinfo(np.int64).max // 4
    c = np.asarray(cost, np.int64)
    val = np.where(allowed[0], c, big)
    back = np.zeros((S, R), int)
    for i in range(1, S):
        cand = np.where(edge_ok[i - 1], val[:, None], big)       # from r (rows) to r' (cols)
        back[i] = np.argmin(cand, axis=0)                        # first minimum: smaller r
        val = np.where(allowed[i], cand[back[i], np.arange(R)] + c, big)
        val = np.minimum(val, big)
    if val.min() >= big:
        return None
    path = [int(np.argmin(val))]
    for i in range(S - 1, 0, -1):
        path.append(int(back[i][path[-1]]))
    return np.asarray(path[::-1], int)


def best_path(scores: Sequence[np.ndarray], allowed: np.ndarray, edge_ok: np.ndarray,
              rotations_deg: np.ndarray, nominal_deg: float = 0.0
              ) -> tuple[np.ndarray | None, list[float]]:
    """The lexicographic best path (module docstring): indices ``(S,)`` into
    ``rotations_deg`` and the worst value of each score along it; (None, []) when no
    feasible path exists.

    Parameters
    ----------
    scores
        ``(S, R)`` arrays in priority order (NaN or −inf: unusable node; +inf: above every
        finite value, :func:`usable`).
    allowed
        ``(S, R)`` feasible nodes.
    edge_ok
        ``(S−1, R, R)`` allowed steps.
    """
    raw = [np.asarray(sc, float) for sc in scores]
    scores = [usable(sc) for sc in raw]
    ok = np.asarray(allowed, bool).copy()
    for sc in scores:
        ok &= np.isfinite(sc)
    for sc in scores:
        W = bottleneck_value(sc, ok, edge_ok)
        if not np.isfinite(W):
            return None, []
        ok &= sc >= W - tie_tolerance(np.where(ok, sc, np.nan))
    cost = np.rint(np.abs(np.asarray(rotations_deg, float) - nominal_deg) * 1000.0)
    path = min_cost_path(cost, ok, edge_ok)
    if path is None:
        return None, []
    idx = np.arange(len(path))
    return path, [float(sc[idx, path].min()) for sc in raw]


def best_fixed(scores: Sequence[np.ndarray], allowed: np.ndarray, same_config: np.ndarray,
               rotations_deg: np.ndarray, nominal_deg: float = 0.0
               ) -> tuple[int | None, list[float]]:
    """The best single rotation held along the whole cut, by the same lexicographic rule as
    :func:`best_path` (the comparison the path must beat): index and worst scores."""
    raw = [np.asarray(sc, float) for sc in scores]
    scores = [usable(sc) for sc in raw]
    ok = np.all(allowed, axis=0) & np.asarray(same_config, bool)
    for sc in scores:
        ok &= np.all(np.isfinite(np.asarray(sc, float)), axis=0)
    if not ok.any():
        return None, []
    for sc in scores:
        worst = np.asarray(sc, float).min(0)
        W = worst[ok].max()
        ok &= worst >= W - tie_tolerance(np.where(ok, worst, np.nan))
    cost = np.where(ok, np.abs(np.asarray(rotations_deg, float) - nominal_deg), np.inf)
    r = int(np.argmin(cost))
    return r, [float(sc[:, r].min()) for sc in raw]


def edges(rotations_deg: np.ndarray, q_rad: np.ndarray, config: np.ndarray, *,
          max_step_deg: float, dt_s: float | None, speed_limits_deg_s: np.ndarray | None
          ) -> np.ndarray:
    """Allowed steps ``(S−1, R, R)`` between neighbouring stations: |Δθ| ≤ ``max_step_deg``,
    the same configuration, and every joint's move (shortest turn) over ``dt_s`` within its
    axis speed (when both are given)."""
    th = np.asarray(rotations_deg, float)
    step = np.abs(th[:, None] - th[None, :]) <= max_step_deg + 1e-9
    cfg = np.asarray(config)
    same = cfg[:-1, :, None] == cfg[1:, None, :]
    ok = step[None] & same
    if dt_s is not None and speed_limits_deg_s is not None and dt_s > 0:
        dq = q_rad[1:, None, :, :] - q_rad[:-1, :, None, :]               # (S-1, R, R', n)
        dq = np.abs((dq + np.pi) % (2 * np.pi) - np.pi)
        rate = np.rad2deg(dq) / dt_s
        ok &= np.all(rate <= np.asarray(speed_limits_deg_s, float), axis=-1)
    return ok


def prefer_nominal(table, keys=("placement", "direction", "spindle_rpm", "depth_mm",
                                "feed_mm_s"), nominal_deg: float = 0.0):
    """Of the candidates that differ only by their rotation about the tool axis, keep one: the
    smallest upper form error, then the largest pessimistic margin, each to within
    :func:`tie_tolerance`, then the rotation closest to ``nominal_deg`` (then the smaller
    angle) — so that a rotation whose effect is rounding noise is never chosen over the
    nominal orientation."""
    import pandas as pd

    t = table
    if not len(t):
        return t
    keys = [k for k in keys if k in t]
    fe = t["form_error_high_um"].astype(float)
    m = t["stability_margin_low"].astype(float).fillna(np.inf)
    fe_tol = tie_tolerance(fe.to_numpy())
    m_tol = tie_tolerance(m.to_numpy())
    best_fe = fe.groupby([t[k] for k in keys]).transform("min")
    keep = fe <= best_fe + fe_tol
    best_m = m.where(keep, -np.inf).groupby([t[k] for k in keys]).transform("max")
    keep &= (m >= best_m - m_tol) | (np.isinf(best_m) & np.isinf(m))
    t = t[keep]
    order = pd.DataFrame({"_d": (t["rotation_deg"] - nominal_deg).abs().to_numpy(),
                          "_r": t["rotation_deg"].to_numpy()}, index=t.index)
    t = t.assign(**order).sort_values(["_d", "_r"], kind="stable")
    return t.groupby(keys, sort=False).head(1).drop(columns=["_d", "_r"]).sort_index()
