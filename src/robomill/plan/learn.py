"""Designs that learn (``plan.yaml: purpose: learn``): the next cuts chosen to narrow the
predictions that bind a production plan, each with the reason it was chosen and the expected
narrowing of the interval it aims at.

* **Narrow the binding cut's stability limit by expected information** (with the production
  plan's binding cut and the stability model's members, :mod:`robomill.plan.stability`): the
  members a_m (weights w_m) at the binding cut's pose, direction and speed define its
  critical-depth interval, the weighted central ``level`` range of a_m. A learn cut c of depth
  d_c is predicted stable by member m when its a_m(c) > d_c; after verdicts y of the chosen
  cuts the weights become w_m Π_c (1 − ε)^[agree] ε^[disagree] (Bayesian updating of
  stability lobes, [Karandikar et al. 2014]; ε ``stability.verdict_error``). The cuts are
  chosen greedily (Bayesian experimental design, [Chaloner & Verdinelli 1995]): each next cut
  is the allowed grid point that, with those already chosen, minimizes the expected interval
  width at the binding cut, E_y[width | y] = Σ_y P(y) width(w·L(y)) with the members'
  predictive probability P(y) = Σ_m w_m L_m(y) over the 2ᵏ verdicts of the k cuts. A cut all
  members predict alike cannot change the weights and is never chosen. At the binding cut
  itself, with members spread evenly and ε → 0, the first cut lies at the weighted median of
  a_m (bisection). Ties go to the cut nearest the binding cut (its speed, direction,
  placement, rotation). Expected narrowing 1 − E[width]/width. The design stops when one
  more cut would narrow the expected width by less than 1 % of the prior width. The critical
  depth does not depend on the feed: each cut takes the allowed feed whose chip load lies
  nearest the binding cut's, so that its mean force also brings the evidence of the force
  and deflection predictions toward the binding cut's chip load (their widening by the
  distance from the evidence, :mod:`robomill.plan.extrapolation`).
* **The binding cut itself** where its speed or chip load lies outside the study's (its
  intervals widened by w > 1, :mod:`robomill.plan.extrapolation`): a cut the deflection or
  force constraint binds is narrowed by what the cut's own measurements add, not by a
  verdict; run once, its mean force and deflection put the evidence at the binding cut and
  the widening goes: expected narrowing 1 − 1/w. It takes one of the ``n_cuts`` before the
  stability cuts are chosen.
* **Straddle the stability limit where it is least certain** (without a binding cut or
  members): at the reachable pose and speed
  whose critical-depth interval is widest relative to its nominal (the limit inside the
  request's depths), one cut at the largest requested depth below the interval's low end (a
  stable verdict at the interval's level; below the nominal limit where no depth is that low)
  and one at the smallest above the nominal limit (a parallel slot two tool diameters beside
  the first, on its own material; the pose moves by that much). Their verdicts (stable,
  chatter) bracket the true limit between the two depths: expected narrowing
  1 − (d_above − d_below)/(a_high − a_low).
* **The farthest pose**: the reachable placement farthest from the study's cuts, at a depth
  the pessimistic margin still calls stable where one is; when the pose is extrapolated
  (farther than ``extrapolation.max_pose_distance_mm``) it removes the widening factor w:
  expected narrowing 1 − 1/w (0 otherwise: the pose's own check).
* **A feed that separates edge and shearing coefficients**: the chip load of the request's
  grid that, added to the identifying cuts, most shrinks the force's prediction interval at
  the production plan's binding cut (largest removal rate): the half-width goes from
  t s √(1 + a₀ (AᵀA)⁻¹ a₀ᵀ) to t s √(1 + a₀ (AᵀA + a aᵀ)⁻¹ a₀ᵀ) (the regression of
  :mod:`robomill.forces.prediction`; the straight line in the chip load whose intercept is the
  edge force and slope the shearing force).

The request's constraints other than the stability margin and ``min_p_stable`` apply (a cut
above the limit is the point of the design); every cut lies on its own material
(:mod:`robomill.plan.material`).

Karandikar 2014: Karandikar, J.; Traverso, M.; Abbas, A.; Schmitz, T. Bayesian inference for
milling stability using a random walk approach. *J. Manuf. Sci. Eng.* 136(3), 031015, 2014.
Chaloner & Verdinelli 1995: Chaloner, K.; Verdinelli, I. Bayesian experimental design: a
review. *Statistical Science* 10(3), 273–304, 1995.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
import xarray as xr

from robomill.plan.choose import constraint_masks, feasible_table
from robomill.plan.material import overlaps, slot_segment
from robomill.plan.request import PlanRequest

DIMS = ("placement", "rotation", "direction", "spindle_rpm", "depth_mm", "feed_mm_s")


def learn_allowed(ds: xr.Dataset, req: PlanRequest) -> xr.DataArray:
    """Candidates a learn cut may take: reachable, meeting every constraint of the request but
    the stability margin and ``min_p_stable`` (a cut above the limit is the point), and not
    extrapolated where the request forbids it; full candidate dims."""
    m = ds["reachable"] & xr.ones_like(ds["mrr_mm3_s"], dtype=bool)
    m = m & xr.ones_like(ds["feed_mark_um"], dtype=bool)
    for key, mask in constraint_masks(ds, req).items():
        if key not in ("min_stability_margin", "min_p_stable"):
            m = m & mask
    if not req.extrapolation.get("allow", True) and "extrapolation" in ds:
        m = m & ~ds["extrapolation"]
    return m.transpose(*DIMS)


def _row(ds: xr.Dataset, idx: tuple[int, ...]) -> pd.DataFrame:
    mask = xr.DataArray(np.zeros([ds.sizes[d] for d in DIMS], bool), dims=DIMS)
    mask.values[idx] = True
    return feasible_table(ds, mask)


def _segment(r, req: PlanRequest) -> np.ndarray:
    return slot_segment([r["placement_x_mm"], r["placement_y_mm"], r["placement_z_mm"]],
                        r["direction_deg"], req.length_mm)


def place_apart(r: pd.DataFrame, req: PlanRequest, taken: list, tries: int = 4) -> bool:
    """Put the cut ``r`` (one row) on material no slot in ``taken`` has cut: as it is, or
    moved sideways by 2, 4, … tool diameters (a parallel slot; the pose moves by that much and
    its predictions are the unmoved one's); on success its segment joins ``taken``."""
    seg = _segment(r.iloc[0], req)
    u = (seg[1] - seg[0]) / np.linalg.norm(seg[1] - seg[0])
    side = np.cross([0.0, 0.0, 1.0], u) * 2 * req.tool_diameter_mm
    for k in range(tries):
        shift = side * ((k + 1) // 2) * (1 if k % 2 else -1)
        moved = seg + shift
        if not overlaps(moved, taken, req.tool_diameter_mm):
            for i, ax in enumerate("xyz"):
                r[f"placement_{ax}_mm"] = r[f"placement_{ax}_mm"] + shift[i]
            taken.append(moved)
            return True
    return False


def straddle(ds: xr.Dataset, req: PlanRequest, allowed: xr.DataArray,
             taken: list, skip: set | None = None) -> list[pd.DataFrame]:
    """The pair of cuts on both sides of the least certain predicted stability limit (not at
    a speed and placement in ``skip``, to which the pair's own are added)."""
    skip = set() if skip is None else skip
    a = ds["a_crit_mm"].transpose(*DIMS[:4]).values
    lo = ds["a_crit_low_mm"].transpose(*DIMS[:4]).values
    hi = ds["a_crit_high_mm"].transpose(*DIMS[:4]).values
    depths = ds["depth_mm"].values
    ok = (np.isfinite(a) & np.isfinite(lo) & np.isfinite(hi) & (a > depths.min())
          & (a < depths.max()) & allowed.any(("depth_mm", "feed_mm_s")).values)
    if not ok.any():
        return []
    rel = np.where(ok, (hi - lo) / np.where(ok, a, 1.0), -np.inf)
    for flat in np.argsort(rel, axis=None)[::-1][:50]:
        pos = np.unravel_index(flat, rel.shape)
        if not np.isfinite(rel[pos]):
            break
        if (pos[0], pos[3]) in skip:
            continue
        # below: the largest depth under the interval's low end, stable at the interval's
        # level (else the largest under the nominal limit); above: the smallest over the
        # nominal limit. Below the nominal alone, a member share of 0.17 chatters: on the
        # default study both cuts of a round at 10 000 rpm chattered (0.3 mm, p_stable 0.83)
        safe = np.flatnonzero(depths <= lo[pos])
        i_lo = int(safe.max() if safe.size else np.flatnonzero(depths <= a[pos]).max())
        i_hi = int(np.flatnonzero(depths > a[pos]).min())
        feeds = np.flatnonzero(allowed.values[pos + (i_lo,)] & allowed.values[pos + (i_hi,)])
        if feeds.size == 0:
            continue
        below = _row(ds, pos + (i_lo, int(feeds[0])))
        above = _row(ds, pos + (i_hi, int(feeds[0])))
        seg = _segment(below.iloc[0], req)
        u = seg[1] - seg[0]
        side = np.cross([0.0, 0.0, 1.0], u / np.linalg.norm(u)) * 2 * req.tool_diameter_mm
        for k, ax in enumerate("xyz"):
            above[f"placement_{ax}_mm"] = above[f"placement_{ax}_mm"] + side[k]
        seg2 = _segment(above.iloc[0], req)
        if overlaps(seg, taken, req.tool_diameter_mm) or overlaps(seg2, taken + [seg],
                                                                   req.tool_diameter_mm):
            continue
        taken += [seg, seg2]
        skip.add((pos[0], pos[3]))
        width = hi[pos] - lo[pos]
        gain = float(np.clip(1 - (depths[i_hi] - depths[i_lo]) / width, 0, 1)) if width > 0 \
            else 0.0
        where = (f"{float(ds['spindle_rpm'].values[pos[3]]):.6g} rpm, placement {pos[0]}, "
                 f"rotation {float(ds['rotation'].values[pos[1]]):g} deg")
        below["reason"] = (f"stability limit least certain here ({where}: a_crit "
                           f"{lo[pos]:.3g}-{hi[pos]:.3g} mm): the depth below it")
        above["reason"] = (f"stability limit least certain here ({where}): the depth above it, "
                           f"a parallel slot {2 * req.tool_diameter_mm:g} mm beside")
        for r in (below, above):
            r["learn_target"] = "a_crit_mm"
            r["expected_narrowing"] = gain
        return [below, above]
    return []


def expected_width(target_mm: np.ndarray, weights: np.ndarray, level: float,
                   patterns: np.ndarray, error_rate: float) -> tuple[float, np.ndarray]:
    """The expected weighted ``level`` interval width of ``target_mm`` ``(E,)`` (the members'
    critical depth at the binding cut) after the verdicts of cuts whose members' predictions
    are ``patterns`` ``(E, k)`` (True: stable), averaged over the 2ᵏ verdicts by their
    predictive probability (module docstring), and those probabilities ``(2ᵏ,)``."""
    from robomill.plan.stability import summary

    E, k = patterns.shape
    ys = (np.arange(2**k)[:, None] >> np.arange(k)[None]) & 1          # (2^k, k) outcomes
    eps = float(np.clip(error_rate, 1e-9, 0.5))
    agree = patterns[None].astype(bool) == ys[:, None].astype(bool)     # (2^k, E, k)
    lik = np.prod(np.where(agree, 1 - eps, eps), axis=2)                # (2^k, E)
    joint = weights[None] * lik
    p_y = joint.sum(1)
    post = joint / p_y[:, None]
    width = np.empty(2**k)
    for i in range(2**k):  # the plan's own interval (summary) under each verdict's weights
        sm = summary(target_mm[:, None], post[i], level)
        width[i] = float(sm["high"][0] - sm["low"][0])
    return float(np.sum(p_y * width)), p_y


def candidate_widths(target_mm: np.ndarray, weights: np.ndarray, level: float,
                     patterns: np.ndarray, chosen: Sequence[np.ndarray],
                     error_rate: float) -> np.ndarray:
    """The expected interval width at the binding cut (:func:`expected_width`) if each
    candidate (a column of ``patterns`` ``(E, n)``, the members' predicted verdicts, True
    stable) joined the ``chosen`` cuts' patterns; +inf for a candidate every member of
    positive weight predicts alike (its verdict cannot move the weights)."""
    live = np.asarray(weights, float) > 0
    pats = np.asarray(patterns, bool)
    split = pats[live].any(0) & ~pats[live].all(0)
    out = np.full(pats.shape[1], np.inf)
    for j in np.flatnonzero(split):
        out[j] = expected_width(target_mm, weights, level,
                                np.stack(list(chosen) + [pats[:, j]], 1), error_rate)[0]
    return out


def _nearness(pos: np.ndarray, at: tuple[int, int, int, int], n_speeds: int) -> np.ndarray:
    """Sort key of candidate grid points ``pos`` ``(n, 4)`` (placement, rotation, direction,
    speed index) by nearness to the binding cut ``at``: its own speed, direction, placement
    and rotation first, then the smallest change of speed."""
    p, r, d, s = at
    return (np.abs(pos[:, 3] - s) / max(n_speeds, 1) + (pos[:, 2] != d) + (pos[:, 0] != p)
            + 0.5 * (pos[:, 1] != r))


def _nearest_chip_load(ds: xr.Dataset, feeds: np.ndarray, i_speed: int,
                       binding: pd.Series) -> int:
    """Of the allowed feed indices ``feeds`` at speed index ``i_speed``, the one whose chip
    load lies nearest the binding cut's (in ratio; the slower of two as near), else the
    slowest."""
    c_b = float(binding.get("feed_per_tooth_mm", np.nan))
    if not np.isfinite(c_b) or c_b <= 0 or "feed_per_tooth_mm" not in ds:
        return int(feeds[0])
    c = ds["feed_per_tooth_mm"].transpose("spindle_rpm", "feed_mm_s").values[i_speed, feeds]
    return int(feeds[int(np.argmin(np.round(np.abs(np.log(c / c_b)), 9)))])


def bisect_binding(ds: xr.Dataset, req: PlanRequest, allowed: xr.DataArray, taken: list,
                   binding: pd.Series | None, n_cuts: int, error_rate: float = 0.05,
                   min_gain: float = 0.01) -> list[pd.DataFrame]:
    """Up to ``n_cuts`` cuts whose verdicts are expected to narrow the binding cut's
    critical-depth interval most (module docstring: greedy, each added where the weighted
    members' predictions of its verdict, with those already chosen, give the smallest
    expected interval width), each on its own material; a cut every member predicts alike is
    never chosen, and the design stops when one more cut would narrow the expected width by
    less than ``min_gain`` of the prior width. Empty without members or a binding cut."""
    if binding is None or "a_crit_members_mm" not in ds or "member_weight" not in ds:
        return []
    level = float(ds.attrs.get("interval_level", 0.95))
    mem = ds["a_crit_members_mm"].transpose("member", *DIMS[:4]).values      # (E, P, R, D, S)
    w = np.asarray(ds["member_weight"].values, float)
    rpm = ds["spindle_rpm"].values
    at = (int(binding["i_placement"]), int(binding["i_rotation"]),
          int(binding["i_direction"]), int(np.argmin(np.abs(rpm - float(binding["spindle_rpm"])))))
    target = mem[(slice(None),) + at]
    if not np.all(np.isfinite(target)) or w.sum() <= 0:
        return []
    from robomill.plan.stability import summary

    prior = summary(target[:, None], w, level)
    width0 = float(prior["high"][0] - prior["low"][0])
    if width0 <= 0:
        return []
    depths = ds["depth_mm"].values
    ok = allowed.any("feed_mm_s").values & np.all(np.isfinite(mem), 0)[..., None]
    pos = np.argwhere(ok)                                                 # (n, 5)
    if not len(pos):
        return []
    pred = mem[(slice(None),) + tuple(pos[:, :4].T)] > depths[pos[:, 4]][None]   # (E, n)
    live = w > 0
    split = pred[live].any(0) & ~pred[live].all(0)       # the members disagree on its verdict
    pos, pred = pos[split], pred[:, split]
    if not len(pos):
        return []
    patterns, which = np.unique(pred, axis=1, return_inverse=True)
    which = np.ravel(which)
    near = _nearness(pos[:, :4], at, len(rpm))
    pat_near = np.full(patterns.shape[1], np.inf)
    np.minimum.at(pat_near, which, near)
    chosen: list[np.ndarray] = []
    out: list[pd.DataFrame] = []
    now = width0
    where = (f"{float(rpm[at[3]]):.6g} rpm, placement {at[0]}, rotation "
             f"{float(ds['rotation'].values[at[1]]):g} deg, direction "
             f"{ds['direction'].values[at[2]]}")
    while len(out) < n_cuts:
        ew = candidate_widths(target, w, level, patterns, chosen, error_rate)
        placed = False
        for j in np.lexsort((pat_near, np.round(ew / width0, 6))):
            if not np.isfinite(ew[j]) or now - ew[j] < min_gain * width0:
                break
            for i in np.flatnonzero(which == j)[np.argsort(near[which == j], kind="stable")]:
                p, r, d, s, a = (int(x) for x in pos[i])
                feeds = np.flatnonzero(allowed.values[p, r, d, s, a])
                row = _row(ds, (p, r, d, s, a, _nearest_chip_load(ds, feeds, s, binding)))
                if not place_apart(row, req, taken):
                    continue
                share = float(np.sum(w * pred[:, i]) / w.sum())
                row["reason"] = (
                    f"the binding cut's stability limit ({where}: a_crit "
                    f"{prior['low'][0]:.3g}-{prior['high'][0]:.3g} mm): the members disagree "
                    f"on this cut's verdict (weighted share stable {share:.2f}); expected "
                    f"interval width after {len(out) + 1} such cut(s) {ew[j]:.3g} mm")
                row["learn_target"] = "a_crit_mm at the binding cut"
                row["expected_narrowing"] = float(1 - ew[j] / width0)
                out.append(row)
                chosen.append(patterns[:, j])
                now = float(ew[j])
                placed = True
                break
            if placed:
                break
        if not placed:
            break
    return out


def reach_binding(ds: xr.Dataset, req: PlanRequest, allowed: xr.DataArray, taken: list,
                  binding: pd.Series | None) -> list[pd.DataFrame]:
    """The production plan's binding cut itself, on its own material, where its speed or chip
    load lies outside what the study measured (``interval_widening`` w > 1 there): once run,
    its mean force and deflection are evidence at the binding cut, and the widening of the
    force and deflection intervals there goes (expected narrowing 1 − 1/w). Empty inside the
    study's reach, or where the cut is not allowed."""
    if binding is None or "interval_widening" not in ds:
        return []
    at = {"placement": int(binding["i_placement"]), "rotation": int(binding["i_rotation"]),
          "direction": int(binding["i_direction"])}
    idx = []
    for dim in DIMS:
        if dim in at:
            idx.append(at[dim])
        else:
            grid = np.asarray(ds[dim].values, float)
            idx.append(int(np.argmin(np.abs(grid - float(binding[dim])))))
    if not bool(allowed.values[tuple(idx)]):
        return []
    r = _row(ds, tuple(idx))
    w = float(r["interval_widening"].iloc[0])
    if not (np.isfinite(w) and w > 1.0):
        return []
    if not place_apart(r, req, taken):
        return []
    from robomill.plan.extrapolation import reason_text

    why = reason_text(int(r["extrapolation_code"].iloc[0])) if "extrapolation_code" in r else ""
    r["reason"] = (f"the binding cut itself ({why or 'outside the study'}: its intervals "
                   f"widened {w:.3g}x): its own force and deflection bring the evidence to it")
    r["learn_target"] = "force and deflection at the binding cut"
    r["expected_narrowing"] = float(1 - 1 / w)
    return [r]


def far_pose(ds: xr.Dataset, req: PlanRequest, allowed: xr.DataArray, taken: list,
             midpoints_mm: np.ndarray | None) -> list[pd.DataFrame]:
    """One cut at the reachable placement farthest from the study's cuts."""
    if midpoints_mm is None or not len(midpoints_mm):
        return []
    pts = np.stack([ds[f"placement_{a}_mm"].values for a in "xyz"], -1)
    dist = np.linalg.norm(pts[:, None] - np.asarray(midpoints_mm)[None], axis=-1).min(1)
    margin = ds["stability_margin_low"].transpose(*DIMS).values
    for p in np.argsort(dist)[::-1]:
        ok = allowed.values[p]
        if not ok.any():
            continue
        idx = np.argwhere(ok)                                   # (n, 5): r, d, s, a, v
        stable = np.nan_to_num(margin[p][ok], nan=-1.0) >= 0
        pool = idx[stable] if stable.any() else idx
        rest = pool[np.lexsort((pool[:, 4], -pool[:, 3]))[0]]   # deepest, then slowest feed
        r = _row(ds, (int(p),) + tuple(int(i) for i in rest))
        if not place_apart(r, req, taken):
            continue
        posed = "extrapolation_code" in r and int(r["extrapolation_code"].iloc[0]) & 8
        w = float(r["interval_widening"].iloc[0]) if posed else 1.0
        r["reason"] = f"pose farthest from the study's cuts ({dist[p]:.0f} mm)"
        r["learn_target"] = "pose"
        r["expected_narrowing"] = float(1 - 1 / w) if w > 1 else 0.0
        return [r]
    return []


def separating_feed(ds: xr.Dataset, req: PlanRequest, allowed: xr.DataArray, taken: list,
                    regression, binding: pd.Series | None) -> list[pd.DataFrame]:
    """One cut at the chip load that most shrinks the binding cut's force interval."""
    from robomill.forces.prediction import design_rows
    from robomill.plan.predict import engagement

    if regression is None or binding is None:
        return []
    ent, ext = engagement(req)

    def rows(c, a):
        Ax, Ay, Az = design_rows(c, a, req.flutes, ent, ext)
        return np.stack([Ax, Ay], -2), Az

    c0 = float(binding["feed_per_tooth_mm"])
    A0, z0 = rows(c0, float(binding["depth_mm"]))
    inv_xy, inv_z = regression.xtx_inv_xy, regression.xtx_inv_z
    q0 = float(np.trace(A0 @ inv_xy @ A0.T)) / 2 + float(z0 @ inv_z @ z0)
    c_grid = ds["feed_per_tooth_mm"].transpose("spindle_rpm", "feed_mm_s").values
    best = None
    for s in range(c_grid.shape[0]):
        for v in range(c_grid.shape[1]):
            A, z = rows(float(c_grid[s, v]), float(ds["depth_mm"].values.max()))
            nxy = np.linalg.inv(np.linalg.pinv(inv_xy) + A.T @ A)
            nz = np.linalg.inv(np.linalg.pinv(inv_z) + np.outer(z, z))
            q = float(np.trace(A0 @ nxy @ A0.T)) / 2 + float(z0 @ nz @ z0)
            if best is None or q < best[0]:
                best = (q, s, v)
    q, s, v = best
    ok = allowed.values[:, :, :, s, :, v]
    if not ok.any():
        return []
    for flat in np.flatnonzero(ok.ravel())[::-1]:
        p, r_, d, a = np.unravel_index(flat, ok.shape)
        r = _row(ds, (int(p), int(r_), int(d), int(s), int(a), int(v)))
        if not place_apart(r, req, taken):
            continue
        r["reason"] = (f"chip load {c_grid[s, v] * 1e3:.3g} um separates the edge and shearing "
                       f"forces best for the binding cut's force interval (at "
                       f"{c0 * 1e3:.3g} um)")
        r["learn_target"] = "force_N"
        r["expected_narrowing"] = float(1 - np.sqrt((1 + q) / (1 + q0)))
        return [r]
    return []


def learn_design(ds: xr.Dataset, req: PlanRequest, *, occupied: Sequence[np.ndarray] = (),
                 midpoints_mm: np.ndarray | None = None, regression=None,
                 binding: pd.Series | None = None) -> pd.DataFrame:
    """The learn cuts (module docstring): with the production plan's ``binding`` cut and the
    stability model's members, first the cuts that narrow its critical-depth interval most
    (:func:`bisect_binding`), else the straddle pair; the binding cut itself where it lies
    outside the study's reach (:func:`reach_binding`: placed on the block first, listed after
    the stability cuts); then far pose,
    separating feed, then
    further straddle pairs at the next least certain speed and placement while two more fit
    in ``n_cuts``; columns as the production plan's plus ``reason``,
    ``learn_target`` and ``expected_narrowing``. Empty when nothing can be learnt."""
    allowed = learn_allowed(ds, req)
    taken = [np.asarray(o, float) for o in occupied]
    done: set = set()
    reach = reach_binding(ds, req, allowed, taken, binding) if req.n_cuts > 1 else []
    parts = bisect_binding(ds, req, allowed, taken, binding, req.n_cuts - len(reach),
                           req.stability.verdict_error)
    if not parts:
        parts = straddle(ds, req, allowed, taken, done)
    parts += reach
    if len(parts) < req.n_cuts:
        parts += far_pose(ds, req, allowed, taken, midpoints_mm)
    if len(parts) < req.n_cuts:
        parts += separating_feed(ds, req, allowed, taken, regression, binding)
    while len(parts) + 2 <= req.n_cuts:          # more pairs where the limit is next least sure
        more = straddle(ds, req, allowed, taken, done)
        if not more:
            break
        parts += more
    if not parts:
        return pd.DataFrame()
    out = pd.concat(parts, ignore_index=True).head(req.n_cuts)
    out.insert(0, "rank", np.arange(1, len(out) + 1))
    out.insert(0, "cut", [f"plan_{i:02d}" for i in out["rank"]])
    return out
