"""How the robot's controller sees the cell (``cell.yaml``, both keys optional): the
controller's flange and joint conventions relative to the robot model, and the spindle's
interface (``docs/data-contract.md``, *The cell*)::

    controller_frames:                 # the controller's conventions, relative to the model
      flange: {xyz_mm: [0, 0, 0], rpy_deg: [0, 0, 180]}   # controller flange in the model's
                                                          # last frame (ABB tool0, KUKA $FLANGE)
      joint_sign: [1, 1, 1, 1, 1, 1]   # q_controller = sign · q_model + offset
      joint_offset_deg: [0, 0, 0, 0, 0, 0]
    spindle:                           # the spindle as the cell wires it (controller signals)
      speed: aoSpindleSpeed            # analog output set to rpm · speed_per_rpm
      speed_per_rpm: 1.0               # (KUKA $ANOUT: 1/max rpm, the output is in -1 … 1)
      start: doSpindleOn               # digital output: on to run, off to stop
      ready: diSpindleAtSpeed          # digital input: on when the spindle runs at speed
      runup_s: 4.0                     # or/and a run-up time waited after the start

``flange`` uses the tool-frame form of :mod:`robomill.io.tool_frame` (R = Rz(yaw) Ry(pitch)
Rx(roll)). Without ``controller_frames`` the model's last frame and joint angles are taken as
the controller's (stated in the program's header). KUKA signals are numbers
(``$ANOUT[n]``, ``$OUT[n]``, ``$IN[n]``), ABB signals names. Without ``spindle`` (or without
its ``start``) the program stops before the first cut and asks the operator to start it.
Every problem raises one :class:`~robomill.errors.RawDataError` naming the file and the key.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from robomill.errors import RawDataError

FRAMES_KEYS = ("flange", "joint_sign", "joint_offset_deg")
SPINDLE_KEYS = ("speed", "speed_per_rpm", "start", "ready", "runup_s")


@dataclass(frozen=True)
class ControllerFrames:
    """The controller's flange in the model's last frame (4×4, mm) and its joint angles
    ``q_controller = joint_sign · q_model + joint_offset_deg``; ``stated``: from cell.yaml."""

    flange_in_model: np.ndarray
    joint_sign: np.ndarray
    joint_offset_deg: np.ndarray
    stated: bool = True

    def joints_deg(self, q_model_deg) -> np.ndarray:
        """The controller's joint angles [deg] of model angles ``(..., n)`` [deg]."""
        return self.joint_sign * np.asarray(q_model_deg, float) + self.joint_offset_deg

    def model_deg(self, q_controller_deg) -> np.ndarray:
        """The model's joint angles of controller angles (the inverse of :meth:`joints_deg`)."""
        return (np.asarray(q_controller_deg, float) - self.joint_offset_deg) * self.joint_sign


def model_frames(n_joints: int) -> ControllerFrames:
    """No stated convention: the model's last frame and joint angles are the controller's."""
    return ControllerFrames(np.eye(4), np.ones(n_joints), np.zeros(n_joints), stated=False)


@dataclass(frozen=True)
class SpindleInterface:
    """The spindle's signals (ABB names or KUKA numbers; None: not wired) and run-up time."""

    speed: str | int | None = None
    speed_per_rpm: float = 1.0
    start: str | int | None = None
    ready: str | int | None = None
    runup_s: float | None = None

    @property
    def wired(self) -> bool:
        """Whether the program can start the spindle itself (a start signal is named)."""
        return self.start is not None


def _bad(path, where, got, expected):
    raise RawDataError(Path(path), f"{where} is {got!r}", where=where, expected=expected)


def _vector(path, where, value, n, what, *, allowed=None):
    if (not isinstance(value, list) or len(value) != n
            or any(isinstance(v, bool) or not isinstance(v, int | float) or not np.isfinite(v)
                   for v in value)
            or (allowed is not None and any(v not in allowed for v in value))):
        _bad(path, where, value, what)
    return np.asarray(value, float)


def parse_controller_frames(value: Any, path: str | Path, n_joints: int) -> ControllerFrames:
    """Validate ``controller_frames`` (module docstring); None: :func:`model_frames`."""
    from robomill.io.tool_frame import parse_tool, tool_frame

    if value is None:
        return model_frames(n_joints)
    if not isinstance(value, dict):
        _bad(path, "controller_frames", value, "a mapping {flange, joint_sign, "
             "joint_offset_deg}")
    extra = sorted(set(map(str, value)) - set(FRAMES_KEYS))
    if extra:
        _bad(path, "controller_frames", extra, "keys " + ", ".join(FRAMES_KEYS))
    fl = parse_tool(value.get("flange", [0.0, 0.0, 0.0]), path, "controller_frames.flange")
    p, R = tool_frame(fl)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    sign = _vector(path, "controller_frames.joint_sign", value.get("joint_sign", [1] * n_joints),
                   n_joints, f"{n_joints} signs, each 1 or -1", allowed=(1, -1))
    off = _vector(path, "controller_frames.joint_offset_deg",
                  value.get("joint_offset_deg", [0.0] * n_joints), n_joints,
                  f"{n_joints} angles [deg]")
    return ControllerFrames(T, sign, off)


def parse_spindle(value: Any, path: str | Path, controller: str | None) -> SpindleInterface | None:
    """Validate ``spindle`` (module docstring); None when the cell names no interface."""
    if value is None:
        return None
    if not isinstance(value, dict):
        _bad(path, "spindle", value, "a mapping {speed, speed_per_rpm, start, ready, runup_s}")
    extra = sorted(set(map(str, value)) - set(SPINDLE_KEYS))
    if extra:
        _bad(path, "spindle", extra, "keys " + ", ".join(SPINDLE_KEYS))
    kuka = controller == "kuka"
    sig = {}
    for k in ("speed", "start", "ready"):
        v = value.get(k)
        if v is None:
            sig[k] = None
        elif kuka and (isinstance(v, bool) or not isinstance(v, int) or v < 1):
            _bad(path, f"spindle.{k}", v, "a KUKA I/O number (an integer ≥ 1)")
        elif not kuka and (not isinstance(v, str) or not v.isidentifier()):
            _bad(path, f"spindle.{k}", v, "an ABB signal name (letters, digits, _)")
        else:
            sig[k] = v
    scale = value.get("speed_per_rpm", 1.0)
    if isinstance(scale, bool) or not isinstance(scale, int | float) or not scale > 0:
        _bad(path, "spindle.speed_per_rpm", scale, "a positive number")
    runup = value.get("runup_s")
    if runup is not None and (isinstance(runup, bool) or not isinstance(runup, int | float)
                              or not runup >= 0):
        _bad(path, "spindle.runup_s", runup, "a run-up time ≥ 0 [s]")
    if sig["start"] is not None and sig["ready"] is None and runup is None:
        _bad(path, "spindle.runup_s", runup, "a run-up time [s] or a ready input (the program "
             "must wait until the spindle runs at speed)")
    return SpindleInterface(sig["speed"], float(scale), sig["start"], sig["ready"],
                            None if runup is None else float(runup))
