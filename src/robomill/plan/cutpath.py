"""One chosen cut as a path a robot can run: stations on the slot floor, the rotation about the
tool axis at each (:mod:`robomill.plan.path`), feasible postures in one configuration
(:mod:`robomill.plan.feasible`), scored and checked by the candidate grid's own predictions at
each station (:mod:`robomill.plan.stationgrid`), and the moves around it
(:mod:`robomill.plan.motion`).

The cut's placement point lies on the part's top face; the tool point runs along the slot
floor, ``depth_mm`` below it along the part's z axis, from the cut's start to its end. The
rows of ``stations`` are the move targets in order: the safe point ``safe_height_mm`` above the
top face over the start, the approach ``clearance_mm`` above it, the entry ramp (``entry``),
the cut's stations, the retract ``clearance_mm`` above the end (straight up the tool axis) and
the safe point over the end; the targets before the cut keep the first station's rotation,
those after it the last's. A station's rotation may be used only where every one of these
targets is feasible too. A cut no feasible path reaches (every path leaves the joint limits,
meets the wrist singularity, needs a configuration change or a station the grid would refuse)
is refused.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from robomill.kinematics import ik_batch
from robomill.plan.feasible import (
    REASONS,
    configuration_name,
    into_limits,
    pose_checks,
)
from robomill.plan.path import best_fixed, best_path, edges
from robomill.plan.poses import cut_frames, direction_vectors
from robomill.plan.workobject import WorkObject
from robomill.stiffness import solve_poses, tool_rotation_redundancy


@dataclass
class CutPath:
    """A planned cut's path: ``stations`` (one row per move target: approach, the cut's
    stations, retract) and its summary (worst scores along the path and for the best fixed
    rotation, the configuration); ``refused`` says why no path exists (None when it does)."""

    cut: str
    feed_mm_s: float
    spindle_rpm: float
    stations: pd.DataFrame
    summary: dict = field(default_factory=dict)
    refused: str | None = None
    nodes: dict = field(default_factory=dict)
    """Over stations × rotations: ``s_mm``, ``rotation_deg``, each score, ``feasible``,
    ``configuration`` and the chosen ``path`` (indices), for the pose map."""


def _stiffness(measured, cell, req, q, frame):
    """Per node ``(S, R)``: the tool tip's static stiffness normal to the wall at its softest
    end (:mod:`robomill.plan.tooltip`); empty without a joint or modal model."""
    from robomill.plan.tooltip import static_compliance_m_N

    S, R, n = q.shape
    comp = static_compliance_m_N(measured, cell, q.reshape(-1, n), req.robot_mode_max_hz)
    if comp is None:
        return {}
    nrm = frame[:, 1]
    c_nn = np.max([np.einsum("i,bij,j->b", nrm, C, nrm) for C in comp.values()], axis=0)
    with np.errstate(divide="ignore"):
        return {"k_normal_low_N_m": (1.0 / c_nn).reshape(S, R)}


def plan_cut_path(cut: str, mid_mm: np.ndarray, direction_deg: float, depth_mm: float,
                  feed_mm_s: float, spindle_rpm: float, req, measured, cell,
                  wobj: WorkObject, allowed_rotations: np.ndarray | None = None,
                  reach=None) -> CutPath:
    """The path of one chosen cut (module docstring). ``mid_mm``: the placement point on the
    top face in the base frame; ``cell``: :class:`robomill.plan.predict.Cell`;
    ``allowed_rotations`` ``(R,)``: the rotations at which the cut meets every constraint of
    the request (checked, as every candidate is, at its middle: they bound the middle
    station's rotation; None: all); the pessimistic margin meets ``min_stability_margin`` at
    every station."""
    robot = cell.robot
    lim = getattr(cell, "joint_limits_deg", None)
    speeds = getattr(cell, "joint_speed_limits_deg_s", None)
    th = np.asarray(req.rotations_deg, float)
    n_st = max(int(req.path_stations) | 1, 3)
    s_mm = np.linspace(0.0, req.length_mm, n_st)
    zp = wobj.z_axis
    u = direction_vectors(np.array([direction_deg]))[0]
    u = wobj.to_base_dir(u)
    frame = np.stack([u, np.cross(zp, u), zp], -1)
    floor = np.asarray(mid_mm, float) - depth_mm * zp
    pts = floor + (s_mm - req.length_mm / 2)[:, None] * u                 # (S, 3)
    Rt = tool_rotation_redundancy(cell.R0, np.deg2rad(th))                # (R, 3, 3)
    S, R = len(s_mm), len(th)
    P = np.broadcast_to(pts[:, None], (S, R, 3)).reshape(-1, 3)
    Rb = np.broadcast_to(Rt[None], (S, R, 3, 3)).reshape(-1, 3, 3)
    q, conv = solve_poses(robot, P, Rb, cell.q_seed_rad)
    q = into_limits(q, lim, cell.q_seed_rad)
    n = robot.n_joints
    q = q.reshape(S, R, n)
    chk = pose_checks(robot, q, conv.reshape(S, R), limits_deg=lim,
                      limit_margin_deg=req.joint_limit_margin_deg,
                      min_wrist_angle_deg=req.min_wrist_angle_deg)
    node_ok = chk["status"] == 0
    if allowed_rotations is not None:       # the middle station: the cut's row of the plan
        node_ok[S // 2] &= np.asarray(allowed_rotations, bool)
    cfg = chk["configuration"]
    # approach and retract above the top face over the first and last station, at that
    # station's rotation: a path may start or end only where they are feasible too
    lift = depth_mm + wobj.top_z_offset_mm(mid_mm) + req.clearance_mm
    ends = {}
    for i, kind in ((0, "approach"), (S - 1, "retract")):
        Te = np.broadcast_to(np.eye(4), (R, 4, 4)).copy()
        Te[:, :3, :3], Te[:, :3, 3] = Rt, pts[i] + lift * zp
        qe, ok = ik_batch(robot, Te, q[i])
        qe = into_limits(qe, lim, q[i])
        ce = pose_checks(robot, qe, ok, limits_deg=lim,
                         limit_margin_deg=req.joint_limit_margin_deg,
                         min_wrist_angle_deg=req.min_wrist_angle_deg)
        node_ok[i] &= (ce["status"] == 0) & (ce["configuration"] == cfg[i])
        ends[kind] = (qe, Te[:, :3, 3])
    # the safe points over the start and the end and the entry ramp (plan.motion), likewise
    air = _air_targets(req, wobj, mid_mm, depth_mm, pts, u, zp)
    for i, kind in ((0, "in"), (S - 1, "out")):
        good, q_air = _feasible_at(robot, lim, req, Rt, air[kind], q[i], cfg[i])
        node_ok[i] &= good
        ends[kind] = q_air
    from robomill.plan.stationgrid import station_grid

    grid = station_grid(req, measured, cell, reach, pts + depth_mm * zp, direction_deg,
                        spindle_rpm, depth_mm, feed_mm_s)
    before_grid = node_ok.copy()
    node_ok &= grid["feasible"]                 # reachable, every constraint, as the grid
    sc = {}
    if np.isfinite(grid["stability_margin_low"]).any():
        sc["stability_margin_low"] = grid["stability_margin_low"]
    sc.update(_stiffness(measured, cell, req, q, frame))
    names = list(sc)
    scores = [sc[k] for k in names]
    dt = (s_mm[1] - s_mm[0]) / feed_mm_s
    E = edges(th, q, cfg, max_step_deg=req.max_rotation_step_deg, dt_s=dt,
              speed_limits_deg_s=speeds)
    best, best_cfg = None, None
    for c in np.unique(cfg[node_ok]) if node_ok.any() else []:
        idx, worst = best_path(scores, node_ok & (cfg == c), E, th)
        if idx is None:
            continue
        key = (worst, -float(np.abs(th[idx]).sum()))
        if best is None or _better(key, best[1], scores):
            best, best_cfg = (idx, key), int(c)
    summary = {"configuration": "", "score": "/".join(names) or "none"}
    nodes = {"s_mm": s_mm, "rotation_deg": th, "feasible": node_ok, "configuration": cfg,
             **sc, "path": None}
    if best is None:
        reasons = np.unique(chk["status"][~node_ok])
        blocked = [f"{s_mm[i]:g} mm" for i in range(S) if before_grid[i].any()
                   and not node_ok[i].any()]
        why = ("no path keeps one configuration within the joint limits, the wrist angle, the "
               "axis speeds, the rotation step and the request's constraints (the stability "
               "margin at every station) from the safe point to the retract"
               + (f"; the candidate grid refuses every posable rotation at the station(s) "
                  f"{', '.join(blocked)} (its constraints, widened where the study does not "
                  "reach)" if blocked else "")
               if node_ok.any() else
               "the candidate grid refuses every posable station and rotation (its "
               "constraints, widened where the study does not reach)" if before_grid.any() else
               "no station is feasible at any rotation ("
               + ", ".join(REASONS[int(r)] for r in reasons if r > 0) + ")")
        return CutPath(cut, feed_mm_s, spindle_rpm, pd.DataFrame(), summary, refused=why,
                       nodes=nodes)
    idx = best[0]
    nodes["path"] = idx
    ar = np.arange(S)
    qp = q[ar, idx]
    ref = cell.q_seed_rad
    for i in range(S):                      # whole turns chosen for continuity along the path
        qp[i] = into_limits(qp[i], lim, ref)
        ref = qp[i]
    fixed_r, fixed_worst = best_fixed(scores, node_ok, np.all(cfg == best_cfg, axis=0), th)
    summary.update({"configuration": configuration_name(best_cfg),
                    "configuration_code": best_cfg,
                    "rotation_path_deg": ";".join(f"{a:g}" for a in th[idx]),
                    "fixed_rotation_deg": np.nan if fixed_r is None else float(th[fixed_r])})
    for k, name in enumerate(names):
        pw = float(sc[name][ar, idx].min())          # +inf: no finite limit along the path
        fw = fixed_worst[k] if fixed_r is not None else np.nan
        summary[f"path_worst_{name}"] = pw
        summary[f"fixed_worst_{name}"] = fw
    app, ret = ends["approach"][0][idx[0]], ends["retract"][0][idx[-1]]
    app, ret = into_limits(app, lim, qp[0]), into_limits(ret, lim, qp[-1])
    def target(p_mm, i_rot):
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = Rt[i_rot], p_mm
        return T

    r0, r1 = idx[0], idx[-1]
    q_in, T_in = ends["in"][-1, r0], target(air["in"][-1], r0)
    q_out, T_out = ends["out"][0, r1], target(air["out"][0], r1)
    ramp = [(target(pt, r0), ends["in"][k, r0]) for k, pt in enumerate(air["in"][:-1])]
    rows = [_row(wobj, "safe_in", np.nan, th[idx[0]], q_in, T_in, None),
            _row(wobj, "approach", np.nan, th[idx[0]], app,
                 target(ends["approach"][1][idx[0]], idx[0]), None)]
    rows += [_row(wobj, "entry", float((T[:3, 3] - pts[0]) @ u), th[idx[0]], q, T, None)
             for T, q in ramp]
    for i in range(S):
        extra = {name: float(sc[name][i, idx[i]]) for name in names}
        extra.update({"wrist_angle_deg": float(chk["wrist_deg"][i, idx[i]]),
                      "limit_clearance_deg": float(chk["clearance_deg"][i, idx[i]]),
                      "sigma_min": float(chk["sigma_min"][i, idx[i]])})
        rows.append(_row(wobj, "cut", float(s_mm[i]), th[idx[i]], qp[i],
                         target(pts[i], idx[i]), extra))
    rows.append(_row(wobj, "retract", np.nan, th[idx[-1]], ret,
                     target(ends["retract"][1][idx[-1]], idx[-1]), None))
    rows.append(_row(wobj, "safe_out", np.nan, th[idx[-1]], q_out, T_out, None))
    st = pd.DataFrame(rows)
    st.insert(0, "cut", cut)
    st.insert(1, "configuration", configuration_name(best_cfg))
    cutrows = st[st["move"] == "cut"]
    summary.update({"min_wrist_angle_deg": float(cutrows["wrist_angle_deg"].min()),
                    "min_limit_clearance_deg": float(cutrows["limit_clearance_deg"].min()),
                    "min_sigma": float(cutrows["sigma_min"].min())})
    return CutPath(cut, feed_mm_s, spindle_rpm, st, summary, nodes=nodes)


def _air_targets(req, wobj, mid_mm, depth_mm, pts, u, zp) -> dict[str, np.ndarray]:
    """Points in the air and on the way in (:mod:`robomill.plan.motion`): ``in`` the entry
    ramp's points then the safe point over the start, ``out`` the safe point over the end."""
    from robomill.plan.motion import Motion, ramp_points

    mo = req.motion or Motion()
    top = depth_mm + wobj.top_z_offset_mm(mid_mm)           # the slot floor → the top face
    ramp = ramp_points(pts[0], u, zp, top + mo.ramp_gap_mm, req.length_mm, mo.ramp_angle_deg)
    return {"in": np.vstack([ramp, pts[0] + (top + mo.safe_height_mm) * zp]),
            "out": (pts[-1] + (top + mo.safe_height_mm) * zp)[None]}


def _feasible_at(robot, lim, req, Rt, points, q_seed, config):
    """Per rotation ``(R,)``: whether every point ``(k, 3)`` at that rotation is feasible in
    the station's configuration, and the joints ``(k, R, n)`` [rad] (solved near the
    station's ``q_seed`` ``(R, n)``)."""
    k, R, n = len(points), len(Rt), q_seed.shape[-1]
    T = np.broadcast_to(np.eye(4), (k, R, 4, 4)).copy()
    T[..., :3, :3], T[..., :3, 3] = Rt[None], np.asarray(points)[:, None]
    seed = np.broadcast_to(q_seed, (k, R, n)).reshape(-1, n)
    qe, ok = ik_batch(robot, T.reshape(-1, 4, 4), seed)
    qe = into_limits(qe, lim, seed)
    ce = pose_checks(robot, qe, ok, limits_deg=lim, limit_margin_deg=req.joint_limit_margin_deg,
                     min_wrist_angle_deg=req.min_wrist_angle_deg)
    good = ((ce["status"] == 0) & (ce["configuration"] == np.tile(config, k))).reshape(k, R)
    return good.all(0), qe.reshape(k, R, n)


def _better(key, other, scores) -> bool:
    """Lexicographic comparison of (worst scores, −Σ|θ|) with the scores' tie tolerance."""
    from robomill.plan.path import tie_tolerance, usable

    for a, b, sc in zip(key[0], other[0], scores, strict=True):
        tol = tie_tolerance(usable(sc))
        if a > b + tol:
            return True
        if a < b - tol:
            return False
    return key[1] > other[1]


def _row(wobj: WorkObject, move: str, s_mm: float, rot_deg: float, q_rad: np.ndarray,
         T: np.ndarray, extra: dict | None) -> dict:
    """One stations.csv row: the joint target, the Cartesian target T it reaches (the TCP
    pose, position and quaternion w, x, y, z) in the base and the part frame, the rotation,
    and the scores at the station."""
    from robomill.plan.program import quaternion_wxyz

    Tp = wobj.to_part(T)
    row = {"move": move, "s_mm": s_mm, "rotation_deg": float(rot_deg)}
    row.update({f"q{j + 1}_deg": float(np.rad2deg(v)) for j, v in enumerate(q_rad)})
    for tag, M in (("base", T), ("part", Tp)):
        for ax, v in zip("xyz", M[:3, 3], strict=True):
            row[f"{ax}_{tag}_mm"] = float(v)
        for c, v in zip("wxyz", quaternion_wxyz(M[:3, :3]), strict=True):
            row[f"q{c}_{tag}"] = float(v)
    row.update(extra or {})
    return row


def cut_frame_base(direction_deg: float) -> np.ndarray:
    """The cut frame (feed, wall normal, tool axis) of a direction in the base frame."""
    return cut_frames(np.array([direction_deg]))[0]
