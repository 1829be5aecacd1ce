"""The work object: the part's frame and its block, where the planned slots are cut.

``plan.yaml`` (or ``cell.yaml``) states it as::

    work_object:
      frame: {xyz_mm: [600.0, -120.0, 200.0], rpy_deg: [0.0, 0.0, 0.0]}   # part in the base frame
      block_mm: {min: [0.0, 0.0, -50.0], max: [200.0, 150.0, 0.0]}        # in the part frame

The part frame's z axis must be the base frame's (roll = pitch = 0: the slots are milled with
the tool axis along it); its yaw and origin are free. The block's top face (``max`` z) is the
face the slots are cut into; each slot's start and end lie on its floor, ``depth_mm`` below
that face, inside the block's outline. Without a work object the part frame is the base frame
and the top face passes through each cut's placement point.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from robomill.io.tool_frame import rpy_matrix


class WorkObjectError(ValueError):
    """A work object that does not follow the format (one line: file, field, expected)."""

    def __init__(self, path: str, where: str, problem: str):
        self.path, self.where, self.problem = str(path), where, problem
        super().__init__(f"{path}: {where}: {problem}")


@dataclass(frozen=True)
class WorkObject:
    """Part frame ``T_base_part`` (4×4, mm) and the block ``(min, max)`` in it (or None)."""

    T_base_part: np.ndarray
    block_min_mm: np.ndarray | None = None
    block_max_mm: np.ndarray | None = None

    @property
    def z_axis(self) -> np.ndarray:
        return self.T_base_part[:3, 2].copy()

    def to_part(self, T_base: np.ndarray) -> np.ndarray:
        """A pose (4×4) in the base frame expressed in the part frame."""
        return np.linalg.inv(self.T_base_part) @ np.asarray(T_base, float)

    def points_in_part(self, p_base: np.ndarray) -> np.ndarray:
        """Points ``(..., 3)`` of the base frame in the part frame."""
        R, t = self.T_base_part[:3, :3], self.T_base_part[:3, 3]
        return (np.asarray(p_base, float) - t) @ R

    @property
    def yaw_deg(self) -> float:
        """The part frame's yaw about the base z axis [deg]."""
        return float(np.rad2deg(np.arctan2(self.T_base_part[1, 0], self.T_base_part[0, 0])))

    def to_base_dir(self, u: np.ndarray) -> np.ndarray:
        """A base-frame direction, unchanged: the request's feed directions, given in the
        part frame, are turned into the base frame when it is read
        (:func:`robomill.plan.request.parse_request`)."""
        return np.asarray(u, float)

    def top_z_offset_mm(self, p_base: np.ndarray) -> float:
        """Height of the top face above ``p_base`` along the part's z [mm] (0 without a
        block: the top face passes through the point)."""
        if self.block_max_mm is None:
            return 0.0
        return float(self.block_max_mm[2] - self.points_in_part(p_base)[2])

    def inside_outline(self, p_base: np.ndarray, tol_mm: float = 1e-6) -> np.ndarray:
        """Whether points lie within the block's x–y outline and above its bottom."""
        if self.block_min_mm is None:
            return np.ones(np.asarray(p_base).shape[:-1], bool)
        p = self.points_in_part(p_base)
        lo, hi = self.block_min_mm, self.block_max_mm
        return np.all((p >= lo - tol_mm) & (p <= hi + tol_mm), axis=-1)


BASE = WorkObject(np.eye(4))
"""No work object: the part frame is the base frame."""


def parse_work_object(value: Any, path: str, where: str = "work_object") -> WorkObject:
    """Validate a ``work_object`` mapping (module docstring).

    Raises
    ------
    WorkObjectError
        One line naming the file and the field.
    """
    def bad(field, what, got):
        raise WorkObjectError(path, field, f"expected {what}, got {got!r}")

    def vec(field, v):
        if (not isinstance(v, list) or len(v) != 3
                or any(isinstance(x, bool) or not isinstance(x, int | float)
                       or not np.isfinite(x) for x in v)):
            bad(field, "[x, y, z] (three numbers)", v)
        return np.asarray(v, float)

    if value is None:
        return BASE
    if not isinstance(value, dict) or "frame" not in value:
        bad(where, "a mapping {frame: {xyz_mm, rpy_deg}, block_mm: {min, max}}", value)
    extra = sorted(set(map(str, value)) - {"frame", "block_mm"})
    if extra:
        bad(where, "keys frame, block_mm", extra)
    fr = value["frame"]
    if not isinstance(fr, dict) or "xyz_mm" not in fr:
        bad(f"{where}.frame", "a mapping {xyz_mm, rpy_deg}", fr)
    xyz = vec(f"{where}.frame.xyz_mm", fr["xyz_mm"])
    rpy = vec(f"{where}.frame.rpy_deg", fr.get("rpy_deg", [0.0, 0.0, 0.0]))
    if abs(rpy[0]) > 0 or abs(rpy[1]) > 0:
        bad(f"{where}.frame.rpy_deg", "roll = pitch = 0 (the part's z axis along the base's)",
            fr.get("rpy_deg"))
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = rpy_matrix(rpy), xyz
    blk = value.get("block_mm")
    if blk is None:
        return WorkObject(T)
    if not isinstance(blk, dict) or not {"min", "max"} <= set(blk):
        bad(f"{where}.block_mm", "a mapping {min: [x, y, z], max: [x, y, z]}", blk)
    lo, hi = vec(f"{where}.block_mm.min", blk["min"]), vec(f"{where}.block_mm.max", blk["max"])
    if np.any(hi <= lo):
        bad(f"{where}.block_mm.max", "every coordinate above min's", blk["max"])
    return WorkObject(T, lo, hi)
