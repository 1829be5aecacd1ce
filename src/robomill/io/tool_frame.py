"""The spindle as mounted: the tool frame of ``cell.yaml``'s ``robot.tool``, and the robot's
joint limits, joint speed limits and controller (``docs/data-contract.md``, *The cell*).

The tool frame places the tool point (TCP) and the tool axis (the frame's z axis, the spindle
axis) in the flange frame, in either of two forms::

    tool: [0.0, 0.0, 180.0]                       # translation only: the tool axis is the
                                                  # flange's z axis (length_unit of the file)
    tool: {xyz_mm: [150.0, 0.0, 120.0], rpy_deg: [0.0, 90.0, 0.0]}

``rpy_deg`` = [roll, pitch, yaw] about the flange's fixed x, y, z axes in that order, i.e.
R = Rz(yaw) Ry(pitch) Rx(roll) [Craig 2005, §2.8, X-Y-Z fixed angles]; the example turns the
spindle axis onto the flange's +x axis, 150 mm off the flange axis.

``joint_limits_deg`` ([[low, high]] per joint) and ``joint_speed_limits_deg_s`` (one positive
speed per joint) are the manufacturer's working range and axis speeds; ``controller`` names
the program the plan writes (``abb``: RAPID, ``kuka``: KRL). Every problem raises one
:class:`~robomill.errors.RawDataError` naming the file and the key.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from robomill.errors import RawDataError

CONTROLLERS = ("abb", "kuka")
"""Controllers whose program the plan writes (``robot.controller``)."""

TOOL_EXPECTED = ("[x, y, z] of the TCP in the flange frame, or {xyz_mm: [x, y, z], rpy_deg: "
                 "[roll, pitch, yaw]} (the tool frame: TCP and spindle axis z in the flange "
                 "frame)")


def rpy_matrix(rpy_deg) -> np.ndarray:
    """Rotation of fixed-axis roll, pitch, yaw angles [deg]:
    R = Rz(yaw) Ry(pitch) Rx(roll) [Craig 2005, §2.8]."""
    r, p, y = np.deg2rad(np.asarray(rpy_deg, float))
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    Rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    Ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    Rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    return Rz @ Ry @ Rx


def tool_frame(value: Any, *, length_mm: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """(TCP position [mm], tool orientation) in the flange frame of a validated ``tool`` value.

    ``length_mm`` converts the three-number form (which is in the file's ``length_unit``);
    ``xyz_mm`` is in millimetres whatever the unit. None: the flange itself.
    """
    if value is None:
        return np.zeros(3), np.eye(3)
    if isinstance(value, dict):
        return (np.asarray(value.get("xyz_mm", [0.0, 0.0, 0.0]), float),
                rpy_matrix(value.get("rpy_deg", [0.0, 0.0, 0.0])))
    return np.asarray(value, float) * length_mm, np.eye(3)


def _numbers(path: Path, where: str, value: Any, n: int, what: str) -> list[float]:
    if not isinstance(value, list) or len(value) != n:
        raise RawDataError(path, f"{where} is {value!r}", where=where, expected=what)
    for i, v in enumerate(value):
        if isinstance(v, bool) or not isinstance(v, int | float) or not np.isfinite(v):
            raise RawDataError(path, f"value {v!r} is not a number", where=f"{where}[{i}]",
                               expected=what)
    return [float(v) for v in value]


def parse_tool(value: Any, path: str | Path, where: str = "tool") -> list[float] | dict:
    """Validate a ``tool`` value; return it normalized (floats; both keys of the frame form).

    Raises
    ------
    RawDataError
        Naming ``where`` (``tool``, ``tool.rpy_deg`` …): not three numbers, not a mapping with
        keys ``xyz_mm`` and ``rpy_deg``, an unknown key.
    """
    path = Path(path)
    if isinstance(value, list):
        return _numbers(path, where, value, 3, TOOL_EXPECTED)
    if not isinstance(value, dict):
        raise RawDataError(path, f"{where} is {value!r}", where=where, expected=TOOL_EXPECTED)
    extra = sorted(set(map(str, value)) - {"xyz_mm", "rpy_deg"})
    if extra:
        raise RawDataError(path, f"unknown key(s) {', '.join(extra)}", where=where,
                           expected="keys xyz_mm, rpy_deg")
    if "xyz_mm" not in value:
        raise RawDataError(path, "key 'xyz_mm' is missing", where=where,
                           expected="keys xyz_mm, rpy_deg")
    return {"xyz_mm": _numbers(path, f"{where}.xyz_mm", value["xyz_mm"], 3,
                               "[x, y, z] of the TCP in the flange frame [mm]"),
            "rpy_deg": _numbers(path, f"{where}.rpy_deg", value.get("rpy_deg", [0.0, 0.0, 0.0]),
                                3, "[roll, pitch, yaw] of the tool frame in the flange frame "
                                   "[deg]")}


def parse_joint_limits(value: Any, path: str | Path, n: int,
                       where: str = "joint_limits_deg") -> list[list[float]]:
    """Validate ``joint_limits_deg``: ``n`` pairs [low, high] with low < high [deg]."""
    path = Path(path)
    what = f"{n} pairs [low, high] in degrees (one per joint, low < high)"
    if not isinstance(value, list) or len(value) != n:
        raise RawDataError(path, f"{where} is {value!r}", where=where, expected=what)
    out = []
    for i, pair in enumerate(value):
        lo, hi = _numbers(path, f"{where}[{i}]", pair, 2, "[low, high] in degrees")
        if not lo < hi:
            raise RawDataError(path, f"low {lo:g} is not below high {hi:g}",
                               where=f"{where}[{i}]", expected="[low, high] with low < high")
        out.append([lo, hi])
    return out


def parse_speed_limits(value: Any, path: str | Path, n: int,
                       where: str = "joint_speed_limits_deg_s") -> list[float]:
    """Validate ``joint_speed_limits_deg_s``: ``n`` positive speeds [deg/s]."""
    path = Path(path)
    out = _numbers(path, where, value, n, f"{n} positive joint speeds in deg/s")
    for i, v in enumerate(out):
        if v <= 0:
            raise RawDataError(path, f"speed {v:g}", where=f"{where}[{i}]",
                               expected="a positive joint speed in deg/s")
    return out


def parse_controller(value: Any, path: str | Path, where: str = "controller") -> str:
    """Validate ``controller`` (one of :data:`CONTROLLERS`)."""
    if value not in CONTROLLERS:
        raise RawDataError(Path(path), f"controller is {value!r}", where=where,
                           expected="one of " + ", ".join(CONTROLLERS))
    return str(value)
