"""Motion as a robot programmer writes it around each planned cut: the settings of
``plan.yaml``'s ``program:`` section and the targets in the air and on the way in.

``plan.yaml``::

    program:
      safe_height_mm: 50.0       # safe point this far above the part's top face, over the
                                 # cut's start and end (the moves between cuts join them)
      ramp_angle_deg: 3.0        # the tool enters the part along the slot at this angle
      ramp_gap_mm: 1.0           # the ramp starts this far above the top face
      zone_cut_mm: 0.1           # corner zone of the cutting moves (no fine point in a cut)
      zone_air_mm: 5.0           # corner zone of the moves in the air
      air_speed_mm_s: 100.0      # TCP speed in the air (approach, retract, safe moves)
      joint_speed_pct: 20.0      # joint moves (home, to each safe point): % of the axis speeds
      cp_acceleration_m_s2: 1.0  # path acceleration of the linear moves (KRL $ACC.CP)
      home_deg: null             # home posture [deg, controller angles]; null: the cell's
                                 # q_home_deg

Per cut the program runs: safe point over the start (joint move; the spindle is set there),
the approach ``clearance_mm`` above the top face, the ramp's start ``ramp_gap_mm`` above it,
the ramp down along the feed direction at ``ramp_angle_deg`` to the slot's floor (back and
forth over the slot when one pass is too short), back along the floor to the start, the
cut's stations, the retract along the tool axis to ``clearance_mm`` and on to the safe point
over the end. Each of these targets is solved for the cut's configuration and rotation and
must be feasible like every station (else the cut is refused).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

MOTION_KEYS = ("safe_height_mm", "ramp_angle_deg", "ramp_gap_mm", "zone_cut_mm",
               "zone_air_mm", "air_speed_mm_s", "joint_speed_pct", "cp_acceleration_m_s2",
               "home_deg")


@dataclass(frozen=True)
class Motion:
    """The ``program:`` settings (module docstring)."""

    safe_height_mm: float = 50.0
    ramp_angle_deg: float = 3.0
    ramp_gap_mm: float = 1.0
    zone_cut_mm: float = 0.1
    zone_air_mm: float = 5.0
    air_speed_mm_s: float = 100.0
    joint_speed_pct: float = 20.0
    cp_acceleration_m_s2: float = 1.0
    home_deg: tuple[float, ...] | None = None


def parse_motion(value: Any, path, error) -> Motion:
    """Validate ``program:`` (None: the defaults); ``error(path, where, problem)`` builds
    the request's one-line error."""
    if value is None:
        return Motion()
    if not isinstance(value, dict):
        raise error(path, "program", "expected a mapping {" + ", ".join(MOTION_KEYS) + "}")
    out: dict[str, Any] = {}
    for k, v in value.items():
        if k not in MOTION_KEYS:
            raise error(path, f"program.{k}", "unknown field (expected one of "
                        + ", ".join(MOTION_KEYS) + ")")
        if k == "home_deg":
            if v is not None and (not isinstance(v, list) or any(
                    isinstance(x, bool) or not isinstance(x, int | float)
                    or not np.isfinite(x) for x in v)):
                raise error(path, "program.home_deg", f"expected a list of joint angles "
                            f"[deg] or null, got {v!r}")
            out[k] = None if v is None else tuple(float(x) for x in v)
            continue
        ok = isinstance(v, int | float) and not isinstance(v, bool) and np.isfinite(v)
        lo, hi = {"ramp_angle_deg": (0.0, 45.0), "joint_speed_pct": (0.0, 100.0)}.get(
            k, (0.0, np.inf))
        if not ok or not lo < v <= hi or (k in ("zone_cut_mm", "zone_air_mm") and v < 0):
            raise error(path, f"program.{k}", f"expected a number in ({lo:g}, {hi:g}], "
                        f"got {v!r}")
        out[k] = float(v)
    m = Motion(**out)
    if m.safe_height_mm < 50.0:
        raise error(path, "program.safe_height_mm", "expected at least 50 mm above the part, "
                    f"got {m.safe_height_mm:g}")
    return m


def ramp_points(start_mm: np.ndarray, u: np.ndarray, zp: np.ndarray, drop_mm: float,
                length_mm: float, angle_deg: float) -> np.ndarray:
    """The entry ramp ``(k, 3)``: from ``drop_mm`` above ``start_mm`` (on the slot floor)
    down along ``u`` at ``angle_deg``, back and forth over ``length_mm`` of the slot until
    the floor; the first row is the ramp's start, and the cut's first station (the way back
    along the floor) follows the last."""
    tan = np.tan(np.deg2rad(angle_deg))
    pts = [start_mm + drop_mm * zp]
    s, h, forward = 0.0, drop_mm, True
    while h > 1e-9:
        step = min(length_mm, h / tan)
        s = s + step if forward else s - step
        h = max(h - step * tan, 0.0)
        pts.append(start_mm + s * u + h * zp)
        forward = not forward
    return np.asarray(pts)


def solve_targets(robot, lim, req, T: np.ndarray, q_seed: np.ndarray, config: int):
    """Joint targets ``(m, n)`` [rad] of TCP poses ``(m, 4, 4)`` near ``q_seed``, and
    whether every one is feasible in ``config`` (limits with margin, wrist, convergence)."""
    from robomill.kinematics import ik_batch
    from robomill.plan.feasible import into_limits, pose_checks

    q, ok = ik_batch(robot, T, np.broadcast_to(q_seed, (len(T), len(q_seed))))
    q = into_limits(q, lim, q_seed)
    chk = pose_checks(robot, q, ok, limits_deg=lim, limit_margin_deg=req.joint_limit_margin_deg,
                      min_wrist_angle_deg=req.min_wrist_angle_deg)
    good = bool(np.all((chk["status"] == 0) & (chk["configuration"] == config)))
    return q, good
