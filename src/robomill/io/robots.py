"""Readers for the stiffness chapter's raw files (``docs/data-contract.md``).

* kind ``robot`` — ``stiffness/<robot>.yaml``: name, convention (dh | mdh), length_unit
  (mm | m), angle_unit (deg | rad), joints (one mapping {a, alpha, d, theta_offset} per joint,
  base to flange), tool [x, y, z] (TCP in the flange frame) or {xyz_mm, rpy_deg} (the tool
  frame, :mod:`robomill.io.tool_frame`), optional joint_limits_deg, joint_speed_limits_deg_s,
  controller;
* kind ``stiffness`` — ``stiffness/load_tests_<robot>.csv``: columns ``pose, role,
  q1_deg … qN_deg, Fx_N, Fy_N, Fz_N, dx_mm, dy_mm, dz_mm`` (force at the TCP and TCP
  deflection in the base frame; role ``identify`` or ``validate``).

Every problem raises :class:`~robomill.io.RawDataError` naming the file and the field.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import yaml

from robomill.errors import RawDataError
from robomill.io.tables import read_numeric_csv
from robomill.io.tool_frame import (
    parse_controller,
    parse_joint_limits,
    parse_speed_limits,
    parse_tool,
)
from robomill.kinematics import SerialRobot, robot_from_mapping

ROBOT_KEYS = ("name", "convention", "length_unit", "angle_unit", "joints", "tool",
              "joint_limits_deg", "joint_speed_limits_deg_s", "controller")
"""Keys of a robot mapping (the last three optional: the cell's working range, axis speeds
and controller, :mod:`robomill.io.tool_frame`)."""

CONVENTIONS = ("dh", "mdh")
LENGTH_UNITS = ("mm", "m")
ANGLE_UNITS = ("deg", "rad")
ROLES = ("identify", "validate")
FORCE_COLUMNS = ("Fx_N", "Fy_N", "Fz_N")
DEFLECTION_COLUMNS = ("dx_mm", "dy_mm", "dz_mm")


def _number(path: Path, where: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not np.isfinite(value):
        raise RawDataError(path, f"value {value!r} is not a number", where=where,
                           expected="a finite number")
    return float(value)


def parse_robot(data: Any, path: str | Path, *, n_joints: int | None = 6) -> dict[str, Any]:
    """Validate a robot-file mapping; return it normalized (floats, defaults filled).

    Raises
    ------
    RawDataError
        Naming the key (``convention``, ``joints[2].alpha``, ``tool`` …) and what is expected.
    """
    path = Path(path)
    if not isinstance(data, dict):
        raise RawDataError(path, "not a YAML mapping",
                           expected="keys name, convention, length_unit, angle_unit, joints, tool")
    for key in ("name", "convention", "joints"):
        if key not in data:
            raise RawDataError(path, f"key '{key}' is missing", where=key,
                               expected="keys name, convention, length_unit, angle_unit, "
                                        "joints, tool")
    out: dict[str, Any] = {"name": str(data["name"])}
    for key, allowed, default in (("convention", CONVENTIONS, None),
                                  ("length_unit", LENGTH_UNITS, "mm"),
                                  ("angle_unit", ANGLE_UNITS, "deg")):
        value = data.get(key, default)
        if value not in allowed:
            raise RawDataError(path, f"unknown {key} {value!r}", where=key,
                               expected="one of " + ", ".join(allowed))
        out[key] = value
    joints = data["joints"]
    if not isinstance(joints, list) or not joints:
        raise RawDataError(path, "joints is not a non-empty list", where="joints",
                           expected="one mapping {a, alpha, d, theta_offset} per joint")
    if n_joints is not None and len(joints) != n_joints:
        raise RawDataError(path, f"{len(joints)} joints listed", where="joints",
                           expected=f"{n_joints} joints (base to flange)")
    rows = []
    for i, j in enumerate(joints):
        if not isinstance(j, dict):
            raise RawDataError(path, f"{type(j).__name__} found", where=f"joints[{i}]",
                               expected="a mapping {a, alpha, d, theta_offset}")
        for key in ("a", "alpha", "d"):
            if key not in j:
                raise RawDataError(path, f"key '{key}' is missing", where=f"joints[{i}]",
                                   expected="keys a, alpha, d, theta_offset")
        unknown = set(j) - {"a", "alpha", "d", "theta_offset"}
        if unknown:
            raise RawDataError(path, f"unknown key(s) {', '.join(sorted(unknown))}",
                               where=f"joints[{i}]", expected="keys a, alpha, d, theta_offset")
        rows.append({k: _number(path, f"joints[{i}].{k}", j.get(k, 0.0))
                     for k in ("a", "alpha", "d", "theta_offset")})
    out["joints"] = rows
    out["tool"] = parse_tool(data.get("tool", [0.0, 0.0, 0.0]), path)
    n = len(rows)
    if data.get("joint_limits_deg") is not None:
        out["joint_limits_deg"] = parse_joint_limits(data["joint_limits_deg"], path, n)
    if data.get("joint_speed_limits_deg_s") is not None:
        out["joint_speed_limits_deg_s"] = parse_speed_limits(data["joint_speed_limits_deg_s"],
                                                             path, n)
    if data.get("controller") is not None:
        out["controller"] = parse_controller(data["controller"], path)
    unknown = sorted(set(map(str, data)) - set(ROBOT_KEYS))
    if unknown:
        raise RawDataError(path, f"unknown key(s) {', '.join(unknown)}", where="<robot>",
                           expected="keys " + ", ".join(ROBOT_KEYS))
    return out


def read_robot_file(path: str | Path, *, n_joints: int | None = 6
                    ) -> tuple[SerialRobot, dict[str, Any]]:
    """Read ``stiffness/<robot>.yaml``: the robot and its normalized mapping."""
    path = Path(path)
    if not path.exists():
        raise RawDataError(path, "file does not exist")
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as exc:
        raise RawDataError(path, f"not valid YAML: {exc}") from None
    spec = parse_robot(data, path, n_joints=n_joints)
    return robot_from_mapping(spec), spec


def joint_columns(n_joints: int) -> list[str]:
    return [f"q{i}_deg" for i in range(1, n_joints + 1)]


def read_load_tests(path: str | Path, n_joints: int = 6) -> pd.DataFrame:
    """Read ``stiffness/load_tests_<robot>.csv`` for a robot with ``n_joints`` joints.

    Returns the table with numeric columns as floats and ``pose``/``role`` as text.

    Raises
    ------
    RawDataError
        Missing column, joint columns not matching the robot's joint count, text in a
        numeric field, a role other than identify/validate, no identify row, duplicate pose.
    """
    path = Path(path)
    if path.exists():
        header = path.read_text(encoding="utf-8-sig").splitlines()[:1]
        found = [h.strip() for h in header[0].split(",")] if header else []
        qcols = sorted((c for c in found if re.fullmatch(r"q\d+_deg", c)),
                       key=lambda c: int(c[1:-4]))
        if qcols and qcols != joint_columns(n_joints):
            raise RawDataError(path, f"joint columns {', '.join(qcols)} found",
                               where="header (row 1)",
                               expected=f"{n_joints} joint columns "
                                        f"{', '.join(joint_columns(n_joints))} (the robot "
                                        f"file lists {n_joints} joints)")
    columns = joint_columns(n_joints) + list(FORCE_COLUMNS) + list(DEFLECTION_COLUMNS)
    df = read_numeric_csv(path, columns, text_columns=("pose", "role"))
    bad = ~df["role"].isin(ROLES)
    if bad.any():
        i = int(np.argmax(bad.to_numpy()))
        raise RawDataError(path, f"role {df['role'].iloc[i]!r}", where=f"row {i + 2}, column role",
                           expected="identify or validate")
    dup = df["pose"].duplicated()
    if dup.any():
        i = int(np.argmax(dup.to_numpy()))
        raise RawDataError(path, f"duplicate pose {df['pose'].iloc[i]!r}",
                           where=f"row {i + 2}, column pose", expected="unique pose names")
    if not (df["role"] == "identify").any():
        raise RawDataError(path, "no identify rows", where="column role",
                           expected="at least one row with role identify")
    return df
